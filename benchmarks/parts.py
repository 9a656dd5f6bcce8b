"""The parts of every library mechanism: layers, the interference check (MuJoCo against the plane test) and
MuJoCo's mesh inertia against the exact parts. Prints per mechanism: (name, layers, collisions, same-layer
pairs, largest |MuJoCo - plane| clearance / size, largest |MuJoCo mass / exact - 1|, the same for I, seconds).

    python benchmarks/parts.py
"""
import time
from sim import service, parts_service as ps
rows = []
worst = 0.0
for r in service.list_mechanisms():
    t = time.time()
    m = service.load(r["name"], {})
    pm = ps.prepare(m)
    rep = ps.interference(pm)
    size = pm.mech.size / pm.mech.scale
    d = max([abs(v - rep["min_clearance_geometric"][k]) / size for k, v in rep["min_clearance"].items()] or [0])
    worst = max(worst, d)
    mass = ps.mass_comparison(pm)
    mj = max(abs(v["mujoco"]["m"] / v["parts"]["m"] - 1) for v in mass.values())
    mjI = max(abs(v["mujoco"]["I"] / v["parts"]["I"] - 1) for v in mass.values())
    rows.append((r["name"], pm.layout.count, len(rep["interference"]), len(rep["min_clearance"]), d, mj, mjI, time.time() - t))
    print(rows[-1], flush=True)
print("worst clearance diff / size", worst)
