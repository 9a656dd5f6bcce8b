"""``RRR``: a dyad of two links pinned at the point it places (circle-circle intersection).

Fields: ``point``, ``from`` [P, Q] (the known points), ``lengths`` [a, b] (|P point|, |Q point|), ``links``
[m, n] (the links P-point and Q-point), ``branch`` (+1: the point left of the directed line P -> Q).
Its own output: ``muP`` (P the placed point), the transmission angle between the two links in [0, pi/2].
"""

from __future__ import annotations

import math

import numpy as np

from ..quantities import ANGLE
from . import compiled as C
from .base import ExtraOutput, Field, JitSpec, Kind, LinkPart, State, Structure


class RRR(Kind):
    name = "RRR"
    summary = "links P-point and Q-point pinned at point (circle-circle)"
    group_class = "dyad RRR (class II)"
    fields = {"point": Field("new"), "from": Field("pair"), "lengths": Field("lengths2"),
              "links": Field("links2", ("{from0}{point}", "{from1}{point}")), "branch": Field("branch", 1)}

    def needs(self, f):
        return tuple(f["from"])

    def structure(self, f):
        (p, q), (m, n), c = f["from"], f["links"], f["point"]
        return Structure(links=(LinkPart(m, p, (p, c)), LinkPart(n, q, (q, c))))

    def extra_outputs(self, e):
        return (ExtraOutput("mu" + e["point"], ANGLE, "transmission angle at " + e["point"], e["point"]),)

    def solve(self, e, st: State):
        p, q = e["from"]
        a, b = e["lengths"]
        C_, (lm, ln), mu = rrr(st.points[p], st.points[q], a, b, e["branch"], st.extras_wanted)
        st.points[e["point"]] = C_
        st.links[e["links"][0]], st.links[e["links"][1]] = lm, ln
        if st.extras_wanted:
            st.extras["mu" + e["point"]] = mu

    def measured_extras(self, e, st):
        c1, s1, _, _ = st.links[e["links"][0]]
        c2, s2, _, _ = st.links[e["links"][1]]
        return {"mu" + e["point"]: np.arctan2(np.abs(c1 * s2 - s1 * c2), np.abs(c1 * c2 + s1 * s2))}

    def singularity(self, e, st, size):
        c1, s1, _, _ = st.links[e["links"][0]]
        c2, s2, _, _ = st.links[e["links"][1]]
        return np.abs(c1 * s2 - s1 * c2)            # sin of the transmission angle

    def forces(self, e, ctx):
        """Closed form. With r1 = C - P, r2 = C - Q and F the force link m puts on link n at C, the moments
        about P of link m and about Q of link n give r1 x F = M_m(P), r2 x F = -M_n(Q): a 2x2 system of
        determinant r1 x r2 (zero where the dyad folds); then P and Q carry the rest of each link's load."""
        p, q = e["from"]
        m, n = e["links"]
        c = e["point"]
        px, py = ctx.xy(p)
        qx, qy = ctx.xy(q)
        cx, cy = ctx.xy(c)
        r1x, r1y, r2x, r2y = cx - px, cy - py, cx - qx, cy - qy
        mm, mn = ctx.moment(m, p), ctx.moment(n, q)
        det = r1x * r2y
        det -= r1y * r2x
        fx = mm * r2x
        fx += mn * r1x
        fx /= det
        fy = mm * r2y
        fy += mn * r1y
        fy /= det
        wm, wn = ctx.resultant(m), ctx.resultant(n)
        ctx.pin(c, n, fx, fy, other=m)
        ctx.pin(p, m, fx - wm[0], fy - wm[1])
        ctx.pin(q, n, -fx - wn[0], -fy - wn[1])


def rrr(P, Q, a, b, branch, mu=True):
    """C with |C - P| = a, |C - Q| = b, left of P -> Q for branch +1.

    With d = Q - P, r1 = C - P = k1 d + k2 perp(d), where k1 = x / |d| and k2 = +-h / |d| (x along
    P -> Q, h the height of C over it), so no square root of |d|^2 is needed; r2 = C - Q = r1 - d and
    det = cross(r1, r2) = k2 |d|^2. The rates are the links' own: C = P + a e1 = Q + b e2 gives, dotted
    with r2 and r1, w1 = r2.(vQ - vP) / det, w2 = r1.(vQ - vP) / det, and with
    R = (aQ - aP) + w1^2 r1 - w2^2 r2: alpha1 = R.r2 / det, alpha2 = R.r1 / det.

    Written with as few array operations as possible (in place): the solver evaluates it on blocks of a
    few thousand samples, where each numpy call costs about a microsecond besides its arithmetic. Returns
    (C, (link P->C, link Q->C), transmission angle or None).
    """
    px, py, pvx, pvy, pax, pay = P
    dx = Q[0] - px
    dy = Q[1] - py
    L2 = dx * dx
    L2 += dy * dy
    inv = 1.0 / L2
    k1 = inv * (0.5 * (a * a - b * b))
    k1 += 0.5
    k2 = inv * (a * a)
    k2 -= k1 * k1
    np.sqrt(k2, out=k2)                              # NaN where the circles do not meet
    if branch < 0:
        np.negative(k2, out=k2)
    r1x = k1 * dx
    r1x -= k2 * dy
    r1y = k1 * dy
    r1y += k2 * dx
    r2x = r1x - dx
    r2y = r1y - dy
    idet = inv / k2                                  # 1 / cross(r1, r2)
    # velocities: the angular velocities w1 (P->C) and w2 (Q->C)
    dvx = Q[2] - pvx
    dvy = Q[3] - pvy
    w1 = r2x * dvx
    w1 += r2y * dvy
    w1 *= idet
    w2 = r1x * dvx
    w2 += r1y * dvy
    w2 *= idet
    vx = pvx - w1 * r1y
    vy = pvy + w1 * r1x
    # accelerations
    w1s = w1 * w1
    w2s = w2 * w2
    Rx = Q[4] - pax
    Rx += w1s * r1x
    Rx -= w2s * r2x
    Ry = Q[5] - pay
    Ry += w1s * r1y
    Ry -= w2s * r2y
    al1 = Rx * r2x
    al1 += Ry * r2y
    al1 *= idet
    al2 = Rx * r1x
    al2 += Ry * r1y
    al2 *= idet
    ax = pax - al1 * r1y
    ax -= w1s * r1x
    ay = pay + al1 * r1x
    ay -= w1s * r1y
    C = (px + r1x, py + r1y, vx, vy, ax, ay)
    links = ((r1x / a, r1y / a, w1, al1), (r2x / b, r2y / b, w2, al2))
    if not mu:
        return C, links, None
    dot = r1x * r2x
    dot += r1y * r2y
    det = k2 * L2
    return C, links, np.arctan2(np.abs(det, out=det), np.abs(dot, out=dot))


# ----------------------------------------------------------------------------------- compiled row
def _layout(e, L, row, par):
    a, b = e["lengths"]
    row[2], row[3], row[7] = L.point(e["from"][0]), L.point(e["from"][1]), e["branch"]
    par[:4] = a, b, a * a, 0.5 * (a * a - b * b)                    # as rrr() computes them
    row[4] = L.new_link(e["links"][0])
    row[5] = L.new_link(e["links"][1])
    row[6] = L.new_extra("mu" + e["point"], 2, L.OUT_ABS_ANGLE)   # det, dot: mu = atan2(|det|, |dot|)
    L.new_point(e["point"])


def _at(st, i, p, pq, a2, c1, flip):
    px, py, pvx, pvy, pax, pay = st[p, i], st[p + 1, i], st[p + 2, i], st[p + 3, i], st[p + 4, i], st[p + 5, i]
    dx = st[pq, i] - px
    dy = st[pq + 1, i] - py
    L2 = dx * dx + dy * dy
    inv = 1.0 / L2
    k1 = inv * c1 + 0.5
    k2 = math.sqrt(inv * a2 - k1 * k1)
    if flip:
        k2 = -k2
    r1x = k1 * dx - k2 * dy
    r1y = k1 * dy + k2 * dx
    r2x = r1x - dx
    r2y = r1y - dy
    idet = inv / k2
    dvx = st[pq + 2, i] - pvx
    dvy = st[pq + 3, i] - pvy
    w1 = (r2x * dvx + r2y * dvy) * idet
    w2 = (r1x * dvx + r1y * dvy) * idet
    w1s = w1 * w1
    w2s = w2 * w2
    Rx = st[pq + 4, i] - pax + w1s * r1x - w2s * r2x
    Ry = st[pq + 5, i] - pay + w1s * r1y - w2s * r2y
    al1 = (Rx * r2x + Ry * r2y) * idet
    P = (px + r1x, py + r1y, pvx - w1 * r1y, pvy + w1 * r1x, pax - al1 * r1y - w1s * r1x,
         pay + al1 * r1x - w1s * r1y)
    return P, r1x, r1y, r2x, r2y, w1, w2, al1, (Rx * r1x + Ry * r1y) * idet, k2 * L2


def _kernel(st, m, e, ops, par, q, qd, qdd, step, i0, need):
    n, p, pq, L1, L2, mu = ops[e, 1], ops[e, 2], ops[e, 3], ops[e, 4], ops[e, 5], ops[e, 6]
    a, b, a2, c1 = par[e, 0], par[e, 1], par[e, 2], par[e, 3]
    flip = ops[e, 7] < 0
    if need[L1] or need[L2] or need[mu]:         # two loops rather than tests inside one: 3x faster
        for i in range(m):
            P, r1x, r1y, r2x, r2y, w1, w2, al1, al2, det = _at(st, i, p, pq, a2, c1, flip)
            C.put(st, n, i, P[0], P[1], P[2], P[3], P[4], P[5])
            C.put4(st, L1, i, r1x / a, r1y / a, w1, al1)
            C.put4(st, L2, i, r2x / b, r2y / b, w2, al2)
            st[mu, i] = det
            st[mu + 1, i] = r1x * r2x + r1y * r2y
    else:
        for i in range(m):
            P = _at(st, i, p, pq, a2, c1, flip)[0]
            C.put(st, n, i, P[0], P[1], P[2], P[3], P[4], P[5])


KIND = RRR()
KIND.jit = JitSpec(_layout, _kernel, helpers=("_at",))
