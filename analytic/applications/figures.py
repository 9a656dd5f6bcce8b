"""Figures of merit of any mechanism: where its first input can go, its dead points and singular poses,
transmission angles, and its output point's path; plus the built-ins' own figures (Grashof type,
stroke, quick-return ratio...) from their dedicated closed forms.

Singularity measures (dimensionless, zero where a group folds and its rates are undefined):
RRR, sin of the angle between its two links; RRP, cos of the angle between rod and guide; RPR, the
block's distance from the pivot over the mechanism's size.
"""

from __future__ import annotations

import math

import numpy as np

from analytic import kinds
from analytic._common import fmt_deg
from analytic.solution import StateView
from analytic.applications.averages import closed_mean

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


def _valid(mech, q: np.ndarray) -> np.ndarray:
    return mech.solve(q).valid


def assembly_ranges(mech, samples: int = SCAN) -> list[tuple[float, float]]:
    """Intervals of the first input (others at their start values) where every group assembles, over
    one turn from its start angle (a slider: +-4 sizes about its start). Ends are refined by bisection
    to 1e-12 rad (m). One interval spanning the whole turn means it turns fully."""
    lo, hi = _first_range(mech)
    q = np.linspace(lo, hi, samples + 1)
    others = [i.motion.q0 for i in mech.inputs[1:]]

    def ok(x):
        x = np.atleast_1d(x)
        if others:
            x = np.column_stack([x] + [np.full_like(x, o) for o in others])
        return mech.solve(x, outputs=()).valid

    good = ok(q)
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


def singular_poses(mech, samples: int = SCAN, ranges=None, scan=None) -> list[tuple[float, str, float]]:
    """Values of the first input at which a group passes through a singular pose inside its assembly
    range (measure < SINGULAR; the range's own ends are its dead points): ``[(q, group label,
    measure)]``. Local minima of each measure on a fine scan are refined by golden section. Other inputs
    stay at their start values. ``ranges``: :func:`assembly_ranges`' (found here when None); ``scan``: for a
    full turn, the measures already solved over it, (q ascending over the turn, both ends included, {label:
    measure}) (a cycle's: sim.service.simulation.turn_scan), instead of a scan solved here."""
    ranges = assembly_ranges(mech, samples) if ranges is None else ranges
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
                if value < SINGULAR and not any(abs(xi - f[0]) < 1e-6 and f[1] == label for f in found):
                    found.append((xi, label, float(value)))
    return sorted(found)


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


def _span(x) -> list[float]:
    x = np.asarray(x)
    return [float(np.nanmin(x)), float(np.nanmax(x))] if np.any(np.isfinite(x)) else [math.nan, math.nan]


def general(mech, sol) -> dict:
    """Figures every mechanism has, over the sampled solution ``sol``."""
    p = mech.output_point
    speed = np.hypot(sol["vx" + p], sol["vy" + p])
    out = {
        "output_point": p,
        f"x{p}_range": _span(sol["x" + p]), f"y{p}_range": _span(sol["y" + p]),
        f"v{p}_min": float(np.nanmin(speed)), f"v{p}_mean": float(closed_mean(speed)),
        f"v{p}_max": float(np.nanmax(speed)),
        "transmission": {p: _span(sol[name]) for p, name in mech.transmission_angles.items()},
    }
    if len(mech.inputs) == 1:
        ranges = assembly_ranges(mech)
        first = mech.inputs[0]
        full = turns_fully(mech, ranges)
        out["input"] = first.q
        out["turns_fully"] = full
        out["input_ranges"] = [list(r) for r in ranges]
        out["dead_points"] = [] if full else [x for r in ranges for x in r]
        out["singular_points"] = [{"at": x, "group": g} for x, g, _ in singular_poses(mech)]
    out["slides"] = {j: {"range": _span(sol["s" + j]), "stroke": float(np.nanmax(sol["s" + j]) - np.nanmin(sol["s" + j]))}
                     for j in mech.slides if j not in {i.link for i in mech.inputs}}
    out["time_ratio"] = time_ratio(mech, sol)
    m, label = min_singularity(mech, sol)
    out["min_singularity"] = {"value": m, "group": label}
    return out


def time_ratio(mech, sol) -> float:
    """Quick-return ratio K of the output point over one run: the slower of its two strokes along x (from
    one x-extreme to the other) over the faster, >= 1. The extremes are where vx changes sign, located by
    linear interpolation between samples (NaN if the run does not show exactly one of each)."""
    x, vx = np.asarray(sol["x" + mech.output_point]), np.asarray(sol["vx" + mech.output_point])
    if len(x) < 8 or not np.all(np.isfinite(vx)) or np.ptp(x) <= 1e-12 * mech.size:
        return math.nan
    n = len(vx) - 1
    k = np.flatnonzero(np.sign(vx[:-1]) * np.sign(vx[1:]) < 0)
    if len(k) != 2:
        return math.nan
    at = k + vx[k] / (vx[k] - vx[k + 1])             # fractional sample index of each extreme
    one = at[1] - at[0]
    other = n - one
    return float(max(one, other) / min(one, other))


# ------------------------------------------------------------------------------ the built-ins' own
def fourbar_figures(p, sol) -> dict:
    from analytic.closed_forms import fourbar
    g = fourbar.grashof(p)
    lim = fourbar.crank_limits(p)
    speed = np.hypot(sol["vxE"], sol["vyE"])
    return {
        "grashof": g.chain, "inversion": g.inversion, "crank_turns_fully": lim.full_turn,
        "limit_angles": list(lim.limit_angles), "reachable_phi1": [list(iv) for iv in lim.intervals],
        "mu_min": float(np.nanmin(sol["mu"])), "mu_max": float(np.nanmax(sol["mu"])),
        "mu_extremes": list(fourbar.transmission_extremes(p)),
        "xE_range": _span(sol["xE"]), "yE_range": _span(sol["yE"]), "vE_max": float(np.nanmax(speed)),
        "phi3_swing": float(np.ptp(np.unwrap(sol["phi3"][np.isfinite(sol["phi3"])]))) if np.any(
            np.isfinite(sol["phi3"])) else math.nan,
    }


def sixbar_figures(p, sol) -> dict:
    from analytic.closed_forms import sixbar
    f = sixbar.figures(p)
    return {"h": p.h, "stroke": f.stroke, "swing": f.swing, "theta": f.swing, "K": f.K,
            "phi1_limits": list(f.phi1_limits), "xC_limits": list(f.xC_limits),
            "s_range": _span(sol["s"]), "vxC_range": _span(sol["vxC"]), "axC_range": _span(sol["axC"])}


def fivebar_figures(p, sol) -> dict:
    speed = np.hypot(sol["vxP"], sol["vyP"])
    return {"speed_ratio": p.omega2 / p.omega4 if p.omega4 != 0 else math.inf,
            "S_range": _span(sol["S"]), "S_min_possible": p.l1 - p.l2 - p.l4,
            "xP_range": _span(sol["xP"]), "yP_range": _span(sol["yP"]),
            "vP_min": float(np.nanmin(speed)), "vP_max": float(np.nanmax(speed)),
            "vP_mean": float(closed_mean(speed))}


def fourbar_summary(f: dict, u=None) -> list[str]:
    deg = math.degrees
    L, V = _shown(u, "length"), _shown(u, "velocity")
    lines = [f"  Grashof: {f['grashof']}, {f['inversion']}; crank turns fully: "
             f"{'yes' if f['crank_turns_fully'] else 'no'}"]
    if f["limit_angles"]:
        lines.append("  limit angles: " + ", ".join(f"{deg(a):.3f} deg" for a in f["limit_angles"]))
    lo, hi = f["mu_extremes"]
    lines.append(f"  transmission angle mu: {deg(f['mu_min']):.3f} .. {deg(f['mu_max']):.3f} deg over the "
                 f"samples; {deg(lo):.3f} .. {deg(hi):.3f} deg over every crank angle")
    lines.append(f"  rocker swing: {deg(f['phi3_swing']):.3f} deg;  |vE| max {V(f['vE_max'])}")
    lines.append(f"  E path: x {L(f['xE_range'][0], 0)} .. {L(f['xE_range'][1])}, "
                 f"y {L(f['yE_range'][0], 0)} .. {L(f['yE_range'][1])}")
    return lines


def sixbar_summary(f: dict, u=None) -> list[str]:
    L, V, A = _shown(u, "length"), _shown(u, "velocity"), _shown(u, "acceleration")
    return [f"  ram line h = {L(f['h'])}; stroke H = {L(f['stroke'])}",
            f"  guide swing theta = {math.degrees(f['swing']):.3f} deg; quick-return ratio K = {f['K']:.4f}",
            f"  ram velocity {V(f['vxC_range'][0], 0)} .. {V(f['vxC_range'][1])}; "
            f"acceleration {A(f['axC_range'][0], 0)} .. {A(f['axC_range'][1])}"]


def fivebar_summary(f: dict, u=None) -> list[str]:
    L, V = _shown(u, "length"), _shown(u, "velocity")
    return [f"  speed ratio i = omega2/omega4 = {f['speed_ratio']:.6g}",
            f"  S: {L(f['S_range'][0], 0)} .. {L(f['S_range'][1])} (never below {L(f['S_min_possible'])})",
            f"  |vP|: min {V(f['vP_min'], 0)}, mean {V(f['vP_mean'], 0)}, max {V(f['vP_max'])}"]


def _shown(u, quantity: str):
    """A formatter of an SI value of ``quantity`` in display units ``u`` (analytic.quantities.Display;
    None: SI): ``fmt(value)`` gives "1.5 mm", ``fmt(value, 0)`` the number alone."""
    from analytic.quantities import SI
    u = u or SI
    f, unit = u.factor(quantity), u.unit(quantity)
    return lambda v, with_unit=1: f"{v * f:.6g}" + (f" {unit}" if with_unit else "")


def general_summary(mech, f: dict, u=None) -> list[str]:
    deg = math.degrees
    L, V = _shown(u, "length"), _shown(u, "velocity")
    p = f["output_point"]
    lines = []
    if "turns_fully" in f:
        first = mech.inputs[0]
        lines.append(f"  {first.q}: " + ("turns fully" if f["turns_fully"] else
                                          "assembles in " + describe_ranges(first, f["input_ranges"], u)))
        for s in f["singular_points"]:
            where = fmt_deg(s["at"]) if first.angular else L(s["at"])
            lines.append(f"  singular pose at {first.q}={where}: {s['group']} folds (change point)")
    for point, (lo, hi) in f["transmission"].items():
        lines.append(f"  transmission angle at {point}: {deg(lo):.3f} .. {deg(hi):.3f} deg")
    for j, v in f.get("slides", {}).items():
        lines.append(f"  slide s{j}: {L(v['range'][0], 0)} .. {L(v['range'][1])} (stroke {L(v['stroke'])})")
    if f.get("time_ratio") == f.get("time_ratio"):
        lines.append(f"  time ratio of {p}'s strokes along x: K = {f['time_ratio']:.4f}")
    lines.append(f"  {p} path: x {L(f[f'x{p}_range'][0], 0)} .. {L(f[f'x{p}_range'][1])}, "
                 f"y {L(f[f'y{p}_range'][0], 0)} .. {L(f[f'y{p}_range'][1])}; |v{p}| "
                 f"{V(f[f'v{p}_min'], 0)} .. {V(f[f'v{p}_max'])}")
    return lines


def of(mech, sol) -> dict:
    """Figures of merit over a sampled solution: the general ones, and a built-in's own."""
    out = general(mech, sol)
    if mech.builtin is not None:
        out.update(mech.builtin.figures(mech.builtin.parameters(mech.values), sol))
    return out


def summary(mech, figs: dict, display=None) -> list[str]:
    """The figures of merit (SI) as readable lines, in ``display`` units (analytic.quantities.Display;
    None: the file's length unit)."""
    from analytic.quantities import Display
    display = display or Display(mech.units)
    if mech.builtin is not None:
        return mech.builtin.summary(figs, display)
    return general_summary(mech, figs, display)
