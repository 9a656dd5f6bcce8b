"""The motion solved once (analytic.cycle.Cycle, issue 30 item 2): what the cycle holds, checked against the
mechanism's geometry by finite differences, and how many times a compare solves the mechanism (a structural
count of Mechanism.solve calls, not a timing)."""

from __future__ import annotations

import collections
import contextlib
import math
import traceback
from pathlib import Path

import numpy as np
import pytest

import analytic
from analytic import ParameterError
from analytic.cycle import Cycle
from analytic.mechanism import Mechanism
from sim import service


@contextlib.contextmanager
def counted():
    """Count Mechanism.solve calls by what they were made for: ``cycle`` (in Cycle.of), ``prepare`` (the run's
    checks, outside the cycle), ``model`` (sim.model, the model builder), ``run`` (sim.run, the comparison)."""
    counts: collections.Counter = collections.Counter()
    original = Mechanism.solve

    def solve(self, *a, **k):
        stack = traceback.extract_stack()
        names = [(f.filename.replace("\\", "/"), f.name) for f in stack]
        if any(path.endswith("analytic/cycle.py") and fn == "of" for path, fn in names):
            counts["cycle"] += 1
        elif any(path.endswith("sim/service/simulation.py") and fn == "prepare_run" for path, fn in names):
            counts["prepare"] += 1
        elif any("/sim/model/" in path for path, _ in names):
            counts["model"] += 1
        elif any("/sim/run/" in path for path, _ in names):
            counts["run"] += 1
        else:
            counts["other"] += 1
        q = a[0] if a else k.get("q")
        if np.shape(q) and np.shape(q)[0] > 1000:      # a scan (a golden-section step solves a few values)
            counts["scans"] += 1
        return original(self, *a, **k)

    Mechanism.solve = solve
    try:
        yield counts
    finally:
        Mechanism.solve = original


@pytest.mark.parametrize("name, cycle", [("fourbar", 1), ("jansen", 1), ("stephenson_ii", 2), ("double_butterfly", 2)])
def test_a_compare_solves_the_mechanism_at_most_three_times(name, cycle):
    # The run's checks (prepare) read the cycle; their one solve, where there is one, is the change points'
    # scan of the turn (dyads), which the cycle then reads its rate peaks from (one solve: the refined grid);
    # a numerically solved group has no such scan: its cycle solves a dense grid, then the refined one. The
    # model builder solves nothing (it reads the cycle); the comparison solves the simulated inputs once
    # (its drive and joint forces read that solve too).
    mech = service.load(name)
    with counted() as n:
        _, c = service.compare(mech, 1.0)
    assert c.passed
    assert n["cycle"] == cycle, n
    assert n["model"] == 0, n
    assert n["run"] == 1, n
    assert n["other"] == 0, n
    assert sum(v for k, v in n.items() if k != "scans") <= 3, n


@pytest.mark.parametrize("name, slow_stroke", [("jansen", False), ("sixbar", True)])
def test_the_model_builder_never_solves_when_handed_a_cycle(name, slow_stroke):
    # (a load on the slow stroke only: the stroke is found from the cycle's samples too)
    from sim.model import Loads, build
    mech = service.load(name)
    cycle = Cycle.of(mech, 1.0)
    loads = Loads(force=(-500.0, 0.0), slow_stroke_only=True) if slow_stroke else Loads()
    with counted() as n:
        built = build(mech, loads=loads, cycle=cycle)
    assert not n, n
    # and what it read is the pose at t = 0: the output point's site where the solver puts it
    import mujoco
    data = mujoco.MjData(built.model)
    data.qpos[:] = built.qpos0
    mujoco.mj_forward(built.model, data)
    p = mech.output_point
    sol = mech.solve(*mech.drive([0.0]))
    site = data.site(p).xpos[:2]
    assert math.hypot(site[0] - sol["x" + p][0], site[1] - sol["y" + p][0]) <= 1e-9 * mech.size   # rounding


def test_the_cycle_spans_a_period_or_the_whole_run():
    fourbar = service.load("fourbar")
    c = Cycle.of(fourbar, 3.0)                       # constant speed: one turn repeats, one turn is solved
    assert c.t[0] == 0.0 and c.t[-1] == pytest.approx(fourbar.duration(1.0), rel=1e-12)   # rounding
    assert np.all(np.diff(c.t) > 0)
    accelerating = service.load("fourbar", {"alpha1": 3.0})
    c = Cycle.of(accelerating, 5.0)                  # it speeds up: every turn differs, the run is solved
    assert c.t[-1] == pytest.approx(accelerating.duration(5.0), rel=1e-12)                # rounding
    turned = c.q[-1, 0] - c.q[0, 0]
    assert turned == pytest.approx(5 * 2 * math.pi, rel=1e-12)                              # rounding


def test_the_refinement_gathers_at_the_peak_between_dense_samples():
    # Whitworth with the lever pivot 0.2 mm inside the 150 mm crank circle: the lever's speed peaks at
    # r omega / (r - c) (hand geometry) when the crank pin passes closest to the pivot, a peak ~1 mrad of
    # crank angle wide that the dense 0.5 deg grid straddles.
    mech = service.load("whitworth", {"c": 149.8, "phi1_0": 0.0043})
    c = Cycle.of(mech, 1.0)
    q = c.q[c.refined, 0]
    assert len(q) > 0
    r = c.rates()
    k = int(np.nanargmax(r.max(axis=1)))
    assert c.refined[k]                              # the fastest sample is a refined one
    peak = 2 * math.pi * 150 / 0.2
    assert float(r[k].max()) == pytest.approx(peak, rel=1e-3)     # the sample itself within 0.1 % of the top
    dense = c.rates()[c.dense].max()
    assert dense < 0.9 * peak                        # the dense grid alone misses it by > 10 % (why it is refined)


@pytest.mark.parametrize("name", ["fourbar", "fivebar", "stephenson_ii", "slider_crank"])
def test_the_velocity_coefficients_are_the_derivatives_of_the_positions(name):
    # Each input's coefficient of a point's velocity is d(position)/d(input): central differences of the
    # positions solved at q +- e (the others held) agree to O(e^2) (e = 1e-5 rad or 1e-5 of the size).
    mech = service.load(name)
    c = Cycle.of(mech, 1.0)
    idx = c.dense[:: max(1, len(c.dense) // 40)]
    for j, inp in enumerate(mech.inputs):
        e = 1e-5 * (1.0 if inp.kind == "crank" else mech.size)
        step = np.zeros(len(mech.inputs))
        step[j] = e
        plus = mech.solve(c.q[idx] + step)
        minus = mech.solve(c.q[idx] - step)
        for p in mech.points:
            for axis in "xy":
                fd = (plus[axis + p] - minus[axis + p]) / (2 * e)
                got = c.coefficients[j]["v" + axis + p][idx]
                scale = max(1e-12, float(np.max(np.abs(fd))))
                # 1e-6 of the largest: the differences' truncation (e^2 ~ 1e-10) and rounding (1e-16 / e)
                assert np.max(np.abs(got - fd)) <= 1e-6 * max(scale, mech.size), (name, p, axis)


def test_a_singular_pose_in_the_turn_is_still_refused_from_the_cycles_scan(tmp_path):
    # A parallelogram (l1 = l3 = 0.1, l2 = l4 = 0.3) whose dyad is declared to switch form at its change points
    # (change = -1): by hand its links align where the crank lies along the ground line, phi1 = 0 and 180 deg;
    # the run's check reads the cycle's scan of the turn and names the first, 180 deg (the run starts 1 deg
    # past 0 deg, so 180 deg comes first), the same as its own scan did.
    text = (Path(analytic.__file__).parent / "library" / "fourbar.toml").read_text()
    text = text.replace('branch = "branch"', 'branch = "branch"\nchange = -1')
    path = tmp_path / "switching.toml"
    path.write_text(text)
    mech = analytic.load(str(path), l1=0.1, l3=0.1, phi1_0=math.radians(1.0))
    with counted() as n, pytest.raises(ParameterError, match=r"passes a change point at phi1=180\.00deg"):
        service.prepare(mech, 1.0)
    assert n["scans"] == 2 and n["cycle"] == 2, n   # the cycle's two (dense, refined): the turn is not scanned again


PRESS = Path(__file__).parent / "mechanisms" / "press_loads.toml"


def test_a_file_with_loads_and_friction_is_solved_four_times_by_compare():
    # press_loads.toml: a punch, a spring, a damper, a torsion spring and friction in every joint. The model
    # builder reads the loads' share of the drives from the cycle (nothing solved: it solved the mechanism 10
    # times before); the run solves the commanded pose at every step once for the loads' wrenches (MuJoCo
    # gets them as xfrc_applied; the run's checks read them again from the model), and the simulated inputs
    # once (compare's, read by the drive forces, the loads' virtual work and the joint forces). Measured: 4.
    mech = analytic.load(str(PRESS))
    with counted() as n:
        _, c = service.compare(mech, 1.0)
    assert c.passed
    assert n["cycle"] == 2 and n["run"] == 1, n
    assert n["model"] == 1, n                      # the commanded wrenches, once (sim.model.loads.wrenches)
    assert n["other"] == 0, n
    assert sum(v for k, v in n.items() if k != "scans") <= 4, n


def test_forces_simulate_hands_its_cycle_to_the_model():
    # The simulated half of `forces --simulate` (the analytic forces run's own checks are counted apart):
    # the cycle (two solves), the loads' commanded wrenches at the steps, one solve at the simulated inputs
    # for the kinetostatics, the loads' virtual work and the power balance. Before: 13 (the time step's
    # choice and the builder each made their own cycle; the builder solved the loads twice).
    mech = analytic.load(str(PRESS))
    run = service.forces_run(mech, 73)
    with counted() as n:
        s = service.simulated_forces_run(run)
    assert s.agreement.passed
    assert n["cycle"] == 2 and n["model"] == 1 and n["run"] == 1 and n["other"] == 0, n


def test_export_builds_from_one_cycle_with_the_files_loads():
    mech = analytic.load(str(PRESS))
    with counted() as n:
        xml = service.export_mjcf(mech)
    assert "<mujoco" in xml
    assert n["cycle"] == 2 and sum(n.values()) - n["scans"] == 2, n     # before: 2 + 5 in the model builder


def test_dynamics_builds_both_models_from_one_cycle():
    # `dynamics` builds the prescribed-motion model (the mass model MuJoCo has) and the motor-driven one:
    # both, and the time step, from the service's one cycle of the prescribed motion (before: a cycle per
    # build and one for the time step, 4 Cycle.of); the reduced equation's own terms are solved in sim.run
    # (2 for a four-bar without loads). The app's split run (the reduced equation, the step bound, then
    # MuJoCo) hands the same cycle to each part.
    from analytic.applications import motor as amotor
    from sim.model import Loads
    from sim.service import dynamics as sdyn
    mech = service.load("fourbar")
    motor = amotor.LinearMotor(2.0, 20.0)
    with counted() as n:
        d = sdyn.dynamics(mech, Loads(), motor, 0.01, revolutions=3)
    assert d.passed
    assert n["cycle"] <= 2 and n["model"] == 0 and n["other"] == 0 and n["run"] <= 2, n
    with counted() as n:
        cycle = sdyn.cycle_of(mech)
        d = sdyn.dynamics(mech, Loads(), motor, 0.01, revolutions=3, simulate_too=False, cycle=cycle)
        assert sdyn.motor_timestep(d, cycle) > 0
        d = sdyn.simulated(d, Loads(), cycle=cycle)
    assert d.passed
    assert n["cycle"] <= 2 and n["model"] == 0 and n["other"] == 0 and n["run"] <= 2, n


def test_dynamics_with_loads_solves_each_grid_once():
    # fourbar_loads.toml: a spring and a damper (MuJoCo tendons in the motor run) and a torque (not a tendon).
    # The reduced equation's load terms solve the turn's grid and its midpoints once each (the loads' virtual
    # work reads that solve's velocities, exact at the unit rate: before, one more solve per load and grid,
    # 10 in all); the mass terms two more. MuJoCo's motor run evaluates the torque at each step's midpoint
    # state, which is known only then: one one-pose solve per step (measured: 910 for 3 turns).
    from analytic.applications import motor as amotor
    from sim.model import Loads
    from sim.service import dynamics as sdyn
    mech = analytic.load(str(Path(__file__).parent / "mechanisms" / "fourbar_loads.toml"))
    cycle = sdyn.cycle_of(mech)
    with counted() as n:
        d = sdyn.dynamics(mech, Loads(), amotor.LinearMotor(5.0, 20.0), 0.01, revolutions=3, simulate_too=False,
                          cycle=cycle)
    assert n["run"] == 4 and n["cycle"] == 0 and n["model"] == 0 and n["other"] == 0, n
    with counted() as n:
        d = sdyn.simulated(d, Loads(), cycle=cycle)
    assert d.passed
    assert n["cycle"] == 0 and n["run"] == 0 and n["other"] == 0, n
    assert n["model"] == len(d.sim.t) - 1, (n, len(d.sim.t))          # one pose per step, nothing more


def test_the_model_builder_reads_the_loads_share_from_the_cycle():
    # press_loads: the loads' share of the drives (friction's fixed point included) at the cycle's samples,
    # from its solution and velocity coefficients: the builder solves nothing (it solved 5 times before);
    # that share is what the servos are sized from: the drive's stiffness grows with the punch
    from sim.model import build
    mech = analytic.load(str(PRESS))
    cycle = Cycle.of(mech, 1.0)
    with counted() as n:
        loaded = build(mech, cycle=cycle)
    assert not n, n
    kp = loaded.drives[0].kp
    # a 500 N punch at up to ~55 mm of lever (r = 50 mm, the rod's angle): > 20 N m of drive share; the
    # inertia-only drive of these light links is < 1 N m, so kp (peak / budget) is > 20x the bare one's
    assert kp * 1e-6 > 20.0, kp                      # DRIVE_ERROR_BUDGET = 1e-6 rad: kp = peak / budget
