"""The first input's values a script gives: a range to rock over (``input_range=``) and one pose (``at=``),
as numbers (SI) or as the command line's text."""

from __future__ import annotations

import math

from analytic.errors import ParameterError


def input_range_of(mech, input_range):
    """``input_range=``: None (the file's own ``input_range``, if any), ``(lo, hi)`` [rad, or m for a slider]
    or the command line's text ``"LO:HI"`` (a crank's in rad, or deg with a ``deg`` suffix; a slider's in the
    file's length unit): (lo, hi) in SI, or None."""
    from sim.service.values import parse_value
    text = mech.definition.input_range if input_range is None else input_range
    if not text:
        return None
    if not isinstance(text, str):
        if not isinstance(text, (tuple, list)) or len(text) != 2:
            raise ParameterError(f"input_range={text!r} is not (lo, hi) nor 'LO:HI' (e.g. '-40deg:40deg')")
        lo, hi = (float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else math.nan for v in text)
        return lo, hi
    if ":" not in text:
        raise ParameterError(f"input_range={text!r} is not LO:HI (e.g. -40deg:40deg)")
    lo, hi = text.split(":", 1)
    angle = mech.inputs[0].angular
    scale = 1.0 if angle else mech.scale
    return (parse_value("input_range", lo, angle=None if angle else False) * scale,
            parse_value("input_range", hi, angle=None if angle else False) * scale)


def at_value(mech, at):
    """``at=``: the first input's value, a number [rad, or m for a slider] or text (``"30deg"``; a slider's in
    file units): [rad or m], or None."""
    if at is None or not isinstance(at, str):
        return None if at is None else float(at)
    from sim.service.values import parse_value
    first = mech.inputs[0]
    if first.angular:
        return parse_value("at", at, angle=None)
    return parse_value("at", at, angle=False) * mech.scale
