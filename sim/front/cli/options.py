"""What the command modules share: the common options and their values (``--set``, the input range, the
simulation settings and loads), the checks of output paths, and CSV columns with their units sidecar.

Every command module imports this one and nothing else of the command line, so that the modules form no
circle: :mod:`sim.front.cli` assembles the parser from the command modules, which import this.
"""

from __future__ import annotations

import argparse
import json
import os
import sys

from analytic import ParameterError
from sim import service
from sim.output.io import check_writable, write_csv
from sim.service.values import parse_value


def sets_of(items: list[str]) -> dict[str, str]:
    """``--set NAME=VALUE`` items as {name: text}; a name given twice is an error."""
    out: dict[str, str] = {}
    for item in items or []:
        if "=" not in item:
            raise ParameterError(f"--set {item!r} is not NAME=VALUE (e.g. --set l1=0.12)")
        name, text = (x.strip() for x in item.split("=", 1))
        if name in out:
            raise ParameterError(f"--set {name} is given twice ({out[name]} and {text}); give it once")
        out[name] = text
    return out


def mechanism_from(args):
    mech = service.load(args.mechanism, sets_of(args.sets))
    guard_tables(args, mech)
    return mech


def guard_tables(args, mech) -> None:
    """No output is a table file the mechanism's loads read (named inside the file, so known only once it
    is read; before any work still): one line naming the option, the table and the fix."""
    if not any(isinstance(getattr(args, name, None), str) for name in OUTPUT_ARGS):
        return                                 # no output: nothing to guard (and the loads' modules not loaded)
    from sim.service.loads import table_files
    tables = {os.path.realpath(p): p for p in table_files(mech)}
    for name in OUTPUT_ARGS:
        v = getattr(args, name, None)
        if isinstance(v, str) and v and os.path.realpath(v) in tables:
            raise ParameterError(f"--{name.replace('_', '-')} {v} is an input of this command and would be "
                                 f"overwritten (a load table of {mech.definition.source}); choose another output name")


def _outputs(args) -> set[str]:
    outs = set()
    for name in ("csv", "out", "mjcf", "toml", "plot", "render"):
        v = getattr(args, name, None)
        if v:
            outs.add(os.path.abspath(v))
    return outs


def check_outputs(args, suffixes: dict[str, tuple[str, ...]]) -> None:
    """Every output path writable with the right type, and none of them one of the inputs."""
    for name, sfx in suffixes.items():
        v = getattr(args, name, None)
        if v:
            check_writable(v, sfx)
    inputs = set()
    mech = getattr(args, "mechanism", None)
    if isinstance(mech, str) and os.path.exists(mech):
        inputs.add(os.path.abspath(mech))
    if getattr(args, "inertia", None):
        inputs.add(os.path.abspath(args.inertia))
    from sim.service.catalog import LIBRARY
    library = os.path.realpath(LIBRARY)
    for out in sorted(_outputs(args)):
        if os.path.dirname(os.path.realpath(out)) == library:
            raise ParameterError(f"{out} is in the shipped mechanism library, which is never written; "
                                 f"choose an output outside {library}")
    clash = {os.path.realpath(x) for x in inputs} & {os.path.realpath(x) for x in _outputs(args)}
    if clash:
        raise ParameterError(f"{sorted(clash)[0]} is an input of this command and would be overwritten; "
                             f"choose another output name")


INPUT_ARGS = ("mechanism", "mechanisms", "inertia", "target", "poses", "pairs", "motor_table")
"""The options and arguments every command reads from (files the user already had)."""
OUTPUT_ARGS = ("csv", "out", "mjcf", "toml", "plot", "render")
"""The options every command writes to (and FILE_2.toml ... beside a synthesis --out)."""


def guard_outputs(args) -> None:
    """Before any work, for every command: no output is one of the inputs or in the shipped library, and
    ``run --out-dir`` is not the library. One line naming the option and the fix."""
    from sim.service.catalog import LIBRARY
    library = os.path.realpath(LIBRARY)
    inputs: dict[str, str] = {}
    for name in INPUT_ARGS:
        values = getattr(args, name, None)
        for v in values if isinstance(values, list) else [values]:
            if isinstance(v, str) and v and os.path.exists(v):
                inputs.setdefault(os.path.realpath(v), name)
    for name in OUTPUT_ARGS:
        v = getattr(args, name, None)
        if not isinstance(v, str) or not v:
            continue
        real = os.path.realpath(v)
        option = "--" + name.replace("_", "-")
        if os.path.dirname(real) == library:
            raise ParameterError(f"{option} {v}: that is in the shipped mechanism library, which is never written; "
                                 f"choose an output outside {library}")
        if real in inputs:
            what = inputs[real].replace("_", "-")
            what = f"--{what}" if what in ("inertia", "motor-table") else f"the {what.rstrip('s')} file"
            raise ParameterError(f"{option} {v} is an input of this command and would be overwritten ({what}); "
                                 f"choose another output name")
    out_dir = getattr(args, "out_dir", None)
    if isinstance(out_dir, str) and os.path.realpath(out_dir) == library:
        raise ParameterError(f"--out-dir {out_dir}: that is the shipped mechanism library, which is never written; "
                             f"choose another folder")


def one_line(text: str) -> str:
    """A message as one line: a newline or other control character inside it (a file name holding one) is
    written as its escape (``\\n``), so that the message cannot spread over lines or forge another."""
    return "".join(c if c.isprintable() or c == " " else repr(c)[1:-1] for c in text)


def degrees(text: str) -> float:
    """An argparse type for an angle option given in degrees: ``30``, ``30deg`` (as every other angle the
    command line takes) or ``0.5rad``; returns degrees."""
    import math
    t = text.strip()
    try:
        if t.lower().endswith("rad"):
            return math.degrees(parse_value("angle", t[:-3], angle=False))
        if t.lower().endswith("deg"):
            t = t[:-3]
        return parse_value("angle", t, angle=False)
    except ParameterError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an angle in degrees (e.g. 30 or 30deg)") from None


SMALLEST_SIZE = 1e-3
"""[m] Below this a design cannot be simulated (sim.model.build.MIN_SIZE: MuJoCo's minimum masses); in a
file of mm, cm or in it is most often metres typed into it."""
LARGEST_SIZE = 100.0
"""[m] Above this a linkage is a building: most often mm typed into a file of metres."""


def size_warning(mech) -> str | None:
    """One line for ``check`` and ``analyze`` when the design's size is implausible (what only ``compare``
    used to notice), else None."""
    size, unit = mech.size, mech.definition.units
    shown = f"{size / mech.scale:.3g} {unit}"
    if size < SMALLEST_SIZE:
        hint = ("were metres typed into a mm file? give the lengths in " + unit if unit != "m"
                else "is it in mm? add units = \"mm\" to the file")
        return f"the {mech.name} spans {shown}, too small to simulate (at least {SMALLEST_SIZE:g} m): {hint}"
    if size > LARGEST_SIZE:
        hint = ("were mm typed into a file of metres? add units = \"mm\" to the file" if unit == "m"
                else "check the file's units")
        return f"the {mech.name} spans {shown}{f' ({size:.3g} m)' if unit != 'm' else ''}: {hint}"
    return None


def warn_size(mech) -> None:
    """``check`` and ``analyze``: one warning line on stderr for an implausible size (see size_warning)."""
    note = size_warning(mech)
    if note:
        print(f"linkage: warning: {note}", file=sys.stderr)


def parse_range(mech, text: str | None) -> tuple[float, float] | None:
    """``LO:HI`` of the first input: a crank's in radians, or degrees with a deg suffix; a slider's in the
    file's length unit (like ``--set``, and as ``linkage check`` prints it), returned in metres. Without
    ``text``: the file's own ``input_range`` (a synthesised rocking design's working range), if any."""
    given = text
    text = text or mech.definition.input_range
    if not text:
        return None
    if ":" not in text:
        raise ParameterError(f"--input-range {text!r} is not LO:HI (e.g. -40deg:40deg)")
    lo, hi = text.split(":", 1)
    angle = mech.inputs[0].angular
    scale = 1.0 if angle else mech.scale
    out = (parse_value("--input-range", lo, angle=None if angle else False) * scale,
           parse_value("--input-range", hi, angle=None if angle else False) * scale)
    if not out[1] > out[0]:
        where = f"--input-range {text}" if given else f"{mech.definition.source}: input_range = {text!r}"
        raise ParameterError(f"{where}: the end must exceed the start; give LO:HI with LO < HI (e.g. -40deg:40deg)")
    return out


def pair(option: str, text: str | None) -> tuple[float, float] | None:
    if text is None:
        return None
    parts = text.split(",")
    if len(parts) != 2:
        raise ParameterError(f"{option} {text!r} is not two numbers X,Y (e.g. {option} 0,-9.81)")
    return parse_value(option, parts[0], angle=False), parse_value(option, parts[1], angle=False)


def settings_from(args):
    from sim.service.simulation import settings
    return settings(args.timestep, args.integrator)


def load_keywords(args, mech) -> dict:
    """The command line's loads as the keywords :mod:`linkage`'s functions take (``gravity``, ``force``,
    ``cutting_force``, ``torque``, ``inertia``), their text read and checked here so that a mistake is named
    by its option (``--force``, ``--torque``, ...)."""
    from sim.front.cli.loads_opts import command_loads, split_force, _pair
    gravity = pair("--gravity", args.gravity)
    force_text, _ = command_loads(args, mech)         # --force FX,FY@POINT[:LINK], --torque T@LINK checked
    force = pair("--force", force_text)
    if force is None and getattr(args, "force", None):                  # a force at a named point
        value, point, link = split_force(args.force)
        force = (*_pair("--force", value), point) + ((link,) if link else ())
    cutting = args.cutting_force
    if cutting is not None:
        cutting = parse_value("--cutting-force", cutting, angle=False)
        if cutting < 0:
            raise ParameterError(f"--cutting-force {cutting:g} must be >= 0 [N] (it always resists the motion)")
        if args.force:
            raise ParameterError("give either --force or --cutting-force, not both")
    torque = []
    for item in getattr(args, "torque", None) or []:
        value, ln = item.split("@", 1)
        torque.append((ln.strip(), parse_value("--torque", value.strip(), angle=False)))
    inertia = None
    if args.inertia:
        if os.path.abspath(args.inertia) in _outputs(args):
            raise ParameterError(f"--inertia {args.inertia} is also an output of this command; it would be "
                                 f"overwritten: choose another output name")
        from sim.readers import read_json
        inertia = read_json("--inertia", args.inertia)
        if not isinstance(inertia, dict):
            raise ParameterError(f"--inertia {args.inertia}: expected an object of links")
    return {"gravity": gravity, "force": force, "cutting_force": cutting, "torque": torque or None,
            "inertia": inertia}


def loads_from(args, mech):
    """The Loads of the command line: gravity, external or cutting force, couples, links' inertias (what
    :func:`linkage._loads.run_loads` makes of :func:`load_keywords`)."""
    from linkage._loads import run_loads
    return run_loads(mech, **load_keywords(args, mech))


def cutting_direction(mech) -> float:
    """:func:`sim.service.loads.cutting_direction`, where the app and scripts found it before."""
    from sim.service.loads import cutting_direction as direction
    return direction(mech)


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


def timestep_advice(args, mech, revolutions: float) -> str | None:
    """Where ``--timestep`` is coarser than the step the design needs: the words that say so and the fix."""
    given = getattr(args, "timestep", None)
    if given is None:
        return None
    from sim.service.simulation import chosen_timestep
    chosen = chosen_timestep(mech, revolutions)
    if given > chosen * (1 + 1e-3):                           # not a value that only prints the same
        return (f"the time step {given:.4g} s given by --timestep is above the {chosen:.4g} s this design needs; "
                f"drop --timestep")
    return None


def say_not_written(paths, why: str, fix: str | None = None) -> None:
    """A run whose verdict failed (exit 1) writes none of its files: one line on stderr naming them, why, and
    the fix. Nothing is said where no file was asked for."""
    names = [str(p) for p in paths if p]
    if names:
        print(one_line(f"linkage: not written: {', '.join(names)} ({why}); {fix or 'see the verdict above'}"),
              file=sys.stderr)


def say_start(mech, run) -> None:
    """A note on stderr where the run starts elsewhere than the file (a crank starting at a change point)."""
    note = service.start_note(mech, run)
    if note:
        print(f"linkage: note: {note}", file=sys.stderr)


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
    p.add_argument("--force", metavar="FX,FY[@POINT[:LINK]]",
                   help="constant external force [N] on the output point, or at POINT on LINK (default: its carrier)")
    p.add_argument("--cutting-force", metavar="F",
                   help="a force F [N] resisting the output point's slow (cutting) stroke along x")
    from sim.front.cli.loads_opts import add_options
    add_options(p)
    p.add_argument("--input-range", metavar="LO:HI",
                   help="rock the first input between LO and HI (e.g. a crank that cannot turn fully)")
    p.add_argument("--inertia", metavar="PATH.json",
                   help='links\' inertial data: {"2": {"m": 0.5, "cx": 0.15, "cy": 0, "I": 0.004}, ...}')


def add_video_options(p, out_required: bool = True) -> None:
    if out_required:
        p.add_argument("--out", required=True, metavar="PATH", help="video file, .mp4 (H.264) or .gif")
    p.add_argument("--fps", type=float, default=30.0, metavar="F", help="frames per second (default 30)")
    p.add_argument("--size", default="640x480", metavar="WxH", help="frame size in pixels (default 640x480)")
