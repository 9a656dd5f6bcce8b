"""Closed-form kinematics of planar linkages (SPEC.md names and conventions).

:func:`load` returns a :class:`Mechanism` (any ``linkage/1`` file, the shipped library, or a built-in)
with one interface: parameters, inputs and their motion law, ``solve(q, qd, qdd)``. The three built-ins
also keep their dedicated closed forms in :mod:`analytic.closed_forms` (four-bar, shaper six-bar,
five-bar), used as independent checks.

Data flows down the sub-packages: :mod:`.format` (the ``linkage/1`` files) -> :mod:`.kinds` (one module per
element kind) and :mod:`.topology` (links, joints, loops, groups) -> :mod:`.solver` -> :mod:`.applications`
and :mod:`.synthesis`.
"""

from analytic._common import AssemblyError, FileError, ParameterError
from analytic.closed_forms import fivebar, fourbar, sixbar
from analytic.closed_forms.fivebar import FiveBar
from analytic.closed_forms.fourbar import FourBar
from analytic.closed_forms.sixbar import SixBar
from analytic.mechanism import Input, Mechanism, Motion, Solution
from analytic.registry import BUILTINS, definition, from_text, load, names

MECHANISMS = {"fourbar": fourbar, "sixbar": sixbar, "fivebar": fivebar}

__all__ = ["fourbar", "sixbar", "fivebar", "FourBar", "SixBar", "FiveBar", "ParameterError", "AssemblyError",
           "FileError", "MECHANISMS", "Mechanism", "Input", "Motion", "Solution", "load", "names", "definition",
           "from_text", "BUILTINS"]
