"""Closed-form kinematics of planar linkages (SPEC.md names and conventions).

:func:`load` returns a :class:`Mechanism` (any ``linkage/1`` file, the shipped library, or a built-in)
with one interface: parameters, inputs and their motion law, ``solve(q, qd, qdd)``. The three built-ins
also keep their dedicated closed forms in :mod:`analytic.closed_forms` (four-bar, shaper six-bar,
five-bar), used as independent checks.

Data flows down the sub-packages: :mod:`.format` (the ``linkage/1`` files) -> :mod:`.kinds` (one module per
element kind) and :mod:`.topology` (links, joints, loops, groups) -> :mod:`.solver` -> :mod:`.applications`
and :mod:`.synthesis`.
"""

from analytic.errors import AssemblyError, FileError, ParameterError

__all__ = ["fourbar", "sixbar", "fivebar", "FourBar", "SixBar", "FiveBar", "ParameterError", "AssemblyError",
           "FileError", "MECHANISMS", "Mechanism", "Input", "Motion", "Solution", "load", "names", "definition",
           "from_text", "BUILTINS"]

_HEAVY = frozenset(__all__) - {"ParameterError", "AssemblyError", "FileError"}


def _everything() -> dict:
    """The package's names that need numpy (the solver, the built-ins, the registry), imported on first use:
    ``from analytic import ParameterError`` stays light (a command line's error handling, ``linkage list``)."""
    from analytic.closed_forms import fivebar, fourbar, sixbar
    from analytic import mechanism, registry
    return {"fourbar": fourbar, "sixbar": sixbar, "fivebar": fivebar, "FourBar": fourbar.FourBar,
            "SixBar": sixbar.SixBar, "FiveBar": fivebar.FiveBar, "MECHANISMS": {"fourbar": fourbar, "sixbar": sixbar,
                                                                                "fivebar": fivebar},
            **{k: getattr(mechanism, k) for k in ("Mechanism", "Input", "Motion", "Solution")},
            **{k: getattr(registry, k) for k in ("BUILTINS", "definition", "from_text", "load", "names")}}


def __getattr__(name: str):
    """PEP 562: the numpy-backed names on first access; any other name is a submodule (``analytic.registry``),
    imported as ``import analytic.registry`` would."""
    if name in _HEAVY:
        names = _everything()
        globals().update(names)
        return names[name]
    if name.startswith("__"):
        raise AttributeError(name)
    import importlib
    try:
        return importlib.import_module(f"analytic.{name}")
    except ModuleNotFoundError as exc:
        if exc.name != f"analytic.{name}":
            raise
        raise AttributeError(f"module 'analytic' has no attribute {name!r}") from None


def __dir__():
    return sorted(set(globals()) | set(__all__))
