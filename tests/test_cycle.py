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
