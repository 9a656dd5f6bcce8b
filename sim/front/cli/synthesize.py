"""``linkage synthesize PROBLEM``: two-position (seed 001) here; path, motion and function register from
their own modules (:mod:`.synth_path`, :mod:`.synth_exact`). The use cases are :mod:`sim.service.design`'s:
these functions parse the options, print and write files."""

from __future__ import annotations

import math

import numpy as np

from analytic import ParameterError
from sim.service import design as design_service
from sim.service.values import parse_value
from sim.front.cli.options import add_video_options
from sim.front.cli.synth_options import add_limits, limits_of, measure_words
from sim.output.jsonout import dumps
from sim.output.io import check_writable

UNIT_TO_M = {"mm": 1e-3, "cm": 1e-2, "m": 1.0}


# --------------------------------------------------------------------------------------- synthesis
def _point(option: str, text: str) -> tuple[float, float]:
    parts = text.split(",")
    if len(parts) != 2:
        raise ParameterError(f"{option} {text!r} is not x,y (e.g. {option} 30,31)")
    return parse_value(option, parts[0], angle=False), parse_value(option, parts[1], angle=False)


def _angle_range(option: str, text: str) -> tuple[float, float]:
    if ":" not in text:
        raise ParameterError(f"{option} {text!r} is not LO:HI (e.g. {option} -90deg:90deg)")
    lo, hi = text.split(":", 1)
    return parse_value(option, lo), parse_value(option, hi)


def cmd_synthesize(args) -> int:
    if args.problem != "two-position":
        raise ParameterError(f"unknown synthesis problem {args.problem!r}: use two-position")
    if args.render:
        from sim.output.render import check_video_args
        check_video_args(args.render, args.fps, args.size)
    if args.plot:
        check_writable(args.plot, (".png", ".svg", ".pdf"))
    task = design_service.two_position_task(E1=_point("--E1", args.E1), E2=_point("--E2", args.E2),
                                            A=_point("--A", args.A), D=_point("--D", args.D),
                                            phi12=parse_value("--crank-rotation", args.crank_rotation),
                                            psi12=parse_value("--rocker-rotation", args.rocker_rotation))
    lo, hi = _angle_range("--theta-range", args.theta_range)
    limits = limits_of(args)
    res = design_service.two_position(task, lo, hi, args.unit, limits)
    rows, best, excluded, search = res["rows"], res["optimum"], res["excluded"], res["search"]
    if args.json:
        record = {"rows": rows, "optimum": best, "excluded": excluded, "unit": args.unit}
        if limits is not None:
            record["limited"] = res["limited"]
        print(dumps(record))
    else:
        print(_table(rows, best, args.unit))
        print(_excluded_summary(search.excluded))
        if limits is not None and best is not None:
            print(f"optimum under the limits: {measure_words(best, args.unit)}"
                  + (f" (the unconstrained optimum broke one: {res['limited']})" if res["limited"] else ""))
    if best is None:
        if limits is not None:
            raise ParameterError(f"no coupler rotation in the range gives a linkage that moves E from E1 to E2 "
                                 f"within the limits (the unconstrained optimum: {res['limited']}); relax them")
        raise ParameterError("no coupler rotation in the range gives a linkage that moves E from E1 to E2")
    if args.plot:
        _plot_total(task, search, lo, hi, args.plot, args.unit)
        print(f"wrote {args.plot}")
    if args.render:
        _render_design(task, search.optimum, args)
    return 0


def _table(rows, best, unit) -> str:
    head = (f"{'theta [deg]':>12s} {'phi0 [deg]':>11s} {'psi0 [deg]':>11s} {'l1':>9s} {'l2':>9s} {'l3':>9s} "
            f"{'l4':>7s} {'total':>10s}  Grashof   [lengths in {unit}]")
    lines = [head]
    for r in rows + ([dict(best, label="optimum")] if best else []):
        lines.append(f"{r['theta_deg']:12.4f} {r['phi0_deg']:11.4f} {r['psi0_deg']:11.4f} {r['l1']:9.4f} "
                     f"{r['l2']:9.4f} {r['l3']:9.4f} {r['l4']:7.2f} {r['total']:10.4f}  {r['grashof']}"
                     + ("   <- optimum" if r.get("label") else ""))
    return "\n".join(lines)


def _excluded_summary(excluded) -> str:
    if not excluded:
        return "no coupler rotation in the range was excluded"
    groups: list[list] = []
    for th, why in excluded:
        kind = why.split(" (")[0].split(" at crank angle")[0]
        if groups and groups[-1][2] == kind and abs(th - groups[-1][1] - math.radians(1.0)) < 1e-9:
            groups[-1][1] = th
        else:
            groups.append([th, th, kind])
    parts = [f"{math.degrees(a):.0f}..{math.degrees(b):.0f} deg: {k}" if a != b else f"{math.degrees(a):.0f} deg: {k}"
             for a, b, k in groups]
    return "excluded coupler rotations (1 deg scan): " + "; ".join(parts)


def _plot_total(task, search, lo, hi, out, unit) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from sim.output.io import atomic_path
    from sim.output.fit import fit
    th = np.linspace(lo, hi, 721)
    total = np.array([design_service.two_position_design(task, float(t)).total for t in th])
    ok = np.array([design_service.two_position_feasible(task, design_service.two_position_design(task, float(t)), 91)
                   for t in th])
    fig, ax = plt.subplots(figsize=(8, 5), constrained_layout=True)
    ax.plot(np.degrees(th), np.where(ok, total, np.nan), lw=1.8, label="feasible designs")
    ax.plot(np.degrees(th), np.where(~ok, total, np.nan), lw=1.0, color="0.6", ls="--", label="excluded")
    o = search.optimum
    ax.plot(math.degrees(o.theta), o.total, "o", color="tab:red",
            label=f"optimum: theta={math.degrees(o.theta):.3f} deg, total={o.total:.4f} {unit}")
    finite = total[np.isfinite(total) & ok]
    ax.set_ylim(0.95 * finite.min(), min(finite.max(), 2.0 * finite.min()))
    ax.set(xlabel="coupler rotation theta [deg]", ylabel=f"total link length l1+l2+l3+l4 [{unit}]",
           title="Two-position synthesis: total length against coupler rotation")
    ax.grid(alpha=0.3)
    ax.legend()
    fit(fig)
    with atomic_path(out) as tmp:
        fig.savefig(tmp, dpi=100)
    plt.close(fig)


def _render_design(task, dsg, args) -> None:
    """Animate the optimum moving E from E1 to E2 in MuJoCo, with E1 and E2 marked (SI scale)."""
    from sim.output.render import parse_size, render
    k = UNIT_TO_M[args.unit]
    duration = 2.0                                                 # seconds for the motion E1 -> E2
    mech = design_service.two_position_mechanism(task, dsg, scale=k, omega1=task.phi12 / duration)
    built, tr = _simulate_partial(mech, abs(task.phi12) / (2 * math.pi))
    marks = tuple(tuple(task.local(q) * k) for q in (task.E1, task.E2))
    stats = render(built, tr, args.render, args.fps, parse_size(args.size), markers=marks)
    print(f"wrote {stats.path}: {stats.frames} frames (E1 and E2 marked with crosses)")


def _simulate_partial(mech, revolutions):
    """Simulate part of a turn (the crank need not turn fully: it only goes from position 1 to 2)."""
    from sim.service.simulation import simulate_part
    return simulate_part(mech, revolutions)


def register(sub) -> None:
    syn = sub.add_parser("synthesize", help="find a linkage: two-position (seed 001), path, motion, function")
    problems = syn.add_subparsers(dest="problem", required=True, metavar="PROBLEM", parser_class=type(syn))
    p = problems.add_parser("two-position", help="seed 001: four-bar carrying E from E1 to E2, minimum total length")
    p.add_argument("--E1", default="30,31", help="coupler point E in position 1 (default 30,31)")
    p.add_argument("--E2", default="10,35", help="coupler point E in position 2 (default 10,35)")
    p.add_argument("--A", default="0,0", help="crank pivot (default 0,0)")
    p.add_argument("--D", default="36,0", help="rocker pivot (default 36,0)")
    p.add_argument("--crank-rotation", default="35deg", help="crank rotation from 1 to 2 (default 35deg)")
    p.add_argument("--rocker-rotation", default="50deg", help="rocker rotation from 1 to 2 (default 50deg)")
    p.add_argument("--theta-range", default="-90deg:90deg", metavar="LO:HI",
                   help="coupler rotations searched (default -90deg:90deg)")
    p.add_argument("--units", "--unit", dest="unit", choices=sorted(UNIT_TO_M), default="mm", help="length unit of the data (default mm)")
    add_limits(p, "A (the crank's), D (the rocker's)", min_transmission=None)
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--plot", metavar="PATH", help="plot total length against theta (.png/.svg/.pdf)")
    p.add_argument("--render", metavar="PATH", help="animate the optimum moving E from E1 to E2 (.mp4/.gif)")
    add_video_options(p, out_required=False)
    p.set_defaults(func=cmd_synthesize)
    # the other synthesis problems, each in its own module: module.register(problems)
    from sim.front.cli import synth_exact, synth_path
    synth_exact.register(problems)
    synth_path.register(problems)
