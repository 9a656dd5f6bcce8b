"""The loads in the reduced equation of a motor-driven mechanism (analytic.applications.motor): each load's
generalized force on the input's advance u, by virtual work (analytic.loads.kinetostatics.generalized).

Forces, torques, pressures, springs and torsion springs depend on the pose only (a ``stroke`` condition reads
the point's direction of motion, which for an input turning forward is the sign of its velocity coefficient):
their sum is QL(u). A damper's generalized force is linear in the speed: -C(u) w with C(u) >= 0 its
coefficient at unit speed. Both are tabulated on a periodic grid and interpolated linearly (a load that
switches on and off has jumps a trigonometric interpolant would ring at). Loads that read the speed or the
time in an expression, and Coulomb friction (its torque depends on the reactions, hence on the accelerations
it produces), are refused with one line.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic.loads.common import LoadError, State

GRID = 8192
"""Grid points per turn: linear interpolation of a smooth QL errs by (2 pi / GRID)^2 / 8 |QL''| ~ 7e-8 of its
scale, below the 1e-6 the motor runs are compared to."""


SMOOTH_TOL = 1e-10
"""[of the loads' scale] Where the trigonometric interpolant of QL and C matches the loads at every midpoint
of the grid to this, it is used (smooth, so the integrator keeps its long steps); otherwise the loads have
jumps or kinks (an active range, a stroke, a table) and are interpolated linearly."""


@dataclass(frozen=True)
class Terms:
    """QL(u) [N m] and C(u) [N m s] on the grid u_k = 2 pi k / GRID (k < GRID), periodic; per load its
    QL or C (by name); ``smooth``: their trigonometric interpolants (None: linear interpolation)."""

    u: np.ndarray
    QL: np.ndarray
    C: np.ndarray
    per_load: dict
    smooth: tuple | None = None

    def at(self, u):
        """(QL, C) at advances ``u`` (periodic)."""
        p = np.mod(u, 2 * math.pi)
        if self.smooth is not None:
            return self.smooth[0](p), self.smooth[1](p)
        return (np.interp(p, self.u, self.QL, period=2 * math.pi), np.interp(p, self.u, self.C, period=2 * math.pi))

    def scalar(self, u: float):
        p = u % (2 * math.pi)
        if self.smooth is not None:
            return self.smooth[0].scalar(p), self.smooth[1].scalar(p)
        x = p / (2 * math.pi) * len(self.u)
        k = int(x) % len(self.u)
        f = x - int(x)
        k1 = (k + 1) % len(self.u)
        return (self.QL[k] + f * (self.QL[k1] - self.QL[k]), self.C[k] + f * (self.C[k1] - self.C[k]))


def check(mech, loadset) -> None:
    """Refuse what the reduced equation cannot carry (one line naming the load)."""
    if loadset.friction:
        raise LoadError("[friction]: dynamics cannot carry Coulomb friction yet: a pin's torque mu r |F| follows "
                        "its reaction F = A(u) phi'' + B(u) phi'^2 + C(u), so the reduced equation becomes implicit "
                        "in phi'' (planned: solve it per step from the tabulated A, B, C, issue 41); meanwhile "
                        "`linkage forces` gives the friction losses along the prescribed motion, or remove [friction]")
    rates = {"t"} | {n for inp in mech.inputs for n in (inp.qd,)} | {f"omega{k + 1}" for k in range(len(mech.inputs))} \
        | {f"ds{k + 1}" for k in range(len(mech.inputs))}
    for ld in loadset.loads:
        used = sorted(ld.rates_read() & rates)
        if used:
            raise LoadError(f"load {ld.name}: its magnitude reads {', '.join(used)}; the reduced equation takes loads "
                            f"of the pose only (and dampers); write it in the input angle")


def terms(mech, loadset, s: float, q0: float, n: int = GRID) -> Terms:
    """The loads' terms of the reduced equation on the advance u in [0, 2 pi) (input angle q0 + s u)."""
    from analytic.periodic import Trig as _Trig
    check(mech, loadset)
    u, QL, C, per = _evaluate(mech, loadset, s, q0, np.linspace(0.0, 2 * math.pi, n + 1), closed=True)
    um, QLm, Cm, _ = _evaluate(mech, loadset, s, q0, u + math.pi / n)
    tq, tc = _Trig(QL), _Trig(C)
    err = max(float(np.max(np.abs(tq(um) - QLm))) / max(float(np.max(np.abs(QL))), 1e-300),
              float(np.max(np.abs(tc(um) - Cm))) / max(float(np.max(np.abs(C))), 1e-300) if np.any(C) else 0.0)
    smooth = (tq, tc) if err <= SMOOTH_TOL and not (tq.full or tc.full) else None
    return Terms(u, QL, C, per, smooth)


def _evaluate(mech, loadset, s, q0, u, closed: bool = False):
    """(u, QL, C, per load) at the advances ``u``; ``closed``: ``u`` ends a turn after it starts (its last
    point is checked to repeat the first and dropped)."""
    from analytic.loads import scales
    from analytic.loads.kinetostatics import full_wanted, generalized
    n = len(u) - 1
    q = q0 + s * u
    qd = np.full_like(u, s)
    sol = mech.solve(q, qd, 0.0, outputs=full_wanted(mech))
    sol = {k: np.asarray(sol[k]) for k in full_wanted(mech)}
    state = State(mech, sol, q, qd, np.zeros_like(u))
    variables = state.variables(scales(mech.definition, mech.parameters))
    QL, C = np.zeros(n + 1), np.zeros(n + 1)
    per = {}
    coefficients = None
    if len(mech.inputs) == 1:         # the velocities at the input's unit rate s (s = +-1), no acceleration:
        coefficients = ({k: v / s for k, v in sol.items() if k.startswith(("vx", "vy", "omega"))},)   # exact
    for ld in loadset.loads:
        try:
            apps = ld.applications(state, variables)
        except ValueError as exc:                  # an expression not finite along the turn (1/sin(phi1))
            raise LoadError(f"load {ld.name}: {exc}") from None
        Q = s * generalized(mech, q, state, apps, coefficients)[mech.inputs[0].link]       # on u, at unit speed
        if ld.speed_linear:
            C = C - Q
        else:
            QL = QL + Q
        per[ld.name] = Q[:-1] if closed else Q
        if closed and not abs(Q[-1] - Q[0]) <= 1e-9 * max(1.0, float(np.max(np.abs(Q)))):
            raise LoadError(f"load {ld.name} does not repeat after a turn of {mech.inputs[0].q} (a torsion spring "
                            f"wound by a full turn, or a table over part of a turn): the motor's steady state needs "
                            f"loads that repeat every turn")
    if closed:
        return u[:-1], QL[:-1], C[:-1], per
    return u, QL, C, per
