"""``kind = "spring"``: a spring between two ends (each on a link or the ground). Its tension T (positive
pulling the ends together) is ``stiffness (L - free_length)``; or ``preload`` (the tension at the start
pose, t = 0) in place of ``free_length``; or a ``table`` of length -> tension (file units, interpolated
linearly, held constant in slope beyond its ends). Its energy is the integral of T over the length, exactly
(quadratic per table segment)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.loads.base import Field, LineTendon, Load, LoadKind, between_drawing, ends_table
from analytic.loads.common import Application, End, Scales, end

BETWEEN = Field("between", "between", "between", "two ends LINK:POINT or LINK:u,v separated by a space, e.g. "
                                                 "ground:S0 3:0.2,0")


def geometry(ends: tuple, state):
    """((x1, y1), (x2, y2), length, ex, ey) of the line between two ends (e the unit vector 1 -> 2)."""
    (x1, y1), (x2, y2) = state.position(ends[0]), state.position(ends[1])
    dx, dy = x2 - x1, y2 - y1
    length = np.hypot(dx, dy)
    with np.errstate(invalid="ignore", divide="ignore"):
        ex, ey = dx / length, dy / length
    return (x1, y1), (x2, y2), length, ex, ey


def line_applications(ends: tuple, state, tension) -> list[Application]:
    """A tension (+ pulling the ends together) along the line between two ends."""
    (x1, y1), (x2, y2), _, ex, ey = geometry(ends, state)
    return [Application(ends[0].link, tension * ex, tension * ey, x1, y1),
            Application(ends[1].link, -tension * ex, -tension * ey, x2, y2)]


def table_value(x, y, s):
    """The table (x, y) at ``s``: linear between rows, continued with its end segments' slopes beyond."""
    slope_lo = (y[1] - y[0]) / (x[1] - x[0])
    slope_hi = (y[-1] - y[-2]) / (x[-1] - x[-2])
    return np.where(s < x[0], y[0] + slope_lo * (s - x[0]),
                    np.where(s > x[-1], y[-1] + slope_hi * (s - x[-1]), np.interp(s, x, y)))


def table_integral(x, y, s):
    """The integral of :func:`table_value` from x[0] to ``s``: exact (quadratic per segment)."""
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(x))])
    k = np.clip(np.searchsorted(x, s) - 1, 0, len(x) - 2)
    slope = (y[k + 1] - y[k]) / (x[k + 1] - x[k])
    d = s - x[k]
    return cum[k] + y[k] * d + 0.5 * slope * d * d


@dataclass(frozen=True)
class Spring(Load):
    name: str
    ends: tuple
    stiffness: float = 0.0
    """[N/m]"""
    free_length: float | None = None
    """[m]; None with a preload: fixed from the start pose"""
    preload: float | None = None
    table: tuple | None = None
    """(lengths [m], tensions [N])"""
    kind: str = "spring"

    @property
    def link(self) -> str:
        return self.ends[1].link

    @property
    def needs_start(self) -> bool:
        return self.free_length is None and self.table is None

    def geometry(self, state):
        return geometry(self.ends, state)

    def rest(self, state=None) -> float:
        """The free length [m] (a preload's is set from the start pose by :meth:`at_start`)."""
        if self.free_length is None:
            raise RuntimeError(f"spring {self.name}: its free length was not set from its preload")
        return self.free_length

    def at_start(self, state) -> "Spring":
        """The spring with its free length fixed from its preload and its length at the start pose."""
        if not self.needs_start:
            return self
        from dataclasses import replace
        length0 = float(np.atleast_1d(geometry(self.ends, state)[2])[0])
        return replace(self, free_length=length0 - self.preload / self.stiffness)

    def tension(self, length, state=None):
        if self.table is not None:
            return table_value(*self.table, length)
        return self.stiffness * (length - self.rest(state))

    def applications(self, state, variables=None) -> list[Application]:
        return line_applications(self.ends, state, self.tension(geometry(self.ends, state)[2], state))

    def energy(self, state) -> np.ndarray:
        """The spring's stored energy [J] (0 at its free length; a table's: from its first row's length)."""
        length = geometry(self.ends, state)[2]
        if self.table is None:
            return 0.5 * self.stiffness * (length - self.rest(state)) ** 2
        return table_integral(*self.table, length)

    def mujoco(self):
        if self.table is not None:
            return "a force-length table"
        return LineTendon(self.ends, stiffness=self.stiffness, length=self.rest())

    def drawing(self, state, apps) -> dict:
        return between_drawing(self, state, apps, "zigzag")

    def file_table(self, sc) -> dict:
        out = {"name": self.name, "kind": self.kind, "between": ends_table(self, sc)}
        if self.table is not None:
            x, y = self.table
            return {**out, "table": [[float(a / sc.length), float(b / sc.force)] for a, b in zip(x, y)]}
        if self.free_length is None:
            return {**out, "stiffness": self.stiffness * sc.length / sc.force, "preload": self.preload / sc.force}
        return {**out, "stiffness": self.stiffness * sc.length / sc.force, "free_length": self.free_length / sc.length}

    def record(self, scale: float) -> dict:
        return {"name": self.name, "kind": self.kind, "link": self.ends[1].link, **self.ends[1].record(scale),
                "between": [[e.link, e.record(scale).get("point") or e.record(scale)["at"]] for e in self.ends]}


def ends(sc: Scales, item: dict, where: str) -> tuple[End, End]:
    b = item.get("between")
    if not (isinstance(b, list) and len(b) == 2 and all(isinstance(x, list) and len(x) == 2 for x in b)):
        raise sc.fail(f"{where}.between", "give two ends [[LINK, POINT or [u, v]], [LINK, POINT or [u, v]]] "
                                          "(LINK may be \"ground\")")
    out = []
    for k, (link, p) in enumerate(b):
        w = f"{where}.between[{k + 1}]"
        ln = sc.link(link, w, ground=True)
        out.append(end(sc, ln, p if isinstance(p, str) else None, None if isinstance(p, str) else p, w))
    if out[0].link == out[1].link:
        raise sc.fail(f"{where}.between", "both ends are on the same link: the spring would do nothing")
    return out[0], out[1]


def parse(item: dict, where: str, sc: Scales) -> Spring:
    e = ends(sc, item, where)
    if "table" in item:
        if any(k in item for k in ("stiffness", "free_length", "preload")):
            raise sc.fail(where, "a table (length -> tension) replaces stiffness, free_length and preload")
        from analytic.loads.law import _table
        x, y = _table(item["table"], f"{where}.table", sc, crank=False)
        return Spring(item["name"], e, table=(x, y * sc.force))
    if "stiffness" not in item:
        raise sc.fail(f"{where}.stiffness", "give the stiffness (force per length, file units), or a table")
    k = sc.number(item["stiffness"], f"{where}.stiffness") * sc.force / sc.length
    if not k >= 0:
        raise sc.fail(f"{where}.stiffness", "must be >= 0")
    if ("free_length" in item) == ("preload" in item):
        raise sc.fail(where, "give either free_length (file length unit) or preload (the tension at the start pose)")
    if "free_length" in item:
        L0 = sc.number(item["free_length"], f"{where}.free_length") * sc.length
        if not L0 >= 0:
            raise sc.fail(f"{where}.free_length", "must be >= 0")
        return Spring(item["name"], e, k, L0)
    if not k > 0:
        raise sc.fail(f"{where}.stiffness", "a preload needs a stiffness > 0")
    return Spring(item["name"], e, k, None, sc.number(item["preload"], f"{where}.preload") * sc.force)


KIND = LoadKind("spring", (BETWEEN, Field("stiffness", "number", "stiffness", "force per length"),
                           Field("free_length", "number", "free length", "file units"),
                           Field("preload", "number", "preload", "the tension at the start pose, instead of the "
                                                                 "free length"),
                           Field("table", "table", "table", "rows length,tension separated by ';' instead of "
                                                            "stiffness and free length")),
                parse, "a linear spring between two ends (or a table of length -> tension)")
FIELDS = KIND.field_names

__all__ = ["Spring", "KIND", "parse", "ends", "geometry", "line_applications", "table_value", "table_integral",
           "BETWEEN", "FIELDS"]
