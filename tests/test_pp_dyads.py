"""The dyads with two prismatic pairs (RPP, PRP, PPR) against hand geometry, and their bad input.

The conformance suite (test_kinds.py) checks them against the Newton oracle; here the library's Scotch
yoke and elliptic trammel are checked against their textbook closed forms (the yoke's harmonic motion,
the trammel's ellipse), which share nothing with the solver or the oracle, and the fields that cannot make
a mechanism (a slot along its guide, parallel or identical guides) are refused in one line naming them.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import analytic
from agreement import POS_TOL, RATE_TOL, rng_for
from analytic import ParameterError


def _inputs(n=181, seed="pp"):
    """Crank angles over a turn with random speeds and accelerations: (q, qd, qdd)."""
    rng = rng_for(seed)
    q = np.linspace(0.0, 2 * math.pi, n)
    return q, rng.uniform(-8, 8, n), rng.uniform(-50, 50, n)


def _close(got, want, scale):
    assert np.max(np.abs(got - want)) <= scale, float(np.max(np.abs(got - want)) / scale)


@pytest.mark.parametrize("slot_deg", [90.0, 60.0, -125.0])
def test_scotch_yoke_moves_as_its_closed_form(slot_deg):
    """C = the crank pin B projected on the x-axis along the slot (slot_deg from the axis, counterclockwise):
    x = r cos(q) - r sin(q) cot(slot); at 90 deg pure harmonic motion. The block runs r sin(q) / sin(slot)
    along the slot from C to B. Derivatives by hand (chain rule in q, qd, qdd)."""
    m = analytic.load("scotch_yoke", slot=math.radians(slot_deg))
    r, k = m.values["r"] * m.scale, 1.0 / math.tan(math.radians(slot_deg))
    sb = r / math.sin(math.radians(slot_deg))
    q, qd, qdd = _inputs()
    sol = m.solve(q, qd, qdd)
    c, s = np.cos(q), np.sin(q)
    x, dx, ddx = r * (c - k * s), r * (-s - k * c), r * (-c + k * s)      # and d/dq, d2/dq2
    # positions: a closed form against another, rounding only; rates: / their peak, rounding only
    _close(sol["xC"], x, POS_TOL * m.size)
    _close(sol["yC"], 0.0 * x, POS_TOL * m.size)
    _close(sol["syoke"], x, POS_TOL * m.size)              # the yoke's slide from the guide's origin A
    _close(sol["sblock"], sb * s, POS_TOL * m.size)
    for got, want in ((sol["vxC"], dx * qd), (sol["axC"], dx * qdd + ddx * qd * qd),
                      (sol["dsblock"], sb * c * qd), (sol["ddsblock"], sb * (c * qdd - s * qd * qd))):
        _close(got, want, RATE_TOL * np.max(np.abs(want)))
    slot = math.atan2(math.sin(math.radians(slot_deg)), math.cos(math.radians(slot_deg)))
    _close(sol["phiblock"], slot + 0.0 * q, POS_TOL)       # the block's angle is the slot's: rounding
    _close(sol["omegablock"], 0.0 * q, 0.0)                # a ground guide does not turn: exactly 0


def test_elliptic_trammel_traces_its_ellipse():
    """A = (L cos q, 0) and B = (0, L sin q) (the crank pin's projections), E on AB at b from A:
    ((L - b) cos q, b sin q); the rod's slot keeps block B at s = L."""
    m = analytic.load("elliptic_trammel")
    L, b = m.values["L"] * m.scale, m.values["b"] * m.scale
    q, qd, qdd = _inputs(seed="trammel")
    sol = m.solve(q, qd, qdd)
    c, s = np.cos(q), np.sin(q)
    for p, (ax_, ay_) in {"A": (L, 0.0), "B": (0.0, L), "E": (L - b, b)}.items():
        x, y = ax_ * c, ay_ * s
        vx, vy = -ax_ * s * qd, ay_ * c * qd
        accx, accy = -ax_ * (s * qdd + c * qd * qd), ay_ * (c * qdd - s * qd * qd)
        vpeak = np.max(np.hypot(vx, vy))
        apeak = np.max(np.hypot(accx, accy))
        _close(np.hypot(sol["x" + p] - x, sol["y" + p] - y), 0.0, POS_TOL * m.size)   # rounding
        _close(np.hypot(sol["vx" + p] - vx, sol["vy" + p] - vy), 0.0, RATE_TOL * vpeak)
        _close(np.hypot(sol["ax" + p] - accx, sol["ay" + p] - accy), 0.0, RATE_TOL * apeak)
    _close(sol["srod_slot"], L + 0.0 * q, POS_TOL * m.size)
    _close(sol["dsrod_slot"], 0.0 * q, RATE_TOL * L * np.max(np.abs(qd)))   # / the blocks' speed scale


BASE = """
format = "linkage/1"
[ground]
A = [0, 0]
P = [0, 0.1]
Q = [0.1, 0.1]
R = [0, 0.2]
S = [0.1, 0.25]
T = [0.2, 0.25]
[[inputs]]
kind = "crank"
pivot = "A"
point = "B"
length = 0.05
"""


@pytest.mark.parametrize("group, field", [
    ('kind = "RPP"\npoint = "C"\nthrough = "B"\nguide = { through = "A", angle = "30deg" }\nangle = "180deg"',
     "angle"),
    ('kind = "PPR"\npoint = "C"\nthrough = "B"\nguide = ["P", "Q"]\nangle = 0', "angle"),
    ('kind = "PRP"\npoint = "C"\nguide1 = { through = "A", angle = "10deg" }\n'
     'guide2 = { through = [0, 1], angle = "-170deg" }', "guide2"),
    ('kind = "PRP"\npoint = "C"\nguide1 = ["P", "Q"]\nguide2 = ["P", "Q"]', "guide2"),
])
def test_a_slot_or_guide_that_never_crosses_is_refused_in_one_line(group, field):
    with pytest.raises(ParameterError) as err:
        analytic.from_text(BASE + "[[groups]]\n" + group + "\n", "pp")
    message = str(err.value)
    assert "\n" not in message and f"field {field!r}" in message and "(point C)" in message, message


def test_parallel_guides_through_ground_points_fail_to_assemble_at_that_element():
    """Two guides through ground points, parallel (P->Q and S->T, both horizontal):
    the lines never meet, which only the numbers show: every sample fails, at the PRP element."""
    m = analytic.from_text(BASE + '[[groups]]\nkind = "PRP"\npoint = "C"\nguide1 = ["P", "Q"]\n'
                                  'guide2 = ["S", "T"]\n', "pp")
    sol = m.solve(np.linspace(0, 6, 7))
    assert not sol.valid.any()
    assert "(point C)" in sol.first_failure()[1]
