"""Four-bar path synthesis: many designs' coupler curves at once, a global search and a least-squares polish.

A design is the vector ``(ax, ay, theta0, d, a, b, c, ex, ey)`` [length unit of the targets, rad]: crank
pivot A, ground angle theta0 of A->D, ground |AD| = d, crank AB = a, coupler BC = b, rocker DC = c, and the
coupler point E = B + ex u + ey n in the coupler frame (u along B->C, n = u turned +90 deg); ``branch`` is
+1 when C is left of the line B->D (the solver's RRR branch). The crank angle ``phi`` is B's absolute angle
about A, from +x.

The crank turns fully on one branch and keeps the transmission angle mu (between coupler and rocker) in
``[mu_min, 180 deg - mu_min]`` iff both extremes of |BD| (``|d - a|`` and ``d + a``) satisfy it; that closed
form is the constraint used everywhere here (Grashof crank-rocker and double-crank pass, nothing else can).

Free timing: the error of a target is its distance to the closed coupler curve. Timing: to the coupler point
at the crank angle ``phi_i + phi_offset`` (the targets' input angles up to one common, free offset).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from analytic._common import ParameterError

__all__ = ["Target", "Constraints", "Design", "coupler_points", "violation", "curve_distance",
           "errors", "synthesize", "restart", "from_four_bar_rs"]

NAMES = ("ax", "ay", "theta0", "d", "a", "b", "c", "ex", "ey")


@dataclass(frozen=True)
class Target:
    """Target points ``xy`` (M, 2) [length]; ``phi`` (M,) input angles [rad] with timing, else None."""

    xy: np.ndarray
    phi: np.ndarray | None = None

    @property
    def centre(self) -> np.ndarray:
        return 0.5 * (self.xy.min(axis=0) + self.xy.max(axis=0))

    @property
    def size(self) -> float:
        """The larger side of the targets' bounding box [length]."""
        return float(np.ptp(self.xy, axis=0).max())


@dataclass(frozen=True)
class Constraints:
    """``mu_min``: least transmission angle [rad]; ``max_ratio``: longest/shortest of d, a, b, c;
    ``region``: pivots and lengths within this many target sizes of the targets' centre."""

    mu_min: float = math.radians(30.0)
    max_ratio: float = 20.0
    region: float = 3.0


@dataclass(frozen=True)
class Design:
    """One synthesised design: ``x`` the 9 parameters, ``branch`` +-1, ``phi_offset`` (timing) [rad],
    ``err`` (M,) the distance of each target [length], ``phis`` (M,) the crank angle of each target's
    nearest (or timed) point [rad], ``violation`` (0 when every constraint holds), ``seed``."""

    x: np.ndarray
    branch: int
    phi_offset: float
    err: np.ndarray
    phis: np.ndarray
    violation: float
    seed: int
    failed: str = ""
    stats: dict = field(default_factory=dict)

    @property
    def sum_sq(self) -> float:
        return float(np.sum(self.err ** 2))

    def parameters(self) -> dict[str, float]:
        return {**{k: float(v) for k, v in zip(NAMES, self.x)}, "branch": int(self.branch)}


def coupler_points(x: np.ndarray, phi: np.ndarray, branch) -> tuple[np.ndarray, np.ndarray]:
    """Coupler point E of K designs at crank angles ``phi``.

    Parameters
    ----------
    x : (K, 9) designs [length, rad]
    phi : (K, N) or (N,) crank angles [rad]
    branch : (K,) or scalar +-1

    Returns
    -------
    E : (K, N, 2) [length], NaN where the loop does not close
    ok : (K, N) bool, the loop closes
    """
    x = np.atleast_2d(np.asarray(x, dtype=float))
    ax, ay, th, d, a, b, c, ex, ey = (x[:, i:i + 1] for i in range(9))
    br = np.broadcast_to(np.asarray(branch, dtype=float).reshape(-1, 1), (x.shape[0], 1))
    phi = np.asarray(phi, dtype=float)
    bx, by = ax + a * np.cos(phi), ay + a * np.sin(phi)
    dx, dy = ax + d * np.cos(th), ay + d * np.sin(th)
    vx, vy = dx - bx, dy - by
    r2 = vx * vx + vy * vy
    r = np.sqrt(r2)
    ca = (b * b + r2 - c * c) / (2 * b * r)                 # cos of the angle D-B-C
    ok = np.abs(ca) <= 1.0
    sa = br * np.sqrt(np.clip(1.0 - ca * ca, 0.0, None))
    ux, uy = vx / r, vy / r                                  # unit B->D
    cx, cy = ca * ux - sa * uy, sa * ux + ca * uy            # unit B->C (B->D turned by the branch's angle)
    E = np.stack([bx + ex * cx - ey * cy, by + ex * cy + ey * cx], axis=-1)
    E[~ok] = np.nan
    return E, ok


def violation(x: np.ndarray, cons: Constraints, target: Target) -> np.ndarray:
    """How far K designs break the constraints (0 = all hold; dimensionless, >= 0), (K,)."""
    x = np.atleast_2d(x)
    d, a, b, c = x[:, 3], x[:, 4], x[:, 5], x[:, 6]
    cm = math.cos(cons.mu_min)
    with np.errstate(divide="ignore", invalid="ignore"):
        cos_lo = (b * b + c * c - (d - a) ** 2) / (2 * b * c)   # mu at |BD| least: must be <= cos mu_min
        cos_hi = (b * b + c * c - (d + a) ** 2) / (2 * b * c)   # mu at |BD| most: must be >= -cos mu_min
        L = np.stack([d, a, b, c], axis=1)
        ratio = L.max(axis=1) / L.min(axis=1)
    s = max(target.size, 1e-300)
    piv = np.stack([x[:, 0], x[:, 1], x[:, 0] + d * np.cos(x[:, 2]), x[:, 1] + d * np.sin(x[:, 2])], axis=1)
    cen = np.tile(target.centre, 2)
    out = (np.maximum(cos_lo - cm, 0) + np.maximum(-cm - cos_hi, 0)
           + np.maximum(ratio / cons.max_ratio - 1, 0)
           + np.maximum(np.abs(piv - cen).max(axis=1) / (cons.region * s) - 1, 0)
           + np.maximum(-L.min(axis=1), 0) / s)
    return np.where(np.isfinite(out), out, 1e3)


def failed_constraint(x, cons: Constraints, target: Target) -> str:
    """Words for the first constraint one design breaks ('' when none)."""
    x = np.asarray(x, dtype=float)
    d, a, b, c = x[3:7]
    cm = math.cos(cons.mu_min)
    if min(d, a, b, c) <= 0:
        return "a link length is not positive"
    lo = (b * b + c * c - (d - a) ** 2) / (2 * b * c)
    hi = (b * b + c * c - (d + a) ** 2) / (2 * b * c)
    if lo > 1 or hi < -1:
        return "the crank does not turn fully (not a Grashof crank-rocker or double-crank)"
    if lo > cm or hi < -cm:
        mu = math.degrees(min(math.acos(min(lo, 1)), math.pi - math.acos(max(hi, -1))))
        return f"transmission angle {mu:.1f} deg is below --min-transmission {math.degrees(cons.mu_min):.1f} deg"
    if max(d, a, b, c) / min(d, a, b, c) > cons.max_ratio:
        return f"link-length ratio above {cons.max_ratio:g}"
    if violation(x[None], cons, target)[0] > 0:
        return f"a pivot lies outside {cons.region:g} target sizes of the targets' centre"
    return ""


def _nearest_sample(E: np.ndarray, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Squared distance (K, M) from each target to the nearest curve sample and that sample's index.

    The search uses |e|^2 - 2 e.t (a matrix product; |t|^2 is the same for every sample), the returned
    distance is recomputed directly at the chosen sample (no cancellation)."""
    G = (E * E).sum(-1)[:, :, None] - 2.0 * (E @ xy.T)              # (K, N, M)
    G = np.nan_to_num(G, nan=np.inf)
    k = G.argmin(axis=1)
    P = np.take_along_axis(E, k[:, :, None], axis=1)                  # (K, M, 2)
    d2 = ((P - xy[None]) ** 2).sum(-1)
    return np.where(np.isfinite(d2), d2, np.inf), k


def batch_error(x: np.ndarray, target: Target, branch, n: int = 192) -> np.ndarray:
    """Sum of squared distances (K,) from the targets to each design's curve sampled at n crank angles
    (free timing), or to its timed points (timing: x carries a 10th column, the crank offset)."""
    x = np.atleast_2d(x)
    if target.phi is not None:
        E, _ = coupler_points(x[:, :9], x[:, 9:10] + target.phi[None, :], branch)
        e = ((E - target.xy[None]) ** 2).sum(-1).sum(-1)
        return np.where(np.isfinite(e), e, np.inf)
    out = np.empty(x.shape[0])
    phi = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    step = max(1, int(4e6 // (n * len(target.xy))))           # keep (K, N, M) arrays near 32 MB
    for i in range(0, x.shape[0], step):
        E, _ = coupler_points(x[i:i + step], phi, branch[i:i + step] if np.ndim(branch) else branch)
        out[i:i + step] = _nearest_sample(E, target.xy)[0].sum(-1)
    return out


def similarity(x: np.ndarray, z: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Designs (K, 9) moved by the similarity p -> z p + t (complex z = scale e^(i angle), t) [length]."""
    x = np.array(x, dtype=float)
    A = (x[:, 0] + 1j * x[:, 1]) * z + t
    x[:, 0], x[:, 1] = A.real, A.imag
    x[:, 2] = x[:, 2] + np.angle(z)
    x[:, 3:9] = x[:, 3:9] * np.abs(z)[:, None]
    return x


def align(x: np.ndarray, target: Target, branch, n: int = 160, steps: int = 2) -> np.ndarray:
    """Move, turn and scale K designs (free timing) so their curves lie nearest the targets: ``steps``
    rounds of nearest-sample correspondence and the least-squares similarity (Umeyama, in complex form)."""
    x = np.atleast_2d(np.asarray(x, dtype=float)).copy()
    phi = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    q = target.xy[:, 0] + 1j * target.xy[:, 1]
    for _ in range(steps):
        E, _ = coupler_points(x, phi, branch)
        _, k = _nearest_sample(E, target.xy)
        P = np.take_along_axis(E, k[:, :, None], axis=1)          # (K, M, 2) corresponding curve points
        p = P[..., 0] + 1j * P[..., 1]
        pc = p - p.mean(axis=1, keepdims=True)
        qc = q - q.mean()
        with np.errstate(divide="ignore", invalid="ignore"):
            z = (np.conj(pc) * qc[None]).sum(1) / (np.abs(pc) ** 2).sum(1)
        good = np.isfinite(z) & (np.abs(z) > 0.5) & (np.abs(z) < 2.0)
        z = np.where(good, z, 1.0)
        t = np.where(good, q.mean() - z * p.mean(axis=1), 0.0)
        x = similarity(x, z, t)
    return x


def curve_distance(x, branch: int, xy: np.ndarray, n: int = 4096, iters: int = 60):
    """Distance from each target to one design's closed coupler curve: nearest of n samples, refined by
    a golden-section search over the neighbouring two sample intervals (vectorised over targets).

    Returns (dist (M,) [length], phi (M,) [rad])."""
    x = np.asarray(x, dtype=float)[None, :9]
    phi = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    E, _ = coupler_points(x, phi, branch)
    _, k = _nearest_sample(E, xy)
    h = 2 * math.pi / n
    lo, hi = phi[k[0]] - h, phi[k[0]] + h
    g = (math.sqrt(5) - 1) / 2

    def f(p):
        P, _ = coupler_points(x, p[None, :], branch)
        v = ((P[0] - xy) ** 2).sum(-1)
        return np.where(np.isnan(v), np.inf, v)
    for _ in range(iters):
        p1, p2 = hi - g * (hi - lo), lo + g * (hi - lo)
        left = f(p1) < f(p2)
        hi, lo = np.where(left, p2, hi), np.where(left, lo, p1)
    p = 0.5 * (lo + hi)
    d2 = f(p)
    # the sample itself may be better where the curve has a gap (a NaN neighbour)
    d2s = ((E[0, k[0]] - xy) ** 2).sum(-1)
    use = ~(d2 <= d2s)
    return np.sqrt(np.where(use, d2s, d2)), np.where(use, phi[k[0]], p)


def errors(x, branch: int, target: Target, phi_offset: float = 0.0):
    """Each target's error [length] and crank angle [rad] for one design (see the module doc)."""
    if target.phi is None:
        return curve_distance(x, branch, target.xy)
    phis = target.phi + phi_offset
    E, _ = coupler_points(np.asarray(x)[None, :9], phis[None], branch)
    return np.hypot(*(E[0] - target.xy).T), phis


# --- normalised design space -------------------------------------------------------------------------

RATIO = 6.0  # ground, coupler and rocker searched in [1/RATIO, RATIO] crank lengths (log scale)
ROTATIONS = 8  # starting turns of each shape before the similarity alignment


def _shape(u: np.ndarray) -> np.ndarray:
    """(K, 5) unit-cube points -> designs with A at the origin, D on +x and a unit crank."""
    x = np.zeros((len(u), 9))
    x[:, 3:7] = 1.0
    x[:, [3, 5, 6]] = np.exp((2 * u[:, 0:3] - 1) * math.log(RATIO))
    x[:, 7:9] = (2 * u[:, 3:5] - 1) * 2 * RATIO ** 0.5
    return x


def _pose(xn: np.ndarray, target: Target, branch, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Each shape moved, turned and scaled onto the targets: ROTATIONS starts matching the curve's centroid
    and RMS radius to the targets', each aligned (``align``); the best kept. Returns (x (K, 9), sum_sq (K,))."""
    K = len(xn)
    phi = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    E, _ = coupler_points(xn, phi, branch)
    cE = np.nanmean(E, axis=1)
    rE = np.sqrt(np.nanmean(((E - cE[:, None]) ** 2).sum(-1), axis=1))
    cT = target.xy.mean(0)
    rT = math.sqrt(((target.xy - cT) ** 2).sum(-1).mean())
    psi = 2 * math.pi * np.arange(ROTATIONS) / ROTATIONS
    z = (rT / rE)[:, None] * np.exp(1j * psi)[None, :]                     # (K, R)
    t = (cT[0] + 1j * cT[1]) - z * (cE[:, 0] + 1j * cE[:, 1])[:, None]
    xs = similarity(np.repeat(xn, ROTATIONS, axis=0), z.ravel(), t.ravel())
    br = np.repeat(np.broadcast_to(np.asarray(branch), (K,)), ROTATIONS)
    xs = align(xs, target, br, n, steps=3)
    f = batch_error(xs, target, br, n).reshape(K, ROTATIONS)
    f = np.where(np.isfinite(f), f, np.inf)
    j = f.argmin(axis=1)
    return xs.reshape(K, ROTATIONS, 9)[np.arange(K), j], f[np.arange(K), j]


def _pose_timed(u: np.ndarray, target: Target, branch) -> tuple[np.ndarray, np.ndarray]:
    """Timing: shapes (first 5 columns) with a crank offset (6th), posed by the exact least-squares
    similarity onto the timed targets (the correspondences are known). Returns (x (K, 10) with the offset
    last, sum_sq (K,)); a turn of the design adds its angle to the offset."""
    xn = _shape(u[:, :5])
    off = (2 * u[:, 5] - 1) * math.pi
    E, _ = coupler_points(xn, off[:, None] + target.phi[None, :], branch)
    p = E[..., 0] + 1j * E[..., 1]
    q = target.xy[:, 0] + 1j * target.xy[:, 1]
    pc, qc = p - p.mean(1, keepdims=True), q - q.mean()
    with np.errstate(divide="ignore", invalid="ignore"):
        z = (np.conj(pc) * qc[None]).sum(1) / (np.abs(pc) ** 2).sum(1)
    z = np.where(np.isfinite(z) & (z != 0), z, 1.0)
    t = q.mean() - z * p.mean(1)
    x = np.column_stack([similarity(xn, z, t), off + np.angle(z)])
    e = (np.abs(z[:, None] * p + t[:, None] - q[None]) ** 2).sum(1)
    return x, np.where(np.isfinite(e), e, np.inf)


def _shape_objective(u, target, cons, branch, n):
    """Deb's rule on the posed shapes (error / size^2; infeasible above 1e6 by violation)."""
    xn = _shape(u[:, :5])
    loose = Constraints(cons.mu_min, cons.max_ratio, 1e9)
    v = violation(xn, loose, target)
    f = 1e6 + v
    ok = v == 0
    if ok.any():
        x, e = _pose(xn[ok], target, branch, n) if target.phi is None else _pose_timed(u[ok], target, branch)
        v2 = violation(x[:, :9], cons, target)
        f[ok] = np.where(v2 == 0, np.minimum(e / target.size ** 2, 1e6), 1e6 + v2)
    return f


def restart(job: tuple) -> Design:
    """One seeded restart: an atlas of random feasible designs, differential evolution from its best,
    a least-squares polish of the best distinct members. ``job`` = (target, cons, seed, branch,
    generations, popsize, deadline, n_polish).

    Both search the 5 shape parameters (crank = 1), each shape posed onto the targets by a similarity:
    free timing by nearest-point alignment, timing (plus a crank offset) by the exact least squares."""
    from scipy.optimize import differential_evolution

    target, cons, seed, branch, generations, popsize, deadline, n_polish = job
    free = target.phi is None
    dim = 5 if free else 6
    rng = np.random.default_rng(seed)
    obj = lambda u, n: _shape_objective(u, target, cons, branch, n)  # noqa: E731
    if free:
        to_x = lambda u: _pose(_shape(u[None]), target, branch, 256)[0][0]  # noqa: E731
    else:
        to_x = lambda u: _pose_timed(u[None], target, branch)[0][0]  # noqa: E731
    U = rng.random((20000, dim))
    pre = violation(_shape(U[:, :5]), Constraints(cons.mu_min, cons.max_ratio, 1e9), target)
    # atlas: random designs, the least constraint-breaking ranked by error seed the population
    U = U[np.argsort(pre, kind="stable")][:max(popsize * 4, 200)]
    f = obj(U, 96)
    init = U[np.argsort(f, kind="stable")[:popsize]]

    def stop(*_a, **_k):
        return deadline is not None and time.time() > deadline
    res = differential_evolution(
        lambda u: obj(u.T, 128), [(0.0, 1.0)] * dim, init=init,
        maxiter=generations, tol=0, atol=0, seed=int(rng.integers(2 ** 31)), polish=False,
        vectorized=True, updating="deferred", mutation=(0.5, 1.0), recombination=0.9, callback=stop)
    # polish the best distinct members of the final population, keep the best polished one
    order = np.argsort(res.population_energies, kind="stable")
    picks = []
    for j in order:
        if res.population_energies[j] >= 1e6 or len(picks) == n_polish:
            break
        if all(np.abs(res.population[j] - res.population[p]).max() > 1e-3 for p in picks):
            picks.append(j)
    cands = [polish(to_x(res.population[j]), branch, target, cons) for j in (picks or order[:1])]
    d = min(cands, key=lambda c: (c.violation > 0, c.sum_sq))
    return Design(d.x, d.branch, d.phi_offset, d.err, d.phis, d.violation, int(seed), d.failed,
                  {"de_generations": int(res.nit), "de_evaluations": int(res.nfev)})


def polish(x0: np.ndarray, branch: int, target: Target, cons: Constraints) -> Design:
    """Least squares on (design, each target's crank angle) with the constraints as penalty residuals;
    the polished design is kept only if it stays feasible and improves the (refined) error."""
    from scipy.optimize import least_squares

    timing = target.phi is not None
    m = len(target.xy)
    s = target.size
    e0, ph0 = errors(x0[:9], branch, target, x0[9] if timing else 0.0)

    def design(p):
        return p[:9], (p[9] if timing else 0.0), (target.phi + p[9] if timing else p[9:])

    def resid(p):
        x, _, ph = design(p)
        E, _ = coupler_points(x[None], ph[None], branch)
        r = ((E[0] - target.xy) / s).ravel()
        v = violation(x[None], cons, target)[0]
        return np.concatenate([np.nan_to_num(r, nan=10.0), [1e3 * v]])

    def jac(p):
        """Forward differences, batched: the 9 design columns (and the offset) in one call, the crank
        angles' columns (each touches its own target only) in another."""
        x, off, ph = design(p)
        nd = 10 if timing else 9
        h = 1e-7 * np.maximum(1.0, np.abs(p[:nd]))
        X = np.repeat(x[None], nd, axis=0)
        X[np.arange(9), np.arange(9)] += h[:9]
        PH = np.repeat(ph[None], nd, axis=0)
        if timing:
            PH[9] += h[9]
        E0, _ = coupler_points(x[None], ph[None], branch)
        E, _ = coupler_points(X, PH, branch)
        J = np.zeros((2 * m + 1, len(p)))
        J[:2 * m, :nd] = ((E - E0) / s).reshape(nd, -1).T / h
        v0 = violation(x[None], cons, target)[0]
        J[2 * m, :9] = 1e3 * (violation(X[:9], cons, target) - v0) / h[:9]
        if not timing:
            hp = 1e-7 * np.maximum(1.0, np.abs(ph))
            E1, _ = coupler_points(x[None], (ph + hp)[None], branch)
            dE = (E1[0] - E0[0]) / s / hp[:, None]                    # (m, 2)
            J[2 * np.arange(m), 9 + np.arange(m)] = dE[:, 0]
            J[2 * np.arange(m) + 1, 9 + np.arange(m)] = dE[:, 1]
        return np.nan_to_num(J)

    p0 = np.concatenate([x0[:9], [x0[9]] if timing else ph0])
    try:
        r = least_squares(resid, p0, jac=jac, x_scale="jac", max_nfev=300, ftol=1e-13, xtol=1e-13, gtol=1e-13)
        p = r.x
    except (ValueError, np.linalg.LinAlgError):
        p = p0
    x1, off1, _ = design(p)
    e1, ph1 = errors(x1, branch, target, off1)
    v1 = violation(x1[None], cons, target)[0]
    v0 = violation(x0[None, :9], cons, target)[0]
    if np.all(np.isfinite(e1)) and v1 <= v0 and np.sum(e1 ** 2) <= np.sum(e0 ** 2):
        x, off, e, ph, v = x1, off1, e1, ph1, v1
    else:
        x, off, e, ph, v = x0[:9], (x0[9] if timing else 0.0), e0, ph0, v0
    return Design(np.asarray(x, float).copy(), int(branch), float(off), e, ph, float(v), 0,
                  failed_constraint(x, cons, target))


def jobs(target: Target, cons: Constraints, seed: int, restarts: int, generations: int = 300,
         popsize: int = 40, deadline: float | None = None, n_polish: int = 6) -> list[tuple]:
    """The restarts' jobs: both branches, seeds spawned from ``seed`` (the same for any worker count)."""
    seeds = np.random.SeedSequence(seed).generate_state(restarts)
    return [(target, cons, int(sd), (1 if i % 2 == 0 else -1), generations, popsize, deadline, n_polish)
            for i, sd in enumerate(seeds)]


def synthesize(target: Target, cons: Constraints = Constraints(), seed: int = 0, restarts: int = 4,
               generations: int = 300, popsize: int = 40, budget: float | None = None, mapper=map,
               progress=None, n_polish: int = 6) -> list[Design]:
    """Run ``restarts`` seeded restarts through ``mapper`` (``map`` or an executor's) and return the
    designs best first (feasible first, then by sum of squared distances; ties by restart order)."""
    m = len(target.xy)
    if m < 4:
        raise ParameterError(f"{m} target points; path synthesis needs at least 4")
    deadline = None if budget is None else time.time() + float(budget)
    out = []
    for i, d in enumerate(mapper(restart, jobs(target, cons, seed, restarts, generations, popsize, deadline, n_polish))):
        out.append((i, d))
        if progress is not None:
            progress(i + 1, restarts)
    out.sort(key=lambda t: (t[1].violation > 0, t[1].sum_sq, t[0]))
    return [d for _, d in out]


def from_four_bar_rs(p1x, p1y, a, l1, l2, l3, l4, l5, g, stat: str) -> tuple[np.ndarray, int]:
    """A design given in four-bar-rs's parameters (crank pivot p1, ground angle a, ground l1, crank l2,
    coupler l3, follower l4, coupler point at l5 and angle g from the coupler line; stat c1* / c2*) as
    this module's (x, branch): circuit 1 turns B->D counter-clockwise onto B->C, i.e. branch +1."""
    x = np.array([p1x, p1y, a, l1, l2, l3, l4, l5 * math.cos(g), l5 * math.sin(g)], dtype=float)
    return x, (1 if stat.lower().startswith("c1") else -1)
