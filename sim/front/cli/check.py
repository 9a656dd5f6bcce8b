"""``linkage check MECH``: a mechanism's structure (links, joints, loops, mobility, solve order, range)."""

from __future__ import annotations

from analytic import ParameterError
from sim.output.units import add_unit_options
from sim.front.cli.options import (warn_size, add_common, mechanism_from)


def register(sub) -> None:
    p = sub.add_parser("check", help="a mechanism's structure: links, joints, loops, mobility, solve order, range")
    add_common(p)
    add_unit_options(p)
    from sim.front.cli import parts
    parts.add_check_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from sim.service.analysis import assembly_ranges
    from sim.service.structure import structure_report
    from sim.output.units import shown_units
    from sim.front.cli import parts
    mech = mechanism_from(args)
    warn_size(mech)
    if args.json and not args.interference:
        raise ParameterError("--json goes with --interference (linkage check MECH --interference --json)")
    if not args.json:
        print(structure_report(mech, shown_units(args, mech)))
    if len(mech.inputs) == 1 and not assembly_ranges(mech):
        raise ParameterError(f"{mech.definition.source}: the mechanism assembles at no value of "
                             f"{mech.inputs[0].q}; change the lengths (see the report above)")
    if args.interference:                          # the parts over the cycle (issue 28)
        return parts.cmd_interference(args, mech)
    print("\n".join(parts.layer_lines(mech, args)))
    return 0
