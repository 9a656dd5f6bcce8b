"""Simulation accuracy against cost, and the recording harness against a bare mj_step loop.

Run:  python benchmarks/simulate.py [--quick]
For each mechanism (the five-bar also at omega4 = 2 omega2), for a few integrators and timesteps, prints
the worst error as a fraction of its tolerance (<= 1 passes; see sim/run/compare.py), the loop violation and
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
from sim.run import compare  # noqa: E402
from sim import model  # noqa: E402
from sim import service  # noqa: E402
from sim.run import simulate  # noqa: E402

CASES = {"fourbar": service.load("fourbar"), "sixbar": service.load("sixbar"), "fivebar": service.load("fivebar"),
         "fivebar w4=2w2": service.load("fivebar", {"omega4": 4 * math.pi}), "jansen": service.load("jansen")}


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
        auto = model.choose_timestep(mech)
        for integrator, factor in settings:
            h = auto * factor
            try:
                built = model.build(mech, model.Settings(h, integrator))
                tr = simulate.simulate(built, 1.0)
            except simulate.SimulationError as exc:
                print(f"{case:<16s} {integrator:<12s} {h * 1e3:7.2f}  failed: {exc}")
                continue
            c = compare.compare(tr, built)
            name, ratio = worst(c)
            cpu = min(tr.cpu_seconds, best_cpu(lambda: simulate.simulate(built, 1.0)))
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
            d.qpos[:], d.qvel[:], d.act[:], d.ctrl[:] = built.qpos0, built.qvel0, built.act0, built.ctrl0
            for _ in range(tr.steps):
                mujoco.mj_step(m, d)

        t_bare = best_cpu(bare, 5)
        t_ours = best_cpu(lambda: simulate.simulate(built, 1.0), 5)
        print(f"{case:<16s} {t_bare * 1e3:15.2f} ms {t_ours * 1e3:12.2f} ms {t_ours / t_bare:6.2f}")


def main() -> None:
    quick = "--quick" in sys.argv
    print(f"MuJoCo {mujoco.__version__}; worst error / tolerance over all outputs (<= 1 passes); steps as "
          f"multiples of the one chosen from the design ({model.STEP_ANGLE} rad per step of the fastest rate)")
    settings = [("rk4", 1.0)] if quick else [
        ("rk4", 0.5), ("rk4", 1.0), ("rk4", 2.0), ("rk4", 5.0), ("implicitfast", 0.25), ("implicitfast", 1.0),
        ("euler", 0.25)]
    study(settings)
    harness()


if __name__ == "__main__":
    main()
