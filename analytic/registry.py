"""Where mechanisms come from: the built-ins, the shipped library and the user's files.

``load(NAME_OR_PATH, **overrides)`` returns a :class:`~analytic.mechanism.Mechanism`. A name is looked
up among the files shipped in ``analytic/library/`` (the three built-ins of SPEC.md are among them, with
their SPEC output names and dedicated closed forms attached); anything else is read as a file path.
This module is the only place that knows mechanisms by name.
"""

from __future__ import annotations

import functools
from pathlib import Path

from analytic.closed_forms import fivebar
from analytic.applications import figures
from analytic.closed_forms import fourbar
from analytic.format import foreign, linkfile
from analytic.closed_forms import sixbar
from analytic._common import ParameterError
from analytic.closed_forms import Builtin
from analytic.mechanism import Mechanism
from analytic.catalog import BUILTIN_NAMES, LIBRARY, names, summary  # noqa: F401 (re-exported: the names and headers, light)

BUILTINS: dict[str, Builtin] = {
    "fourbar": Builtin(fourbar.OUTPUTS, {"mu": "muC"}, fourbar, fourbar.FourBar,
                       figures.fourbar_figures, figures.fourbar_summary),
    "sixbar": Builtin(sixbar.OUTPUTS, {"s": "sblock", "ds": "dsblock", "dds": "ddsblock"}, sixbar,
                      sixbar.SixBar, figures.sixbar_figures, figures.sixbar_summary),
    "fivebar": Builtin(fivebar.OUTPUTS, {"S": "sblock", "dS": "dsblock", "ddS": "ddsblock", "theta3": "phi3"},
                       fivebar, fivebar.FiveBar, figures.fivebar_figures, figures.fivebar_summary),
}
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
