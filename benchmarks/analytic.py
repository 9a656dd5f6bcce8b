"""Throughput of the analytic solvers: samples per second (position + velocity + acceleration).

Run:  python benchmarks/analytic.py
Prints the best of several repeats at N = 1e4 and 1e6 for each mechanism, and, when pylinkage is
installed, its ``step_fast_with_kinematics`` on the same four-bar for the ratio.
"""

from __future__ import annotations

import math
import os
import subprocess
import time

import sys
from pathlib import Path

import numpy as np

# This file is named like the package it measures: keep its own folder off the import path.
sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]
from analytic.closed_forms import fivebar  # noqa: E402
from analytic.closed_forms import fourbar  # noqa: E402
from analytic.closed_forms import sixbar  # noqa: E402


def best_rate(fn, n: int, repeats: int) -> float:
    best = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return n / best


def pylinkage_rate(n: int) -> float | None:
    """pylinkage's numba-compiled ``step_fast_with_kinematics`` on the default four-bar (n steps)."""
    try:
        from pylinkage.mechanism.factories import fourbar as pl_fourbar
    except ImportError:
        return None
    m = fourbar.FourBar()
    mech = pl_fourbar(m.l1, m.l2, m.l3, m.l4, omega=2 * math.pi / n)
    mech.set_input_velocity(mech._driver_links[0], m.omega1)
    mech.step_fast_with_kinematics(iterations=1000)             # compile outside the timing
    t0 = time.perf_counter()
    mech.step_fast_with_kinematics(iterations=n)
    return n / (time.perf_counter() - t0)


def default_allocator_rate() -> str:
    """The four-bar at N = 1e6 in a fresh process with LINKAGE_MALLOPT=0 (glibc's default thresholds)."""
    code = ("import math, numpy as np, time; from analytic import fourbar; m = fourbar.FourBar(); "
            "x = np.random.default_rng(0).uniform(-3, 3, 1_000_000); b = 1e9\n"
            "for _ in range(5):\n t = time.perf_counter(); fourbar.solve(m, x, 2 * math.pi); "
            "b = min(b, time.perf_counter() - t)\nprint(f'{1e6 / b / 1e6:.2f}')")
    env = {**os.environ, "LINKAGE_MALLOPT": "0"}
    root = str(Path(__file__).resolve().parent.parent)
    env["PYTHONPATH"] = root + os.pathsep + env.get("PYTHONPATH", "")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=root)
    return out.stdout.strip() or out.stderr.strip().splitlines()[-1]


def main() -> None:
    rng = np.random.default_rng(0)
    print(f"numpy {np.__version__}; best of repeats; samples/s (position + velocity + acceleration)")
    for n in (10_000, 1_000_000):
        phi = rng.uniform(-math.pi, math.pi, n)
        phi4 = rng.uniform(-math.pi, math.pi, n)
        w = np.full(n, 2 * math.pi)
        reps = 20 if n < 100_000 else 5
        cases = {
            "fourbar": lambda: fourbar.solve(fourbar.FourBar(), phi, w),
            "sixbar": lambda: sixbar.solve(sixbar.SixBar(), phi, w),
            "fivebar complex": lambda: fivebar.solve(fivebar.FiveBar(), phi, phi4, w, w),
            "fivebar matrix": lambda: fivebar.solve(fivebar.FiveBar(), phi, phi4, w, w, method="matrix"),
        }
        for name, fn in cases.items():
            print(f"N={n:>9,d}  {name:<16s} {best_rate(fn, n, reps) / 1e6:8.2f} M samples/s")
    from analytic.applications import studies
    vary = {"l2": [float(v) for v in np.linspace(0.03, 0.09, 100)],
            "l4": [float(v) for v in np.linspace(0.04, 0.10, 100)]}
    t0 = time.perf_counter()
    rows, _ = studies.sweep(fivebar.FiveBar(), vary, samples=360)
    print(f"five-bar sweep, 10,000 parameter sets x 360 samples (positions + velocities): "
          f"{time.perf_counter() - t0:.2f} s, {sum(r.valid for r in rows)} valid")
    ours = best_rate(lambda: fourbar.solve(fourbar.FourBar(), phi, w), 1_000_000, 5)
    print(f"fourbar N=1e6 with glibc's default malloc thresholds (LINKAGE_MALLOPT=0): "
          f"{default_allocator_rate()} M samples/s")
    ref = pylinkage_rate(1_000_000)
    if ref is None:
        print("pylinkage not installed: no ratio (pip install pylinkage numba to compare)")
    else:
        print(f"pylinkage step_fast_with_kinematics, N=1e6: {ref / 1e6:.2f} M samples/s; "
              f"our four-bar at N=1e6: {ours / 1e6:.2f} M samples/s = {ours / ref:.1f}x")


if __name__ == "__main__":
    main()
