"""How many times a ``compare`` solves the mechanism, and its CPU time (issue 30, item 2: the motion solved
once, as a :class:`analytic.cycle.Cycle`).

Run:  python benchmarks/cycle.py [NAME ...] [--repeats 2]

The default names include three compares over an input range (RANGED: ``NAME@LO:HI``), whose run's checks
search the dead points beyond the range.

Each compare runs in this process through the command line (``sim.front.cli.main(["compare", NAME])``) with
``analytic.mechanism.Mechanism.solve`` wrapped by a counter keyed by its caller (the first frame outside the
solver), after one warm-up compare of the same mechanism (imports, compiled kernels and the change-point
schedule's cache are paid there); the CPU figure is ``time.process_time`` of the counted run, the least of
the repeats. Targets (issue 30): at most 3 solves per compare; a numerically solved group's compare
(``stephenson_ii``, ``double_butterfly``) at most 2 s of CPU.
"""

from __future__ import annotations

import argparse
import collections
import contextlib
import io
import os
import sys
import time
import traceback

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[0] = ROOT                       # the project, not benchmarks/analytic.py, is ``analytic``

DEFAULT = ("fourbar", "stephenson_ii", "double_butterfly", "jansen")
NUMERIC = {"stephenson_ii", "double_butterfly"}
RANGED = {                                  # compare --input-range: the dead-point search reads the cycle too
    "double_rocker@45:100deg": ["fourbar", "--set", "l1=0.2", "--set", "l3=0.1", "--input-range", "45deg:100deg"],
    "fourbar@10:80deg": ["fourbar", "--input-range", "10deg:80deg"],
    "stephenson_ii@10:80deg": ["stephenson_ii", "--input-range", "10deg:80deg"],
}


@contextlib.contextmanager
def counting():
    """Count ``Mechanism.solve`` calls by caller ("module:function") while the block runs."""
    from analytic.mechanism import Mechanism
    counts: collections.Counter = collections.Counter()
    original = Mechanism.solve

    def solve(self, *a, **k):
        frames = traceback.extract_stack(limit=8)[:-1]
        caller = next((f for f in reversed(frames) if not f.filename.endswith("analytic/mechanism.py")), frames[-1])
        path = os.path.relpath(caller.filename, ROOT)
        counts[f"{path}:{caller.name}"] += 1
        return original(self, *a, **k)

    Mechanism.solve = solve
    try:
        yield counts
    finally:
        Mechanism.solve = original


def compare(name: str) -> int:
    from sim.front.cli import main
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        return main(["compare", *RANGED.get(name, [name])])




def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", default=list(DEFAULT) + list(RANGED),
                    help=f"library names, or a ranged compare: {', '.join(RANGED)}")
    ap.add_argument("--repeats", type=int, default=2)
    args = ap.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; least CPU of {args.repeats} runs "
          f"after a warm-up")
    failed = False
    for name in args.names:
        rc = compare(name)                                     # warm-up
        best, counts = float("inf"), None
        for _ in range(args.repeats):
            with counting() as c:
                t0 = time.process_time()
                rc = compare(name)
                cpu = time.process_time() - t0
            best, counts = min(best, cpu), c
        solves = sum(counts.values())
        target = 2.0 if name.split("@")[0] in NUMERIC else None
        verdict = [f"solves {'met' if solves <= 3 else 'MISSED'} (<= 3)"]
        if target is not None:
            verdict.append(f"CPU {'met' if best <= target else 'MISSED'} (<= {target:g} s)")
        failed |= solves > 3 or (target is not None and best > target) or rc != 0
        print(f"{name:<24s} {solves:3d} solves  {best:6.3f} s CPU  exit {rc}  " + "; ".join(verdict))
        for caller, n in counts.most_common():
            print(f"    {n:3d}  {caller}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
