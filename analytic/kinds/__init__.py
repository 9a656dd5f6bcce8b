"""The element kinds a ``linkage/1`` file is built from: one module per kind (see :mod:`.base` for the
protocol every kind implements), listed here once. Nothing outside a kind's module switches on its name.
"""

from __future__ import annotations

import functools
import importlib
from collections.abc import Iterator, Mapping

from .base import GROUND, Kind

SECTIONS = {
    "crank": "inputs",
    "slider": "inputs",
    "actuator": "inputs",
    "motor": "inputs",
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


@functools.cache
def _kind(name: str) -> Kind:
    kind = importlib.import_module(f"{__name__}.{name.lower()}").KIND
    if (kind.name, kind.section) != (name, SECTIONS[name]):
        raise RuntimeError(f"analytic/kinds/{name.lower()}.py: its KIND is {kind.name!r} in {kind.section!r}; "
                           f"SECTIONS says {name!r} in {SECTIONS[name]!r}: make them agree")
    return kind


class _Kinds(Mapping):
    """The kinds by name, each module imported when its kind is first asked for (a four-bar's command loads
    the crank and the RRR group, not the cam's or the general group's solvers)."""

    def __getitem__(self, name: str) -> Kind:
        if not isinstance(name, str) or name not in SECTIONS:
            raise KeyError(name)
        return _kind(name)

    def __contains__(self, name) -> bool:
        return isinstance(name, str) and name in SECTIONS

    def __iter__(self) -> Iterator[str]:
        return iter(SECTIONS)

    def __len__(self) -> int:
        return len(SECTIONS)


KINDS: Mapping[str, Kind] = _Kinds()
"""Every element kind by name."""


def get(name: str) -> Kind:
    """The kind called ``name`` (KeyError if there is none)."""
    return KINDS[name]


def of_section(section: str) -> tuple[str, ...]:
    """The names of the kinds an ``[[inputs]]`` or ``[[groups]]`` entry may have."""
    return tuple(n for n, s in SECTIONS.items() if s == section)


__all__ = ["KINDS", "MODULES", "SECTIONS", "GROUND", "Kind", "get", "of_section"]
