"""Optional compiled path of the general solver: the formulas of :mod:`analytic.kinematics`, sample by
sample, compiled with numba and run in parallel over the samples.

It is used by :meth:`analytic.mechanism.Mechanism.solve` when numba is installed (``pip install
linkage[jit]``) and the environment variable ``LINKAGE_JIT`` is not ``"0"``; without numba, numpy stays
the solver. Both give the same numbers to rounding (tests/test_solver_paths.py).

How it works: a mechanism's elements become a table of integer codes (kind, state slots of the points,
links and prismatic pairs each one reads and writes) and one of numbers (lengths, offsets, branches);
one compiled function, the same for every mechanism, walks that table for each sample, keeping the
sample's state (6 numbers per point, 4 per link, 3 per pair) in a small scratch vector, then writes the
requested outputs. Link angles and transmission angles (an arctan2 each) are computed only when asked
for. numba is imported, and the function compiled (or loaded from numba's on-disk cache, ``cache=True``:
a few seconds the first time on a machine, well under a second after), at the first solve.
"""

from __future__ import annotations

import importlib.util
import math
import os

import numpy as np

AVAILABLE = importlib.util.find_spec("numba") is not None
"""Whether numba can be imported (it is not imported until the first compiled solve)."""

CHUNK = 512
"""Samples per parallel work item."""

# element kinds, guide kinds, output kinds
_CRANK, _SLIDER, _RRR, _RRP, _RPR, _POINT = range(6)
_G_LINE, _G_ORIGIN = 0, 1
_OUT_COPY, _OUT_PHI, _OUT_MU = 0, 1, 2


def enabled() -> bool:
    """True when solves go through the compiled path: numba importable and LINKAGE_JIT != "0"."""
    return AVAILABLE and os.environ.get("LINKAGE_JIT", "1") != "0"


# ------------------------------------------------------------------------------ per-sample formulas
# Plain Python here; :func:`_compile` turns them into numba functions. Each mirrors the function of the
# same name in analytic.kinematics operation for operation, so both paths round alike.

def _line(st, p, q):
    dx = st[q] - st[p]
    dy = st[q + 1] - st[p + 1]
    L2 = dx * dx + dy * dy
    L = math.sqrt(L2)
    w = (dx * (st[q + 3] - st[p + 3]) - dy * (st[q + 2] - st[p + 2])) / L2
    a = (dx * (st[q + 5] - st[p + 5]) - dy * (st[q + 4] - st[p + 4])) / L2
    return dx / L, dy / L, w, a


def _frame(o0, o1, o2, o3, o4, o5, c, s, w, a, u, v):
    rx = u * c - v * s
    ry = u * s + v * c
    w2 = w * w
    return (o0 + rx, o1 + ry, o2 - w * ry, o3 + w * rx, o4 - a * ry - w2 * rx, o5 + a * rx - w2 * ry)


def _put(st, n, x0, x1, x2, x3, x4, x5):
    st[n] = x0
    st[n + 1] = x1
    st[n + 2] = x2
    st[n + 3] = x3
    st[n + 4] = x4
    st[n + 5] = x5


def _put4(st, n, x0, x1, x2, x3):
    st[n] = x0
    st[n + 1] = x1
    st[n + 2] = x2
    st[n + 3] = x3


def _guide(st, e, ops, par):
    """(origin slot, c, s, w, a) of an element's guide line."""
    o = ops[e, 6]
    if ops[e, 5] == _G_LINE:
        c, s, w, a = _line(st, o, ops[e, 7])
        return o, c, s, w, a
    return o, par[e, 2], par[e, 3], 0.0, 0.0


def _link_from(st, p, n, length, L):
    rx = st[n] - st[p]
    ry = st[n + 1] - st[p + 1]
    l2 = length * length
    _put4(st, L, rx / length, ry / length, (rx * (st[n + 3] - st[p + 3]) - ry * (st[n + 2] - st[p + 2])) / l2,
          (rx * (st[n + 5] - st[p + 5]) - ry * (st[n + 4] - st[p + 4])) / l2)


def _sample(st, ops, par, qi, qdi, qddi):
    """Solve every element at one sample into the state vector; the index of the first element whose
    point is not finite, -1 if none."""
    fail = -1
    for e in range(ops.shape[0]):
        kind = ops[e, 0]
        n = ops[e, 1]
        if kind == _CRANK:
            p, j = ops[e, 2], ops[e, 4]
            r = par[e, 0]
            x, xd, xdd = qi[j], qdi[j], qddi[j]
            c = math.cos(x)
            s = math.sin(x)
            rx = r * c
            ry = r * s
            w2 = xd * xd
            _put(st, n, st[p] + rx, st[p + 1] + ry, st[p + 2] - xd * ry, st[p + 3] + xd * rx,
                 st[p + 4] - xdd * ry - w2 * rx, st[p + 5] + xdd * rx - w2 * ry)
            _put4(st, ops[e, 3], c, s, xd, xdd)
        elif kind == _SLIDER:
            j = ops[e, 4]
            x, xd, xdd = qi[j], qdi[j], qddi[j]
            o, c, s, w, a = _guide(st, e, ops, par)
            _put(st, n, st[o] + (x * c - 0.0 * s), st[o + 1] + (x * s + 0.0 * c), st[o + 2] + xd * c,
                 st[o + 3] + xd * s, st[o + 4] + xdd * c, st[o + 5] + xdd * s)
            _put4(st, ops[e, 3], c, s, 0.0, 0.0)
            sl = ops[e, 8]
            st[sl] = x
            st[sl + 1] = xd
            st[sl + 2] = xdd
        elif kind == _RRR:
            p, q = ops[e, 2], ops[e, 3]
            a, b, a2, c1 = par[e, 0], par[e, 1], par[e, 2], par[e, 3]
            px, py, pvx, pvy, pax, pay = st[p], st[p + 1], st[p + 2], st[p + 3], st[p + 4], st[p + 5]
            dx = st[q] - px
            dy = st[q + 1] - py
            L2 = dx * dx + dy * dy
            inv = 1.0 / L2
            k1 = inv * c1 + 0.5
            k2 = math.sqrt(inv * a2 - k1 * k1)
            if ops[e, 7] < 0:
                k2 = -k2
            r1x = k1 * dx - k2 * dy
            r1y = k1 * dy + k2 * dx
            r2x = r1x - dx
            r2y = r1y - dy
            idet = inv / k2
            dvx = st[q + 2] - pvx
            dvy = st[q + 3] - pvy
            w1 = (r2x * dvx + r2y * dvy) * idet
            w2 = (r1x * dvx + r1y * dvy) * idet
            w1s = w1 * w1
            w2s = w2 * w2
            Rx = st[q + 4] - pax + w1s * r1x - w2s * r2x
            Ry = st[q + 5] - pay + w1s * r1y - w2s * r2y
            al1 = (Rx * r2x + Ry * r2y) * idet
            al2 = (Rx * r1x + Ry * r1y) * idet
            _put(st, n, px + r1x, py + r1y, pvx - w1 * r1y, pvy + w1 * r1x,
                 pax - al1 * r1y - w1s * r1x, pay + al1 * r1x - w1s * r1y)
            _put4(st, ops[e, 4], r1x / a, r1y / a, w1, al1)
            _put4(st, ops[e, 5], r2x / b, r2y / b, w2, al2)
            m = ops[e, 6]
            st[m] = k2 * L2                      # cross(r1, r2) and r1.r2: mu = atan2(|det|, |dot|)
            st[m + 1] = r1x * r2x + r1y * r2y
        elif kind == _RRP:
            p = ops[e, 2]
            length, offset, branch = par[e, 0], par[e, 1], par[e, 4]
            o, c, s, w, a = _guide(st, e, ops, par)
            oe0, oe1, oe2, oe3, oe4, oe5 = _frame(st[o], st[o + 1], st[o + 2], st[o + 3], st[o + 4], st[o + 5],
                                                  c, s, w, a, 0.0, offset)
            wx = st[p] - oe0
            wy = st[p + 1] - oe1
            wu = wx * c + wy * s
            disc = wu * wu - (wx * wx + wy * wy) + length * length
            sd = wu + branch * math.sqrt(disc)
            c0, c1, c2, c3, c4, c5 = _frame(oe0, oe1, oe2, oe3, oe4, oe5, c, s, w, a, sd, 0.0)
            rx = c0 - st[p]
            ry = c1 - st[p + 1]
            ru = rx * c + ry * s
            ds = -(rx * (c2 - st[p + 2]) + ry * (c3 - st[p + 3])) / ru
            vx = c2 + ds * c
            vy = c3 + ds * s
            ax0 = c4 - 2.0 * ds * w * s
            ay0 = c5 + 2.0 * ds * w * c
            ux = vx - st[p + 2]
            uy = vy - st[p + 3]
            dds = -(rx * (ax0 - st[p + 4]) + ry * (ay0 - st[p + 5]) + ux * ux + uy * uy) / ru
            _put(st, n, c0, c1, vx, vy, ax0 + dds * c, ay0 + dds * s)
            _link_from(st, p, n, length, ops[e, 3])
            _put4(st, ops[e, 4], c, s, w, a)
            sl = ops[e, 8]
            st[sl] = sd
            st[sl + 1] = ds
            st[sl + 2] = dds
        elif kind == _RPR:
            p, q = ops[e, 2], ops[e, 3]
            length, offset, branch = par[e, 0], par[e, 1], par[e, 4]
            dx = st[q] - st[p]
            dy = st[q + 1] - st[p + 1]
            d2 = dx * dx + dy * dy
            s = branch * math.sqrt(d2 - offset * offset)
            c = (s * dx + offset * dy) / d2
            sn = (s * dy - offset * dx) / d2
            vdx = st[q + 2] - st[p + 2]
            vdy = st[q + 3] - st[p + 3]
            w = (-vdx * sn + vdy * c) / s
            ds = vdx * c + vdy * sn + offset * w
            adx = st[q + 4] - st[p + 4]
            ady = st[q + 5] - st[p + 5]
            a = (-adx * sn + ady * c - 2.0 * ds * w + offset * w * w) / s
            dds = adx * c + ady * sn + s * w * w + offset * a
            x0, x1, x2, x3, x4, x5 = _frame(st[p], st[p + 1], st[p + 2], st[p + 3], st[p + 4], st[p + 5],
                                            c, sn, w, a, length, 0.0)
            _put(st, n, x0, x1, x2, x3, x4, x5)
            _put4(st, ops[e, 4], c, sn, w, a)
            sl = ops[e, 8]
            st[sl] = s
            st[sl + 1] = ds
            st[sl + 2] = dds
        else:
            p, q = ops[e, 2], ops[e, 3]
            c, s, w, a = _line(st, p, q)
            x0, x1, x2, x3, x4, x5 = _frame(st[p], st[p + 1], st[p + 2], st[p + 3], st[p + 4], st[p + 5],
                                            c, s, w, a, par[e, 0], par[e, 1])
            _put(st, n, x0, x1, x2, x3, x4, x5)
        if fail < 0 and not math.isfinite(st[n]):
            fail = e
    return fail


def _kernel(ops, par, init, q, qd, qdd, rows, out, failed):
    """Every sample of q, qd, qdd (n_inputs, N): ``failed`` (N,) and the rows of ``out`` (n_rows, N) as
    ``rows`` (n_rows, 2: output kind, state slot) says."""
    n = q.shape[1]
    k = q.shape[0]
    nr = rows.shape[0]
    for chunk in prange((n + CHUNK - 1) // CHUNK):
        st = init.copy()
        qi = np.empty(k)
        qdi = np.empty(k)
        qddi = np.empty(k)
        for i in range(chunk * CHUNK, min(n, (chunk + 1) * CHUNK)):
            for j in range(k):
                qi[j] = q[j, i]
                qdi[j] = qd[j, i]
                qddi[j] = qdd[j, i]
            failed[i] = _sample(st, ops, par, qi, qdi, qddi)
            for r in range(nr):
                kind = rows[r, 0]
                src = rows[r, 1]
                if kind == _OUT_COPY:
                    out[r, i] = st[src]
                elif kind == _OUT_PHI:
                    out[r, i] = math.atan2(st[src + 1], st[src])
                else:
                    out[r, i] = math.atan2(abs(st[src]), abs(st[src + 1]))


prange = range
_compiled = None


def _compile():
    """Import numba and compile (or load from its cache) the kernel, once per process."""
    global _compiled, prange
    if _compiled is None:
        import numba
        prange = numba.prange
        g = globals()
        for name in ("_line", "_frame", "_put", "_put4", "_guide", "_link_from", "_sample"):
            g[name] = numba.njit(cache=True, inline="always", error_model="numpy")(g[name])
        _compiled = numba.njit(cache=True, parallel=True, error_model="numpy")(_kernel)
    return _compiled


# ------------------------------------------------------------------------------------------ layout
class _Layout:
    """A geometry's element table and state layout, and the output names in the numpy path's order."""

    def __init__(self, geometry):
        slots = 0

        def alloc(size):
            nonlocal slots
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
    q, qd, qdd = (np.ascontiguousarray(a, dtype=np.float64) for a in (q, qd, qdd))
    n = q.shape[1]
    out = np.empty((len(names), n))
    failed = np.empty(n, dtype=np.int64)
    kernel(layout.ops, layout.par, layout.init, q, qd, qdd, rows, out, failed)
    return dict(zip(names, out)), failed
