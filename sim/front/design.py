"""Design commands: ``linkage synthesize two-position`` (seed 001) and ``linkage sweep`` (seed 003); the
other synthesis problems register from their own modules. The use cases are :mod:`sim.design_service`'s:
these functions parse the options, print and write files."""

from __future__ import annotations

import json
import math

import numpy as np

from analytic import ParameterError
from analytic.format import expr
from analytic.applications import studies
from analytic.synthesis import two_position as synthesis
from sim import design_service
from sim.front.common import check_outputs, mechanism_from
from sim.output.jsonout import dumps
from sim.output.io import check_writable, write_csv

UNIT_TO_M = {"mm": 1e-3, "cm": 1e-2, "m": 1.0}


# --------------------------------------------------------------------------------------- synthesis
def _point(option: str, text: str) -> tuple[float, float]:
    parts = text.split(",")
    if len(parts) != 2:
        raise ParameterError(f"{option} {text!r} is not x,y (e.g. {option} 30,31)")
    return expr.parse_value(option, parts[0], angle=False), expr.parse_value(option, parts[1], angle=False)


def _angle_range(option: str, text: str) -> tuple[float, float]:
    if ":" not in text:
        raise ParameterError(f"{option} {text!r} is not LO:HI (e.g. {option} -90deg:90deg)")
    lo, hi = text.split(":", 1)
    return expr.parse_value(option, lo), expr.parse_value(option, hi)


def cmd_synthesize(args) -> int:
    if args.problem != "two-position":
        raise ParameterError(f"unknown synthesis problem {args.problem!r}: use two-position")
    if args.render:
        from sim.output.render import check_video_args
        check_video_args(args.render, args.fps, args.size)
    if args.plot:
        check_writable(args.plot, (".png", ".svg", ".pdf"))
    task = synthesis.Task(E1=_point("--E1", args.E1), E2=_point("--E2", args.E2), A=_point("--A", args.A),
                          D=_point("--D", args.D),
                          phi12=expr.parse_value("--crank-rotation", args.crank_rotation),
                          psi12=expr.parse_value("--rocker-rotation", args.rocker_rotation))
    lo, hi = _angle_range("--theta-range", args.theta_range)
    res = design_service.two_position(task, lo, hi, args.unit)
    rows, best, excluded, search = res["rows"], res["optimum"], res["excluded"], res["search"]
    if args.json:
        print(dumps({"rows": rows, "optimum": best, "excluded": excluded, "unit": args.unit}))
    else:
        print(_table(rows, best, args.unit))
        print(_excluded_summary(search.excluded))
    if best is None:
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
    th = np.linspace(lo, hi, 721)
    total = np.array([synthesis.design(task, float(t)).total for t in th])
    ok = np.array([synthesis.feasibility(task, synthesis.design(task, float(t)), 91) is None for t in th])
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
    with atomic_path(out) as tmp:
        fig.savefig(tmp, dpi=100)
    plt.close(fig)


def _render_design(task, dsg, args) -> None:
    """Animate the optimum moving E from E1 to E2 in MuJoCo, with E1 and E2 marked (SI scale)."""
    from sim.output.render import parse_size, render
    k = UNIT_TO_M[args.unit]
    duration = 2.0                                                 # seconds for the motion E1 -> E2
    mech = synthesis.mechanism(task, dsg, scale=k, omega1=task.phi12 / duration)
    built, tr = _simulate_partial(mech, abs(task.phi12) / (2 * math.pi))
    marks = tuple(tuple(task.local(q) * k) for q in (task.E1, task.E2))
    stats = render(built, tr, args.render, args.fps, parse_size(args.size), markers=marks)
    print(f"wrote {stats.path}: {stats.frames} frames (E1 and E2 marked with crosses)")


def _simulate_partial(mech, revolutions):
    """Simulate part of a turn (the crank need not turn fully: it only goes from position 1 to 2)."""
    from sim.model import build
    from sim.run.simulate import simulate
    built = build(mech, revolutions=revolutions)
    return built, simulate(built, revolutions)


# ------------------------------------------------------------------------------------------- sweep
MAX_COMBOS = design_service.MAX_COMBOS


def cmd_sweep(args) -> int:
    check_outputs(args, {"csv": (".csv",), "plot": (".png", ".svg", ".pdf")})
    base = mechanism_from(args)
    vary = design_service.parse_vary(args.vary, base) if args.vary else {}
    n = design_service.check_grid(vary, args.yes)
    if args.show < 0:
        raise ParameterError(f"--show {args.show} must be >= 0")
    from sim.output.progress import Progress
    bar = Progress(n, "sweep")
    rows, paths = design_service.sweep(base, vary, args.samples, keep_paths=12 if args.plot else 0,
                                       progress=bar.update, workers=args.workers, scheduler=args.scheduler,
                                       allow_large=args.yes)
    keys = list(vary)
    if args.csv:
        machine = _machine(args)
        cols, units = design_service.sweep_columns(base, keys, rows, machine)
        write_csv(args.csv, cols)
        from sim.output.io import write_text
        write_text(f"{args.csv}.units.json", json.dumps({"mechanism": base.name, "file_units": base.units,
                                                         "si": machine.is_si, "units": units}, indent=2) + "\n")
    from sim.output.units import shown_units
    shown = shown_units(args, base)
    print(_sweep_table(rows, keys, limit=args.show, display=shown))
    bad = [r for r in rows if not r.valid]
    print(f"{len(rows)} combinations, {len(rows) - len(bad)} valid" +
          (f"; invalid, e.g. {', '.join(f'{k}={v:g}' for k, v in bad[0].params.items())}: {bad[0].reason}" if bad else ""))
    if args.csv:
        print(f"wrote {args.csv}")
    if args.plot:
        _plot_family(paths, base.output_point, args.plot, len(rows), display=shown)
        print(f"wrote {args.plot}")
    return 0


def _machine(args):
    from sim.output.units import machine_units
    return machine_units(args)


def _sweep_table(rows, keys, limit: int, display=None) -> str:
    """The first ``limit`` rows: the varied values (file units), the path's box, area and speeds in
    ``display`` units (analytic.quantities.Display; None: SI)."""
    from analytic.quantities import SI
    u = display or SI
    f, L, V = u.factor("length"), u.unit("length"), u.unit("velocity")
    head = " ".join(f"{k:>10s}" for k in keys) + (
        f" {f'x range [{L}]':>21s} {f'y range [{L}]':>21s} {f'area [{L}^2]':>12s} {f'|v| mean [{V}]':>16s} "
        f"{'min':>8s} {'max':>8s} {'fluct.':>7s}")
    lines = [head]
    for r in rows[:limit]:
        p = " ".join(f"{r.params[k]:10.5g}" for k in keys)
        if not r.valid:
            lines.append(f"{p}  invalid: {r.reason}")
            continue
        v = {k: x * (f * f if k == "area" else f if k != "fluctuation" else 1.0) for k, x in r.values.items()
             if k in studies.STATS}                         # lengths, speeds: f; the area f^2
        lines.append(f"{p} {v['x_min']:10.5g}..{v['x_max']:<9.5g} {v['y_min']:10.5g}..{v['y_max']:<9.5g} "
                     f"{v['area']:12.4e} {v['speed_mean']:16.5g} {v['speed_min']:8.5g} {v['speed_max']:8.5g} "
                     f"{v['fluctuation']:7.4f}")
    if len(rows) > limit:
        lines.append(f"... {len(rows) - limit} more rows (--csv writes them all, --show N prints more)")
    return "\n".join(lines)


SWEEP_STYLES = ("-", "--", "-.", ":")
"""Line styles cycled once the distinct colours (matplotlib's tab20, dark shades first) run out."""


def family_styles(n: int) -> list[tuple[tuple, str]]:
    """(colour RGBA, line style) of ``n`` curves, no two alike: tab20's dark shades, then its light ones,
    each pass of 20 in the next line style."""
    import matplotlib
    tab = matplotlib.colormaps["tab20"].colors
    order = list(tab[0::2]) + list(tab[1::2])
    return [(order[i % 20], SWEEP_STYLES[(i // 20) % len(SWEEP_STYLES)]) for i in range(n)]


def _plot_family(paths, point, out, total, display=None) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from analytic.quantities import SI
    from sim.output.io import atomic_path
    u = display or SI
    f, L, V = u.factor("length"), u.unit("length"), u.unit("velocity")
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13, 5.5), constrained_layout=True)
    for (params_, t, x, y, speed), (color, ls) in zip(paths, family_styles(len(paths))):
        label = ", ".join(f"{k}={v:.4g}" for k, v in params_.items())
        ax1.plot(x * f, y * f, lw=1.4, color=color, ls=ls, label=label)
        ax2.plot(t / t[-1], speed * f, lw=1.4, color=color, ls=ls, label=label)
    ax1.set(title=f"Paths of {point}", xlabel=f"x [{L}]", ylabel=f"y [{L}]")
    ax1.set_aspect("equal", adjustable="datalim")
    ax2.set(title=f"Speed of {point} over one period (colours as in the paths)", xlabel="t / period",
            ylabel=f"|v{point}| [{V}]")
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
    ax1.legend(fontsize=8, loc="best")
    if total > len(paths):
        fig.suptitle(f"first {len(paths)} of {total} combinations")
    with atomic_path(out) as tmp:
        fig.savefig(tmp, dpi=100)
    plt.close(fig)


def register(sub, add_common, add_video_options) -> None:
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
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--plot", metavar="PATH", help="plot total length against theta (.png/.svg/.pdf)")
    p.add_argument("--render", metavar="PATH", help="animate the optimum moving E from E1 to E2 (.mp4/.gif)")
    add_video_options(p, out_required=False)
    p.set_defaults(func=cmd_synthesize)
    # further synthesis problems, each in its own module: module.register(problems, add_video_options)
    from sim.front import synth_exact_cmd
    synth_exact_cmd.register(problems, add_video_options)
    from sim.front import synth_path_cmd
    synth_path_cmd.register(problems, add_video_options)

    p = sub.add_parser("sweep", help="seed 003 parameter studies: families of output paths and speeds")
    add_common(p)
    p.add_argument("--vary", action="append", default=[], metavar="NAME=V1,V2,...|start:stop:count",
                   help="a varied parameter (repeatable: every combination is evaluated)")
    p.add_argument("--samples", type=int, default=360, help="samples per period (default 360)")
    p.add_argument("--csv", metavar="PATH", help="write every combination as CSV")
    p.add_argument("--plot", metavar="PATH", help="families of paths and speed curves (.png/.svg/.pdf)")
    p.add_argument("--show", type=int, default=20, metavar="N", help="rows to print (default 20)")
    p.add_argument("--yes", action="store_true", help=f"allow grids over {MAX_COMBOS:,} combinations")
    p.add_argument("--workers", type=int, default=1, help="processes for the grid's chunks (default 1)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="Dask scheduler address (or 'local': a local cluster "
                                                          "of --workers processes)")
    from sim.output.units import add_unit_options
    add_unit_options(p)
    p.set_defaults(revolutions=1.0)
    p.set_defaults(func=cmd_sweep)
