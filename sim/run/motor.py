"""MuJoCo's answer under a motor: the generated model (:func:`sim.model.build`) with its input's position
servo turned into a motor, run from the same initial state as the reduced equation of motion
(:mod:`analytic.applications.motor`), and the comparison of the two.

The drive actuator keeps its compiled form (an integrator activation times a fixed gain, plus an affine
bias) with the activation held at 1 and no control: force = gain + bias1 q + bias2 qdot, so with
gain = s a and bias2 = b it is the motor's torque s (a + b w) along the joint, w = s qdot the speed in
the input's turning direction s, evaluated by RK4 at every stage. A torque-speed table is one such line
per piece, switched at each step's start when the speed crosses a row. The flywheel is the joint's
armature. The loads are the model's (gravity, the load actuator on the output point); a cutting force
switches where the input's phase crosses the window's ends, and the step that would cross such an angle
(or the start or end of the last revolution) is shortened to land on it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import mujoco
import numpy as np

from analytic import ParameterError
from analytic.applications import motor as amotor
from analytic.cycle import Cycle
from sim import model as M
from sim.model.armature import set_armature

SPEED_TOL = 1e-4
"""[relative] mean speed over the last revolution, MuJoCo against the reduced equation: the issue's bound;
RK4 at STEP_ANGLE per step and the loops' regulariser leak are far below it."""
CS_TOL = 1e-3
"""[absolute] coefficient of fluctuation: the issue's bound; the extrema of the stepped speed are refined
by a parabola through the three samples around them (error O(h^3))."""
CURVE_TOL = 1e-3
"""[of the mean speed] speed against angle over the last revolution, each step's speed against the
reduced equation's at the same angle: RK4's and the constraint solver's errors (60 random designs,
benchmarks/dynamics.py seed 0: median ~1e-7, worst 1.4e-4, a Whitworth design near its singular pose)."""
TIME_TOL = 1e-3
"""[of the mean speed] speed against time over the run: adds the phase the two drift apart by (a small
speed error integrated over the run shifts the cycle in time)."""
ENERGY_TOL = 1e-4
"""[relative] kinetic energy of the coasting linkage over 100 revolutions in MuJoCo: RK4's energy error
and the loops' drift correction at STEP_ANGLE per step (benchmarks/dynamics.py --energy 5: median
1.2e-5, worst 4.4e-5; the default four-bar 5e-7)."""
MOTOR_STEP = 0.5
"""The step is also at most this fraction of the motor's own time constant J_min / |dtau/dw| (a stiff motor
on a light linkage): RK4 is stable to 2.8 and its error on that decaying mode is ~(0.5)^5 / 120 = 3e-4 of
the mode per step, which the mode itself damps out; benchmarks/dynamics.py measures the result."""


@dataclass(frozen=True)
class MotorRun:
    """MuJoCo's run: time [s], input angle [rad], speed dq/dt [rad/s], motor torque along q [N m] at each
    recorded state, the mean speed and Cs over the last revolution, the start-up time, the largest loop
    violation [m] and the time step [s]."""

    t: np.ndarray
    phi: np.ndarray
    omega: np.ndarray
    torque: np.ndarray
    mean_speed: float
    fluctuation: float
    startup_time: float
    loop_violation: float
    timestep: float
    qpos: np.ndarray
    qvel: np.ndarray


def timestep_for(mech, red, motor, w_max: float, cycle=None) -> float:
    """The step for a run reaching speed ``w_max``: sim.model's choice for the prescribed motion scaled
    from its speed to w_max (every rate of the motion scales with the input speed), and at most
    MOTOR_STEP of the motor's time constant. ``cycle``: the prescribed motion's (made here when None)."""
    rate = abs(mech.inputs[0].motion.rate) or 1.0
    h = M.choose_timestep(mech, 1.0, cycle) * rate / max(w_max, 1e-9)
    _, b = motor.affine(np.array([0.0, w_max]))
    slope = float(np.max(np.abs(b)))
    if slope > 0:
        J_min = float(red.J(np.linspace(0, 2 * math.pi, 721)).min())
        h = min(h, MOTOR_STEP * J_min / slope)
    if h < M.MIN_TIMESTEP:
        raise ParameterError(f"the {mech.name} under this motor needs a time step of {h:.2g} s < "
                             f"{M.MIN_TIMESTEP:g} s to simulate; lower the motor's speed")
    return min(h, M.MAX_TIMESTEP)


def build(mech, loads, red, motor, w_max: float, settings=M.Settings(), cycle=None):
    """The model of ``mech`` with ``loads``, its drive a motor (set per step by :func:`simulate`) and the
    flywheel ``red.flywheel`` as the input joint's armature. ``cycle``: the prescribed motion over one turn
    (:class:`analytic.cycle.Cycle`; made here when None), for the time step and the model builder."""
    if cycle is None:
        cycle = Cycle.of(mech, 1.0)
    if settings.timestep is None:
        settings = replace(settings, timestep=timestep_for(mech, red, motor, w_max, cycle))
    built = M.build(mech, settings, loads, native=True, cycle=cycle)
    d = built.drives[0]
    set_armature(built.model, d.joint, red.flywheel)
    return built


def _set_motor(model, d, motor, s, w):
    a, b = motor.affine(w)
    act = model.actuator(d.actuator)
    act.gainprm[0] = s * float(a)
    act.biasprm[:3] = [0.0, 0.0, float(b)]


def simulate(built, red, motor, revolutions: float, start_speed: float = 0.0) -> MotorRun:
    """Run the motor-driven model from the reduced equation's initial state (advance 0, speed
    ``start_speed``) for ``revolutions`` turns of the input."""
    model, mech = built.model, built.mech
    d = built.drives[0]
    s = red.direction
    jid = model.joint(d.joint).id
    qadr, vadr = model.jnt_qposadr[jid], model.jnt_dofadr[jid]
    aid = model.actuator(d.actuator).id
    load_id = model.actuator("load").id
    rate = mech.inputs[0].motion.rate or 1.0
    data = mujoco.MjData(model)
    data.qpos[:] = built.qpos0
    data.qvel[:] = built.qvel0 * (s * start_speed / rate)
    data.act[:] = 0.0
    data.act[model.actuator(d.actuator).actadr[0]] = 1.0
    data.ctrl[:] = 0.0
    h = built.timestep
    two_pi = 2 * math.pi
    end = two_pi * revolutions
    last0 = end - two_pi
    sw = red.switches()
    marks = [last0, end] + [k * two_pi + a for k in range(int(math.ceil(revolutions)) + 1) for a in sw]
    marks = np.unique([m for m in marks if 0 < m <= end])
    q0 = d.q_offset
    u_of = lambda: s * (data.qpos[qadr] + q0 - red.q0)                      # noqa: E731
    T, U, W, TAU, QP, QV = [], [], [], [], [], []
    viol = 0.0
    mi = 0
    mark_t = {}
    limit = 20_000_000                       # as sim.run.simulate.MAX_STEPS
    from sim.model.loads import wrenches
    held = built.loadset is not None and any(ld.name not in built.native for ld in built.loadset.loads)
    kinks = np.asarray(getattr(motor, "omega", ()), dtype=float)[1:-1]      # a table motor's inner rows [rad/s]
    steps = 0
    while mi < len(marks):
        u, w = u_of(), s * data.qvel[vadr]
        _set_motor(model, d, motor, s, w)
        data.ctrl[load_id] = float(red.on(np.array([u + 1e-12]))[0])
        mujoco.mj_forward(model, data)
        T.append(data.time)
        U.append(u)
        W.append(w)
        TAU.append(s * data.actuator_force[aid])
        QP.append(data.qpos.copy())
        QV.append(data.qvel.copy())
        for lp in built.loops:
            viol = max(viol, float(np.linalg.norm(data.site(lp.site1).xpos - data.site(lp.site2).xpos)))
        alpha = s * data.qacc[vadr]
        gap = marks[mi] - u
        if gap <= 1e-12 * (1 + abs(u)):
            mark_t[mi] = data.time
            mi += 1
            if mi == len(marks):
                break
            gap = marks[mi] - u
        dt = h
        if w * h + 0.5 * alpha * h * h >= gap:
            # land on the mark: the root of u + w dt + alpha dt^2 / 2 = mark
            if abs(alpha) * h < 1e-9 * max(w, 1e-300):
                dt = gap / w
            else:
                disc = w * w + 2 * alpha * gap
                dt = (2 * gap / (w + math.sqrt(disc))) if disc >= 0 and w + math.sqrt(max(disc, 0)) > 0 else h
            dt = min(max(dt, 1e-3 * h), h)
        if kinks.size and alpha != 0.0:
            # a table motor's torque bends at its rows: land on the next row's speed, so that every step sees
            # one piece of the curve (the piece is set at the step's start; a step across a row would carry
            # the old piece's slope past it: 2 % speed error in a start-up of six steps, issue 27 item 6)
            ahead = (kinks - w) / alpha
            ahead = ahead[ahead > 1e-9 * h]
            if ahead.size and ahead.min() < dt:
                dt = max(float(ahead.min()) * (1.0 + 1e-9), 1e-3 * h)
        if w <= 0 and data.time > 0 and alpha <= 0:
            raise amotor.Stall(f"in MuJoCo the motor stalls the {mech.name} at "
                               f"phi={math.degrees(red.angle(u)):.1f}deg (t={data.time:.3g} s)")
        if held:                           # the other loads at the step's midpoint state, held over the step
            um, wm = u + w * dt / 2 + alpha * dt * dt / 8, w + alpha * dt / 2
            data.xfrc_applied[:] = wrenches(built, np.array([data.time + dt / 2]), np.array([red.angle(um)]),
                                            np.array([s * wm])).xfrc[0]
        model.opt.timestep = dt
        mujoco.mj_step(model, data)
        model.opt.timestep = h
        steps += 1
        if steps > limit or not np.all(np.isfinite(data.qvel)):
            raise ParameterError(f"the {mech.name} motor run diverged at t={data.time:.4g} s")
    t, u, w = np.array(T), np.array(U), np.array(W)
    ta, tb = mark_t[int(np.searchsorted(marks, last0 - 1e-12))], mark_t[len(marks) - 1]
    # the landing leaves u within round-off of the mark; correct the times by the speed
    ka, kb = int(np.argmin(np.abs(t - ta))), len(t) - 1
    ta -= (u[ka] - last0) / w[ka]
    tb -= (u[kb] - end) / w[kb]
    mean = two_pi / (tb - ta)
    sel = np.flatnonzero((t >= t[ka]) & (t <= t[kb]))
    w_max, w_min = _extreme(t, w, sel, 1.0), _extreme(t, w, sel, -1.0)
    target = amotor.STARTUP_FRACTION * mean
    if w[0] >= target:
        t_up = 0.0
    else:
        k = int(np.argmax(w >= target))
        t_up = float(t[k - 1] + (target - w[k - 1]) * (t[k] - t[k - 1]) / (w[k] - w[k - 1]))
    return MotorRun(t=t, phi=red.angle(u), omega=s * w, torque=np.array(TAU), mean_speed=mean,
                    fluctuation=(w_max - w_min) / mean, startup_time=t_up, loop_violation=viol, timestep=h,
                    qpos=np.array(QP), qvel=np.array(QV))


def _extreme(t, w, sel, sign):
    """Largest (sign=1) or smallest (sign=-1) speed over the samples ``sel``, refined by the parabola
    through the best sample and its neighbours."""
    k = sel[int(np.argmax(sign * w[sel]))]
    if k == sel[0] or k == sel[-1]:
        return float(w[k])
    t0, t1, t2 = t[k - 1:k + 2]
    w0, w1, w2 = w[k - 1:k + 2]
    # parabola through three (possibly unevenly spaced) points: its vertex value
    d1, d2 = (w1 - w0) / (t1 - t0), (w2 - w1) / (t2 - t1)
    c = (d2 - d1) / (t2 - t0)
    if c == 0:
        return float(w1)
    b = d1 - c * (t0 + t1)
    tv = -b / (2 * c)
    if not (t0 <= tv <= t2):
        return float(w1)
    return float(w0 + (tv - t0) * (d1 + c * (tv - t1)))


def kinetic_energy(built, qpos, qvel) -> np.ndarray:
    """MuJoCo's kinetic energy [J] (armature included) at the given states, by mj_forward on each."""
    model = built.model
    data = mujoco.MjData(model)
    flags = model.opt.enableflags
    model.opt.enableflags = flags | mujoco.mjtEnableBit.mjENBL_ENERGY
    try:
        out = np.empty(len(qpos))
        for k in range(len(qpos)):
            data.qpos[:], data.qvel[:] = qpos[k], qvel[k]
            mujoco.mj_forward(model, data)
            out[k] = data.energy[1]
    finally:
        model.opt.enableflags = flags
    return out


@dataclass(frozen=True)
class Agreement:
    """MuJoCo against the reduced equation: the differences and the verdict."""

    mean_speed: float
    """relative difference of the mean speeds"""
    fluctuation: float
    """absolute difference of Cs"""
    curve: float
    """largest speed difference against angle over the last revolution, of the mean speed"""
    time: float
    """largest speed difference against time over the run, of the mean speed"""
    passed: bool

    def as_dict(self) -> dict:
        return {"mean_speed": self.mean_speed, "fluctuation": self.fluctuation, "speed_vs_angle": self.curve,
                "speed_vs_time": self.time,
                "tolerances": {"mean_speed": SPEED_TOL, "fluctuation": CS_TOL, "speed_vs_angle": CURVE_TOL,
                               "speed_vs_time": TIME_TOL},
                "passed": self.passed}


def agreement(run: amotor.Run, sim: MotorRun) -> Agreement:
    """Compare MuJoCo's run with the reduced equation's (see the tolerances above)."""
    s = run.reduced.direction
    ds = abs(sim.mean_speed / run.mean_speed - 1)
    dc = abs(sim.fluctuation - run.fluctuation)
    u = s * (sim.phi - run.reduced.q0)
    last = u >= u[-1] - 2 * math.pi - 1e-9
    curve = float(np.max(np.abs(run.speed_at(u[last]) - s * sim.omega[last]))) / run.mean_speed
    ok_t = sim.t <= run.t[-1]
    tdiff = float(np.max(np.abs(run.dense(sim.t[ok_t])[1] - s * sim.omega[ok_t]))) / run.mean_speed
    passed = ds <= SPEED_TOL and dc <= CS_TOL and curve <= CURVE_TOL and tdiff <= TIME_TOL
    return Agreement(ds, dc, curve, tdiff, bool(passed))


SIZING_TOL = 0.02
"""[relative] the sized flywheel's Cs against the target, in both answers: the issue's bound (the sizing
itself solves the steady cycle to 1e-10; what is left is the run's distance from its steady cycle)."""

SETTLED = SIZING_TOL / 10
"""[relative] a sizing run from rest is long enough when its last revolution's Cs is within this of the
steady cycle's: a heavy flywheel's start-up can take longer than the revolutions asked for (the shaper
with a 200 N m motor, 500 N cutting force and Cs = 0.02: 11.8 kg m^2, 3.2 s to start, Cs 0.0241 after
10 revolutions), so the run is doubled until it settles, leaving the 2 % bound to the simulation."""

MAX_SETTLING_REVOLUTIONS = 1280.0
"""The most revolutions a sizing run is extended to (7 doublings of the default 10)."""


@dataclass(frozen=True)
class Dynamics:
    """Both answers of `linkage dynamics`: the reduced equation's run, MuJoCo's run and their agreement,
    the flywheel used [kg m^2] and, when it was sized, the target Cs and the check of both runs."""

    mech: object
    motor: object
    flywheel: float
    run: amotor.Run
    sim: MotorRun | None
    agreement: Agreement | None
    target: float | None
    sizing_passed: bool | None
    built: object = None
    revolutions_asked: float | None = None
    """The revolutions asked for, where a sizing run was extended past them to reach its steady cycle."""

    @property
    def passed(self) -> bool:
        ok = self.agreement.passed if self.agreement is not None else True
        return bool(ok and (self.sizing_passed is not False))


def reduced_for(mech, loads, settings=M.Settings(), cycle=None):
    """(make_reduced(J), the inertias): the mass model and loads as MuJoCo's model carries them
    (sim.model.model_loads: its bodies' inertias, its gravity, its load's force and slow-stroke window, the
    file's loads), found without building a model: the one model of a motor run is the motor's
    (:func:`build`), which carries the same. ``cycle``: the prescribed motion over one turn (made here when
    None). ``settings`` is accepted for the callers that pass it; the reduced equation does not read it."""
    cycle = cycle if cycle is not None else Cycle.of(mech, 1.0)
    inertias, gravity, force, window, loadset = M.model_loads(mech, loads, cycle)

    def make(J):
        return amotor.reduce(mech, inertias, J, gravity, force, window, loadset)
    return make, inertias


def dynamics(mech, loads, motor, flywheel: float | None = 0.0, target: float | None = None,
             start_speed: float = 0.0, revolutions: float = 10.0, settings=M.Settings(),
             simulate_too: bool = True, cycle=None) -> Dynamics:
    """Drive ``mech`` by ``motor`` under ``loads``: the reduced equation's answer and MuJoCo's, with the
    flywheel given or (``target``) sized for that Cs and checked by both runs. ``cycle``: the prescribed
    motion over one turn (:class:`analytic.cycle.Cycle`, made by the service; made here when None), which
    both models are built from."""
    if flywheel is not None and target is not None and flywheel > 0:
        raise ParameterError("give --flywheel or --target-fluctuation, not both")
    if target is not None and not (isinstance(target, (int, float)) and math.isfinite(target) and 0 < target < 1):
        raise ParameterError(f"--target-fluctuation {target!r} must be a number in (0, 1) (e.g. 0.02)")
    if flywheel is not None and not (math.isfinite(flywheel) and flywheel >= 0):
        raise ParameterError(f"--flywheel {flywheel!r} must be a finite number >= 0 [kg m^2]")
    if not flywheel:                          # sizing starts from the bare linkage: the same singular equation
        try:
            check_inertia(mech, loads)
        except ParameterError as exc:
            if target is None:
                raise
            raise ParameterError(f"--target-fluctuation sizes the flywheel from the bare linkage, but {exc}") from None
    if cycle is None:
        cycle = Cycle.of(mech, 1.0)
    make, _ = reduced_for(mech, loads, cycle=cycle)
    J = flywheel or 0.0
    if target is not None:
        J, steady = amotor.size_flywheel(make, motor, target, start_speed=start_speed)
    red = make(J)
    r = amotor.run(red, motor, revolutions, start_speed)
    if target is not None:
        r = settled(red, motor, r, steady.fluctuation, start_speed)
    sizing = None if target is None else bool(abs(r.fluctuation / target - 1) <= SIZING_TOL)
    d = Dynamics(mech, motor, J, r, None, None, target, sizing, None,
                 revolutions if r.revolutions > revolutions else None)
    return simulated(d, loads, start_speed, settings, cycle) if simulate_too else d


def check_inertia(mech, loads) -> None:
    """Refuse a run without a flywheel whose reduced inertia vanishes somewhere with the file's masses (massless
    links, SPEC "Loads": m = 0; e.g. a massless crank and rod whose massive piston stops at its dead centres):
    the motor's equation is singular there (MuJoCo's stand-in masses would only make it stiff)."""
    from analytic import mass
    model = mass.model(mech, loads.inertias)
    if all(b.m > 0 for b in model.values()):
        return
    inp = mech.inputs[0]
    s = 1.0 if inp.motion.rate >= 0 else -1.0
    u = np.linspace(0.0, 2 * math.pi, 721)
    J = amotor._terms(mech, u, s, float(inp.motion.q0), {k: b for k, b in model.items() if b.m > 0}, 0.0,
                      (0.0, 0.0), (0.0, 0.0))[0]
    k = int(np.argmin(J))
    if not J[k] > 1e-9 * max(float(np.max(J)), 1e-300):
        raise ParameterError(f"the {mech.name}'s reduced inertia vanishes at {inp.q}="
                             f"{math.degrees(inp.motion.q0 + s * u[k]):.2f}deg (massless links, m = 0, and no "
                             f"flywheel): the motor's equation is singular there; give --flywheel or the links masses")


def settled(red, motor, r, steady_cs: float, start_speed: float = 0.0):
    """``r``, or the same run doubled in length until its last revolution's Cs is within :data:`SETTLED` of
    ``steady_cs`` (at most :data:`MAX_SETTLING_REVOLUTIONS`)."""
    while abs(r.fluctuation / steady_cs - 1) > SETTLED and r.revolutions < MAX_SETTLING_REVOLUTIONS:
        r = amotor.run(red, motor, min(2 * r.revolutions, MAX_SETTLING_REVOLUTIONS), start_speed)
    return r


def simulated(d: Dynamics, loads, start_speed: float = 0.0, settings=M.Settings(), cycle=None) -> Dynamics:
    """``d`` (the reduced equation's answer, from :func:`dynamics` with ``simulate_too=False``) with MuJoCo's
    run from the same initial state under the same ``loads``, their agreement and the sizing checked by both
    runs: a front end can look at the reduced equation's run (its duration, its peak speed) before paying
    for the simulation."""
    r = d.run
    w_max = float(np.max(np.abs(r.omega)))
    built = build(d.mech, loads, r.reduced, d.motor, w_max, settings, cycle)
    try:
        s = simulate(built, r.reduced, d.motor, r.revolutions, start_speed)
    except amotor.Stall as exc:                    # the reduced equation turned it: a stall of a coarse step
        needed = timestep_for(d.mech, r.reduced, d.motor, w_max, cycle) if settings.timestep is not None else None
        if needed is None or not settings.timestep > needed * (1 + 1e-3):
            raise
        raise ParameterError(f"{exc}, where the reduced equation turns it: the time step {settings.timestep:.4g} s "
                             f"given by --timestep is above the {needed:.4g} s this motor run needs; drop "
                             f"--timestep") from None
    sizing = d.sizing_passed
    if d.target is not None:
        sizing = bool(sizing and abs(s.fluctuation / d.target - 1) <= SIZING_TOL)
    return replace(d, sim=s, agreement=agreement(r, s), sizing_passed=sizing, built=built)


def record(d: Dynamics) -> dict:
    """The JSON object of SPEC's `linkage dynamics` (SI units)."""
    r = d.run
    out = {"mechanism": d.mech.name, "input": d.mech.inputs[0].q,
           "motor": ({"T0": d.motor.T0, "W0": d.motor.W0} if isinstance(d.motor, amotor.LinearMotor)
                     else {"omega": list(d.motor.omega), "tau": list(d.motor.tau)}),
           "t": r.t, "phi": r.phi, "omega": r.omega, "torque": r.torque,
           "flywheel": d.flywheel, "mean_speed": r.mean_speed, "fluctuation": r.fluctuation,
           "startup_time": r.startup_time, "peak_torque": r.peak_torque, "peak_power": r.peak_power,
           "energy_per_cycle": r.energy_per_cycle, "revolutions": r.revolutions,
           "units": {"t": "s", "phi": "rad", "omega": "rad/s", "torque": "N m", "flywheel": "kg m^2",
                     "mean_speed": "rad/s", "fluctuation": "1", "startup_time": "s", "peak_torque": "N m",
                     "peak_power": "W", "energy_per_cycle": "J"}}
    if d.target is not None:
        out["sizing"] = {"target": d.target, "flywheel": d.flywheel, "fluctuation": r.fluctuation,
                         "simulated_fluctuation": d.sim.fluctuation if d.sim else None, "tolerance": SIZING_TOL,
                         "passed": d.sizing_passed}
    if d.sim is not None:
        s = d.sim
        out["simulated"] = {"t": s.t, "phi": s.phi, "omega": s.omega, "torque": s.torque,
                            "mean_speed": s.mean_speed, "fluctuation": s.fluctuation,
                            "startup_time": s.startup_time, "timestep": s.timestep,
                            "loop_violation": s.loop_violation, "agreement": d.agreement.as_dict(),
                            "passed": d.agreement.passed}
    from sim.service.loads import dynamics_loads
    extra = dynamics_loads(d)
    if extra is not None:                     # SPEC "Loads": each load's work per cycle and the balance
        out["loads"], out["energy"] = extra
        out["friction"] = {"dissipated_per_cycle": 0.0}
    out["passed"] = d.passed
    return out


# ------------------------------------------------------------------------------- two inputs, two motors
def build_two(mech, loads, motors, run2, armature=(0.0, 0.0), settings=M.Settings()):
    """The five-bar's model with both drives made motors (see :func:`build`); the step from the faster
    input's peak speed."""
    if settings.timestep is None:
        rate = max(abs(i.motion.rate) for i in mech.inputs) or 1.0
        w_max = float(np.max(np.abs(run2.omega)))
        h = M.choose_timestep(mech) * rate / max(w_max, 1e-9)
        settings = replace(settings, timestep=min(max(h, M.MIN_TIMESTEP), M.MAX_TIMESTEP))
    built = M.build(mech, settings, loads)
    for d, a in zip(built.drives, armature):
        set_armature(built.model, d.joint, a)
    return built


def simulate_two(built, run2, motors, revolutions: float, start_speed=(0.0, 0.0)) -> dict:
    """Both motors driving, from the reduced equation's initial state; the first input's last revolution
    is landed on as in :func:`simulate`. Returns t, phi (N, 2), omega (N, 2), mean_speed (2,), fluctuation (2,)."""
    model, mech = built.model, built.mech
    s, q0 = run2.direction, run2.q0
    drives = built.drives
    jid = [model.joint(d.joint).id for d in drives]
    qadr = [model.jnt_qposadr[j] for j in jid]
    vadr = [model.jnt_dofadr[j] for j in jid]
    data = mujoco.MjData(model)
    data.qpos[:] = built.qpos0
    qvel = _initial_qvel(built, s * np.asarray(start_speed, float))
    data.qvel[:] = qvel
    data.act[:] = 0.0
    for d in drives:
        data.act[model.actuator(d.actuator).actadr[0]] = 1.0
    data.ctrl[:] = 0.0
    data.ctrl[model.actuator("load").id] = 1.0
    h = built.timestep
    two_pi = 2 * math.pi
    end, last0 = two_pi * revolutions, two_pi * (revolutions - 1)
    marks = [m for m in (last0, end) if m > 0]
    mi, mark_t = 0, {}
    T, U, W = [], [], []
    while mi < len(marks):
        u = np.array([s[k] * (data.qpos[qadr[k]] + drives[k].q_offset - q0[k]) for k in range(2)])
        w = np.array([s[k] * data.qvel[vadr[k]] for k in range(2)])
        for k, d in enumerate(drives):
            _set_motor(model, d, motors[k], s[k], w[k])
        mujoco.mj_forward(model, data)
        T.append(data.time)
        U.append(u)
        W.append(w)
        alpha = s[0] * data.qacc[vadr[0]]
        gap = marks[mi] - u[0]
        if gap <= 1e-12 * (1 + abs(u[0])):
            mark_t[mi] = data.time
            mi += 1
            if mi == len(marks):
                break
            gap = marks[mi] - u[0]
        dt = h
        if w[0] * h + 0.5 * alpha * h * h >= gap:
            disc = w[0] * w[0] + 2 * alpha * gap
            dt = (2 * gap / (w[0] + math.sqrt(disc))) if disc >= 0 and w[0] + math.sqrt(max(disc, 0)) > 0 else h
            dt = min(max(dt, 1e-3 * h), h)
        model.opt.timestep = dt
        mujoco.mj_step(model, data)
        model.opt.timestep = h
        if len(T) > 20_000_000 or not np.all(np.isfinite(data.qvel)):
            raise ParameterError(f"the {mech.name} two-motor run diverged at t={data.time:.4g} s")
    t, u, w = np.array(T), np.array(U), np.array(W)
    ta = mark_t[0] if len(marks) == 2 else 0.0
    tb = mark_t[len(marks) - 1]
    ka, kb = (int(np.argmin(np.abs(t - ta))) if len(marks) == 2 else 0), len(t) - 1
    ta -= (u[ka, 0] - last0) / w[ka, 0] if len(marks) == 2 else 0.0
    tb -= (u[kb, 0] - end) / w[kb, 0]
    # input 2's advance over the same interval, at the corrected ends (first-order by its speed)
    u2a = u[ka, 1] + w[ka, 1] * (ta - t[ka])
    u2b = u[kb, 1] + w[kb, 1] * (tb - t[kb])
    mean = np.array([(end - last0) / (tb - ta), (u2b - u2a) / (tb - ta)])
    sel = np.flatnonzero((t >= t[ka]) & (t <= t[kb]))
    cs = np.array([(_extreme(t, w[:, k], sel, 1.0) - _extreme(t, w[:, k], sel, -1.0)) / mean[k] for k in range(2)])
    return {"t": t, "phi": q0 + s * u, "omega": s * w, "mean_speed": mean, "fluctuation": cs}


def _initial_qvel(built, qd):
    """Joint velocities of the model at its start pose for input speeds ``qd`` (2,): the home state's
    velocities are those of the motion law's speeds; the loop-closing velocities are linear in the input
    speeds, so they are solved from the tree's constraint Jacobian with the inputs' joints held at qd."""
    model = built.model
    data = mujoco.MjData(model)
    data.qpos[:] = built.qpos0
    mujoco.mj_forward(model, data)
    nv = model.nv
    drives = built.drives
    fixed = [model.jnt_dofadr[model.joint(d.joint).id] for d in drives]
    free = [i for i in range(nv) if i not in fixed]
    Jc = np.zeros((0, nv))
    for lp in built.loops:
        ja, jb = np.zeros((3, nv)), np.zeros((3, nv))
        mujoco.mj_jacSite(model, data, ja, None, model.site(lp.site1).id)
        mujoco.mj_jacSite(model, data, jb, None, model.site(lp.site2).id)
        Jc = np.vstack([Jc, (ja - jb)[:2]])
    v = np.zeros(nv)
    v[fixed] = qd
    if free:
        rhs = -Jc[:, fixed] @ np.asarray(qd, float)
        v[free] = np.linalg.lstsq(Jc[:, free], rhs, rcond=None)[0]
    return v


@dataclass(frozen=True)
class Dynamics2:
    """Both answers for two motors: the reduced equation's run, MuJoCo's run (a dict) and the verdict
    (each input's mean speed within SPEED_TOL relative, Cs within CS_TOL, speed against time within
    TIME_TOL of its mean)."""

    mech: object
    motors: tuple
    flywheel: tuple
    run: amotor.Run2
    sim: dict
    differences: dict
    passed: bool


def dynamics_two(mech, loads, motors, flywheel=(0.0, 0.0), start_speed=(0.0, 0.0), revolutions: float = 10.0,
                 settings=M.Settings()) -> Dynamics2:
    """Two motors on the five-bar's two cranks: the 2x2 reduced equation and MuJoCo."""
    if loads.slow_stroke_only:
        raise ParameterError("--cutting-force acts on the slow stroke of one crank; with two motors give --force")
    from sim.model.loads import loadset_of
    if loadset_of(mech, loads) is not None:
        raise ParameterError(f"the {mech.name}'s [[loads]] (or --torque, --force ...@POINT) with two motors: not "
                             f"supported yet; give one motor, or only --gravity/--force")
    for k, J in enumerate(flywheel):
        if not (math.isfinite(J) and J >= 0):
            raise ParameterError(f"--flywheel {mech.inputs[k].q}={J!r} must be a finite number >= 0 [kg m^2]")
    b0 = M.build(mech, settings, loads)
    inertias = M.body_inertias(b0.model, mech.links)
    gravity = tuple(float(x) for x in b0.model.opt.gravity[:2]) if loads.gravity is not None else (0.0, 0.0)
    force = tuple(float(x) for x in b0.model.actuator("load").gear[:2])
    r = amotor.run_two(mech, inertias, motors, revolutions, start_speed, flywheel, gravity, force)
    built = build_two(mech, loads, motors, r, flywheel, settings)
    s = simulate_two(built, r, motors, revolutions, start_speed)
    ds = np.abs(s["mean_speed"] / r.mean_speed - 1)
    dc = np.abs(s["fluctuation"] - r.fluctuation)
    keep = s["t"] <= r.last_revolution[1]
    y = r.dense(s["t"][keep])
    dt = np.max(np.abs(r.direction[:, None] * y[2:4] - s["omega"][keep].T), axis=1) / np.abs(r.mean_speed)
    diffs = {"mean_speed": ds, "fluctuation": dc, "speed_vs_time": dt}
    passed = bool(np.all(ds <= SPEED_TOL) and np.all(dc <= CS_TOL) and np.all(dt <= TIME_TOL))
    return Dynamics2(mech, tuple(motors), tuple(flywheel), r, s, diffs, passed)


def record_two(d: Dynamics2) -> dict:
    """The JSON object for two motors: every per-input field keyed by the input's name (phi2, phi4)."""
    names = [i.q for i in d.mech.inputs]
    r, s = d.run, d.sim

    def per(x):
        x = np.asarray(x)
        return {n: (float(x[k]) if x.ndim == 1 else x[..., k]) for k, n in enumerate(names)}
    return {"mechanism": d.mech.name, "inputs": names,
            "motor": {n: {"T0": m.T0, "W0": m.W0} for n, m in zip(names, d.motors)},
            "t": r.t, "phi": per(r.phi), "omega": per(r.omega), "torque": per(r.torque),
            "flywheel": dict(zip(names, d.flywheel)), "mean_speed": per(r.mean_speed),
            "fluctuation": per(r.fluctuation), "startup_time": per(r.startup_time), "revolutions": r.revolutions,
            "simulated": {"t": s["t"], "phi": per(s["phi"]), "omega": per(s["omega"]),
                          "mean_speed": per(s["mean_speed"]), "fluctuation": per(s["fluctuation"]),
                          "differences": {k: per(v) for k, v in d.differences.items()},
                          "tolerances": {"mean_speed": SPEED_TOL, "fluctuation": CS_TOL, "speed_vs_time": TIME_TOL},
                          "passed": d.passed},
            "passed": d.passed}
