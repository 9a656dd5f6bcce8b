"""The kinematic checks read from one scan of the turn (analytic/checks.py): the assembly ranges and singular
poses a mechanism finds once (:attr:`analytic.mechanism.Mechanism.checks`) against hand geometry and against
the scans they replaced (a positions-only scan for the ranges, the singular poses' own grid)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import analytic
from analytic import checks

PARALLELOGRAM = dict(l1=0.1, l2=0.3, l3=0.1, l4=0.3)
"""Crank 0.1, coupler 0.3, rocker 0.1, ground 0.3: the coupler and rocker align when the crank lies along the
ground, at 0 and 180 deg (its change points)."""


def test_a_parallelogram_folds_at_0_and_180_deg_once_each():
    mech = analytic.load("fourbar", **PARALLELOGRAM)
    found = checks.singular_poses(mech)
    assert [label for _, label, _ in found] == ["groups[1] (point C)"] * 2, found
    # golden section brackets the fold to ~1e-13 rad; 1e-9 leaves room for the measure's rounding
    assert found[0][0] == pytest.approx(0.0, abs=1e-9)
    assert found[1][0] == pytest.approx(math.pi, abs=1e-9)
    own = checks.find_singular_poses(mech)        # a scan of its own (its grid padded past the turn's ends)
    assert len(own) == len(found)
    for (x, label, _), (y, other, _) in zip(found, own):
        assert label == other and x == pytest.approx(y, abs=1e-9)      # both refined to ~1e-13 rad


def test_a_crank_that_cannot_turn_assembles_between_its_limit_positions():
    """l1 = 0.3, l2 = 0.3, l3 = 0.25, l4 = 0.3: B = l1 (cos phi, sin phi), D = (l4, 0); the dyad closes while
    |l2 - l3| <= |BD| <= l2 + l3, |BD|^2 = l1^2 + l4^2 - 2 l1 l4 cos phi."""
    mech = analytic.load("fourbar", l1=0.3)
    p = mech.parameters
    assert (p["l1"], p["l2"], p["l3"], p["l4"]) == (0.3, 0.3, 0.25, 0.3)

    def limit(d):
        return math.acos((p["l1"] ** 2 + p["l4"] ** 2 - d ** 2) / (2 * p["l1"] * p["l4"]))
    inner, outer = limit(p["l2"] - p["l3"]), limit(p["l2"] + p["l3"])
    want = [(inner, outer), (2 * math.pi - outer, 2 * math.pi - inner)]
    ranges = checks.assembly_ranges(mech)
    # the ends are bisected to 1e-13 rad; near a limit the closure's discriminant is ~ the angle, so rounding
    # moves them by ~1e-15: 1e-9 rad is a generous margin
    assert np.allclose(ranges, want, rtol=0.0, atol=1e-9), (ranges, want)
    positions_only = checks.find_assembly_ranges(mech)      # the scan solved at rest, positions only
    assert np.allclose(ranges, positions_only, rtol=0.0, atol=1e-12)   # the same bisection on the same grid
    assert not checks.turns_fully(mech)
