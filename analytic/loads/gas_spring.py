"""``kind = "gas_spring"``: a gas strut between two ends (a press's cushion, a hatch's lift), SPEC "Gas
springs". At compression x = extended_length - L (0 <= x <= stroke; outside it the motion is refused) it
pushes its ends apart with the polytropic law of its gas, p V^n constant over a volume V = V0 (1 - a x /
stroke) that falls linearly with x:

    F(x) = force (1 - a x / stroke)^(-n),   a = 1 - ratio^(-1/n)

so F(0) = ``force`` (F1, fully extended) and F(stroke) = ratio x F1. Its energy is the integral of F over x,
in closed form: with u = a x / stroke and w = 1 - u,

    E(x) = F1 stroke / a (w^(1-n) - 1) / (n - 1)    (n != 1),    F1 stroke / a (-ln w)    (n = 1),

written as F1 x (-ln(1 - u) / u) expm1(z) / z with z = (1 - n) ln(1 - u), exact at n = 1 and ratio = 1 (a = 0:
E = F1 x) with no cancellation near them."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.loads import spring as S
from analytic.loads.base import Field, Load, LoadKind, between_drawing, ends_table
from analytic.loads.common import LoadError, Scales

SLACK = 1e-9
"""[of the stroke] How far past its ends a motion may take the strut before it is refused: the rounding of a
pose solved to 1e-12 of the mechanism's size."""


def _phi(z):
    """expm1(z) / z, 1 at z = 0."""
    z = np.asarray(z, dtype=float)
    small = np.abs(z) < 1e-8
    safe = np.where(small, 1.0, z)
    return np.where(small, 1.0 + 0.5 * z, np.expm1(safe) / safe)


def _log_ratio(u):
    """-ln(1 - u) / u, 1 at u = 0."""
    u = np.asarray(u, dtype=float)
    small = np.abs(u) < 1e-8
    safe = np.where(small, 0.5, u)
    return np.where(small, 1.0 + 0.5 * u, -np.log1p(-safe) / safe)


@dataclass(frozen=True)
class GasSpring(Load):
    name: str
    ends: tuple
    extended_length: float
    """[m] pin to pin, fully extended"""
    stroke: float
    """[m]"""
    force: float
    """[N] the push at full extension, F1"""
    ratio: float = 1.3
    n: float = 1.0
    kind: str = "gas_spring"

    @property
    def link(self) -> str:
        return self.ends[1].link

    needs_start = True
    """Checked at the start pose: a strut that does not fit its ends there is refused when the file's loads
    are resolved (the panel's edit, every command), before any motion."""

    def at_start(self, state) -> "GasSpring":
        self.compression(state)
        return self

    @property
    def a(self) -> float:
        """The share of the volume the full stroke takes: 1 - ratio^(-1/n)."""
        return -float(np.expm1(-np.log(self.ratio) / self.n))

    def compression(self, state):
        """x = extended_length - L [m] over the samples; a :class:`LoadError` where the motion takes it
        outside [0, stroke]."""
        x = self.extended_length - S.geometry(self.ends, state)[2]
        lo, hi = float(np.min(x)), float(np.max(x))
        if lo < -SLACK * self.stroke or hi > self.stroke * (1 + SLACK):
            raise LoadError(f"load {self.name}: the motion takes the gas spring to a compression of "
                            f"{(lo if lo < 0 else hi) * 1e3:.4g} mm, outside 0 to its stroke {self.stroke * 1e3:.4g} mm; "
                            f"move its ends or change extended_length and stroke")
        return np.clip(x, 0.0, self.stroke)

    def push(self, x):
        """F(x) [N], pushing the ends apart."""
        return self.force * np.exp(-self.n * np.log1p(-self.a * np.asarray(x) / self.stroke))

    def stored(self, x):
        """E(x) [J]: the integral of F from 0 to x (closed form; see the module's note)."""
        x = np.asarray(x, dtype=float)
        u = self.a * x / self.stroke
        return self.force * x * _log_ratio(u) * _phi((1.0 - self.n) * np.log1p(-u))

    def applications(self, state, variables=None) -> list:
        return S.line_applications(self.ends, state, -self.push(self.compression(state)))

    def energy(self, state):
        return self.stored(self.compression(state))

    def mujoco(self):
        return "a gas spring's force is not linear in its length (MuJoCo's tendons are)"

    def drawing(self, state, apps) -> dict:
        return between_drawing(self, state, apps, "strut")

    def file_table(self, sc) -> dict:
        return {"name": self.name, "kind": self.kind, "between": ends_table(self, sc),
                "extended_length": self.extended_length / sc.length, "stroke": self.stroke / sc.length,
                "force": self.force / sc.force, "ratio": self.ratio, "n": self.n}

    def record(self, scale: float) -> dict:
        return {"name": self.name, "kind": self.kind, "link": self.ends[1].link, **self.ends[1].record(scale),
                "between": [[e.link, e.record(scale).get("point") or e.record(scale)["at"]] for e in self.ends]}


def parse(item: dict, where: str, sc: Scales) -> GasSpring:
    e = S.ends(sc, item, where)

    def value(key, unit, test, what, default=None):
        if key not in item and default is None:
            raise sc.fail(f"{where}.{key}", f"give the {what}")
        v = sc.number(item.get(key, default), f"{where}.{key}")
        if not test(v):
            raise sc.fail(f"{where}.{key}", f"{v:g}: the {what} {test.__doc__}")
        return v * unit

    def positive(v):
        """must be > 0"""
        return v > 0

    def at_least_one(v):
        """must be >= 1 (the push grows as the gas is compressed)"""
        return v >= 1

    def exponent(v):
        """must be in (0, 3] (1 isothermal, 1.4 adiabatic air)"""
        return 0 < v <= 3

    length = value("extended_length", sc.length, positive, "length pin to pin fully extended (file units)")
    stroke = value("stroke", sc.length, positive, "stroke (file units)")
    if not stroke < length:
        raise sc.fail(f"{where}.stroke", f"{stroke / sc.length:g} must be shorter than extended_length "
                                         f"{length / sc.length:g}")
    force = value("force", sc.force, positive, "push at full extension (force unit)")
    ratio = value("ratio", 1.0, at_least_one, "ratio F2/F1 of the push fully compressed to fully extended", 1.3)
    n = value("n", 1.0, exponent, "polytropic exponent", 1.0)
    return GasSpring(item["name"], e, length, stroke, force, ratio, n)


KIND = LoadKind("gas_spring", (S.BETWEEN,
                               Field("extended_length", "number", "extended length", "pin to pin, fully extended "
                                                                                      "(file units)"),
                               Field("stroke", "number", "stroke", "file units"),
                               Field("force", "number", "force", "the push fully extended, F1 (force unit)"),
                               Field("ratio", "number", "ratio", "F2/F1, fully compressed to extended (default 1.3)"),
                               Field("n", "number", "n", "polytropic exponent (default 1: isothermal)")),
                parse, "a gas strut between two ends: F = F1 (V0/V)^n over its stroke")

__all__ = ["GasSpring", "KIND", "parse"]
