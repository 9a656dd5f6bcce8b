"""The element kinds a ``linkage/1`` file is built from: one module per kind (see :mod:`.base` for the
protocol every kind implements), listed here once. Nothing outside a kind's module switches on its name.
"""

from __future__ import annotations

import importlib

from .base import GROUND, Kind

MODULES = (
    "crank",
    "slider",
    "actuator",
    "motor",
    "rrr",
    "rrp",
    "rpr",
    "point",
    "rpp",
    "prp",
    "ppr",
    "gear",
    "cam",
    "group",
)
"""The kinds' modules, in the order the docs list them: adding a kind is one line here."""

KINDS: dict[str, Kind] = {k.name: k for k in (importlib.import_module(f"{__name__}.{m}").KIND for m in MODULES)}
"""Every element kind by name."""


def get(name: str) -> Kind:
    """The kind called ``name`` (KeyError if there is none)."""
    return KINDS[name]


def of_section(section: str) -> tuple[str, ...]:
    """The names of the kinds an ``[[inputs]]`` or ``[[groups]]`` entry may have."""
    return tuple(n for n, k in KINDS.items() if k.section == section)


__all__ = ["KINDS", "MODULES", "GROUND", "Kind", "get", "of_section"]
