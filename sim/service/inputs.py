"""Values of a mechanism's first input given as text (public API): an angle with a ``deg`` suffix or in rad,
a slider's travel in metres, and a range ``"LO:HI"`` of them, as the app's input-range field and a script
take them."""

from __future__ import annotations

from analytic import Mechanism
from analytic.format import expr


def input_value(mech: Mechanism, text: str, what: str = "input range") -> float:
    """One value of ``mech``'s first input from ``text`` [rad or m]: ``"30deg"`` or ``"0.5"`` for a crank
    (rad), a length for a slider (a ``deg`` suffix refused); ``what`` names the field in the error line."""
    angle = None if mech.inputs[0].angular else False
    return expr.parse_value(what, text.strip(), angle)


def input_range(mech: Mechanism, text: str, what: str = "input range") -> tuple[float, float]:
    """``"LO:HI"`` as two values of the first input (:func:`input_value`)."""
    lo, hi = text.split(":", 1)
    return input_value(mech, lo, what), input_value(mech, hi, what)
