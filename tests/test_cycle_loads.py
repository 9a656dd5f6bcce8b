"""The motion solved once with loads (issue 30 item 2, issue 27): how many times a compare, the simulated half of
``forces --simulate``, ``export --mjcf`` and ``dynamics`` solve a mechanism whose file has ``[[loads]]`` (and
friction), counted by tests/test_cycle.py's structural count of Mechanism.solve calls (not a timing)."""

from __future__ import annotations

from pathlib import Path

import analytic
from analytic.cycle import Cycle
from sim import service
from test_cycle import counted


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
