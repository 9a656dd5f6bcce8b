"""A motor drives the linkage (the app's Dynamics tab, the loads its Forces tab applies; public API): the
reduced equation's run under a linear motor, MuJoCo's run of the same model when it is affordable, and the
record both are reported as (SPEC "Dynamics under a motor"). ``linkage dynamics`` runs the same functions of
:mod:`sim.run.motor`; MuJoCo is imported only when a run is simulated."""

from __future__ import annotations

import numpy as np


def run_loads(gravity=None, force=(0.0, 0.0), slow_stroke_only: bool = False):
    """What acts on the mechanism besides its drives (:class:`sim.model.Loads`): ``gravity`` (gx, gy)
    [m/s^2] or None, ``force`` (Fx, Fy) [N] on the output point, on its slow stroke only where asked (a
    cutting force); the file's ``[[loads]]`` are added by the runs themselves."""
    from sim.model import Loads
    return Loads(gravity=gravity, force=force, slow_stroke_only=slow_stroke_only)


def linear_motor(stall_torque: float, no_load_speed: float):
    """tau = T0 (1 - omega / W0): stall torque [N m], no-load speed [rad/s]."""
    from analytic.applications.motor import LinearMotor
    return LinearMotor(float(stall_torque), float(no_load_speed))


def reduced_run(mech, loads, motor, flywheel: float | None = 0.0, target: float | None = None,
                start_speed: float = 0.0, revolutions: float = 10.0):
    """The reduced equation's answer (a :class:`sim.run.motor.Dynamics` without MuJoCo's run): ``flywheel``
    [kg m^2] added to the input, or None with ``target`` the fluctuation Cs to size it for."""
    from sim.run import motor as smotor
    return smotor.dynamics(mech, loads, motor, flywheel, target, start_speed, revolutions, simulate_too=False)


def mujoco_steps(d, motor) -> tuple[float, float]:
    """(steps, step [s]) MuJoCo would take to run ``d``'s duration: what a front end bounds before it asks."""
    from sim.run import motor as smotor
    h = smotor.timestep_for(d.mech, d.run.reduced, motor, float(np.max(np.abs(d.run.omega))))
    return float(d.run.t[-1]) / h, h


def simulated(d, loads, start_speed: float = 0.0):
    """``d`` with MuJoCo's run of the same model and the agreement of both."""
    from sim.run import motor as smotor
    return smotor.simulated(d, loads, start_speed)


def record(d) -> dict:
    """``linkage dynamics --json``'s record of ``d`` (SI)."""
    from sim.run import motor as smotor
    return smotor.record(d)
