"""Assur groups with prismatic pairs (sliding blocks), solved numerically: the ``group`` kind's path for a
group whose ``slides`` is not empty (groups of revolute joints only take :mod:`.general_group`).

Coordinates: every link of the group is a rigid frame with unknowns ``(x, y, theta)`` (its origin, the first
of its points, and its angle), ``3 L`` in all. Each point of a link has constant coordinates in its frame,
taken from the assembled pose. Equations (as many as unknowns in an Assur group), in metres:

* a point the group places, carried by links ``a, b, ...``: ``pos_a(p) - pos_b(p) = 0`` (2 rows per further
  link);
* a known point carried by a link ``a``: ``pos_a(p) - K_p = 0`` (2 rows);
* a prismatic pair (a block ``b`` sliding on a guide ``g``: a link of the group, a placed link given by two
  of its points, or the ground): the block's point stays on the guide's line, ``n_g . (pos_b(p) - L_g) = 0``
  (``L_g`` a point of the line and ``n_g`` its normal, both fixed in the guide's frame), and the block does
  not turn relative to the guide, ``S (theta_b - theta_g - rel) = 0`` (``S`` the group's size: a length).

A block link's frame is along its slide (its angle ``phiL`` is the slide's direction, as for every block);
another link's runs from its first point to its second, or along its slide where it has one point.

Positions along a path, as the revolute groups: nodes by sequential Newton from the previous node (the
first from the pose), every 1/16 of the size of the known points' travel and where they turn back, halved
where Newton fails or the solution moves far; then every sample batched (``np.linalg.solve`` over stacked
samples) by Newton from the nodes' solutions interpolated linearly in the travel, until the residual is
below 1e-11 of the size, and one more step. Rates are exact linear solves with the Jacobian ``J`` at the
solution: ``J qd = -dPhi/dt`` (the equations' rates with the group's own frames at rest) and
``J qdd = -gamma`` (their second rates with the group's frames not accelerating).

Branch: the sign of ``det J`` at the pose, held by continuity: a sample whose determinant has the other sign,
where Newton does not converge, or whose solution lies farther from its interpolated start than the nodes
around it allow (a jump to another assembly) is not assembled (NaN).

Cost: about 3 L unknowns against the revolute engine's L reduced ones, and LAPACK's batched solve instead
of that engine's hand-written LU: several times a revolute group's cost per sample (benchmarks/prismatic_group.py).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from analytic._common import ParameterError

from . import general_group as gg

NEWTON_STEPS = 12
NEWTON_TOL = 1e-13          # a node: converged when its step is below this fraction of the size
RESIDUAL_CONVERGED = 4e-15  # ... or its residual below this fraction of the size
NEWTON_LOOSE = 1e-11        # batched samples: iterate to this residual [fraction of size], then one more step
RESIDUAL_TOL = 1e-10        # a sample whose residual after that exceeds this fraction of the size is refused
SINGULAR_COND = 1e12        # a pose whose (scaled) Jacobian's condition number exceeds this is singular
BLOCK = 16384
DYAD_CALIBRATION = 2 * math.sqrt(2)
"""The singularity measure's scale (:func:`singularity`): an RRP dyad written as a group reads its transmission
sine (the RRP kind's measure) near its fold, the smallest singular value then being 0.34-0.36 of that sine
(tests/test_prismatic_group.py)."""


@dataclass(frozen=True)
class PrismaticPair:
    """A prismatic pair of the group: ``block`` (a link index) slides on ``guide``: ``("link", i)`` (a link
    of the group), ``("pair", kP, kQ)`` (the placed link carrying known points kP, kQ: frame origin kP, x-axis
    kP -> kQ) or ``("ground",)``. ``point`` (of the block, local ``pu, pv``) stays on the line through the
    guide's local ``(cu, cv)`` along its local unit ``(tu, tv)``; ``rel`` = theta_block - theta_guide."""

    name: str
    block: int
    guide: tuple
    point: str
    pu: float
    pv: float
    cu: float
    cv: float
    tu: float
    tv: float
    rel: float


@dataclass(frozen=True)
class PrismaticGroup:
    """A numerically solved Assur group with prismatic pairs (see the module docstring)."""

    known: tuple
    unknown: tuple
    links: tuple             # (name, points) each
    local: tuple             # per link: {point: (u, v)}
    pins: tuple              # (a, ua, va, b, ub, vb): an unknown point on links a and b
    kpins: tuple             # (k, a, ua, va): known point k (index into known) on link a
    slides: tuple            # PrismaticPair each
    z0: np.ndarray           # (3 L,) the pose's frames: x, y, theta per link
    size: float
    sign: int
    branch: int
    pose: np.ndarray         # (n_points, 2): known + unknown

    @property
    def n(self) -> int:
        return 3 * len(self.links)

    @property
    def dof(self) -> int:
        return self.n

    @property
    def scale(self) -> np.ndarray:
        """Per unknown: 1 for a coordinate, the size for an angle (steps compared in metres)."""
        return np.tile([1.0, 1.0, self.size], len(self.links))


def _rot(th, u, v):
    c, s = math.cos(th), math.sin(th)
    return c * u - s * v, s * u + c * v


def make_group(links: Mapping[str, Sequence[str]], known: Sequence[str], unknown: Sequence[str],
               pose: Mapping[str, Sequence[float]], slides: Mapping[str, tuple], *,
               where: str = "group") -> PrismaticGroup:
    """Build the group from its links, known and unknown points, assembled pose [m] and prismatic pairs
    ``{block: (guide, point, angle)}``: ``guide`` a link of the group (its name), a pair of known points (a
    placed link) or None (the ground); ``point`` a point of the block; ``angle`` the slide's direction at the
    pose [rad, world]."""
    known, unknown = tuple(known), tuple(unknown)
    names = known + unknown
    kidx = {p: i for i, p in enumerate(known)}
    for p in names:
        if p not in pose:
            raise ParameterError(f"{where}: the pose has no position for point {p!r}; give its x, y")
    P = {p: (float(pose[p][0]), float(pose[p][1])) for p in names}
    if not all(math.isfinite(c) for xy in P.values() for c in xy):
        raise ParameterError(f"{where}: the pose has a non-finite coordinate; give finite x, y")
    lnames = list(links)
    lidx = {ln: i for i, ln in enumerate(lnames)}
    pts_of = [tuple(links[ln]) for ln in lnames]
    # each link's frame at the pose: a block's along its slide; else first point -> second; else its slide
    theta0 = []
    for i, ln in enumerate(lnames):
        pts = pts_of[i]
        if not pts:
            raise ParameterError(f"{where}: link {ln!r} carries no point; give it one")
        if ln in slides:
            theta0.append(float(slides[ln][2]))
        elif len(pts) >= 2:
            (x0, y0), (x1, y1) = P[pts[0]], P[pts[1]]
            if math.hypot(x1 - x0, y1 - y0) <= 0.0:
                raise ParameterError(f"{where}: link {ln!r}: points {pts[0]!r} and {pts[1]!r} coincide in the pose")
            theta0.append(math.atan2(y1 - y0, x1 - x0))
        else:
            guided = [s for s in slides.values() if s[0] == ln]
            if not guided:
                raise ParameterError(f"{where}: link {ln!r} has one point and no slide; it cannot be placed")
            theta0.append(float(guided[0][2]))
    local = []
    for i, pts in enumerate(pts_of):
        ox, oy = P[pts[0]]
        local.append({p: _rot(-theta0[i], P[p][0] - ox, P[p][1] - oy) for p in pts})
    pins, kpins = [], []
    for p in dict.fromkeys(q for pts in pts_of for q in pts):
        on = [i for i, pts in enumerate(pts_of) if p in pts]
        if p in kidx:
            kpins += [(kidx[p], a, *local[a][p]) for a in on]
        else:
            pins += [(on[0], *local[on[0]][p], b, *local[b][p]) for b in on[1:]]
    pairs = []
    for block, (guide, point, angle) in slides.items():
        if block not in lidx:
            raise ParameterError(f"{where}: slide of {block!r}: the block is not a link of the group")
        b = lidx[block]
        if point not in local[b]:
            raise ParameterError(f"{where}: slide of {block!r}: point {point!r} is not on the block")
        if guide is None:
            gspec, (ox, oy), gth = ("ground",), (0.0, 0.0), 0.0
        elif isinstance(guide, str):
            if guide not in lidx or guide == block:
                raise ParameterError(f"{where}: slide of {block!r}: guide {guide!r} is not another link of the "
                                     f"group")
            g = lidx[guide]
            gspec, (ox, oy), gth = ("link", g), P[pts_of[g][0]], theta0[g]
        else:
            gp, gq = guide
            if gp not in kidx or gq not in kidx:
                raise ParameterError(f"{where}: slide of {block!r}: the guide's points {gp!r}, {gq!r} must be "
                                     f"known points")
            (ox, oy), (qx, qy) = P[gp], P[gq]
            gspec, gth = ("pair", kidx[gp], kidx[gq]), math.atan2(qy - oy, qx - ox)
        cu, cv = _rot(-gth, P[point][0] - ox, P[point][1] - oy)
        tu, tv = math.cos(angle - gth), math.sin(angle - gth)
        pairs.append(PrismaticPair(block, b, gspec, point, *local[b][point], cu, cv, tu, tv, theta0[b] - gth))
    n = 3 * len(lnames)
    rows = 2 * len(pins) + 2 * len(kpins) + 2 * len(pairs)
    if rows != n:
        raise ParameterError(f"{where}: not an Assur group: {rows} equations for {n} unknowns (3 per link; 2 per "
                             "pin, per known point on a link and per prismatic pair); check the links and slides")
    arr = np.array([P[p] for p in names])
    diff = arr[:, None, :] - arr[None, :, :]
    size = float(np.sqrt(np.max(np.sum(diff * diff, axis=-1))))
    if not size > 0.0:
        raise ParameterError(f"{where}: every point of the pose coincides; give the assembled pose")
    z0 = np.array([c for i, pts in enumerate(pts_of) for c in (*P[pts[0]], theta0[i])])
    g = PrismaticGroup(known, unknown, tuple(zip(lnames, pts_of)), tuple(local), tuple(pins), tuple(kpins),
                       tuple(pairs), z0, size, 1, 1, arr)
    K = arr[:len(known)].ravel()
    F, J = _residual(g, z0[:, None], K[:, None], jac=True)
    Js = J[0] / g.scale[None, :]
    cond = np.linalg.cond(Js) if np.all(np.isfinite(Js)) else np.inf
    if not np.isfinite(cond) or cond > SINGULAR_COND:
        raise ParameterError(f"{where}: the pose is singular for links {', '.join(lnames)} (a locked or "
                             "underconstrained group, or a group folded at a dead point); give another pose or "
                             "other links")
    if float(np.max(np.abs(F))) > 1e-9 * size:
        raise ParameterError(f"{where}: the pose does not close the group ({float(np.max(np.abs(F))):.3g} m); "
                             "give the assembled pose")
    sign = 1 if np.linalg.det(J[0]) > 0 else -1
    return PrismaticGroup(known, unknown, g.links, g.local, g.pins, g.kpins, g.slides, z0,
                          size, sign, sign, arr)


# ------------------------------------------------------------------------------------ kinematics
class _Frames:
    """Frames over m samples: the group's links from z (and its rates), the placed guides from the known
    points. Each: origin (x, y), angle's cos, sin, and rates (vx, vy, w, ax, ay, a)."""

    def __init__(self, g: PrismaticGroup, z, K3, zd=None, zdd=None):
        L = len(g.links)
        m = z.shape[1]
        self.x, self.y, th = z[0::3], z[1::3], z[2::3]
        self.c, self.s = np.cos(th), np.sin(th)
        zero = np.zeros((L, m))
        self.vx, self.vy, self.w = (zero, zero, zero) if zd is None else (zd[0::3], zd[1::3], zd[2::3])
        self.ax, self.ay, self.a = (zero, zero, zero) if zdd is None else (zdd[0::3], zdd[1::3], zdd[2::3])
        self.K3 = K3

    def link(self, i):
        return (self.x[i], self.y[i], self.c[i], self.s[i], self.vx[i], self.vy[i], self.w[i], self.ax[i],
                self.ay[i], self.a[i])

    def guide(self, spec):
        K3 = self.K3
        if spec[0] == "link":
            return self.link(spec[1])
        if spec[0] == "ground":
            return (0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
        _, kp, kq = spec
        Px, Py = K3[0, 2 * kp], K3[0, 2 * kp + 1]
        dx, dy = K3[0, 2 * kq] - Px, K3[0, 2 * kq + 1] - Py
        vx, vy = K3[1, 2 * kq] - K3[1, 2 * kp], K3[1, 2 * kq + 1] - K3[1, 2 * kp + 1]
        ax, ay = K3[2, 2 * kq] - K3[2, 2 * kp], K3[2, 2 * kq + 1] - K3[2, 2 * kp + 1]
        L2 = dx * dx + dy * dy
        Ln = np.sqrt(L2)
        return (Px, Py, dx / Ln, dy / Ln, K3[1, 2 * kp], K3[1, 2 * kp + 1], (dx * vy - dy * vx) / L2,
                K3[2, 2 * kp], K3[2, 2 * kp + 1], (dx * ay - dy * ax) / L2)


def _point(f, u, v):
    """A point at local (u, v) of frame f: world offset r from the origin, position, velocity, acceleration."""
    x, y, c, s, vx, vy, w, ax, ay, a = f
    rx, ry = c * u - s * v, s * u + c * v
    w2 = w * w
    return (rx, ry), (x + rx, y + ry), (vx - w * ry, vy + w * rx), (ax - a * ry - w2 * rx, ay + a * rx - w2 * ry)


def _residual(g: PrismaticGroup, z, K, jac: bool = False):
    """The equations at z (n, m) with the known positions K (2 nk, m): F (n, m) and (``jac``) J (m, n, n)."""
    m = z.shape[1]
    K3 = np.zeros((3,) + K.shape)
    K3[0] = K
    fr = _Frames(g, z, K3)
    n = g.n
    F = np.empty((n, m))
    J = np.zeros((m, n, n)) if jac else None
    r = 0
    for a, ua, va, b, ub, vb in g.pins:
        (rax, ray), (pax, pay), _, _ = _point(fr.link(a), ua, va)
        (rbx, rby), (pbx, pby), _, _ = _point(fr.link(b), ub, vb)
        F[r], F[r + 1] = pax - pbx, pay - pby
        if jac:
            J[:, r, 3 * a], J[:, r, 3 * a + 2] = 1.0, -ray
            J[:, r + 1, 3 * a + 1], J[:, r + 1, 3 * a + 2] = 1.0, rax
            J[:, r, 3 * b], J[:, r, 3 * b + 2] = -1.0, rby
            J[:, r + 1, 3 * b + 1], J[:, r + 1, 3 * b + 2] = -1.0, -rbx
        r += 2
    for k, a, ua, va in g.kpins:
        (rax, ray), (pax, pay), _, _ = _point(fr.link(a), ua, va)
        F[r], F[r + 1] = pax - K[2 * k], pay - K[2 * k + 1]
        if jac:
            J[:, r, 3 * a], J[:, r, 3 * a + 2] = 1.0, -ray
            J[:, r + 1, 3 * a + 1], J[:, r + 1, 3 * a + 2] = 1.0, rax
        r += 2
    S = g.size
    for sp in g.slides:
        fb, fg = fr.link(sp.block), fr.guide(sp.guide)
        (rbx, rby), (pbx, pby), _, _ = _point(fb, sp.pu, sp.pv)
        _, (lx, ly), _, _ = _point(fg, sp.cu, sp.cv)
        gc, gs = fg[2], fg[3]
        nx, ny = -(gc * sp.tv + gs * sp.tu), gc * sp.tu - gs * sp.tv      # R(theta_g) (-tv, tu)
        F[r] = nx * (pbx - lx) + ny * (pby - ly)
        th_b = z[3 * sp.block + 2]
        th_g = z[3 * sp.guide[1] + 2] if sp.guide[0] == "link" else np.arctan2(gs, gc)
        F[r + 1] = S * (th_b - th_g - sp.rel)
        if sp.guide[0] != "link":               # a placed guide's angle: continuous only near the block's
            F[r + 1] = S * (np.remainder(th_b - th_g - sp.rel + math.pi, 2 * math.pi) - math.pi)
        if jac:
            b = sp.block
            J[:, r, 3 * b], J[:, r, 3 * b + 1], J[:, r, 3 * b + 2] = nx, ny, -nx * rby + ny * rbx
            J[:, r + 1, 3 * b + 2] = S
            if sp.guide[0] == "link":
                q = sp.guide[1]
                J[:, r, 3 * q], J[:, r, 3 * q + 1] = -nx, -ny
                J[:, r, 3 * q + 2] = -ny * (pbx - fg[0]) + nx * (pby - fg[1])
                J[:, r + 1, 3 * q + 2] = -S
        r += 2
    return F, J


def _rates(g: PrismaticGroup, z, K3, zd, zdd, order: int):
    """The equations' first (``order`` 1) or second time derivative at z with the frames' rates zd, zdd
    (zdd ignored for order 1) and the known points' (K3): (n, m)."""
    fr = _Frames(g, z, K3, zd, zdd)
    F = np.empty((g.n, z.shape[1]))
    c = order
    r = 0
    for a, ua, va, b, ub, vb in g.pins:
        A, B = _point(fr.link(a), ua, va), _point(fr.link(b), ub, vb)
        F[r], F[r + 1] = A[1 + c][0] - B[1 + c][0], A[1 + c][1] - B[1 + c][1]
        r += 2
    for k, a, ua, va in g.kpins:
        A = _point(fr.link(a), ua, va)
        F[r], F[r + 1] = A[1 + c][0] - K3[c, 2 * k], A[1 + c][1] - K3[c, 2 * k + 1]
        r += 2
    S = g.size
    for sp in g.slides:
        fb, fg = fr.link(sp.block), fr.guide(sp.guide)
        B = _point(fb, sp.pu, sp.pv)
        Lp = _point(fg, sp.cu, sp.cv)
        gc, gs, wg, ag = fg[2], fg[3], fg[6], fg[9]
        nx, ny = -(gc * sp.tv + gs * sp.tu), gc * sp.tu - gs * sp.tv
        px, py = -ny, nx                                   # perp(n)
        dx, dy = B[1][0] - Lp[1][0], B[1][1] - Lp[1][1]
        vx, vy = B[2][0] - Lp[2][0], B[2][1] - Lp[2][1]
        if c == 1:
            F[r] = wg * (px * dx + py * dy) + nx * vx + ny * vy
            F[r + 1] = S * (fb[6] - wg)
        else:
            ax, ay = B[3][0] - Lp[3][0], B[3][1] - Lp[3][1]
            F[r] = ((ag * px - wg * wg * nx) * dx + (ag * py - wg * wg * ny) * dy
                    + 2.0 * wg * (px * vx + py * vy) + nx * ax + ny * ay)
            F[r + 1] = S * (fb[9] - ag)
        r += 2
    return F


# --------------------------------------------------------------------------------- one sample (nodes)
def _newton1(g: PrismaticGroup, k, z):
    z = np.array(z, dtype=float)
    step = np.inf
    sc = g.scale
    with np.errstate(all="ignore"):
        for it in range(NEWTON_STEPS + 1):
            F, J = _residual(g, z[:, None], k[:, None], jac=True)
            res = float(np.max(np.abs(F)))
            if not np.isfinite(res):
                return z, False
            if res <= RESIDUAL_CONVERGED * g.size or step <= NEWTON_TOL * g.size:
                det = np.linalg.det(J[0])
                return z, bool(res <= RESIDUAL_TOL * g.size and np.isfinite(det) and np.sign(det) == g.sign)
            if it == NEWTON_STEPS:
                return z, False
            try:
                dz = np.linalg.solve(J[0], F[:, 0])
            except np.linalg.LinAlgError:
                return z, False
            z -= dz
            step = float(np.max(np.abs(dz * sc)))
    return z, False


def _far(g, za, zb) -> float:
    return float(np.max(np.abs((zb - za) * g.scale)))


def _nodes(g, path, z_start):
    """:func:`general_group.trace_nodes` on the links' frames: (indices, solutions (n_nodes, n), assembled)."""
    s = gg.Stepper(lambda k, z: _newton1(g, k, z), lambda za, z: _far(g, za, z), g.size, g.n)
    return gg.trace_nodes(s, path, z_start)


# ------------------------------------------------------------------------------ many samples (batched)
def _solve(J, F):
    """J (m, n, n), F (n, m): J^-1 F (n, m); NaN where a matrix is singular."""
    try:
        return np.linalg.solve(J, F.T[:, :, None])[:, :, 0].T
    except np.linalg.LinAlgError:
        out = np.full(F.shape, np.nan)
        det = np.linalg.det(J)
        ok = np.isfinite(det) & (det != 0.0)
        if ok.any():
            out[:, ok] = np.linalg.solve(J[ok], F[:, ok].T[:, :, None])[:, :, 0].T
        return out


def _level(g, K3, idx, nodes, travel):
    """Every sample of idx (a block) from the nodes: z, zd, zdd (n, m) and whether each is assembled."""
    ix, zs, good = nodes
    m = len(idx)
    if len(ix) == 1:
        z0 = np.repeat(zs.T, m, axis=1)
        usable = np.full(m, bool(good[0]))
        allow = np.zeros(m)
    else:
        j = np.clip(np.searchsorted(ix, idx, side="right") - 1, 0, len(ix) - 2)
        X = travel[ix]
        span = X[j + 1] - X[j]
        with np.errstate(all="ignore"):
            t = np.where(span > 0.0, (travel[idx] - X[j]) / span, 0.0)
            t = np.where(idx == ix[j + 1], 1.0, np.where(idx == ix[j], 0.0, t))
            za, zb = zs[j].T, zs[j + 1].T
            z0 = za + (zb - za) * t
            hop = np.nan_to_num(np.max(np.abs((zs[1:] - zs[:-1]) * g.scale), axis=1), nan=0.0)
        hop3 = np.maximum.reduce([np.r_[0.0, hop[:-1]], hop, np.r_[hop[1:], 0.0]])
        allow = 2.0 * hop3[j]
        usable = np.where(idx == ix[j], good[j], np.where(idx == ix[j + 1], good[j + 1], good[j] & good[j + 1]))
    z0 = np.where(usable, z0, g.z0[:, None])
    K = K3[0]
    z = z0.copy()
    with np.errstate(all="ignore"):
        act = np.arange(m)
        for _ in range(NEWTON_STEPS):
            F, J = _residual(g, z[:, act], K[:, act], jac=True)
            res = np.max(np.abs(F), axis=0)
            keep = (res > NEWTON_LOOSE * g.size) & np.isfinite(res)
            if not keep.any():
                break
            act, F, J = act[keep], F[:, keep], J[keep]
            z[:, act] -= _solve(J, F)
        F, J = _residual(g, z, K, jac=True)               # one more step: rounding
        z = z - _solve(J, F)
        F, J = _residual(g, z, K, jac=True)
        det = np.linalg.det(J)
        ok = (usable & (np.sign(det) == g.sign) & (np.max(np.abs(F), axis=0) <= RESIDUAL_TOL * g.size)
              & (np.max(np.abs((z - z0) * g.scale[:, None]), axis=0) <= allow + 1e-9 * g.size))
        zero = np.zeros_like(z)
        zd = _solve(J, -_rates(g, z, K3, zero, zero, 1))
        zdd = _solve(J, -_rates(g, z, K3, zd, zero, 2))
    return z, zd, zdd, ok


@dataclass(frozen=True)
class GroupSolution:
    """As :class:`general_group.GroupSolution`, with the prismatic pairs' frames: ``frames`` {link: (x, y,
    vx, vy, ax, ay)} of each link's origin are in ``points`` already."""

    points: dict
    links: dict
    assembled: np.ndarray
    branch: int
    end: np.ndarray | None = None


def start_of(g: PrismaticGroup, start, K3) -> np.ndarray:
    if start is None:
        return g.z0.copy()
    return np.asarray(start, dtype=float)


def solve_group(g: PrismaticGroup, known: Mapping[str, Sequence[np.ndarray]], *, start=None) -> GroupSolution:
    """Positions, velocities and accelerations of the group's unknown points and links over N samples (a
    path); ``start``: None (the pose) or a previous run's :attr:`GroupSolution.end`."""
    K3 = gg.known_arrays(g, known)
    n = K3.shape[2]
    path = gg._Path.of(g, K3[0])
    nodes = _nodes(g, path, start_of(g, start, K3))
    L = len(g.links)
    Z = np.empty((3, 3 * L, n))
    assembled = np.empty(n, dtype=bool)
    for s in range(0, n, BLOCK):
        e = min(n, s + BLOCK)
        z, zd, zdd, ok = _level(g, K3[:, :, s:e], np.arange(s, e), nodes, path.travel)
        Z[0, :, s:e], Z[1, :, s:e], Z[2, :, s:e] = z, zd, zdd
        assembled[s:e] = ok
    end = Z[0, :, np.flatnonzero(assembled)[-1]].copy() if assembled.any() else None
    Z[:, :, ~assembled] = np.nan
    fr = _Frames(g, Z[0], K3, Z[1], Z[2])
    points, links = {}, {}
    for p in g.unknown:
        i = next(i for i, (_, pts) in enumerate(g.links) if p in pts)
        _, pos, vel, acc = _point(fr.link(i), *g.local[i][p])
        points[p] = (pos[0], pos[1], vel[0], vel[1], acc[0], acc[1])
    for i, (name, _) in enumerate(g.links):
        links[name] = (fr.c[i], fr.s[i], fr.w[i], fr.a[i])
    return GroupSolution(points, links, assembled, g.branch, end)


def singularity(g: PrismaticGroup, positions: Mapping[str, Sequence], angles: Mapping[str, tuple]) -> np.ndarray:
    """The group's distance from a singular pose, in [0, 1] (0 where it folds): the smallest singular value of
    the Jacobian with angles in units of the size and each row scaled to unit length, times
    :data:`DYAD_CALIBRATION` (so that it reads like a dyad's transmission sine), at most 1. NaN where a point
    is. ``positions``: the group's points (x, y, ...); ``angles``: its links' (cos, sin, ...).

    Not the determinant (the revolute groups' measure, :func:`.general_group.singularity`): over the ``3 L``
    frame coordinates it is the product of ``3 L`` singular values, all but one well away from 0 and below 1,
    so it reads 2.5x lower than a dyad's sine for a slider-crank written as a group and about 50x lower for a
    six-link group at the same distance from its fold (the smallest singular value bounds how much a
    constraint error is magnified in the positions, whatever the group's size)."""
    L = len(g.links)
    cols = []
    for name, pts in g.links:
        x, y = positions[pts[0]][0], positions[pts[0]][1]
        c, s = angles[name][0], angles[name][1]
        cols += [x, y, np.arctan2(s, c)]
    arrs = np.broadcast_arrays(*cols, *[positions[p][0] for p in g.known])
    m = arrs[0].shape
    z = np.array([np.ravel(a) for a in arrs[:3 * L]])
    K = np.array([c for p in g.known for c in (np.ravel(np.broadcast_to(positions[p][0], m)),
                                                np.ravel(np.broadcast_to(positions[p][1], m)))])
    K = K.reshape(2 * len(g.known), -1) if len(g.known) else np.zeros((0, z.shape[1]))
    _, J = _residual(g, z, K, jac=True)
    out = np.full(J.shape[0], np.nan)
    with np.errstate(all="ignore"):
        J = J / g.scale[None, None, :]
        J /= np.sqrt(np.sum(J * J, axis=2, keepdims=True))
        ok = np.all(np.isfinite(J), axis=(1, 2))
    if ok.any():
        out[ok] = np.minimum(DYAD_CALIBRATION * np.linalg.svd(J[ok], compute_uv=False)[:, -1], 1.0)
    return out.reshape(m) if m else out[0]
