"""MuJoCo's answer under a cylinder's supply: the generated model (:func:`sim.model.build`) with its actuator
input's position servo turned into the supply's force line (:mod:`analytic.applications.cylinder`), run from
rest at the start length until the rod reaches the end of its stroke (or the analytic run's duration), and
its agreement with the reduced equation.

The drive actuator keeps its compiled form (an integrator activation held at 1 times a fixed gain, plus an
affine bias): force = gain + bias2 qdot, so gain = F0 and bias2 = -F0 / v0 is the supply's F0 (1 - v / v0)
along the slide, evaluated by the integrator at every stage. The slide's armature (the servo's rotor, a
numerical aid of the prescribed runs) is removed: the supply pushes the linkage's own inertia.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import mujoco
import numpy as np

from analytic import ParameterError
from sim import model as M
from sim.model.armature import set_armature

STEP_FRACTION = 0.25
"""The time step is at most this fraction of the supply's time constant J_min / (F0 / v0) (how fast the rod
reaches its speed: a stiff line on a light linkage), and at most the prescribed run's step."""


@dataclass(frozen=True)
class CylinderSim:
    """MuJoCo's run: times [s], the cylinder's length s [m] and speed v [m/s] at each step, the supply's force
    [N], the largest loop violation [m], the time step [s]."""

    t: np.ndarray
    s: np.ndarray
    v: np.ndarray
    force: np.ndarray
    loop_violation: float
    timestep: float


def timestep_for(mech, J_min: float, drive, settings=M.Settings()) -> float:
    """The step: the prescribed model's (its rates' scan), at most STEP_FRACTION of J_min / (F0 / v0)."""
    if settings.timestep is not None:
        return settings.timestep
    h = M.choose_timestep(mech)
    return min(h, STEP_FRACTION * J_min / (drive.F0 / drive.v0))


def simulate(mech, loads, drive, t_end: float, hi: float, J_min: float, settings=M.Settings()) -> CylinderSim:
    """The supply-driven model of ``mech`` (one actuator input) with ``loads`` from rest, until the length
    reaches ``hi`` or the time ``t_end`` [s]."""
    h = timestep_for(mech, J_min, drive, settings)
    built = M.build(mech, replace(settings, timestep=h), loads, native=True)
    model = built.model
    d = built.drives[0]
    set_armature(model, d.joint, 0.0)
    act = model.actuator(d.actuator)
    act.gainprm[0] = drive.F0
    act.biasprm[:3] = [0.0, 0.0, -drive.F0 / drive.v0]
    data = mujoco.MjData(model)
    data.qpos[:] = built.qpos0
    data.qvel[:] = 0.0
    data.act[:] = 0.0
    data.act[act.actadr[0]] = 1.0
    data.ctrl[:] = 0.0
    jid = model.joint(d.joint).id
    qadr, vadr = model.jnt_qposadr[jid], model.jnt_dofadr[jid]
    T, S, V = [], [], []
    viol = 0.0
    limit = int(20_000_000)
    while True:
        s, v = data.qpos[qadr] + d.q_offset, data.qvel[vadr]
        T.append(data.time)
        S.append(s)
        V.append(v)
        for lp in built.loops:
            viol = max(viol, float(np.linalg.norm(data.site(lp.site1).xpos - data.site(lp.site2).xpos)))
        if s >= hi or data.time >= t_end - 0.5 * h or len(T) > limit:
            break
        mujoco.mj_step(model, data)
        if not np.all(np.isfinite(data.qvel)):
            raise ParameterError(f"the {mech.name} cylinder run diverged at t={data.time:.4g} s")
    V = np.array(V)
    return CylinderSim(np.array(T), np.array(S), V, drive.force(V), viol, h)
