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
    add_unit_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from sim.run.compare import table
    mech = mechanism_from(args)
    built, c = service.compare(mech, args.revolutions, settings_from(args), loads_from(args, mech),
                               parse_range(mech, args.input_range))
    from sim.output.units import machine_units, shown_units
    say_start(mech, built.mech)
    if args.json:
        print(dumps(service.comparison_record(built, c, machine_units(args))))
    else:
        print(table(c, mech.size, shown_units(args, built.mech), built.mech.output_point))
    if not c.passed and getattr(args, "timestep", None) is not None:
        from sim.model import choose_timestep
        chosen = choose_timestep(built.mech, args.revolutions)
        if args.timestep > chosen * (1 + 1e-3):              # not a value that only prints the same
            print(f"linkage: the time step {args.timestep:.4g} s given by --timestep is above the {chosen:.4g} s this "
                  f"design needs; drop --timestep", file=sys.stderr)
    return 0 if c.passed else 1
