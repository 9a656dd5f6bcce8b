"""A motor drives the linkage: the reduced (Eksergian) equation of motion of a one-input mechanism.

With the input angle's advance u = s (q - q0) (s the sign of the input's motion law, so u grows in the
direction the input turns) as the one generalized coordinate and w = du/dt, the kinetic energy is
T = J(u) w^2 / 2 and Lagrange's equation is

    J(u) w' + J'(u) w^2 / 2 = tau_motor(w) + Q(u)                                   (Eksergian)

    J(u)  = J_fly + sum_k [ m_k |dG_k/du|^2 + I_k (dtheta_k/du)^2 ]
    J'(u) = 2 sum_k [ m_k dG_k/du . d2G_k/du2 + I_k dtheta_k/du d2theta_k/du2 ]
    Q(u)  = sum_k m_k g . dG_k/du + on(u) F . dP/du              (the loads' generalized force)

The kinematic coefficients dG/du, dtheta/du are the solver's velocities at unit input speed and
d2G/du2, d2theta/du2 its accelerations at unit speed with zero input acceleration (``mech.solve(q, s,
0)``): no finite differences. J_fly is the flywheel plus the drive's rotor inertia on the input link; g the
gravity in the plane; F the force on the output point P, on throughout or only inside a window of the
input's phase (a cutting stroke), so Q jumps where the window opens and closes.

J and Q are evaluated in closed form on a grid over one turn and represented by their trigonometric
(Fourier) interpolants, smooth and periodic like the functions themselves; J' in the equation is the
derivative of J's interpolant, so that the conservative system keeps J w^2 / 2 exactly and the right-hand
side is smooth for the high-order integrator. The grid is refined until the interpolants match the closed
form at every midpoint, and J's derivative matches the closed-form J' at every node, to INTERP_TOL. The equation is
integrated by scipy's ``solve_ivp`` (DOP853, tight tolerances, dense output) in segments that end where
the load switches, at the start of the last revolution and at the end of the run.

Two cranks with a motor each (the five-bar): M(q) q'' + h(q, q') = tau(q') + Q(q) with the 2x2 reduced
mass matrix M_ij = sum m dG/du_i . dG/du_j + I dtheta/du_i dtheta/du_j and h the velocity-product
torques from the solver's accelerations at the current speeds with zero input accelerations
(:func:`mass_matrix`, :func:`run_two`), evaluated in closed form at every step (no grid on the torus).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from analytic._common import ParameterError
from analytic.applications.torque import _com
from analytic.periodic import Trig as _Trig

if TYPE_CHECKING:   # scipy.integrate is imported by the functions that integrate: loading it costs ~0.6 s of CPU
    from scipy.integrate import OdeSolution     # and ~40 MB, and the app imports this module at its start

__all__ = ["LinearMotor", "TableMotor", "Coast", "Reduced", "Run", "Run2", "Stall", "reduce", "run", "steady_cycle",
           "size_flywheel", "mass_matrix", "run_two", "STARTUP_FRACTION"]

STARTUP_FRACTION = 0.95
"""The start-up time is when the speed first reaches this fraction of the steady mean speed (SPEC)."""
INTERP_TOL = 1e-11
"""Largest mismatch of the interpolants of J and Q with the closed form at the grid's midpoints,
relative to max J and to the loads' scale: far below the 1e-6 the answers are checked to."""
INTERP_FAIL = 1e-8
"""Past this mismatch at the finest grid the design is refused (a pose too close to singular, or J' and J
disagreeing, which would be a bug)."""
GRID_MIN, GRID_MAX = 512, 65536
"""Grid points per turn of the input: the first try and the most (a design near a singular pose)."""
RTOL = 1e-12
"""solve_ivp's relative tolerance: the energy of the conservative system then drifts < 1e-9 over 100
revolutions (tests/test_dynamics_motor.py)."""


# ------------------------------------------------------------------------------------------ motors
@dataclass(frozen=True)
class LinearMotor:
    """A DC-like motor: tau = T0 (1 - w / W0); stall torque ``T0`` [N m], no-load speed ``W0`` [rad/s]."""

    T0: float
    W0: float

    def __post_init__(self):
        for name in ("T0", "W0"):
            v = getattr(self, name)
            what = "stall torque [N m]" if name == "T0" else "no-load speed [rad/s]"
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ParameterError(f"--motor {name}={v!r}: the {what} must be a finite number > 0 "
                                     f"(e.g. --motor 2,150rpm)")

    def torque(self, w):
        """Motor torque [N m] at speed ``w`` [rad/s] (array)."""
        return self.T0 * (1.0 - np.asarray(w, float) / self.W0)

    def affine(self, w):
        """(a, b) with torque = a + b w on the curve's piece that holds ``w``."""
        return self.T0, -self.T0 / self.W0

    @property
    def stall(self) -> float:
        return float(self.T0)

    @property
    def free_speed(self) -> float:
        return float(self.W0)


@dataclass(frozen=True)
class Coast:
    """No motor torque at all (the linkage coasts): for the conservation-of-energy check. ``W`` [rad/s]
    only scales the integrator's absolute tolerance."""

    W: float = 1.0

    def torque(self, w):
        return np.zeros_like(np.asarray(w, float))

    def affine(self, w):
        return 0.0, 0.0

    @property
    def stall(self) -> float:
        return 0.0

    @property
    def free_speed(self) -> float:
        return float(self.W)


@dataclass(frozen=True)
class TableMotor:
    """A torque-speed table: ``omega`` [rad/s] strictly increasing from 0, ``tau`` [N m]; linear between
    rows and extended along the last piece beyond the last row."""

    omega: tuple
    tau: tuple
    source: str = "the table"

    def __post_init__(self):
        w, t = np.asarray(self.omega, float), np.asarray(self.tau, float)
        if w.ndim != 1 or len(w) < 2 or w.shape != t.shape:
            raise ParameterError(f"{self.source}: give at least two rows of omega,tau")
        if not (np.all(np.isfinite(w)) and np.all(np.isfinite(t))):
            raise ParameterError(f"{self.source}: every omega and tau must be a finite number")
        bad = np.flatnonzero(np.diff(w) <= 0)
        if len(bad):
            raise ParameterError(f"{self.source}: row {bad[0] + 2}: omega must increase strictly down the table")
        if w[0] != 0.0:
            raise ParameterError(f"{self.source}: row 1: the first omega must be 0 (the stall torque)")
        if t[0] <= 0:
            raise ParameterError(f"{self.source}: row 1: the stall torque tau={t[0]:g} must be > 0 [N m]")
        if t[-1] >= t[-2] and t[-1] > 0:
            raise ParameterError(f"{self.source}: the last rows must fall (a motor's torque drops with speed); "
                                 f"add a row at the no-load speed with tau=0")

    def _piece(self, w):
        w_tab = np.asarray(self.omega, float)
        return np.clip(np.searchsorted(w_tab, w, side="right") - 1, 0, len(w_tab) - 2)

    def affine(self, w):
        w_tab, t_tab = np.asarray(self.omega, float), np.asarray(self.tau, float)
        k = self._piece(np.asarray(w, float))
        b = (t_tab[k + 1] - t_tab[k]) / (w_tab[k + 1] - w_tab[k])
        return t_tab[k] - b * w_tab[k], b

    def torque(self, w):
        a, b = self.affine(w)
        return a + b * np.asarray(w, float)

    @property
    def stall(self) -> float:
        return float(self.tau[0])

    @property
    def free_speed(self) -> float:
        a, b = self.affine(self.omega[-1])
        return float(-a / b) if b < 0 else float(self.omega[-1])


# ------------------------------------------------------------------------------------- reduced terms
@dataclass(frozen=True)
class Reduced:
    """The reduced terms of a one-input mechanism over one turn of its input (see the module docstring).

    ``J(u)``, ``dJ(u)`` [kg m^2, kg m^2/rad], ``Q(u)`` [N m] take the input's advance u [rad] (any real;
    periodic). ``window``: the phase interval of q - q0 [rad] where the force acts (as sim's load switch
    reads it), None when it always does. ``interp_error``: the midpoint check's largest relative mismatch."""

    name: str
    q0: float
    direction: float
    flywheel: float
    grid: int
    interp_error: float
    window: tuple[float, float] | None
    _J: _Trig = field(repr=False)
    _Qg: _Trig = field(repr=False)
    _QF: _Trig = field(repr=False)
    loads: object = field(default=None, repr=False)
    """The file's loads' terms (:class:`analytic.loads.reduced.Terms`): QL(u) added to Q and a damping
    -C(u) w; None without loads."""

    def J(self, u):
        return self._J(np.mod(u, 2 * math.pi))

    def dJ(self, u):
        return self._J(np.mod(u, 2 * math.pi), 1)

    def on(self, u):
        """1 where the force acts at advance ``u``, else 0."""
        if self.window is None:
            return np.ones_like(np.asarray(u, float))
        lo, hi = self.window
        p = np.mod(self.direction * np.asarray(u, float), 2 * math.pi)
        return (((p >= lo) & (p <= hi)) | ((p + 2 * math.pi >= lo) & (p + 2 * math.pi <= hi))).astype(float)

    def Q(self, u):
        """The loads' generalized force at rest [N m] (a damper's, -C(u) w, is apart: :meth:`damping`)."""
        p = np.mod(u, 2 * math.pi)
        out = self._Qg(p) + self.on(u) * self._QF(p)
        if self.loads is not None:
            out = out + self.loads.at(u)[0]
        return out

    def damping(self, u):
        """C(u) [N m s]: the dampers' generalized force is -C(u) w (0 without dampers)."""
        return self.loads.at(u)[1] if self.loads is not None else np.zeros_like(np.asarray(u, float))

    def switches(self) -> np.ndarray:
        """Advances in [0, 2 pi) where the force switches on or off (empty when it never does)."""
        if self.window is None:
            return np.empty(0)
        # on() changes only where the phase passes an end of the window or wraps at 0 (a window that
        # reaches outside [0, 2 pi) switches there); keep the candidates where it does change
        c = np.unique(np.mod(self.direction * np.array([self.window[0], self.window[1], 0.0]), 2 * math.pi))
        eps = 1e-9
        return c[self.on(c - eps) != self.on(c + eps)]

    def quasi_static(self, n: int = 4096) -> tuple[float, float]:
        """(largest torque [N m] the loads oppose over a turn, the advance [rad] where it peaks)."""
        u = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
        need = -self.Q(u)
        k = int(np.argmax(need))
        return float(need[k]), float(u[k])

    def angle(self, u):
        """The input's angle q [rad] at advance u."""
        return self.q0 + self.direction * np.asarray(u, float)


def _terms(mech, u, s, q0, inertias, flywheel, gravity, force):
    """J, dJ, Qg, dQg, QF, dQF at advances u (closed form from the kinematic coefficients)."""
    q = (q0 + s * u)[:, None]
    c = mech.solve(q, s, 0.0)
    origins = mech.link_origins
    gx, gy = gravity
    fx, fy = force
    J = np.full(len(u), float(flywheel))
    dJ, Qg, dQg = np.zeros(len(u)), np.zeros(len(u)), np.zeros(len(u))
    for link, b in inertias.items():
        vx, vy, ax, ay = _com(c, origins[link], link, b)
        w, a = c["omega" + link], c["alpha" + link]
        J = J + b.m * (vx * vx + vy * vy) + b.I * w * w
        dJ = dJ + 2.0 * (b.m * (vx * ax + vy * ay) + b.I * w * a)
        Qg = Qg + b.m * (gx * vx + gy * vy)
        dQg = dQg + b.m * (gx * ax + gy * ay)
    p = mech.output_point
    QF = fx * c["vx" + p] + fy * c["vy" + p]
    dQF = fx * c["ax" + p] + fy * c["ay" + p]
    return J, dJ, Qg, dQg, QF, dQF


def reduce(mech, inertias: dict, flywheel: float = 0.0, gravity=(0.0, 0.0), force=(0.0, 0.0),
           window: tuple[float, float] | None = None, loadset=None) -> Reduced:
    """The reduced terms of ``mech`` driven at its first (only) input.

    Parameters
    ----------
    mech : analytic.Mechanism
        One crank input that turns fully.
    inertias : dict
        :class:`~analytic.mass.Inertia` per link name (links not named are massless).
    flywheel : float
        Flywheel plus rotor inertia on the input link [kg m^2], >= 0.
    gravity, force : (x, y)
        Gravity in the plane [m/s^2]; force on the output point [N] (world frame).
    window : (lo, hi), optional
        Phase interval [rad] of q - q0 (as :func:`sim.model._slow_stroke` gives it) where the force acts.
    loadset : analytic.loads.LoadSet, optional
        The file's loads (SPEC "Loads"), carried by :mod:`analytic.loads.reduced`.
    """
    if len(mech.inputs) != 1:
        raise ParameterError(f"the {mech.name} has {len(mech.inputs)} inputs; the reduced equation of one "
                             f"coordinate needs one (two cranks: run_two, a motor on each)")
    inp = mech.inputs[0]
    if not inp.angular:
        raise ParameterError(f"the {mech.name}'s input {inp.q} is a {inp.kind} (a length); a motor drives an "
                             f"angle (a crank, a motor)")
    if not (isinstance(flywheel, (int, float)) and math.isfinite(flywheel) and flywheel >= 0):
        raise ParameterError(f"--flywheel {flywheel!r} must be a finite number >= 0 [kg m^2]")
    unknown = set(inertias) - set(mech.links)
    if unknown:
        raise ParameterError(f"no link named {', '.join(sorted(unknown))} in the {mech.name}; links: "
                             f"{', '.join(mech.links)}")
    s = 1.0 if inp.motion.rate >= 0 else -1.0
    q0 = float(inp.motion.q0)
    if window is not None:
        window = (float(window[0]), float(window[1]))
    n = GRID_MIN
    while True:
        u = np.linspace(0.0, 2 * math.pi, n + 1)
        J, dJ, Qg, dQg, QF, dQF = _terms(mech, u, s, q0, inertias, flywheel, gravity, force)
        if not np.all(np.isfinite(J)):
            k = int(np.argmax(~np.isfinite(J)))
            raise ParameterError(f"the {mech.name} cannot be assembled at {inp.q}={math.degrees(q0 + s * u[k]):.2f}deg; "
                                 f"a motor drives a crank that turns fully: check its proportions")
        if not np.all(J > 0):
            k = int(np.argmin(J))
            raise ParameterError(f"the {mech.name}'s reduced inertia vanishes at {inp.q}={math.degrees(q0 + s * u[k]):.2f}deg "
                                 f"(massless links and no flywheel): the motor's equation is singular there; give "
                                 f"--flywheel or the links masses")
        if not np.allclose([J[-1], Qg[-1], QF[-1]], [J[0], Qg[0], QF[0]], rtol=1e-9, atol=1e-12 * (1 + J.max())):
            raise ParameterError(f"the {mech.name} does not repeat after one turn of {inp.q}; a motor drives a "
                                 f"mechanism whose motion repeats every turn")
        sJ, sQg, sQF = _Trig(J[:-1]), _Trig(Qg[:-1]), _Trig(QF[:-1])
        mid = 0.5 * (u[1:] + u[:-1])
        Jm, _, Qgm, _, QFm, _ = _terms(mech, mid, s, q0, inertias, flywheel, gravity, force)
        qscale = max(float(np.abs(Qg).max() + np.abs(QF).max()), 1e-300)
        jscale = float(J.max())
        fine = {k: (f.grid(2 * n), f.grid(2 * n, 1)) for k, f in (("J", sJ), ("Qg", sQg), ("QF", sQF))}
        err = max(float(np.max(np.abs(fine["J"][0][1::2] - Jm)) / jscale),
                  float(np.max(np.abs(fine["J"][1][0::2] - dJ[:-1])) / jscale),
                  float(np.max(np.abs(fine["Qg"][0][1::2] - Qgm) + np.abs(fine["QF"][0][1::2] - QFm)) / qscale),
                  float(np.max(np.abs(fine["Qg"][1][0::2] - dQg[:-1]) + np.abs(fine["QF"][1][0::2] - dQF[:-1]))
                        / qscale))
        full = sJ.full or sQg.full or sQF.full
        if (err <= INTERP_TOL and not full) or n >= GRID_MAX:
            break
        n *= 2
    if err > INTERP_FAIL:
        raise ParameterError(f"the {mech.name}'s inertia J(phi) cannot be represented to {INTERP_FAIL:g} over a "
                             f"turn ({err:.2g} at {n} points): it is too close to a singular pose; move it away")
    terms = None
    if loadset:
        from analytic.loads import reduced as LR
        terms = LR.terms(mech, loadset, s, q0)
    return Reduced(mech.name, q0, s, float(flywheel), n, err, window, sJ, sQg, sQF, terms)


# ----------------------------------------------------------------------------------------- the run
@dataclass(frozen=True)
class Run:
    """The motion under the motor and its design answers (SI units).

    ``t``, ``phi`` (the input angle q), ``omega`` (dq/dt), ``torque`` (the motor's, along q) sample the
    run; ``mean_speed`` = 2 pi / (time of the last full revolution) [rad/s]; ``fluctuation`` Cs =
    (w_max - w_min) / mean over that revolution; ``startup_time`` [s] when w first reaches
    STARTUP_FRACTION of the mean; ``peak_torque`` [N m], ``peak_power`` [W] of the motor over the run;
    ``energy_per_cycle`` [J] the motor's work over the last revolution. ``dense(t)`` gives (u, w, work)."""

    t: np.ndarray
    phi: np.ndarray
    omega: np.ndarray
    torque: np.ndarray
    mean_speed: float
    fluctuation: float
    w_max: float
    w_min: float
    startup_time: float
    peak_torque: float
    peak_power: float
    energy_per_cycle: float
    last_revolution: tuple[float, float]
    revolutions: float
    reduced: Reduced = field(repr=False)
    motor: object = field(repr=False)
    dense: OdeSolution = field(repr=False)

    def speed_at(self, u) -> np.ndarray:
        """w [rad/s] at advances ``u`` [rad] within the run (Newton on the dense output for t(u))."""
        u = np.asarray(u, float)
        t = np.interp(u, self.direction_u, self.t)
        for _ in range(30):
            y = self.dense(t)
            step = (y[0] - u) / np.where(y[1] > 0, y[1], np.inf)
            t = t - step
            if np.all(np.abs(step) <= 1e-15 * (1 + np.abs(t))):
                break
        return self.dense(t)[1]

    @property
    def direction_u(self) -> np.ndarray:
        """The sampled advances u [rad]."""
        return self.reduced.direction * (self.phi - self.reduced.q0)


class Stall(ParameterError):
    """The motor cannot turn the linkage over: names the angle and the torque it would need."""


def _rhs(red: Reduced, motor, on_value):
    def f(t, y):
        u, w = y[0], y[1]
        e = np.exp(1j * u * red._J.k)
        J, dJ = float((e @ red._J.c).real), float((e @ (red._J.c * 1j * red._J.k)).real)
        Q = red._Qg.scalar(u) + (on_value * red._QF.scalar(u) if on_value else 0.0)
        if red.loads is not None:
            QL, C = red.loads.scalar(u)
            Q = Q + QL - C * w
        tau = float(motor.torque(w))
        return [w, (tau + Q - 0.5 * dJ * w * w) / J, tau * w]
    return f


def run(red: Reduced, motor, revolutions: float, start_speed: float = 0.0, rtol: float = RTOL,
        samples_per_rev: int = 360) -> Run:
    """Integrate the reduced equation from advance 0 at ``start_speed`` [rad/s, >= 0] for ``revolutions``
    turns (>= 1) of the input. Raises :class:`Stall` when the speed falls to zero."""
    from scipy.integrate import OdeSolution, solve_ivp
    if not (isinstance(revolutions, (int, float)) and math.isfinite(revolutions) and 1 <= revolutions <= 1e5):
        raise ParameterError(f"--revolutions {revolutions!r} must be a number in [1, 1e5] (the last full "
                             f"revolution is the one measured)")
    if not (isinstance(start_speed, (int, float)) and math.isfinite(start_speed) and start_speed >= 0):
        raise ParameterError(f"--start-speed {start_speed!r} must be a finite number >= 0 [rad/s]")
    two_pi = 2 * math.pi
    end = two_pi * revolutions
    last0 = end - two_pi
    sw = red.switches()
    marks = [last0, end] + [k * two_pi + a for k in range(int(math.ceil(revolutions)) + 1) for a in sw]
    marks = np.unique([m for m in marks if 0 < m <= end])
    scale_w = max(motor.free_speed, start_speed, 1.0)
    atol = [rtol * two_pi, rtol * scale_w, rtol * max(motor.stall, 1e-300) * two_pi]
    y = [0.0, float(start_speed), 0.0]
    t0 = 0.0
    sols, ts, ext_t, ext_w = [], [0.0], [], []
    u_prev = 0.0
    horizon = 1e3 * end / max(scale_w, 1e-9) + 1e6
    for mark in marks:
        mid = 0.5 * (u_prev + mark)
        on_value = float(red.on(np.array([mid]))[0])
        f = _rhs(red, motor, on_value)

        def reach(t, yy, m=mark):
            return yy[0] - m
        reach.terminal, reach.direction = True, 1

        def stop(t, yy):
            return yy[1]
        stop.terminal, stop.direction = True, -1

        def turn(t, yy):
            return f(t, yy)[1]
        sol = solve_ivp(f, (t0, t0 + horizon), y, method="DOP853", rtol=rtol, atol=atol, dense_output=True,
                        events=(reach, stop, turn))
        if sol.t_events[1].size and (not sol.t_events[0].size or sol.t_events[1][0] < sol.t_events[0][0]):
            ts_ = float(sol.t_events[1][0])
            us = float(sol.y_events[1][0][0])
            need, at = red.quasi_static()
            q = math.degrees(red.angle(us))
            raise Stall(f"the motor stalls the {red.name} at phi={q:.1f}deg (t={ts_:.3g} s, after {us / two_pi:.2f} "
                        f"turns): the loads there need more than it gives; turning it over slowly needs a stall "
                        f"torque above {need:.4g} N m (peak at phi={math.degrees(red.angle(at)):.1f}deg), the "
                        f"motor has {motor.stall:.4g} N m: raise the stall torque, add a flywheel or a start speed")
        if not sol.t_events[0].size:
            raise ParameterError(f"the {red.name} did not complete {revolutions:g} turns within {horizon:.3g} s "
                                 f"({sol.message}); raise the motor's torque or speed")
        te = float(sol.t_events[0][0])
        sols.append(sol.sol)
        ts.extend(sol.sol.ts[1:])
        ext_t.extend(sol.t_events[2])
        ext_w.extend(ye[1] for ye in sol.y_events[2])
        y = list(sol.y_events[0][0])
        y[0] = mark
        t0, u_prev = te, mark
    interps = [ip for s in sols for ip in s.interpolants]
    times = np.concatenate([[sols[0].ts[0]]] + [s.ts[1:] for s in sols])
    dense = OdeSolution(times, interps)
    # samples: evenly in time within each segment, about samples_per_rev per turn
    t_s = [np.array([0.0])]
    for s in sols:
        a, b = s.ts[0], s.ts[-1]
        du = float(s(b)[0] - s(a)[0])
        k = max(2, int(math.ceil(samples_per_rev * du / two_pi)) + 1)
        t_s.append(np.linspace(a, b, k)[1:])
    t = np.concatenate(t_s)
    Y = dense(t)
    u, w = Y[0], Y[1]
    u[-1] = end
    # the last revolution
    bounds = np.array([s.ts[0] for s in sols] + [sols[-1].ts[-1]])
    ubounds = np.concatenate([[0.0], marks])
    ta = float(bounds[np.argmin(np.abs(ubounds - last0))])
    tb = float(bounds[-1])
    mean = two_pi / (tb - ta)
    inside = [float(dense(tt)[1]) for tt in bounds if ta - 1e-12 <= tt <= tb + 1e-12]
    inside += [float(ww) for tt, ww in zip(ext_t, ext_w) if ta <= tt <= tb]
    inside += list(w[(t >= ta) & (t <= tb)])
    w_max, w_min = max(inside), min(inside)
    work = float(dense(tb)[2] - dense(ta)[2])
    # start-up: first reach of STARTUP_FRACTION of the mean
    target = STARTUP_FRACTION * mean
    if w[0] >= target:
        t_up = 0.0
    else:
        k = int(np.argmax(w >= target))
        lo, hi = t[k - 1], t[k]
        for _ in range(80):
            m = 0.5 * (lo + hi)
            lo, hi = (m, hi) if dense(m)[1] < target else (lo, m)
        t_up = 0.5 * (lo + hi)
    tau = motor.torque(w)
    return Run(t=t, phi=red.angle(u), omega=red.direction * w, torque=red.direction * tau, mean_speed=mean,
               fluctuation=(w_max - w_min) / mean, w_max=w_max, w_min=w_min, startup_time=float(t_up),
               peak_torque=float(np.max(np.abs(tau))), peak_power=float(np.max(tau * w)),
               energy_per_cycle=work, last_revolution=(ta, tb), revolutions=float(revolutions), reduced=red,
               motor=motor, dense=dense)


def steady_cycle(red: Reduced, motor, guess: float | None = None, rtol: float = RTOL,
                 start_speed: float = 0.0) -> Run:
    """The periodic motion: one revolution from the start speed w0 that it returns to (a secant search
    on w(2 pi) - w0, started from a run of a few turns from ``start_speed``: rest, or the run's own start
    speed, which carries a motor too weak to turn the loads over slowly through them)."""
    from scipy.optimize import brentq

    def gap(w0):
        return run(red, motor, 1.0, w0, rtol, samples_per_rev=16).speed_at(np.array([2 * math.pi]))[0] - w0
    if guess is None:
        warm = run(red, motor, 3.0, start_speed, rtol, samples_per_rev=16)
        guess = warm.speed_at(np.array([6 * math.pi]))[0]
    w_a = guess
    g_a = gap(w_a)
    # walk to a bracket: the map u=0 -> 2 pi contracts towards the periodic speed
    step = max(abs(g_a), 1e-6 * guess)
    w_b = w_a + (step if g_a > 0 else -step)
    for _ in range(60):
        g_b = gap(w_b)
        if g_a * g_b <= 0:
            break
        w_a, g_a, step = w_b, g_b, 2 * step
        w_b = w_a + (step if g_a > 0 else -step)
        if w_b <= 0:
            w_b = 0.5 * w_a
    else:
        raise ParameterError("no steady motion found under this motor: raise its torque or add a flywheel")
    w0 = brentq(gap, min(w_a, w_b), max(w_a, w_b), xtol=1e-13 * guess, rtol=1e-13)
    return run(red, motor, 1.0, w0, rtol)


def size_flywheel(make_reduced, motor, target: float, rtol: float = 1e-10,
                  start_speed: float = 0.0) -> tuple[float, Run]:
    """The flywheel J [kg m^2] whose steady cycle has Cs = ``target``; ``make_reduced(J)`` gives the
    reduced terms with flywheel J. Returns (J, the steady cycle). J = 0 when the bare linkage already runs
    within the target. The steady cycles are reached from ``start_speed`` [rad/s] (``--start-speed``, as the
    run itself starts); a flywheel too light to carry the linkage through its loads from there (the motor
    stalls) counts as one whose Cs is above the target."""
    from scipy.optimize import brentq
    if not (isinstance(target, (int, float)) and math.isfinite(target) and 0 < target < 1):
        raise ParameterError(f"--target-fluctuation {target!r} must be a number in (0, 1) (e.g. 0.02)")
    def steady(J):
        try:
            return steady_cycle(make_reduced(J), motor, rtol=rtol, start_speed=start_speed)
        except ParameterError:
            if not start_speed:                    # from rest a stall is the linkage's, whatever the flywheel
                raise
            return None
    bare = steady(0.0)
    if bare is not None and bare.fluctuation <= target:
        return 0.0, bare
    J_scale = float(make_reduced(0.0).J(np.linspace(0, 2 * math.pi, 64)).max())
    cache = {}

    def cs(log_j):
        r = steady(math.exp(log_j))
        if r is None:                              # stalls: more flywheel needed
            return 1.0
        cache[log_j] = r
        return r.fluctuation - target
    lo, hi = math.log(J_scale * 1e-3), math.log(J_scale)
    while cs(hi) > 0:
        lo, hi = hi, hi + math.log(8.0)
        if hi > lo + 60:
            raise ParameterError(f"--target-fluctuation {target:g} cannot be reached with a flywheel")
    if cs(lo) < 0:
        lo = -60.0
    root = brentq(cs, lo, hi, xtol=1e-10, rtol=1e-10)
    return math.exp(root), cache.get(root) or steady_cycle(make_reduced(math.exp(root)), motor, rtol=rtol,
                                                           start_speed=start_speed)


# ------------------------------------------------------------------------------- two inputs, two motors
@dataclass(frozen=True)
class Run2:
    """Two motors on the two inputs (the five-bar): time [s], each input's angle q [rad], speed dq/dt
    [rad/s] and motor torque along q [N m] (arrays of shape (N, 2)), and per input the mean speed, Cs and
    start-up time over/against the last full revolution of the first input."""

    t: np.ndarray
    phi: np.ndarray
    omega: np.ndarray
    torque: np.ndarray
    mean_speed: np.ndarray
    fluctuation: np.ndarray
    startup_time: np.ndarray
    last_revolution: tuple[float, float]
    revolutions: float
    q0: np.ndarray
    direction: np.ndarray
    dense: OdeSolution = field(repr=False)


def mass_matrix(mech, inertias, q, w, direction, armature=(0.0, 0.0), gravity=(0.0, 0.0), force=(0.0, 0.0)):
    """The two-input reduced terms at one state: M (2x2) [kg m^2], the velocity-product torques h (2,) and
    the loads' generalized forces Q (2,) [N m], in the inputs' advances u_k = s_k (q_k - q0_k).

    M_ij = sum m dG/du_i . dG/du_j + I dtheta/du_i dtheta/du_j (+ armature on the diagonal);
    h_i = sum m dG/du_i . a_G|bias + I dtheta/du_i alpha|bias, the bias accelerations at the speeds w with
    zero input accelerations (``mech.solve(q, qd, 0)``); Q_i = sum m g . dG/du_i + F . dP/du_i."""
    s = np.asarray(direction, float)
    qq = np.repeat(np.asarray(q, float)[None, :], 3, axis=0)
    qd = np.array([[s[0], 0.0], [0.0, s[1]], [s[0] * w[0], s[1] * w[1]]])
    c = mech.solve(qq, qd, 0.0)
    origins = mech.link_origins
    M = np.diag(np.asarray(armature, float))
    h = np.zeros(2)
    Q = np.zeros(2)
    gx, gy = gravity
    for link, b in inertias.items():
        vx, vy, ax, ay = _com(c, origins[link], link, b)
        om, al = c["omega" + link], c["alpha" + link]
        V = np.array([[vx[0], vy[0]], [vx[1], vy[1]]])
        M = M + b.m * V @ V.T + b.I * np.outer(om[:2], om[:2])
        h = h + b.m * V @ np.array([ax[2], ay[2]]) + b.I * om[:2] * al[2]
        Q = Q + b.m * V @ np.array([gx, gy])
    p = mech.output_point
    Q = Q + np.array([force[0] * c["vx" + p][k] + force[1] * c["vy" + p][k] for k in range(2)])
    return M, h, Q


def run_two(mech, inertias: dict, motors, revolutions: float, start_speed=(0.0, 0.0), armature=(0.0, 0.0),
            gravity=(0.0, 0.0), force=(0.0, 0.0), rtol: float = 1e-11, samples_per_rev: int = 360,
            stall: bool = True) -> Run2:
    """Integrate M(u) w' + h(u, w) = tau(w) + Q(u) for two motors on the two inputs of ``mech`` until
    the first input has turned ``revolutions`` (>= 1). Raises :class:`Stall` if either speed falls to 0
    after the start (``stall=False``: a speed may pass through zero, e.g. coasting)."""
    from scipy.integrate import solve_ivp
    if len(mech.inputs) != 2 or any(not i.angular for i in mech.inputs):
        raise ParameterError(f"the {mech.name} is not driven by two cranks; give one --motor")
    if not (isinstance(revolutions, (int, float)) and math.isfinite(revolutions) and 1 <= revolutions <= 1e4):
        raise ParameterError(f"--revolutions {revolutions!r} must be a number in [1, 1e4]")
    s = np.array([1.0 if i.motion.rate >= 0 else -1.0 for i in mech.inputs])
    q0 = np.array([float(i.motion.q0) for i in mech.inputs])
    two_pi = 2 * math.pi
    end, last0 = two_pi * revolutions, two_pi * (revolutions - 1)

    def f(t, y):
        w = y[2:4]
        M, h, Q = mass_matrix(mech, inertias, q0 + s * y[:2], w, s, armature, gravity, force)
        tau = np.array([float(motors[0].torque(w[0])), float(motors[1].torque(w[1]))])
        acc = np.linalg.solve(M, tau + Q - h)
        return np.concatenate([w, acc, tau * w])

    def reach(t, y):
        return y[0] - end
    reach.terminal, reach.direction = True, 1

    def mark(t, y):
        return y[0] - last0
    mark.direction = 1

    def stop0(t, y):
        return y[2] if t > 0 else 1.0
    stop0.terminal, stop0.direction = True, -1

    def stop1(t, y):
        return y[3] if t > 0 else 1.0
    stop1.terminal, stop1.direction = True, -1
    W = max(motors[0].free_speed, motors[1].free_speed, max(start_speed), 1.0)
    atol = [rtol * two_pi] * 2 + [rtol * W] * 2 + [rtol * max(motors[0].stall, motors[1].stall, 1e-300) * two_pi] * 2
    y0 = [0.0, 0.0, float(start_speed[0]), float(start_speed[1]), 0.0, 0.0]
    sol = solve_ivp(f, (0.0, 1e3 * end / W + 1e6), y0, method="DOP853", rtol=rtol, atol=atol, dense_output=True,
                    events=(reach, mark, stop0, stop1) if stall else (reach, mark))
    for k, ev in ((0, 2), (1, 3)) if stall else ():
        if sol.t_events[ev].size:
            u = sol.y_events[ev][0][k]
            raise Stall(f"the motor on {mech.inputs[k].q} stalls the {mech.name} at "
                        f"{mech.inputs[k].q}={math.degrees(q0[k] + s[k] * u):.1f}deg (t={sol.t_events[ev][0]:.3g} s): "
                        f"raise its stall torque")
    if not sol.t_events[0].size:
        raise ParameterError(f"the {mech.name} did not complete {revolutions:g} turns ({sol.message})")
    tb = float(sol.t_events[0][0])
    ta = float(sol.t_events[1][0]) if last0 > 0 else 0.0
    n = max(2, int(samples_per_rev * revolutions) + 1)
    t = np.linspace(0.0, tb, n)
    Y = sol.sol(t)
    tt = np.linspace(ta, tb, 4001)
    Yl = sol.sol(tt)
    ya, yb = sol.sol(ta), sol.sol(tb)
    mean = (yb[:2] - ya[:2]) / (tb - ta)
    cs = (Yl[2:4].max(axis=1) - Yl[2:4].min(axis=1)) / mean
    up = np.array([float(t[np.argmax(Y[2 + k] >= STARTUP_FRACTION * mean[k])]) for k in range(2)])
    tau = np.column_stack([motors[0].torque(Y[2]), motors[1].torque(Y[3])])
    return Run2(t=t, phi=(q0[:, None] + s[:, None] * Y[:2]).T, omega=(s[:, None] * Y[2:4]).T, torque=tau * s,
                mean_speed=mean, fluctuation=cs, startup_time=up, last_revolution=(ta, tb),
                revolutions=float(revolutions), q0=q0, direction=s, dense=sol.sol)
