"""``linkage sweep MECH --vary NAME=...``: seed 003's parameter studies, families of output paths and speeds
(the use case: :func:`sim.service.design.sweep`)."""

from __future__ import annotations

import json

from analytic import ParameterError
from sim.service.design import MAX_COMBOS, STATS
from sim.front.cli.options import add_common, check_outputs, mechanism_from
from sim.output.io import write_csv


def register(sub) -> None:
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
                                                          "of --workers processes); needs pip install 'linkage[dask]'")
    p.add_argument("--forces", action="store_true",
                   help="also each design's peak joint (bearing) force, peak drive torque (a slider: force) and "
                        "energy per cycle, with the file's [[loads]]/[friction] and the loads below (implied by them)")
    p.add_argument("--gravity", metavar="GX,GY", help="gravity in the plane [m/s^2] for --forces, e.g. 0,-9.81")
    p.add_argument("--force", metavar="FX,FY[@POINT[:LINK]]",
                   help="constant external force [N] on the output point, or at POINT on LINK, for --forces")
    p.add_argument("--cutting-force", metavar="F",
                   help="a force F [N] resisting the output point's slow (cutting) stroke along x, for --forces")
    from sim.front.cli.loads_opts import add_options
    add_options(p)
    p.add_argument("--inertia", metavar="PATH.json", help="links' inertial data for --forces (as linkage forces)")
    from sim.output.units import add_unit_options
    add_unit_options(p)
    p.set_defaults(revolutions=1.0)
    p.set_defaults(func=run)


MAX_FORCE_COMBOS = 2000
"""Largest grid whose forces (one forces run per design) are computed without an explicit --yes."""


def run(args) -> int:
    from sim.service import design as design_service
    check_outputs(args, {"csv": (".csv",), "plot": (".png", ".svg", ".pdf")})
    base = mechanism_from(args)
    vary = design_service.parse_vary(args.vary, base) if args.vary else {}
    n = design_service.check_grid(vary, args.yes)
    if args.show < 0:
        raise ParameterError(f"--show {args.show} must be >= 0")
    from sim.output.progress import Progress
    bar = Progress(n, "sweep")
    forces = args.forces or any(getattr(args, k) for k in ("gravity", "force", "cutting_force", "torque", "inertia"))
    loads = None
    if forces:
        from sim.front.cli.options import loads_from
        loads = loads_from(args, base)
        if n > MAX_FORCE_COMBOS and not args.yes:
            raise ParameterError(f"--forces over {n:,} combinations (over {MAX_FORCE_COMBOS:,}; each design takes a "
                                 f"forces run, 5-50 ms): narrow the grid, or add --yes")
    rows, paths = design_service.sweep(base, vary, args.samples, keep_paths=12 if args.plot else 0,
                                       progress=bar.update, workers=args.workers, scheduler=args.scheduler,
                                       allow_large=args.yes)
    if forces:
        from sim.service.sweep_forces import sweep_forces
        rows = sweep_forces(base, rows, loads, args.samples, progress=Progress(n, "forces").update)
    keys = list(vary)
    if args.csv:
        machine = _machine(args, base)
        cols, units = design_service.sweep_columns(base, keys, rows, machine)
        write_csv(args.csv, cols)
        from sim.output.io import write_text
        write_text(f"{args.csv}.units.json", json.dumps({"mechanism": base.name, "file_units": base.units,
                                                         "si": machine.is_si, "units": units}, indent=2) + "\n")
    from sim.output.units import shown_units
    shown = shown_units(args, base)
    print(_sweep_table(rows, keys, limit=args.show, display=shown, angular=base.inputs[0].angular))
    bad = [r for r in rows if not r.valid]
    print(f"{len(rows)} combinations, {len(rows) - len(bad)} valid" +
          (f"; invalid, e.g. {', '.join(f'{k}={v:g}' for k, v in bad[0].params.items())}: {bad[0].reason}" if bad else ""))
    if args.csv:
        print(f"wrote {args.csv}")
    if args.plot:
        _plot_family(paths, base.output_point, args.plot, len(rows), display=shown)
        print(f"wrote {args.plot}")
    return 0


def _machine(args, base=None):
    from sim.output.units import machine_units
    return machine_units(args, base)


def _sweep_table(rows, keys, limit: int, display=None, angular: bool = True) -> str:
    """The first ``limit`` rows: the varied values (file units), the path's box, area and speeds in
    ``display`` units (analytic.quantities.Display; None: SI); with ``--forces`` the peak joint force, the
    peak drive (a torque for a turning input, ``angular``, else a force) and the energy per cycle [J]."""
    from sim.service.analysis import SI
    from sim.service.sweep_forces import FORCE_FIGURES
    u = display or SI
    f, L, V = u.factor("length"), u.unit("length"), u.unit("velocity")
    with_forces = any(FORCE_FIGURES[0] in r.values for r in rows)
    dq = "torque" if angular else "force"
    head = " ".join(f"{k:>10s}" for k in keys) + (
        f" {f'x range [{L}]':>21s} {f'y range [{L}]':>21s} {f'area [{L}^2]':>12s} {f'|v| mean [{V}]':>16s} "
        f"{'min':>8s} {'max':>8s} {'fluct.':>7s}")
    if with_forces:
        F, D = u.unit("force"), u.unit(dq)
        head += (f" {f'peak |F| [{F}]':>16s} {f'peak drive [{D}]':>18s} "
                 f"{'energy/cycle [J]':>17s}")
    lines = [head]
    for r in rows[:limit]:
        p = " ".join(f"{r.params[k]:10.5g}" for k in keys)
        if not r.valid:
            lines.append(f"{p}  invalid: {r.reason}")
            continue
        v = {k: x * (f * f if k == "area" else f if k != "fluctuation" else 1.0) for k, x in r.values.items()
             if k in STATS}                         # lengths, speeds: f; the area f^2
        lines.append(f"{p} {v['x_min']:10.5g}..{v['x_max']:<9.5g} {v['y_min']:10.5g}..{v['y_max']:<9.5g} "
                     f"{v['area']:12.4e} {v['speed_mean']:16.5g} {v['speed_min']:8.5g} {v['speed_max']:8.5g} "
                     f"{v['fluctuation']:7.4f}" + (
                         f" {u.convert('force', r.values['peak_joint_force']):16.5g} "
                         f"{u.convert(dq, r.values['peak_drive']):18.5g} {r.values['energy_per_cycle']:17.5g}"
                         if with_forces else ""))
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
    from sim.service.analysis import SI
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


