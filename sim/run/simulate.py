"""Run a built model with ``mujoco.rollout`` and read every output it measures, by sensor name, in the
world frame, named as the analytic solver names them.

Sensor values that ``rollout`` returns for step k are evaluated at the state *before* that step (mj_step
runs mj_forward on the current state, then integrates), so every recorded quantity, time included
(``clock`` sensor), belongs to one instant.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import mujoco
import numpy as np
from mujoco import rollout

from analytic import ParameterError
from analytic import kinds
from analytic.solution import Solution, StateView
from sim.model import DEFAULT_INTEGRATOR, INTEGRATORS, Built, drive_command, input_jerk
from sim.model.drives import load_switch

MAX_STEPS = 20_000_000
"""Longest run accepted [steps] (~2 GB of recorded sensors for a four-bar); more is refused up front."""


class SimulationError(ParameterError):
    """The simulation diverged or its loops opened; the message names the time and input value."""


LOOP_BOUND = 1e-3
"""Loop violation [relative to the mechanism's size] past which a run is stopped as failed."""


@dataclass(frozen=True)
class Trajectory:
    """One simulated run: time [s], the drive inputs and every output measured by the model (world
    frame, SI units), the loop-closure violation [m], drive forces, commanded inputs and joint states."""

    name: str
    timestep: float
    integrator: str
    steps: int
    cpu_seconds: float
    t: np.ndarray
    inputs: dict[str, np.ndarray]
    outputs: Solution
    loop_violation: np.ndarray
    forces: dict[str, np.ndarray]
    commanded: dict[str, np.ndarray]
    """Each input's commanded position at the recorded instants, keyed by its q name (phi1, ...)."""
    load: np.ndarray
    """The external load's switch (1 on, 0 off) at each step, as the load actuator applied it."""
    qpos: np.ndarray
    qvel: np.ndarray
    act: np.ndarray
    joint_names: tuple[str, ...]
    cams: dict = field(default_factory=dict)
    """Per cam (its name): {"separated": bool, "first_at": cam angle [rad] in [0, 2 pi) or None}: whether its
    follower left it (sim.run.cams.separations); {} without a cam."""


def steps_for(built: Built, revolutions: float) -> int:
    end = built.mech.duration(revolutions)
    n = int(math.ceil(end / built.timestep - 1e-9)) + 1
    if n > MAX_STEPS:
        raise ParameterError(f"{built.mech.definition.source}: revolutions={revolutions:g} runs {end:.3g} s, "
                             f"{n:.3g} steps of {built.timestep:.3g} s; at most {MAX_STEPS:.0e} are simulated at "
                             f"once: reduce the revolutions or shorten the cycle (the inputs' speeds, or their "
                             f"laws' durations)")
    return n


def controls(built: Built, t: np.ndarray) -> np.ndarray:
    """Controls at step start times t, shape (len(t), nu): each drive's activation rate at the step's
    midpoint (the activation integrates it exactly for a steady drive), and the load switch. A drive whose
    input follows a motion law takes instead the change of its target over the step, divided by h, so that
    its activation meets the target at every step's end: the midpoint rate misses a law's jumps and its
    rounding accumulates (a dwell then held 3.8e-5 rad off)."""
    model, mech = built.model, built.mech
    h = built.timestep
    mid = t + 0.5 * h
    q, qd, qdd = mech.drive(mid)
    jerk = input_jerk(mech, mid)
    ctrl = np.zeros((len(t), model.nu))
    ends = None
    for k, d in enumerate(built.drives):
        _, rate = drive_command(d, q[:, k], qd[:, k], qdd[:, k], jerk[:, k])
        if d.input.motion.law is not None:
            ends = ends or (mech.drive(t), mech.drive(t + h))
            a0, _ = drive_command(d, *(x[:, k] for x in ends[0]), 0.0)
            a1, _ = drive_command(d, *(x[:, k] for x in ends[1]), 0.0)
            rate = (a1 - a0) / h
        ctrl[:, model.actuator(d.actuator).id] = rate
    ctrl[:, model.actuator("load").id] = load_switch(built, t)
    return ctrl


def _reader(model, sens):
    def g(name):
        s = model.sensor(name)
        values = sens[:, s.adr[0]:s.adr[0] + s.dim[0]]
        if s.type[0] == mujoco.mjtSensor.mjSENS_FRAMELINACC:
            values = values + model.opt.gravity          # frame accelerometers read a - g
        return values
    return g


def measure(built: Built, sens: np.ndarray):
    """(inputs, outputs, loop violation, forces) from the recorded sensor rows."""
    model, mech = built.model, built.mech
    g = _reader(model, sens)
    out: dict[str, np.ndarray] = {}
    for p in mech.points:
        pos, vel, acc = g(f"{p}_pos"), g(f"{p}_vel"), g(f"{p}_acc")
        out["x" + p], out["y" + p], out["vx" + p], out["vy" + p] = pos[:, 0], pos[:, 1], vel[:, 0], vel[:, 1]
        out["ax" + p], out["ay" + p] = acc[:, 0], acc[:, 1]
    for ln in mech.links:
        xa = g(f"{ln}_xaxis")
        out["phi" + ln] = np.arctan2(xa[:, 1], xa[:, 0])
        out["cos" + ln], out["sin" + ln] = np.cos(out["phi" + ln]), np.sin(out["phi" + ln])
        out["omega" + ln] = g(f"{ln}_angvel")[:, 2]
        out["alpha" + ln] = g(f"{ln}_angacc")[:, 2]
    for block, (origin, point, offset) in mech.slide_frames.items():
        if isinstance(origin, str):
            O = [out[k + origin] for k in ("x", "y", "vx", "vy", "ax", "ay")]
        else:
            zero = np.zeros(len(sens))
            O = [zero + origin[0], zero + origin[1], zero, zero, zero, zero]
        c, s = out["cos" + block], out["sin" + block]
        w, a = out["omega" + block], out["alpha" + block]
        dx, dy = out["x" + point] - O[0], out["y" + point] - O[1]
        sd = dx * c + dy * s
        out["s" + block] = sd
        out["ds" + block] = (out["vx" + point] - O[2]) * c + (out["vy" + point] - O[3]) * s + offset * w
        out["dds" + block] = ((out["ax" + point] - O[4]) * c + (out["ay" + point] - O[5]) * s + sd * w * w
                              + offset * a)
    view = StateView(out)
    for e in mech.geometry.elements:
        out.update(kinds.get(e["kind"]).measured_extras(e, view))
    inputs = {}
    for d in built.drives:
        inp = d.input
        inputs[inp.q] = d.q_offset + g(f"{d.joint}_q")[:, 0]
        inputs[inp.qd] = g(f"{d.joint}_qd")[:, 0]
        inputs[inp.qdd] = out[inp.qdd]                   # the input's own column of the measured state
    viol = np.zeros(len(sens))
    for lp in built.loops:
        viol = np.maximum(viol, np.linalg.norm(g(f"{lp.site1}_pos") - g(f"{lp.site2}_pos"), axis=1))
    forces = {f"tau{d.input.link}": delivered(d, g(f"tau{d.input.link}")[:, 0], inputs[d.input.qdd])
              for d in built.drives}
    labels = tuple(e["label"] for e in mech.geometry.elements)
    sol = Solution(out, np.full(len(sens), -1), labels, mech.aliases)
    return inputs, sol, viol, forces


def delivered(drive, actuator_force: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """What drive ``drive`` applies to its link [N m or N]: its servo's actuator force less its rotor's inertia
    term, armature x qdd (qdd: the driven joint's measured acceleration, the input's own column). The rotor
    inertia is a numerical constant of the servo (sim.model.drives.SERVO_RATE), not part of the design: 1.9e6
    kg m^2 on the 5 kN press of tests/test_drive_torque.py, whose rotor term reached 197 N m on a 207 N m drive;
    what reaches the link is what ``forces`` and hand statics give (docs/CONVENTIONS.md, "What the simulation
    adds")."""
    return np.asarray(actuator_force) - drive.armature * np.asarray(qdd)


def simulate(built: Built, revolutions: float = 1.0) -> Trajectory:
    """Simulate ``revolutions`` turns of the first input; every loop starts closed (analytic state)."""
    model, mech = built.model, built.mech
    h = built.timestep
    nstep = steps_for(built, revolutions)
    data = mujoco.MjData(model)
    data.qpos[:], data.qvel[:], data.act[:], data.ctrl[:] = built.qpos0, built.qvel0, built.act0, built.ctrl0
    mujoco.mj_forward(model, data)
    kind = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state0 = np.empty(mujoco.mj_stateSize(model, kind))
    mujoco.mj_getState(model, data, state0, kind)
    t = np.arange(nstep) * h
    ctrl = controls(built, t)
    spec = mujoco.mjtState.mjSTATE_CTRL
    if built.loadset is not None:                  # the file's loads as xfrc_applied (sim.model.loads)
        from sim.model.loads import wrenches
        ctrl = np.concatenate([ctrl, wrenches(built, t).xfrc.reshape(nstep, -1)], axis=1)
        spec = spec | mujoco.mjtState.mjSTATE_XFRC_APPLIED
    t0 = time.process_time()
    states, sens = rollout.rollout(model, data, state0[None], ctrl[None], control_spec=int(spec), nstep=nstep)
    cpu = time.process_time() - t0
    sens = sens[0]
    nq, nv, na = model.nq, model.nv, model.na
    full = np.concatenate([state0[None], states[0, :-1]])
    qpos, qvel, act = full[:, 1:1 + nq], full[:, 1 + nq:1 + nq + nv], full[:, 1 + nq + nv:1 + nq + nv + na]
    inputs, outputs, viol, forces = measure(built, sens)
    q_des = mech.drive(t)[0]
    commanded = {inp.q: q_des[:, k] for k, inp in enumerate(mech.inputs)}
    _check_run(built, sens, inputs, viol, h)
    integrator = next(k for k, v in INTEGRATORS.items() if v == model.opt.integrator)
    from sim.run import cams
    separated = cams.separations(built, sens, {ln: outputs["phi" + ln] for ln in mech.links})
    return Trajectory(mech.name, h, integrator, nstep, cpu, _reader(model, sens)("time")[:, 0], inputs, outputs,
                      viol, forces, commanded, _reader(model, sens)("load")[:, 0], qpos, qvel, act,
                      tuple(model.joint(i).name for i in range(model.njnt)), separated)


def energies(built: Built, tr: Trajectory) -> tuple[np.ndarray, np.ndarray]:
    """MuJoCo's kinetic and potential energy [J] at every recorded state (armature included), by
    mj_forward on each state (the energy sensors inside an RK4 step are not at the step's start)."""
    model = built.model
    data = mujoco.MjData(model)
    flags = model.opt.enableflags
    model.opt.enableflags = flags | mujoco.mjtEnableBit.mjENBL_ENERGY
    try:
        out = np.empty((len(tr.t), 2))
        for k in range(len(tr.t)):
            data.qpos[:] = tr.qpos[k]
            data.qvel[:] = tr.qvel[k]
            mujoco.mj_forward(model, data)
            out[k] = data.energy[1], data.energy[0]
    finally:
        model.opt.enableflags = flags
    return out[:, 0], out[:, 1]


def _check_run(built: Built, sens: np.ndarray, inputs: dict, viol: np.ndarray, h: float) -> None:
    bad = ~np.all(np.isfinite(sens), axis=1) | ~(viol <= LOOP_BOUND * built.mech.size)
    if bad.any():
        k = int(np.argmax(bad))
        first = built.mech.inputs[0]
        value = inputs[first.q][k]
        where = (f"{first.q}={math.degrees(value):.2f}deg" if first.angular else f"{first.q}={value:.6g} m") \
            if np.isfinite(value) else "an undefined input"
        what = "diverged" if not np.all(np.isfinite(sens[k])) else f"opened a loop by {viol[k]:.3g} m"
        from sim.model import choose_timestep
        needed = choose_timestep(built.mech)
        if h > 1.5 * needed:
            raise SimulationError(f"the {built.name} simulation {what} at t={k * h:.4f} s ({where}): the time step "
                                  f"{h:g} s is too large for this design, which needs about {needed:.3g} s; leave "
                                  f"the time step to be chosen from the design")
        if built.settings.integrator != DEFAULT_INTEGRATOR:
            raise SimulationError(f"the {built.name} simulation {what} at t={k * h:.4f} s ({where}): the "
                                  f"{built.settings.integrator} integrator cannot hold the loops at a step of {h:.3g} s; "
                                  f"use --integrator {DEFAULT_INTEGRATOR} (the default) or a smaller --timestep")
        raise SimulationError(f"the {built.name} simulation {what} at t={k * h:.4f} s ({where}): the design is "
                              f"too close to a singular pose there to simulate; move it away or lower the speed")


@dataclass(frozen=True)
class Ends:
    """Evaluations a :func:`replay` carries along (compare's work balance): for each step k of ``steps``, its
    end state (the recorded state k + 1) under step k's own controls and body wrenches, row n of ``inputs``
    (set by ``mj_setState`` with ``sig``: mjSTATE_CTRL, with mjSTATE_XFRC_APPLIED for the file's loads), then
    ``read(n, data)``. ``energy``: MuJoCo's energies are computed too (``data.energy``)."""

    steps: np.ndarray
    inputs: np.ndarray
    sig: int
    read: Callable
    energy: bool = False


def replay(built: Built, tr: Trajectory, steps, read, ends: Ends | None = None, sensors: bool = True
           ) -> tuple[np.ndarray, mujoco.MjData]:
    """``read(data)`` (a flat array) at each recorded step in ``steps`` (indices into the trajectory), after
    ``mj_forward`` on that step's state and controls: what the rollout computed at the step's start (its
    sensors' instant), for what ``rollout`` does not return (constraint forces, ``cfrc_int``). Run only when
    asked (joint forces), so an ordinary simulation costs nothing more. The equality constraints' problem
    is quadratic, so Newton's solver reaches the same forces from any warm start. Returns the stacked reads
    (len(steps), width) and the MjData of the last step (for the model's row layout). ``sensors=False``: the
    sensors are not evaluated (a ``read`` that reads none of them).

    ``ends`` (:class:`Ends`) are evaluated on the way: where the replay has just evaluated a step's end state
    itself, only the acceleration stage is redone under the earlier step's controls and wrenches
    (``mj_forwardSkip`` from mjSTAGE_VEL: the position and velocity stages, the contacts' collision among
    them, depend on the state alone, not on ``ctrl`` or ``xfrc_applied``, which MuJoCo reads from
    ``mj_fwdActuation`` on, as mj_step1/mj_step2 document; the solver starts from ``qacc_warmstart``, which
    only ``mj_step`` writes), so each gives what a fresh ``mj_forward`` gives, bit for bit; the others are
    evaluated whole after the replay."""
    model = built.model
    steps = np.asarray(steps, dtype=int)
    data = mujoco.MjData(model)
    pending = {} if ends is None else {k + 1: n for n, k in enumerate(np.asarray(ends.steps).tolist())}
    flags = model.opt.enableflags
    if ends is not None and ends.energy:
        model.opt.enableflags = flags | mujoco.mjtEnableBit.mjENBL_ENERGY
    out = None
    try:
        if len(steps):
            states, sig = _states(built, tr, steps, controls(built, steps * built.timestep))
            for row, (k, state) in enumerate(zip(steps.tolist(), states)):
                mujoco.mj_setState(model, data, state, sig)
                mujoco.mj_forwardSkip(model, data, mujoco.mjtStage.mjSTAGE_NONE, 0 if sensors else 1)
                values = read(data)
                if out is None:
                    out = np.empty((len(steps), len(values)))
                out[row] = values
                n = pending.pop(k, None)
                if n is not None:                  # step k - 1's end: this state under that step's inputs
                    mujoco.mj_setState(model, data, ends.inputs[n], ends.sig)
                    mujoco.mj_forwardSkip(model, data, mujoco.mjtStage.mjSTAGE_VEL, 1)
                    ends.read(n, data)
        if pending:
            _evaluate_ends(built, tr, ends, pending)
    finally:
        model.opt.enableflags = flags
    return (out if out is not None else np.empty((0, 0))), data


def _states(built: Built, tr: Trajectory, steps: np.ndarray, ctrl=None) -> tuple[np.ndarray, int]:
    """The recorded states at ``steps`` as rows ``mj_setState`` takes whole (time, qpos, qvel, act, in
    mjtState's order; with ``ctrl`` rows, the controls and the file's loads' wrenches at the steps too) and
    their signature."""
    S = mujoco.mjtState
    t = steps * built.timestep
    sig = S.mjSTATE_TIME | S.mjSTATE_QPOS | S.mjSTATE_QVEL | S.mjSTATE_ACT
    parts = [t[:, None], tr.qpos[steps], tr.qvel[steps], tr.act[steps]]
    if ctrl is not None:
        sig |= S.mjSTATE_CTRL
        parts.append(ctrl)
        if built.loadset is not None:
            from sim.model.loads import wrenches
            sig |= S.mjSTATE_XFRC_APPLIED
            parts.append(wrenches(built, t).xfrc.reshape(len(steps), 6 * built.model.nbody))
    return np.concatenate(parts, axis=1), int(sig)


def _evaluate_ends(built: Built, tr: Trajectory, ends: Ends, pending: dict) -> None:
    """The end states ``pending`` ({state index: row of ``ends``}) evaluated whole, each under its step's
    inputs (sensors skipped: none is read)."""
    model = built.model
    data = mujoco.MjData(model)
    at = sorted(pending)
    states, sig = _states(built, tr, np.asarray(at, dtype=int))
    for j, state in zip(at, states):
        n = pending[j]
        mujoco.mj_setState(model, data, state, sig)
        mujoco.mj_setState(model, data, ends.inputs[n], ends.sig)
        mujoco.mj_forwardSkip(model, data, mujoco.mjtStage.mjSTAGE_NONE, 1)
        ends.read(n, data)
