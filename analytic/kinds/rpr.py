"""``RPR``: a slotted link pivoted at a known point whose slot passes through a block pinned at a second
known point (a line through a pivot).

Fields: ``pivot`` P, ``through`` Q, ``point`` (placed on the slotted link at ``length`` from P along the
slot), ``offset`` (the slot shifted that far to the left of P -> Q), ``links`` [slotted, block],
``branch`` (picks the side when offset != 0). The block slides by ``s`` = the distance P -> Q along the slot;
both links' angle is the slot's direction.
"""

from __future__ import annotations

import math

import numpy as np

from . import compiled as C
from .base import Field, JitSpec, Kind, LinkPart, Slide, State, Structure, on_frame


class RPR(Kind):
    name = "RPR"
    summary = ("a slotted link pivoted at P whose slot (shifted offset left) passes a block pinned at Q; "
               "point at length from P along the slot")
    group_class = "dyad RPR (class II)"
    fields = {"pivot": Field("point"), "through": Field("point"), "point": Field("new"), "length": Field("size"),
              "offset": Field("length", 0.0), "links": Field("links2", ("{pivot}{point}", "{through}_block")),
              "branch": Field("branch", 1)}

    def needs(self, f):
        return (f["pivot"], f["through"])

    def structure(self, f):
        (slotted, block), p, q = f["links"], f["pivot"], f["through"]
        return Structure(links=(LinkPart(slotted, p, (p, f["point"])), LinkPart(block, q, (q,), block=True)),
                         slides=(Slide(block, slotted, q),))

    def slide_frames(self, e):
        return {e["links"][1]: (e["pivot"], e["through"], e["offset"])}

    def solve(self, e, st: State):
        R, slot, slide = rpr(st.points[e["pivot"]], st.points[e["through"]], e["length"], e["offset"], e["branch"])
        st.points[e["point"]] = R
        st.links[e["links"][0]] = st.links[e["links"][1]] = slot
        st.slides[e["links"][1]] = slide

    def singularity(self, e, st, size):
        return np.abs(st.slides[e["links"][1]][0]) / size

    def forces(self, e, ctx):
        """Closed form. The block's moment about its pin Q gives the slot's couple M on it; with d = Q - P,
        the slotted link's moment about its pivot P gives the slot's normal force N n on the block:
        N (d . u) = M_slotted(P) - M (zero where the block passes the pivot); the pins carry the rest."""
        slotted, block = e["links"]
        p, q = e["pivot"], e["through"]
        c, s = ctx.direction(block)
        px, py = ctx.xy(p)
        qx, qy = ctx.xy(q)
        dx, dy = qx - px, qy - py
        couple = -ctx.moment(block, q)
        normal = ctx.moment(slotted, p) - couple
        normal /= dx * c + dy * s
        nx, ny = -s * normal, c * normal
        ctx.guide(block, nx, ny, couple)
        wb, wk = ctx.resultant(block), ctx.resultant(slotted)
        ctx.pin(q, block, -wb[0] - nx, -wb[1] - ny)
        ctx.pin(p, slotted, nx - wk[0], ny - wk[1])


def rpr(P, Q, length, offset, branch):
    """Slotted link pivoted at P whose slot (shifted ``offset`` to the left) passes through Q.
    Returns the new point at ``length`` along the slot, the slotted link, and the block's (s, ds, dds)
    with s the distance P -> Q along the slot."""
    dx, dy = Q[0] - P[0], Q[1] - P[1]
    d2 = dx * dx + dy * dy
    s = branch * np.sqrt(d2 - offset * offset)
    c, sn = (s * dx + offset * dy) / d2, (s * dy - offset * dx) / d2
    vdx, vdy = Q[2] - P[2], Q[3] - P[3]
    w = (-vdx * sn + vdy * c) / s
    ds = vdx * c + vdy * sn + offset * w
    adx, ady = Q[4] - P[4], Q[5] - P[5]
    a = (-adx * sn + ady * c - 2.0 * ds * w + offset * w * w) / s
    dds = adx * c + ady * sn + s * w * w + offset * a
    R = on_frame(P, c, sn, w, a, length, 0.0)
    return R, (c, sn, w, a), (s, ds, dds)


# ----------------------------------------------------------------------------------- compiled row
def _layout(e, L, row, par):
    row[2], row[3] = L.point(e["pivot"]), L.point(e["through"])
    par[0], par[1], par[4] = e["length"], e["offset"], e["branch"]
    row[4] = L.new_link(e["links"][0])
    L.new_link(e["links"][1], row[4])                # the block turns with the slot: the same slots
    row[8] = L.new_slide(e["links"][1])
    L.new_point(e["point"])


def _kernel(st, m, e, ops, par, q, qd, qdd, step, i0, need):
    n, p, pq, L, sl = ops[e, 1], ops[e, 2], ops[e, 3], ops[e, 4], ops[e, 8]
    length, offset, branch = par[e, 0], par[e, 1], par[e, 4]
    for i in range(m):
        dx = st[pq, i] - st[p, i]
        dy = st[pq + 1, i] - st[p + 1, i]
        d2 = dx * dx + dy * dy
        s = branch * math.sqrt(d2 - offset * offset)
        c = (s * dx + offset * dy) / d2
        sn = (s * dy - offset * dx) / d2
        vdx = st[pq + 2, i] - st[p + 2, i]
        vdy = st[pq + 3, i] - st[p + 3, i]
        w = (-vdx * sn + vdy * c) / s
        ds = vdx * c + vdy * sn + offset * w
        adx = st[pq + 4, i] - st[p + 4, i]
        ady = st[pq + 5, i] - st[p + 5, i]
        a = (-adx * sn + ady * c - 2.0 * ds * w + offset * w * w) / s
        dds = adx * c + ady * sn + s * w * w + offset * a
        x0, x1, x2, x3, x4, x5 = C.frame(st[p, i], st[p + 1, i], st[p + 2, i], st[p + 3, i], st[p + 4, i],
                                         st[p + 5, i], c, sn, w, a, length, 0.0)
        C.put(st, n, i, x0, x1, x2, x3, x4, x5)
        C.put4(st, L, i, c, sn, w, a)
        st[sl, i] = s
        st[sl + 1, i] = ds
        st[sl + 2, i] = dds


KIND = RPR()
KIND.jit = JitSpec(_layout, _kernel)
