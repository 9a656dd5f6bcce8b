"""Numbers and angles as people type them (``0.25``, ``30deg``, ``1e-3``): what every use case reads from a
user before it reaches a mechanism. Light: no numpy, so a front end can parse its options before anything
heavy is loaded."""

from __future__ import annotations

from analytic.format import expr


def parse_value(name: str, text: str, angle: bool | None = None) -> float:
    """A value typed as text: a number, or an angle with a ``deg`` suffix (returned in radians).

    ``name`` names the value in the error message (a parameter, or the option it came from); ``angle``
    False refuses a ``deg`` suffix (the value is a length or a force), None accepts both. A value that is
    not a finite number of magnitude <= 1e12 raises :class:`analytic.ParameterError` in one line."""
    return expr.parse_value(name, text, angle=angle)


__all__ = ["parse_value"]
