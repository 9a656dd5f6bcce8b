"""A cam's profile of 3600 points in under 50 ms (issue 38): ``analytic.cams.build`` (the pitch curve, the
outline, the pressure angle and the radius of curvature on 3600 cam angles) for a translating roller, an
offset flat face and an oscillating roller follower, and ``analytic.cams.polygon_lift`` (a given outline of
3600 points back to the follower's law, translating roller), in-process.

Run:  python benchmarks/cams.py [--points 3600] [--repeats 20]

Each figure is the least wall time of the repeats after one warm-up. Target: build under 50 ms.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[0] = ROOT                       # the project, not benchmarks/, is ``analytic``


def best(fn, repeats: int) -> float:
    fn()
    out = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return min(out)


def main(argv=None) -> int:
    from analytic import cams, laws
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=3600)
    ap.add_argument("--repeats", type=int, default=20)
    args = ap.parse_args(argv)
    law = laws.Profile(tuple(laws.Segment(s, math.radians(d), r) for s, d, r in
                             (("dwell", 90, 0.0), ("cycloidal", 120, 0.02), ("dwell", 30, 0.0),
                              ("poly345", 120, -0.02))))
    arm = laws.Profile(tuple(laws.Segment(s.shape, s.duration, s.rise * 10) for s in law.segments))
    setups = {
        "translating roller": cams.Setup((0.0, 0.0), "translating", "roller", 0.01, None, 0.03, law,
                                         math.pi / 2, 0.005, (-0.005, 0.0)),
        "offset flat face": cams.Setup((0.0, 0.0), "translating", "flat", 0.0, None, 0.035, law,
                                       math.radians(75), -0.008, (0.0, 0.0)),
        "oscillating roller": cams.Setup((0.0, 0.0), "oscillating", "roller", 0.008, None, 0.025, arm,
                                         arm_pivot=(0.06, 0.045), arm=0.055),
    }
    print(f"cam profile of {args.points} points (least of {args.repeats}):")
    for name, st in setups.items():
        t = best(lambda st=st: cams.build(st, args.points), args.repeats)
        print(f"  build, {name}: {t * 1e3:.2f} ms")
    st = setups["translating roller"]
    outline = cams.build(st, args.points).profile
    t = best(lambda: cams.polygon_lift(st, outline), max(3, args.repeats // 4))
    print(f"  polygon_lift (a given outline of {len(outline)} points -> the law), translating roller: {t * 1e3:.1f} ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
