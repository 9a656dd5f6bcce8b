"""Cost per sample of a numerically solved Assur group against a dyad chain of the same size.

The group: the class III triad of ``tests/test_general_group.py`` (a ternary link D E F pinned through three
binary links to a crank tip A and two ground pivots; 6 unknown coordinates), solved by
:func:`analytic.solver.general_group.solve_group` (coarse continuation, batched Newton, exact rates). The chain:
three closed-form RRR dyads (:func:`analytic.kinds.rrr.rrr`) placing three points from the same crank
(6 unknown coordinates). Both give positions, velocities and accelerations of their three points.
Goal (issue 16): the group costs at most 10x the chain per sample, numpy, N = 1e6.

    python benchmarks/general_group.py [--samples 1000000] [--repeats 3]
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

# benchmarks/analytic.py would shadow the package of that name: keep this folder off the import path.
sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]

from analytic.solver.general_group import make_group, solve_group  # noqa: E402
from analytic.kinds.base import on_frame  # noqa: E402
from analytic.kinds.rrr import rrr as _rrr  # noqa: E402


def _crank(P, r, q, qd, qdd):
    """The crank tip at radius r about P (as the crank kind solves it)."""
    return on_frame(P, np.cos(q), np.sin(q), qd, qdd, r, 0.0), None

Q0 = 0.5
O1, O2 = (4.0, 3.5), (3.5, -0.5)
POSE = dict(A=(math.cos(Q0), math.sin(Q0)), O1=O1, O2=O2, D=(1.5, 2.0), E=(3.0, 2.5), F=(2.6, 1.2))
LINKS = {"2": ("A", "D"), "T": ("D", "E", "F"), "4": ("O1", "E"), "5": ("O2", "F")}


def best(fn, repeats: int) -> float:
    out = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        out = min(out, time.perf_counter() - t0)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=1_000_000)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    n = args.samples
    q = Q0 + np.linspace(0.0, 0.8, n)          # the triad's assembly range (it locks near Q0 + 0.96)
    qd, qdd = np.full(n, 2.0), np.full(n, 0.5)
    ground = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    g = make_group(LINKS, ("A", "O1", "O2"), ("D", "E", "F"), POSE)

    def triad():
        A, _ = _crank(ground, 1.0, q, qd, qdd)
        sol = solve_group(g, dict(A=A, O1=O1 + (0, 0, 0, 0), O2=O2 + (0, 0, 0, 0)))
        return sol

    fixed1 = tuple(np.full(n, v) for v in O1 + (0, 0, 0, 0))
    fixed2 = tuple(np.full(n, v) for v in O2 + (0, 0, 0, 0))

    def chain():
        A, _ = _crank(ground, 1.0, q, qd, qdd)
        D, _, _ = _rrr(A, fixed1, 3.2, 2.6, 1, mu=False)
        E, _, _ = _rrr(D, fixed2, 2.0, 3.0, 1, mu=False)
        F, _, _ = _rrr(E, fixed1, 1.8, 1.5, -1, mu=False)
        return F

    sol = triad()
    assert sol.assembled.all(), "the benchmark triad must assemble over its whole range"
    t_group = best(triad, args.repeats)
    t_chain = best(chain, args.repeats)
    print(f"numpy {np.__version__}; N = {n}; best of {args.repeats}; position + velocity + acceleration")
    print(f"class III triad (general group, Newton): {t_group:.3f} s  {t_group / n * 1e9:8.1f} ns/sample")
    print(f"three RRR dyads (closed form):          {t_chain:.3f} s  {t_chain / n * 1e9:8.1f} ns/sample")
    print(f"ratio group / chain: {t_group / t_chain:.1f}x (goal <= 10x)")


if __name__ == "__main__":
    main()
