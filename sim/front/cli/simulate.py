"""``linkage simulate MECH``: the MuJoCo model simulated, its trajectory recorded."""

from __future__ import annotations



from sim.output.units import add_unit_options
from sim.front.cli.options import (add_common, add_sim_options, check_outputs, load_keywords,
                                   mechanism_from, parse_range, settings_from, write_columns)


def register(sub) -> None:
    p = sub.add_parser("simulate", help="simulate in MuJoCo and record the trajectory")
    add_common(p)
    add_sim_options(p)
    p.add_argument("--csv", metavar="PATH", help="write every step as CSV (units in PATH.units.json)")
    p.add_argument("--speed", type=float, default=None, metavar="W",
                   help="a cam mechanism: the cam's speed [rad/s] (every input's speed scaled alike); the JSON's "
                        "\"cams\" says whether the follower left the cam and where")
    p.add_argument("--json", action="store_true",
                   help="print one JSON object: the run's settings, its loop violation and every column")
    add_unit_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    mech = mechanism_from(args)
    if args.speed is not None:
        from sim.front.cli.options import sets_of
        from sim.service import load
        from sim.service.simulation import cam_speed_sets, check_cam_speed
        sets = sets_of(args.sets)
        sets.update(cam_speed_sets(mech, args.speed))
        before, mech = mech, load(args.mechanism, sets)
        if args.timestep is None:
            check_cam_speed(before, mech, args.speed, args.revolutions)
    check_outputs(args, {"csv": (".csv",)})
    import linkage as lk
    settings = settings_from(args)
    result = lk.simulate(mech, revolutions=args.revolutions, input_range=parse_range(mech, args.input_range),
                         timestep=settings.timestep, integrator=settings.integrator, **load_keywords(args, mech))
    tr = result.trajectory
    from sim.output.units import machine_units, shown_units
    if args.csv:
        write_columns(args.csv, mech, result.columns, machine_units(args))
    if args.json:
        from sim.output.jsonout import dumps
        record = result.to_dict(display=machine_units(args))
        if args.csv:
            record["csv"] = args.csv
        print(dumps(record))
        return 0
    u = shown_units(args, mech)
    print(f"{tr.name}: {tr.steps} steps of {tr.timestep:.3g} s ({tr.integrator}), {tr.cpu_seconds * 1e3:.1f} ms CPU; "
          f"max loop violation {u.convert('length', tr.loop_violation.max()):.3e} {u.unit('length')}")
    for name, c in tr.cams.items():
        print(f"cam {name}: " + (f"the follower leaves the cam at cam angle {c['first_at']:.4f} rad"
                                 if c["separated"] else "the follower stays on the cam"))
    if args.csv:
        print(f"wrote {args.csv} ({len(tr.t)} rows)")
    return 0
