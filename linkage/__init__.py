"""``import linkage as lk``: planar linkages in Python, the door every front end uses.

Load a mechanism (a name from ``linkage list``, or a ``linkage/1`` file) with its parameter values as
keywords, then ask it questions; every option is a keyword, every result a frozen object with attributes
and ``to_dict()`` (the object the matching command prints with ``--json``); bad input raises
:class:`ParameterError` with one line, as the command prints it::

    import linkage as lk
    mech = lk.load("fourbar", l1=0.12)
    a = lk.analyze(mech, samples=361)                   # a["xE"], a.t, a.figures
    c = lk.compare(mech)                                # c.passed, c.errors, c.trajectory
    f = lk.forces(mech, samples=73, gravity=(0, -9.81)) # f.drives["phi1"], f.joints, f.shaking, f.peaks
    f.to_dict()                                         # what `linkage forces --json` prints

The packages behind the door stay where they are: :mod:`analytic` (closed forms, synthesis), :mod:`sim`
(the MuJoCo model, the service layer, the command line and the app) and :mod:`mjcf`. Importing ``linkage``
loads none of them: each name is imported on first use.

Why a small package in front of :mod:`sim.service` rather than the service moved behind this name: the
service's ~60 functions are the front ends' working vocabulary (records, tables, checks, the app's drag and
synthesis jobs) and keep their positional, dict-returning form for them; the door adds only what a script
needs (ten functions with keyword-only options, typed frozen results, notebook views) and nothing below it
changes, so the layers stay format -> topology -> solver -> applications -> service -> door -> front ends.
"""

from __future__ import annotations

from analytic.errors import ParameterError

_FROM = {
    "linkage.api": ("load", "analyze", "simulate", "compare", "forces", "dynamics", "export", "tolerance",
                    "synthesize", "sweep", "list_mechanisms"),
    "linkage.mechanism": ("Mechanism",),
    "linkage.results": ("Analysis", "Simulation", "Comparison", "Forces", "Dynamics", "Export", "Tolerance",
                        "Synthesis", "Sweep"),
}
"""Where each name of the door lives; imported on first access (numpy, the solver) so that ``import linkage``
costs nothing until a function is used."""

__all__ = ["load", "analyze", "simulate", "compare", "forces", "dynamics", "export", "tolerance", "synthesize",
           "sweep", "list_mechanisms", "ParameterError", "Mechanism", "Analysis", "Simulation", "Comparison",
           "Forces", "Dynamics", "Export", "Tolerance", "Synthesis", "Sweep"]


def __getattr__(name: str):
    """PEP 562: a name of the door imports its module on first use; a submodule by its name."""
    import importlib
    for module, names in _FROM.items():
        if name in names:
            value = getattr(importlib.import_module(module), name)
            globals()[name] = value
            return value
    if name.startswith("__"):
        raise AttributeError(name)
    try:
        return importlib.import_module(f"linkage.{name}")
    except ModuleNotFoundError as exc:
        if exc.name != f"linkage.{name}":
            raise
        raise AttributeError(f"module 'linkage' has no attribute {name!r}") from None


def __dir__():
    return sorted(set(globals()) | set(__all__))
