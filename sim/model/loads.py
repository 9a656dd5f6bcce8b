"""How the MuJoCo model carries the file's loads (SPEC "Loads"): as body wrenches (``xfrc_applied``).

Design. Along a prescribed motion (``simulate``, ``compare``, ``forces --simulate``) the drives hold the inputs
to their commanded motion within 1e-6 rad (sim.model.drives.DRIVE_ERROR_BUDGET), so every load -- a force or
torque with its law, a pressure, a spring, a torsion spring, a damper, and Coulomb friction with the
analytic fixed point's moments -- is evaluated from the commanded motion at each step's start and applied
over the step as ``xfrc_applied`` on its link's body (the force, and its moment about the body's centre of
mass plus any couple), given to ``mujoco.rollout`` as a control with the drives' commands. MuJoCo then solves
the multibody dynamics and every constraint force under these loads, which is what the comparison checks; it
does not model the loads' own physics (a spring's stiffness, Coulomb friction): those are checked against
hand statics and the energy balance (tests/test_loads_*.py). A load's reaction on the ground (a spring or a
damper anchored to the frame) is added to MuJoCo's shaking force and moment from the same evaluation.
Because xfrc_applied is part of ``cfrc_ext``, MuJoCo's joint forces (``cfrc_int``) include the loads with no
correction. Over a step a wrench is constant, so its work is exactly f . (displacement of the body's centre
of mass) + torque x (rotation of the body) (sim.run.compare.work_balance).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.kinds import GROUND


@dataclass(frozen=True)
class Wrenches:
    """Per step: ``xfrc`` (n, nbody, 6) for ``xfrc_applied`` (world frame: force, then torque about the body's
    centre of mass), ``ground`` (n, 3): (Fx, Fy, Mz about the origin) the loads put on the frame."""

    xfrc: np.ndarray
    ground: np.ndarray
    Ft: dict
    """Prismatic friction: joint index -> the force along the guide on the block [N] (a joint's share)."""


def loadset_of(mech, loads):
    """The file's loads and the command line's (``loads.extra``), resolved for ``mech``; None when there are
    none."""
    from analytic import loads as AL
    ls = AL.resolve(mech, tuple(getattr(loads, "extra", ()) or ()))
    return ls if ls else None


def applications(built, t, q=None, qd=None, qdd=None, sol=None):
    """Every load's wrenches (friction's included) at times ``t`` along the commanded motion (or the given
    inputs), with the compiled model's masses, gravity and shorthand load; and the State. ``sol``: the
    solution there (an analytic.cycle.Cycle's), or solved here."""
    from analytic.loads import kinetostatics as K
    from sim.model.inertia import body_inertias
    mech, model = built.mech, built.model
    if q is None:
        q, qd, qdd = mech.drive(t)
    inertias = body_inertias(model, mech.links)
    gravity = tuple(float(x) for x in model.opt.gravity[:2])
    ls = built.loadset
    if ls.friction:
        from sim.model.drives import load_switch
        load = tuple(float(x) for x in model.actuator("load").gear[:2])
        res = K.solve(mech, q, qd, qdd, t, inertias, ls, gravity, load, load_switch(built, np.asarray(t)), sol=sol)
        apps = [a for v in res.applications.values() for a in v] + list(res.friction_apps)
        return apps, res.state, inertias, res.Ft
    from analytic import loads as AL
    if sol is None:
        sol = mech.solve(q, qd, qdd, outputs=K.full_wanted(mech))
    state = AL.State(mech, sol, q, qd, t)
    variables = state.variables(AL.scales(mech.definition, mech.parameters))
    skip = set(getattr(built, "native", ()) or ())
    apps = [a for ld in ls.loads if ld.name not in skip for a in _applied(ld, state, variables)]
    return apps, state, inertias, {}


def _applied(ld, state, variables):
    """A load's applications; an expression not finite along the run (1/sin(phi1)) in one line naming the
    load, as the analytic side (analytic.loads.kinetostatics) words it."""
    from analytic.loads.common import LoadError
    try:
        return ld.applications(state, variables)
    except ValueError as exc:
        raise LoadError(f"load {ld.name}: {exc}") from None


def wrenches(built, t, q=None, qd=None) -> Wrenches:
    """The loads as ``xfrc_applied`` at step start times ``t`` (see the module's note), along the commanded
    motion or at the inputs ``q``, ``qd`` (a motor-driven run: its state at each step)."""
    from analytic.applications.forces import centres
    model, mech = built.model, built.mech
    t = np.atleast_1d(np.asarray(t, dtype=float))
    n = len(t)
    if q is None:
        kept = _kept(built, t)
        if kept is not None:
            return kept
        apps, state, inertias, Ft = applications(built, t)
    else:
        q = np.asarray(q, dtype=float).reshape(n, -1)
        apps, state, inertias, Ft = applications(built, t, q, np.asarray(qd, dtype=float).reshape(n, -1),
                                                 np.zeros_like(q))
    com = centres(mech, state.sol, inertias)
    xfrc = np.zeros((n, model.nbody, 6))
    ground = np.zeros((n, 3))
    for a in apps:
        fx = np.broadcast_to(a.fx, (n,))
        fy = np.broadcast_to(a.fy, (n,))
        px = np.broadcast_to(a.px, (n,))
        py = np.broadcast_to(a.py, (n,))
        m = np.broadcast_to(a.couple, (n,))
        if a.link == GROUND:
            ground[:, 0] += fx
            ground[:, 1] += fy
            ground[:, 2] += px * fy - py * fx + m
            continue
        b = model.body(a.link).id
        gx, gy = com[a.link]
        xfrc[:, b, 0] += fx
        xfrc[:, b, 1] += fy
        xfrc[:, b, 5] += (px - gx) * fy - (py - gy) * fx + m
    out = Wrenches(xfrc, ground, Ft)
    if q is None and n > 1 and np.array_equal(t, np.arange(n) * built.timestep):
        memo = getattr(built, "memo", None)
        if memo is not None and n > len(memo.get("wrenches", Wrenches(xfrc[:0], ground[:0], {})).xfrc):
            memo["wrenches"] = out             # every step start of a run: what the run's checks read again
    return out


def _kept(built, t) -> Wrenches | None:
    """The wrenches along the commanded motion at step starts ``t`` (whole multiples of the time step) from
    the ones kept for the run's every step start (:func:`wrenches`), or None."""
    kept = (getattr(built, "memo", None) or {}).get("wrenches")
    if kept is None:
        return None
    h = built.timestep
    k = np.rint(t / h).astype(int)
    if k.min() < 0 or k.max() >= len(kept.xfrc) or not np.array_equal(t, k * h):
        return None
    return Wrenches(kept.xfrc[k], kept.ground[k], {j: np.asarray(v)[k] for j, v in kept.Ft.items()})


@dataclass(frozen=True)
class DriveLoads:
    """The loads' share of each drive [N m or N] at the samples of the run's cycle (analytic.cycle.Cycle, the
    first at t = 0), as sim.model.drives sizes the servos from, and the largest total load force [N] (the
    regulariser's scale)."""

    tau: dict
    peak_force: float


SIZING_SAMPLES = 360
"""Samples per turn at which the loads' share of the drives is evaluated to size the servos (as before the
cycle was handed down: 361 per turn); interpolated to the cycle's other samples."""


def drive_loads(built, revolutions: float = 1.0, cycle=None) -> DriveLoads:
    """What the drives must add to hold the commanded motion against the loads: minus the loads' generalized
    forces (virtual work, analytic.loads.kinetostatics.generalized) at the samples of the run's ``cycle``
    (made here when None), where size_drives reads the drive forces. They are evaluated at SIZING_SAMPLES of
    the cycle's evenly spaced samples per turn (t = 0 among them: the servos' start) and interpolated to the
    rest: they only size the servos' gains (a peak) and their start, and friction's reactions cost a fixed
    point at every sample they are evaluated at."""
    from analytic.cycle import Cycle, take
    from analytic.loads.kinetostatics import full_wanted, generalized
    mech = built.mech
    cycle = cycle if cycle is not None else Cycle.of(mech, revolutions)
    dense = cycle.dense
    stride = max(1, int(np.ceil((len(dense) - 1) / (SIZING_SAMPLES * max(1.0, cycle.revolutions)))))
    rows = np.unique(np.r_[dense[::stride], dense[-1:]])
    t, q = cycle.t[rows], cycle.q[rows]
    sol = {k: np.asarray(cycle.solution[k])[rows] for k in full_wanted(mech)}
    coefficients = tuple(take(c, rows) for c in cycle.coefficients)
    apps, state, _, _ = applications(built, t, q, cycle.qd[rows], cycle.qdd[rows], sol)
    Q = generalized(mech, q, state, apps, coefficients)
    peak = np.zeros(len(t))
    size = mech.size
    for a in apps:
        if a.link != GROUND:
            peak = peak + np.hypot(a.fx, a.fy) + np.abs(np.broadcast_to(a.couple, (len(t),))) / size
    tau = {k: -np.interp(cycle.t, t, np.asarray(v, dtype=float)) for k, v in Q.items()}
    return DriveLoads(tau, float(np.max(peak)) if len(t) else 0.0)


def drive_share(built, t, inputs, solved=None) -> dict:
    """The loads' share of each drive at the given inputs (q, qd, qdd) and times: minus their generalized
    forces there (virtual work). ``solved``: the solution at those inputs and its velocity coefficients
    (analytic.cycle.solve_with_coefficients), else solved here."""
    from analytic.loads.kinetostatics import generalized
    q, qd, qdd = inputs
    sol, coefficients = solved if solved is not None else (None, None)
    apps, state, _, _ = applications(built, t, q, qd, qdd, sol=sol)
    return {k: -v for k, v in generalized(built.mech, q, state, apps, coefficients).items()}


def step_work(built, tr) -> np.ndarray:
    """The loads' work over each step of a run [J]: each step's wrench (constant over it, as applied) times
    the displacement of its body's centre of mass and its body's rotation, read from the recorded states."""
    from analytic.applications.forces import centres
    from sim.model.inertia import body_inertias
    model, mech = built.model, built.mech
    h = built.timestep
    t = np.arange(len(tr.t)) * h
    xfrc = wrenches(built, t[:-1]).xfrc
    com = centres(mech, tr.outputs, body_inertias(model, mech.links))
    work = np.zeros(len(t) - 1)
    for ln in mech.links:
        b = model.body(ln).id
        gx, gy = (np.asarray(v) for v in com[ln])
        turn = np.diff(np.unwrap(np.arctan2(np.asarray(tr.outputs["sin" + ln]), np.asarray(tr.outputs["cos" + ln]))))
        work += xfrc[:, b, 0] * np.diff(gx) + xfrc[:, b, 1] * np.diff(gy) + xfrc[:, b, 5] * turn
    return work


def add_native(context, bodies, loadset, sol) -> tuple:
    """For a motor-driven run (sim.run.motor), where the motion is not known in advance: the loads whose MuJoCo
    form (:meth:`analytic.loads.base.Load.mujoco`) is a tendon -- linear springs and dampers between two ends
    as spatial tendons (stiffness, spring length, damping) between sites at the ends, torsion springs and
    dampers at a pin as fixed tendons over the hinges that turn the two links (their relative angle) -- so
    MuJoCo's integrator evaluates them within its steps from its own state. Their forces then act in joint
    space (``qfrc_passive``), not in ``cfrc_ext``: only the motor runs, which read no joint forces, use this.
    Returns the names of the loads so carried (they are left out of the wrenches)."""
    from analytic.loads.base import LineTendon, PinTendon
    from sim.model.frames import local
    spec, mech = context.spec, context.mech
    native = []

    def site(e, tag):
        link = e.link
        if e.point is not None:
            x, y = context.points[e.point] if e.point in context.points else mech.geometry.ground[e.point]
            lx, ly = local(context.frames[link], x, y) if link != GROUND else (x, y)
        else:
            lx, ly = e.u, e.v
        return bodies[link].add_site(name=f"load_{tag}", pos=[lx, ly, 0], size=[1e-3, 1e-3, 1e-3], group=4)

    for ld in loadset.loads:
        form = ld.mujoco()
        if isinstance(form, LineTendon):
            t = spec.add_tendon(name=f"load_{ld.name}")
            s1, s2 = site(form.ends[0], f"{ld.name}_1"), site(form.ends[1], f"{ld.name}_2")
            t.wrap_site(s1.name)
            t.wrap_site(s2.name)
            if form.stiffness:
                t.stiffness = [form.stiffness, 0.0, 0.0]
                t.springlength = [form.length, form.length]
            if form.damping:
                t.damping = [form.damping, 0.0, 0.0]
            native.append(ld.name)
        elif isinstance(form, PinTendon):
            l0, l1 = form.links
            terms = dict(context.angle_terms(l1))
            for j, c in context.angle_terms(l0).items():
                terms[j] = terms.get(j, 0.0) - c
            t = spec.add_tendon(name=f"load_{ld.name}")
            for j, c in terms.items():
                if c != 0.0:
                    t.wrap_joint(j, c)
            if form.stiffness:
                def phi(ln):
                    return 0.0 if ln == GROUND else float(np.arctan2(sol["sin" + ln][0], sol["cos" + ln][0]))
                d = phi(l1) - phi(l0) - form.free_angle
                theta0 = float(np.pi - np.mod(np.pi - d, 2 * np.pi))
                t.stiffness = [form.stiffness, 0.0, 0.0]
                t.springlength = [-theta0, -theta0]
            if form.damping:
                t.damping = [form.damping, 0.0, 0.0]
            native.append(ld.name)
    return tuple(native)


def not_in_xml(ld) -> str | None:
    """Why MJCF cannot hold the load ``ld`` statically (an exported model, ``linkage export --mjcf``), or None
    where it can: its kind's MuJoCo form (:meth:`analytic.loads.base.Load.mujoco`), a tendon
    (:func:`add_native`) or a constant-force actuator (:func:`add_static`), else its kind's sentence."""
    form = ld.mujoco()
    return form if isinstance(form, str) else None


def add_static(context, bodies, loadset, skip=()) -> tuple:
    """For an exported model: every constant force (its direction fixed in the world, or turning with its
    link) and constant torque as a constant-force actuator (gain 0, affine bias = the value) with a site
    transmission: the force along the actuator's gear, in the world frame (refsite ``origin``) or the site's
    (the link's frame), at the load's point; a torque as the gear's z moment. Returns the names so carried."""
    import mujoco
    from analytic.loads.base import ConstantActuator
    from sim.model.frames import local
    spec, mech = context.spec, context.mech
    done = []
    for ld in loadset.loads:
        form = ld.mujoco()
        if ld.name in skip or not isinstance(form, ConstantActuator):
            continue
        e = form.end
        if e is not None:
            if e.link == GROUND:
                continue                            # a load on the frame moves nothing
            if e.point is not None:
                x, y = context.points[e.point] if e.point in context.points else mech.geometry.ground[e.point]
                lx, ly = local(context.frames[e.link], x, y)
            else:
                lx, ly = e.u, e.v
            body, gear = e.link, [form.direction[0], form.direction[1], 0.0, 0.0, 0.0, 0.0]
            world = form.world
        else:
            lx, ly, body, gear, world = 0.0, 0.0, form.link, [0.0, 0.0, 0.0, 0.0, 0.0, 1.0], True
        site = bodies[body].add_site(name=f"load_{ld.name}", pos=[lx, ly, 0], size=[1e-3] * 3, group=4)
        act = spec.add_actuator(name=f"load_{ld.name}", target=site.name, trntype=mujoco.mjtTrn.mjTRN_SITE)
        if world:
            act.refsite = "origin"
        act.gear = gear
        act.gainprm[0] = 0.0
        act.biastype = mujoco.mjtBias.mjBIAS_AFFINE
        act.biasprm[:3] = [form.value, 0.0, 0.0]
        act.ctrllimited = False
        done.append(ld.name)
    return tuple(done)
