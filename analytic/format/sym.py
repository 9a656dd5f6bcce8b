"""Values derived from a pose, kept both as a number and as an expression of the file's parameters.

The links-and-joints form derives every length, offset, start angle and local coordinate from the pose.
Where the pose is given in numbers, a derived value is a number; where a coordinate is a parameter or an
expression, the derived value is an expression of it (``"hypot((xC) - (xB), ...)"``), so that ``--set`` on
that parameter moves the mechanism consistently. :class:`Sym` carries both: the value at the file's
parameter values (for branches and checks) and the text (None while the value is a plain number).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from analytic.format import expr


@dataclass(frozen=True)
class Sym:
    """A derived value: ``value`` at the file's parameter values; ``text`` its expression, or None for a
    constant (then ``value`` is exact)."""

    value: float
    text: str | None = None

    # ----------------------------------------------------------------------------------- output
    def out(self):
        """What a field holds: the number, or the expression text (raises ValueError when the text is over
        the format's limits of length or depth)."""
        if self.text is None:
            return self.value
        expr.names_in(self.text)                  # the format's own checks (length, depth)
        return self.text

    @property
    def const(self) -> bool:
        return self.text is None

    def _t(self) -> str:
        if self.text is not None:
            return self.text
        return repr(self.value) if self.value >= 0 else f"({self.value!r})"

    # ------------------------------------------------------------------------------ arithmetic
    def __add__(self, o: Sym) -> Sym:
        if o.const and o.value == 0.0:
            return self
        if self.const and self.value == 0.0:
            return o
        return Sym(self.value + o.value, None if self.const and o.const else f"({self._t()} + {o._t()})")

    def __sub__(self, o: Sym) -> Sym:
        if o.const and o.value == 0.0:
            return self
        return Sym(self.value - o.value, None if self.const and o.const else f"({self._t()} - {o._t()})")

    def __mul__(self, o: Sym) -> Sym:
        for a, b in ((self, o), (o, self)):
            if a.const and a.value == 1.0:
                return b
            if a.const and a.value == 0.0:
                return Sym(0.0)
        return Sym(self.value * o.value, None if self.const and o.const else f"({self._t()} * {o._t()})")

    def __truediv__(self, o: Sym) -> Sym:
        if o.const and o.value == 1.0:
            return self
        return Sym(self.value / o.value, None if self.const and o.const else f"({self._t()} / {o._t()})")

    def __neg__(self) -> Sym:
        return Sym(-self.value, None if self.const else f"(-{self._t()})")


def const(x: float) -> Sym:
    return Sym(float(x))


def _call(name: str, fn, *args: Sym) -> Sym:
    value = float(fn(*(a.value for a in args)))
    if all(a.const for a in args):
        return Sym(value)
    return Sym(value, f"{name}({', '.join(a._t() for a in args)})")


def hypot(x: Sym, y: Sym) -> Sym:
    return _call("hypot", math.hypot, x, y)


def atan2(y: Sym, x: Sym) -> Sym:
    return _call("atan2", math.atan2, y, x)


def cos(a: Sym) -> Sym:
    return _call("cos", math.cos, a)


def sin(a: Sym) -> Sym:
    return _call("sin", math.sin, a)


# ---------------------------------------------------------------------------------- plane vectors
@dataclass(frozen=True)
class Vec:
    """A point or direction in the plane with :class:`Sym` coordinates."""

    x: Sym
    y: Sym

    def __add__(self, o: Vec) -> Vec:
        return Vec(self.x + o.x, self.y + o.y)

    def __sub__(self, o: Vec) -> Vec:
        return Vec(self.x - o.x, self.y - o.y)

    def scaled(self, k: Sym) -> Vec:
        return Vec(self.x * k, self.y * k)

    def __neg__(self) -> Vec:
        return Vec(-self.x, -self.y)

    def dot(self, o: Vec) -> Sym:
        return self.x * o.x + self.y * o.y

    def cross(self, o: Vec) -> Sym:
        """z of self x o: > 0 where o points to the left of self."""
        return self.x * o.y - self.y * o.x

    def perp(self) -> Vec:
        """Turned a quarter turn counter-clockwise."""
        return Vec(-self.y, self.x)

    def norm(self) -> Sym:
        return hypot(self.x, self.y)

    def unit(self) -> Vec:
        n = self.norm()
        return Vec(self.x / n, self.y / n)

    def angle(self) -> Sym:
        return atan2(self.y, self.x)

    @property
    def value(self) -> tuple[float, float]:
        return self.x.value, self.y.value


def direction(angle: Sym) -> Vec:
    """The unit vector at ``angle`` [rad] from +x."""
    return Vec(cos(angle), sin(angle))
