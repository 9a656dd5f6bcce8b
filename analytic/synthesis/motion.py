"""Motion generation of a four-bar by Burmester theory: a coupler that takes given poses (x_j, y_j, theta_j).

The coupler is the moving frame: its origin at (x_j, y_j), turned by theta_j. A moving point with frame
coordinates z is at Z_j = P_j + R(theta_j) z; it can be guided by a ground pivot (centre point) c when
all its positions lie on one circle about c: |Z_j - c| = |Z_1 - c|. Expanded, for j = 2..n,

    E_j(c, z) = alpha_j + beta_j . z - gamma_j . c - c^T G_j z = 0,
    alpha_j = |P_j|^2 - |P_1|^2,  beta_j = 2 (R_j^T P_j - R_1^T P_1),  gamma_j = 2 (P_j - P_1),
    G_j = 2 (R_j - R_1),

linear in c for a given z and in z for a given c (Burmester 1888; Sandor & Erdman, Advanced Mechanism
Design, vol. 2, ch. 2). Hence:

* 3 poses: any circle point gives its centre point (a 2x2 solve): dyads are picked over a grid of circle
  points (the free parameters), or given;
* 4 poses: c is a centre point when the 3x2 system in z is consistent: det [beta_j - G_j^T c | gamma_j . c
  - alpha_j] = 0, the cubic centre-point curve, sampled along rays (a cubic in the distance along each);
  the circle points follow by the linear solve;
* 5 poses: the Burmester points, where the centre-point curves of poses 1-4 and 1-3,5 meet: the four
  bilinear equations solved by Newton's method from points sampled on the first curve;
* more poses: dyads minimising sum_j E_j^2 (Gauss-Newton from the same starting points).

Two dyads make a four-bar (crank: the first, rocker: the second). A pair is kept only if the linkage,
assembled at the first pose, meets every pose on the same branch, in the order the poses are given with
the crank turning one way, and can close everywhere in between; otherwise its ``defect`` says why.
Pairs are ranked by the output error (least squares) and then by the smallest transmission angle over
the travel (largest first).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic._common import ParameterError
from analytic.synthesis.fourbar import Linkage, coupler_frame

__all__ = ["Dyad", "Design", "dyad_equations", "centre_point", "centre_point_curve", "burmester_points",
           "dyads", "synthesize"]


@dataclass(frozen=True)
class Dyad:
    """A ground pivot ``centre`` (fixed frame) and a ``circle`` point (coupler frame); ``residual``: the
    largest |E_j| / size^2 (0 for an exact dyad)."""

    centre: tuple[float, float]
    circle: tuple[float, float]
    residual: float = 0.0


@dataclass(frozen=True)
class Design:
    """A four-bar for the poses: ``linkage``; ``inputs``: its crank angle at each pose [rad]; ``errors``:
    per pose, the distance [length unit] of the coupler point from the pose point and the coupler angle
    error [rad] (closed form of the dyads, on the branch of pose 1); ``mu_min``: the smallest transmission
    angle over the travel [rad]; ``defect``: "" or why the crank cannot take the poses in order."""

    linkage: Linkage
    inputs: np.ndarray
    errors: np.ndarray
    angle_errors: np.ndarray
    mu_min: float
    defect: str
    crank: Dyad
    rocker: Dyad


def _poses(poses) -> tuple[np.ndarray, np.ndarray]:
    a = np.asarray(poses, dtype=float)
    if a.ndim != 2 or a.shape[1] != 3:
        raise ParameterError("poses must be rows of (x, y, theta)")
    return a[:, :2], a[:, 2]


def _rot(t):
    c, s = np.cos(t), np.sin(t)
    return np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)


def dyad_equations(poses):
    """(alpha, beta, gamma, G) of E_j for j = 2..n: shapes (n-1,), (n-1, 2), (n-1, 2), (n-1, 2, 2)."""
    P, th = _poses(poses)
    R = _rot(th)
    RtP = np.einsum("jki,jk->ji", R, P)
    alpha = np.sum(P[1:] ** 2, axis=1) - np.sum(P[0] ** 2)
    beta = 2 * (RtP[1:] - RtP[0])
    gamma = 2 * (P[1:] - P[0])
    G = 2 * (R[1:] - R[0])
    return alpha, beta, gamma, G


def residuals(poses, c, z):
    """E_j(c, z), j = 2..n, for arrays of centre and circle points (..., 2): shape (..., n-1)."""
    alpha, beta, gamma, G = dyad_equations(poses)
    c, z = np.asarray(c, dtype=float), np.asarray(z, dtype=float)
    Gz = np.einsum("jab,...b->...ja", G, z)
    return alpha + z @ beta.T - c @ gamma.T - np.einsum("...a,...ja->...j", c, Gz)


def centre_point(poses, circle) -> np.ndarray:
    """The centre point of moving point ``circle`` (coupler frame) through 3 poses (or the least-squares
    one for more): (gamma_j + G_j z) . c = alpha_j + beta_j . z."""
    alpha, beta, gamma, G = dyad_equations(poses)
    z = np.asarray(circle, dtype=float)
    A = gamma + np.einsum("jab,b->ja", G, z)
    rhs = alpha + beta @ z
    if len(alpha) == 2:
        if abs(np.linalg.det(A)) < 1e-14 * max(1.0, np.abs(A).max()) ** 2:
            raise ParameterError("that circle point's three positions lie on a line: it has no centre point")
        return np.linalg.solve(A, rhs)
    return np.linalg.lstsq(A, rhs, rcond=None)[0]


def _circle_of(alpha, beta, gamma, G, c):
    """Circle points for centre points c (..., 2): least squares of (beta_j - G_j^T c) . z = gamma_j . c
    - alpha_j (exact where the system is consistent)."""
    M = beta - np.einsum("jab,...a->...jb", G, c)
    rhs = np.einsum("ja,...a->...j", gamma, c) - alpha
    MtM = np.einsum("...ja,...jb->...ab", M, M)
    Mtr = np.einsum("...ja,...j->...a", M, rhs)
    with np.errstate(all="ignore"):
        return np.linalg.solve(MtM, Mtr[..., None])[..., 0]


def _size(poses) -> float:
    P, _ = _poses(poses)
    return float(max(np.ptp(P, axis=0).max(), 1e-9))


def centre_point_curve(poses, rays: int = 720) -> np.ndarray:
    """Points (m, 2) of the centre-point curve of 4 poses: on each of ``rays`` lines through the poses'
    centroid, the real roots of the cubic det [beta_j - G_j^T c | gamma_j . c - alpha_j] = 0."""
    alpha, beta, gamma, G = dyad_equations(poses)
    if len(alpha) != 3:
        raise ParameterError("the centre-point curve is that of exactly 4 poses")
    P, _ = _poses(poses)
    o, s = P.mean(axis=0), _size(poses)
    psi = np.linspace(0.0, np.pi, rays, endpoint=False)
    u = np.stack([np.cos(psi), np.sin(psi)], -1)
    nodes = np.array([-1.0, 0.0, 1.0, 2.0])
    c = o + s * nodes[None, :, None] * u[:, None, :]                  # (rays, 4, 2)
    M = beta - np.einsum("jab,...a->...jb", G, c)                    # (rays, 4, 3, 2)
    rhs = np.einsum("ja,...a->...j", gamma, c) - alpha
    det = np.linalg.det(np.concatenate([M, rhs[..., None]], axis=-1))  # (rays, 4)
    coef = np.linalg.solve(np.vander(nodes, 4), det.T).T                # cubic in rho/s, highest first
    lead = coef[:, 0]
    ok = np.abs(lead) > 1e-12 * np.abs(coef).max(axis=1)
    comp = np.zeros((ok.sum(), 3, 3))
    comp[:, 0, :] = -coef[ok, 1:] / lead[ok, None]
    comp[:, 1, 0] = comp[:, 2, 1] = 1.0
    roots = np.linalg.eigvals(comp)                                     # (rays', 3)
    real = np.abs(roots.imag) < 1e-9 * np.maximum(1.0, np.abs(roots.real))
    rho = np.where(real, roots.real, np.nan)
    pts = o + s * rho[..., None] * u[ok][:, None, :]
    pts = pts.reshape(-1, 2)
    return pts[np.all(np.isfinite(pts), axis=1) & (np.abs(pts - o).max(axis=1) < 100 * s)]


def _newton(poses, c, z, least_squares: bool, iters: int = 60):
    """Newton (square system) or Gauss-Newton (more equations) on E_j(c, z) = 0 from many starts."""
    alpha, beta, gamma, G = dyad_equations(poses)
    x = np.concatenate([c, z], axis=1)
    for _ in range(iters):
        c, z = x[:, :2], x[:, 2:]
        E = residuals(poses, c, z)                                     # (m, n-1)
        Jz = beta - np.einsum("jab,ma->mjb", G, c)
        Jc = -gamma - np.einsum("jab,mb->mja", G, z)
        J = np.concatenate([Jc, Jz], axis=2)                           # (m, n-1, 4)
        with np.errstate(all="ignore"):
            if least_squares:
                JtJ = np.einsum("mja,mjb->mab", J, J) + 1e-12 * np.eye(4)
                step = np.linalg.solve(JtJ, np.einsum("mja,mj->ma", J, E)[..., None])[..., 0]
            else:
                bad = np.abs(np.linalg.det(J)) < 1e-300
                J[bad] = np.eye(4)
                step = np.linalg.solve(J, E[..., None])[..., 0]
        x = x - step
        x[~np.all(np.isfinite(x), axis=1)] = np.nan
    return x[:, :2], x[:, 2:]


def _unique(c, z, scale, tol=1e-6):
    keep: list[int] = []
    for i in range(len(c)):
        if all(np.hypot(*(c[i] - c[k])) > tol * scale or np.hypot(*(z[i] - z[k])) > tol * scale for k in keep):
            keep.append(i)
    return keep


def burmester_points(poses) -> list[Dyad]:
    """The Burmester dyads of 5 poses (0, 2 or 4 real; exact to rounding), or the least-squares dyads of
    more poses (local minima of sum_j E_j^2, best first)."""
    P, _ = _poses(poses)
    n = len(P)
    if n < 5:
        raise ParameterError("Burmester points need at least 5 poses")
    s = _size(poses)
    c0 = centre_point_curve(poses[:4], rays=360)
    alpha, beta, gamma, G = dyad_equations(poses[:4])
    z0 = _circle_of(alpha, beta, gamma, G, c0)
    ok = np.all(np.isfinite(z0), axis=1)
    c, z = _newton(poses, c0[ok], z0[ok], least_squares=n > 5)
    E = residuals(poses, c, z)
    err = np.sqrt(np.nanmax(E ** 2, axis=1)) / s ** 2
    good = np.isfinite(err) & (np.abs(c - P.mean(0)).max(axis=1) < 100 * s)
    if n == 5:
        good &= err < 1e-10
    order = np.argsort(np.where(good, err, np.inf))
    order = order[good[order]]
    keep = _unique(c[order], z[order], s)
    return [Dyad(tuple(map(float, c[order][k])), tuple(map(float, z[order][k])), float(err[order][k]))
            for k in keep]


def dyads(poses, circle_points=None, count: int = 120) -> list[Dyad]:
    """Candidate dyads for the poses: for 3, one per circle point (given in the fixed frame at pose 1, or
    a grid around the poses); for 4, points spread along the centre-point curve; for 5+, Burmester's."""
    P, th = _poses(poses)
    n = len(P)
    if n < 3:
        raise ParameterError(f"motion synthesis needs at least 3 poses, got {n}")
    s = _size(poses)
    if n >= 5:
        return burmester_points(poses)
    alpha, beta, gamma, G = dyad_equations(poses)
    if n == 4:
        c = centre_point_curve(poses)
        z = _circle_of(alpha, beta, gamma, G, c)
        ok = np.all(np.isfinite(z), axis=1)
        c, z = c[ok], z[ok]
        if len(c) > count:
            # spread along the curve: order by angle about the centroid, then take evenly
            ang = np.arctan2(*(c - P.mean(0)).T[::-1])
            idx = np.argsort(ang)[np.linspace(0, len(c) - 1, count).astype(int)]
            c, z = c[idx], z[idx]
        E = residuals(poses, c, z)
        return [Dyad(tuple(map(float, ci)), tuple(map(float, zi)), float(np.abs(e).max() / s ** 2))
                for ci, zi, e in zip(c, z, E)]
    if circle_points is None:
        g = np.linspace(-1.0, 1.0, 11)
        X, Y = np.meshgrid(g, g)
        circle_points = P[0] + 1.5 * s * np.stack([X.ravel(), Y.ravel()], -1)
    out = []
    R1 = _rot(th[0])
    for Z1 in np.asarray(circle_points, dtype=float):
        z = R1.T @ (Z1 - P[0])
        try:
            c = centre_point(poses, z)
        except ParameterError:
            continue
        if np.abs(c - P.mean(0)).max() < 20 * s:
            out.append(Dyad(tuple(map(float, c)), tuple(map(float, z))))
    return out


def _wrap(x):
    return (np.asarray(x) + np.pi) % (2 * np.pi) - np.pi


def _pairs(poses, cranks: list[Dyad], rockers: list[Dyad], samples: int = 91):
    """Every (crank, rocker) pair evaluated at once: arrays per pair."""
    P, th = _poses(poses)
    R = _rot(th)
    ca = np.array([d.centre for d in cranks])[:, None, :]
    za = np.array([d.circle for d in cranks])
    cb = np.array([d.centre for d in rockers])[None, :, :]
    zb = np.array([d.circle for d in rockers])
    Bj = P[None, :, :] + np.einsum("jab,kb->kja", R, za)             # (ka, n, 2)
    Cj = P[None, :, :] + np.einsum("jab,kb->kja", R, zb)             # (kb, n, 2)
    shape = (len(cranks), len(rockers), len(P), 2)
    B, C = np.broadcast_to(Bj[:, None], shape), np.broadcast_to(Cj[None, :], shape)
    A, D = np.broadcast_to(ca[:, :, None, :], shape), np.broadcast_to(cb[:, :, None, :], shape)
    l1 = np.hypot(*(B[..., 0, :] - A[..., 0, :]).transpose(2, 0, 1))
    l2 = np.hypot(*(C[..., 0, :] - B[..., 0, :]).transpose(2, 0, 1))
    l3 = np.hypot(*(C[..., 0, :] - D[..., 0, :]).transpose(2, 0, 1))
    cross = (D[..., 0] - B[..., 0]) * (C[..., 1] - B[..., 1]) - (D[..., 1] - B[..., 1]) * (C[..., 0] - B[..., 0])
    branch = np.where(cross[..., 0] > 0, 1, -1)
    same = np.all(np.sign(cross) == branch[..., None], axis=-1)
    q = np.arctan2(B[..., 1] - A[..., 1], B[..., 0] - A[..., 0])       # crank angle at each pose
    sense = np.where(_wrap(q[..., 1] - q[..., 0]) >= 0, 1.0, -1.0)
    travel = np.mod(sense[..., None] * (q - q[..., :1]), 2 * np.pi)
    ordered = np.all(np.diff(travel, axis=-1) > 0, axis=-1)
    # closure and transmission angle over the travel from the first pose to the last
    u = np.linspace(0.0, 1.0, samples)
    qs = q[..., :1] + sense[..., None] * travel[..., -1:] * u
    Bx = A[..., :1, 0] + l1[..., None] * np.cos(qs)
    By = A[..., :1, 1] + l1[..., None] * np.sin(qs)
    d2 = (Bx - D[..., :1, 0]) ** 2 + (By - D[..., :1, 1]) ** 2
    with np.errstate(all="ignore"):
        cosmu = (l2[..., None] ** 2 + l3[..., None] ** 2 - d2) / (2 * l2[..., None] * l3[..., None])
    closes = np.all(np.abs(cosmu) <= 1.0, axis=-1)
    mu = np.arccos(np.clip(cosmu, -1.0, 1.0))
    mu_min = np.min(np.minimum(mu, np.pi - mu), axis=-1)
    return dict(l1=l1, l2=l2, l3=l3, branch=branch, same=same, ordered=ordered, closes=closes,
                mu_min=mu_min, q=q, sense=sense, B=B, C=C)


def _design(poses, crank: Dyad, rocker: Dyad, ev, i, k) -> Design:
    P, th = _poses(poses)
    B1, C1 = ev["B"][i, k, 0], ev["C"][i, k, 0]
    ex, ey = coupler_frame(B1, C1, P[0])
    q = ev["q"][i, k]
    link = Linkage(crank.centre, rocker.centre, float(ev["l1"][i, k]), float(ev["l2"][i, k]),
                   float(ev["l3"][i, k]), ex, ey, int(ev["branch"][i, k]), float(q[0]),
                   float(ev["sense"][i, k]) * 2 * math.pi)
    pos_err, ang_err = _closed_form_errors(poses, link, q)
    defect = ""
    if not ev["same"][i, k]:
        B, C, D = ev["B"][i, k], ev["C"][i, k], rocker.centre
        cross = (D[0] - B[:, 0]) * (C[:, 1] - B[:, 1]) - (D[1] - B[:, 1]) * (C[:, 0] - B[:, 0])
        j = int(np.flatnonzero(np.sign(cross) != ev["branch"][i, k])[0])
        defect = f"pose {j + 1} is on the other branch of the loop than pose 1 (a branch defect)"
    elif not ev["ordered"][i, k]:
        defect = "the crank turning one way does not meet the poses in their order (an order defect)"
    elif not ev["closes"][i, k]:
        defect = "the loop cannot close somewhere between the first and the last pose"
    return Design(link, q, pos_err, ang_err, float(ev["mu_min"][i, k]), defect, crank, rocker)


def _closed_form_errors(poses, link: Linkage, q):
    """Coupler point and angle at crank angles ``q`` on the linkage's branch (circle intersection),
    against the poses."""
    P, th = _poses(poses)
    A, D = np.asarray(link.A), np.asarray(link.D)
    B = A + link.l1 * np.stack([np.cos(q), np.sin(q)], -1)
    d = D - B
    L2 = np.sum(d * d, axis=1)
    x = (link.l2 ** 2 - link.l3 ** 2 + L2) / (2 * L2)
    with np.errstate(invalid="ignore"):
        h = np.sqrt(link.l2 ** 2 / L2 - x * x)
    C = B + x[:, None] * d + link.branch * h[:, None] * np.stack([-d[:, 1], d[:, 0]], -1)
    u = (C - B) / link.l2
    E = B + link.ex * u + link.ey * np.stack([-u[:, 1], u[:, 0]], -1)
    ang = np.arctan2(u[:, 1], u[:, 0])
    return np.hypot(*(E - P).T), _wrap((ang - ang[0]) - (th - th[0]))


def dyads_of_centres(poses, centres) -> list[Dyad]:
    """3 poses: the dyad of each given centre point (fixed frame), its circle point by the 2x2 solve of
    (beta_j - G_j^T c) . z = gamma_j . c - alpha_j; centres whose system is singular are skipped."""
    P, _ = _poses(poses)
    if len(P) != 3:
        raise ParameterError("centre points give their dyads directly for exactly 3 poses")
    alpha, beta, gamma, G = dyad_equations(poses)
    c = np.asarray(centres, dtype=float).reshape(-1, 2)
    z = _circle_of(alpha, beta, gamma, G, c)
    ok = np.all(np.isfinite(z), axis=1) & (np.abs(residuals(poses, c, z)).max(axis=1) <= 1e-9 * _size(poses) ** 2)
    return [Dyad(tuple(map(float, ci)), tuple(map(float, zi))) for ci, zi in zip(c[ok], z[ok])]


def synthesize(poses, circle_points=None, count: int = 5, centres=None) -> tuple[list[Design], list[Dyad]]:
    """Four-bars whose coupler takes ``poses`` (rows x, y, theta [length unit, rad]) in order.

    Parameters
    ----------
    poses : array_like, (n, 3)
        n >= 3 poses of the coupler frame (its origin becomes the output point E).
    circle_points : array_like, (m, 2), optional
        For 3 poses: the circle points to use (fixed frame, at pose 1); default a grid around the poses.
    count : int
        How many designs to return at most.
    centres : array_like, (m, 2), optional
        For 3 poses: centre points (ground pivots) whose dyads join the candidates (:func:`dyads_of_centres`).

    Returns
    -------
    (designs, dyads)
        Designs best first, those without a defect before those with one; the candidate dyads.
        Raises ParameterError when no dyad exists (no real Burmester point: no four-bar reaches the poses).
    """
    P, th = _poses(poses)
    cand = dyads(poses, circle_points)
    if centres is not None and len(P) == 3:
        cand = cand + dyads_of_centres(poses, centres)
    if len(cand) < 1 or (len(P) == 5 and len(cand) < 2):
        raise ParameterError(f"the {len(P)} poses have {len(cand)} real Burmester dyad(s): no four-bar takes "
                             f"the coupler through them")
    ev = _pairs(poses, cand, cand)
    s = _size(poses)
    n = len(cand)
    ii, kk = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    distinct = ii != kk
    # the two pivots of one linkage must differ
    sep = np.hypot(*(np.array([d.centre for d in cand])[ii] - np.array([d.centre for d in cand])[kk]).transpose(2, 0, 1))
    distinct &= sep > 1e-6 * s
    ok = distinct & ev["same"] & ev["ordered"] & ev["closes"]
    resid = np.array([d.residual for d in cand])
    score_err = resid[ii] + resid[kk]
    # rank: feasible first, then by residual (least squares), then larger mu_min, then compactness
    size = ev["l1"] + ev["l2"] + ev["l3"]
    key = np.lexsort((size.ravel(), -np.round(ev["mu_min"].ravel(), 6), np.round(score_err.ravel(), 12),
                      ~ok.ravel(), ~distinct.ravel()))
    if len(P) > 5:
        # least squares: rank every distinct pair by its design's own pose error (few dyads: few pairs)
        pairs = [divmod(int(f), n) for f in key if distinct.ravel()[f]][:400]
        found = [_design(poses, cand[i], cand[k], ev, i, k) for i, k in pairs]
        found.sort(key=lambda d: (bool(d.defect), float(np.sqrt(np.mean(d.errors ** 2))), -d.mu_min))
        return found[:count], cand
    out: list[Design] = []
    for flat in key[: max(count, 1) * 4]:
        i, k = divmod(int(flat), n)
        if not distinct[i, k]:
            break
        out.append(_design(poses, cand[i], cand[k], ev, i, k))
        if len(out) >= count:
            break
    return out, cand
