"""Seed 003 parameter studies: the sweep agrees with direct analysis, invalid sets are rows, bad grids fail."""

import csv
import math
import subprocess
import sys

import numpy as np
import pytest

from analytic import FiveBar, FourBar
from analytic.closed_forms import fivebar
from analytic.applications import studies

import cli_runner  # the command in this process (tests/cli_runner.py)


def run(*args):
    return cli_runner.run(*args)


def test_common_period_of_two_cranks():
    assert studies.common_period(2 * math.pi, 4 * math.pi)[:3] == (1.0, 1, 2)
    t, a, b = studies.common_period(2 * math.pi, 2 * math.pi * 2 / 3)
    assert (a, b) == (3, 2) and abs(t - 3.0) < 1e-12   # in 3 s crank 2 turns 3 times and crank 4 twice


def test_sweep_row_equals_a_direct_analysis():
    vary = {"l2": [0.05, 0.06], "omega4": [2 * math.pi, 4 * math.pi]}
    rows, _ = studies.sweep(FiveBar(), vary, samples=360)
    for r in rows:
        mech = FiveBar(**r.params)
        period = studies.common_period(mech.omega2, mech.omega4)[0]
        st = fivebar.solve(mech, *fivebar.drive(mech, np.linspace(0, period, 361)))
        speed = np.hypot(st.vxP, st.vyP)
        # same samples, same closed form: agreement to rounding; the mean over the period counts its closing
        # sample (t = period, the same instant as t = 0) once
        assert r.values["speed_mean"] == pytest.approx(speed[:-1].mean(), rel=1e-12)
        assert r.values["speed_max"] == pytest.approx(speed.max(), rel=1e-12)
        assert r.values["x_min"] == pytest.approx(st.xP.min(), abs=1e-15)
        assert r.values["S_min"] == pytest.approx(st.S.min(), abs=1e-15)


def test_sweep_agrees_with_linkage_analyze(tmp_path):
    out = tmp_path / "sweep.csv"
    r = run("sweep", "fivebar", "--vary", "l1=0.2,0.25", "--csv", str(out))
    assert r.returncode == 0, r.stderr
    sweep = list(csv.DictReader(out.open()))
    for row in sweep:
        a = tmp_path / "a.csv"
        r = run("analyze", "fivebar", "--set", f"l1={row['l1']}", "--samples", "361", "--csv", str(a))
        assert r.returncode == 0, r.stderr
        d = np.genfromtxt(a, delimiter=",", names=True)
        speed = np.hypot(d["vxP"], d["vyP"])
        assert float(row["speed_max"]) == pytest.approx(speed.max(), rel=1e-12)
        assert float(row["y_max"]) == pytest.approx(d["yP"].max(), rel=1e-12)


def test_invalid_combinations_are_rows_not_crashes():
    rows, _ = studies.sweep(FiveBar(), {"l1": [0.1, 0.2]})
    assert [r.valid for r in rows] == [False, True]
    assert "B and C can meet" in rows[0].reason
    rows, _ = studies.sweep(FourBar(), {"l1": [0.1, 0.29]})
    assert [r.valid for r in rows] == [True, False] and "cannot turn fully" in rows[1].reason


def test_area_of_a_circle_path():
    # l2 = l4, phi2 = phi4: link 3 translates, P runs on a circle of radius l2: area pi l2^2.
    rows, _ = studies.sweep(FiveBar(l2=0.07, l4=0.07, phi4_0=0.0), {"lp": [0.3]}, samples=2000)
    assert rows[0].values["area"] == pytest.approx(math.pi * 0.07 ** 2, rel=1e-5)   # polygon of 2000 sides


@pytest.mark.parametrize("args,pattern", [
    (["--vary", "bogus=1,2"], "'bogus' is not a parameter of fivebar"),
    (["--vary", "l1=0.3:0.2:5"], "empty or inverted"),
    (["--vary", "l1="], "no values"),
    (["--vary", "l1=0.2:0.3:100000", "--vary", "l2=0.01:0.02:101"], "add --yes"),
])
def test_bad_sweeps(args, pattern):
    r = run("sweep", "fivebar", *args)
    assert r.returncode == 2 and pattern in r.stderr and "Traceback" not in r.stderr


def test_sweep_plot_and_fourbar_coupler_curves(tmp_path):
    out = tmp_path / "family.png"
    r = run("sweep", "fourbar", "--vary", "ex=0.0,0.1,0.2", "--plot", str(out))
    assert r.returncode == 0, r.stderr
    assert out.stat().st_size > 10_000 and "3 combinations, 3 valid" in r.stdout


@pytest.mark.slow
def test_sweep_workers_give_the_same_csv(tmp_path):
    a, b = tmp_path / "one.csv", tmp_path / "two.csv"
    grid = ["--vary", "l1=0.1:0.3:50", "--vary", "l2=0.03:0.09:50"]          # 2500 rows: 2 chunks
    r = run("sweep", "fivebar", *grid, "--csv", str(a))
    assert r.returncode == 0, r.stderr
    r = run("sweep", "fivebar", *grid, "--csv", str(b), "--workers", "2")
    assert r.returncode == 0, r.stderr
    one, two = (list(csv.reader(f.open())) for f in (a, b))
    assert one[0] == two[0] and len(one) == len(two) == 2501
    # the same rows in the same order, computed in other processes: bit-identical numbers (the claim is
    # determinism for any number of workers, so no tolerance: any difference is the defect)
    num = [np.array([[float(v) for v in r] for r in t[1:]]) for t in (one, two)]
    assert np.array_equal(num[0], num[1], equal_nan=True)


@pytest.mark.slow
def test_sweep_scheduler_that_cannot_be_reached():
    r = run("sweep", "fivebar", "--vary", "l1=0.2,0.25", "--scheduler", "tcp://127.0.0.1:9")
    assert r.returncode == 2 and "--scheduler tcp://127.0.0.1:9" in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1


def test_workers_start_cleanly_after_a_compiled_solve():
    # a process that has run the compiled solver holds GNU OpenMP's threads: a worker forked from it was
    # killed at once (BrokenProcessPool); the pool's workers come from a fork server instead
    from analytic.solver import jit
    if not jit.AVAILABLE:
        pytest.skip("numba is not installed")
    code = ("import os, numpy as np, analytic\n"
            "os.environ['LINKAGE_JIT'] = '1'\n"
            "from analytic.applications import studies\n"
            "m = analytic.load('fivebar'); m.solve(*m.drive(np.linspace(0, 1, 5000)))\n"
            "from sim.run.parallel import mapper\n"
            "with mapper(2) as run:\n"
            "    rows, _ = studies.sweep_mechanism(m, {'l2': [0.05, 0.06, 0.07]}, 90, mapper=run)\n"
            "print(sum(r.valid for r in rows))\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    assert r.stdout.split()[-1] == "3"
