"""Closed-form kinematics of planar linkages (SPEC.md names and conventions).

:func:`load` returns a :class:`Mechanism` (any ``linkage/1`` file, the shipped library, or a built-in)
with one interface: parameters, inputs and their motion law, ``solve(q, qd, qdd)``. The three built-ins
also keep their dedicated closed forms in :mod:`analytic.fourbar`, :mod:`analytic.sixbar` and
:mod:`analytic.fivebar`, used as independent checks.
"""

from . import fivebar, fourbar, sixbar
from ._common import AssemblyError, ParameterError
from .fivebar import FiveBar
from .fourbar import FourBar
from .linkfile import FileError
from .mechanism import Input, Mechanism, Motion, Solution
from .registry import BUILTINS, definition, from_text, load, names
from .sixbar import SixBar

MECHANISMS = {"fourbar": fourbar, "sixbar": sixbar, "fivebar": fivebar}

__all__ = ["fourbar", "sixbar", "fivebar", "FourBar", "SixBar", "FiveBar", "ParameterError", "AssemblyError",
           "FileError", "MECHANISMS", "Mechanism", "Input", "Motion", "Solution", "load", "names", "definition",
           "from_text", "BUILTINS"]
