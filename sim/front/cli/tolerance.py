"""`linkage tolerance MECH`: the spread of a linkage's results under its parameters' tolerances, and which
tolerance drives each (SPEC, "Tolerance")."""

from __future__ import annotations

from analytic import ParameterError
from sim.front.cli.options import add_common


def register(sub) -> None:
    from sim.output.units import add_unit_options
    p = sub.add_parser("tolerance", help="Monte Carlo and Sobol tolerance analysis: path deviation, transmission, "
                                         "drive torque and joint forces under the parameters' tolerances")
    add_common(p)
    _drop_option(p, "--revolutions")                    # always one cycle of the inputs
    p.add_argument("--tol", action="append", default=[], metavar="NAME=±V",
                   help="a parameter's tolerance (repeatable): NAME=±V uniform on [-V, V] in the file's units "
                        "(+-V also works), NAME=±V%% relative to its value, NAME=normal:SIGMA")
    p.add_argument("--samples", type=int, default=1000, metavar="N", help="Monte Carlo designs (default 1000)")
    p.add_argument("--seed", type=int, default=1, metavar="S", help="random seed (default 1)")
    p.add_argument("--outputs", metavar="LIST",
                   help="outputs, comma-separated: path_deviation, transmission_min, transmission_max, "
                        "peak_torque, peak_joint_force, speed_fluctuation (default: the first five it has)")
    p.add_argument("--sobol", action="store_true",
                   help="variance-based Sobol indices S1 and ST (Saltelli design of N' (D+2) more designs, N' the "
                        "power of 2 >= N)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="evaluate the designs on a Dask scheduler (tcp://host:8786; 'local' starts one here); needs "
                        "pip install 'linkage[dask]'")
    p.add_argument("--workers", type=int, default=1, metavar="W",
                   help="worker processes on this machine, or of a --scheduler local cluster (default 1)")
    p.add_argument("--json", action="store_true", help="print one JSON object (SI unless --units/--angles)")
    p.add_argument("--plot", metavar="PATH", help="histograms and what drives each output: .png, .svg or .pdf")
    p.add_argument("--gravity", metavar="GX,GY", help="gravity in the plane [m/s^2], e.g. 0,-9.81")
    p.add_argument("--force", metavar="FX,FY", help="constant external force on the output point [N]")
    p.add_argument("--cutting-force", metavar="F",
                   help="a force F [N] resisting the output point's slow (cutting) stroke along x")
    p.add_argument("--inertia", metavar="PATH.json",
                   help='links\' inertial data: {"2": {"m": 0.5, "cx": 0.15, "cy": 0, "I": 0.004}, ...}')
    p.add_argument("--input-range", metavar="LO:HI",
                   help="rock the first input between LO and HI (e.g. a crank that cannot turn fully)")
    add_unit_options(p)
    p.set_defaults(func=cmd_tolerance)


def _drop_option(p, option: str) -> None:
    """Remove an option the shared helper added (from the parser and its help)."""
    action = p._option_string_actions.pop(option)
    p._remove_action(action)
    for group in p._action_groups:
        if action in group._group_actions:
            group._group_actions.remove(action)


def cmd_tolerance(args) -> int:
    from sim.service import tolerance as ts
    from sim.front.cli.options import check_outputs, load_keywords, mechanism_from, parse_range
    from sim.output.jsonout import dumps
    from sim.output.units import machine_units, shown_units
    check_outputs(args, {"plot": (".png", ".svg", ".pdf")})
    if not args.tol:
        raise ParameterError("give at least one --tol NAME=±V (e.g. --tol l1=±0.1; +-0.1 also works)")
    import linkage as lk
    mech = mechanism_from(args)
    keywords = load_keywords(args, mech)
    keywords.pop("torque")                             # the command takes no --torque
    from sim.output.progress import Progress
    bar = Progress(args.samples, "tolerance")
    t = lk.tolerance(mech, tol=args.tol, samples=args.samples, seed=args.seed, outputs=args.outputs,
                     sobol=args.sobol, scheduler=args.scheduler, workers=args.workers,
                     input_range=parse_range(mech, args.input_range), progress=bar.update, **keywords)
    result = t.result
    if args.plot:
        from sim.output.tolerance_plot import sheet
        sheet(result, mech, args.plot, shown_units(args, mech))
    if args.json:
        record = t.to_dict(display=machine_units(args))
        if args.plot:
            record["plot"] = args.plot
        print(dumps(record))
    else:
        print(ts.tolerance_table(result, mech, shown_units(args, mech)))
        if args.plot:
            print(f"wrote {args.plot}")
    return 0


__all__ = ["register", "cmd_tolerance"]
