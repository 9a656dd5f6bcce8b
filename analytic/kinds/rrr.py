"""``RRR``: a dyad of two links pinned at the point it places (circle-circle intersection).

Fields: ``point``, ``from`` [P, Q] (the known points), ``lengths`` [a, b] (|P point|, |Q point|), ``links``
[m, n] (the links P-point and Q-point), ``branch`` (+1: the point left of the directed line P -> Q, at the
first input's start), ``change`` (what the dyad does where it passes a change point, its links aligned
while the input moves on: +1, the default, keeps its form and moves on smoothly, as a real linkage does
(a parallelogram stays a parallelogram): its branch sign flips there; -1 keeps the branch sign, switching
form (the parallelogram turns into the crossed form) with a kink in its motion).
Its own output: ``muP`` (P the placed point), the transmission angle between the two links in [0, pi/2].

Where the branch sign flips is the resolved element's ``flips`` (see :mod:`analytic.solver.change_points`):
the sign at a sample follows from the first input's value there, so any set of samples is solved alike;
at a change point itself the rates are the limits of the continuous motion (:func:`limit_rates`).
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
              "links": Field("links2", ("{from0}{point}", "{from1}{point}")), "branch": Field("branch", 1),
              "change": Field("branch", 1)}

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
        flips = e.get("flips")
        if flips:
            C_, (lm, ln), mu = _through_change_points(e, st, flips)
        else:
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


def rrr(P, Q, a, b, branch, mu=True, fold=0.0):
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
    if fold:                                         # at a change point passed: rounding below zero is zero
        k2[(k2 < 0) & (k2 > -fold)] = 0.0
    np.sqrt(k2, out=k2)                              # NaN where the circles do not meet
    if np.ndim(branch):                              # a sign per sample (through change points)
        k2 *= branch
    elif branch < 0:
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


# ------------------------------------------------------------------------------------ change points
FOLD_ROUNDING = 1e-12
"""At a change point the dyad's squared height (over |PQ|^2) is zero up to rounding (~1e-16 of a^2 / |PQ|^2);
a value this far below zero is taken as zero there, so the fold itself assembles."""
LIMIT_MEASURE = 1e-5
"""Below this |sin| between the two links the rates are taken as the limits of the continuous motion:
the closed form divides by it, and its rounding (1e-16 / sin^2 relative) would pass 1e-6 there."""
LIMIT_STEP = 1e-3
"""[rad of the links' relative motion] how far on each side of such a sample the motion is followed (its
Taylor expansion from the sample's rates) to take the limit: the means of the two sides at this step and
twice it, extrapolated (Richardson), give the limit to O(step^4) = 1e-12 relative; there sin is ~1e-3,
where the closed form's rounding is 1e-10."""
LIMIT_WIDEN = 4
"""A side sample whose |sin| between the links is below LIMIT_STEP / LIMIT_WIDEN is too close to the change
point: the step first guessed from how fast the line P-Q turns (|vQ - vP| / |PQ|) is then widened by
LIMIT_STEP / |sin| (|sin| grows linearly away from a change point), at most LIMIT_TRIES times. This matters
where P and Q meet at the change point (a rhombus at its folded pose, a slider-lifter's block over the
rocker's pivot): the line P-Q turns ever faster there (|PQ| -> 0) while the links part at the input's pace."""
LIMIT_TRIES = 4


def signs(flips: dict, q) -> np.ndarray:
    """The branch sign factor (+1 or -1) at first-input values ``q``: -1 after an odd number of the
    ``flips["at"]`` values lie between the reference (the input's start, ``flips["ref"]``) and q, repeated
    every ``flips["period"]`` (2 pi for a crank; None for a slider)."""
    q = np.asarray(q, dtype=float)
    ref, period = flips["ref"], flips["period"]
    count = np.zeros(q.shape, dtype=np.int64)
    for f in flips["at"]:
        if period:
            count += (np.floor((q - f) / period) - np.floor((ref - f) / period)).astype(np.int64)
        else:
            count += (q >= f).astype(np.int64) - int(ref >= f)
    return np.where(count % 2 == 0, 1.0, -1.0)


def _through_change_points(e, st: State, flips: dict):
    """:func:`rrr` with the branch sign of each sample from the first input's value, and the rates at a
    change point itself (|sin| < LIMIT_MEASURE) as the limits of the continuous motion."""
    p, q = e["from"]
    a, b = e["lengths"]
    P, Q = st.points[p], st.points[q]
    n = st.n
    q1, qd1, qdd1 = (np.broadcast_to(x[0], (n,)) for x in (st.q, st.qd, st.qdd))
    sign = e["branch"] * signs(flips, q1)
    C_, links, mu = rrr(P, Q, a, b, sign, st.extras_wanted, FOLD_ROUNDING)
    (c1, s1, _, _), (c2, s2, _, _) = links
    apart = np.abs(c1 * s2 - s1 * c2)
    at = np.flatnonzero((apart < LIMIT_MEASURE) | (np.isnan(apart) & _on_each_other(P, Q, a, n)))
    if at.size:
        others = [np.broadcast_to(x, (n,)) for rates in (st.qd[1:], st.qdd[1:]) for x in rates]
        alone = np.logical_and.reduce([x == 0 for x in others]) if others else np.ones(n, bool)
        C_, links = limit_rates(e, flips, P, Q, (q1, qd1, qdd1), C_, links, at, alone)
    return C_, links, mu


def _on_each_other(P, Q, a, n) -> np.ndarray:
    """Where the known points P and Q coincide (to rounding of the size a): the closed form divides by |PQ|^2."""
    dx, dy = (np.broadcast_to(Q[k] - P[k], (n,)) for k in (0, 1))
    return dx * dx + dy * dy <= (1e-12 * a) ** 2


def limit_rates(e, flips, P, Q, inputs, C_, links, at, alone=None):
    """The rates at samples ``at`` (at a change point) as the limit of the rates a little before and a
    little after along the motion (LIMIT_STEP): P, Q and the first input are advanced by their Taylor
    expansions (velocity, acceleration, jerk) over times +-tau and +-2 tau, the dyad solved there on its own
    branch, and the means of the two sides extrapolated to tau = 0.
    Where P and Q do not move relative to each other, the dyad moves with them (its links at rest).

    The jerk of P (and Q) is the part the input's acceleration brings, 3 P2 qd qdd (P2 = d2P/dq2 =
    (aP - vP qdd / qd) / qd^2), where the first input moves alone (``alone``: the others at rest): without it
    the side samples' accelerations are off by O(tau), which the closed form's 1/sin turns into an O(1) error
    of the limit (a parallelogram's rocker read alpha = 0 at its fold while the crank accelerated). The term
    P3 qd^3 (P3 = d3P/dq3) stays out, as before (the sample does not hold it); the limit does not depend on
    it where P3 has no component along the aligned links (a crank's pin: P3 = -P1, normal to them there)."""
    a, b = e["lengths"]
    P_, Q_ = [np.array([np.broadcast_to(x, (len(C_[0]),))[at] for x in pt]) for pt in (P, Q)]
    q1, qd1, qdd1 = (np.asarray(x)[at] for x in inputs)
    alone = np.ones(len(at), bool) if alone is None else np.asarray(alone)[at]
    moves = alone & (qd1 != 0)
    k = np.where(moves, qdd1 / np.where(moves, qd1, 1.0), 0.0)          # qdd / qd [1/s]
    jerk = [(3 * k * (X[4] - X[2] * k), 3 * k * (X[5] - X[3] * k)) for X in (P_, Q_)]
    dx, dy = Q_[0] - P_[0], Q_[1] - P_[1]
    d = np.hypot(dx, dy)
    with np.errstate(divide="ignore", invalid="ignore"):
        rate = np.maximum(np.hypot(Q_[2] - P_[2], Q_[3] - P_[3]) / d, np.sqrt(np.hypot(Q_[4] - P_[4], Q_[5] - P_[5]) / d))
    rate = np.where(np.isfinite(rate), rate, np.hypot(Q_[2] - P_[2], Q_[3] - P_[3]) / a)   # P on Q: a first guess
    moving = rate > 0
    tau = np.where(moving, LIMIT_STEP / np.where(moving, rate, 1.0), 0.0)

    def side(t):
        def ahead(X, J):
            t2, t3 = t * t / 2, t * t * t / 6
            return (X[0] + X[2] * t + X[4] * t2 + J[0] * t3, X[1] + X[3] * t + X[5] * t2 + J[1] * t3,
                    X[2] + X[4] * t + J[0] * t2, X[3] + X[5] * t + J[1] * t2, X[4] + J[0] * t, X[5] + J[1] * t)
        sign = e["branch"] * signs(flips, q1 + qd1 * t + 0.5 * qdd1 * t * t)
        C, (l1, l2), _ = rrr(ahead(P_, jerk[0]), ahead(Q_, jerk[1]), a, b, sign, False)
        C = (C[0] - P_[0], C[1] - P_[1]) + C[2:]              # C relative to P: P moved along with the sides
        return list(C) + list(l1) + list(l2)

    for _ in range(LIMIT_TRIES):                     # widen a step whose sides are still at the change point
        sides = [side(t) for t in (-tau, tau)]
        apart = np.fmax(*(np.abs(x[6] * x[11] - x[7] * x[10]) for x in sides))    # the farther side's |sin|
        grow = np.where(moving & ~(apart >= LIMIT_STEP / LIMIT_WIDEN),
                        LIMIT_STEP / np.maximum(np.nan_to_num(apart), LIMIT_STEP * 1e-6), 1.0)
        if not np.any(grow > 1.0):
            break
        tau = tau * grow
    means = []
    for k in (1.0, 2.0):                             # the means at tau and 2 tau: Richardson's extrapolation
        sides = [side(t) for t in (-k * tau, k * tau)]
        means.append([0.5 * (x + y) for x, y in zip(*sides)])
    lim = [(4.0 * x - y) / 3.0 for x, y in zip(*means)]
    C_ = [np.array(x, dtype=float, copy=True) for x in C_]
    links = [[np.array(x, dtype=float, copy=True) for x in link] for link in links]
    moving = moving & np.all(np.isfinite(lim), axis=0)
    for k in range(6):                               # positions too: sqrt(rounding) ~ 1e-8 at the fold itself
        limit = lim[k] + P_[k] if k < 2 else lim[k]
        C_[k][at] = np.where(moving, limit, C_[k][at] if k < 2 else P_[k])
    for j in range(8):
        link, k = divmod(j, 4)
        links[link][k][at] = np.where(moving, lim[6 + j], links[link][k][at] if k < 2 else 0.0)
    return tuple(C_), tuple(tuple(link) for link in links)


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
