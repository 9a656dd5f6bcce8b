"""``kind = "pressure"``: a pressure (a table or expression, force per file length unit squared) times an
area, pushing a block or piston along ``direction`` at its pin (or at ``point``/``at``): an indicator
diagram."""

from __future__ import annotations

from dataclasses import dataclass

from analytic.loads import force as Fo
from analytic.loads import law as L
from analytic.loads.base import Field, LoadKind
from analytic.loads.common import Application, Scales, end


@dataclass(frozen=True)
class Pressure(Fo.Force):
    area: float = 0.0
    """[m^2]"""
    kind: str = "pressure"

    def applications(self, state, variables) -> list[Application]:
        return [Application(a.link, a.fx * self.area, a.fy * self.area, a.px, a.py)
                for a in super().applications(state, variables)]

    @property
    def area_factor(self) -> float:
        return self.area

    def file_table(self, sc) -> dict:
        return {**super().file_table(sc), "area": self.area / sc.length ** 2}

    def record(self, scale: float) -> dict:
        return {**super().record(scale), "area": self.area / scale ** 2}


def parse(item: dict, where: str, sc: Scales) -> Pressure:
    link = sc.link(item.get("link"), f"{where}.link")
    topo = sc.topology
    if "point" not in item and "at" not in item:
        item = {**item, "point": topo.links[link].origin}
    e = end(sc, link, item.get("point"), item.get("at"), where)
    u, turning = Fo.direction(sc, item, where)
    if "area" not in item:
        raise sc.fail(f"{where}.area", "give the area the pressure acts on (file length unit squared)")
    area = sc.number(item["area"], f"{where}.area")
    if not area > 0:
        raise sc.fail(f"{where}.area", f"{area:g} must be > 0")
    law = L.parse(item, where, sc, sc.force / sc.length ** 2)
    return Pressure(item["name"], e, u, turning, law, area=area * sc.length ** 2)


KIND = LoadKind("pressure", Fo.PLACE + (Field("area", "number", "area", "file units squared"),)
                + L.editor_fields("force per area"), parse,
                "a pressure times an area pushing a block or piston (an indicator diagram)")
FIELDS = KIND.field_names

__all__ = ["Pressure", "KIND", "parse", "FIELDS"]
