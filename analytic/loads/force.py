"""``kind = "force"``: a force at a point of a link, its direction fixed in the world or turning with the
link, its magnitude a :class:`~analytic.loads.law.Law`."""

from __future__ import annotations

import math
from dataclasses import dataclass

from analytic.loads import law as L
from analytic.loads.base import ConstantActuator, Field, Load, LoadKind
from analytic.loads.common import Application, End, Scales, end

PLACE = (Field("link", "text", "link", "the link it acts on"),
         Field("point", "point", "point or u,v", "a point's name, or u,v in the link's frame (file units)"),
         Field("direction", "pair", "direction", "x,y e.g. 0,-1"),
         Field("frame", "frame", "frame", "world (fixed), or link (turns with it)"))


@dataclass(frozen=True)
class Force(Load):
    name: str
    end: End
    direction: tuple
    """Unit vector (world frame, or the link's when ``turning``)."""
    turning: bool
    law: L.Law
    kind: str = "force"

    @property
    def link(self) -> str:
        return self.end.link

    def applications(self, state, variables) -> list[Application]:
        px, py = state.position(self.end)
        ux, uy = self.direction
        if self.turning:
            _, _, c, s, _ = state.frame(self.end.link)
            ux, uy = ux * c - uy * s, ux * s + uy * c
        v = self.law.value(state, variables)
        if self.law.stroke is not None:
            v = self.law.gate(v, state.velocity(self.end), state.omega(self.end.link))
        return [Application(self.end.link, v * ux, v * uy, px, py)]

    def rates_read(self) -> frozenset:
        return self.law.reads()

    def mujoco(self):
        """A constant-force actuator where the law is a constant always on; else why not."""
        law = self.law
        return law.not_constant() or ConstantActuator(self.end.link, self.end, self.direction, not self.turning,
                                float(law.constant * law.unit) * self.area_factor)

    area_factor = 1.0
    """What the law's value is multiplied by to give the force [m^2 for a pressure]."""

    def place_fields(self, sc) -> dict:
        e = self.end
        where = {"point": e.point} if e.point else {"at": [e.u / sc.length, e.v / sc.length]}
        return {"link": e.link, **where, "direction": list(self.direction),
                **({"frame": "link"} if self.turning else {})}

    def file_table(self, sc) -> dict:
        return {"name": self.name, "kind": self.kind, **self.place_fields(sc), **self.law.fields(sc)}

    def record(self, scale: float) -> dict:
        return {"name": self.name, "kind": self.kind, "link": self.end.link, **self.end.record(scale),
                "direction": list(self.direction), "frame": "link" if self.turning else "world", **self.law.record()}


def direction(sc: Scales, item: dict, where: str, default=None) -> tuple[tuple, bool]:
    d = item.get("direction", default)
    if d is None:
        raise sc.fail(f"{where}.direction", "give the force's direction [x, y] (a unit vector, or any length)")
    dx, dy = sc.pair(d, f"{where}.direction")
    n = math.hypot(dx, dy)
    if not n > 0:
        raise sc.fail(f"{where}.direction", "must not be [0, 0]")
    frame = item.get("frame", "world")
    if frame not in ("world", "link"):
        raise sc.fail(f"{where}.frame", f"{frame!r}: use \"world\" or \"link\"")
    return (dx / n, dy / n), frame == "link"


def parse(item: dict, where: str, sc: Scales) -> Force:
    link = sc.link(item.get("link"), f"{where}.link")
    e = end(sc, link, item.get("point"), item.get("at"), where)
    (ux, uy), turning = direction(sc, item, where)
    return Force(item["name"], e, (ux, uy), turning, L.parse(item, where, sc, sc.force))


def constant(name: str, link: str, point: str, fx: float, fy: float, crank: bool = True) -> Force:
    """A constant world-frame force (fx, fy) [N] at a named point (the command line's ``--force``)."""
    mag = math.hypot(fx, fy)
    u = (fx / mag, fy / mag) if mag > 0 else (1.0, 0.0)
    return Force(name, End(link, math.nan, math.nan, point), u, False, L.Law(1.0, constant=mag, crank=crank))


KIND = LoadKind("force", PLACE + L.editor_fields(), parse, "a force at a point of a link, its magnitude a law")
FIELDS = KIND.field_names

__all__ = ["Force", "KIND", "parse", "constant", "direction", "FIELDS", "PLACE"]
