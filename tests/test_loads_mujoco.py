"""MuJoCo carries the file's loads (sim.model.loads: body wrenches each step from the commanded motion):
``forces --simulate`` and ``compare`` agree with the analytic answer with every kind of load and friction,
within the stated tolerances (sim.run.forces.FORCE_TOL, sim.run.compare)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

PRESS = Path(__file__).parent / "mechanisms" / "press_loads.toml"


def linkage(*args):
    return subprocess.run([sys.executable, "-m", "sim", *map(str, args)], capture_output=True, text=True, timeout=600)


def test_forces_simulate_agrees_with_every_load_kind_and_friction():
    # 73 samples put one on each of the rod's reversals (90 and 270 deg): the friction check skips them
    r = linkage("forces", PRESS, "--samples", 73, "--simulate", "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    a = d["simulated"]["agreement"]
    assert d["simulated"]["passed"] is True and a["worst"] <= 1e-4          # FORCE_TOL of the peak joint force
    # the loads are really there: the punch and friction make the peak far above the inertia-only one
    assert a["peak"] > 500.0
    kinds = {ld["name"]: ld["kind"] for ld in d["loads"]}
    assert kinds == {"punch": "force", "ret": "spring", "shock": "damper", "h": "torsion_spring"}
    assert d["friction"]["dissipated_per_cycle"] > 1.0
    pins = [j for j in d["joints"] if j["kind"] == "R"]
    assert all("Mf" in j and len(j["Mf"]) == 73 for j in pins)
    # the energy balance of the analytic answer: drive + loads = friction + dampers + kinetic + springs
    e = d["energy"]
    lhs = e["drive_work"] + e["loads_work"]
    rhs = e["friction_dissipated"] + e["damper_dissipated"] + e["kinetic_change"] + e["spring_change"]
    # the trapezoidal rule over 73 samples of a power with friction's jumps at the reversals: 1e-3 J here
    assert lhs == pytest.approx(rhs, abs=0.02) and abs(e["residual"]) < 0.02
    assert e["power_residual"] < 1e-9                                  # pointwise: rounding only


def test_compare_passes_with_the_loads():
    r = linkage("compare", PRESS)
    assert r.returncode == 0 and "PASSED" in r.stdout, r.stdout + r.stderr
    assert "work balance" in r.stdout


@pytest.mark.parametrize("text", ["--torque", "--force"])
def test_command_line_loads_reach_mujoco(text, tmp_path):
    args = ["--torque", "2@2"] if text == "--torque" else ["--force", "-300,50@C:piston"]
    base = tmp_path / "p.toml"
    body = PRESS.read_text()
    base.write_text(body[:body.index("[[loads]]")])
    r = linkage("forces", base, "--samples", 37, "--simulate", "--json", *args)
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["simulated"]["passed"] is True
    plain = json.loads(linkage("forces", base, "--samples", 37, "--json").stdout)
    # the load changes the drive by far more than the tolerance (it is applied, not dropped): 2 N m on the rod
    # reaches the crank as 2 dphi2/dphi1, up to 2 r / l ~ 0.67 N m
    assert np.max(np.abs(np.array(d["drives"]["phi1"]) - np.array(plain["drives"]["phi1"]))) > 0.5


def test_render_draws_the_punch_at_the_piston_pin():
    # sim.output.load_arrows: every force of the file at its point; the punch is (-500, 0) N at C at every frame
    import analytic
    from sim.model import build
    from sim.output.load_arrows import load_arrows
    m = analytic.load(str(PRESS))
    built = build(m)
    t = np.linspace(0.0, 1.0, 7)
    rows = load_arrows(built, t)
    sol = m.solve(m.drive(t)[0])
    punch = [k for k in range(rows.shape[1]) if np.allclose(rows[:, k, 2:], [-500.0, 0.0], rtol=0, atol=1e-9)]
    assert len(punch) == 1
    k = punch[0]
    assert np.allclose(rows[:, k, 0], sol["xC"], atol=1e-12) and np.allclose(rows[:, k, 1], sol["yC"], atol=1e-12)
