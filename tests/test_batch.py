"""Batch over designs (analytic/solver/batch.py) and ``linkage sweep`` on it: the same numbers as one
``Mechanism.solve`` per design, invalid designs flagged with the one-at-a-time reason, bad --vary refused."""

import csv
import math

import numpy as np
import pytest

import analytic
from analytic import ParameterError
from analytic.solver import batch
from analytic.applications import studies

import cli_runner  # the command in this process (tests/cli_runner.py)

MECHANISMS = ["fourbar", "fivebar", "slider_crank", "jansen", "watt_six_bar", "whitworth",
              "inverted_slider_crank", "stephenson_six_bar", "scotch_yoke", "elliptic_trammel"]


def run(*args):
    return cli_runner.run(*args)


def _random_designs(mech, k, seed):
    """Up to three length parameters of ``mech`` scattered by 5 % (seeded)."""
    rng = np.random.default_rng(seed)
    names = [p for p, kind in mech.definition.parameter_kind.items() if kind == "length"][:3]
    return {p: mech.values[p] * (1 + 0.05 * rng.standard_normal(k)) for p in names}


@pytest.mark.parametrize("name", MECHANISMS)
def test_batch_equals_one_solve_per_design(name):
    mech = analytic.load(name)
    k, n = 12, 40
    over = _random_designs(mech, k, seed=19)
    designs = batch.resolve(mech, over)
    t = np.broadcast_to(np.linspace(0.0, mech.duration(1.0), n), (k, n))
    sol = batch.solve(designs, *batch.drive(designs, t))
    checked = 0
    for i in range(k):
        params = {p: float(v[i]) for p, v in over.items()}
        try:
            one = mech.with_values(**params)
        except ParameterError as exc:                     # then the batch must say the same
            assert not designs.valid[i] and designs.reasons[i] == str(exc)
            continue
        assert designs.valid[i]
        ref = one.solve(*one.drive(t[i]))
        np.testing.assert_array_equal(sol.failed[i], ref.failed_index)
        for key in ref._arrays:
            a, b = ref._arrays[key], sol[key][i]
            np.testing.assert_array_equal(np.isnan(a), np.isnan(b))
            # same formulas on the same numbers: identical on numpy; with numba installed the reference
            # runs compiled (sin/cos within 2 ulp, amplified near singular poses: 5e-13 of the peak seen)
            peak = np.nanmax(np.abs(a)) if np.any(np.isfinite(a)) else 0.0
            np.testing.assert_allclose(b, a, rtol=0, atol=1e-10 * max(peak, 1e-9), equal_nan=True,
                                       err_msg=f"{name}: {key}")
        checked += 1
    assert checked >= k // 2                              # most scattered designs must assemble


def test_invalid_designs_are_flagged_with_the_single_design_reason():
    mech = analytic.load("fourbar")
    l2 = np.array([mech.values["l2"], 3.0, -0.1, mech.values["l2"]])
    designs = batch.resolve(mech, {"l2": l2})
    assert designs.valid.tolist() == [True, False, False, True]
    for i in (1, 2):
        with pytest.raises(ParameterError) as exc:
            mech.with_values(l2=float(l2[i]))
        assert designs.reasons[i] == str(exc.value)
    sol = batch.solve(designs, np.zeros((4, 3)))
    assert np.all(np.isnan(sol["xC"][1:3])) and np.all(np.isfinite(sol["xC"][[0, 3]]))


def test_a_design_that_cannot_close_fails_at_its_samples():
    mech = analytic.load("fourbar")
    # l2 = 0.5 passes the parameter checks but C cannot close at phi = 0 (see linkage sweep)
    designs = batch.resolve(mech, {"l2": [mech.values["l2"], 0.5]})
    assert designs.valid.all()
    sol = batch.solve(designs, np.zeros((2, 1)))
    assert sol.failed[0, 0] == -1 and sol.failed[1, 0] >= 0
    assert sol.labels[sol.failed[1, 0]] == "groups[1] (point C)"


def test_designs_on_both_branches_are_grouped_and_each_right():
    mech = analytic.load("fourbar")
    designs = batch.resolve(mech, {"branch": [1, -1, 1, -1]})
    assert len(designs.groups) == 2
    q = np.full((4, 1), 0.7)
    sol = batch.solve(designs, q)
    for i, b in enumerate((1, -1, 1, -1)):
        ref = mech.with_values(branch=float(b)).solve(np.array([0.7]))
        assert sol["yC"][i, 0] == pytest.approx(ref["yC"][0], abs=1e-15)    # same arithmetic: rounding
    assert sol["yC"][0, 0] != pytest.approx(sol["yC"][1, 0], abs=1e-6)     # the two roots differ


def test_sweep_rows_against_one_solve_per_design():
    base = analytic.load("fivebar")
    vary = {"l2": [0.05, 0.06], "omega4": [2 * math.pi, 4 * math.pi, 0.0]}
    rows, _ = studies.sweep_mechanism(base, vary, samples=90)
    assert len(rows) == 6 and all(r.valid for r in rows)
    for r in rows:
        one = base.with_values(**r.params)
        t = np.linspace(0.0, studies.period_of(one), 91)
        sol = one.solve(*one.drive(t))
        x, y, v = sol["xP"], sol["yP"], np.hypot(sol["vxP"], sol["vyP"])
        # the same samples and formulas: rounding of the time grid (T*u vs linspace(0, T)) only; the mean over
        # the period counts its closing sample (the instant t = 0 again) once
        assert r.values["speed_mean"] == pytest.approx(v[:-1].mean(), rel=1e-12)
        assert r.values["speed_min"] == pytest.approx(v.min(), rel=1e-12)
        assert r.values["x_max"] == pytest.approx(x.max(), abs=1e-14)
        assert r.values["y_min"] == pytest.approx(y.min(), abs=1e-14)
        assert r.values["period"] == pytest.approx(t[-1], rel=1e-15)
        area = 0.5 * abs(np.sum(x[:-1] * np.roll(y[:-1], -1) - np.roll(x[:-1], -1) * y[:-1]))
        assert r.values["area"] == pytest.approx(area, rel=1e-10)
        assert "mu_min" not in r.values                   # no RRR group: no transmission angle, no NaN
        assert all(math.isfinite(v) for v in r.values.values())


def test_sweep_four_bar_mu_min_and_invalid_rows():
    base = analytic.load("fourbar")
    rows, _ = studies.sweep_mechanism(base, {"l2": [base.values["l2"], 0.5, 3.0]}, samples=180)
    assert [r.valid for r in rows] == [True, False, False]
    assert "cannot close at t=0 s" in rows[1].reason and "shorter than the other three" in rows[2].reason
    one = base
    t = np.linspace(0.0, one.duration(1.0), 181)
    assert rows[0].values["mu_min"] == pytest.approx(np.nanmin(one.solve(*one.drive(t))["muC"]), abs=1e-14)


def test_sweep_cli_refuses_degrees_for_lengths_and_set_with_vary(tmp_path):
    r = run("sweep", "fivebar", "--vary", "l2=4deg,6deg")
    assert r.returncode == 2 and "l2 is a length" in r.stderr and "Traceback" not in r.stderr
    r = run("sweep", "fivebar", "--set", "l2=0.05", "--vary", "l2=0.04,0.06")
    assert r.returncode == 2 and "--vary l2 and --set l2" in r.stderr
    out = tmp_path / "s.csv"
    r = run("sweep", "fivebar", "--vary", "omega4=0,360deg", "--csv", str(out))
    assert r.returncode == 0, r.stderr
    rows = list(csv.DictReader(out.open()))
    assert len(rows) == 2
    for row in rows:                                      # a valid row carries no NaN
        assert row["valid"] == "1" and all(math.isfinite(float(v)) for v in row.values())
