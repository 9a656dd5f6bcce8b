"""Path synthesis under the limits every synthesis type takes (SPEC, "Synthesis constraints and budgets"):
the search's size (each family's sampled extent), pivot boxes and Grashof type against the general solver
reading the written file (:func:`analytic.synthesis.constraints.measure`, independent code) and hand
geometry; the constrained polish ending inside a size limit; budgets: ``--evaluations`` reproducible,
``--budget`` a hard wall-clock limit."""

import json
import math
import subprocess
import sys
import time

import numpy as np
import pytest

from analytic.registry import from_text
from analytic.synthesis import constraints as sc
from analytic.synthesis import path as sp
from analytic.synthesis.curves import FAMILIES
from sim.service import design as design_service

LIB = np.array([0.0, 0.0, 0.0, 0.3, 0.1, 0.3, 0.25, 0.15, 0.10])
"""The library four-bar (SPEC defaults) as a path design: A = (0, 0), D = (0.3, 0), a crank-rocker."""


def run(*args, timeout=600):
    return subprocess.run([sys.executable, "-m", "sim", *map(str, args)], capture_output=True, text=True,
                          timeout=timeout)


def lib_target(n=8):
    E, _ = FAMILIES["fourbar"].points(LIB[None], np.linspace(0, 2 * math.pi, n, endpoint=False), (1,))
    return sp.Target(E[0], closed=True)


def solver_measure(name, x, branch):
    fam = FAMILIES[name]
    mech = from_text(fam.text(x, branch, "m", "t", "d"), "<t>")
    return sc.measure(mech, 0.0, 2 * math.pi, 20001)


@pytest.mark.parametrize("name,seed", [("fourbar", 1), ("slider_crank", 2), ("watt", 3), ("stephenson", 4)])
def test_family_extent_matches_the_general_solver(name, seed):
    fam = FAMILIES[name]
    rng = np.random.default_rng(seed)
    cons = sp.Constraints(mu_min=math.radians(25))
    for _ in range(4000):
        b = fam.branches[rng.integers(len(fam.branches))]
        x = fam.shape(rng.random((1, fam.shape_dim)))[0]
        if sp.shape_violation(x[None], cons, b, fam, 4096)[0] == 0:
            break
    else:
        pytest.fail("no feasible shape drawn")
    m = solver_measure(name, x, b)
    e = fam.extent(x[None], b, 512)[0]
    scale = m.size
    # 512 samples miss an extreme by at most 1 - cos(pi / 512) = 1.9e-5 of its radius (<= the size)
    np.testing.assert_allclose(e, m.box, atol=2e-5 * scale)
    assert fam.pivot_names == tuple(p for p in m.pivots)       # the file's ground pivots, in order


def test_size_box_and_grashof_limits_by_hand():
    t = lib_target()
    size = solver_measure("fourbar", LIB, (1,)).size
    base = sp.Constraints()
    assert sp.violation(LIB[None], base, t)[0] == 0
    assert sp.violation(LIB[None], sp.Constraints(max_size=size * 1.001), t)[0] == 0
    over = sp.Constraints(max_size=size * 0.99)
    assert sp.violation(LIB[None], over, t)[0] > 0
    assert "--max-size" in sp.failed_constraint(LIB, over, t)
    # A = (0, 0) and D = (0.3, 0)
    inside = sp.Constraints(boxes=(("A", -0.01, 0.01, -0.01, 0.01), ("D", 0.29, 0.31, -0.01, 0.01)))
    assert sp.violation(LIB[None], inside, t)[0] == 0
    outside = sp.Constraints(boxes=(("D", 0.31, 0.5, -0.01, 0.01),))
    assert sp.violation(LIB[None], outside, t)[0] > 0
    assert "ground pivot D" in sp.failed_constraint(LIB, outside, t)
    # crank 0.1 the shortest of (0.3, 0.1, 0.3, 0.25): a crank-rocker, not a double-crank
    assert sp.violation(LIB[None], sp.Constraints(grashof="crank-rocker"), t)[0] == 0
    dc = sp.Constraints(grashof="double-crank")
    assert sp.violation(LIB[None], dc, t)[0] > 0 and "double-crank" in sp.failed_constraint(LIB, dc, t)


def test_max_ratio_by_hand():
    # the library four-bar's links (ground 0.3, crank 0.1, coupler 0.3, rocker 0.25): longest/shortest 3 exactly
    t = lib_target()
    assert sp.violation(LIB[None], sp.Constraints(max_ratio=3.01), t)[0] == 0
    over = sp.Constraints(max_ratio=2.9)
    assert sp.violation(LIB[None], over, t)[0] > 0                  # the search's penalty sees it
    assert "link-length ratio above 2.9" in sp.failed_constraint(LIB, over, t)    # and the final check says it


def test_margins_hold_exactly_where_nothing_is_violated_with_the_new_limits():
    fam = FAMILIES["fourbar"]
    rng = np.random.default_rng(8)
    t = sp.Target(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]))
    cons = sp.Constraints(mu_min=math.radians(20), max_size=12.0, boxes=(("D", -3.0, 3.0, -3.0, 3.0),),
                          grashof="crank-rocker")
    seen = {True: 0, False: 0}
    for _ in range(400):
        b = fam.branches[rng.integers(2)]
        while True:                                  # shapes meeting the shape-only limits; size and box vary
            x = fam.shape(rng.random((1, fam.shape_dim)))
            if sp.shape_violation(x, cons, b)[0] == 0:
                break
        z = rng.uniform(0.2, 1.5) * np.exp(1j * rng.uniform(-math.pi, math.pi))
        x = fam.move(x, z, complex(*rng.normal(0, 2, 2)))[0]
        ok = sp.violation(x[None], cons, t, b)[0] == 0
        assert ok == bool(np.all(sp.margins(x[None], cons, t, b)[0] >= 0))
        seen[ok] += 1
    assert min(seen.values()) > 20                   # both sides drawn


def test_polish_ends_inside_a_size_limit_as_the_solver_measures_it():
    t = lib_target(12)
    size = solver_measure("fourbar", LIB, (1,)).size
    cons = sp.Constraints(max_size=0.97 * size)      # the exact design is 3 % too big: the polish must shrink it
    d = sp.polish(LIB, (1,), t, cons)
    assert d.violation == 0 and d.failed == "" and d.stats["evaluations"] > 0
    m = solver_measure("fourbar", d.x, d.branch)
    assert m.size <= 0.97 * size * (1 + sc.SLACK_REL)   # what the command's check demands
    assert d.sum_sq > 0                               # it had to leave the exact design


def test_deadline_stops_a_polish_and_keeps_the_start():
    t = lib_target(12)
    start = LIB * np.r_[1, 1, 1, 1.05, 1, 1, 1, 1, 1]
    d = sp.polish(start, (1,), t, sp.Constraints(), deadline=time.time() - 1.0)   # already past
    # nothing evaluated beyond the start's angles and its own finish (two evaluations on the targets,
    # both counted since issue 41): the start comes back
    assert np.array_equal(d.x, start) and d.stats["evaluations"] == 2


def test_evaluations_exclude_a_budget():
    # (--evaluations no longer sets the generations up front: the restarts' caps do, issue 41)
    with pytest.raises(Exception, match="--evaluations and --budget"):
        design_service.PathOptions(evaluations=1000, budget=5.0).check()
    r = run("synthesize", "path", "x.csv", "--evaluations", "100", "--budget", "3")
    assert r.returncode == 2 and "not allowed with" in r.stderr


def test_a_region_for_a_pivot_the_type_lacks_is_refused(tmp_path):
    f = tmp_path / "t.csv"
    f.write_text("x,y\n0,0\n1,0\n1,1\n0,1\n")
    r = run("synthesize", "path", str(f), "--type", "slider_crank", "--pivot-region", "D=0:1,0:1")
    assert r.returncode == 2 and "--pivot-region D" in r.stderr and "Traceback" not in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1


# ------------------------------------------------------------------------------------ slow: searches
def write_target(path, t):
    path.write_text("x,y\n" + "".join(f"{float(a)!r},{float(b)!r}\n" for a, b in t.xy))
    return str(path)


@pytest.mark.slow
def test_every_returned_path_design_meets_the_limits_as_written(tmp_path):
    t = lib_target(8)
    f = write_target(tmp_path / "t.csv", t)
    out = tmp_path / "d.toml"
    r = run("synthesize", "path", f, "--closed", "--restarts", 2, "--generations", 10, "--designs", 2,
            "--max-size", "0.5", "--pivot-region", "A=-0.2:0.2,-0.2:0.2", "--grashof", "crank-rocker",
            "--min-transmission", "35deg", "--json", "--out", out)
    assert r.returncode == 0, r.stderr
    data = json.loads(r.stdout)
    assert data["designs"] and data["run"]["evaluations"] > 0
    for d in data["designs"]:
        mech = from_text(open(d["file"]).read(), d["file"])
        m = sc.measure(mech, *d["input_range"], n=20001, lengths=tuple(d["parameters"][k] for k in "abcd"))
        assert m.size <= 0.5 and m.transmission_deg[0] >= 35 - 1e-3        # 20001 samples vs 3601: 1e-3 deg
        assert -0.2 <= m.pivots["A"][0] <= 0.2 and -0.2 <= m.pivots["A"][1] <= 0.2
        assert m.grashof == "crank-rocker" and d["grashof"] == "crank-rocker"
        assert d["size"] == pytest.approx(m.size, rel=1e-4)               # 3601 samples vs 20001
        assert d["evaluations"] == data["run"]["evaluations"]


@pytest.mark.slow
def test_evaluations_give_the_same_answer_on_one_and_two_workers(tmp_path):
    f = write_target(tmp_path / "t.csv", lib_target(8))
    args = ("synthesize", "path", f, "--closed", "--restarts", 2, "--evaluations", 3000, "--seed", 5, "--json")
    a, b = run(*args), run(*args, "--workers", 2)
    assert a.returncode == 0 and b.returncode == 0, a.stderr + b.stderr
    da, db = json.loads(a.stdout), json.loads(b.stdout)
    # determinism, not accuracy: the same seeded jobs give bit-identical designs and counts in any process
    assert [d["parameters"] for d in da["designs"]] == [d["parameters"] for d in db["designs"]]
    assert da["run"]["evaluations"] == db["run"]["evaluations"] and not da["run"]["stopped_by_budget"]
    assert da["run"]["evaluations"] <= 3000                        # the bound holds (issue 41)


@pytest.mark.slow
def test_budget_is_a_hard_wall_clock_limit(tmp_path):
    """``--budget 3`` on the literature's densest target (Ullah and Kota, 142 points; the default search
    takes minutes) returns within the budget plus 1 s. The command's own clock (``run.seconds``: from the
    synthesis's start to its answer, checks included) is held to that; the process's wall time is held to it
    plus the interpreter's start-up (imports of numpy, scipy and MuJoCo), measured in the same test so a
    loaded machine slows both alike."""
    data = __import__("pathlib").Path(__file__).resolve().parents[1] / "benchmarks" / "data" / "path_ullah.csv"
    t0 = time.monotonic()
    subprocess.run([sys.executable, "-c", "import sim.service.design, scipy.optimize, mujoco, "
                    "sim.front.cli"], check=True, timeout=120)
    startup = time.monotonic() - t0
    t0 = time.monotonic()
    r = run("synthesize", "path", data, "--any-order", "--budget", 3, "--json")
    wall = time.monotonic() - t0
    assert r.returncode in (0, 1), r.stderr
    out = json.loads(r.stdout)
    assert out["run"]["stopped_by_budget"] is True
    assert out["run"]["seconds"] <= 3 + 1.0
    assert wall <= 3 + 1.0 + 1.5 * startup           # start-up measured above, with half again for its spread


def test_grashof_for_a_slider_crank_is_refused():
    with pytest.raises(Exception, match="--grashof crank-rocker applies to a four-bar loop"):
        design_service.PathOptions(types=("slider_crank",), grashof="crank-rocker").check()
