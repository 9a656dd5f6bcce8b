"""``PPR``: a link slides on a guide line and carries a slot at an angle to it, in which a block pinned at a
known point slides (the ``RPP`` chain read from its other end; line-line intersection).

Fields: ``point`` C (where the slot crosses the guide line: the sliding link's point on it), ``guide``
(the line P->Q of a link, or a ground line), ``offset`` (the sliding link's line shifted that far to the
guide's left), ``angle`` (the slot's direction relative to the guide's; default 90deg), ``through`` Q (the
block's pin, a point that exists), ``links`` [slider, block] (the chain's order: the slotted link on the
guide, the block at the R end). The slider slides by ``s`` from the guide's origin (its first point, or
``through``) and its angle is the guide's; the block slides in the slot by ``s`` from C to Q and its angle
is the slot's. Both turn with the guide. No branch; a slot parallel to its guide is refused.
"""

from __future__ import annotations

import math

from . import _lines
from . import compiled as C
from ._lines import meet as _meet_row
from .base import Field, JitSpec, Kind, LinkPart, Slide, State, Structure, guide_line, guide_link, slide_origin


class PPR(Kind):
    name = "PPR"
    summary = ("a slider on the guide carrying a slot (at `angle` to the guide) in which a block pinned at "
               "`through` slides; point where the slot crosses the guide")
    group_class = "dyad PPR (class II)"
    fields = {"point": Field("new"), "guide": Field("guide"), "offset": Field("length", 0.0),
              "angle": Field("angle", math.pi / 2), "through": Field("point"),
              "links": Field("links2", ("{point}_slider", "{through}_block"))}

    def needs(self, f):
        return f["guide"].uses() + (f["through"],)

    def check_resolved(self, e, units="m"):
        return _lines.check_slot_angle(e)

    def structure(self, f):
        (slider, block), c, q = f["links"], f["point"], f["through"]
        return Structure(links=(LinkPart(slider, c, (c,), block=True), LinkPart(block, q, (q,), block=True)),
                         slides=(Slide(slider, guide_link(f["guide"]), c), Slide(block, slider, q)))

    def rails(self, e):
        return ((e["links"][0], e["guide"], e["offset"]),) if "points" not in e["guide"] else ()

    def slide_frames(self, e):
        (slider, block), c = e["links"], e["point"]
        return {slider: (slide_origin(e["guide"]), c, e["offset"]), block: (c, e["through"], 0.0)}

    def solve(self, e, st: State):
        C_, on_guide, in_slot, s_slider, s_block = _lines.pin_in_slot(
            guide_line(e["guide"], st), e["offset"], e["angle"], st.points[e["through"]])
        slider, block = e["links"]
        st.points[e["point"]] = _lines.samples(C_, st.n)
        st.links[slider] = _lines.samples(on_guide, st.n)
        st.links[block] = _lines.samples(in_slot, st.n)
        st.slides[slider] = _lines.samples(s_slider, st.n)
        st.slides[block] = _lines.samples(s_block, st.n)

    def singularity(self, e, st, size):
        # the sin of the angle between slot and guide: constant, as the slot turns with the guide (NaN where
        # the element failed)
        return abs(math.sin(e["angle"])) + 0.0 * st.points[e["point"]][0]


# ----------------------------------------------------------------------------------- compiled row
def _layout(e, L, row, par):
    slider, block = e["links"]
    _lines.layout_pin_in_slot(e, L, row, par, on_guide=slider, in_slot=block)


def _kernel(st, m, e, ops, par, q, qd, qdd, step, i0, need):
    n, p, o, Lg, Ls, Sg, Ss = ops[e, 1], ops[e, 2], ops[e, 6], ops[e, 3], ops[e, 4], ops[e, 8], ops[e, 9]
    offset, ca, sa = par[e, 0], par[e, 1], par[e, 4]
    for i in range(m):
        c, s, w, a = C.guide(st, e, ops, par, i)
        A = C.frame(st[o, i], st[o + 1, i], st[o + 2, i], st[o + 3, i], st[o + 4, i], st[o + 5, i],
                    c, s, w, a, 0.0, offset)
        cv = c * ca - s * sa
        sv = s * ca + c * sa
        Q = (st[p, i], st[p + 1, i], st[p + 2, i], st[p + 3, i], st[p + 4, i], st[p + 5, i])
        X, g, t = _meet_row(A, c, s, w, a, Q, cv, sv, w, a)
        C.put(st, n, i, X[0], X[1], X[2], X[3], X[4], X[5])
        C.put4(st, Lg, i, c, s, w, a)
        C.put4(st, Ls, i, cv, sv, w, a)
        st[Sg, i] = g[0]
        st[Sg + 1, i] = g[1]
        st[Sg + 2, i] = g[2]
        st[Ss, i] = -t[0]
        st[Ss + 1, i] = -t[1]
        st[Ss + 2, i] = -t[2]


KIND = PPR()
KIND.jit = JitSpec(_layout, _kernel, helpers=("_meet_row",))
