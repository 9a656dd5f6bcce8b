"""``linkage synthesize path TARGET.csv --objectives error,torque,...``: a Pareto set of path generators
(:mod:`sim.service.pareto`), each checked in MuJoCo; JSON ``front``, a CSV of the front, a plot of the front
with each design's coupler curve, and the designs' files."""

from __future__ import annotations

import lazy_loader

import math
import sys
from pathlib import Path

import numpy as np

from analytic import ParameterError
from sim.service.values import parse_value
from sim.output.io import atomic_path, check_writable, write_text
from sim.output.jsonout import dumps
from sim.output.progress import Progress

# loaded by the command, not by its options (suppress_warning: the parent, sim.service, is light and loaded)
design_service = lazy_loader.load("sim.service.design", suppress_warning=True)  # scipy and pymoo
P = lazy_loader.load("sim.service.pareto", suppress_warning=True)

UNITS_OF = {"error": "{u}", "peak_torque": "N m", "peak_bearing": "N", "rms_shaking": "N", "size": "{u}"}


def register(p) -> None:
    """The multi-objective options of ``synthesize path``."""
    p.add_argument("--objectives", metavar="LIST",
                   help="two or more of error,torque,bearing,shaking,size: a Pareto set (NSGA-II) instead of "
                        "one best design; each design of the front is checked in MuJoCo")
    p.add_argument("--force", metavar="FX,FY", help="--objectives: a force [N] on the traced point")
    p.add_argument("--cutting", action="store_true", help="--objectives: --force acts on the slow stroke only")
    p.add_argument("--gravity", metavar="GX,GY", help="--objectives: gravity in the plane [m/s^2]")
    p.add_argument("--front", type=int, default=6, help="--objectives: designs of the front returned at most")
    p.add_argument("--csv", metavar="PATH", help="--objectives: the front as CSV")
    p.add_argument("--max-error", type=float, metavar="E",
                   help="--objectives: the largest RMS target distance a design of the front may have (file units)")


def _pair(option: str, text: str | None):
    if text is None:
        return None
    parts = text.split(",")
    if len(parts) != 2:
        raise ParameterError(f"{option} {text!r} is not two numbers X,Y")
    return tuple(parse_value(option, v, angle=False) for v in parts)


def options_of(args, path_options) -> P.ParetoOptions:
    if args.budget is not None:
        raise ParameterError("--objectives runs a counted search: give --evaluations N (or --generations), not "
                             "--budget")
    if args.type not in P.FRONT_TYPES:
        raise ParameterError(f"--objectives with --type {args.type}: use {' or '.join(P.FRONT_TYPES)}")
    generations = args.generations or 30
    return P.ParetoOptions(P.parse_objectives(args.objectives), args.type, args.seed, args.popsize, generations,
                           front=args.front, force=_pair("--force", args.force) or (0.0, 0.0), cutting=args.cutting,
                           gravity=_pair("--gravity", args.gravity), constraints=path_options.constraints,
                           max_error=args.max_error, evaluations=args.evaluations).check()


def write_csv(path: str, front: list[dict], unit: str) -> None:
    cols = ["design", "type", "error", "peak_torque", "peak_bearing", "rms_shaking", "size", "transmission_min_deg",
            "simulated_passed", "simulated_peak_torque", "simulated_peak_bearing", "simulated_rms_shaking", "file"]
    lines = ["# units: error, size in " + unit + "; torque N m; forces N", ",".join(cols)]
    for n, f in enumerate(front, 1):
        s = f["simulated"]
        row = [n, f["type"], f["error"], f["peak_torque"], f["peak_bearing"], f["rms_shaking"], f["size"],
               f["transmission_deg"][0], int(s["passed"]), s["peak_torque"], s["peak_bearing"], s["rms_shaking"],
               f["file"] or ""]
        lines.append(",".join(repr(v) if isinstance(v, float) else str(v) for v in row))
    write_text(path, "\n".join(lines) + "\n")


def plot(path: str, target, front: list[dict], objectives: list[str], unit: str) -> None:
    """The front (the first objective against each other one, designs numbered) and each design's coupler
    curve over the targets, its ground pivots marked."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from sim.output.fit import fit
    keys = [P.OBJECTIVES[o] for o in objectives]
    others = keys[1:]
    k = len(front)
    ncols = max(len(others), min(k, 4))
    nrows = 1 + math.ceil(k / ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(4.2 * ncols, 3.8 * nrows), squeeze=False)
    colors = plt.cm.viridis(np.linspace(0, 0.9, max(k, 2)))
    label = {key: f"{key.replace('_', ' ')} [{UNITS_OF[key].format(u=unit)}]" for key in keys}
    for j, ax in enumerate(axes[0]):
        if j >= len(others):
            ax.axis("off")
            continue
        xs = [f[keys[0]] for f in front]
        ys = [f[others[j]] for f in front]
        if len(keys) == 2:                     # two objectives: the front is a curve (more: a projection)
            ax.plot(xs, ys, "-", color="0.7", lw=1, zorder=1)
        for n, (a, b) in enumerate(zip(xs, ys)):
            ax.scatter([a], [b], color=colors[n], zorder=2, s=36)
            ax.annotate(str(n + 1), (a, b), textcoords="offset points", xytext=(5, 4), fontsize=8)
        ax.set_xlabel(label[keys[0]])
        ax.set_ylabel(label[others[j]])
        ax.set_title("Pareto front (checked in MuJoCo)" if len(keys) == 2 else
                     f"Pareto front of {len(keys)} objectives: projection", fontsize=9)
        ax.grid(alpha=0.3)
    for n, f in enumerate(front):
        ax = axes[1 + n // ncols][n % ncols]
        d = f["design"]
        E = design_service.curve(f)
        ax.plot(E[:, 0], E[:, 1], "-", color=colors[n], lw=1.4, label="coupler curve")
        ax.plot(target.xy[:, 0], target.xy[:, 1], "o", mfc="none", color="tab:red", ms=4, label="targets")
        piv = d.family.pivots(d.x[None])[0][:len(d.family.pivot_names)]
        ax.plot(piv[:, 0], piv[:, 1], "k^", ms=7, label="ground pivots")
        ax.set_aspect("equal")
        ax.set_title(f"#{n + 1}: " + ", ".join(f"{o} {f[P.OBJECTIVES[o]]:.3g}" for o in objectives), fontsize=8)
        ax.set_xlabel(f"x [{unit}]")
        ax.set_ylabel(f"y [{unit}]")
        if n == 0:
            ax.legend(fontsize=7, loc="best")
    for n in range(k, (nrows - 1) * ncols):
        axes[1 + n // ncols][n % ncols].axis("off")
    fig.tight_layout()
    fit(fig)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=100, format=Path(path).suffix.lstrip(".") or "png")
    plt.close(fig)


def cmd(args, path_options, target) -> int:
    """Run the multi-objective search and write/print its checked front; exit 1 when none passes."""
    import time
    from sim.front.cli.synth_options import out_names
    if args.csv:
        check_writable(args.csv, (".csv",))
    opts = options_of(args, path_options)
    bar = Progress(opts.generations, "synthesize path --objectives")
    t0 = time.time()
    res = P.pareto(target, opts, args.unit, path_options.limits, progress=bar.update)
    seconds = time.time() - t0
    front = res["front"]
    for f, name in zip(front, out_names(args.out, len(front))):
        if name:
            write_text(name, f["text"])
            f["file"] = name
    if args.csv and front:
        write_csv(args.csv, front, args.unit)
    if args.plot and front:
        plot(args.plot, target, front, res["objectives"], args.unit)
    run = {"evaluations": res["evaluations"], "seconds": seconds, "seed": args.seed,
           "generations": res.get("generations", opts.generations), "evaluations_bound": args.evaluations,
           "popsize": opts.popsize, "loads": {"force": list(opts.force), "cutting": opts.cutting,
                                              "gravity": list(opts.gravity) if opts.gravity else None}}
    if args.json:
        out = [{"design": {k: f[k] for k in ("type", "parameters", "file")},
                **{k: v for k, v in f.items() if k not in ("type", "parameters", "file", "text", "design")},
                "evaluations": res["evaluations"]} for f in front]
        print(dumps({"objectives": res["objectives"], "front": out, "rejected": res["rejected"], "run": run}))
    else:
        print(f"Pareto front ({', '.join(res['objectives'])}), {len(front)} designs checked in MuJoCo:")
        for n, f in enumerate(front, 1):
            print(f"{n}. {f['type']}: error rms {f['error']:.4g} {args.unit}, peak torque {f['peak_torque']:.4g} N m, "
                  f"peak bearing {f['peak_bearing']:.4g} N, rms shaking {f['rms_shaking']:.4g} N, size "
                  f"{f['size']:.4g} {args.unit}; transmission {f['transmission_deg'][0]:.1f}-"
                  f"{f['transmission_deg'][1]:.1f} deg; simulated: "
                  f"{'passed' if f['simulated']['passed'] else 'FAILED'}" + (f"; wrote {f['file']}" if f["file"] else ""))
        for r in res["rejected"]:
            print(f"   dropped: {r['why']}")
        print(f"{res['evaluations']} evaluations in {seconds:.1f} s (seed {args.seed}; reproducible)")
        for extra in (args.csv, args.plot):
            if extra and front:
                print(f"wrote {extra}")
    if not front:
        print("linkage: no design of the front passes its checks" + (f": {res['rejected'][0]['why']}"
                                                                       if res["rejected"] else ""),
              file=sys.stderr if args.json else sys.stdout)
        return 1
    return 0
