"""``linkage dynamics`` with the file's loads (SPEC "Loads"): the reduced equation carries every load's
generalized force (a damper's as -C(u) w), MuJoCo the same loads (springs and dampers as tendons, the rest as
body wrenches at each step's midpoint), checked against a hand steady state and the energy balance."""

from __future__ import annotations

import json
import math
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

HERE = Path(__file__).parent
FOURBAR = HERE / "mechanisms" / "fourbar_loads.toml"


def linkage(*args):
    return subprocess.run([sys.executable, "-m", "sim", *map(str, args)], capture_output=True, text=True, timeout=600)


def dyn(path, *args):
    r = linkage("dynamics", path, "--json", *args)
    assert r.returncode in (0, 1), r.stderr
    return json.loads(r.stdout)


def test_constant_brake_on_the_crank_sets_the_mean_speed_by_hand(tmp_path):
    # A resisting torque T_L on the crank of a linear motor T0 (1 - w / W0): over a steady turn the motor's work
    # T0 2 pi - (T0 / W0) integral(w dphi) equals 2 pi T_L, so the angle-mean speed is W0 (1 - T_L / T0).
    # SPEC's mean speed (2 pi / the turn's time) is the harmonic mean over the angle, below it by about
    # Cs^2 / 8 (1.3e-5 at Cs = 0.0104); 80 turns at a time constant J W0 / T0 = 1.9 s leave no transient.
    import analytic
    from analytic.applications import motor as am
    from sim.service.loads import dynamics_loads
    from sim.model import Loads
    from sim.run import motor as sm
    body = FOURBAR.read_text()
    text = body[:body.index("[[loads]]")] + textwrap.dedent("""
        [[loads]]
        name = "brake"
        kind = "torque"
        link = "1"
        magnitude = -2.0
        """)
    p = tmp_path / "b.toml"
    p.write_text(text)
    W0 = 300 * 2 * math.pi / 60
    hand = W0 * (1 - 2.0 / 5.0)
    d = sm.dynamics(analytic.load(str(p)), Loads(), am.LinearMotor(5.0, W0), 0.3, None, hand, 80, simulate_too=False)
    r = d.run
    cs = r.fluctuation
    assert 0.005 < cs < 0.02
    assert r.mean_speed == pytest.approx(hand, rel=cs * cs / 8 * 1.5)       # the harmonic-mean offset, bounded
    assert r.mean_speed < hand                                           # ... and of its sign
    assert r.energy_per_cycle == pytest.approx(2.0 * 2 * math.pi, rel=1e-6)  # steady: the motor pays the brake
    table, energy = dynamics_loads(d)
    brake = next(ld for ld in table if ld["name"] == "brake")
    assert brake["work_per_cycle"] == pytest.approx(-2.0 * 2 * math.pi, rel=1e-12)   # a constant torque x a turn
    assert abs(energy["residual"]) < 1e-6 * 4 * math.pi


def test_spring_damper_and_torque_law_agree_with_mujoco_and_balance_energy():
    d = dyn(FOURBAR, "--motor", "5,300rpm", "--flywheel", "0.01", "--revolutions", 5)
    assert d["passed"] is True and d["simulated"]["passed"] is True
    a = d["simulated"]["agreement"]
    # SPEC tolerance of the mean speed (sim.run.motor): measured 3.5e-7 here
    assert a["mean_speed"] <= 1e-4
    w = {ld["name"]: ld["work_per_cycle"] for ld in d["loads"]}
    assert w["s"] == pytest.approx(0.0, abs=1e-9)                     # a spring returns its energy over a turn
    assert w["d"] < -0.1                                              # a damper only takes
    e = d["energy"]
    # motor + loads = kinetic change over the last turn; the damper's integral on 8192 points: ~1e-7 J
    assert abs(e["residual"]) < 1e-6
    assert e["motor_work"] + e["loads_work"] == pytest.approx(e["kinetic_change"], abs=1e-6)


def test_friction_is_refused_in_dynamics_in_one_line(tmp_path):
    p = tmp_path / "f.toml"
    p.write_text(FOURBAR.read_text() + "\n[friction]\nmu = 0.1\npin_radius = 0.005\n")
    r = linkage("dynamics", p, "--motor", "5,300rpm")
    assert r.returncode == 2 and "[friction]" in r.stderr and "planned" in r.stderr and len(r.stderr.strip().splitlines()) == 1, r.stderr
