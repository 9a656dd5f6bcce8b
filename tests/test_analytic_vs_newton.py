"""The closed forms agree with an independent Newton solver on the loop equations (issue targets).

Targets: positions <= 1e-12 (rad, or m relative to the link length); velocities and accelerations
<= 1e-9 relative to their peak over the sample set; random valid parameters, seeded.
"""

import math

import numpy as np
import pytest

from analytic.closed_forms import fivebar
from analytic.closed_forms import fourbar
from analytic.closed_forms import sixbar
from oracle import solve_loops

RNG_SEEDS = range(8)
POS_TOL = 1e-12     # rounding of a closed form vs converged Newton, away from singular positions
RATE_TOL = 1e-9     # rates divide by sin(transmission angle) >= sin(0.15): rounding stays far below this


def _perturb(rng, x):
    return x + rng.uniform(-1e-3, 1e-3, np.shape(x))


def _random_fourbar(rng):
    while True:
        l1, l2, l3, l4 = rng.uniform(0.05, 0.5, 4)
        try:
            return fourbar.FourBar(l1, l2, l3, l4, ex=rng.uniform(-0.2, 0.2), ey=rng.uniform(-0.2, 0.2),
                                   branch=int(rng.choice([1, -1])))
        except ValueError:
            continue


@pytest.mark.parametrize("seed", RNG_SEEDS)
def test_fourbar_matches_newton(seed):
    rng = np.random.default_rng(seed)
    m = _random_fourbar(rng)
    phi1 = rng.uniform(-math.pi, math.pi, 400)
    w1, a1 = rng.uniform(-10, 10, 400), rng.uniform(-50, 50, 400)
    st = fourbar.solve(m, phi1, w1, a1)
    keep = st.valid & (st.mu > 0.15)       # away from dead centres, where any solver loses digits
    assert keep.sum() > 20
    phi1, w1, a1 = phi1[keep], w1[keep], a1[keep]
    loops = [[(1, m.l1, "phi1"), (1, m.l2, "phi2"), (-1, m.l3, "phi3"), (-1, m.l4, 0.0)]]
    q, qd, qdd = solve_loops(loops, {"phi1": (phi1, w1, a1)},
                             {"phi2": _perturb(rng, st.phi2[keep]), "phi3": _perturb(rng, st.phi3[keep])})
    for name, ref in [("phi2", q["phi2"]), ("phi3", q["phi3"])]:
        err = np.abs(np.angle(np.exp(1j * (getattr(st, name)[keep] - ref))))
        assert err.max() <= POS_TOL, name
    for name, ref in [("omega2", qd["phi2"]), ("omega3", qd["phi3"]),
                      ("alpha2", qdd["phi2"]), ("alpha3", qdd["phi3"])]:
        err = np.abs(getattr(st, name)[keep] - ref)
        assert err.max() <= RATE_TOL * np.abs(ref).max(), name


@pytest.mark.parametrize("seed", RNG_SEEDS)
def test_sixbar_matches_newton(seed):
    rng = np.random.default_rng(seed)
    l6 = rng.uniform(0.2, 0.6)
    l1 = rng.uniform(0.05, 0.8) * l6
    l3 = (l6 + l1) * rng.uniform(1.0, 1.5)
    m = sixbar.SixBar(l6=l6, l1=l1, l3=l3, l4=rng.uniform(0.3, 1.0) * l3, branch=int(rng.choice([1, -1])))
    phi1 = rng.uniform(-math.pi, math.pi, 300)
    w1, a1 = rng.uniform(-10, 10, 300), rng.uniform(-50, 50, 300)
    st = sixbar.solve(m, phi1, w1, a1)
    loops = [[(1, "s", "phi3"), (-1, m.l6, math.pi / 2), (-1, m.l1, "phi1")],
             [(1, m.l3, "phi3"), (1, m.l4, "phi4"), (-1, "xC", 0.0), (-1, m.h, math.pi / 2)]]
    guess = {k: _perturb(rng, getattr(st, k)) for k in ("s", "phi3", "phi4", "xC")}
    q, qd, qdd = solve_loops(loops, {"phi1": (phi1, w1, a1)}, guess)
    scale = {"s": m.l3, "xC": m.l3, "phi3": 1.0, "phi4": 1.0}
    for name in ("s", "phi3", "phi4", "xC"):
        diff = getattr(st, name) - q[name]
        if name.startswith("phi"):
            diff = np.angle(np.exp(1j * diff))
        assert np.abs(diff).max() <= POS_TOL * scale[name], name
    pairs = [("ds", qd["s"]), ("omega3", qd["phi3"]), ("omega4", qd["phi4"]), ("vxC", qd["xC"]),
             ("dds", qdd["s"]), ("alpha3", qdd["phi3"]), ("alpha4", qdd["phi4"]), ("axC", qdd["xC"])]
    for name, ref in pairs:
        assert np.abs(getattr(st, name) - ref).max() <= RATE_TOL * np.abs(ref).max(), name


@pytest.mark.parametrize("method", fivebar.METHODS)
@pytest.mark.parametrize("seed", RNG_SEEDS)
def test_fivebar_matches_newton(seed, method):
    rng = np.random.default_rng(seed)
    l2, l4 = rng.uniform(0.02, 0.2, 2)
    m = fivebar.FiveBar(l1=(l2 + l4) * rng.uniform(1.05, 3.0), l2=l2, l4=l4, lp=rng.uniform(0.05, 0.5))
    n = 300
    phi2, phi4 = rng.uniform(-math.pi, math.pi, (2, n))
    w2, w4, a2, a4 = rng.uniform(-10, 10, (4, n))
    st = fivebar.solve(m, phi2, phi4, w2, w4, a2, a4, method=method)
    loops = [[(1, m.l2, "phi2"), (1, "S", "theta3"), (-1, m.l1, 0.0), (-1, m.l4, "phi4")]]
    q, qd, qdd = solve_loops(loops, {"phi2": (phi2, w2, a2), "phi4": (phi4, w4, a4)},
                             {"S": _perturb(rng, st.S), "theta3": _perturb(rng, st.theta3)})
    assert np.abs(st.S - q["S"]).max() <= POS_TOL * m.l1
    assert np.abs(np.angle(np.exp(1j * (st.theta3 - q["theta3"])))).max() <= POS_TOL
    for name, ref in [("dS", qd["S"]), ("omega3", qd["theta3"]), ("ddS", qdd["S"]), ("alpha3", qdd["theta3"])]:
        assert np.abs(getattr(st, name) - ref).max() <= RATE_TOL * np.abs(ref).max(), name
