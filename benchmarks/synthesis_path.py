"""Four-bar path synthesis on the literature's targets (collected in KmolYuan/four-bar-rs, see
benchmarks/data/README.md): the reported design's sum of squared distances from the targets to ITS coupler
curve (our evaluator, from its published parameters) against ours, under the reported design's own least
transmission angle (so the reported design is feasible under the constraints ours meets).

    python benchmarks/synthesis_path.py [--cases mkh1,...] [--seeds 1] [--workers 2] [--speedup]
"""

from __future__ import annotations

import argparse
import math
import re
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from analytic.synthesis import path as sp  # noqa: E402
from sim.run.parallel import mapper  # noqa: E402
from sim.front.synth_path_cmd import _mu_min_deg  # noqa: E402

DATA = Path(__file__).parent / "data"
CASES = ("mkh1", "mkh2", "mkh3", "mcgarva", "ullah")


def load(name: str):
    """Targets (M, 2) and the reported design (x, branch) of one case."""
    xy = np.array([[float(v) for v in line.split(",")] for line in (DATA / f"path_{name}.csv").read_text().splitlines()
                   if line.strip() and not line.startswith("#")])
    ron = (DATA / f"path_{name}.refer.ron").read_text().split("*/")[-1]
    kv = dict(re.findall(r"(\w+):\s*([-\w.]+)", ron))
    x, br = sp.from_four_bar_rs(*[float(kv[k]) for k in "p1x p1y a l1 l2 l3 l4 l5 g".split()], kv["stat"])
    return xy, x, br


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument("--seeds", type=int, default=1)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--restarts", type=int, default=4)
    ap.add_argument("--generations", type=int, default=300)
    ap.add_argument("--speedup", action="store_true", help="also run the first case, seed 0, on 1 worker and print the ratio")
    a = ap.parse_args()
    print(f"{'target':8s} {'M':>4s} {'mu_ref':>6s} {'reported':>11s} {'ours(best)':>11s} {'ours/rep':>8s} "
          f"{'mu_ours':>7s} {'time/seed':>9s} {'seed spread':>11s}")
    with mapper(a.workers) as m:
        for name in a.cases.split(","):
            xy, xr, br = load(name)
            t = sp.Target(xy)
            rep = float(np.sum(sp.curve_distance(xr, br, xy)[0] ** 2))
            mu_ref = _mu_min_deg(xr)
            cons = sp.Constraints(mu_min=math.radians(math.floor(mu_ref * 10) / 10), region=8.0)
            res, times = [], []
            for seed in range(a.seeds):
                t0 = time.perf_counter()
                d = sp.synthesize(t, cons, seed=seed, restarts=a.restarts, generations=a.generations,
                                  popsize=100, mapper=m)[0]
                times.append(time.perf_counter() - t0)
                res.append(d)
            best = min(res, key=lambda d: (d.violation > 0, d.sum_sq))
            spread = max(d.sum_sq for d in res) / best.sum_sq - 1
            print(f"{name:8s} {len(xy):4d} {mu_ref:6.1f} {rep:11.5g} {best.sum_sq:11.5g} {best.sum_sq / rep:8.3f} "
                  f"{_mu_min_deg(best.x):7.1f} {np.mean(times):8.1f}s {100 * spread:10.2f}%"
                  + ("" if not best.failed else f"  INFEASIBLE: {best.failed}"), flush=True)
            if a.speedup and name == a.cases.split(",")[0]:
                t0 = time.perf_counter()
                d1 = sp.synthesize(t, cons, seed=0, restarts=a.restarts, generations=a.generations, popsize=100)[0]
                t1 = time.perf_counter() - t0
                same = np.allclose(d1.x, res[0].x, rtol=0, atol=0)
                print(f"  {name}: 1 worker {t1:.1f} s, {a.workers} workers {times[0]:.1f} s: speed-up "
                      f"{t1 / times[0]:.2f}x; identical result: {same}", flush=True)


if __name__ == "__main__":
    main()
