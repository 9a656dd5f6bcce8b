"""Any Assur group of revolute joints, solved numerically: class III triads, class IV and 6-link groups.

A group is its rigid links (each a set of points), the known (outer) points it is pinned to and the unknown
points it places, dimensioned from one assembled pose. Each link with points ``p0, p1, p2, ...`` (``p0``,
``p1`` its base pair) contributes ``2 m - 3`` equations, written in the link's own frame so that a link
cannot be mirrored:

* ``g = (|p1 - p0|^2 - L^2) / (2 L) = 0`` (the base length ``L``; a length, in m),
* ``pk - p0 - alpha_k d - beta_k perp(d) = 0`` for every further point (``d = p1 - p0``,
  ``perp(x, y) = (-y, x)``, ``alpha_k``, ``beta_k`` the point's coordinates in the frame spanned by ``d``).

A group has as many equations as unknown coordinates (``n``). The further points' rows are linear with
constant coefficients, so they are eliminated once, when the group is built: every solution is
``x = M k + N z`` (``k`` the known points' coordinates, ``N`` an orthonormal basis of the rows' null space,
``M`` a particular solution), and only the base-length rows remain, one per link, in the ``L`` reduced
coordinates ``z`` [m]. Every link's base vector is then affine in them: ``d = C k + E z``.

Positions, along a path (the samples are a motion in time, as every command produces):

1. **nodes**, sequentially: Newton from the previous node (the first from the pose or from where the
   previous block ended); nodes are placed every 1/16 of the group's size of travel of the known points,
   refined by halving where the solution moves far between two nodes and, down to adjacent samples, where
   the group stops or starts assembling;
2. **every 64th sample**, batched, by Newton from the nodes' solutions interpolated linearly in the sample
   index;
3. **every sample**, batched, from those, by Newton (one or two steps reach rounding).

Branch: the sign of ``det(J_u)``, the Jacobian of all the equations in the unknown coordinates (for a dyad:
which side of ``P -> Q`` the point lies on, the ``branch`` of ``RRR``); it equals the sign of the reduced
Jacobian's determinant times a constant, and it changes only through a singular pose. A sample is not
assembled (NaN, as the dyads leave where they cannot be assembled) where Newton does not converge, where the
determinant has the other sign (the path went through a singular pose), or where the solution lies farther
from its interpolated start than the nodes around it allow (a jump to another assembly). The known points
jumping by more than a quarter of the size between two adjacent samples breaks the path there.

Rates: exact linear solves with the same reduced Jacobian ``J`` (rows ``d^T E / L``):
``J vz = -d.(C vk) / L`` and ``J az = -(|dv|^2 + d.(C ak)) / L`` with ``dv = C vk + E vz``.

Every batched linear solve is an LU factorisation with partial pivoting written over the samples (arrays
(L, L, N), each entry a contiguous run of samples), which costs a fraction of a LAPACK call per sample for
these small systems; the determinant comes with it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from analytic._common import ParameterError

NEWTON_STEPS = 12          # most Newton steps per sample: from an interpolated start it takes 1 or 2
NEWTON_TOL = 1e-13         # converged when the largest step is below this fraction of the group's size
RESIDUAL_CONVERGED = 4e-15  # residual at rounding level [fraction of size]: the rows are lengths of the
#                             order of the size, each rounded to ~eps times a few terms
RESIDUAL_TOL = 1e-10       # a sample whose residual exceeds this fraction of size is refused
SINGULAR_COND = 1e12       # a pose whose reduced Jacobian's condition number exceeds this is singular: a
#                            Newton step there loses 12 of 16 digits
NODE_TRAVEL = 1 / 16       # nodes every this fraction of the size of the known points' travel
HOP = 1 / 4                # a node farther than this fraction of size from the previous one is refined
JUMP = 1 / 4               # the known points moving farther than this fraction of size between two adjacent
#                            samples break the path (the kinematics fills in inputs far apart first)
REFINE = 64                # samples per node of the batched middle level
BLOCK = 16384              # samples per batched block (bounds the (L, L, N) Jacobians' memory)
GROWTH = 16.0              # largest multiplier accepted in an LU without pivot search (partial pivoting: 1)


@dataclass(frozen=True)
class GeneralGroup:
    """A numerically solved Assur group of revolute joints, dimensioned from an assembled pose.

    Attributes
    ----------
    known, unknown : tuple of str
        The outer points the group is pinned to, and the points it places.
    links : tuple of (str, tuple of str)
        Each link's name and its points, the first two its base pair.
    length : ndarray, shape (L,)
        Each link's base length [m].
    M : ndarray, shape (n, 2 nk)
        Unknown coordinates of the particular solution of the linear rows, from the known coordinates.
    N : ndarray, shape (n, L)
        Orthonormal basis of the linear rows' null space: ``x = M k + N z``.
    Cx, Cy : ndarray, shape (L, 2 nk)
        The links' base vectors' x and y components from the known coordinates ...
    Ex, Ey : ndarray, shape (L, L)
        ... and from the reduced coordinates: ``d = C k + E z``.
    z0 : ndarray, shape (L,)
        The pose's reduced coordinates [m].
    sign : int
        The sign of the reduced Jacobian's determinant on the group's branch.
    branch : int
        The sign of ``det(J_u)`` at the pose (+1 or -1): the branch reported.
    size : float
        The largest distance between two points of the pose [m] (the scale of the tolerances).
    pose : ndarray, shape (n_points, 2)
        The assembled pose, points in the order ``known + unknown`` [m].
    """

    known: tuple
    unknown: tuple
    links: tuple
    length: np.ndarray
    M: np.ndarray
    N: np.ndarray
    Cx: np.ndarray
    Cy: np.ndarray
    Ex: np.ndarray
    Ey: np.ndarray
    z0: np.ndarray
    sign: int
    branch: int
    size: float
    pose: np.ndarray

    @property
    def n(self) -> int:
        """The number of unknown coordinates (= equations)."""
        return 2 * len(self.unknown)

    @property
    def Jx(self) -> np.ndarray:
        """Ex / L: row l of the reduced Jacobian is ``dx_l Jx[l] + dy_l Jy[l]``."""
        return self.Ex / self.length[:, None]

    @property
    def Jy(self) -> np.ndarray:
        return self.Ey / self.length[:, None]

    @property
    def dof(self) -> int:
        """The number of reduced coordinates (= links = base-length rows)."""
        return len(self.links)


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
    nk, n = len(known), 2 * len(unknown)
    on_link = set()
    base, further, link_list = [], [], []
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
        base.append((a, b, dd))
        for p in pts[2:]:
            r = P[index[p]] - P[a]
            further.append((index[p], a, b, float(r @ d) / dd, float(d[0] * r[1] - d[1] * r[0]) / dd))
        link_list.append((str(name), pts))
    for p in unknown:
        if p not in on_link:
            raise ParameterError(f"{where}: unknown point {p!r} is on no link; add it to a link")
    n_eq = len(base) + 2 * len(further)
    if n_eq != n:
        raise ParameterError(f"{where}: not an Assur group: {n_eq} equations for {n} unknowns "
                             "(each link of m points gives 2 m - 3; check the links' points)")
    # the linear rows R [p] = 0 over every point's coordinates (known first), split into known and unknown
    R = np.zeros((2 * len(further), 2 * len(names)))
    eye, perp = np.eye(2), np.array([[0.0, -1.0], [1.0, 0.0]])
    for e, (k, a, b, al, be) in enumerate(further):
        M1 = al * eye + be * perp
        for idx, blk in ((k, eye), (a, M1 - eye), (b, -M1)):
            R[2 * e:2 * e + 2, 2 * idx:2 * idx + 2] += blk
    Rk, Ru = R[:, :2 * nk], R[:, 2 * nk:]
    L = len(base)
    if len(further):
        U, S, Vt = np.linalg.svd(Ru)
        if S[-1] <= 1e-12 * S[0]:       # rank-deficient rigid-point rows: rounding level of the SVD
            raise ParameterError(f"{where}: the links' further points do not fix them (a point given twice "
                                 "on one frame?); check the links' points")
        N = Vt[len(S):].T
        M = -(Vt[:len(S)].T / S) @ (U.T @ Rk)
    else:
        N, M = np.eye(n), np.zeros((n, 2 * nk))
    # the links' base vectors: selectors over (known, unknown) coordinates, then through x = M k + N z
    Sel = np.zeros((2 * L, 2 * len(names)))
    for i, (a, b, _) in enumerate(base):
        for c in (0, 1):
            Sel[c * L + i, 2 * b + c] += 1.0
            Sel[c * L + i, 2 * a + c] -= 1.0
    C = Sel[:, :2 * nk] + Sel[:, 2 * nk:] @ M
    E = Sel[:, 2 * nk:] @ N
    length = np.sqrt(np.array([dd for _, _, dd in base]))
    k_pose = P[:nk].ravel()
    z0 = N.T @ (P[nk:].ravel() - M @ k_pose)
    diff = P[:, None, :] - P[None, :, :]
    size = float(np.sqrt(np.max(np.sum(diff * diff, axis=-1))))
    g = GeneralGroup(known, unknown, tuple(link_list), length, M, N, C[:L], C[L:], E[:L], E[L:], z0, 1, 1,
                     size, P)
    J = _jac1(g, k_pose, z0)
    cond = np.linalg.cond(J) if np.all(np.isfinite(J)) else np.inf
    if not np.isfinite(cond) or cond > SINGULAR_COND:
        raise ParameterError(f"{where}: the pose is singular for links {[name for name, _ in link_list]} "
                             "(a locked or underconstrained group, or a group folded at a dead point); "
                             "give another pose or other links")
    sign = 1 if np.linalg.det(J) > 0 else -1
    # the branch reported: sign of det of every equation's Jacobian in the unknown coordinates (the rows
    # as the module docstring writes them: base lengths / L, then the further points' rows)
    Ju = np.zeros((n, n))
    for i, (a, b, _) in enumerate(base):
        d = (P[b] - P[a]) / length[i]
        if b >= nk:
            Ju[i, 2 * (b - nk):2 * (b - nk) + 2] += d
        if a >= nk:
            Ju[i, 2 * (a - nk):2 * (a - nk) + 2] -= d
    Ju[L:] = Ru
    branch = 1 if np.linalg.det(Ju) > 0 else -1
    return GeneralGroup(known, unknown, tuple(link_list), length, M, N, C[:L], C[L:], E[:L], E[L:], z0, sign,
                        branch, size, P)


# ------------------------------------------------------------------------------- one sample (nodes)
def _base1(g: GeneralGroup, k, z):
    return g.Cx @ k + g.Ex @ z, g.Cy @ k + g.Ey @ z


def _jac1(g: GeneralGroup, k, z):
    dx, dy = _base1(g, k, z)
    return (dx[:, None] * g.Ex + dy[:, None] * g.Ey) / g.length[:, None]


def _newton1(g: GeneralGroup, k, z):
    """Newton for one sample (known coordinates k) from z: (z, converged on the branch)."""
    z = np.array(z, dtype=float)
    step = np.inf
    with np.errstate(all="ignore"):
        for it in range(NEWTON_STEPS + 1):
            dx, dy = _base1(g, k, z)
            F = (dx * dx + dy * dy - g.length * g.length) / (2.0 * g.length)
            res = float(np.max(np.abs(F)))
            if not np.isfinite(res):
                return z, False
            if res <= RESIDUAL_CONVERGED * g.size or step <= NEWTON_TOL * g.size:
                J = (dx[:, None] * g.Ex + dy[:, None] * g.Ey) / g.length[:, None]
                det = np.linalg.det(J)
                return z, bool(res <= RESIDUAL_TOL * g.size and np.isfinite(det) and np.sign(det) == g.sign)
            if it == NEWTON_STEPS:
                return z, False
            J = (dx[:, None] * g.Ex + dy[:, None] * g.Ey) / g.length[:, None]
            try:
                dz = np.linalg.solve(J, F)
            except np.linalg.LinAlgError:
                return z, False
            z -= dz
            step = float(np.max(np.abs(dz)))
    return z, False


@dataclass(frozen=True)
class _Path:
    """The known points along a block: their coordinates K (2 nk, N), the travel [m] from the first sample
    (the largest distance any known point has moved, summed over the samples) and where they jump."""

    K: np.ndarray
    travel: np.ndarray
    jump: np.ndarray

    @staticmethod
    def of(g: GeneralGroup, K) -> "_Path":
        n = K.shape[1]
        P = K.reshape(-1, 2, n)
        step = np.sqrt(np.max(np.sum(np.diff(P, axis=2) ** 2, axis=1), axis=0)) if n > 1 else np.zeros(0)
        return _Path(K, np.r_[0.0, np.cumsum(step)], np.r_[False, step > JUMP * g.size])


def _walk(g: GeneralGroup, path: _Path, a: int, za, b: int) -> list:
    """Continue from sample a (solved, za) to sample b (either side of a), halving the step where Newton
    fails or the solution moves far: the nodes decided, ``[(index, z, ok), ...]`` in walking order, b last
    unless a node before it failed (then that one is last)."""
    z, ok = _newton1(g, path.K[:, b], za)
    far = (abs(path.travel[b] - path.travel[a]) > 2 * NODE_TRAVEL * g.size
           or float(np.max(np.abs(z - za))) > HOP * g.size)
    if ok and not far:
        return [(b, z, True)]
    if abs(b - a) == 1:                      # adjacent samples: nothing to halve
        ok = ok and not path.jump[max(a, b)]
        return [(b, z, ok)]
    m = (a + b) // 2
    first = _walk(g, path, a, za, m)
    if not first[-1][2]:
        return first
    return first + _walk(g, path, m, first[-1][1], b)


def _nodes(g: GeneralGroup, path: _Path, z_start):
    """Sequential continuation over nodes along the block (module docstring, step 1): the node indices
    (sorted), their reduced coordinates (n_nodes, L; NaN where not assembled) and whether each is."""
    n = path.K.shape[1]
    marks = np.floor(path.travel / (NODE_TRAVEL * g.size))
    cand = np.flatnonzero(np.r_[True, marks[1:] != marks[:-1]] | path.jump)
    cand = np.unique(np.r_[cand, n - 1])
    found: dict[int, tuple] = {}
    z, ok = _newton1(g, path.K[:, 0], z_start)
    found[0] = (z, ok)
    z_good, i_good = (z, 0) if ok else (np.asarray(z_start, dtype=float), None)
    last_bad = None if ok else 0
    for c in cand[1:]:
        c = int(c)
        if last_bad is None:                                   # on the branch: continue
            decided = _walk(g, path, i_good, z_good, c)
            for i, z, ok in decided:
                found[i] = (z, ok)
            i, z, ok = decided[-1]
            if ok:
                z_good, i_good = z, i
            else:
                last_bad = i
            continue
        z, ok = _newton1(g, path.K[:, c], z_good)             # after a gap: back on the branch here?
        if not ok:
            found[c] = (z, False)
            last_bad = c
            continue
        found[c] = (z, True)
        if c - last_bad > 1:                                   # where it starts again: back from here
            for i, zb, okb in _walk(g, path, c, z, last_bad + 1):
                found[i] = (zb, okb)
        z_good, i_good, last_bad = z, c, None
    idx = np.array(sorted(found), dtype=np.intp)
    good = np.array([found[i][1] for i in idx], dtype=bool)
    zs = np.array([found[i][0] for i in idx], dtype=float).reshape(len(idx), g.dof)
    zs[~good] = np.nan
    return idx, zs, good


# ---------------------------------------------------------------------- many samples (batched)
def _lu_pivoting(A):
    """LU with partial pivoting of A (n, n, m), in place: (LU, perm, det) as :func:`lu` returns them."""
    n, _, m = A.shape
    perm = np.empty((n, m), dtype=np.intp)
    perm[:] = np.arange(n)[:, None]
    det = np.ones(m)
    for k in range(n):
        if k < n - 1:
            p = np.argmax(np.abs(A[k:, k]), axis=0) + k
            sw = np.flatnonzero(p != k)
            if sw.size:
                pk = p[sw]
                row = A[k][:, sw]                              # (n, m'): a copy (advanced index)
                A[k][:, sw] = A[pk, :, sw].T
                A[pk, :, sw] = row.T
                tmp = perm[pk, sw]
                perm[pk, sw] = perm[k, sw]
                perm[k, sw] = tmp
                det[sw] = -det[sw]
        piv = A[k, k]
        det *= piv
        if k < n - 1:
            f = A[k + 1:, k] / piv
            A[k + 1:, k] = f
            A[k + 1:, k + 1:] -= f[:, None, :] * A[k, None, k + 1:]
    return A, perm, det


def parity(perm) -> np.ndarray:
    """+1 or -1 per column of perm (n, m): the sign of each permutation."""
    n = perm.shape[0]
    inv = np.zeros(perm.shape[1], dtype=np.intp)
    for i in range(n):
        for j in range(i + 1, n):
            inv += perm[i] > perm[j]
    return 1.0 - 2.0 * (inv % 2)


def lu(A, order=None):
    """LU factorisation of many small matrices at once.

    Parameters
    ----------
    A : ndarray, shape (n, n, N)
        N matrices, entry (i, j) of matrix s at ``A[i, j, s]`` (overwritten).
    order : ndarray of int, shape (n, N), optional
        A row order per matrix known to pivot well (that of a nearby matrix): the rows are taken in this
        order and eliminated without searching for pivots, which is several times faster; a matrix whose
        multipliers then exceed ``GROWTH`` is factorised again with partial pivoting. None: partial pivoting.

    Returns
    -------
    (LU, perm, det)
        ``LU`` (unit lower factor below the diagonal, upper factor on and above it), ``perm`` (n, N): row i
        of the factors is row ``perm[i]`` of the matrix, and ``det`` (N,) the determinants. A singular
        matrix gives a zero or non-finite pivot, and NaN or inf in what is solved with it.
    """
    if order is None:
        return _lu_pivoting(A)
    n, _, m = A.shape
    A0 = A
    if (order == order[:, :1]).all():          # one order for every matrix (the usual case): a row copy
        order = order[:, 0]
        A = A[order]
        det = np.full(m, parity(order[:, None])[0])
    else:
        A = np.take_along_axis(A, order[:, None, :], axis=0)
        det = parity(order)
    growth = np.zeros(m)
    for k in range(n):
        piv = A[k, k]
        det *= piv
        if k < n - 1:
            f = A[k + 1:, k] / piv
            A[k + 1:, k] = f
            np.maximum(growth, np.max(np.abs(f), axis=0), out=growth)
            A[k + 1:, k + 1:] -= f[:, None, :] * A[k, None, k + 1:]
    perm = order
    redo = np.flatnonzero(~(growth <= GROWTH))
    if redo.size:
        LU, p, d = _lu_pivoting(A0[:, :, redo])
        A[:, :, redo], det[redo] = LU, d
        perm = np.array(np.broadcast_to(order.reshape(n, -1), (n, m)))
        perm[:, redo] = p
    return A, perm, det


def lu_solve(LU, perm, b):
    """Solve with :func:`lu`'s factors: b (n, N) -> x (n, N) (``perm`` (n, N), or (n,) for one order)."""
    n = LU.shape[0]
    y = b[perm] if perm.ndim == 1 else np.take_along_axis(b, perm, axis=0)
    for i in range(1, n):
        y[i] -= np.sum(LU[i, :i] * y[:i], axis=0)
    for i in range(n - 1, -1, -1):
        if i < n - 1:
            y[i] -= np.sum(LU[i, i + 1:] * y[i + 1:], axis=0)
        y[i] /= LU[i, i]
    return y


def _jacobian(g: GeneralGroup, dx, dy):
    """The reduced Jacobian (L, L, N) from the base vectors' components (L, N)."""
    jx, jy = g.Jx, g.Jy
    J = dx[:, None, :] * jx[:, :, None]
    J += dy[:, None, :] * jy[:, :, None]
    return J


def _newton(g: GeneralGroup, Bx, By, z, order):
    """Batched Newton on the reduced coordinates z (L, m), the known points' part of the base vectors
    Bx, By (L, m) given (``order``: see :func:`lu`). Only the samples not yet converged are iterated.
    Returns z and whether each sample converged (residual at rounding level, or its last step below
    NEWTON_TOL of size)."""
    m = z.shape[1]
    z = np.array(z, dtype=float)
    done = np.zeros(m, dtype=bool)
    act = None                                  # None: every sample (no copies)
    step = np.full(m, np.inf)
    inv2 = 0.5 / g.length[:, None]
    L2 = (g.length * g.length)[:, None]
    with np.errstate(all="ignore"):
        for it in range(NEWTON_STEPS + 1):
            if act is None:
                za, bx, by, st, od = z, Bx, By, step, order
            else:
                za, bx, by, st = z[:, act], Bx[:, act], By[:, act], step[act]
                od = None if order is None else order[:, act]
            dx = g.Ex @ za
            dx += bx
            dy = g.Ey @ za
            dy += by
            F = dx * dx
            F += dy * dy
            F -= L2
            F *= inv2
            res = np.max(np.abs(F), axis=0)
            conv = (res <= RESIDUAL_CONVERGED * g.size) | (st <= NEWTON_TOL * g.size)
            ok = conv & (res <= RESIDUAL_TOL * g.size)
            if act is None:
                done[:] = ok
            else:
                done[act] = ok
            keep = ~conv & np.isfinite(res)
            if it == NEWTON_STEPS or not keep.any():
                break
            if not keep.all():
                sel = np.flatnonzero(keep)
                act = sel if act is None else act[sel]
                dx, dy, F = dx[:, sel], dy[:, sel], F[:, sel]
                od = None if od is None else od[:, sel]
            LU, perm, _ = lu(_jacobian(g, dx, dy), od)
            dz = lu_solve(LU, perm, F)
            if act is None:
                z -= dz
                step = np.max(np.abs(dz), axis=0)
            else:
                z[:, act] -= dz
                step[act] = np.max(np.abs(dz), axis=0)
    return z, done


def _finish(g: GeneralGroup, K3, z, order, rates: bool):
    """At the converged z (L, m): one more Newton correction with the Jacobian there, its determinant's
    sign against the branch, and (``rates``) the velocities and accelerations.

    K3: known coordinates, velocities and accelerations (3, 2 nk, m). Returns z, the on-branch mask, the
    row order of the factorisation, and (``rates``) (vz, az, (D, dD, ddD)) with the links' base vectors and
    their rates, each a pair (x, y) of (L, m)."""
    with np.errstate(all="ignore"):
        Bx, By = g.Cx @ K3[0], g.Cy @ K3[0]
        dx = Bx + g.Ex @ z
        dy = By + g.Ey @ z
        F = (dx * dx + dy * dy - (g.length * g.length)[:, None]) * (0.5 / g.length[:, None])
        LU, perm, det = lu(_jacobian(g, dx, dy), order)
        on = np.isfinite(det) & (np.sign(det) == g.sign)
        if not rates:
            return z - lu_solve(LU, perm, F), on, perm, None
        inv = 1.0 / g.length[:, None]
        vBx, vBy = g.Cx @ K3[1], g.Cy @ K3[1]
        aBx, aBy = g.Cx @ K3[2], g.Cy @ K3[2]
        vz = lu_solve(LU, perm, -(dx * vBx + dy * vBy) * inv)
        vx = vBx + g.Ex @ vz
        vy = vBy + g.Ey @ vz
        az = lu_solve(LU, perm, -(vx * vx + vy * vy + dx * aBx + dy * aBy) * inv)
        ax = aBx + g.Ex @ az
        ay = aBy + g.Ey @ az
        z = z - lu_solve(LU, perm, F)
        dx = Bx + g.Ex @ z                     # the base vectors where the points are
        dy = By + g.Ey @ z
    return z, on, perm, (vz, az, ((dx, dy), (vx, vy), (ax, ay)))


@dataclass(frozen=True)
class _Nodes:
    """Solved samples along the path: indices (sorted), reduced coordinates (n_nodes, L; NaN where not
    assembled), whether each is assembled, and the row order its Jacobian pivots in (L, n_nodes)."""

    index: np.ndarray
    z: np.ndarray
    good: np.ndarray
    order: np.ndarray

    def merged(self, other: "_Nodes") -> "_Nodes":
        idx = np.r_[self.index, other.index]
        k = np.argsort(idx, kind="stable")
        return _Nodes(idx[k], np.r_[self.z, other.z][k], np.r_[self.good, other.good][k],
                      np.c_[self.order, other.order][:, k])


def _interpolated(nodes: _Nodes, idx):
    """The start of every sample in idx: the nodes' solutions interpolated linearly in the sample index
    (L, m); whether the nodes around it hold the branch; how far a solution may lie from its start (the
    nodes' distance plus their path's bend); and the row order of the node before it."""
    zs, good, ix = nodes.z, nodes.good, nodes.index
    dd = np.zeros(len(ix) + 1)
    if len(ix) >= 3:
        dd[1:-2] = np.nan_to_num(np.max(np.abs(zs[2:] - 2 * zs[1:-1] + zs[:-2]), axis=1), nan=0.0)
    bend = np.maximum.reduce([dd[:-1], dd[1:], np.r_[dd[2:], 0.0]])
    j = np.clip(np.searchsorted(ix, idx, side="right") - 1, 0, max(len(ix) - 2, 0))
    j1 = np.minimum(j + 1, len(ix) - 1)
    span = np.maximum(ix[j1] - ix[j], 1)
    t = (idx - ix[j]) / span
    zt = zs.T
    with np.errstate(all="ignore"):
        a, b = zt[:, j], zt[:, j1]
        z0 = np.where(t <= 0.0, a, np.where(t >= 1.0, b, a + t * (b - a)))
        hop = np.nan_to_num(np.max(np.abs(b - a), axis=0), nan=0.0)
    usable = np.where(t <= 0.0, good[j], np.where(t >= 1.0, good[j1], good[j] & good[j1]))  # a node: its own
    return z0, usable, hop + bend[j], nodes.order[:, j]


def _level(g: GeneralGroup, K3, nodes: _Nodes, idx, rates: bool, pivot: bool):
    """Every sample of idx solved by batched Newton from the nodes (module docstring, steps 2 and 3):
    z (L, m), whether each is assembled on the branch, the row order of its Jacobian and the rates (see
    :func:`_finish`). ``pivot``: search the pivots (else start from the nodes' row order)."""
    z0, usable, allow, order = _interpolated(nodes, idx)
    if pivot:
        order = None
    z0 = np.where(usable, z0, g.z0[:, None])
    z, ok = _newton(g, g.Cx @ K3[0], g.Cy @ K3[0], z0, order)
    z, on, perm, extra = _finish(g, K3, z, order, rates)
    with np.errstate(invalid="ignore"):
        # a jump: farther from the interpolated start than the nodes around it allow; 1e-9 of size:
        # rounding where the nodes coincide
        ok &= usable & on & (np.max(np.abs(z - z0), axis=0) <= allow + 1e-9 * g.size)
    return z, ok, perm, extra


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
    end : ndarray, shape (L,), or None
        The reduced coordinates at the last assembled sample (where a following block starts), or None.
    """

    points: dict
    links: dict
    assembled: np.ndarray
    branch: int
    end: np.ndarray | None = None


def known_arrays(g: GeneralGroup, known: Mapping[str, Sequence], n: int | None = None) -> np.ndarray:
    """The known points' coordinates, velocities and accelerations as one array (3, 2 nk, N)."""
    arrays = [[np.asarray(c, dtype=float) for c in known[p]] for p in g.known]
    if n is None:
        n = max(max(np.size(c) for c in a) for a in arrays)
    K3 = np.empty((3, 2 * len(g.known), n))
    for j, a in enumerate(arrays):
        for c in range(6):
            K3[c // 2, 2 * j + c % 2] = a[c]
    return K3


def start_of(g: GeneralGroup, start, K3) -> np.ndarray:
    """Reduced coordinates near the first sample: the pose's (start None), a previous run's end (an array of
    L), or the unknown points' positions {point: (x, y)} [m]."""
    if start is None:
        return g.z0.copy()
    if isinstance(start, np.ndarray):
        return start.astype(float)
    x = np.array([float(c) for p in g.unknown for c in start[p][:2]])
    return g.N.T @ (x - g.M @ K3[0, :, 0])


def solve_group(g: GeneralGroup, known: Mapping[str, Sequence[np.ndarray]], *,
                start=None) -> GroupSolution:
    """Positions, velocities and accelerations of the group's unknown points over N samples (a path).

    Parameters
    ----------
    g : GeneralGroup
        The group; its pose is the assembly at the first sample.
    known : mapping of str to (x, y, vx, vy, ax, ay)
        Each known point's arrays, each shape (N,) (or scalars for a fixed point) [m, m/s, m/s^2].
    start : None, ndarray of shape (L,), or mapping of str to (x, y)
        Where the group is near the first sample, on its branch: None for its pose; a previous run's
        :attr:`GroupSolution.end` (a long motion solved in blocks); or the unknown points' positions [m].

    Returns
    -------
    GroupSolution
    """
    K3 = known_arrays(g, known)
    n = K3.shape[2]
    path = _Path.of(g, K3[0])
    idx, zs, good = _nodes(g, path, start_of(g, start, K3))
    # the nodes' row orders: partial pivoting at their solutions
    _, _, order, _ = _finish(g, K3[:, :, idx], np.where(good, zs.T, g.z0[:, None]), None, False)
    nodes = _Nodes(idx, zs, good, order)
    if n > REFINE * len(idx):
        # a batched middle level: from it the interpolation is close enough for one Newton step per sample
        mid = np.setdiff1d(np.arange(0, n, REFINE), idx)
        zm, okm, pm, _ = _level(g, K3[:, :, mid], nodes, mid, rates=False, pivot=True)
        nodes = nodes.merged(_Nodes(mid, np.where(okm, zm, np.nan).T, okm, pm))
    L = g.dof
    X = np.empty((3, g.n, n))
    D = np.empty((3, 2, L, n))
    assembled = np.empty(n, dtype=bool)
    for s in range(0, n, BLOCK):
        e = min(n, s + BLOCK)
        k3 = K3[:, :, s:e]
        z, ok, _, (vz, az, base) = _level(g, k3, nodes, np.arange(s, e), rates=True, pivot=False)
        for c, r in enumerate((z, vz, az)):
            np.matmul(g.M, k3[c], out=X[c, :, s:e])
            X[c, :, s:e] += g.N @ r
            D[c, 0, :, s:e], D[c, 1, :, s:e] = base[c]
        assembled[s:e] = ok
    if not assembled.all():
        X[:, :, ~assembled] = np.nan
        D[..., ~assembled] = np.nan
    points = {p: (X[0, 2 * i], X[0, 2 * i + 1], X[1, 2 * i], X[1, 2 * i + 1], X[2, 2 * i], X[2, 2 * i + 1])
              for i, p in enumerate(g.unknown)}
    last = np.flatnonzero(assembled)
    end = None
    if last.size:
        i = last[-1]
        end = g.N.T @ (X[0, :, i] - g.M @ K3[0, :, i])
    return GroupSolution(points, link_rates(g, D), assembled, g.branch, end)


def link_rates(g: GeneralGroup, D) -> dict:
    """Each link's (cos, sin, omega, alpha) from its base vector and its rates D (3, 2, L, N)."""
    (dx, dy), (vx, vy), (ax, ay) = D
    L2 = dx * dx + dy * dy
    L = np.sqrt(L2)
    c, s = dx / L, dy / L
    w = (dx * vy - dy * vx) / L2
    a = (dx * ay - dy * ax) / L2
    return {name: (c[i], s[i], w[i], a[i]) for i, (name, _) in enumerate(g.links)}


def singularity(g: GeneralGroup, positions: Mapping[str, Sequence[np.ndarray]]) -> np.ndarray:
    """The group's distance from a singular pose, in [0, 1]: |det| of the reduced Jacobian with each row
    scaled to unit length (Hadamard's bound makes it at most 1; zero where the group folds). For a dyad it is
    the sine of the angle between its two links, the RRR's transmission measure.

    ``positions``: every point of the group (known and unknown) as (x, y, ...) arrays [m]."""
    xy = {p: (np.asarray(positions[p][0], dtype=float), np.asarray(positions[p][1], dtype=float))
          for p in g.known + g.unknown}
    rows = []
    for _, pts in g.links:
        (x0, y0), (x1, y1) = xy[pts[0]], xy[pts[1]]
        rows.append((x1 - x0, y1 - y0))
    dx = np.array(np.broadcast_arrays(*[r[0] for r in rows]))
    dy = np.array(np.broadcast_arrays(*[r[1] for r in rows]))
    J = _jacobian(g, dx, dy)
    with np.errstate(all="ignore"):
        J /= np.sqrt(np.sum(J * J, axis=1, keepdims=True))
        return np.abs(np.linalg.det(np.moveaxis(J, 2, 0)))
