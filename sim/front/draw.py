"""A linkage drawn on the app's empty page, as a ``linkage/1`` file in the links-and-joints form.

The page sends what was drawn: points (``ground`` pivots and moving joints) at their positions [m], links
(each a list of the points it carries) and the driven link. :func:`drawing_text` writes the file (``[pose]``
in mm, ``[[links]]``, an ``R`` joint at every point that two or more links, or a link and the ground,
share, and the crank ``[[inputs]]``); :func:`check` counts the mobility (Gruebler) first, so a rigid or
under-constrained drawing is named as such, then lets the tool find the Assur groups and answers them, or
the loader's one line.
"""

from __future__ import annotations

import math
import re

from analytic import ParameterError

UNITS = "mm"
SCALE = 1000.0
"""[mm per m] The drawn file's unit: the page draws in metres."""
NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


def _fail(message: str) -> ParameterError:
    return ParameterError(message)


def parse(drawing: dict) -> tuple[dict[str, tuple[float, float, bool]], list[tuple[str, list[str]]], str | None]:
    """(points {name: (x, y, ground)}, links [(name, points)], the driven link) of a drawing, checked."""
    if not isinstance(drawing, dict):
        raise _fail("drawing must be an object {points, links, input}")
    raw_points = drawing.get("points")
    if not isinstance(raw_points, dict) or not raw_points:
        raise _fail("place the ground pivots and joints first: the drawing has no points")
    points = {}
    for name, p in raw_points.items():
        if not (isinstance(name, str) and NAME.match(name)):
            raise _fail(f"point name {name!r} must be a letter then letters, digits or _")
        ok = isinstance(p, dict) and all(isinstance(p.get(c), (int, float)) and not isinstance(p.get(c), bool)
                                         and math.isfinite(p[c]) and abs(p[c]) < 1e3 for c in "xy")
        if not ok:
            raise _fail(f"point {name}: give x and y in metres (finite, |x|, |y| < 1000)")
        points[name] = (float(p["x"]), float(p["y"]), bool(p.get("ground", False)))
    links = []
    seen = set()
    for k, link in enumerate(drawing.get("links") or []):
        if not isinstance(link, dict):
            raise _fail(f"links[{k}] must be {{name, points}}")
        name, pts = link.get("name"), link.get("points")
        if not (isinstance(name, str) and NAME.match(name)) or name == "ground" or name in seen or name in points:
            raise _fail(f"link name {name!r}: give each link its own name (not 'ground', not a point's)")
        if not (isinstance(pts, list) and len(pts) >= 2 and all(p in points for p in pts) and len(set(pts)) == len(pts)):
            raise _fail(f"link {name}: it must join two or more different placed points")
        seen.add(name)
        links.append((name, list(pts)))
    driven = drawing.get("input")
    if driven is not None and driven not in seen:
        raise _fail(f"input {driven!r} is not a link of the drawing")
    return points, links, driven


def mobility(points, links) -> int:
    """Gruebler's count: 3 (n - 1) - 2 j with n links (the ground included) and j revolute pairs (k links
    meeting at a point make k - 1)."""
    n = len(links) + 1
    j = 0
    for name, (_, _, ground) in points.items():
        k = sum(name in pts for _, pts in links) + (1 if ground else 0)
        j += max(0, k - 1)
    return 3 * (n - 1) - 2 * j


def drawing_text(drawing: dict, name: str = "drawn") -> str:
    """The ``linkage/1`` text of a drawing (see the module docstring)."""
    from sim import service
    points, links, driven = parse(drawing)
    at = {p: [lk for lk, pts in links if p in pts] for p in points}
    data = {"format": "linkage/1", "name": name, "units": UNITS, "description": "drawn in linkage app"}
    moving = [p for p, (_, _, g) in points.items() if not g and at[p]]
    if moving:
        data["output"] = moving[-1]
    data["pose"] = {p: [_num(x * SCALE), _num(y * SCALE)] for p, (x, y, _) in points.items()}
    data["links"] = [{"name": lk, "points": list(pts)} for lk, pts in links]
    data["joints"] = []
    for p, (_, _, ground) in points.items():
        pair = (["ground"] if ground else []) + at[p]
        if len(pair) >= 2:
            data["joints"].append({"kind": "R", "point": p, "links": pair})
    if driven is not None:
        pts = dict(links)[driven]
        pivots = [p for p in pts if points[p][2]]
        if len(pivots) != 1:
            raise _fail(f"input {driven}: the driven link must have exactly one ground pivot (it has "
                        f"{len(pivots)}); mark a link pinned to the ground")
        tip = next(p for p in pts if p != pivots[0])
        data["inputs"] = [{"kind": "crank", "pivot": pivots[0], "point": tip, "link": driven, "omega": "360deg"}]
    return service.table_text(data)


def _num(v: float) -> float:
    r = round(v, 4)
    return 0.0 if r == 0 else r


def check(drawing: dict) -> dict:
    """The drawing's file and what the tool makes of it: ``text``; ``mobility``; ``error`` (one line, or
    None) with ``names`` (the points and links it names, for the page to mark); ``groups`` (the Assur groups
    found: the points each places, its links, its class) when it loads."""
    from sim import service
    from sim.service import editing
    points, links, driven = parse(drawing)
    m = mobility(points, links)
    out = {"text": None, "mobility": m, "error": None, "names": [], "groups": [], "output": None}
    loose = [p for p, (_, _, g) in points.items() if not any(p in pts for _, pts in links)]
    if loose:
        return {**out, "error": f"{', '.join(loose)} {'is' if len(loose) == 1 else 'are'} on no link: join "
                                f"{'it' if len(loose) == 1 else 'them'} with the link tool or erase", "names": loose}
    if not links:
        return {**out, "error": "no links yet: join the points with the link tool"}
    if m <= 0:
        what = "a rigid structure" if m == 0 else "over-constrained (a structure with redundant links)"
        return {**out, "error": f"mobility {m}: {what}, nothing can move; remove a link or add a joint and a link",
                "names": [lk for lk, _ in links]}
    if driven is None:
        return {**out, "error": f"mobility {m}: mark the driven link with the input tool"
                                + ("" if m == 1 else f" (and {m - 1} more: the drawing has {m} degrees of freedom)")}
    if m > 1:
        return {**out, "error": f"mobility {m} with one input: {m - 1} degree(s) of freedom are left loose; add "
                                f"links that tie them down (a four-bar: four links with the ground)"}
    try:
        text = drawing_text(drawing)
    except ParameterError as exc:
        return {**out, "error": str(exc), "names": [driven]}
    out["text"] = text
    try:
        mech = service.load("<drawn>", text=text)
    except ParameterError as exc:
        message = re.sub(r"<(drawn|upload)>:? ?", "", str(exc))
        names = [n for n in list(points) + [lk for lk, _ in links] if re.search(rf"\b{re.escape(n)}\b", message)]
        return {**out, "error": message.splitlines()[0], "names": names}
    out["groups"] = editing.assur_groups(mech)
    out["output"] = mech.output_point
    return out
