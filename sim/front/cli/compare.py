"""``linkage compare MECH``: the simulation cross-validated against the analytic solution."""

from __future__ import annotations

import sys


from sim import service
from sim.output.jsonout import dumps
from sim.output.units import add_unit_options
from sim.front.cli.options import (add_common, add_sim_options, loads_from,
                                   mechanism_from, parse_range, say_start, settings_from)


def register(sub) -> None:
    p = sub.add_parser("compare", help="simulate and cross-validate against the analytic solution")
    add_common(p)
    add_sim_options(p)
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--interference", action="store_true",
                   help="also sweep the link solids over the same run (linkage check --interference): a collision "
                        "between links of one layer fails the comparison")
    add_unit_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from sim.service.simulation import comparison_table
    mech = mechanism_from(args)
    built, c = service.compare(mech, args.revolutions, settings_from(args), loads_from(args, mech),
                               parse_range(mech, args.input_range))
    from sim.output.units import machine_units, shown_units
    say_start(mech, built.mech)
    clash = None
    if args.interference:                          # the parts over the same run (SPEC "Parts ... interference")
        from sim.service import parts as parts_service
        clash = parts_service.interference(parts_service.prepare(mech, parse_range(mech, args.input_range)))
    if args.json:
        record = service.comparison_record(built, c, machine_units(args))
        if clash is not None:
            record["interference"] = clash
        print(dumps(record))
    else:
        print(comparison_table(c, mech.size, shown_units(args, built.mech), built.mech.output_point))
        if clash is not None:
            print(interference_line(clash))
    if not c.passed and getattr(args, "timestep", None) is not None:
        from sim.service.simulation import chosen_timestep
        chosen = chosen_timestep(built.mech, args.revolutions)
        if args.timestep > chosen * (1 + 1e-3):              # not a value that only prints the same
            print(f"linkage: the time step {args.timestep:.4g} s given by --timestep is above the {chosen:.4g} s this "
                  f"design needs; drop --timestep", file=sys.stderr)
    return 0 if c.passed and not (clash and clash["interference"]) else 1


def interference_line(report: dict) -> str:
    """One line of the parts' verdict over the run: the first collision, or the least clearance."""
    if report["interference"]:
        first = min(report["interference"], key=lambda item: item["first_at"])
        a, b = first["links"]
        return (f"  interference: FAILED, {a} and {b} collide first at {report['input']} = {first['first_at']:.6g} "
                f"{report['input_unit']} (depth {first['depth']:.4g} {report['units']})")
    if not report["min_clearance"]:
        return "  interference: passed (no two links share a layer)"
    key, least = min(report["min_clearance"].items(), key=lambda kv: kv[1])
    return (f"  interference: passed, least clearance {least:.4g} {report['units']} "
            f"({key.replace('|', ' / ')})")
