"""Change points passed on a declared branch: where along its first input a dyad's links align while the
input moves on (a parallelogram at phi1 = 0 and 180 deg), and the branch sign it takes on each side.

At a change point the two assembly modes of a dyad meet, and its configuration curve crosses the other
mode's: a real linkage, carried by its momentum, moves on smoothly, keeping its form (a parallelogram stays
a parallelogram), so the closed form's branch sign flips there (the dyad's height over the line of its two
known points passes through zero, |height| ~ |q - q*|). An element declares it with ``change = 1`` (the
default of an RRR; ``change = -1`` keeps the sign and switches form, with a kink in the motion).

:func:`schedule` finds, for a mechanism with one input, each such element's change points over one turn of
its input (a slider: +-4 sizes about its start), in solving order (a flip upstream moves the dyads
downstream), and writes them into the resolved element as ``flips``: ``{"ref": the input's start value,
"period": 2 pi or None, "at": (q*, ...)}``. The element's kind turns them into a sign per sample from the
first input's value (``analytic.kinds.rrr.signs``), so the samples of any solve, in any order, agree. A
mechanism with several inputs is left as it is (its change points depend on every input).

Cost: one solve of SCAN + 1 samples per mechanism (about a millisecond for a four-bar) when no element
comes near a fold; golden-section refinements only for candidates. That scan is solved with the input at
unit rate and kept (:func:`schedule_and_scan`, :attr:`analytic.mechanism.Mechanism.turn_scan`): a cycle of a
crank turning at constant speed reads its rates from it (analytic.cycle) instead of solving the turn again.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from analytic import kinds
from analytic.solver import kinematics
from analytic.format.linkfile import Geometry

SCAN = 1440
"""Samples per turn of the first input (a slider: over +-4 sizes) of the scan for change points."""
CANDIDATE = 0.05
"""A local minimum of an element's singularity measure below this on the scan is refined: at a change
point the measure is ~ slope x |q - q*| and the nearest sample lies within pi / SCAN of it, so a slope up
to 20 (a link turning 20x faster than the input there) is not missed."""
CHANGE = 1e-6
"""A refined minimum below this is a change point (figures.SINGULAR): the links align to rounding."""
FLOOR = 4 * np.finfo(float).eps
"""A golden-section bracket narrower than this fraction of its value (or of 1) is done: its ends are a few
units of the last place apart (~59 steps from a scan's bracket instead of 70; the change points move by
< 2e-15 rad on the tests' parallelograms)."""


def candidates(geometry: Geometry) -> list[int]:
    """The indices of the elements that pass change points smoothly (``change = 1``) and have not been
    scheduled yet."""
    return [i for i, e in enumerate(geometry.elements) if e.get("change") == 1 and "flips" not in e
            and kinds.get(e["kind"]).name == "RRR"]


def schedule(mech) -> Geometry:
    """``mech.geometry`` with each smoothly passing element's change points written in (see the module
    docstring); the geometry unchanged when there is nothing to schedule."""
    return schedule_and_scan(mech)[0]


def schedule_and_scan(mech):
    """(:func:`schedule`'s geometry, the scan it solved last: (q, the solution at q with the first input at
    unit rate and no acceleration, on that geometry), or None where it solved none)."""
    geometry = mech.geometry
    todo = candidates(geometry)
    if not todo:
        return geometry, None
    elements = [dict(e) for e in geometry.elements]
    for i in todo:
        elements[i]["flips"] = None                   # scheduled, no flips (yet): a solve takes them as they are
    if len(mech.inputs) != 1:
        return replace(geometry, elements=tuple(elements)), None
    first = next(e for e in geometry.elements if kinds.get(e["kind"]).section == "inputs")
    kind = kinds.get(first["kind"])
    ref = float(first[kind.motion_fields[0]])
    crank = kind.periodic
    period = 2 * math.pi if crank else None
    lo, hi = (ref, ref + 2 * math.pi) if crank else (ref - 4 * mech.size, ref + 4 * mech.size)
    step = (hi - lo) / SCAN
    q = np.linspace(lo - step, hi + step, SCAN + 3)                  # one sample past each end
    current = replace(mech, geometry=replace(geometry, elements=tuple(elements)), rock=None)
    measures, sol = _measures(current, q, True)
    for i in todo:
        label = elements[i]["label"]
        m = measures.get(label)
        if m is None:
            continue
        found = _distinct(_change_points(current, label, q, m, crank), lo, period)
        if found:
            elements[i]["flips"] = {"ref": ref, "period": period, "at": tuple(found)}
            current = replace(current, geometry=replace(geometry, elements=tuple(elements)))
            measures, sol = _measures(current, q, True)   # the dyads downstream move with the flips
    return replace(geometry, elements=tuple(elements)), (q, sol)


SAME = 1e-6
"""[rad, or of the size for a slider] Change points closer than this are one (found from both ends of the
scan, or by two neighbouring candidates); one this close to a crank's start is at the start."""


def _distinct(found: list[float], lo: float, period: float | None) -> list[float]:
    """The change points sorted, a crank's taken into [lo, lo + 2 pi), those within SAME of each other (or
    of the turn's ends) kept once."""
    if period:
        found = [lo + (x - lo) % period for x in found]
        found = [lo if lo + period - x < SAME else x for x in found]
    # one at the start itself (within rounding): the declared branch is the sign just after the start
    found = [lo if abs(x - lo) < SAME else x for x in found] if period else found
    out: list[float] = []
    for x in sorted(found):
        if not out or x - out[-1] >= SAME:
            out.append(x)
    return out


def _measures(mech, q: np.ndarray, keep: bool = False):
    """The elements' singularity measures at q ({label: measure}); ``keep``: and the solution (the input at
    unit rate: its velocities are the velocity coefficients, its accelerations the motion's at unit speed)."""
    from analytic.checks import singularity
    if not keep:                                      # the measures read positions only: no rates to solve
        return singularity(mech, mech.solve(q))
    sol = mech.solve(q, 1.0)
    return singularity(mech, sol), sol


def _measure(mech, label: str, x: np.ndarray) -> np.ndarray:
    """Element ``label``'s singularity measure at the first input's values ``x`` (a lone input), solved on the
    elements up to it (those after it in solving order cannot move its links) and their positions only: the
    numbers :func:`_measures` gives for it, at a fraction of the work (a golden section asks ~60 times)."""
    geometry = mech.solving_geometry
    k = next(i for i, e in enumerate(geometry.elements) if e["label"] == label)
    part = replace(geometry, elements=geometry.elements[:k + 1])
    q = np.asarray(x, dtype=float).reshape(1, -1)
    zero = np.zeros_like(q)
    with np.errstate(invalid="ignore", divide="ignore"):
        st, _ = kinematics.evaluate(part, q, zero, zero, mu=False)
    e = part.elements[k]
    return kinds.get(e["kind"]).singularity(e, st, mech.size)


def _change_points(mech, label: str, q: np.ndarray, m: np.ndarray, crank: bool) -> list[float]:
    """Where element ``label``'s measure ``m`` (sampled at ``q``) touches zero inside the range where the
    mechanism assembles: local minima below CANDIDATE with assembled samples on both sides (a lone NaN
    between two is rounding at the fold itself), refined by golden section."""
    m = np.array(m, dtype=float)
    finite = np.isfinite(m)
    lone = ~finite
    lone[1:-1] &= finite[:-2] & finite[2:]
    lone[[0, -1]] = False
    m[lone] = 0.0
    ok = np.isfinite(m)
    k = np.flatnonzero(ok[1:-1] & ok[:-2] & ok[2:] & (m[1:-1] <= m[:-2]) & (m[1:-1] <= m[2:])
                       & (m[1:-1] < CANDIDATE)) + 1
    if k.size == 0:
        return []
    a, b = q[k - 1].copy(), q[k + 1].copy()
    g = (math.sqrt(5) - 1) / 2

    def measure(x):
        return np.nan_to_num(_measure(mech, label, x), nan=0.0)

    for _ in range(70):                               # golden section on every candidate at once
        if np.all(b - a <= FLOOR * np.maximum(1.0, np.abs(a))):
            break                                     # the brackets are at rounding: further steps move nothing
        c, d = b - g * (b - a), a + g * (b - a)
        fc, fd = measure(np.concatenate([c, d])).reshape(2, -1)
        left = fc < fd
        a, b = np.where(left, a, c), np.where(left, d, b)
    x = 0.5 * (a + b)
    values = measure(x)
    return [float(xi) for xi, v in zip(x, values) if v < CHANGE]


MEET = 1e-6
"""[of the size] A change point where the dyad's two known points lie closer than this is a folded one."""


def folded(mech) -> list[tuple[float, str, str, str]]:
    """The scheduled change points at which the dyad's two known points meet, ``[(first input's value,
    element label, P, Q)]``: there both links turn about one point and fold onto each other (a rhombus at
    its flat pose, a block carried over the pivot of a rocker as long as its rod), so the loop leaves the
    dyad free to turn about that point. The closed form follows the form kept through it (its rates the
    limits of the motion on each side), but a simulation holds the dyad there only by its momentum, and
    Pyslvs' and PMKS' solvers stop there (|PQ| = 0)."""
    out = []
    for e in mech.solving_geometry.elements:
        flips = e.get("flips")
        if not flips or kinds.get(e["kind"]).name != "RRR":
            continue
        p, q = e["from"]
        x = np.asarray(flips["at"], dtype=float)
        if len(mech.inputs) > 1:
            x = np.column_stack([x] + [np.full_like(x, i.motion.q0) for i in mech.inputs[1:]])
        sol = mech.solve(x, outputs=[f"{c}{n}" for n in (p, q) for c in "xy"])
        gap = np.hypot(np.asarray(sol["x" + p]) - sol["x" + q], np.asarray(sol["y" + p]) - sol["y" + q])
        out += [(float(f), e["label"], p, q) for f, g in zip(flips["at"], gap) if g < MEET * mech.size]
    return sorted(out)
