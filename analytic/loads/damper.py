"""``kind = "damper"``: viscous, between two ends (a force ``damping x dL/dt`` along the line, resisting the
change of length) or at a pin (``joint``, ``links``: a moment ``-damping (omega1 - omega0)`` on links[1]).
It dissipates damping (dL/dt)^2 (or damping (omega1 - omega0)^2)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.loads import spring as S
from analytic.loads import torsion_spring as TS
from analytic.loads.base import Field, LineTendon, Load, LoadKind, PinTendon, between_drawing, ends_table, pin_drawing
from analytic.loads.common import Application, Scales


@dataclass(frozen=True)
class Damper(Load):
    name: str
    damping: float
    """[N s/m] between ends; [N m s/rad] at a pin"""
    ends: tuple | None = None
    joint: str | None = None
    links: tuple | None = None
    kind: str = "damper"

    speed_linear = True

    @property
    def link(self) -> str:
        return self.ends[1].link if self.ends else self.links[1]

    def rate(self, state):
        """dL/dt [m/s] (between ends) or omega1 - omega0 [rad/s] (at a pin)."""
        if self.ends is None:
            return state.omega(self.links[1]) - state.omega(self.links[0])
        (x1, y1), (x2, y2), length, ex, ey = S.geometry(self.ends, state)
        v1, v2 = state.velocity(self.ends[0]), state.velocity(self.ends[1])
        return (v2[0] - v1[0]) * ex + (v2[1] - v1[1]) * ey

    def applications(self, state, variables=None) -> list[Application]:
        r = self.rate(state)
        if self.ends is None:
            m = -self.damping * r
            z = np.zeros(state.n)
            return [Application(self.links[1], z, z, z, z, m), Application(self.links[0], z, z, z, z, -m)]
        (x1, y1), (x2, y2), _, ex, ey = S.geometry(self.ends, state)
        T = self.damping * r
        return [Application(self.ends[0].link, T * ex, T * ey, x1, y1),
                Application(self.ends[1].link, -T * ex, -T * ey, x2, y2)]

    def dissipation(self, state):
        """The power it dissipates [W] (>= 0)."""
        r = self.rate(state)
        return self.damping * r * r

    def mujoco(self):
        if self.ends is not None:
            return LineTendon(self.ends, damping=self.damping)
        return PinTendon(self.links, damping=self.damping)

    def drawing(self, state, apps) -> dict:
        if self.ends is not None:
            return between_drawing(self, state, apps, "dashpot")
        return pin_drawing(self, state, apps, "dashpot")

    def file_table(self, sc) -> dict:
        out = {"name": self.name, "kind": self.kind}
        if self.ends is not None:
            return {**out, "between": ends_table(self, sc), "damping": self.damping * sc.length / sc.force}
        return {**out, "joint": self.joint, "links": list(self.links),
                "damping": self.damping / (sc.force * sc.length)}

    def record(self, scale: float) -> dict:
        out = {"name": self.name, "kind": self.kind, "link": self.link}
        if self.ends:
            out.update(self.ends[1].record(scale))
            out["between"] = [[e.link, e.record(scale).get("point") or e.record(scale)["at"]] for e in self.ends]
        else:
            out.update({"point": self.joint, "links": list(self.links)})
        return out


def parse(item: dict, where: str, sc: Scales) -> Damper:
    if "damping" not in item:
        raise sc.fail(f"{where}.damping", "give the damping (force per speed, or moment per angular speed)")
    if ("between" in item) == ("joint" in item):
        raise sc.fail(where, "give either between = [[LINK, POINT], [LINK, POINT]] or joint and links (at a pin)")
    c = sc.number(item["damping"], f"{where}.damping")
    if not c >= 0:
        raise sc.fail(f"{where}.damping", "must be >= 0")
    if "between" in item:
        return Damper(item["name"], c * sc.force / sc.length, ends=S.ends(sc, item, where))
    j, ls = TS.pin(sc, item, where)
    return Damper(item["name"], c * sc.force * sc.length, joint=j, links=ls)


KIND = LoadKind("damper", (S.BETWEEN, TS.JOINT, TS.LINKS,
                           Field("damping", "number", "damping", "force per speed (at a pin: moment per angular speed)")),
                parse, "viscous, between two ends or at a pin")
FIELDS = KIND.field_names

__all__ = ["Damper", "KIND", "parse", "FIELDS"]
