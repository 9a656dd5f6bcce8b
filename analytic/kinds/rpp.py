"""``RPP``: a block pinned at a known point slides in a slot of a link that itself slides on a guide line
(the Scotch yoke's dyad; line-line intersection).

Fields: ``point`` C (where the slot crosses the guide line: the slotted link's point on it), ``through`` P
(the block's pin, a point that exists), ``guide`` (the line P->Q of a link, or a ground line),
``offset`` (the slotted link's line shifted that far to the guide's left), ``angle`` (the slot's direction
relative to the guide's; default 90deg, the Scotch yoke), ``links`` [block, yoke] (the chain's order: the
block at the R end, the slotted link on the guide). The yoke slides by ``s`` from the guide's origin (its
first point, or ``through``) and its angle is the guide's; the block slides in the slot by ``s`` from C to
P and its angle is the slot's. Both turn with the guide. No branch (the lines meet once); a slot parallel
to its guide (``angle`` 0 or 180deg) is refused.
"""

from __future__ import annotations

import math

from . import _lines
from . import compiled as C
from ._lines import meet as _meet_row
from .base import Field, JitSpec, Kind, LinkPart, Slide, State, Structure, guide_line, guide_link, slide_origin


class RPP(Kind):
    name = "RPP"
    summary = ("a block pinned at `through` slides in a slot (at `angle` to the guide) of a yoke sliding on the "
               "guide; point where the slot crosses the guide (Scotch yoke)")
    group_class = "dyad RPP (class II)"
    fields = {"point": Field("new"), "through": Field("point"), "guide": Field("guide"),
              "offset": Field("length", 0.0), "angle": Field("angle", math.pi / 2),
              "links": Field("links2", ("{through}_block", "{point}_yoke"))}

    def needs(self, f):
        return (f["through"],) + f["guide"].uses()

    def check_resolved(self, e, units="m"):
        return _lines.check_slot_angle(e)

    def structure(self, f):
        (block, yoke), c, p = f["links"], f["point"], f["through"]
        return Structure(links=(LinkPart(block, p, (p,), block=True), LinkPart(yoke, c, (c,), block=True)),
                         slides=(Slide(yoke, guide_link(f["guide"]), c), Slide(block, yoke, p)))

    def rails(self, e):
        return ((e["links"][1], e["guide"], e["offset"]),) if "points" not in e["guide"] else ()

    def slide_frames(self, e):
        (block, yoke), c = e["links"], e["point"]
        return {yoke: (slide_origin(e["guide"]), c, e["offset"]), block: (c, e["through"], 0.0)}

    def solve(self, e, st: State):
        C_, on_guide, in_slot, s_yoke, s_block = _lines.pin_in_slot(
            guide_line(e["guide"], st), e["offset"], e["angle"], st.points[e["through"]])
        block, yoke = e["links"]
        st.points[e["point"]] = _lines.samples(C_, st.n)
        st.links[block] = _lines.samples(in_slot, st.n)
        st.links[yoke] = _lines.samples(on_guide, st.n)
        st.slides[block] = _lines.samples(s_block, st.n)
        st.slides[yoke] = _lines.samples(s_yoke, st.n)

    def singularity(self, e, st, size):
        # the sin of the angle between slot and guide: constant, as the slot turns with the guide (NaN where
        # the element failed)
        return abs(math.sin(e["angle"])) + 0.0 * st.points[e["point"]][0]


# ----------------------------------------------------------------------------------- compiled row
def _layout(e, L, row, par):
    block, yoke = e["links"]
    _lines.layout_pin_in_slot(e, L, row, par, on_guide=yoke, in_slot=block)


def _kernel(st, m, e, ops, par, q, qd, qdd, step, i0, need):
    n, p, o, Lg, Ls, Sg, Ss = ops[e, 1], ops[e, 2], ops[e, 6], ops[e, 3], ops[e, 4], ops[e, 8], ops[e, 9]
    offset, ca, sa = par[e, 0], par[e, 1], par[e, 4]
    for i in range(m):
        c, s, w, a = C.guide(st, e, ops, par, i)
        A = C.frame(st[o, i], st[o + 1, i], st[o + 2, i], st[o + 3, i], st[o + 4, i], st[o + 5, i],
                    c, s, w, a, 0.0, offset)
        cv = c * ca - s * sa
        sv = s * ca + c * sa
        P = (st[p, i], st[p + 1, i], st[p + 2, i], st[p + 3, i], st[p + 4, i], st[p + 5, i])
        X, g, t = _meet_row(A, c, s, w, a, P, cv, sv, w, a)
        C.put(st, n, i, X[0], X[1], X[2], X[3], X[4], X[5])
        C.put4(st, Lg, i, c, s, w, a)
        C.put4(st, Ls, i, cv, sv, w, a)
        st[Sg, i] = g[0]
        st[Sg + 1, i] = g[1]
        st[Sg + 2, i] = g[2]
        st[Ss, i] = -t[0]
        st[Ss + 1, i] = -t[1]
        st[Ss + 2, i] = -t[2]


KIND = RPP()
KIND.jit = JitSpec(_layout, _kernel, helpers=("_meet_row",))
