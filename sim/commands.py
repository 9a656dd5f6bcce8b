"""Subcommands that run MuJoCo: simulate, compare, render, plot, run."""

from __future__ import annotations

import math

from analytic import ParameterError, fourbar
from . import params
from .io import check_writable, write_csv


def add_sim_options(p) -> None:
    from .model import DEFAULT_INTEGRATOR, DEFAULT_TIMESTEP, INTEGRATORS
    p.add_argument("--timestep", type=float, default=DEFAULT_TIMESTEP, metavar="H",
                   help=f"physics timestep [s] (default {DEFAULT_TIMESTEP:g})")
    p.add_argument("--integrator", default=DEFAULT_INTEGRATOR, choices=sorted(INTEGRATORS),
                   help=f"MuJoCo integrator (default {DEFAULT_INTEGRATOR})")
    p.add_argument("--gravity", metavar="GX,GY", help="gravity in the plane [m/s^2], e.g. 0,-9.81")
    p.add_argument("--force", metavar="FX,FY", help="constant external force on the output point [N]")
    p.add_argument("--cutting-force", type=float, metavar="F",
                   help="shaper: cutting force on the ram during the cutting stroke [N]")
    p.add_argument("--input-range", metavar="LO:HI",
                   help="four-bar: rock the crank between LO and HI (e.g. a crank that cannot turn fully)")
    p.add_argument("--inertia", metavar="PATH.json",
                   help='bodies\' inertial data: {"coupler": {"m": 0.5, "cx": 0.15, "cy": 0, "I": 0.004}, ...}')


def _pair(option: str, text: str | None) -> tuple[float, float] | None:
    if text is None:
        return None
    parts = text.split(",")
    if len(parts) != 2:
        raise ParameterError(f"{option} {text!r} is not two numbers X,Y (e.g. {option} 0,-9.81)")
    return params.parse_value(option, parts[0]), params.parse_value(option, parts[1])


def loads_from(args, mech):
    """The Loads of the command line: gravity, external or cutting force, bodies' inertias."""
    import json
    from analytic.dynamics import Inertia
    from .model import Loads
    gravity = _pair("--gravity", getattr(args, "gravity", None))
    force = _pair("--force", getattr(args, "force", None)) or (0.0, 0.0)
    cutting = getattr(args, "cutting_force", None)
    if cutting is not None:
        if params.mechanism_name(mech) != "sixbar":
            raise ParameterError("--cutting-force applies to the shaper (sixbar) only; use --force for a constant load")
        if not (math.isfinite(cutting) and cutting >= 0):
            raise ParameterError(f"--cutting-force {cutting!r} must be a number >= 0 [N]")
        if getattr(args, "force", None):
            raise ParameterError("give either --force or --cutting-force, not both")
        # It resists the ram, whose cutting (slow) stroke runs towards -x when the crank turns CCW.
        force = (math.copysign(cutting, mech.omega1), 0.0)
    inertias = None
    if getattr(args, "inertia", None):
        try:
            with open(args.inertia) as f:
                raw = json.load(f)
        except (OSError, ValueError) as exc:
            raise ParameterError(f"--inertia {args.inertia}: cannot read it as JSON ({exc})") from None
        if not isinstance(raw, dict):
            raise ParameterError(f"--inertia {args.inertia}: expected an object of bodies")
        inertias = {}
        for body, data in raw.items():
            try:
                inertias[body] = Inertia(**data)
            except TypeError:
                raise ParameterError(f"--inertia {body}: give m, cx, cy and I (got {sorted(data)})") from None
            except ParameterError as exc:
                raise ParameterError(f"--inertia {body}: {exc}") from None
    return Loads(gravity=gravity, force=force, cutting_only=cutting is not None, inertias=inertias)


def check_full_turn(mech) -> None:
    """A four-bar crank that cannot turn fully is refused before simulating, with its limit angles."""
    if params.mechanism_name(mech) == "fourbar":
        lim = fourbar.crank_limits(mech)
        if not lim.full_turn:
            ends = ", ".join(f"{math.degrees(a):.2f}deg" for a in lim.limit_angles)
            raise ParameterError(
                f"the crank l1={mech.l1:g} cannot turn fully (limit angles {ends}; reachable "
                f"{fourbar.describe_range(lim)}): a velocity-driven simulation would lock at a dead centre; "
                f"rock it between them with --input-range LO:HI")


def rock_from(args):
    """The rocking range of ``--input-range`` [rad], or None."""
    text = getattr(args, "input_range", None)
    if not text:
        return None
    from .cli import _range
    return _range(text)


def run_simulation(mech, revolutions: float, timestep: float, integrator: str, loads=None, rock=None):
    """Build, check and simulate; returns (Built, Trajectory). ``revolutions`` counts rocking cycles
    (period 2 pi / |omega1|) when ``rock`` is given."""
    from .model import Loads, build
    from .simulate import simulate
    if rock is None:
        check_full_turn(mech)
    params.duration(mech, revolutions)             # validates revolutions and the drive before building
    built = build(mech, timestep, integrator, loads=loads or Loads(), rock=rock)
    return built, simulate(built, revolutions)


def trajectory_columns(tr) -> dict:
    """CSV columns of a trajectory: t, drive inputs, SPEC outputs, loop violation, actuator forces, and
    every joint's coordinate and rate (``q_NAME``, ``v_NAME``: rad or m, rad/s or m/s)."""
    joints = {f"q_{n}": tr.qpos[:, i] for i, n in enumerate(tr.joint_names)}
    joints.update({f"v_{n}": tr.qvel[:, i] for i, n in enumerate(tr.joint_names)})
    return {"t": tr.t, **tr.inputs, **tr.outputs, "loop_violation": tr.loop_violation, **tr.forces, **joints}


def cmd_simulate(args) -> int:
    mech = params.build(args.mechanism, args.sets)
    if args.csv:
        check_writable(args.csv, (".csv",))
    _, tr = run_simulation(mech, args.revolutions, args.timestep, args.integrator, loads_from(args, mech),
                                   rock_from(args))
    if args.csv:
        write_csv(args.csv, trajectory_columns(tr))
    print(f"{tr.name}: {tr.steps} steps of {tr.timestep:g} s ({tr.integrator}), {tr.cpu_seconds * 1e3:.1f} ms CPU; "
          f"max loop violation {tr.loop_violation.max():.3e} m")
    if args.csv:
        print(f"wrote {args.csv} ({len(tr.t)} rows)")
    return 0


def cmd_compare(args) -> int:
    from .cli import dumps
    from .compare import compare, table
    mech = params.build(args.mechanism, args.sets)
    built, tr = run_simulation(mech, args.revolutions, args.timestep, args.integrator, loads_from(args, mech),
                                   rock_from(args))
    c = compare(tr, built)
    if args.json:
        out = c.as_dict()
        out["revolutions"] = args.revolutions
        print(dumps(out))
    else:
        print(table(c))
    return 0 if c.passed else 1


def cmd_render(args) -> int:
    from .render import check_video_args, render
    from .model import build
    from .simulate import simulate
    path, size = check_video_args(args.out, args.fps, args.size)
    mech = params.build(args.mechanism, args.sets)
    rock = rock_from(args)
    if rock is None:
        check_full_turn(mech)
    params.duration(mech, args.revolutions)
    built = build(mech, args.timestep, args.integrator, loads=loads_from(args, mech), rock=rock)
    tr = simulate(built, args.revolutions)
    stats = render(built, tr, str(path), args.fps, size)
    print(f"wrote {stats.path}: {stats.frames} frames {size[0]}x{size[1]} at {args.fps:g} fps "
          f"({stats.fps:.1f} frames/s rendered)")
    return 0


def cmd_plot(args) -> int:
    from .compare import compare
    from .plot import check_plot_path, sheet
    check_plot_path(args.out)
    mech = params.build(args.mechanism, args.sets)
    built, tr = run_simulation(mech, args.revolutions, args.timestep, args.integrator, loads_from(args, mech),
                                   rock_from(args))
    sheet(compare(tr, built), mech, args.out)
    print(f"wrote {args.out}")
    return 0


def cmd_run(args) -> int:
    """The main job: simulate, cross-validate, render, plot and write CSV for each mechanism."""
    import time
    from pathlib import Path
    from .compare import compare, table
    from .model import build
    from .plot import sheet
    from .render import check_video_args, render
    from .simulate import simulate

    out_dir = Path(args.out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    names = args.mechanisms or ["fourbar", "sixbar", "fivebar"]
    for name in names:
        if name not in params.CLASSES:
            raise ParameterError(f"{name!r} is not a mechanism: use fourbar, sixbar or fivebar")
    if (args.sets or args.inertia or args.cutting_force is not None or args.input_range) and len(names) != 1:
        raise ParameterError("--set applies to one mechanism at a time: name it (e.g. linkage run fourbar --set l1=0.12)")
    ext = "." + args.format
    if not args.no_video:
        check_video_args(str(out_dir / f"{names[0]}{ext}"), args.fps, args.size)
    mechs = {name: params.build(name, args.sets) for name in names}
    rock = rock_from(args)
    for mech in mechs.values():
        if rock is None:
            check_full_turn(mech)
        params.duration(mech, args.revolutions)
    t_start = time.perf_counter()
    results = []
    for name, mech in mechs.items():
        built = build(mech, args.timestep, args.integrator, loads=loads_from(args, mech), rock=rock)
        tr = simulate(built, args.revolutions)
        c = compare(tr, built)
        print(table(c))
        files = []
        write_csv(out_dir / f"{name}.csv", trajectory_columns(tr))
        files.append(out_dir / f"{name}.csv")
        sheet(c, mech, str(out_dir / f"{name}.png"))
        files.append(out_dir / f"{name}.png")
        if not args.no_video:
            from .render import parse_size
            render(built, tr, str(out_dir / f"{name}{ext}"), args.fps, parse_size(args.size))
            files.append(out_dir / f"{name}{ext}")
        results.append((name, c, files))
        print()
    print(f"summary ({time.perf_counter() - t_start:.1f} s):")
    for name, c, files in results:
        worst = max(c.errors, key=lambda k: c.errors[k]["max"] / c.errors[k]["tol"])
        e = c.errors[worst]
        print(f"  {name:<8s} {'PASSED' if c.passed else 'FAILED'}  worst {worst}: {e['max']:.2e} {e['unit']} "
              f"(tol {e['tol']:.1e}); loop {c.max_loop_violation:.1e} m")
        for f in files:
            print(f"           {f}")
    return 0 if all(c.passed for _, c, _ in results) else 1


def add_video_options(p, out_required: bool = True) -> None:
    if out_required:
        p.add_argument("--out", required=True, metavar="PATH", help="video file, .mp4 (H.264) or .gif")
    p.add_argument("--fps", type=float, default=30.0, metavar="F", help="frames per second (default 30)")
    p.add_argument("--size", default="640x480", metavar="WxH", help="frame size in pixels (default 640x480)")


def register(sub, add_common) -> None:
    p = sub.add_parser("render", help="render the simulation offscreen to MP4 or GIF")
    add_common(p)
    add_sim_options(p)
    add_video_options(p)
    p.set_defaults(func=cmd_render)

    p = sub.add_parser("plot", help="analysis sheet: simulated samples over analytic curves, with errors")
    add_common(p)
    add_sim_options(p)
    p.add_argument("--out", required=True, metavar="PATH", help="image file: .png, .svg or .pdf")
    p.set_defaults(func=cmd_plot)

    p = sub.add_parser("run", help="the main job: simulate, cross-validate, render, plot and save every mechanism")
    p.add_argument("mechanisms", nargs="*", metavar="MECH", help="fourbar, sixbar, fivebar (default: all three)")
    p.add_argument("--set", dest="sets", action="append", default=[], metavar="NAME=VALUE",
                   help="override a parameter (only with a single mechanism)")
    p.add_argument("--revolutions", type=float, default=1.0, metavar="R", help="revolutions (default 1)")
    p.add_argument("--out-dir", default="renders", metavar="DIR", help="output folder (default renders/)")
    p.add_argument("--format", choices=("mp4", "gif"), default="mp4", help="video format (default mp4)")
    p.add_argument("--no-video", action="store_true", help="skip the animations")
    add_sim_options(p)
    add_video_options(p, out_required=False)
    p.set_defaults(func=cmd_run)

    p = sub.add_parser("simulate", help="simulate in MuJoCo and record the trajectory")
    add_common(p)
    add_sim_options(p)
    p.add_argument("--csv", metavar="PATH", help="write every step as CSV")
    p.set_defaults(func=cmd_simulate)

    p = sub.add_parser("compare", help="simulate and cross-validate against the analytic solution")
    add_common(p)
    add_sim_options(p)
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=cmd_compare)
