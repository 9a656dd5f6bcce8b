"""Every named mechanism (built-ins and the shipped library) against an independent Newton oracle.

The general solver (``analytic/solver/kinematics.py``, closed form group by group) and ``oracle_linkage``
(Newton on the whole constraint system, exact derivatives by Taylor jets) share only the file's
resolved numbers. Over one full period of the inputs, at 180 samples, with random (seeded) input
accelerations, they must agree on every point's position, velocity and acceleration, every prismatic
pair's slide and every link's angular rates. Two tests perturb the oracle's data slightly and check that
the comparison then fails, so the tolerances are known to bite.

The library files must also be usable as shipped: a one-line description, a moving output point,
assembly over a full turn, transmission angles clear of dead centres, and velocities and accelerations
that match finite differences of the motion.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import analytic
from agreement import (FD_STEPS, FD_TOL, MIN_MU_DEG, MIN_SLIDE, POS_TOL, RATE_TOL, assert_agree, compare, drive,
                       period, rng_for)
from analytic.applications import figures
from analytic.solver import jit as _jit

NAMES = analytic.names()
MIN_SINGULARITY = min(math.sin(math.radians(MIN_MU_DEG)), MIN_SLIDE)
"""The least singularity measure of a shipped file: the sin of an RRR's or RRP's angle clear of dead centre
by MIN_MU_DEG, an RPR's block MIN_SLIDE of the size from its pivot (rates up to 1/0.05 = 20x their usual
size); the measures are the kinds' own (analytic.applications.figures.singularity)."""

# ------------------------------------------------------------------------------------- vs the oracle
@pytest.fixture(params=["numpy", "compiled"])
def solver_path(request, monkeypatch):
    """Mechanism.solve through analytic/solver/kinematics.py (numpy) or its numba twin (analytic/solver/jit.py)."""
    if request.param == "compiled" and not _jit.AVAILABLE:
        pytest.skip("numba is not installed")
    monkeypatch.setenv("LINKAGE_JIT", "1" if request.param == "compiled" else "0")
    return request.param


@pytest.mark.parametrize("name", NAMES)
def test_solver_matches_newton_oracle(name, solver_path):
    m = analytic.load(name)
    assert_agree(name, compare(m, rng_for(name)))


@pytest.mark.parametrize("name, overrides", [
    ("two_crank_five_bar", {"ratio": 2.0}),                  # common period: 2 turns of crank 4
    ("two_crank_five_bar", {"ratio": -1.5, "branch": -1}),   # opposite senses, 3 half-turns; other branch
    ("slider_crank", {"e": 0.03, "branch": -1}),             # offset guide, piston on the left
    ("fourbar", {"branch": -1}),
])
def test_solver_matches_newton_oracle_off_defaults(name, overrides, solver_path):
    m = analytic.load(name, **overrides)
    assert_agree(name, compare(m, rng_for(name, 1)))


OTHER_FORMS = {
    # an RPR with an offset slot on its other branch, a point on the slotted link, and a block sliding on
    # that moving slot (RRP guided by two points of a turning link: the Coriolis term); crank turning CW
    "slot_and_block": """
format = "linkage/1"
[ground]
A = [0, 0]
P = [0.3, 0]
G = [0.1, 0.25]
[[inputs]]
kind = "crank"
pivot = "A"
point = "B"
length = 0.1
omega = "-250deg"
[[groups]]
kind = "RPR"
pivot = "P"
through = "B"
point = "R"
length = 0.4
offset = 0.02
branch = -1
[[groups]]
kind = "point"
point = "T"
on = ["P", "R"]
at = [0.2, -0.05]
[[groups]]
kind = "RRP"
point = "C"
from = "G"
length = 0.35
guide = ["P", "R"]
offset = 0.01
""",
    # a driven slider on an inclined ground line moving an RRR dyad
    "driven_slider": """
format = "linkage/1"
[ground]
O = [0, 0]
Q = [0.25, 0.05]
[[inputs]]
kind = "slider"
point = "S"
guide = { through = "O", angle = "30deg" }
s0 = 0.02
v = 0.1
[[groups]]
kind = "RRR"
point = "C"
from = ["S", "Q"]
lengths = [0.2, 0.15]
""",
}


@pytest.mark.parametrize("name", sorted(OTHER_FORMS))
def test_solver_matches_newton_oracle_on_other_element_forms(name, solver_path):
    """Element forms the library does not use: RPR offset and branch -1, a guide on a moving link, a
    driven slider."""
    m = analytic.from_text(OTHER_FORMS[name], name)
    assert_agree(name, compare(m, rng_for(name)))


def _perturbed(geometry, index, rel):
    """A copy of ``geometry`` with the lengths of element ``index`` scaled by (1 + rel)."""
    elements = [dict(e) for e in geometry.elements]
    e = elements[index]
    if "lengths" in e:
        e["lengths"] = tuple(x * (1 + rel) for x in e["lengths"])
    elif "at" in e:
        e["at"] = tuple(x * (1 + rel) for x in e["at"])
    else:
        e["length"] *= 1 + rel
    return dataclasses.replace(geometry, elements=tuple(elements))


@pytest.mark.parametrize("name", ["fourbar", "slider_crank", "whitworth", "jansen", "peaucellier"])
def test_comparison_fails_when_a_length_is_off_by_1e_6(name):
    """The oracle's copy of one length (of the last element: every error there reaches a point) is
    1e-6 too long: positions must then disagree far beyond POS_TOL."""
    m = analytic.load(name)
    worst = compare(m, rng_for(name), geometry=_perturbed(m.geometry, len(m.geometry.elements) - 1, 1e-6))
    assert worst["position"] > 1e3 * POS_TOL, worst      # ~1e-7 size expected: far outside POS_TOL


@pytest.mark.parametrize("name", ["fourbar", "whitworth", "two_crank_five_bar"])
def test_comparison_fails_when_input_accelerations_are_off_by_1e_6(name):
    """Positions and velocities still agree, accelerations must not: RATE_TOL resolves 1e-6 errors."""
    m = analytic.load(name)
    worst = compare(m, rng_for(name), qdd_scale=1 + 1e-6)
    assert worst["position"] <= POS_TOL and worst["velocity"] <= RATE_TOL, worst
    assert worst["acceleration"] > 10 * RATE_TOL, worst  # ~1e-6 expected: RATE_TOL resolves it


# ------------------------------------------------------------------------------- the files as shipped
@pytest.mark.parametrize("name", NAMES)
def test_file_is_described_and_has_a_moving_output(name):
    m = analytic.load(name)
    assert m.description and "\n" not in m.description, name
    assert m.output_point in {p for e in m.geometry.elements for p in e["places"]}, name


@pytest.mark.parametrize("name", NAMES)
def test_assembles_over_a_full_period_clear_of_dead_centres(name):
    m = analytic.load(name)
    t, *_ = drive(m, 721, endpoint=True)
    _, sol = m.solve_at(t)
    assert sol.valid.all(), (name, sol.first_failure())
    mus = list(m.transmission_angles.values())
    if m.builtin is None:                 # a file mechanism reports every transmission angle its groups have
        assert set(mus) <= set(m.outputs), (name, mus)
    for mu in mus:
        assert np.degrees(np.min(sol[mu])) >= MIN_MU_DEG, (name, mu, np.degrees(np.min(sol[mu])))
    # every group's own singularity measure (its kind's: 0 where it folds, its rates growing as 1/measure)
    for label, measure in figures.singularity(m, sol).items():
        assert np.min(measure) >= MIN_SINGULARITY, (name, label, float(np.min(measure)))


def _five_point(f, h):
    """d/dt by the five-point stencil on samples f(t + k h), k = -2..2 (rows)."""
    return (f[0] - 8 * f[1] + 8 * f[3] - f[4]) / (12 * h)


def _smooth(m, t, reach):
    """The times ``t`` whose stencil (``reach`` either side) stays inside one segment of every input's motion
    law: across a boundary the jerk jumps and the differences meet the kink, not the solver."""
    keep = np.ones(len(t), dtype=bool)
    for i in m.inputs:
        law = i.motion.law
        if law is not None:
            edges = np.asarray(getattr(law, "starts", [0.0, law.duration]))
            gap = np.abs((t[:, None] - edges[None, :] + 0.5 * law.duration) % law.duration - 0.5 * law.duration)
            keep &= gap.min(axis=1) > reach
    cams = [e for e in m.geometry.elements if e["kind"] == "cam"]
    if cams:                              # a cam's law has its segments over the cam's angle
        _, sol = m.solve_at(t)
        for e in cams:
            theta, w = np.arctan2(sol["sin" + e["cam"]], sol["cos" + e["cam"]]), np.abs(sol["omega" + e["cam"]])
            edges = np.asarray(e["segments"].starts)
            gap = np.abs((theta[:, None] - edges[None, :] + np.pi) % (2 * np.pi) - np.pi)
            keep &= gap.min(axis=1) > 1.5 * reach * w
    return t[keep]


@pytest.mark.parametrize("name", NAMES)
def test_rates_match_finite_differences(name):
    m = analytic.load(name)
    T = m.duration(1.0) if any(i.motion.law is not None for i in m.inputs) else period(m)
    h = T / FD_STEPS
    t = _smooth(m, np.linspace(0.0, T, 97, endpoint=False), 2.5 * h)
    sols = [m.solve_at(t + k * h)[1] for k in (-2, -1, 0, 1, 2)]
    mid = sols[2]
    for p in (p for e in m.geometry.elements for p in e["places"]):
        for d, dd in (("", "v"), ("v", "a")):
            fx = _five_point([s[f"{d}x{p}"] for s in sols], h)
            fy = _five_point([s[f"{d}y{p}"] for s in sols], h)
            ref_x, ref_y = mid[f"{dd}x{p}"], mid[f"{dd}y{p}"]
            peak = np.max(np.hypot(ref_x, ref_y))
            err = np.max(np.hypot(fx - ref_x, fy - ref_y)) / peak
            assert err <= FD_TOL, (name, p, dd, err)


# ------------------------------------------------------------------------- what the files are famous for
def test_peaucellier_draws_an_exact_straight_line():
    m = analytic.load("peaucellier")
    t, *_ = drive(m, 721, endpoint=True)
    _, sol = m.solve_at(t)
    v = m.values
    x_line = (v["arm"] ** 2 - v["side"] ** 2) / (2 * v["r"]) * m.scale
    assert np.max(np.abs(sol["xP"] - x_line)) <= POS_TOL * m.size      # OC * OP = arm^2 - side^2: rounding only
    assert np.max(np.abs(sol["vxP"])) <= RATE_TOL * np.max(np.abs(sol["vyP"]))   # no sideways motion, to rounding
    assert np.max(np.abs(sol["axP"])) <= RATE_TOL * np.max(np.abs(sol["ayP"]))


def test_slider_crank_and_whitworth_strokes():
    """Dead centres where theory puts them: the ram at rest there, at the stroke's ends."""
    sc = analytic.load("slider_crank")
    r, l = sc.values["r"], sc.values["l"]
    sol = sc.solve([0.0, math.pi], 2 * math.pi)             # in-line: dead centres at 0 and 180 deg
    assert np.allclose(sol["xC"], [l + r, l - r], rtol=0, atol=POS_TOL * sc.size)
    assert np.max(np.abs(sol["vxC"])) <= RATE_TOL * 2 * math.pi * r     # / the crank pin's speed
    w = analytic.load("whitworth")
    v, k = w.values, w.scale
    a = math.asin(v["c"] / v["r"])                           # the lever is horizontal: crank pin at C's height
    sol = w.solve([-a, a - math.pi], 2 * math.pi)
    assert np.allclose(sol["xR"], [(v["rod"] - v["arm"]) * k, (v["rod"] + v["arm"]) * k], rtol=0,
                       atol=POS_TOL * w.size)                # stroke 2 CD: the ram line runs through C
    assert np.max(np.abs(sol["vxR"])) <= RATE_TOL * 2 * math.pi * v["r"] * k
    assert (math.pi + 2 * a) / (math.pi - 2 * a) == pytest.approx(2.735, abs=5e-4)   # quick-return ratio
