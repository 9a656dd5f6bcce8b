"""``linkage simulate MECH``: the MuJoCo model simulated, its trajectory recorded."""

from __future__ import annotations



from sim import service
from sim.output.units import add_unit_options
from sim.front.cli.options import (add_common, add_sim_options, check_outputs, loads_from,
                                   mechanism_from, parse_range, settings_from, write_columns)


def register(sub) -> None:
    p = sub.add_parser("simulate", help="simulate in MuJoCo and record the trajectory")
    add_common(p)
    add_sim_options(p)
    p.add_argument("--csv", metavar="PATH", help="write every step as CSV (units in PATH.units.json)")
    add_unit_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    mech = mechanism_from(args)
    check_outputs(args, {"csv": (".csv",)})
    _, tr = service.simulate(mech, args.revolutions, settings_from(args), loads_from(args, mech),
                             parse_range(mech, args.input_range))
    from sim.output.units import machine_units, shown_units
    if args.csv:
        write_columns(args.csv, mech, service.trajectory_columns(tr), machine_units(args))
    u = shown_units(args, mech)
    print(f"{tr.name}: {tr.steps} steps of {tr.timestep:.3g} s ({tr.integrator}), {tr.cpu_seconds * 1e3:.1f} ms CPU; "
          f"max loop violation {u.convert('length', tr.loop_violation.max()):.3e} {u.unit('length')}")
    if args.csv:
        print(f"wrote {args.csv} ({len(tr.t)} rows)")
    return 0
