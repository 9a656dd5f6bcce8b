"""Disc cams and followers (SPEC "Cams and followers"; analytic/cams.py, analytic/kinds/cam.py).

Every figure is checked against a construction the code under test does not use: the profile against the
envelope of densely sampled roller circles or of the flat face's tangent lines (the follower placed from
:mod:`analytic.laws` directly), the pressure angle and the radius of curvature against finite differences of
the profile polyline, an eccentric circle with a flat-faced follower (exact harmonic motion, derived by hand
below), the contact force against the follower's Newton equation by hand, and the jump speed against a scan
of the contact force over cam speeds.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import analytic
from analytic import cams, laws
from cli_runner import run

HERE = Path(__file__).resolve().parent
KINDS = HERE / "kinds"
LIBRARY = HERE.parent / "analytic" / "library"


def _law(*segs):
    return laws.Profile(tuple(laws.Segment(s, math.radians(d), r) for s, d, r in segs))


DRDR = _law(("dwell", 90, 0.0), ("cycloidal", 120, 0.020), ("dwell", 30, 0.0), ("poly345", 120, -0.020))


def _translating(contact, law=DRDR, e=0.005, rb=0.030, rr=0.010, gamma=math.pi / 2, face=None):
    """A cam at A = (0.01, -0.02) with a guide of direction gamma at offset e (to its left)."""
    A = (0.01, -0.02)
    n = (-math.sin(gamma), math.cos(gamma))
    return cams.Setup(pivot=A, motion="translating", contact=contact, roller=rr if contact == "roller" else 0.0,
                      face_width=face, base_radius=rb, law=law, direction=gamma, offset=e,
                      origin=(A[0] + e * n[0], A[1] + e * n[1]))


def _centres(setup, theta):
    """The trace point in the cam's frame (from A), from the law alone: world A + e n + (d0 + h) u, d0 by hand,
    turned back by the cam's angle."""
    h = setup.law.at(theta)[0]
    c, s = math.cos(setup.direction), math.sin(setup.direction)
    d0 = math.sqrt((setup.base_radius + setup.roller) ** 2 - setup.offset ** 2)
    x, y = -setup.offset * s + (d0 + h) * c, setup.offset * c + (d0 + h) * s
    ct, st = np.cos(theta), np.sin(theta)
    return np.column_stack([ct * x + st * y, -st * x + ct * y])


def _polar_radius(poly, phi):
    """Where rays from the origin at angles phi leave a closed polygon (the farthest crossing)."""
    a, b = poly, np.roll(poly, -1, axis=0)
    vx, vy = np.cos(phi)[:, None], np.sin(phi)[:, None]
    # a + t (b - a) = r v: solve for (r, t) per ray and edge
    ex, ey = (b - a)[None, :, 0], (b - a)[None, :, 1]
    det = ex * vy - ey * vx
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (a[None, :, 0] * vy - a[None, :, 1] * vx) / -det
        r = (a[None, :, 0] * ey - a[None, :, 1] * ex) / -det
    ok = (t >= 0) & (t <= 1) & (r > 0)
    return np.max(np.where(ok, r, -np.inf), axis=1)


# ------------------------------------------------------------------------------------------ profiles
def test_roller_profile_is_the_envelope_of_the_roller_circles():
    st = _translating("roller")
    geo = cams.build(st)
    centres = _centres(st, np.linspace(0, 2 * np.pi, 20000, endpoint=False))
    phi = np.linspace(-np.pi, np.pi, 361)[:-1]
    v = np.column_stack([np.cos(phi), np.sin(phi)])
    # the cam along each ray ends where the ray first enters a roller circle (the roller sweeps the rest)
    cv = v @ centres.T
    disc = cv ** 2 - np.sum(centres ** 2, axis=1)[None, :] + st.roller ** 2
    enter = np.where(disc >= 0, cv - np.sqrt(np.maximum(disc, 0)), np.inf)
    envelope = np.min(np.where(enter > 0, enter, np.inf), axis=1)
    got = _polar_radius(geo.profile, phi)
    # 20000 circles scallop by (2 pi 0.06 / 20000)^2 / (8 r_r) ~ 5e-9 m; the 3600-point polygon's chords sag
    # by at most (2 pi 0.06 / 3600)^2 / (8 rho_min) ~ 5e-8 m
    assert np.max(np.abs(got - envelope)) <= 1e-7


def test_profile_is_counter_clockwise_closed_and_dense():
    geo = cams.build(_translating("roller"))
    p = geo.profile
    area = 0.5 * np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1])
    assert area > 0 and len(p) == cams.DENSE
    gaps = np.hypot(*(np.roll(p, -1, axis=0) - p).T)
    assert gaps.max() <= 2 * np.pi * 0.06 / cams.DENSE * 1.5     # no jump: each step at most 1.5 x the mean arc


def test_flat_face_profile_is_the_envelope_of_the_face_lines():
    st = _translating("flat", e=-0.004, gamma=math.radians(75))
    geo = cams.build(st)
    theta = np.linspace(0, 2 * np.pi, 4000, endpoint=False)
    d = st.base_radius + st.law.at(theta)[0]
    u = np.column_stack([np.cos(st.direction - theta), np.sin(st.direction - theta)])   # R(-theta) u
    reach = geo.profile @ u.T                                  # (profile points, lines)
    # the face touches the outline at every angle (the support function is d) ...
    # (3600 vertices: a vertex sits at most (2 pi 0.05 / 3600)^2 / (8 rho) ~ 1e-8 m inside a tangent line)
    assert np.max(np.abs(reach.max(axis=0) - d)) <= 5e-8
    # ... and no point of the outline crosses any face line (rounding of the dot products)
    assert np.max(reach - d[None, :]) <= 1e-12


def test_knife_profile_is_the_trace_points_path():
    st = _translating("knife", rr=0.0)
    geo = cams.build(st)
    ref = _centres(st, geo.theta)
    assert np.max(np.abs(geo.contact_cam - ref)) <= 1e-15 + 1e-12 * 0.05   # the same point, rounding


# --------------------------------------------------------------------- pressure angle and curvature
def _fd_tangent_and_rho(points):
    """Unit tangents and signed radii of curvature of a closed polyline by central differences (the circle
    through each point and its neighbours); positive where it turns the way it runs (clockwise here:
    the cam's frame sees the follower go round clockwise)."""
    a, b, c = np.roll(points, 1, axis=0), points, np.roll(points, -1, axis=0)
    t = c - a
    t /= np.hypot(t[:, 0], t[:, 1])[:, None]
    ab, bc, ca = np.hypot(*(b - a).T), np.hypot(*(c - b).T), np.hypot(*(a - c).T)
    cross = (b - a)[:, 0] * (c - b)[:, 1] - (b - a)[:, 1] * (c - b)[:, 0]
    return t, -ab * bc * ca / (2 * cross)


@pytest.mark.parametrize("contact", ["roller", "knife"])
def test_pressure_angle_and_curvature_match_finite_differences(contact):
    st = _translating(contact, rr=0.010 if contact == "roller" else 0.0)
    geo = cams.build(st, 36000)
    t, rho = _fd_tangent_and_rho(geo.contact_cam)
    # the normal is square to the outline's tangent (the profile made from it must agree with it)
    ndot = np.abs(np.sum(t * geo.normal_cam, axis=1))
    assert ndot.max() <= 1e-6                              # central differences: (0.01 deg)^2 x curvature terms
    finite = np.abs(geo.rho) < 1.0
    # three-point circles at 0.01 deg: relative error ~ (h / rho)^2 ~ 1e-8; and where the law's acceleration
    # jumps (cycloid / 3-4-5 joins) the circle straddles two curvatures: those samples are left out
    jumps = np.zeros_like(finite)
    for k in np.cumsum([0, 90, 120, 30, 120]):
        jumps |= np.abs(((np.degrees(geo.theta) - k + 180) % 360) - 180) < 0.02
    ok = finite & ~jumps
    assert np.max(np.abs(rho[ok] - geo.rho[ok]) / np.abs(geo.rho[ok])) <= 1e-5
    # the pressure angle against the world normal from the finite-difference tangent: the outline turned by
    # the cam's angle, its outward normal (left of a clockwise run) against the guide's direction
    c, s = np.cos(geo.theta), np.sin(geo.theta)
    tx, ty = c * t[:, 0] - s * t[:, 1], s * t[:, 0] + c * t[:, 1]
    nx, ny = -ty, tx
    ux, uy = math.cos(st.direction), math.sin(st.direction)
    pa = np.arctan2(ux * ny - uy * nx, ux * nx + uy * ny)
    assert np.max(np.abs(pa - geo.pressure_angle)) <= 1e-6    # the tangent's O(h^2) error, in rad


def test_pressure_angle_by_the_textbook_formula():
    """Translating roller follower with offset: tan(phi) = (s' - e) / (s + sqrt(Rp^2 - e^2)) (Norton, Design
    of Machinery, 5th ed., eq. 8.29, offset e measured the other way round: here e is to the guide's left,
    so the formula reads (s' + e)). Sign: positive where the normal leans to the guide's left."""
    st = _translating("roller", e=0.007)
    geo = cams.build(st)
    h, h1, _, _ = st.law.at(geo.theta)
    Rp = st.base_radius + st.roller
    expect = np.arctan((h1 + st.offset) / (h + math.sqrt(Rp ** 2 - st.offset ** 2)))
    assert np.max(np.abs(geo.pressure_angle - expect)) <= 1e-13     # rounding of two atan2s


# ------------------------------------------------------------- exact case: an eccentric circle, flat face
def test_eccentric_circle_with_a_flat_face_is_exact_harmonic_motion():
    """By hand: a circle of radius R whose centre sits eps from the pivot at angle c0 in the cam's frame. A
    flat face square to the guide u rests on it at d(theta) = max over the circle of p . R(-theta) u
    = eps cos(gamma - theta - c0) + R: harmonic motion of stroke 2 eps; the face touches at the circle's
    point in the face's normal direction, d + d'' = R everywhere (the outline's radius is R), and the contact
    sits along the face -d' - e = -eps sin(gamma - theta - c0) - e from the foot (the face's line is square
    to the guide whatever the offset e, so the circle is the same): a travel of 2 eps. (The setup of the
    textbook problem: a radial flat-faced follower with simple harmonic motion out and back in one turn,
    stroke 50 mm, least radius 25 mm: the contour is a circle of radius 50 mm about a centre 25 mm off the
    pivot, and the face must be at least 50 mm long.)"""
    eps, R, gamma = 0.025, 0.050, math.pi / 2
    law = _law(("harmonic", 180, 2 * eps), ("harmonic", 180, -2 * eps))
    e = 0.004                                   # an offset face: the same circle, the contact off the foot
    st = _translating("flat", law=law, e=e, rb=R - eps, gamma=gamma)
    geo = cams.build(st)
    # the law starts at its lowest (theta = 0): gamma - 0 - c0 = pi, so the centre is at c0 = gamma - pi
    c0 = gamma - math.pi
    centre = eps * np.array([math.cos(c0), math.sin(c0)])
    radius = np.hypot(*(geo.profile - centre).T)
    assert np.max(np.abs(radius - R)) <= 1e-15 + 1e-13 * R            # a circle, to rounding
    assert np.max(np.abs(geo.rho - R)) <= 1e-13 * R
    assert np.max(np.abs(geo.pressure_angle)) == 0.0                   # the normal is the guide's direction
    along = -eps * np.sin(gamma - geo.theta - c0) - e
    assert np.max(np.abs(geo.face_offset - along)) <= 1e-15 + 1e-13 * eps
    assert geo.face_travel == pytest.approx(2 * eps, rel=1e-6)         # sin sampled at 0.1 deg: 1 - cos(0.05deg)
    assert geo.rho_min == pytest.approx(R, rel=1e-13)


def test_a_given_eccentric_circle_moves_a_flat_follower_harmonically():
    eps, R = 0.02, 0.045
    phi = np.linspace(0, 2 * np.pi, 7200, endpoint=False)
    c0 = math.radians(30)
    outline = np.column_stack([eps * math.cos(c0) + R * np.cos(phi), eps * math.sin(c0) + R * np.sin(phi)])
    st = _translating("flat", e=0.003, rb=R - eps)
    lift = cams.polygon_lift(st, outline)
    theta = np.linspace(0, 2 * np.pi, 997)
    h, h1, h2, _ = lift.at(theta)
    d = eps * np.cos(st.direction - theta - c0) + R
    # the polygon's support falls short of the circle's by at most R (1 - cos(pi / 7200)) ~ 4e-9 m; the periodic
    # spline of 1440 samples adds (2 pi / 1440)^4 / 384 x eps ~ 2e-11 m, its slope ~ 1e-8 m/rad
    assert np.max(np.abs(st.base_radius + h - d)) <= 1e-8
    assert np.max(np.abs(h1 - eps * np.sin(st.direction - theta - c0))) <= 1e-6
    assert np.max(np.abs(h2 + eps * np.cos(st.direction - theta - c0))) <= 1e-4 * eps * 10


def test_a_designed_profile_read_back_gives_its_law():
    for contact in ("roller", "knife", "flat"):
        st = _translating(contact, rr=0.010 if contact == "roller" else 0.0)
        geo = cams.build(st, 7200)
        lift = cams.polygon_lift(st, geo.profile)
        theta = np.linspace(0, 2 * np.pi, 721)
        err = np.abs(lift.at(theta)[0] - st.law.at(theta)[0])
        # 7200 vertices: the follower rides on the chords, (2 pi 0.06 / 7200)^2 / (8 rho) ~ 1e-8 m below the
        # outline; the spline through 1440 lifts of a law whose acceleration jumps (cycloid / 3-4-5 ends) adds
        # ~ jump x (2 pi / 1440)^2 / 8 ~ 1e-7 m
        assert err.max() <= 3e-7, contact


# --------------------------------------------------------------------------------- oscillating
def test_oscillating_roller_profile_is_the_envelope_of_its_roller_circles():
    law = _law(("cycloidal", 100, math.radians(12)), ("dwell", 50, 0.0), ("poly345", 110, -math.radians(12)),
               ("dwell", 100, 0.0))
    A, B, arm, rr, rb = (0.0, 0.0), (0.06, 0.045), 0.055, 0.008, 0.025
    st = cams.Setup(pivot=A, motion="oscillating", contact="roller", roller=rr, face_width=None, base_radius=rb,
                    law=law, arm_pivot=B, arm=arm)
    geo = cams.build(st)
    # by hand: psi0 where |B + arm w - A| = rb + rr, on the side where a counter-clockwise turn lifts
    D = math.hypot(*B)
    g = math.acos((arm ** 2 + D ** 2 - (rb + rr) ** 2) / (2 * arm * D))
    psi0 = [p for p in (math.atan2(-B[1], -B[0]) + g, math.atan2(-B[1], -B[0]) - g)
            if math.cos(p) * (B[1] + arm * math.sin(p)) - math.sin(p) * (B[0] + arm * math.cos(p)) > 0][0]
    theta = np.linspace(0, 2 * np.pi, 20000, endpoint=False)
    psi = psi0 + law.at(theta)[0]
    x, y = B[0] + arm * np.cos(psi), B[1] + arm * np.sin(psi)
    ct, s_ = np.cos(theta), np.sin(theta)
    centres = np.column_stack([ct * x + s_ * y, -s_ * x + ct * y])
    phi = np.linspace(-np.pi, np.pi, 361)[:-1]
    v = np.column_stack([np.cos(phi), np.sin(phi)])
    cv = v @ centres.T
    disc = cv ** 2 - np.sum(centres ** 2, axis=1)[None, :] + rr ** 2
    enter = np.where(disc >= 0, cv - np.sqrt(np.maximum(disc, 0)), np.inf)
    envelope = np.min(np.where(enter > 0, enter, np.inf), axis=1)
    # as for the translating roller: scallops ~ 5e-9 m, the polygon's sag ~ 5e-8 m
    assert np.max(np.abs(_polar_radius(geo.profile, phi) - envelope)) <= 1e-7


def test_an_arms_pressure_angle_is_from_its_swing_to_the_normal_by_finite_differences():
    """SPEC: the pressure angle is the signed angle from the follower's direction of motion (an arm's
    counter-clockwise tangent at the trace point, square to the arm) to the contact normal. Here the roller
    centres are placed by hand (psi0 as above, then the law), the normal is square to their polyline's
    finite-difference tangent, and the swing's direction is (-sin psi, cos psi)."""
    law = _law(("cycloidal", 100, math.radians(12)), ("dwell", 50, 0.0), ("poly345", 110, -math.radians(12)),
               ("dwell", 100, 0.0))
    A, B, arm, rr, rb = (0.0, 0.0), (0.06, 0.045), 0.055, 0.008, 0.025
    st = cams.Setup(pivot=A, motion="oscillating", contact="roller", roller=rr, face_width=None, base_radius=rb,
                    law=law, arm_pivot=B, arm=arm)
    n = 36000
    geo = cams.build(st, n)
    D = math.hypot(*B)
    g = math.acos((arm ** 2 + D ** 2 - (rb + rr) ** 2) / (2 * arm * D))
    psi0 = [p for p in (math.atan2(-B[1], -B[0]) + g, math.atan2(-B[1], -B[0]) - g)
            if math.cos(p) * (B[1] + arm * math.sin(p)) - math.sin(p) * (B[0] + arm * math.cos(p)) > 0][0]
    theta = np.arange(n) * (2 * np.pi / n)
    psi = psi0 + law.at(theta)[0]
    x, y = B[0] + arm * np.cos(psi), B[1] + arm * np.sin(psi)
    ct, s_ = np.cos(theta), np.sin(theta)
    centres = np.column_stack([ct * x + s_ * y, -s_ * x + ct * y])          # the pitch curve, cam's frame
    t, _ = _fd_tangent_and_rho(centres)
    tx, ty = ct * t[:, 0] - s_ * t[:, 1], s_ * t[:, 0] + ct * t[:, 1]        # the tangent turned to the world
    nx, ny = -ty, tx                                                        # outward: left of a clockwise run
    ux, uy = -np.sin(psi), np.cos(psi)                                      # the swing at F
    pa = np.arctan2(ux * ny - uy * nx, ux * nx + uy * ny)
    assert np.max(np.abs(pa - geo.pressure_angle)) <= 1e-6                  # the tangent's O(h^2) error, in rad
    assert np.max(np.abs(pa)) > math.radians(5)                             # a real swing, not a near-zero angle


# ----------------------------------------------------------------------------------- checks refused
def test_an_undercut_is_refused_saying_where():
    st = _translating("roller", rr=0.030, rb=0.012, e=0.0,
                      law=_law(("dwell", 60, 0.0), ("cycloidal", 50, 0.030), ("poly345", 90, -0.030),
                               ("dwell", 160, 0.0)))       # not symmetric: one worst angle
    geo = cams.build(st)
    msg = cams.problems(geo)
    assert msg and "undercuts at cam angle" in msg
    deg = float(msg.split("cam angle ")[1].split("deg")[0])
    theta = np.arange(36000) * (2 * np.pi / 36000)
    _, rho = _fd_tangent_and_rho(_centres(st, theta))     # the law's roller centres, by finite differences
    worst = np.degrees(theta[np.argmin(np.where(rho > 0, rho, np.inf))])
    assert abs(deg - worst) <= 0.1                          # the check samples every 0.1 deg


def test_a_flat_face_cusp_and_a_narrow_face_are_refused():
    cusp = _translating("flat", rb=0.005, e=0.0)
    assert "cusp" in cams.problems(cams.build(cusp))
    wide = cams.build(_translating("flat", e=0.0))
    assert cams.problems(wide) is None
    narrow = _translating("flat", e=0.0, face=0.9 * wide.face_travel)
    assert "face_width" in cams.problems(cams.build(narrow))


# --------------------------------------------------------------------------------- the mechanism
def test_follower_columns_and_jsons(tmp_path):
    r = run("analyze", LIBRARY / "cam_roller.toml", "--json")
    assert r.returncode == 0, r.stderr
    cam = json.loads(r.stdout)["cams"]["c1"]
    assert set(cam) == {"pressure_angle_max", "rho_min", "profile"}
    m = analytic.load(str(LIBRARY / "cam_roller.toml"))
    geo = cams.geometry(m, "c1")
    assert cam["rho_min"] == pytest.approx(geo.rho_min, rel=1e-15)
    assert np.allclose(cam["profile"], geo.profile, rtol=0, atol=1e-15)
    r = run("forces", LIBRARY / "cam_roller.toml", "--json")
    assert r.returncode == 0, r.stderr
    f = json.loads(r.stdout)
    joint = next(j for j in f["joints"] if j["kind"] == "cam")
    assert joint["name"] == "c1" and len(joint["N"]) == f["samples"]
    assert set(f["cams"]["c1"]) == {"contact_min", "jump_speed"}
    assert f["cams"]["c1"]["contact_min"] == pytest.approx(min(joint["N"]), rel=1e-15)


def test_contact_force_by_the_followers_newton_equation():
    """Translating follower of mass m on a vertical guide with the return spring k from R above: along the
    guide N cos(pa) = k (L0 - |R - F|) + m a (the spring pushes down while compressed; no gravity)."""
    m = analytic.load(str(LIBRARY / "cam_roller.toml"))
    from sim.service import forces as SF
    fr = SF.forces_run(m, samples=181)
    k, L0, mass = 2000.0, 0.10, 0.2
    sol = fr.solution
    length = 0.12 - sol["yF"]
    N = SF.cam_joints(fr)[0]["N"]
    pa = m.solve(fr.q, fr.qd, fr.qdd)["pa_c1"]
    expect = (k * (L0 - length) + mass * sol["ayF"]) / np.cos(pa)
    assert np.max(np.abs(N - expect)) <= 1e-10 * np.max(np.abs(expect))   # rounding


@pytest.mark.parametrize("alpha", [0.0, 20.0])
def test_jump_speed_matches_a_scan_of_the_contact_force(tmp_path, alpha):
    """The file's law run k times faster (omega k w0, alpha k^2 a0: the same cam angles at every sample) until
    the least contact force reaches 0, by a scan and bisection of the force solve itself; the jump speed is
    that k times the cam's mean speed in the file's run (a steady cam, alpha = 0: its speed)."""
    from sim.service import forces as SF
    text = (LIBRARY / "cam_roller.toml").read_text()
    assert "alpha = 0.0" in text
    path = tmp_path / "cam.toml"
    path.write_text(text.replace("alpha = 0.0", 'alpha = "alpha1"').replace("[parameters]",
                                                                           f"[parameters]\nalpha1 = {alpha!r}"))
    base = analytic.load(str(path))
    fr = SF.forces_run(base, samples=721)
    w_jump = SF.cams_record(fr)["c1"]["jump_speed"]
    mean = float(np.mean(np.abs(fr.solution["omega1"])))
    w0 = 2 * np.pi

    def least(k):
        run_ = SF.forces_run(base.with_values(omega1=k * w0, alpha1=k * k * alpha), samples=721)
        return float(np.min(SF.cam_joints(run_)[0]["N"]))

    ks = np.linspace(0.5, 1.5, 11) * w_jump / mean
    mins = np.array([least(k) for k in ks])
    i = int(np.argmax(mins <= 0))
    assert mins[i - 1] > 0 >= mins[i]                        # the scan's sign change brackets it ...
    lo, hi = ks[i - 1], ks[i]
    for _ in range(40):                                      # ... and bisection on the scan finds it
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if least(mid) > 0 else (lo, mid)
    assert w_jump / mean == pytest.approx(0.5 * (lo + hi), rel=1e-9)   # bisection to 2^-40 of the bracket


@pytest.mark.parametrize("edit, says", [
    (('{ shape = "dwell", duration = "30deg" }', '{ shape = "dwell", duration = "40deg" }'), "sum to 370deg"),
    (('{ shape = "dwell", duration = "30deg" }', '{ shape = "dwell", duration = "30deg", rise = 0.01 }'),
     "a dwell does not move"),
    (("roller = 0.010", "roller = -0.010"), "roller"),
    (("base_radius = 0.030", "base_radius = 0"), "base_radius"),
    (('follower = "translating"', 'follower = "sliding"'), "not a follower kind"),
])
def test_bad_input_is_one_line_exit_2_nothing_written(tmp_path, edit, says):
    text = (LIBRARY / "cam_roller.toml").read_text()
    assert edit[0] in text
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace(edit[0], edit[1]))
    out = tmp_path / "out.csv"
    r = run("analyze", bad, "--csv", out)
    assert r.returncode == 2 and says in r.stderr, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1 and "Traceback" not in r.stderr
    assert not out.exists()


def test_check_prints_the_cams_figures():
    r = run("check", LIBRARY / "cam_roller.toml")
    assert r.returncode == 0
    m = analytic.load(str(LIBRARY / "cam_roller.toml"))
    geo = cams.geometry(m, "c1")
    line = next(ln for ln in r.stdout.splitlines() if "largest pressure angle" in ln)
    assert f"{math.degrees(geo.pressure_angle_max):.4g}deg" in line and f"{geo.rho_min:.6g} m" in line


# ---------------------------------------------------------------------------------------------- parts
def _polygon_distance(points, poly):
    """The distance from each point to the closed polygon's edges."""
    a, b = poly, np.roll(poly, -1, axis=0)
    ab = b - a
    t = np.clip(np.einsum("pkj,kj->pk", points[:, None, :] - a[None], ab) / np.sum(ab * ab, axis=1), 0, 1)
    near = a[None] + t[..., None] * ab[None]
    return np.min(np.hypot(*(points[:, None, :] - near).transpose(2, 0, 1)), axis=1)


def test_the_cam_plate_is_exported_within_1e_4_of_the_size(tmp_path):
    import ezdxf
    r = run("export", "cam_roller", "--dxf", tmp_path / "c.dxf", "--stl", tmp_path / "stl", "--bom",
            tmp_path / "bom.csv")
    assert r.returncode == 0, r.stderr
    m = analytic.load("cam_roller")
    dense = cams.geometry(m, "c1").profile              # the cam's frame; at the pose the cam angle is 0
    doc = ezdxf.readfile(tmp_path / "c.dxf")
    plate = [e for e in doc.modelspace() if e.dxftype() == "LWPOLYLINE" and e.dxf.layer == "1"]
    assert len(plate) == 1
    outline = np.array([(x, y) for x, y, *_ in plate[0].get_points()])
    tol = 1e-4 * m.size                                 # SPEC: the outline within 1e-4 of the size
    assert np.max(_polygon_distance(dense, outline)) <= tol
    assert np.max(_polygon_distance(outline, dense)) <= tol
    holes = [e for e in doc.modelspace() if e.dxftype() == "CIRCLE" and e.dxf.layer == "1"]
    assert any(math.hypot(h.dxf.center[0], h.dxf.center[1]) <= 1e-12 for h in holes)   # the shaft's, at A
    stl = (tmp_path / "stl" / "1.stl").read_bytes()
    tri = np.frombuffer(stl[84:], dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]))
    xy = tri["v"][:, :, :2].reshape(-1, 2).astype(float)
    # the solid in its link's frame: the plate's extent matches the profile's (float32 vertices: 1e-7 relative)
    assert np.allclose([xy[:, 0].min(), xy[:, 0].max(), xy[:, 1].min(), xy[:, 1].max()],
                       [dense[:, 0].min(), dense[:, 0].max(), dense[:, 1].min(), dense[:, 1].max()], atol=tol)
    bom = (tmp_path / "bom.csv").read_text().splitlines()
    assert any(line.startswith("1,") and ",cam," in line for line in bom)


def test_the_cam_rows_of_the_sheet_plot_the_law_over_the_cam_angle():
    from analytic.quantities import Display
    from sim.output import plot
    m = analytic.load("cam_flat")                       # a file in mm: the lift is drawn in mm
    fig = plot.cam_figure(m, Display("mm"))
    lift = fig.axes[0].lines[0]
    theta = np.radians(lift.get_xdata())
    law = cams.elements(m)["tappet"]["segments"]
    assert np.allclose(lift.get_ydata(), law.at(theta)[0] * 1e3, rtol=0, atol=1e-12)    # m -> mm, rounding
    jerk = fig.axes[3].lines[0]
    assert np.allclose(jerk.get_ydata(), law.at(theta)[3] * 1e3, rtol=0, atol=1e-9)
    pa = fig.axes[4].lines[0]
    assert np.max(np.abs(pa.get_ydata())) == 0.0         # a flat face square to its guide


def test_a_given_profile_file_drives_the_follower_as_its_law_would(tmp_path):
    m = analytic.load("cam_roller")
    outline = cams.geometry(m, "c1", 7200).profile
    (tmp_path / "cam.csv").write_text("x,y\n" + "\n".join(f"{float(x)!r},{float(y)!r}" for x, y in outline) + "\n")
    text = (LIBRARY / "cam_roller.toml").read_text()
    start, end = text.index("segments = ["), text.index("]\n\n[inertia]") + 2
    (tmp_path / "given.toml").write_text(text[:start] + 'profile = "cam.csv"\n' + text[end:])
    given = analytic.load(str(tmp_path / "given.toml"))
    q = np.linspace(0, 2 * np.pi, 361)[:, None]
    a, b = m.solve(q, 2 * np.pi, 0.0), given.solve(q, 2 * np.pi, 0.0)
    # the outline's 7200 chords and the 1440-point spline (see test_a_designed_profile_read_back_gives_its_law)
    assert np.max(np.abs(a["sfollower"] - b["sfollower"])) <= 3e-7
    assert np.max(np.abs(a["dsfollower"] - b["dsfollower"])) <= 1e-4 * np.max(np.abs(a["dsfollower"]))


def test_check_refuses_an_undercut_saying_where(tmp_path):
    text = (LIBRARY / "cam_roller.toml").read_text()
    for a, b in (('{ shape = "dwell", duration = "90deg" }', '{ shape = "dwell", duration = "170deg" }'),
                 ('duration = "120deg", rise = 0.020', 'duration = "40deg", rise = 0.020'),
                 ("base_radius = 0.030", "base_radius = 0.020"), ("roller = 0.010", "roller = 0.015")):
        assert a in text
        text = text.replace(a, b)
    bad = tmp_path / "bad.toml"
    bad.write_text(text)                     # a rise of 20 mm in 40deg: the pitch curve turns on a 12 mm radius
    r = run("check", bad)
    assert r.returncode == 2 and "undercuts at cam angle" in r.stderr and "bad.toml" in r.stderr, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1
    said = float(r.stderr.split("cam angle ")[1].split("deg")[0])
    # where the pitch curve (the roller centres placed from the law alone) turns tightest, by finite differences
    law = _law(("dwell", 170, 0.0), ("cycloidal", 40, 0.020), ("dwell", 30, 0.0), ("poly345", 120, -0.020))
    st = _translating("roller", law=law, rb=0.020, rr=0.015)
    theta = np.arange(36000) * (2 * np.pi / 36000)
    _, rho = _fd_tangent_and_rho(_centres(st, theta))
    worst = np.degrees(theta[np.argmin(np.where(rho > 0, rho, np.inf))])
    assert abs(said - worst) <= 0.1                          # the check samples every 0.1 deg


def test_a_mm_files_cam_refusals_speak_mm(tmp_path):
    """The undercut, the roller and the guide refusals of a cam in a mm file give their lengths in mm (they were
    printed in metres: 0.015 m for a 15 mm roller)."""
    text = (LIBRARY / "cam_roller.toml").read_text()
    for a, b in (('units = "m"', 'units = "mm"'), ("G = [-0.005, 0]", "G = [-5, 0]"),
                 ("R = [-0.005, 0.12]", "R = [-5, 120]"), ("length = 0.02", "length = 20"),
                 ('{ shape = "dwell", duration = "90deg" }', '{ shape = "dwell", duration = "170deg" }'),
                 ('duration = "120deg", rise = 0.020', 'duration = "40deg", rise = 20'), ("rise = -0.020", "rise = -20"),
                 ("base_radius = 0.030", "base_radius = 20"), ("roller = 0.010", "roller = 15"),
                 ("free_length = 0.10", "free_length = 100"), ("stiffness = 2000.0", "stiffness = 2.0"),
                 ("I = 2e-5", "I = 20")):
        assert a in text
        text = text.replace(a, b)
    cases = {"undercut": (text, "the roller (15 mm) is larger than the pitch curve's radius of curvature there ("),
             "roller": (text.replace("roller = 15", "roller = -4"), "field 'roller': -4 mm;"),
             "guide": (text.replace("G = [-5, 0]", "G = [-50, 0]"), "passes 50 mm from the pivot, outside the prime "
                                                                     "circle (35 mm)")}
    for name, (body, said) in cases.items():
        bad = tmp_path / f"{name}.toml"
        bad.write_text(body)
        r = run("check", bad)
        assert r.returncode == 2 and said in r.stderr, (name, r.stderr)
        assert " m " not in r.stderr and " m)" not in r.stderr, (name, r.stderr)   # no metre left in the line
    # the undercut's radius of curvature in mm: the same geometry in metres says 12.x mm as 0.012x m
    rho = float(r_undercut := run("check", tmp_path / "undercut.toml").stderr.split("radius of curvature there (")[1]
                .split(" mm")[0])
    assert 5 < rho < 15, r_undercut.stderr                   # the 20 mm rise in 40deg turns on a ~12 mm radius


def test_check_refuses_a_face_too_narrow(tmp_path):
    text = (LIBRARY / "cam_flat.toml").read_text()
    assert "face_width = 40" in text
    bad = tmp_path / "bad.toml"
    bad.write_text(text.replace("face_width = 40", "face_width = 20"))
    r = run("check", bad)
    # the contact's travel is 22.46 mm (the eccentric-circle test checks the travel by hand); the file is in mm
    assert r.returncode == 2 and "field 'face_width': 20 mm is narrower" in r.stderr, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1


def test_a_tangent_cam_lifts_a_radial_roller_by_the_textbook_flank_formula():
    """A tangent cam (a base circle r1, a nose circle r3 at d from the centre, straight flanks tangent to both:
    the convex hull of the two circles) lifts a radial roller follower of radius r2 on a flank by
    x = (r1 + r2) (1 - cos a) / cos a, a the cam's turn from where the flank begins (S. S. Rattan, Theory of
    Machines, ch. "Cams", tangent cam with reciprocating roller follower: contact on the straight flanks).
    Here, by hand: the flank's normal is at beta = acos((r1 - r3) / d) from the nose's direction (+x), the
    follower runs along +y turned back by theta in the cam's frame, so a = theta - (90deg - beta), and the
    roller stays on the flank while tan(a) (r1 + r2) <= d sin(beta) (the nose's tangent point)."""
    from scipy.spatial import ConvexHull
    r1, r3, d, r2 = 0.030, 0.010, 0.030, 0.008
    t = np.linspace(0, 2 * np.pi, 4000, endpoint=False)
    pts = np.vstack([np.column_stack([r1 * np.cos(t), r1 * np.sin(t)]),
                     np.column_stack([d + r3 * np.cos(t), r3 * np.sin(t)])])
    outline = pts[ConvexHull(pts).vertices]                    # counter-clockwise
    st = cams.Setup(pivot=(0.0, 0.0), motion="translating", contact="roller", roller=r2, face_width=None,
                    base_radius=r1, law=None, direction=math.pi / 2, offset=0.0, origin=(0.0, 0.0))
    lift = cams.polygon_lift(st, outline)
    beta = math.acos((r1 - r3) / d)
    a_end = math.atan(d * math.sin(beta) / (r1 + r2))
    a = np.linspace(0.02, a_end - 0.02, 200)
    theta = a + math.pi / 2 - beta
    x = (r1 + r2) * (1 - np.cos(a)) / np.cos(a)
    # the hull's circle arcs are chords of (2 pi r / 4000): sag r (pi / 4000)^2 / 2 ~ 1e-11 m; the flank is
    # exact; the lift's periodic spline over 1440 angles: the flank's x'''' (r1 + r2) ~ 0.2 m/rad^4 times
    # (2 pi / 1440)^4 / 384 ~ 2e-13 m, with the nose and base joins (a jump in x'') ~ 1e-7 m nearby
    assert np.max(np.abs(lift.at(theta)[0] - x)) <= 2e-7


@pytest.mark.parametrize("contact", ["roller", "knife"])
def test_an_arms_designed_profile_read_back_gives_its_law(contact):
    law = _law(("cycloidal", 100, math.radians(12)), ("dwell", 50, 0.0), ("poly345", 110, -math.radians(12)),
               ("dwell", 100, 0.0))
    st = cams.Setup(pivot=(0.01, -0.02), motion="oscillating", contact=contact,
                    roller=0.008 if contact == "roller" else 0.0, face_width=None, base_radius=0.025, law=law,
                    arm_pivot=(0.07, 0.025), arm=0.055)
    geo = cams.build(st, 3600)
    lift = cams.polygon_lift(st, geo.profile)
    theta = np.linspace(0, 2 * np.pi, 721)
    err = np.abs(lift.at(theta)[0] - law.at(theta)[0])
    # 3600 corners: the roller rides ~(2 pi 0.05 / 3600)^2 / (8 x 0.02) ~ 5e-9 m below the outline; the spline
    # adds ~1e-7 m at the law's acceleration jumps (as for the translating follower); over the arm's 0.055 m
    # that is ~3e-6 rad
    assert err.max() <= 5e-6, contact


def test_a_batch_of_cam_designs_solves_as_each_design_alone(tmp_path):
    from analytic.solver import batch
    text = (LIBRARY / "cam_roller.toml").read_text()
    text = text.replace('omega1 = "360deg"', 'omega1 = "360deg"\nrb = 0.030').replace("base_radius = 0.030",
                                                                                     'base_radius = "rb"')
    (tmp_path / "c.toml").write_text(text)
    base = analytic.load(str(tmp_path / "c.toml"))
    rbs = np.array([0.026, 0.030, 0.034])
    designs = batch.resolve(base, {"rb": rbs})
    q = np.broadcast_to(np.linspace(0, 2 * np.pi, 91), (3, 91))
    got = batch.solve(designs, q[..., None], 2 * np.pi, 0.0)
    for i, rb in enumerate(rbs):
        ref = base.with_values(rb=float(rb)).solve(q[i][:, None], 2 * np.pi, 0.0)
        for name in ("sfollower", "ddsfollower", "pa_c1", "rho_c1"):
            assert np.max(np.abs(got[name][i] - ref[name])) <= 1e-15 + 1e-12 * np.max(np.abs(ref[name])), name


@pytest.mark.parametrize("contact", ["roller", "knife"])
def test_the_search_near_the_followers_line_leaves_out_nothing_that_touches(contact):
    """The pruned search (corners and edges near the follower's line per block of cam angles) against every
    corner and edge at every angle: the same resting place, bit for bit (the pruning only drops candidates
    that cannot touch)."""
    st = _translating(contact, rr=0.010 if contact == "roller" else 0.0, gamma=1.2, e=0.006)
    q = cams.build(st, 3600).profile
    theta = np.arange(1441) * (2 * np.pi / 1440)
    near = np.concatenate([cams._rest_near(st, q, theta[k:k + cams.BAND]) for k in range(0, 1441, cams.BAND)])
    assert np.array_equal(near, cams._rest(st, q, theta))


# ------------------------------------------------------------------------------- a published cam, to its digits
INCH = 0.0254


def test_the_mechanism_packages_readme_cam_to_its_printed_digits():
    """The cam of the README of the ``mechanism`` package (PyPI ``mechanism`` 1.1.8, Gabe Morris,
    https://github.com/gabemorris12/mechanism, README section "Cams", "Problem Statement" and "Solution"):
    dwell 90deg, cycloidal rise 1 in over 90deg, dwell 90deg, cycloidal fall 1 in over 90deg, a radial
    flat-faced follower sized with ``get_base_circle(kind='cycloidal', follower='flat', desired_min_rho=0.25)``;
    it prints "The base circle radius was found to be 1.893" and the minimum face width for the follower was
    found to be 2.55"". Our file (tests/mechanisms/cam_mechanism_readme.toml) takes that printed base radius:
    the profile's smallest radius of curvature must then be the 0.25 in it was sized for, and the face the
    contact sweeps the printed 2.55 in. A peer's printed output, not a textbook's: no textbook example with
    printed base circle, pressure angle or curvature figures was found in the searchable sources."""
    r = run("analyze", HERE / "mechanisms" / "cam_mechanism_readme.toml", "--json")
    assert r.returncode == 0, r.stderr
    cam = json.loads(r.stdout)["cams"]["c1"]
    # rho = Rb + s + s'' for a radial flat face (Rb enters one to one), and the README prints Rb to 0.001 in:
    # half a unit of that last digit
    assert abs(cam["rho_min"] / INCH - 0.25) <= 0.0005, cam["rho_min"] / INCH
    # the printed 2.55 in: half a unit of its last digit (0.01 in)
    assert abs(cam["face_width"] / INCH - 2.55) <= 0.005, cam["face_width"] / INCH
    # a flat face square to its radial guide: the normal is always along the guide (pressure angle 0 by
    # construction, Norton sec. 8.8); rounding only
    assert cam["pressure_angle_max"] <= 1e-12



def test_the_mechanism_packages_readme_roller_cam_to_its_printed_base_circle():
    """The same README's roller follower (radius 1/2 in, sized with ``get_base_circle(kind='cycloidal',
    follower='roller', roller_radius=1/2, max_pressure_angle=30, plot=True)``): its figure
    images/pressure_angle.png is titled "Pressure Angles with R_b = 1.25091", the base circle at which the
    largest pressure angle is the 30 deg asked for. Our file (tests/mechanisms/cam_mechanism_readme_roller.toml)
    takes that printed base radius: our largest pressure angle must be that 30 deg."""
    r = run("analyze", HERE / "mechanisms" / "cam_mechanism_readme_roller.toml", "--json")
    assert r.returncode == 0, r.stderr
    cam = json.loads(r.stdout)["cams"]["c1"]
    # the package takes the largest pressure angle over its samples 0.0062 rad apart, which can miss the peak
    # by 1/2 |phi''| (0.0031 rad)^2 = 0.00097 deg (phi'' = -3.5 /rad^2 there), and prints R_b to 1e-5 in
    # (5e-6 in of R_b: 6e-5 deg)
    assert abs(math.degrees(cam["pressure_angle_max"]) - 30.0) <= 0.0011, math.degrees(cam["pressure_angle_max"])

def test_a_textbook_valve_cam_to_its_printed_answers():
    """A textbook exercise with its printed answers: "Design a cam to raise a valve with simple harmonic motion
    through 50 mm in 1/3 of a revolution, keep it fully raised through 1/12 revolution and to lower it with
    harmonic motion in 1/6 revolution. The valve remains closed during the rest of the revolution. The diameter
    of the roller is 20 mm and the minimum radius of the cam is 25 mm. [...] The axis of the valve rod passes
    through the axis of the camshaft. If the camshaft rotates at uniform speed of 100 r.p.m.; find the maximum
    velocity and acceleration of a valve during raising and lowering. [Ans. 0.39 m/s, 0.78 m/s; 6.17 m/s2,
    24.67 m/s2]" (the exercises of the chapter "Cams" in R.S. Khurmi and J.K. Gupta, Theory of Machines, as
    quoted at https://www.mycoursehelp.com/QA/design-a-cam-to-raise-a-valve-with-simpl/67124/1). The same
    valve is B.K. Sarkar's worked Illustration 3 (Theory of Machines, ch. 9, p. 249), whose FOSSEE companion
    (github.com/FOSSEE/Python-Textbook-Companions, Theory_Of_Machines_by_B._K._Sarkar/Chapter9_1.ipynb)
    prints 6.2 and 24.7 m/s2 for the two accelerations. Our file
    (tests/mechanisms/cam_valve_textbook.toml) states the exercise's data; the answers come from the solved
    motion, sampled every 0.1 deg, and the plate's outline from the analysis' profile."""
    import linkage as lk
    a = lk.analyze(lk.load(HERE / "mechanisms" / "cam_valve_textbook.toml"), samples=3601)
    turn = np.degrees(np.mod(a["phi1"], 2 * np.pi))
    raising, lowering = (turn > 0) & (turn < 120), (turn > 150) & (turn < 210)
    v, acc = a["vyF"], a["ayF"]
    # the printed answers to one unit of their last digit: the book truncates (pi 0.05 x 10.47 / (2 x 2.094)
    # = 0.3927 and 0.7854 m/s are printed 0.39 and 0.78)
    assert abs(v[raising].max() - 0.39) <= 0.01, v[raising].max()
    assert abs(-v[lowering].min() - 0.78) <= 0.01, v[lowering].min()
    assert abs(np.abs(acc[raising]).max() - 6.17) <= 0.01, np.abs(acc[raising]).max()
    assert abs(np.abs(acc[lowering]).max() - 24.67) <= 0.01, np.abs(acc[lowering]).max()
    # the valve closed, then 50 mm up (the roller's centre on the prime circle, 25 + 10 mm, in line)
    assert abs(a["yF"].min() - 0.035) <= 1e-12 and abs(a["yF"].max() - 0.085) <= 1e-12
    r = run("analyze", HERE / "mechanisms" / "cam_valve_textbook.toml", "--json")
    assert r.returncode == 0, r.stderr
    outline = np.asarray(json.loads(r.stdout)["cams"]["c1"]["profile"])
    radius = np.hypot(outline[:, 0], outline[:, 1])
    # the exercise's least cam radius, 25 mm (the closed dwell is that arc), and the nose 50 mm beyond it (the
    # roller in line touches the plate on the line of centres when the valve is fully raised): the outline's
    # 3600 points, rounding only
    assert abs(radius.min() - 0.025) <= 1e-9 and abs(radius.max() - 0.075) <= 1e-9, (radius.min(), radius.max())
