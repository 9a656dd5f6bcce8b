"""``linkage plot MECH --out PATH``: the analysis sheet (or the force or dynamics sheet)."""

from __future__ import annotations



from analytic import ParameterError
from sim import service
from sim.output.units import add_unit_options
from sim.front.cli.options import (add_common, add_sim_options, check_outputs, loads_from,
                                   mechanism_from, parse_range, settings_from)


def register(sub) -> None:
    p = sub.add_parser("plot", help="analysis sheet: simulated samples over analytic curves, with errors")
    add_common(p)
    p.set_defaults(revolutions=None)
    next(a for a in p._actions if a.dest == "revolutions").help = (
        "revolutions of the first input (default 1; with --motor 10, the last one measured)")
    add_sim_options(p)
    p.add_argument("--out", required=True, metavar="PATH", help="image file: .png, .svg or .pdf")
    p.add_argument("--forces", action="store_true",
                   help="the force sheet instead: bearing loads (polar), joint forces, drives, shaking force")
    from sim.front.cli.dynamics import add_motor_options
    add_motor_options(p, two=False)
    p.epilog = ("--motor T0,W0 (or --motor-table) draws the dynamics sheet instead: the motor drives the input; "
                "speed against angle over the last revolution with its mean and Cs band, start-up against time, "
                "motor torque, the reduced equation with MuJoCo's steps over it (as linkage dynamics --plot)")
    add_unit_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from sim.output.plot import PLOT_SUFFIXES, sheet
    motor = bool(args.motor or args.motor_table)
    if args.revolutions is None:                  # a motor run measures its last revolution: start-up first
        args.revolutions = 10.0 if motor else 1.0
    if motor:
        return _plot_dynamics(args)
    for name in ("flywheel", "start_speed", "target_fluctuation"):
        if getattr(args, name) not in (None, [], "0"):
            raise ParameterError(f"--{name.replace('_', '-')} belongs to a motor-driven run: give --motor T0,W0 too")
    check_outputs(args, {"out": PLOT_SUFFIXES})
    mech = mechanism_from(args)
    built, c = service.compare(mech, args.revolutions, settings_from(args), loads_from(args, mech),
                               parse_range(mech, args.input_range))
    from sim.output.units import shown_units
    if args.forces:
        from sim.output.plot import force_sheet
        force_sheet(c, built, args.out, shown_units(args, built.mech))
    else:
        sheet(c, built, args.out, shown_units(args, built.mech))
    print(f"wrote {args.out}")
    return 0


def _plot_dynamics(args) -> int:
    """``linkage plot MECH --motor T0,W0``: the dynamics sheet (sim.output.dynamics_plot) of the motor-driven
    run, as ``linkage dynamics --plot`` draws it."""
    from sim.front.cli.dynamics import check_motor_args, motor_run
    from sim.output.dynamics_plot import sheet
    from sim.output.plot import PLOT_SUFFIXES
    if args.forces:
        raise ParameterError("--forces and --motor are two sheets: give one (the force sheet follows the "
                             "prescribed motion, the dynamics sheet the motor's)")
    check_motor_args(args)
    check_outputs(args, {"out": PLOT_SUFFIXES})
    mech = mechanism_from(args)
    if len(mech.inputs) != 1:
        raise ParameterError(f"the {mech.name} has {len(mech.inputs)} inputs; the dynamics sheet drives one (for "
                             f"two motors run `linkage dynamics` with --motor per input)")
    d = motor_run(args, mech)
    from sim.output.units import shown_units
    sheet(d, args.out, shown_units(args, mech))
    print(f"wrote {args.out}" + ("" if d.passed else " (MuJoCo disagrees with the reduced equation: see the title)"))
    return 0 if d.passed else 1
