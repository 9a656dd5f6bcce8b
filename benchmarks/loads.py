"""The three answers with loads (issue 27): Newton-Euler per group, the power balance (virtual work) and
MuJoCo, over the library's mechanisms with random loads of every kind -- a force (world or link frame, some
on a stroke), a torque with an expression law, a spring and a damper between a ground point and a link, a
torsion spring and a pin damper at a pin, and Coulomb friction in every joint -- reporting the worst
disagreement of each pair and the kinetostatics' cost per sample.

    python benchmarks/loads.py [--seeds 2] [--samples 145] [--cost-samples 20000] [--no-mujoco]

Tolerances, as the tests state them: the power balance's drive within 1e-8 of its scale (two eliminations
of the same equations, sim.run.forces.IDENTITY_TOL), MuJoCo's joint forces within 1e-4 of the peak
(sim.run.forces.FORCE_TOL).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]

import analytic  # noqa: E402
from analytic import loads as AL  # noqa: E402
from analytic.applications import torque  # noqa: E402
from analytic.kinds import GROUND  # noqa: E402
from analytic.loads import kinetostatics as K  # noqa: E402
from analytic.loads.common import End  # noqa: E402
from analytic.loads.law import Law  # noqa: E402


def random_loads(m, rng):
    """Loads of every kind on random links of ``m`` (SI), sized to the mechanism's inertial forces."""
    size = m.size
    links = list(m.links)
    force = 5.0 * (1 + rng.random())
    out = []
    ln = links[rng.integers(len(links))]
    ang = rng.uniform(0, 2 * math.pi)
    stroke = (0, 1.0) if rng.random() < 0.5 else None
    out.append(AL.force.Force("f", End(ln, rng.uniform(-0.3, 0.6) * size, rng.uniform(-0.2, 0.2) * size),
                              (math.cos(ang), math.sin(ang)), bool(rng.random() < 0.5),
                              Law(1.0, constant=force, stroke=stroke)))
    out.append(AL.torque.Torque("T", links[rng.integers(len(links))],
                                Law(1.0, expression=f"{0.2 * force * size:.6g}*cos(phi1)", crank=True)))
    g = (rng.uniform(-0.5, 0.5) * size, rng.uniform(0.5, 1.0) * size)
    ln2 = links[rng.integers(len(links))]
    e2 = End(ln2, rng.uniform(0, 0.5) * size, 0.0)
    out.append(AL.spring.Spring("k", (End(GROUND, *g), e2), force / size, 0.5 * size))
    out.append(AL.damper.Damper("c", 0.05 * force / size, ends=(End(GROUND, g[0], g[1] + 0.1 * size), e2)))
    pins = [j for j in m.joints if j.kind == "revolute"]
    j = pins[rng.integers(len(pins))]
    out.append(AL.torsion_spring.TorsionSpring("ts", j.point, (j.a, j.b), 0.1 * force * size, 0.0))
    j2 = pins[rng.integers(len(pins))]
    out.append(AL.damper.Damper("pd", 0.01 * force * size, joint=j2.point, links=(j2.a, j2.b)))
    return tuple(out)


def with_friction(m, rng):
    mu = float(rng.uniform(0.02, 0.12))
    r = float(rng.uniform(0.005, 0.02)) * m.size / m.scale
    d = replace(m.definition, friction={"mu": mu, "pin_radius": r})
    return analytic.Mechanism.from_definition(d, m.overrides, m.builtin), mu, r


def one(name, seed, samples, cost_samples, mujoco_too):
    from sim import service
    from sim.model import Loads
    rng = np.random.default_rng(seed)
    m0 = analytic.load(name)
    if len(m0.inputs) != 1 or m0.inputs[0].kind != "crank":
        return None
    m, mu, r = with_friction(m0, rng)
    extra = random_loads(m, rng)
    try:
        run = service.forces_run(m, samples, extra_loads=extra)
    except Exception as exc:                      # a design the force solve refuses (redundant, singular)
        return {"name": name, "seed": seed, "skipped": str(exc).splitlines()[0][:90]}
    loaded, inert = run.loaded, run.inertias
    apps = [a for v in loaded.applications.values() for a in v] + list(loaded.friction_apps)
    Q = K.generalized(m, run.q, loaded.state, apps)
    power = torque.drive_forces(m, run.q, run.qd, run.qdd, inert)
    link = m.inputs[0].link
    ne = loaded.forces.drives[link]
    pb = power[link] - Q[link]
    scale = max(float(np.max(np.abs(ne))), 1e-300)
    out = {"name": name, "seed": seed, "mu": mu, "solves": loaded.iterations,
           "ne_vs_power": float(np.max(np.abs(ne - pb))) / scale,
           "power_residual": run.energy["power_residual"],
           "friction_J": run.energy["friction_dissipated_per_cycle"]}
    t = np.linspace(0.0, m.duration(1.0), cost_samples)
    q, qd, qdd = m.drive(t)
    sol = m.solve(q, qd, qdd, outputs=K.full_wanted(m))
    t0 = time.perf_counter()
    K.solve(m, q, qd, qdd, t, inert, run.loadset, sol=sol)
    out["us_per_sample"] = (time.perf_counter() - t0) / cost_samples * 1e6
    if mujoco_too:
        try:
            s = service.simulated_forces_run(run, None, Loads(extra=extra))
            out["mujoco"] = s.agreement.worst
            out["mujoco_of"] = s.agreement.worst_of
        except Exception as exc:
            out["mujoco"] = float("nan")
            out["mujoco_of"] = str(exc).splitlines()[0][:60]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--samples", type=int, default=145)
    ap.add_argument("--cost-samples", type=int, default=20000)
    ap.add_argument("--no-mujoco", action="store_true")
    args = ap.parse_args()
    names = [p.stem for p in sorted((Path(analytic.__file__).parent / "library").glob("*.toml"))]
    rows = []
    for name in names:
        for seed in range(args.seeds):
            r = one(name, seed, args.samples, args.cost_samples, not args.no_mujoco)
            if r is None:
                continue
            rows.append(r)
            if "skipped" in r:
                print(f"{name:24s} seed {seed}: skipped ({r['skipped']})")
                continue
            mj = f"{r['mujoco']:.1e} ({r['mujoco_of']})" if "mujoco" in r else "-"
            print(f"{name:24s} seed {seed}: NE vs power {r['ne_vs_power']:.1e}, power residual "
                  f"{r['power_residual']:.1e}, MuJoCo {mj}, friction {r['friction_J']:.3g} J in {r['solves']} solves, "
                  f"{r['us_per_sample']:.1f} us/sample")
    done = [r for r in rows if "skipped" not in r]
    print(f"\n{len(done)} runs ({len(rows) - len(done)} skipped): worst NE vs power balance "
          f"{max(r['ne_vs_power'] for r in done):.1e} (tol 1e-8), worst power residual "
          f"{max(r['power_residual'] for r in done):.1e}", end="")
    if not args.no_mujoco:
        mj = [r["mujoco"] for r in done if math.isfinite(r["mujoco"])]
        print(f", worst MuJoCo {max(mj):.1e} of the peak (tol 1e-4) over {len(mj)} runs", end="")
    print(f"; median cost {np.median([r['us_per_sample'] for r in done]):.1f} us per sample (loads, friction "
          f"fixed point and all)")


if __name__ == "__main__":
    main()
