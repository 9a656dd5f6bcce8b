"""A motion law costs nothing next to the solve (issue 37, item 3): the servo press (``servo_press``: a
slider-crank driven by segments) against the same mechanism at constant speed (its ``segments`` replaced by
``omega = "360deg"``, same duration), in-process, per sample count.

Run:  python benchmarks/motion_laws.py [--samples 361 3600 100000] [--repeats 5] [--clock cpu] [--no-compare]

Three figures per sample count, each the least wall time of the repeats after one warm-up (imports, compiled
kernels): ``drive`` (``Mechanism.drive(t)``: the inputs' q, qd, qdd at t), ``solve_at`` (``drive`` plus the
whole solve, every output) and ``analyze`` (``sim.service.analyze``: the run ``linkage analyze`` makes, its
figures of merit included); and once, ``compare`` (``sim.service.compare``: the MuJoCo run and its checks,
one cycle). Target: the law's ``solve_at``, ``analyze`` and ``compare`` within 20 % of the constant speed's.

Measured (2 shared cores, ``--samples 361 3600 --repeats 40 --clock cpu --no-compare``, two runs each, ms):
before (a loop over the segments, each sample through its shape's closed forms) drive 0.062 / 0.072 at 361
and 0.159 / 0.133 at 3600, solve_at ratio 1.43 / 1.49 and 1.34 / 1.29; after (``analytic.laws.Compiled``:
one search, each sample's polynomial and sine gathered, or a piece's run a slice at a time from 1000
samples on; no jerk unless asked) drive 0.065 / 0.046 and 0.132 / 0.101, solve_at ratio 1.34 / 1.02 and
1.21 / 1.18. The constant speed's drive is 0.012 / 0.020 ms; the law's fixed cost is now ~0.035 ms.

Issue 37 (``--samples 361 3600 100000 --repeats 40 --clock cpu --no-compare``, main at efa21bc and after, two
alternating runs each, load 1.5): before drive 0.040 / 0.040 at 361, 0.085 / 0.086 at 3600, solve_at ratio
1.21 / 1.23 at 361, 1.20 / 1.28 at 3600, 1.12 / 1.15 at 100000; after (each piece as weights on one basis per
sample, 1, u .. u^k, sin, cos: the gather one matrix product and one take, a run one small product; the
wrap in place) drive 0.035 / 0.031 and 0.077 / 0.078, solve_at ratio 1.17 / 1.20, 1.18 / 1.16, 1.07 / 1.09;
analyze 1.15 / 1.12, 1.15 / 1.10, 1.00 / 1.08. The solve after the law's drive costs 10-20 us more than the
same solve after the constant's (its caches: measured with the drives' arrays fixed), so solve_at's gap is
larger than the drives'. benchmarks/RESULTS-2026-12-02.md.
"""

from __future__ import annotations

import argparse
import os
import re
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[0] = ROOT                       # the project, not benchmarks/, is ``analytic``


CLOCK = time.perf_counter
"""The clock the figures are taken on: wall time, or with ``--clock cpu`` this process's CPU time (on a
machine shared with other work, where the wall clock also counts the time others run)."""


def best(fn, repeats: int) -> float:
    fn()
    out = []
    for _ in range(repeats):
        t0 = CLOCK()
        fn()
        out.append(CLOCK() - t0)
    return min(out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, nargs="+", default=[361, 3600, 100_000])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--clock", choices=("wall", "cpu"), default="wall",
                    help="wall time (default) or this process's CPU time (a shared machine)")
    ap.add_argument("--no-compare", action="store_true", help="leave out the MuJoCo compare")
    args = ap.parse_args(argv)
    global CLOCK
    CLOCK = time.process_time if args.clock == "cpu" else time.perf_counter
    import numpy as np

    import analytic
    from analytic.format import linkfile
    from sim import service
    path = os.path.join(ROOT, "analytic", "library", "servo_press.toml")
    text = open(path).read()
    constant = re.sub(r"segments = \[.*?\n\]\n", 'omega = "360deg"\n', text, flags=re.S)
    law = analytic.Mechanism.from_definition(linkfile.parse(text, path))
    const = analytic.Mechanism.from_definition(linkfile.parse(constant, "servo_press (constant speed)"))
    assert law.duration(1.0) == const.duration(1.0) == 1.0
    print(f"{'samples':>8} {'what':>9} {'law [ms]':>10} {'constant [ms]':>14} {'ratio':>7}")
    for n in args.samples:
        t = np.linspace(0.0, 1.0, n)
        rows = (("drive", lambda m: m.drive(t)), ("solve_at", lambda m: m.solve_at(t)),
                ("analyze", lambda m: service.analyze(m, samples=n)))
        for what, fn in rows:
            a = best(lambda: fn(law), args.repeats)
            b = best(lambda: fn(const), args.repeats)
            print(f"{n:>8} {what:>9} {a * 1e3:>10.3f} {b * 1e3:>14.3f} {a / b:>7.2f}")
    if args.no_compare:
        return 0
    a = best(lambda: service.compare(law, 1.0), max(1, args.repeats // 2))
    b = best(lambda: service.compare(const, 1.0), max(1, args.repeats // 2))
    steps = [service.compare(m, 1.0)[1].trajectory.steps for m in (law, const)]
    print(f"{'1 cycle':>8} {'compare':>9} {a * 1e3:>10.3f} {b * 1e3:>14.3f} {a / b:>7.2f}   MuJoCo steps "
          f"{steps[0]} and {steps[1]} (the step follows the peak speed: the law's is 3.3 times the mean)")
    print(f"{'per step':>8} {'compare':>9} {a * 1e3 / steps[0]:>10.4f} {b * 1e3 / steps[1]:>14.4f} "
          f"{a / steps[0] / (b / steps[1]):>7.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
