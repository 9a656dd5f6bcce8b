"""The cam plate as the videos draw it (sim.output.drawing.Plate): the outline turned with its link about its
pivot, so that the roller drawn on the follower touches it at every pose of the analytic solution (the
roller's centre one roller radius from the drawn outline), and the drawn frame shows the plate."""

from __future__ import annotations

import numpy as np
import pytest

import analytic
from sim.output import drawing


def _distance_to_polygon(p, poly):
    """The least distance [m] from point p to the closed polygon's edges (the test's own geometry)."""
    a, b = poly, np.roll(poly, -1, axis=0)
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    return float(np.min(np.hypot(*(a + t[:, None] * ab - p).T)))


@pytest.mark.parametrize("name", ["cam_roller", "cam_rocker"])
def test_the_drawn_plate_touches_the_drawn_roller_at_every_pose(name):
    mech = analytic.load(name)
    (pl,) = drawing.plates_of(mech)
    assert pl.roller > 0
    for phi in np.linspace(0.0, 2 * np.pi, 13)[:-1]:
        s = mech.solve(np.array([[phi]]))
        at = {p: (float(np.ravel(s["x" + p])[0]), float(np.ravel(s["y" + p])[0])) for p in mech.points}
        world = drawing.plate_world(pl, at)
        gap = _distance_to_polygon(np.array(at[pl.point]), world)
        # the outline's 360 corners lie on the profile: the chord sag (r dtheta^2 / 8, ~1e-5 m on a 50 mm cam)
        assert gap == pytest.approx(pl.roller, abs=5e-5), (phi, gap)


def test_a_plate_turned_the_wrong_way_would_miss_the_roller():
    # the check above has teeth: the outline turned half a turn more (its link's points swapped) leaves a gap
    mech = analytic.load("cam_roller")
    (pl,) = drawing.plates_of(mech)
    turned = drawing.Plate(pl.link, pl.pivot, pl.ref[::-1], pl.outline, pl.roller, pl.point)
    gaps = []
    for phi in np.linspace(0.0, 2 * np.pi, 13)[:-1]:
        s = mech.solve(np.array([[phi]]))
        at = {p: (float(np.ravel(s["x" + p])[0]), float(np.ravel(s["y" + p])[0])) for p in mech.points}
        gaps.append(_distance_to_polygon(np.array(at[pl.point]), drawing.plate_world(turned, at)))
    assert max(abs(g - pl.roller) for g in gaps) > 1e-3
