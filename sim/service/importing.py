"""Another tool's mechanism as a ``linkage/1`` file (``linkage import``; SPEC "linkages as users draw them"): a
Pyslvs-UI project (.pyslvs), a Pyslvs expression ``M[...]`` or a PMKS text file, written in the links-and-joints
form, checked to be a mechanism and to read back as one before it is returned.

Driven as the source drives it: the first input moves, the others are held (Pyslvs turns one dial at a
time); where that input cannot run a turn (a slider: its default second), because it cannot turn fully, would
leave its assembly range, or would pass a singular pose or a change point where a dyad's two pivots meet, the
file gets the range the source moves it through, ``input_range`` (:func:`source_range`), which every command
then rocks over: PMKS steps its input forward and back from the drawn pose until the mechanism cannot move
(its ``FindFullMovement``), and Pyslvs' solver stops at those poses too."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from analytic.format import foreign

if TYPE_CHECKING:
    from analytic.format.linkfile import Definition

UNITS = foreign.UNITS
"""The length units a source's numbers may be given in (neither format stores one)."""
DEFAULT_UNITS = foreign.DEFAULT_UNITS
"""The length unit assumed when none is given."""

MARGIN = 0.10
"""The fraction of the source's range kept clear of each of its ends (its dead points, singular poses or
change points, where the simulation cannot meet compare's tolerances); a start nearer an end than twice that
keeps half its distance to it, so the drawn pose is always inside."""
REFUSALS = ("cannot turn fully", "singular pose", "cannot be assembled", " meet (")
"""The refusals of a run over a turn that mean the source stops earlier: its range is written instead."""

__all__ = ["UNITS", "DEFAULT_UNITS", "MARGIN", "Imported", "detect", "convert", "source_range", "driven", "foreign_definition", "range_text",
           "range_values"]


@dataclass(frozen=True)
class Imported:
    """A converted source: its ``kind`` (as :func:`detect` names it), the ``linkage/1`` ``text`` to write, its
    ``data`` (the links-and-joints dict: ``pose``, ``links``, ``joints``, ..., and ``input_range`` where the
    source cannot run a turn) and the Assur ``groups`` it decomposes into, in solving order (one readable
    label each); ``why``: the refusal of a run over a turn that the range answers ('' without one)."""

    kind: str
    text: str
    data: dict
    groups: tuple[str, ...]
    why: str = ""


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
    data, why = driven(foreign.read(source, inputs, units, kind), source)
    text = foreign.dumps(data)
    d = linkfile.from_data(data, source)
    linkfile.parse(text, out)
    return Imported(kind, text, data, tuple(joints.structure(data, source, linkfile.parameter_values(d))), why)


def foreign_definition(path) -> Definition | None:
    """The definition of the Pyslvs or PMKS file at ``path`` as :func:`convert` writes it (its own inputs, the
    default unit), for the commands that open one as it is; None where ``path`` names no such file (a name,
    a ``linkage/1`` file)."""
    from pathlib import Path
    from analytic import registry
    from analytic.format import linkfile
    p = Path(str(path))
    if registry.is_name(str(path)) or not p.exists() or foreign.detect(p) is None:
        return None
    data, _ = driven(foreign.read(p), str(p))
    return linkfile.from_data(data, str(p), foreign.name_of(p.stem))


def driven(data: dict, source: str = "<import>") -> tuple[dict, str]:
    """``data`` (a links-and-joints dict) with the ``input_range`` its source drives it through where a run
    over a turn of its first input (a slider: a second at its rate) is refused for one of REFUSALS, and that
    refusal ('' and ``data`` unchanged where it has a range already, the turn runs, or no range around the
    start can be run: the commands then say why)."""
    from analytic import ParameterError
    from analytic.format import linkfile
    from analytic.mechanism import Mechanism
    from sim.service.simulation import prepare
    if data.get("input_range"):
        return data, ""
    try:
        mech = Mechanism.from_definition(linkfile.from_data(data, source), {})
    except ParameterError:                     # not a mechanism: the caller's own checks say why
        return data, ""
    try:
        prepare(mech, 1.0)
        return data, ""
    except ParameterError as exc:
        why = str(exc)
    if not any(r in why for r in REFUSALS):
        return data, ""
    rng = source_range(mech)
    if rng is None:
        return data, ""
    text = range_text(mech, *rng)
    try:
        prepare(mech, 1.0, range_values(mech, text))
    except ParameterError:
        return data, ""
    return {**data, "input_range": text}, why


def range_text(mech, lo: float, hi: float) -> str:
    """``lo:hi`` (rad, or m for a slider) as a file's ``input_range``: degrees for a crank, the file's length
    unit for a slider, rounded inward."""
    from analytic.applications.figures import round_inward
    if mech.inputs[0].angular:
        return f"{round_inward(math.degrees(lo), True, 4)}deg:{round_inward(math.degrees(hi), False, 4)}deg"
    return f"{round_inward(lo / mech.scale, True)}:{round_inward(hi / mech.scale, False)}"


def range_values(mech, text: str) -> tuple[float, float]:
    """A file's ``input_range`` text as the first input's values (rad, or m for a slider, whose range is in
    the file's length unit), as the commands read it."""
    from sim.service.inputs import input_range
    lo, hi = input_range(mech, text)
    scale = 1.0 if mech.inputs[0].angular else mech.scale
    return lo * scale, hi * scale


def source_range(mech) -> tuple[float, float] | None:
    """The first input's range around its start as the source drives it (rad, or m for a slider): between
    the nearest ends on either side, an assembly limit, a singular pose (a dead point of a group, a change
    point, or guides turning parallel) or a change point where a dyad's two pivots meet, MARGIN of the width
    clear of each; a start nearer an end than twice that keeps half its distance to it. None where no such
    range holds the start (a locked or unmovable pose)."""
    from analytic.applications import figures
    from analytic.solver.change_points import folded
    q0 = mech.inputs[0].motion.q0
    crank = mech.inputs[0].angular
    ranges = figures.assembly_ranges(mech)
    full = figures.turns_fully(mech, ranges)
    turn = 2 * math.pi if crank else 0.0
    ends = [x for x, _, _ in figures.singular_poses(mech)] + [f[0] for f in folded(mech)]
    if not full:
        ends += [e for r in ranges for e in r if abs(e - q0) > 1e-9 and abs(e - q0 - turn) > 1e-9]
    shifts = (-1, 0, 1) if crank else (0,)
    ends = [c + k * turn for c in ends for k in shifts]
    tiny = 1e-9
    below = [c for c in ends if c <= q0 + tiny]
    above = [c for c in ends if c > q0 + tiny]
    if not below or not above:
        return None
    lo, hi = max(below), min(above)
    if not full and not any(a - tiny <= (lo + hi) / 2 - turn * k <= b + tiny for a, b in ranges for k in shifts):
        return None
    pad = MARGIN * (hi - lo)
    lo_pad = pad if q0 - lo > 2 * pad else 0.5 * (q0 - lo)
    hi_pad = pad if hi - q0 > 2 * pad else 0.5 * (hi - q0)
    return lo + lo_pad, hi - hi_pad
