"""Where mechanisms come from: the built-ins, the shipped library and the user's files.

``load(NAME_OR_PATH, **overrides)`` returns a :class:`~analytic.mechanism.Mechanism`. A name is looked
up among the files shipped in ``analytic/library/`` (the three built-ins of SPEC.md are among them, with
their SPEC output names and dedicated closed forms attached); anything else is read as a file path.
This module is the only place that knows mechanisms by name.
"""

from __future__ import annotations

import functools
import importlib
from collections.abc import Iterator, Mapping
from pathlib import Path

from analytic.applications import figures
from analytic.format import linkfile
from analytic._common import ParameterError
from analytic.closed_forms import Builtin
from analytic.mechanism import Mechanism
from analytic.catalog import BUILTIN_NAMES, LIBRARY, names, summary  # noqa: F401 (re-exported: the names and headers, light)

_BUILTIN_PARTS = {
    "fourbar": ({"mu": "muC"}, "FourBar"),
    "sixbar": ({"s": "sblock", "ds": "dsblock", "dds": "ddsblock"}, "SixBar"),
    "fivebar": ({"S": "sblock", "dS": "dsblock", "ddS": "ddsblock", "theta3": "phi3"}, "FiveBar"),
}
"""Each built-in's aliases and parameter class; its closed-form module is ``analytic.closed_forms.NAME`` and
its figures ``analytic.applications.figures.NAME_figures`` and ``NAME_summary``."""


@functools.cache
def _builtin(name: str) -> Builtin:
    aliases, params = _BUILTIN_PARTS[name]
    module = importlib.import_module(f"analytic.closed_forms.{name}")
    return Builtin(module.OUTPUTS, aliases, module, getattr(module, params), getattr(figures, f"{name}_figures"),
                   getattr(figures, f"{name}_summary"))


class _Builtins(Mapping):
    """The built-ins by name, each closed-form module imported when its mechanism is first loaded."""

    def __getitem__(self, name: str) -> Builtin:
        if not isinstance(name, str) or name not in _BUILTIN_PARTS:
            raise KeyError(name)
        return _builtin(name)

    def __contains__(self, name) -> bool:
        return isinstance(name, str) and name in _BUILTIN_PARTS

    def __iter__(self) -> Iterator[str]:
        return iter(_BUILTIN_PARTS)

    def __len__(self) -> int:
        return len(_BUILTIN_PARTS)


BUILTINS: Mapping[str, Builtin] = _Builtins()
"""The three mechanisms of SPEC.md: their SPEC outputs, aliases and closed-form modules."""


@functools.lru_cache(maxsize=64)
def _library_definition(name: str) -> linkfile.Definition:
    return linkfile.read(LIBRARY / f"{name}.toml")


def is_name(name: str) -> bool:
    """Whether ``name`` is in :func:`names` (a built-in, or a ``.toml`` file of the library folder), asked of
    that one file rather than by listing the folder (every drag step loads its mechanism by name)."""
    if name in BUILTIN_NAMES:
        return True
    return isinstance(name, str) and bool(name) and "/" not in name and "\\" not in name and (LIBRARY / f"{name}.toml").is_file()


def definition(name_or_path: str) -> linkfile.Definition:
    """The definition of a built-in or library mechanism by name, or of a file by path (a ``linkage/1`` file,
    or a Pyslvs or PMKS file: :mod:`analytic.format.foreign`)."""
    if is_name(name_or_path):
        return _library_definition(name_or_path)
    from analytic.format import foreign             # a path: perhaps another tool's file
    p = Path(name_or_path)
    if p.exists() and foreign.detect(p):            # a Pyslvs or PMKS file, opened as it is
        return foreign.definition(p)
    if p.suffix.lower() in (".toml", ".json", ".pyslvs") or p.exists():
        if not p.exists():
            raise linkfile.FileError(f"{name_or_path}: no such file; give a mechanism file's path or one of "
                                     f"the names listed by 'linkage list'")
        return linkfile.read(p)
    raise ParameterError(f"{name_or_path!r} is not a mechanism: use one of {', '.join(names())} "
                         f"(linkage list) or the path of a linkage/1 file (.toml or .json)")


def load(name_or_path: str, **overrides) -> Mechanism:
    """A mechanism by built-in/library name or file path, with parameters overridden (file units,
    angles in rad)."""
    d = definition(name_or_path)
    builtin = BUILTINS.get(name_or_path) if name_or_path in BUILTINS else None
    return Mechanism.from_definition(d, overrides, builtin)


def from_text(text: str, source: str = "<upload>", **overrides) -> Mechanism:
    """A mechanism from a file's text (TOML or JSON), e.g. uploaded to the app."""
    return Mechanism.from_definition(linkfile.parse(text, source), overrides)
