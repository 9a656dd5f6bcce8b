"""``kind = "spring"``: a spring between two ends (each on a link or the ground). Its tension T (positive
pulling the ends together) is ``stiffness (L - free_length)``; or ``preload`` (the tension at the start
pose, t = 0) in place of ``free_length``; or a ``table`` of length -> tension (file units, interpolated
linearly, held constant in slope beyond its ends). Its energy is the integral of T over the length, exactly
(quadratic per table segment)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.loads.common import Application, End, Scales, end

FIELDS = {"name", "kind", "between", "stiffness", "free_length", "preload", "table"}


@dataclass(frozen=True)
class Spring:
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

    def geometry(self, state):
        (x1, y1), (x2, y2) = state.position(self.ends[0]), state.position(self.ends[1])
        dx, dy = x2 - x1, y2 - y1
        length = np.hypot(dx, dy)
        with np.errstate(invalid="ignore", divide="ignore"):
            ex, ey = dx / length, dy / length
        return (x1, y1), (x2, y2), length, ex, ey

    def rest(self, state=None) -> float:
        """The free length [m] (a preload's is set from the start pose by :func:`analytic.loads.resolve`)."""
        if self.free_length is None:
            raise RuntimeError(f"spring {self.name}: its free length was not set from its preload")
        return self.free_length

    def at_start(self, length0: float) -> "Spring":
        """The spring with its free length fixed from its preload and its length at the start pose [m]."""
        if self.free_length is not None or self.table is not None:
            return self
        from dataclasses import replace
        return replace(self, free_length=length0 - self.preload / self.stiffness)

    def tension(self, length, state):
        if self.table is not None:
            x, y = self.table
            slope_lo = (y[1] - y[0]) / (x[1] - x[0])
            slope_hi = (y[-1] - y[-2]) / (x[-1] - x[-2])
            return np.where(length < x[0], y[0] + slope_lo * (length - x[0]),
                            np.where(length > x[-1], y[-1] + slope_hi * (length - x[-1]), np.interp(length, x, y)))
        return self.stiffness * (length - self.rest(state))

    def applications(self, state, variables=None) -> list[Application]:
        (x1, y1), (x2, y2), length, ex, ey = self.geometry(state)
        T = self.tension(length, state)
        return [Application(self.ends[0].link, T * ex, T * ey, x1, y1),
                Application(self.ends[1].link, -T * ex, -T * ey, x2, y2)]

    def energy(self, state) -> np.ndarray:
        """The spring's stored energy [J] (0 at its free length; a table's: from its first row's length)."""
        _, _, length, _, _ = self.geometry(state)
        if self.table is None:
            return 0.5 * self.stiffness * (length - self.rest(state)) ** 2
        x, y = self.table
        cum = np.concatenate([[0.0], np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(x))])
        k = np.clip(np.searchsorted(x, length) - 1, 0, len(x) - 2)
        x0, y0 = x[k], y[k]
        slope = (y[k + 1] - y[k]) / (x[k + 1] - x[k])
        d = length - x0
        return cum[k] + y0 * d + 0.5 * slope * d * d

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


__all__ = ["Spring", "parse", "ends", "FIELDS"]
