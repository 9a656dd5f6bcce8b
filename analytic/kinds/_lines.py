"""What the ``PP`` dyads (``PRP``, ``RPP``, ``PPR``) share: the intersection of two moving lines with its exact
velocity and acceleration, and how a second guide is laid out in a compiled row.

Not a kind (no ``KIND``): the registry lists only the kinds' modules.

:func:`meet` is plain arithmetic on its arguments, so the same function serves the numpy path (arrays of
samples, or scalars for what does not move) and the compiled path (numba compiles it for one sample at a
time): both round alike.
"""

from __future__ import annotations

import math

import numpy as np

from .base import on_frame

PARALLEL = 1e-6
"""Two lines whose |sin| of the angle between them is below this are parallel: the point where they meet
moves at 1e6 times the speed of what moves them (see :func:`meet`), so an element made so is refused."""


def meet(A1, c1, s1, w1, a1, A2, c2, s2, w2, a2):
    """The point C where two moving lines meet, and its place along each.

    Line k passes through the point ``Ak`` = (x, y, vx, vy, ax, ay) [m, m/s, m/s^2] with unit direction
    ``(ck, sk)`` turning at ``wk`` [rad/s] with acceleration ``ak`` [rad/s^2]. With d = A2 - A1 and
    D = cross(u1, u2) = sin(th2 - th1), C = A1 + s u1 = A2 + t u2 where

        s = cross(d, u2) / D,    t = cross(d, u1) / D.

    The rates are these quotients differentiated: u' = w n (n = u turned +90 deg) gives
    D' = E (w2 - w1), D'' = E (a2 - a1) - D (w2 - w1)^2 with E = u1 . u2 = cos(th2 - th1), and for
    N = cross(d, u2): N' = cross(d', u2) + w2 (d . u2), N'' = cross(d'', u2) + 2 w2 (d' . u2) + a2 (d . u2)
    - w2^2 N; then s' = (N' - s D') / D, s'' = (N'' - 2 s' D' - s D'') / D (t likewise with line 1).
    Where ``A1`` is a point of the link that carries line 1, ``s`` is the slide of a block on that line
    measured from A1 (and C's acceleration holds the Coriolis term 2 s' w1 n1); the same for ``t`` and
    line 2.

    Returns
    -------
    C : tuple
        (x, y, vx, vy, ax, ay) of the meeting point [m, m/s, m/s^2]; infinite or NaN where the lines are
        parallel.
    (s, ds, dds), (t, dt, ddt) : tuple
        C's place along line 1 from A1 and along line 2 from A2 [m, m/s, m/s^2].
    """
    D = c1 * s2 - s1 * c2
    E = c1 * c2 + s1 * s2
    dw = w2 - w1
    Dd = E * dw
    Ddd = E * (a2 - a1) - D * dw * dw
    dx = A2[0] - A1[0]
    dy = A2[1] - A1[1]
    vx = A2[2] - A1[2]
    vy = A2[3] - A1[3]
    ax = A2[4] - A1[4]
    ay = A2[5] - A1[5]
    # along line 1: N = cross(d, u2)
    n = dx * s2 - dy * c2
    p = dx * c2 + dy * s2
    nd = vx * s2 - vy * c2 + w2 * p
    ndd = ax * s2 - ay * c2 + 2.0 * w2 * (vx * c2 + vy * s2) + a2 * p - w2 * w2 * n
    s = n / D
    ds = (nd - s * Dd) / D
    dds = (ndd - 2.0 * ds * Dd - s * Ddd) / D
    # along line 2: M = cross(d, u1)
    m = dx * s1 - dy * c1
    r = dx * c1 + dy * s1
    md = vx * s1 - vy * c1 + w1 * r
    mdd = ax * s1 - ay * c1 + 2.0 * w1 * (vx * c1 + vy * s1) + a1 * r - w1 * w1 * m
    t = m / D
    dt = (md - t * Dd) / D
    ddt = (mdd - 2.0 * dt * Dd - t * Ddd) / D
    # C = A1 + s u1 on line 1's link, plus its slide: the Coriolis term 2 s' w1 n1
    sw = s * w1
    k = 2.0 * ds * w1 + s * a1
    C = (A1[0] + s * c1, A1[1] + s * s1, A1[2] + ds * c1 - sw * s1, A1[3] + ds * s1 + sw * c1,
         A1[4] + dds * c1 - k * s1 - sw * w1 * c1, A1[5] + dds * s1 + k * c1 - sw * w1 * s1)
    return C, (s, ds, dds), (t, dt, ddt)


def turned(c, s, ca, sa):
    """The direction (c, s) turned by the angle whose cosine and sine are (ca, sa)."""
    return c * ca - s * sa, s * ca + c * sa


def pin_in_slot(guide, offset, angle, P):
    """A link sliding on a guide line (``guide`` as :func:`~analytic.kinds.base.guide_line` gives it,
    shifted ``offset`` [m] to its left) carrying a slot at ``angle`` [rad] to the guide's direction, through
    which a block pinned at the point ``P`` slides (the ``RPP`` and ``PPR`` dyads: a Scotch yoke).

    Returns C (where the slot crosses the guide: the sliding link's point on it), the sliding link's
    (cos, sin, omega, alpha) (the guide's direction), the block's (the slot's direction: it turns with the
    guide), the sliding link's (s, ds, dds) from the guide's origin and the block's from C to P along the
    slot.
    """
    O, c, s, w, a = guide
    A = on_frame(O, c, s, w, a, 0.0, offset)
    cv, sv = turned(c, s, math.cos(angle), math.sin(angle))
    C, along, (t, dt, ddt) = meet(A, c, s, w, a, P, cv, sv, w, a)
    return C, (c, s, w, a), (cv, sv, w, a), along, (-t, -dt, -ddt)


def check_slot_angle(e) -> str | None:
    """A slot parallel to its guide never crosses it: refuse it (RPP, PPR)."""
    if abs(math.sin(e["angle"])) < PARALLEL:
        return (f"field 'angle': {math.degrees(e['angle']):.6g} deg makes the slot parallel to the guide, so it "
                f"never crosses it; give an angle away from 0 and 180 deg (90deg: square to the guide)")
    return None


def layout_pin_in_slot(e, L, row, par, on_guide: str, in_slot: str) -> None:
    """The compiled row of a pin in a slot on a guide (RPP, PPR; outputs in the order of ``links``, as
    the numpy path gives them): the pin ``row[2]``, the guide
    ``row[5:8]`` and ``par[2:4]``, the link on the guide ``row[3]`` and its slide ``row[8]``, the block in
    the slot ``row[4]`` and its slide ``row[9]``; offset ``par[0]``, the slot angle's cos and sin
    ``par[1]``, ``par[4]`` (as :func:`pin_in_slot` computes them)."""
    row[2] = L.point(e["through"])
    par[0], par[1], par[4] = e["offset"], math.cos(e["angle"]), math.sin(e["angle"])
    L.guide(row, par, e["guide"])
    for name in e["links"]:                      # in the order of the links, as the numpy path adds them
        row[3 if name == on_guide else 4] = L.new_link(name)
    for name in e["links"]:
        row[8 if name == on_guide else 9] = L.new_slide(name)
    L.new_point(e["point"])


def samples(values, n: int):
    """Each value as an array over n samples (a value that does not move is a scalar)."""
    zero = np.zeros(n)
    return tuple(zero + v for v in values)


def layout_second_guide(L, row, par, G, k: int, j: int) -> None:
    """Lay out a second guide of an element's compiled row as :meth:`Layout.guide` lays out the first: its
    kind in ``row[k]``, origin slot in ``row[k + 1]``, second point in ``row[k + 2]``; a ground line's
    direction in ``par[j]``, ``par[j + 1]``."""
    r, p = row.copy(), par.copy()
    L.guide(r, p, G)
    row[k], row[k + 1], row[k + 2] = r[5], r[6], r[7]
    par[j], par[j + 1] = p[2], p[3]
