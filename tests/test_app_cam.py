"""The app's cam panel over HTTP (``POST /api/cam``, issue 38 item 7) and the plates the page draws
(``describe``'s ``cams``): the SVAJ the server sends agrees with finite differences of the displacement it
sends; the plate outline the page turns touches the follower's roller at the solve's poses; the profile
undercuts where the pitch curve it sends bends tighter than the roller; an edit is written into the file
with its comments kept and the new law read back; and every bad edit is one line, naming the field."""

import json
import math
import re

import numpy as np
import pytest

from sim.front import app
from tests.test_app_api import assert_refused, post

ROLLER_TEXT = None


def _library_text(name):
    from pathlib import Path

    import analytic
    return (Path(analytic.__file__).parent / "library" / f"{name}.toml").read_text()


# ------------------------------------------------------------------------------------------ SVAJ
@pytest.mark.parametrize("name, cam, ends", [
    ("cam_roller", "c1", (90, 210, 240, 360)),       # the file's segments end at these cam angles [deg]
    ("cam_fourbar", "c1", (40, 180, 220, 360)),
])
def test_svaj_agrees_with_finite_differences_of_the_displacement_sent(server, name, cam, ends):
    status, data = post(server, "/api/cam", {"mechanism": name})
    assert status == 200, data
    s = data["cams"][cam]["svaj"]
    theta = np.radians(s["theta"])                   # the derivatives are per radian of cam angle
    h = theta[1] - theta[0]
    y = {k: np.asarray(s[k]) for k in "svaj"}
    # central differences inside each segment (a jerk, and so an acceleration's slope, may jump at an end)
    deg = np.degrees(theta)
    inside = np.ones(len(theta), bool)
    inside[[0, -1]] = False
    for e in (0,) + ends:
        inside &= np.abs(deg - e) > 1.01 * np.degrees(h)
    i = np.flatnonzero(inside)
    for lower, higher in (("s", "v"), ("v", "a"), ("a", "j")):
        fd = (y[lower][i + 1] - y[lower][i - 1]) / (2 * h)
        peak = np.max(np.abs(y[higher]))
        assert peak > 0
        # central difference error h^2/6 |f'''| on a 0.5 deg step: ~1e-4 of the peak for these laws' jerk slopes
        assert np.max(np.abs(fd - y[higher][i])) < 2e-3 * peak, (lower, higher)
    # the units say what the numbers are: the file's length unit (or deg for an arm) per radian
    assert s["units"]["v"].endswith("/rad") and s["units"]["j"].endswith("/rad^3")


def test_the_displacement_sent_is_the_file_law_by_hand(server):
    # cam_roller: dwell to 90deg, then a cycloidal rise of 20 mm over 120deg (Norton eq. 8.11)
    status, data = post(server, "/api/cam", {"mechanism": "cam_roller"})
    s = data["cams"]["c1"]["svaj"]
    theta = np.asarray(s["theta"])
    k = np.flatnonzero((theta > 90) & (theta < 210))
    x = (theta[k] - 90) / 120
    hand = 0.020 * (x - np.sin(2 * np.pi * x) / (2 * np.pi))
    assert np.max(np.abs(np.asarray(s["s"])[k] - hand)) < 1e-12      # the same closed form: rounding only
    assert s["units"]["s"] == "m"


# ----------------------------------------------------------------------------------- drawn plates
def _distance_to_polygon(p, poly):
    a, b = poly, np.roll(poly, -1, axis=0)
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    return float(np.min(np.hypot(*(a + t[:, None] * ab - p).T)))


def _turned(outline, pivot, a, b):
    """The page's turn (app.js drawCam): the outline about the pivot by the angle from a to b."""
    ang = math.atan2(b[1] - a[1], b[0] - a[0])
    c, s = math.cos(ang), math.sin(ang)
    o = np.asarray(outline)
    return np.column_stack([pivot[0] + c * o[:, 0] - s * o[:, 1], pivot[1] + s * o[:, 0] + c * o[:, 1]])


@pytest.mark.parametrize("name", ["cam_roller", "cam_fourbar"])
def test_the_page_plate_touches_the_roller_at_the_solve_poses(server, name):
    status, data = post(server, "/api/solve", {"mechanism": name, "samples": 25})
    assert status == 200, data
    (cm,) = data["describe"]["cams"]
    assert cm["roller"] > 0
    pts = data["points"]
    status, panel = post(server, "/api/cam", {"mechanism": name})
    profile = panel["cams"][cm["name"]]["profile"]
    for i in range(0, 24, 3):
        at = {p: (pts[p]["x"][i], pts[p]["y"][i]) for p in (cm["pivot"], *cm["ref"], cm["point"])}
        f = np.array(at[cm["point"]])
        plate = _turned(cm["outline"], at[cm["pivot"]], at[cm["ref"][0]], at[cm["ref"][1]])
        # 360 corners on the profile: a chord's sag (r dtheta^2 / 8, ~1e-5 m on a 60 mm cam) is the gap's slack
        assert _distance_to_polygon(f, plate) == pytest.approx(cm["roller"], abs=5e-5), i
        # the panel's profile (720 corners) is the same outline
        panel_plate = _turned(np.column_stack([profile["x"], profile["y"]]), at[cm["pivot"]], at[cm["ref"][0]],
                              at[cm["ref"][1]])
        assert _distance_to_polygon(f, panel_plate) == pytest.approx(cm["roller"], abs=2e-5), i


def test_a_flat_face_is_drawn_on_the_plate_across_its_contact(server):
    status, data = post(server, "/api/solve", {"mechanism": "cam_flat", "samples": 13})
    (cm,) = data["describe"]["cams"]
    ux, uy = cm["face"]["u"]
    lo, hi = cm["face"]["ends"]
    assert hi - lo == pytest.approx(0.040, abs=1e-9)          # the file's face_width, 40 mm
    pts = data["points"]
    for i in range(12):
        at = {p: (pts[p]["x"][i], pts[p]["y"][i]) for p in (cm["pivot"], *cm["ref"], cm["point"])}
        plate = _turned(cm["outline"], at[cm["pivot"]], at[cm["ref"][0]], at[cm["ref"][1]])
        f = np.array(at[cm["point"]])
        # the plate lies behind the face's line (along -u from F) and touches it: its support distance is 0
        along = (plate - f) @ np.array([ux, uy])
        assert np.max(along) == pytest.approx(0.0, abs=5e-5)    # 360 corners: chord sag on a 47 mm cam
        k = int(np.argmax(along))
        across = float((plate[k] - f) @ np.array([-uy, ux]))
        assert lo - 1e-4 <= across <= hi + 1e-4                 # the contact is on the drawn face


# ------------------------------------------------------------------------------------- edits
SEGS = [{"shape": "dwell", "duration": "90deg"}, {"shape": "cycloidal", "duration": "120deg", "rise": 0.025},
        {"shape": "dwell", "duration": "30deg"}, {"shape": "poly345", "duration": "120deg", "rise": -0.025}]


def test_an_edit_is_written_into_the_file_with_its_comments_and_read_back(server):
    text = _library_text("cam_roller")
    status, data = post(server, "/api/cam", {"text": text, "cam": "c1", "edit": {"segments": SEGS, "roller": 0.008}})
    assert status == 200, data
    new = data["text"]
    assert data["problem"] is None and new is not None
    for comment in ("# the cam's shaft", "# the return spring: from its anchor above", "# N/m"):
        assert comment in new                        # every comment the edit does not touch is kept
    assert re.search(r"roller = 0\.008\b", new) and "rise = 0.025" in new
    # only the edited lines changed: the roller and the two rises (the rows are written as the file writes them)
    import difflib
    changed = [ln for ln in difflib.unified_diff(text.splitlines(), new.splitlines(), lineterm="", n=0)
               if ln[:1] in "+-" and not ln.startswith(("+++", "---"))]
    assert sorted(changed) == sorted([
        "-roller = 0.010", "+roller = 0.008",
        '-  { shape = "cycloidal", duration = "120deg", rise = 0.020 },',
        '+  { shape = "cycloidal", duration = "120deg", rise = 0.025 },',
        '-  { shape = "poly345", duration = "120deg", rise = -0.020 },',
        '+  { shape = "poly345", duration = "120deg", rise = -0.025 },']), changed
    # read back: the follower's rise is the new 25 mm (the analysis of the new text, not the panel's answer)
    status, solved = post(server, "/api/solve", {"text": new, "samples": 361})
    y = np.asarray(solved["points"]["F"]["y"])
    assert np.ptp(y) == pytest.approx(0.025, abs=1e-9)         # a vertical guide: F's y moves by the rise
    # and the panel's answer is the new law's
    assert max(data["cams"]["c1"]["svaj"]["s"]) == pytest.approx(0.025, abs=1e-12)


def test_a_library_mechanism_is_written_out_then_edited(server):
    status, data = post(server, "/api/cam", {"mechanism": "cam_roller", "cam": "c1", "edit": {"segments": SEGS}})
    assert status == 200, data
    assert "rise = 0.025" in data["text"] and data["mechanism"] == "cam_roller"


@pytest.mark.parametrize("edit, words", [
    ({"segments": SEGS[:1] + [{**SEGS[1], "duration": "100deg"}] + SEGS[2:]}, ("segments", "sum to 340deg", "add 20deg")),
    ({"segments": [{**SEGS[0], "rise": 0.01}] + SEGS[1:]}, ("segment 1", "a dwell does not move")),
    ({"roller": -0.01}, ("roller", "must be > 0")),
    ({"segments": SEGS[:1] + [{"shape": "bogus", "duration": "120deg", "rise": 0.02}] + SEGS[2:]}, ("segment 2", "bogus")),
    ({"segments": [{"shape": "dwell", "duration": "360deg", "speed": 1}]}, ("unknown key", "speed")),
    ({"segments": []}, ("segments",)),
    ({"roller": True}, ("roller",)),
    ({"width": 3}, ("edit.width",)),
])
def test_a_bad_edit_is_one_line_naming_the_field_and_nothing_is_written(server, edit, words):
    status, data = post(server, "/api/cam", {"mechanism": "cam_roller", "cam": "c1", "edit": edit})
    assert_refused(server, status, data)
    for w in words:
        assert w in data["error"], data["error"]
    assert "<upload>" not in data["error"]


def test_an_edit_that_undercuts_is_drawn_marked_and_refused(server):
    # a steep rise: 40 mm in 30deg of cam angle bends the pitch curve tighter than the 10 mm roller
    segs = [SEGS[0], {"shape": "cycloidal", "duration": "30deg", "rise": 0.04}, {"shape": "dwell", "duration": "120deg"},
            {"shape": "poly345", "duration": "120deg", "rise": -0.04}]
    status, data = post(server, "/api/cam", {"mechanism": "cam_roller", "cam": "c1", "edit": {"segments": segs}})
    assert status == 200, data
    assert data["text"] is None                      # nothing written
    assert "undercuts at cam angle" in data["problem"] and "\n" not in data["problem"]
    cam = data["cams"]["c1"]
    mark = cam["undercut"]
    named = float(re.search(r"cam angle ([\d.]+)deg", data["problem"])[1])
    assert mark["theta"] == pytest.approx(named, abs=0.05)     # the mark is where the line says (4 digits)
    # independently: the pitch curve sent bends tighter than the roller there (circle through 3 neighbours)
    px, py = np.asarray(cam["pitch"]["x"]), np.asarray(cam["pitch"]["y"])
    k = int(np.argmin(np.abs(np.asarray(cam["profile"]["theta"]) - mark["theta"])))
    a, b, c = (np.array([px[j], py[j]]) for j in (k - 1, k, k + 1))
    area2 = abs((b - a)[0] * (c - a)[1] - (b - a)[1] * (c - a)[0])
    radius = np.linalg.norm(b - a) * np.linalg.norm(c - b) * np.linalg.norm(c - a) / (2 * area2)
    assert radius < 0.010
    # and the profile's samples there are flagged red for the page
    assert any(cam["profile"]["undercut"][max(0, k - 3):k + 4])
    # a sound cam flags none
    status, good = post(server, "/api/cam", {"mechanism": "cam_roller"})
    assert good["cams"]["c1"]["undercut"] is None and not any(good["cams"]["c1"]["profile"]["undercut"])


def test_the_largest_pressure_angle_is_the_pitch_curve_normal_against_the_guide(server):
    # independently of the server's pressure angle: from the pitch curve it sends (finite differences of P(theta)
    # give its tangent; the normal turned to the world at that cam angle) against the vertical guide
    status, data = post(server, "/api/cam", {"mechanism": "cam_roller"})
    cam = data["cams"]["c1"]
    px, py = np.asarray(cam["pitch"]["x"]), np.asarray(cam["pitch"]["y"])
    theta = np.radians(cam["profile"]["theta"])
    tx, ty = np.roll(px, -1) - np.roll(px, 1), np.roll(py, -1) - np.roll(py, 1)
    nx, ny = -ty, tx                                  # a normal of the cam-frame pitch curve
    wx = np.cos(theta) * nx - np.sin(theta) * ny      # turned to the world by the cam angle
    wy = np.sin(theta) * nx + np.cos(theta) * ny
    pa = np.degrees(np.arctan2(np.abs(wx), np.abs(wy)))   # from the guide's +y direction
    mark = cam["pressure_angle_max"]
    # 0.5 deg samples and central differences: the maximum moves by less than a tenth of a degree
    assert np.max(pa) == pytest.approx(mark["value"], abs=0.1)
    assert math.degrees(theta[int(np.argmax(pa))]) == pytest.approx(mark["theta"], abs=1.0)


def test_the_app_page_has_the_cam_tab(server):
    from tests.test_app_api import request
    status, _, page = request(server, "GET", "/")
    text = page.decode()
    assert 'id="tab-cam"' in text and 'id="cam-segments"' in text and 'id="cam-profile"' in text
    assert "/api/cam" in app.ROUTES
    assert json.dumps(app.describe(__import__("sim.service", fromlist=["load"]).load("fourbar"))["cams"]) == "[]"


def test_a_flat_face_cusp_is_marked_where_base_plus_lift_plus_its_curvature_goes_negative(server):
    # Norton eq. 8.31: a flat face's profile has radius of curvature r_b + s + s'' (s'' per rad^2); a 25 mm
    # modified-sine rise over 30deg on a 35 mm base circle drives it negative: a cusp, drawn and refused
    segs = [{"shape": "dwell", "duration": "80deg"}, {"shape": "modified_sine", "duration": "30deg", "rise": 25},
            {"shape": "dwell", "duration": "130deg"}, {"shape": "cycloidal", "duration": "120deg", "rise": -25}]
    status, data = post(server, "/api/cam", {"mechanism": "cam_flat", "cam": "tappet", "edit": {"segments": segs}})
    assert status == 200, data
    assert data["text"] is None and "cusp" in data["problem"]
    cam = data["cams"]["tappet"]
    s = cam["svaj"]
    theta, lift, acc = (np.asarray(s[k]) for k in ("theta", "s", "a"))
    assert s["units"]["s"] == "mm" and s["units"]["a"] == "mm/rad^2"
    rho = 35.0 + lift + acc                          # the file's base radius, 35 mm, in the file's unit
    flagged = np.asarray(cam["profile"]["undercut"])
    t_flag = np.asarray(cam["profile"]["theta"])[flagged]
    # every flagged sample lies where the hand formula is negative (within one 0.5 deg sample of its edge)
    for t in t_flag:
        near = np.abs(theta - t) <= 0.5
        assert np.min(rho[near]) <= 0, t
    assert np.interp(cam["undercut"]["theta"], theta, rho) < 0
    assert cam["undercut"]["theta"] == pytest.approx(theta[np.argmin(rho)], abs=0.5)
