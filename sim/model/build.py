"""Building a model: the spanning tree of link bodies placed at their assembled pose, the loops closed by
connect constraints, the kinds' own constraints, masses, drives, load, sensors; compiled with the
regulariser of the validated simulation and the initial state from the analytic solver."""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path

import mujoco
import numpy as np

import mjcf
from analytic import ParameterError
from analytic.kinds import GROUND
from sim.model.appearance import COLORS, draw_ground, draw_link, frame_camera
from sim.model.drives import Drive, add_drives, add_load, initial_controls, size_drives, slow_stroke
from sim.model.frames import body_frames, local, point_local, quat
from sim.model.inertia import add_inertias, link_members
from sim.model.sensors import add_sensors
from sim.model.settings import INTEGRATORS, Loads, Settings
from sim.model.timestep import choose_timestep, motion_scale

MJCF_DIR = Path(mjcf.__file__).resolve().parent

TEMPLATE = MJCF_DIR / "template.xml"

REGULARIZATION_SCALE = 1e-6
"""Scale applied to the compiled ``body_invweight0`` (and ``tendon_invweight0``, which sizes a gear coupling's
tendon equality the same way): MuJoCo sizes each constraint's regulariser as
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
    """The spec's MJCF before compiling, for :func:`sim.model.export.export_xml`: written only by a build with
    ``export=True`` ("" otherwise)."""
    loadset: object = None
    """The file's and the command line's loads (analytic.loads.LoadSet), carried as xfrc_applied
    (sim.model.loads); None when there are none."""
    native: tuple = ()
    """Loads carried as MuJoCo tendons instead (a motor-driven run: sim.model.loads.add_native)."""
    regularization: float | None = None
    """The factor the constraints' inverse weights were scaled by (:func:`regularization`), as built."""
    memo: dict = field(default_factory=dict, repr=False, compare=False)
    """What a run reads several times from the model's commanded motion, kept once per model: the loads'
    wrenches at every step start (sim.model.loads.wrenches) and, for a cam's one-period motion, the cycle the
    model was built from (analytic.cycle.Cycle, read by sim.run.cams.analytic_contact; a longer cycle, up to
    analytic.cycle.SAMPLES_MAX samples, is not held past the build)."""

    @property
    def name(self) -> str:
        return self.mech.name

    @property
    def timestep(self) -> float:
        return float(self.model.opt.timestep)


def regularization(model, mech, loads, extra=None, spread: float = 1.0) -> float:
    """REGULARIZATION_SCALE / (1 + load / inertial force), with the load |F| + m |g| and the inertial force
    m L Omega^2 (m the links' mass, L the size, Omega the fastest input speed), times min(1, SPREAD_REF /
    ``spread``) (the loops' :func:`loop_spread`). The leak into the loops grows with the constraint force
    (R lambda) and the torque error with the inertial forces over R, so scaling R by their ratio keeps both
    at their unloaded level: a 6.6 mm Peaucellier cell pushed by 24 N (140x its inertial force) had 4e-6 rad
    of angle error at 1e-6, 3e-8 at the 8e-9 chosen here."""
    m = float(model.body_mass.sum())
    inertial = m * mech.size * motion_scale(mech) ** 2
    load = math.hypot(*loads.force) + (m * math.hypot(*loads.gravity) if loads.gravity is not None else 0.0)
    if extra is not None:
        load += extra.peak_force                     # the file's loads (sim.model.loads.drive_loads)
    scale = REGULARIZATION_SCALE / (1.0 + load / inertial) if inertial > 0 else REGULARIZATION_SCALE
    if any(e.get("flips") for e in mech.solving_geometry.elements):
        scale *= CHANGE_POINT_SCALE
    return scale * min(1.0, SPREAD_REF / spread)


SPREAD_REF = 30.0
"""The largest :func:`loop_spread` the regulariser is left at REGULARIZATION_SCALE for; a loop closure with a
larger spread has its scale divided by spread / SPREAD_REF. MuJoCo sizes a connect's regulariser from its two
bodies' compiled mobilities (R = (1 - d) / d (invweight0_1 + invweight0_2)), so the leak's share is R over the
constraint's mobility in its stiffest direction, lambda_min(J M^-1 J'); their ratio is the spread. Over the
library's linkages of slender bars it is 0.27-29 (scissor_lift's cylinder pin 29, klann 23, the four-bar 0.86).
A cylinder's rod (0.29 kg in the excavator) pinned to a boom of 1.5 t, its slide carrying the servo's rotor,
moves along its axis with the boom: there the spread is 1.5e3-1.1e5 (excavator), 3.2e4 (dump_tipper), the
leak 1e4x its calibrated share, and without gravity (which divides the scale by 1 + m g / m L Omega^2, 113 in
the excavator) tests/drives/excavator_cycle.toml's points missed by 2.2x their tolerance and its boom force by
1.1x at the rate-chosen step (a shorter step only shortens the loops' correction time, 32 steps)."""


def loop_spread(model, loops, qpos, qvel) -> float:
    """The largest over the loop closures (connects, :class:`Loop`) of (invweight0_1 + invweight0_2) /
    lambda_min, lambda_min the smallest eigenvalue of the in-plane block of J M^-1 J' at the pose ``qpos`` with
    the drives' rotor inertias (armature) in M, invweight0 as compiled (unscaled); 1 without loops."""
    if not loops:
        return 1.0
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:] = qpos, qvel
    mujoco.mj_forward(model, data)
    worst = 1.0
    for loop in loops:
        a, b = model.site(loop.site1), model.site(loop.site2)
        ja, jb = np.zeros((3, model.nv)), np.zeros((3, model.nv))
        mujoco.mj_jacSite(model, data, ja, None, a.id)
        mujoco.mj_jacSite(model, data, jb, None, b.id)
        J = (ja - jb)[:2]                                 # the plane's two directions (nothing moves along z)
        X = np.zeros((2, model.nv))
        mujoco.mj_solveM(model, data, X, J)
        lam = float(np.linalg.eigvalsh(0.5 * (J @ X.T + X @ J.T))[0])
        diag = float(model.body_invweight0[a.bodyid[0], 0] + model.body_invweight0[b.bodyid[0], 0])
        if lam > 0.0 and diag > 0.0:
            worst = max(worst, diag / lam)
    return worst


CHANGE_POINT_SCALE = 1e-4
"""A further factor on the regulariser of a mechanism whose dyads pass change points on their declared
branch (analytic.solver.change_points): there the loops' equations lose rank, J M^-1 J' vanishes and the
leak R lambda of the other directions is all that holds the dyad; a parallelogram's errors through its
change points were 30-200x the tolerances at 1 (whatever the step, h/4 to h), 0.3-2x at 1e-2 and
< 0.03x at 1e-4."""


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


def build(mech, settings: Settings = Settings(), loads: Loads = Loads(), revolutions: float = 1.0,
          native: bool = False, cycle=None, export: bool = False) -> Built:
    """Generate and compile the model of ``mech`` with its initial state from the analytic solver; ``native``:
    linear springs and dampers as MuJoCo tendons (a motor-driven run, sim.model.loads.add_native). ``cycle``:
    the run's motion solved once (:class:`analytic.cycle.Cycle`, made by the service; made here when None),
    read for the time step, the initial pose, the drives' sizes and the camera: the model never solves the
    mechanism itself. ``export``: the model written as a file (sim.model.export): the loads MJCF can hold
    statically in it (sim.model.loads.not_in_xml), as tendons and constant-force actuators."""
    from analytic.cycle import Cycle, periodic
    if cycle is None:
        cycle = Cycle.of(mech, revolutions)
    if settings.timestep is None:
        settings = replace(settings, timestep=cam_capped(mech, choose_timestep(mech, revolutions, cycle)))
    if mech.size < MIN_SIZE:
        raise ParameterError(
            f"{mech.definition.source}: the {mech.name} spans {mech.size:.3g} m ({mech.size / mech.scale:.3g} "
            f"{mech.definition.units}); the simulation needs at least {MIN_SIZE:g} m (MuJoCo's minimum masses)"
            + (": were metres typed into a mm file? give the lengths in mm" if mech.definition.units != "m" else
               "; scale the lengths up"))
    h = float(settings.timestep)
    (q0, qd0, qdd0), sol = cycle.at_start()
    if not sol.valid.all():
        mech.check_assembles(q0)
    points = {p: (float(sol["x" + p][0]), float(sol["y" + p][0])) for p in mech.points}
    built = build_model(mech, settings, loads, h, sol, points, (q0[0], qd0[0], qdd0[0]), revolutions, native, cycle,
                        export)
    if any(c.kind == "cam" for c in mech.topology.couplings) and periodic(mech):
        built.memo["cycle"] = cycle              # one period: a cam's contact force read from it (sim.run.cams)
    return built


def model_loads(mech, loads: Loads, cycle):
    """What a model of ``mech`` under ``loads`` carries besides its geometry, without building one: (each link's
    inertia as its body has it, sim.model.inertia.model_inertias at the cycle's start pose; gravity (gx, gy),
    (0, 0) where None; the load's force (Fx, Fy); its slow-stroke window or None; the file's loads,
    sim.model.loads.loadset_of). ``cycle``: the run's (analytic.cycle.Cycle), whose start pose the bodies
    are placed at."""
    from sim.model import loads as ML
    from sim.model.inertia import model_inertias
    _, sol = cycle.at_start()
    if not sol.valid.all():
        mech.check_assembles(cycle.q[:1])
    points = {p: (float(sol["x" + p][0]), float(sol["y" + p][0])) for p in mech.points}
    inertias = model_inertias(mech, points, body_frames(mech, sol), loads)
    gravity = (float(loads.gravity[0]), float(loads.gravity[1])) if loads.gravity is not None else (0.0, 0.0)
    force = (float(loads.force[0]), float(loads.force[1]))
    window = slow_stroke(mech, cycle) if loads.slow_stroke_only else None
    return inertias, gravity, force, window, ML.loadset_of(mech, loads)


def cam_capped(mech, h: float) -> float:
    """The chosen step ``h`` [s], at most 1 / cam_contact.STEPS_PER_TURN of a turn of the fastest input for a
    mechanism with a cam: MuJoCo's contact (sim.model.cam_contact) is as stiff as its step allows, its
    penetration growing as h^2; at the ~250 steps a turn the motion alone needs it is 60x softer than
    the 2000 its figures were measured at."""
    if not any(e["kind"] == "cam" for e in mech.geometry.elements):
        return h
    from sim.model.cam_contact import STEPS_PER_TURN
    return min(h, 2 * math.pi / (motion_scale(mech) * STEPS_PER_TURN))


def build_model(mech, settings, loads, h, sol, points, q_start, revolutions, native=False, cycle=None,
                export=False) -> Built:
    spec = mujoco.MjSpec.from_file(str(TEMPLATE))
    spec.modelname = mech.name
    size = mech.size
    frames = body_frames(mech, sol)
    order, cuts = spanning_tree(mech)
    members = link_members(mech)
    carriers = mech.topology.carriers
    bodies = {GROUND: spec.worldbody}
    radius = 0.015 * size

    for n, (parent, child, j) in enumerate(order):
        pf, cf = frames[parent], frames[child]
        px, py = local(pf, cf[0], cf[1])
        body = bodies[parent].add_body(name=child, pos=[px, py, 0.0], quat=quat(cf[2] - pf[2]))
        bodies[child] = body
        jx, jy = point_local(points, frames, child, j.point)
        if j.kind == "revolute":
            body.add_joint(name=j.name, type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, 0, 1], pos=[jx, jy, 0])
        else:
            u = frames[j.slide][2]                         # the block's angle is the slide direction
            ax, ay = math.cos(u - cf[2]), math.sin(u - cf[2])
            body.add_joint(name=j.name, type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[ax, ay, 0], pos=[jx, jy, 0])
        draw_link(spec, body, mech, points, frames, child, members, radius, COLORS[n % 4])
    draw_ground(spec, mech, points, radius, cycle)

    # Sites: every point on its carrier body; loop closures get a second site on the other body.
    for p, (x, y) in points.items():
        link = carriers[p]
        lx, ly = local(frames[link], x, y)
        marker = p == mech.output_point
        site = bodies[link].add_site(name=p, pos=[lx, ly, 0], size=[radius * (0.8 if marker else 0.3)] * 3,
                                     rgba=[0.89, 0.10, 0.11, 1] if marker else [1, 1, 1, 0])
        site.group = 0 if marker else 4
    out = mech.output_point
    loaded = mech.topology.loaded_link(out)            # a force at a block's pin acts on the block (issue 41)
    load_site = None
    if loaded != carriers[out]:
        load_site = f"{out}_load"
        lx, ly = local(frames[loaded], *points[out])
        bodies[loaded].add_site(name=load_site, pos=[lx, ly, 0], size=[radius * 0.3] * 3, rgba=[1, 1, 1, 0],
                                group=4)
    loops = []
    for j in cuts:
        other = j.b if carriers[j.point] == j.a else j.a
        host = j.a if other == j.b else j.b
        x, y = points[j.point]
        name2 = f"{j.point}_{other}"
        lx, ly = local(frames[other], x, y)
        bodies[other].add_site(name=name2, pos=[lx, ly, 0], size=[radius * 0.3] * 3, rgba=[1, 1, 1, 0], group=4)
        site1 = j.point if carriers[j.point] == host else f"{j.point}_{host}"
        if site1 != j.point:
            lx1, ly1 = local(frames[host], x, y)
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
    from sim.model import loads as ML
    loadset = ML.loadset_of(mech, loads)
    carried = ML.add_native(context, bodies, loadset, sol) if (native or export) and loadset else ()
    add_inertias(spec, mech, points, frames, loads)
    drives = add_drives(spec, mech, order, q_start, h)
    add_load(spec, mech, loads, load_site)
    if export and loadset:                             # after the drives and the load: their indices stay
        carried = carried + ML.add_static(context, bodies, loadset, carried)
    add_sensors(spec, mech, drives, loops)
    spec.option.timestep = h
    spec.option.integrator = INTEGRATORS[settings.integrator]
    if loads.gravity is not None:
        spec.option.gravity = [loads.gravity[0], loads.gravity[1], 0.0]
    frame_camera(spec, mech, cycle=cycle)
    xml = spec.to_xml() if export else ""          # read by export_xml alone (a cam's meshes: ~16 ms to write)
    try:
        model = spec.compile()
    except ValueError as exc:
        raise ParameterError(f"MuJoCo cannot compile the {mech.name}: {str(exc).splitlines()[0]}") from None
    window = slow_stroke(mech, cycle) if loads.slow_stroke_only else None
    held = loadset
    if export and loadset:                             # an exported model's servos hold the loads it carries
        held = replace(loadset, loads=tuple(ld for ld in loadset.loads if ld.name in carried), friction=None)
        held = held if held else None
    draft = Built(mech, model, settings, loads, tuple(drives), tuple(loops), tuple(mech.links), None, None, None,
                  None, window, xml, held, () if export else carried)
    extra = ML.drive_loads(draft, revolutions, cycle) if held else None
    drives = size_drives(model, mech, drives, loads, h, extra, cycle)
    qpos0, qvel0 = initial_state(model, mech, order, frames, sol)
    scale = regularization(model, mech, loads, extra, loop_spread(model, loops, qpos0, qvel0))
    model.body_invweight0[:] *= scale
    model.tendon_invweight0[:] *= scale             # a tendon equality (a gear coupling) is sized by these
    act0, ctrl0 = initial_controls(model, mech, drives, q_start, loads, extra, cycle)
    built = Built(mech, model, settings, loads, tuple(drives), tuple(loops), tuple(mech.links),
                  qpos0, qvel0, act0, ctrl0, window, xml, loadset, carried, scale)
    return built


def initial_state(model, mech, order, frames, sol):
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
