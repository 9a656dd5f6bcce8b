"""Modules imported on first use, so that building the command line's parser stays light.

``linkage list`` and ``linkage check`` need numpy and the solver, not scipy's optimisers, matplotlib or
MuJoCo; a command module that needs such a module for its work (not for its options) names it here:
``design_service = lazy("sim.service.design")`` binds a module whose code runs at its first attribute
access (importlib's LazyLoader, the standard library's recipe)."""

from __future__ import annotations

import importlib.util
import sys


def lazy(name: str):
    """The module ``name``: the one already imported, or one that loads itself when first used."""
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.find_spec(name)
    spec.loader = importlib.util.LazyLoader(spec.loader)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module
