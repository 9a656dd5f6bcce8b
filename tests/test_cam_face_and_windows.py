"""A flat face as narrow as the check allows, as the drawings draw it (sim.output.drawing.face_of), and the
forces' window means (sim.run.cams.window_means) on hand samples: both found unchecked by benchmarks/mutation.py
(round 4: the drawn face centred on the foot, the windows starting at their step)."""

import math
from pathlib import Path

import numpy as np
import pytest

import analytic
from sim.output import drawing
from sim.run import cams as run_cams

LIBRARY = Path(__file__).resolve().parent.parent / "analytic" / "library"


def test_a_drawn_face_as_narrow_as_the_travel_holds_the_touching_point_at_every_pose(tmp_path):
    """cam_flat with ``face_width = 23`` mm (its contact runs about -3 to +19.5 mm along the face from the foot:
    the least width the check accepts): at 180 poses of the analytic solution the plate's point farthest up the
    guide (where a flat face square to it touches; the test's own geometry from the drawn outline) lies within
    the drawn face's ends. Centred on the foot, the face would end 8 mm short of it."""
    text = (LIBRARY / "cam_flat.toml").read_text()
    assert "face_width = 40" in text
    f = tmp_path / "narrow_face.toml"
    f.write_text(text.replace("face_width = 40", "face_width = 23"))
    mech = analytic.load(str(f))
    (pl,) = drawing.plates_of(mech)
    u = np.array(pl.face[:2])
    chord = float(np.max(np.hypot(*(np.roll(pl.outline, -1, axis=0) - pl.outline).T)))
    lows, highs = [], []
    for phi in np.linspace(0.0, 2 * math.pi, 181)[:-1]:
        s = mech.solve(np.array([[phi]]))
        at = {p: (float(np.ravel(s["x" + p])[0]), float(np.ravel(s["y" + p])[0])) for p in mech.points}
        edge = drawing.face_world(pl, at)
        world = drawing.plate_world(pl, at)
        width = float(np.hypot(*(edge[1] - edge[0])))
        assert width == pytest.approx(0.023, abs=1e-12)            # the file's face_width; rounding only
        k = int(np.argmax(world @ u))
        t = float((world[k] - edge[0]) @ (edge[1] - edge[0])) / width
        lows.append(t)
        highs.append(t - width)
    # the farthest corner along u is one of the two about the true touching point: within the outline's
    # longest chord (0.93 mm) of it
    assert min(lows) >= -chord and max(highs) <= chord, (min(lows), max(highs), chord)


def test_window_means_of_a_ramp_are_its_values_at_the_centres():
    """The mean of x = k over an odd window of w steps centred on step k is k; near the run's ends the window
    slides inside (w steps from the first or to the last); a run shorter than w: its mean at every step."""
    x = np.arange(40, dtype=float)
    at = np.array([0, 1, 2, 10, 25, 37, 38, 39])
    got = run_cams.window_means(x, at, 5)
    # sums of small integers over 5: exact in binary to within one rounding
    np.testing.assert_allclose(got, [2, 2, 2, 10, 25, 37, 37, 37], rtol=0, atol=1e-12)
    both = run_cams.window_means(np.vstack([x, 2 * x]), at, 5)          # the last axis is the steps
    np.testing.assert_allclose(both[1], 2 * got, rtol=0, atol=1e-12)
    np.testing.assert_allclose(run_cams.window_means(x[:4], np.array([0, 3]), 5), [1.5, 1.5], rtol=0, atol=1e-12)


def test_the_default_window_is_the_contacts_ring_period_centred():
    """The default window: 2 pi tau steps, rounded (tau = sim.model.cam_contact.CONTACT_STEPS = 8 steps: 50); an
    even window holds w/2 - 1 steps before its centre and w/2 after, so a ramp's mean is its value half a step
    on."""
    from sim.model.cam_contact import CONTACT_STEPS
    w = round(2 * math.pi * CONTACT_STEPS)
    assert run_cams.window_steps() == w == 50
    x = np.arange(2000, dtype=float)
    at = np.array([500, 1000, 1500])
    # sums of integers below 2000 (exact in binary) over 50: one rounding
    np.testing.assert_allclose(run_cams.window_means(x, at), at + 0.5, rtol=0, atol=1e-9)
