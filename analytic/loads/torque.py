"""``kind = "torque"``: a couple on a link (+ counter-clockwise), its value a :class:`~analytic.loads.law.Law`
(moment units: the file's force unit times its length unit)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.loads import law as L
from analytic.loads.base import ConstantActuator, Field, Load, LoadKind
from analytic.loads.common import Application, Scales


@dataclass(frozen=True)
class Torque(Load):
    name: str
    link: str
    law: L.Law
    kind: str = "torque"

    def applications(self, state, variables) -> list[Application]:
        v = self.law.value(state, variables)
        v = self.law.gate(v, None, state.omega(self.link))
        z = np.zeros(state.n)
        return [Application(self.link, z, z, z, z, v)]

    def rates_read(self) -> frozenset:
        return self.law.reads()

    def mujoco(self):
        law = self.law
        return law.not_constant() or ConstantActuator(self.link, None, (0.0, 0.0), True, float(law.constant * law.unit))

    def drawing(self, state, apps) -> dict:
        """The link's centre (its points' mean) and the couple."""
        from analytic.kinds import GROUND
        n = state.n
        pts = state.mech.definition.topology.links[self.link].points if self.link != GROUND else ()
        x = np.mean([state.xy(p)[0] for p in pts], axis=0) if pts else np.zeros(n)
        y = np.mean([state.xy(p)[1] for p in pts], axis=0) if pts else np.zeros(n)
        return {"shape": "moment", "symbol": "arc", "quantity": "moment", "x": x, "y": y, "value": apps[0].couple}

    def file_table(self, sc) -> dict:
        return {"name": self.name, "kind": self.kind, "link": self.link, **self.law.fields(sc)}

    def record(self, scale: float) -> dict:
        return {"name": self.name, "kind": self.kind, "link": self.link, "point": None, **self.law.record()}


def parse(item: dict, where: str, sc: Scales) -> Torque:
    link = sc.link(item.get("link"), f"{where}.link")
    return Torque(item["name"], link, L.parse(item, where, sc, sc.force * sc.length, stroke_ok="turn"))


def constant(name: str, link: str, value: float) -> Torque:
    """A constant couple [N m] (the command line's ``--torque``)."""
    return Torque(name, link, L.Law(1.0, constant=float(value)))


KIND = LoadKind("torque", (Field("link", "text", "link", "the link it turns"),)
                + L.editor_fields("force unit x length unit; + counter-clockwise", turning=True), parse,
                "a couple on a link (+ counter-clockwise), its value a law")
FIELDS = KIND.field_names

__all__ = ["Torque", "KIND", "parse", "constant", "FIELDS"]
