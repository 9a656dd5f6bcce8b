"""The general solver (any linkage/1 file): equal to the three dedicated closed forms, every element
kind and both branches against finite differences, NaN with the failing group named."""

import math

import numpy as np
import pytest

import analytic
from analytic import ParameterError
from analytic.closed_forms import closed_form

HERE = __import__("pathlib").Path(__file__).parent / "mechanisms"


def _wrap(d):
    return np.pi - np.mod(np.pi - d, 2 * np.pi)


@pytest.mark.parametrize("name,values", [
    ("fourbar", {}), ("fourbar", {"branch": -1, "ex": -0.05, "ey": 0.2, "phi1_0": 0.4}),
    ("fourbar", {"l1": 0.2, "l3": 0.1}),                      # a rocker: NaN where it cannot assemble
    ("sixbar", {}), ("sixbar", {"l1": 0.09, "l4": 0.2, "branch": -1}),
    ("fivebar", {}), ("fivebar", {"l1": 0.25, "l2": 0.05, "l4": 0.07, "lp": 0.2}),
])
def test_the_general_solver_equals_the_dedicated_closed_forms(name, values):
    mech = analytic.load(name, **values)
    rng = np.random.default_rng(7)
    n = 2000
    k = len(mech.inputs)
    q = rng.uniform(-math.pi, math.pi, (n, k))
    qd = rng.normal(0.0, 5.0, (n, k))
    qdd = rng.normal(0.0, 30.0, (n, k))
    general = mech.solve(q, qd, qdd)
    closed = closed_form(mech, q, qd, qdd)
    size = mech.size
    for out in mech.outputs:
        a, b = np.asarray(general[out]), closed[out]
        assert np.array_equal(np.isnan(a), np.isnan(b)), out          # the same samples fail to assemble
        ok = np.isfinite(b)
        if out.startswith(("phi", "theta", "mu")):
            err, tol = np.abs(_wrap(a[ok] - b[ok])).max(), 1e-12           # [rad] rounding
        elif out in ("s", "S", "xC", "xE", "yE", "xP", "yP"):
            err, tol = np.abs(a[ok] - b[ok]).max(), 1e-12 * size           # positions: rounding of the size
        else:
            err, tol = np.abs(a[ok] - b[ok]).max(), 1e-10 * np.abs(b[ok]).max()   # rates: 1e-10 of the peak
        assert err <= tol, (out, err, tol)


def _finite_difference_check(mech, t):
    """Velocities against central differences of positions, accelerations against those of velocities
    (h = 1e-6 s: truncation ~h^2 x third derivative ~1e-10 of the peak, rounding ~1e-16/h ~1e-10)."""
    h = 1e-6
    sol = mech.solve(*mech.drive(t))
    plus, minus = mech.solve(*mech.drive(t + h)), mech.solve(*mech.drive(t - h))
    checked = 0
    for p in mech.points:
        for pos, vel, acc in ((f"x{p}", f"vx{p}", f"ax{p}"), (f"y{p}", f"vy{p}", f"ay{p}")):
            fd_v = (plus[pos] - minus[pos]) / (2 * h)
            fd_a = (plus[vel] - minus[vel]) / (2 * h)
            vscale = max(np.abs(sol[vel]).max(), 1e-3)
            ascale = max(np.abs(sol[acc]).max(), 1e-3)
            assert np.abs(fd_v - sol[vel]).max() <= 1e-6 * vscale, (p, pos)
            assert np.abs(fd_a - sol[acc]).max() <= 1e-6 * ascale, (p, acc)
            checked += 1
    for ln in mech.links:
        fd_w = _wrap(plus["phi" + ln] - minus["phi" + ln]) / (2 * h)
        assert np.abs(fd_w - sol["omega" + ln]).max() <= 1e-6 * max(np.abs(sol["omega" + ln]).max(), 1.0), ln
        fd_a = (plus["omega" + ln] - minus["omega" + ln]) / (2 * h)
        assert np.abs(fd_a - sol["alpha" + ln]).max() <= 1e-6 * max(np.abs(sol["alpha" + ln]).max(), 1.0), ln
    for j in mech.slides:
        fd = (plus["s" + j] - minus["s" + j]) / (2 * h)
        assert np.abs(fd - sol["ds" + j]).max() <= 1e-6 * max(np.abs(sol["ds" + j]).max(), 1e-3), j
        fd = (plus["ds" + j] - minus["ds" + j]) / (2 * h)
        assert np.abs(fd - sol["dds" + j]).max() <= 1e-6 * max(np.abs(sol["dds" + j]).max(), 1e-3), j
    return checked


@pytest.mark.parametrize("path", ["slider_driven.toml", "moving_guide.toml"])
@pytest.mark.parametrize("branch", [1, -1])
def test_every_element_kind_and_both_branches_against_finite_differences(path, branch):
    text = (HERE / path).read_text().replace("branch = 1", f"branch = {branch}")
    mech = analytic.from_text(text, path)
    t = np.linspace(0.0, 0.6, 61)
    sol = mech.solve(*mech.drive(t))
    assert sol.valid.all(), sol.first_failure()
    assert _finite_difference_check(mech, t) >= 2 * len(mech.points)


def test_branches_put_the_point_on_the_side_they_name():
    # RRR branch +1: C left of B -> D (positive cross product), -1: right.
    for branch in (1, -1):
        m = analytic.load("fourbar", branch=branch)
        s = m.solve(np.linspace(0, 2 * np.pi, 50))
        cross = (s["xD"] - s["xB"]) * (s["yC"] - s["yB"]) - (s["yD"] - s["yB"]) * (s["xC"] - s["xB"])
        assert np.all(np.sign(cross) == branch)


def test_a_slider_input_moves_its_point_along_the_guide_in_file_units():
    mech = analytic.from_text((HERE / "slider_driven.toml").read_text())
    (q, qd, qdd), sol = mech.solve_at([0.0, 1.0])
    # s(t) = s0 + v t + a t^2 / 2 in mm, converted to m: 60 mm, then 60 + 30 - 2.5 = 87.5 mm
    assert sol["xB"] == pytest.approx([0.060, 0.0875], abs=1e-15)
    assert sol["vxB"] == pytest.approx([0.030, 0.025], abs=1e-15)
    assert sol["axB"] == pytest.approx([-0.005, -0.005], abs=1e-15)


def test_nan_where_a_group_cannot_assemble_and_the_group_is_named():
    mech = analytic.load("fourbar", l1=0.2, l3=0.1)
    sol = mech.solve(np.radians([60.0, 0.0, 80.0]))
    assert list(sol.valid) == [True, False, True]
    assert np.isnan(sol["phi3"][1]) and np.isfinite(sol["phi3"][0])
    assert sol.first_failure() == (1, "groups[1] (point C)")
    with pytest.raises(analytic.AssemblyError, match=r"at phi1=0\.00deg: groups\[1\] \(point C\) cannot close; "
                                                    r"phi1 assembles in -104\.47deg\.\.-41\.41deg or 41\.41deg\.\.104\.47deg"):
        mech.check_assembles(np.radians([60.0, 0.0]))


def test_transmission_angle_per_rrr_group_matches_hand_geometry():
    # At phi1 = 0 the four-bar's B is nearest D: cos(mu) = (l2^2 + l3^2 - (l4 - l1)^2) / (2 l2 l3)
    sol = analytic.load("fourbar").solve([0.0])
    assert sol["muC"][0] == pytest.approx(math.acos((0.09 + 0.0625 - 0.04) / (2 * 0.3 * 0.25)), abs=1e-15)
    assert sol["mu"][0] == sol["muC"][0]                        # SPEC's alias


def test_several_inputs_take_an_n_by_k_array():
    mech = analytic.load("fivebar")
    with pytest.raises(ParameterError, match=r"2 inputs: give q of shape \(N, 2\)"):
        mech.solve(np.zeros(5))
    assert mech.solve(np.zeros((5, 2)))["S"].shape == (5,)
