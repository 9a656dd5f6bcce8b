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

from analytic._common import fmt_deg
from analytic.applications.averages import closed_mean

from analytic.checks import (GAP, HELD_REFINE, INWARD, REFINE, SCAN, SINGULAR, _first_range,  # noqa: F401
                             _padded, assembly_ranges, describe_ranges, min_singularity, round_inward,
                             singular_poses, singularity, turns_fully)
"""The checks of where the first input goes and where a group folds live in :mod:`analytic.checks` (one module
reading the solved run); their names stay importable from here."""


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
                     for j in mech.slides if j not in mech.driven_slides}
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
