"""The drives: position-tracking servos (MuJoCo's integrated-velocity actuator) sized from the peak load,
their commands, their initial state, and the external load's actuator.

Drives track the commanded motion by position: the actuator's activation integrates the commanded speed,
and force = kp (act - q) - kv qdot. With the speed and acceleration fed forward (see
:func:`drive_command`) there is no phase drift; the tracking error is the reaction torque over kp."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import mujoco
import numpy as np

from analytic.checks import slow_stroke  # noqa: F401 (the builder's and the loads' window; found in analytic)
from sim.model.armature import set_armature
from sim.model.inertia import body_inertias

DRIVE_ERROR_BUDGET = 1e-6
"""[rad, or of the size for a slider] The drives' stiffness kp is sized so that the peak reaction
torque deflects the drive by at most this much (kp = peak / budget)."""

SERVO_RATE = 0.25
"""The drive's natural frequency times the time step: sqrt(kp / J) h. The rotor inertia J (armature)
is sized for it (J = kp (h / SERVO_RATE)^2), critically damped (kv = 2 sqrt(kp J)); RK4 resolves a mode
of 0.25 rad per step without pumping energy."""


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


def add_drives(spec, mech, order, q_start, h) -> list[Drive]:
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


def add_load(spec, mech, loads, site: str | None = None):
    """The output point's force (``loads.force``) as a site actuator at ``site`` (default: the point's own)."""
    act = spec.add_actuator(name="load", target=site or mech.output_point, trntype=mujoco.mjtTrn.mjTRN_SITE,
                            refsite="origin")
    fx, fy = loads.force
    act.gear = [fx, fy, 0.0, 0.0, 0.0, 0.0]
    act.ctrllimited = False


def size_drives(model, mech, drives, loads, h, extra=None, cycle=None) -> list[Drive]:
    """kp from the peak analytic drive force (DRIVE_ERROR_BUDGET), J and kv for SERVO_RATE: over the samples
    of the run's ``cycle`` (analytic.cycle.Cycle; made here when None), with ``extra`` (the file's loads'
    share of the drives at the same samples, sim.model.loads.drive_loads) added where given."""
    from analytic.applications import torque
    from analytic.cycle import Cycle
    switch = 1.0
    inertias = body_inertias(model, mech.links)
    gravity, gear = tuple(model.opt.gravity[:2]), tuple(model.actuator("load").gear[:2])
    cycle = cycle if cycle is not None else Cycle.of(mech)
    tau = torque.drive_forces(mech, cycle.q, cycle.qd, cycle.qdd, inertias, None, gravity, gear, switch,
                              cycle.solution, cycle.coefficients)
    if extra is not None:
        tau = {k: v + extra.tau[k] for k, v in tau.items()}
    out = []
    size = mech.size
    for d in drives:
        peak = float(np.nanmax(np.abs(tau[d.input.link])))
        budget = DRIVE_ERROR_BUDGET * d.input.spec.rate_scale(size)
        total_mass = float(sum(model.body_mass))
        floor = 1e-3 * total_mass * 9.81 * size          # a small load so kp is never zero
        kp = max(peak, floor) / budget
        J = kp * (h / SERVO_RATE) ** 2
        kv = 2.0 * math.sqrt(kp * J)
        a = model.actuator(d.actuator)
        a.gainprm[0] = kp
        a.biasprm[:3] = [0.0, -kp, -kv]
        set_armature(model, d.joint, J)
        out.append(replace(d, kp=kp, kv=kv, armature=J))
    return out


def drive_command(d: Drive, q, qd, qdd, qddd):
    """The servo's activation target and its rate for a desired motion (q, qd, qdd, qddd): the
    activation a leads q by (kv qd + J qdd) / kp, so that force = kp (a - q) - kv qdot = J qdd on the
    desired motion with no reaction; ctrl = da/dt."""
    lead = (d.kv * qd + d.armature * qdd) / d.kp
    rate = qd + (d.kv * qdd + d.armature * qddd) / d.kp
    return q - d.q_offset + lead, rate


def initial_controls(model, mech, drives, q_start, loads, extra=None, cycle=None):
    """The drives' activations at t = 0: the commanded motion's lead plus the deflection that the
    mechanism's reaction needs (kp a = tau), so the servo starts already carrying its load and the
    torque curve has no start-up transient. ``cycle``: the run's (its first sample is t = 0), or None."""
    from analytic.applications import torque
    q0, qd0, qdd0 = q_start
    act = np.zeros(model.na)
    ctrl = np.zeros(model.nu)
    jerk = input_jerk(mech, np.array([0.0]))
    on = 1.0
    if loads.slow_stroke_only:
        lo, hi = slow_stroke(mech, cycle)
        on = float(lo <= 0.0 <= hi or lo <= 2 * math.pi <= hi)
    start = {}
    if cycle is not None:
        from analytic.cycle import take
        start = {"sol": take(cycle.solution, slice(0, 1)),
                 "coefficients": tuple(take(c, slice(0, 1)) for c in cycle.coefficients)}
    reaction = torque.drive_forces(mech, q0[None], qd0[None], qdd0[None], body_inertias(model, mech.links), None,
                                   tuple(model.opt.gravity[:2]), tuple(model.actuator("load").gear[:2]), on, **start)
    for k, d in enumerate(drives):
        a, c = drive_command(d, q0[k], qd0[k], qdd0[k], jerk[0, k])
        held = float(reaction[d.input.link][0]) + (float(extra.tau[d.input.link][0]) if extra is not None else 0.0)
        act[model.actuator(d.actuator).actadr[0]] = a + held / d.kp
        ctrl[model.actuator(d.actuator).id] = c
    return act, ctrl


def input_jerk(mech, t):
    """d^3 q / dt^3 of every input at times t (nonzero for a rocking drive or a motion law)."""
    out = np.zeros((len(t), len(mech.inputs)))
    for k, inp in enumerate(mech.inputs):
        out[:, k] = inp.motion.jerk(t)
    return out


def load_switch(built, t: np.ndarray) -> np.ndarray:
    """1 where the external load acts, else 0 (always, or during the slow stroke only)."""
    if built.slow_stroke is None:
        return np.ones_like(t)
    first = built.mech.inputs[0]
    phase = np.mod(first.motion.at(t)[0] - first.motion.q0, 2 * math.pi)
    lo, hi = built.slow_stroke
    return (((phase >= lo) & (phase <= hi)) | ((phase + 2 * math.pi >= lo) & (phase + 2 * math.pi <= hi))).astype(float)
