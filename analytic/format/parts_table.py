"""The ``[parts]`` section of a mechanism file (SPEC "Parts, drawings and interference"), checked as written:
``pin_diameter``, ``clearance``, ``end_radius``, ``layer_gap`` (file units), ``frame`` (a polygon
``[[x, y], ...]`` in file units) and ``layers`` (``{LINK = z index}``, to fix a link's layer). What the numbers
make is :mod:`analytic.parts`."""

from __future__ import annotations

import math

from analytic._common import FileError

FIELDS = {"pin_diameter": "> 0", "clearance": ">= 0", "end_radius": "> 0", "layer_gap": ">= 0"}
MAX_MAGNITUDE = 1e12
MAX_FRAME_CORNERS = 1000
"""The most corners of a ``frame`` polygon: its sweep against the links grows with their count (a four-bar's
``check --interference`` took 8 s at 1,000 corners, 23 s at 4,000, and ``check`` alone 31 s at 20,000)."""


def _fail(source: str, where: str, what: str) -> FileError:
    return FileError(f"{source}: {where}: {what}")


def _number(v) -> bool:
    return not isinstance(v, bool) and isinstance(v, (int, float)) and math.isfinite(v) and abs(v) <= MAX_MAGNITUDE


def check(section, links: set, source: str) -> dict:
    """The ``[parts]`` table checked (one line naming the field otherwise); returned as written."""
    if not isinstance(section, dict):
        raise _fail(source, "parts", "must be a table (pin_diameter, clearance, end_radius, layer_gap, frame, "
                                     "layers)")
    known = set(FIELDS) | {"frame", "layers"}
    for key in section:
        if key not in known:
            raise _fail(source, f"parts.{str(key)[:60]}", f"unknown field; [parts] takes {', '.join(sorted(known))}")
    for key, rule in FIELDS.items():
        if key not in section:
            continue
        v = section[key]
        if not _number(v):
            raise _fail(source, f"parts.{key}", f"{str(v)[:60]} must be a finite number [file units]")
        if not (v > 0 if rule == "> 0" else v >= 0):
            raise _fail(source, f"parts.{key}", f"{v!r} must be {rule} [file units]")
    if "frame" in section:
        frame = section["frame"]
        if isinstance(frame, list) and len(frame) > MAX_FRAME_CORNERS:
            raise _fail(source, "parts.frame", f"{len(frame)} corners; a frame has at most {MAX_FRAME_CORNERS} "
                                               f"(simplify its outline)")
        if not (isinstance(frame, list) and len(frame) >= 3 and all(
                isinstance(p, list) and len(p) == 2 and all(_number(c) for c in p) for p in frame)):
            raise _fail(source, "parts.frame", "must be a polygon [[x, y], [x, y], [x, y], ...] of at least three "
                                               "corners [file units]")
        area = 0.5 * sum(frame[k][0] * frame[k - 1][1] - frame[k - 1][0] * frame[k][1] for k in range(len(frame)))
        if area == 0:
            raise _fail(source, "parts.frame", "the polygon has no area; give its corners in order around it")
    if "layers" in section:
        layers = section["layers"]
        if not isinstance(layers, dict):
            raise _fail(source, "parts.layers", "must be a table LINK = z index (0 = against the frame)")
        for ln, z in layers.items():
            if ln not in links:
                raise _fail(source, f"parts.layers.{str(ln)[:60]}", f"no link named {ln!r}; links: "
                                                                   f"{', '.join(sorted(links))}")
            if isinstance(z, bool) or not isinstance(z, int) or not 0 <= z < 64:
                raise _fail(source, f"parts.layers.{ln}", f"{str(z)[:60]} must be a whole number 0..63 (the z index)")
    return section
