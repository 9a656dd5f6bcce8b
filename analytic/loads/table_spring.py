"""``kind = "table_spring"``: a non-linear spring between two ends given by its force-deflection table: rows
(deflection, force), the deflection L - free_length (file length unit, + stretched), the force its tension
(force unit, + pulling the ends together), inline rows or a CSV file; interpolated linearly, continued with
the end rows' slopes beyond them. Its energy is the integral of the tension over the deflection from 0,
exact (quadratic per row)."""

from __future__ import annotations

from dataclasses import dataclass

from analytic.loads import spring as S
from analytic.loads.base import Field, Load, LoadKind, between_drawing, ends_table
from analytic.loads.common import Scales


@dataclass(frozen=True)
class TableSpring(Load):
    name: str
    ends: tuple
    free_length: float
    """[m]"""
    rows: tuple
    """(deflections [m], tensions [N])"""
    kind: str = "table_spring"

    @property
    def link(self) -> str:
        return self.ends[1].link

    def deflection(self, state):
        return S.geometry(self.ends, state)[2] - self.free_length

    def applications(self, state, variables=None) -> list:
        return S.line_applications(self.ends, state, S.table_value(*self.rows, self.deflection(state)))

    def energy(self, state):
        x, y = self.rows
        return S.table_integral(x, y, self.deflection(state)) - S.table_integral(x, y, 0.0)

    def mujoco(self):
        return "a force-deflection table (MuJoCo's tendons are linear)"

    def drawing(self, state, apps) -> dict:
        return between_drawing(self, state, apps, "zigzag")

    def file_table(self, sc) -> dict:
        x, y = self.rows
        return {"name": self.name, "kind": self.kind, "between": ends_table(self, sc),
                "free_length": self.free_length / sc.length,
                "table": [[float(a / sc.length), float(b / sc.force)] for a, b in zip(x, y)]}

    def record(self, scale: float) -> dict:
        return {"name": self.name, "kind": self.kind, "link": self.ends[1].link, **self.ends[1].record(scale),
                "between": [[e.link, e.record(scale).get("point") or e.record(scale)["at"]] for e in self.ends]}


def parse(item: dict, where: str, sc: Scales) -> TableSpring:
    from analytic.loads.law import _table
    e = S.ends(sc, item, where)
    if "free_length" not in item:
        raise sc.fail(f"{where}.free_length", "give the free length (file length unit): the deflection is measured "
                                              "from it")
    L0 = sc.number(item["free_length"], f"{where}.free_length") * sc.length
    if not L0 >= 0:
        raise sc.fail(f"{where}.free_length", "must be >= 0")
    if "table" not in item:
        raise sc.fail(f"{where}.table", "give the rows [[deflection, force], ...] or a CSV file of them")
    x, y = _table(item["table"], f"{where}.table", sc, crank=False)
    return TableSpring(item["name"], e, L0, (x, y * sc.force))


KIND = LoadKind("table_spring", (S.BETWEEN, Field("free_length", "number", "free length", "file units"),
                                 Field("table", "table", "table", "rows deflection,force separated by ';' "
                                                                  "(+ stretched, + pulling the ends together)")),
                parse, "a non-linear spring between two ends: a force-deflection table")

__all__ = ["TableSpring", "KIND", "parse"]
