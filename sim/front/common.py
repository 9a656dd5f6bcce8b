"""What the command modules share: parameter overrides from ``--set`` and the checks of output paths.

Kept apart from :mod:`sim.front.cli` so that the command modules (design, dynamics, ...) never import the
module that imports them.
"""

from __future__ import annotations

import os

from analytic import ParameterError
from sim import service
from sim.output.io import check_writable


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
    return service.load(args.mechanism, sets_of(args.sets))


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
    from analytic.registry import LIBRARY
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
    from analytic.registry import LIBRARY
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
    import argparse
    import math
    from analytic.format import expr
    t = text.strip()
    try:
        if t.lower().endswith("rad"):
            return math.degrees(expr.parse_value("angle", t[:-3], angle=False))
        if t.lower().endswith("deg"):
            t = t[:-3]
        return expr.parse_value("angle", t, angle=False)
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
