"""The ``linkage`` command (also ``python -m sim``): argument parsing over :mod:`sim.service`.

Every user error ends in one line on stderr and exit code 2, never a traceback. MuJoCo and matplotlib
are imported only by the commands that need them.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import threading
import warnings

import numpy as np

import analytic
from analytic import ParameterError
from analytic.format import expr
from sim import service
from sim.output.io import write_csv
from sim.output.jsonout import dumps
from sim.output.units import add_unit_options
from sim.front.common import _outputs, check_outputs, mechanism_from, sets_of  # noqa: F401 (used by command modules)


class _Parser(argparse.ArgumentParser):
    def error(self, message):            # argparse's own errors: one line, exit 2
        self.exit(2, f"linkage: error: {message}\n")


# ------------------------------------------------------------------------------------ option values
def parse_range(mech, text: str | None) -> tuple[float, float] | None:
    """``LO:HI`` of the first input: a crank's in radians, or degrees with a deg suffix; a slider's in the
    file's length unit (like ``--set``, and as ``linkage check`` prints it), returned in metres."""
    if not text:
        return None
    if ":" not in text:
        raise ParameterError(f"--input-range {text!r} is not LO:HI (e.g. -40deg:40deg)")
    lo, hi = text.split(":", 1)
    angle = mech.inputs[0].kind == "crank"
    scale = 1.0 if angle else mech.scale
    return (expr.parse_value("--input-range", lo, angle=None if angle else False) * scale,
            expr.parse_value("--input-range", hi, angle=None if angle else False) * scale)


def pair(option: str, text: str | None) -> tuple[float, float] | None:
    if text is None:
        return None
    parts = text.split(",")
    if len(parts) != 2:
        raise ParameterError(f"{option} {text!r} is not two numbers X,Y (e.g. {option} 0,-9.81)")
    return expr.parse_value(option, parts[0], angle=False), expr.parse_value(option, parts[1], angle=False)


def settings_from(args):
    from sim.model import Settings
    return Settings(timestep=args.timestep, integrator=args.integrator)


def loads_from(args, mech):
    """The Loads of the command line: gravity, external or cutting force, links' inertias."""
    from analytic.mass import Inertia
    from sim.model import Loads
    gravity = pair("--gravity", args.gravity)
    force = pair("--force", args.force) or (0.0, 0.0)
    cutting = args.cutting_force
    slow = False
    if cutting is not None:
        cutting = expr.parse_value("--cutting-force", cutting, angle=False)
        if cutting < 0:
            raise ParameterError(f"--cutting-force {cutting:g} must be >= 0 [N] (it always resists the motion)")
        if args.force:
            raise ParameterError("give either --force or --cutting-force, not both")
        force, slow = (cutting_direction(mech) * cutting, 0.0), True
    inertias = None
    if args.inertia:
        if os.path.abspath(args.inertia) in _outputs(args):
            raise ParameterError(f"--inertia {args.inertia} is also an output of this command; it would be "
                                 f"overwritten: choose another output name")
        try:
            with open(args.inertia) as f:
                raw = json.load(f)
        except (OSError, ValueError) as exc:
            raise ParameterError(f"--inertia {args.inertia}: cannot read it as JSON ({exc})") from None
        if not isinstance(raw, dict):
            raise ParameterError(f"--inertia {args.inertia}: expected an object of links")
        inertias = {}
        for link, data in raw.items():
            if not isinstance(data, dict):
                raise ParameterError(f"--inertia {link}: give an object with m, cx, cy and I")
            try:
                given = Inertia(**data)            # file units, like the file's [inertia]: m kg, cx cy, I kg unit^2
                s = mech.scale
                inertias[link] = Inertia(m=given.m, cx=given.cx * s, cy=given.cy * s, I=given.I * s * s)
            except TypeError:
                raise ParameterError(f"--inertia {link}: give m, cx, cy and I (got {sorted(data)})") from None
            except ParameterError as exc:
                raise ParameterError(f"--inertia {link}: {exc}") from None
    return Loads(gravity=gravity, force=force, slow_stroke_only=slow, inertias=inertias)


def cutting_direction(mech) -> float:
    """-1 or +1: the x direction that resists the output point during its slow (cutting) stroke."""
    from sim.model import slow_stroke
    lo, hi = slow_stroke(mech)
    first = mech.inputs[0]
    q = first.motion.q0 + np.linspace(lo, hi, 50)[1:-1]
    sol = mech.solve(q, math.copysign(1.0, first.motion.rate or 1.0))
    vx = float(np.nanmean(sol["vx" + mech.output_point]))
    return -math.copysign(1.0, vx)


def write_columns(path, mech, columns, display=None) -> None:
    """CSV (SPEC column names in the header) plus a sidecar ``PATH.units.json`` with each column's unit:
    SI unless ``display`` (from --units/--angles/--speeds) says otherwise."""
    from sim.output.io import write_text
    from sim.output.units import SI, convert_columns
    display = display or SI
    write_csv(path, convert_columns(mech, columns, display))
    write_text(f"{path}.units.json", json.dumps({"mechanism": mech.name, **service.parameters_record(mech, display),
                                                  "file_units": mech.units, "si": display.is_si,
                                                  "units": service.units_of(mech, columns, display)},
                                                 indent=2) + "\n")


# ----------------------------------------------------------------------------------------- commands
def cmd_list(args) -> int:
    rows = service.list_mechanisms()
    width = max(len(r["name"]) for r in rows)
    for r in rows:
        tag = "built-in" if r["builtin"] else f"{r['inputs']} input" + ("s" if r["inputs"] > 1 else "")
        print(f"{r['name']:<{width}s}  {tag:<9s} {r['description']}")
    return 0


def cmd_check(args) -> int:
    from analytic.applications import figures
    from sim.front import parts_cmd
    from sim.output.units import shown_units
    mech = mechanism_from(args)
    if args.json and not args.interference:
        raise ParameterError("--json goes with --interference (linkage check MECH --interference --json)")
    if not args.json:
        print(structure_report(mech, shown_units(args, mech)))
    if len(mech.inputs) == 1 and not figures.assembly_ranges(mech):
        raise ParameterError(f"{mech.definition.source}: the mechanism assembles at no value of "
                             f"{mech.inputs[0].q}; change the lengths (see the report above)")
    if args.interference:                          # the parts over the cycle (issue 28)
        return parts_cmd.cmd_interference(args, mech)
    print("\n".join(parts_cmd.layer_lines(mech, args)))
    return 0


def structure_report(mech, display=None) -> str:
    """``linkage check``'s report; lengths in ``display`` units (default the file's), a crank's angles in
    deg; an input's range rounded inward, so that it can be pasted into ``--input-range``."""
    from analytic import kinds
    from analytic.applications import figures
    from analytic.quantities import LENGTH, Display
    display = display or Display(mech.units)
    d = mech.definition
    topo = mech.topology
    n, _, _ = topo.counts
    lines = [f"{mech.name}: {d.description}" if d.description else mech.name,
             f"  source: {d.source} (units: {d.units})",
             f"  links: {n} ({', '.join(('ground',) + mech.links)})"]
    joints = mech.joints
    lines.append(f"  joints: {len(joints)} ({', '.join(f'{x.name} {x.kind[0].upper()} {x.a}-{x.b}' for x in joints)})")
    if topo.couplings:
        lines.append(f"  gear pairs: {len(topo.couplings)} ("
                     + ", ".join(f"{c.link}-{c.mesh} on {c.carrier}" for c in topo.couplings) + ")")
    _, start = mech.solve_at([0.0])
    if start.valid.all():                          # what the kinds say about their elements (pitch radii)
        pose = {p: (float(start["x" + p][0]), float(start["y" + p][0])) for p in mech.points}
        notes = (kinds.get(e["kind"]).describe(e, pose, (mech.scale, mech.units)) for e in mech.geometry.elements)
        lines += [f"  {note}" for note in notes if note]
    lines.append(f"  independent loops: {len(topo.loops)}")
    lines.append(f"  mobility (Gruebler): {topo.gruebler()}; inputs: "
                 + ", ".join(f"{i.q} ({i.kind} at {i.joint})" for i in mech.inputs))
    lines.append("  solve order: " + " -> ".join(f"{'+'.join(e.places)} ({e.kind})" for e in d.order))
    groups = [(e, kinds.get(e.kind).group_label(r)) for e, r in zip(d.order, mech.geometry.elements)]
    lines.append("  Assur groups: " + (", ".join(f"{'+'.join(e.places)} (links {', '.join(e.links())}): {cls}"
                                                for e, cls in groups if cls)
                                      or "none"))
    if len(mech.inputs) == 1:
        ranges = figures.assembly_ranges(mech)
        first = mech.inputs[0]
        crank = first.kind == "crank"

        def at(x):                                   # an input value as people read it
            if crank:
                return f"{(math.degrees(x) + 180) % 360 - 180:.4f}deg"
            return f"{display.convert(LENGTH, x):.6g} {display.unit(LENGTH)}"

        if figures.turns_fully(mech, ranges):
            lines.append(f"  {first.q} assembles over a full turn")
        elif ranges:
            lines.append(f"  {first.q} assembles in {figures.describe_ranges(first, ranges, display)} (ends rounded "
                         f"inward); dead points at " + ", ".join(dict.fromkeys(at(a) for r in ranges for a in r)))
        else:
            lines.append(f"  {first.q} assembles nowhere: change the lengths")
        for x, label, _ in figures.singular_poses(mech):
            where = f"{math.degrees(x) % 360:.2f}deg" if crank else at(x)
            how = ("passed on its declared branch, its form kept (change = 1)" if service.passes_smoothly(mech, label, x)
                   else "the motion is undefined there")
            lines.append(f"  singular pose at {first.q}={where}: {label} folds (change point; {how})")
    lines.append(f"  outputs: {len(mech.outputs)} ({' '.join(mech.outputs[:12])}{' ...' if len(mech.outputs) > 12 else ''})")
    return "\n".join(lines)


def cmd_analyze(args) -> int:
    mech = mechanism_from(args)
    check_outputs(args, {"csv": (".csv",)})
    a = service.analyze(mech, args.samples, args.revolutions, parse_range(mech, args.input_range))
    from analytic.applications import figures
    from sim.output.units import machine_units, shown_units
    if args.csv:
        write_columns(args.csv, mech, service.analysis_columns(mech, a), machine_units(args))
    if args.json:
        record = service.analysis_record(mech, a, args.samples, args.revolutions, machine_units(args))
        if args.csv:
            record["csv"] = args.csv
        print(dumps(record))
    else:
        from analytic.quantities import parameters_text
        shown = shown_units(args, mech)
        print("\n".join([f"{mech.name}: {parameters_text(mech, shown)}"] + figures.summary(mech, a.figures, shown)))
        if args.csv:
            print(f"wrote {args.csv} ({args.samples} rows)")
    return 0


def cmd_simulate(args) -> int:
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


def _say_start(mech, run) -> None:
    """A note on stderr where the run starts elsewhere than the file (a crank starting at a change point)."""
    note = service.start_note(mech, run)
    if note:
        print(f"linkage: note: {note}", file=sys.stderr)


def cmd_compare(args) -> int:
    from sim.run.compare import table
    mech = mechanism_from(args)
    built, c = service.compare(mech, args.revolutions, settings_from(args), loads_from(args, mech),
                               parse_range(mech, args.input_range))
    from sim.output.units import machine_units, shown_units
    _say_start(mech, built.mech)
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


def cmd_render(args) -> int:
    from sim.output.render import check_video_args, render
    path, size = check_video_args(args.out, args.fps, args.size)
    check_outputs(args, {})
    mech = mechanism_from(args)
    built, tr = service.simulate(mech, args.revolutions, settings_from(args), loads_from(args, mech),
                                 parse_range(mech, args.input_range))
    from sim.output.units import shown_units
    _say_start(mech, built.mech)
    stats = render(built, tr, str(path), args.fps, size, display=shown_units(args, built.mech),
                   forces=args.forces)
    print(f"wrote {stats.path}: {stats.frames} frames {size[0]}x{size[1]} at {stats.stored_fps:g} fps "
          f"({stats.fps:.1f} frames/s rendered)")
    return 0


def cmd_plot(args) -> int:
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
    from sim.front.dynamics_cmd import check_motor_args, motor_run
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


def cmd_export(args) -> int:
    from sim.front import parts_cmd
    from sim.output.io import write_text
    if not (args.mjcf or args.toml or parts_cmd.wanted(args)):
        raise ParameterError("give --mjcf PATH (the MuJoCo model), --toml PATH (the mechanism file) and/or parts: "
                             "--dxf, --svg, --pdf, --step, --stl DIR, --bom")
    check_outputs(args, {"mjcf": (".xml",), "toml": (".toml",)})
    parts_cmd.check_paths(args)
    mech = mechanism_from(args)
    if args.balance is not None:                   # counterweights written into the model (issue 17)
        from sim.front.forces_cmd import balance_links
        mech, _ = service.balanced_mechanism(mech, balance_links(args.balance))
    if args.mjcf:
        write_text(args.mjcf, service.export_mjcf(mech, settings_from(args), getattr(args, "revolutions", 1.0)))
        print(f"wrote {args.mjcf}")
    if args.toml:
        write_text(args.toml, service.mechanism_text(mech))
        print(f"wrote {args.toml}")
    if parts_cmd.wanted(args):                     # link solids, drawings, bill of materials (issue 28)
        parts_cmd.export(args, mech)
    return 0


def cmd_run(args) -> int:
    """The main job: simulate, cross-validate, render, plot and write CSV for each mechanism."""
    import time
    from pathlib import Path
    from sim.run.compare import table
    from sim.output.plot import sheet
    from sim.output.render import check_video_args, parse_size, render
    names = args.mechanisms or list(analytic.BUILTINS)
    if len(set(names)) != len(names):
        raise ParameterError("a mechanism is named twice; name each once")
    if (args.sets or args.inertia or args.cutting_force is not None or args.input_range) and len(names) != 1:
        raise ParameterError("--set, --inertia, --cutting-force and --input-range apply to one mechanism at a time: "
                             "name it (e.g. linkage run fourbar --set l1=0.12)")
    out_dir = Path(args.out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise ParameterError(f"--out-dir {out_dir} is a file, not a folder; choose a folder")
    mechs = []
    for name in names:
        mech = service.load(name, sets_of(args.sets))
        mechs.append((mech, service.prepare(mech, args.revolutions, parse_range(mech, args.input_range))))
    ext = "." + args.format
    size = parse_size(args.size)
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ParameterError(f"--out-dir {out_dir}: cannot create it ({exc.strerror or exc})") from None
    if not os.access(out_dir, os.W_OK):
        raise ParameterError(f"--out-dir {out_dir} is not writable; choose another folder")
    if not args.no_video:
        check_video_args(str(out_dir / f"{mechs[0][0].name}{ext}"), args.fps, args.size)
    t_start = time.perf_counter()
    results = []
    for k, (mech, _) in enumerate(mechs):
        if len(mechs) > 1 and sys.stderr.isatty():
            sys.stderr.write(f"[{k + 1}/{len(mechs)}] {mech.name}\n")
        built, c = service.compare(mech, args.revolutions, settings_from(args), loads_from(args, mech),
                                   parse_range(mech, args.input_range))
        from sim.output.units import machine_units, shown_units
        _say_start(mech, built.mech)
        shown = shown_units(args, mech)
        print(table(c, mech.size, shown, mech.output_point))
        files = [out_dir / f"{mech.name}.csv", out_dir / f"{mech.name}.png"]
        write_columns(files[0], mech, service.trajectory_columns(c.trajectory), machine_units(args))
        sheet(c, built, str(files[1]), shown)
        if not args.no_video:
            render(built, c.trajectory, str(out_dir / f"{mech.name}{ext}"), args.fps, size, display=shown)
            files.append(out_dir / f"{mech.name}{ext}")
        results.append((mech, c, files))
        print()
    print(f"summary ({time.perf_counter() - t_start:.1f} s):")
    for mech, c, files in results:
        from sim.run.compare import errors_in
        from sim.output.units import shown_units
        u = shown_units(args, mech)
        worst = max(c.errors, key=lambda k: c.errors[k]["max"] / c.errors[k]["tol"])
        e = errors_in({worst: c.errors[worst]}, u)[worst]
        print(f"  {mech.name:<8s} {'PASSED' if c.passed else 'FAILED'}  worst {worst}: {e['max']:.2e} {e['unit']} "
              f"(tol {e['tol']:.1e}); loop {u.convert('length', c.max_loop_violation):.1e} {u.unit('length')}; "
              f"drive {c.drive_error:.1e}")
        for f in files:
            print(f"           {f}")
    return 0 if all(c.passed for _, c, _ in results) else 1


# ------------------------------------------------------------------------------------------ parser
def add_common(p: argparse.ArgumentParser, revolutions: float = 1.0, mechanism: bool = True) -> None:
    if mechanism:
        p.add_argument("mechanism", metavar="MECH",
                       help="a built-in or library name (linkage list) or a linkage/1 file (.toml/.json)")
    p.add_argument("--set", dest="sets", action="append", default=[], metavar="NAME=VALUE",
                   help="override a parameter (repeatable); an angle may end in deg")
    p.add_argument("--revolutions", type=float, default=revolutions, metavar="R",
                   help=f"revolutions of the first input (default {revolutions:g})")


def add_sim_options(p) -> None:
    from sim.front.defaults import DEFAULT_INTEGRATOR, INTEGRATOR_NAMES
    p.add_argument("--timestep", type=float, default=None, metavar="H",
                   help="physics time step [s] (default: chosen from the design's fastest rate)")
    p.add_argument("--integrator", default=DEFAULT_INTEGRATOR, choices=INTEGRATOR_NAMES,
                   help=f"MuJoCo integrator (default {DEFAULT_INTEGRATOR})")
    p.add_argument("--gravity", metavar="GX,GY", help="gravity in the plane [m/s^2], e.g. 0,-9.81")
    p.add_argument("--force", metavar="FX,FY", help="constant external force on the output point [N]")
    p.add_argument("--cutting-force", metavar="F",
                   help="a force F [N] resisting the output point's slow (cutting) stroke along x")
    p.add_argument("--input-range", metavar="LO:HI",
                   help="rock the first input between LO and HI (e.g. a crank that cannot turn fully)")
    p.add_argument("--inertia", metavar="PATH.json",
                   help='links\' inertial data: {"2": {"m": 0.5, "cx": 0.15, "cy": 0, "I": 0.004}, ...}')


def add_video_options(p, out_required: bool = True) -> None:
    if out_required:
        p.add_argument("--out", required=True, metavar="PATH", help="video file, .mp4 (H.264) or .gif")
    p.add_argument("--fps", type=float, default=30.0, metavar="F", help="frames per second (default 30)")
    p.add_argument("--size", default="640x480", metavar="WxH", help="frame size in pixels (default 640x480)")


def make_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="linkage", description="Planar linkage kinematics, MuJoCo simulation and rendering.")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    p = sub.add_parser("list", help="the built-in and library mechanisms")
    p.set_defaults(func=cmd_list)

    p = sub.add_parser("check", help="a mechanism's structure: links, joints, loops, mobility, solve order, range")
    add_common(p)
    add_unit_options(p)
    from sim.front import parts_cmd
    parts_cmd.add_check_options(p)
    p.set_defaults(func=cmd_check)

    p = sub.add_parser("analyze", help="closed-form kinematics over a run; summary, CSV or JSON")
    add_common(p)
    p.add_argument("--samples", type=int, default=361, metavar="N", help="samples (default 361)")
    p.add_argument("--input-range", metavar="LO:HI", help="sample the first input between LO and HI instead")
    p.add_argument("--csv", metavar="PATH", help="write every sample as CSV (units in PATH.units.json)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    add_unit_options(p)
    p.set_defaults(func=cmd_analyze)

    p = sub.add_parser("simulate", help="simulate in MuJoCo and record the trajectory")
    add_common(p)
    add_sim_options(p)
    p.add_argument("--csv", metavar="PATH", help="write every step as CSV (units in PATH.units.json)")
    add_unit_options(p)
    p.set_defaults(func=cmd_simulate)

    p = sub.add_parser("compare", help="simulate and cross-validate against the analytic solution")
    add_common(p)
    add_sim_options(p)
    p.add_argument("--json", action="store_true", help="print one JSON object")
    add_unit_options(p)
    p.set_defaults(func=cmd_compare)

    p = sub.add_parser("render", help="render the simulation offscreen to MP4 or GIF")
    add_common(p)
    add_sim_options(p)
    add_video_options(p)
    p.add_argument("--forces", action="store_true",
                   help="draw MuJoCo's joint forces as arrows (the first link's force on the second; scale in "
                        "the legend)")
    add_unit_options(p)
    p.set_defaults(func=cmd_render)

    p = sub.add_parser("plot", help="analysis sheet: simulated samples over analytic curves, with errors")
    add_common(p)
    p.set_defaults(revolutions=None)
    next(a for a in p._actions if a.dest == "revolutions").help = (
        "revolutions of the first input (default 1; with --motor 10, the last one measured)")
    add_sim_options(p)
    p.add_argument("--out", required=True, metavar="PATH", help="image file: .png, .svg or .pdf")
    p.add_argument("--forces", action="store_true",
                   help="the force sheet instead: bearing loads (polar), joint forces, drives, shaking force")
    from sim.front.dynamics_cmd import add_motor_options
    add_motor_options(p, two=False)
    p.epilog = ("--motor T0,W0 (or --motor-table) draws the dynamics sheet instead: the motor drives the input; "
                "speed against angle over the last revolution with its mean and Cs band, start-up against time, "
                "motor torque, the reduced equation with MuJoCo's steps over it (as linkage dynamics --plot)")
    add_unit_options(p)
    p.set_defaults(func=cmd_plot)

    p = sub.add_parser("export", help="write the generated MuJoCo model (MJCF) and/or the mechanism file")
    add_common(p)
    p.add_argument("--mjcf", metavar="PATH.xml", help="the MuJoCo model, its home keyframe closing every loop")
    p.add_argument("--toml", metavar="PATH.toml", help="the mechanism file with the current parameter values")
    p.add_argument("--timestep", type=float, default=None, metavar="H", help="time step written into the model")
    p.add_argument("--integrator", default="rk4", help=argparse.SUPPRESS)
    p.add_argument("--balance", nargs="?", const="", default=None, metavar="LINK,LINK",
                   help="add counterweights that balance the shaking force ([mass.counterweights]; see forces)")
    parts_cmd.add_export_options(p)
    p.set_defaults(func=cmd_export)

    p = sub.add_parser("run", help="the main job: simulate, cross-validate, render, plot and save")
    p.add_argument("mechanisms", nargs="*", metavar="MECH", help="mechanisms (default: the three built-ins)")
    p.add_argument("--set", dest="sets", action="append", default=[], metavar="NAME=VALUE",
                   help="override a parameter (only with a single mechanism)")
    p.add_argument("--revolutions", type=float, default=1.0, metavar="R", help="revolutions (default 1)")
    p.add_argument("--out-dir", default="renders", metavar="DIR", help="output folder (default renders/)")
    p.add_argument("--format", choices=("mp4", "gif"), default="mp4", help="video format (default mp4)")
    p.add_argument("--no-video", action="store_true", help="skip the animations")
    add_sim_options(p)
    add_video_options(p, out_required=False)
    add_unit_options(p)
    p.set_defaults(func=cmd_run)

    from sim.front import design  # synthesis and sweeps
    design.register(sub, add_common, add_video_options)
    # commands in their own modules: module.register(sub, add_common, add_sim_options, add_video_options)
    from sim.front import dynamics_cmd  # a motor drives the linkage (issue 18)
    dynamics_cmd.register(sub, add_common, add_sim_options, add_video_options)
    from sim.front import forces_cmd  # joint forces, shaking, balancing (issue 17)
    forces_cmd.register(sub, add_common, add_sim_options, add_video_options)
    from sim.front import import_cmd  # Pyslvs and PMKS files (issue 16)
    import_cmd.register(sub, add_common, add_sim_options, add_video_options)
    try:
        from sim.front import app
        app.register(sub)
    except ImportError:
        pass
    return parser


def _join_negative_values(parser: argparse.ArgumentParser, argv: list[str]) -> list[str]:
    """``--force -10,0`` as ``--force=-10,0``: argparse would take ``-10,0`` for an option. Any value
    that starts with '-' followed by a digit or '.' is joined to the option before it."""
    takes_value = set()
    for action in _all_actions(parser):
        if action.option_strings and action.nargs is None and not isinstance(
                action, (argparse._StoreTrueAction, argparse._StoreFalseAction, argparse._HelpAction)):
            takes_value.update(action.option_strings)
    out, i = [], 0
    while i < len(argv):
        tok = argv[i]
        if tok in takes_value and i + 1 < len(argv) and len(argv[i + 1]) > 1 and argv[i + 1][0] == "-" \
                and (argv[i + 1][1].isdigit() or argv[i + 1][1] == "."):
            out.append(f"{tok}={argv[i + 1]}")
            i += 2
            continue
        out.append(tok)
        i += 1
    return out


def _all_actions(parser):
    for action in parser._actions:
        yield action
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                yield from _all_actions(sub)


class Terminated(BaseException):
    """SIGTERM, raised in the main thread so that partial outputs are removed on the way out."""


def _on_sigterm(signum, frame):
    raise Terminated()


def main(argv: list[str] | None = None) -> int:
    import signal
    main_thread = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGTERM, _on_sigterm) if main_thread else None
    try:
        with warnings.catch_warnings():
            # numpy's RuntimeWarnings (sqrt of a negative, 0/0) mark poses where a group does not assemble;
            # the solver flags those samples itself (Solution.valid) and every command reports them in words
            warnings.simplefilter("ignore", RuntimeWarning)
            return _main(argv)
    finally:
        if main_thread:
            signal.signal(signal.SIGTERM, previous)


def _main(argv: list[str] | None) -> int:
    try:
        parser = make_parser()
        argv = _join_negative_values(parser, list(sys.argv[1:] if argv is None else argv))
        args = parser.parse_args(argv)
        return args.func(args)
    except ParameterError as exc:
        print(f"linkage: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("linkage: interrupted", file=sys.stderr)
        return 130
    except Terminated:
        print("linkage: terminated", file=sys.stderr)
        return 143
    except BrokenPipeError:
        # the reader went away (e.g. | head): stop quietly, and keep Python from complaining at exit
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0
    except OSError as exc:
        where = f" {exc.filename}" if exc.filename else ""
        print(f"linkage: error:{where} {exc.strerror or exc}", file=sys.stderr)
        return 2
    except MemoryError:
        print("linkage: error: out of memory: reduce --samples, --revolutions or the sweep grid", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
