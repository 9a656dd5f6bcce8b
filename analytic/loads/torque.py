"""``kind = "torque"``: a couple on a link (+ counter-clockwise), its value a :class:`~analytic.loads.law.Law`
(moment units: the file's force unit times its length unit)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.loads import law as L
from analytic.loads.common import Application, Scales

FIELDS = {"name", "kind", "link"} | set(L.LAW_FIELDS)


@dataclass(frozen=True)
class Torque:
    name: str
    link: str
    law: L.Law
    kind: str = "torque"

    def applications(self, state, variables) -> list[Application]:
        v = self.law.value(state, variables)
        v = self.law.gate(v, None, state.omega(self.link))
        z = np.zeros(state.n)
        return [Application(self.link, z, z, z, z, v)]

    def record(self, scale: float) -> dict:
        return {"name": self.name, "kind": self.kind, "link": self.link, "point": None, **self.law.record()}


def parse(item: dict, where: str, sc: Scales) -> Torque:
    link = sc.link(item.get("link"), f"{where}.link")
    return Torque(item["name"], link, L.parse(item, where, sc, sc.force * sc.length, stroke_ok="turn"))


def constant(name: str, link: str, value: float) -> Torque:
    """A constant couple [N m] (the command line's ``--torque``)."""
    return Torque(name, link, L.Law(1.0, constant=float(value)))


__all__ = ["Torque", "parse", "constant", "FIELDS"]
