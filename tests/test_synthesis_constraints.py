"""Synthesis constraints (SPEC, "Synthesis constraints and budgets"; issue 29 item 1): the measures of a
design (transmission range, size, working range, Grashof type) against hand geometry and an independent
closed form, the limits' words, and the motion and function commands under limits: nothing that breaks
them is returned, every returned design's file holds its working range and runs as written."""

import json
import math
import subprocess
import sys

import numpy as np
import pytest

import analytic
from analytic import ParameterError
from analytic.synthesis import constraints as sc
from analytic.synthesis import function as synthesis_function
from analytic.synthesis.fourbar import Linkage, mechanism


def run(*args):
    return subprocess.run([sys.executable, "-m", "sim", *args], capture_output=True, text=True, timeout=300)


# ------------------------------------------------------------------------------------------- measures
@pytest.mark.parametrize("lengths,kind", [
    ((1.0, 3.0, 2.5, 3.0), "crank-rocker"),     # s = crank, 1 + 3 <= 3 + 2.5
    ((3.0, 3.0, 2.5, 1.0), "double-crank"),     # s = ground
    ((3.0, 1.0, 2.5, 3.0), "double-rocker"),    # s = coupler
    ((3.0, 3.0, 1.0, 2.5), "rocker-crank"),     # s = rocker
    ((1.0, 4.0, 2.0, 2.5), "triple-rocker"),    # 1 + 4 > 2 + 2.5
    ((1.0, 3.0, 2.0, 2.0), "change-point"),     # 1 + 3 = 2 + 2
])
def test_grashof_type_by_hand(lengths, kind):
    assert sc.grashof_type(*lengths) == kind


def test_measure_of_a_crank_rocker_against_hand_geometry_and_an_independent_closed_form():
    # the library four-bar: |BD| runs from d - a = 0.2 to d + a = 0.4 over the turn, so
    # cos mu = (b^2 + c^2 - |BD|^2) / (2 b c) runs from 0.75 (41.41 deg) to -0.05 (92.87 deg, folded 87.13),
    # passing 90 deg: the folded range is [41.41, 90]
    link = Linkage((0.0, 0.0), (0.3, 0.0), 0.1, 0.3, 0.25, 0.15, 0.10, 1)
    m = sc.measure(mechanism(link), 0.0, 2 * math.pi, n=3601, lengths=(0.1, 0.3, 0.25, 0.3))
    assert m.transmission_deg[0] == pytest.approx(math.degrees(math.acos(0.75)), abs=1e-3)  # 0.1 deg samples
    assert m.transmission_deg[1] == pytest.approx(90.0, abs=1e-2)                            # at a sample
    assert m.grashof == "crank-rocker" and m.input_range == (0.0, 2 * math.pi)
    # the box of A, D, B, C, E from the rocker angle of Freudenstein's closed form (not the general solver)
    q = np.linspace(0.0, 2 * math.pi, 3601)
    psi = synthesis_function.output_angles(0.1, 0.3, 0.25, 0.3, q, 1)
    B = 0.1 * np.column_stack([np.cos(q), np.sin(q)])
    C = np.array([0.3, 0.0]) + 0.25 * np.column_stack([np.cos(psi), np.sin(psi)])
    u = (C - B) / 0.3
    E = B + 0.15 * u + 0.10 * np.column_stack([-u[:, 1], u[:, 0]])
    P = np.concatenate([[[0.0, 0.0], [0.3, 0.0]], B, C, E])
    box = (*P.min(axis=0), *P.max(axis=0))
    np.testing.assert_allclose(m.box, box, atol=1e-12)     # the same samples: rounding only
    assert m.size == pytest.approx(max(box[2] - box[0], box[3] - box[1]), abs=1e-12)
    assert m.pivots == {"A": (0.0, 0.0), "D": (0.3, 0.0)}


def test_broken_names_each_limit_with_its_numbers():
    m = sc.Measure((35.0, 80.0), 120.0, (0.0, 0.0, 120.0, 50.0), (0.0, 1.0), {"A": (0.0, 0.0), "D": (90.0, 5.0)},
                   "double-rocker")
    assert sc.broken(m, sc.Limits()) == ""
    assert "35.0-80.0 deg" in sc.broken(m, sc.Limits(min_transmission=40))
    assert "size 120 mm" in sc.broken(m, sc.Limits(max_size=100.0), "mm")
    assert sc.broken(m, sc.Limits(max_size=120.0)) == ""
    assert "ground pivot D at (90, 5)" in sc.broken(m, sc.Limits(regions=(sc.Region("D", 0, 80, -10, 10),)))
    assert sc.broken(m, sc.Limits(regions=(sc.Region("D", 0, 100, -10, 10),))) == ""
    assert "double-rocker" in sc.broken(m, sc.Limits(grashof="crank-rocker"))


@pytest.mark.parametrize("text", ["A", "A=1:2", "A=1:2,3", "A=2:1,0:1", "A=a:b,0:1", "1A=0:1,0:1"])
def test_bad_pivot_region_is_refused_with_its_option(text):
    with pytest.raises(ParameterError, match="--pivot-region"):
        sc.parse_region(text)


def test_region_and_angle_parsing():
    r = sc.parse_region("D=-1.5:2,0:3")
    # parsed decimal text: one rounding of each number at most
    assert r.name == "D" and (r.x0, r.x1, r.y0, r.y1) == pytest.approx((-1.5, 2.0, 0.0, 3.0), abs=1e-15)
    assert sc.parse_angle_deg("--min-transmission", "30deg") == pytest.approx(30.0, abs=1e-15)
    assert sc.parse_angle_deg("--min-transmission", "12.5") == pytest.approx(12.5, abs=1e-15)
    with pytest.raises(ParameterError, match="--min-transmission"):
        sc.parse_angle_deg("--min-transmission", "thirty")
    with pytest.raises(ParameterError, match="--min-transmission"):
        sc.Limits(min_transmission=95).check()


# ------------------------------------------------------------------------------------------ function
def write(path, header, rows):
    path.write_text(header + "\n" + "\n".join(",".join(repr(float(v)) for v in r) for r in rows) + "\n")
    return str(path)


def known_pairs(tmp_path, phi_deg, name="f.csv", **over):
    p = dict(l1=0.3, l2=1.1, l3=0.8, l4=1.0, **over)
    m = analytic.load("fourbar", **p)
    phi = np.radians(phi_deg)
    psi = np.asarray(m.solve(phi, outputs=["phi3"])["phi3"])
    return write(tmp_path / name, "input,output", np.degrees(np.column_stack([phi, psi])))


def hand_transmission(a, b, c, d, q):
    """Folded transmission angles [deg] of a four-bar at crank angles q (A at the origin, D = (d, 0))."""
    bd2 = a * a + d * d - 2 * a * d * np.cos(q)
    mu = np.degrees(np.arccos((b * b + c * c - bd2) / (2 * b * c)))
    return np.minimum(mu, 180 - mu)


def test_function_reports_its_working_range_transmission_and_refuses_a_higher_limit(tmp_path):
    csv = known_pairs(tmp_path, [30, 75, 140])
    out = tmp_path / "f.toml"
    r = run("synthesize", "function", csv, "--json", "--out", str(out))
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)["designs"][0]
    mu = hand_transmission(0.3, 1.1, 0.8, 1.0, np.radians(np.linspace(30, 140, 11001)))
    assert d["transmission_deg"][0] == pytest.approx(mu.min(), abs=2e-3)     # 1441 samples vs 11001: 0.002 deg
    assert d["transmission_deg"][1] == pytest.approx(mu.max(), abs=2e-3)
    np.testing.assert_allclose(d["input_range"], np.radians([30, 140]), atol=1e-12)     # rounding
    assert d["grashof"] == "crank-rocker" and d["evaluations"] >= 1
    mech = analytic.load(str(out))
    assert mech.definition.input_range                      # the file holds its working range
    lo, hi = (float(v) for v in mech.definition.input_range.split(":"))
    assert (lo, hi) == pytest.approx(tuple(np.radians([30, 140])), abs=1e-12)
    r = run("analyze", str(out))                            # runs as written: rocking over that range
    assert r.returncode == 0, r.stderr
    r = run("synthesize", "function", csv, "--min-transmission", f"{mu.min() + 1:.3f}deg", "--out", str(tmp_path / "g.toml"))
    assert r.returncode == 1 and "below --min-transmission" in r.stdout
    assert not (tmp_path / "g.toml").exists()               # nothing written for a design that breaks a limit


def test_function_size_and_region_limits(tmp_path):
    csv = known_pairs(tmp_path, [30, 75, 140])
    r = run("synthesize", "function", csv, "--max-size", "1.0", "--json")
    assert r.returncode == 1 and json.loads(r.stdout)["designs"] == []
    assert "exceeds --max-size 1" in json.loads(r.stdout)["rejected"][0]["why"]
    r = run("synthesize", "function", csv, "--pivot-region", "D=0.5:0.9,-1:1")
    assert r.returncode == 1 and "ground pivot D at (1, 0)" in r.stdout
    r = run("synthesize", "function", csv, "--pivot-region", "Q=0:1,0:1")
    assert r.returncode == 2 and "--pivot-region Q" in r.stderr and "Traceback" not in r.stderr


def test_function_offsets_are_explained(tmp_path):
    # the pairs of a design with its crank drawn the other way (input + 180 deg): Freudenstein gives a < 0
    csv = tmp_path / "f.csv"
    phi = np.radians([30.0, 75.0, 140.0])
    m = analytic.load("fourbar", l1=0.3, l2=1.1, l3=0.8, l4=1.0)
    psi = np.asarray(m.solve(phi, outputs=["phi3"])["phi3"])
    write(csv, "input,output", np.degrees(np.column_stack([phi + np.pi, psi])))
    r = run("synthesize", "function", str(csv))
    assert r.returncode == 0, r.stdout + r.stderr
    assert "input offset 180 deg" in r.stdout and "phi1 = input + 180 deg" in r.stdout


# -------------------------------------------------------------------------------------------- motion
def test_motion_limits_hold_for_every_returned_design_and_files_run_as_written(tmp_path):
    # an 80 x 20 mm task (issue 29: a 571 mm crank was ranked first)
    csv = write(tmp_path / "p.csv", "x,y,theta", [(0, 0, 0), (40, 15, 20), (80, 20, 45)])
    out = tmp_path / "m.toml"
    r = run("synthesize", "motion", csv, "--units", "mm", "--max-size", "150", "--min-transmission", "40deg",
            "--pivot-region", "A=-20:100,-80:0", "--count", "3", "--json", "--out", str(out))
    assert r.returncode == 0, r.stderr
    designs = json.loads(r.stdout)["designs"]
    assert len(designs) == 3
    for d in designs:
        assert d["size"] <= 150 and d["transmission_deg"][0] >= 40 and d["simulated"]["passed"]
        p = d["parameters"]
        assert -20 <= p["ax"] <= 100 and -80 <= p["ay"] <= 0
        # the transmission range by hand at the design's own travel
        a, b, c = p["l1"], p["l2"], p["l3"]
        dd = math.hypot(p["dx"] - p["ax"], p["dy"] - p["ay"])
        th = math.atan2(p["dy"] - p["ay"], p["dx"] - p["ax"])
        q = np.linspace(*d["input_range"], 20001) - th
        mu = hand_transmission(a, b, c, dd, q)
        assert d["transmission_deg"][0] == pytest.approx(mu.min(), abs=0.02)   # 1441 samples: a 0.02 deg step
    keys = [np.array([d["parameters"][k] for k in ("ax", "ay", "dx", "dy", "l1", "l2", "l3")]) for d in designs]
    for i in range(3):
        for j in range(i):
            assert np.abs(keys[i] - keys[j]).max() > 0.02 * 80     # distinct designs, not copies
    mech = analytic.load(str(out))
    lo, hi = (float(v) for v in mech.definition.input_range.split(":"))
    sol = mech.solve(np.array([lo, hi]))
    ends = {(round(float(x) * 1000, 6), round(float(y) * 1000, 6)) for x, y in zip(sol["xE"], sol["yE"])}
    assert ends == {(0.0, 0.0), (80.0, 20.0)}               # the range runs from the first pose to the last
    r = run("analyze", str(out))
    assert r.returncode == 0, r.stderr


def test_motion_with_an_impossible_size_returns_nothing_and_says_why(tmp_path):
    csv = write(tmp_path / "p.csv", "x,y,theta", [(0, 0, 0), (40, 15, 20), (80, 20, 45)])
    r = run("synthesize", "motion", csv, "--unit", "mm", "--max-size", "60", "--json")
    # the poses alone span 80 mm: no mechanism carrying E through them fits in 60 mm
    assert r.returncode == 1 and json.loads(r.stdout)["designs"] == []
    assert "no motion design meets the constraints" in r.stderr


# ------------------------------------------------------------------------------ simulated, distinct
def test_every_design_is_simulated_with_its_forces_checked():
    from sim.service.synth_checks import simulate_design
    link = Linkage((0.0, 0.0), (0.3, 0.0), 0.1, 0.3, 0.25, 0.15, 0.10, 1)
    for rng in (None, (0.2, 1.4)):                          # a full turn, and rocking over a working range
        s = simulate_design(mechanism(link), rng)
        assert s["passed"] and s["compare_passed"] and s["forces_passed"] and s["problem"] == ""
        # MuJoCo's equality-constraint forces against the closed-form kinetostatics: 2 % bounds the
        # integration and constraint drift (the agreement check itself is tighter)
        for k in ("peak_torque", "peak_bearing", "rms_shaking"):
            assert s[k] == pytest.approx(s["analytic"][k], rel=0.02) and s[k] > 0


def test_one_design_found_twice_is_returned_once():
    from analytic.synthesis import path as sp
    from analytic.synthesis.curves import FAMILIES
    x = np.array([0.0, 0.0, 0.0, 0.3, 0.1, 0.3, 0.25, 0.15, 0.10])

    def design(x, branch=(1,), err=1.0):
        return sp.Design(np.asarray(x, dtype=float), branch, 0.0, np.array([err]), np.zeros(1), 0.0, 0,
                         family=FAMILIES["fourbar"])
    a, copy, other, mirror = design(x), design(x + 1e-5, err=1.1), design(x * 1.1, err=1.2), design(x, (-1,), 1.3)
    assert sp.same_design(a, copy, 1.0) and not sp.same_design(a, other, 1.0) and not sp.same_design(a, mirror, 1.0)
    got = sp.distinct_first([a, copy, other, mirror], 3, 1.0)
    assert got[:3] == [a, other, mirror] and got[3] is copy


# ------------------------------------------------------------------------------ the file's input range
def library_with(tmp_path, line):
    import pathlib
    src = pathlib.Path(analytic.__file__).parent / "library" / "fourbar.toml"
    text = src.read_text().replace('output = "E"\n', f'output = "E"\n{line}\n', 1)
    p = tmp_path / "f.toml"
    p.write_text(text)
    return str(p)


def phi1_column(path):
    rows = [r for r in open(path).read().splitlines() if r and not r.startswith("#")]
    head = rows[0].split(",")
    k = head.index("phi1")
    return np.array([float(r.split(",")[k]) for r in rows[1:]])


def test_a_files_input_range_is_what_every_command_runs_unless_given(tmp_path):
    f = library_with(tmp_path, 'input_range = "0.2:1.4"')
    assert analytic.load(f).definition.input_range == "0.2:1.4"
    r = run("analyze", f, "--csv", str(tmp_path / "a.csv"))
    assert r.returncode == 0, r.stderr
    q = phi1_column(tmp_path / "a.csv")
    assert q.min() == pytest.approx(0.2, abs=1e-12) and q.max() == pytest.approx(1.4, abs=1e-12)   # rounding
    r = run("analyze", f, "--input-range", "0.3:1.0", "--csv", str(tmp_path / "b.csv"))
    assert r.returncode == 0, r.stderr
    q = phi1_column(tmp_path / "b.csv")
    assert q.min() == pytest.approx(0.3, abs=1e-12) and q.max() == pytest.approx(1.0, abs=1e-12)


def test_a_bad_input_range_in_a_file_is_one_line_naming_it(tmp_path):
    f = library_with(tmp_path, "input_range = 5")
    r = run("analyze", f)
    assert r.returncode == 2 and "input_range" in r.stderr and "Traceback" not in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1


def test_motion_evaluations_bound_the_candidates(tmp_path):
    csv = write(tmp_path / "p.csv", "x,y,theta", [(0, 0, 0), (40, 15, 20), (80, 20, 45)])
    r = run("synthesize", "motion", csv, "--units", "mm", "--evaluations", "40", "--json")
    assert r.returncode == 0, r.stderr
    assert {d["evaluations"] for d in json.loads(r.stdout)["designs"]} == {40}   # 121 dyads give far more pairs
