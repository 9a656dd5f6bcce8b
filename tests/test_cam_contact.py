"""A cam and its follower in MuJoCo with real contact (sim/model/cam_contact.py) against closed forms written
here: an eccentric disc cam (radius R, eccentricity e) lifts a flat-faced follower by s = e (1 - cos theta)
and a roller's centre by s = y_c + sqrt((R + r)^2 - x_c^2); Newton's law on the follower gives the contact
force along the guide, m s'' omega^2 + k (s - s_min) + F0, whose zero is where the follower leaves the cam.
"""

import math

import numpy as np
import pytest

from analytic import ParameterError
from analytic.laws import Profile, Segment
from sim.model import cam_contact as cc

R, E, RR, M, K, F0 = 0.03, 0.01, 0.01, 0.1, 1000.0, 10.0
N_PTS = 720
SAGITTA = (R + E) * (2 * math.pi / N_PTS) ** 2 / 8
"""[m] The polyline's chord error against the circle it samples (rho dtheta^2 / 8)."""


def disc(n=N_PTS):
    th = np.linspace(0, 2 * math.pi, n, endpoint=False)
    return np.c_[R * np.cos(th), -E + R * np.sin(th)]          # the disc's centre at (0, -e) in the cam's frame


def centre(theta):
    """The disc's centre in the world at cam angle theta (pivot at the origin)."""
    return E * np.sin(theta), -E * np.cos(theta)


def law(contact, theta):
    """(s, ds/dtheta, d2s/dtheta2) of the follower on the guide x = 0 (direction +y), from the closed forms;
    the roller's derivatives by central differences of its closed form (step 1e-4 rad: error ~1e-9 of s)."""
    if contact == "flat":
        return R - E * np.cos(theta), E * np.sin(theta), E * np.cos(theta)

    def s(t):
        cx, cy = centre(t)
        return cy + np.sqrt((R + RR) ** 2 - cx ** 2)
    d = 1e-4
    return s(theta), (s(theta + d) - s(theta - d)) / (2 * d), (s(theta + d) - 2 * s(theta) + s(theta - d)) / d ** 2


def axial_force(contact, theta, omega):
    """The force the cam must press the follower with along the guide [N] (Newton: m a + spring + preload)."""
    s, _, s2 = law(contact, theta)
    s_min = law(contact, np.array([0.0]))[0][0]
    return M * s2 * omega ** 2 + K * (s - s_min) + F0


def jump_speed(contact):
    """The cam speed [rad/s] at which the smallest axial force first reaches zero: min over theta where
    s'' < 0 of sqrt((k (s - s_min) + F0) / (-m s''))."""
    th = np.linspace(0, 2 * math.pi, 200001)
    s, _, s2 = law(contact, th)
    neg = s2 < 0
    return float(np.min(np.sqrt((K * (s[neg] - s[0]) + F0) / (-M * s2[neg]))))


def first_zero(contact, omega):
    """The first cam angle where the axial force falls to zero at ``omega`` (bisection on a fine grid)."""
    th = np.linspace(0, 2 * math.pi, 200001)
    f = axial_force(contact, th, omega)
    k = int(np.flatnonzero(f <= 0)[0])
    lo, hi = th[k - 1], th[k]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if axial_force(contact, np.array([mid]), omega)[0] > 0 else (lo, mid)
    return 0.5 * (lo + hi)


def cam(contact, omega, profile=None):
    return cc.CamFollower(disc() if profile is None else profile, (0.0, 0.0), omega, contact=contact, roller=RR,
                          face_width=0.06, mass=M, stiffness=K, preload=F0)


# ---------------------------------------------------------------------------------------- geometry
def test_flat_disc_jump_speed_by_hand():
    # N(theta) = F0 + k e (1 - cos) + m e w^2 cos: smallest at theta = pi, zero at w^2 = (F0 + 2 k e) / (m e)
    assert jump_speed("flat") == pytest.approx(math.sqrt((F0 + 2 * K * E) / (M * E)), rel=1e-6)  # grid of 2pi/2e5


@pytest.mark.parametrize("contact", ["flat", "roller", "knife"])
def test_follower_position_of_the_polyline_matches_the_closed_form(contact):
    th = np.linspace(0, 2 * math.pi, 97)
    got = cc.follower_position(cam(contact, 10.0), th)
    if contact == "knife":
        cx, cy = centre(th)
        want = cy + np.sqrt(R ** 2 - cx ** 2)                          # the knife edge on the disc
        tol = SAGITTA + cc.KNIFE_RADIUS * (R + E) * (1 / math.cos(math.asin(E / R)) - 1) + 1e-12
        # the knife's sphere rests r_k (1/cos(pa) - 1) above the edge, pa <= asin(e / R) on this disc
    else:
        want = law(contact, th)[0]
        tol = 1.01 * SAGITTA                                          # the polyline's chord error
    assert np.max(np.abs(got - want)) <= tol


def lobed(n=720):
    """A three-lobed plate r = R (1 + 0.2 cos 3 phi): star-shaped about the pivot, concave between the lobes."""
    phi = np.linspace(0, 2 * math.pi, n, endpoint=False)
    r = R * (1 + 0.2 * np.cos(3 * phi))
    return np.c_[r * np.cos(phi), r * np.sin(phi)]


@pytest.mark.parametrize("make", [lobed, disc])
def test_convex_pieces_are_convex_and_tile_the_plate(make):
    prof = make()
    pieces = cc.convex_pieces(prof)
    n = len(prof)
    area = 0.0
    for i, j in pieces:
        poly = np.vstack([[0.0, 0.0]] + [prof[m % n] for m in range(i, j + 1)])
        a, b = poly, np.roll(poly, -1, axis=0)
        area += 0.5 * float(np.sum(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]))
        e1 = np.roll(poly, -1, axis=0) - poly
        e0 = np.roll(e1, 1, axis=0)
        turn = e0[:, 0] * e1[:, 1] - e0[:, 1] * e1[:, 0]
        assert np.all(turn >= -1e-12 * np.hypot(*e0.T) * np.hypot(*e1.T))   # rounding of collinear points
    a, b = prof, np.roll(prof, -1, axis=0)
    whole = 0.5 * float(np.sum(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]))
    assert area == pytest.approx(whole, rel=1e-12)                   # rounding: the fans sum to the outline
    assert pieces[-1][1] - pieces[0][0] == n                          # once round, no vertex twice


def test_separation_starts_at_the_first_sample_off_the_cam_before_the_gap_grows():
    # samples by hand: a brief lift of 0.02 mm at theta = 0.05, back on the cam at 0.1, off from 0.2 on, the gap
    # past the threshold (1 mm) at 0.4: the separation is the one the large gap belongs to, and it starts at the
    # first sample after the last one in contact (gap <= 0)
    theta = np.array([0.0, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5])
    gap = np.array([0.0, 2e-5, -1e-7, 1e-6, 5e-4, 2e-3, 4e-3])
    force = np.where(gap <= 0, 1.0, 0.0)
    assert cc.separation(theta, force, gap, 1e-3) == (True, 0.2)       # theta's own sample: exact
    assert cc.separation(theta, force, gap, 1e-2) == (False, None)      # never past a 10 mm threshold
    # off the cam from the start: the separation starts at the first sample
    assert cc.separation(theta[3:], force[3:], gap[3:], 1e-3) == (True, 0.2)


def test_outline_not_around_the_pivot_is_refused():
    with pytest.raises(ParameterError, match="profile"):
        cc.build(cc.CamFollower(disc() + [0.05, 0.0], (0.0, 0.0), 10.0, roller=RR, stiffness=K))


def test_spring_missing_is_refused():
    with pytest.raises(ParameterError, match="stiffness and preload"):
        cc.CamFollower(disc(), (0.0, 0.0), 10.0, roller=RR)


# ------------------------------------------------------------------------------------------ MuJoCo
def tracking_tolerance(built, contact, omega):
    """50 static penetrations under the largest force the law needs, plus the chord error: the facets' kinks
    make the stiff contact chatter (its force up to ~5x the law's, measured) and ring about its static depth."""
    th = np.linspace(0, 2 * math.pi, 3601)
    n_max = float(np.max(axial_force(contact, th, omega)))
    return 50 * float(cc.penetration(n_max, built.m_eff, built.timestep)) + SAGITTA


@pytest.mark.parametrize("contact", ["flat", "roller"])
def test_follower_tracks_the_law_at_half_the_jump_speed(contact):
    w = 0.5 * jump_speed(contact)
    built = cc.build(cam(contact, w))
    run = cc.run(built, 1.0)
    err = run.q - law(contact, run.theta)[0]
    assert np.max(np.abs(err)) <= tracking_tolerance(built, contact, w)
    assert not run.separated
    assert run.speed_variation < 1e-5                                # the cam's armature: 1e-6 of the energy


@pytest.mark.parametrize("contact", ["flat", "roller"])
def test_no_separation_at_0_8_the_jump_speed(contact):
    run = cc.run(cc.build(cam(contact, 0.8 * jump_speed(contact))), 1.0)
    assert not run.separated
    assert run.to_dict() == {"separated": False, "first_at": None}


FIRST_TOL = 0.15
"""[rad] Separation's first angle: near zero force the chattering contact lets micro-flights start early
(measured 0.12 rad before the analytic zero on the flat face); the step is 0.003 rad."""


@pytest.mark.parametrize("contact", ["flat", "roller"])
def test_separation_at_1_3_the_jump_speed_where_the_force_vanishes(contact):
    w = 1.3 * jump_speed(contact)
    run = cc.run(cc.build(cam(contact, w)), 1.0)
    assert run.separated
    assert abs(run.first_at - first_zero(contact, w)) <= FIRST_TOL
    assert run.to_dict()["separated"] is True
    assert np.max(run.q - law(contact, run.theta)[0]) > 10 * run.gap_threshold   # a real flight, not a graze


# ---------------------------------------------------------------- dwell-rise-dwell-return from laws.py
H_RISE, BASE = 0.015, 0.03


def drdr_law():
    turn = 2 * math.pi
    return Profile((Segment("dwell", turn / 4), Segment("cycloidal", turn / 3, H_RISE),
                    Segment("dwell", turn / 12), Segment("poly345", turn / 3, -H_RISE)))


def drdr_pitch(theta):
    """The roller centre's lift s(phi) over the cam's own angle phi (the law with time read as angle), and
    the pitch curve in the cam's frame: the follower on the +y axis, the cam turning counter-clockwise, so
    the point under the follower at cam angle theta is at angle pi/2 - theta in the cam's frame."""
    s, ds, dds, _ = drdr_law().at(theta)
    rp = BASE + RR + s
    a = math.pi / 2 - theta
    return s, ds, dds, np.c_[rp * np.cos(a), rp * np.sin(a)]


def drdr_profile(n=1440):
    """The roller cam's outline: the inner envelope of the roller circles along the pitch curve, as the pitch
    curve offset inward along its normal (exact where the pitch curve's radius exceeds the roller's)."""
    th = np.linspace(0, 2 * math.pi, n, endpoint=False)
    _, _, _, pitch = drdr_pitch(th)
    d = np.gradient(pitch, axis=0)
    d = np.roll(pitch, -1, axis=0) - np.roll(pitch, 1, axis=0)       # periodic central difference
    t = d / np.hypot(*d.T)[:, None]
    # the pitch curve runs clockwise in the cam's frame (a = pi/2 - theta decreases): its inward normal is (-t_y, t_x)... reversed
    inward = np.c_[t[:, 1], -t[:, 0]]
    inward *= np.sign(np.sum(inward * -pitch, axis=1))[:, None]
    prof = pitch + RR * inward
    return prof[::-1].copy()                                          # counter-clockwise


def drdr_jump_speed():
    th = np.linspace(0, 2 * math.pi, 200001)
    s, _, s2, _ = drdr_pitch(th)
    neg = s2 < -1e-12
    return float(np.min(np.sqrt((K * s[neg] + F0) / (-M * s2[neg]))))


def test_dwell_rise_dwell_return_roller_tracks_its_law():
    w = 0.5 * drdr_jump_speed()
    c = cc.CamFollower(drdr_profile(), (0.0, 0.0), w, contact="roller", roller=RR, mass=M, stiffness=K, preload=F0)
    built = cc.build(c)
    run = cc.run(built, 1.0)
    s = drdr_pitch(run.theta)[0] + BASE + RR
    th = np.linspace(0, 2 * math.pi, 3601)
    s_, _, s2, _ = drdr_pitch(th)
    n_max = float(np.max(M * s2 * w ** 2 + K * s_ + F0))
    # 50 static penetrations (see tracking_tolerance) plus the envelope's chord error at 1440 points
    tol = 50 * float(cc.penetration(n_max, built.m_eff, built.timestep)) + (BASE + RR + H_RISE) * (2 * math.pi / 1440) ** 2 / 8
    assert np.max(np.abs(run.q - s)) <= tol
    assert not run.separated


def test_dwell_rise_dwell_return_separates_above_its_jump_speed():
    w = 1.3 * drdr_jump_speed()
    c = cc.CamFollower(drdr_profile(), (0.0, 0.0), w, contact="roller", roller=RR, mass=M, stiffness=K, preload=F0)
    run = cc.run(cc.build(c), 1.0)
    assert run.separated
    th = np.linspace(0, 2 * math.pi, 200001)
    s, _, s2, _ = drdr_pitch(th)
    f = M * s2 * w ** 2 + K * s + F0
    first = th[np.flatnonzero(f <= 0)[0]]
    assert abs(run.first_at - first) <= FIRST_TOL


# ------------------------------------------------------------------------------ oscillating follower
ARM_PIVOT, ARM = (0.06, 0.04), 0.06
J_ARM, K_ARM, T0_ARM = M * ARM ** 2, K * ARM ** 2, F0 * ARM      # the translating case's figures at the roller


def arm_angle(theta):
    """The arm's angle with the roller on the disc: the roller's centre where the arm's circle about the pivot
    meets the circle of radius R + r about the disc's centre (two-circle intersection, the upper point)."""
    cx, cy = centre(theta)
    ox, oy = ARM_PIVOT
    dx, dy = cx - ox, cy - oy
    d = np.hypot(dx, dy)
    a = (ARM ** 2 - (R + RR) ** 2 + d ** 2) / (2 * d)
    h = np.sqrt(ARM ** 2 - a ** 2)
    px, py = ox + a * dx / d, oy + a * dy / d
    c1 = (px - h * dy / d, py + h * dx / d)
    c2 = (px + h * dy / d, py - h * dx / d)
    up = c1[1] > c2[1]
    x, y = np.where(up, c1[0], c2[0]), np.where(up, c1[1], c2[1])
    return np.mod(np.arctan2(y - oy, x - ox), 2 * math.pi)           # in [0, 2 pi): this arm stays near pi


def arm_lift(theta):
    """The lift beta = psi_low - psi (the cam turns this arm clockwise) and its derivatives over theta
    (central differences of the closed form, step 1e-4 rad)."""
    low = np.max(arm_angle(np.linspace(0, 2 * math.pi, 20001)))
    d = 1e-4
    b = low - arm_angle(theta)
    bp, bm = low - arm_angle(theta + d), low - arm_angle(theta - d)
    return b, (bp - bm) / (2 * d), (bp - 2 * b + bm) / d ** 2


def wrapped(a):
    """An angle difference in (-pi, pi]."""
    return np.angle(np.exp(1j * np.asarray(a)))


def arm_jump_speed():
    th = np.linspace(0, 2 * math.pi, 20001)
    b, _, b2 = arm_lift(th)
    neg = b2 < 0
    return float(np.min(np.sqrt((K_ARM * b[neg] + T0_ARM) / (-J_ARM * b2[neg]))))


def arm_cam(omega):
    return cc.CamFollower(disc(), (0.0, 0.0), omega, follower="oscillating", contact="roller", roller=RR,
                          arm_pivot=ARM_PIVOT, arm=ARM, inertia=J_ARM, stiffness=K_ARM, preload=T0_ARM)


def test_arm_position_of_the_polyline_matches_the_closed_form():
    th = np.linspace(0, 2 * math.pi, 61)
    c = arm_cam(10.0)
    assert c.sign == -1.0                                             # lifted clockwise: the roller is left of the pivot
    got = cc.follower_position(c, th)
    assert np.max(np.abs(wrapped(got - arm_angle(th)))) * ARM <= 1.01 * SAGITTA + 1e-12   # the chord error, at the roller


def test_arm_tracks_the_law_at_half_its_jump_speed_and_leaves_at_1_3():
    w = 0.5 * arm_jump_speed()
    built = cc.build(arm_cam(w))
    run = cc.run(built, 1.0)
    th = np.linspace(0, 2 * math.pi, 3601)
    b, _, b2 = arm_lift(th)
    n_max = float(np.max((J_ARM * b2 * w ** 2 + K_ARM * b + T0_ARM) / ARM))   # the force at the roller [N]
    tol = (50 * float(cc.penetration(n_max, built.m_eff, built.timestep)) + SAGITTA) / ARM   # see tracking_tolerance
    assert np.max(np.abs(wrapped(run.q - arm_angle(run.theta)))) <= tol
    assert not run.separated
    w = 1.3 * arm_jump_speed()
    run = cc.run(cc.build(arm_cam(w)), 1.0)
    assert run.separated
    th = np.linspace(0, 2 * math.pi, 200001)
    b, _, b2 = arm_lift(th)
    first = th[np.flatnonzero(J_ARM * b2 * w ** 2 + K_ARM * b + T0_ARM <= 0)[0]]
    assert abs(run.first_at - first) <= FIRST_TOL


# ------------------------------------------------------------------- the kind's hook: add to a model
@pytest.mark.parametrize("contact", ["roller", "knife", "flat"])
def test_add_places_the_plate_and_follower_in_a_mechanisms_bodies(contact):
    """A mechanism's model as sim/model/build.py makes it (bodies at their assembled pose, every geom
    contype 0, contact disabled): the cam link's body with its origin off the pivot and turned by the cam's
    angle, the follower block on a slide. After :func:`add` the roller (the knife's small sphere, the flat
    face) rests on the plate where the closed form puts it, raised by 0.1 mm the gap reads what the hand
    geometry gives, and only the plate and the follower's contact can touch."""
    import types

    import mujoco
    A, phi, O = (0.01, 0.02), 0.3, (0.03, -0.01)                    # pivot, cam angle, cam body's origin
    dcx, dcy = A[0] + E * math.sin(phi), A[1] - E * math.cos(phi)   # the disc's centre, R(phi) (0, -e) + A
    rk = cc.KNIFE_RADIUS * (R + E)                                  # the knife's sphere: of the plate's size
    if contact == "roller":                                         # the trace point on the vertical through A:
        fy = dcy + math.sqrt((R + RR) ** 2 - (A[0] - dcx) ** 2)     # the roller's centre,
    elif contact == "knife":
        fy = dcy + math.sqrt(R ** 2 - (A[0] - dcx) ** 2)            # the knife's edge on the disc,
    else:
        fy = dcy + R                                                # the face's foot on the disc's top

    def gap_by_hand(lift):
        """The follower's distance from the disc raised by ``lift`` along the guide (+y), by hand: the
        roller's centre or the knife's sphere (its lowest point on the edge) from the disc's centre less both
        radii; the flat face's underside above the disc's top."""
        if contact == "flat":
            return lift
        r = RR if contact == "roller" else rk
        cy = fy + lift + (rk if contact == "knife" else 0.0)
        return math.hypot(A[0] - dcx, cy - dcy) - R - r
    spec = mujoco.MjSpec()
    spec.option.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
    spec.worldbody.add_geom(name="paper", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[1, 1, 0.01], contype=0,
                            conaffinity=0)
    cam_b = spec.worldbody.add_body(name="1", pos=[O[0], O[1], 0], quat=[math.cos(phi / 2), 0, 0, math.sin(phi / 2)])
    cam_b.add_joint(name="A", type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, 0, 1],
                    pos=[(A[0] - O[0]) * math.cos(phi) + (A[1] - O[1]) * math.sin(phi),
                         -(A[0] - O[0]) * math.sin(phi) + (A[1] - O[1]) * math.cos(phi), 0])
    cam_b.add_geom(name="bar", type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[0.005, 0, 0], contype=0, conaffinity=0, mass=1)
    fol = spec.worldbody.add_body(name="follower", pos=[A[0], 0.0, 0])
    fol.add_joint(name="follower", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[0, 1, 0])
    fol.add_geom(name="block", type=mujoco.mjtGeom.mjGEOM_BOX, size=[0.005] * 3, contype=0, conaffinity=0, mass=0.1)
    ctx = types.SimpleNamespace(spec=spec, timestep=1e-4, frames={"1": (O[0], O[1], phi), "follower": (A[0], 0.0, 0.0)},
                                points={"F": (A[0], fy)})
    setup = types.SimpleNamespace(pivot=A, u=(0.0, 1.0), motion="translating")
    geo = types.SimpleNamespace(profile=disc(), setup=setup, face_centre=0.0)   # the disc sweeps the face evenly
    e = {"name": "c1", "cam": "1", "links": ["follower"], "point": "F", "contact": contact, "roller": RR,
         "face_width": 0.06}
    cc.add(e, ctx, geo)
    m = spec.compile()
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    dists = [d.contact[j].dist for j in range(d.ncon)]
    assert dists and abs(min(dists) - gap_by_hand(0.0)) <= 2 * SAGITTA   # resting: the polyline's chord error
    d.qpos[1] = 1e-4
    mujoco.mj_forward(m, d)
    force, gap = cc.readings(m, d.sensordata[None], "c1", 1.0)
    assert gap[0] == pytest.approx(gap_by_hand(1e-4), abs=2 * SAGITTA)   # the chord error again
    assert force[0] == 0.0                                           # exact: no contact force across a gap
    pairs = {(m.geom(int(d.contact[j].geom[0])).name, m.geom(int(d.contact[j].geom[1])).name) for j in range(d.ncon)}
    assert pairs and all(a.startswith("cam0_piece") or a == "c1_contact" for p in pairs for a in p)
    can = [(i, j) for i in range(m.ngeom) for j in range(i + 1, m.ngeom)
           if (m.geom_contype[i] & m.geom_conaffinity[j]) or (m.geom_contype[j] & m.geom_conaffinity[i])]
    assert can and all({m.geom(i).name, m.geom(j).name} & {"c1_contact"} for i, j in can)   # only with the follower
