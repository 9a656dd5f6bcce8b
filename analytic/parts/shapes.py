"""Exact plane shapes of the parts: the convex hull of a set of discs (a rounded plate; a bar is the hull of
two discs, a slot the hull of two hole discs, a block the hull of four corner points), its boundary as
circular arcs joined by their common tangents, its tessellation and its area moments.

A disc of radius 0 is a point (a block's corner). Everything here is pure and in one length unit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

TAU = 2.0 * math.pi


@dataclass(frozen=True)
class Disc:
    x: float
    y: float
    r: float


@dataclass(frozen=True)
class Arc:
    """The arc of the circle about (x, y) of radius ``r`` from angle ``a0`` to ``a1`` (counter-clockwise,
    a1 >= a0; a corner when r = 0). Consecutive arcs of a boundary are joined by straight tangent segments."""

    x: float
    y: float
    r: float
    a0: float
    a1: float

    def at(self, a: float) -> tuple[float, float]:
        return self.x + self.r * math.cos(a), self.y + self.r * math.sin(a)

    @property
    def start(self) -> tuple[float, float]:
        return self.at(self.a0)

    @property
    def end(self) -> tuple[float, float]:
        return self.at(self.a1)


def _distinct(discs, eps: float) -> list[Disc]:
    """The discs without those inside another (the larger kept; of equal ones the first)."""
    out: list[Disc] = []
    for d in discs:
        inside = False
        for k, e in enumerate(out):
            gap = math.hypot(d.x - e.x, d.y - e.y)
            if gap + d.r <= e.r + eps:
                inside = True
                break
        if inside:
            continue
        out = [e for e in out if not math.hypot(d.x - e.x, d.y - e.y) + e.r <= d.r + eps]
        out.append(d)
    return out


def hull(discs, eps: float = 1e-12) -> tuple[Arc, ...]:
    """The boundary of the convex hull of ``discs`` (counter-clockwise, starting at the lowest point), by
    gift wrapping over the outward normal's angle: the disc of largest support c.n + r holds the boundary
    until another overtakes it where (c_j - c_i).n = r_i - r_j. ``eps``: a length below which two discs'
    supports count as equal (a scale-relative tolerance is the caller's)."""
    ds = _distinct([Disc(float(d.x), float(d.y), float(d.r)) for d in discs], eps)
    if not ds:
        raise ValueError("a shape needs at least one disc")
    if len(ds) == 1:
        d = ds[0]
        return (Arc(d.x, d.y, d.r, -math.pi / 2, 1.5 * math.pi),)
    theta0 = -math.pi / 2
    start = max(range(len(ds)), key=lambda k: (-ds[k].y + ds[k].r, ds[k].x))
    arcs: list[Arc] = []
    i, theta = start, theta0
    for _ in range(4 * len(ds) + 4):
        best, best_d, best_far = None, None, -math.inf
        for j, dj in enumerate(ds):
            if j == i:
                continue
            di = ds[i]
            dx, dy = dj.x - di.x, dj.y - di.y
            D = math.hypot(dx, dy)
            c = (di.r - dj.r) / D
            c = max(-1.0, min(1.0, c))
            t = math.atan2(dy, dx) - math.acos(c)
            delta = (t - theta) % TAU
            if delta > TAU - 1e-12:
                delta = 0.0
            # how far along the tangent the next disc's contact lies (ties: the farthest disc wins)
            tx, ty = -math.sin(t), math.cos(t)
            far = (dj.x + dj.r * math.cos(t) - di.x - di.r * math.cos(t)) * tx + \
                  (dj.y + dj.r * math.sin(t) - di.y - di.r * math.sin(t)) * ty
            if best is None or delta < best_d - 1e-12 or (abs(delta - best_d) <= 1e-12 and far > best_far):
                best, best_d, best_far = j, delta, far
        end = theta + best_d
        if end >= theta0 + TAU - 1e-12 or (best == start and arcs and end + 1e-12 >= theta0 + TAU):
            arcs.append(Arc(ds[i].x, ds[i].y, ds[i].r, theta, theta0 + TAU))
            break
        arcs.append(Arc(ds[i].x, ds[i].y, ds[i].r, theta, end))
        i, theta = best, end
        if i == start and theta >= theta0 + TAU - 1e-12:
            break
    else:                                              # pragma: no cover - a wrapping that does not close
        raise RuntimeError("the hull of the discs did not close")
    if len(arcs) > 1 and arcs[-1].x == arcs[0].x and arcs[-1].y == arcs[0].y and arcs[-1].r == arcs[0].r:
        first, last = arcs[0], arcs[-1]
        arcs = [Arc(last.x, last.y, last.r, last.a0, first.a1 + TAU)] + arcs[1:-1]
    # an arc of no sweep (a disc touching the hull at one point, e.g. collinear discs) is dropped: the
    # tangents on either side are one straight line through it (a sweep below 1e-9 rad moves the boundary by
    # less than 1e-9 of the radius)
    return tuple(a for a in arcs if a.a1 - a.a0 > 1e-9 or a.r == 0.0)


# ------------------------------------------------------------------------------------------ tessellation
def arc_steps(r: float, sweep: float, chord: float) -> int:
    """Segments that keep an arc of radius ``r`` within ``chord`` (its sagitta) of the polygon through its
    points."""
    if r <= chord or sweep <= 0.0:
        return 1 if sweep > 0.0 else 0
    step = 2.0 * math.acos(1.0 - chord / r)
    return max(1, math.ceil(sweep / step))


def tessellate(arcs, chord: float) -> np.ndarray:
    """The boundary's vertices (k, 2), counter-clockwise, the last not repeating the first; every arc
    within ``chord`` of its chords (the polygon lies inside the exact shape)."""
    pts = []
    for a in arcs:
        n = arc_steps(a.r, a.a1 - a.a0, chord)
        if a.r == 0.0 or n == 0:
            pts.append((a.x, a.y))
            continue
        for t in np.linspace(a.a0, a.a1, n + 1):
            pts.append((a.x + a.r * math.cos(t), a.y + a.r * math.sin(t)))
    out = [pts[0]]
    for p in pts[1:]:
        if math.hypot(p[0] - out[-1][0], p[1] - out[-1][1]) > 1e-12 * (1.0 + abs(p[0]) + abs(p[1])):
            out.append(p)
    if len(out) > 1 and math.hypot(out[0][0] - out[-1][0], out[0][1] - out[-1][1]) <= 1e-12 * (
            1.0 + abs(out[0][0]) + abs(out[0][1])):
        out.pop()
    return np.asarray(out, dtype=float)


def segments(arcs):
    """The boundary as pieces: ("line", p, q) and ("arc", Arc) in order (degenerate pieces left out)."""
    out = []
    n = len(arcs)
    for k, a in enumerate(arcs):
        if a.r > 0.0 and a.a1 > a.a0:
            out.append(("arc", a))
        p, q = a.end, arcs[(k + 1) % n].start
        if n > 1 and math.hypot(q[0] - p[0], q[1] - p[1]) > 0.0:
            out.append(("line", p, q))
    return out


# ------------------------------------------------------------------------------------------ area moments
_GX, _GW = np.polynomial.legendre.leggauss(24)


def moments(arcs) -> tuple[float, float, float, float]:
    """(A, Sx, Sy, Jo) of the region inside the boundary: area, first moments (integrals of x and of y)
    and the polar moment about the origin, by Green's theorem on each line and arc (Gauss-Legendre, exact
    for the lines' cubic integrands and to rounding for the arcs' trigonometric ones)."""
    A = Sx = Sy = Jo = 0.0
    for piece in segments(arcs):
        if piece[0] == "line":
            (x0, y0), (x1, y1) = piece[1], piece[2]
            u = 0.5 * (_GX + 1.0)
            w = 0.5 * _GW
            x, y = x0 + (x1 - x0) * u, y0 + (y1 - y0) * u
            dx, dy = x1 - x0, y1 - y0
        else:
            a = piece[1]
            h = a.a1 - a.a0
            t = a.a0 + 0.5 * h * (_GX + 1.0)
            w = 0.5 * h * _GW
            x, y = a.x + a.r * np.cos(t), a.y + a.r * np.sin(t)
            dx, dy = -a.r * np.sin(t), a.r * np.cos(t)
        A += float(np.sum(w * 0.5 * (x * dy - y * dx)))
        Sx += float(np.sum(w * 0.5 * x * x * dy))
        Sy += float(np.sum(w * -0.5 * y * y * dx))
        Jo += float(np.sum(w * (x ** 3 * dy - y ** 3 * dx))) / 3.0
    return A, Sx, Sy, Jo


def disc_moments(d: Disc) -> tuple[float, float, float, float]:
    a = math.pi * d.r * d.r
    return a, a * d.x, a * d.y, a * (0.5 * d.r * d.r + d.x * d.x + d.y * d.y)


def support(arcs, nx: float, ny: float) -> float:
    """max over the shape of p.n (its extent along the unit direction n)."""
    return max(a.x * nx + a.y * ny + a.r for a in arcs)
