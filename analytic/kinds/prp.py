"""``PRP``: two blocks, each sliding on a guide line of a link that exists, pinned together at the point
they place (line-line intersection).

Fields: ``point`` C (where the two lines meet: the blocks' common pin), ``guide1`` and ``guide2`` (each the
line P->Q of a link or a ground line, as an RRP's ``guide``), ``offset1`` and ``offset2`` (each block's line
shifted that far to its guide's left), ``links`` [block1, block2]. Block k slides by ``s`` from its guide's
origin (its first point, or ``through``); its angle is its guide's. No branch: two lines meet once, and
not at all where they are parallel (two parallel ground guides are refused when the file is resolved).
"""

from __future__ import annotations

import math

import numpy as np

from . import _lines
from . import compiled as C
from ._lines import meet as _meet_row
from .base import (Field, JitSpec, Kind, LinkPart, Slide, State, Structure, guide_line, guide_link, on_frame,
                   slide_origin)


class PRP(Kind):
    name = "PRP"
    summary = "two blocks on two guides (each shifted its offset to the left) pinned together where the lines meet"
    group_class = "dyad PRP (class II)"
    fields = {"point": Field("new"), "guide1": Field("guide"), "offset1": Field("length", 0.0),
              "guide2": Field("guide"), "offset2": Field("length", 0.0),
              "links": Field("links2", ("{point}_block1", "{point}_block2"))}

    def needs(self, f):
        return f["guide1"].uses() + f["guide2"].uses()

    def check(self, f):
        if f["guide1"].points and f["guide1"].points == f["guide2"].points:
            return "field 'guide2': the same line as guide1; the two guides must cross"
        return None

    def check_resolved(self, e, units="m"):
        g1, g2 = e["guide1"], e["guide2"]
        if "angle" in g1 and "angle" in g2 and abs(math.sin(g2["angle"] - g1["angle"])) < _lines.PARALLEL:
            return (f"field 'guide2': parallel to guide1 (ground lines at {math.degrees(g1['angle']):.6g} and "
                    f"{math.degrees(g2['angle']):.6g} deg never meet); give guides that cross")
        return None

    def structure(self, f):
        (b1, b2), c = f["links"], f["point"]
        return Structure(links=(LinkPart(b1, c, (c,), block=True), LinkPart(b2, c, (c,), block=True)),
                         slides=(Slide(b1, guide_link(f["guide1"]), c), Slide(b2, guide_link(f["guide2"]), c)))

    def rails(self, e):
        return tuple((b, e[g], e[o]) for b, g, o in zip(e["links"], ("guide1", "guide2"), ("offset1", "offset2"))
                     if "points" not in e[g])

    def slide_frames(self, e):
        (b1, b2), c = e["links"], e["point"]
        return {b1: (slide_origin(e["guide1"]), c, e["offset1"]), b2: (slide_origin(e["guide2"]), c, e["offset2"])}

    def solve(self, e, st: State):
        O1, c1, s1, w1, a1 = guide_line(e["guide1"], st)
        O2, c2, s2, w2, a2 = guide_line(e["guide2"], st)
        A1 = on_frame(O1, c1, s1, w1, a1, 0.0, e["offset1"])
        A2 = on_frame(O2, c2, s2, w2, a2, 0.0, e["offset2"])
        C_, slide1, slide2 = _lines.meet(A1, c1, s1, w1, a1, A2, c2, s2, w2, a2)
        b1, b2 = e["links"]
        st.points[e["point"]] = _lines.samples(C_, st.n)
        st.links[b1] = _lines.samples((c1, s1, w1, a1), st.n)
        st.links[b2] = _lines.samples((c2, s2, w2, a2), st.n)
        st.slides[b1] = _lines.samples(slide1, st.n)
        st.slides[b2] = _lines.samples(slide2, st.n)

    def singularity(self, e, st, size):
        c1, s1, _, _ = st.links[e["links"][0]]
        c2, s2, _, _ = st.links[e["links"][1]]
        return np.abs(c1 * s2 - s1 * c2)            # sin of the angle between the guides


# ----------------------------------------------------------------------------------- compiled row
def _layout(e, L, row, par):
    par[0], par[1] = e["offset1"], e["offset2"]
    L.guide(row, par, e["guide1"])                  # row[5:8], par[2:4]
    _lines.layout_second_guide(L, row, par, e["guide2"], 9, 4)   # row[9:12], par[4:6]
    row[2] = L.new_link(e["links"][0])
    row[3] = L.new_link(e["links"][1])
    row[4] = L.new_slide(e["links"][0])
    row[8] = L.new_slide(e["links"][1])
    L.new_point(e["point"])


def _kernel(st, m, e, ops, par, q, qd, qdd, step, i0, need):
    n, L1, L2, S1, S2 = ops[e, 1], ops[e, 2], ops[e, 3], ops[e, 4], ops[e, 8]
    o1, o2 = ops[e, 6], ops[e, 10]
    off1, off2 = par[e, 0], par[e, 1]
    line2 = ops[e, 9] == C.G_LINE
    for i in range(m):
        c1, s1, w1, a1 = C.guide(st, e, ops, par, i)
        if line2:
            c2, s2, w2, a2 = C.line(st, ops[e, 10], ops[e, 11], i)
        else:
            c2, s2, w2, a2 = par[e, 4], par[e, 5], 0.0, 0.0
        A1 = C.frame(st[o1, i], st[o1 + 1, i], st[o1 + 2, i], st[o1 + 3, i], st[o1 + 4, i], st[o1 + 5, i],
                     c1, s1, w1, a1, 0.0, off1)
        A2 = C.frame(st[o2, i], st[o2 + 1, i], st[o2 + 2, i], st[o2 + 3, i], st[o2 + 4, i], st[o2 + 5, i],
                     c2, s2, w2, a2, 0.0, off2)
        P, sl1, sl2 = _meet_row(A1, c1, s1, w1, a1, A2, c2, s2, w2, a2)
        C.put(st, n, i, P[0], P[1], P[2], P[3], P[4], P[5])
        C.put4(st, L1, i, c1, s1, w1, a1)
        C.put4(st, L2, i, c2, s2, w2, a2)
        st[S1, i] = sl1[0]
        st[S1 + 1, i] = sl1[1]
        st[S1 + 2, i] = sl1[2]
        st[S2, i] = sl2[0]
        st[S2 + 1, i] = sl2[1]
        st[S2 + 2, i] = sl2[2]


KIND = PRP()
KIND.jit = JitSpec(_layout, _kernel, helpers=("_meet_row",))
