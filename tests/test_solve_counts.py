"""One solved run feeds every command (issue 39, item 2): how many times a command solves the motion.

Every solve of a mechanism goes through :meth:`analytic.mechanism.Mechanism.solve` (the change points' scan,
the assembly and singular-pose checks, the run itself, a cycle's two solves): the tests wrap it, run the
command in this process through the CLI (tests/cli_runner.py) and count the calls. Before the issue,
``linkage forces fourbar`` solved 8 times (the same 3601-sample turn scan twice) and ``linkage analyze
fourbar`` 6 times; a command now solves at most 3 times: the change points' scan, the turn the checks read
(or the run's cycle), and the run. ``forces`` reads no MuJoCo (a fresh interpreter's ``sys.modules``), and
``dynamics`` builds one MuJoCo model.
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
