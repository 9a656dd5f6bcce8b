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
"""

from __future__ import annotations

import numpy as np

from .._common import ParameterError
from ..solver import general_group as gg
from .base import Field, Kind, LinkPart, State, Structure

ROMAN = {2: "II", 3: "III", 4: "IV", 5: "V", 6: "VI", 7: "VII", 8: "VIII"}
START_TOL = 1e-9
"""The pose's known points must lie where the earlier elements put them at the start within this fraction of
the group's size (the pose's rounding in a file is far below it; a mistyped coordinate far above)."""


def _known(f: dict) -> tuple[str, ...]:
    """The known points of the group: every point of its links that it does not place, in order."""
    placed = set(f["points"])
    return tuple(dict.fromkeys(p for pts in f["links"].values() for p in pts if p not in placed))


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
    summary = ("any Assur group of revolute joints (triad, tetrad, 6-link group...) solved as one group by "
               "Newton, dimensioned from its pose; branch held by continuity")
    group_class = "Assur group (numeric)"
    continuous = True
    fields = {"points": Field("news"), "links": Field("linktable"), "pose": Field("pose")}

    # ------------------------------------------------------------------------------------ format
    def places(self, f):
        return tuple(f["points"])

    def needs(self, f):
        return _known(f)

    def check(self, f):
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

    def check_resolved(self, e):
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
        return Structure(links=tuple(LinkPart(ln, pts[0], tuple(pts)) for ln, pts in f["links"].items()))

    # ------------------------------------------------------------------------------------ solver
    def solve(self, e, st: State):
        g = group(e)
        label = e["label"]
        prev = (st.start or {}).get(label)
        sol = gg.solve_group(g, {p: st.points[p] for p in g.known}, start=prev)
        st.points.update(sol.points)
        st.links.update(sol.links)
        st.carry[label] = sol.end if sol.end is not None else prev

    def singularity(self, e, st, size):
        g = group(e)
        return gg.singularity(g, {p: st.points[p] for p in g.known + g.unknown})


def group(e: dict) -> gg.GeneralGroup:
    """The resolved element's group, built once (by :meth:`Group.check_resolved`) and kept in ``e``."""
    g = e.get("_group")
    if g is None:
        pose = e["pose"]
        g = gg.make_group(e["links"], _known(e), e["points"], pose, where=e["label"])
        e["_group"] = g
    return g


KIND = Group()
