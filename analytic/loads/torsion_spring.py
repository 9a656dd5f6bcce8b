"""``kind = "torsion_spring"``: a spring at a pin between two links. Its angle is theta = phi(links[1]) -
phi(links[0]) - free_angle (taken in (-180, 180] deg at the first sample, continuous after it), its moment on
links[1] is -stiffness theta (and the opposite on links[0]); its energy stiffness theta^2 / 2."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.kinds import GROUND
from analytic.loads.base import Field, Load, LoadKind, PinTendon, pin_drawing
from analytic.loads.common import Application, Scales

JOINT = Field("joint", "text", "joint", "a pin's point")
LINKS = Field("links", "links", "links", "the two links the pin joins, e.g. 2,3")


@dataclass(frozen=True)
class TorsionSpring(Load):
    name: str
    joint: str
    links: tuple
    stiffness: float
    """[N m / rad]"""
    free_angle: float
    kind: str = "torsion_spring"

    @property
    def link(self) -> str:
        return self.links[1]

    def angle(self, state):
        """theta [rad]: in (-pi, pi] at the first sample, followed continuously over the samples after it (a
        spring wound by a full turn keeps its winding)."""
        d = np.unwrap(np.atleast_1d(state.angle(self.links[1]) - state.angle(self.links[0]) - self.free_angle))
        first = np.pi - np.mod(np.pi - d[0], 2 * np.pi)
        return first + (d - d[0])

    def applications(self, state, variables=None) -> list[Application]:
        m = -self.stiffness * self.angle(state)
        z = np.zeros(state.n)
        return [Application(self.links[1], z, z, z, z, m), Application(self.links[0], z, z, z, z, -m)]

    def energy(self, state):
        return 0.5 * self.stiffness * self.angle(state) ** 2

    def mujoco(self):
        return PinTendon(self.links, stiffness=self.stiffness, free_angle=self.free_angle)

    def drawing(self, state, apps) -> dict:
        return pin_drawing(self, state, apps, "arc")

    def file_table(self, sc) -> dict:
        return {"name": self.name, "kind": self.kind, "joint": self.joint, "links": list(self.links),
                "stiffness": self.stiffness / (sc.force * sc.length), "free_angle": self.free_angle}

    def record(self, scale: float) -> dict:
        return {"name": self.name, "kind": self.kind, "link": self.links[1], "point": self.joint,
                "links": list(self.links)}


def pin(sc: Scales, item: dict, where: str) -> tuple[str, tuple]:
    """The joint point and its two links, checked: both links carry the point."""
    j = item.get("joint")
    links = item.get("links")
    if not isinstance(j, str):
        raise sc.fail(f"{where}.joint", "give the pin's point name")
    if not (isinstance(links, list) and len(links) == 2):
        raise sc.fail(f"{where}.links", "give the two links the pin joins [LINK0, LINK1]")
    ls = tuple(sc.link(x, f"{where}.links", ground=True) for x in links)
    topo = sc.topology
    for ln in ls:
        members = topo.ground if ln == GROUND else topo.links[ln].points
        if j not in members:
            raise sc.fail(f"{where}.joint", f"{j!r} is not a point of link {ln}")
    if ls[0] == ls[1]:
        raise sc.fail(f"{where}.links", "the two links must differ")
    return j, ls


def parse(item: dict, where: str, sc: Scales) -> TorsionSpring:
    j, ls = pin(sc, item, where)
    if "stiffness" not in item:
        raise sc.fail(f"{where}.stiffness", "give the stiffness (moment per radian, file units)")
    k = sc.number(item["stiffness"], f"{where}.stiffness") * sc.force * sc.length
    if not k >= 0:
        raise sc.fail(f"{where}.stiffness", "must be >= 0")
    a = sc.number(item.get("free_angle", 0.0), f"{where}.free_angle", angle=None)
    return TorsionSpring(item["name"], j, ls, k, a)


KIND = LoadKind("torsion_spring", (JOINT, LINKS, Field("stiffness", "number", "stiffness", "moment per radian"),
                                   Field("free_angle", "number", "free angle", "e.g. 90deg")),
                parse, "a spring at a pin between its two links")
FIELDS = KIND.field_names

__all__ = ["TorsionSpring", "KIND", "parse", "pin", "FIELDS", "JOINT", "LINKS"]
