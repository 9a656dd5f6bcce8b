"""Closed-form kinematics of planar linkages (SPEC.md names and conventions).

:func:`load` returns a :class:`Mechanism` (any ``linkage/1`` file, the shipped library, or a built-in)
with one interface: parameters, inputs and their motion law, ``solve(q, qd, qdd)``. The three built-ins
also keep their dedicated closed forms in :mod:`analytic.closed_forms` (four-bar, shaper six-bar,
five-bar), used as independent checks.

Data flows down the sub-packages: :mod:`.format` (the ``linkage/1`` files) -> :mod:`.kinds` (one module per
element kind) and :mod:`.topology` (links, joints, loops, groups) -> :mod:`.solver` -> :mod:`.applications`
and :mod:`.synthesis`.
"""

import lazy_loader

from analytic.errors import AssemblyError, FileError, ParameterError

SUBMODULES = ("_common", "applications", "builtin_forms", "cams", "catalog", "checks", "closed_forms", "cycle", "errors",
              "format", "kinds", "laws", "loads", "mass", "mechanism", "motion", "parts", "periodic", "quantities", "registry",
              "solution", "solver", "synthesis", "topology")
"""The package's modules, each imported on its first access (``analytic.registry``)."""

# the names that need numpy (the solver, the built-ins, the registry), imported on first use (lazy_loader):
# ``from analytic import ParameterError`` stays light (a command line's error handling, ``linkage list``)
__getattr__, __dir__, _ = lazy_loader.attach(__name__, submodules=SUBMODULES, submod_attrs={
    "builtin_forms": ["fourbar", "sixbar", "fivebar", "FourBar", "SixBar", "FiveBar", "MECHANISMS"],
    "mechanism": ["Mechanism", "Input", "Motion", "Solution"],
    "registry": ["BUILTINS", "definition", "from_text", "load", "names"]})

__all__ = ["fourbar", "sixbar", "fivebar", "FourBar", "SixBar", "FiveBar", "ParameterError", "AssemblyError",
           "FileError", "MECHANISMS", "Mechanism", "Input", "Motion", "Solution", "load", "names", "definition",
           "from_text", "BUILTINS"]
