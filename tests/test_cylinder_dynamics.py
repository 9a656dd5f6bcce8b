"""A cylinder drives the linkage by its supply (issue 37, item 5): ``linkage dynamics MECH --pressure P --flow Q``,
the force F(v) = p A (1 - v / v0), v0 = Q / A on the push area, pushing the dump tipper's loaded body from rest
to the end of the stroke. The reduced equation's run against the energy balance written here from the
kinematics alone (the supply's work = the kinetic energy gained + the potential energy gained), and against
MuJoCo's run of the same supply (the command's verdict)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.integrate import simpson

import analytic
from analytic import mass
from analytic.applications import cylinder as C
from tests.cli_runner import run

G = 9.81


def _energy(mech, inertias, s, v):
    """Kinetic and potential energy [J] at length s, speed v: each body's centre and angle from the solver's
    positions and velocities (no reduced mass, no generalized force)."""
    sol = mech.solve(np.array([s]), np.array([v]), 0.0)
    T = V = 0.0
    for link, b in inertias.items():
        o = mech.link_origins[link]
        c, sn = sol["cos" + link][0], sol["sin" + link][0]
        rx, ry = b.cx * c - b.cy * sn, b.cx * sn + b.cy * c
        w = sol["omega" + link][0]
        vx, vy = sol["vx" + o][0] - w * ry, sol["vy" + o][0] + w * rx
        T += 0.5 * b.m * (vx * vx + vy * vy) + 0.5 * b.I * w * w
        V += b.m * G * (sol["y" + o][0] + ry)
    return T, V


def test_the_supplys_work_equals_the_energy_gained():
    mech = analytic.load("dump_tipper")
    e = next(x for x in mech.geometry.elements if x["kind"] == "actuator")
    inertias = mass.model(mech)
    drive = C.supply(e, 200e5, 5e-3)
    r = C.run(mech, inertias, drive, gravity=(0.0, -G))
    assert r.end == "stroke" and r.s[-1] == pytest.approx(e["stroke"][1], rel=1e-9)   # the event's root
    t = np.linspace(0.0, r.t[-1], 40001)
    s, v = r.dense(t)
    work = float(simpson(drive.force(v) * v, x=t))                         # the supply's power over time
    T0, V0 = _energy(mech, inertias, s[0], v[0])
    T1, V1 = _energy(mech, inertias, s[-1], v[-1])
    # the integrator's tolerance 1e-10 and Simpson's rule on 40000 steps through the start's fast rise
    # (measured 7e-11; the trapezoid rule there is off by 4e-7)
    assert work == pytest.approx((T1 - T0) + (V1 - V0), rel=1e-9)
    # and the speed never passes the supply's free speed: its force falls to zero there
    assert 0.0 < r.v.max() < drive.v0


def test_the_supply_is_the_pressure_and_flow_on_the_push_area():
    e = {"name": "tip", "bore": 0.16, "rod": 0.12}
    d = C.supply(e, 200e5, 2e-3)
    # p pi D^2 / 4 = 2e7 x 0.020106193 = 402123.86 N; Q / A = 0.002 / 0.020106193 = 0.0994718 m/s (by hand)
    assert d.F0 == pytest.approx(402123.86, rel=1e-8)
    assert d.v0 == pytest.approx(0.0994718, rel=1e-6)


def test_the_command_agrees_with_mujoco():
    r = run("dynamics", "dump_tipper", "--pressure", "200bar", "--flow", "5L/s", "--gravity", "0,-9.81", "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    sim = out["simulated"]
    assert out["passed"] and sim["agreement"]["s"] <= sim["agreement"]["tol_s"]
    assert out["supply"]["pressure"] == pytest.approx(2e7, rel=1e-15) and out["supply"]["flow"] == pytest.approx(5e-3)
    assert out["analytic"]["end"] == "stroke"
    # MuJoCo ran to the same end of the stroke in the same time, within a step
    assert sim["duration"] == pytest.approx(out["analytic"]["duration"], abs=sim["timestep"])


@pytest.mark.parametrize("args, needle", [
    (("dump_tipper", "--pressure", "200bar"), "--flow"),
    (("dump_tipper", "--flow", "2L/s"), "--pressure"),
    (("fourbar", "--pressure", "200bar", "--flow", "1L/s"), "actuator"),
    (("dump_tipper", "--pressure", "2bar", "--flow", "1L/s", "--gravity", "0,-9.81"), "raise the pressure"),
    (("dump_tipper", "--pressure", "200bar", "--flow", "-1L/s"), "--flow"),
    (("dump_tipper", "--pressure", "200bar", "--flow", "1L/s", "--motor", "2,10"), "--motor"),
])
def test_bad_supplies_are_refused_in_one_line(args, needle):
    r = run("dynamics", *args)
    assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1 and needle in lines[0], lines
