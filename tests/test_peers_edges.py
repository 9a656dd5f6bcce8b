"""The peers' examples at their edges (issue 32): the poses Pyslvs' and PMKS' own examples drive through.

The files are ours (tests/peers_examples/), each with the geometry of a peer example that failed: a rhombus
(Pyslvs' "Parallel Linkage" is a 100 x 100 one) and a block carried over a rocker's pivot (Pyslvs' "Slider
lifter"), both passing a change point where the dyad's two known points meet. Each is checked against the
geometry written here (a parallelogram's rocker turns with its crank), not against the solver's own output.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import analytic
from analytic import ParameterError
from analytic.format import foreign
from sim import service
from sim.model.timestep import rate_scale
from test_joints_form import EXAMPLES

RATE_TOL = 1e-6      # relative: the limit of the rates at a change point (Richardson, O(step^4) ~ 1e-12) and the
#                      closed form's rounding 1e-3 rad away from it (1e-10); a wrong limit is off by O(1)
ACC_TOL = 1e-5       # of w^2: the closed form's rounding 1e-16 / sin^2 at the edge of the limit zone (sin = 1e-5),
#                      measured 2.6e-6; the faulty limit read 1318 rad/s^2 (3e1 w^2) at 1e-6 rad


def mech_of(name, inputs):
    return analytic.registry.Mechanism.from_definition(foreign.definition(EXAMPLES / name, inputs), {})


# --------------------------------------------------------------------------------------- the rhombus
def test_the_rhombus_rocker_turns_with_its_crank_through_its_folded_pose():
    """At 0 deg the crank's pin lands on the rocker's pivot; a parallelogram's rocker stays parallel to the crank,
    so its rate and acceleration are the crank's and the coupler does not turn (the geometry, not the solver)."""
    m = mech_of("rhombus.txt", [(0, 2)])
    w, a = 2 * math.pi, 0.0
    # (a crank speeding up: tests/test_change_point_acceleration.py)
    for d in (1e-3, 1e-5, 1e-6, 1e-8, 1e-10, 0.0, -1e-10, -1e-8, -1e-6, -1e-5, -1e-3):
        s = m.solve(np.array([d]), w, a)
        assert s["omegarocker"][0] == pytest.approx(w, rel=RATE_TOL), d
        assert s["alpharocker"][0] == pytest.approx(a, abs=ACC_TOL * w * w), d
        assert abs(s["omegacoupler"][0]) <= RATE_TOL * w, d
        assert abs(s["alphacoupler"][0]) <= ACC_TOL * w * w, d
        # J3 = J2 + (J1 - J0): 80 mm further along x than the crank's pin, moving with it
        assert s["xJ3"][0] == pytest.approx(s["xJ2"][0] + 0.08, abs=1e-12), d
        assert s["vyJ3"][0] == pytest.approx(s["vyJ2"][0], rel=RATE_TOL), d


def test_the_rhombus_rate_scan_sees_the_crank_speed_only():
    """The time step's rate scan over a turn: every link of a parallelogram turns at the crank's speed or not at
    all (it read 4e8 rad/s at the folded pose, and the run was refused as too fast)."""
    m = mech_of("rhombus.txt", [(0, 2)])
    assert rate_scale(m) == pytest.approx(2 * math.pi, rel=1e-5)   # 1e-5: the scan's rounding near the folds


def test_a_full_turn_through_the_folded_pose_is_refused_naming_it():
    m = mech_of("rhombus.txt", [(0, 2)])
    with pytest.raises(ParameterError) as exc:
        service.prepare(m, 1.0)
    msg = str(exc.value)
    assert "0.00deg where J1 and J2 meet" in msg and "--input-range" in msg and "\n" not in msg
    assert "0.00deg, 180.00deg" in msg                               # the change points to run between


def test_the_rhombus_between_its_change_points_passes_compare():
    """Pyslvs' own motion of it: from the drawn 90 deg until its solver stops at the flat pose."""
    m = mech_of("rhombus.txt", [(0, 2)])
    _, c = service.compare(m, 1.0, input_range=(math.radians(5.0), math.radians(175.0)))
    assert c.passed


# ------------------------------------------------------------------------------- a block over the pivot
def test_the_block_over_the_pivot_rates_are_the_limits_of_the_motion():
    """s = 60 mm puts the pin on the rocker's pivot; the rod and the rocker (both 50) fold onto each other. With
    J0 = (s, 0), J1 = (60, 0) and J2 the kite's tip, |J2 - J0| = |J2 - J1|: J2 lies over the midpoint,
    x2 = (s + 60) / 2, y2 = sqrt(50^2 - ((60 - s) / 2)^2), so vx2 = v / 2 and vy2 = v (60 - s) / (4 y2): at
    s = 60, vy2 = 0 and the rocker turns at -(v / 2) / 50 (J2 right above J1)."""
    m = mech_of("block_over_pivot.txt", [(0, 0)])
    v = 0.05                                                          # m/s
    for d in (1e-3, 1e-6, 1e-9, 0.0, -1e-9, -1e-6, -1e-3):
        s = 0.06 + d
        sol = m.solve(np.array([s]), v, 0.0)
        y2 = math.sqrt(0.05 ** 2 - ((0.06 - s) / 2) ** 2)
        assert sol["xJ2"][0] == pytest.approx((s + 0.06) / 2, abs=1e-12), d
        assert sol["vxJ2"][0] == pytest.approx(v / 2, rel=RATE_TOL), d
        assert sol["vyJ2"][0] == pytest.approx(v * (0.06 - s) / (4 * y2), abs=RATE_TOL * v), d
        assert abs(sol["omegarocker"][0]) == pytest.approx(v / (2 * y2), rel=RATE_TOL), d   # |J2 J1| = 50 mm


def test_the_block_over_the_pivot_is_refused_only_where_the_run_reaches_it():
    m = mech_of("block_over_pivot.txt", [(0, 0)])
    with pytest.raises(ParameterError, match=r"sJ0_block=60 mm where J0 and J1 meet"):
        service.check_folded_change_points(m, np.linspace(0.0, 0.07, 50))
    service.check_folded_change_points(m, np.linspace(0.0, 0.055, 50))   # short of it: nothing to refuse


# --------------------------------------------------------------------------- a slider's default speed
def test_a_slider_without_a_speed_moves_its_mechanisms_size_per_second(tmp_path):
    """The links-and-joints form and ``linkage import``: the block-over-pivot's pose spans 100 mm (J0 to J4,
    J1 to J3: hand geometry), so its slider moves 100 mm/s = 0.1 m/s (it moved 0.1 mm/s, a thousandth)."""
    from analytic.format import linkfile
    data = foreign.read(EXAMPLES / "block_over_pivot.txt", [(0, 0)])
    assert data["inputs"][0]["v"] == pytest.approx(100.0)
    del data["inputs"][0]["v"]
    path = tmp_path / "bop.toml"
    path.write_text(foreign.dumps(data))
    m = analytic.registry.Mechanism.from_definition(linkfile.read(path), {})
    assert m.inputs[0].motion.rate == pytest.approx(0.1, rel=1e-12)


def test_a_slow_slider_is_judged_against_the_forces_of_its_reference_speed():
    """At 0.1 mm/s the drive force is ~1e-8 N and MuJoCo's residual ~2 % of it: the tolerances' floors are those
    of the reference speed (one size per second), so the run passes; it failed on the drive force before."""
    from analytic.format import linkfile
    data = foreign.read(EXAMPLES / "block_over_pivot.txt", [(0, 0)])
    data["inputs"][0]["v"] = 0.1                                     # mm/s
    slow = analytic.registry.Mechanism.from_definition(linkfile.from_data(data, "bop", "bop"), {})
    _, c = service.compare(slow, 1.0)
    e = c.errors["tauJ0_block"]
    assert e["peak"] < 1e-6                                          # a vanishing force: N
    assert e["tol"] > 10 * 5e-3 * e["peak"]                          # the floor binds, not 0.5 % of the peak
    assert c.passed
    # rocked over most of its stroke as the sources drive it, at 0.1 mm/s: the joint forces (3e-8 N) too
    _, c = service.compare(slow, 1.0, input_range=(-0.03, 0.05))
    assert c.forces is not None and c.forces.peak < 1e-6 and c.forces.floor > 100 * c.forces.peak
    assert c.passed, c.forces.line()


# ------------------------------------------------------------------- a rocking run with several inputs
def test_a_rocking_run_checks_the_poses_its_other_inputs_move_through():
    """Pyslvs' arm has two inputs; rocking the first while the second turned passed the range check (which held
    the second) and then failed inside the simulation ("cannot be assembled over the whole run"). The check
    now drives every input as the run does, and says how to hold one. Two cranks 30 long on pivots 100 apart
    with a pair 2 x 58.31: with the second crank pointing away (J3 = (130, 0)) and the first up, |J2 J3| =
    sqrt(130^2 + 30^2) = 133.4 > 116.6: no pose (hand geometry)."""
    from analytic.format import linkfile
    data = foreign.read(EXAMPLES / "two_crank_fivebar.txt", [(0, 2), (1, 3)])
    assert data["inputs"][1]["omega"] == 0.0                          # imported held, as Pyslvs sweeps them
    held = analytic.registry.Mechanism.from_definition(linkfile.from_data(data, "h", "h"), {})
    rng = (math.radians(80.0), math.radians(100.0))
    service.prepare(held, 1.0, rng)                                   # every pose of that run assembles
    data["inputs"][1]["omega"] = "360deg"                             # the second turning while the first rocks
    m = analytic.registry.Mechanism.from_definition(linkfile.from_data(data, "t", "t"), {})
    with pytest.raises(ParameterError, match=r"cannot be assembled at .*others keep their own motion .*omega = 0"):
        service.prepare(m, 1.0, rng)


@pytest.mark.slow
def test_the_peers_benchmark_drives_our_edge_files_as_the_sources_do(tmp_path):
    """benchmarks/peers.py on our three files: the rhombus rocked between its change points, the block between its
    stroke's end and its folded change point, the five-bar's cranks each in turn with the other held."""
    import shutil
    import subprocess
    import sys
    from pathlib import Path
    for name in ("rhombus.txt", "block_over_pivot.txt", "two_crank_fivebar.txt"):
        shutil.copy(EXAMPLES / name, tmp_path / name)
    out = tmp_path / "rows.json"
    bench = Path(__file__).resolve().parent.parent / "benchmarks" / "peers.py"
    done = subprocess.run([sys.executable, str(bench), "--pyslvs", str(tmp_path), "--json", str(out)],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    import json
    rows = {r["example"]: r for r in json.loads(out.read_text())}
    assert all(r["compare"] == "passed" for r in rows.values()), rows
    assert "between change points" in rows["rhombus.txt"]["reason"]
    lo, hi = (float(x) for x in rows["rhombus.txt"]["reason"].split("rocking ")[1].split(" deg")[0].split(" to "))
    assert 0.0 < lo < 90.0 < hi < 180.0                              # around the drawn 90 deg, inside (0, 180)
    assert "between change points" in rows["block_over_pivot.txt"]["reason"]
    assert rows["two_crank_fivebar.txt"]["reason"].count("the others held: passed") == 2


def test_a_slider_rocks_at_its_speed_over_the_size():
    """A rocking slider's frequency is its speed over the mechanism's size (a crank's is its speed): the block
    over the pivot (size 50 mm: its longest pin-to-pin link, rod J0-J2 and rocker J1-J2, hand geometry) at its
    default 100 mm/s rocks once in 2 pi x 50 / 100 = pi s, its peak speed amp x v / size. It rocked at v read as
    rad/s: 0.1 rad/s, once a minute, 20 x too slow; at the old default 0.1 mm/s once in 17 hours, its forces
    down at MuJoCo's noise."""
    m = mech_of("block_over_pivot.txt", [(0, 0)])
    assert m.size == pytest.approx(0.05, rel=1e-12)
    assert m.inputs[0].motion.rate == pytest.approx(0.1, rel=1e-12)
    lo, hi = -0.03, 0.05
    r = m.rocking(lo, hi)
    assert r.duration(1.0) == pytest.approx(math.pi, rel=1e-12)
    t = np.linspace(0.0, r.duration(1.0), 2001)
    q, qd, _ = r.drive(t)
    assert q[0, 0] == pytest.approx(lo) and np.max(q) == pytest.approx(hi, abs=1e-9)
    assert np.max(np.abs(qd)) == pytest.approx((hi - lo) / 2 * 0.1 / 0.05, rel=1e-5)   # amp v / size, m/s


def test_the_import_rocking_range_keeps_the_drawn_start_inside(tmp_path):
    """The rhombus drawn at 175 deg, 5 deg short of its change point at 180 (J2 = 80 (cos 175, sin 175), J3 = J2 +
    (80, 0): hand geometry): the window between its change points 0 and 180 keeps 10 % clear of each except on the
    start's side, where it keeps half the start's distance (PMKS' rprp is drawn 1 deg from its singular pose;
    the window was 18-162 deg, leaving out the pose the source starts from). The range linkage import writes
    (sim.service.importing.source_range; it was benchmarks/peers.py's window)."""
    from sim.service.importing import source_range
    c, s = math.cos(math.radians(175.0)), math.sin(math.radians(175.0))
    (tmp_path / "r175.txt").write_text(
        f"M[J[R, P[0, 0], L[ground, crank]], J[R, P[80, 0], L[ground, rocker]], "
        f"J[R, P[{80 * c!r}, {80 * s!r}], L[crank, coupler]], J[R, P[{80 * c + 80!r}, {80 * s!r}], L[coupler, rocker]]]")
    m = analytic.registry.Mechanism.from_definition(foreign.definition(tmp_path / "r175.txt", [(0, 2)]), {})
    lo, hi = (math.degrees(x) for x in source_range(m))
    assert lo == pytest.approx(18.0, abs=1e-3)                      # 10 % of 180 deg clear of the change point at 0
    assert hi == pytest.approx(177.5, abs=1e-3)                     # half of the start's 5 deg to 180
