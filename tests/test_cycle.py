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
from test_library import OTHER_FORMS  # the driven slider's text, as the library's tests load it


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


LOADED = str(Path(__file__).parent / "mechanisms" / "fourbar_loads.toml")
FRICTION = "\n[friction]\nmu = 0.1\npin_radius = 0.005\n"


@pytest.mark.parametrize("name, slow_stroke", [("jansen", False), ("sixbar", True), (LOADED, False),
                                               (LOADED + FRICTION, False)],
                         ids=["jansen", "sixbar-slow-stroke", "file-loads", "file-loads-friction"])
def test_the_model_builder_never_solves_when_handed_a_cycle(name, slow_stroke):
    # (a load on the slow stroke only: the stroke is found from the cycle's samples too; the file's loads,
    # with Coulomb friction or not: their share of the drives is taken at the cycle's samples)
    from sim.model import Loads, build
    if name.startswith(LOADED):
        mech = analytic.from_text(Path(LOADED).read_text() + name[len(LOADED):], "loaded")
    else:
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


DOUBLE_ROCKER = {"l1": 0.2, "l3": 0.1}       # with l2 = l4 = 0.3: dead points where B, C, D are aligned

DRIVEN_SLIDER = OTHER_FORMS["driven_slider"]
"""A driven slider moving an RRR dyad (tests/test_library.py's): a slider's range [m], a dyad's scan."""


def load(name, over):
    return analytic.from_text(DRIVEN_SLIDER, name) if name == "driven_slider" else service.load(name, over)


def dead_points_by_hand() -> tuple[float, float]:
    """The double rocker's dead points [rad]: C on line BD, |BD| = l2 - l3 = 0.2 or l2 + l3 = 0.4, and
    |BD|^2 = l1^2 + l4^2 - 2 l1 l4 cos(phi1) (cosine rule): 41.4096 and 104.4775 deg."""
    l1, l4 = 0.2, 0.3
    return tuple(math.acos((l1 * l1 + l4 * l4 - d * d) / (2 * l1 * l4)) for d in (0.2, 0.4))


@pytest.mark.parametrize("name, over, rng", [
    ("fourbar", DOUBLE_ROCKER, (45.0, 100.0)),        # a dyad, its dead points beyond the range
    ("fourbar", {}, (10.0, 80.0)),                    # a crank that could turn, rocked
    ("stephenson_ii", {}, (10.0, 80.0)),              # a numerically solved group: no change-point scan
    ("slider_crank", {}, (-20.0, 20.0)),              # a closed-form RRP dyad
    ("driven_slider", {}, (0.0, 0.04)),               # a slider's stroke [m]
])
def test_a_compare_over_an_input_range_solves_the_mechanism_at_most_three_times(name, over, rng):
    # The dead-point search (the assembly range's ends, refined by bisection: 2-10 more solves) is not made
    # when the cycle's poses FOLD_MARGIN beyond both ends assemble; a dyad's cycle reads its rate peaks from
    # the change points' scan of the turn, so its three solves are that scan, the cycle and the comparison.
    mech = load(name, over)
    angular = mech.inputs[0].angular
    rock = tuple(math.radians(x) for x in rng) if angular else rng
    with counted() as n:
        _, c = service.compare(mech, 1.0, input_range=rock)
    assert c.passed, {k: e for k, e in c.errors.items() if not e["passed"]}
    assert n["model"] == 0 and n["run"] == 1 and n["other"] == 0, n
    assert sum(v for k, v in n.items() if k != "scans") <= 3, n


def test_the_cli_compare_over_an_input_range_solves_at_most_three_times():
    from tests.cli_runner import run
    with counted() as n:
        r = run("compare", "fourbar", "--set", "l1=0.2", "--set", "l3=0.1", "--input-range", "45deg:100deg")
    assert r.returncode == 0, r.stderr
    assert sum(v for k, v in n.items() if k != "scans") <= 3, n


@pytest.mark.parametrize("inside, valid", [(2.0, True), (0.5, False)])
def test_the_poses_beyond_a_rocking_range_see_a_dead_point_within_the_margin(inside, valid):
    # The range ends ``inside`` margins short of both hand-computed dead points: at 2 margins the poses one
    # margin beyond still assemble; at half a margin they lie past the dead points and do not.
    lo, hi = dead_points_by_hand()
    margin = 1e-5
    mech = service.load("fourbar", DOUBLE_ROCKER).rocking(lo + inside * margin, hi - inside * margin)
    c = Cycle.of(mech, 1.0, margin)
    assert c.solution.valid.all()
    assert c.beyond is not None and len(c.beyond.valid) == 2
    assert bool(c.beyond.valid[0]) is valid and bool(c.beyond.valid[1]) is valid
    # and the cycle's own samples are the rocking motion's, not shifted by the two poses solved with them
    sol = mech.solve(c.q, c.qd, c.qdd)
    assert np.max(np.abs(sol["xC"] - c.solution["xC"])) <= 1e-12 * mech.size          # rounding


def test_a_range_within_the_margin_of_a_dead_point_is_still_refused():
    # 0.5e-5 rad inside the dead point at 41.4096 deg: check_fold's search runs and names it (the same as
    # before the cycle solved the poses beyond the range)
    lo, hi = dead_points_by_hand()
    mech = service.load("fourbar", DOUBLE_ROCKER)
    with pytest.raises(ParameterError, match=r"dead point at 41\.4096deg"):
        service.prepare(mech, 1.0, (lo + 0.5e-5, math.radians(100.0)))


@pytest.mark.parametrize("name, over, rng", [
    ("fourbar", {}, (10.0, 80.0)),
    ("fourbar", {}, (-170.0, 170.0)),                  # across the scan's start (phi1_0 = 0): wrapped
    ("fourbar", DOUBLE_ROCKER, (41.42, 104.46)),       # near both dead points: the rates peak at the ends
    ("jansen", {}, (0.0, 170.0)),
    ("driven_slider", {}, (0.0, 0.04)),                # [m]
])
def test_the_rocking_cycles_rates_from_the_turn_scan_are_the_motions(name, over, rng):
    # The rates the cycle picks its peaks from, computed from the change points' scan at unit rate
    # (omega = c1 qd, alpha = c2 qd^2 + c1 qdd), against the rocking mechanism solved at those times: equal
    # to rounding at the scanned poses. (A dropped c1 qdd term, a time at the wrong half of the swing or the
    # swing's phase reversed all fail it: tried.) The range's three end samples use interpolated
    # coefficients and are left out.
    from analytic.cycle import _from_rocking_scan, rates
    mech = load(name, over)
    mech = mech.rocking(*(math.radians(x) if mech.inputs[0].angular else x for x in rng))
    ts, r = _from_rocking_scan(mech, mech.duration(1.0))
    ends = np.isin(ts, [0.0, 0.5 * mech.duration(1.0), mech.duration(1.0)])
    assert ends.sum() == 3 and len(ts) > 50              # a slider: its 40 mm of the scanned +-4 sizes
    q, qd, qdd = mech.drive(ts[~ends])
    want = rates(mech, qd, qdd, mech.solve(q, qd, qdd))
    scale = np.nanmax(want, axis=0)
    scale = np.where(scale > 0, scale, 1.0)          # a rate that stays 0 (a ground-fixed link's): absolute [1/s]
    # 1e-7 of each rate's peak: the scan's poses are the run's to rounding, the times to acos's rounding
    # near the swing's ends (where d(acos)/dx grows as 1/sqrt(1 - x^2))
    assert np.nanmax(np.abs(r[~ends] - want) / scale) <= 1e-7
    # and the cycle's peaks: its highest rates, refined, are the dense brute force's (200 000 samples)
    c = Cycle.of(mech, 1.0)
    t = np.linspace(0.0, mech.duration(1.0), 200_001)
    q, qd, qdd = mech.drive(t)
    brute = np.nanmax(rates(mech, qd, qdd, mech.solve(q, qd, qdd, outputs=None)), axis=0)
    got = np.nanmax(c.rates(), axis=0)
    # 1e-6: the brute force's own grid (its step 1/200000 of a period) misses a smooth peak by ~1e-9
    assert np.all(got >= brute * (1 - 1e-6)), (got / brute).min()
