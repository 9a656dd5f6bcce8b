"""``linkage import`` and opening other tools' files directly: Pyslvs projects and expressions, PMKS text.

The example files (tests/peers_examples/) are ours, written from the formats' descriptions; their motion is
checked against hand geometry here, and against the file's joints in test_joints_form.
"""

from __future__ import annotations

import json
import math
import tomllib

import numpy as np
import pytest

import analytic
from analytic import FileError
from analytic.format import foreign, pmks, pyslvs
from sim import service
from test_joints_form import EXAMPLES, check_motion, solved_points

import cli_runner  # the command in this process (tests/cli_runner.py)

HAND_TOL = 1e-12     # / size: the solver against hand geometry (closed forms on both sides: rounding)


def run(*args, cwd=None):
    return cli_runner.run(*args, cwd=cwd)


def mech_of(name, inputs=None):
    return analytic.registry.Mechanism.from_definition(foreign.definition(EXAMPLES / name, inputs), {})


# ------------------------------------------------------------------------------------------- Pyslvs
def test_expression_grammar():
    joints = pyslvs.parse_expression((EXAMPLES / "slider_crank_rp.txt").read_text(), "x")
    assert joints == [("R", None, (0.0, 0.0), ["ground", "L1"]), ("R", None, (14.1421, 14.1421), ["L1", "L2"]),
                      ("RP", 0.0, (72.4517, 0.0), ["ground", "L2"]), ("R", None, (43.3, 17.0), ["L2"])]
    assert pyslvs.parse_expression("M[J[P,A[-3e1],P[.5,-2],L[a,b,]],]", "x") == [("P", -30.0, (0.5, -2.0), ["a", "b"])]
    with pytest.raises(FileError, match=r"x: not a Pyslvs expression: expected 'L\[' at line 2, column 3 "
                                        r"\(near 'X\[ground\]\]\]'\)"):
        pyslvs.parse_expression("M[J[R, P[0, 0], # a comment\n  X[ground]]]", "x")


def test_pyslvs_meaning():
    """An RP joint is a block sliding in links[0] with links[1:] pinned to it; a P joint's links[1] is the block
    (the ground written second is made the guide); an input (b, d) turns the link J_b and J_d share about J_b,
    (b, b) drives the slider at J_b."""
    text = "M[J[R,P[0,0],L[ground,a]], J[RP,A[30],P[1,2],L[b,a,c]], J[P,A[90],P[5,5],L[c,ground]], J[R,P[3,3],L[b]]]"
    form = pyslvs.to_form(pyslvs.parse_expression(text, "x"), [(0, 1)], "x")
    assert {"kind": "P", "point": "J1", "guide": "b", "block": "J1_block", "angle": "30deg"} in form["joints"]
    assert {"kind": "R", "point": "J1", "links": ["J1_block", "a", "c"]} in form["joints"]
    assert {"kind": "P", "point": "J2", "guide": "ground", "block": "c", "angle": "90deg"} in form["joints"]
    assert {"name": "b", "points": ["J3"]} in form["links"]
    assert form["inputs"] == [{"kind": "crank", "pivot": "J0", "point": "J1", "link": "a"}]
    slider = pyslvs.to_form(pyslvs.parse_expression("M[J[RP,A[0],P[0,0],L[ground,a]]]", "x"), [(0, 0)], "x")
    assert slider["inputs"] == [{"kind": "slider", "point": "J0"}]


def test_project_opens_directly_with_pyslvs_input_angle():
    m = analytic.load(str(EXAMPLES / "fourbar.pyslvs"))
    assert m.name == "fourbar" and m.units == "mm"
    assert m.inputs[0].link == "L1" and m.inputs[0].joint == "J0"
    assert m.inputs[0].motion.q0 == pytest.approx(math.atan2(21.6506, 12.5), abs=1e-15)   # the angle J0 -> J1
    r = run("analyze", str(EXAMPLES / "fourbar.pyslvs"), "--json", "--samples", "37")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["mechanism"] == "fourbar"


def test_rp_slider_crank_against_hand_geometry():
    m = mech_of("slider_crank_rp.txt", [(0, 1)])
    r, l = math.hypot(14.1421, 14.1421), math.hypot(72.4517 - 14.1421, 14.1421)
    q = np.linspace(0, 2 * np.pi, 37)
    pts = solved_points(m, q)
    x = r * np.cos(q) + np.sqrt(l * l - (r * np.sin(q)) ** 2)
    assert np.max(np.abs(pts["J2"][:, 0] - x)) <= HAND_TOL * m.size / m.scale
    assert np.max(np.abs(pts["J2"][:, 1])) <= HAND_TOL * m.size / m.scale


def test_quick_return_against_hand_geometry():
    """The lever through the crank's block: its slot keeps its distance from the pivot J2 (from the drawn pose:
    the slot at 70.8934 deg through J1), so its angle is atan2(J1) - asin(off / |J1|)."""
    m = mech_of("quick_return.txt", [(0, 1)])
    a0 = math.radians(70.8934)
    J1, J3 = np.array([12.9904, 37.5]), np.array([19.6396, 56.6947])
    r = np.linalg.norm(J1 - [0, 30])                  # the crank as drawn: 15.0000167
    off = math.cos(a0) * J1[1] - math.sin(a0) * J1[0]
    u3, v3 = J3 @ [math.cos(a0), math.sin(a0)], math.cos(a0) * J3[1] - math.sin(a0) * J3[0]
    q = np.linspace(0, 2 * np.pi, 37)
    pts = solved_points(m, q)
    crank = np.array([0, 30]) + r * np.stack([np.cos(q), np.sin(q)], axis=-1)
    th = np.arctan2(crank[:, 1], crank[:, 0]) - np.arcsin(off / np.linalg.norm(crank, axis=-1))
    tip = np.stack([u3 * np.cos(th) - v3 * np.sin(th), u3 * np.sin(th) + v3 * np.cos(th)], axis=-1)
    assert np.max(np.linalg.norm(pts["J3"] - tip, axis=-1)) <= HAND_TOL * 60


# --------------------------------------------------------------------------------------------- PMKS
def test_pmks_reading_quirks():
    """URL-encoded ``mech=``, a link called P, links separated by spaces, a capitalised Ground, ``d=``,
    settings ignored; joints named by line order."""
    joints, driver, flags = pmks.parse((EXAMPLES / "quirks.txt").read_text(), "q")
    assert driver == 0 and flags == [True, False, False, False, False]
    assert [(k, links) for k, _, _, links in joints] == [("R", ["ground", "crank"]), ("R", ["crank", "P"]),
                                                        ("R", ["P", "coupler2"]), ("R", ["P"]),
                                                        ("R", ["coupler2", "ground"])]
    form = pmks.to_form((EXAMPLES / "quirks.txt").read_text(), "q")
    assert form["inputs"] == [{"kind": "crank", "pivot": "J0", "point": "J1", "link": "crank"}]
    assert pmks.parse("input ground r 1 2 0 ffft|", "u")[0] == [("R", None, (1.0, 2.0), ["input", "ground"])]
    assert pmks._driving(["+--+"]) is False and pmks._driving(["True", "False", "false"]) is False


def test_pmks_block_with_an_offset_pin_against_hand_geometry():
    """PMKS ``ground,output,P``: the block output slides on the ground along x; its pin to the coupler is 3
    above the line, so the pin runs on y = 3."""
    m = mech_of("offset_block.txt")
    B0, C0 = np.array([0.0, 10.0]), np.array([22.0, 3.0])
    l = np.linalg.norm(C0 - B0)
    q = np.linspace(0, 2 * np.pi, 37)
    pts = solved_points(m, q)
    B = 10 * np.stack([np.cos(q), np.sin(q)], axis=-1)
    x = B[:, 0] + np.sqrt(l * l - (3 - B[:, 1]) ** 2)
    assert np.max(np.abs(pts["J2"][:, 0] - x)) <= HAND_TOL * 30
    assert np.max(np.abs(pts["J3"][:, 0] - (x + 0.0))) <= HAND_TOL * 30       # the block's P point, 3 below it


# ------------------------------------------------------------------------------------------ command
def test_import_writes_a_links_and_joints_file(tmp_path):
    out = tmp_path / "sc.toml"
    r = run("import", str(EXAMPLES / "slider_crank_rp.txt"), "--input", "0,1", "--out", str(out))
    assert r.returncode == 0, r.stderr
    assert "dyad RRP L2, J2_block at J2" in r.stdout
    data = tomllib.loads(out.read_text())
    assert set(data) >= {"pose", "links", "joints", "inputs"} and "groups" not in data
    assert data["units"] == "mm" and data["inputs"][0]["omega"] == "360deg"
    written, direct = analytic.load(str(out)), mech_of("slider_crank_rp.txt", [(0, 1)])
    q = np.linspace(0, 6, 13)
    a, b = written.solve(q), direct.solve(q)
    assert all(np.array_equal(a[k], b[k]) for k in direct.outputs)
    check_motion(written, data)
    r = run("check", str(out))
    assert r.returncode == 0 and "Assur groups: J2 (links L2, J2_block): dyad RRP" in r.stdout


@pytest.mark.parametrize("args,match", [
    (["fourbar.pkl.pyslvs"], r"is a pickled Pyslvs project \(binary\), which is never loaded"),
    (["gear.txt"], r"gear.txt: joints\[3\] \(point J1\): the pitch point J1 is at the centre J0 of input's gear \(a "
                 r"pitch radius of 0\); put it where the two pitch circles touch"),
    (["slider_crank_rp.txt"], r"a bare Pyslvs expression has no inputs; import it with 'linkage import"),
    (["slider_crank_rp.txt", "--input", "0,3"], r"input \(0, 3\): J0 and J3 share no moving link"),
    (["free.txt", "--input", "0,1"], r"joint J2 is a free point \(L\[\] names no link\)"),
    (["three.txt", "--input", "0,1"], r"joint J2 is a P joint on 3 links \(ground, L2, L3\); a prismatic pair joins "
                                      r"two links"),
    # a relative drive of a triangle (mobility 0): the motor's link is already placed by the dyad
    (["relative.txt"], r"inputs\[1\] \(joint J1\): link 'b' is already placed by other joints \(or driven twice; "
                       r"Gruebler: 3 x \(3 - 1\) - 2 x 3 = 0, with 1 input\)"),
    (["notes.txt"], r"not a Pyslvs project \(.pyslvs\), a Pyslvs expression \(M\[...\]\) or a PMKS text file"),
    (["locked_ppp.txt"], r"locked_ppp.txt: links a, b: the loop input - a - b - ground locks the mechanism"),
])
def test_import_bad_input_one_line_nothing_written(tmp_path, args, match):
    files = {"fourbar.pkl.pyslvs": b"\x80\x04\x95\x00", "gear.txt": b"ground,input,R,0,0\ninput,output,G,0,0\n"
             b"output,ground,R,5,0\n", "free.txt": b"M[J[R,P[0,0],L[ground,L1]],J[R,P[1,0],L[L1,L2]],J[R,P[2,2],L[]]]",
             "three.txt": b"M[J[R,P[0,0],L[ground,L1]],J[R,P[1,0],L[L1,L2]],J[P,A[0],P[3,0],L[ground,L2,L3]]]",
             "relative.txt": b"ground,a,R,0,0\na,b,R,1,0,tfft\nb,ground,R,3,1\n", "notes.txt": b"a list of things\n"}
    for name, raw in files.items():
        (tmp_path / name).write_bytes(raw)
    src = str(tmp_path / args[0]) if args[0] in files else str(EXAMPLES / args[0])
    out = tmp_path / "out.toml"
    r = run("import", src, *args[1:], "--out", str(out))
    assert r.returncode == 2 and r.stdout == "" and "Traceback" not in r.stderr
    assert r.stderr.count("\n") == 1
    assert __import__("re").search(match, r.stderr), r.stderr
    assert not out.exists()
    if args[0] in files:
        r = run("import", str(tmp_path / args[0]), "--out", str(tmp_path / "x.csv"))
        assert r.returncode == 2 and "unsupported output type '.csv'" in r.stderr


@pytest.mark.parametrize("name,inputs,rng", [("fourbar.pyslvs", None, None), ("slider_crank_rp.txt", [(0, 1)], None),
                                             ("quick_return.txt", [(0, 1)], None),
                                             ("moving_guide.txt", None, (-1.0, 1.5))])
def test_imported_examples_pass_compare(name, inputs, rng):
    m = mech_of(name, inputs)
    _, c = service.compare(m, 1.0, input_range=rng)
    assert c.passed


def test_the_app_opens_a_pyslvs_project():
    from sim.front.app import initial_mechanism
    first = initial_mechanism(str(EXAMPLES / "fourbar.pyslvs"))
    assert first["name"] == "fourbar" and "[[joints]]" in first["text"]
    with pytest.raises(FileError, match=r"locked_ppp.txt: links a, b: the loop input - a - b - ground locks"):
        initial_mechanism(str(EXAMPLES / "locked_ppp.txt"))


@pytest.mark.slow
def test_mangled_sources_are_one_line_each(tmp_path):
    """Seeded fuzz: our example files cut, spliced with format characters and deep nesting; every outcome is
    a mechanism or a ParameterError (one line), never another exception."""
    import random
    deep = tmp_path / "deep.pyslvs"
    deep.write_text("mechanism: " + "[" * 5000)
    with pytest.raises(FileError, match=r"deep.pyslvs: nested too deeply"):
        foreign.definition(deep)
    rng = random.Random(16)
    seeds = [(EXAMPLES / n).read_bytes() for n in ("fourbar.pyslvs", "slider_crank_rp.txt", "quirks.txt",
                                                     "moving_guide.txt")]
    for i in range(300):
        s = bytearray(rng.choice(seeds))
        for _ in range(rng.randint(1, 6)):
            k = rng.randrange(len(s) or 1)
            op = rng.random()
            if op < 0.4:
                del s[k:k + rng.randint(1, 5)]
            elif op < 0.85:
                s[k:k] = bytes(rng.choice(b"[](),:|=-.0123456789RPGJLAM# \n\x80eE") for _ in range(rng.randint(1, 4)))
            else:
                s[k:k] = b"[" * rng.randint(1, 3000)
        p = tmp_path / f"f{i}{rng.choice(['.pyslvs', '.txt'])}"
        p.write_bytes(bytes(s))
        try:
            kind = foreign.detect(p)
            if kind:
                foreign.definition(p, [(0, 1)] if kind == foreign.PYSLVS_EXPRESSION else None)
        except analytic.ParameterError as exc:
            assert "\n" not in str(exc)
