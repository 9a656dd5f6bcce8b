"""A cam and its follower in MuJoCo with real contact: the follower tracks the law while pressed on the cam
and leaves it (jumps) when the return spring can no longer hold it (SPEC "Cams and followers").

Input is plain data (:class:`CamFollower`): the cam's profile as a dense closed counter-clockwise polyline in
the cam's frame (origin at the cam's pivot, x along the cam's angle 0) [m], the pivot's world position, the
follower (translating on a guide line, or oscillating about an arm pivot), its contact (knife, roller, flat
face), its mass or inertia, a return spring (stiffness and preload) and the cam's speed. :func:`build` makes
the MjSpec (and :func:`compile_model` the MjModel): a ``cam`` body on a hinge ``cam`` (its position is the
cam's angle), a ``follower`` body on a slide (its position: the trace point's coordinate along the guide) or
a hinge (its position plus :attr:`Built.psi_ref`: the arm's angle), the contact geometry, contacts on
between cam and follower only. :func:`run` steps it (``mujoco.rollout``, sensors only) and returns
:class:`CamRun`: the cam's angle, the follower's position, the contact force along the normal, the gap, and
the separation: where the follower first leaves the cam. Inside a mechanism's model (the cam kind's
``mjcf`` hook), :func:`add` puts the same plate and contact on the cam link's and follower link's bodies
and :func:`readings` and :func:`separation` read the run.

The cam's collision geometry, measured (``python benchmarks/cam_contact.py``: a 720-point eccentric disc,
R = 30 mm, e = 10 mm, roller r = 10 mm, the roller pressed 0.1 mm into the plate at 73 cam angles; one
revolution at 0.5x the jump speed)::

    geometry                          surface error [m]   compile [s]   CPU per step [us]
    convex pieces (this module)       3e-7 at touch (the chord), 3.4e-6 pressed   0.09 (with the kinematics)   7
    one mesh SDF, octree depth 5      9e-5                0.15          ~400
    one mesh SDF, octree depth 7      7e-5                1.9           ~560
    one mesh SDF, octree depth 9      7e-5                38            ~750 (a first trial)

The plate is cut into **convex pieces** (:func:`convex_pieces`): each a fan from the pivot over a run of
profile vertices that turn left, spanning less than 120 deg, extruded into a prism mesh (MuJoCo collides a
mesh by its convex hull, which here is the piece itself). A convex arc is one piece, a concave arc one thin
piece per polyline segment. The collision surface is then the polyline itself: its error against the smooth
profile is the chord's sagitta (rho * dtheta^2 / 8, 3e-7 m above), and convex-convex collision (GJK/EPA) is
MuJoCo's fastest general path. MuJoCo's SDF (a mesh with ``needsdf``: an octree distance field, collided by
gradient descent) takes the whole non-convex plate as one geom but is 20-300x less accurate (the octree's
interpolation near the surface; deeper octrees do not help: the descent's tolerance dominates) and 50-80x
slower per step; MuJoCo's SDF plugins (``mujoco.sdf.*``: bolt, nut, gear, bowl, torus) are fixed shapes, and
the ``sdflib`` mesh plugin is not in the wheel. A cam outline that is not star-shaped about its pivot (a ray
from the pivot crossing it twice) is refused: every practical disc cam is.

The follower's contact: a roller is a sphere of the roller's radius centred on the trace point (its section
by the cam's plane is the roller's circle, and a sphere collides with a prism's wall exactly at its equator);
a knife is a sphere of radius :data:`KNIFE_RADIUS` x the cam's size whose lowest point is the trace point
(the trace point then sits r_k (1 / cos(pa) - 1) above the pitch curve at pressure angle pa: 1.5e-5 x size at
30 deg); a flat face is a thin box whose face, through the trace point, is perpendicular to the guide.
Contacts are frictionless (condim 1, the analytic law's assumption): the force is along the normal.

Contact compliance: ``solref = (tau, 1)`` with tau = :data:`CONTACT_STEPS` time steps (2 h is MuJoCo's
stiffest safe value; at 2 and 4 steps the contact chatters hardest over the facets) and ``solimp = (0.99, 0.99, ...)`` (a constant impedance d). MuJoCo's soft contact then
holds a static force N with a penetration (MuJoCo's constraint model: d k r = (1 - d) a0, k = 1 / (d tau)^2)

    delta = (1 - d) / d * (d tau)^2 * N / m_eff            (:func:`penetration`)

with m_eff the follower's mass (or J / L^2 for an arm; the cam's inertia is made huge, see below): an upper
bound (measured at rest: a third of it). The time step is one :data:`STEPS_PER_TURN`-th of a cam revolution,
so delta scales as (8 * 2 pi / 2000)^2 N / (m omega^2): ~2e-7 m at half the jump speed of the tests' cams
(1e-5 of the stroke). Measured, the follower's error against the law is 5-25x that: the polyline's facets
(and the kinks of a flat face's motion over them) make the stiff contact chatter (force noise up to ~5x the
law's force, rms ~half of it) and ring; the tests allow 50 static penetrations plus the chord's sagitta.

The cam turns at constant speed: its hinge has an armature :data:`CAM_INERTIA_RATIO` times the follower's
largest energy over omega^2, so the energy the follower exchanges with it changes its speed by < 1e-6
(:attr:`CamRun.speed_variation` reports it), with no servo to tune and nothing in the solver to stiffen. The
contact force is read from MuJoCo's contact sensor (the constraint force, efc_force, summed over the cam's
pieces); the gap from the contact distance of the roller (or face) inflated by a ``margin`` equal to its
``gap`` (MuJoCo's inactive contacts: reported, not acting; active only at distance < 0).

Separation: the follower has left the cam where the gap exceeds :data:`SEPARATION_GAP` x the cam's size
(1e-3: 40 um on a 40 mm cam, 10x the chatter's largest gap measured below the jump speed); its first angle
(:attr:`CamRun.first_at`) is the cam's angle just after the last step still touching (gap <= 0) before that
gap was first reached: where the flight starts. Near zero force the chattering contact starts micro-flights
early: measured 0.12 rad before the analytic angle on a flat face, 0.05 with a roller.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import mujoco
import numpy as np

from analytic import ParameterError

IN_MECHANISMS = True
"""Whether a mechanism's model (``compare``, ``simulate``, ``plot`` of a file with a ``cam`` group) builds its
cam through :func:`add`: its time step is capped at STEPS_PER_TURN a turn (sim.model.build.cam_capped), its
readings go to ``simulate``'s ``cams`` and compare's tolerances (sim.run.cams); False makes the cam kind
refuse the model in one line."""

STEPS_PER_TURN = 2000
"""Time steps per cam revolution: h = 2 pi / (omega * STEPS_PER_TURN) (1000 doubled the tracking error)."""

CONTACT_STEPS = 8.0
"""The contact's time constant tau in time steps (MuJoCo clamps it at 2 h): 2 and 4 chattered more, 16 and
32 tracked 4-25x worse (eccentric disc sweeps, 1000-4000 steps a turn)."""

IMPEDANCE = 0.99
"""solimp's d (dmin = dmax): the share of the contact's reference acceleration the solver enforces."""

KNIFE_RADIUS = 1e-4
"""A knife edge's sphere radius as a fraction of the cam's size (its largest radius)."""

SEPARATION_GAP = 1e-3
"""The gap [fraction of the cam's size] above which the follower has left the cam."""

CAM_INERTIA_RATIO = 1e6
"""The cam's inertia times omega^2 over the follower's largest energy: the speed varies by its inverse."""

MAX_SPAN = 2 * math.pi / 3
"""A convex piece's largest angle at the pivot [rad] (a fan near pi would be a sliver of a hull)."""

THICKNESS = 0.2
"""The plate's thickness as a fraction of the cam's size (the geometry is planar: only drawn)."""

FOLLOWERS = ("translating", "oscillating")
CONTACTS = ("knife", "roller", "flat")


# ------------------------------------------------------------------------------------------- input
@dataclass(frozen=True)
class CamFollower:
    """A cam and its follower, SI units, world frame in the plane.

    ``profile``: the cam's outline, shape (n, 2) [m], a closed counter-clockwise polyline (the last point not
    repeating the first) in the cam's frame: origin at the pivot, x along the cam's angle 0. ``pivot``: the
    pivot's world position [m]. ``omega``: the cam's speed [rad/s] (> 0: counter-clockwise).

    The follower: ``follower`` = "translating": its trace point moves on the guide line through ``through``
    [m] in direction ``angle`` [rad] (the direction the cam lifts it); "oscillating": the trace point is at
    ``arm`` [m] from ``arm_pivot`` [m] on an arm turning about it. ``contact``: "knife", "roller" (radius
    ``roller`` [m]) or "flat" (translating only: a face of width ``face_width`` [m] perpendicular to the
    guide, centred on the trace point). ``mass`` [kg] (translating) or ``inertia`` [kg m^2] about the arm
    pivot (oscillating). The return spring pushes the follower onto the cam: ``stiffness`` [N/m or N m/rad]
    and ``preload`` [N or N m], its force at the follower's lowest position over a revolution.
    """

    profile: np.ndarray
    pivot: tuple[float, float]
    omega: float
    follower: str = "translating"
    contact: str = "roller"
    through: tuple[float, float] = (0.0, 0.0)
    angle: float = math.pi / 2
    arm_pivot: tuple[float, float] = (0.0, 0.0)
    arm: float = 0.0
    roller: float = 0.0
    face_width: float = 0.0
    mass: float = 0.1
    inertia: float = 0.0
    stiffness: float = 0.0
    preload: float = 0.0

    def __post_init__(self):
        p = np.asarray(self.profile, dtype=float)
        if p.ndim != 2 or p.shape[1] != 2 or len(p) < 8 or not np.isfinite(p).all():
            raise ParameterError(f"profile: shape {p.shape} must be (n, 2) finite points [m], n >= 8")
        object.__setattr__(self, "profile", p)
        check_star(p)
        if self.follower not in FOLLOWERS:
            raise ParameterError(f"follower={self.follower!r}: use one of {', '.join(FOLLOWERS)}")
        if self.contact not in CONTACTS:
            raise ParameterError(f"contact={self.contact!r}: use one of {', '.join(CONTACTS)}")
        if self.follower == "oscillating" and self.contact == "flat":
            raise ParameterError("contact='flat' with an oscillating follower is not simulated; use a roller")
        if not (math.isfinite(self.omega) and self.omega > 0):
            raise ParameterError(f"omega={self.omega!r} must be > 0 rad/s (the cam turns counter-clockwise)")
        checks = [("stiffness", self.stiffness, 0.0), ("preload", self.preload, 0.0)]
        if self.contact == "roller":
            checks.append(("roller", self.roller, None))
        if self.contact == "flat":
            checks.append(("face_width", self.face_width, None))
        if self.follower == "translating":
            checks.append(("mass", self.mass, None))
        else:
            checks += [("arm", self.arm, None), ("inertia", self.inertia, None)]
        for name, v, low in checks:
            if not (isinstance(v, (int, float)) and math.isfinite(v) and (v >= low if low is not None else v > 0)):
                raise ParameterError(f"{name}={v!r} must be a finite number {'>= 0' if low is not None else '> 0'}")
        if self.stiffness == 0 and self.preload == 0:
            raise ParameterError("stiffness and preload are both 0: give the return spring (stiffness > 0 or "
                                 "preload > 0), or the follower is never pressed on the cam")

    @property
    def size(self) -> float:
        """The cam's largest radius [m]."""
        return float(np.max(np.hypot(self.profile[:, 0], self.profile[:, 1])))

    @property
    def sign(self) -> float:
        """+1 for a translating follower; for an arm, the way (+1 counter-clockwise) the cam turns it."""
        return 1.0 if self.follower == "translating" else _arm_sign(self)


# --------------------------------------------------------------------------------------- geometry
def _rot(theta):
    c, s = np.cos(theta), np.sin(theta)
    return c, s


def check_star(profile: np.ndarray, where: str = "profile",
               fix: str = "give a counter-clockwise outline around the pivot (star-shaped about it)") -> None:
    """Refuse an outline that is not counter-clockwise and star-shaped about the origin (the pivot): one line
    starting with ``where`` (the file, element and field where a mechanism's cam is built) and ending with
    ``fix``."""
    a, b = profile, np.roll(profile, -1, axis=0)
    cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    turn = np.arctan2(cross, np.sum(a * b, axis=1))
    if np.any(cross <= 0) or abs(float(turn.sum()) - 2 * math.pi) > 1e-6:
        k = int(np.argmin(cross))
        at = math.degrees(math.atan2(profile[k, 1], profile[k, 0])) % 360
        raise ParameterError(f"{where}: the cam's outline turns back about the pivot at {at:.4g}deg in the cam's "
                             f"frame (point {k + 1} of {len(profile)}); the simulation collides a plate star-shaped "
                             f"about its pivot: {fix}")


def convex_pieces(profile: np.ndarray) -> list[tuple[int, int]]:
    """The plate cut into convex fans from the pivot: (first, last) vertex indices (last may exceed n: taken
    modulo n), consecutive pieces sharing their end vertex, covering the outline once. A piece runs on while
    each interior vertex turns left (cross product > -1e-12 of the edges' lengths' product) and its angle at
    the pivot stays below :data:`MAX_SPAN`."""
    check_star(profile)
    n = len(profile)
    e = np.roll(profile, -1, axis=0) - profile                            # edge k: vertex k -> k + 1
    ep = np.roll(e, 1, axis=0)                                            # edge into vertex k
    cross = ep[:, 0] * e[:, 1] - ep[:, 1] * e[:, 0]
    left = cross > -1e-12 * np.hypot(*ep.T) * np.hypot(*e.T)
    ang = np.unwrap(np.arctan2(profile[:, 1], profile[:, 0]))
    ang = np.r_[ang, ang[0] + 2 * math.pi]
    # start at a concave vertex if there is one (a piece must end there), else anywhere
    start = int(np.flatnonzero(~left)[0]) if (~left).any() else 0
    pieces = []
    i = start
    end = start + n
    while i < end:
        j = i + 1
        while j < end and left[j % n] and _span(ang, i, j + 1, n) < MAX_SPAN:
            j += 1
        pieces.append((i, j))
        i = j
    return pieces


def _span(ang, i, j, n):
    """The angle at the pivot from vertex i to vertex j (indices modulo n, j > i)."""
    ai = ang[i % n]
    aj = ang[j % n] + 2 * math.pi * (j // n - i // n)
    return aj - ai


# ------------------------------------------------------------------------------------- kinematics
def _guide(cam):
    ux, uy = math.cos(cam.angle), math.sin(cam.angle)
    return np.asarray(cam.through, dtype=float), np.array([ux, uy]), np.array([-uy, ux])


def _world_profile(cam, theta):
    """The outline at cam angles ``theta`` (shape (m,)): world points, shape (m, n, 2)."""
    c, s = _rot(np.asarray(theta, dtype=float)[:, None])
    x, y = cam.profile[:, 0], cam.profile[:, 1]
    return np.stack([cam.pivot[0] + c * x - s * y, cam.pivot[1] + s * x + c * y], axis=-1)


def _line_capsules(o, u, pts, r):
    """The largest coordinate s along the line o + s u at which a circle of radius r centred there touches
    the closed polyline ``pts`` (shape (m, n, 2)), per row: shape (m,). NaN where it touches nothing."""
    a = pts - o
    b = np.roll(a, -1, axis=1)
    wa, pa = a @ u, a @ np.array([-u[1], u[0]])
    wb, pb = b @ u, b @ np.array([-u[1], u[0]])
    cand = []
    # the circles about the vertices
    d2 = r * r - pa * pa
    cand.append(np.where(d2 >= 0, wa + np.sqrt(np.maximum(d2, 0)), -np.inf))
    # the two sides of each segment's band, where the foot falls inside the segment
    dw, dp = wb - wa, pb - pa
    L = np.hypot(dw, dp)
    L = np.where(L > 0, L, 1.0)
    nw, np_ = dp / L, -dw / L                                             # a unit normal of the segment
    for sgn in (1.0, -1.0):
        # points on the segment's offset line: (wa, pa) + sgn r (nw, np_) + t (dw, dp); on the guide: p = 0
        with np.errstate(divide="ignore", invalid="ignore"):
            t = -(pa + sgn * r * np_) / dp
            w = wa + sgn * r * nw + t * dw
        ok = (t >= 0) & (t <= 1) & np.isfinite(w)
        cand.append(np.where(ok, w, -np.inf))
    best = np.max(np.stack(cand), axis=(0, 2))
    return np.where(np.isfinite(best), best, np.nan)


def _flat_height(o, u, pts, half):
    """The largest coordinate along u of the polyline within |p| <= half of the guide line: shape (m,)."""
    a = pts - o
    b = np.roll(a, -1, axis=1)
    v = np.array([-u[1], u[0]])
    wa, pa, wb, pb = a @ u, a @ v, b @ u, b @ v
    cand = [np.where(np.abs(pa) <= half, wa, -np.inf)]
    for edge in (half, -half):
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (edge - pa) / (pb - pa)
        ok = (t >= 0) & (t <= 1)
        cand.append(np.where(ok, wa + t * (wb - wa), -np.inf))
    best = np.max(np.stack(cand), axis=(0, 2))
    return np.where(np.isfinite(best), best, np.nan)


def knife_radius(cam) -> float:
    return KNIFE_RADIUS * cam.size


def follower_position(cam: CamFollower, theta) -> np.ndarray:
    """The follower's position in rigid contact with the polyline at cam angles ``theta`` [rad], shape (m,):
    the trace point's coordinate along the guide from ``through`` [m] (translating) or the arm's angle [rad]
    (oscillating): the kinematics of the polyline itself, computed without MuJoCo (the initial state, the
    stroke, and a reference for a profile given without a law)."""
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    pts = _world_profile(cam, theta)
    if cam.follower == "translating":
        o, u, _ = _guide(cam)
        if cam.contact == "flat":
            return _flat_height(o, u, pts, 0.5 * cam.face_width)
        r = cam.roller if cam.contact == "roller" else knife_radius(cam)
        s = _line_capsules(o, u, pts, r)
        return s if cam.contact == "roller" else s - r
    return _arm_angles(cam, pts)


def _dist(c, pts):
    """Distance from points c (m, 2) to the closed polylines pts (m, n, 2), and the unit direction from the
    nearest point to c: (m,), (m, 2)."""
    a = pts
    b = np.roll(pts, -1, axis=1)
    ab = b - a
    t = np.clip(np.sum((c[:, None] - a) * ab, axis=-1) / np.maximum(np.sum(ab * ab, axis=-1), 1e-300), 0, 1)
    q = a + t[..., None] * ab
    d = np.hypot(*(c[:, None] - q).transpose(2, 0, 1))
    k = np.argmin(d, axis=1)
    rows = np.arange(len(c))
    dmin = d[rows, k]
    n = (c - q[rows, k]) / np.maximum(dmin, 1e-300)[:, None]
    return dmin, n


def _inside(c, pts):
    """Whether points c (m, 2) are inside the closed polylines (m, n, 2) (crossing number)."""
    a = pts - c[:, None]
    b = np.roll(a, -1, axis=1)
    cross = ((a[..., 1] > 0) != (b[..., 1] > 0))
    with np.errstate(divide="ignore", invalid="ignore"):
        x = a[..., 0] + (0 - a[..., 1]) * (b[..., 0] - a[..., 0]) / (b[..., 1] - a[..., 1])
    return (np.sum(cross & (x > 0), axis=1) % 2) == 1


def _arm_angles(cam, pts):
    """The arm's angle with its circle (knife: the sphere's lowest point on the arm's circle is approximated
    by the sphere's centre on it at the knife radius) resting on the outline, per row of pts: Newton on the
    signed distance, each angle started from the last."""
    r = cam.roller if cam.contact == "roller" else knife_radius(cam)
    O = np.asarray(cam.arm_pivot, dtype=float)
    L = cam.arm
    psi = _arm_start(cam, pts[0], r)
    out = np.empty(len(pts))
    for m in range(len(pts)):
        for _ in range(50):
            e = np.array([math.cos(psi), math.sin(psi)])
            c = O + L * e
            d, n = _dist(c[None], pts[m][None])
            sd = d[0] * (-1.0 if _inside(c[None], pts[m][None])[0] else 1.0)
            nn = n[0] * (-1.0 if sd < 0 else 1.0)
            f = sd - r
            df = float(nn @ (L * np.array([-e[1], e[0]])))
            if abs(df) < 1e-12 * L:
                break
            step = -f / df
            step = max(-0.05, min(0.05, step))
            psi += step
            if abs(step) < 1e-13:
                break
        out[m] = psi
    return out


def _arm_start(cam, pts, r):
    """A first arm angle: on the arm's circle, the point of the arc outside the cam nearest to touching it
    (sampled), from which Newton converges."""
    O = np.asarray(cam.arm_pivot, dtype=float)
    L = cam.arm
    psi = np.linspace(-math.pi, math.pi, 3601)
    c = O + L * np.stack([np.cos(psi), np.sin(psi)], axis=-1)
    d, _ = _dist(c, np.broadcast_to(pts, (len(c),) + pts.shape))
    inside = _inside(c, np.broadcast_to(pts, (len(c),) + pts.shape))
    sd = np.where(inside, -d, d) - r
    ok = sd >= 0
    if not ok.any() or ok.all():
        raise ParameterError("arm: the roller's circle about arm_pivot never (or always) meets the cam; check "
                             "arm_pivot and arm")
    k = np.flatnonzero(ok & ~np.roll(ok, 1))                              # entering the free arc...
    j = np.flatnonzero(ok & ~np.roll(ok, -1))                             # ...or leaving it
    cands = np.r_[k, j]
    return float(psi[cands[np.argmin(sd[cands])]])


def _arm_sign(cam) -> float:
    """+1 when the cam, turning counter-clockwise, turns the arm counter-clockwise at the start (the
    torque of the contact normal about the arm pivot)."""
    psi = follower_position(cam, np.array([0.0]))[0]
    O = np.asarray(cam.arm_pivot, dtype=float)
    c = O + cam.arm * np.array([math.cos(psi), math.sin(psi)])
    _, n = _dist(c[None], _world_profile(cam, np.array([0.0])))
    lever = c - O
    return 1.0 if lever[0] * n[0, 1] - lever[1] * n[0, 0] > 0 else -1.0


# ------------------------------------------------------------------------------------------ model
@dataclass(frozen=True)
class Built:
    """A compiled cam model: the MjSpec and MjModel, the time step [s], the follower's reference
    (``psi_ref``: the arm's angle at joint position 0; 0 for a slide), its lowest position over a revolution,
    the contact's solref/solimp, its effective mass [kg] and the run's thresholds [m]."""

    cam: CamFollower
    spec: object
    model: object
    timestep: float
    steps_per_turn: int
    theta0: float
    q0: float
    psi_ref: float
    low: float
    m_eff: float
    gap_threshold: float
    gap_cutoff: float
    pieces: tuple = field(default=())


def penetration(force, m_eff: float, timestep: float) -> np.ndarray:
    """MuJoCo's static penetration [m] of a contact holding ``force`` [N] with this module's solref/solimp:
    (1 - d) / d * (d tau)^2 * force / m_eff, tau = CONTACT_STEPS * timestep (see the module docstring)."""
    d, tau = IMPEDANCE, CONTACT_STEPS * timestep
    return (1 - d) / d * (d * tau) ** 2 * np.asarray(force, dtype=float) / m_eff


def _energy(cam, q, dq_dtheta):
    """An upper bound of the follower's energy over a revolution [J]: kinetic plus the spring's work."""
    stroke = float(np.ptp(q))
    kin = 0.5 * (cam.mass if cam.follower == "translating" else cam.inertia) * (cam.omega * np.max(np.abs(dq_dtheta))) ** 2
    return kin + (cam.preload + cam.stiffness * stroke) * stroke + 1e-12


def build(cam: CamFollower, theta0: float = 0.0, steps_per_turn: int = STEPS_PER_TURN) -> Built:
    """The MjSpec and MjModel of ``cam`` at cam angle ``theta0`` [rad], the follower at rest on the cam with
    the law's velocity there (from :func:`follower_position`)."""
    S, G, J = mujoco.mjtSensor, mujoco.mjtGeom, mujoco.mjtJoint
    size = cam.size
    h = 2 * math.pi / (cam.omega * steps_per_turn)
    thetas = theta0 + np.linspace(0.0, 2 * math.pi, 721)
    q = follower_position(cam, thetas)
    if not np.isfinite(q).all():
        raise ParameterError("follower: it does not touch the cam at every angle (check through/angle, arm_pivot "
                             "and arm, or the face's width)")
    sign = cam.sign
    step = thetas[1] - thetas[0]
    qc = q[:-1]                                                           # one turn, periodic
    dq = (np.roll(qc, -1) - np.roll(qc, 1)) / (2 * step)
    ddq = (np.roll(qc, -1) - 2 * qc + np.roll(qc, 1)) / step ** 2
    low = float(np.min(q) if sign > 0 else np.max(q))
    v_start = float(dq[0] * cam.omega)
    # start pressed by the force the law needs there (spring, preload, inertia), as deep as it holds it
    spring = sign * (cam.stiffness * (q[0] - low)) + cam.preload
    m_eff = cam.mass if cam.follower == "translating" else cam.inertia / cam.arm ** 2
    lever = 1.0 if cam.follower == "translating" else cam.arm
    n0 = max(spring / lever + m_eff * lever * sign * ddq[0] * cam.omega ** 2, 0.0)
    q_start = float(q[0] - sign * penetration(n0, m_eff, h) / lever)

    spec = mujoco.MjSpec()
    spec.modelname = "cam"
    spec.compiler.degree = False
    spec.option.timestep = h
    spec.option.gravity = [0, 0, 0]
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_EULER
    tau = CONTACT_STEPS * h
    solref = [tau, 1.0]
    solimp = [IMPEDANCE, IMPEDANCE, 1e-3 * size, 0.5, 2.0]
    gap_threshold = SEPARATION_GAP * size
    cutoff = 4 * gap_threshold

    # the cam: a hinge at the pivot, the plate's convex pieces
    body = spec.worldbody.add_body(name="cam", pos=[cam.pivot[0], cam.pivot[1], 0])
    energy = _energy(cam, q, dq)
    body.add_joint(name="cam", type=J.mjJNT_HINGE, axis=[0, 0, 1],
                   armature=CAM_INERTIA_RATIO * energy / cam.omega ** 2)
    body.explicitinertial = True
    body.mass = 1e-6
    body.inertia = [1e-9, 1e-9, 1e-9]
    P = cam.profile
    n = len(P)
    t = 0.5 * THICKNESS * size
    pieces = convex_pieces(P)
    for k, (i, j) in enumerate(pieces):
        ring = [P[m % n] for m in range(i, j + 1)]
        vert = []
        for z in (-t, t):
            vert += [0.0, 0.0, z]
            for x, y in ring:
                vert += [float(x), float(y), z]
        spec.add_mesh(name=f"piece{k}", uservert=vert)
        body.add_geom(name=f"cam{k}", type=G.mjGEOM_MESH, meshname=f"piece{k}", contype=1, conaffinity=0,
                      condim=1, solref=solref, solimp=solimp, density=0, rgba=[0.85, 0.55, 0.2, 1])

    # the follower
    fb = spec.worldbody.add_body(name="follower")
    if cam.follower == "translating":
        o, u, v = _guide(cam)
        fb.pos = [o[0], o[1], 0]
        fb.add_joint(name="follower", type=J.mjJNT_SLIDE, axis=[u[0], u[1], 0], stiffness=cam.stiffness,
                     springref=low)
        fb.explicitinertial = True
        fb.mass = cam.mass
        fb.inertia = [1e-9, 1e-9, 1e-9]
        psi_ref = 0.0
        q0 = q_start
        if cam.contact == "flat":
            ht = 0.02 * size                                              # the face plate's half thickness
            fb.add_geom(name="contact", type=G.mjGEOM_BOX, size=[0.5 * cam.face_width, ht, 1.5 * t],
                        pos=[*(ht * u), 0], quat=_quat(cam.angle - math.pi / 2), contype=0, conaffinity=1,
                        condim=1, solref=solref, solimp=solimp, gap=cutoff, density=0,
                        rgba=[0.3, 0.45, 0.8, 1])
            stem_from = 2 * ht
        else:
            r = cam.roller if cam.contact == "roller" else knife_radius(cam)
            centre = np.zeros(2) if cam.contact == "roller" else r * u
            fb.add_geom(name="contact", type=G.mjGEOM_SPHERE, size=[r, 0, 0], pos=[centre[0], centre[1], 0],
                        contype=0, conaffinity=1, condim=1, solref=solref, solimp=solimp, gap=cutoff, density=0, rgba=[0.3, 0.45, 0.8, 1])
            stem_from = r if cam.contact == "roller" else 0.0
        # the stem along the guide, drawn only (a child body: not the follower's geoms for the sensors)
        deco = fb.add_body(name="follower_stem")
        a, b = stem_from * u, (stem_from + 0.8 * size) * u
        deco.add_geom(name="stem", type=G.mjGEOM_CAPSULE, size=[0.04 * size, 0, 0],
                      fromto=[a[0], a[1], 0, b[0], b[1], 0], contype=0, conaffinity=0, density=0,
                      rgba=[0.3, 0.45, 0.8, 1])
    else:
        O = np.asarray(cam.arm_pivot, dtype=float)
        psi_ref = q_start
        q0 = 0.0
        fb.pos = [O[0], O[1], 0]
        fb.add_joint(name="follower", type=J.mjJNT_HINGE, axis=[0, 0, 1], stiffness=cam.stiffness,
                     springref=low - psi_ref)
        fb.explicitinertial = True
        fb.mass = 1e-6
        fb.inertia = [cam.inertia, cam.inertia, cam.inertia]
        r = cam.roller if cam.contact == "roller" else knife_radius(cam)
        c = cam.arm * np.array([math.cos(psi_ref), math.sin(psi_ref)])
        fb.add_geom(name="contact", type=G.mjGEOM_SPHERE, size=[r, 0, 0], pos=[c[0], c[1], 0], contype=0,
                    conaffinity=1, condim=1, solref=solref, solimp=solimp, gap=cutoff, density=0,
                    rgba=[0.3, 0.45, 0.8, 1])
        deco = fb.add_body(name="follower_stem")
        deco.add_geom(name="stem", type=G.mjGEOM_CAPSULE, size=[0.04 * size, 0, 0],
                      fromto=[0, 0, 0, c[0], c[1], 0], contype=0, conaffinity=0, density=0,
                      rgba=[0.3, 0.45, 0.8, 1])
    # the preload: a constant force toward the cam (an actuator with only a bias: no control)
    act = spec.add_actuator(name="preload", target="follower", trntype=mujoco.mjtTrn.mjTRN_JOINT)
    act.gaintype = mujoco.mjtGain.mjGAIN_FIXED
    act.gainprm[0] = 0.0
    act.biastype = mujoco.mjtBias.mjBIAS_AFFINE
    act.biasprm[0] = -sign * cam.preload
    act.biasprm[1] = 0.0
    act.biasprm[2] = 0.0

    jp, jv = S.mjSENS_JOINTPOS, S.mjSENS_JOINTVEL
    for name in ("cam", "follower"):
        spec.add_sensor(name=f"{name}_q", type=jp, objtype=mujoco.mjtObj.mjOBJ_JOINT, objname=name)
        spec.add_sensor(name=f"{name}_qd", type=jv, objtype=mujoco.mjtObj.mjOBJ_JOINT, objname=name)
    # contact force between the bodies (found, force: net), and the smallest distance (found, dist)
    spec.add_sensor(name="contact_force", type=S.mjSENS_CONTACT, objtype=mujoco.mjtObj.mjOBJ_BODY,
                    objname="cam", reftype=mujoco.mjtObj.mjOBJ_BODY, refname="follower", intprm=[1 | 2, 3, 1])
    spec.add_sensor(name="contact_dist", type=S.mjSENS_CONTACT, objtype=mujoco.mjtObj.mjOBJ_BODY,
                    objname="cam", reftype=mujoco.mjtObj.mjOBJ_BODY, refname="follower", intprm=[1 | 8, 1, 1])
    spec.add_key(name="start", qpos=[theta0, q0], qvel=[cam.omega, v_start])
    model = spec.compile()
    return Built(cam, spec, model, h, steps_per_turn, float(theta0), q0, psi_ref, low, m_eff, gap_threshold,
                 cutoff, tuple(pieces))


def _quat(a):
    return [math.cos(a / 2), 0, 0, math.sin(a / 2)]


# -------------------------------------------------------------------------------------------- run
@dataclass(frozen=True)
class CamRun:
    """A run: at each step (the state before it), the time ``t`` [s], the cam's angle ``theta`` [rad, from
    theta0, increasing], the follower's position ``q`` [m or rad: :func:`follower_position`'s coordinate]
    and velocity ``qd``, the contact ``force`` along the normal [N] (summed over the cam's pieces) and the
    ``gap`` [m] (negative: penetration; at most ``gap_cutoff``). ``separated``: the gap exceeded
    ``gap_threshold`` [m]; ``first_at``: the cam's angle [rad] where that separation started (the force last
    zero-free sample before it), or None; ``speed_variation``: the cam's largest relative speed change."""

    t: np.ndarray
    theta: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    force: np.ndarray
    gap: np.ndarray
    gap_threshold: float
    gap_cutoff: float
    separated: bool
    first_at: float | None
    speed_variation: float

    def to_dict(self) -> dict:
        """SPEC's ``"cams": {name: ...}`` entry of ``simulate``: separated and first_at (the cam's angle in
        [0, 2 pi))."""
        first = None if self.first_at is None else float(self.first_at % (2 * math.pi))
        return {"separated": bool(self.separated), "first_at": first}


def run(built: Built, revolutions: float = 1.0) -> CamRun:
    """Step ``built`` from its start for ``revolutions`` cam turns (``mujoco.rollout``: the loop in C)."""
    from mujoco import rollout
    m = built.model
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, 0)
    nstep = int(round(revolutions * built.steps_per_turn))
    spec_ = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state0 = np.empty(mujoco.mj_stateSize(m, spec_))
    mujoco.mj_getState(m, d, state0, spec_)
    _, sens = rollout.rollout(m, d, state0[None], nstep=nstep)
    sens = sens[0]
    adr = {m.sensor(i).name: int(m.sensor_adr[i]) for i in range(m.nsensor)}
    theta = sens[:, adr["cam_q"]]
    w = sens[:, adr["cam_qd"]]
    q = sens[:, adr["follower_q"]] + built.psi_ref
    qd = sens[:, adr["follower_qd"]]
    fa = adr["contact_force"]
    found = sens[:, fa] > 0
    force = np.where(found, np.linalg.norm(sens[:, fa + 1:fa + 4], axis=1), 0.0)
    da = adr["contact_dist"]
    gap = np.where(sens[:, da] > 0, sens[:, da + 1], built.gap_cutoff)
    t = np.arange(nstep) * built.timestep
    sep, first = separation(theta, force, gap, built.gap_threshold)
    return CamRun(t, theta, q, qd, force, gap, built.gap_threshold, built.gap_cutoff, sep, first,
                  float(np.max(np.abs(w / built.cam.omega - 1.0))))


def separation(theta, force, gap, threshold) -> tuple[bool, float | None]:
    """Whether the gap ever exceeds ``threshold``, and the cam angle where that first separation started:
    the first sample without contact force after the last sample with it, before the gap first exceeded the
    threshold."""
    over = np.flatnonzero(gap > threshold)
    if not len(over):
        return False, None
    k = int(over[0])
    touching = np.flatnonzero(gap[:k] <= 0)
    start = int(touching[-1]) + 1 if len(touching) else 0
    return True, float(theta[start])


# ----------------------------------------------------------------------------------------- render
def render_frame(built: Built, run: CamRun, k: int, size: tuple[int, int] = (640, 480)) -> np.ndarray:
    """MuJoCo's offscreen picture (RGB, shape (height, width, 3)) of step ``k`` of ``run``, seen from above
    the cam's plane, framing the cam and the follower (MUJOCO_GL chosen by sim.output.gl)."""
    from sim.output.gl import ensure_gl_backend
    ensure_gl_backend()
    m = built.model
    d = mujoco.MjData(m)
    d.qpos[:] = [run.theta[k], run.q[k] - built.psi_ref]
    mujoco.mj_forward(m, d)
    cam = mujoco.MjvCamera()
    cam.type = mujoco.mjtCamera.mjCAMERA_FREE
    size_ = built.cam.size
    cam.lookat[:] = [built.cam.pivot[0], built.cam.pivot[1] + 0.5 * size_, 0]
    cam.distance = 6.0 * size_
    cam.azimuth, cam.elevation = 90.0, -90.0
    m.vis.global_.offwidth, m.vis.global_.offheight = max(size[0], 640), max(size[1], 480)
    with mujoco.Renderer(m, height=size[1], width=size[0]) as r:
        r.update_scene(d, camera=cam)
        return r.render().copy()


# ------------------------------------------------------------------- inside a mechanism's model
COLLISION_POINTS = 720
"""The most outline vertices a mechanism's cam plate is collided with (:func:`collision_profile`): the
contact's figures were measured at 720 (chord sagitta 7e-7 m on cam_roller's 29.5 mm smallest radius of
curvature); the 3600 of :func:`analytic.cams.build` made the model's compile and XML 5x slower (1.9 s)."""


MIN_PLATE = 1e-6
"""[m] The smallest cam plate (its largest radius) simulated: a plate 1e-6 m across with ~100 vertices to a
convex piece has pieces of ~1e-13 m^2, well above the mesh area MuJoCo refuses (mjMINVAL, 1e-15); a profile
typed in the wrong units (35e-9 mm) is far below it."""


def collision_profile(profile: np.ndarray) -> np.ndarray:
    """``profile`` thinned to at most :data:`COLLISION_POINTS` vertices (every k-th: still on the outline)."""
    prof = np.asarray(profile, dtype=float)
    return prof[::max(1, -(-len(prof) // COLLISION_POINTS))]


def add(e: dict, ctx, geo) -> None:
    """The cam kind's ``mjcf`` hook (:class:`sim.model.build.Context` ``ctx``): the cam plate's convex
    pieces on the cam link's body and the follower's roller, knife or face on the follower link's body, at
    their assembled pose, contacts on between them only (a contype/conaffinity bit of their own: every other
    geom of the model has both 0), with this module's solref/solimp at the model's time step; and two
    sensors, ``<name>_contact_force`` (found, net force) and ``<name>_contact_dist`` (found, smallest
    distance, within the contact geom's ``gap``), read by :func:`readings` after a run.

    ``e``: the cam element (``name``, ``cam``, ``links`` [follower link first], ``point``, ``contact``,
    ``roller``, ``face_width``); ``geo``: its :class:`analytic.cams.CamGeometry` (``profile``: the outline
    in the cam's frame, origin at the pivot, x along the cam link's angle; ``setup``: pivot, u, motion).
    The return spring and preload are the file's loads, the cam's speed its drive."""
    G = mujoco.mjtGeom
    spec = ctx.spec
    name = e["name"]
    from analytic.cams import plate
    prof = collision_profile(plate(e, geo))             # a given profile as given, else the law's
    mech = getattr(ctx, "mech", None)                  # the file and the element, to say where
    where = (f"{mech.definition.source}: " if mech is not None else "") + str(e.get("label", f"cam {name}"))
    if e.get("profile"):
        check_star(prof, f"{where}: field 'profile'")
    else:
        check_star(prof, f"{where}: field 'segments'",
                   "rise less steeply there (a smaller rise or a longer segment) or make base_radius larger")
    size = float(np.max(np.hypot(prof[:, 0], prof[:, 1])))
    if not size >= MIN_PLATE:
        field = "profile" if e.get("profile") else "base_radius"
        raise ParameterError(f"{where}: field '{field}': the cam plate reaches {size:.3g} m from its pivot; the "
                             f"simulation meshes plates of {MIN_PLATE:g} m and more: check the {field}'s units")
    h = ctx.timestep
    solref = [CONTACT_STEPS * h, 1.0]
    solimp = [IMPEDANCE, IMPEDANCE, 1e-3 * size, 0.5, 2.0]
    cutoff = 4 * SEPARATION_GAP * size
    taken = {g.name for g in spec.geoms}
    k = 0
    while f"cam{k}_piece0" in taken:                                   # one bit per cam of the model
        k += 1
    bit = 1 << (1 + k % 30)
    # the plate in the cam link's body frame: p + R(-phi)(A - O), phi the body's angle (= the cam's theta)
    ox, oy, phi = ctx.frames[e["cam"]]
    ax, ay = geo.setup.pivot
    c, s = math.cos(phi), math.sin(phi)
    shift = np.array([(ax - ox) * c + (ay - oy) * s, -(ax - ox) * s + (ay - oy) * c])
    body = spec.body(e["cam"])
    t = 0.5 * THICKNESS * size
    n = len(prof)
    for j, (i0, i1) in enumerate(convex_pieces(prof)):
        ring = np.vstack([shift, prof[np.arange(i0, i1 + 1) % n] + shift])          # the pivot, then the arc
        vert = np.concatenate([np.c_[ring, np.full(len(ring), z)] for z in (-t, t)])
        spec.add_mesh(name=f"cam{k}_piece{j}", uservert=vert.ravel().tolist())
        body.add_geom(name=f"cam{k}_piece{j}", type=G.mjGEOM_MESH, meshname=f"cam{k}_piece{j}", contype=0,
                      conaffinity=bit, condim=1, solref=solref, solimp=solimp, density=0,
                      rgba=[0.85, 0.55, 0.2, 1])
    # the follower's contact at the trace point, in the follower link's frame
    link = e["links"][0]
    fx, fy, fphi = ctx.frames[link]
    px, py = ctx.points[e["point"]]
    cf, sf = math.cos(fphi), math.sin(fphi)

    def loc(x, y):
        return [(x - fx) * cf + (y - fy) * sf, -(x - fx) * sf + (y - fy) * cf, 0.0]
    fb = spec.body(link)
    common = dict(contype=bit, conaffinity=0, condim=1, solref=solref, solimp=solimp, gap=cutoff, density=0,
                  rgba=[0.3, 0.45, 0.8, 1])
    if e["contact"] == "flat":
        ux, uy = geo.setup.u
        ht = 0.02 * size
        width = e.get("face_width") or 2 * size
        mid = geo.face_centre                  # the face over the contact's travel, as the check measures it
        fb.add_geom(name=f"{name}_contact", type=G.mjGEOM_BOX, size=[0.5 * width, ht, 1.5 * t],
                    pos=loc(px + ht * ux - mid * uy, py + ht * uy + mid * ux),
                    quat=_quat(math.atan2(uy, ux) - math.pi / 2 - fphi), **common)
    else:
        r = e["roller"] if e["contact"] == "roller" else KNIFE_RADIUS * size
        if e["contact"] == "knife":                                    # the sphere's lowest point on F
            ux, uy = geo.setup.u if geo.setup.motion == "translating" else _arm_out(geo.setup, px, py)
            px, py = px + r * ux, py + r * uy
        fb.add_geom(name=f"{name}_contact", type=G.mjGEOM_SPHERE, size=[r, 0, 0], pos=loc(px, py), **common)
    spec.option.disableflags &= ~int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
    B = mujoco.mjtObj.mjOBJ_BODY
    spec.add_sensor(name=f"{name}_contact_force", type=mujoco.mjtSensor.mjSENS_CONTACT, objtype=B,
                    objname=e["cam"], reftype=B, refname=link, intprm=[1 | 2, 3, 1])
    spec.add_sensor(name=f"{name}_contact_dist", type=mujoco.mjtSensor.mjSENS_CONTACT, objtype=B,
                    objname=e["cam"], reftype=B, refname=link, intprm=[1 | 8, 1, 1])


def _arm_out(setup, px, py):
    """An arm's knife: the unit direction from the cam's pivot to the trace point (away from the cam)."""
    dx, dy = px - setup.pivot[0], py - setup.pivot[1]
    d = math.hypot(dx, dy)
    return dx / d, dy / d


def readings(model, sensordata: np.ndarray, name: str, gap_cutoff: float) -> tuple[np.ndarray, np.ndarray]:
    """The contact force [N] and gap [m] of cam ``name`` from recorded sensor rows (steps, nsensordata) of a
    model built with :func:`add`: force 0 and gap ``gap_cutoff`` where no contact was found."""
    fa = int(model.sensor_adr[model.sensor(f"{name}_contact_force").id])
    da = int(model.sensor_adr[model.sensor(f"{name}_contact_dist").id])
    force = np.where(sensordata[:, fa] > 0, np.linalg.norm(sensordata[:, fa + 1:fa + 4], axis=1), 0.0)
    gap = np.where(sensordata[:, da] > 0, sensordata[:, da + 1], gap_cutoff)
    return force, gap
