"""An input's motion law in a file (SPEC "Motion laws"): ``segments = [...]`` or ``table = "motion.csv"`` on
any ``[[inputs]]`` entry, checked when the file is read (:func:`check`) and resolved with the parameters'
values into an :class:`analytic.laws.Profile` or :class:`analytic.laws.Table` (:func:`resolve`).

Any input kind takes them: the fields are the format's, not a kind's; the kind says only whether its
coordinate is an angle (a rise in rad or ``"120deg"``) or a length (file units), and whether it turns
(a crank's cycle must end where it starts or a whole number of turns on).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from analytic._common import FileError, ParameterError
from analytic.format import expr

FIELDS = ("segments", "table")
"""The law fields every input takes."""

SEGMENT_KEYS = ("shape", "duration", "rise")
MAX_SEGMENTS = 500
MAX_TABLE_BYTES = 1 << 20


@dataclass(frozen=True)
class Written:
    """A law as the file writes it: ``segments`` ((shape, duration, rise) with values still symbolic) or a
    table's columns (t [s], q [rad or m]) read from its file."""

    segments: tuple = ()
    table: tuple | None = None
    path: str | None = None
    """A table's file, resolved (absolute: a file generated elsewhere still finds it)."""


def _short(v, limit: int = 40) -> str:
    s = repr(v)
    return s if len(s) <= limit else s[:limit - 3] + "..."


def _value(v, what: str):
    if isinstance(v, bool) or not isinstance(v, (int, float, str)):
        raise ValueError(f"{what}: {_short(v)} must be a number, a parameter name or an expression")
    if isinstance(v, float) and not math.isfinite(v):
        raise ValueError(f"{what}: must be finite")
    if isinstance(v, str) and expr.quantity(v) is None:
        try:
            expr.names_in(v)
        except ValueError as exc:
            raise ValueError(f"{what}: {exc}") from None
    return v


def _number(v) -> float | None:
    """A value's number when it is one already (a number or a quantity such as "120deg"), else None."""
    if isinstance(v, (int, float)):
        return float(v)
    q = expr.quantity(v)
    return q[0] if q else None


def check(item: dict, kind, motion_fields, label: str, source: str, scale: float) -> Written | None:
    """The law of input ``item`` (a raw ``[[inputs]]`` table) of ``kind``, or None when it gives none; a
    problem raises FileError naming the input (``label``) and the field. ``scale``: metres per file unit
    (a table's lengths)."""
    given = [f for f in FIELDS if f in item]
    if not given:
        return None

    def fail(field, what):
        return FileError(f"{source}: {label}: field {field!r}: {what}")

    if len(given) > 1:
        raise fail("table", "give segments or a table, not both")
    law = given[0]
    for f in motion_fields[1:]:
        if f in item:
            raise fail(f, f"the {law} set the motion; drop {f} (or the {law})")
    if law == "segments":
        return Written(segments=_segments(item["segments"], kind, fail))
    if motion_fields[0] in item:
        raise fail(motion_fields[0], f"the table's first q is the start value; drop {motion_fields[0]} "
                                     f"(or shift the table)")
    return Written(table=_table(item["table"], kind, source, scale, fail), path=str(_resolve(item["table"], source)))


def _segments(value, kind, fail) -> tuple:
    from analytic import laws                   # a file with a law only (a constant speed needs none)
    if not (isinstance(value, list) and value):
        raise fail("segments", "give a list of {shape = ..., duration = ..., rise = ...}")
    if len(value) > MAX_SEGMENTS:
        raise fail("segments", f"{len(value)} segments; at most {MAX_SEGMENTS}")
    out = []
    unit = "an angle (\"120deg\")" if kind.angular else "a length in file units"
    for k, seg in enumerate(value, 1):
        where = f"segment {k}"
        if not isinstance(seg, dict):
            raise fail("segments", f"{where}: {_short(seg)} must be a table {{shape = ..., duration = ...}}")
        extra = sorted(set(seg) - set(SEGMENT_KEYS))
        if extra:
            raise fail("segments", f"{where}: unknown key {extra[0]!r}; a segment takes shape, duration, rise")
        shape = seg.get("shape")
        if shape not in laws.SHAPES:
            raise fail("segments", f"{where}: shape {_short(shape)} is not one of {', '.join(laws.SHAPES)}")
        if "duration" not in seg:
            raise fail("segments", f"{where}: give its duration [s]")
        try:
            duration = _value(seg["duration"], f"{where}: duration")
            rise = _value(seg.get("rise", 0.0), f"{where}: rise")
        except ValueError as exc:
            raise fail("segments", str(exc)) from None
        d = _number(duration)
        if d is not None and not d > 0:
            raise fail("segments", f"{where}: duration {d:g} s must be > 0")
        if shape == "dwell" and "rise" in seg:
            raise fail("segments", f"{where}: a dwell does not move; drop its rise (or give another shape)")
        if shape != "dwell" and "rise" not in seg:
            raise fail("segments", f"{where}: a {shape} segment needs its rise, {unit}")
        if isinstance(rise, str) and not kind.angular and (expr.quantity(rise) or ("", False))[1]:
            raise fail("segments", f"{where}: rise {rise!r} is an angle; this input is a length: give file units")
        out.append((shape, duration, rise))
    return tuple(out)


def _resolve(value: str, source: str) -> Path:
    """A table's path: as written when absolute, else in the mechanism file's folder (the working folder for
    a text without a file)."""
    path = Path(value)
    if not path.is_absolute():
        base = Path(source).parent if Path(source).is_file() else Path.cwd()
        path = (base / path).resolve()
    return path


def _table(value, kind, source, scale, fail):
    from analytic import laws                   # a file with a law only (a constant speed needs none)
    if not (isinstance(value, str) and value.strip()):
        raise fail("table", f"{_short(value)} must be the path of a CSV file (columns t,q or t,q_deg)")
    path = _resolve(value, source)
    try:
        with open(path, "rb") as fh:
            raw = fh.read(MAX_TABLE_BYTES + 1)
    except OSError as exc:
        raise fail("table", f"cannot read {value!r} ({exc.strerror or exc})") from None
    if len(raw) > MAX_TABLE_BYTES:
        raise fail("table", f"{value!r} is over {MAX_TABLE_BYTES} bytes")
    try:
        t, q = laws.read_table(raw.decode("utf-8-sig"), kind.angular, scale)
    except (ValueError, UnicodeDecodeError) as exc:
        raise fail("table", f"{value}: {exc}") from None
    return tuple(t), tuple(q)


def uses(written: Written, kind) -> list[tuple[object, str]]:
    """(value, what it measures) of every symbolic value: parameters used in a law."""
    out = []
    for _, duration, rise in written.segments:
        out += [(duration, "number"), (rise, "angle" if kind.angular else "length")]
    return out


def resolve(written: Written, kind, num, label: str, source: str):
    """The law (:class:`analytic.laws.Profile` or :class:`~analytic.laws.Table`) with values from
    ``num(value, kind, where)`` (SI); a duration <= 0 or a turning input whose cycle does not close raises
    ParameterError naming the input and the field."""
    from analytic import laws                   # a file with a law only (a constant speed needs none)
    turn = 2 * math.pi if kind.periodic else None
    if written.table is not None:
        t, q = written.table
        law = laws.table_law(t, q, turn)
        if turn is not None and law.period_rise is None:
            raise ParameterError(f"{source}: {label}: field 'table': q ends {math.degrees(law.rise):.6g}deg from where "
                                 f"it starts; a crank's cycle must end where it starts or a whole number of turns on "
                                 f"(0deg, 360deg, ...): {_fix(law.rise)}")
        return law
    segs = []
    for k, (shape, duration, rise) in enumerate(written.segments, 1):
        where = f"{label}: field 'segments': segment {k}"
        d = num(duration, "number", where + ": duration")
        if not d > 0:
            raise ParameterError(f"{source}: {where}: duration {d:g} s must be > 0")
        segs.append(laws.Segment(shape, d, num(rise, "angle" if kind.angular else "length", where + ": rise")))
    law = laws.Profile(tuple(segs))
    if turn is not None and not laws.whole_turns(law.rise, turn):
        raise ParameterError(f"{source}: {label}: field 'segments': the rises sum to {math.degrees(law.rise):.6g}deg; a "
                             f"crank's cycle must end where it starts or a whole number of turns on (0deg, 360deg, "
                             f"...): {_fix(law.rise)}")
    return law


def _fix(rise: float) -> str:
    turn = 2 * math.pi
    up = math.ceil(rise / turn) * turn - rise
    down = rise - math.floor(rise / turn) * turn
    return f"add a segment rising {math.degrees(up):.6g}deg or {-math.degrees(down):.6g}deg"
