"""The names of the mechanisms and their one-line headers, read without building any of them: the shipped
library's folder, the built-ins' names, each file's description and number of inputs. Light (no numpy),
so that listing the mechanisms costs one small file read each; :mod:`analytic.registry` builds them."""

from __future__ import annotations

from pathlib import Path

LIBRARY = Path(__file__).resolve().parent / "library"
"""The folder of the shipped ``linkage/1`` files (never written by any command)."""

BUILTIN_NAMES = ("fourbar", "sixbar", "fivebar")
"""The three mechanisms of SPEC.md, in the order they are listed (analytic.registry.BUILTINS)."""


def names() -> tuple[str, ...]:
    """Every mechanism addressable by name: the built-ins first, then the library in name order."""
    lib = sorted(p.stem for p in LIBRARY.glob("*.toml") if p.stem not in BUILTIN_NAMES)
    return BUILTIN_NAMES + tuple(lib)


def summary(name: str) -> tuple[str, int]:
    """A library mechanism's description and number of inputs, read from its file without building its
    definition (``linkage list`` stays at one file read per mechanism; the shipped files are checked
    whole by the tests)."""
    import tomllib
    with open(LIBRARY / f"{name}.toml", "rb") as f:
        raw = tomllib.load(f)
    return str(raw.get("description", "")), len(raw.get("inputs", ()))
