"""A cylinder drives the linkage by a force law: the reduced equation of motion of a one-input mechanism whose
input is an actuator (a hydraulic cylinder) pushed by a pressure-limited, flow-limited supply.

The supply: the pump's pressure p on the push area A = pi bore^2 / 4 gives the stall force F0 = p A; its flow
Q limits the rod's speed to v0 = Q / A. Between the two the force falls linearly with the speed (the supply's
line, as a motor's torque with its speed: :class:`analytic.applications.motor.LinearMotor`):

    F(v) = F0 (1 - v / v0)

With the cylinder's length s the one coordinate and v = ds/dt, the kinetic energy is T = J(s) v^2 / 2 and
Lagrange's equation is

    J(s) dv/dt + J'(s) v^2 / 2 = F(v) + Q(s)

J, J' and Q (the loads' generalized force: gravity, the force on the output point) are the crank's
(:func:`analytic.applications.motor._terms`), from the kinematic coefficients at unit rod speed: no finite
differences. The run starts at rest at the file's start length l0 and ends where the rod reaches the end of
its stroke it moves toward (or stalls: F(v) + Q(s) <= 0 at rest).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic._common import ParameterError

__all__ = ["Supply", "CylinderRun", "supply", "run"]


@dataclass(frozen=True)
class Supply:
    """The cylinder's supply line: stall force ``F0`` [N] (pressure times push area) and free speed ``v0``
    [m/s] (flow over push area)."""

    F0: float
    v0: float

    def force(self, v):
        return self.F0 * (1.0 - np.asarray(v, dtype=float) / self.v0)


def supply(e: dict, pressure: float, flow: float) -> Supply:
    """The supply of actuator ``e`` (its resolved entry, SI) at ``pressure`` [Pa] and ``flow`` [m^3/s]: F0 = p A,
    v0 = Q / A on the push area pi bore^2 / 4 (the file's bore)."""
    bore = e["bore"]
    if not bore > 0:
        raise ParameterError(f"actuator {e['name']!r} has no bore: give its bore (a diameter) to drive it by a "
                             f"pressure")
    if not (math.isfinite(pressure) and pressure > 0 and math.isfinite(flow) and flow > 0):
        raise ParameterError(f"the supply's pressure {pressure!r} Pa and flow {flow!r} m^3/s must be > 0")
    area = math.pi * bore * bore / 4
    return Supply(pressure * area, flow / area)


@dataclass(frozen=True)
class CylinderRun:
    """The run: times [s], the cylinder's length s [m], speed v [m/s] and force F(v) [N] at each output time,
    and why it ended (``"stroke"``: the rod reached the end of its stroke; ``"time"``: the time limit)."""

    t: np.ndarray
    s: np.ndarray
    v: np.ndarray
    force: np.ndarray
    end: str
    dense: object = None
    """(s, v) at any time of the run: the integrator's dense output, ``dense(t)`` of shape (2, len(t))."""
    J_min: float = 0.0
    """The least reduced mass over the run [kg] (for the simulation's time step)."""


def _terms(mech, s, inertias, gravity, force):
    from analytic.applications import motor as amotor
    J, dJ, Qg, _, QF, _ = amotor._terms(mech, np.atleast_1d(s) - mech.inputs[0].motion.q0, 1.0,
                                        mech.inputs[0].motion.q0, inertias, 0.0, gravity, force)
    return J, dJ, Qg + QF


def run(mech, inertias: dict, drive: Supply, gravity=(0.0, 0.0), force=(0.0, 0.0), t_max: float = 60.0,
        samples: int = 401, rtol: float = 1e-10) -> CylinderRun:
    """The linkage pushed out by its cylinder from rest at its start length until the rod reaches the extended
    end of its stroke (or ``t_max`` [s]), ``samples`` output times evenly spaced over the run."""
    from scipy.integrate import solve_ivp
    if len(mech.inputs) != 1 or mech.inputs[0].kind != "actuator":
        raise ParameterError(f"the {mech.name} is not driven by one actuator: a cylinder's supply drives a "
                             f"mechanism whose one input is an actuator")
    e = next(x for x in mech.geometry.elements if x["kind"] == "actuator")
    lo, hi = e["stroke"]
    l0 = mech.inputs[0].motion.q0
    J0, _, Q0 = _terms(mech, l0, inertias, gravity, force)
    if not J0[0] > 0:
        raise ParameterError(f"the {mech.name}'s reduced mass vanishes (massless links): give the links masses")
    if drive.F0 + Q0[0] <= 0:
        raise ParameterError(f"the supply's stall force {drive.F0:.4g} N does not lift the load at the start "
                             f"({-Q0[0]:.4g} N): raise the pressure")

    def rhs(_, y):
        J, dJ, Q = _terms(mech, y[0], inertias, gravity, force)
        return [y[1], (float(drive.force(y[1])) + Q[0] - 0.5 * dJ[0] * y[1] * y[1]) / J[0]]

    def at_end(_, y):
        return y[0] - hi
    at_end.terminal, at_end.direction = True, 1.0
    sol = solve_ivp(rhs, (0.0, t_max), [l0, 0.0], method="DOP853", rtol=rtol, atol=rtol * max(hi, 1e-9),
                    events=at_end, dense_output=True)
    if not sol.success:
        raise ParameterError(f"the {mech.name}'s cylinder run failed: {sol.message}")
    t_end = float(sol.t[-1])
    t = np.linspace(0.0, t_end, samples)
    s, v = sol.sol(t)
    J, _, _ = _terms(mech, s, inertias, gravity, force)
    return CylinderRun(t, s, v, drive.force(v), "stroke" if sol.status == 1 else "time", sol.sol, float(J.min()))
