"""Hand-checkable four-bar geometry, branches, loop closure, Grashof table and limit positions."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from analytic import ParameterError
from analytic.closed_forms import fourbar
from analytic.closed_forms.fourbar import FourBar

ROUND = 1e-14       # a few ulps of lengths of order 1 m: what rounding alone leaves


def _pts(m, st):
    """The state with its joint coordinates xB, yB, xC, yC attached, for short assertions."""
    j = fourbar.joints(m, st)
    return SimpleNamespace(**vars(st), xB=j["B"][0], yB=j["B"][1], xC=j["C"][0], yC=j["C"][1])


def test_parallelogram_translates_the_coupler():
    m = FourBar(l1=0.1, l2=0.3, l3=0.1, l4=0.3, branch=1)
    phi1 = np.linspace(0.1, math.pi - 0.1, 50)          # away from the change points 0 and pi
    st = fourbar.solve(m, phi1, 2.0, 0.7)
    assert np.allclose(st.phi3, phi1, atol=ROUND)
    assert np.allclose(st.phi2, 0.0, atol=ROUND)
    assert np.allclose(st.omega3, 2.0, atol=ROUND) and np.allclose(st.omega2, 0.0, atol=ROUND)
    # rounding of omega^2 terms amplified by 1/sin(phi1) <= 10 near the ends of the range
    assert np.allclose(st.alpha3, 0.7, atol=1e-12) and np.allclose(st.alpha2, 0.0, atol=1e-12)
    # Every coupler point moves like B: its path is B's circle shifted by (ex, ey).
    assert np.allclose(np.hypot(st.xE - m.ex, st.yE - m.ey), m.l1, atol=ROUND)


def test_345_triangle_pose_by_hand():
    # A=(0,0), D=(0.4,0), B=(0,0.3) at phi1=90deg, C=(0.4,0.3): BC=0.4 horizontal, DC=0.3 vertical, BD=0.5.
    m = FourBar(l1=0.3, l2=0.4, l3=0.3, l4=0.4, ex=0.0, ey=0.0)
    st = _pts(m, fourbar.solve(m, math.pi / 2, 1.0))
    assert abs(st.xC - 0.4) < ROUND and abs(st.yC - 0.3) < ROUND
    assert abs(st.phi2) < ROUND and abs(st.phi3 - math.pi / 2) < ROUND
    assert abs(st.mu - math.pi / 2) < 1e-7           # arccos near 0 loses half the digits
    # vB = (-0.3, 0); vC = omega3 x DC = (-0.3 omega3, 0); vC - vB = omega2 x BC = (0, 0.4 omega2).
    assert abs(st.omega3 - 1.0) < ROUND and abs(st.omega2) < ROUND
    # The other branch reflects C across BD: C' = (0.4 - 0.32*..., ...) computed by reflection.
    mm = FourBar(l1=0.3, l2=0.4, l3=0.3, l4=0.4, ex=0.0, ey=0.0, branch=-1)
    other = _pts(mm, fourbar.solve(mm, math.pi / 2, 1.0))
    b, d, c = np.array([0, 0.3]), np.array([0.4, 0.0]), np.array([0.4, 0.3])
    u = (d - b) / 0.5
    mirror = b + 2 * np.dot(c - b, u) * u - (c - b)
    assert np.allclose([other.xC, other.yC], mirror, atol=ROUND)


@pytest.mark.parametrize("seed", range(5))
def test_branches_mirror_across_BD_and_close_the_loop(seed):
    rng = np.random.default_rng(seed)
    m = FourBar(0.1, 0.3, 0.25, 0.3, ex=0.15, ey=0.1)
    mm = FourBar(0.1, 0.3, 0.25, 0.3, ex=0.15, ey=0.1, branch=-1)
    phi1 = rng.uniform(-math.pi, math.pi, 200)
    p, q = _pts(m, fourbar.solve(m, phi1, 1.0)), _pts(mm, fourbar.solve(mm, phi1, 1.0))
    for st, sign in ((p, 1), (q, -1)):
        assert np.allclose(np.hypot(st.xC - st.xB, st.yC - st.yB), m.l2, atol=ROUND)
        assert np.allclose(np.hypot(st.xC - m.l4, st.yC), m.l3, atol=ROUND)
        cross = (m.l4 - st.xB) * (st.yC - st.yB) - (0 - st.yB) * (st.xC - st.xB)
        assert np.all(sign * cross > 0)
    # Mirror: the reflection of C(+1) across line BD is C(-1).
    bx, by = p.xB, p.yB
    ux, uy = (m.l4 - bx), (0 - by)
    n = np.hypot(ux, uy)
    ux, uy = ux / n, uy / n
    rx, ry = p.xC - bx, p.yC - by
    dot = rx * ux + ry * uy
    assert np.allclose(bx + 2 * dot * ux - rx, q.xC, atol=1e-13)
    assert np.allclose(by + 2 * dot * uy - ry, q.yC, atol=1e-13)


def test_change_point_branches_meet_when_collinear():
    m = FourBar(l1=0.1, l2=0.25, l3=0.15, l4=0.2)        # s + l = p + q = 0.35
    assert fourbar.grashof(m).chain == "change-point"
    mm = FourBar(0.1, 0.25, 0.15, 0.2, branch=-1)
    a, b = _pts(m, fourbar.solve(m, 0.0, 1.0)), _pts(mm, fourbar.solve(mm, 0.0, 1.0))
    # At phi1 = 0 all four pivots are collinear (|BD| = l2 - l3), so both assembly modes coincide;
    # the square root of a rounding-size discriminant leaves ~1e-8.
    assert math.hypot(a.xC - b.xC, a.yC - b.yC) < 1e-7
    assert abs(a.yC) < 1e-7 and a.mu < 1e-6


GRASHOF = (0.10, 0.25, 0.30, 0.35)       # s + l = 0.45 < p + q = 0.55
NON_GRASHOF = (0.10, 0.20, 0.25, 0.50)   # s + l = 0.60 > 0.45


@pytest.mark.parametrize("where,inversion,full", [
    ("l4", "double-crank", True), ("l1", "crank-rocker", True),
    ("l2", "double-rocker", False), ("l3", "rocker-crank", False)])
def test_grashof_table_over_the_four_inversions(where, inversion, full):
    s, p, q, l = GRASHOF
    others = iter((p, q, l))
    lengths = {k: (s if k == where else next(others)) for k in ("l1", "l2", "l3", "l4")}
    m = FourBar(**lengths)
    g = fourbar.grashof(m)
    assert (g.chain, g.inversion) == ("grashof", inversion)
    # The geometric reachability test (|BD| within [|l2-l3|, l2+l3]) agrees with the table.
    assert fourbar.crank_limits(m).full_turn is full


@pytest.mark.parametrize("where", ["l1", "l2", "l3", "l4"])
def test_non_grashof_is_a_triple_rocker_whose_crank_stops_at_dead_centres(where):
    s, p, q, l = NON_GRASHOF
    others = iter((p, q, l))
    m = FourBar(**{k: (s if k == where else next(others)) for k in ("l1", "l2", "l3", "l4")})
    assert fourbar.grashof(m).inversion == "triple-rocker"
    lim = fourbar.crank_limits(m)
    assert not lim.full_turn and lim.limit_angles
    for a in lim.limit_angles:
        # At a limit angle the coupler and rocker are collinear (mu = 0)...
        assert fourbar.solve(m, a, 1.0).mu < 1e-6
    lo, hi = lim.intervals[0]
    # ...and just outside the reachable interval the linkage cannot be assembled (NaN, not garbage).
    assert not fourbar.solve(m, lo - 1e-6, 1.0).valid and not fourbar.solve(m, hi + 1e-6, 1.0).valid
    assert fourbar.solve(m, 0.5 * (lo + hi), 1.0).valid


def test_unreachable_angle_names_the_angle_and_the_range():
    m = FourBar(l1=0.2, l2=0.3, l3=0.1, l4=0.3)
    with pytest.raises(ParameterError, match=r"phi1=0\.00deg.*reaches only"):
        fourbar.check_reachable(m, [0.0])


@pytest.mark.parametrize("kw,name", [({"l1": -1}, "l1"), ({"l2": float("nan")}, "l2"), ({"branch": 0}, "branch"),
                                     ({"l4": 2.0}, "l4"), ({"omega1": float("inf")}, "omega1")])
def test_bad_parameters_name_themselves(kw, name):
    with pytest.raises(ParameterError, match=name):
        FourBar(**kw)


@pytest.mark.parametrize("lengths", [(0.1, 0.3, 0.25, 0.3), (0.1, 0.25, 0.3, 0.35), (0.2, 0.3, 0.1, 0.3),
                                     (0.3, 0.1, 0.35, 0.25)])
def test_exact_transmission_extremes_bound_a_dense_sweep(lengths):
    m = FourBar(*lengths)
    lo, hi = fourbar.transmission_extremes(m)
    mu = fourbar.solve(m, np.linspace(-math.pi, math.pi, 200_001), 1.0).mu
    mu = mu[np.isfinite(mu)]
    # A sweep with step 3e-5 rad approaches the extremes within: O(step) at the kink of mu = 90 deg,
    # O(sqrt(step)) = 6e-3 at a dead centre (mu ~ sqrt(phi - limit)); it never passes them.
    tol = 1e-4 if fourbar.crank_limits(m).full_turn else 1e-2
    assert lo - 1e-12 <= mu.min() <= lo + tol and hi - tol <= mu.max() <= hi + 1e-12
