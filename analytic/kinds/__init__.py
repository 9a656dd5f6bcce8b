"""The element kinds a ``linkage/1`` file is built from: one module per kind (see :mod:`.base` for the
protocol every kind implements), listed here once. Nothing outside a kind's module switches on its name.
"""

from __future__ import annotations

from analytic._common import LazyKinds, module_getattr

from .base import GROUND, Kind

SECTIONS = {
    "crank": "inputs",
    "slider": "inputs",
    "actuator": "inputs",
    "motor": "inputs",
    "motor_dyad": "inputs",
    "RRR": "groups",
    "RRP": "groups",
    "RPR": "groups",
    "point": "groups",
    "RPP": "groups",
    "PRP": "groups",
    "PPR": "groups",
    "gear": "groups",
    "cam": "groups",
    "group": "groups",
}
"""Every kind's name and the section (``[[inputs]]`` or ``[[groups]]``) it is written in, in the order the docs
list them; its module is its name in lower case. Adding a kind is one line here."""

MODULES = tuple(name.lower() for name in SECTIONS)
"""The kinds' modules, in the same order."""


KINDS: LazyKinds = LazyKinds(__name__, tuple(SECTIONS))
"""Every element kind by name, each module imported when its kind is first asked for (a four-bar's command
loads the crank and the RRR group, not the cam's or the general group's solvers)."""


def get(name: str) -> Kind:
    """The kind called ``name`` (KeyError if there is none)."""
    return KINDS[name]


def of_section(section: str) -> tuple[str, ...]:
    """The names of the kinds an ``[[inputs]]`` or ``[[groups]]`` entry may have."""
    def section_of(name: str) -> str:        # a kind not imported yet: its line of SECTIONS (nothing imported)
        kind = KINDS.loaded(name) if isinstance(KINDS, LazyKinds) else KINDS[name]
        return SECTIONS[name] if kind is None else kind.section
    return tuple(n for n in KINDS if section_of(n) == section)


__all__ = ["KINDS", "MODULES", "SECTIONS", "GROUND", "Kind", "get", "of_section"]

__getattr__ = module_getattr(__name__, MODULES)
