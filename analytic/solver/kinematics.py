"""The general solver: closed-form position, velocity and acceleration of any ``linkage/1`` mechanism,
one Assur group at a time, vectorised with numpy over every sample.

Each element places one new point from points already known (see :mod:`analytic.format.linkfile`):

* ``crank``: the point on a circle about a ground pivot at the input angle;
* ``slider``: the point on a ground line at the input distance;
* ``RRR``: circle-circle intersection (two links pinned at the new point);
* ``RRP``: circle-line intersection (a rod whose end is pinned to a block on a guide line);
* ``RPR``: a line through a pivot and a block (a slotted link), the new point on it;
* ``point``: a point fixed in the frame of a link given by two of its points.

Positions are explicit (the ``branch`` of each group picks the root). Rates follow from the constraint
equations differentiated once and twice, which are linear in the unknown rates: a 2x2 solve per group
(with the Coriolis term 2 ds omega where a block slides on a turning guide). A group that cannot be
assembled at a sample leaves NaN there, and :class:`Solution` records which group failed first.

Per point ``P`` the arrays are ``(x, y, vx, vy, ax, ay)``; per link ``(cos, sin, omega, alpha)`` of its
angle; per prismatic pair ``(s, ds, dds)``.

Speed: :class:`~analytic.mechanism.Mechanism` calls :func:`evaluate` on blocks of a few thousand samples,
so every numpy call here costs about a microsecond of overhead plus its arithmetic; the RRR group (the
most common one) is therefore written with as few array operations as possible (see :func:`_rrr`), and
the transmission angles, the only trigonometry besides the inputs', can be skipped (``mu=False``).
:mod:`analytic.solver.jit` evaluates the same formulas sample by sample when numba is installed.
"""

from __future__ import annotations

import math

import numpy as np

from analytic.format.linkfile import Geometry


def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


def _line(P, Q):
    """A line through points P -> Q of one rigid link: origin P, unit direction (c, s), its angular
    velocity and acceleration (from the relative motion of Q about P)."""
    dx, dy = Q[0] - P[0], Q[1] - P[1]
    L2 = dx * dx + dy * dy
    L = np.sqrt(L2)
    w = _cross(dx, dy, Q[2] - P[2], Q[3] - P[3]) / L2
    a = _cross(dx, dy, Q[4] - P[4], Q[5] - P[5]) / L2
    return P, dx / L, dy / L, w, a


def _on_frame(O, c, s, w, a, u, v):
    """Point at local (u, v) in a frame with origin O, x-axis (c, s), angular velocity w, acceleration a."""
    rx, ry = u * c - v * s, u * s + v * c
    w2 = w * w
    return (O[0] + rx, O[1] + ry, O[2] - w * ry, O[3] + w * rx,
            O[4] - a * ry - w2 * rx, O[5] + a * rx - w2 * ry)


def _crank(P, r, q, qd, qdd):
    """The crank tip at radius r about P: ``_on_frame(P, cos q, sin q, qd, qdd, r, 0)`` without the
    products by the zero ordinate."""
    c, s = np.cos(q), np.sin(q)
    rx, ry = r * c, r * s
    w2 = qd * qd
    ax = P[4] - qdd * ry
    ax -= w2 * rx
    ay = P[5] + qdd * rx
    ay -= w2 * ry
    point = (P[0] + rx, P[1] + ry, P[2] - qd * ry, P[3] + qd * rx, ax, ay)
    return point, (c, s, qd, qdd)


def _rrr(P, Q, a, b, branch, mu=True):
    """C with |C - P| = a, |C - Q| = b, left of P -> Q for branch +1.

    With d = Q - P, r1 = C - P = k1 d + k2 perp(d), where k1 = x / |d| and k2 = +-h / |d| (x along
    P -> Q, h the height of C over it), so no square root of |d|^2 is needed; r2 = C - Q = r1 - d and
    det = cross(r1, r2) = k2 |d|^2. The rates are the links' own: C = P + a e1 = Q + b e2 gives, dotted
    with r2 and r1, w1 = r2.(vQ - vP) / det, w2 = r1.(vQ - vP) / det, and with
    R = (aQ - aP) + w1^2 r1 - w2^2 r2: alpha1 = R.r2 / det, alpha2 = R.r1 / det.
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


def _link_from(P, C, length):
    """The link P -> C of the given length: (cos, sin, omega, alpha)."""
    rx, ry = C[0] - P[0], C[1] - P[1]
    l2 = length * length
    return (rx / length, ry / length, _cross(rx, ry, C[2] - P[2], C[3] - P[3]) / l2,
            _cross(rx, ry, C[4] - P[4], C[5] - P[5]) / l2)


def _guide(G, points, ground):
    """Origin and motion of a guide line (dict from Geometry), as ``_line`` returns them."""
    if "points" in G:
        p, q = G["points"]
        return _line(points[p], points[q])
    through = G["through"]
    O = points[through] if isinstance(through, str) else (through[0], through[1], 0.0, 0.0, 0.0, 0.0)
    return O, np.cos(G["angle"]), np.sin(G["angle"]), 0.0, 0.0


def _rrp(P, guide, length, offset, branch):
    """C on the guide line (shifted ``offset`` to its left) with |C - P| = length; branch +1 takes the
    intersection farther along the guide. Returns C, the rod link, the block's (s, ds, dds)."""
    O, c, s, w, a = guide
    Oe = _on_frame(O, c, s, w, a, 0.0, offset)
    wx, wy = P[0] - Oe[0], P[1] - Oe[1]
    wu = wx * c + wy * s
    disc = wu * wu - (wx * wx + wy * wy) + length * length
    sd = wu + branch * np.sqrt(disc)
    C0 = _on_frame(Oe, c, s, w, a, sd, 0.0)        # the guide's point at C (moves with the guide)
    rx, ry = C0[0] - P[0], C0[1] - P[1]
    ru = rx * c + ry * s
    ds = -(rx * (C0[2] - P[2]) + ry * (C0[3] - P[3])) / ru
    vx, vy = C0[2] + ds * c, C0[3] + ds * s
    # relative to the guide: a = a_guide_point + dds u + 2 ds w u_perp
    ax0, ay0 = C0[4] - 2.0 * ds * w * s, C0[5] + 2.0 * ds * w * c
    ux, uy = vx - P[2], vy - P[3]
    dds = -(rx * (ax0 - P[4]) + ry * (ay0 - P[5]) + ux * ux + uy * uy) / ru
    C = (C0[0], C0[1], vx, vy, ax0 + dds * c, ay0 + dds * s)
    return C, _link_from(P, C, length), (c, s, w, a), (sd, ds, dds)


def _rpr(P, Q, length, offset, branch):
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
    R = _on_frame(P, c, sn, w, a, length, 0.0)
    return R, (c, sn, w, a), (s, ds, dds)


def _point(P, Q, u, v):
    O, c, s, w, a = _line(P, Q)
    return _on_frame(O, c, s, w, a, u, v)


def evaluate(geometry: Geometry, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, *, mu: bool = True):
    """Solve every element on 1-D arrays; ``q``, ``qd``, ``qdd`` have shape (n_inputs, N).

    Returns ``(points, links, slides, mus, failed)``: dicts keyed by name as in the module docstring,
    ``mus`` keyed by the RRR group's point, and ``failed`` the index (in solving order) of the first
    element that could not be assembled at each sample, -1 where all did. With ``mu=False`` the
    transmission angles (an arctan2 per RRR group, a good part of the cost) are skipped: ``mus`` is empty.
    """
    n = q.shape[1]
    zero = np.zeros(n)
    points = {g: (zero + x, zero + y, zero, zero, zero, zero) for g, (x, y) in geometry.ground.items()}
    links, slides, mus = {}, {}, {}
    failed = np.full(n, -1, dtype=np.int64)
    any_failed = False
    i_input = 0
    for index, e in enumerate(geometry.elements):
        kind = e["kind"]
        if kind == "crank":
            j = i_input
            i_input += 1
            point, links[e["link"]] = _crank(points[e["pivot"]], e["length"], q[j], qd[j], qdd[j])
        elif kind == "slider":
            j = i_input
            i_input += 1
            O, c, s, w, a = _guide(e["guide"], points, geometry.ground)
            point = _on_frame(O, c, s, 0.0, 0.0, q[j], 0.0)
            point = (point[0], point[1], O[2] + qd[j] * c, O[3] + qd[j] * s, O[4] + qdd[j] * c, O[5] + qdd[j] * s)
            links[e["link"]] = (zero + c, zero + s, zero, zero)
            slides[e["link"]] = (q[j], qd[j], qdd[j])
        elif kind == "RRR":
            p, qn = e["from"]
            a, b = e["lengths"]
            point, (lm, ln), m = _rrr(points[p], points[qn], a, b, e["branch"], mu)
            links[e["links"][0]], links[e["links"][1]] = lm, ln
            if mu:
                mus[e["point"]] = m
        elif kind == "RRP":
            guide = _guide(e["guide"], points, geometry.ground)
            point, rod, block, slide = _rrp(points[e["from"]], guide, e["length"], e["offset"], e["branch"])
            rod_name, block_name = e["links"]
            links[rod_name] = rod
            links[block_name] = tuple(zero + x for x in block)
            slides[block_name] = slide
        elif kind == "RPR":
            point, slot, slide = _rpr(points[e["pivot"]], points[e["through"]], e["length"], e["offset"],
                                      e["branch"])
            links[e["links"][0]] = links[e["links"][1]] = slot
            slides[e["links"][1]] = slide
        else:
            p, qn = e["on"]
            point = _point(points[p], points[qn], *e["at"])
        x = point[0]
        # One sum tells whether every sample assembled (NaN propagates; a non-finite sum from huge
        # finite values only sends it down the exact path).
        if any_failed or not math.isfinite(np.add.reduce(x, axis=None)):
            bad = ~np.isfinite(x)
            bad &= failed < 0
            failed[bad] = index
            any_failed = True
        points[e["point"]] = point
    return points, links, slides, mus, failed
