"""``linkage analyze MECH``: closed-form kinematics over a run; a summary, CSV or JSON."""

from __future__ import annotations



from sim.output.jsonout import dumps
from sim.output.units import add_unit_options
from sim.front.cli.options import (warn_size, add_common, check_outputs, mechanism_from, parse_range, write_columns)


def register(sub) -> None:
    p = sub.add_parser("analyze", help="closed-form kinematics over a run; summary, CSV or JSON")
    add_common(p)
    p.add_argument("--samples", type=int, default=361, metavar="N", help="samples (default 361)")
    from sim.front.cli.loads_opts import add_at
    add_at(p)
    p.add_argument("--input-range", metavar="LO:HI", help="sample the first input between LO and HI instead")
    p.add_argument("--csv", metavar="PATH", help="write every sample as CSV (units in PATH.units.json)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    add_unit_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    mech = mechanism_from(args)
    warn_size(mech)
    check_outputs(args, {"csv": (".csv",)})
    if getattr(args, "at", None) is not None:                  # one pose (SPEC "Loads": --at)
        from sim.front.cli.loads_opts import analyze_at
        if args.input_range:                   # a rocking drive: the pose where it first passes --at
            from sim.service.analysis import check_range
            mech = mech.rocking(*check_range(mech, *parse_range(mech, args.input_range)))
        return analyze_at(args, mech)
    import linkage as lk
    result = lk.analyze(mech, samples=args.samples, revolutions=args.revolutions,
                        input_range=parse_range(mech, args.input_range))
    a = result.analysis
    from sim.output.units import machine_units, shown_units
    if args.csv:
        write_columns(args.csv, mech, result.columns, machine_units(args))
    if args.json:
        record = result.to_dict(display=machine_units(args))
        if args.csv:
            record["csv"] = args.csv
        print(dumps(record))
    else:
        from sim.service.analysis import parameters_text, summary_lines
        shown = shown_units(args, mech)
        print("\n".join([f"{mech.name}: {parameters_text(mech, shown)}"] + summary_lines(mech, a.figures, shown)))
        if args.csv:
            print(f"wrote {args.csv} ({args.samples} rows)")
    return 0
