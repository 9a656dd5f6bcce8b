"""``group``: any Assur group of revolute joints that is not a chain of dyads (a class III triad, a class IV
tetrad, a 6-link group ...), solved as one group, numerically.

Fields: ``points`` (the points it places), ``links`` (every link of the group and its points,
``{LINK = ["P", "Q", ...]}``: a link's first two points are its frame's origin and x-axis; points not in
``points`` are known, placed earlier), ``pose`` (every point of its links at the start, ``{P = [x, y]}`` in
the file's unit). The group is dimensioned from the pose: each link's base length and its further points'
coordinates in its frame. Joints follow from the shared points: a revolute wherever two of its links, or a
link and an earlier one, carry the same point.

The engine is :mod:`analytic.solver.general_group`: Newton from the previous sample (the first from the
pose), exact rates from the group's Jacobian, the branch (the sign of the Jacobian's determinant at the
pose) held by continuity and reported; NaN where continuity breaks (a singular pose, a jump). The solver
therefore takes a solve's samples as a path (:attr:`Kind.continuous`).

With ``slides`` (prismatic pairs, ``{BLOCK = {guide = LINK or ["P", "Q"] or "ground", point = "P", angle =
A}}``: the block, a link of the group, slides without turning on the guide, a link of the group, the placed
link carrying the known points P and Q, or the ground; its ``point`` stays on the guide's line through where
the pose puts it, along ``angle``, the slide's direction at the pose), the group is solved by
:mod:`analytic.solver.prismatic_group` (every link's frame as unknowns). A block's frame is along its slide
(``phiL`` the slide's direction, origin its first point); a link with one point and no slide of its own runs
along the slide it guides. Each pair's ``s`` (named after its block) is measured along the slide from the
guide's first point (``P`` for a placed guide; for the ground, from where the pose puts the block's point).
"""

from __future__ import annotations

import numpy as np

from .._common import ParameterError
from ..solver import general_group as gg
from ..solver import prismatic_group as pg
from .base import Field, Kind, LinkPart, Slide, State, Structure

ROMAN = {2: "II", 3: "III", 4: "IV", 5: "V", 6: "VI", 7: "VII", 8: "VIII"}
START_TOL = 1e-9
"""The pose's known points must lie where the earlier elements put them at the start within this fraction of
the group's size (the pose's rounding in a file is far below it; a mistyped coordinate far above)."""


def _known(f: dict) -> tuple[str, ...]:
    """The known points of the group: every point of its links that it does not place, in order."""
    placed = set(f["points"])
    guides = [p for g, _, _ in f.get("slides", {}).values() if isinstance(g, tuple) for p in g]
    return tuple(dict.fromkeys([p for pts in f["links"].values() for p in pts if p not in placed] + guides))


def _pairs(f: dict) -> tuple[list, list]:
    """The group's internal joints (an unknown point on two of its links: (point, link, link)) and its
    external pairs (a link pinned at a known point: (point, link))."""
    placed = set(f["points"])
    internal, external = [], []
    for p in dict.fromkeys(q for pts in f["links"].values() for q in pts):
        on = [ln for ln, pts in f["links"].items() if p in pts]
        if p in placed:
            internal += [(p, on[0], other) for other in on[1:]]
        else:
            external += [(p, ln) for ln in on]
    for block, (guide, point, _) in f.get("slides", {}).items():
        if isinstance(guide, str) and guide in f["links"]:
            internal.append((f"P{point}", guide, block))
        else:
            external.append((f"P{point}", block))
    return internal, external


def assur_class(f: dict) -> tuple[str, int]:
    """The group's name and Assur class (Artobolevsky): the number of pairs of its largest closed contour,
    or, without one, the most inner pairs on one link (a dyad is class II, a triad's ternary link makes it
    class III)."""
    internal, _ = _pairs(f)
    links = list(f["links"])
    inner = {ln: 0 for ln in links}
    adj = {ln: [] for ln in links}
    for p, a, b in internal:
        inner[a] += 1
        inner[b] += 1
        adj[a].append((b, p))
        adj[b].append((a, p))
    longest = 0

    def dfs(start, node, seen, used, depth):
        nonlocal longest
        for nxt, p in adj[node]:
            if p in used:
                continue
            if nxt == start and depth >= 2:
                longest = max(longest, depth + 1)
            elif nxt not in seen and links.index(nxt) > links.index(start):
                dfs(start, nxt, seen | {nxt}, used | {p}, depth + 1)

    for ln in links:
        dfs(ln, ln, {ln}, frozenset(), 0)
    cls = max(2, longest, max(inner.values(), default=0))
    n = len(links)
    if n == 2:
        name = "dyad"
    elif n == 4 and cls == 3:
        name = "triad"
    elif n == 4 and cls == 4:
        name = "tetrad"
    else:
        name = f"{n}-link group"
    return name, cls


class Group(Kind):
    name = "group"
    summary = ("any Assur group (triad, tetrad, 6-link group...; revolute joints, and prismatic pairs in "
               "`slides`) solved as one group by Newton, dimensioned from its pose; branch held by continuity")
    group_class = "Assur group (numeric)"
    continuous = True
    fields = {"points": Field("news"), "links": Field("linktable"), "pose": Field("pose"),
              "slides": Field("slidetable", {})}

    # ------------------------------------------------------------------------------------ format
    def places(self, f):
        return tuple(f["points"])

    def needs(self, f):
        return _known(f)

    def check(self, f):
        if f["slides"]:
            return _check_slides(f)
        placed = set(f["points"])
        for ln, pts in f["links"].items():
            if len(pts) < 2:
                return f"field 'links': link {ln} has {len(pts)} point(s); a link carries two or more"
            if len(set(pts)) != len(pts):
                return f"field 'links': link {ln} lists a point twice ({', '.join(pts)})"
            if not placed.intersection(pts):
                return (f"field 'links': link {ln} carries only known points ({', '.join(pts)}); it belongs to "
                        f"no group: define it with the elements that place them")
        on = {p for pts in f["links"].values() for p in pts}
        missing = [p for p in f["points"] if p not in on]
        if missing:
            return f"field 'points': {missing[0]} is on none of the links; add it to a link in 'links'"
        equations = sum(2 * len(pts) - 3 for pts in f["links"].values())
        unknowns = 2 * len(f["points"])
        if equations != unknowns:
            return (f"field 'links': not an Assur group: {equations} equations for {unknowns} unknowns (each "
                    f"link of m points gives 2 m - 3, each placed point 2 unknowns); add or remove links or "
                    f"points")
        absent = [p for p in on if p not in f["pose"]]
        if absent:
            return f"field 'pose': no position for point {sorted(absent)[0]}; give its [x, y] at the start"
        extra = [p for p in f["pose"] if p not in on]
        if extra:
            return f"field 'pose': point {extra[0]} is on none of the group's links; remove it from the pose"
        return None

    def check_resolved(self, e, units="m"):
        try:
            group(e)
        except ParameterError as exc:          # the fields as written passed check(): what is left is the pose
            return "field 'pose': " + str(exc).split(": ", 1)[1]
        return None

    def check_start(self, e, st):
        g = group(e)
        worst, which, at = 0.0, None, None
        for i, p in enumerate(g.known):
            x, y = (float(np.ravel(st.points[p][c])[0]) for c in (0, 1))
            d = float(np.hypot(x - g.pose[i, 0], y - g.pose[i, 1]))
            if not d <= worst:
                worst, which, at = d, p, (x, y)
        if which is not None and not worst <= START_TOL * g.size:
            return (f"field 'pose': point {which} is at ({at[0]:.9g}, {at[1]:.9g}) m at the start but the pose "
                    f"puts it {worst:.3g} m away; give the pose where the earlier elements put it")
        return None

    def group_label(self, e):
        name, cls = assur_class(e)
        branch = group(e).branch
        return f"{name} (class {ROMAN.get(cls, cls)}), branch {branch:+d}"

    def extent(self, e):
        """The largest distance between two points of one of its links, in the pose [m]."""
        pose = e["pose"]
        return max(float(np.hypot(pose[p][0] - pose[q][0], pose[p][1] - pose[q][1]))
                   for pts in e["links"].values() for p in pts for q in pts)

    # ---------------------------------------------------------------------------------- topology
    def structure(self, f):
        sl = f["slides"]
        links = tuple(LinkPart(ln, pts[0], tuple(pts), block=ln in sl and len(pts) == 1)
                      for ln, pts in f["links"].items())
        return Structure(links=links, slides=tuple(Slide(b, g, p) for b, (g, p, _) in sl.items()))

    def rails(self, e):
        return tuple((b, {"through": tuple(e["pose"][p]), "angle": a}, 0.0)
                     for b, (g, p, a) in e["slides"].items() if g is None)

    def slide_frames(self, e):
        out = {}
        for b, (g, p, a) in e["slides"].items():
            origin = _slide_origin(e, g, p)
            ox, oy = e["pose"][origin] if isinstance(origin, str) else origin
            x, y = e["pose"][p]
            out[b] = (origin, p, float(np.cos(a) * (y - oy) - np.sin(a) * (x - ox)))
        return out

    # ------------------------------------------------------------------------------------ solver
    def solve(self, e, st: State):
        g = group(e)
        label = e["label"]
        prev = (st.start or {}).get(label)
        engine = pg if e["slides"] else gg
        sol = engine.solve_group(g, {p: st.points[p] for p in g.known}, start=prev)
        st.points.update(sol.points)
        st.links.update(sol.links)
        st.carry[label] = sol.end if sol.end is not None else prev
        for b, (origin, p, offset) in self.slide_frames(e).items():
            st.slides[b] = _slide(st, b, origin, p, offset)

    def singularity(self, e, st, size):
        g = group(e)
        if e["slides"]:
            return pg.singularity(g, {p: st.points[p] for p in g.known + g.unknown},
                                  {ln: st.links[ln] for ln, _ in g.links})
        return gg.singularity(g, {p: st.points[p] for p in g.known + g.unknown})


def group(e: dict):
    """The resolved element's group (a :class:`general_group.GeneralGroup`, or with slides a
    :class:`prismatic_group.PrismaticGroup`), built once (by :meth:`Group.check_resolved`) and kept in ``e``."""
    g = e.get("_group")
    if g is None:
        pose = e["pose"]
        if e["slides"]:
            g = pg.make_group(e["links"], _known(e), e["points"], pose, e["slides"], where=e["label"])
        else:
            g = gg.make_group(e["links"], _known(e), e["points"], pose, where=e["label"])
        e["_group"] = g
    return g


def _check_slides(f: dict) -> str | None:
    """:meth:`Group.check` for a group with prismatic pairs."""
    placed, links, sl = set(f["points"]), f["links"], f["slides"]
    guided = {g for g, _, _ in sl.values() if isinstance(g, str)}
    for ln, pts in links.items():
        if len(set(pts)) != len(pts):
            return f"field 'links': link {ln} lists a point twice ({', '.join(pts)})"
        if not pts or (len(pts) < 2 and ln not in sl and ln not in guided):
            return (f"field 'links': link {ln} has {len(pts)} point(s) and no slide; a link carries two or more, "
                    f"or one and a prismatic pair")
    for b, (g, p, _) in sl.items():
        if b not in links:
            return f"field 'slides': block {b} is not a link of the group; list it in 'links'"
        if p not in links[b]:
            return f"field 'slides': the point {p} of block {b} is not on it; list it among {b}'s points"
        if isinstance(g, str) and (g not in links or g == b):
            return (f"field 'slides': the guide {g} of block {b} is not another link of the group; give a link "
                    f"of the group, two known points [\"P\", \"Q\"] of a placed link, or \"ground\"")
        if isinstance(g, tuple) and placed.intersection(g):
            return f"field 'slides': the guide {list(g)} of block {b} must be two known points of a placed link"
    on = {p for pts in links.values() for p in pts}
    missing = [p for p in f["points"] if p not in on]
    if missing:
        return f"field 'points': {missing[0]} is on none of the links; add it to a link in 'links'"
    rows = 2 * len(sl)
    for p in on:
        k = sum(p in pts for pts in links.values())
        rows += 2 * (k - 1) if p in placed else 2 * k
    if rows != 3 * len(links):
        return (f"field 'links': not an Assur group: {rows} equations for {3 * len(links)} unknowns (3 per link; "
                f"2 per pin between two links, per known point on a link and per slide); add or remove links, "
                f"points or slides")
    need = on | {p for g, _, _ in sl.values() if isinstance(g, tuple) for p in g}
    absent = [p for p in need if p not in f["pose"]]
    if absent:
        return f"field 'pose': no position for point {sorted(absent)[0]}; give its [x, y] at the start"
    extra = [p for p in f["pose"] if p not in need]
    if extra:
        return f"field 'pose': point {extra[0]} is on none of the group's links; remove it from the pose"
    return None


def _slide_origin(e: dict, guide, point):
    """Where a pair's ``s`` is measured from: the guide's first point, or (the ground) the pose's point."""
    if guide is None:
        return tuple(float(c) for c in e["pose"][point])
    if isinstance(guide, tuple):
        return guide[0]
    return e["links"][guide][0]


def _slide(st: State, block: str, origin, point: str, offset: float):
    """(s, ds, dds) of a block from the solved points and its angle: s = (P - O) . u, ds = (vP - vO) . u +
    offset w, dds = (aP - aO) . u + s w^2 + offset a (the point on the line ``offset`` left of O)."""
    P = st.points[point]
    O = st.points[origin] if isinstance(origin, str) else (origin[0], origin[1], 0.0, 0.0, 0.0, 0.0)
    c, s_, w, a = st.links[block]
    s = (P[0] - O[0]) * c + (P[1] - O[1]) * s_
    ds = (P[2] - O[2]) * c + (P[3] - O[3]) * s_ + offset * w
    dds = (P[4] - O[4]) * c + (P[5] - O[5]) * s_ + s * w * w + offset * a
    return s, ds, dds


KIND = Group()
