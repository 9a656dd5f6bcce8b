"""One solved run feeds every command (issue 39, item 2): how many times a command solves the motion.

Every solve of a mechanism goes through :meth:`analytic.mechanism.Mechanism.solve` (the change points' scan,
the assembly and singular-pose checks, the run itself, a cycle's two solves): the tests wrap it, run the
command in this process through the CLI (tests/cli_runner.py) and count the calls. Before the issue,
``linkage forces fourbar`` solved 8 times (the same 3601-sample turn scan twice) and ``linkage analyze
fourbar`` 6 times; a command now solves at most 3 times: the change points' scan, the turn the checks read
(or the run's cycle), and the run. ``forces`` reads no MuJoCo (a fresh interpreter's ``sys.modules``), and
``dynamics`` builds one MuJoCo model.

Every command is counted on one design of each kind (REPRESENTATIVE, ``--revolutions 0.25`` for the simulating
ones); a compare with a file's loads solves once more, for the loads' wrenches along the commanded motion (OVER).
Outside this rule, measured and left: a one-input machine whose input does not sweep a whole turn or stroke
that assembles (an actuator or a slider: dump_tipper, scissor_lift, tests/drives/scissor_*.toml,
tests/mechanisms/slider_driven.toml) solves 12 to 17 times, the ends of its assembly range refined by 9
successive solves of 32 values and its singular poses scanned over that range apart.
"""

from __future__ import annotations

import importlib
import os
import subprocess
import sys

import numpy as np
import pytest

from analytic import mechanism as _mechanism
from tests import cli_runner

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

MOST = 3
"""Solves per command: the change points' scan, the checks' turn (or the run's cycle), the run."""


@pytest.fixture
def solves(monkeypatch):
    """A list that receives (samples, outputs) of every :meth:`Mechanism.solve` while the test runs."""
    calls = []
    solve = _mechanism.Mechanism.solve

    def counted(self, q, qd=0.0, qdd=0.0, outputs=None):
        calls.append(int(np.size(q)) // len(self.inputs))
        return solve(self, q, qd, qdd, outputs)
    monkeypatch.setattr(_mechanism.Mechanism, "solve", counted)
    return calls


@pytest.mark.parametrize("mech", ["fourbar", "slider_crank"])
@pytest.mark.parametrize("command", ["analyze", "forces"])
def test_kinematic_commands_solve_at_most_three_times(solves, command, mech):
    r = cli_runner.run(command, mech, "--json")
    assert r.returncode == 0, r.stderr
    assert 1 <= len(solves) <= MOST, f"{command} {mech}: {len(solves)} solves of {solves} samples"


@pytest.mark.parametrize("mech", ["fourbar", "slider_crank"])
@pytest.mark.parametrize("command", ["compare", "simulate"])
def test_simulating_commands_solve_at_most_three_times(solves, command, mech):
    r = cli_runner.run(command, mech, "--json", "--revolutions", "0.25")
    assert r.returncode == 0, r.stderr
    assert 1 <= len(solves) <= MOST, f"{command} {mech}: {len(solves)} solves of {solves} samples"


REPRESENTATIVE = {
    "tests/mechanisms/press_5kn.toml": "a file's loads",
    "servo_press": "an input driven by a motion law",
    "excavator": "an actuator machine (three cylinders)",
    "cam_roller": "a cam and its follower",
    "stephenson_ii": "a group solved numerically (a class III triad)",
    "geared_five_bar": "a gear pair",
    "elliptic_trammel": "prismatic pairs (two blocks on ground lines)",
}
"""One of each kind of design the commands treat apart, with what it stands for."""

OVER = {
    ("compare", "tests/mechanisms/press_5kn.toml"): "the loads' wrenches at the commanded motion's step starts",
    ("compare", "cam_roller"): "the return spring's wrenches at the commanded motion's step starts",
}
"""The commands known to solve 4 times, and the fourth solve: a file's loads are applied to MuJoCo as wrenches
evaluated along the commanded motion at the run's step starts (sim.model.loads.wrenches), before the run; the
step starts are known only once the cycle's solve has chosen the time step, and compare's own solve is at the
simulated inputs after the run, so no solve in the chain holds those poses (the cycle, then those wrenches,
then compare's: 4 with the cycle's 2, or the change points' scan and a cycle read from it)."""


@pytest.mark.parametrize("mech", list(REPRESENTATIVE))
@pytest.mark.parametrize("command", ["analyze", "forces", "compare", "simulate"])
def test_each_kind_of_design_solves_at_most_three_times(solves, command, mech):
    """Every command on one design of each kind (REPRESENTATIVE): a loaded file, a motion law, an actuator
    machine, a cam, a numerically solved group, a gear, prismatic pairs; those of OVER one solve more, named
    there. Before: ``forces cam_roller`` 4 (the jump speed's rest poses solved again, twice), ``compare
    cam_roller`` 5 (the contact force's 721 samples solved again), ``compare servo_press`` 4 (the checks' scan
    of the turn beside the law's cycle)."""
    run = ("--revolutions", "0.25") if command in ("compare", "simulate") else ()
    r = cli_runner.run(command, mech, "--json", *run)
    assert r.returncode == 0, r.stderr
    most = MOST + 1 if (command, mech) in OVER else MOST
    assert 1 <= len(solves) <= most, f"{command} {mech}: {len(solves)} solves of {solves} samples"


def test_forces_on_a_cam_solves_its_rest_poses_with_the_run(solves):
    """48 samples on a cam: the change points' scan is not needed (no dyad passes one), the checks' scan of the
    turn (3601) and one solve of the run's 48 poses with their 48 poses at rest interleaved (96), which the jump
    speed weighs (before: 48 more, twice: the record was made twice)."""
    r = cli_runner.run("forces", "cam_roller", "--samples", "48", "--json")
    assert r.returncode == 0, r.stderr
    assert sorted(solves) == [96, 3601], solves


def test_jump_speed_from_the_shared_rest_poses_is_the_one_solved_apart():
    """The jump speed read from the rest poses solved with the run (ForceRun.rest) against the same with the
    rest poses solved apart, at zero rates (rest=None: kinetostatics solves them), on every library cam."""
    from dataclasses import replace
    from analytic.registry import load as load_mechanism
    from sim.service.forces import cams_record, forces_run, jump_speed
    for name in ("cam_roller", "cam_flat", "cam_rocker", "cam_fourbar"):
        run = forces_run(load_mechanism(name), samples=90)
        assert run.rest is not None, name
        for cam in cams_record(run):
            shared, apart = jump_speed(run, cam), jump_speed(replace(run, rest=None), cam)
            # the same poses solved in one call or two: equal to the rounding of the kinetostatics (~1e-15)
            assert shared == pytest.approx(apart, rel=1e-12), (name, cam, shared, apart)


def test_jump_speed_of_other_poses_does_not_read_the_runs_rest_poses():
    """A run whose samples were replaced (as ``forces --simulate`` puts MuJoCo's in) but which still carries the
    analytic run's rest poses: its jump speed is weighed at its own poses, as with no rest poses at all."""
    from dataclasses import replace
    from analytic.loads.kinetostatics import full_wanted
    from analytic.registry import load as load_mechanism
    from sim.service.forces import cams_record, forces_run, jump_speed
    mech = load_mechanism("cam_roller")
    run = forces_run(mech, samples=90)
    q = run.q + 0.01                                  # 0.01 rad further on
    moved = replace(run, q=q, solution=mech.solve(q, run.qd, run.qdd, outputs=full_wanted(mech)))
    for cam in cams_record(run):
        kept, own = jump_speed(moved, cam), jump_speed(replace(moved, rest=None), cam)
        # the same poses weighed both ways: equal to the kinetostatics' rounding (~1e-15)
        assert kept == pytest.approx(own, rel=1e-12), (cam, kept, own)


def test_cam_contact_from_the_cycle_is_the_one_solved_apart():
    """The cam's analytic contact force over a cycle (compare's tolerance floors) read from the run's cycle
    against the same 721 instants solved apart (no cycle kept in the model's memo)."""
    from analytic.registry import load as load_mechanism
    from sim.model import build
    from sim.run.cams import analytic_contact
    built = build(load_mechanism("cam_roller"), revolutions=0.25)
    assert built.memo.get("cycle") is not None
    shared = analytic_contact(built)
    built.memo.pop("cycle")
    apart = analytic_contact(built)
    for a, b in zip(shared, apart):
        # the cycle's instants are k T / 3600 for k = 5 j, the others j T / 720: the same to rounding (1e-16 of
        # T), so the forces agree to the rounding of the kinetostatics
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * float(np.max(np.abs(b))))


def test_forces_record_made_once(monkeypatch):
    """``forces --json`` makes its record once: ``passed`` (the SI record) and ``to_dict`` (the one printed,
    SI too) share it (linkage.results.Forces)."""
    from sim.service import forces as service
    made = []
    record = service.forces_record

    def counted(*args, **kwargs):
        made.append(1)
        return record(*args, **kwargs)
    monkeypatch.setattr(service, "forces_record", counted)
    r = cli_runner.run("forces", "cam_roller", "--json")
    assert r.returncode == 0, r.stderr
    assert len(made) == 1, f"the forces record was made {len(made)} times"


def test_forces_samples_solved_are_the_run_and_one_turn(solves):
    """48 samples asked: the run's 48, the checks' one scan of the turn (3601) and the change points' scan
    (1443): no turn scanned twice (before: 12.4 k samples in 8 solves)."""
    r = cli_runner.run("forces", "fourbar", "--samples", "48", "--json")
    assert r.returncode == 0, r.stderr
    assert sorted(solves) == [48, 1443, 3601], solves


def test_forces_does_not_import_mujoco():
    code = ("import sys\nfrom sim.front.cli import main\ncode = main(['forces', 'fourbar', '--json'])\n"
            "print('MUJOCO' if 'mujoco' in sys.modules else 'NO-MUJOCO', code, file=sys.stderr)\n")
    env = {**os.environ, "PYTHONPATH": ROOT}
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, env=env, timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stderr.strip().splitlines()[-1] == "NO-MUJOCO 0", r.stderr


def test_dynamics_builds_one_model(monkeypatch):
    _build = importlib.import_module("sim.model.build")      # the package's ``build`` is the function
    built = []
    build_model = _build.build_model

    def counted(*args, **kwargs):
        built.append(1)
        return build_model(*args, **kwargs)
    monkeypatch.setattr(_build, "build_model", counted)
    r = cli_runner.run("dynamics", "fourbar", "--motor", "2,15", "--revolutions", "3", "--json")
    assert r.returncode == 0, r.stderr
    assert len(built) == 1, f"dynamics built {len(built)} MuJoCo models"


def test_a_motion_laws_cycle_is_its_turns_scan():
    """A crank driven by a motion law that turns it once a cycle (servo_press): its cycle read as the turn's scan
    (sim.service.simulation.turn_scan) holds each value of the turn once, ascending from the start to a turn
    on, with the singularity measures of those values solved apart here."""
    import math
    from analytic.checks import singularity
    from analytic.cycle import Cycle
    from analytic.registry import load as load_mechanism
    from sim.service.simulation import turn_scan
    mech = load_mechanism("servo_press")
    cycle = Cycle.of(mech, 0.25)
    assert cycle.covers_turn and not cycle.full_turn
    q, measures = turn_scan(mech, cycle)
    q0 = mech.inputs[0].motion.q0
    assert np.all(np.diff(q) > 0)
    # the start itself, and the start a turn on (its pose repeated): 2 pi added to q0 rounds to ~1e-15
    assert q[0] == pytest.approx(q0, abs=1e-12) and q[-1] == pytest.approx(q0 + 2 * math.pi, abs=1e-12)
    apart = singularity(mech, mech.solve(q))
    assert set(measures) == set(apart) and measures
    for label, m in measures.items():
        # the values taken into the turn (q0 + (q - q0) mod 2 pi) move by rounding: the measures by ~1e-15
        np.testing.assert_allclose(m, apart[label], rtol=0, atol=1e-12)


def test_a_motion_law_that_cannot_turn_fully_is_refused_with_its_limits():
    """The law's cycle is the turn's check only where it assembles at every sample: a rod shorter than the
    crank (servo_press, l = 0.04 < r = 0.05) is still refused in one line naming the limit angles."""
    r = cli_runner.run("compare", "servo_press", "--set", "l=0.04", "--revolutions", "0.25")
    assert r.returncode == 2
    assert "cannot turn fully (limit angles -143.1301deg, -36.8699deg, 36.8699deg, 143.1301deg" in r.stderr, r.stderr
    assert "Traceback" not in r.stderr


def test_tolerance_solves_the_nominal_cycle_once(solves):
    """``tolerance``'s nominal cycle (sim.service.tolerance.cycle_of, what every design is evaluated along) on the
    four-bar: the checks' scan of the turn (3601), the change points' scan (1443) and the cycle's 361 instants,
    once (before: twice, its assembly checked by a solve of its own)."""
    from analytic.registry import load as load_mechanism
    from sim.service.tolerance import cycle_of
    cycle_of(load_mechanism("fourbar"))
    assert sorted(solves) == [361, 1443, 3601], solves
