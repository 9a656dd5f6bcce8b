"""The kinematic checks of a run, read from the motion solved once: where the first input assembles
(:func:`assembly_ranges`), where a group folds on the way (:func:`singular_poses`, :func:`singularity`), whether
a run visits a value (:func:`visited`) and the output point's slow stroke (:func:`slow_stroke`).

A command used to scan the first input's turn once per check (the assembly ranges for "does it turn fully",
again for the figures, again inside the singular poses, and the singular poses' own scan of the measures): a
mechanism now scans it once, solved at unit rate with every output (:attr:`Checks.scan`), and finds its
assembly ranges and singular poses from that scan once (:class:`Checks`, held by the mechanism:
:attr:`analytic.mechanism.Mechanism.checks`). A run's cycle (:class:`analytic.cycle.Cycle`) that is one full
turn of a crank at constant speed is itself such a scan (``scan=`` of :func:`find_singular_poses`).

Singularity measures (dimensionless, zero where a group folds and its rates are undefined):
RRR, sin of the angle between its two links; RRP, cos of the angle between rod and guide; RPR, the
block's distance from the pivot over the mechanism's size.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from analytic import kinds
from analytic.errors import ParameterError
from analytic.solution import StateView


SINGULAR = 1e-6
"""A group whose singularity measure falls below this is at a singular (change-point) pose: its rates
are of order 1/measure, i.e. >= 1e6 times their usual size."""
SCAN = 3600
"""Samples per turn when scanning the first input's range; boundaries are then refined (REFINE)."""
REFINE = 16
"""Points solved inside each boundary's bracket per refinement step (the bracket shrinks 17 times)."""


def _first_range(mech) -> tuple[float, float]:
    first = mech.inputs[0]
    if first.spec.periodic:
        q0 = first.motion.q0
        return q0, q0 + 2 * math.pi
    span = 4.0 * mech.size                           # a slider's q and the size are both in metres
    return first.motion.q0 - span, first.motion.q0 + span


def find_assembly_ranges(mech, samples: int = SCAN, good=None) -> list[tuple[float, float]]:
    """Intervals of the first input (others at their start values) where every group assembles, over
    one turn from its start angle (a slider: +-4 sizes about its start). Ends are refined by bisection
    to 1e-12 rad (m). One interval spanning the whole turn means it turns fully. ``good``: whether it
    assembles at the scan's values (``samples + 1`` evenly over the range, :attr:`Checks.scan`), when solved
    already."""
    lo, hi = _first_range(mech)
    q = np.linspace(lo, hi, samples + 1)
    others = [i.motion.q0 for i in mech.inputs[1:]]

    def ok(x):
        x = np.atleast_1d(x)
        if others:
            x = np.column_stack([x] + [np.full_like(x, o) for o in others])
        return mech.solve(x, outputs=()).valid

    good = ok(q) if good is None else np.asarray(good, dtype=bool)
    if good.all():
        return [(lo, hi)]
    if not good.any():
        return []                                    # it assembles nowhere on the scan
    edges = np.flatnonzero(np.diff(good.astype(np.int8)))
    # refine every edge at once, REFINE points inside each bracket per solve: the bracket shrinks
    # REFINE + 1 times per solve (bisection: twice), so a solve whose cost is mostly fixed (a group solved
    # numerically, traced from the start pose) is paid 9 times rather than 34 for the same 1e-13
    a, b = q[edges].copy(), q[edges + 1].copy()
    side = good[edges]
    rows = np.arange(len(edges))
    frac = np.arange(1, REFINE + 1) / (REFINE + 1)
    for _ in range(60):
        inner = a[:, None] + (b - a)[:, None] * frac[None, :]
        flipped = ok(inner.ravel()).reshape(inner.shape) != side[:, None]
        j = np.where(flipped.any(axis=1), flipped.argmax(axis=1), REFINE)   # the first point past the edge
        grid = np.concatenate([a[:, None], inner, b[:, None]], axis=1)
        a, b = grid[rows, j], grid[rows, j + 1]
        if np.max(b - a) < 1e-13:
            break
    ranges, start = [], (lo if good[0] else None)
    for i in range(len(edges)):
        if side[i]:
            ranges.append((start, float(a[i])))
            start = None
        else:
            start = float(b[i])
    if start is not None:
        ranges.append((start, hi))
    # a gap narrower than GAP is rounding at a fold that still assembles (a change point): close it
    merged = []
    for r in ranges:
        if merged and r[0] - merged[-1][1] < GAP:
            merged[-1] = (merged[-1][0], r[1])
        else:
            merged.append(r)
    ranges = merged
    if len(ranges) == 1 and ranges[0][1] - ranges[0][0] >= hi - lo - GAP:
        return [(lo, hi)]
    crank = mech.inputs[0].spec.periodic
    if any(kinds.get(e["kind"]).continuous for e in mech.geometry.elements):
        return _with_held_range(mech, ok, ranges, lo, hi, samples)
    # a range wrapping round the turn's end joins the one at its start (cranks only)
    if crank and len(ranges) > 1 and good[0] and good[-1]:
        first = ranges.pop(0)
        last = ranges.pop()
        ranges.append((last[0], first[1] + 2 * math.pi))
    return ranges


def _held_end(ok, q0: float, far: float, samples: int) -> float:
    """How far from ``q0`` towards ``far`` the branch held by continuity from the start goes: a scan taken as
    one path from the start, its first failure refined by finer scans of the step it lies in (each a path
    from the start through the last good value), to 1e-12 rad (m)."""
    q = np.linspace(q0, far, samples + 1)[1:]
    good = ok(q)
    if good.all():
        return far
    k = int(np.argmin(good))
    a, b = (q0 if k == 0 else float(q[k - 1])), float(q[k])
    while abs(b - a) > 1e-12:
        sub = np.linspace(a, b, HELD_REFINE + 1)[1:]
        g = ok(np.concatenate(([a], sub)))[1:]
        j = int(np.argmin(g)) if not g.all() else len(sub) - 1
        a, b = (a if j == 0 else float(sub[j - 1])), float(sub[j])
    return a


HELD_REFINE = 64
"""Values per refining scan in :func:`_held_end` (each refines the failure's place 64-fold)."""


def _with_held_range(mech, ok, ranges, lo: float, hi: float, samples: int) -> list[tuple[float, float]]:
    """The ranges of a mechanism whose groups hold their branch by continuity (numerically solved groups):
    the one holding the start comes from scans taken as paths from the start each way (the forward scan
    alone can rejoin the branch after a gap on another assembly and carry it across a fold to the start's
    branch); the others are the forward scan's, outside it."""
    q0 = mech.inputs[0].motion.q0
    crank = mech.inputs[0].spec.periodic
    a = _held_end(ok, q0, q0 - 2 * math.pi if crank else lo, samples)
    b = _held_end(ok, q0, hi, samples)
    if crank and b - a >= 2 * math.pi - GAP:          # either way reaches a full turn: it turns fully
        return [(lo, hi)]
    held = (a + 2 * math.pi, b + 2 * math.pi) if crank else (a, b)
    gap = (b, a + 2 * math.pi) if crank else None
    others = []
    for r0, r1 in ranges:
        parts = [(max(r0, gap[0]), min(r1, gap[1]))] if crank else [(r0, min(r1, a)), (max(r0, b), r1)]
        others += [(x, y) for x, y in parts if y - x > GAP]
    return sorted(others) + [held] if crank else sorted(others + [held])


GAP = 1e-7
"""[rad or m] Unassembled gaps narrower than this are rounding at a fold that does assemble (a change
point): near a fold the discriminant is ~ angle^2, so rounding (1e-16) hides ~1e-8 rad of it."""


def turns_fully(mech, ranges=None) -> bool:
    ranges = assembly_ranges(mech) if ranges is None else ranges
    lo, hi = _first_range(mech)
    return len(ranges) == 1 and ranges[0][1] - ranges[0][0] >= hi - lo - 1e-9


def describe_ranges(first, ranges, display=None) -> str:
    """Ranges in words, each end rounded inward (a crank's to 0.01 deg, a slider's to 6 significant digits
    in ``display``'s length unit, default m, with the unit), so that a range copied into ``--input-range``
    assembles at both ends; a crank's are shifted so each starts in (-180, 180] deg, in increasing order."""
    if not first.angular:
        from analytic.quantities import LENGTH, SI
        u = display or SI
        f, unit = u.factor(LENGTH), u.unit(LENGTH)
        return " or ".join(f"{round_inward(a * f, True)}..{round_inward(b * f, False)} {unit}" for a, b in ranges)
    shifted = []
    for a, b in ranges:
        k = math.floor((a + math.pi) / (2 * math.pi))
        if a - 2 * math.pi * k <= -math.pi:
            k -= 1
        shifted.append((a - 2 * math.pi * k, b - 2 * math.pi * k))
    return " or ".join(f"{round_inward(math.degrees(a), True, 2)}deg..{round_inward(math.degrees(b), False, 2)}deg"
                       for a, b in sorted(shifted))


INWARD = 1e-4
"""[of the last printed digit] the least distance between a range's end and its printed value rounded
inward (0.01 deg: 1e-6 deg), so that the printed end is strictly inside."""


def round_inward(x: float, up: bool, decimals: int | None = None) -> str:
    """``x`` printed to ``decimals`` decimals (None: 6 significant digits), rounded up (``up``: a range's
    start) or down (its end) by at least INWARD of the last digit, so the printed value lies inside."""
    if not math.isfinite(x):
        return f"{x}"
    if decimals is None:
        decimals = 5 - math.floor(math.log10(abs(x))) if x != 0 else 6
    quantum = 10.0 ** -decimals
    v = (math.ceil(x / quantum + INWARD) if up else math.floor(x / quantum - INWARD)) * quantum
    return f"{v + 0.0:.{max(decimals, 0)}f}"                    # + 0.0: no "-0.00"


def singularity(mech, sol) -> dict[str, np.ndarray]:
    """Each group's singularity measure (see the module docstring), keyed by the group's label: what its
    kind says (:meth:`analytic.kinds.base.Kind.singularity`) from the solution."""
    view = StateView(sol)
    out = {}
    for e in mech.geometry.elements:
        m = kinds.get(e["kind"]).singularity(e, view, mech.size)
        if m is not None:
            out[e["label"]] = m
    return out


def find_singular_poses(mech, samples: int = SCAN, ranges=None, scan=None) -> list[tuple[float, str, float]]:
    """Values of the first input at which a group passes through a singular pose inside its assembly
    range (measure < SINGULAR; the range's own ends are its dead points): ``[(q, group label,
    measure)]``. Local minima of each measure on a fine scan are refined by golden section. Other inputs
    stay at their start values. ``ranges``: :func:`assembly_ranges`' (found here when None); ``scan``: for a
    full turn, the measures already solved over it, (q ascending over the turn, both ends included, {label:
    measure}) (a cycle's: sim.service.simulation.turn_scan), instead of a scan solved here."""
    ranges = find_assembly_ranges(mech, samples) if ranges is None else ranges
    full = turns_fully(mech, ranges)
    others = [i.motion.q0 for i in mech.inputs[1:]]

    def measures(x):
        x = np.atleast_1d(np.asarray(x, dtype=float))
        if others:
            x = np.column_stack([x] + [np.full_like(x, o) for o in others])
        return singularity(mech, mech.solve(x, 1.0))

    found = []
    for a0, b0 in ranges:
        nan_as = 0.0 if full else np.inf           # inside a full turn a NaN is rounding at a fold: singular
        if full and scan is not None:
            q, ms = _padded(*scan)
        else:
            n = max(int(samples * (b0 - a0) / (2 * math.pi)), 16)
            pad = (b0 - a0) / n if full else 0.0          # a full turn is periodic: look past its ends
            q = np.linspace(a0 - pad, b0 + pad, n + 3 if full else n + 1)
            ms = measures(q)
        for label, m in ms.items():
            m = np.where(np.isfinite(m), m, nan_as)
            k = np.flatnonzero((m[1:-1] <= m[:-2]) & (m[1:-1] <= m[2:]) & (m[1:-1] < 100 * SINGULAR + 1e-3)) + 1
            if k.size == 0:
                continue
            a, b = q[k - 1].copy(), q[k + 1].copy()
            g = (math.sqrt(5) - 1) / 2
            for _ in range(80):                       # golden section on every candidate at once
                c, d = b - g * (b - a), a + g * (b - a)
                fc, fd = np.nan_to_num(measures(np.concatenate([c, d]))[label], nan=nan_as).reshape(2, -1)
                left = fc < fd
                a, b = np.where(left, a, c), np.where(left, d, b)
            x = 0.5 * (a + b)
            values = np.nan_to_num(measures(x)[label], nan=nan_as)
            for xi, value in zip(x, values):
                xi = float(xi)
                if full:
                    xi = a0 + (xi - a0) % (2 * math.pi)
                elif min(abs(xi - a0), abs(xi - b0)) < 1e-6:
                    continue                               # a dead point, reported as a range end
                if value < SINGULAR and not any(_apart(xi, f[0], full) < 1e-6 and f[1] == label for f in found):
                    found.append((xi, label, float(value)))
    return sorted(found)


def _apart(a: float, b: float, full: bool) -> float:
    """|a - b|, over a full turn the shorter way round (a pose found at both ends of the scanned turn, at 0 and
    at 2 pi to rounding, is one pose)."""
    d = a - b
    return abs((d + math.pi) % (2 * math.pi) - math.pi) if full else abs(d)


def _padded(q, measures):
    """A full turn's scan (q ascending, its last sample a turn past its first) with one sample past each end,
    taken from the other end (the turn is periodic)."""
    q = np.asarray(q, dtype=float)
    turn = q[-1] - q[0]
    qp = np.r_[q[-2] - turn, q, q[1] + turn]
    return qp, {k: np.r_[m[-2], m, m[1]] for k, m in measures.items()}


def min_singularity(mech, sol) -> tuple[float, str]:
    """The smallest singularity measure over a solution and the group it belongs to."""
    best, where = math.inf, ""
    for label, m in singularity(mech, sol).items():
        v = float(np.nanmin(m)) if np.any(np.isfinite(m)) else math.inf
        if v < best:
            best, where = v, label
    return best, where


@dataclass(frozen=True)
class Checks:
    """What the checks find of one mechanism, each found once, when first asked: the scan of its first input's
    range (:attr:`scan`), the ranges where it assembles (:attr:`ranges`) and its singular poses
    (:attr:`singular`). A mechanism holds one (:attr:`analytic.mechanism.Mechanism.checks`)."""

    mech: object

    @functools.cached_property
    def scan(self):
        """(q, solution): the first input's range (:func:`_first_range`) at SCAN + 1 evenly spaced values, the
        other inputs at their start values, solved at unit rate with every output: which values assemble
        (``solution.valid``) and the groups' singularity measures there."""
        mech = self.mech
        lo, hi = _first_range(mech)
        q = np.linspace(lo, hi, SCAN + 1)
        x = q
        others = [i.motion.q0 for i in mech.inputs[1:]]
        if others:
            x = np.column_stack([q] + [np.full_like(q, o) for o in others])
        return q, mech.solve(x, 1.0 if not others else np.ones(len(mech.inputs)))

    @functools.cached_property
    def ranges(self) -> tuple[tuple[float, float], ...]:
        """:func:`find_assembly_ranges` from :attr:`scan`."""
        return tuple(find_assembly_ranges(self.mech, SCAN, good=self.scan[1].valid))

    @functools.cached_property
    def singular(self) -> tuple[tuple[float, str, float], ...]:
        """:func:`find_singular_poses` over :attr:`ranges`, a crank that turns fully read from :attr:`scan`."""
        mech = self.mech
        ranges = list(self.ranges)
        scan = None
        if mech.inputs[0].spec.periodic and turns_fully(mech, ranges):
            q, sol = self.scan
            scan = (q, singularity(mech, sol))
        return tuple(find_singular_poses(mech, SCAN, ranges=ranges, scan=scan))


    @functools.cached_property
    def stroke(self) -> tuple[float, float]:
        """:func:`slow_stroke` with no cycle: the output point's slow stroke over one turn solved here."""
        return _slow_stroke(self.mech, None)


def checks_of(mech) -> Checks:
    """The mechanism's :class:`Checks` (a :class:`analytic.mechanism.Mechanism` holds one; another object gets
    a new one)."""
    found = getattr(mech, "checks", None)
    return found if isinstance(found, Checks) else Checks(mech)


def assembly_ranges(mech, samples: int = SCAN) -> list[tuple[float, float]]:
    """Intervals of the first input (others at their start values) where every group assembles
    (:func:`find_assembly_ranges`); at SCAN samples, the mechanism's, found once (:attr:`Checks.ranges`)."""
    if samples == SCAN:
        return list(checks_of(mech).ranges)
    return find_assembly_ranges(mech, samples)


def singular_poses(mech, samples: int = SCAN, ranges=None, scan=None) -> list[tuple[float, str, float]]:
    """Values of the first input at which a group passes through a singular pose inside its assembly range
    (:func:`find_singular_poses`); with no arguments, the mechanism's, found once (:attr:`Checks.singular`)."""
    if samples == SCAN and ranges is None and scan is None:
        return list(checks_of(mech).singular)
    return find_singular_poses(mech, samples, ranges, scan)


def visited(first, q1: np.ndarray, x: float) -> bool:
    """Whether the first input's run ``q1`` passes the value ``x`` (a crank: any turn of it)."""
    lo, hi = float(np.min(q1)), float(np.max(q1))
    tol = 1e-9 * max(1.0, abs(lo), abs(hi))
    if not first.angular:
        return lo - tol <= x <= hi + tol
    k = math.ceil((lo - tol - x) / (2 * math.pi))
    return x + 2 * math.pi * k <= hi + tol


def slow_stroke(mech, cycle=None) -> tuple[float, float]:
    """The first input's phase interval [rad from its start] in which the output point makes its slower
    stroke along x (the cutting stroke of a quick-return mechanism), from analytic.cycle.SAMPLES + 1 instants
    of one turn: the dense samples of the run's ``cycle`` where it is one period (analytic.cycle.Cycle), else
    the same instants solved once per mechanism (:attr:`Checks.stroke`)."""
    from analytic.cycle import SAMPLES, periodic
    if not (cycle is not None and periodic(mech) and len(cycle.dense) == SAMPLES + 1):
        return checks_of(mech).stroke
    return _slow_stroke(mech, cycle)


def _slow_stroke(mech, cycle) -> tuple[float, float]:
    from analytic.cycle import SAMPLES, periodic
    first = mech.inputs[0]
    T = mech.duration(1.0)
    if cycle is not None and periodic(mech) and len(cycle.dense) == SAMPLES + 1:
        t = cycle.t[cycle.dense]
        x = np.asarray(cycle.solution["x" + mech.output_point])[cycle.dense]
    else:
        t = np.linspace(0.0, T, SAMPLES + 1)
        x = mech.solve(*mech.drive(t))["x" + mech.output_point]
    k_min, k_max = int(np.nanargmin(x)), int(np.nanargmax(x))
    a, b = sorted((k_min, k_max))
    inner = b - a                           # samples from one extreme to the other
    phase = (first.motion.at(t)[0] - first.motion.q0)
    if inner >= len(t) - 1 - inner:
        return float(phase[a]), float(phase[b])
    return float(phase[b]), float(phase[a] + 2 * math.pi)


# ------------------------------------------------------------------------------ the runs' refusals
def check_turns_fully(mech, cycle=None) -> None:
    """A single-input mechanism whose first input cannot make a full turn is refused with its limits
    (a rocking drive, ``input_range``, is the way to run it). ``cycle``: the run's (analytic.cycle.Cycle);
    one that sweeps the crank's turn (:attr:`analytic.cycle.Cycle.covers_turn`: at constant speed the 3600 of a
    turn that :attr:`Checks.scan` scans, and the refined ones; a motion law's cycle, its samples the values the
    run visits) and assembles at every sample turns fully; else the mechanism's assembly ranges
    (:attr:`Checks.ranges`) say."""
    if len(mech.inputs) != 1 or mech.rock is not None or not mech.inputs[0].angular:
        return
    law = mech.inputs[0].motion.law
    if law is not None and law.rise == 0.0:      # a law that returns to its start: its samples are checked
        return
    if cycle is not None and cycle.covers_turn and cycle.solution.valid.all():
        return
    ranges = assembly_ranges(mech)
    if not ranges:
        raise ParameterError(f"{mech.definition.source}: the {mech.name} cannot be assembled at any value of "
                             f"{mech.inputs[0].q}: change its lengths")
    if not turns_fully(mech, ranges):
        first = mech.inputs[0]
        ends = ", ".join(sorted({f"{(math.degrees(a) + 180) % 360 - 180:.4f}deg" for r in ranges for a in r},
                                key=lambda x: float(x[:-3])))
        reach = describe_ranges(first, ranges) if ranges else "nowhere"
        raise ParameterError(f"the input {first.q} of the {mech.name} cannot turn fully (limit angles {ends}; "
                             f"reachable {reach}, rounded inward): run it between the limits with an input range LO:HI")


def check_forces_singular(mech, q: np.ndarray, sol=None) -> None:
    """Refuse a run that passes a singular pose of a group (its joint forces are unbounded there), naming the
    first input's value: the refined singular poses of the first input's range (one input), or the smallest
    singularity measure over the run's samples (``sol``: the run's solution at ``q``, with the outputs the
    measures read, :func:`measured_outputs`; solved here when None)."""
    from analytic.cycle import take
    first = mech.inputs[0]
    if len(mech.inputs) == 1:
        for x, label, _ in singular_poses(mech):
            if visited(first, q[:, 0], x):
                raise ParameterError(singular_text(mech, x, label))
    step = max(1, len(q) // 20001)
    if sol is not None:                        # the measures read the poses: the run's own, at every step-th sample
        sub = take(sol, slice(None, None, step))
    else:
        sub = mech.solve(q[::step], 1.0 if len(mech.inputs) == 1 else np.ones(len(mech.inputs)))
    for label, m in singularity(mech, sub).items():
        m = np.where(np.isfinite(m), m, np.inf)
        k = int(np.argmin(m))
        if m[k] < SINGULAR:
            raise ParameterError(singular_text(mech, float(q[::step][k, 0]), label))


def measured_outputs(mech) -> list[str]:
    """The outputs the singularity measures read (:func:`singularity`, through
    analytic.solution.StateView): every point's, link's and prismatic pair's state."""
    return ([c + p for p in mech.points for c in ("x", "y", "vx", "vy", "ax", "ay")]
            + [c + ln for ln in mech.links for c in ("cos", "sin", "omega", "alpha")]
            + [c + j for j in mech.slides for c in ("s", "ds", "dds")])


def singular_text(mech, x: float, label: str) -> str:
    """The refusal of a run whose joint forces are unbounded at the first input's value ``x`` (``label`` folds)."""
    from analytic.applications.forces import angle_text
    first = mech.inputs[0]
    return (f"the {mech.name} passes through a singular pose at {first.q}={angle_text(first, x)} ({label} folds): "
            f"its joint forces are unbounded there; change a length by a little, or run between two such "
            f"values with an input range")
