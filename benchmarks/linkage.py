"""Throughput of the general solver (any linkage/1 file) on Theo Jansen's leg, against pylinkage.

Run:  python benchmarks/linkage.py [--n 1000000] [--repeats 5] [--no-compile-times]

Position, velocity and acceleration of every point of the leg (analytic/library/jansen.toml: crank,
three RRR dyads and two rigid-triangle points) at N crank angles through ``analytic.load(...).solve``:

* the numpy path (``LINKAGE_JIT=0``; blocks of ``analytic._common.BLOCK`` samples) and the compiled path
  (analytic/solver/jit.py, when numba is installed), each for the points only (``outputs=`` the 48 point
  columns) and for every output (link angles and transmission angles too: 16 more arctan2 per sample);
* pylinkage's numba-compiled ``Linkage.step_fast_with_kinematics`` on the same leg, same dimensions,
  same crank angles (it steps the crank by 2 pi / N per sample), with the same omega and alpha;
* a plain numpy dyad chain: the textbook formulas on whole arrays, no blocks (a baseline).

Prints samples/s (best and median of the repeats, wall clock), the ratios, numba's compile time (a cold
compile in a fresh process with an empty cache, and a warm start from the cache), and checks that all
of them give the same foot path (and every point's rates) at a few crank angles. The machine's load
average is printed too: other processes on a shared machine slow every figure down.
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

# This folder holds a file named like a module (linkage.py): keep it off the import path.
sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]
ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
import analytic  # noqa: E402
from analytic.solver import jit as _jit  # noqa: E402

OMEGA, ALPHA = 2 * math.pi, 1.5          # crank speed [rad/s] and acceleration [rad/s^2] at every sample


def timed(fn, repeats: int) -> tuple[float, float, object]:
    """(best, median) seconds of ``fn()`` over ``repeats`` runs, and the last result."""
    ts, out = [], None
    for _ in range(repeats):
        out = None                                      # free the previous result first
        t0 = time.perf_counter()
        out = fn()
        ts.append(time.perf_counter() - t0)
    ts.sort()
    return ts[0], ts[len(ts) // 2], out


def with_env(name: str, value: str, fn):
    old = os.environ.get(name)
    os.environ[name] = value
    try:
        return fn()
    finally:
        if old is None:
            del os.environ[name]
        else:
            os.environ[name] = old


# -------------------------------------------------------------------------------------- pylinkage
def pylinkage_leg(mech, q0: float, step: float):
    """The same leg in pylinkage: Ground points, a Crank, an RRRDyad per RRR group, a FixedDyad per
    point; each dyad starts at our solution at q0 (pylinkage keeps the nearest intersection)."""
    from pylinkage.actuators import Crank
    from pylinkage.components import Ground
    from pylinkage.dyads import FixedDyad, RRRDyad
    from pylinkage.simulation import Linkage

    start = mech.solve(np.array([q0]))
    nodes, parts, crank = {}, [], None
    for name, (x, y) in mech.geometry.ground.items():
        nodes[name] = Ground(x, y, name=name)
        parts.append(nodes[name])
    for e in mech.geometry.elements:
        p = e["point"]
        if e["kind"] == "crank":
            crank = Crank(nodes[e["pivot"]], e["length"], angular_velocity=step, initial_angle=q0, name=p)
            parts.append(crank)
            nodes[p] = crank.output
        elif e["kind"] == "RRR":
            a, b = e["from"]
            nodes[p] = RRRDyad(nodes[a], nodes[b], *e["lengths"], x=float(start["x" + p][0]),
                               y=float(start["y" + p][0]), name=p)
            parts.append(nodes[p])
        elif e["kind"] == "point":
            a, b = e["on"]
            u, v = e["at"]
            nodes[p] = FixedDyad(nodes[a], nodes[b], math.hypot(u, v), math.atan2(v, u), name=p)
            parts.append(nodes[p])
        else:
            raise ValueError(f"no pylinkage counterpart written here for a {e['kind']} element")
    linkage = Linkage(parts, name=mech.name)
    linkage.set_input_velocity(crank, OMEGA, ALPHA)
    return linkage, [c.name for c in parts]


def run_pylinkage(mech, n: int, q0: float):
    linkage, names = pylinkage_leg(mech, q0, 2 * math.pi / n)
    pos, vel, acc = linkage.step_fast_with_kinematics(iterations=n)
    return names, pos, vel, acc


# ------------------------------------------------------------------------- plain numpy dyad chain
def numpy_chain(mech, q, qd, qdd):
    """Textbook vectorised kinematics on whole arrays: crank; RRR by the law of cosines, its rates from
    the 2x2 systems (C - P).(vC - vP) = 0, (C - Q).(vC - vQ) = 0 and their derivatives; a point in the
    frame of two others. Returns {point: (x, y, vx, vy, ax, ay)}."""
    zero = np.zeros_like(q)
    pts = {g: (zero + x, zero + y, zero, zero, zero, zero) for g, (x, y) in mech.geometry.ground.items()}
    for e in mech.geometry.elements:
        kind = e["kind"]
        if kind == "crank":
            x0, y0 = pts[e["pivot"]][:2]
            r, c, s = e["length"], np.cos(q), np.sin(q)
            pts[e["point"]] = (x0 + r * c, y0 + r * s, -r * s * qd, r * c * qd,
                               -r * (s * qdd + c * qd * qd), r * (c * qdd - s * qd * qd))
        elif kind == "RRR":
            P, Q = pts[e["from"][0]], pts[e["from"][1]]
            a, b = e["lengths"]
            dx, dy = Q[0] - P[0], Q[1] - P[1]
            d = np.hypot(dx, dy)
            along = (a * a - b * b + d * d) / (2 * d)
            h = e["branch"] * np.sqrt(a * a - along * along)
            x = P[0] + (along * dx - h * dy) / d
            y = P[1] + (along * dy + h * dx) / d
            r1x, r1y, r2x, r2y = x - P[0], y - P[1], x - Q[0], y - Q[1]
            det = r1x * r2y - r1y * r2x
            b1, b2 = r1x * P[2] + r1y * P[3], r2x * Q[2] + r2y * Q[3]
            vx, vy = (b1 * r2y - b2 * r1y) / det, (r1x * b2 - r2x * b1) / det
            b1 = r1x * P[4] + r1y * P[5] - ((vx - P[2]) ** 2 + (vy - P[3]) ** 2)
            b2 = r2x * Q[4] + r2y * Q[5] - ((vx - Q[2]) ** 2 + (vy - Q[3]) ** 2)
            pts[e["point"]] = (x, y, vx, vy, (b1 * r2y - b2 * r1y) / det, (r1x * b2 - r2x * b1) / det)
        elif kind == "point":
            P, Q = pts[e["on"][0]], pts[e["on"][1]]
            u, v = e["at"]
            dx, dy = Q[0] - P[0], Q[1] - P[1]
            L2 = dx * dx + dy * dy
            L = np.sqrt(L2)
            c, s = dx / L, dy / L
            w = (dx * (Q[3] - P[3]) - dy * (Q[2] - P[2])) / L2
            al = (dx * (Q[5] - P[5]) - dy * (Q[4] - P[4])) / L2
            rx, ry = u * c - v * s, u * s + v * c
            pts[e["point"]] = (P[0] + rx, P[1] + ry, P[2] - w * ry, P[3] + w * rx,
                               P[4] - al * ry - w * w * rx, P[5] + al * rx - w * w * ry)
        else:
            raise ValueError(f"the baseline does not handle {kind} elements")
    return pts


# ------------------------------------------------------------------------------------ compile time
def compile_seconds(cold: bool) -> str:
    """Seconds to the first compiled solve in a fresh process: with an empty numba cache (cold) or with
    the cache analytic/solver/jit.py keeps next to itself (warm), ``import numba`` included."""
    code = ("import time, numpy as np, analytic; m = analytic.load('fourbar'); t = time.perf_counter(); "
            "m.solve(np.zeros(3)); print(f'{time.perf_counter() - t:.2f}')")
    env = {**os.environ, "LINKAGE_JIT": "1", "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    with tempfile.TemporaryDirectory() as cache:
        if cold:
            env["NUMBA_CACHE_DIR"] = cache
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=ROOT)
    return out.stdout.strip() or (out.stderr.strip().splitlines() or ["?"])[-1]


# ------------------------------------------------------------------------------------------- main
def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1_000_000, help="crank angles (default 1e6)")
    ap.add_argument("--repeats", type=int, default=5, help="runs per figure; best and median are printed")
    ap.add_argument("--no-compile-times", action="store_true", help="skip the fresh-process compile timings")
    args = ap.parse_args()
    n, reps = args.n, args.repeats

    mech = analytic.load("jansen")
    q0, step = 0.3, 2 * math.pi / n
    q = q0 + step * np.arange(1, n + 1)                 # the angles pylinkage visits: it steps, then records
    points = [f"{c}{p}" for p in mech.points for c in ("x", "y", "vx", "vy", "ax", "ay")]
    every = len(with_env("LINKAGE_JIT", "0", lambda: mech.solve(q[:2])))
    print(f"{mech.name}: {len(mech.points)} points ({len(points)} point outputs), {every} outputs in all "
          f"(with the links' cos, sin); N = {n:,} crank angles; omega = {OMEGA:.4f} rad/s, alpha = {ALPHA} rad/s^2")
    print(f"numpy {np.__version__}, BLOCK = {analytic._common.BLOCK}; load average before: "
          f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}; {os.cpu_count()} CPUs")
    rates: dict[str, float] = {}

    def report(label, seconds):
        best, median = seconds
        rates[label] = n / best
        print(f"  {label:<44s} {n / best / 1e6:7.2f} M samples/s   (median {n / median / 1e6:6.2f})")

    # numpy path
    def numpy_solve(outputs):
        return lambda: with_env("LINKAGE_JIT", "0", lambda: mech.solve(q, OMEGA, ALPHA, outputs=outputs))

    print("analytic, numpy path (LINKAGE_JIT=0):")
    b, m, sol_np = timed(numpy_solve(points), reps)
    report("numpy, every point", (b, m))
    b, m, _ = timed(numpy_solve(None), max(2, reps // 2))
    report("numpy, every output", (b, m))

    # compiled path
    sol_jit = None
    if _jit.AVAILABLE:
        import numba
        threads = numba.config.NUMBA_NUM_THREADS
        if not args.no_compile_times:
            print(f"analytic, compiled path (numba {numba.__version__}): first solve in a fresh process: "
                  f"{compile_seconds(True)} s with an empty cache (compile), {compile_seconds(False)} s from "
                  f"the cache")
        else:
            print(f"analytic, compiled path (numba {numba.__version__}):")
        t0 = time.perf_counter()
        with_env("LINKAGE_JIT", "1", lambda: mech.solve(q[:10], OMEGA, ALPHA))
        print(f"  first solve in this process (import numba, load or compile): {time.perf_counter() - t0:.2f} s")

        def jit_solve(outputs, nthreads):
            def run():
                numba.set_num_threads(nthreads)
                return with_env("LINKAGE_JIT", "1", lambda: mech.solve(q, OMEGA, ALPHA, outputs=outputs))
            return run

        b, m, sol_jit = timed(jit_solve(points, threads), reps)
        report(f"compiled, every point, {threads} threads", (b, m))
        if threads > 1:
            b, m, _ = timed(jit_solve(points, 1), reps)
            report("compiled, every point, 1 thread", (b, m))
        b, m, _ = timed(jit_solve(None, threads), max(2, reps // 2))
        report(f"compiled, every output, {threads} threads", (b, m))
        numba.set_num_threads(threads)
    else:
        print("analytic, compiled path: numba not installed (pip install 'linkage[jit]')")

    # plain numpy
    print("plain numpy dyad chain (whole arrays, no blocks):")
    b, m, chain = timed(lambda: numpy_chain(mech, q, OMEGA + 0 * q, ALPHA + 0 * q), max(2, reps // 2))
    report("plain numpy, every point", (b, m))

    # pylinkage
    try:
        import pylinkage
    except ImportError:
        pylinkage = None
        print("pylinkage not installed: no comparison (pip install pylinkage numba)")
    if pylinkage is not None:
        t0 = time.perf_counter()
        run_pylinkage(mech, 10, q0)
        print(f"pylinkage {pylinkage.__version__} step_fast_with_kinematics (numba; first call "
              f"{time.perf_counter() - t0:.2f} s, not counted):")
        b, m, (names, pos, vel, acc) = timed(lambda: run_pylinkage(mech, n, q0), reps)
        report("pylinkage, every point", (b, m))

        # the check: the same foot path (and every point's rates) at a few angles
        foot = mech.output_point
        j = names.index(foot)
        print(f"check at a few crank angles, foot {foot} (pylinkage's crank angle drifts by rounding as it "
              f"accumulates 2 pi / N steps):")
        print(f"  {'q [rad]':>9s} {'x ours':>16s} {'x pylinkage':>16s} {'y ours':>16s} {'y pylinkage':>16s}"
              f" {'|dpos| m':>9s} {'|dvel| m/s':>10s} {'|dacc| m/s2':>11s}")
        for i in np.linspace(0, n - 1, 6).astype(int):
            dp = math.hypot(sol_np["x" + foot][i] - pos[i, j, 0], sol_np["y" + foot][i] - pos[i, j, 1])
            dv = math.hypot(sol_np["vx" + foot][i] - vel[i, j, 0], sol_np["vy" + foot][i] - vel[i, j, 1])
            da = math.hypot(sol_np["ax" + foot][i] - acc[i, j, 0], sol_np["ay" + foot][i] - acc[i, j, 1])
            print(f"  {q[i]:9.5f} {sol_np['x' + foot][i]:16.12f} {pos[i, j, 0]:16.12f} "
                  f"{sol_np['y' + foot][i]:16.12f} {pos[i, j, 1]:16.12f} {dp:9.1e} {dv:10.1e} {da:11.1e}")
        # the same samples at pylinkage's own crank angle (read off its crank pin): the drift removed
        crank = next(e for e in mech.geometry.elements if e["kind"] == "crank")
        pin, pivot = names.index(crank["point"]), names.index(crank["pivot"])
        picks = np.linspace(0, n - 1, 6).astype(int)
        q_pl = np.arctan2(pos[picks, pin, 1] - pos[picks, pivot, 1], pos[picks, pin, 0] - pos[picks, pivot, 0])
        at = with_env("LINKAGE_JIT", "0", lambda: mech.solve(q_pl, OMEGA, ALPHA))
        d = [max(float(np.abs(at[c + foot] - arr[picks, j, i]).max() / np.abs(at[c + foot]).max())
                 for i, c in enumerate(cs))
             for cs, arr in ((("x", "y"), pos), (("vx", "vy"), vel), (("ax", "ay"), acc))]
        print(f"  at pylinkage's own crank angles (these 6 samples): relative differences position {d[0]:.1e}, "
              f"velocity {d[1]:.1e}, acceleration {d[2]:.1e}")
        worst = 0.0
        for k, p in enumerate(names):
            for comp, arr in ((("x", "y"), pos), (("vx", "vy"), vel), (("ax", "ay"), acc)):
                ours = np.stack([sol_np[comp[0] + p], sol_np[comp[1] + p]], axis=-1)
                scale = max(np.abs(ours).max(), 1e-300)
                worst = max(worst, float(np.abs(ours - arr[:, k]).max() / scale))
        print(f"  every point, every sample: max |ours - pylinkage| / max |ours| = {worst:.1e} "
              f"({'OK' if worst < 1e-9 else 'MORE THAN 1e-9'})")
        del pos, vel, acc

    worst_chain = max(float(np.abs(sol_np[c + p] - chain[p][i]).max() / max(np.abs(sol_np[c + p]).max(), 1e-300))
                      for p in mech.points for i, c in enumerate(("x", "y", "vx", "vy", "ax", "ay")))
    print(f"plain numpy vs analytic: max relative difference {worst_chain:.1e}")
    if sol_jit is not None:
        worst_jit = max(float(np.abs(sol_np[c] - sol_jit[c]).max() / max(np.abs(sol_np[c]).max(), 1e-300))
                        for c in points)
        print(f"compiled vs numpy path: max relative difference {worst_jit:.1e}")

    print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    if "pylinkage, every point" in rates:
        ref = rates["pylinkage, every point"]
        print("ratios to pylinkage (best runs, every point):")
        for label, rate in rates.items():
            if label != "pylinkage, every point":
                print(f"  {label:<44s} {rate / ref:6.1f}x")
        best = max(rate for label, rate in rates.items() if label.startswith("compiled, every point")) \
            if any(label.startswith("compiled") for label in rates) else rates["numpy, every point"]
        print(f"target >= 10x pylinkage, every point: {'met' if best >= 10 * ref else 'NOT met'} "
              f"({best / ref:.1f}x)")


if __name__ == "__main__":
    main()
