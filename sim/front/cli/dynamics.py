"""`linkage dynamics MECH`: a motor drives the linkage (SPEC, "Dynamics under a motor")."""

from __future__ import annotations

import math


from analytic import ParameterError
from sim.front.cli.options import add_common, add_sim_options, add_video_options
from sim.service import analysis as Q
from sim.service.values import parse_value
from sim.service.dynamics import in_units  # noqa: F401 (where the command line found it before)

RPM = 2 * math.pi / 60


def parse_speed(option: str, text: str) -> float:
    """A speed [rad/s]: a bare number or one with a ``rad/s`` suffix in rad/s (SI, as every physical value
    the command line takes), with an ``rpm`` suffix in revolutions per minute (the app's unit)."""
    t = text.strip()
    scale = 1.0
    if t.lower().endswith("rpm"):
        t, scale = t[:-3].strip(), RPM
    elif t.lower().endswith("rad/s"):
        t = t[:-5].strip()
    return parse_value(option, t, angle=False) * scale


INERTIA_UNITS = {"kg*m^2": 1.0, "kg*cm^2": 1e-4, "kg*mm^2": 1e-6, "kg*in^2": 0.0254 ** 2}
"""The moment-of-inertia suffixes --flywheel takes, in kg m^2 each: kg*mm^2 is a mm file's [inertia] unit."""


def parse_flywheel(text: str) -> float:
    """``--flywheel J`` [kg m^2]: a bare number is kg m^2 (SI, its meaning since the option exists); a
    suffix ``kg*mm^2`` (also ``kg*cm^2``, ``kg*in^2``, ``kg*m^2``) gives it in a file's [inertia] unit."""
    t = text.strip()
    key = t.lower().replace(" ", "")
    for unit, scale in INERTIA_UNITS.items():
        for form in (unit, unit.replace("*", "").replace("^", "")):          # kg*mm^2 or kgmm2
            if key.endswith(form):
                return parse_value("--flywheel", key[:-len(form)], angle=False) * scale
    return parse_value("--flywheel", t, angle=False)


def parse_motor(text: str):
    """``T0,W0``: stall torque [N m], no-load speed [rad/s or rpm]: an ``analytic.applications.motor.LinearMotor``."""
    from sim.service.dynamics import linear_motor
    parts = text.split(",")
    if len(parts) != 2:
        raise ParameterError(f"--motor {text!r} is not T0,W0 (stall torque N m, no-load speed rad/s or rpm; "
                             f"e.g. --motor 2,150rpm)")
    return linear_motor(parse_value("--motor T0", parts[0], angle=False), parse_speed("--motor W0", parts[1]))


def read_table(path: str):
    """A torque-speed table: CSV with a header ``omega,tau`` (rad/s, N m) or ``rpm,tau`` (a ``TableMotor``)."""
    from sim.service.dynamics import table_motor
    from sim.readers import csv_rows
    rows = [r for _, r in csv_rows("--motor-table", path) if r and any(c.strip() for c in r)]
    if not rows:
        raise ParameterError(f"--motor-table {path}: the file is empty; give a header omega,tau and rows")
    head = [c.strip().lower() for c in rows[0]]
    if len(head) != 2 or head[1] != "tau" or head[0] not in ("omega", "rpm"):
        raise ParameterError(f"--motor-table {path}: the header must be omega,tau (rad/s, N m) or rpm,tau")
    scale = RPM if head[0] == "rpm" else 1.0
    w, tau = [], []
    for k, r in enumerate(rows[1:], start=1):
        if len(r) != 2:
            raise ParameterError(f"--motor-table {path}: row {k}: give two numbers {head[0]},tau")
        try:
            w.append(float(r[0]) * scale)
            tau.append(float(r[1]))
        except ValueError:
            raise ParameterError(f"--motor-table {path}: row {k}: {','.join(r)!r} is not two numbers") from None
    return table_motor(w, tau, source=f"--motor-table {path}")


def add_motor_options(p, two: bool = True) -> None:
    """The motor, flywheel and start of a motor-driven run (``linkage dynamics``; ``linkage plot --motor``)."""
    p.add_argument("--motor", metavar="[NAME=]T0,W0" if two else "T0,W0", action="append", default=[],
                   help="linear motor: stall torque [N m], no-load speed [rad/s; with a suffix rpm (as the app) or "
                        "rad/s], e.g. 2,150rpm"
                        + ("; a two-crank five-bar takes one per input: --motor phi2=2,150rpm --motor phi4=..."
                           if two else ""))
    p.add_argument("--motor-table", metavar="PATH.csv", help="torque-speed table: header omega,tau (or rpm,tau)")
    p.add_argument("--flywheel", metavar="[NAME=]J" if two else "J", action="append", default=[],
                   help="flywheel on the input link: kg m^2, or with a unit kg*mm^2 (a mm file's [inertia] unit), "
                        "kg*cm^2, kg*in^2 (default 0)" + ("; per input for two motors" if two else ""))
    p.add_argument("--target-fluctuation", metavar="CS", help="size the flywheel for this Cs, in (0, 1)")
    p.add_argument("--start-speed", metavar="W", default="0",
                   help="input speed at t = 0: rad/s, or with an rpm suffix (default 0)")


def register(sub) -> None:
    from sim.output.units import add_unit_options
    p = sub.add_parser("dynamics", help="a motor drives the linkage: speed fluctuation, start-up, flywheel")
    add_common(p, revolutions=10.0)
    add_sim_options(p)
    add_motor_options(p)
    p.add_argument("--pressure", metavar="P",
                   help="instead of a motor: the cylinder (the one actuator input) pushed by a supply at this "
                        "pressure (e.g. 200bar; Pa, kPa, MPa, bar, psi) on its bore's push area, from rest to the "
                        "end of its stroke; with --flow")
    p.add_argument("--flow", metavar="Q", help="the supply's flow with --pressure: m^3/s, or with a suffix L/s or "
                                               "L/min (the free speed is Q over the push area)")
    p.add_argument("--json", action="store_true", help="print one JSON object (SI unless --units/--angles/--speeds)")
    p.add_argument("--csv", metavar="PATH", help="write the analytic run (t, phi, omega, torque) as CSV")
    p.add_argument("--plot", metavar="PATH", help="dynamics sheet: .png, .svg or .pdf")
    p.add_argument("--render", "--out", dest="render", metavar="PATH",
                   help="video of MuJoCo's motor-driven run (.mp4 or .gif), the input's speed in the corner")
    add_video_options(p, out_required=False)
    add_unit_options(p)
    p.set_defaults(func=cmd_dynamics)


def motor_run(args, mech, check=True):
    """The one-input motor run the command line asks for (:func:`sim.service.dynamics.dynamics`): the motor,
    flywheel or target fluctuation and start speed of ``args`` (:func:`add_motor_options`) and the loads of the
    simulation options."""
    from sim.front.cli.options import load_keywords, settings_from
    target = (parse_value("--target-fluctuation", args.target_fluctuation, angle=False)
              if args.target_fluctuation is not None else None)
    if len(args.motor) > 1 or len(args.flywheel) > 1:
        raise ParameterError(f"the {mech.name} has one input: give one --motor and at most one --flywheel")
    mot = _named(args.motor[0], mech, "--motor")[1] if args.motor else read_table(args.motor_table)
    mot = parse_motor(mot) if isinstance(mot, str) else mot
    flywheel = None
    if args.flywheel:
        flywheel = parse_flywheel(_named(args.flywheel[0], mech, "--flywheel")[1])
        if not flywheel >= 0:
            raise ParameterError(f"--flywheel {flywheel:g} must be >= 0 [kg m^2] (the flywheel's moment of inertia)")
    start = parse_speed("--start-speed", args.start_speed)
    import linkage as lk
    settings = settings_from(args)
    return lk.dynamics(mech, motor=mot, flywheel=flywheel, target_fluctuation=target, start_speed=start,
                       revolutions=args.revolutions, timestep=settings.timestep, integrator=settings.integrator,
                       **load_keywords(args, mech)).run


def check_motor_args(args) -> None:
    """What must hold before any work: one motor given, no input range (whole revolutions)."""
    if bool(args.motor) == bool(args.motor_table):
        raise ParameterError("give the motor: --motor T0,W0 or --motor-table PATH.csv (one of them)")
    if args.input_range:
        raise ParameterError("--input-range does not apply to a motor-driven run: the motor turns the crank "
                             "through whole revolutions; leave it out")


FLOW_UNITS = {"l/s": 1e-3, "l/min": 1e-3 / 60, "m^3/s": 1.0, "m3/s": 1.0}
"""The flow suffixes --flow takes, in m^3/s each."""


def parse_flow(text: str) -> float:
    """``--flow Q`` [m^3/s]: a bare number is m^3/s; a suffix L/s or L/min (also m^3/s)."""
    t = text.strip()
    key = t.lower().replace(" ", "")
    for unit, scale in FLOW_UNITS.items():
        if key.endswith(unit):
            t, break_scale = key[:-len(unit)], scale
            break
    else:
        break_scale = 1.0
    value = parse_value("--flow", t, angle=False) * break_scale
    if not value > 0:
        raise ParameterError(f"--flow {text!r} must be > 0 (m^3/s, or with a suffix L/s or L/min)")
    return value


def _cylinder(args, mech) -> int:
    """``--pressure P --flow Q``: the cylinder driven out by its supply (sim.service.dynamics.cylinder_dynamics)."""
    from sim.front.cli.options import load_keywords, settings_from
    from sim.output.jsonout import dumps
    from sim.service import dynamics as dynamics_service
    from sim.service.forces import supply_pressure
    given = [o for o, v in (("--motor", args.motor), ("--motor-table", args.motor_table), ("--flywheel", args.flywheel),
                            ("--target-fluctuation", args.target_fluctuation), ("--csv", args.csv),
                            ("--plot", args.plot), ("--render", args.render)) if v]
    if given:
        raise ParameterError(f"--pressure drives the cylinder by its supply: {', '.join(given)} "
                             f"{'do' if len(given) > 1 else 'does'} not apply; leave {'them' if len(given) > 1 else 'it'} out")
    if args.flow is None:
        raise ParameterError("--pressure needs the supply's flow: --flow Q (m^3/s, or e.g. 2L/s, 120L/min)")
    pressure = supply_pressure(args.pressure, mech)
    flow = parse_flow(args.flow)
    kw = load_keywords(args, mech)
    force = kw.get("force")
    if kw.get("cutting_force") is not None or kw.get("torque") or kw.get("inertia") or (force and len(force) != 2):
        raise ParameterError("--pressure runs with --gravity and --force FX,FY (on the output point) only")
    d = dynamics_service.cylinder_dynamics(mech, pressure, flow, kw.get("gravity"), tuple(force or (0.0, 0.0)),
                                           settings_from(args))
    rec = dynamics_service.cylinder_record(d)
    if args.json:
        print(dumps(rec))
        return 0 if d.passed else 1
    a, sup = rec["analytic"], rec["supply"]
    print(f"{mech.name}: cylinder {mech.inputs[0].q} pushed at {sup['pressure'] / 1e5:.4g} bar (stall force "
          f"{sup['F0']:.5g} N) and {sup['flow'] * 1e3:.4g} L/s (free speed {sup['v0']:.4g} m/s)")
    end = "the end of its stroke" if a["end"] == "stroke" else "the time limit"
    print(f"  from {a['s'][0]:.5g} m at rest to {a['s'][-1]:.5g} m ({end}) in {a['duration']:.5g} s; peak speed "
          f"{a['v_max']:.4g} m/s")
    sim = rec.get("simulated")
    if sim is not None:
        g = sim["agreement"]
        print(f"  MuJoCo ({sim['steps']} steps of {sim['timestep']:.3g} s): length within {g['s']:.2e} m (tol "
              f"{g['tol_s']:.1e}), speed within {g['v']:.2e} m/s (tol {g['tol_v']:.1e}): "
              f"{'PASSED' if rec['passed'] else 'FAILED'}")
    return 0 if d.passed else 1


def cmd_dynamics(args) -> int:
    from sim.service import dynamics as dynamics_service
    from sim.front.cli.options import check_outputs, mechanism_from
    from sim.output.io import write_csv, write_text
    from sim.output.jsonout import dumps
    from sim.output.units import machine_units, shown_units
    if args.pressure is not None or args.flow is not None:
        if args.pressure is None:
            raise ParameterError("--flow is the supply's flow of --pressure: give --pressure P too")
        return _cylinder(args, mechanism_from(args))
    check_motor_args(args)
    check_outputs(args, {"csv": (".csv",), "plot": (".png", ".svg", ".pdf")})
    if args.render:
        from sim.output.render import check_video_args
        check_video_args(args.render, args.fps, args.size)
    if args.motor_table and args.csv and args.motor_table == args.csv:
        raise ParameterError(f"--csv {args.csv} is the motor table; choose another output name")
    mech = mechanism_from(args)
    display = machine_units(args, mech)
    if len(mech.inputs) == 2:
        given = [o for o, v in (("--csv", args.csv), ("--plot", args.plot), ("--render", args.render)) if v]
        if given:                                 # refused rather than silently not written
            raise ParameterError(f"{', '.join(given)}: the {mech.name}'s two-motor run writes no files yet; "
                                 f"leave {'them' if len(given) > 1 else 'it'} out (--json prints every value)")
        target = args.target_fluctuation
        return _two_motors(args, mech, target, display)
    if len(mech.inputs) != 1:
        raise ParameterError(f"the {mech.name} has {len(mech.inputs)} inputs; `linkage dynamics` drives one or two")
    d = motor_run(args, mech)
    if not d.passed:                               # a failed verdict writes no file (exit 1)
        return _failed(args, d, mech, display)
    if args.csv:
        cols = {"t": d.run.t, "phi": d.run.phi, "omega": d.run.omega, "torque": d.run.torque}
        write_csv(args.csv, {k: display.convert(QUANTITIES[k], v) for k, v in cols.items()})
        import json
        write_text(f"{args.csv}.units.json", json.dumps({"mechanism": mech.name, "si": display.is_si, "units": {
            k: display.unit(QUANTITIES[k]) for k in cols}}, indent=2) + "\n")
    if args.plot:
        from sim.output.dynamics_plot import sheet
        sheet(d, args.plot, shown_units(args, mech))
    if args.render:
        from sim.output.render import parse_size, render_motor
        stats = render_motor(d.built, d.sim, args.render, args.fps, parse_size(args.size),
                             display=shown_units(args, mech))
        if not args.json:
            print(f"wrote {stats.path}: {stats.frames} frames at {stats.stored_fps:g} fps")
    if args.json:
        print(dumps(in_units(dynamics_service.record(d), display)))
    else:
        print(summary(d, shown_units(args, mech)))
        for path in (args.csv, args.plot):         # every file written is said, as the other commands do
            if path:
                print(f"wrote {path}")
    return 0 if d.passed else 1


def _failed(args, d, mech, display) -> int:
    """A motor run whose MuJoCo run disagrees with the reduced equation: its verdict, and none of its
    files (one line on stderr naming them and the fix)."""
    from sim.front.cli.options import say_not_written
    from sim.output.jsonout import dumps
    from sim.output.units import shown_units
    from sim.service import dynamics as dynamics_service
    if args.json:
        print(dumps(in_units(dynamics_service.record(d), display)))
    else:
        print(summary(d, shown_units(args, mech)))
    paths = [args.csv, args.csv and f"{args.csv}.units.json", args.plot, args.render]
    fix = ("drop --timestep (the run chooses a step that holds the motor)" if args.timestep is not None else
           "see the agreement above; `linkage plot MECH --motor ...` draws the two runs")
    say_not_written(paths, "MuJoCo disagrees with the reduced equation: a failed run writes no files", fix)
    return 1


QUANTITIES = {"t": Q.TIME, "phi": Q.ANGLE, "omega": Q.ANGULAR_VELOCITY, "torque": Q.TORQUE}
"""The quantity (:mod:`analytic.quantities`) of each CSV column."""


def _named(text: str, mech, option: str) -> tuple[str, str]:
    """``NAME=VALUE`` or ``VALUE`` (the first input): (input name, value text); NAME must be an input."""
    names = [i.q for i in mech.inputs]
    if "=" not in text:
        return names[0], text
    name, value = text.split("=", 1)
    name = name.strip()
    if name not in names:
        raise ParameterError(f"{option} {text!r}: the {mech.name} has no input {name!r}; inputs: {', '.join(names)}")
    return name, value


def _two_motors(args, mech, target, display) -> int:
    from sim.service import dynamics as dynamics_service
    from sim.front.cli.options import load_keywords, settings_from
    from sim.output.jsonout import dumps
    names = [i.q for i in mech.inputs]
    if args.motor_table or target is not None or args.plot or args.csv or args.render:
        raise ParameterError(f"the {mech.name} has two inputs: give --motor per input; --motor-table, "
                             f"--target-fluctuation, --plot, --csv and --render drive one input only")
    motors = {}
    for text in args.motor:
        if "=" not in text:
            raise ParameterError(f"--motor {text!r}: the {mech.name} has two inputs; name each: "
                                 f"--motor {names[0]}=T0,W0 --motor {names[1]}=T0,W0")
        name, value = _named(text, mech, "--motor")
        motors[name] = parse_motor(value)
    missing = [n for n in names if n not in motors]
    if missing:
        raise ParameterError(f"--motor: no motor for {', '.join(missing)}; give --motor NAME=T0,W0 for each of "
                             f"{', '.join(names)}")
    fly = dict.fromkeys(names, 0.0)
    for text in args.flywheel:
        if "=" not in text:
            raise ParameterError(f"--flywheel {text!r}: name the input (--flywheel {names[0]}=J)")
        name, value = _named(text, mech, "--flywheel")
        fly[name] = parse_flywheel(value)
    start = parse_speed("--start-speed", args.start_speed)
    import linkage as lk
    settings = settings_from(args)
    d = lk.dynamics(mech, motor=motors, flywheel=fly, start_speed=start, revolutions=args.revolutions,
                    timestep=settings.timestep, integrator=settings.integrator, **load_keywords(args, mech)).run
    if args.json:
        print(dumps(in_units(dynamics_service.record_two(d), display)))
    else:
        r, s = d.run, d.sim
        print(f"{mech.name} driven by two motors, {r.revolutions:g} revolutions of {names[0]}")
        for k, n in enumerate(names):
            print(f"  {n}: mean speed {r.mean_speed[k]:.6g} rad/s (MuJoCo {s['mean_speed'][k]:.6g}), Cs "
                  f"{r.fluctuation[k]:.6g} (MuJoCo {s['fluctuation'][k]:.6g}), start-up {r.startup_time[k]:.4g} s")
        print("PASS" if d.passed else "FAIL")
    return 0 if d.passed else 1


def summary(d, display=None) -> str:
    """The text of a motor run; the peak motor torque in ``display``'s moment unit (the file's force unit x
    its length unit for a kN or lbf file; N m by default)."""
    r, s, a = d.run, d.sim, d.agreement
    rpm = 1 / RPM
    display = display or Q.SI
    lines = [f"{d.mech.name} driven by {_motor_text(d.motor)}, flywheel {d.flywheel:.4g} kg m^2, "
             f"{r.revolutions:g} revolutions",
             f"{'':24s}{'analytic':>14s}{'MuJoCo':>14s}",
             f"{'mean speed [rad/s]':24s}{r.mean_speed:14.6g}{s.mean_speed:14.6g}   ({r.mean_speed * rpm:.4g} rpm)",
             f"{'fluctuation Cs':24s}{r.fluctuation:14.6g}{s.fluctuation:14.6g}",
             f"{'start-up time [s]':24s}{r.startup_time:14.6g}{s.startup_time:14.6g}",
             f"peak motor torque {display.convert(Q.TORQUE, r.peak_torque):.4g} {display.unit(Q.TORQUE)}, "
             f"peak power {r.peak_power:.4g} W, "
             f"energy per cycle {r.energy_per_cycle:.4g} J"]
    if d.target is not None:
        lines.append(f"flywheel sized for Cs = {d.target:g}: {d.flywheel:.6g} kg m^2; runs give "
                     f"{r.fluctuation:.5g} (analytic), {s.fluctuation:.5g} (MuJoCo) "
                     f"[{'ok' if d.sizing_passed else f'FAIL: outside {smotor_tol():.0%}; try more --revolutions'}]")
        if d.revolutions_asked is not None and r.revolutions > d.revolutions_asked:
            lines.append(f"  (run for {r.revolutions:g} revolutions instead of {d.revolutions_asked:g}: the start-up "
                         f"with this flywheel takes {r.startup_time:.3g} s, and the last revolution must be steady)")
    lines.append(f"agreement: mean speed {a.mean_speed:.1e} (tol {a.as_dict()['tolerances']['mean_speed']:.0e}), "
                 f"Cs {a.fluctuation:.1e} (tol {a.as_dict()['tolerances']['fluctuation']:.0e}), speed vs angle "
                 f"{a.curve:.1e}, vs time {a.time:.1e}; loop {s.loop_violation:.1e} m; step {s.timestep:.3g} s")
    lines.append("PASS" if d.passed else "FAIL")
    return "\n".join(lines)


def smotor_tol() -> float:
    from sim.service.dynamics import sizing_tolerance
    return sizing_tolerance()


def _motor_text(m) -> str:
    from sim.service.dynamics import is_linear_motor
    if is_linear_motor(m):
        return f"a linear motor T0={m.T0:g} N m, W0={m.W0:g} rad/s ({m.W0 / RPM:.4g} rpm)"
    return f"a table motor ({len(m.omega)} rows, stall {m.stall:g} N m)"


__all__ = ["register", "cmd_dynamics", "parse_motor", "read_table", "add_motor_options", "motor_run",
           "check_motor_args", "in_units"]
