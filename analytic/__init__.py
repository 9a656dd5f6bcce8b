"""Closed-form kinematics of planar linkages (SPEC.md names and conventions).

One module per mechanism: :mod:`analytic.fourbar`, :mod:`analytic.sixbar`, :mod:`analytic.fivebar`.
Each has a frozen parameter dataclass, ``solve`` (vectorized over input angles) and ``drive``.
"""

from . import fivebar, fourbar, sixbar
from ._common import AssemblyError, ParameterError
from .fivebar import FiveBar
from .fourbar import FourBar
from .sixbar import SixBar

MECHANISMS = {"fourbar": fourbar, "sixbar": sixbar, "fivebar": fivebar}

__all__ = ["fourbar", "sixbar", "fivebar", "FourBar", "SixBar", "FiveBar",
           "ParameterError", "AssemblyError", "MECHANISMS"]
