"""Simulation accuracy against cost, and the recording harness against a bare mj_step loop.

Run:  python benchmarks/simulate.py [--quick]
For each mechanism (the five-bar also at omega4 = 2 omega2), for a few integrators and timesteps, prints
the worst error as a fraction of its tolerance (<= 1 passes; see sim/compare.py), the loop violation and
the CPU milliseconds per simulated crank revolution; then, at the default settings, the harness
(rollout + reading the outputs) against a bare Python loop of mj_step on the same model.
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import mujoco

# benchmarks/analytic.py would shadow the package of that name: keep this folder off the import path.
sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]
from analytic import FiveBar, FourBar, SixBar  # noqa: E402
from sim import compare, model, simulate  # noqa: E402

CASES = {"fourbar": FourBar(), "sixbar": SixBar(), "fivebar": FiveBar(),
         "fivebar w4=2w2": FiveBar(omega4=4 * math.pi)}


def worst(c) -> tuple[str, float]:
    name = max(c.errors, key=lambda k: c.errors[k]["max"] / c.errors[k]["tol"])
    return name, c.errors[name]["max"] / c.errors[name]["tol"]


def best_cpu(fn, repeats: int = 3) -> float:
    best = math.inf
    for _ in range(repeats):
        t0 = time.process_time()
        fn()
        best = min(best, time.process_time() - t0)
    return best


def study(settings) -> None:
    print(f"{'case':<16s} {'integrator':<12s} {'h [ms]':>7s} {'worst/tol':>10s} {'(output)':<9s} "
          f"{'loop [m]':>9s} {'ms CPU/rev':>10s}")
    for case, mech in CASES.items():
        for integrator, h in settings:
            try:
                built = model.build(mech, h, integrator)
                tr = simulate.simulate(built, 1.0)
            except simulate.SimulationError as exc:
                print(f"{case:<16s} {integrator:<12s} {h * 1e3:7.2f}  failed: {exc}")
                continue
            c = compare.compare(tr, built)
            name, ratio = worst(c)
            cpu = min(tr.cpu_seconds, best_cpu(lambda: simulate.simulate(model.build(mech, h, integrator), 1.0)))
            print(f"{case:<16s} {integrator:<12s} {h * 1e3:7.2f} {ratio:10.3g} {name:<9s} "
                  f"{c.max_loop_violation:9.2e} {cpu * 1e3:10.2f}")


def harness() -> None:
    print("\nharness overhead at the default settings (one revolution, best of 5):")
    print(f"{'case':<16s} {'bare mj_step loop':>18s} {'rollout+record':>15s} {'ratio':>6s}")
    for case, mech in CASES.items():
        built = model.build(mech)
        tr = simulate.simulate(built, 1.0)
        m = built.model

        def bare():
            d = mujoco.MjData(m)
            mujoco.mj_resetDataKeyframe(m, d, m.key("home").id)
            for _ in range(tr.steps):
                mujoco.mj_step(m, d)

        t_bare = best_cpu(bare, 5)
        t_ours = best_cpu(lambda: simulate.simulate(built, 1.0), 5)
        print(f"{case:<16s} {t_bare * 1e3:15.2f} ms {t_ours * 1e3:12.2f} ms {t_ours / t_bare:6.2f}")


def main() -> None:
    quick = "--quick" in sys.argv
    print(f"MuJoCo {mujoco.__version__}; worst error / tolerance over all SPEC outputs (<= 1 passes)")
    settings = [("rk4", 0.002)] if quick else [
        ("rk4", 0.001), ("rk4", 0.002), ("rk4", 0.004), ("rk4", 0.01),
        ("implicitfast", 0.0005), ("implicitfast", 0.002), ("euler", 0.0005),
    ] + ([("discrete", 0.0005), ("discrete", 0.002)] if "discrete" in model.INTEGRATORS else [])
    study(settings)
    harness()


if __name__ == "__main__":
    main()
