"""Closed-form kinematics of planar linkages (SPEC.md names and conventions).

:func:`load` returns a :class:`Mechanism` (any ``linkage/1`` file, the shipped library, or a built-in)
with one interface: parameters, inputs and their motion law, ``solve(q, qd, qdd)``. The three built-ins
also keep their dedicated closed forms in :mod:`analytic.closed_forms.fourbar`, :mod:`analytic.closed_forms.sixbar` and
:mod:`analytic.closed_forms.fivebar`, used as independent checks.
"""

from analytic.closed_forms import fivebar
from analytic.closed_forms import fourbar
from analytic.closed_forms import sixbar
from analytic._common import AssemblyError, ParameterError
from analytic.closed_forms.fivebar import FiveBar
from analytic.closed_forms.fourbar import FourBar
from analytic.format.linkfile import FileError
from analytic.mechanism import Input, Mechanism, Motion, Solution
from analytic.registry import BUILTINS, definition, from_text, load, names
from analytic.closed_forms.sixbar import SixBar

MECHANISMS = {"fourbar": fourbar, "sixbar": sixbar, "fivebar": fivebar}

__all__ = ["fourbar", "sixbar", "fivebar", "FourBar", "SixBar", "FiveBar", "ParameterError", "AssemblyError",
           "FileError", "MECHANISMS", "Mechanism", "Input", "Motion", "Solution", "load", "names", "definition",
           "from_text", "BUILTINS"]
