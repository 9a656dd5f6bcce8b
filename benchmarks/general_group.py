"""Cost per sample of a numerically solved Assur group against a dyad chain of the same size (numpy, N = 1e6).

Two comparisons, each positions + velocities + accelerations of the same number of placed points:

* **mechanism**: ``Mechanism.solve`` on numpy (``LINKAGE_JIT=0``; blocks of 8192 samples, a long run's
  group carrying its solution from block to block) of the library's ``stephenson_ii`` (crank, a point on
  it, the class III triad Q1-Q2-Q3 with its coupler point C: one ``group`` element, 8 unknown coordinates)
  against a six-bar of the same links, joints and placed points written as dyads (crank, the same point,
  RRR Q1, RRR Q2, rigid points Q3 and C on the coupler Q1-Q2), over one crank turn;
* **kernel**: :func:`analytic.solver.general_group.solve_group` on the triad of
  ``tests/test_general_group.py`` (6 unknown coordinates) against three closed-form RRR dyads
  (:func:`analytic.kinds.rrr.rrr`) placing three points, on 1e6-sample arrays.

Goal (issue 16): the group costs at most 10x the chain per sample. Timings are the best of ``--repeats``
runs, wall clock and this process's CPU time; check that the machine is quiet first (``uptime``).

    python benchmarks/general_group.py [--samples 1000000] [--repeats 3]
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
os.environ["LINKAGE_JIT"] = "0"                                        # numpy, as the goal says

import analytic  # noqa: E402
from analytic.solver.general_group import make_group, solve_group  # noqa: E402
from analytic.kinds.base import on_frame  # noqa: E402
from analytic.kinds.rrr import rrr as _rrr  # noqa: E402

Q0 = 0.5
O1, O2 = (4.0, 3.5), (3.5, -0.5)
POSE = dict(A=(math.cos(Q0), math.sin(Q0)), O1=O1, O2=O2, D=(1.5, 2.0), E=(3.0, 2.5), F=(2.6, 1.2))
LINKS = {"2": ("A", "D"), "T": ("D", "E", "F"), "4": ("O1", "E"), "5": ("O2", "F")}

DYADS = """
format = "linkage/1"
name = "stephenson_ii_as_dyads"
units = "mm"
[ground]
G1 = [0, 0]
G2 = [405, -42]
[[inputs]]
kind = "crank"
pivot = "G1"
point = "P1"
length = 100
link = "crank"
omega = "360deg"
[[groups]]
kind = "point"
point = "P2"
on = "crank"
at = [135, -53]
[[groups]]
kind = "RRR"
point = "Q1"
from = ["P1", "G2"]
lengths = [170, 400]
links = ["rod1", "rod3"]
[[groups]]
kind = "RRR"
point = "Q2"
from = ["P2", "Q1"]
lengths = [144, 140]
links = ["rod2", "coupler"]
branch = -1
[[groups]]
kind = "point"
point = "Q3"
on = ["Q1", "Q2"]
at = [60, 200]
[[groups]]
kind = "point"
point = "C"
on = ["Q1", "Q2"]
at = [30, 80]
"""


def best(fn, repeats: int) -> tuple[float, float]:
    """The best wall-clock and CPU (this process) times [s] of ``repeats`` runs of fn; on a shared machine the
    CPU time is the steadier of the two."""
    wall = cpu = math.inf
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        fn()
        wall, cpu = min(wall, time.perf_counter() - t0), min(cpu, time.process_time() - c0)
    return wall, cpu


def mechanisms(n: int, repeats: int) -> tuple[float, float]:
    group = analytic.load("stephenson_ii")
    dyads = analytic.from_text(DYADS, "stephenson_ii_as_dyads")
    assert group.points == dyads.points and len(group.links) == len(dyads.links)
    q = np.linspace(0.0, 2 * math.pi, n)
    for m in (group, dyads):
        assert m.solve(q[::1000], 1.0).valid.all(), m.name
    t_group = best(lambda: group.solve(q, 1.0, 0.0, outputs=()), repeats)
    t_dyads = best(lambda: dyads.solve(q, 1.0, 0.0, outputs=()), repeats)
    return t_group, t_dyads


def kernels(n: int, repeats: int) -> tuple[float, float]:
    q = Q0 + np.linspace(0.0, 0.8, n)          # the triad's assembly range (it locks near Q0 + 0.96)
    qd, qdd = np.full(n, 2.0), np.full(n, 0.5)
    ground = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    g = make_group(LINKS, ("A", "O1", "O2"), ("D", "E", "F"), POSE)

    def crank():
        return on_frame(ground, np.cos(q), np.sin(q), qd, qdd, 1.0, 0.0)

    def triad():
        return solve_group(g, dict(A=crank(), O1=O1 + (0, 0, 0, 0), O2=O2 + (0, 0, 0, 0)))

    fixed1 = tuple(np.full(n, v) for v in O1 + (0, 0, 0, 0))
    fixed2 = tuple(np.full(n, v) for v in O2 + (0, 0, 0, 0))

    def chain():
        A = crank()
        D, _, _ = _rrr(A, fixed1, 3.2, 2.6, 1, mu=False)
        E, _, _ = _rrr(D, fixed2, 2.0, 3.0, 1, mu=False)
        F, _, _ = _rrr(E, fixed1, 1.8, 1.5, -1, mu=False)
        return F

    assert triad().assembled.all(), "the benchmark triad must assemble over its whole range"
    return best(triad, repeats), best(chain, repeats)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=1_000_000)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    n = args.samples
    print(f"numpy {np.__version__}; N = {n}; best of {args.repeats}; position + velocity + acceleration; "
          f"load average {os.getloadavg()[0]:.2f}")
    rows = [("mechanism: stephenson_ii (triad, Mechanism.solve)", "its six-bar as dyads", *mechanisms(n, args.repeats)),
            ("kernel: class III triad (solve_group)", "three RRR dyads (closed form)", *kernels(n, args.repeats))]
    print(f"{'':52s} {'wall':>9s} {'ns/sample':>9s} {'cpu':>9s}")
    for group, chain, (wg, cg), (wc, cc) in rows:
        print(f"{group:52s} {wg:8.3f}s {wg / n * 1e9:9.1f} {cg:8.3f}s")
        print(f"{chain:52s} {wc:8.3f}s {wc / n * 1e9:9.1f} {cc:8.3f}s")
        print(f"{'':52s} ratio group / chain: {wg / wc:.1f}x wall, {cg / cc:.1f}x cpu (goal <= 10x)")


if __name__ == "__main__":
    main()
