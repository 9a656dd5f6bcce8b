"""Batch over designs: a 10,000-design five-bar sweep end to end against one solve with as many samples.

Prints the sweep's time on the batch path (analytic.solver.batch, what ``linkage sweep`` runs) and one at a time
(``Mechanism.with_values`` + ``solve`` per design, the path ``sweep`` took before), their throughput in
samples per second, and the ratio to one solve of 10,000 x 361 samples of one design (goal: >= 0.3).

    python benchmarks/batch.py [--designs 10000] [--samples 360] [--workers 2] [--skip-old]

With ``--workers N`` the sweep is also timed with its chunks on N processes (``linkage sweep --workers N``;
the pool started before the clock). What limits the ratio is printed last: the batch solve's share of the
sweep (numpy kinematics of every sample, against the reference's compiled single-design path).
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

import analytic  # noqa: E402
from analytic.applications import studies  # noqa: E402


def old_sweep(base, vary, samples):
    """The one-at-a-time path: one Mechanism built and solved per design (the code sweep ran before)."""
    keys = list(vary)
    n_ok = 0
    for combo in np.stack(np.meshgrid(*(vary[k] for k in keys), indexing="ij"), -1).reshape(-1, len(keys)):
        mech = base.with_values(**dict(zip(keys, map(float, combo))))
        t = np.linspace(0.0, studies.period_of(mech), samples + 1)
        sol = mech.solve(*mech.drive(t))
        n_ok += sol.first_failure() is None
    return n_ok


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=int, default=10_000)
    ap.add_argument("--samples", type=int, default=360)
    ap.add_argument("--skip-old", action="store_true", help="do not time the one-at-a-time path")
    ap.add_argument("--workers", type=int, default=2, help="also time the sweep on this many processes (1: no)")
    a = ap.parse_args()
    side = int(round(math.sqrt(a.designs)))
    base = analytic.load("fivebar")
    vary = {"l2": list(np.linspace(0.04, 0.07, side)), "l4": list(np.linspace(0.06, 0.09, side))}
    k = side * side
    n = k * (a.samples + 1)
    # one solve of one design with as many samples
    t = np.linspace(0.0, studies.period_of(base) * k, n)
    q = base.drive(t)
    from analytic.solver import jit as _jit
    path = "numba" if _jit.enabled(n) else "numpy"
    print(f"single-design solves of {n:,} samples and the batch path run on {path}")
    p = base.output_point
    base.solve(*q, outputs=("x" + p,))                        # warm-up (numba: import and kernel load)
    t0 = time.perf_counter()
    base.solve(*q)
    full = time.perf_counter() - t0
    print(f"one solve of one five-bar, {n:,} samples, every output: {full:.3f} s  ({n / full / 1e6:.2f} M samples/s)")
    t0 = time.perf_counter()
    base.solve(*q, outputs=("x" + p, "y" + p, "vx" + p, "vy" + p))
    one = time.perf_counter() - t0
    print(f"one solve of one five-bar, {n:,} samples, the sweep's outputs (x, y, vx, vy of {p}): {one:.3f} s  "
          f"({n / one / 1e6:.2f} M samples/s): the reference below")
    t0 = time.perf_counter()
    rows, _ = studies.sweep_mechanism(base, vary, a.samples)
    new = time.perf_counter() - t0
    valid = sum(r.valid for r in rows)
    print(f"sweep, batch path: {k:,} designs x {a.samples + 1} samples: {new:.3f} s  "
          f"({n / new / 1e6:.2f} M samples/s, {valid} valid); ratio to one solve: {one / new:.2f} (goal >= 0.3)")
    if a.workers > 1:
        from sim.run.parallel import mapper
        with mapper(a.workers) as m:
            studies.sweep_mechanism(base, {"l2": vary["l2"][:2]}, a.samples, mapper=m)     # start the pool
            t0 = time.perf_counter()
            rows2, _ = studies.sweep_mechanism(base, vary, a.samples, mapper=m)
            par = time.perf_counter() - t0
        same = [r.values for r in rows2] == [r.values for r in rows]
        print(f"sweep, batch path on {a.workers} processes: {par:.3f} s ({n / par / 1e6:.2f} M samples/s); ratio to "
              f"one solve: {one / par:.2f}; rows identical to one process: {same}")
    from analytic.solver import batch
    chunk = {kk: np.asarray(v[:studies.DESIGNS_PER_CHUNK]) for kk, v in
             zip(vary, np.meshgrid(*(np.asarray(vary[kk]) for kk in vary), indexing="ij"))}
    chunk = {kk: v.ravel()[:studies.DESIGNS_PER_CHUNK] for kk, v in chunk.items()}
    designs = batch.resolve(base, chunk)
    t = np.linspace(0.0, studies.period_of(base), a.samples + 1)[None, :].repeat(designs.count, 0)
    drive = batch.drive(designs, t)
    want = ["x" + p, "y" + p, "vx" + p, "vy" + p]
    t0 = time.perf_counter()
    batch.solve(designs, *drive, outputs=want)
    solve_part = (time.perf_counter() - t0) * k / designs.count
    print(f"of the sweep, the batch solve alone (numpy kinematics, {designs.count} designs timed, scaled to {k:,}): "
          f"{solve_part:.3f} s = {solve_part / new:.0%} of it; that alone is {solve_part / one:.1f}x the reference "
          f"solve, so the ratio cannot reach {one / solve_part:.2f} on this path")
    if not a.skip_old:
        t0 = time.perf_counter()
        ok = old_sweep(base, vary, a.samples)
        old = time.perf_counter() - t0
        print(f"sweep, one design at a time (before): {old:.3f} s  ({n / old / 1e6:.2f} M samples/s, {ok} valid); "
              f"ratio to one solve: {one / old:.3f}; batch speed-up {old / new:.1f}x")


if __name__ == "__main__":
    main()
