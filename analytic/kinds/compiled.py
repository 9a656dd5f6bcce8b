"""What the kinds' compiled rows share (see :mod:`analytic.solver.jit`): vectorisable sin, cos and atan2,
frames, lines and guides on the solver's state array ``st`` (slot, sample), and the state's writers.

Plain Python: :func:`analytic.solver.jit.compile_kernel` replaces each function here by its numba version
(inlined) before any kernel is compiled, so a kind's kernel calls them as ``C.name(...)`` with ``C`` this
module. The formulas are those of the numpy path written per sample in the same order of operations, so
both paths round alike (sin, cos, atan2 to within 2 ulp).
"""

import math

G_LINE, G_ORIGIN = 0, 1
"""A guide's kind in a row: the line through two points of a link, or a ground line."""

HELPERS = ("sincos", "atan2", "frame", "line", "guide", "put", "put4")
"""The functions numba compiles (inlined into the kernels that call them)."""

# sin, cos and atan2 as vectorisable code: the C library's (what numba calls for math.sin ...) take 25-35 ns
# each here and keep a loop scalar; these take 3-5 ns in a vectorised loop. Coefficients and range
# reduction of Cephes (S. L. Moshier, sin.c, atan.c); within 2 ulp of numpy's (tests/test_solver_paths.py).
_DP1, _DP2, _DP3 = 7.85398125648498535156e-1, 3.77489470793079817668e-8, 2.69515142907905952645e-15
_FOPI = 1.27323954473516268615                    # 4 / pi
LOSSTH = 1.073741824e9                           # beyond: math.sin / math.cos
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


def sincos(x):
    """(sin x, cos x) for |x| <= 2^30: Cephes' range reduction modulo pi/4 (three-part pi/4) and
    polynomials, without branches so that a loop of it vectorises. Larger |x|, inf, NaN: see the crank kernel."""
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


def atan2(y, x):
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


def frame(o0, o1, o2, o3, o4, o5, c, s, w, a, u, v):
    rx = u * c - v * s
    ry = u * s + v * c
    w2 = w * w
    return (o0 + rx, o1 + ry, o2 - w * ry, o3 + w * rx, o4 - a * ry - w2 * rx, o5 + a * rx - w2 * ry)


def line(st, p, q, i):
    dx = st[q, i] - st[p, i]
    dy = st[q + 1, i] - st[p + 1, i]
    L2 = dx * dx + dy * dy
    L = math.sqrt(L2)
    w = (dx * (st[q + 3, i] - st[p + 3, i]) - dy * (st[q + 2, i] - st[p + 2, i])) / L2
    a = (dx * (st[q + 5, i] - st[p + 5, i]) - dy * (st[q + 4, i] - st[p + 4, i])) / L2
    return dx / L, dy / L, w, a


def guide(st, e, ops, par, i):
    """(c, s, w, a) of an element's guide line at sample i (laid out by Layout.guide: its kind in
    ops[e, 5], origin slot in ops[e, 6], second point's slot in ops[e, 7]; a ground line's direction in
    par[e, 2:4])."""
    if ops[e, 5] == G_LINE:
        return line(st, ops[e, 6], ops[e, 7], i)
    return par[e, 2], par[e, 3], 0.0, 0.0


def put(st, n, i, x0, x1, x2, x3, x4, x5):
    st[n, i] = x0
    st[n + 1, i] = x1
    st[n + 2, i] = x2
    st[n + 3, i] = x3
    st[n + 4, i] = x4
    st[n + 5, i] = x5


def put4(st, n, i, x0, x1, x2, x3):
    st[n, i] = x0
    st[n + 1, i] = x1
    st[n + 2, i] = x2
    st[n + 3, i] = x3
