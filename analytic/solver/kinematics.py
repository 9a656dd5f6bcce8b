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


def evaluate(geometry: Geometry, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, *, mu: bool = True,
             start: dict | None = None):
    """Solve every element on 1-D arrays; ``q``, ``qd``, ``qdd`` have shape (n_inputs, N).

    Returns ``(state, failed)``: the :class:`~analytic.kinds.base.State` with every point, link, prismatic
    pair and extra output, and ``failed``, the index (in solving order) of the first element that could not
    be assembled at each sample, -1 where all did. With ``mu=False`` the extra outputs (the transmission
    angles, an arctan2 per RRR group) are skipped. ``start``: the previous block's final state, for
    elements that continue a motion from sample to sample (numerically solved groups; see ``State.carry``).
    """
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
