"""MuJoCo models generated for any mechanism through :class:`mujoco.MjSpec`.

The model is a spanning tree of link bodies: every driven pair and every prismatic pair is a tree joint
(MuJoCo cannot close a loop at a slide), the remaining revolutes close the loops, one site-based
``connect`` each. Bodies carry the file's link names, joints the point (revolute) or block-link
(prismatic) names, sites the point names. Every body is placed at its assembled pose at t = 0 (joint
values 0 there), so the model as written, before any keyframe, already closes every loop; the ``home``
keyframe adds the analytic initial velocities and drive states.

Drives track the commanded motion by position (MuJoCo's integrated-velocity servo): the actuator's
activation integrates the commanded speed, and force = kp (act - q) - kv qdot. With the speed and
acceleration fed forward (see :func:`drive_command`) there is no phase drift; the tracking error is the
reaction torque over kp. Everything in sim/ reads the model by name.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path

import mujoco
import numpy as np

import mjcf
from analytic import ParameterError
from analytic.kinds import GROUND

MJCF_DIR = Path(mjcf.__file__).resolve().parent

WARNINGS: list[str] = []
"""MuJoCo's warnings, kept here instead of printed to the terminal and written to MUJOCO_LOG.TXT in the
user's folder: a failed run is reported by SimulationError in one line."""


def _keep_warning(message: str) -> None:
    WARNINGS.append(str(message).strip())
    del WARNINGS[:-20]


mujoco.set_mju_user_warning(_keep_warning)
TEMPLATE = MJCF_DIR / "template.xml"

INTEGRATORS = {"euler": mujoco.mjtIntegrator.mjINT_EULER, "rk4": mujoco.mjtIntegrator.mjINT_RK4,
               "implicit": mujoco.mjtIntegrator.mjINT_IMPLICIT,
               "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST}
DEFAULT_INTEGRATOR = "rk4"
STEP_ANGLE = 0.03
"""The time step is chosen so that the fastest rate in the motion turns at most this many radians per
step: h = STEP_ANGLE / Omega, with Omega the largest of every link's |omega|, sqrt(|alpha|) and the
sliders' |ds| / size over the run. With the loops held as below, the error is RK4's (it scales as h^4);
over 360 random designs of every mechanism (benchmarks/trust.py's draws, seeds 11-14) the worst
error/target was 0.05 at 0.025 rad per step, 0.12-0.19 at 0.03, 0.37 at 0.04 and 0.6 at 0.05."""
MAX_TIMESTEP = 0.05
MIN_TIMESTEP = 1e-6
"""Bounds of the chosen step [s]: the largest step a user may set; a design that would need a step
below MIN_TIMESTEP is refused. The drives' and loops' time constants are counted in steps, so a slow
design needs no smaller step than its motion asks for."""
LOOP_TIMECONST = 32.0
"""Time constant of the loops' drift correction, in time steps (solref[0] = LOOP_TIMECONST * h).
With the regulariser below made negligible the loops are held by the constraint force itself and this
Baumgarte-style correction only removes integration drift: too fast a correction disturbs RK4 (8 steps:
3x the loop error of 32 at 0.03 rad per step), too slow lets the drift build up (128 and 512 steps:
2x and 6x); 32 and 64 did equally well over 200 designs."""
REGULARIZATION_SCALE = 1e-6
"""Scale applied to the compiled ``body_invweight0``: MuJoCo sizes each constraint's regulariser as
R = (1 - d) / d * invweight with the impedance d capped at 0.9999, so a share of about R / (J M^-1 J')
of the constraint force leaks into loop violation. invweight0 is computed at the initial pose and serves
only that purpose in a model without contacts; near a singular pose J M^-1 J' becomes small and the leak
grows: a near-singular Whitworth design had 1e-6 rad of error from it at 1e-4, none visible at 1e-6
(loop violation 9e-9 -> 1.4e-9 of the size). Smaller is not better: the constraint force is the
solver's residual over R, and the drive torques' error grows as 1/R (400 random designs, worst torque
error/tolerance: 0.004 at 1e-6, 0.02 at 1e-7, 0.5 at 1e-8, 18 at 1e-10). External loads add constraint
force that inertia does not, so the scale is divided by 1 + (load / inertial force): see regularization."""
MIN_SIZE = 1e-3
"""[m] The smallest mechanism simulated: below it the default masses and inertias (LINEAR_DENSITY)
approach MuJoCo's mjMINVAL (1e-15) and the model does not compile (a slider crank typed in metres
into a mm file: 0.2 mm, piston inertia 1e-15 kg m^2)."""
MIN_MASS, MIN_INERTIA = 1e-9, 1e-14
"""[kg], [kg m^2] The smallest link mass and moment of inertia accepted, a margin above mjMINVAL."""
DRIVE_ERROR_BUDGET = 1e-6
"""[rad, or of the size for a slider] The drives' stiffness kp is sized so that the peak reaction
torque deflects the drive by at most this much (kp = peak / budget)."""
SERVO_RATE = 0.25
"""The drive's natural frequency times the time step: sqrt(kp / J) h. The rotor inertia J (armature)
is sized for it (J = kp (h / SERVO_RATE)^2), critically damped (kv = 2 sqrt(kp J)); RK4 resolves a mode
of 0.25 rad per step without pumping energy."""
LINEAR_DENSITY = 1.0
"""[kg/m] Default mass per length of a link: a slender bar (a 12.8 mm steel rod), pinned at its
points; a link with several points is a star of bars from its origin. Blocks weigh as 0.1 size of bar.
Override per link with the file's [inertia] table or --inertia."""


@dataclass(frozen=True)
class Settings:
    """Simulation settings: ``timestep`` [s] (None: chosen from the design, see STEP_ANGLE), the
    integrator, and the loops' drift-correction time constant in steps."""

    timestep: float | None = None
    integrator: str = DEFAULT_INTEGRATOR
    timeconst: float = LOOP_TIMECONST

    def __post_init__(self):
        if self.timestep is not None and not (isinstance(self.timestep, (float, int))
                                              and math.isfinite(self.timestep) and 0 < self.timestep <= 0.05):
            raise ParameterError(f"timestep={self.timestep!r} must be a number in (0, 0.05] s (e.g. 0.001)")
        if self.integrator not in INTEGRATORS:
            raise ParameterError(f"integrator={self.integrator!r} is not known: use one of {', '.join(INTEGRATORS)}")


@dataclass(frozen=True)
class Loads:
    """What acts on the mechanism besides its drives: ``gravity`` (gx, gy) [m/s^2] in the plane (None:
    normal to it, no effect); ``force`` (Fx, Fy) [N] on the output point, fixed in the world frame, on
    throughout or (``slow_stroke_only``) only while the output point makes its slow stroke (a cutting
    force); ``inertias``: {link: Inertia} replacing the default masses."""

    gravity: tuple[float, float] | None = None
    force: tuple[float, float] = (0.0, 0.0)
    slow_stroke_only: bool = False
    inertias: dict | None = None

    def __post_init__(self):
        for name, v in (("gravity", self.gravity), ("force", self.force)):
            if v is not None and not all(isinstance(x, (int, float)) and math.isfinite(x) and abs(x) <= 1e9
                                         for x in v):
                raise ParameterError(f"{name}={v} must be two finite numbers of magnitude <= 1e9")


@dataclass(frozen=True)
class Drive:
    """A driven tree joint: its input, actuator and joint names, servo gains and rotor inertia."""

    input: object
    joint: str
    actuator: str
    kp: float
    kv: float
    armature: float
    q_offset: float
    """The input's value at qpos = 0 (the joint measures q - q_offset)."""


@dataclass(frozen=True)
class Loop:
    """A loop closed by a connect at ``point`` between the sites ``site1`` and ``site2``."""

    name: str
    point: str
    site1: str
    site2: str


@dataclass(frozen=True)
class Context:
    """What a kind's :meth:`~analytic.kinds.base.Kind.mjcf` hook sees while the model is built: the spec
    being built, the mechanism, the spanning tree (parent, child, joint) from the ground outwards, every
    body's world pose (x, y, angle) and every point's position at t = 0 [m], the time step [s] and the
    settings. Every joint's position is 0 at the assembled pose the bodies are placed in."""

    spec: object
    mech: object
    tree: tuple
    frames: dict
    points: dict
    timestep: float
    settings: Settings

    def angle_terms(self, link: str) -> dict[str, float]:
        """The link's angle minus its angle at t = 0 as a sum of hinge positions {joint name: coefficient}
        (the hinges on the tree path from the ground to it; slides do not turn). The ground: {}."""
        parent = {child: (par, j) for par, child, j in self.tree}
        out: dict[str, float] = {}
        while link in parent:
            link, j = parent[link][0], parent[link][1]
            if j.kind == "revolute":
                out[j.name] = out.get(j.name, 0.0) + 1.0
        return out

    def couple(self, name: str, terms: dict[str, float]) -> None:
        """Hold sum(coef x joint position) at its value at t = 0 (0): a fixed tendon over the joints and a
        tendon equality constraint, stiff as the loops' (solref, solimp as the loop closures)."""
        tendon = self.spec.add_tendon(name=name)
        for joint, coef in terms.items():
            if coef != 0.0:
                tendon.wrap_joint(joint, coef)
        eq = self.spec.add_equality(name=f"couple_{name}", type=mujoco.mjtEq.mjEQ_TENDON, name1=name)
        eq.data[:5] = [0.0, 0.0, 0.0, 0.0, 0.0]
        eq.solref = [self.settings.timeconst * self.timestep, 1.0]
        eq.solimp = [0.9999, 0.9999, 0.001, 0.5, 2]


@dataclass(frozen=True)
class Built:
    """A compiled model with the mechanism it was built from, its initial state and its parts."""

    mech: object
    model: mujoco.MjModel
    settings: Settings
    loads: Loads
    drives: tuple[Drive, ...]
    loops: tuple[Loop, ...]
    bodies: tuple[str, ...]
    qpos0: np.ndarray
    qvel0: np.ndarray
    act0: np.ndarray
    ctrl0: np.ndarray
    slow_stroke: tuple[float, float] | None = None
    """For a slow-stroke load: the first input's phase interval [rad] where it acts."""
    spec_xml: str = field(default="", repr=False)

    @property
    def name(self) -> str:
        return self.mech.name

    @property
    def timestep(self) -> float:
        return float(self.model.opt.timestep)


# ------------------------------------------------------------------------------- the time step
RATE_SAMPLES = 720
"""Samples per revolution of the scan for the fastest rate (at most RATE_SAMPLES_MAX over a run). Each
rate's highest local maxima are then refined by zooming in (RATE_ZOOMS rounds): near a singular pose a
link's speed peaks between samples (a Whitworth lever 0.2 mm from its singular pose peaks 4.5x higher
than a 720-sample scan shows, and the step chosen from the scan failed by 400x)."""
RATE_SAMPLES_MAX = 200_000
RATE_PEAKS = 4
"""Local maxima of each rate refined per revolution (at most 64 per rate)."""
RATE_ZOOMS = 8


def _rates(mech, t: np.ndarray) -> np.ndarray:
    """Every rate of the motion at times ``t`` [1/s], shape (len(t), k): each input's and link's |omega|
    and sqrt(|alpha|), each slide's |ds| / size and sqrt(|dds| / size) (an input slider's over the size);
    NaN where the mechanism cannot be assembled."""
    q, qd, qdd = mech.drive(t)
    size = mech.size
    names = [f"{k}{ln}" for ln in mech.links for k in ("omega", "alpha")]
    names += [f"{k}{j}" for j in mech.slides for k in ("ds", "dds")]
    sol = mech.solve(q, qd, qdd, outputs=names)
    cols = []
    for k, inp in enumerate(mech.inputs):
        scale = 1.0 if inp.kind == "crank" else size
        cols += [np.abs(qd[:, k]) / scale, np.sqrt(np.abs(qdd[:, k]) / scale)]
    for ln in mech.links:
        cols += [np.abs(sol["omega" + ln]), np.sqrt(np.abs(sol["alpha" + ln]))]
    for j in mech.slides:
        cols += [np.abs(sol["ds" + j]) / size, np.sqrt(np.abs(sol["dds" + j]) / size)]
    return np.column_stack(cols)


def _peaks(r: np.ndarray, keep: int) -> tuple[np.ndarray, np.ndarray]:
    """(sample, column) of the ``keep`` highest local maxima of each column of ``r`` (ends included)."""
    pad = np.pad(r, ((1, 1), (0, 0)), constant_values=-np.inf)
    is_peak = (pad[1:-1] >= pad[:-2]) & (pad[1:-1] >= pad[2:]) & np.isfinite(r)
    rows, cols = [], []
    for c in range(r.shape[1]):
        idx = np.flatnonzero(is_peak[:, c])
        idx = idx[np.argsort(r[idx, c])[-keep:]]
        rows.append(idx)
        cols.append(np.full(len(idx), c))
    return np.concatenate(rows), np.concatenate(cols)


def rate_scale(mech, revolutions: float = 1.0) -> float:
    """Omega [1/s]: the fastest rate over a run of ``revolutions`` (see STEP_ANGLE), NaN if the mechanism
    cannot be assembled somewhere on it. A scan, then each rate's highest peaks refined by zooming in."""
    end = mech.duration(revolutions)
    turns = max(1.0, revolutions)
    t = np.linspace(0.0, end, int(min(RATE_SAMPLES * turns, RATE_SAMPLES_MAX)) + 1)
    r = _rates(mech, t)
    if np.isnan(r).any():
        return math.nan
    best = float(r.max())
    rows, cols = _peaks(r, min(64, int(math.ceil(RATE_PEAKS * turns))))
    lo, hi = t[np.maximum(rows - 1, 0)], t[np.minimum(rows + 1, len(t) - 1)]
    u = np.linspace(0.0, 1.0, 9)
    for _ in range(RATE_ZOOMS):
        tt = lo[:, None] + (hi - lo)[:, None] * u[None, :]
        rr = _rates(mech, tt.ravel())
        if np.isnan(rr).any():
            return math.nan
        best = max(best, float(rr.max()))
        own = rr[np.arange(rr.shape[0]), np.repeat(cols, len(u))].reshape(tt.shape)
        k = np.argmax(own, axis=1)
        lo, hi = tt[np.arange(len(k)), np.maximum(k - 1, 0)], tt[np.arange(len(k)), np.minimum(k + 1, len(u) - 1)]
    return best


def choose_timestep(mech, revolutions: float = 1.0) -> float:
    """The time step for ``mech`` (STEP_ANGLE, MAX_TIMESTEP); refuses a design needing < MIN_TIMESTEP."""
    omega = rate_scale(mech, revolutions)
    if not math.isfinite(omega):
        raise ParameterError(f"the {mech.name} cannot be assembled over the whole run; check its input range")
    h = min(MAX_TIMESTEP, STEP_ANGLE / omega) if omega > 0 else MAX_TIMESTEP
    if h < MIN_TIMESTEP:
        raise ParameterError(f"the {mech.name} moves too fast to simulate accurately (a link turns at up to "
                             f"{omega:.3g} rad/s, needing a step of {h:.2g} s < {MIN_TIMESTEP:g} s): slow its "
                             f"drives or move it away from its singular pose")
    return h


def motion_scale(mech) -> float:
    """Omega [1/s]: the fastest commanded input speed (a slider's over the size)."""
    t = np.linspace(0.0, mech.duration(1.0), 181)
    qd = mech.drive(t)[1]
    scales = [np.max(np.abs(qd[:, k])) / (1.0 if i.kind == "crank" else mech.size) for k, i in enumerate(mech.inputs)]
    return float(max(scales))


def regularization(model, mech, loads) -> float:
    """REGULARIZATION_SCALE / (1 + load / inertial force), with the load |F| + m |g| and the inertial force
    m L Omega^2 (m the links' mass, L the size, Omega the fastest input speed). The leak into the loops
    grows with the constraint force (R lambda) and the torque error with the inertial forces over R, so
    scaling R by their ratio keeps both at their unloaded level: a 6.6 mm Peaucellier cell pushed by 24 N
    (140x its inertial force) had 4e-6 rad of angle error at 1e-6, 3e-8 at the 8e-9 chosen here."""
    m = float(model.body_mass.sum())
    inertial = m * mech.size * motion_scale(mech) ** 2
    load = math.hypot(*loads.force) + (m * math.hypot(*loads.gravity) if loads.gravity is not None else 0.0)
    return REGULARIZATION_SCALE / (1.0 + load / inertial) if inertial > 0 else REGULARIZATION_SCALE


# --------------------------------------------------------------------------------------- building
def _frames(mech, sol) -> dict[str, tuple[float, float, float]]:
    """World pose (x, y, angle) of every body at the solution's first sample."""
    origins = mech.link_origins
    frames = {GROUND: (0.0, 0.0, 0.0)}
    for ln in mech.links:
        p = origins[ln]
        frames[ln] = (float(sol["x" + p][0]), float(sol["y" + p][0]), float(sol["phi" + ln][0]))
    return frames


def _local(frame, x, y):
    ox, oy, th = frame
    c, s = math.cos(th), math.sin(th)
    return ((x - ox) * c + (y - oy) * s, -(x - ox) * s + (y - oy) * c)


def _quat(angle: float) -> list[float]:
    return [math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2)]


def spanning_tree(mech):
    """The topology's spanning tree (parent, child, joint) from the ground outwards, and the joints that
    close its loops; MuJoCo closes a loop at a revolute only."""
    topo = mech.topology
    for loop in topo.loops:
        j = loop.joint
        if j.kind == "prismatic" or j.input is not None:
            raise ParameterError(f"the {mech.name}'s loop through {j.name} would close at a prismatic or "
                                 f"driven pair, which MuJoCo cannot close; restructure the loop")
    from analytic.topology import disconnected
    missing = disconnected(topo)
    if missing:
        raise ParameterError(f"links {', '.join(sorted(missing))} of the {mech.name} are not connected to the ground")
    return topo.tree, tuple(loop.joint for loop in topo.loops)


def default_inertia(mech, points, frames, link: str):
    """Slender-bar inertia of a link (see LINEAR_DENSITY), in its frame: (m, cx, cy, Izz about COM)."""
    from analytic.closed_forms.dynamics import Inertia
    size = mech.size
    members = [p for p in _members(mech)[link] if p != mech.link_origins[link]]
    segs = []
    for p in members:
        x, y = _point_local(points, frames, link, p)
        segs.append((math.hypot(x, y), x / 2, y / 2))
    if link in mech.slides or not segs or all(L < 1e-12 * size for L, _, _ in segs):
        m = LINEAR_DENSITY * 0.1 * size
        return Inertia(m=m, cx=0.0, cy=0.0, I=m * (0.1 * size) ** 2 / 6)
    mass = sum(LINEAR_DENSITY * L for L, _, _ in segs)
    cx = sum(LINEAR_DENSITY * L * x for L, x, _ in segs) / mass
    cy = sum(LINEAR_DENSITY * L * y for L, _, y in segs) / mass
    inertia = sum(LINEAR_DENSITY * L * (L * L / 12 + (x - cx) ** 2 + (y - cy) ** 2) for L, x, y in segs)
    return Inertia(m=mass, cx=cx, cy=cy, I=max(inertia, mass * (0.01 * size) ** 2))


def _point_local(points, frames, link, p):
    """Point ``p`` (world position at t = 0 in ``points``) in the frame of ``link``."""
    x, y = points[p]
    return _local(frames[link], x, y)


def _members(mech) -> dict[str, set[str]]:
    topo = mech.topology
    return {GROUND: set(topo.ground), **{ln: set(link.points) for ln, link in topo.links.items()}}


_COLORS = ["crank", "coupler", "rocker", "slider", "ground"]


def build(mech, settings: Settings = Settings(), loads: Loads = Loads(), revolutions: float = 1.0) -> Built:
    """Generate and compile the model of ``mech`` with its initial state from the analytic solver."""
    if settings.timestep is None:
        settings = replace(settings, timestep=choose_timestep(mech, revolutions))
    if mech.size < MIN_SIZE:
        raise ParameterError(
            f"{mech.definition.source}: the {mech.name} spans {mech.size:.3g} m ({mech.size / mech.scale:.3g} "
            f"{mech.definition.units}); the simulation needs at least {MIN_SIZE:g} m (MuJoCo's minimum masses)"
            + (": were metres typed into a mm file? give the lengths in mm" if mech.definition.units != "m" else
               "; scale the lengths up"))
    h = float(settings.timestep)
    (q0, qd0, qdd0), sol = mech.solve_at([0.0])
    if not sol.valid.all():
        mech.check_assembles(q0)
    points = {p: (float(sol["x" + p][0]), float(sol["y" + p][0])) for p in mech.points}
    return _build(mech, settings, loads, h, sol, points, (q0[0], qd0[0], qdd0[0]), revolutions)


def _build(mech, settings, loads, h, sol, points, q_start, revolutions) -> Built:
    spec = mujoco.MjSpec.from_file(str(TEMPLATE))
    spec.modelname = mech.name
    size = mech.size
    frames = _frames(mech, sol)
    order, cuts = spanning_tree(mech)
    members = _members(mech)
    carriers = _carriers(mech)
    bodies = {GROUND: spec.worldbody}
    radius = 0.015 * size

    for n, (parent, child, j) in enumerate(order):
        pf, cf = frames[parent], frames[child]
        px, py = _local(pf, cf[0], cf[1])
        body = bodies[parent].add_body(name=child, pos=[px, py, 0.0], quat=_quat(cf[2] - pf[2]))
        bodies[child] = body
        jx, jy = _point_local(points, frames, child, j.point)
        if j.kind == "revolute":
            body.add_joint(name=j.name, type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, 0, 1], pos=[jx, jy, 0])
        else:
            u = frames[j.slide][2]                         # the block's angle is the slide direction
            ax, ay = math.cos(u - cf[2]), math.sin(u - cf[2])
            body.add_joint(name=j.name, type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[ax, ay, 0], pos=[jx, jy, 0])
        _draw_link(spec, body, mech, points, frames, child, members, radius, _COLORS[n % 4])
    _draw_ground(spec, mech, points, radius)

    # Sites: every point on its carrier body; loop closures get a second site on the other body.
    for p, (x, y) in points.items():
        link = carriers[p]
        lx, ly = _local(frames[link], x, y)
        marker = p == mech.output_point
        site = bodies[link].add_site(name=p, pos=[lx, ly, 0], size=[radius * (0.8 if marker else 0.3)] * 3,
                                     rgba=[0.89, 0.10, 0.11, 1] if marker else [1, 1, 1, 0])
        site.group = 0 if marker else 4
    loops = []
    for j in cuts:
        other = j.b if carriers[j.point] == j.a else j.a
        host = j.a if other == j.b else j.b
        x, y = points[j.point]
        name2 = f"{j.point}_{other}"
        lx, ly = _local(frames[other], x, y)
        bodies[other].add_site(name=name2, pos=[lx, ly, 0], size=[radius * 0.3] * 3, rgba=[1, 1, 1, 0], group=4)
        site1 = j.point if carriers[j.point] == host else f"{j.point}_{host}"
        if site1 != j.point:
            lx1, ly1 = _local(frames[host], x, y)
            bodies[host].add_site(name=site1, pos=[lx1, ly1, 0], size=[radius * 0.3] * 3, rgba=[1, 1, 1, 0])
        eq = spec.add_equality(name=f"loop_{j.name}", type=mujoco.mjtEq.mjEQ_CONNECT,
                               objtype=mujoco.mjtObj.mjOBJ_SITE, name1=site1, name2=name2)
        eq.solref = [settings.timeconst * h, 1.0]
        eq.solimp = [0.9999, 0.9999, 0.001, 0.5, 2]
        loops.append(Loop(eq.name, j.point, site1, name2))

    context = Context(spec, mech, order, frames, points, h, settings)
    from analytic import kinds
    for e in mech.geometry.elements:                   # constraints a kind adds (a gear's coupling)
        kinds.get(e["kind"]).mjcf(e, context)
    _add_inertias(spec, mech, points, frames, loads)
    drives = _add_drives(spec, mech, order, q_start, h)
    _add_load(spec, mech, loads)
    _add_sensors(spec, mech, drives, loops)
    spec.option.timestep = h
    spec.option.integrator = INTEGRATORS[settings.integrator]
    if loads.gravity is not None:
        spec.option.gravity = [loads.gravity[0], loads.gravity[1], 0.0]
    _frame_camera(spec, mech)
    xml = spec.to_xml()
    try:
        model = spec.compile()
    except ValueError as exc:
        raise ParameterError(f"MuJoCo cannot compile the {mech.name}: {str(exc).splitlines()[0]}") from None
    model.body_invweight0[:] *= regularization(model, mech, loads)
    drives = _size_drives(model, mech, drives, loads, h)
    qpos0, qvel0 = _initial_state(model, mech, order, frames, sol)
    act0, ctrl0 = _initial_controls(model, mech, drives, q_start, loads)
    built = Built(mech, model, settings, loads, tuple(drives), tuple(loops), tuple(mech.links),
                  qpos0, qvel0, act0, ctrl0, _slow_stroke(mech) if loads.slow_stroke_only else None, xml)
    return built


def _carriers(mech) -> dict[str, str]:
    return mech.topology.carriers


def _draw_link(spec, body, mech, points, frames, link, members, radius, material):
    origin = mech.link_origins[link]
    if link in mech.slides:
        s = 0.04 * mech.size
        body.add_geom(name=link, type=mujoco.mjtGeom.mjGEOM_BOX, size=[1.6 * s, s, 0.5 * radius],
                      pos=[0, 0, 2 * radius], material="slider", contype=0, conaffinity=0, density=0)
        return
    z = 2.0 * radius * (len(spec.geoms) % 3)
    for k, p in enumerate(sorted(members[link] - {origin})):
        x, y = _point_local(points, frames, link, p)
        if math.hypot(x, y) > 1e-6 * mech.size:           # a point on the link's pin gets no bar (MuJoCo refuses it)
            body.add_geom(name=f"{link}_{p}", type=mujoco.mjtGeom.mjGEOM_CAPSULE, size=[radius, 0, 0],
                          fromto=[0, 0, z, x, y, z], material=material, contype=0, conaffinity=0, density=0)
        body.add_geom(name=f"pin_{link}_{p}", type=mujoco.mjtGeom.mjGEOM_CYLINDER,
                      size=[1.4 * radius, 0.7 * radius, 0], pos=[x, y, z + radius], material="pin",
                      contype=0, conaffinity=0, density=0)
    body.add_geom(name=f"pin_{link}_{origin}", type=mujoco.mjtGeom.mjGEOM_CYLINDER,
                  size=[1.4 * radius, 0.7 * radius, 0], pos=[0, 0, z + radius], material="pin",
                  contype=0, conaffinity=0, density=0)


def _draw_ground(spec, mech, points, radius):
    world = spec.worldbody
    for g in mech.ground_points:
        x, y = points[g]
        world.add_geom(name=f"ground_{g}", type=mujoco.mjtGeom.mjGEOM_BOX,
                       size=[3 * radius, 2 * radius, 0.7 * radius], pos=[x, y - 2 * radius, -2 * radius],
                       material="ground", contype=0, conaffinity=0)
    # ground guide lines: a rail over the block's travel
    from analytic import kinds
    rails = [r for e in mech.geometry.elements for r in kinds.get(e["kind"]).rails(e)]
    if rails:
        t = np.linspace(0.0, mech.duration(1.0), 181)
        sol = mech.solve(*mech.drive(t))
    for block, g, off in rails:
        s = sol["s" + block]
        lo, hi = float(np.nanmin(s)), float(np.nanmax(s))
        ox, oy = (points[g["through"]] if isinstance(g["through"], str) else g["through"])
        c, sn = math.cos(g["angle"]), math.sin(g["angle"])
        mid = 0.5 * (lo + hi)
        world.add_geom(name=f"rail_{block}", type=mujoco.mjtGeom.mjGEOM_BOX,
                       size=[0.5 * (hi - lo) + 3 * radius, 0.4 * radius, 0.2 * radius],
                       pos=[ox + mid * c - off * sn, oy + mid * sn + off * c, -2 * radius],
                       quat=_quat(g["angle"]), material="ground", contype=0, conaffinity=0)


def _add_inertias(spec, mech, points, frames, loads):
    given = dict(mech.definition.inertia)
    from analytic.closed_forms.dynamics import Inertia
    user = {k: Inertia(m=float(v["m"]), cx=float(v.get("cx", 0.0)) * mech.scale,
                       cy=float(v.get("cy", 0.0)) * mech.scale, I=float(v["I"]) * mech.scale ** 2)
            for k, v in given.items()}
    user.update(loads.inertias or {})
    unknown = set(user) - set(mech.links)
    if unknown:
        raise ParameterError(f"inertia: the {mech.name} has no link {sorted(unknown)[0]!r}; links: "
                             f"{', '.join(mech.links)}")
    for ln in mech.links:
        b = spec.body(ln)
        inertia = user.get(ln) or default_inertia(mech, points, frames, ln)
        if not (inertia.m >= MIN_MASS and inertia.I >= MIN_INERTIA):
            raise ParameterError(f"inertia of link {ln}: m = {inertia.m:.3g} kg, I = {inertia.I:.3g} kg m^2; the "
                                 f"simulation needs m >= {MIN_MASS:g} kg and I >= {MIN_INERTIA:g} kg m^2 "
                                 f"(MuJoCo's minimum): give a realistic [inertia] or --inertia")
        b.explicitinertial = True
        b.mass = inertia.m
        b.ipos = [inertia.cx, inertia.cy, 0.0]
        b.iquat = [1.0, 0.0, 0.0, 0.0]
        b.inertia = [inertia.I / 2, inertia.I / 2, inertia.I]   # a thin plate: Ixx + Iyy = Izz


def _add_drives(spec, mech, order, q_start, h) -> list[Drive]:
    drives = []
    q0, _, _ = q_start
    for k, inp in enumerate(mech.inputs):
        j = next(jt for _, _, jt in order if jt.input == k)
        name = f"drive_{inp.link}"
        act = spec.add_actuator(name=name, target=j.name, trntype=mujoco.mjtTrn.mjTRN_JOINT)
        act.dyntype = mujoco.mjtDyn.mjDYN_INTEGRATOR
        act.gaintype = mujoco.mjtGain.mjGAIN_FIXED
        act.biastype = mujoco.mjtBias.mjBIAS_AFFINE
        act.actlimited = False
        act.ctrllimited = False
        act.forcelimited = False
        drives.append(Drive(inp, j.name, name, 1.0, 0.0, 0.0, float(q0[k])))
    return drives


def _add_load(spec, mech, loads):
    act = spec.add_actuator(name="load", target=mech.output_point, trntype=mujoco.mjtTrn.mjTRN_SITE,
                            refsite="origin")
    fx, fy = loads.force
    act.gear = [fx, fy, 0.0, 0.0, 0.0, 0.0]
    act.ctrllimited = False


def _add_sensors(spec, mech, drives, loops):
    S = mujoco.mjtSensor
    site, body = mujoco.mjtObj.mjOBJ_SITE, mujoco.mjtObj.mjOBJ_BODY

    def add(name, kind, objtype=None, objname=None):
        s = spec.add_sensor(name=name, type=kind)
        if objtype is not None:
            s.objtype, s.objname = objtype, objname
        return s

    add("time", S.mjSENS_CLOCK)
    for p in mech.points:
        add(f"{p}_pos", S.mjSENS_FRAMEPOS, site, p)
        add(f"{p}_vel", S.mjSENS_FRAMELINVEL, site, p)
        add(f"{p}_acc", S.mjSENS_FRAMELINACC, site, p)
    for ln in mech.links:
        add(f"{ln}_xaxis", S.mjSENS_FRAMEXAXIS, body, ln)
        add(f"{ln}_angvel", S.mjSENS_FRAMEANGVEL, body, ln)
        add(f"{ln}_angacc", S.mjSENS_FRAMEANGACC, body, ln)
    for d in drives:
        s = add(f"{d.joint}_q", S.mjSENS_JOINTPOS)
        s.objtype, s.objname = mujoco.mjtObj.mjOBJ_JOINT, d.joint
        s = add(f"{d.joint}_qd", S.mjSENS_JOINTVEL)
        s.objtype, s.objname = mujoco.mjtObj.mjOBJ_JOINT, d.joint
        s = add(f"tau{d.input.link}", S.mjSENS_ACTUATORFRC)
        s.objtype, s.objname = mujoco.mjtObj.mjOBJ_ACTUATOR, d.actuator
    s = add("load", S.mjSENS_ACTUATORFRC)
    s.objtype, s.objname = mujoco.mjtObj.mjOBJ_ACTUATOR, "load"
    for lp in loops:
        for nm in (lp.site1, lp.site2):
            if nm not in mech.points:
                add(f"{nm}_pos", S.mjSENS_FRAMEPOS, site, nm)


def _frame_camera(spec, mech, aspect: float = 4 / 3) -> None:
    center, extent = framing(mech, aspect)
    cam = spec.camera("top")
    cam.pos = [center[0], center[1], 10.0 * extent]
    cam.fovy = extent
    paper = spec.geom("paper")
    paper.pos = [center[0], center[1], -0.1 * extent]
    paper.size = [2 * extent, 2 * extent, 0.01]
    spec.visual.map.znear = 0.001
    spec.stat.extent = extent


def path_points(mech, samples: int = 361) -> np.ndarray:
    """Every point over one period of the first input, shape (k, 2) [m]: frames the camera."""
    t = np.linspace(0.0, mech.duration(1.0), samples)
    sol = mech.solve(*mech.drive(t))
    pts = [np.column_stack([sol["x" + p], sol["y" + p]]) for p in mech.points]
    pts = np.concatenate(pts)
    return pts[np.all(np.isfinite(pts), axis=1)]


def framing(mech, aspect: float) -> tuple[np.ndarray, float]:
    """Centre (x, y) [m] and vertical extent [m] of an orthographic view showing every point of ``mech``
    in an image of width/height ``aspect``, with a 30 % margin."""
    pts = path_points(mech)
    lo, hi = pts.min(0), pts.max(0)
    return 0.5 * (lo + hi), float(max(hi[1] - lo[1], (hi[0] - lo[0]) / aspect, 1e-9) * 1.3)


def frame_extent(mech, aspect: float) -> float:
    return framing(mech, aspect)[1]


# ----------------------------------------------------------------------------------- drives sizing
def body_inertias(model: mujoco.MjModel, names) -> dict:
    """The compiled bodies' inertial data as analytic.closed_forms.dynamics.Inertia (mass, COM in the body frame, Izz
    about the COM)."""
    from analytic.closed_forms.dynamics import Inertia
    out = {}
    for n in names:
        b = model.body(n)
        rot = np.empty(9)
        mujoco.mju_quat2Mat(rot, b.iquat)
        rot = rot.reshape(3, 3)
        izz = float((rot @ np.diag(b.inertia) @ rot.T)[2, 2])
        out[n] = Inertia(m=float(b.mass[0]), cx=float(b.ipos[0]), cy=float(b.ipos[1]), I=izz)
    return out


def _size_drives(model, mech, drives, loads, h) -> list[Drive]:
    """kp from the peak analytic drive force (DRIVE_ERROR_BUDGET), J and kv for SERVO_RATE."""
    from analytic.applications import torque
    t = np.linspace(0.0, mech.duration(1.0), 361)
    q, qd, qdd = mech.drive(t)
    switch = 1.0
    tau = torque.drive_forces(mech, q, qd, qdd, body_inertias(model, mech.links), None,
                              tuple(model.opt.gravity[:2]), tuple(model.actuator("load").gear[:2]), switch)
    out = []
    size = mech.size
    for d in drives:
        peak = float(np.nanmax(np.abs(tau[d.input.link])))
        budget = DRIVE_ERROR_BUDGET * (1.0 if d.input.kind == "crank" else size)
        total_mass = float(sum(model.body_mass))
        floor = 1e-3 * total_mass * 9.81 * size          # a small load so kp is never zero
        kp = max(peak, floor) / budget
        J = kp * (h / SERVO_RATE) ** 2
        kv = 2.0 * math.sqrt(kp * J)
        a = model.actuator(d.actuator)
        a.gainprm[0] = kp
        a.biasprm[:3] = [0.0, -kp, -kv]
        model.dof_armature[model.jnt_dofadr[model.joint(d.joint).id]] = J
        out.append(replace(d, kp=kp, kv=kv, armature=J))
    return out


def drive_command(d: Drive, q, qd, qdd, qddd):
    """The servo's activation target and its rate for a desired motion (q, qd, qdd, qddd): the
    activation a leads q by (kv qd + J qdd) / kp, so that force = kp (a - q) - kv qdot = J qdd on the
    desired motion with no reaction; ctrl = da/dt."""
    lead = (d.kv * qd + d.armature * qdd) / d.kp
    rate = qd + (d.kv * qdd + d.armature * qddd) / d.kp
    return q - d.q_offset + lead, rate


def _initial_state(model, mech, order, frames, sol):
    qpos = np.zeros(model.nq)
    qvel = np.zeros(model.nv)
    vel = {GROUND: (0.0, 0.0, 0.0)}
    origins = mech.link_origins
    for ln in mech.links:
        p = origins[ln]
        vel[ln] = (float(sol["vx" + p][0]), float(sol["vy" + p][0]), float(sol["omega" + ln][0]))
    for parent, child, j in order:
        dof = model.jnt_dofadr[model.joint(j.name).id]
        if j.kind == "revolute":
            qvel[dof] = vel[child][2] - vel[parent][2]
        else:
            px, py, pth = frames[parent]
            cx, cy, _ = frames[child]
            vpx = vel[parent][0] - vel[parent][2] * (cy - py)
            vpy = vel[parent][1] + vel[parent][2] * (cx - px)
            u = frames[j.slide][2]
            qvel[dof] = (vel[child][0] - vpx) * math.cos(u) + (vel[child][1] - vpy) * math.sin(u)
    return qpos, qvel


def _initial_controls(model, mech, drives, q_start, loads):
    """The drives' activations at t = 0: the commanded motion's lead plus the deflection that the
    mechanism's reaction needs (kp a = tau), so the servo starts already carrying its load and the
    torque curve has no start-up transient."""
    from analytic.applications import torque
    q0, qd0, qdd0 = q_start
    act = np.zeros(model.na)
    ctrl = np.zeros(model.nu)
    jerk = _jerk(mech, np.array([0.0]))
    on = 1.0
    if loads.slow_stroke_only:
        lo, hi = _slow_stroke(mech)
        on = float(lo <= 0.0 <= hi or lo <= 2 * math.pi <= hi)
    reaction = torque.drive_forces(mech, q0[None], qd0[None], qdd0[None], body_inertias(model, mech.links), None,
                                   tuple(model.opt.gravity[:2]), tuple(model.actuator("load").gear[:2]), on)
    for k, d in enumerate(drives):
        a, c = drive_command(d, q0[k], qd0[k], qdd0[k], jerk[0, k])
        act[model.actuator(d.actuator).actadr[0]] = a + float(reaction[d.input.link][0]) / d.kp
        ctrl[model.actuator(d.actuator).id] = c
    return act, ctrl


def _jerk(mech, t):
    """d^3 q / dt^3 of every input at times t (nonzero only for a rocking drive)."""
    out = np.zeros((len(t), len(mech.inputs)))
    for k, inp in enumerate(mech.inputs):
        m = inp.motion
        if m.rock is not None:
            w, amp = abs(m.rate), 0.5 * (m.rock[1] - m.rock[0])
            out[:, k] = -amp * w ** 3 * np.sin(w * t)
    return out


def _slow_stroke(mech) -> tuple[float, float]:
    """The first input's phase interval [rad from its start] in which the output point makes its slower
    stroke along x (the cutting stroke of a quick-return mechanism)."""
    first = mech.inputs[0]
    T = mech.duration(1.0)
    t = np.linspace(0.0, T, 3601)
    sol = mech.solve(*mech.drive(t))
    x = sol["x" + mech.output_point]
    k_min, k_max = int(np.nanargmin(x)), int(np.nanargmax(x))
    a, b = sorted((k_min, k_max))
    inner = b - a                           # samples from one extreme to the other
    phase = (first.motion.at(t)[0] - first.motion.q0)
    if inner >= len(t) - 1 - inner:
        return float(phase[a]), float(phase[b])
    return float(phase[b]), float(phase[a] + 2 * math.pi)


def export_xml(built: Built) -> str:
    """The model as a standalone MJCF document whose default pose closes every loop, with its home key.

    MjSpec.to_xml writes 6 significant digits, which would open the loops by ~1e-7 of the size; every
    pose (bodies, joints, sites, geoms), the drives' gains and the keyframe are written again here at full
    double precision from the compiled model."""
    import xml.etree.ElementTree as ET
    m = built.model
    root = ET.fromstring(built.spec_xml)
    fmt = lambda xs: " ".join(repr(float(x)) for x in xs)                   # noqa: E731
    for el in root.iter():
        name = el.get("name")
        if name is None:
            continue
        if el.tag == "body":
            b = m.body(name)
            el.set("pos", fmt(b.pos))
            el.set("quat", fmt(b.quat))
            inertial = el.find("inertial")
            if inertial is not None:
                inertial.attrib.pop("fullinertia", None)
                inertial.set("pos", fmt(b.ipos))
                inertial.set("quat", fmt(b.iquat))
                inertial.set("mass", repr(float(b.mass[0])))
                inertial.set("diaginertia", fmt(b.inertia))
        elif el.tag == "joint":
            j = m.joint(name)
            el.set("pos", fmt(m.jnt_pos[j.id]))
            el.set("axis", fmt(m.jnt_axis[j.id]))
            if m.jnt_dofadr[j.id] >= 0:
                el.set("armature", repr(float(m.dof_armature[m.jnt_dofadr[j.id]])))
        elif el.tag == "site":
            st = m.site(name)
            el.set("pos", fmt(st.pos))
            el.set("quat", fmt(st.quat))
        elif el.tag == "geom":
            g = m.geom(name)
            el.set("pos", fmt(g.pos))
            el.set("quat", fmt(g.quat))
        elif el.tag == "general" or el.tag in ("motor", "velocity", "position", "intvelocity"):
            a = m.actuator(name)
            el.set("gainprm", fmt(a.gainprm[:3]))
            el.set("biasprm", fmt(a.biasprm[:3]))
    keyframe = root.find("keyframe")
    if keyframe is None:
        keyframe = ET.SubElement(root, "keyframe")
    ET.SubElement(keyframe, "key", name="home", qpos=fmt(built.qpos0), qvel=fmt(built.qvel0), act=fmt(built.act0),
                  ctrl=fmt(built.ctrl0))
    scale = regularization(m, built.mech, built.loads)      # what _build applied (masses are not scaled)
    custom = root.find("custom")
    if custom is None:
        custom = ET.SubElement(root, "custom")
    ET.SubElement(custom, "numeric", name=INVWEIGHT_NUMERIC, data=repr(scale))
    ET.indent(root, space="  ")
    source = _comment_safe(str(built.mech.definition.source))
    head = (f"<!-- {_comment_safe(built.mech.name)}: generated by linkage (sim/model/__init__.py) from {source}.\n"
            f"     Every body is at its assembled pose at t = 0 and the home keyframe adds the initial\n"
            f"     velocities and the drives' states. The validated simulation shrinks MuJoCo's constraint\n"
            f"     regulariser after compiling (body_invweight0 times the custom numeric {INVWEIGHT_NUMERIC});\n"
            f"     MJCF cannot hold that (solimp is already at MuJoCo's cap 0.9999), so loaded as it is the\n"
            f"     loops open by 3e-6 to 8e-5 of the size over a turn (3 to 80 times the loop tolerance of\n"
            f"     1e-6 of the size; measured on the library, docs/CONVENTIONS.md).\n"
            f"     Load it with sim.load_exported(FILE) to get the validated model; view it with\n"
            f"     python -m mujoco.viewer with the mjcf option set to FILE -->\n")
    return head + ET.tostring(root, encoding="unicode") + "\n"


INVWEIGHT_NUMERIC = "linkage_invweight0_scale"
"""Name of the MJCF custom numeric holding the factor sim.load_exported applies to body_invweight0."""


def _comment_safe(text: str) -> str:
    """Text that may stand inside an XML comment: no '--' (not well-formed) and no line breaks."""
    text = " ".join(text.splitlines())
    while "--" in text:
        text = text.replace("--", "-_")
    return text.rstrip("-")

