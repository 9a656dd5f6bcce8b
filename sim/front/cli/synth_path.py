"""``linkage synthesize path TARGET.csv``: a four-bar, slider-crank or six-bar whose traced point passes
through (or nearest to) target points (the use case: :func:`sim.service.design.synthesize_path`); this
module parses the options, writes the files and the plot, prints the table or JSON."""

from __future__ import annotations

import lazy_loader

from pathlib import Path


from sim.service.design import DEFAULT_TYPE, TYPES
from sim.front.cli.synth_options import add_limits, add_units, limits_of, measure_words, out_names
from sim.output.io import atomic_path, check_writable, write_text
from sim.output.jsonout import dumps
from sim.output.progress import Progress

# loaded by the command, not by its options (suppress_warning: the parent, sim.service, is light and loaded)
design_service = lazy_loader.load("sim.service.design", suppress_warning=True)  # scipy's optimisers


def plot(path: str, target, found: list[dict], unit: str) -> None:
    """Targets over each candidate's coupler curve, one panel per candidate, ground pivots marked."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from sim.output.fit import fit
    k = len(found)
    fig, axes = plt.subplots(1, k, figsize=(5 * k, 5), squeeze=False)
    for i, (ax, f) in enumerate(zip(axes[0], found)):
        d = f["design"]
        E = design_service.curve(f)
        ax.plot(E[:, 0], E[:, 1], "-", color="tab:blue", lw=1.2, label="coupler curve")
        ax.plot(target.xy[:, 0], target.xy[:, 1], "o", mfc="none", color="tab:red", label="targets")
        piv = d.family.pivots(d.x[None])[0]
        ax.plot(piv[:, 0], piv[:, 1], "k^", ms=8, label="ground pivots")
        ax.set_aspect("equal")
        ax.set_title(f"#{i + 1} {d.family.label}: sum of squares {f['error']['sum_sq']:.4g} {unit}^2"
                     + ("" if not f["failed"] else f"\n({f['failed']})"), fontsize=9)
        ax.set_xlabel(f"x [{unit}]")
        ax.set_ylabel(f"y [{unit}]")
        ax.legend(fontsize=7, loc="best")
    fig.tight_layout()
    fit(fig)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format=Path(path).suffix.lstrip(".") or "png")
    plt.close(fig)


def options_of(args) -> design_service.PathOptions:
    """The command line's :class:`PathOptions`."""
    lim = limits_of(args)
    return design_service.PathOptions(
        types=(args.type,), seed=args.seed, restarts=args.restarts, generations=args.generations,
        popsize=args.popsize, budget=args.budget, designs=args.designs, min_transmission=lim.min_transmission,
        max_ratio=args.max_ratio, region=args.region, workers=args.workers, scheduler=args.scheduler,
        evaluations=args.evaluations, max_size=lim.max_size, boxes=lim.regions, grashof=lim.grashof).check()


def process_started() -> float:
    """``time.time()`` at which this process started (Linux: from /proc, so the interpreter's start and the
    imports count against a --budget as a user's clock counts them), else now."""
    import os
    import time
    try:
        with open("/proc/self/stat") as f:                     # field 22: starttime, clock ticks after boot
            ticks = int(f.read().rsplit(")", 1)[1].split()[19])
        with open("/proc/uptime") as f:
            uptime = float(f.read().split()[0])
        return time.time() - max(0.0, uptime - ticks / os.sysconf("SC_CLK_TCK"))
    except (OSError, ValueError, IndexError):
        return time.time()


def cmd_path(args) -> int:
    started = process_started()
    if args.out:
        check_writable(args.out, (".toml",))
    if args.plot:
        check_writable(args.plot, (".png", ".svg", ".pdf"))
    options = options_of(args)
    target = design_service.read_target(args.target, args.timing, args.closed, not args.any_order)
    why = design_service.unreachable(target.xy, options.limits, args.unit)
    if why:                                 # limits no design can meet: say so, search nothing, write nothing
        import sys
        if args.json:
            print(dumps({"designs": [], "rejected": [{"type": args.type, "why": why}],
                         "run": {"evaluations": 0, "seconds": 0.0, "seed": args.seed}}))
        print(f"linkage: no path design can meet the constraints: {why}", file=sys.stderr if args.json else sys.stdout)
        return 1
    if args.objectives:
        from sim.front.cli import synth_pareto
        return synth_pareto.cmd(args, options, target)
    bar = Progress(options.restart_count + options.designs, "synthesize path")
    try:
        found = design_service.synthesize_path(target, options, args.unit, progress=bar.update, started=started)
    except design_service.BudgetSpent as e:        # no time for a search: no design, said in one line
        import sys
        import time
        if args.json:
            print(dumps({"designs": [], "rejected": [{"type": args.type, "why": str(e)}],
                         "run": {"evaluations": 0, "seconds": time.time() - started, "stopped_by_budget": True, "budget": args.budget,
                                 "seed": args.seed}}))
        print(f"linkage: no path design within the budget: {e}", file=sys.stderr if args.json else sys.stdout)
        return 1
    ok = [f for f in found if not f["failed"] and f["compare_passed"] and f["simulated"]["passed"]]
    rejected = [{"type": f["type"], "parameters": f["parameters"], "error": f["error"],
                 "why": f["failed"] or (f["simulated"] or {}).get("problem") or "it fails linkage compare"}
                for f in found if f not in ok]
    for f, fname in zip(ok, out_names(args.out, len(ok))):
        if fname:
            write_text(fname, f["text"])
            f["file"] = fname
    if args.plot and ok:
        plot(args.plot, target, ok, args.unit)
    stats = found[0]["stats"]
    run = {"evaluations": found[0]["evaluations"], "polish_evaluations": found[0]["polish_evaluations"],
           "evaluations_bound": args.evaluations, "seconds": stats["seconds"],
           "stopped_by_budget": bool(stats.get("stopped_by_budget")), "budget": args.budget, "seed": args.seed,
           "restarts": int(stats.get("restarts", max(options.restart_count, options.designs))),
           "generations": options.generations_value if args.evaluations is None else
           int(stats.get("de_generations", 0))}
    if args.json:
        print(dumps({"designs": [{k: v for k, v in f.items() if k not in ("text", "design")} for f in ok],
                     "rejected": rejected, "run": run}))
    else:
        for n, f in enumerate(ok, 1):
            e = f["error"]
            print(f"{n}. {f['type']}: sum of squares {e['sum_sq']:.6g} {args.unit}^2, max {e['max']:.4g}, rms "
                  f"{e['rms']:.4g} {args.unit}; {measure_words(f, args.unit)}; compare and forces in MuJoCo passed "
                  f"({f['compare_mode']})" + (f"; wrote {f['file']}" if f["file"] else ""))
            for note in f.get("notes", []):
                print("   note: " + note)
        for f in rejected:
            print(f"   turned down: {f['type']}, sum of squares {f['error']['sum_sq']:.6g} {args.unit}^2: {f['why']}")
        print(f"{run['evaluations']} evaluations in {run['seconds']:.1f} s (seed {args.seed}"
              + (f"; stopped by --budget {args.budget:g} s: the best so far" if run["stopped_by_budget"] else
                 "" if args.budget else "; reproducible: the same seed gives the same answer") + ")")
        if args.plot and ok:
            print(f"wrote {args.plot}")
    if not ok:
        import sys
        print(f"linkage: no path design meets the constraints; the best found (sum of squares "
              f"{found[0]['error']['sum_sq']:.6g}): {rejected[0]['why']}", file=sys.stderr if args.json else sys.stdout)
        return 1
    return 0


def register(problems) -> None:
    """``synthesize path`` under ``linkage synthesize``."""
    p = problems.add_parser("path", help="four-bar, slider-crank or six-bar whose traced point passes through "
                                         "target points")
    p.add_argument("target", metavar="TARGET.csv",
                   help="CSV with columns x,y (and phi, the input angle in deg, with --timing); lines starting "
                        "with # are comments; without a header row the columns are x,y(,phi) in that order")
    p.add_argument("--timing", action="store_true", help="targets carry input angles (column phi, deg; "
                                                         "up to one common offset)")
    p.add_argument("--closed", action="store_true",
                   help="the targets go once round a closed path (the last and the first are neighbours); "
                        "default: an open path, met in order from the first to the last, the return free")
    p.add_argument("--any-order", action="store_true",
                   help="the targets need not be met in their order: each one's distance to the coupler curve "
                        "alone (an open path)")
    p.add_argument("--type", choices=tuple(TYPES), default=DEFAULT_TYPE,
                   help="fourbar, slider_crank, or sixbar (Watt II and Stephenson III both searched)")
    p.add_argument("--seed", type=int, default=0, help="random seed (same seed, same answer, any --workers)")
    budget = p.add_mutually_exclusive_group()
    budget.add_argument("--evaluations", type=int, default=None, metavar="N",
                        help="designs evaluated on the targets at most, the whole run: the atlas, differential "
                             "evolution's populations, every pose and every polish's residuals, Jacobian difference "
                             "designs and finishes (JSON run.evaluations <= N; the hops' and final polishes' own "
                             "count: polish_evaluations). The random shapes screened against the limits before any "
                             "is posed (20,000 a restart) are not evaluated on the targets and not counted; the "
                             "compare and force checks of the returned designs neither. Restarts are cut to fit. "
                             "Reproducible: the same seed gives the same answer on any machine and --workers. "
                             "Default: fixed counts (no bound), reproducible too")
    budget.add_argument("--budget", type=float, default=None, metavar="SECONDS",
                        help="a hard wall-clock limit on the whole command, from its start (imports, a local "
                             "cluster's start and the checks included): the search stops and returns its best so "
                             "far, polished within it, leaving time for the checks by the machine's load (the "
                             "answer then depends on the machine)")
    add_limits(p, "A, D (four-bar); A (slider-crank); A, D, G (six-bars)")
    p.add_argument("--max-ratio", type=float, default=20.0, help="longest/shortest link at most")
    p.add_argument("--region", type=float, default=3.0,
                   help="ground pivots within this many target sizes of the targets' centre (default 3)")
    add_units(p, "length unit of x, y and the files")
    p.add_argument("--restarts", type=int, default=None,
                   help="seeded restarts (default: 16, eight per branch; sixbar: 8, one per chain and branches)")
    p.add_argument("--generations", type=int, default=None,
                   help="differential-evolution generations per restart (default: 80; sixbar: 400)")
    p.add_argument("--popsize", type=int, default=40, help="differential-evolution population per restart")
    p.add_argument("--designs", type=int, default=1, help="designs to return, best first")
    p.add_argument("--workers", type=int, default=1, help="processes for the restarts and the compares")
    p.add_argument("--scheduler", metavar="ADDRESS", help="Dask scheduler address (or 'local': a local cluster "
                                                          "of --workers processes); needs pip install 'linkage[dask]'")
    p.add_argument("--out", metavar="FILE.toml", help="write the best design (next ones FILE_2.toml ...)")
    p.add_argument("--plot", metavar="PATH", help="targets over each candidate's coupler curve (png/svg/pdf)")
    p.add_argument("--json", action="store_true", help="print one JSON object (SPEC: designs)")
    from sim.front.cli import synth_pareto
    synth_pareto.register(p)
    p.set_defaults(func=cmd_path)
