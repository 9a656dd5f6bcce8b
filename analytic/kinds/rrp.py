"""``RRP``: a rod from a known point whose end is pinned to a block sliding on a guide line
(circle-line intersection).

Fields: ``point`` (the rod's end and the block's pin), ``from`` P, ``length`` |P point|, ``guide`` (the line
P->Q of a link, or a ground line), ``offset`` (the block's line shifted that far to the guide's left),
``links`` [rod, block], ``branch`` (+1: the intersection farther along the guide's direction). The block
slides by ``s`` from the guide's origin (its first point, or ``through``); its angle is the guide's.

Its own output: ``muC`` (C the placed point), the transmission angle between the rod and the guide's normal in
[0, pi/2]: 90 deg where the rod lies along the guide (the block pushed straight), 0 where it stands across it
(the dyad folds; :meth:`RRP.singularity` is its sine).
"""

from __future__ import annotations

import math

import numpy as np

from ..quantities import ANGLE
from . import compiled as C
from .base import (ExtraOutput, Field, JitSpec, Kind, LinkPart, Slide, State, Structure, guide_line, guide_link,
                   link_from, on_frame, slide_origin)


class RRP(Kind):
    name = "RRP"
    summary = "a rod P-point pinned to a block on the guide (shifted offset to its left; circle-line)"
    group_class = "dyad RRP (class II)"
    fields = {"point": Field("new"), "from": Field("point"), "length": Field("size"), "guide": Field("guide"),
              "offset": Field("length", 0.0), "links": Field("links2", ("{from}{point}", "{point}_block")),
              "branch": Field("branch", 1)}

    def needs(self, f):
        return (f["from"],) + f["guide"].uses()

    def structure(self, f):
        (rod, block), c = f["links"], f["point"]
        return Structure(links=(LinkPart(rod, f["from"], (f["from"], c)), LinkPart(block, c, (c,), block=True)),
                         slides=(Slide(block, guide_link(f["guide"]), c),))

    def extra_outputs(self, e):
        return (ExtraOutput("mu" + e["point"], ANGLE, "transmission angle at " + e["point"], e["point"]),)

    def rails(self, e):
        return ((e["links"][1], e["guide"], e["offset"]),) if "points" not in e["guide"] else ()

    def slide_frames(self, e):
        return {e["links"][1]: (slide_origin(e["guide"]), e["point"], e["offset"])}

    def solve(self, e, st: State):
        guide = guide_line(e["guide"], st)
        C_, rod, block, slide = rrp(st.points[e["from"]], guide, e["length"], e["offset"], e["branch"])
        rod_name, block_name = e["links"]
        st.points[e["point"]] = C_
        st.links[rod_name] = rod
        zero = np.zeros(np.shape(C_[0]))
        st.links[block_name] = tuple(zero + x for x in block)
        st.slides[block_name] = slide
        if st.extras_wanted:
            st.extras["mu" + e["point"]] = transmission(st.points[e["from"]], C_, block[0], block[1])

    def measured_extras(self, e, st):
        c, s = st.links[e["links"][1]][:2]
        return {"mu" + e["point"]: transmission(st.points[e["from"]], st.points[e["point"]], c, s)}

    def singularity(self, e, st, size):
        P, Cp = st.points[e["from"]], st.points[e["point"]]
        c, s, _, _ = st.links[e["links"][1]]
        return np.abs((Cp[0] - P[0]) * c + (Cp[1] - P[1]) * s) / e["length"]

    def forces(self, e, ctx):
        """Closed form. The block's moment about its pin C gives the guide's couple; with r = C - P and the
        guide's normal force N n (n the guide's left normal), the rod's moment about P gives
        N = -(M_rod(P) + r x W_block) / (r . u) (zero denominator: the rod across the guide); the rod's pin C
        and its pin at P carry the rest."""
        rod, block = e["links"]
        p, point = e["from"], e["point"]
        c, s = ctx.direction(block)
        px, py = ctx.xy(p)
        cx, cy = ctx.xy(point)
        rx, ry = cx - px, cy - py
        wb, wr = ctx.resultant(block), ctx.resultant(rod)
        normal = ctx.moment(rod, p) + rx * wb[1] - ry * wb[0]
        normal /= -(rx * c + ry * s)
        nx, ny = -s * normal, c * normal
        ctx.guide(block, nx, ny, -ctx.moment(block, point))
        fcx, fcy = -wb[0] - nx, -wb[1] - ny         # the rod's force on the block at C
        ctx.pin(point, block, fcx, fcy, other=rod)
        ctx.pin(p, rod, fcx - wr[0], fcy - wr[1])


def transmission(P, C, c, s):
    """The angle between the rod P -> C and the normal of a guide of direction (c, s), in [0, pi/2]: its
    cosine is the rod's share across the guide |r x u| / |r|, its sine the share along it |r . u| / |r|."""
    rx, ry = C[0] - P[0], C[1] - P[1]
    return np.arctan2(np.abs(rx * c + ry * s), np.abs(rx * s - ry * c))


def rrp(P, guide, length, offset, branch):
    """C on the guide line (shifted ``offset`` to its left) with |C - P| = length; branch +1 takes the
    intersection farther along the guide. Returns C, the rod link, the block's (c, s, w, a) and its
    (s, ds, dds), with the Coriolis term 2 ds w where the guide turns."""
    O, c, s, w, a = guide
    Oe = on_frame(O, c, s, w, a, 0.0, offset)
    wx, wy = P[0] - Oe[0], P[1] - Oe[1]
    wu = wx * c + wy * s
    disc = wu * wu - (wx * wx + wy * wy) + length * length
    sd = wu + branch * np.sqrt(disc)
    C0 = on_frame(Oe, c, s, w, a, sd, 0.0)        # the guide's point at C (moves with the guide)
    rx, ry = C0[0] - P[0], C0[1] - P[1]
    ru = rx * c + ry * s
    ds = -(rx * (C0[2] - P[2]) + ry * (C0[3] - P[3])) / ru
    vx, vy = C0[2] + ds * c, C0[3] + ds * s
    # relative to the guide: a = a_guide_point + dds u + 2 ds w u_perp
    ax0, ay0 = C0[4] - 2.0 * ds * w * s, C0[5] + 2.0 * ds * w * c
    ux, uy = vx - P[2], vy - P[3]
    dds = -(rx * (ax0 - P[4]) + ry * (ay0 - P[5]) + ux * ux + uy * uy) / ru
    C = (C0[0], C0[1], vx, vy, ax0 + dds * c, ay0 + dds * s)
    return C, link_from(P, C, length), (c, s, w, a), (sd, ds, dds)


# ----------------------------------------------------------------------------------- compiled row
def _layout(e, L, row, par):
    row[2] = L.point(e["from"])
    par[0], par[1], par[4] = e["length"], e["offset"], e["branch"]
    L.guide(row, par, e["guide"])
    row[3] = L.new_link(e["links"][0])
    row[4] = L.new_link(e["links"][1])
    row[8] = L.new_slide(e["links"][1])
    row[9] = L.new_extra("mu" + e["point"], 2, L.OUT_ABS_ANGLE)   # along, across: mu = atan2(|along|, |across|)
    L.new_point(e["point"])


def _kernel(st, m, e, ops, par, q, qd, qdd, step, i0, need):
    n, p, o, Lr, Lb, sl, mu = ops[e, 1], ops[e, 2], ops[e, 6], ops[e, 3], ops[e, 4], ops[e, 8], ops[e, 9]
    length, offset, branch = par[e, 0], par[e, 1], par[e, 4]
    l2 = length * length
    for i in range(m):
        c, s, w, a = C.guide(st, e, ops, par, i)
        oe0, oe1, oe2, oe3, oe4, oe5 = C.frame(st[o, i], st[o + 1, i], st[o + 2, i], st[o + 3, i],
                                               st[o + 4, i], st[o + 5, i], c, s, w, a, 0.0, offset)
        px, py, pvx, pvy, pax, pay = st[p, i], st[p + 1, i], st[p + 2, i], st[p + 3, i], st[p + 4, i], st[p + 5, i]
        wx = px - oe0
        wy = py - oe1
        wu = wx * c + wy * s
        disc = wu * wu - (wx * wx + wy * wy) + length * length
        sd = wu + branch * math.sqrt(disc)
        c0, c1, c2, c3, c4, c5 = C.frame(oe0, oe1, oe2, oe3, oe4, oe5, c, s, w, a, sd, 0.0)
        rx = c0 - px
        ry = c1 - py
        ru = rx * c + ry * s
        ds = -(rx * (c2 - pvx) + ry * (c3 - pvy)) / ru
        vx = c2 + ds * c
        vy = c3 + ds * s
        ax0 = c4 - 2.0 * ds * w * s
        ay0 = c5 + 2.0 * ds * w * c
        ux = vx - pvx
        uy = vy - pvy
        dds = -(rx * (ax0 - pax) + ry * (ay0 - pay) + ux * ux + uy * uy) / ru
        ax = ax0 + dds * c
        ay = ay0 + dds * s
        C.put(st, n, i, c0, c1, vx, vy, ax, ay)
        C.put4(st, Lr, i, rx / length, ry / length, (rx * (vy - pvy) - ry * (vx - pvx)) / l2,
               (rx * (ay - pay) - ry * (ax - pax)) / l2)
        C.put4(st, Lb, i, c, s, w, a)
        st[sl, i] = sd
        st[sl + 1, i] = ds
        st[sl + 2, i] = dds
        st[mu, i] = ru
        st[mu + 1, i] = rx * s - ry * c


KIND = RRP()
KIND.jit = JitSpec(_layout, _kernel)
