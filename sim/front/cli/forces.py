"""`linkage forces MECH`: every joint's force, the drives, the shaking force and moment (SPEC, "Forces")."""

from __future__ import annotations

from analytic import ParameterError
from sim.front.cli.options import add_common, add_sim_options


def register(sub) -> None:
    from sim.output.units import add_unit_options
    p = sub.add_parser("forces", help="forces in every joint, the drives, the shaking force; balancing")
    add_common(p)
    add_sim_options(p)
    p.add_argument("--samples", type=int, default=361, metavar="N", help="samples (default 361)")
    p.add_argument("--json", action="store_true", help="print one JSON object (SI unless --units/--angles)")
    p.add_argument("--csv", metavar="PATH", help="write every sample as CSV (units in PATH.units.json)")
    p.add_argument("--balance", nargs="?", const="", default=None, metavar="LINK,LINK",
                   help="counterweights minimising the RMS shaking force (a four-bar: full force balance); on the "
                        "links named (default: those pivoted at the ground); before/after reported")
    p.add_argument("--simulate", action="store_true",
                   help="also run the MuJoCo model and compare its joint forces with the analytic ones")
    p.add_argument("--pressure", metavar="P",
                   help="size each actuator for this supply pressure (e.g. 200bar; units Pa, kPa, MPa, bar, psi): "
                        "the bore its peak push needs (area pi D^2/4) and its peak pull needs round the rod "
                        "(pi (D^2 - d^2)/4)")
    from sim.front.cli.loads_opts import add_at
    add_at(p)
    add_unit_options(p)
    p.set_defaults(func=cmd_forces)


def balance_links(text: str | None):
    """``--balance``: None (not asked), () (the default links) or the named links."""
    if text is None:
        return None
    names = tuple(x.strip() for x in text.split(",") if x.strip())
    if text.strip() and not names:
        raise ParameterError(f"--balance {text!r}: give link names separated by commas (e.g. --balance 1,3)")
    return names


def cmd_forces(args) -> int:
    import json
    import linkage as lk
    from sim import service
    from sim.front.cli.options import check_outputs, load_keywords, mechanism_from, parse_range, settings_from
    from sim.output.io import write_csv, write_text
    from sim.output.jsonout import dumps
    from sim.output.units import machine_units, shown_units
    check_outputs(args, {"csv": (".csv",)})
    mech = mechanism_from(args)
    from sim.front.cli.loads_opts import at_value
    keywords = load_keywords(args, mech)
    at = at_value(args, mech)
    if at is not None and (args.simulate or args.balance is not None):
        raise ParameterError("--at evaluates one pose: it does not combine with --simulate or --balance")
    links = balance_links(args.balance)
    from sim.service.forces import supply_pressure
    pressure = supply_pressure(args.pressure, mech) if args.pressure is not None else None
    settings = settings_from(args) if args.simulate else None
    f = lk.forces(mech, samples=args.samples, revolutions=args.revolutions,
                  input_range=parse_range(mech, args.input_range),
                  balance=links, at=at, simulate=args.simulate,
                  timestep=settings.timestep if settings else None,
                  integrator=settings.integrator if settings else None, pressure=pressure, **keywords)
    run = f.run
    display = machine_units(args, mech)
    written = args.csv and f.passed                 # a failed MuJoCo check writes nothing (exit 1)
    if args.csv and not written:
        from sim.front.cli.options import say_not_written
        say_not_written([args.csv, f"{args.csv}.units.json"], "MuJoCo's joint forces disagree with the analytic ones")
    if written:
        cols, qty = service.forces_columns(run)
        write_csv(args.csv, {c: display.convert(qty[c], v) for c, v in cols.items()})
        write_text(f"{args.csv}.units.json", json.dumps(
            {"mechanism": mech.name, "parameters": mech.parameters, "file_units": mech.units, "si": display.is_si,
             "units": {c: display.unit(q) for c, q in qty.items()}}, indent=2) + "\n")
    if args.json:
        record = f.to_dict(display=display)
        if written:
            record["csv"] = args.csv
        print(dumps(record))
    else:
        print(service.forces_table(run, shown_units(args, mech)))
        simulated = f.to_dict(display=display).get("simulated") if args.simulate else None
        if simulated is not None:
            a = simulated["agreement"]
            plain = ", the file's masses without the counterweights" if run.balance is not None else ""
            means = f" (means over {a['window']} steps: a cam's contact is a train of impulses)" if a.get("window") else ""
            print(f"  MuJoCo ({simulated['steps']} steps of {simulated['timestep']:.3g} s{plain}): joint forces within "
                  f"{a['worst']:.2e} of the peak {a['peak']:.4g} N ({a['worst_of']}; median {a['median']:.2e}), "
                  f"tolerance {a['tol']:{'.2g' if means else '.0e'}}{means}: {'PASSED' if simulated.get('passed') else 'FAILED'}")
        if written:
            print(f"wrote {args.csv} ({len(run.t)} rows)")
    return 0 if f.passed else 1


__all__ = ["register", "cmd_forces", "balance_links"]
