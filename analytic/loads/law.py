"""How a load's value follows the motion (SPEC "Loads"): a constant, an expression of the inputs and time,
or a table (input -> value, interpolated linearly, periodic over a crank's turn); optionally active only over
a range of the first input (``active = "LO:HI"``) and only while its point moves one way (``stroke``)."""

from __future__ import annotations

import csv
import io
import math
import os
import stat
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from analytic import kinds
from analytic.format import expr
from analytic.loads.common import Scales

LAW_FIELDS = ("magnitude", "table", "active", "stroke")


def editor_fields(what: str = "force unit", turning: bool = False) -> tuple:
    """The law's fields as the load editor shows them (:class:`analytic.loads.base.Field`)."""
    from analytic.loads.base import Field
    return (Field("magnitude", "number", "magnitude",
                  f"a number ({what}) or an expression of phi1, omega1, t"),
            Field("table", "table", "table", "rows input,value separated by ';' (input in deg, or file units for a "
                                             "slide) instead of a magnitude"),
            Field("active", "text", "active", "optional: only over this range of the first input, e.g. 120deg:240deg"),
            Field("stroke", "text", "stroke", "optional: only while the link turns this way (+ or -)" if turning else
                  "optional: only while the point moves this way (+x, -x, +y, -y)"))
STROKES = {"+x": (0, 1.0), "-x": (0, -1.0), "+y": (1, 1.0), "-y": (1, -1.0), "+": (2, 1.0), "-": (2, -1.0)}
"""stroke -> (axis: 0 x, 1 y, 2 the link's rotation; sign)."""
MAX_ROWS = 100000
MAX_TABLE_BYTES = 8 * 1024 * 1024
"""The largest table file read [bytes]: MAX_ROWS rows of two numbers in full precision fit in 5 MB."""



@dataclass(frozen=True)
class Law:
    """A value over the samples, in SI once multiplied by ``unit`` (newtons, N m or N/m^2 per file unit).

    ``constant`` (file units) or ``expression`` (text) or ``table`` ((x, y): x the first input in rad or m,
    y file units; ``periodic`` for a crank); ``active`` (lo, hi) of the first input [rad or m]; ``stroke``
    (axis, sign) or None."""

    unit: float
    constant: float | None = None
    expression: str | None = None
    table: tuple | None = None
    periodic: bool = False
    active: tuple | None = None
    stroke: tuple | None = None
    crank: bool = True

    def value(self, state, variables: dict | None = None) -> np.ndarray:
        """The law's value [SI] at every sample of ``state`` before the stroke condition."""
        n = state.n
        q1 = state.q[:, 0]
        if self.constant is not None:
            v = np.full(n, self.constant)
        elif self.expression is not None:
            v = np.broadcast_to(evaluate(self.expression, variables or {}), (n,)).astype(float)
        else:
            x, y = self.table
            v = np.interp(q1, x, y, period=2 * math.pi) if self.periodic else np.interp(q1, x, y)
        v = v * self.unit
        if self.active is not None:
            v = np.where(self.on(q1), v, 0.0)
        return v

    def on(self, q1) -> np.ndarray:
        """Where the first input's values ``q1`` [rad or m] lie in the ``active`` window (everywhere without one)."""
        q1 = np.asarray(q1, dtype=float)
        if self.active is None:
            return np.ones(q1.shape, dtype=bool)
        lo, hi = self.active
        if self.crank:
            return np.mod(q1 - lo, 2 * math.pi) <= (hi - lo) + 1e-12
        return (q1 >= lo) & (q1 <= hi)

    def crossing(self, a, b) -> np.ndarray:
        """The value [rad or m] at which the first input, going from ``a`` to ``b`` (arrays, one interval each),
        passes an edge of the ``active`` window (a crank's edges on every turn), the one nearest ``a``; NaN
        where it passes none."""
        a, b = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(b, dtype=float))
        best = np.full(a.shape, np.nan)
        if self.active is None:
            return best
        eps = 1e-9 * max(1.0, *(abs(e) for e in self.active))      # an edge met at a sample, to rounding
        step = b - a
        for e in self.active:
            if self.crank:                                  # the edge's turn nearest a, ahead in the motion
                d = np.where(step >= 0, np.mod(e - a + eps, 2 * math.pi) - eps,
                             -(np.mod(a - e + eps, 2 * math.pi) - eps))
            else:
                d = e - a
            inside = (d * np.sign(step) >= -eps) & (np.abs(d) <= np.abs(step) + eps)
            better = inside & ~(np.abs(d) >= np.abs(best - a))
            best = np.where(better, a + d, best)
        return best

    def gate(self, v, velocity=None, omega=None):
        """``v`` where the stroke condition holds (the point's velocity (vx, vy), or the link's rate, of the
        wanted sign), 0 elsewhere."""
        if self.stroke is None:
            return v
        axis, sign = self.stroke
        rate = omega if axis == 2 else velocity[axis]
        return np.where(sign * rate > 0, v, 0.0)

    def fields(self, sc: Scales) -> dict:
        """The law's fields as the file writes them (file units of ``sc``): what :func:`parse` reads back."""
        out = {}
        if self.constant is not None:
            out["magnitude"] = self.constant
        elif self.expression is not None:
            out["magnitude"] = self.expression
        else:
            x, y = self.table
            xs = np.degrees(x) if self.crank else np.asarray(x) / sc.length
            out["table"] = [[float(a), float(b)] for a, b in zip(xs, y)]
        if self.active is not None:
            lo, hi = self.active
            out["active"] = (f"{math.degrees(lo)!r}deg:{math.degrees(hi)!r}deg" if self.crank
                             else f"{lo / sc.length!r}:{hi / sc.length!r}")
        if self.stroke is not None:
            out["stroke"] = next(k for k, v in STROKES.items() if v == self.stroke)
        return out

    def reads(self) -> frozenset:
        """The names its expression reads (none for a constant or a table)."""
        return frozenset(expr.names_in(self.expression)) if self.expression is not None else frozenset()

    def not_constant(self) -> str | None:
        """Why the law is no constant always on (a MuJoCo constant actuator cannot hold it), or None."""
        if self.expression is not None:
            return f"its magnitude {self.expression!r} follows the motion"
        if self.table is not None:
            return "its magnitude is a table over the input"
        if self.active is not None or self.stroke is not None:
            return "it acts over part of the cycle only (active/stroke)"
        return None

    def record(self) -> dict:
        out = {}
        if self.constant is not None:
            out["magnitude"] = self.constant
        elif self.expression is not None:
            out["magnitude"] = self.expression
        else:
            out["table"] = len(self.table[0])
        return out


def evaluate(text: str, values: dict):
    """An expression of arrays (numpy): the file's one evaluator (:func:`analytic.format.expr.evaluate_array`,
    the same parse and closures as the file's values), refused where it is not finite at some sample."""
    names = ", ".join(k for k in values if k != "t")
    out = expr.evaluate_array(text, values, unknown=lambda name: f"{text!r} uses {name!r}, which is neither an "
                              f"input, t nor a parameter (inputs: {names})")
    if not np.all(np.isfinite(out)):
        raise ValueError(f"{text!r} is not finite at every sample (a division by zero or a root of a negative); "
                         f"write it finite over the whole motion")
    return out


def parse(item: dict, where: str, sc: Scales, unit: float, required: bool = True, stroke_ok=True) -> Law:
    """The law of a load's fields ``magnitude`` / ``table`` / ``active`` / ``stroke``."""
    inputs = sc.input_names
    crank = not inputs or kinds.get(inputs[0][2]).angular          # an angle: a crank's turn
    has_m, has_t = "magnitude" in item, "table" in item
    if has_m == has_t:
        if not required and not has_m:
            return None
        raise sc.fail(where, "give either magnitude = (a number or an expression of the inputs and t) or "
                             "table = \"file.csv\" (rows: input, value)")
    active = stroke = None
    if "active" in item:
        active = _range(item["active"], f"{where}.active", sc, crank)
    if "stroke" in item:
        if not stroke_ok or item["stroke"] not in STROKES or (item["stroke"] in ("+", "-")) != (stroke_ok == "turn"):
            allowed = "\"+\" or \"-\" (the link's turning)" if stroke_ok == "turn" else "\"+x\", \"-x\", \"+y\" or \"-y\""
            raise sc.fail(f"{where}.stroke", f"{item['stroke']!r}: use {allowed}")
        stroke = STROKES[item["stroke"]]
    if has_t:
        x, y = _table(item["table"], f"{where}.table", sc, crank)
        return Law(unit, table=(x, y), periodic=crank, active=active, stroke=stroke, crank=crank)
    m = item["magnitude"]
    if isinstance(m, str) and expr.quantity(m) is None:
        try:
            names = expr.names_in(m)
        except ValueError as exc:
            raise sc.fail(f"{where}.magnitude", str(exc)) from None
        known = set(sc.parameters) | {"t"} | {n for q, qd, _ in inputs for n in (q, qd)}
        for k, (_, _, kind) in enumerate(inputs, 1):
            known |= {f"{c}{k}" for c in kinds.get(kind).columns[:2]}
        unknown = sorted(names - known)
        if unknown:
            raise sc.fail(f"{where}.magnitude", f"{unknown[0]!r} is neither an input ({', '.join(sorted(known - set(sc.parameters)))}), "
                                                f"t nor a parameter")
        if not (names - set(sc.parameters)):
            return Law(unit, constant=sc.number(m, f"{where}.magnitude"), active=active, stroke=stroke, crank=crank)
        return Law(unit, expression=m, active=active, stroke=stroke, crank=crank)
    return Law(unit, constant=sc.number(m, f"{where}.magnitude"), active=active, stroke=stroke, crank=crank)


def _range(text, where, sc: Scales, crank: bool):
    if not isinstance(text, str) or ":" not in text:
        raise sc.fail(where, f"{text!r} must be \"LO:HI\" of the first input (e.g. \"120deg:240deg\")")
    lo, hi = text.split(":", 1)
    a = sc.number(lo.strip(), where, angle=None if crank else False)
    b = sc.number(hi.strip(), where, angle=None if crank else False)
    if not crank:
        a, b = a * sc.length, b * sc.length
    if not b > a:
        raise sc.fail(where, f"{text!r}: HI must exceed LO")
    if crank and b - a > 2 * math.pi + 1e-12:
        raise sc.fail(where, f"{text!r} spans more than a turn")
    return a, b


def table_path(value: str, folder: str) -> Path:
    """The file a load's ``table = "file.csv"`` names: relative to the mechanism file's folder."""
    path = Path(value)
    return path if path.is_absolute() else Path(folder) / path


def table_files(definition) -> tuple[Path, ...]:
    """The table files a definition's ``[[loads]]`` read (inputs of every command that loads it)."""
    source = definition.source
    folder = str(Path(source).parent) if source and not source.startswith("<") else "."
    return tuple(table_path(item["table"], folder) for item in definition.loads or ()
                 if isinstance(item, dict) and isinstance(item.get("table"), str))


def _cut(text: str, limit: int = 60) -> str:
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _table_text(path: Path, value: str, where: str, sc: Scales) -> str:
    """The UTF-8 text of a table file: a regular file of at most MAX_TABLE_BYTES (a pipe or a device such as
    /dev/zero would block or never end; refused before reading)."""
    try:
        st = os.stat(path)
        if not stat.S_ISREG(st.st_mode):
            raise sc.fail(where, f"{value} is not a regular file (a pipe or a device); give a CSV file")
        if st.st_size > MAX_TABLE_BYTES:
            raise sc.fail(where, f"{value} is over {MAX_TABLE_BYTES // (1024 * 1024)} MB; a table is at most that "
                                 f"({MAX_ROWS} rows)")
        with open(path, "rb") as fh:
            raw = fh.read(MAX_TABLE_BYTES + 1)
    except OSError as exc:
        raise sc.fail(where, f"cannot read {value} ({exc.strerror or exc})") from None
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise sc.fail(where, f"{value} is not UTF-8 text (byte 0x{raw[exc.start]:02x} at offset {exc.start}); "
                             f"save it as UTF-8") from None


def _table(value, where, sc: Scales, crank: bool):
    """(x, y) of a table: inline rows [[input, value], ...] or a CSV file (relative to the mechanism file's
    folder) of such rows, a header row allowed; the input in degrees (a crank) or file units (a slider)."""
    rows = []
    if isinstance(value, str):
        reader = csv.reader(io.StringIO(_table_text(table_path(value, sc.folder), value, where, sc), newline=""))
        try:
            for k, row in enumerate(reader, 1):
                if k > MAX_ROWS:
                    raise sc.fail(where, f"{value}: more than {MAX_ROWS} rows")
                if not row or not "".join(row).strip():
                    continue
                try:
                    rows.append((float(row[0]), float(row[1])))
                except (ValueError, IndexError):
                    if rows or k > 1:
                        raise sc.fail(where, f"{value} row {k}: {_cut(','.join(row))!r} is not two numbers "
                                             f"(input, value)") from None
        except csv.Error as exc:
            raise sc.fail(where, f"{value} line {reader.line_num}: not a CSV row ({exc}); give numbers separated "
                                 f"by commas") from None
    elif isinstance(value, list):
        for k, row in enumerate(value, 1):
            if not (isinstance(row, list) and len(row) == 2):
                raise sc.fail(where, f"row {k}: {row!r} must be [input, value]")
            rows.append((sc.number(row[0], f"{where}[{k}]"), sc.number(row[1], f"{where}[{k}]")))
    else:
        raise sc.fail(where, "give a CSV file name or rows [[input, value], ...]")
    if len(rows) < 2:
        raise sc.fail(where, "needs at least two rows (input, value)")
    x = np.array([r[0] for r in rows])
    y = np.array([r[1] for r in rows])
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise sc.fail(where, "every input and value must be finite")
    if np.any(np.diff(x) <= 0):
        k = int(np.argmax(np.diff(x) <= 0)) + 2
        raise sc.fail(where, f"row {k}: the inputs must increase")
    if crank:
        x = np.radians(x)
        if x[-1] - x[0] > 2 * math.pi + 1e-9:
            raise sc.fail(where, "a crank's table spans at most 360 deg (it repeats every turn)")
        if x[-1] - x[0] > 2 * math.pi - 1e-9:          # the 360 deg row repeats the 0 deg one
            x, y = x[:-1], y[:-1]
    else:
        x = x * sc.length
    return x, y
