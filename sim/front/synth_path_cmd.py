"""``linkage synthesize path TARGET.csv``: a four-bar whose coupler point passes through (or nearest to)
target points, by a seeded global search and a least-squares polish; every returned design simulated by
``linkage compare``."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from analytic import ParameterError
from analytic.synthesis import fourbar as synth_fourbar
from analytic.synthesis import path as sp
from analytic.format.linkfile import UNITS
from sim.output.io import atomic_path, check_writable, write_text
from sim.output.jsonout import dumps
from sim.run.parallel import mapper
from sim.output.progress import Progress
from sim.front.synth_exact_cmd import _check, _repeats, read_table


def read_target(path: str, timing: bool) -> sp.Target:
    """The target CSV (columns x,y and, with timing, phi in degrees) as a Target; one-line errors."""
    cols = ("x", "y", "phi") if timing else ("x", "y")
    data, lines = read_table(path, cols, ("phi",), True, 4)
    _repeats(path, data, lines, lambda d: d[:, :2], "point")
    if float(np.ptp(data[:, :2], axis=0).max()) <= 0:
        raise ParameterError(f"{path}: all points coincide; give points spread over the path")
    return sp.Target(data[:, :2].copy(), data[:, 2].copy() if timing else None)


def linkage_of(d: sp.Design) -> synth_fourbar.Linkage:
    """The design as a ``linkage/1`` four-bar (crank A-B, coupler B-C carrying E, rocker D-C), the crank
    starting at the first target's angle and turning the sense that meets the targets in order."""
    ax, ay, th, dd, a, b, c, ex, ey = (float(v) for v in d.x)
    steps = np.angle(np.exp(1j * np.diff(d.phis)))
    sense = 1.0 if steps.sum() >= 0 else -1.0
    return synth_fourbar.Linkage(A=(ax, ay), D=(ax + dd * math.cos(th), ay + dd * math.sin(th)), l1=a, l2=b,
                                 l3=c, ex=ex, ey=ey, branch=int(d.branch), phi1_0=float(d.phis[0]),
                                 omega1=sense * 2 * math.pi)


def _err(e) -> dict:
    e = np.abs(np.asarray(e, dtype=float))
    return {"sum_sq": float(np.sum(e ** 2)), "max": float(np.max(e)), "rms": float(np.sqrt(np.mean(e ** 2)))}


def out_names(out: str | None, k: int) -> list[str | None]:
    """FILE.toml for the best design, FILE_2.toml ... for the next ones."""
    if not out:
        return [None] * k
    p = Path(out)
    return [out] + [str(p.with_name(f"{p.stem}_{i}{p.suffix}")) for i in range(2, k + 1)]


def plot(path: str, target: sp.Target, designs: list[sp.Design], unit: str) -> None:
    """Targets over each candidate's coupler curve, one panel per candidate."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    k = len(designs)
    fig, axes = plt.subplots(1, k, figsize=(5 * k, 5), squeeze=False)
    phi = np.linspace(0, 2 * math.pi, 1441)
    for i, (ax, d) in enumerate(zip(axes[0], designs)):
        E, _ = sp.coupler_points(d.x[None], phi, d.branch)
        ax.plot(E[0, :, 0], E[0, :, 1], "-", color="tab:blue", lw=1.2, label="coupler curve")
        ax.plot(target.xy[:, 0], target.xy[:, 1], "o", mfc="none", color="tab:red", label="targets")
        A = d.x[:2]
        D = A + d.x[3] * np.array([math.cos(d.x[2]), math.sin(d.x[2])])
        ax.plot(*np.array([A, D]).T, "k^", ms=8, label="ground pivots")
        ax.set_aspect("equal")
        ax.set_title(f"#{i + 1}: sum of squares {d.sum_sq:.4g} {unit}^2"
                     + ("" if not d.failed else f"\n({d.failed})"), fontsize=9)
        ax.set_xlabel(f"x [{unit}]")
        ax.set_ylabel(f"y [{unit}]")
        ax.legend(fontsize=7, loc="best")
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format=Path(path).suffix.lstrip(".") or "png")
    plt.close(fig)


def cmd_path(args) -> int:
    if args.type != "fourbar":
        raise ParameterError(f"--type {args.type}: only fourbar is implemented for path synthesis")
    if args.out:
        check_writable(args.out, (".toml",))
    if args.plot:
        check_writable(args.plot, (".png", ".svg", ".pdf"))
    for name in ("designs", "restarts", "generations"):
        if getattr(args, name) < 1:
            raise ParameterError(f"--{name} {getattr(args, name)} must be >= 1")
    if not (0 <= args.min_transmission < 90):
        raise ParameterError(f"--min-transmission {args.min_transmission} must be in [0, 90) deg")
    if not (args.budget > 0):
        raise ParameterError(f"--budget {args.budget} must be > 0 seconds")
    target = read_target(args.target, args.timing)
    cons = sp.Constraints(mu_min=math.radians(args.min_transmission), max_ratio=args.max_ratio)
    restarts = max(args.restarts, args.designs)
    bar = Progress(restarts, "synthesize path")
    with mapper(args.workers, args.scheduler) as m:
        designs = sp.synthesize(target, cons, seed=args.seed, restarts=restarts, generations=args.generations,
                                budget=args.budget, mapper=m, progress=bar.update)
    designs = designs[:args.designs]
    names = out_names(args.out, len(designs))
    found = []
    for i, (d, fname) in enumerate(zip(designs, names)):
        link = linkage_of(d)
        text = synth_fourbar.text(link, args.unit, "path_fourbar",
                                  f"four-bar path generator through {len(target.xy)} targets "
                                  f"({'timed' if args.timing else 'free timing'}), seed {args.seed}; output E")
        mech = synth_fourbar.mechanism(link, args.unit)
        passed, mode = _check(mech, link, d.phis) if not d.failed else (False, "not run: " + d.failed)
        params = {**link.parameters(), "mu_min_deg": _mu_min_deg(d.x)}
        found.append({"file": fname, "error": _err(d.err), "error_unit": args.unit, "parameters": params,
                      "compare_passed": passed, "compare_mode": mode, "failed": d.failed, "text": text})
    ok = [f for f in found if not f["failed"] and f["compare_passed"]]
    for f in found:
        if f["file"] and (not f["failed"] or f is found[0]):
            write_text(f["file"], f["text"])
        elif f["file"]:
            f["file"] = None
    if args.plot:
        plot(args.plot, target, designs, args.unit)
    if args.json:
        print(dumps({"designs": [{k: v for k, v in f.items() if k != "text"} for f in found]}))
    else:
        for n, f in enumerate(found, 1):
            e = f["error"]
            state = "ok" if not f["failed"] and f["compare_passed"] else (f["failed"] or "compare failed")
            print(f"{n}. sum of squares {e['sum_sq']:.6g} {args.unit}^2, max {e['max']:.4g}, rms {e['rms']:.4g} "
                  f"{args.unit}; transmission >= {f['parameters']['mu_min_deg']:.1f} deg; compare "
                  f"{'passed' if f['compare_passed'] else 'FAILED'} ({f['compare_mode']}); {state}"
                  + (f"; wrote {f['file']}" if f["file"] else ""))
    if not ok:
        why = found[0]["failed"] or "it fails linkage compare"
        print(f"linkage: no path design meets the constraints; the best found (sum of squares "
              f"{found[0]['error']['sum_sq']:.6g}): {why}")
        return 1
    return 0


def _mu_min_deg(x) -> float:
    """The least transmission angle over a full crank turn [deg] (NaN if the crank cannot turn)."""
    d, a, b, c = (float(v) for v in x[3:7])
    lo = (b * b + c * c - (d - a) ** 2) / (2 * b * c)
    hi = (b * b + c * c - (d + a) ** 2) / (2 * b * c)
    if lo > 1 or hi < -1:
        return float("nan")
    return math.degrees(min(math.acos(lo), math.pi - math.acos(hi)))


def register(problems, add_video_options) -> None:
    """``synthesize path`` under ``linkage synthesize``."""
    p = problems.add_parser("path", help="four-bar whose coupler point passes through target points")
    p.add_argument("target", metavar="TARGET.csv",
                   help="CSV with columns x,y (and phi, the input angle in deg, with --timing)")
    p.add_argument("--timing", action="store_true", help="targets carry input angles (column phi, deg; "
                                                         "up to one common offset)")
    p.add_argument("--closed", action="store_true", help="the targets lie on a closed path (the coupler "
                                                         "curve is closed either way)")
    p.add_argument("--type", choices=("fourbar", "slider_crank", "sixbar"), default="fourbar")
    p.add_argument("--seed", type=int, default=0, help="random seed (same seed, same answer, any --workers)")
    p.add_argument("--budget", type=float, default=120.0, help="seconds at most (stops the search early; "
                                                               "then the answer depends on the speed)")
    p.add_argument("--min-transmission", type=float, default=30.0, help="least transmission angle [deg]")
    p.add_argument("--max-ratio", type=float, default=20.0, help="longest/shortest link at most")
    p.add_argument("--unit", choices=sorted(UNITS), default="m", help="length unit of x, y and the files")
    p.add_argument("--restarts", type=int, default=4, help="seeded restarts (both branches)")
    p.add_argument("--generations", type=int, default=400, help="differential-evolution generations per restart")
    p.add_argument("--designs", type=int, default=1, help="designs to return, best first")
    p.add_argument("--workers", type=int, default=1, help="processes for the restarts")
    p.add_argument("--scheduler", metavar="ADDRESS", help="Dask scheduler address (or 'local')")
    p.add_argument("--out", metavar="FILE.toml", help="write the best design (next ones FILE_2.toml ...)")
    p.add_argument("--plot", metavar="PATH", help="targets over each candidate's coupler curve (png/svg/pdf)")
    p.add_argument("--json", action="store_true", help="print one JSON object (SPEC: designs)")
    p.set_defaults(func=cmd_path)
