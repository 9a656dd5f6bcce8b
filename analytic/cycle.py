"""The motion over the working range solved once: :class:`Cycle`.

A run's preparation needs the motion many times over (the time step's rate scan and its peaks, the camera's
framing, the rails, the initial pose, the drives' peak forces, the run's checks). A cycle solves it once, on
a dense grid of times, and refines it where it bends: near each rate's highest peaks, in one more solve of
the merged, sorted grid (one path, so a numerically solved group continues along it instead of re-tracing
from the start). A lone crank turning at constant speed whose change points were searched for reads its
peaks from that search's scan of the turn (analytic.solver.change_points.schedule_and_scan) instead of the
dense solve, so its cycle is one solve; so does a lone input rocking over a range that scan covers (each
scanned pose at the two times the rocking passes it, its rates from the scan's velocity coefficients). Change points themselves are not refined around: a dyad passes them
smoothly (its rates are continuous there) and samples within ~1e-5 rad of one meet the closed form's
rounding, not the motion. That second solve also gives the velocity
coefficients of every input (its outputs with that input at unit rate, the others at rest, no
acceleration: the virtual-work factors of :func:`analytic.applications.torque.drive_forces`), as rows
interleaved with the motion's, so that each sample's pose is solved next to itself.

The grid covers one period of the motion where the motion repeats (one input turning at constant speed, or
rocking), else the whole run of ``revolutions`` turns of the first input (several inputs, an accelerating
input): a scan of that span sees every rate the run reaches.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from analytic.solution import Solution

SAMPLES = 3600
"""Samples per revolution of the dense grid (at most SAMPLES_MAX over a run): the time step's rate scan
(sim.model.timestep) and, for a crank turning at constant speed, the 0.1 deg scan of a turn that the run's
checks read (analytic.applications.figures.SCAN: where it assembles, its singular poses)."""

SAMPLES_MAX = 200_000

PEAKS = 4
"""Local maxima of each rate refined per revolution (at most 64 per rate)."""

REFINE = 256
"""Samples added between the two dense samples around each refined peak or change point: the peak's
neighbourhood resolved 128x finer than the dense grid (its value then taken from an interpolant,
sim.model.timestep.peak_rate)."""


def rate_names(mech) -> list[str]:
    """The outputs the rates are read from (see :func:`rates`)."""
    names = [f"{k}{ln}" for ln in mech.links for k in ("omega", "alpha")]
    return names + [f"{k}{j}" for j in mech.slides for k in ("ds", "dds")]


def rates(mech, qd, qdd, sol) -> np.ndarray:
    """Every rate of the motion [1/s], shape (N, k): each input's and link's |omega| and sqrt(|alpha|), each
    slide's |ds| / size and sqrt(|dds| / size) (an input slider's over the size); NaN where the mechanism
    cannot be assembled. ``qd``, ``qdd``: the inputs' rates (N, n_inputs); ``sol``: the solution there."""
    size = mech.size
    cols = []
    for k, inp in enumerate(mech.inputs):
        scale = inp.spec.rate_scale(size)
        cols += [np.abs(qd[:, k]) / scale, np.sqrt(np.abs(qdd[:, k]) / scale)]
    for ln in mech.links:
        cols += [np.abs(sol["omega" + ln]), np.sqrt(np.abs(sol["alpha" + ln]))]
    for j in mech.slides:
        cols += [np.abs(sol["ds" + j]) / size, np.sqrt(np.abs(sol["dds" + j]) / size)]
    return np.column_stack(cols)


def peaks(r: np.ndarray, keep: int) -> tuple[np.ndarray, np.ndarray]:
    """(sample, column) of the ``keep`` highest local maxima of each column of ``r`` (ends included)."""
    pad = np.pad(r, ((1, 1), (0, 0)), constant_values=-np.inf)
    is_peak = (pad[1:-1] >= pad[:-2]) & (pad[1:-1] >= pad[2:]) & np.isfinite(r)
    rows, cols = [], []
    for c in range(r.shape[1]):
        idx = np.flatnonzero(is_peak[:, c])
        idx = idx[np.argsort(r[idx, c])[-keep:]]
        rows.append(idx)
        cols.append(np.full(len(idx), c))
    return np.concatenate(rows), np.concatenate(cols)


def take(sol: Solution, idx) -> Solution:
    """The samples ``idx`` (an index array or a slice) of a solution of shape (N,)."""
    return Solution({k: np.asarray(v)[idx] for k, v in sol._arrays.items()}, sol.failed_index[idx], sol.labels,
                    sol._aliases)


def solve_with_coefficients(mech, q, qd, qdd) -> tuple[Solution, tuple[Solution, ...]]:
    """The solution at (q, qd, qdd), each (N, n_inputs), and each input's velocity coefficients there (the
    solution with that input at unit rate, the others at rest, no acceleration), in one solve: the rows
    interleaved, sample by sample, so a numerically solved group meets each pose next to itself."""
    q, qd, qdd = (np.asarray(x, dtype=float).reshape(len(np.atleast_2d(q)), -1) for x in (q, qd, qdd))
    n, k = q.shape
    Q = np.repeat(q[:, None, :], k + 1, axis=1)
    QD = np.zeros_like(Q)
    QDD = np.zeros_like(Q)
    QD[:, 0], QDD[:, 0] = qd, qdd
    for j in range(k):
        QD[:, j + 1, j] = 1.0
    sol = mech.solve(Q.reshape(-1, k), QD.reshape(-1, k), QDD.reshape(-1, k))
    parts = tuple(take(sol, slice(j, None, k + 1)) for j in range(k + 1))
    return parts[0], parts[1:]


def periodic(mech) -> bool:
    """Whether the motion repeats every turn of the first input: one input, at constant speed, rocking or
    driven by a law (its cycle)."""
    if len(mech.inputs) != 1:
        return False
    m = mech.inputs[0].motion
    return m.rock is not None or m.accel == 0.0


@dataclass(frozen=True)
class Cycle:
    """The motion of ``mech`` over its working range, solved at the sorted times ``t`` [s]: the inputs
    (q, qd, qdd: (N, n_inputs)), every output (``solution``), each input's velocity coefficients
    (``coefficients``, one :class:`Solution` per input) and which samples the refinement added
    (``refined``). ``revolutions``: the turns of the first input the grid covers."""

    mech: object
    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    solution: Solution = field(repr=False)
    coefficients: tuple = field(repr=False)
    refined: np.ndarray = field(repr=False)
    revolutions: float = 1.0
    beyond: Solution | None = field(default=None, repr=False)

    @classmethod
    def of(cls, mech, revolutions: float = 1.0, margin: float = 0.0) -> "Cycle":
        """The cycle of ``mech`` for a run of ``revolutions`` turns (module docstring): a dense solve, then
        the refined grid solved with the velocity coefficients. ``margin`` (rad, or m for a slider) > 0, for
        a lone input rocking over (lo, hi): also the poses at lo - margin and hi + margin, in the same solve
        (``beyond``, shape (2,): whether a dead point lies that close beyond an end of the range)."""
        span = 1.0 if periodic(mech) else float(revolutions)
        end = mech.duration(span)
        turns = max(1.0, span)
        t = np.linspace(0.0, end, int(min(SAMPLES * turns, SAMPLES_MAX)) + 1)
        q, qd, qdd = mech.drive(t)
        mech.check_motion(q, t)
        scanned = (_from_turn_scan(mech, end) or _from_rocking_scan(mech, end)) if span == 1.0 else None
        if scanned is not None:                  # the change points' scan of the turn, at unit rate
            ts, r = scanned
        else:
            ts = t
            r = rates(mech, qd, qdd, mech.solve(q, qd, qdd, outputs=rate_names(mech)))
        rows = np.empty(0, dtype=int)
        if np.isfinite(r).any():
            rows, _ = peaks(np.where(np.isfinite(r), r, -np.inf), min(64, int(math.ceil(PEAKS * turns))))
        lo, hi = ts[np.maximum(rows - 1, 0)], ts[np.minimum(rows + 1, len(ts) - 1)]
        u = np.linspace(0.0, 1.0, 2 * REFINE + 1)[1:-1]
        extra = (lo[:, None] + (hi - lo)[:, None] * u[None, :]).ravel()
        extra = extra[(extra > 0.0) & (extra < end)]
        gap = 1e-6 * end / len(t)                       # a refined sample this near another is dropped
        extra = np.unique(extra)
        extra = extra[np.r_[True, np.diff(extra) > gap]]
        k = np.clip(np.searchsorted(t, extra), 1, len(t) - 1)
        extra = extra[np.minimum(np.abs(extra - t[k - 1]), np.abs(t[k] - extra)) > gap]
        tt = np.unique(np.r_[t, extra])
        refined = ~np.isin(tt, t)
        q, qd, qdd = mech.drive(tt)
        if margin > 0.0 and mech.rock is not None and len(mech.inputs) == 1:
            # the poses beyond the ends solved next to the samples at the ends (t = 0 and the top of the swing),
            # so that a group that continues from sample to sample reaches them along the range
            lo, hi = mech.rock
            at = np.array([0, int(np.argmax(q[:, 0])) + 1])
            rows = np.array([[lo - margin], [hi + margin]])
            Q, QD, QDD = (np.insert(x, at, v, axis=0) for x, v in ((q, rows), (qd, 0.0), (qdd, 0.0)))
            sol, coeffs = solve_with_coefficients(mech, Q, QD, QDD)
            probe = at + np.arange(2)                  # where the two rows landed
            keep = np.setdiff1d(np.arange(len(Q)), probe)
            beyond = take(sol, probe)
            sol, coeffs = take(sol, keep), tuple(take(c, keep) for c in coeffs)
            return cls(mech, tt, q, qd, qdd, sol, coeffs, refined, span, beyond)
        sol, coeffs = solve_with_coefficients(mech, q, qd, qdd)
        return cls(mech, tt, q, qd, qdd, sol, coeffs, refined, span)

    @property
    def dense(self) -> np.ndarray:
        """The indices of the dense (evenly spaced) samples."""
        return np.flatnonzero(~self.refined)

    def rates(self) -> np.ndarray:
        """:func:`rates` at every sample."""
        return rates(self.mech, self.qd, self.qdd, self.solution)

    @property
    def full_turn(self) -> bool:
        """Whether the samples are one turn of a lone crank at constant speed: then they are also a scan of
        the crank's turn (its values evenly spaced, every 1 / SAMPLES of a turn, and the refined ones)."""
        mech = self.mech
        if len(mech.inputs) != 1 or not mech.inputs[0].angular:
            return False
        m = mech.inputs[0].motion
        return m.constant and m.rate != 0.0 and self.revolutions == 1.0

    @property
    def covers_turn(self) -> bool:
        """Whether the samples sweep every value of a lone crank's turn: one turn at constant speed
        (:attr:`full_turn`), or one cycle of a motion law that turns it by whole turns (analytic.laws: a crank's
        law rises by a whole number of turns, or returns); the run visits exactly these values, so they are the
        turn's check (analytic.checks.check_turns_fully, sim.service.simulation.turn_scan)."""
        if self.full_turn:
            return True
        mech = self.mech
        if len(mech.inputs) != 1 or not mech.inputs[0].angular or mech.rock is not None:
            return False
        law = mech.inputs[0].motion.law
        return law is not None and law.rise != 0.0 and self.revolutions == 1.0

    def at_start(self) -> tuple[tuple[np.ndarray, np.ndarray, np.ndarray], Solution]:
        """The inputs and the solution at t = 0 (shapes (1, n_inputs) and (1,))."""
        return (self.q[:1], self.qd[:1], self.qdd[:1]), take(self.solution, slice(0, 1))


def _from_turn_scan(mech, end: float):
    """For a lone crank turning at constant speed w over one turn (duration ``end``) whose change points'
    scan is at hand (:attr:`analytic.mechanism.Mechanism.turn_scan`: the turn at unit rate): the scan's
    times in the run ((q - q0) / w, wrapped into the turn: the turn's poses are the same) and the run's rates
    there (:func:`rates`), the unit rate's scaled by |w| (velocities) and w^2 (accelerations, the input not
    accelerating); else None."""
    if len(mech.inputs) != 1 or not mech.inputs[0].angular:
        return None
    m = mech.inputs[0].motion
    if not m.constant or m.rate == 0.0 or mech.turn_scan is None:
        return None
    q, sol = mech.turn_scan
    w = abs(m.rate)
    ts = np.mod((q - m.q0) / m.rate, end)
    order = np.argsort(ts, kind="stable")
    n = len(q)
    r = rates(mech, np.full((n, 1), w), np.zeros((n, 1)), sol) * w      # |omega| w, sqrt(|alpha| w^2), ...
    r[:, 0] = w                                                            # the input's own speed
    return ts[order], r[order]


def _from_rocking_scan(mech, end: float):
    """For a lone input rocking over (lo, hi) (q = mid - amp cos(w t), one period ``end``) whose change points'
    scan is at hand and covers the range (:attr:`analytic.mechanism.Mechanism.turn_scan`: the turn at unit
    rate, its velocities the velocity coefficients c1, its accelerations the second-order ones c2): each
    scanned pose inside the range at the two times of the period the rocking passes it, the range's ends at
    0, end / 2 and end, and the run's rates there (:func:`rates`), from omega = c1 qd and
    alpha = c2 qd^2 + c1 qdd (the same for a slide's ds, dds); else None. The ends' coefficients are
    interpolated from the scan's neighbours (they only choose where the cycle refines)."""
    if len(mech.inputs) != 1 or mech.rock is None or mech.turn_scan is None:
        return None
    first = mech.inputs[0]
    w = abs(first.motion.rate)
    if w == 0.0:
        return None
    q, sol = mech.turn_scan
    lo, hi = mech.rock
    x = q[1:-1]                                       # the scan's own turn (one sample past each end dropped)
    if first.spec.periodic:
        x = lo + np.mod(x - lo, 2 * math.pi)
    elif not (x.min() <= lo and hi <= x.max()):
        return None                                   # a slider's range reaching past the scanned stroke
    inside = np.flatnonzero((x > lo) & (x < hi))
    order = np.argsort(x, kind="stable")
    period = 2 * math.pi if first.spec.periodic else None
    coeff = {k: np.asarray(sol[k])[1:-1] for k in rate_names(mech)}

    def at_ends(v):                                   # a coefficient at lo and hi, from the scan's neighbours
        return np.interp([lo, hi], x[order], v[order], period=period)

    mid, amp = 0.5 * (lo + hi), 0.5 * (hi - lo)
    theta = np.arccos(np.clip((mid - x[inside]) / amp, -1.0, 1.0))     # w t over the first half period
    ts = np.r_[theta / w, end - theta / w, 0.0, 0.5 * end, end]
    qd = np.r_[amp * w * np.sin(theta), -amp * w * np.sin(theta), 0.0, 0.0, 0.0]
    qdd = np.r_[amp * w * w * np.cos(theta), amp * w * w * np.cos(theta), amp * w * w, -amp * w * w, amp * w * w]
    c = {k: np.r_[v[inside], v[inside], at_ends(v)[[0, 1, 0]]] for k, v in coeff.items()}
    run = {}
    for first_order, second_order in [(f"omega{ln}", f"alpha{ln}") for ln in mech.links] + \
            [(f"ds{j}", f"dds{j}") for j in mech.slides]:
        run[first_order] = c[first_order] * qd
        run[second_order] = c[second_order] * qd * qd + c[first_order] * qdd
    r = rates(mech, qd[:, None], qdd[:, None], run)
    order = np.argsort(ts, kind="stable")
    return ts[order], r[order]
