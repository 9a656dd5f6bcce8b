"""The mechanisms addressable by name (``linkage list``), read from the library files' headers alone: no
mechanism is built and nothing heavy is imported (no numpy), so listing them starts at once."""

from __future__ import annotations

from analytic.catalog import BUILTIN_NAMES, LIBRARY, names, summary

__all__ = ["LIBRARY", "list_mechanisms"]


def list_mechanisms() -> list[dict]:
    """Every mechanism addressable by name: name, description, number of inputs, built-in or not."""
    out = []
    for name in names():
        description, inputs = summary(name)
        out.append({"name": name, "description": description, "inputs": inputs, "builtin": name in BUILTIN_NAMES})
    return out

