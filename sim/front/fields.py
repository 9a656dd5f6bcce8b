"""The fields each of the app's actions accepts and their checks, derived from the door (:mod:`linkage.api`):
an action that runs a door function takes that function's keyword-only arguments (their names, defaults and
annotations, read by :func:`inspect.signature`), less the few the server withholds (:data:`WITHHELD`), plus
the app's own fields (:data:`APP_FIELDS`: which mechanism, how the answer is encoded). One validation: a new
keyword of the door becomes a field of the app, checked by its annotation, or the table test fails until it
is withheld with its reason. Any other field is refused in one line naming it and the accepted ones."""

from __future__ import annotations

import functools
import inspect
import math

import linkage.api as door
from sim.front.requests import MAX_REVOLUTIONS, MAX_SAMPLES, RequestError, _short

MAX_RENDER_REVOLUTIONS = 5.0
MAX_DYNAMICS_REVOLUTIONS = 50.0
"""Revolutions of a motor run from the page: the last is the one measured, the first ones the start-up."""
MAX_LOAD = 1e9
"""[N, m/s^2] The largest gravity or force component accepted (sim.model.Loads' own bound)."""
MAX_MOTOR = 1e6
"""[N m, rad/s] The largest stall torque, no-load speed or start speed accepted."""
MAX_FLYWHEEL = 1e6
"""[kg m^2] The largest flywheel accepted."""

DOORS = {"solve": (door.analyze,), "drag": (door.analyze,), "simulate": (door.compare,),
         "render": (door.simulate,), "forces": (door.forces,), "dynamics": (door.dynamics,),
         "export": (door.analyze, door.export)}
"""The door functions each action runs (its fields are their keywords): export's CSV and JSON are an analysis,
its MJCF the door's export."""

_MECHANISM = ("mechanism", "text", "set")
APP_FIELDS = {
    "solve": {*_MECHANISM, "outputs", "digits", "arrays"},
    "drag": {*_MECHANISM, "outputs", "digits", "arrays", "point", "target", "input", "locked", "round"},
    "simulate": {*_MECHANISM, "outputs"},
    "render": {*_MECHANISM, "size", "fps"},
    "forces": {*_MECHANISM, "digits"},
    "dynamics": {*_MECHANISM},
    "export": {*_MECHANISM},
}
"""The app's own fields by action: the mechanism (a name or a file's ``text``, and the values ``set``), the
plotted ``outputs``, how arrays are encoded (``digits``, ``arrays``), a video's ``size`` and ``fps``, a drag's
point and target."""

WITHHELD = {
    "mjcf": "a path the door writes: the server writes no file a request names",
    "toml": "a path the door writes: the server writes no file a request names",
    "timestep": "the page bounds a run's work by its revolutions and samples; a time step would bypass that",
    "integrator": "the page offers MuJoCo's default integrator only",
    "balance": "the page shows no counterweights",
    "at": "the forces panel draws a run, not one pose",
    "interference": "the page's comparison draws no parts",
    "max_steps": "the server bounds a motor run's MuJoCo steps itself (sim.front.app.MAX_DYNAMICS_STEPS)",
}
"""The door's keywords the app does not take, each with its reason."""

NUMBERS = {"samples": (2, MAX_SAMPLES), "revolutions": (1e-6, MAX_REVOLUTIONS), "start_speed": (0.0, MAX_MOTOR),
           "target_fluctuation": (0.0, 1.0), "flywheel": (0.0, MAX_FLYWHEEL), "cutting_force": (0.0, MAX_LOAD)}
"""[lo, hi] of each numeric keyword from a page: the server's bounds on a request's work."""
ACTION_NUMBERS = {("render", "revolutions"): (1e-6, MAX_RENDER_REVOLUTIONS),
                  ("dynamics", "revolutions"): (1.0, MAX_DYNAMICS_REVOLUTIONS)}
"""The bounds of one action where they differ (a video's frames, a motor run's revolutions)."""


def _pair(name: str, v):
    ok = (isinstance(v, list) and len(v) == 2
          and all(isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) and abs(x) <= MAX_LOAD
                  for x in v))
    if not ok:
        example = "[0, -9.81]" if name == "gravity" else "[10, 0]"
        raise RequestError(400, f"{name} {_short(v)} must be two numbers [x, y] of magnitude <= {MAX_LOAD:g}, "
                                f"e.g. {example}")
    return float(v[0]), float(v[1])


def _input_range(name: str, v):
    if v == "":
        return None                                 # an emptied field: the file's own range
    if isinstance(v, str) and ":" in v:
        return v
    if isinstance(v, list) and len(v) == 2 and all(isinstance(x, (int, float)) and not isinstance(x, bool)
                                                   for x in v):
        return float(v[0]), float(v[1])
    raise RequestError(400, f"input_range {_short(v)} is not LO:HI (e.g. \"-100deg:-45deg\") or [LO, HI]")


def _object(example: str):
    def check(name: str, v):
        if not isinstance(v, dict) or not v or not all(isinstance(k, str) for k in v):
            raise RequestError(400, f"{name} {_short(v)} must be an object, e.g. {example}")
        return v
    return check


def _motor(name: str, v):
    if not isinstance(v, dict) or set(v) != {"T0", "W0"}:
        raise RequestError(400, "motor must be {\"T0\": stall torque [N m], \"W0\": no-load speed [rad/s]}, e.g. "
                                "{\"T0\": 2, \"W0\": 15.7}")
    for key, what in (("T0", "stall torque [N m]"), ("W0", "no-load speed [rad/s]")):
        x = v[key]
        if isinstance(x, bool) or not isinstance(x, (int, float)) or not (math.isfinite(x) and 0 < x <= MAX_MOTOR):
            raise RequestError(400, f"motor.{key}={_short(x)}: the {what} must be a number in (0, {MAX_MOTOR:g}]")
    return float(v["T0"]), float(v["W0"])


SHAPES = {"input_range": _input_range, "gravity": _pair, "force": _pair, "motor": _motor,
          "torque": _object("{\"4\": -2.5} (N m on link 4)"),
          "inertia": _object("{\"2\": {\"m\": 0.5, \"cx\": 0.05, \"cy\": 0, \"I\": 0.001}}")}
"""The checks of the keywords whose annotation does not say their shape (a pair, a range, an object); an
object's contents are the door's to check (a link's name, an inertia's fields)."""

UNANNOTATED_NUMBERS = {"flywheel", "cutting_force"}
"""Keywords without an annotation that are plain numbers (the door takes more for a two-motor run)."""


@functools.cache
def _kind(param: inspect.Parameter) -> tuple[str, bool]:
    """(kind, may be null) of a keyword from its annotation's text (the door's annotations are strings):
    ``int``, ``float``, ``bool``, ``str``, or ``shape`` where :data:`SHAPES` checks it."""
    text = param.annotation if isinstance(param.annotation, str) else getattr(param.annotation, "__name__", "")
    parts = [p.strip() for p in text.split("|")] if text and text != inspect.Parameter.empty else []
    nullable = "None" in parts or param.default is None
    kinds = [p for p in parts if p != "None"]
    if param.name in SHAPES:
        return "shape", nullable
    if param.name in UNANNOTATED_NUMBERS:
        return "float", nullable
    if len(kinds) == 1 and kinds[0] in ("int", "float", "bool", "str"):
        return kinds[0], nullable
    raise TypeError(f"the door's keyword {param.name}: no check for its annotation {text!r}: add it to SHAPES")


@functools.cache
def keywords(action: str) -> dict[str, inspect.Parameter]:
    """The keyword-only arguments of the door functions ``action`` runs, by name (the first function's where
    two share one), the withheld ones left out."""
    out = {}
    for fn in DOORS[action]:
        for p in inspect.signature(fn).parameters.values():
            if p.kind is inspect.Parameter.KEYWORD_ONLY and p.name not in WITHHELD:
                out.setdefault(p.name, p)
    return out


@functools.cache
def accepted(action: str) -> frozenset:
    """Every field ``action`` accepts: its door functions' keywords (less the withheld) and its own."""
    return frozenset(keywords(action)) | frozenset(APP_FIELDS[action])


def check_fields(body: dict, action: str, fields=None) -> None:
    """Refuse a field ``action`` does not take, naming it and the accepted ones."""
    fields = accepted(action) if fields is None else fields
    unknown = sorted(set(body) - set(fields))
    if unknown:
        raise RequestError(400, f"unknown field {unknown[0]!r}; {action} takes {', '.join(sorted(fields))}")


def check(action: str, name: str, v):
    """One door keyword's value from a request, checked by its annotation (and bounds) or its shape."""
    kind, nullable = _kind(keywords(action)[name])
    if v is None and nullable:
        return None
    if kind == "shape":
        return SHAPES[name](name, v)
    if kind == "bool":
        if not isinstance(v, bool):
            raise RequestError(400, f"{name} must be true or false (got {_short(v)})")
        return v
    if kind == "str":
        if not isinstance(v, str) or len(v) > 200:
            raise RequestError(400, f"{name} must be text (got {_short(v)})")
        return v
    integer = kind == "int"
    if isinstance(v, bool) or not isinstance(v, (int,) if integer else (int, float)):
        raise RequestError(400, f"{name} must be {'an integer' if integer else 'a number'} (got {_short(v)})")
    lo, hi = ACTION_NUMBERS.get((action, name)) or NUMBERS[name]
    if not (math.isfinite(v) and lo <= v <= hi):
        raise RequestError(400, f"{name}={_short(v)} is out of range: give {'an integer' if integer else 'a number'} "
                                f"in {lo:g}..{hi:g}")
    return int(v) if integer else float(v)


def arguments(body: dict, action: str) -> dict:
    """The door's keyword arguments of a request to ``action``: every accepted keyword, checked where the
    request gives it, its default where not. Refuses an unknown field first."""
    check_fields(body, action)
    return {name: check(action, name, body.get(name)) if name in body or p.default is p.empty else p.default
            for name, p in keywords(action).items()}


def for_door(args: dict, fn) -> dict:
    """Of ``args``, the keywords ``fn`` takes."""
    names = _parameters(fn)
    return {k: v for k, v in args.items() if k in names}


@functools.cache
def _parameters(fn) -> frozenset:
    """The names of ``fn``'s parameters (read once: a drag step asks at every step)."""
    return frozenset(inspect.signature(fn).parameters)
