"""Motion laws: the shapes of a rise (SPEC "Drives ... motion laws") and the laws built from them.

One library for every law of motion, of an input over time (:class:`Profile`: ``segments`` run in order;
:class:`Table`: a cubic spline through (t, q)) and, later, of a cam's follower over the cam's angle.

A shape is a pure function of the normalised abscissa x in [0, 1] (time in the segment over its duration)
giving the fraction y of the rise and its exact derivatives (:func:`shape`): (y, y', y'', y''') with
y(0) = 0, y(1) = 1 (a dwell: y = 0). A segment of duration T and rise h then moves q = h y(t / T), with
dq/dt = h y' / T, d2q/dt2 = h y'' / T^2 and d3q/dt3 = h y''' / T^3. The peak |y''| is the shape's
acceleration coefficient C_a: peak acceleration C_a h / T^2 (Norton, Design of Machinery, ch. 8: cycloidal
2 pi, 3-4-5 polynomial 5.774, 4-5-6-7 polynomial 7.513, modified trapezoid 4.888, modified sine 5.528).

The modified trapezoid and modified sine are written here from their acceleration (Norton ch. 8): the
trapezoid's ramps replaced by quarter-sine waves of period 1/2 (trapezoid: quarter waves on [0, 1/8],
[3/8, 1/2], a constant between, odd about x = 1/2), the modified sine a quarter wave of period 1/2 on
[0, 1/8] and [7/8, 1] joined by a 3/2-period sine; each piece integrated in closed form and the peak set so
that y(1) = 1.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

SHAPES = ("dwell", "constant", "harmonic", "parabolic", "cycloidal", "poly345", "poly4567",
          "modified_trapezoid", "modified_sine")
"""The segment shapes, as a file names them."""

CLOSE = 1e-9
"""Relative tolerance [of the largest |value| involved] under which two velocities or accelerations at a
segment boundary are the same (a jump smaller than that is the closed forms' rounding) and under which a
profile's net rise is a whole number of turns."""


# ------------------------------------------------------------------------------------------ shapes
@dataclass(frozen=True)
class _Piece:
    """One piece of a normalised law given by its acceleration on [x0, x1): ``k`` (constant) or
    ``k sin(w (x - x0) + p)`` (w > 0); ``y0``, ``v0``: the value and slope at x0."""

    x0: float
    x1: float
    k: float
    w: float = 0.0
    p: float = 0.0
    y0: float = 0.0
    v0: float = 0.0

    def end(self) -> tuple[float, float]:
        """(y, y') at x1."""
        y, v, _, _ = self.eval(np.array([self.x1]))
        return float(y[0]), float(v[0])

    def eval(self, x):
        u = x - self.x0
        if self.w == 0.0:
            a = np.full_like(u, self.k)
            return self.y0 + self.v0 * u + 0.5 * self.k * u * u, self.v0 + self.k * u, a, np.zeros_like(u)
        k, w, p = self.k, self.w, self.p
        arg = w * u + p
        s, c = np.sin(arg), np.cos(arg)
        v = self.v0 + k / w * (math.cos(p) - c)
        y = self.y0 + self.v0 * u + k / w * (u * math.cos(p) - (s - math.sin(p)) / w)
        return y, v, k * s, k * w * c


def _chain(pieces) -> tuple[_Piece, ...]:
    """Pieces (x0, x1, k, w, p) of a unit-peak acceleration integrated in turn from rest at y = 0, then
    scaled so that y(1) = 1."""
    out, y, v = [], 0.0, 0.0
    for x0, x1, k, w, p in pieces:
        piece = _Piece(x0, x1, k, w, p, y, v)
        y, v = piece.end()
        out.append(piece)
    return tuple(_Piece(q.x0, q.x1, q.k / y, q.w, q.p, q.y0 / y, q.v0 / y) for q in out)


_HALF = math.pi / 2
MODIFIED_TRAPEZOID = _chain([(0.0, 1 / 8, 1.0, 4 * math.pi, 0.0), (1 / 8, 3 / 8, 1.0, 0.0, 0.0),
                             (3 / 8, 5 / 8, 1.0, 4 * math.pi, _HALF), (5 / 8, 7 / 8, -1.0, 0.0, 0.0),
                             (7 / 8, 1.0, -1.0, 4 * math.pi, _HALF)])
"""The modified trapezoid's pieces: a sin(4 pi x) up to 1/8, the peak held to 3/8, a cosine through zero at
1/2 to the negative peak at 5/8, held to 7/8, back to zero at 1 (Norton ch. 8)."""

MODIFIED_SINE = _chain([(0.0, 1 / 8, 1.0, 4 * math.pi, 0.0), (1 / 8, 7 / 8, 1.0, 4 * math.pi / 3, _HALF),
                        (7 / 8, 1.0, -1.0, 4 * math.pi, _HALF)])
"""The modified sine's pieces: a sin(4 pi x) up to 1/8, a cos(4 pi / 3 (x - 1/8)) through zero at 1/2 to
the negative peak at 7/8, then back to zero at 1 (Norton ch. 8)."""


def _pieces(pieces, x):
    out = [np.zeros_like(x) for _ in range(4)]
    for k, piece in enumerate(pieces):
        last = k == len(pieces) - 1
        m = (x >= piece.x0) & ((x <= piece.x1) if last else (x < piece.x1))
        if m.any():
            for o, v in zip(out, piece.eval(x[m])):
                o[m] = v
    return tuple(out)


def shape(name: str, x) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(y, dy/dx, d2y/dx2, d3y/dx3) of shape ``name`` (one of :data:`SHAPES`) at ``x`` in [0, 1] (an array;
    values outside are clipped: the segment's ends)."""
    x = np.clip(np.asarray(x, dtype=float), 0.0, 1.0)
    zero = np.zeros(x.shape)
    if name == "dwell":
        return zero, zero.copy(), zero.copy(), zero.copy()
    if name == "constant":
        return x, zero + 1.0, zero, zero.copy()
    if name == "harmonic":
        a = math.pi * x
        return ((1 - np.cos(a)) / 2, math.pi / 2 * np.sin(a), math.pi ** 2 / 2 * np.cos(a),
                -math.pi ** 3 / 2 * np.sin(a))
    if name == "parabolic":
        first = x < 0.5
        return (np.where(first, 2 * x * x, 1 - 2 * (1 - x) ** 2), np.where(first, 4 * x, 4 * (1 - x)),
                np.where(first, 4.0, -4.0), zero.copy())
    if name == "cycloidal":
        a = 2 * math.pi * x
        s, c = np.sin(a), np.cos(a)
        return (x - s * (1 / (2 * math.pi)), 1 - c, s * (2 * math.pi), c * (4 * math.pi ** 2))
    if name == "poly345":
        return (x ** 3 * (10 - 15 * x + 6 * x * x), x * x * (30 - 60 * x + 30 * x * x),
                x * (60 - 180 * x + 120 * x * x), 60 - 360 * x + 360 * x * x)
    if name == "poly4567":
        return (x ** 4 * (35 - 84 * x + 70 * x * x - 20 * x ** 3), x ** 3 * (140 - 420 * x + 420 * x * x - 140 * x ** 3),
                x * x * (420 - 1680 * x + 2100 * x * x - 840 * x ** 3),
                x * (840 - 5040 * x + 8400 * x * x - 4200 * x ** 3))
    if name == "modified_trapezoid":
        return _pieces(MODIFIED_TRAPEZOID, x)
    if name == "modified_sine":
        return _pieces(MODIFIED_SINE, x)
    raise ValueError(f"unknown shape {name!r}; shapes: {', '.join(SHAPES)}")


def shape_pieces(name: str) -> tuple[tuple[float, float, tuple[float, ...], float, float, float], ...]:
    """Shape ``name`` as pieces (x0, x1, c, A, w, p) on [x0, x1): y = sum_k c[k] u^k + A sin(w u + p) with
    u = x - x0, the same closed forms as :func:`shape` written as a polynomial and one sine each (a dwell: none
    of either), so that a profile evaluates every sample in one pass (:class:`Compiled`)."""
    tau = 2 * math.pi
    if name == "dwell":
        return ((0.0, 1.0, (0.0,), 0.0, 0.0, 0.0),)
    if name == "constant":
        return ((0.0, 1.0, (0.0, 1.0), 0.0, 0.0, 0.0),)
    if name == "harmonic":                          # (1 - cos pi x) / 2 = 1/2 - sin(pi x + pi/2) / 2
        return ((0.0, 1.0, (0.5,), -0.5, math.pi, _HALF),)
    if name == "parabolic":                         # 1 - 2 (1 - x)^2 = 1/2 + 2 u - 2 u^2 with u = x - 1/2
        return ((0.0, 0.5, (0.0, 0.0, 2.0), 0.0, 0.0, 0.0), (0.5, 1.0, (0.5, 2.0, -2.0), 0.0, 0.0, 0.0))
    if name == "cycloidal":
        return ((0.0, 1.0, (0.0, 1.0), -1.0 / tau, tau, 0.0),)
    if name == "poly345":
        return ((0.0, 1.0, (0.0, 0.0, 0.0, 10.0, -15.0, 6.0), 0.0, 0.0, 0.0),)
    if name == "poly4567":
        return ((0.0, 1.0, (0.0, 0.0, 0.0, 0.0, 35.0, -84.0, 70.0, -20.0), 0.0, 0.0, 0.0),)
    if name in ("modified_trapezoid", "modified_sine"):
        # an acceleration k sin(w u + p) integrated from (y0, v0): y0 + k sin p / w^2 + (v0 + k cos p / w) u
        # - k / w^2 sin(w u + p); a constant k: y0 + v0 u + k u^2 / 2
        out = []
        for q in (MODIFIED_TRAPEZOID if name == "modified_trapezoid" else MODIFIED_SINE):
            if q.w == 0.0:
                out.append((q.x0, q.x1, (q.y0, q.v0, 0.5 * q.k), 0.0, 0.0, 0.0))
            else:
                out.append((q.x0, q.x1, (q.y0 + q.k * math.sin(q.p) / q.w ** 2, q.v0 + q.k * math.cos(q.p) / q.w),
                            -q.k / q.w ** 2, q.w, q.p))
        return tuple(out)
    raise ValueError(f"unknown shape {name!r}; shapes: {', '.join(SHAPES)}")


@dataclass(frozen=True)
class Compiled:
    """A profile's pieces over one cycle, ready to evaluate every sample at once: ``breaks`` (P - 1,) the
    times [s] where each piece after the first starts (the first starts at 0); ``starts`` (P,) every piece's
    start; ``poly`` (D, 4, P) the coefficients of q (its start value included), dq, ddq and dddq in powers
    0..D-1 of the time since the piece's start; ``wave`` (2, P) the angular frequency [rad/s] and phase of
    its sine term and ``amp`` (4, P) the amplitude of that term in q and its three derivatives, A w^d
    (d/du A sin(w u + p) = A w sin(w u + p + pi/2)); all zero where a piece has none.

    ``basis`` (4, P, B): the same as each derivative's weights on one basis per sample, 1, u .. u^(D-1), then
    (where any piece has a sine) sin(w u + p) and cos(w u + p): A w^d sin(w u + p + d pi/2) is A w^d times
    s, c, -s, -c for d = 0..3. Every derivative is then one matrix product with the basis."""

    breaks: np.ndarray
    starts: np.ndarray
    poly: np.ndarray
    wave: np.ndarray
    amp: np.ndarray
    has_sine: bool
    degree: tuple = ()
    """Per derivative and piece the highest power with a non-zero coefficient (-1: none)."""
    basis: np.ndarray = None

    @classmethod
    def of(cls, segments) -> Compiled:
        rows, waves, amps, starts = [], [], [], []
        start, lift = 0.0, 0.0
        for seg in segments:
            T, h = seg.duration, seg.rise
            for x0, _x1, c, A, w, p in shape_pieces(seg.shape if h != 0.0 else "dwell"):
                starts.append(start + x0 * T)
                rows.append([h * ck / T ** k for k, ck in enumerate(c)])
                rows[-1][0] += lift
                waves.append((w / T, p))
                amps.append([A * h * (w / T) ** d for d in range(4)])
            start += T
            lift += h
        deg = max(len(r) for r in rows)
        poly = np.zeros((len(rows), 4, deg))
        k = np.arange(deg, dtype=float)
        for i, r in enumerate(rows):
            poly[i, 0, :len(r)] = r
            for d in range(1, 4):                    # d/du of sum c_k u^k: sum k c_k u^(k - 1)
                poly[i, d, :-1] = poly[i, d - 1, 1:] * k[1:]
        amp = np.asarray(amps, dtype=float)
        degree = tuple(tuple(int(np.flatnonzero(poly[i, d])[-1]) if poly[i, d].any() else -1
                             for i in range(len(rows))) for d in range(4))
        has_sine = bool(np.any(amp[:, 0] != 0.0))
        basis = poly.transpose(1, 0, 2)                                   # (4, P, D)
        if has_sine:                                 # A w^d on s (d even, sign (-1)^(d/2)) or c (d odd)
            sc = np.zeros((4, len(rows), 2))
            for d in range(4):
                sc[d, :, d % 2] = (-1.0) ** (d // 2) * amp[:, d]
            basis = np.concatenate([basis, sc], axis=2)
        return cls(np.asarray(starts[1:]), np.asarray(starts), np.ascontiguousarray(poly.transpose(2, 1, 0)),
                   np.ascontiguousarray(np.asarray(waves, dtype=float).T), np.ascontiguousarray(amp.T),
                   has_sine, degree, np.ascontiguousarray(basis))

    @staticmethod
    def _basis(u, w, p, top: int, sine: bool) -> np.ndarray:
        """(top + 1 [+ 2], n): 1, u .. u^top [, sin(w u + p), cos(w u + p)] at the times ``u`` since the pieces'
        starts (``w``, ``p``: scalars, or per sample)."""
        out = np.empty((top + 1 + (2 if sine else 0), len(u)))
        out[0] = 1.0
        if top >= 1:
            out[1] = u
        for d in range(2, top + 1):
            np.multiply(out[d - 1], u, out=out[d])
        if sine:
            th = u * w
            th += p
            np.sin(th, out=out[top + 1])
            np.cos(th, out=out[top + 2])
        return out

    def at(self, tau, rows: int = 4) -> np.ndarray:
        """(q, dq, ddq, dddq) stacked (``rows``, N) (the first ``rows`` of them) at the times ``tau`` [s] in the
        cycle (a flat array). Samples in long runs of one piece, from :data:`RUNS` of them on, are evaluated a
        run at a time (views, no gather: the cheaper per sample); others as every piece's rows times the basis
        of each sample (one matrix product), each sample's own piece's taken (one search, one gather: the
        cheaper per call)."""
        k = np.searchsorted(self.breaks, tau, side="right")       # the piece: 0 .. P - 1
        n = len(tau)
        if n >= RUNS:
            change = np.flatnonzero(k[1:] != k[:-1]) + 1
            if len(change) * 64 <= n:              # long runs of one piece (samples in time order)
                return self._runs(tau, k, change, rows)
        u = tau - self.starts.take(k)
        P = len(self.starts)
        w, p = self.wave.take(k, axis=1) if self.has_sine else (0.0, 0.0)
        every = self.basis[:rows].reshape(rows * P, -1) @ self._basis(u, w, p, len(self.poly) - 1, self.has_sine)
        return every.reshape(rows, P * n).take(k * n + np.arange(n), axis=1)   # row r: piece k_i's at sample i

    def _runs(self, tau, k, change, rows: int) -> np.ndarray:
        """:meth:`at` a run of samples of one piece (``k``: each sample's; ``change``: where a run starts) at a
        time: each a slice, its piece's rows times the slice's basis (only the powers it has, its sine if any)."""
        out = np.empty((rows, len(tau)))
        bounds = [0, *change.tolist(), len(tau)]
        D = len(self.poly)
        for a, b, p in zip(bounds[:-1], bounds[1:], k[bounds[:-1]].tolist()):
            top = max(self.degree[r][p] for r in range(rows))
            sine = bool(self.amp[0, p] != 0.0)
            if top <= 0 and not sine:                # a constant (0 where all are zero)
                out[:, a:b] = self.basis[:rows, p, :1]
                continue
            weights = self.basis[:rows, p, :top + 1]
            if sine:
                weights = np.concatenate([weights, self.basis[:rows, p, D:]], axis=1)
            np.matmul(weights, self._basis(tau[a:b] - self.starts[p], self.wave[0, p], self.wave[1, p], top, sine),
                      out=out[:, a:b])
        return out


RUNS = 1000
"""From this many samples on, a profile whose samples come in runs of one piece (64 or more on average: samples
in time order) is evaluated a run at a time (benchmarks/motion_laws.py, the servo press's drive: the gather's
per-sample cost overtakes the runs' per-piece cost near 1000 samples)."""


# --------------------------------------------------------------------------------------- profiles
@dataclass(frozen=True)
class Segment:
    """One segment of a profile: its ``shape`` (:data:`SHAPES`), ``duration`` [s] > 0 and ``rise`` (the
    input's change over it [rad or m]; 0 for a dwell)."""

    shape: str
    duration: float
    rise: float = 0.0

    def at(self, tau):
        """(q, dq, ddq, dddq) at times ``tau`` [s] from the segment's start, q from its start value."""
        T, h = self.duration, self.rise
        y, y1, y2, y3 = shape(self.shape, np.asarray(tau, dtype=float) * (1.0 / T))
        y *= h                                     # in place: the shape's arrays are its own
        y1 *= h / T
        y2 *= h / T ** 2
        y3 *= h / T ** 3
        return y, y1, y2, y3


@dataclass(frozen=True)
class Jump:
    """A jump between two segments (or from the cycle's end to its start: ``after`` the last, ``before``
    0): at time ``t`` [s] of the cycle, where the input is at ``q`` (from its start value), its velocity
    jumps by ``dv`` and its acceleration by ``da`` (after minus before; 0 where it is continuous)."""

    after: int
    before: int
    t: float
    q: float
    dv: float
    da: float


@dataclass(frozen=True)
class Profile:
    """``segments`` run in order from t = 0: one cycle of :attr:`duration`; the motion repeats after it,
    each cycle starting where the last ended (q(t + T) = q(t) + :attr:`rise`)."""

    segments: tuple[Segment, ...]

    @property
    def duration(self) -> float:
        return float(sum(s.duration for s in self.segments))

    @property
    def rise(self) -> float:
        """The net change of the input over one cycle [rad or m]."""
        return float(sum(s.rise for s in self.segments))

    @functools.cached_property
    def starts(self) -> np.ndarray:
        """Each segment's start time [s] in the cycle, and the cycle's end."""
        return np.r_[0.0, np.cumsum([s.duration for s in self.segments])]

    @functools.cached_property
    def lifted(self) -> np.ndarray:
        """The input at each segment's start, from the cycle's start value [rad or m], and at the end."""
        return np.r_[0.0, np.cumsum([s.rise for s in self.segments])]

    @functools.cached_property
    def compiled(self) -> Compiled:
        """The segments' pieces and their coefficients, built once (:class:`Compiled`)."""
        return Compiled.of(self.segments)

    @functools.cached_property
    def _cycle(self) -> tuple[float, float]:
        return self.duration, self.rise

    def at(self, t, jerk: bool = True):
        """(q, dq, ddq, dddq) at times ``t`` [s] (any shape), q from the start value, evaluated together
        (:attr:`compiled`; no loop over the segments); ``jerk=False``: dddq not computed (None)."""
        t = np.asarray(t, dtype=float)
        shape_ = t.shape
        t = t.reshape(-1)
        T, rise = self._cycle
        n = np.floor(t / T)                        # each sample's cycle; in place below (fewer temporaries)
        tau = n * T
        np.subtract(t, tau, out=tau)
        out = self.compiled.at(tau, 4 if jerk else 3)
        if rise != 0.0:
            n *= rise
            out[0] += n
        return tuple(x.reshape(shape_) for x in out) + (() if jerk else (None,))

    def at_segments(self, t):
        """(q, dq, ddq, dddq) at times ``t`` [s] as :meth:`at`, segment by segment through :meth:`Segment.at`
        (:func:`shape`'s closed forms): the reference :meth:`at` is checked against."""
        t = np.asarray(t, dtype=float)
        shape_ = t.shape
        t = t.reshape(-1)
        T = self.duration
        n = np.floor(t / T)
        tau = t - n * T
        starts = self.starts
        k = np.searchsorted(starts, tau, side="right") - 1
        np.clip(k, 0, len(self.segments) - 1, out=k)
        q = n * self.rise + self.lifted[k]
        v, a, j = np.zeros_like(t), np.zeros_like(t), np.zeros_like(t)
        for i, seg in enumerate(self.segments):
            if seg.shape == "dwell" or seg.rise == 0.0:
                continue
            idx = np.flatnonzero(k == i)
            parts = seg.at(tau[idx] - starts[i])
            q[idx] += parts[0]
            v[idx], a[idx], j[idx] = parts[1:]
        return tuple(x.reshape(shape_) for x in (q, v, a, j))

    def jumps(self, closed: bool = True) -> tuple[Jump, ...]:
        """Every jump in velocity or acceleration between consecutive segments, and (``closed``: the cycle
        repeats) from the last segment into the first, where the next cycle begins."""
        segs = self.segments
        starts = self.starts
        pairs = list(zip(range(len(segs) - 1), range(1, len(segs))))
        if closed:
            pairs.append((len(segs) - 1, 0))
        ends = [s.at(np.array([s.duration])) for s in segs]
        begins = [s.at(np.array([0.0])) for s in segs]
        scale_v = max(max(abs(s.rise) / s.duration for s in segs), 1e-300)
        scale_a = max(max(abs(s.rise) / s.duration ** 2 for s in segs), 1e-300)
        lifted = self.lifted
        out = []
        for a, b in pairs:
            dv = float(begins[b][1][0] - ends[a][1][0])
            da = float(begins[b][2][0] - ends[a][2][0])
            dv = 0.0 if abs(dv) <= CLOSE * 10 * scale_v else dv
            da = 0.0 if abs(da) <= CLOSE * 100 * scale_a else da
            if dv or da:
                t = float(starts[a + 1])
                out.append(Jump(a, b, t, float(lifted[a + 1]), dv, da))
        return tuple(out)


@dataclass(frozen=True)
class Table:
    """A law given as samples (t, q) [s; rad or m], t increasing from its first value: a cubic spline
    (continuous acceleration), periodic where the table closes (q at its end equal to q at its start plus
    ``period_rise``: 0, or for a crank a whole number of turns), else with not-a-knot ends. One cycle runs
    from the first t to the last; q is given from the first row's value."""

    t: tuple[float, ...]
    q: tuple[float, ...]
    period_rise: float | None = None
    """The net change over a cycle that makes the spline periodic, or None (not-a-knot ends)."""

    @property
    def duration(self) -> float:
        return float(self.t[-1] - self.t[0])

    @property
    def rise(self) -> float:
        return float(self.q[-1] - self.q[0])

    def _spline(self):
        return self._spline_once

    @functools.cached_property
    def _spline_once(self):
        from scipy.interpolate import CubicSpline
        t = np.asarray(self.t) - self.t[0]
        q = np.asarray(self.q) - self.q[0]
        if self.period_rise is None:
            return CubicSpline(t, q, bc_type="not-a-knot" if len(t) > 3 else "natural")
        trend = self.period_rise * t / t[-1]
        resid = q - trend
        resid[-1] = resid[0]
        return CubicSpline(t, resid, bc_type="periodic")

    def at(self, t, jerk: bool = True):
        """(q, dq, ddq, dddq) at times ``t`` [s] from the table's start (q from its first row), repeated
        after each cycle as a :class:`Profile` is (``jerk`` is accepted as :meth:`Profile.at` takes it)."""
        t = np.asarray(t, dtype=float)
        T = self.duration
        n = np.floor(t / T)
        tau = t - n * T
        s = self._spline()
        slope = 0.0 if self.period_rise is None else self.period_rise / T
        return (n * self.rise + s(tau) + slope * tau, s(tau, 1) + slope, s(tau, 2), s(tau, 3))

    def jumps(self, closed: bool = True) -> tuple[Jump, ...]:
        """A spline has none inside; a table that does not close jumps where its cycle repeats."""
        if not closed or self.period_rise is not None:
            return ()
        s = self._spline()
        T = self.duration
        dv = float(s(0.0, 1) - s(T, 1))
        da = float(s(0.0, 2) - s(T, 2))
        return (Jump(0, 0, T, self.rise, dv, da),)


def whole_turns(rise: float, turn: float = 2 * math.pi) -> bool:
    """Whether ``rise`` is a whole number of turns (0 included)."""
    n = round(rise / turn)
    return abs(rise - n * turn) <= CLOSE * max(turn, abs(rise))


def read_table(text: str, angular: bool, scale: float) -> tuple[np.ndarray, np.ndarray]:
    """The (t, q) columns of a table's CSV text: a header ``t,q`` (q in rad, or file units for a length:
    times ``scale`` [m per file unit]) or ``t,q_deg`` (degrees). Raises ValueError (a one-line reason)."""
    lines = [ln.strip() for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        raise ValueError("the table is empty; give a header t,q and rows of numbers")
    head = [h.strip().lower() for h in lines[0].split(",")]
    if len(head) != 2 or head[0] != "t" or head[1] not in ("q", "q_deg"):
        raise ValueError(f"header {lines[0]!r}: give the columns t,q (or t,q_deg)")
    if head[1] == "q_deg" and not angular:
        raise ValueError("q_deg is for an angle; this input is a length: give t,q in file units")
    rows = []
    for k, ln in enumerate(lines[1:], 2):
        cells = ln.split(",")
        try:
            row = [float(c) for c in cells]
        except ValueError:
            raise ValueError(f"line {k}: {ln[:40]!r} is not two numbers") from None
        if len(row) != 2 or not all(math.isfinite(v) for v in row):
            raise ValueError(f"line {k}: {ln[:40]!r} is not two finite numbers")
        rows.append(row)
    if len(rows) < 3:
        raise ValueError(f"{len(rows)} rows; a spline needs at least 3")
    arr = np.asarray(rows)
    t, q = arr[:, 0], arr[:, 1]
    bad = np.flatnonzero(np.diff(t) <= 0)
    if len(bad):
        k = int(bad[0])
        raise ValueError(f"t must increase: row {k + 2} has t={t[k + 1]:g} after t={t[k]:g}")
    q = np.radians(q) if head[1] == "q_deg" else q * (1.0 if angular else scale)
    return t, q


def table_law(t, q, periodic_turn: float | None) -> Table:
    """A :class:`Table` of (t, q), periodic where it closes: q at its end equal to q at its start, or (for
    an input that turns, ``periodic_turn`` = 2 pi) a whole number of turns on."""
    rise = float(q[-1] - q[0])
    scale = max(float(np.max(np.abs(q - q[0]))), 1e-300)
    if abs(rise) <= CLOSE * scale:
        period = 0.0
    elif periodic_turn is not None and whole_turns(rise, periodic_turn):
        period = round(rise / periodic_turn) * periodic_turn
    else:
        period = None
    return Table(tuple(float(x) for x in t), tuple(float(x) for x in q), period)


def describe(law, angular: bool, name: str = "q", q0: float = 0.0, unit: tuple[float, str] = (1.0, "m")) -> list[str]:
    """The law as ``linkage check`` prints it: one line per segment (or the table's size) and each jump in
    velocity or acceleration (at which time and input value ``name`` = ``q0`` + the law's, how large).
    ``unit``: (metres per display unit, its name) for a length's rises."""
    def value(v):
        return f"{(math.degrees(v) + 180) % 360 - 180:.6g}deg" if angular else f"{v / unit[0]:.6g} {unit[1]}"

    def amount(v):
        return f"{math.degrees(v):+.6g}deg" if angular else f"{v / unit[0]:+.6g} {unit[1]}"

    def rate(v, order):
        per = "/s" if order == 1 else f"/s^{order}"
        return f"{math.degrees(v):+.6g} deg{per}" if angular else f"{v / unit[0]:+.6g} {unit[1]}{per}"

    lines = []
    if isinstance(law, Profile):
        lines.append(f"law: {len(law.segments)} segments, cycle {law.duration:.6g} s, net {amount(law.rise)}")
        t0 = 0.0
        for k, s in enumerate(law.segments, 1):
            extra = "" if s.shape == "dwell" else f", rise {amount(s.rise)}"
            lines.append(f"  {k}. {s.shape} {t0:.6g}..{t0 + s.duration:.6g} s{extra}")
            t0 += s.duration
    else:
        kind = "periodic" if law.period_rise is not None else "not-a-knot ends"
        lines.append(f"law: table of {len(law.t)} rows, cubic spline ({kind}), cycle {law.duration:.6g} s, "
                     f"net {amount(law.rise)}")
    jumps = law.jumps()
    if not jumps:
        lines.append("  velocity and acceleration continuous at every boundary")
    for j in jumps:
        where = (f"segment {j.after + 1} -> {j.before + 1}" if isinstance(law, Profile) else "cycle end -> start")
        parts = ([f"velocity jumps {rate(j.dv, 1)}"] if j.dv else []) + \
                ([f"acceleration jumps {rate(j.da, 2)}"] if j.da else [])
        lines.append(f"  jump at t={j.t:.6g} s, {name}={value(q0 + j.q)} ({where}): {', '.join(parts)}")
    return lines
