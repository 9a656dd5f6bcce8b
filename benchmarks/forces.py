"""Cost of every joint force of the Jansen leg (7 links, 10 revolutes, a drive, the shaking force and moment)
for 1e6 samples on numpy. Goal (issue 17): <= 1 s.

Reported apart: the kinematics the forces read (positions, accelerations, link angles and rates; numpy, and
the compiled path when numba is there) and the force solve itself (Newton-Euler per Assur group, closed forms,
numpy), each the best of ``--repeats`` runs. Measure on a quiet machine (``uptime``: a load average well below
the number of cores), as timings on a shared one vary by 2x.

    python benchmarks/forces.py [--samples 1000000] [--repeats 3] [--mechanism jansen]
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

# benchmarks/analytic.py would shadow the package of that name: keep this folder off the import path.
sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]

import analytic  # noqa: E402
from analytic import mass  # noqa: E402
from analytic.applications import forces as F  # noqa: E402


def best(fn, repeats: int):
    out, result = math.inf, None
    for _ in range(repeats):
        t0 = time.perf_counter()
        result = fn()
        out = min(out, time.perf_counter() - t0)
    return out, result


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=1_000_000)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--mechanism", default="jansen")
    args = ap.parse_args()
    m = analytic.load(args.mechanism)
    t = np.linspace(0.0, m.duration(1.0), args.samples)
    q, qd, qdd = m.drive(t)
    inertias = mass.model(m)
    want = F.wanted(m)
    m.solve(q[:2000], qd[:2000], qdd[:2000], outputs=want)      # warm up (numba's cache, allocators)
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"{m.name}: {len(m.links)} links, {len(m.joints)} joints, {args.samples:,} samples; load average "
          f"{load:.2f} on {os.cpu_count()} cores")
    os.environ["LINKAGE_JIT"] = "0"
    t_np, sol = best(lambda: m.solve(q, qd, qdd, outputs=want), args.repeats)
    os.environ.pop("LINKAGE_JIT")
    t_jit, _ = best(lambda: m.solve(q, qd, qdd, outputs=want), args.repeats)
    t_f, f = best(lambda: F.solve(m, q, qd, qdd, inertias, (0.0, -9.81), (10.0, 0.0), sol=sol), args.repeats)
    print(f"  kinematics (numpy)            {t_np:7.3f} s")
    print(f"  kinematics (compiled, numba)  {t_jit:7.3f} s")
    print(f"  joint forces (numpy)          {t_f:7.3f} s   ({t_f / args.samples * 1e9:.0f} ns per sample; "
          f"{len(f.joints)} joints, drive, shaking force and moment)")
    print(f"  total on numpy                {t_np + t_f:7.3f} s   (goal: the forces <= 1 s per 1e6 samples)")


if __name__ == "__main__":
    main()
