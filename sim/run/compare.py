"""Cross-validation: the analytic solution evaluated at the *simulated* inputs against every output the
MuJoCo model measures, the drives' tracking of their commanded motion, the loops' closure, the drive
forces against inverse dynamics and the work done against the energy change.

Tolerances are relative to the mechanism's size L (its longest link) and to each output's scale: its
peak over the run, but never less than the motion's own scale (L Omega for a velocity, L Omega^2 for an
acceleration, Omega the fastest input speed), so an output that happens to stay near zero (a perfect
parallelogram's coupler) is not judged against zero. Each constant says which error it bounds.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from sim.model import motion_scale
from sim.model.timestep import reference_rate
from sim.run import forces as joint_forces
from sim.run.simulate import Ends, Trajectory, controls, energies, replay
from sim.output.units import output_kind

ANGLE_TOL = 1e-6
"""[rad] RK4's truncation error at 0.025 rad per step over a run plus the loop drift it carries (1000 random
designs, benchmarks/trust.py: median 2e-8, worst 3e-7)."""
POSITION_TOL = 1e-6
"""[of the size L] the same for points and slides, measured against the mechanism's size."""
VELOCITY_TOL = 1e-5
"""[of the output's scale] the loops' velocity stabilisation and the drives' servo ripple (median 6e-8,
worst 3e-6)."""
ACCELERATION_TOL = 1e-3
"""[of the output's scale] the constraint solver's residual and the regulariser's leak (median 1e-7,
worst 5e-6)."""
LOOP_TOL = 1e-6
"""[of the size L] the loops' position drift under the stiff constraint's drift correction (median 7e-9,
worst 2.4e-8)."""
DRIVE_TOL = 1e-4
"""[rad, or of L for a slider] commanded minus simulated input: the servo's deflection under the peak
reaction (sized to 1e-6, sim.model.DRIVE_ERROR_BUDGET) plus its transient at start."""
TORQUE_TOL = 5e-3
"""[of the peak drive force, at least TORQUE_FLOOR of the inertial scale] the force the servo delivers to its
link at each step's start (its actuator force less the rotor's armature x qacc, sim.run.simulate.delivered)
against inverse dynamics without the armature: the constraint solver's residual (~1e-8 of the constraint
force) is all that separates them. Neither side carries the rotor, so neither the error nor the peak this
is a share of does (with it, an accelerating four-bar's peak read 144 N m for 0.38 N m)."""
TORQUE_FLOOR = 1e-3
"""[of the inertial drive-force scale sum_k (m_k L^2 + I_k) Omega^2 (a slider's: over L), Omega the run's speed
or the reference speed, sim.model.timestep.reference_rate, whichever is faster] the least peak a drive force is
judged against: a force that stays at rounding level (a parallelogram's at constant speed:
its kinetic energy is constant) is not judged against its own noise. The library's peaks are 0.018-0.70
of that scale, so the floor never binds for a force that does work."""
WORK_TOL = 1e-3
"""[of the work scale (work_scale: the kinetic-energy or the loads' work swing, see WORK_FLOOR), per
revolution] 4-point Gauss quadrature of the drive power over each step (exact for the interpolated motion) against MuJoCo's energy; what is left is RK4's energy error."""
WORK_FLOOR = 1e-5
"""[of the peak kinetic energy] the least work scale: the work balance is measured against the
kinetic-energy swing, or against this share of the peak kinetic energy where the swing is smaller (a lone
crank at constant speed swings by 3e-14 of its peak: the rounding of the energy sums, ~ steps x 1e-16 of
it, would be all there is to measure). Never zero: a driven input moves, so its kinetic energy is > 0."""


def tolerance(mech, name: str, peak: float, omega: float, force_scale: float = 0.0) -> float:
    """The tolerance of output ``name`` whose analytic peak is ``peak``, with ``omega`` the motion's speed
    scale and ``force_scale`` a drive force's inertial scale (see TORQUE_FLOOR)."""
    L = mech.size
    _, kind = output_kind(mech, name)
    if kind == "angle":
        return ANGLE_TOL
    if kind == "position":
        return POSITION_TOL * L
    if kind == "ang_velocity":
        return VELOCITY_TOL * max(peak, omega)
    if kind == "velocity":
        return VELOCITY_TOL * max(peak, L * omega)
    if kind == "ang_acceleration":
        return ACCELERATION_TOL * max(peak, omega ** 2)
    if kind == "acceleration":
        return ACCELERATION_TOL * max(peak, L * omega ** 2)
    return TORQUE_TOL * max(peak, TORQUE_FLOOR * force_scale)


def force_scale(built, name: str, omega: float) -> float:
    """The inertial scale of drive force ``name`` (``tauL``): sum over the links of (m L^2 + I) Omega^2 for
    a crank (N m), over L for a slider (N), from the compiled model's masses; Omega at least the
    reference speed (sim.model.timestep.reference_rate)."""
    from sim.model import body_inertias
    mech = built.mech
    L = mech.size
    inertia = sum(b.m * L * L + b.I for b in body_inertias(built.model, mech.links).values())
    slider = any(not i.angular and name == "tau" + i.link for i in mech.inputs)   # a force, not a torque
    return inertia * max(omega, reference_rate(mech)) ** 2 / (L if slider else 1.0)


@dataclass(frozen=True)
class Comparison:
    """Per-output error statistics and the run's verdict."""

    trajectory: Trajectory
    analytic: object
    errors: dict[str, dict]
    forces: object = field(default=None, kw_only=True)
    """The joint forces against MuJoCo's (sim.run.forces.Agreement), None where statics cannot give them."""
    drive_error: float
    max_loop_violation: float
    torques: dict[str, np.ndarray]
    work_balance: float
    passed: bool
    revolutions: float
    change_points: tuple = ()
    """The first input's values (rad or m) where a dyad passes a change point on its declared branch."""
    work_judged: bool = field(default=True, kw_only=True)
    """Whether the work balance is judged against WORK_TOL (not with a cam: :func:`compare`)."""

    def as_dict(self, built=None, display=None) -> dict:
        """The JSON record: SI unless ``display`` says otherwise (its ``units`` table says which)."""
        from analytic.quantities import SI
        display = display or SI
        tr = self.trajectory
        mech = built.mech if built is not None else None
        out = {"mechanism": tr.name}
        if mech is not None:
            from analytic.quantities import parameter_units, parameters_in
            out["parameters"] = parameters_in(mech, display)
            out["units"] = {"file": mech.units, "length": display.unit("length"), "angle": display.unit("angle"),
                            "parameters": parameter_units(mech, display),
                            "outputs": {k: e["unit"] for k, e in errors_in(self.errors, display).items()}}
            loads = built.loads
            out["loads"] = {"gravity": list(loads.gravity) if loads.gravity else None, "force": list(loads.force),
                            "slow_stroke_only": loads.slow_stroke_only,
                            "inertias": {k: vars(v) for k, v in (loads.inertias or {}).items()}}
            out["input_range"] = list(mech.rock) if mech.rock else None
        out.update({"timestep": tr.timestep, "integrator": tr.integrator, "revolutions": self.revolutions,
                    "steps": tr.steps, "cpu_seconds": tr.cpu_seconds, "errors": errors_in(self.errors, display),
                    "drive_error": self.drive_error, "drive_tol": DRIVE_TOL,
                    "max_loop_violation": display.convert("length", self.max_loop_violation),
                    "loop_tol": display.convert("length", LOOP_TOL * (mech.size if mech is not None else 1.0)),
                    "work_balance": self.work_balance, "work_tol": WORK_TOL if self.work_judged else None,
                    "passed": self.passed})
        if self.forces is not None:
            out["forces"] = self.forces.as_dict()
        return out


def simulated_inputs(tr: Trajectory, mech):
    cols = [np.column_stack([tr.inputs[getattr(i, a)] for i in mech.inputs]) for a in ("q", "qd", "qdd")]
    return tuple(cols)


def analytic_at(tr: Trajectory, mech):
    """The analytic solution at the simulated inputs."""
    return mech.solve(*simulated_inputs(tr, mech))


def analytic_solved(tr: Trajectory, mech):
    """The analytic solution at the simulated inputs and each input's velocity coefficients there, in one
    exact solve at those inputs (:func:`analytic.cycle.solve_with_coefficients`)."""
    from analytic.cycle import solve_with_coefficients
    return solve_with_coefficients(mech, *simulated_inputs(tr, mech))


def analytic_forces(tr: Trajectory, built, mech=None, solved=None) -> dict[str, np.ndarray]:
    """Inverse-dynamics drive forces at the simulated state, with the compiled model's inertias, gravity and
    the load as applied, and none of the simulation's own constants (the drives' rotor inertia, gains): the
    force that reaches each input's link, as the simulation reports it (sim.run.simulate.delivered), so that
    nothing the two sides share can hide a difference; ``solved``: :func:`analytic_solved`'s (solved here
    when None)."""
    from analytic.applications import torque
    from sim.model import body_inertias
    model = built.model
    mech = mech or built.mech
    gear = tuple(model.actuator("load").gear[:2])
    forces = torque.drive_forces(mech, *simulated_inputs(tr, mech), body_inertias(model, mech.links), None,
                                 tuple(model.opt.gravity[:2]), gear, tr.load, *(solved or (None, None)))
    if getattr(built, "loadset", None) is not None:       # the file's loads: minus their generalized forces
        from sim.model.loads import drive_share
        share = drive_share(built, np.asarray(tr.t), simulated_inputs(tr, mech), solved)
        forces = {k: v + share[k] for k, v in forces.items()}
    return {f"tau{k}": v for k, v in forces.items()}


def drive_error(tr: Trajectory, mech) -> float:
    """Largest |simulated - commanded| input [rad, or of the size for a slider] over the run."""
    worst = 0.0
    for i in mech.inputs:
        e = np.max(np.abs(tr.inputs[i.q] - tr.commanded[i.q]))
        worst = max(worst, float(e) / i.spec.rate_scale(mech.size))
    return worst


def work_balance(tr: Trajectory, built, ends: EndEvaluations | None = None) -> float:
    """max over the run of |work done on the mechanism - change of its energy|, as a fraction of the
    work scale (the kinetic-energy swing, at least WORK_FLOOR of the peak kinetic energy), per revolution.

    Each drive's force over a step is kp (a - q) - kv qdot with the activation a linear in time (its
    rate, the control, is constant over the step) and qdot the cubic through the step's end speeds and
    accelerations (q its integral): 4-point Gauss quadrature of force x qdot is exact for that motion.
    The load's constant force times the output point's displacement is exact. The energy is MuJoCo's
    kinetic + potential energy at each recorded state. ``ends``: :func:`end_evaluations` of the run (made here
    when None), which a replay of the run's states may have carried already."""
    model, mech = built.model, built.mech
    h = tr.timestep
    nodes, weights = np.polynomial.legendre.leggauss(4)
    u = 0.5 * (nodes + 1.0)
    H = np.array([2 * u ** 3 - 3 * u ** 2 + 1, u ** 3 - 2 * u ** 2 + u, -2 * u ** 3 + 3 * u ** 2, u ** 3 - u ** 2])
    # integrals of the Hermite basis from 0 to u (times h)
    Hi = np.array([u - u ** 3 + u ** 4 / 2, u ** 2 / 2 - 2 * u ** 3 / 3 + u ** 4 / 4, u ** 3 - u ** 4 / 2,
                   u ** 4 / 4 - u ** 3 / 3])
    evaluated = ends if ends is not None else end_evaluations(tr, built)
    ctrl = evaluated.ctrl
    ends, both = evaluated.answer()
    work = np.zeros(len(tr.t) - 1)
    for k, d in enumerate(built.drives):
        jid = model.joint(d.joint).id
        q = tr.qpos[:, model.jnt_qposadr[jid]]
        w = tr.qvel[:, model.jnt_dofadr[jid]]
        a = tr.inputs[d.input.qdd]
        a1 = a[1:].copy()
        for step, acc in ends.items():
            a1[step] = acc[k]
        act = tr.act[:, model.actuator(d.actuator).actadr[0]]
        c = ctrl[:-1, model.actuator(d.actuator).id]
        coef = np.column_stack([w[:-1], h * a[:-1], w[1:], h * a1])           # Hermite data per step
        ws = coef @ H                                                         # qdot at the nodes
        qs = q[:-1, None] + h * (coef @ Hi)
        acts = act[:-1, None] + c[:, None] * (u * h)[None]
        force = d.kp * (acts - qs) - d.kv * ws
        work += 0.5 * h * (force * ws) @ weights
    gear = model.actuator("load").gear[:2]
    if np.any(gear):
        p = mech.output_point
        work += tr.load[:-1] * (gear[0] * np.diff(tr.outputs["x" + p]) + gear[1] * np.diff(tr.outputs["y" + p]))
    loads = np.zeros(len(tr.t) - 1)
    if getattr(built, "loadset", None) is not None:       # the file's loads, constant over each step
        from sim.model.loads import step_work
        loads = step_work(built, tr)
        work += loads
    total = np.concatenate([[0.0], np.cumsum(work)])
    kinetic, potential = both if both is not None else energies(built, tr)
    energy = kinetic + potential
    scale = work_scale(kinetic, np.concatenate([[0.0], np.cumsum(loads)]))
    revs = max(1.0, tr.t[-1] / mech.duration(1.0))
    return float(np.max(np.abs(total - (energy - energy[0]))) / scale / revs)


def work_scale(kinetic: np.ndarray, loads=None) -> float:
    """[J] What the work balance is measured against: the energy the run exchanges -- the kinetic-energy
    swing over the run or the swing of the file's loads' accumulated work ``loads``, whichever is larger
    (a spring that stores and returns more than the links' kinetic energy swings: its work is measured
    to the same share of its own size; a spring-only four-bar read 1.1e-3 of its 0.11 J kinetic swing, 5e-5
    of the spring's 2.3 J, issue 41) -- or WORK_FLOOR of the kinetic energy's peak where both are smaller
    (never zero while anything moves)."""
    kinetic = np.asarray(kinetic, dtype=float)
    swing = float(np.ptp(np.asarray(loads, dtype=float))) if loads is not None and len(loads) else 0.0
    return max(float(np.ptp(kinetic)), swing, WORK_FLOOR * float(np.max(np.abs(kinetic))), np.finfo(float).tiny)


@dataclass(frozen=True)
class EndEvaluations:
    """What the work balance needs MuJoCo to evaluate at the steps' ends (:func:`end_evaluations`): the controls
    at every step, the request a replay of the run's states can carry (:class:`sim.run.simulate.Ends`: the
    forces check's, :func:`compare`), and ``answer()``: :func:`_end_accelerations`' answer, the request run
    alone first where no replay carried it."""

    ctrl: np.ndarray
    request: Ends
    answer: Callable


def end_evaluations(tr: Trajectory, built) -> EndEvaluations:
    """The work balance's end-of-step evaluations of run ``tr``: at the steps where the load switched, at every
    step with the file's loads (whose wrenches change at every step), the energies then read there too."""
    h = tr.timestep
    ctrl = controls(built, np.arange(len(tr.t)) * h)
    switch_changes = np.flatnonzero(np.abs(np.diff(tr.load)) > 0)
    xfrc = None
    if getattr(built, "loadset", None) is not None:       # the loads change at every step (sim.model.loads)
        from sim.model.loads import wrenches
        xfrc = wrenches(built, np.arange(len(tr.t)) * h).xfrc
        switch_changes = np.arange(len(tr.t) - 1)
    every = len(switch_changes) == len(tr.t) - 1          # then the energies come from the same evaluations
    return EndEvaluations(ctrl, *_end_request(built, tr, switch_changes, ctrl, xfrc, energy=every))


def _end_request(built, tr: Trajectory, steps, ctrl, xfrc=None, energy: bool = False) -> tuple[Ends, Callable]:
    """:func:`_end_accelerations`' evaluations as a request a replay carries (sim.run.simulate.Ends) and the
    function that gives their answer (running the request alone where no replay carried it)."""
    import mujoco
    model = built.model
    steps = np.asarray(steps, dtype=int)
    S = mujoco.mjtState
    sig, parts = S.mjSTATE_CTRL, [ctrl[steps]]
    if xfrc is not None:
        sig |= S.mjSTATE_XFRC_APPLIED
        parts.append(xfrc[steps].reshape(len(steps), 6 * model.nbody))
    qacc, energy_at = np.empty((len(steps), model.nv)), np.empty((len(steps), 2))
    seen = np.zeros(len(steps), dtype=bool)

    def read(n, data):
        qacc[n] = data.qacc
        energy_at[n] = data.energy                         # (potential, kinetic); zeros unless ``energy``
        seen[n] = True
    request = Ends(steps, np.concatenate(parts, axis=1), int(sig), read, energy)

    def answer():
        if not seen.all():                                 # no replay carried them: evaluated alone
            replay(built, tr, (), None, request)
        dofs = [model.jnt_dofadr[model.joint(d.joint).id] for d in built.drives]
        out = dict(zip(steps.tolist(), qacc[:, dofs].tolist()))
        if not energy:
            return out, None
        energies = np.empty((len(tr.t), 2))
        energies[0] = _energy(model, tr.qpos[0], tr.qvel[0])
        energies[steps + 1] = energy_at
        return out, (energies[:, 1], energies[:, 0])
    return request, answer


def _energy(model, qpos, qvel) -> np.ndarray:
    """MuJoCo's (potential, kinetic) energy [J] of one state (sim.run.simulate.energies' evaluation)."""
    import mujoco
    data = mujoco.MjData(model)
    flags, off = model.opt.enableflags, model.opt.disableflags
    model.opt.enableflags = flags | mujoco.mjtEnableBit.mjENBL_ENERGY
    model.opt.disableflags = off | mujoco.mjtDisableBit.mjDSBL_SENSOR
    try:
        data.qpos[:], data.qvel[:] = qpos, qvel
        mujoco.mj_forward(model, data)
        return data.energy.copy()
    finally:
        model.opt.enableflags, model.opt.disableflags = flags, off


def _end_accelerations(built, tr: Trajectory, steps, ctrl, xfrc=None, energy: bool = False):
    """Each drive's joint acceleration at the end of each step in ``steps`` under that step's controls (and
    body wrenches ``xfrc``, the file's loads), needed where the load switched between steps: ({step: [each
    drive's]}, None). ``energy`` (``steps`` is every step): MuJoCo's kinetic and potential energy at every
    recorded state too, as :func:`sim.run.simulate.energies` gives them, read from the same evaluations (the
    energy depends on the state alone, not on the controls or the wrenches; a cam's contacts make each
    evaluation costly): ({...}, (kinetic, potential)). Evaluated alone here; :func:`compare` has the forces
    check's replay carry them (:func:`end_evaluations`)."""
    return _end_request(built, tr, steps, ctrl, xfrc, energy)[1]()


def compare(tr: Trajectory, built, revolutions: float = 1.0) -> Comparison:
    """Every reported output, the drive forces, drive tracking, loops and work balance of run ``tr``."""
    mech = built.mech
    solved = analytic_solved(tr, mech)                   # the one exact solve at the simulated inputs
    ref = solved[0]
    omega = motion_scale(mech)
    taus = analytic_forces(tr, built, mech, solved)
    pairs = [(n, np.asarray(ref[n]), tr.outputs[n]) for n in mech.outputs]
    pairs += [(n, taus[n], tr.forces[n]) for n in taus]
    away = joint_forces.away_from_change_points(mech, tr, np.arange(len(tr.t)))   # drives: as the joint forces
    from sim.run import cams
    floors = cams.tolerances(built)                      # a cam's follower rides a compliant contact
    errors, ok = {}, True
    for name, a, s in pairs:
        if name in taus and len(away) < len(tr.t):
            a, s = np.asarray(a)[away], np.asarray(s)[away]
        diff = s - a
        unit, kind = output_kind(mech, name)
        if floors is not None and kind == "force":
            diff = cams.impulse_mean(diff)               # a cam's contact force: judged by its impulses
        if kind == "angle":
            diff = np.pi - np.mod(np.pi - diff, 2 * np.pi)
        peak = float(np.nanmax(np.abs(a)))
        tol = tolerance(mech, name, peak, omega, force_scale(built, name, omega) if kind == "force" else 0.0)
        if floors is not None:
            tol = max(tol, floors.get(kind, floors["force"]))
        e_max, e_rms = float(np.max(np.abs(diff))), float(np.sqrt(np.mean(diff ** 2)))
        passed = bool(e_max <= tol)
        ok &= passed
        errors[name] = {"max": e_max, "rms": e_rms, "peak": peak, "tol": tol, "unit": unit, "passed": passed,
                        "role": mech.table[name].role}
    drive = drive_error(tr, mech)
    viol = float(np.max(tr.loop_violation))
    ends = end_evaluations(tr, built)                    # carried by the forces check's replay where it runs
    forces = joint_forces.check(built, tr, solved=solved, ends=ends.request)
    balance = work_balance(tr, built, ends)
    # a cam's contact is critically damped (sim.model.cam_contact): its chatter dissipates energy the analytic
    # model has no term for (cam_roller: 2.6 % of the spring's work swing a turn), so the balance is reported,
    # not judged, with a cam
    judged = floors is None
    ok &= drive <= DRIVE_TOL and viol <= LOOP_TOL * mech.size and (balance <= WORK_TOL or not judged)
    changes = tuple(sorted(f for e in mech.solving_geometry.elements if e.get("flips") for f in e["flips"]["at"]))
    ok &= forces is None or forces.passed
    return Comparison(tr, ref, errors, drive, viol, taus, balance, bool(ok), revolutions, changes, forces=forces,
                      work_judged=judged)


def errors_in(errors: dict, display) -> dict:
    """Per-output error records (SI, each naming its unit) in ``display`` units: max, rms, peak and
    tolerance converted by the output's quantity, ``unit`` relabelled."""
    from analytic.quantities import SI_UNIT
    by_unit = {u: q for q, u in SI_UNIT.items()}
    out = {}
    for name, e in errors.items():
        q = by_unit.get(e["unit"], "")
        out[name] = {**e, **{k: display.convert(q, e[k]) for k in ("max", "rms", "peak", "tol")},
                     "unit": display.unit(q) if q else e["unit"]}
    return out


FIXED = 1e-12
"""[of the size L, or rad] an output whose analytic value moves less than this over the run is fixed (a
ground point, a parallel guide's angle): the table folds such rows into one line."""


def table(c: Comparison, size: float, display=None, output_point: str | None = None) -> str:
    """A readable comparison table in ``display`` units (analytic.quantities.Display; None: SI), led by
    what matters: the output point's coordinates, the other outputs that move, then the drive forces;
    outputs that stay fixed over the run (ground points) folded into one line unless one of them fails."""
    from analytic.quantities import SI
    display = display or SI
    tr = c.trajectory
    errors = errors_in(c.errors, display)
    moving, fixed = [], []
    for name, e in errors.items():
        ref = np.asarray(c.analytic[name]) if c.errors[name]["role"] != "drive" else None
        scale = 1.0 if c.errors[name]["unit"].startswith("rad") else size
        still = ref is not None and np.ptp(np.broadcast_to(ref, np.shape(tr.t))) <= FIXED * scale
        (fixed if still and e["passed"] else moving).append(name)
    lead = {f"{k}{output_point}" for k in ("x", "y", "vx", "vy", "ax", "ay")} if output_point else set()
    moving.sort(key=lambda n: (c.errors[n]["role"] == "drive", n not in lead))     # stable: file order within
    width = max([8] + [len(n) for n in moving])
    lines = [f"{tr.name}: {tr.steps} steps of {tr.timestep:.3g} s ({tr.integrator}), "
             f"{tr.cpu_seconds * 1e3:.1f} ms CPU",
             f"  {'output':<{width}s} {'max error':>11s} {'rms error':>11s} {'peak':>11s} {'tolerance':>11s}  unit"]
    for name in moving:
        e = errors[name]
        flag = "" if e["passed"] else "  FAIL"
        lines.append(f"  {name:<{width}s} {e['max']:11.3e} {e['rms']:11.3e} {e['peak']:11.4g} {e['tol']:11.1e}  "
                     f"{e['unit']}{flag}")
    if fixed:
        # a design that stands still (a law that only dwells) has outputs of tolerance 0 and error 0
        worst = max(c.errors[n]["max"] / c.errors[n]["tol"] if c.errors[n]["tol"] > 0 else 0.0 for n in fixed)
        shown = " ".join(fixed[:8]) + (" ..." if len(fixed) > 8 else "")
        lines.append(f"  {len(fixed)} fixed outputs ({shown}): within tolerance, worst {worst:.1e} of it")
    length = display.unit("length")
    lines.append(f"  drive error {c.drive_error:.3e} (tol {DRIVE_TOL:.0e}); loop violation max "
                 f"{display.convert('length', c.max_loop_violation):.3e} {length} "
                 f"(tol {display.convert('length', LOOP_TOL * size):.1e})")
    verdict = (f"tol {WORK_TOL:.0e}" if c.work_judged else
               "reported, not judged: a cam's contact damping dissipates energy the analytic model has no term for")
    lines.append(f"  work balance {c.work_balance:.3e} of the kinetic-energy or the loads' work swing (at least {WORK_FLOOR:.0e} of its "
                 f"peak) per revolution ({verdict})")
    if c.change_points:
        first = next(iter(tr.inputs))
        crank = first.startswith("phi")
        where = ", ".join(f"{x:.2f}deg" if crank else f"{x:.6g} m"
                          for x in sorted(np.degrees(x) % 360 if crank else x for x in c.change_points))
        lines.append(f"  passes change points at {first}={where} on its declared branch (change = 1: its form kept)")
        if not c.passed:
            lines.append("  at a change point the dyad's links align and the loops' equations lose rank: MuJoCo's "
                         "constraints hold it only approximately there (measured: one turn of a parallelogram "
                         "passes; more turns, or a general change-point linkage, ring far past the tolerances "
                         "after each change point)")
    if c.forces is not None:
        lines.append(f"  {c.forces.line()}{'' if c.forces.passed else '  FAIL'}")
    lines.append(f"  {'PASSED' if c.passed else 'FAILED'}")
    return "\n".join(lines)
