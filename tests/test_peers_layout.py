"""benchmarks/peers_layout.py: the peers' files laid out for benchmarks/peers.py, on a Pyslvs checkout of ours
(a six-link example and collection written here, not Pyslvs' own): the Pyslvs-UI project it writes opens as
the same mechanism as the expression, and a collection's input pair is renumbered from the collection's graph
edges to the expression's joints (Pyslvs' eight-bar collection was refused: its pair (0, 3) read as joints
shares no link; as edges it is the crank J0 -> J2).
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

from analytic import ParameterError
from analytic.format import foreign

# a four-bar (crank J0-J2, coupler J2-J3-J4, rocker J1-J3) with a dyad J4-J5-J1; J1 pins ground, L2 and L4
EXPR = ("M[J[R, P[0, 0], L[ground, L1]], J[R, P[40, 0], L[ground, L2, L4]], J[R, P[0, 10], L[L1, L3]], "
        "J[R, P[40, 30], L[L2, L3]], J[R, P[20, 40], L[L3, L5]], J[R, P[50, 40], L[L4, L5]]]")
# the collection's graph edges: e0 (0,1) J0, e1 (0,2) and e2 (0,4) both J1 (same {2: 1}), e3 (1,3) J2,
# e4 (2,3) J3, e5 (3,5) J4, e6 (4,5) J5; its input (0, 3) is e0 -> e3: J0 -> J2, the crank L1
EXAMPLE = f'_example_list = {{"My six bar": ("{EXPR}", ((0, 2),))}}\n'
COLLECTION = (f'_collection_list = {{"My six bar linkage": {{"expression": "{EXPR}", "input": [((0, 3), [0, 360])], '
              f'"graph": ((0, 1), (0, 2), (0, 4), (1, 3), (2, 3), (3, 5), (4, 5)), "same": {{2: 1}}}}}}\n')


def layout():
    spec = importlib.util.spec_from_file_location(
        "peers_layout", Path(__file__).resolve().parent.parent / "benchmarks" / "peers_layout.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture
def laid_out(tmp_path):
    src = tmp_path / "pyslvs" / "pyslvs"
    src.mkdir(parents=True)
    (src / "example.py").write_text(EXAMPLE)
    (src / "collection.py").write_text(COLLECTION)
    out = tmp_path / "out"
    assert layout().main(["--pyslvs", str(tmp_path / "pyslvs"), "--out", str(out)]) == 0
    return out


def test_the_collection_s_input_pair_is_renumbered_to_the_expression_s_joints(laid_out):
    text = (laid_out / "pyslvs_collection" / "my_six_bar_linkage.txt").read_text()
    assert "# inputs (base, driver): [(0, 2)]" in text
    data = foreign.read(laid_out / "pyslvs_collection" / "my_six_bar_linkage.txt", [(0, 2)])
    assert data["inputs"][0]["kind"] == "crank"
    with pytest.raises(ParameterError):                 # the pair as written, read as joints: J0, J3 share no link
        foreign.read(laid_out / "pyslvs_collection" / "my_six_bar_linkage.txt", [(0, 3)])


def test_joint_index_by_hand():
    mod = layout()
    same = {2: 1, 4: 3, 7: 6}                           # Pyslvs' eight-bar collection's merges
    assert [mod.joint_index(k, same) for k in range(11)] == [0, 1, 1, 2, 2, 3, 4, 4, 5, 6, 7]


def test_the_project_opens_as_the_expression_does(laid_out):
    expr = foreign.read(laid_out / "pyslvs" / "my_six_bar.txt", [(0, 2)])
    proj = foreign.read(laid_out / "pyslvs_yaml" / "my_six_bar.pyslvs")      # its inputs from the project
    assert proj["pose"] == expr["pose"] and proj["inputs"] == expr["inputs"]
    assert proj["pose"]["J5"] == pytest.approx((50.0, 40.0), abs=1e-12)
