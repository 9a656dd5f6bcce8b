"""Every kind's singularity measure on poses worked by hand (issue 32: only the refusals were tested, so a
measure built on the wrong trigonometric function, or on the wrong length, went unnoticed). The RRR's and
the RRP's are in tests/test_measures_on_known_poses.py; here the others (SPEC "Analysis": each group's
distance from a singular pose, 0 where it folds):

* RPR (a slotted link pivoted at C, its block pinned at B): the block's distance from the pivot over the
  size, |B - C| / L (zero where the pin passes the pivot and the slot's direction is lost);
* PRP (two blocks on two guides, pinned together): |sin| of the angle between the guides (zero: parallel);
* RPP / PPR (a pin in a slot at a fixed angle to a guide): |sin| of that angle, constant.
"""

import math
from pathlib import Path

import numpy as np
import pytest

import analytic
from analytic.applications import figures

KINDS = Path(__file__).parent / "kinds"
HAND = 1e-12       # closed-form solver against hand geometry: rounding only


def _measures(mech, phi):
    sol = mech.solve(np.array([[phi]]), 1.0, 0.0)
    return {label.split("(")[1].rstrip(")"): float(np.ravel(m)[0])
            for label, m in figures.singularity(mech, sol).items()}, sol


@pytest.mark.parametrize("phi", [0.0, math.radians(90), math.radians(200)])
def test_rpr_is_the_blocks_distance_from_the_pivot(phi):
    """inverted_slider_crank: crank AB = 0.1 about A = (0, 0), the slotted rocker pivoted at C = (0.25, 0)."""
    mech = analytic.load("inverted_slider_crank")
    got, _ = _measures(mech, phi)
    b = np.array([0.1 * math.cos(phi), 0.1 * math.sin(phi)])
    dist = float(np.hypot(*(b - np.array([0.25, 0.0]))))
    assert got["point D"] * mech.size == pytest.approx(dist, abs=HAND)
    assert got["point D"] == pytest.approx(dist / 0.4, abs=HAND)             # the size: the rocker CD, 0.4


def test_prp_is_the_sine_between_the_guides():
    """tests/kinds/PRP.toml at phi = 0: A = (0, 0), D = (0.11, 0), B = (0.04, 0); C at 0.12 from B and 0.1 from
    D, left of B->D. E: blocks on the coupler BC and the rocker DC; F: on the rocker DC and a ground line at
    -15 deg."""
    mech = analytic.load(str(KINDS / "PRP.toml"))
    got, sol = _measures(mech, 0.0)
    B, D = np.array([0.04, 0.0]), np.array([0.11, 0.0])
    d = 0.07
    a = (0.12 ** 2 - 0.1 ** 2 + d ** 2) / (2 * d)
    C = B + np.array([a, math.sqrt(0.12 ** 2 - a ** 2)])
    assert (float(sol["xC"][0]), float(sol["yC"][0])) == pytest.approx(tuple(C), abs=HAND)
    u, v = C - B, C - D
    sin_uv = abs(u[0] * v[1] - u[1] * v[0]) / (np.linalg.norm(u) * np.linalg.norm(v))
    assert got["point E"] == pytest.approx(sin_uv, abs=HAND)
    theta = math.atan2(v[1], v[0])
    assert got["point F"] == pytest.approx(abs(math.sin(theta - math.radians(-15))), abs=HAND)
    assert got["point F"] < 0.99 and got["point E"] < 0.9          # neither pair at right angles: sin != cos


@pytest.mark.parametrize("file, point, angle", [("RPP.toml", "point F", 70.0), ("PPR.toml", "point G", 120.0)])
@pytest.mark.parametrize("phi", [0.0, 1.3, 4.0])
def test_a_slot_at_a_fixed_angle_measures_its_sine(file, point, angle, phi):
    mech = analytic.load(str(KINDS / file))
    got, _ = _measures(mech, phi)
    assert got[point] == pytest.approx(abs(math.sin(math.radians(angle))), abs=HAND)


# ------------------------------------------------------------------------------------ the general group
GROUP_DYAD = """
format = "linkage/1"
output = "C"

[ground]
A = [0, 0]
D = [0.3, 0]

[[inputs]]
kind = "crank"
pivot = "A"
point = "B"
length = 0.1
link = "crank"
omega = "360deg"

[[groups]]
kind = "group"
points = ["C"]
links = { coupler = ["B", "C"], rocker = ["D", "C"] }
pose = { B = [0.1, 0], D = [0.3, 0], C = [0.3, 0.25] }
"""


def test_a_general_group_of_two_links_measures_the_sine_between_them(tmp_path):
    """A four-bar's dyad written as a general group: at phi = 0 the pose itself, C = (0.3, 0.25) over
    B = (0.1, 0) and D = (0.3, 0): CB = (-0.2, -0.25), CD = (0, -0.25), sin = 0.05 / (0.25 sqrt(0.1025))."""
    f = tmp_path / "g.toml"
    f.write_text(GROUP_DYAD)
    got, sol = _measures(analytic.load(str(f)), 0.0)
    assert (float(sol["xC"][0]), float(sol["yC"][0])) == pytest.approx((0.3, 0.25), abs=1e-9)   # Newton's tol
    assert got["point C"] == pytest.approx(0.05 / (0.25 * math.sqrt(0.1025)), abs=1e-9)


def test_a_triad_is_singular_where_its_three_rods_meet_in_a_point():
    """tests/kinds/group.toml's class III triad (coupler Q1 Q2 Q3 hung from rods P1-Q1, P2-Q2, G2-Q3): the
    triad is singular exactly where the three rods' lines are concurrent (the coupler's instant centre is
    then undetermined). The rods' far ends moved onto lines through one point O: the measure is 0 (rounding);
    the ground pivot moved off its line: it is not."""
    mech = analytic.load(str(KINDS / "group.toml"))
    sol = dict(mech.solve(np.array([[0.0]]), 1.0, 0.0))
    label = "groups[2] (points Q1, Q2, Q3)"
    assert float(np.ravel(figures.singularity(mech, sol)[label])[0]) > 0.1          # the file's pose: regular
    O = np.array([0.3, 0.0])
    for p, q, f in (("P1", "Q1", 0.5), ("P2", "Q2", 0.4), ("G2", "Q3", 0.6)):
        Q = np.array([sol["x" + q][0], sol["y" + q][0]])
        P = O + f * (Q - O)
        sol["x" + p], sol["y" + p] = np.array([P[0]]), np.array([P[1]])
    assert float(np.ravel(figures.singularity(mech, sol)[label])[0]) <= 1e-12      # a determinant's rounding
    sol["xG2"] = sol["xG2"] + 0.05
    assert float(np.ravel(figures.singularity(mech, sol)[label])[0]) > 0.01
