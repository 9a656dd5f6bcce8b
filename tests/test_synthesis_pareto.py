"""Multi-objective path synthesis (SPEC ``--objectives``; issue 29 items 2 and 3): the Pareto filter by hand,
the batch objectives against the single-design evaluations they stand for, every returned design checked in
MuJoCo (kinematics and forces under the same loads), and the command's front, CSV and plot."""

import csv
import json
import math
import subprocess
import sys

import numpy as np
import pytest

from analytic import ParameterError
from analytic.synthesis import path as sp
from analytic.synthesis.curves import FAMILIES
from sim.service import pareto as P

LIB = np.array([0.0, 0.0, 0.0, 0.3, 0.1, 0.3, 0.25, 0.15, 0.10])
"""The library four-bar (SPEC defaults) as a path design."""


def run(*args, timeout=900):
    return subprocess.run([sys.executable, "-m", "sim", *map(str, args)], capture_output=True, text=True,
                          timeout=timeout)


def lib_target(n=8):
    E, _ = FAMILIES["fourbar"].points(LIB[None], np.linspace(0, 2 * math.pi, n, endpoint=False), (1,))
    return sp.Target(E[0], closed=True)


def test_non_dominated_by_hand():
    F = np.array([[1, 5], [2, 3], [3, 4], [4, 1], [2, 3], [5, 5]], dtype=float)
    # (3, 4) is dominated by (2, 3); (5, 5) by everything; the two copies of (2, 3) dominate neither other
    assert sorted(P.non_dominated(F).tolist()) == [0, 1, 3, 4]


@pytest.mark.parametrize("text", ["error", "error,error", "error,speed", ""])
def test_bad_objectives_are_refused(text):
    with pytest.raises(ParameterError, match="--objectives"):
        P.parse_objectives(text)


def test_batch_objectives_match_the_single_design_evaluations():
    t = lib_target()
    opts = P.ParetoOptions(("error", "torque", "bearing", "shaking", "size"), force=(-50.0, 0.0), samples=73)
    moved = LIB * np.r_[1, 1, 1, 1.02, 1, 0.98, 1, 1, 1]
    X = np.array([np.r_[LIB, 0.75], np.r_[moved, 0.75]])
    F, G = P.evaluate(X, t, opts, "m")
    assert np.all(G <= 0)
    assert F[0, 0] < 1e-20 < F[1, 0]           # the exact design meets its own targets (rounding), the other not
    err, _ = sp.batch_error(X[:, :9], t, (1,), 192)
    np.testing.assert_array_equal(F[:, 0], err)
    for i in range(2):
        torque, bearing, shaking, _ = P.forces_of(FAMILIES["fourbar"], X[i, :9], (1,), "m", opts, 73)
        np.testing.assert_array_equal(F[i, 1:4], [torque, bearing, shaking])
        e = FAMILIES["fourbar"].extent(X[i:i + 1, :9], (1,), 256)[0]
        assert F[i, 4] == max(e[2] - e[0], e[3] - e[1])


def test_a_front_design_is_checked_in_mujoco_under_the_same_loads():
    t = lib_target()
    opts = P.ParetoOptions(("error", "torque"), force=(-50.0, 0.0))
    from analytic.synthesis import constraints as sc
    c = P.check(LIB, (1,), t, opts, "m", sc.Limits())
    assert c["problem"] == "" and c["simulated"]["passed"]
    s = c["simulated"]
    # MuJoCo's forces (a physics engine's equality-constraint forces: independent of the analytic
    # kinetostatics) agree with the analytic peaks; 2 % bounds its integration and constraint drift
    assert s["peak_torque"] == pytest.approx(c["peak_torque"], rel=0.02)
    assert s["peak_bearing"] == pytest.approx(c["peak_bearing"], rel=0.02)
    assert s["rms_shaking"] == pytest.approx(c["rms_shaking"], rel=0.02)
    # the 50 N force on E dominates: the shaking force's RMS is near 50 N (the frame reacts the load)
    assert 45 < c["rms_shaking"] < 60
    # without the load the torques are those of the links' inertia alone, far smaller
    c0 = P.check(LIB, (1,), t, P.ParetoOptions(("error", "torque")), "m", sc.Limits())
    assert c0["peak_torque"] < 0.2 * c["peak_torque"]


PRESS = np.column_stack([np.zeros(6), np.linspace(0.0, -75.0, 6)])
"""A press's stroke: six points down a 75 mm vertical line (mm), an open path."""


@pytest.mark.slow
@pytest.mark.parametrize("case", ["fourbar", "press"])
def test_front_trades_error_for_torque_and_every_design_passes_mujoco(tmp_path, case):
    """A four-bar path target under a 50 N side load, and a slider-crank press under a 500 N cutting load on
    its slow stroke: the front's designs trade path error for drive torque, shown by MuJoCo's numbers."""
    f = tmp_path / "t.csv"
    xy = lib_target().xy if case == "fourbar" else PRESS
    f.write_text("x,y\n" + "".join(f"{float(a)!r},{float(b)!r}\n" for a, b in xy))
    out, table, png = tmp_path / "f.toml", tmp_path / "front.csv", tmp_path / "front.png"
    args = (("--closed", "--force=-50,0") if case == "fourbar" else
            ("--type", "slider_crank", "--units", "mm", "--force=0,500", "--cutting", "--max-error", "10"))
    r = run("synthesize", "path", f, *args, "--objectives", "error,torque", "--popsize", 16,
            "--generations", 6, "--front", 4, "--json", "--out", out, "--csv", table, "--plot", png)
    assert r.returncode == 0, r.stderr
    data = json.loads(r.stdout)
    front = data["front"]
    assert 2 <= len(front) <= 4 and data["run"]["evaluations"] > 0
    for d in front:
        assert {"design", "error", "peak_torque", "peak_bearing", "rms_shaking", "size", "simulated"} <= set(d)
        assert d["simulated"]["passed"] and d["simulated"]["compare_passed"] and d["simulated"]["forces_passed"]
        assert d["transmission_deg"][0] >= 30 - 1e-6 and d["design"]["file"]
    # a two-objective front sorted by error has its torque falling: each design trades one for the other
    err = [d["error"] for d in front]
    tq = [d["peak_torque"] for d in front]
    assert err == sorted(err) and all(a > b for a, b in zip(tq, tq[1:]))
    # and MuJoCo's torques (its constraint forces: independent of the kinetostatics) say the same
    sim = [d["simulated"]["peak_torque"] for d in front]
    assert all(a > b for a, b in zip(sim, sim[1:]))
    # distinct designs, not copies
    names = FAMILIES["fourbar" if case == "fourbar" else "slider_crank"].names
    keys = [np.array([d["design"]["parameters"][k] for k in names]) for d in front]
    assert all(np.abs(keys[i] - keys[j]).max() > 1e-4 for i in range(len(keys)) for j in range(i))
    rows = list(csv.DictReader(line for line in table.read_text().splitlines() if not line.startswith("#")))
    assert len(rows) == len(front)
    assert [float(r_["peak_torque"]) for r_ in rows] == pytest.approx(tq, rel=1e-12)   # repr round trip
    assert png.stat().st_size > 10_000
