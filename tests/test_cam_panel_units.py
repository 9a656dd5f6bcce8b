"""The app's cam panel (sim.service.cam_editing) on cam_fourbar, a mm file with an oscillating roller arm whose
largest pressure angle is on the return (negative): the arm's lift in deg, the profile's radius of curvature in
the file's unit, the largest |pressure angle| marked, and a base radius edit written into the file. Each was
found unchecked by benchmarks/mutation.py (round 4); tests/test_app_cam.py covers the translating cams."""

import math
from pathlib import Path

import numpy as np
import pytest

import analytic
from sim.service import cam_editing

LIBRARY = Path(__file__).resolve().parent.parent / "analytic" / "library"


@pytest.fixture(scope="module")
def view():
    (v,) = cam_editing.panel(analytic.load("cam_fourbar")).values()
    return v


def test_an_arms_lift_is_in_degrees_as_the_file_writes_it(view):
    """The file's law swings the arm 25deg and back (poly4567 rises of "25deg" and "-25deg" between dwells): the
    SVAJ's s spans 25 deg, its units say deg, and v is the derivative of s per radian of cam angle (finite
    differences of the sent s over the sent theta in deg)."""
    svaj = view["svaj"]
    s, th = np.asarray(svaj["s"]), np.radians(svaj["theta"])
    assert svaj["units"]["s"] == "deg" and svaj["units"]["v"] == "deg/rad"
    assert s.max() - s.min() == pytest.approx(25.0, abs=1e-9)       # the law's ends are exact: rounding only
    fd = np.diff(s) / np.diff(th)
    mid = 0.5 * (np.asarray(svaj["v"])[1:] + np.asarray(svaj["v"])[:-1])
    # the chord's slope against the mean of the end slopes over 0.5 deg: O(h^2 s''') (measured 2.6e-5 of the peak);
    # 1e-3 leaves room; a v not the derivative of the s sent (another law, another scale) is far off
    assert np.max(np.abs(fd - mid)) < 1e-3 * np.max(np.abs(mid))


def test_the_profiles_curvature_is_in_the_files_unit(view):
    """In a dwell at the arm's lowest the contact curve is a circle about the cam's pivot: its radius of
    curvature [mm] is its distance from the pivot (the sent x, y are in metres, the cam's frame about A)."""
    prof = view["profile"]
    assert view["length_unit"] == "mm"
    r = np.hypot(prof["x"], prof["y"])                                   # [m]
    dwell = np.abs(r - r.min()) <= 1e-9 * r.min()                        # the base circle: r constant to rounding
    assert dwell.sum() >= 10
    rho = np.asarray(prof["rho"], dtype=float)[dwell]
    # the checks' rho from the profile's derivatives: exact on a circle (measured 4e-16 relative): rounding
    np.testing.assert_allclose(rho * 1e-3, r[dwell], rtol=1e-12)
    assert view["rho_min"]["unit"] == "mm"


def test_the_largest_pressure_angle_mark_is_the_largest_in_magnitude(view):
    """cam_fourbar's return is steeper against the arm than its rise: its pressure angle reaches about -35 deg,
    the rise only +15. The mark is the largest |angle| of the profile sent (which samples every 2nd of the
    check's points: the mark, from all of them, is at least as large and within 0.01 deg)."""
    pa = np.asarray([a for a in view["profile"]["pressure_angle"] if a is not None])
    assert pa.min() < -30 and pa.max() < 20                              # the steepest is on the return
    mark = view["pressure_angle_max"]
    assert mark["unit"] == "deg"
    assert np.max(np.abs(pa)) <= mark["value"] <= np.max(np.abs(pa)) + 0.01


def test_a_base_radius_edit_is_written_into_the_file(tmp_path):
    """An edit of base_radius alone: the written file's cam has the new base circle (30 -> 34 mm), every other
    line as it was; the file reads back with the pitch curve's least radius base + roller = 44 mm."""
    text = (LIBRARY / "cam_fourbar.toml").read_text()
    (name,) = cam_editing.panel(analytic.load("cam_fourbar"))
    out = cam_editing.edited_text(text, name, {"base_radius": 34})
    changed = [(a, b) for a, b in zip(text.splitlines(), out.splitlines()) if a != b]
    assert len(text.splitlines()) == len(out.splitlines())
    assert [b.split("#")[0].strip() for _, b in changed] == ["base_radius = 34"]
    p = tmp_path / "cam_fourbar.toml"
    p.write_text(out)
    (v,) = cam_editing.panel(analytic.load(str(p))).values()
    assert v["base_radius"] == pytest.approx(0.034, rel=1e-12)           # mm to m: one product
    pitch = np.hypot(v["pitch"]["x"], v["pitch"]["y"])
    assert pitch.min() == pytest.approx(0.044, rel=1e-12)   # the dwell's samples lie on the circle: rounding
    assert math.isclose(v["roller"], 0.010, rel_tol=1e-12)
