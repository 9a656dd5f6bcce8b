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
   previous block ended); nodes are placed every 1/16 of the group's size of travel of the known points and
   where they turn back (so that between two nodes the samples go one way), refined by halving where the
   solution moves far between two nodes and, down to adjacent samples, where the group stops or starts
   assembling; there the Jacobian is factorised with partial pivoting, which gives each node a row order;
2. **every 32nd sample**, batched, by Newton from the nodes' solutions interpolated in the known points'
   travel along the path (a parabola through three nodes on the same stretch);
3. **every sample**, batched, from those likewise: Newton until the residual is below 1e-11 of the size (from
   the parabola, usually at once), then one more step (rounding).

Branch: the sign of ``det(J_u)``, the Jacobian of all the equations in the unknown coordinates (for a dyad:
which side of ``P -> Q`` the point lies on, the ``branch`` of ``RRR``); it equals the sign of the reduced
Jacobian's determinant times a constant, and it changes only through a singular pose. A sample is not
assembled (NaN, as the dyads leave where they cannot be assembled) where Newton does not converge, where the
determinant has the other sign (the path went through a singular pose), or where the solution lies farther
from its interpolated start than the nodes around it allow (a jump to another assembly). The known points
jumping by more than a quarter of the size between two adjacent samples breaks the path there.

Rates: exact linear solves with the reduced Jacobian ``J`` (rows ``d^T E / L``) factorised again at the
solved points: ``J vz = -d.(C vk) / L`` and ``J az = -(|dv|^2 + d.(C ak)) / L`` with ``dv = C vk + E vz``.

Every batched linear solve is an LU factorisation written over the samples (arrays (L, L, N), each entry a
contiguous run of samples), in the row order of the node before each sample (rows copied run by run, no
pivot search) and with partial pivoting where a multiplier would exceed 16; it costs a fraction of a LAPACK
call per sample for these small systems, and the determinant comes with it.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from analytic._common import ParameterError

NEWTON_STEPS = 12          # most Newton steps per sample: from an interpolated start it takes 0 to 2
NEWTON_TOL = 1e-13         # one sample (nodes): converged when its step is below this fraction of the size
RESIDUAL_CONVERGED = 4e-15  # residual at rounding level [fraction of size]: the rows are lengths of the
#                             order of the size, each rounded to ~eps times a few terms
NEWTON_LOOSE = 1e-11       # many samples: iterate to this residual [fraction of size], then one more step
#                            (its error squared: rounding)
RESIDUAL_TOL = 1e-10       # a sample whose residual after that step exceeds this fraction of size is refused
SINGULAR_COND = 1e12       # a pose whose reduced Jacobian's condition number exceeds this is singular: a
#                            Newton step there loses 12 of 16 digits
NODE_TRAVEL = 1 / 16       # nodes every this fraction of the size of the known points' travel
HOP = 1 / 4                # a node farther than this fraction of size from the previous one is refined
JUMP = 1 / 4               # the known points moving farther than this fraction of size between two adjacent
#                            samples break the path (the kinematics fills in inputs far apart first)
REFINE = 32                # samples per node of the batched middle level
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

    turn: np.ndarray
    """The samples where a known point turns back (its step makes an obtuse angle with the one before)."""

    @staticmethod
    def of(g: GeneralGroup, K) -> "_Path":
        n = K.shape[1]
        P = K.reshape(-1, 2, n)
        d = np.diff(P, axis=2)
        step = np.sqrt(np.max(np.sum(d * d, axis=1), axis=0)) if n > 1 else np.zeros(0)
        moved = np.flatnonzero(step > 0.0)                  # a repeated sample does not hide a turn
        dm = d[:, :, moved]
        back = np.any(np.sum(dm[:, :, 1:] * dm[:, :, :-1], axis=1) < 0.0, axis=0)
        turn = np.unique(np.r_[moved[:-1][back] + 1, moved[1:][back]])
        return _Path(K, np.r_[0.0, np.cumsum(step)], np.r_[False, step > JUMP * g.size], turn)


@dataclass(frozen=True)
class Stepper:
    """What continuation along a path needs of a numeric group: ``newton(k, z)`` -> (z, converged) at the
    known points' coordinates ``k`` from ``z``; ``far(za, z)`` how far a step moved the solution [length];
    the group's ``size`` [length] and ``width`` (unknowns per sample)."""

    newton: Callable
    far: Callable
    size: float
    width: int


def walk(s: Stepper, path: _Path, a: int, za, b: int) -> list:
    """Continue from sample a (solved, za) to sample b (either side of a), halving the step where Newton
    fails or the solution moves far: the nodes decided, ``[(index, z, ok), ...]`` in walking order, b last
    unless a node before it failed (then that one is last)."""
    z, ok = s.newton(path.K[:, b], za)
    far = (abs(path.travel[b] - path.travel[a]) > 2 * NODE_TRAVEL * s.size or s.far(za, z) > HOP * s.size)
    if ok and not far:
        return [(b, z, True)]
    if abs(b - a) == 1:                      # adjacent samples: nothing to halve
        ok = ok and not path.jump[max(a, b)]
        return [(b, z, ok)]
    m = (a + b) // 2
    first = walk(s, path, a, za, m)
    if not first[-1][2]:
        return first
    return first + walk(s, path, m, first[-1][1], b)


def trace_nodes(s: Stepper, path: _Path, z_start):
    """Sequential continuation over nodes along the block (module docstring, step 1): the node indices
    (sorted), their solutions (n_nodes, width; NaN where not assembled) and whether each is."""
    n = path.K.shape[1]
    marks = np.floor(path.travel / (NODE_TRAVEL * s.size))
    cand = np.flatnonzero(np.r_[True, marks[1:] != marks[:-1]] | path.jump)
    cand = np.unique(np.r_[cand, path.turn, n - 1])          # nodes where the path turns back: between
    #                                                          two nodes the samples go one way
    found: dict[int, tuple] = {}
    z, ok = s.newton(path.K[:, 0], z_start)
    found[0] = (z, ok)
    z_good, i_good = (z, 0) if ok else (np.asarray(z_start, dtype=float), None)
    last_bad = None if ok else 0
    for c in cand[1:]:
        c = int(c)
        if last_bad is None:                                   # on the branch: continue
            decided = walk(s, path, i_good, z_good, c)
            for i, z, ok in decided:
                found[i] = (z, ok)
            i, z, ok = decided[-1]
            if ok:
                z_good, i_good = z, i
            else:
                last_bad = i
            continue
        z, ok = s.newton(path.K[:, c], z_good)                 # after a gap: back on the branch here?
        found[c] = (z, ok)
        if not ok:
            last_bad = c
            continue
        if c - last_bad > 1:                                   # where it starts again: back from here
            for i, zb, okb in walk(s, path, c, z, last_bad + 1):
                found[i] = (zb, okb)
        z_good, i_good, last_bad = z, c, None
    idx = np.array(sorted(found), dtype=np.intp)
    good = np.array([found[i][1] for i in idx], dtype=bool)
    zs = np.array([found[i][0] for i in idx], dtype=float).reshape(len(idx), s.width)
    zs[~good] = np.nan
    return idx, zs, good


def _nodes(g: GeneralGroup, path: _Path, z_start):
    """:func:`trace_nodes` on the reduced coordinates of a revolute group."""
    s = Stepper(lambda k, z: _newton1(g, k, z), lambda za, z: float(np.max(np.abs(z - za))), g.size, g.dof)
    return trace_nodes(s, path, z_start)


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


MAX_RUNS = 32
"""Row orders that change at most this many times along the samples are applied run by run (row copies);
beyond, sample by sample (a gather several times slower)."""


def _runs(order):
    """(start, end, order) of the runs of samples sharing one row order, or None if there are too many."""
    m = order.shape[1]
    cut = np.flatnonzero(np.any(order[:, 1:] != order[:, :-1], axis=0)) + 1
    if cut.size > MAX_RUNS:
        return None
    edges = np.r_[0, cut, m]
    return [(int(s), int(e), order[:, s]) for s, e in zip(edges[:-1], edges[1:])]


def lu(A, order=None):
    """LU factorisation of many small matrices at once.

    Parameters
    ----------
    A : ndarray, shape (n, n, N)
        N matrices, entry (i, j) of matrix s at ``A[i, j, s]`` (overwritten).
    order : ndarray of int, shape (n, N), optional
        A row order per matrix known to pivot well (that of a nearby matrix): the rows are taken in this
        order and eliminated without searching for pivots, which is several times faster; a matrix whose
        multipliers then exceed ``GROWTH`` is factorised again with partial pivoting. Also a list of runs
        (start, end, order) of samples sharing one order. None: partial pivoting.

    Returns
    -------
    (LU, perm, det)
        ``LU`` (unit lower factor below the diagonal, upper factor on and above it), ``perm``: row i of the
        factors of matrix s is its row ``perm[i, s]`` (an (n, N) array, or a list of runs (start, end,
        order) of samples sharing one), and ``det`` (N,) the determinants. A singular matrix gives a zero or
        non-finite pivot, and NaN or inf in what is solved with it.
    """
    if order is None:
        return _lu_pivoting(A)
    n, _, m = A.shape
    A0 = A
    runs = order if isinstance(order, list) else _runs(order)
    if runs is None:
        A = np.take_along_axis(A, order[:, None, :], axis=0)
        det = parity(order)
    else:
        A = np.empty_like(A0)
        det = np.empty(m)
        for s, e, o in runs:
            A[:, :, s:e] = A0[o, :, s:e]
            det[s:e] = parity(o[:, None])[0]
    growth = _eliminate(A, det)
    perm = order if runs is None else runs
    redo = np.flatnonzero(~(growth <= GROWTH))
    if redo.size:
        LU, p, d = _lu_pivoting(A0[:, :, redo])
        A[:, :, redo], det[redo] = LU, d
        perm = order_array(perm, m)
        perm[:, redo] = p
    return A, perm, det


def _eliminate(A, det):
    """Gaussian elimination without pivot search of A (n, n, m) in place (its rows already in their order),
    ``det`` (m,) multiplied by the pivots; returns each matrix's largest multiplier (its element growth)."""
    n = A.shape[0]
    for k in range(n):
        piv = A[k, k]
        det *= piv
        if k < n - 1:
            f = A[k + 1:, k]
            f /= piv
            A[k + 1:, k + 1:] -= f[:, None, :] * A[k, None, k + 1:]
    if n < 2:
        return np.zeros(A.shape[2])
    rows, cols = np.tril_indices(n, -1)
    return np.max(np.abs(A[rows, cols]), axis=0)


def _factor(g: GeneralGroup, dx, dy, order):
    """The LU factorisation of the reduced Jacobian at base vectors (dx, dy), each (L, m), as
    ``lu(_jacobian(g, dx, dy), order)`` returns it; built directly in the row order where that is given as
    runs (no copy of the matrices)."""
    if order is None:
        return _lu_pivoting(_jacobian(g, dx, dy))
    runs = order if isinstance(order, list) else _runs(order)
    if runs is None:
        return lu(_jacobian(g, dx, dy), order)
    L, m = dx.shape
    jx, jy = g.Jx, g.Jy
    A = np.empty((L, L, m))
    det = np.empty(m)
    for s, e, o in runs:
        blk = A[:, :, s:e]
        np.multiply(dx[o, s:e][:, None, :], jx[o][:, :, None], out=blk)
        blk += dy[o, s:e][:, None, :] * jy[o][:, :, None]
        det[s:e] = parity(o[:, None])[0]
    growth = _eliminate(A, det)
    perm = runs
    redo = np.flatnonzero(~(growth <= GROWTH))
    if redo.size:
        LU, p, d = _lu_pivoting(_jacobian(g, dx[:, redo], dy[:, redo]))
        A[:, :, redo], det[redo] = LU, d
        perm = order_array(runs, m)
        perm[:, redo] = p
    return A, perm, det


def order_array(perm, m: int) -> np.ndarray:
    """A row order as an (n, m) array (from a list of runs, or a copy of an array)."""
    if not isinstance(perm, list):
        return np.array(perm)
    out = np.empty((len(perm[0][2]), m), dtype=np.intp)
    for s, e, o in perm:
        out[:, s:e] = o[:, None]
    return out


def lu_solve(LU, perm, b):
    """Solve with :func:`lu`'s factors: b (n, N) -> x (n, N)."""
    n = LU.shape[0]
    if isinstance(perm, list):
        y = np.empty_like(b)
        for s, e, o in perm:
            y[:, s:e] = b[o, s:e]
    else:
        y = np.take_along_axis(b, perm, axis=0)
    for j in range(n - 1):                          # column by column: one array operation per column
        y[j + 1:] -= LU[j + 1:, j] * y[j]
    for j in range(n - 1, -1, -1):
        y[j] /= LU[j, j]
        if j:
            y[:j] -= LU[:j, j] * y[j]
    return y


def _jacobian(g: GeneralGroup, dx, dy):
    """The reduced Jacobian (L, L, N) from the base vectors' components (L, N)."""
    jx, jy = g.Jx, g.Jy
    J = dx[:, None, :] * jx[:, :, None]
    J += dy[:, None, :] * jy[:, :, None]
    return J


def _residual(g: GeneralGroup, Bx, By, z):
    """The base vectors (dx, dy) and the rows F = (|d|^2 - L^2) / (2 L) [m] at z, each (L, m)."""
    dx = g.Ex @ z
    dx += Bx
    dy = g.Ey @ z
    dy += By
    F = dx * dx
    F += dy * dy
    F -= (g.length * g.length)[:, None]
    F *= (0.5 / g.length)[:, None]
    return dx, dy, F


def _newton(g: GeneralGroup, Bx, By, z, order):
    """Batched Newton on the reduced coordinates z (L, m), the known points' part of the base vectors
    Bx, By (L, m) given (``order``: see :func:`lu`), until the residual is below NEWTON_LOOSE of size (the
    correction in :func:`_finish` then squares what is left). Only the samples not yet there are iterated.
    Returns z, whether each sample got there, and (dx, dy, F) at z where no sample took a step (else None)."""
    m = z.shape[1]
    z = np.array(z, dtype=float)
    done = np.zeros(m, dtype=bool)
    act = None                                  # None: every sample (no copies)
    with np.errstate(all="ignore"):
        for it in range(NEWTON_STEPS + 1):
            if act is None:
                dx, dy, F = _residual(g, Bx, By, z)
                od = order
            else:
                dx, dy, F = _residual(g, Bx[:, act], By[:, act], z[:, act])
                od = None if order is None else order_array(order, m)[:, act]
            res = np.max(np.abs(F), axis=0)
            conv = res <= NEWTON_LOOSE * g.size
            if act is None:
                done[:] = conv
            else:
                done[act] = conv
            keep = ~conv & np.isfinite(res)
            if it == 0 and conv.all():
                return z, done, (dx, dy, F)
            if it == NEWTON_STEPS or not keep.any():
                break
            if not keep.all():
                sel = np.flatnonzero(keep)
                act = sel if act is None else act[sel]
                dx, dy, F = dx[:, sel], dy[:, sel], F[:, sel]
                od = None if order is None else order_array(order, m)[:, act]
            LU, perm, _ = _factor(g, dx, dy, od)
            dz = lu_solve(LU, perm, F)
            if act is None:
                z -= dz
            else:
                z[:, act] -= dz
    return z, done, None


def _finish(g: GeneralGroup, K3, z, order, rates: bool, cache=None, B=None):
    """At z (L, m), within NEWTON_LOOSE of the solution: one more Newton step (to rounding: the error is
    squared), the residual after it, the determinant's sign against the branch, and (``rates``) the
    velocities and accelerations, solved with the Jacobian factorised again where the points are (exact).

    K3: known coordinates, velocities and accelerations (3, 2 nk, m); ``cache``: (dx, dy, F) at z if known;
    ``B``: (C_x k, C_y k) if known. Returns z, whether each sample is assembled on the branch (the sign, the
    residual below RESIDUAL_TOL of size), the row order of the factorisation, and (``rates``) (vz, az, (D,
    dD, ddD)) with the links' base vectors and their rates, each a pair (x, y) of (L, m)."""
    with np.errstate(all="ignore"):
        Bx, By = (g.Cx @ K3[0], g.Cy @ K3[0]) if B is None else B
        dx, dy, F = _residual(g, Bx, By, z) if cache is None else cache
        LU, perm, det = _factor(g, dx, dy, order)
        z = z - lu_solve(LU, perm, F)
        dx, dy, F = _residual(g, Bx, By, z)             # the base vectors where the points are
        if rates:
            LU, perm, det = _factor(g, dx, dy, perm)
        on = (np.sign(det) == g.sign) & (np.max(np.abs(F), axis=0) <= RESIDUAL_TOL * g.size)
        if not rates:
            return z, on, perm, None
        inv = 1.0 / g.length[:, None]
        vBx, vBy = g.Cx @ K3[1], g.Cy @ K3[1]
        aBx, aBy = g.Cx @ K3[2], g.Cy @ K3[2]
        vz = lu_solve(LU, perm, -(dx * vBx + dy * vBy) * inv)
        vx = vBx + g.Ex @ vz
        vy = vBy + g.Ey @ vz
        az = lu_solve(LU, perm, -(vx * vx + vy * vy + dx * aBx + dy * aBy) * inv)
        ax = aBx + g.Ex @ az
        ay = aBy + g.Ey @ az
    return z, on, perm, (vz, az, ((dx, dy), (vx, vy), (ax, ay)))


@dataclass(frozen=True)
class _Nodes:
    """Solved samples along the path: indices (sorted), reduced coordinates (n_nodes, L; NaN where not
    assembled), whether each is assembled, the row order its Jacobian pivots in (L, n_nodes), and whether the
    path turns back there."""

    index: np.ndarray
    z: np.ndarray
    good: np.ndarray
    order: np.ndarray
    turn: np.ndarray

    def merged(self, other: "_Nodes") -> "_Nodes":
        idx = np.r_[self.index, other.index]
        k = np.argsort(idx, kind="stable")
        return _Nodes(idx[k], np.r_[self.z, other.z][k], np.r_[self.good, other.good][k],
                      np.c_[self.order, other.order][:, k], np.r_[self.turn, other.turn][k])


def _interpolated(nodes: _Nodes, idx, travel):
    """The start of every sample in idx (sorted): the nodes' solutions interpolated in the known points'
    travel along the path (``travel``, one value per sample: a parameter that the sampling's density does not
    bend), (L, m), by the parabola through the two nodes around it and the next one (the one before, at the
    end, or where the path turns back; a straight line where neither is usable); whether the nodes around it
    hold the branch; how far a solution may lie from its start (the nodes' distance plus their path's bend);
    and the row orders of the nodes before the samples, as runs (see :func:`lu`)."""
    zs, good, ix = nodes.z, nodes.good, nodes.index
    n = len(ix)
    if n == 1:
        at = idx == ix[0]
        return (np.repeat(zs.T, len(idx), axis=1), at & good[0], np.zeros(len(idx)),
                [(0, len(idx), nodes.order[:, 0])])
    zt = zs.T
    X = travel[ix]
    span = np.diff(X)
    with np.errstate(all="ignore"):
        a = zt[:, :-1]
        slope = np.where(span > 0.0, (zt[:, 1:] - a) / span, 0.0)
        curve = np.zeros_like(slope)
        if n >= 3:
            # the third node of each interval: the next one, or the one before (at the end, or where the path
            # turns back at the next node); none (a straight line) where it turns back at both ends
            turn = nodes.turn
            ahead = np.r_[~turn[1:-1], False]
            k = np.where(ahead, np.arange(2, n + 1) % n, np.r_[0, np.arange(n - 2)])
            third = (ahead | ~turn[:-1]) & good[k] & (np.arange(n - 1) + ahead > 0)
            curve = ((zt[:, k] - zt[:, 1:]) / (X[k] - X[1:]) - slope) / (X[k] - X[:-1])
            curve = np.where(third & np.isfinite(curve), curve, 0.0)
        hop = np.nan_to_num(np.max(np.abs(zt[:, 1:] - a), axis=0), nan=0.0)
    dd = np.zeros(n + 1)
    if n >= 3:
        dd[1:-2] = np.nan_to_num(np.max(np.abs(zs[2:] - 2 * zs[1:-1] + zs[:-2]), axis=1), nan=0.0)
    allow = hop + np.maximum.reduce([dd[:-2], dd[1:-1], dd[2:]])
    both = good[:-1] & good[1:]
    j = np.clip(np.searchsorted(ix, idx, side="right") - 1, 0, n - 2)
    u = travel[idx] - np.take(X, j)
    sj = np.take(span, j)
    L = zt.shape[0]
    coef = np.take(np.concatenate((curve, slope, a)), j, axis=1)   # np.take: several times faster than [:, j]
    with np.errstate(all="ignore"):
        z0 = coef[:L]
        z0 *= u - sj
        z0 += coef[L:2 * L]
        z0 *= u
        z0 += coef[2 * L:]                                   # Newton's form of the parabola
    first, last = idx == np.take(ix, j), idx == np.take(ix, j + 1)
    on_node = np.flatnonzero(first)                          # a node itself: its own solution
    z0[:, on_node] = a[:, j[on_node]]
    on_node = np.flatnonzero(last)
    z0[:, on_node] = zt[:, j[on_node] + 1]
    usable = np.where(first, np.take(good, j), np.where(last, np.take(good, j + 1), np.take(both, j)))
    # the row orders: one run per stretch of samples whose node before has the same order
    change = np.r_[True, np.any(nodes.order[:, 1:] != nodes.order[:, :-1], axis=0)]
    moved = np.flatnonzero(np.diff(j)) + 1
    cut = moved[change[j[moved]]]
    edges = np.r_[0, cut, len(idx)]
    runs = [(int(s0), int(e0), nodes.order[:, j[s0]]) for s0, e0 in zip(edges[:-1], edges[1:])]
    if len(runs) > MAX_RUNS:
        runs = order_array(runs, len(idx))
    return z0, usable, np.take(allow, j), runs


def _level(g: GeneralGroup, K3, nodes: _Nodes, idx, travel, rates: bool):
    """Every sample of idx solved by batched Newton from the nodes (module docstring, steps 2 and 3):
    z (L, m), whether each is assembled on the branch, the row order of its Jacobian (runs or an array, see
    :func:`lu`) and the rates (see :func:`_finish`). The Jacobians are factorised in the nodes' row orders."""
    z0, usable, allow, order = _interpolated(nodes, idx, travel)
    if not usable.all():
        z0[:, ~usable] = g.z0[:, None]
    B = (g.Cx @ K3[0], g.Cy @ K3[0])
    z, ok, cache = _newton(g, *B, z0, order)
    z, on, perm, extra = _finish(g, K3, z, order, rates, cache, B)
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
    nodes = _Nodes(idx, zs, good, order, np.isin(idx, path.turn))
    if n > REFINE * len(idx):
        # a batched middle level: from it the interpolation is close enough for one Newton step per sample
        mid = np.setdiff1d(np.arange(0, n, REFINE), idx)
        zm, okm, pm, _ = _level(g, K3[:, :, mid], nodes, mid, path.travel, rates=False)
        nodes = nodes.merged(_Nodes(mid, np.where(okm, zm, np.nan).T, okm, order_array(pm, len(mid)),
                                    np.zeros(len(mid), dtype=bool)))
    L, nu = g.dof, len(g.unknown)
    P = np.empty((nu, 6, n))                   # each point's x, y, vx, vy, ax, ay: contiguous rows
    W = np.empty((L, 4, n))                    # each link's cos, sin, omega, alpha
    assembled = np.empty(n, dtype=bool)
    end = None
    for s in range(0, n, BLOCK):
        e = min(n, s + BLOCK)
        k3 = K3[:, :, s:e]
        z, ok, _, (vz, az, base) = _level(g, k3, nodes, np.arange(s, e), path.travel, rates=True)
        for c, r in enumerate((z, vz, az)):
            X = g.M @ k3[c]
            X += g.N @ r
            P[:, 2 * c, s:e], P[:, 2 * c + 1, s:e] = X[0::2], X[1::2]
        W[:, :, s:e] = link_rates(*base, g.length)
        assembled[s:e] = ok
        if not ok.all():
            P[:, :, s:e][:, :, ~ok] = np.nan
            W[:, :, s:e][:, :, ~ok] = np.nan
        if ok.any():
            end = z[:, np.flatnonzero(ok)[-1]].copy()
    points = {p: tuple(P[i]) for i, p in enumerate(g.unknown)}
    links = {name: tuple(W[i]) for i, (name, _) in enumerate(g.links)}
    return GroupSolution(points, links, assembled, g.branch, end)


def link_rates(D, dD, ddD, length) -> np.ndarray:
    """Links' (cos, sin, omega, alpha), shape (L, 4, m), from their base vectors D (whose lengths are
    ``length`` (L,), to rounding: the points are solved) and its rates dD, ddD (pairs (x, y) of (L, m))."""
    (dx, dy), (vx, vy), (ax, ay) = D, dD, ddD
    out = np.empty((dx.shape[0], 4, dx.shape[1]))
    inv = (1.0 / length)[:, None]
    inv2 = inv * inv
    with np.errstate(all="ignore"):
        np.multiply(dx, inv, out=out[:, 0])
        np.multiply(dy, inv, out=out[:, 1])
        w = out[:, 2]
        np.multiply(dx, vy, out=w)
        w -= dy * vx
        w *= inv2
        a = out[:, 3]
        np.multiply(dx, ay, out=a)
        a -= dy * ax
        a *= inv2
    return out


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
