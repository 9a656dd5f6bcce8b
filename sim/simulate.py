"""Run a built model for R crank revolutions with ``mujoco.rollout`` and read the SPEC outputs it
measures, by sensor name, in the world frame.

Sensor values that ``rollout`` returns for step k are evaluated at the state *before* that step (mj_step
runs mj_forward on the current state, then integrates), so every recorded quantity — time included,
through the ``clock`` sensor — belongs to one consistent instant.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import mujoco
import numpy as np
from mujoco import rollout

from analytic import ParameterError
from .model import Built
from .params import FIRST_CRANK, duration


class SimulationError(ParameterError):
    """The simulation diverged or its loops opened; the message names the time and crank angle."""


LOOP_BOUND = 1e-4
"""Loop violation [m, relative to the longest link] past which a run is stopped as failed."""


@dataclass(frozen=True)
class Trajectory:
    """One simulated run: time [s], the drive inputs and SPEC outputs measured by the model (world
    frame, SI units), the loop-closure violation [m] and the crank actuator forces [N m]."""

    name: str
    timestep: float
    integrator: str
    steps: int
    cpu_seconds: float
    t: np.ndarray
    inputs: dict[str, np.ndarray]
    outputs: dict[str, np.ndarray]
    loop_violation: np.ndarray
    forces: dict[str, np.ndarray]
    commanded: dict[str, np.ndarray]
    """Each crank's desired speed [rad/s] at the recorded instants, keyed omega1 / omega2, omega4."""
    load: np.ndarray
    """The external load's switch (1 on, 0 off) at each step, as the load actuator applied it."""
    qpos: np.ndarray
    """Joint positions at the same instants, shape (steps, nq) (every joint here has one coordinate)."""
    qvel: np.ndarray
    """Joint velocities at the same instants, shape (steps, nv)."""
    joint_names: tuple[str, ...]


def _sensor(model, data_rows, name):
    """Sensor ``name``'s columns. Linear accelerations are returned as true accelerations: MuJoCo's
    frame accelerometers read a - g (the world's acceleration is -g), so g is added back."""
    s = model.sensor(name)
    values = data_rows[:, s.adr[0]:s.adr[0] + s.dim[0]]
    if s.type[0] == mujoco.mjtSensor.mjSENS_FRAMELINACC:
        values = values + model.opt.gravity
    return values


def _angle(x):
    return np.pi - np.mod(np.pi - x, 2 * np.pi)


def _dist(a, b):
    return np.linalg.norm(a - b, axis=1)


def _fourbar(model, S):
    g = lambda n: _sensor(model, S, n)          # noqa: E731
    phi1, omega1 = g("phi1")[:, 0], g("omega1")[:, 0]
    phi2, omega2 = phi1 + g("qB")[:, 0], omega1 + g("vB")[:, 0]
    phi3, omega3 = g("phi3")[:, 0], g("omega3")[:, 0]
    inputs = {"phi1": phi1, "omega1": omega1, "alpha1": g("crank_angacc")[:, 2]}
    outputs = {
        "phi2": _angle(phi2), "phi3": _angle(phi3), "omega2": omega2, "omega3": omega3,
        "alpha2": g("coupler_angacc")[:, 2], "alpha3": g("rocker_angacc")[:, 2],
        "xE": g("E_pos")[:, 0], "yE": g("E_pos")[:, 1], "vxE": g("E_vel")[:, 0], "vyE": g("E_vel")[:, 1],
        "axE": g("E_acc")[:, 0], "ayE": g("E_acc")[:, 1],
        "mu": np.arctan2(np.abs(np.sin(phi3 - phi2)), np.abs(np.cos(phi3 - phi2))),
    }
    return inputs, outputs, _dist(g("C_coupler_pos"), g("C_pos")), {"tau1": g("tau1")[:, 0]}


def _sixbar(model, S):
    g = lambda n: _sensor(model, S, n)          # noqa: E731
    phi3, omega3, s, ds = g("phi3")[:, 0], g("omega3")[:, 0], g("s")[:, 0], g("ds")[:, 0]
    # The block's acceleration along the guide: a_A . u = dds - s omega3^2 (u = guide direction).
    a = g("A_block_acc")
    dds = a[:, 0] * np.cos(phi3) + a[:, 1] * np.sin(phi3) + s * omega3 ** 2
    inputs = {"phi1": g("phi1")[:, 0], "omega1": g("omega1")[:, 0], "alpha1": g("crank_angacc")[:, 2]}
    outputs = {
        "s": s, "phi3": _angle(phi3), "phi4": _angle(phi3 + g("qB")[:, 0]), "xC": g("xC")[:, 0],
        "ds": ds, "omega3": omega3, "omega4": omega3 + g("vB")[:, 0], "vxC": g("vxC")[:, 0],
        "dds": dds, "alpha3": g("guide_angacc")[:, 2], "alpha4": g("rod_angacc")[:, 2], "axC": g("C_acc")[:, 0],
    }
    viol = np.maximum(_dist(g("A_pos"), g("A_block_pos")), _dist(g("C_rod_pos"), g("C_pos")))
    return inputs, outputs, viol, {"tau1": g("tau1")[:, 0]}


def _fivebar(model, S):
    g = lambda n: _sensor(model, S, n)          # noqa: E731
    phi2, omega2 = g("phi2")[:, 0], g("omega2")[:, 0]
    theta3, omega3 = phi2 + g("qB")[:, 0], omega2 + g("vB")[:, 0]
    s, ds = g("S")[:, 0], g("dS")[:, 0]
    rel = g("C_block_acc") - g("B_acc")          # = (ddS - S w3^2) u + (S a3 + 2 dS w3) u_perp
    dds = rel[:, 0] * np.cos(theta3) + rel[:, 1] * np.sin(theta3) + s * omega3 ** 2
    inputs = {"phi2": phi2, "phi4": g("phi4")[:, 0], "omega2": omega2, "omega4": g("omega4")[:, 0],
              "alpha2": g("crank2_angacc")[:, 2], "alpha4": g("crank4_angacc")[:, 2]}
    outputs = {
        "S": s, "theta3": _angle(theta3), "dS": ds, "omega3": omega3, "ddS": dds,
        "alpha3": g("link3_angacc")[:, 2],
        "xP": g("P_pos")[:, 0], "yP": g("P_pos")[:, 1], "vxP": g("P_vel")[:, 0], "vyP": g("P_vel")[:, 1],
        "axP": g("P_acc")[:, 0], "ayP": g("P_acc")[:, 1],
    }
    return inputs, outputs, _dist(g("C_block_pos"), g("C_pos")), {"tau2": g("tau2")[:, 0], "tau4": g("tau4")[:, 0]}


_MEASURE = {"fourbar": _fourbar, "sixbar": _sixbar, "fivebar": _fivebar}


def desired_motion(built: Built, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each crank's desired speed [rad/s] and acceleration [rad/s^2] at times t, shape (len(t), ncranks):
    omega + alpha t, or for a rocking four-bar crank phi = mid - amp cos(|omega1| t)."""
    mech = built.mech
    if built.rock is not None:
        lo, hi = built.rock
        rate, amp = abs(mech.omega1), 0.5 * (hi - lo)
        return (amp * rate * np.sin(rate * t))[:, None], (amp * rate ** 2 * np.cos(rate * t))[:, None]
    cranks = ("2", "4") if built.name == "fivebar" else ("1",)
    speed = np.column_stack([getattr(mech, f"omega{c}") + getattr(mech, f"alpha{c}") * t for c in cranks])
    accel = np.column_stack([np.full_like(t, getattr(mech, f"alpha{c}")) for c in cranks])
    return speed, accel


def controls(built: Built, t: np.ndarray) -> np.ndarray:
    """The controls at times t, shape (len(t), nu): each crank servo's command, then the load switch
    (1 on, 0 off: on throughout, or the shaper's cutting stroke only).

    A velocity servo tau = kv (c - omega) driving its rotor (armature J) lags a changing speed by
    alpha J / kv; the command c = omega + alpha J / kv feeds that lag forward, so an accelerating or
    rocking crank follows its desired motion as closely as a steady one."""
    speed, accel = desired_motion(built, t)
    model = built.model
    lead = [model.dof_armature[model.jnt_dofadr[model.actuator(n).trnid[0]]] / model.actuator(n).gainprm[0]
            for n in built.cranks]
    return np.column_stack([speed + accel * np.array(lead), load_switch(built, t)])


def load_switch(built: Built, t: np.ndarray) -> np.ndarray:
    """1 where the external load acts, else 0. The shaper's cutting stroke is the slow one, while the
    commanded crank angle lies between the limit positions -psi and pi + psi (counter-clockwise)."""
    if not built.loads.cutting_only:
        return np.ones_like(t)
    from analytic import sixbar
    mech = built.mech
    psi = sixbar.figures(mech).psi
    phi = mech.phi1_0 + mech.omega1 * t + 0.5 * mech.alpha1 * t * t
    return (np.mod(phi + psi, 2 * np.pi) <= np.pi + 2 * psi).astype(float)


def simulate(built: Built, revolutions: float = 1.0) -> Trajectory:
    """Simulate ``revolutions`` turns of the first crank; every loop starts closed (analytic state)."""
    model = built.model
    h = model.opt.timestep
    end = duration(built.mech, revolutions)
    nstep = int(math.ceil(end / h - 1e-9)) + 1          # sensors of step k are at t = k h; include t_end
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("home").id)
    mujoco.mj_forward(model, data)
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    state0 = np.empty(mujoco.mj_stateSize(model, spec))
    mujoco.mj_getState(model, data, state0, spec)
    ctrl = controls(built, np.arange(nstep) * h)[None]
    desired = desired_motion(built, np.arange(nstep) * h)[0]
    commanded = {f"omega{c}": desired[:, i] for i, c in enumerate(("2", "4") if built.name == "fivebar" else ("1",))}
    t0 = time.process_time()
    states, sens = rollout.rollout(model, data, state0[None], ctrl, nstep=nstep)
    cpu = time.process_time() - t0
    sens = sens[0]
    # states[k] follows step k (time (k+1) h); the sensors of step k see the state before it.
    nq, nv = model.nq, model.nv
    qpos = np.concatenate([state0[None, 1:1 + nq], states[0, :-1, 1:1 + nq]])
    qvel = np.concatenate([state0[None, 1 + nq:1 + nq + nv], states[0, :-1, 1 + nq:1 + nq + nv]])
    inputs, outputs, viol, forces = _MEASURE[built.name](model, sens)
    _check_run(built, sens, inputs, viol)
    return Trajectory(built.name, h, _integrator_name(model), nstep, cpu, _sensor(model, sens, "time")[:, 0],
                      inputs, outputs, viol, forces,
                      commanded,
                      _sensor(model, sens, "load")[:, 0], qpos, qvel,
                      tuple(model.joint(i).name for i in range(model.njnt)))


def energies(built: Built, tr: Trajectory) -> tuple[np.ndarray, np.ndarray]:
    """MuJoCo's kinetic and potential energy [J] at every recorded state (armature included).

    Computed by mj_forward on each recorded state after the run: MuJoCo's energy sensors, read during an
    RK4 step, are not evaluated at the step's initial state (measured: 1e-4 J off for the four-bar).
    """
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


def _integrator_name(model) -> str:
    from .model import INTEGRATORS
    return next(k for k, v in INTEGRATORS.items() if v == model.opt.integrator)


def _check_run(built: Built, sens: np.ndarray, inputs: dict, viol: np.ndarray) -> None:
    scale = max(v for k, v in vars(built.mech).items() if k[0] == "l" and isinstance(v, float))
    bad = ~np.all(np.isfinite(sens), axis=1) | ~(viol <= LOOP_BOUND * scale)
    if bad.any():
        k = int(np.argmax(bad))
        crank = "phi" + FIRST_CRANK[built.name]
        angle = inputs[crank][k] if np.isfinite(inputs[crank][k]) else float("nan")
        what = "diverged" if not np.all(np.isfinite(sens[k])) else f"opened a loop by {viol[k]:.3g} m"
        raise SimulationError(
            f"the {built.name} simulation {what} at t={k * built.model.opt.timestep:.4f} s "
            f"({crank}={math.degrees(angle):.2f}deg); try a smaller --timestep")
