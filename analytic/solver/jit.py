"""Optional compiled path of the general solver: the formulas of :mod:`analytic.solver.kinematics`, compiled
with numba and run in parallel over the samples.

It is used by :meth:`analytic.mechanism.Mechanism.solve` when numba is installed (``pip install
'linkage[jit]'``) and the environment variable ``LINKAGE_JIT`` is not ``"0"``, for solves of at least
:data:`MIN_SAMPLES` samples (``LINKAGE_JIT=1``: for all); without numba, numpy stays the solver. Both give
the same numbers to rounding (tests/test_solver_paths.py).

How it works: a mechanism's elements become a table of integer codes (kind, the state slots of the
points, links and prismatic pairs each one reads and writes) and one of numbers (lengths, offsets,
branches). One compiled kernel, the same for every mechanism, takes the samples in chunks of
:data:`CHUNK` (one chunk per thread at a time); for each element in solving order it runs one loop over
the chunk, reading and writing a (slot, sample) scratch array that stays in the CPU cache, then copies the
requested outputs out. Loops over independent samples let the CPU overlap the long latencies of square
roots and divisions (a loop over the elements of one sample at a time ran 3x slower) and vectorise where
they can. Link angles and transmission angles are computed only when asked for, and sin, cos and atan2
are polynomial versions that vectorise (the C library's take 25-35 ns a call here, keep loops scalar).

numba is imported and the kernel compiled at the first compiled solve of a process: 15-20 s the first
time on a machine, then loaded from numba's on-disk cache (``cache=True``, in ``analytic/__pycache__``) in
0.3-1 s, import of numba included.
"""

from __future__ import annotations

import importlib.util
import math
import os
import warnings

import numpy as np

AVAILABLE = importlib.util.find_spec("numba") is not None
"""Whether numba can be imported (it is not imported until the first compiled solve)."""

CHUNK = 512
"""Samples per work item: its scratch array (a few hundred slots x CHUNK) stays in the L2 cache, and each
output row is copied out in runs of 4 KiB. 64 to 1024 measured within 20 % of each other."""

# element kinds, guide kinds, output kinds
_CRANK, _SLIDER, _RRR, _RRP, _RPR, _POINT = range(6)
_G_LINE, _G_ORIGIN = 0, 1
_OUT_COPY, _OUT_PHI, _OUT_MU = 0, 1, 2


MIN_SAMPLES = 100_000
"""Below this many samples a solve stays on numpy unless LINKAGE_JIT=1: the first compiled solve of a
process costs about half a second (importing numba, loading the kernel from its cache), as much as
numpy takes for several hundred thousand samples; short runs (the CLI's) need not pay it."""


def enabled(n: int | None = None) -> bool:
    """Whether a solve of ``n`` samples goes through the compiled path: numba importable, and the
    environment variable LINKAGE_JIT is "1", or unset (any value but "0") and n >= MIN_SAMPLES (or n is
    None). LINKAGE_JIT=0 keeps every solve on numpy."""
    if not AVAILABLE:
        return False
    flag = os.environ.get("LINKAGE_JIT", "")
    if flag == "0":
        return False
    return flag == "1" or n is None or n >= MIN_SAMPLES


# ---------------------------------------------------------------------------------------- the kernel
# Plain Python here; :func:`_compile` turns these into numba functions. The formulas are those of
# analytic.solver.kinematics, written per sample in the same order of operations, so both paths round alike
# (sin, cos, atan2 to within 2 ulp).

# sin, cos and atan2 as vectorisable code: the C library's (what numba calls for math.sin ...) take 25-35 ns
# each here and keep a loop scalar; these take 3-5 ns in a vectorised loop. Coefficients and range
# reduction of Cephes (S. L. Moshier, sin.c, atan.c); within 2 ulp of numpy's (tests/test_solver_paths.py).
_DP1, _DP2, _DP3 = 7.85398125648498535156e-1, 3.77489470793079817668e-8, 2.69515142907905952645e-15
_FOPI = 1.27323954473516268615                    # 4 / pi
_LOSSTH = 1.073741824e9                           # beyond: math.sin / math.cos
_S0, _S1, _S2, _S3, _S4, _S5 = (1.58962301576546568060e-10, -2.50507477628578072866e-8, 2.75573136213857245213e-6,
                                -1.98412698295895385996e-4, 8.33333333332211858878e-3, -1.66666666666666307295e-1)
_C0, _C1, _C2, _C3, _C4, _C5 = (-1.13585365213876817300e-11, 2.08757008419747316778e-9, -2.75573141792967388112e-7,
                                2.48015872888517045348e-5, -1.38888888888730564116e-3, 4.16666666666665929218e-2)
_P0, _P1, _P2, _P3, _P4 = (-8.750608600031904122785e-1, -1.615753718733365076637e1, -7.500855792314704667340e1,
                           -1.228866684490136173410e2, -6.485021904942025371773e1)
_Q0, _Q1, _Q2, _Q3, _Q4 = (2.485846490142306297962e1, 1.650270098316988542046e2, 4.328810604912902668951e2,
                           4.853903996359136964868e2, 1.945506571482613964425e2)
_MOREBITS = 6.123233995736765886130e-17           # pi/2 - float(pi/2)
_PIO2, _PIO4 = 1.57079632679489661923, 7.85398163397448309616e-1


def _sincos(x):
    """(sin x, cos x) for |x| <= 2^30: Cephes' range reduction modulo pi/4 (three-part pi/4) and
    polynomials, without branches so that a loop of it vectorises. Larger |x|, inf, NaN: see _crank."""
    ax = abs(x)
    j = int(ax * _FOPI)
    j += j & 1                                    # to the nearest even octant
    y = float(j)
    z = ((ax - y * _DP1) - y * _DP2) - y * _DP3   # |z| <= pi/4
    zz = z * z
    ps = z + z * (zz * (((((_S0 * zz + _S1) * zz + _S2) * zz + _S3) * zz + _S4) * zz + _S5))
    pc = 1.0 - 0.5 * zz + zz * zz * (((((_C0 * zz + _C1) * zz + _C2) * zz + _C3) * zz + _C4) * zz + _C5)
    swap = (j & 2) != 0                           # octants 2, 6: sin and cos exchange
    s = pc if swap else ps
    c = ps if swap else pc
    s = -s if (j & 4) != 0 else s
    c = -c if ((j + 2) & 4) != 0 else c          # cos negative in octants 2, 4
    return math.copysign(1.0, x) * s, c


def _atan2(y, x):
    """atan2(y, x) from Cephes' atan on [0, 1] and the octant; signed zeros as IEEE atan2."""
    ax = abs(x)
    ay = abs(y)
    swap = ay > ax
    big = ay if swap else ax
    small = ax if swap else ay
    t = small / big if big != 0.0 else 0.0 * small  # both zero: 0; NaN stays NaN
    far = t > 0.66
    u = (t - 1.0) / (t + 1.0) if far else t
    z = u * u
    p = (z * ((((_P0 * z + _P1) * z + _P2) * z + _P3) * z + _P4)
         / (((((z + _Q0) * z + _Q1) * z + _Q2) * z + _Q3) * z + _Q4))
    r = u * p + u
    r = (_PIO4 + (r + 0.5 * _MOREBITS)) if far else r
    if swap:
        r = (_PIO2 - r) + _MOREBITS
    if math.copysign(1.0, x) < 0.0:
        r = (2.0 * _PIO2 - r) + 2.0 * _MOREBITS
    return math.copysign(r, y)


def _frame(o0, o1, o2, o3, o4, o5, c, s, w, a, u, v):
    rx = u * c - v * s
    ry = u * s + v * c
    w2 = w * w
    return (o0 + rx, o1 + ry, o2 - w * ry, o3 + w * rx, o4 - a * ry - w2 * rx, o5 + a * rx - w2 * ry)


def _line(st, p, q, i):
    dx = st[q, i] - st[p, i]
    dy = st[q + 1, i] - st[p + 1, i]
    L2 = dx * dx + dy * dy
    L = math.sqrt(L2)
    w = (dx * (st[q + 3, i] - st[p + 3, i]) - dy * (st[q + 2, i] - st[p + 2, i])) / L2
    a = (dx * (st[q + 5, i] - st[p + 5, i]) - dy * (st[q + 4, i] - st[p + 4, i])) / L2
    return dx / L, dy / L, w, a


def _guide(st, e, ops, par, i):
    """(c, s, w, a) of an element's guide line at sample i (its origin is slot ops[e, 6])."""
    if ops[e, 5] == _G_LINE:
        return _line(st, ops[e, 6], ops[e, 7], i)
    return par[e, 2], par[e, 3], 0.0, 0.0


def _put(st, n, i, x0, x1, x2, x3, x4, x5):
    st[n, i] = x0
    st[n + 1, i] = x1
    st[n + 2, i] = x2
    st[n + 3, i] = x3
    st[n + 4, i] = x4
    st[n + 5, i] = x5


def _put4(st, n, i, x0, x1, x2, x3):
    st[n, i] = x0
    st[n + 1, i] = x1
    st[n + 2, i] = x2
    st[n + 3, i] = x3


def _sincos_rows(x, s, c):
    """s, c = sin x, cos x over 1-D arrays (separate arrays: the loop vectorises)."""
    for i in range(x.shape[0]):
        s[i], c[i] = _sincos(x[i])


def _crank(st, m, e, ops, par, q, qd, qdd, step, i0):
    n, p, L, j = ops[e, 1], ops[e, 2], ops[e, 3], ops[e, 4]
    r = par[e, 0]
    if step[0] == 0:                                # the same angle at every sample
        x = q[j, 0]
        s, c = _sincos(x) if abs(x) <= _LOSSTH else (math.sin(x), math.cos(x))
        for i in range(m):
            st[L, i] = c
            st[L + 1, i] = s
    else:
        fast = True
        for i in range(m):
            if not abs(q[j, i0 + i]) <= _LOSSTH:    # beyond 2^30 rad, inf, NaN: the C library's
                fast = False
        if fast:
            _sincos_rows(q[j, i0:i0 + m], st[L + 1, :m], st[L, :m])
        else:
            for i in range(m):
                st[L, i] = math.cos(q[j, i0 + i])
                st[L + 1, i] = math.sin(q[j, i0 + i])
    s1, s2 = step[1], step[2]
    for i in range(m):
        c, s, xd, xdd = st[L, i], st[L + 1, i], qd[j, (i0 + i) * s1], qdd[j, (i0 + i) * s2]
        rx = r * c
        ry = r * s
        w2 = xd * xd
        _put(st, n, i, st[p, i] + rx, st[p + 1, i] + ry, st[p + 2, i] - xd * ry, st[p + 3, i] + xd * rx,
             st[p + 4, i] - xdd * ry - w2 * rx, st[p + 5, i] + xdd * rx - w2 * ry)
        st[L + 2, i] = xd
        st[L + 3, i] = xdd


def _slider(st, m, e, ops, par, q, qd, qdd, step, i0):
    n, o, L, j, sl = ops[e, 1], ops[e, 6], ops[e, 3], ops[e, 4], ops[e, 8]
    s0, s1, s2 = step[0], step[1], step[2]
    for i in range(m):
        x, xd, xdd = q[j, (i0 + i) * s0], qd[j, (i0 + i) * s1], qdd[j, (i0 + i) * s2]
        c, s, w, a = _guide(st, e, ops, par, i)
        _put(st, n, i, st[o, i] + (x * c - 0.0 * s), st[o + 1, i] + (x * s + 0.0 * c), st[o + 2, i] + xd * c,
             st[o + 3, i] + xd * s, st[o + 4, i] + xdd * c, st[o + 5, i] + xdd * s)
        _put4(st, L, i, c, s, 0.0, 0.0)
        st[sl, i] = x
        st[sl + 1, i] = xd
        st[sl + 2, i] = xdd


def _rrr_at(st, i, p, pq, a2, c1, flip):
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
    C = (px + r1x, py + r1y, pvx - w1 * r1y, pvy + w1 * r1x, pax - al1 * r1y - w1s * r1x,
         pay + al1 * r1x - w1s * r1y)
    return C, r1x, r1y, r2x, r2y, w1, w2, al1, (Rx * r1x + Ry * r1y) * idet, k2 * L2


def _rrr(st, m, e, ops, par, need):
    n, p, pq, L1, L2, mu = ops[e, 1], ops[e, 2], ops[e, 3], ops[e, 4], ops[e, 5], ops[e, 6]
    a, b, a2, c1 = par[e, 0], par[e, 1], par[e, 2], par[e, 3]
    flip = ops[e, 7] < 0
    if need[L1] or need[L2] or need[mu]:         # two loops rather than tests inside one: 3x faster
        for i in range(m):
            C, r1x, r1y, r2x, r2y, w1, w2, al1, al2, det = _rrr_at(st, i, p, pq, a2, c1, flip)
            _put(st, n, i, C[0], C[1], C[2], C[3], C[4], C[5])
            _put4(st, L1, i, r1x / a, r1y / a, w1, al1)
            _put4(st, L2, i, r2x / b, r2y / b, w2, al2)
            st[mu, i] = det                      # cross(r1, r2) and r1.r2: mu = atan2(|det|, |dot|)
            st[mu + 1, i] = r1x * r2x + r1y * r2y
    else:
        for i in range(m):
            C = _rrr_at(st, i, p, pq, a2, c1, flip)[0]
            _put(st, n, i, C[0], C[1], C[2], C[3], C[4], C[5])


def _rrp(st, m, e, ops, par):
    n, p, o, Lr, Lb, sl = ops[e, 1], ops[e, 2], ops[e, 6], ops[e, 3], ops[e, 4], ops[e, 8]
    length, offset, branch = par[e, 0], par[e, 1], par[e, 4]
    l2 = length * length
    for i in range(m):
        c, s, w, a = _guide(st, e, ops, par, i)
        oe0, oe1, oe2, oe3, oe4, oe5 = _frame(st[o, i], st[o + 1, i], st[o + 2, i], st[o + 3, i],
                                              st[o + 4, i], st[o + 5, i], c, s, w, a, 0.0, offset)
        px, py, pvx, pvy, pax, pay = st[p, i], st[p + 1, i], st[p + 2, i], st[p + 3, i], st[p + 4, i], st[p + 5, i]
        wx = px - oe0
        wy = py - oe1
        wu = wx * c + wy * s
        disc = wu * wu - (wx * wx + wy * wy) + length * length
        sd = wu + branch * math.sqrt(disc)
        c0, c1, c2, c3, c4, c5 = _frame(oe0, oe1, oe2, oe3, oe4, oe5, c, s, w, a, sd, 0.0)
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
        _put(st, n, i, c0, c1, vx, vy, ax, ay)
        _put4(st, Lr, i, rx / length, ry / length, (rx * (vy - pvy) - ry * (vx - pvx)) / l2,
              (rx * (ay - pay) - ry * (ax - pax)) / l2)
        _put4(st, Lb, i, c, s, w, a)
        st[sl, i] = sd
        st[sl + 1, i] = ds
        st[sl + 2, i] = dds


def _rpr(st, m, e, ops, par):
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
        x0, x1, x2, x3, x4, x5 = _frame(st[p, i], st[p + 1, i], st[p + 2, i], st[p + 3, i], st[p + 4, i],
                                        st[p + 5, i], c, sn, w, a, length, 0.0)
        _put(st, n, i, x0, x1, x2, x3, x4, x5)
        _put4(st, L, i, c, sn, w, a)
        st[sl, i] = s
        st[sl + 1, i] = ds
        st[sl + 2, i] = dds


def _point(st, m, e, ops, par):
    n, p, pq = ops[e, 1], ops[e, 2], ops[e, 3]
    u, v = par[e, 0], par[e, 1]
    for i in range(m):
        c, s, w, a = _line(st, p, pq, i)
        x0, x1, x2, x3, x4, x5 = _frame(st[p, i], st[p + 1, i], st[p + 2, i], st[p + 3, i], st[p + 4, i],
                                        st[p + 5, i], c, s, w, a, u, v)
        _put(st, n, i, x0, x1, x2, x3, x4, x5)


def _kernel(ops, par, init, ground, need, q, qd, qdd, step, rows, out, failed, size):
    """Every sample: ``failed`` (N,) and the rows of ``out`` (n_rows, N) as ``rows`` (n_rows, 2: output
    kind, state slot) says. q, qd, qdd are (n_inputs, N) or, where ``step`` is 0, (n_inputs, 1): the same
    at every sample. ``init`` holds the state's constant slots (those listed in ``ground``); ``need``
    marks the link and mu slots that outputs read; ``size``: samples per work item."""
    n = failed.shape[0]
    for chunk in prange((n + size - 1) // size):
        i0 = chunk * size
        m = min(n - i0, size)
        st = np.empty((init.shape[0], size + 8))   # rows 4 KiB + 64 B apart: no cache-set aliasing
        for g in ground:
            st[g, :] = init[g]
        for e in range(ops.shape[0]):
            kind = ops[e, 0]
            if kind == _CRANK:
                _crank(st, m, e, ops, par, q, qd, qdd, step, i0)
            elif kind == _SLIDER:
                _slider(st, m, e, ops, par, q, qd, qdd, step, i0)
            elif kind == _RRR:
                _rrr(st, m, e, ops, par, need)
            elif kind == _RRP:
                _rrp(st, m, e, ops, par)
            elif kind == _RPR:
                _rpr(st, m, e, ops, par)
            else:
                _point(st, m, e, ops, par)
        for i in range(m):                           # the first element whose point is not finite
            f = -1
            for e in range(ops.shape[0]):
                if not math.isfinite(st[ops[e, 1], i]):
                    f = e
                    break
            failed[i0 + i] = f
        for r in range(rows.shape[0]):
            kind = rows[r, 0]
            src = rows[r, 1]
            if kind == _OUT_COPY:
                for i in range(m):
                    out[r, i0 + i] = st[src, i]
            elif kind == _OUT_PHI:
                for i in range(m):
                    out[r, i0 + i] = _atan2(st[src + 1, i], st[src, i])
            else:
                for i in range(m):
                    out[r, i0 + i] = _atan2(abs(st[src, i]), abs(st[src + 1, i]))


prange = range
_compiled = None


def _compile():
    """Import numba and compile the kernel (or load it from numba's cache), once per process."""
    global _compiled, prange
    if _compiled is None:
        import numba
        prange = numba.prange
        g = globals()
        for name in ("_sincos", "_atan2", "_frame", "_line", "_guide", "_put", "_put4", "_rrr_at"):
            g[name] = numba.njit(cache=True, error_model="numpy", inline="always")(g[name])
        for name in ("_sincos_rows", "_crank", "_slider", "_rrr", "_rrp", "_rpr", "_point"):
            g[name] = numba.njit(cache=True, error_model="numpy")(g[name])
        _compiled = numba.njit(cache=True, parallel=True, error_model="numpy")(_kernel)
    return _compiled


# ------------------------------------------------------------------------------------------ layout
class _Layout:
    """A geometry's element table and state layout, and the output names in the numpy path's order."""

    def __init__(self, geometry):
        slots = 0
        base = []                                    # slot -> first slot of its point, link, pair, mu

        def alloc(size):
            nonlocal slots
            base.extend([slots] * size)
            slots += size
            return slots - size

        point, link, slide, mu = {}, {}, {}, {}
        init = []
        for g, (x, y) in geometry.ground.items():
            point[g] = alloc(6)
            init.append((point[g], float(x), float(y)))
        elements = geometry.elements
        ops = np.zeros((len(elements), 9), dtype=np.int64)
        par = np.zeros((len(elements), 5))
        i_input = 0

        def guide(index, G):
            if "points" in G:
                ops[index, 5], ops[index, 6], ops[index, 7] = _G_LINE, point[G["points"][0]], point[G["points"][1]]
                return
            through = G["through"]
            if isinstance(through, str):
                o = point[through]
            else:
                o = alloc(6)
                init.append((o, float(through[0]), float(through[1])))
            ops[index, 5], ops[index, 6] = _G_ORIGIN, o
            par[index, 2], par[index, 3] = np.cos(G["angle"]), np.sin(G["angle"])    # as kinematics does

        for index, e in enumerate(elements):
            kind = e["kind"]
            row = ops[index]
            if kind == "crank":
                row[0], row[2], row[4] = _CRANK, point[e["pivot"]], i_input
                i_input += 1
                par[index, 0] = e["length"]
                link[e["link"]] = row[3] = alloc(4)
            elif kind == "slider":
                row[0], row[4] = _SLIDER, i_input
                i_input += 1
                guide(index, e["guide"])
                link[e["link"]] = row[3] = alloc(4)
                slide[e["link"]] = row[8] = alloc(3)
            elif kind == "RRR":
                a, b = e["lengths"]
                row[0], row[2], row[3], row[7] = _RRR, point[e["from"][0]], point[e["from"][1]], e["branch"]
                par[index, :4] = a, b, a * a, 0.5 * (a * a - b * b)             # as kinematics._rrr
                link[e["links"][0]] = row[4] = alloc(4)
                link[e["links"][1]] = row[5] = alloc(4)
                mu[e["point"]] = row[6] = alloc(2)
            elif kind == "RRP":
                row[0], row[2] = _RRP, point[e["from"]]
                par[index, 0], par[index, 1], par[index, 4] = e["length"], e["offset"], e["branch"]
                guide(index, e["guide"])
                link[e["links"][0]] = row[3] = alloc(4)
                link[e["links"][1]] = row[4] = alloc(4)
                slide[e["links"][1]] = row[8] = alloc(3)
            elif kind == "RPR":
                row[0], row[2], row[3] = _RPR, point[e["pivot"]], point[e["through"]]
                par[index, 0], par[index, 1], par[index, 4] = e["length"], e["offset"], e["branch"]
                link[e["links"][0]] = link[e["links"][1]] = row[4] = alloc(4)
                slide[e["links"][1]] = row[8] = alloc(3)
            else:
                row[0], row[2], row[3] = _POINT, point[e["on"][0]], point[e["on"][1]]
                par[index, 0], par[index, 1] = e["at"]
            point[e["point"]] = row[1] = alloc(6)
        state = np.zeros(slots)
        for o, x, y in init:
            state[o], state[o + 1] = x, y
        self.base = np.array(base, dtype=np.int64)
        self.ground = np.array([o + i for o, _, _ in init for i in range(6)], dtype=np.int64)
        names, rows = [], []
        for p, o in point.items():
            for i, prefix in enumerate(("x", "y", "vx", "vy", "ax", "ay")):
                names.append(prefix + p)
                rows.append((_OUT_COPY, o + i))
        for ln, o in link.items():                   # the order of Mechanism._block
            for prefix, kind, off in (("phi", _OUT_PHI, 0), ("omega", _OUT_COPY, 2), ("alpha", _OUT_COPY, 3),
                                      ("cos", _OUT_COPY, 0), ("sin", _OUT_COPY, 1)):
                names.append(prefix + ln)
                rows.append((kind, o + off))
        for j, o in slide.items():
            for i, prefix in enumerate(("s", "ds", "dds")):
                names.append(prefix + j)
                rows.append((_OUT_COPY, o + i))
        for p, o in mu.items():
            names.append("mu" + p)
            rows.append((_OUT_MU, o))
        self.ops, self.par, self.init = ops, par, state
        self.names = tuple(names)
        self.rows = np.array(rows, dtype=np.int64).reshape(-1, 2)


_LAYOUTS: dict[int, tuple[object, _Layout]] = {}


def _layout(geometry) -> _Layout:
    hit = _LAYOUTS.get(id(geometry))
    if hit is not None and hit[0] is geometry:
        return hit[1]
    if len(_LAYOUTS) >= 64:
        _LAYOUTS.pop(next(iter(_LAYOUTS)))
    layout = _Layout(geometry)
    _LAYOUTS[id(geometry)] = (geometry, layout)       # holds the geometry, so its id is not reused
    return layout


def solve(geometry, q, qd, qdd, want=None):
    """The outputs of :meth:`Mechanism._block` for all samples at once: ``({name: (N,) array}, failed)``.

    ``q``, ``qd``, ``qdd`` have shape (n_inputs, N); ``want`` is a set of output names (None: all). The
    arrays are rows of one (n_outputs, N) array."""
    kernel = _compile()
    layout = _layout(geometry)
    if want is None:
        names, rows = layout.names, layout.rows
    else:
        pick = [i for i, name in enumerate(layout.names) if name in want]
        names, rows = tuple(layout.names[i] for i in pick), layout.rows[pick]
    need = np.zeros(layout.init.shape[0], dtype=np.bool_)     # links and mu: only when asked for
    need[layout.base[rows[:, 1]]] = True
    n = q.shape[1]
    inputs, step = [], np.ones(3, dtype=np.int64)
    for k, a in enumerate((q, qd, qdd)):
        if n > 1 and a.strides[1] == 0:              # broadcast (a constant speed ...): not copied out
            a, step[k] = a[:, :1], 0
        inputs.append(np.ascontiguousarray(a, dtype=np.float64))
    out = np.empty((len(names), n))
    failed = np.empty(n, dtype=np.int64)
    with warnings.catch_warnings():                  # numba reads .flags.writeable, which warns for views
        warnings.simplefilter("ignore", FutureWarning)  # of np.broadcast_to arrays; only read here
        kernel(layout.ops, layout.par, layout.init, layout.ground, need, *inputs, step, rows, out, failed, CHUNK)
    return dict(zip(names, out)), failed
