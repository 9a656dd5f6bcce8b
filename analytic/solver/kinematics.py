"""The general solver: position, velocity and acceleration of any ``linkage/1`` mechanism, one element at a
time in solving order, vectorised with numpy over every sample.

Each element's kind (:mod:`analytic.kinds`) solves it: a closed form for the inputs, the dyads and the rigid
points (positions explicit, the ``branch`` picking the root; rates from the constraint equations
differentiated once and twice, exact linear solves), a numerical solve for a general Assur group. An
element that cannot be assembled at a sample leaves NaN there, and :func:`evaluate` records which element
failed first.

Speed: :class:`~analytic.mechanism.Mechanism` calls :func:`evaluate` on blocks of a few thousand samples,
so each numpy call in a kind costs about a microsecond of overhead plus its arithmetic; the kinds are written
with as few array operations as possible, and the extra outputs (transmission angles, an arctan2 each) can be
skipped. :mod:`analytic.solver.jit` runs the kinds' compiled rows sample by sample when numba is installed.
"""

from __future__ import annotations

import math

import numpy as np

from analytic import kinds
from analytic.format.linkfile import Geometry
from analytic.kinds.base import State, fixed_point


STEPS_PER_TURN = 720
"""For kinds that continue from sample to sample: the inputs' largest step along a solve's path, a crank's
a turn / STEPS_PER_TURN, a slider's the mechanism's size / (STEPS_PER_TURN / 6) (about the same travel of a
point on a crank of that size); samples farther apart are joined by samples filled in between."""


def evaluate(geometry: Geometry, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, *, mu: bool = True,
             start: dict | None = None):
    """Solve every element on 1-D arrays; ``q``, ``qd``, ``qdd`` have shape (n_inputs, N).

    Returns ``(state, failed)``: the :class:`~analytic.kinds.base.State` with every point, link, prismatic
    pair and extra output, and ``failed``, the index (in solving order) of the first element that could not
    be assembled at each sample, -1 where all did. With ``mu=False`` the extra outputs (the transmission
    angles, an arctan2 per RRR group) are skipped. ``start``: the previous block's final state, for
    elements that continue a motion from sample to sample (numerically solved groups; see ``State.carry``).

    With such an element (a kind that is ``continuous``) the samples are a path: it starts where the previous
    block ended (``start["inputs"]``) or, for the first block, at the inputs' start values (where the file's
    pose is), and where two consecutive points of it are farther apart than :data:`STEPS_PER_TURN` allows,
    the inputs are followed along the straight line between them (the samples filled in are solved and
    dropped), so that the group's branch is carried by continuity from its pose to every sample.
    """
    if any(kinds.get(e["kind"]).continuous for e in geometry.elements):
        return _along_path(geometry, q, qd, qdd, mu, start)
    return _evaluate(geometry, q, qd, qdd, mu, start)


def start_values(geometry: Geometry) -> np.ndarray:
    """The inputs' values at t = 0 as the file gives them (where a group's pose is), shape (n_inputs,)."""
    out = []
    for e in geometry.elements:
        kind = kinds.get(e["kind"])
        if kind.section == "inputs":
            out.append(float(e[kind.motion_fields[0]]))
    return np.array(out)


def size_of(geometry: Geometry) -> float:
    """The longest link or the ground's spread [m] (as :attr:`analytic.mechanism.Mechanism.size`)."""
    xy = np.array(list(geometry.ground.values()) or [(0.0, 0.0)], dtype=float)
    spread = float(np.max(np.ptp(xy, axis=0))) if len(xy) > 1 else 0.0
    return max([kinds.get(e["kind"]).extent(e) for e in geometry.elements] + [spread, 1e-12])


def _steps(geometry: Geometry) -> np.ndarray:
    """Each input's largest step along a path (rad or m)."""
    size = None
    out = []
    for e in geometry.elements:
        kind = kinds.get(e["kind"])
        if kind.section != "inputs":
            continue
        if kind.periodic:
            out.append(2 * math.pi / STEPS_PER_TURN)
        else:
            size = size_of(geometry) if size is None else size
            out.append(6.0 * size / STEPS_PER_TURN)
    return np.array(out)


def _along_path(geometry, q, qd, qdd, mu, start):
    """:func:`_evaluate` on the samples as a path (see :func:`evaluate`)."""
    n = q.shape[1]
    prev = start.get("inputs") if start else None
    prev = start_values(geometry) if prev is None else prev
    if n == 0:
        st, failed = _evaluate(geometry, q, qd, qdd, mu, start)
        st.carry["inputs"] = prev
        return st, failed
    full = np.column_stack([prev, q])
    with np.errstate(invalid="ignore"):
        gaps = np.max(np.abs(np.diff(full, axis=1)) / _steps(geometry)[:, None], axis=0)
    extra = np.where(np.isfinite(gaps), np.maximum(np.ceil(gaps) - 1, 0), 0).astype(np.intp)
    if not extra.any():
        st, failed = _evaluate(geometry, q, qd, qdd, mu, start)
    else:
        counts = extra + 1
        at = np.cumsum(counts) - 1                   # where the samples are in the filled-in path
        owner = np.repeat(np.arange(n), counts)
        frac = (np.arange(at[-1] + 1) - np.repeat(at - extra, counts) + 1) / counts[owner]
        qq = full[:, owner] + frac * (full[:, owner + 1] - full[:, owner])
        qq[:, at] = q
        zero = np.zeros_like(qq)
        qqd, qqdd = zero.copy(), zero
        qqd[:, at] = np.broadcast_to(qd, q.shape)
        qqdd = zero.copy()
        qqdd[:, at] = np.broadcast_to(qdd, q.shape)
        st_all, failed = _evaluate(geometry, qq, qqd, qqdd, mu, start)
        st = State(n, q, qd, qdd, mu, start=start)
        for table, source in ((st.points, st_all.points), (st.links, st_all.links), (st.slides, st_all.slides)):
            for key, v in source.items():
                table[key] = tuple(_pick(c, at) for c in v)
        st.extras = {k: _pick(v, at) for k, v in st_all.extras.items()}
        st.carry = st_all.carry
        failed = failed[at]
    st.carry["inputs"] = np.array(q[:, -1], dtype=float)
    return st, failed


def _pick(v, at):
    return v[at] if isinstance(v, np.ndarray) and v.ndim == 1 and v.shape[0] > 1 else v


def start_problem(geometry: Geometry) -> str | None:
    """The first problem a kind finds with where the elements are at the inputs' start values
    (:meth:`analytic.kinds.base.Kind.check_start`), ``"element label: problem"``, or None. Only kinds that
    check anything there are asked (no solve otherwise)."""
    from analytic.kinds.base import Kind
    asked = [e for e in geometry.elements if type(kinds.get(e["kind"])).check_start is not Kind.check_start]
    if not asked:
        return None
    q0 = start_values(geometry)[:, None]
    zero = np.zeros_like(q0)
    with np.errstate(all="ignore"):
        st, _ = _evaluate(geometry, q0, zero, zero, False, None)
    for e in asked:
        problem = kinds.get(e["kind"]).check_start(e, st)
        if problem:
            return f"{e['label']}: {problem}"
    return None


def _evaluate(geometry: Geometry, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, mu: bool, start):
    """Every element in solving order on the samples as given (see :func:`evaluate`)."""
    n = q.shape[1]
    st = State(n, q, qd, qdd, mu, start=start)
    for g, (x, y) in geometry.ground.items():
        st.points[g] = fixed_point(x, y, n)
    failed = np.full(n, -1, dtype=np.int64)
    any_failed = False
    for index, e in enumerate(geometry.elements):
        kinds.get(e["kind"]).solve(e, st)
        for p in e["places"]:
            x = st.points[p][0]
            # One sum tells whether every sample assembled (NaN propagates; a non-finite sum from huge
            # finite values only sends it down the exact path).
            if any_failed or not math.isfinite(np.add.reduce(x, axis=None)):
                bad = ~np.isfinite(x)
                bad &= failed < 0
                failed[bad] = index
                any_failed = True
    return st, failed
