"""Seed 003: the complex-vector and matrix methods agree to rounding; a hand-checkable translation."""

import math

import numpy as np
import pytest

from analytic import ParameterError
from analytic.closed_forms import fivebar


@pytest.mark.parametrize("ratio", [1.0, 2.0, 0.5, -1.0, 3.0])
def test_complex_and_matrix_methods_agree(ratio):
    m = fivebar.FiveBar(omega4=2 * math.pi * ratio, alpha2=1.5, alpha4=-0.5)
    t = np.linspace(0, 2, 1001)
    a = fivebar.solve(m, *fivebar.drive(m, t), method="complex")
    b = fivebar.solve(m, *fivebar.drive(m, t), method="matrix")
    for name in fivebar.OUTPUTS:
        x, y = getattr(a, name), getattr(b, name)
        # two roundings of 2x2 algebra: a few hundred ulps of the output's peak at most
        assert np.abs(x - y).max() <= 1e-13 * max(1.0, np.abs(x).max()), name


def test_equal_cranks_in_phase_translate_link3():
    # l2 = l4 and phi2 = phi4 at equal speeds: C - B = l1 always, so S = l1, theta3 = 0 and link 3 translates.
    m = fivebar.FiveBar(l1=0.2, l2=0.07, l4=0.07, phi4_0=0.0)
    for method in fivebar.METHODS:
        st = fivebar.solve(m, *fivebar.drive(m, np.linspace(0, 1, 50)), method=method)
        assert np.allclose(st.S, 0.2, atol=1e-15) and np.allclose(st.theta3, 0, atol=1e-14)
        assert np.allclose([st.dS, st.omega3, st.ddS, st.alpha3], 0, atol=1e-12)
        # P then moves on B's circle shifted by lp along x.
        assert np.allclose(np.hypot(st.xP - m.lp, st.yP), m.l2, atol=1e-15)


def test_B_and_C_that_can_meet_are_refused():
    with pytest.raises(ParameterError, match=r"l1=0.1 must exceed l2 \+ l4"):
        fivebar.FiveBar(l1=0.1)


def test_unknown_method_is_refused():
    with pytest.raises(ParameterError, match="method"):
        fivebar.solve(fivebar.FiveBar(), 0, 0, 1, 1, method="newton")
