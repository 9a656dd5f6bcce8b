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
