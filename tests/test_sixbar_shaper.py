"""Shaper figures: quick-return ratio from the stroke timing, stroke, limit positions, bad geometry."""

import math

import numpy as np
import pytest

from analytic import ParameterError
from analytic.closed_forms import sixbar


def test_quick_return_ratio_matches_the_timing_of_the_ram():
    m = sixbar.SixBar()
    f = sixbar.figures(m)
    t = np.linspace(0, 1, 400_001)           # one revolution; 2.5e-6 s resolution
    st = sixbar.solve(m, *sixbar.drive(m, t))
    t_max, t_min = t[np.argmax(st.xC)], t[np.argmin(st.xC)]
    slow = (t_min - t_max) % 1.0             # ram right -> left while the crank turns pi + theta
    # ratio of two durations, each known to the time step 2.5e-6 s
    assert abs(slow / (1 - slow) - f.K) < 1e-4
    assert abs(f.K - (math.pi + f.swing) / (math.pi - f.swing)) < 1e-15
    assert abs(np.ptp(st.xC) - f.stroke) < 1e-8   # sampled extremes differ from exact by O(dt^2)


def test_limit_positions_are_where_the_crank_is_perpendicular_to_the_guide():
    m = sixbar.SixBar()
    f = sixbar.figures(m)
    st = sixbar.solve(m, np.array(f.phi1_limits), 1.0)
    assert np.allclose(st.omega3, 0.0, atol=1e-15)          # the guide bar stops
    assert np.allclose(st.phi3, [math.pi / 2 - f.psi, math.pi / 2 + f.psi], atol=1e-15)
    assert np.allclose(st.xC, f.xC_limits, atol=1e-15)


def test_default_ram_line_halves_the_sagitta():
    m = sixbar.SixBar()
    psi = math.asin(m.l1 / m.l6)
    assert abs(m.h - 0.5 * (m.l3 + m.l3 * math.cos(psi))) < 1e-15


@pytest.mark.parametrize("kw,pattern", [({"l3": 0.4}, "run off the guide bar"),
                                         ({"l1": 0.4}, "l1=0.4 must be shorter than l6"),
                                         ({"l4": 0.01}, "cannot reach the ram line"),
                                         ({"h": 0.2}, "cannot reach the ram line")])
def test_bad_shaper_geometry_is_refused(kw, pattern):
    with pytest.raises(ParameterError, match=pattern):
        sixbar.SixBar(**kw)
