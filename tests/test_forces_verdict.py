"""The verdict of ``linkage forces --simulate`` (and of compare's joint-force check) on both sides of each of
its bounds (issue 32: a loosened tolerance slipped through; no test put a value just outside a bound).

MuJoCo's side of a real run is replaced by the analytic forces with ONE quantity moved by 1 % less, then 1 %
more, than its bound: the verdict must read PASS, then FAIL. The bounds are written here from the documented
rule (sim/run/forces.py, docs/reference.md): every joint force within FORCE_TOL = 1e-4 of the run's peak joint force, a
guide's couple, a gear pair's moment and the shaking moment within 1e-4 of the peak force times the size L,
a drive within 1e-4 of max(its own peak, peak force x L) (a slider's drive: of max(its peak, the peak force)),
the Newton-Euler drive against the power balance within 1e-8 of that drive scale, and the peak never taken
below the floor 1e-3 x (sum of the link masses) x L x (2 pi / s)^2 for a crank (its one turn per second).
The scales are computed here from the analytic forces, not read from the verdict.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import analytic
from analytic import mass
from sim import service
from sim.model import Loads, Settings, build
from sim.run import forces as SF
from sim.run.simulate import simulate

import cli_runner  # the command in this process (tests/cli_runner.py)

KINDS = Path(__file__).parent / "kinds"
TOL = 1e-4           # the documented joint-force bound (docs/reference.md, sim/run/forces.py), written here, not imported
IDENTITY = 1e-8      # the documented Newton-Euler vs power-balance bound
FLOOR = 1e-3         # the documented floor: of sum(m) L Omega_ref^2
EPS = 0.01           # how far inside / outside each bound the doctored value sits (relative)
SIDES = [1 - EPS, 1 + EPS]


def _load(name):
    return analytic.load(str(KINDS / name)) if name.endswith(".toml") else analytic.load(name)


@pytest.fixture(scope="module", params=["fourbar", "slider_crank", "gear.toml"])
def case(request):
    """A real one-turn run: the mechanism, the analytic forces at its simulated inputs, the power balance."""
    mech = _load(request.param)
    built = build(mech, Settings(), Loads(), 1.0)
    tr = simulate(built, 1.0)
    steps = SF.spread(len(tr.t))
    an, _, power = SF.analytic_at(built, tr, steps)
    floor = SF.joint_floor(built)
    peak = float(np.max(np.hypot(an.F[:, 0], an.F[:, 1])))
    assert floor < 0.01 * peak        # at the default speed the floor does not bind (documented: peaks >= 0.26)
    return mech, an, power, floor, peak


def _copy(f):
    return replace(f, F=f.F.copy(), couples={k: v.copy() for k, v in f.couples.items()},
                   drives={k: v.copy() for k, v in f.drives.items()}, couplings=f.couplings.copy(),
                   shaking=f.shaking.copy())


def _verdict(mech, mj, an, power, floor):
    return SF.agreement(mech, mj, an, {k: np.asarray(v) for k, v in power.items()}, None, floor)


def test_the_undoctored_copy_passes(case):
    mech, an, power, floor, _ = case
    a = _verdict(mech, _copy(an), an, power, floor)
    assert a.passed and a.worst == 0.0


@pytest.mark.parametrize("side", SIDES)
def test_a_joint_force_just_inside_passes_and_just_outside_fails(case, side):
    mech, an, power, floor, peak = case
    for k in range(len(an.joints)):           # every joint, at a sample in the middle, at an oblique angle
        mj = _copy(an)
        n = mj.F.shape[-1] // 2
        e = side * TOL * peak
        mj.F[k, 0, n] += e * 0.6
        mj.F[k, 1, n] -= e * 0.8
        a = _verdict(mech, mj, an, power, floor)
        assert a.passed is (side < 1), (an.joints[k].name, a.worst, a.worst_of)
        assert a.worst == pytest.approx(side * TOL, rel=1e-6)    # rounding of F + e - F at |F| ~ peak


@pytest.mark.parametrize("side", SIDES)
def test_a_guide_couple_just_inside_passes_and_just_outside_fails(case, side):
    mech, an, power, floor, peak = case
    if not an.couples:
        pytest.skip("no prismatic pair")
    for k in an.couples:
        mj = _copy(an)
        mj.couples[k][3] -= side * TOL * peak * mech.size
        assert _verdict(mech, mj, an, power, floor).passed is (side < 1)


@pytest.mark.parametrize("side", SIDES)
def test_a_drive_just_inside_passes_and_just_outside_fails(case, side):
    mech, an, power, floor, peak = case
    for inp in mech.inputs:
        own = float(np.max(np.abs(an.drives[inp.link])))
        scale = max(own, peak * (mech.size if inp.angular else 1.0))
        mj = _copy(an)
        mj.drives[inp.link][-1] += side * TOL * scale
        assert _verdict(mech, mj, an, power, floor).passed is (side < 1), inp.q


@pytest.mark.parametrize("side", SIDES)
def test_the_power_balance_just_inside_passes_and_just_outside_fails(case, side):
    mech, an, power, floor, peak = case
    for inp in mech.inputs:
        own = float(np.max(np.abs(an.drives[inp.link])))
        scale = max(own, peak * (mech.size if inp.angular else 1.0))
        p = {k: np.array(v, dtype=float) for k, v in power.items()}
        p[inp.link] = np.asarray(an.drives[inp.link], dtype=float).copy()    # the identity exact but for one sample
        for other in p:
            if other != inp.link:
                p[other] = np.asarray(an.drives[other], dtype=float).copy()
        p[inp.link][2] += side * IDENTITY * scale
        a = _verdict(mech, _copy(an), an, p, floor)
        assert a.passed is (side < 1), (inp.q, a.identity)


@pytest.mark.parametrize("side", SIDES)
def test_a_gear_moment_just_inside_passes_and_just_outside_fails(case, side):
    mech, an, power, floor, peak = case
    if not an.couplings.shape[0]:
        pytest.skip("no gear pair")
    mj = _copy(an)
    mj.couplings[0, 5] += side * TOL * peak * mech.size
    assert _verdict(mech, mj, an, power, floor).passed is (side < 1)


@pytest.mark.parametrize("side", SIDES)
@pytest.mark.parametrize("row", [0, 1, 2])
def test_the_shaking_force_and_moment_just_inside_pass_and_just_outside_fail(case, side, row):
    mech, an, power, floor, peak = case
    mj = _copy(an)
    mj.shaking[row, 7] += side * TOL * peak * (mech.size if row == 2 else 1.0)
    assert _verdict(mech, mj, an, power, floor).passed is (side < 1)


# ---------------------------------------------------------------------------------------------- the floor
@pytest.fixture(scope="module")
def slow():
    """The four-bar at 0.01 turn/s: its joint forces (all inertial) fall 1e4-fold, under the floor."""
    mech = service.load("fourbar", {"omega1": 2 * math.pi * 0.01})
    built = build(mech, Settings(), Loads(), 1.0)
    tr = simulate(built, 1.0)
    an, _, power = SF.analytic_at(built, tr, SF.spread(len(tr.t)))
    m = sum(b.m for b in mass.model(mech).values())
    floor = FLOOR * m * mech.size * (2 * math.pi) ** 2
    return mech, an, power, SF.joint_floor(built), floor


def test_the_floor_is_the_reference_speeds_inertial_force(slow):
    mech, an, _, floor, expected = slow
    assert floor == pytest.approx(expected, rel=1e-9)       # the model's masses are the mass model's (rounding)
    # the peak (0.45 of sum(m) L Omega^2 at one turn per second, 1e-4 of that here) is 1/20 of the floor
    assert float(np.max(np.hypot(an.F[:, 0], an.F[:, 1]))) < 0.1 * expected


@pytest.mark.parametrize("side", SIDES)
def test_a_slow_runs_joint_force_is_judged_against_the_floor(slow, side):
    mech, an, power, floor, expected = slow
    mj = _copy(an)
    mj.F[1, 0, 10] += side * TOL * expected
    assert _verdict(mech, mj, an, power, floor).passed is (side < 1)


# --------------------------------------------------------------------------------- through the command
@pytest.mark.parametrize("side", SIDES)
def test_linkage_forces_simulate_exits_1_just_outside_the_bound(monkeypatch, side):
    """``linkage forces fourbar --simulate``: MuJoCo's measurement replaced by the analytic forces with the
    crank pin's force moved by side x 1e-4 of the peak: PASSED and exit 0 inside, FAILED and exit 1 outside."""
    def doctored(built, tr, steps):
        an, _, _ = SF.analytic_at(built, tr, steps)
        out = _copy(an)
        peak = float(np.max(np.hypot(an.F[:, 0], an.F[:, 1])))
        out.F[0, 1, len(steps) // 3] += side * TOL * peak
        return out
    monkeypatch.setattr(SF, "measure", doctored)
    p = cli_runner.run("forces", "fourbar", "--simulate", "--samples", "73")
    assert p.returncode == (0 if side < 1 else 1), p.stderr
    assert ("PASSED" if side < 1 else "FAILED") in p.stdout
