"""The parts of every library mechanism: layers, the interference check (MuJoCo against the plane test) and
MuJoCo's mesh inertia against the exact parts. Prints per mechanism: (name, layers, collisions, same-layer
pairs, largest |MuJoCo - plane| clearance / size, largest |MuJoCo mass / exact - 1|, the same for I, wall
seconds, CPU seconds).

    python benchmarks/parts.py

The last figure is this process's CPU seconds per mechanism (``time.process_time``), less blurred by other
processes on a shared machine than the wall clock.
"""
import sys
import time
from pathlib import Path

# benchmarks/analytic.py would shadow the package of that name: keep this folder off the import path.
sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]

from sim import service  # noqa: E402
from sim.service import parts as ps  # noqa: E402
rows = []
worst = 0.0
for r in service.list_mechanisms():
    t, c = time.time(), time.process_time()
    m = service.load(r["name"], {})
    pm = ps.prepare(m)
    rep = ps.interference(pm)
    size = pm.mech.size / pm.mech.scale
    d = max([abs(v - rep["min_clearance_geometric"][k]) / size for k, v in rep["min_clearance"].items()] or [0])
    worst = max(worst, d)
    mass = ps.mass_comparison(pm)
    mj = max(abs(v["mujoco"]["m"] / v["parts"]["m"] - 1) for v in mass.values())
    mjI = max(abs(v["mujoco"]["I"] / v["parts"]["I"] - 1) for v in mass.values())
    rows.append((r["name"], pm.layout.count, len(rep["interference"]), len(rep["min_clearance"]), d, mj, mjI, time.time() - t, time.process_time() - c))
    print(rows[-1], flush=True)
print("worst clearance diff / size", worst)
print(f"total CPU {sum(r[-1] for r in rows):.2f} s, wall {sum(r[-2] for r in rows):.2f} s")
