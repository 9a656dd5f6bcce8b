"""Velocities and accelerations equal central finite differences of the positions along a run.

Step h = 1e-4 s with crank speeds of ~2 pi rad/s: the truncation error of a central difference is
(h^2 / 6) |x'''| ~ (h omega)^2 / 6 ~ 7e-8 of the peak for the fundamental, up to ~100x that for the
linkages' higher harmonics; rounding adds eps |x| / h ~ 1e-12. Tolerance: 1e-5 of the peak rate.
"""

import math

import numpy as np
import pytest

from analytic.closed_forms import fivebar
from analytic.closed_forms import fourbar
from analytic.closed_forms import sixbar

H = 1e-4
TOL = 1e-5


def _fd(f, t):
    return (f(t + H) - f(t - H)) / (2 * H)


def _check(pos_fn, rate_fn, t, name):
    fd = _fd(pos_fn, t)
    ref = rate_fn(t)
    assert np.abs(fd - ref).max() <= TOL * np.abs(ref).max(), name


@pytest.mark.parametrize("branch", [1, -1])
def test_fourbar_rates(branch):
    m = fourbar.FourBar(branch=branch, alpha1=3.0)
    t = np.linspace(0, 1, 397)

    def st(t):
        return fourbar.solve(m, *fourbar.drive(m, t))

    for pos, vel, acc in [("phi2", "omega2", "alpha2"), ("phi3", "omega3", "alpha3"),
                          ("xE", "vxE", "axE"), ("yE", "vyE", "ayE")]:
        if pos.startswith("phi"):
            fd = np.angle(np.exp(1j * (getattr(st(t + H), pos) - getattr(st(t - H), pos)))) / (2 * H)
            ref = getattr(st(t), vel)
            assert np.abs(fd - ref).max() <= TOL * np.abs(ref).max(), vel
        else:
            _check(lambda t: getattr(st(t), pos), lambda t: getattr(st(t), vel), t, vel)
        _check(lambda t: getattr(st(t), vel), lambda t: getattr(st(t), acc), t, acc)


def test_sixbar_rates():
    m = sixbar.SixBar(alpha1=3.0)
    t = np.linspace(0, 1, 397)

    def st(t):
        return sixbar.solve(m, *sixbar.drive(m, t))

    for pos, vel, acc in [("s", "ds", "dds"), ("phi3", "omega3", "alpha3"), ("phi4", "omega4", "alpha4"),
                          ("xC", "vxC", "axC")]:
        _check(lambda t: getattr(st(t), pos), lambda t: getattr(st(t), vel), t, vel)
        _check(lambda t: getattr(st(t), vel), lambda t: getattr(st(t), acc), t, acc)


@pytest.mark.parametrize("method", fivebar.METHODS)
@pytest.mark.parametrize("omega4", [2 * math.pi, 4 * math.pi, -2 * math.pi])
def test_fivebar_rates(method, omega4):
    m = fivebar.FiveBar(omega4=omega4, alpha2=2.0, alpha4=-1.0)
    t = np.linspace(0, 1, 397)

    def st(t):
        return fivebar.solve(m, *fivebar.drive(m, t), method=method)

    for pos, vel, acc in [("S", "dS", "ddS"), ("xP", "vxP", "axP"), ("yP", "vyP", "ayP")]:
        _check(lambda t: getattr(st(t), pos), lambda t: getattr(st(t), vel), t, vel)
        _check(lambda t: getattr(st(t), vel), lambda t: getattr(st(t), acc), t, acc)
    fd = np.angle(np.exp(1j * (st(t + H).theta3 - st(t - H).theta3))) / (2 * H)
    assert np.abs(fd - st(t).omega3).max() <= TOL * np.abs(st(t).omega3).max()
    _check(lambda t: st(t).omega3, lambda t: st(t).alpha3, t, "alpha3")
