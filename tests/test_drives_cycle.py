"""Several inputs with their own motion laws at once (issue 37, item 4): the excavator's three cylinders, each
through its own segments over one 6 s dig cycle (tests/drives/excavator_cycle.toml). Each cylinder's length
against the shapes' formulas written here; MuJoCo's run against the closed forms (``compare``, under gravity);
the sizing table of ``forces`` over the cycle."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import analytic
from tests.cli_runner import run

CYCLE = Path(__file__).resolve().parent / "drives" / "excavator_cycle.toml"


def _poly345(x):
    return 10 * x ** 3 - 15 * x ** 4 + 6 * x ** 5


def _cycloidal(x):
    return x - math.sin(2 * math.pi * x) / (2 * math.pi)


# (t [s], s_boom, s_stick, s_bucket [m]) from the file's start lengths 2.3436, 2.0248, 1.93 and its segments
EXPECTED = [
    (0.75, 2.3436, 2.0248 - 0.35 * _poly345(0.5), 1.93 + 0.30 * _cycloidal(0.25)),
    (1.75, 2.3436 + 0.40 * _poly345(0.5), 2.0248 - 0.35, 2.23),
    (3.25, 2.7436, 2.0248 - 0.35 + 0.35 * _cycloidal(0.25), 2.23),
    (5.00, 2.7436 - 0.40 * _poly345(2 / 3), 2.0248, 1.93),
    (6.75, 2.3436, 2.0248 - 0.35 * _poly345(0.5), 1.93 + 0.30 * _cycloidal(0.25)),   # the next cycle
]


def test_each_cylinder_follows_its_own_law():
    mech = analytic.load(str(CYCLE))
    assert [i.q for i in mech.inputs] == ["s_boom", "s_stick", "s_bucket"]
    assert mech.duration(1.0) == pytest.approx(6.0, rel=1e-15)          # the first input's cycle: a sum
    t = np.array([e[0] for e in EXPECTED])
    q, qd, _ = mech.drive(t)
    # the laws' closed forms against the formulas above: rounding of a few operations on ~2 m
    np.testing.assert_allclose(q, np.array([e[1:] for e in EXPECTED]), rtol=0, atol=1e-12)
    # the boom halfway up: poly345's peak slope 30 x^2 (1 - x)^2 = 1.875 at x = 1/2, times 0.40 m / 1.5 s
    assert qd[1, 0] == pytest.approx(0.5, rel=1e-12)
    assert qd[1, 1] == 0.0 and qd[1, 2] == 0.0                           # the stick and bucket dwell


def test_mujoco_follows_the_three_laws_under_gravity():
    from sim import service
    from sim.model.settings import Loads
    _, c = service.compare(analytic.load(str(CYCLE)), loads=Loads(gravity=(0.0, -9.81)))
    failed = {k: v for k, v in c.errors.items() if not v["passed"]}
    assert c.passed, (failed, c.drive_error, c.work_balance)


def test_mujoco_follows_the_three_laws_without_gravity_at_the_chosen_step():
    """Without gravity the loops' regulariser is not divided by the weight's share (sim.model.build.regularization)
    and the cylinders' light rods, pinned to 0.6-1.5 t links, set it (sim.model.build.SPREAD_REF): before the
    loops' spread entered it, the points missed by 2.2x their tolerance and the boom's force by 1.1x at the
    default step (passing at --timestep 0.004)."""
    from sim import service
    _, c = service.compare(analytic.load(str(CYCLE)))
    failed = {k: v for k, v in c.errors.items() if not v["passed"]}
    assert c.passed, (failed, c.drive_error, c.work_balance)
    assert c.trajectory.t[1] - c.trajectory.t[0] > 0.006          # the rate-chosen step (8.1 ms), not a shorter one


def test_forces_sizes_the_three_cylinders_over_the_cycle():
    r = run("forces", CYCLE, "--gravity", "0,-9.81", "--samples", "121", "--pressure", "250bar", "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert out["t"][-1] == pytest.approx(6.0, rel=1e-12)                # one cycle of the laws
    for name in ("boom", "stick", "bucket"):
        f = np.array(out["drives"]["s_" + name])
        rec = out["actuators"][name]
        # the peaks are samples of the drive forces the same JSON gives: exact
        assert rec["push"]["F"] == pytest.approx(max(f.max(), 0.0), rel=1e-15)
        assert rec["pull"]["F"] == pytest.approx(max(-f.min(), 0.0), rel=1e-15)
