"""Any Assur group of revolute joints, solved numerically: class III triads, class IV and 6-link groups.

A group is its rigid links (each a set of points), the known (outer) points it is pinned to and the unknown
points it places, dimensioned from one assembled pose. Each link with points ``p0, p1, p2, ...`` (``p0``,
``p1`` its base pair) contributes ``2 m - 3`` equations, written in the link's own frame so that a link
cannot be mirrored:

* ``g = (|p1 - p0|^2 - L^2) / 2 = 0`` (the base length ``L``),
* ``pk - p0 - alpha_k d - beta_k perp(d) = 0`` for every further point (``d = p1 - p0``,
  ``perp(x, y) = (-y, x)``, ``alpha_k``, ``beta_k`` the point's coordinates in the frame spanned by ``d``).

Only the base-length rows are nonlinear. A group has as many equations as unknown coordinates.

Positions: a sequential continuation over a coarse grid of the samples (Newton from the previous node, the
first node from the pose) holds the branch by continuity; then every sample is solved at once by batched
Newton (``np.linalg.solve`` on ``(N, n, n)`` stacks) from the coarse solution interpolated linearly in the
sample index (for long runs through a batched middle level of every 64th sample first, from which one
Newton step per sample reaches rounding). The samples are therefore taken to be a path (a motion in time), as every command produces.

Branch: the sign of ``det(J_u)``, the Jacobian of the equations in the unknown coordinates (for a dyad this
is the side of ``P -> Q`` that ``C`` lies on, the ``branch`` of ``RRR``). It changes only through a singular
pose; a coarse interval over which it changes, a sample whose Newton does not converge or that lands
farther from its interpolated start than the coarse step and the coarse path's bend (a jump to another assembly) is not assembled:
NaN, as the dyads leave where they cannot be assembled.

Rates: exact linear solves with the same Jacobian, ``J_u v_u = -J_k v_k`` and
``J_u a_u = -J_k a_k - (Jdot v)``, where ``Jdot v`` is ``|v1 - v0|^2`` on the base-length rows and zero on
the linear rows.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from analytic._common import ParameterError

NEWTON_STEPS = 12          # most Newton steps per sample: from an interpolated start it takes 2 to 4
NEWTON_TOL = 1e-13         # converged when the largest step is below this fraction of the group's size
RESIDUAL_CONVERGED = 2e-15  # residual at rounding level [fraction of size] (a few eps where coordinates
#                             are of the order of the size; elsewhere the step test ends the iteration)
RESIDUAL_TOL = 1e-10       # a converged sample whose residual exceeds this fraction of size is refused
REFINE = 64                # samples per node of the batched middle level (when N > REFINE * coarse)
BLOCK = 32768              # samples per batched block (bounds the (N, n, n) Jacobians' memory)


@dataclass(frozen=True)
class GeneralGroup:
    """A numerically solved Assur group of revolute joints, dimensioned from an assembled pose.

    Attributes
    ----------
    known, unknown : tuple of str
        The outer points the group is pinned to, and the points it places.
    links : tuple of (str, tuple of str)
        Each link's name and its points, the first two its base pair.
    length2 : ndarray, shape (L,)
        Each link's base length squared [m^2].
    i0, i1 : ndarray of int, shape (L,)
        Each link's base pair, as indices into ``known + unknown``.
    ek, e0, e1 : ndarray of int, shape (E,)
        Each further point on a link, and that link's base pair.
    alpha, beta : ndarray, shape (E,)
        The further points' coordinates in the frame (d, perp(d)) of their link's base pair [-].
    branch : int
        The sign of ``det(J_u)`` at the pose (+1 or -1).
    size : float
        The largest distance between two points of the pose [m] (the scale of the tolerances).
    pose : ndarray, shape (n_points, 2)
        The assembled pose, points in the order ``known + unknown`` [m].
    lin : ndarray, shape (2 E, n)
        The Jacobian's constant rows (see :func:`_structure`).
    """

    known: tuple
    unknown: tuple
    links: tuple
    length2: np.ndarray
    i0: np.ndarray
    i1: np.ndarray
    ek: np.ndarray
    e0: np.ndarray
    e1: np.ndarray
    alpha: np.ndarray
    beta: np.ndarray
    branch: int
    size: float
    pose: np.ndarray
    lin: np.ndarray

    @property
    def n(self) -> int:
        """The number of unknown coordinates (= equations)."""
        return 2 * len(self.unknown)


def make_group(links: Mapping[str, Sequence[str]], known: Sequence[str], unknown: Sequence[str],
               pose: Mapping[str, Sequence[float]], *, where: str = "group") -> GeneralGroup:
    """Build a group from its links, its known and unknown points, and an assembled pose.

    Parameters
    ----------
    links : mapping of str to sequence of str
        Each rigid link's name and the points it carries (two or more).
    known, unknown : sequence of str
        The outer points (given per sample) and the points the group places.
    pose : mapping of str to (x, y)
        Every point's position [m] in one assembled pose (that of the first sample).
    where : str
        Names the group in error messages (e.g. the file and element).

    Raises
    ------
    ParameterError
        A point is missing or on no link, a link has fewer than two points or only known points, the
        equation count differs from the unknown count, or the pose is singular (not an Assur group).
    """
    known, unknown = tuple(known), tuple(unknown)
    names = known + unknown
    if len(set(names)) != len(names):
        raise ParameterError(f"{where}: a point is listed twice among known {known} and unknown {unknown}")
    if not unknown:
        raise ParameterError(f"{where}: the group places no point; list its unknown points")
    index = {p: i for i, p in enumerate(names)}
    for p in names:
        if p not in pose:
            raise ParameterError(f"{where}: the pose has no position for point {p!r}; give its x, y")
    P = np.array([[float(pose[p][0]), float(pose[p][1])] for p in names])
    if not np.all(np.isfinite(P)):
        raise ParameterError(f"{where}: the pose has a non-finite coordinate; give finite x, y")
    on_link = set()
    i0, i1, L2, ek, e0, e1, al, be, link_list = [], [], [], [], [], [], [], [], []
    for name, pts in links.items():
        pts = tuple(pts)
        if len(pts) < 2 or len(set(pts)) != len(pts):
            raise ParameterError(f"{where}: link {name!r} needs two or more distinct points, has {pts}")
        for p in pts:
            if p not in index:
                raise ParameterError(f"{where}: link {name!r} carries {p!r}, which is neither known nor unknown")
        if all(p in known for p in pts):
            raise ParameterError(f"{where}: link {name!r} carries only known points {pts}; it is not part of the group")
        on_link.update(pts)
        a, b = index[pts[0]], index[pts[1]]
        d = P[b] - P[a]
        dd = float(d @ d)
        if dd <= 0.0:
            raise ParameterError(f"{where}: link {name!r}: points {pts[0]!r} and {pts[1]!r} coincide in the pose")
        i0.append(a)
        i1.append(b)
        L2.append(dd)
        for p in pts[2:]:
            r = P[index[p]] - P[a]
            ek.append(index[p])
            e0.append(a)
            e1.append(b)
            al.append(float(r @ d) / dd)
            be.append(float(d[0] * r[1] - d[1] * r[0]) / dd)
        link_list.append((str(name), pts))
    for p in unknown:
        if p not in on_link:
            raise ParameterError(f"{where}: unknown point {p!r} is on no link; add it to a link")
    n_eq = len(i0) + 2 * len(ek)
    if n_eq != 2 * len(unknown):
        raise ParameterError(f"{where}: {n_eq} equations for {2 * len(unknown)} unknown coordinates; "
                             "an Assur group has as many (check the links' points)")
    diff = P[:, None, :] - P[None, :, :]
    size = float(np.sqrt(np.max(np.sum(diff * diff, axis=-1))))
    ia = lambda v: np.asarray(v, dtype=np.intp)  # noqa: E731
    fa = lambda v: np.asarray(v, dtype=float)    # noqa: E731
    arrays = (fa(L2), ia(i0), ia(i1), ia(ek), ia(e0), ia(e1), fa(al), fa(be))
    lin = _structure(len(known), 2 * len(unknown), *arrays[3:])
    g = GeneralGroup(known, unknown, tuple(link_list), *arrays, 1, size, P, lin)
    J = _jac_u(g, P[None])[0]
    det = np.linalg.det(J / size ** (len(i0) / g.n))
    cond = np.linalg.cond(J) if np.isfinite(det) and det != 0.0 else np.inf
    if not np.isfinite(cond) or cond > 1e12:  # 1e12: beyond this a Newton step loses 12 of 16 digits
        raise ParameterError(f"{where}: the pose is singular for links {[n for n, _ in link_list]} "
                             "(a locked or underconstrained group); give another pose or other links")
    return GeneralGroup(known, unknown, tuple(link_list), *arrays, 1 if det > 0 else -1, size, P, lin)


def _perp(d):
    return np.stack((-d[..., 1], d[..., 0]), axis=-1)


def _residual(g: GeneralGroup, P):
    """The equations at points P, shape (N, n_points, 2) -> (N, n)."""
    d = P[:, g.i1] - P[:, g.i0]
    quad = 0.5 * (d[..., 0] * d[..., 0] + d[..., 1] * d[..., 1] - g.length2)
    de = P[:, g.e1] - P[:, g.e0]
    lin = P[:, g.ek] - P[:, g.e0] - g.alpha[:, None] * de - g.beta[:, None] * _perp(de)
    return np.concatenate((quad, lin.reshape(len(P), -1)), axis=1)


def _jvp(g: GeneralGroup, P, V):
    """J(P) V: the equations' derivative along point rates V, both (N, n_points, 2) -> (N, n)."""
    d = P[:, g.i1] - P[:, g.i0]
    dv = V[:, g.i1] - V[:, g.i0]
    quad = d[..., 0] * dv[..., 0] + d[..., 1] * dv[..., 1]
    de = V[:, g.e1] - V[:, g.e0]
    lin = V[:, g.ek] - V[:, g.e0] - g.alpha[:, None] * de - g.beta[:, None] * _perp(de)
    return np.concatenate((quad, lin.reshape(len(P), -1)), axis=1)


def _jdot_v(g: GeneralGroup, V):
    """(dJ/dt) v: |v1 - v0|^2 on the base-length rows, zero on the linear rows, (N, n)."""
    dv = V[:, g.i1] - V[:, g.i0]
    out = np.zeros((len(V), g.n))
    out[:, :len(g.i0)] = dv[..., 0] * dv[..., 0] + dv[..., 1] * dv[..., 1]
    return out


def _structure(nk, n, ek, e0, e1, alpha, beta):
    """The Jacobian's linear rows in the unknown coordinates, shape (2 E, n), which are constant."""
    lin = np.zeros((2 * len(ek), n))
    eye = np.eye(2)
    perp = np.array([[0.0, -1.0], [1.0, 0.0]])
    for e, (k, a, b) in enumerate(zip(ek, e0, e1)):
        M1 = -alpha[e] * eye - beta[e] * perp       # d(row)/d(p1)
        for idx, M in ((k, eye), (a, -eye - M1), (b, M1)):
            if idx >= nk:
                lin[2 * e:2 * e + 2, 2 * (idx - nk):2 * (idx - nk) + 2] += M
    return lin


def _jac_u(g: GeneralGroup, P):
    """J_u: the equations' Jacobian in the unknown coordinates, (N, n, n).

    Built entry by entry in an (n, n, N) array (each entry a contiguous run over the samples) and returned
    as its (N, n, n) view, which ``np.linalg.solve`` reads through its strides.
    """
    nk, nq = len(g.known), len(g.i0)
    J = np.empty((g.n, g.n, len(P)))
    J[nq:] = g.lin[:, :, None]
    J[:nq] = 0.0
    for row, (a, b) in enumerate(zip(g.i0, g.i1)):
        dx, dy = P[:, b, 0] - P[:, a, 0], P[:, b, 1] - P[:, a, 1]
        if b >= nk:
            J[row, 2 * (b - nk)] += dx
            J[row, 2 * (b - nk) + 1] += dy
        if a >= nk:
            J[row, 2 * (a - nk)] -= dx
            J[row, 2 * (a - nk) + 1] -= dy
    return J.transpose(2, 0, 1)


def _solve(J, rhs):
    """Batched J x = rhs; samples whose J is singular get NaN instead of raising."""
    try:
        return np.linalg.solve(J, rhs[..., None])[..., 0]
    except np.linalg.LinAlgError:
        det = np.linalg.det(J)
        bad = ~(np.abs(det) > 0.0)
        J = J.copy()
        J[bad] = np.eye(J.shape[-1])
        x = np.linalg.solve(J, rhs[..., None])[..., 0]
        x[bad] = np.nan
        return x


def _newton(g: GeneralGroup, Pk, x):
    """Batched Newton on the unknown coordinates x (N, n) with known points Pk (N, nk, 2).

    A sample has converged when its residual is at rounding level (base-length rows divided by the base
    length, so every row is in [m]) or its last step is below ``NEWTON_TOL`` of size; only the samples not
    yet converged are iterated. Returns the solution and a mask of the samples that converged.
    """
    N = len(x)
    x = np.array(x, dtype=float)
    inv_len = 1.0 / np.sqrt(g.length2)
    done = np.zeros(N, dtype=bool)
    act = np.arange(N)
    step = np.full(N, np.inf)
    with np.errstate(all="ignore"):
        for it in range(NEWTON_STEPS + 1):
            P = np.concatenate((Pk[act], x[act].reshape(len(act), -1, 2)), axis=1)
            F = _residual(g, P)
            res = np.max(np.abs(np.concatenate((F[:, :len(g.i0)] * inv_len, F[:, len(g.i0):]), axis=1)), axis=1)
            conv = (res <= RESIDUAL_CONVERGED * g.size) | (step[act] <= NEWTON_TOL * g.size)
            done[act] = conv & (res <= RESIDUAL_TOL * g.size)
            keep = ~conv & np.isfinite(res)
            if it == NEWTON_STEPS or not keep.any():
                break
            act, P, F = act[keep], P[keep], F[keep]
            dx = _solve(_jac_u(g, P), -F)
            x[act] += dx
            step[act] = np.max(np.abs(dx), axis=1)
    return x, done


@dataclass(frozen=True)
class GroupSolution:
    """The group's points and links over N samples.

    Attributes
    ----------
    points : dict of str to tuple of 6 ndarrays, each shape (N,)
        Each unknown point's ``(x, y, vx, vy, ax, ay)`` [m, m/s, m/s^2]; NaN where not assembled.
    links : dict of str to tuple of 4 ndarrays, each shape (N,)
        Each link's ``(cos, sin, omega, alpha)`` of its base direction ``p0 -> p1`` [-, rad/s, rad/s^2].
    assembled : ndarray of bool, shape (N,)
        True where the group is assembled on its branch.
    branch : int
        The branch held: the sign of ``det(J_u)`` at the pose.
    """

    points: dict
    links: dict
    assembled: np.ndarray
    branch: int


def _coarse_path(g: GeneralGroup, Pk, nodes, x):
    """Sequential continuation over the coarse nodes from x (1, n) near the first: x at each node, and
    whether it holds the branch."""
    xs = np.full((len(nodes), g.n), np.nan)
    good = np.zeros(len(nodes), dtype=bool)
    with np.errstate(all="ignore"):
        for j, i in enumerate(nodes):
            y, ok = _newton(g, Pk[i:i + 1], x)
            if ok[0]:
                P = np.concatenate((Pk[i], y.reshape(-1, 2)))[None]
                ok[0] = np.sign(np.linalg.det(_jac_u(g, P)[0])) == g.branch
            if ok[0]:
                xs[j], good[j], x = y[0], True, y
    return xs, good


def _from_nodes(g: GeneralGroup, Pk, nodes, xs, good, idx):
    """Batched Newton at the sample indices idx from the solution xs at the nodes (sorted sample indices),
    interpolated linearly in the sample index; NaN and False where it fails or jumps."""
    nk = len(g.known)
    # the largest second difference of the node path next to each interval (zero for fewer than 3 nodes)
    dd = np.zeros(len(nodes) + 1)
    if len(nodes) >= 3:
        dd[1:-2] = np.nan_to_num(np.max(np.abs(xs[2:] - 2 * xs[1:-1] + xs[:-2]), axis=1), nan=0.0)
    bend = np.maximum.reduce([dd[:-1], dd[1:], np.r_[dd[2:], 0.0]])
    j = np.clip(np.searchsorted(nodes, idx, side="right") - 1, 0, max(len(nodes) - 2, 0))
    j1 = np.minimum(j + 1, len(nodes) - 1)
    span = np.maximum(nodes[j1] - nodes[j], 1)
    t = ((idx - nodes[j]) / span)[:, None]
    usable = good[j] & good[j1]
    with np.errstate(all="ignore"):
        x0 = (1.0 - t) * xs[j] + t * xs[j1]
        hop = np.max(np.abs(xs[j1] - xs[j]), axis=1)
        x, ok = _newton(g, Pk[idx], np.where(usable[:, None], x0, g.pose[nk:].ravel()))
        # a jump: farther from the interpolated start than the two nodes are apart plus the nodes' second
        # difference (a smooth path leaves the chord by about 1/8 of it, also where it turns back);
        # 1e-9 of size: rounding where the nodes coincide
        ok &= usable & (np.max(np.abs(x - x0), axis=1) <= hop + bend[j] + 1e-9 * g.size)
    x[~ok] = np.nan
    return x, ok


def solve_group(g: GeneralGroup, known: Mapping[str, Sequence[np.ndarray]], *, coarse: int = 512,
                start: Mapping[str, Sequence[float]] | None = None) -> GroupSolution:
    """Positions, velocities and accelerations of the group's unknown points over N samples.

    Parameters
    ----------
    g : GeneralGroup
        The group; its pose is the assembly at the first sample.
    known : mapping of str to (x, y, vx, vy, ax, ay)
        Each known point's arrays, each shape (N,) (or scalars for a fixed point) [m, m/s, m/s^2].
    coarse : int
        The number of nodes of the sequential continuation (every sample when N <= coarse).
    start : mapping of str to (x, y), optional
        The unknown points near the first sample [m], on the group's branch: the previous run's last
        sample when a long motion is solved in blocks (default: the group's pose).

    Returns
    -------
    GroupSolution
    """
    arrays = [np.broadcast_arrays(*[np.asarray(c, dtype=float) for c in known[p]]) for p in g.known]
    N = max(np.size(a[0]) for a in arrays)
    K = np.empty((3, N, len(g.known), 2))
    for j, a in enumerate(arrays):
        for c in range(6):
            K[c // 2, :, j, c % 2] = a[c]
    nodes = np.unique(np.r_[np.linspace(0, N - 1, min(N, coarse)).round().astype(np.intp), N - 1])
    if start is None:
        x_first = g.pose[len(g.known):].reshape(1, -1)
    else:
        x_first = np.array([[float(c) for p in g.unknown for c in start[p][:2]]])
    xs, good = _coarse_path(g, K[0], nodes, x_first)
    if N > REFINE * len(nodes):
        # a batched middle level: from it the interpolation is close enough for one Newton step per sample
        mid = np.unique(np.r_[np.arange(0, N, REFINE), N - 1])
        xs, good = _from_nodes(g, K[0], nodes, xs, good, mid)
        nodes = mid
    nk, nu = len(g.known), len(g.unknown)
    out = np.full((3, N, nu, 2), np.nan)
    assembled = np.zeros(N, dtype=bool)
    for s in range(0, N, BLOCK):
        idx = np.arange(s, min(N, s + BLOCK))
        x, ok = _from_nodes(g, K[0], nodes, xs, good, idx)
        with np.errstate(all="ignore"):
            P = np.concatenate((K[0, idx], x.reshape(-1, nu, 2)), axis=1)
            Ju = _jac_u(g, P)
            V = np.concatenate((K[1, idx], np.zeros((len(idx), nu, 2))), axis=1)
            v = _solve(Ju, -_jvp(g, P, V))
            V[:, nk:] = v.reshape(-1, nu, 2)
            A = np.concatenate((K[2, idx], np.zeros((len(idx), nu, 2))), axis=1)
            a = _solve(Ju, -_jvp(g, P, A) - _jdot_v(g, V))
        out[0, idx] = x.reshape(-1, nu, 2)
        out[1, idx] = v.reshape(-1, nu, 2)
        out[2, idx] = a.reshape(-1, nu, 2)
        assembled[idx] = ok
    out[:, ~assembled] = np.nan
    points = {p: (out[0, :, i, 0], out[0, :, i, 1], out[1, :, i, 0], out[1, :, i, 1], out[2, :, i, 0],
                  out[2, :, i, 1]) for i, p in enumerate(g.unknown)}
    return GroupSolution(points, _link_rates(g, K, out), assembled, g.branch)


def _link_rates(g: GeneralGroup, K, out):
    """Each link's (cos, sin, omega, alpha) from its base pair's positions and rates."""
    nk = len(g.known)

    def at(i, k):
        return K[k, :, i] if i < nk else out[k, :, i - nk]

    links = {}
    for (name, _), a, b in zip(g.links, g.i0, g.i1):
        d, dv, da = (at(b, k) - at(a, k) for k in range(3))
        dx, dy = d[:, 0], d[:, 1]
        L2 = dx * dx + dy * dy
        L = np.sqrt(L2)
        links[name] = (dx / L, dy / L, (dx * dv[:, 1] - dy * dv[:, 0]) / L2, (dx * da[:, 1] - dy * da[:, 0]) / L2)
    return links
