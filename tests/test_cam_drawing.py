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


def _face_poses(name):
    """(foot, drawn face edge, drawn plate) at 180 poses of the analytic solution."""
    mech = analytic.load(name)
    (pl,) = drawing.plates_of(mech)
    out = []
    for phi in np.linspace(0.0, 2 * np.pi, 181)[:-1]:      # every 2 deg: the contact's extremes on the face
        s = mech.solve(np.array([[phi]]))
        at = {p: (float(np.ravel(s["x" + p])[0]), float(np.ravel(s["y" + p])[0])) for p in mech.points}
        out.append((np.array(at[pl.point]), drawing.face_world(pl, at), drawing.plate_world(pl, at)))
    return pl, out


def test_the_drawn_flat_face_is_tangent_to_the_drawn_plate_at_every_pose():
    """The face's edge is a line through the foot square to the guide; the plate lies on the cam's side of it
    and touches it: the plate's support point along the guide's direction u lies on the edge's line, within
    the drawn face's ends (the test's own geometry: the support point is the outline corner farthest along u)."""
    pl, poses = _face_poses("cam_flat")
    u = np.array(pl.face[:2])
    chord = float(np.max(np.hypot(*(np.roll(pl.outline, -1, axis=0) - pl.outline).T)))
    # the face's back is drawn up the file's guide (75deg): the way the follower leaves the cam
    assert np.allclose(u, (np.cos(np.radians(75)), np.sin(np.radians(75))), atol=1e-12)
    for foot, edge, world in poses:
        # rounding of the foot's coordinates (~0.1 m) times the unit vectors
        assert np.allclose((edge - foot) @ u, 0.0, atol=1e-15)    # the edge is square to the guide through the foot
        width = float(np.hypot(*(edge[1] - edge[0])))
        assert width == pytest.approx(0.040, abs=1e-12)           # the file's face_width, 40 mm; rounding only
        k = int(np.argmax(world @ u))
        gap = float((world[k] - foot) @ u)
        # the outline's 360 corners lie on the profile and the true touching point falls between two of them:
        # the corner nearest it is below the line by at most the chord's sag, rho dtheta^2 / 8 with rho < 0.1 m
        # and dtheta = 1 deg (1.2e-5 m); above it only by rounding
        assert -1.2e-5 <= gap <= 1e-12, gap
        t = float((world[k] - edge[0]) @ (edge[1] - edge[0])) / width
        # within the drawn edge, to the outline's longest chord (0.93 mm): the farthest corner along u is one of
        # the two about the true touching point
        assert -chord <= t <= width + chord, (t, width, chord)


def test_a_plate_turned_the_wrong_way_would_leave_the_face():
    # the check above has teeth: the plate turned half a turn more (its link's points swapped) no longer
    # touches the face's line
    mech = analytic.load("cam_flat")
    (pl,) = drawing.plates_of(mech)
    turned = drawing.Plate(pl.link, pl.pivot, pl.ref[::-1], pl.outline, pl.roller, pl.point, pl.face)
    u = np.array(pl.face[:2])
    gaps = []
    for phi in np.linspace(0.0, 2 * np.pi, 13)[:-1]:
        s = mech.solve(np.array([[phi]]))
        at = {p: (float(np.ravel(s["x" + p])[0]), float(np.ravel(s["y" + p])[0])) for p in mech.points}
        world = drawing.plate_world(turned, at)
        gaps.append(float(np.max((world - np.array(at[pl.point])) @ u)))
    assert max(abs(g) for g in gaps) > 1e-3


def test_without_a_given_width_the_face_spans_the_contacts_travel():
    """No ``face_width`` in the file: the drawn face is the analytic face width (the contact's travel, 2.55 in
    on the mechanism package's README cam, tests/test_cams.py) where the contact sweeps it."""
    from pathlib import Path
    mech = analytic.load(str(Path(__file__).resolve().parent / "mechanisms" / "cam_mechanism_readme.toml"))
    (pl,) = drawing.plates_of(mech)
    ux, uy, lo, hi = pl.face
    # the radial face's contact runs out to the lift's largest slope s' = 2 h / beta = 4 / pi in either way;
    # read on the 0.1 deg grid, where the slope's peak (at 135 and 315 deg, both samples) is flat to 1e-6
    assert lo == pytest.approx(-4 / np.pi * 0.0254, rel=1e-4) and hi == pytest.approx(4 / np.pi * 0.0254, rel=1e-4)


def test_a_roller_follower_draws_no_face():
    (pl,) = drawing.plates_of(analytic.load("cam_roller"))
    assert pl.face is None
