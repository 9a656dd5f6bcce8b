"""Another tool's mechanism as a ``linkage/1`` file (``linkage import``; SPEC "linkages as users draw them"): a
Pyslvs-UI project (.pyslvs), a Pyslvs expression ``M[...]`` or a PMKS text file, written in the links-and-joints
form, checked to be a mechanism and to read back as one before it is returned."""

from __future__ import annotations

from dataclasses import dataclass

from analytic.format import foreign

UNITS = foreign.UNITS
"""The length units a source's numbers may be given in (neither format stores one)."""
DEFAULT_UNITS = foreign.DEFAULT_UNITS
"""The length unit assumed when none is given."""

__all__ = ["UNITS", "DEFAULT_UNITS", "Imported", "detect", "convert"]


@dataclass(frozen=True)
class Imported:
    """A converted source: its ``kind`` (as :func:`detect` names it), the ``linkage/1`` ``text`` to write, its
    ``data`` (the links-and-joints dict: ``pose``, ``links``, ``joints``, ...) and the Assur ``groups`` it
    decomposes into, in solving order (one readable label each)."""

    kind: str
    text: str
    data: dict
    groups: tuple[str, ...]


def detect(source) -> str | None:
    """The kind of file at ``source`` (a Pyslvs project, a Pyslvs expression, a PMKS file), or None."""
    return foreign.detect(source)


def convert(source, inputs=None, units: str = DEFAULT_UNITS, kind: str | None = None, out: str = "<out>") -> Imported:
    """The file at ``source`` as a ``linkage/1`` file: ``inputs`` the Pyslvs input pairs (base joint, driver
    joint) replacing a project's own (None: its own), ``units`` the length unit of its numbers, ``kind`` as
    :func:`detect` gives it (None: detected). The result is a mechanism (else one line naming the source) and
    its text, read back as if from ``out``, is one too."""
    from analytic.format import joints, linkfile
    kind = kind or foreign.detect(source)
    data = foreign.read(source, inputs, units, kind)
    text = foreign.dumps(data)
    d = linkfile.from_data(data, source)
    linkfile.parse(text, out)
    return Imported(kind, text, data, tuple(joints.structure(data, source, linkfile.parameter_values(d))))
