"""Force units in printed results (issue 27 item 4, SPEC "Loads" and "Units of results"): a file with
``force_units = "lbf"`` (or "kN") prints forces in that unit and moments in force unit x length unit in
``linkage forces`` and ``dynamics``; JSON and CSV stay SI unless ``--units``. Expected values by hand statics
and the unit definitions (1 in = 0.0254 m, 1 lbf = 0.45359237 kg x 9.80665 m/s^2), not from the code."""

from __future__ import annotations

import csv
import json
import re

import numpy as np
import pytest

import cli_runner  # the command in this process (tests/cli_runner.py)
from analytic import quantities as Q

LBF = 0.45359237 * 9.80665          # N per lbf, by definition
IN = 0.0254                          # m per inch, by definition
KN = 1000.0

CRANK = """\
format = "linkage/1"
name = "unitcrank"
units = "{units}"
{force_line}
output = "C"

[parameters]
omega1 = {omega}

[ground]
A = [0, 0]
D = [{d}, 0]

[[inputs]]
kind = "crank"
pivot = "A"
point = "B"
length = {r}
link = "1"
phi0 = "30deg"
omega = "omega1"

[[groups]]
kind = "RRR"
point = "C"
from = ["B", "D"]
lengths = [{b}, {c}]
links = ["2", "3"]
branch = 1

[[loads]]
name = "push"
kind = "force"
link = "1"
point = "B"
frame = "link"
direction = [0, 1]
magnitude = {F}
"""

# (length unit, force unit, crank radius, tangential force, N per force unit, m per length unit, moment label)
CASES = {"inch_pound": ("in", "lbf", 2.0, 10.0, LBF, IN, "lbf in"),
         "kN_mm": ("mm", "kN", 50.0, 2.0, KN, 1e-3, "kN mm")}


def crank_file(tmp_path, case, omega=0.001):
    units, fu, r, F, _, _, _ = CASES[case]
    p = tmp_path / f"{case}.toml"
    p.write_text(CRANK.format(units=units, force_line=f'force_units = "{fu}"', omega=omega, d=3 * r, r=r,
                              b=3 * r, c=2.5 * r, F=F))
    return p


def run(*args):
    r = cli_runner.run(*args)
    assert r.returncode == 0, r.stderr
    return r.stdout


def test_display_converts_forces_and_moments_by_definition():
    d = Q.Display(length="in", force="lbf")
    assert d.unit(Q.FORCE) == "lbf" and d.unit(Q.TORQUE) == "lbf in"
    # 2.2597 N m is 20 lbf in (20 x 0.0254 x 4.4482216152605): exact constants, rounding only
    assert d.convert(Q.TORQUE, 20 * LBF * IN) == pytest.approx(20.0, rel=1e-14)
    assert d.convert(Q.FORCE, LBF) == pytest.approx(1.0, rel=1e-14)
    assert not d.is_si
    si = Q.Display(length="mm")                                  # a newton file keeps N and N m
    assert (si.unit(Q.FORCE), si.unit(Q.TORQUE), si.convert(Q.TORQUE, 2.0)) == ("N", "N m", 2.0)


@pytest.mark.parametrize("case", list(CASES))
def test_forces_prints_file_units_json_stays_si(tmp_path, case):
    units, fu, r, F, n_per, m_per, mu = CASES[case]
    path = crank_file(tmp_path, case)
    text = run("forces", path)
    # hand statics of the crank: a tangential force F at radius r needs a drive torque F r (the coupler and
    # rocker carry nothing; the crank turns at 1e-3 rad/s, so inertia adds ~1e-7 of it)
    m = re.search(r"drive of phi1: peak torque (\S+) (.+?) at", text)
    assert m and m.group(2) == mu, text
    assert float(m.group(1)) == pytest.approx(F * r, rel=1e-4)   # printed with 5 significant digits
    a = re.search(r"^\s+A\s+R\s+ground-1\s+(\S+)", text, re.M)
    assert f"peak |F| [{fu}]" in text and float(a.group(1)) == pytest.approx(F, rel=1e-4)

    rec = json.loads(run("forces", path, "--json"))                  # SI by default
    assert rec["units"]["drives"]["phi1"] == "N m" and rec["units"]["force"] == "N"
    tau = np.asarray(rec["drives"]["phi1"])
    # the drive holds the crank against the push: -F r at every sample (SI), inertia ~1e-7 of it
    assert tau == pytest.approx(-F * r * n_per * m_per, rel=1e-6)
    joint_a = next(j for j in rec["joints"] if j["point"] == "A")
    assert np.hypot(joint_a["Fx"], joint_a["Fy"]) == pytest.approx(F * n_per, rel=1e-6)

    rec = json.loads(run("forces", path, "--json", "--units", units))    # --units: the file's force unit too
    assert rec["units"]["drives"]["phi1"] == mu and rec["units"]["force"] == fu
    assert np.asarray(rec["drives"]["phi1"]) == pytest.approx(-F * r, rel=1e-6)
    assert rec["peaks"]["drives"]["phi1"]["value"] == pytest.approx(F * r, rel=1e-6)
    assert rec["peaks"]["joints"]["A"]["F"] == pytest.approx(F, rel=1e-6)


def test_forces_csv_si_unless_units(tmp_path):
    path = crank_file(tmp_path, "inch_pound")
    for extra, tau, unit in (((), -20 * LBF * IN, "N m"), (("--units", "in"), -20.0, "lbf in")):
        out = tmp_path / "f.csv"
        run("forces", path, "--csv", out, *extra)
        rows = list(csv.DictReader(out.open()))
        # hand statics as above (10 lbf at 2 in); inertia at 1e-3 rad/s ~1e-7 of it
        assert [float(x["tau1"]) for x in rows] == pytest.approx([tau] * len(rows), rel=1e-6)
        assert json.loads((tmp_path / "f.csv.units.json").read_text())["units"]["tau1"] == unit


def test_newton_file_keeps_n_m(tmp_path):
    p = tmp_path / "n.toml"
    p.write_text(CRANK.format(units="mm", force_line="", omega=0.001, d=150, r=50, b=150, c=125, F=40))
    text = run("forces", p)
    m = re.search(r"drive of phi1: peak torque (\S+) (.+?) at", text)
    # SPEC "Units of results": a newton file shows N m; 40 N at 50 mm = 2 N m (inertia ~1e-7 of it)
    assert m.group(2) == "N m" and float(m.group(1)) == pytest.approx(2.0, rel=1e-4)


def test_dynamics_prints_the_motor_torque_in_lbf_in(tmp_path):
    path = crank_file(tmp_path, "inch_pound", omega=1.0)
    text = run("dynamics", path, "--motor", "5,20", "--revolutions", "2")
    # from rest the linear motor gives its stall torque T0 = 5 N m first: its peak, 5 / (0.0254 x 4.448...) lbf in
    m = re.search(r"peak motor torque (\S+) (lbf in),", text)
    assert m, text
    assert float(m.group(1)) == pytest.approx(5.0 / (LBF * IN), rel=1e-3)    # printed with 4 digits
    rec = json.loads(run("dynamics", path, "--motor", "5,20", "--revolutions", "2", "--json"))
    assert rec["units"]["peak_torque"] == "N m"
    assert rec["peak_torque"] == pytest.approx(5.0, rel=1e-9)        # SI by default (the motor's own curve)


def test_sweep_forces_print_in_file_units_csv_si_unless_units(tmp_path):
    path = crank_file(tmp_path, "inch_pound")
    out = tmp_path / "s.csv"
    r = cli_runner.run("sweep", path, "--vary", "omega1=0.001,0.002", "--forces", "--csv", out)
    assert r.returncode == 0, r.stderr
    assert "peak |F| [lbf]" in r.stdout and "peak drive [lbf in]" in r.stdout
    row = r.stdout.splitlines()[1].split()
    # hand statics (10 lbf at 2 in): peak |F| 10 lbf at A, drive 20 lbf in; inertia at 2e-3 rad/s ~1e-6 of it
    assert float(row[-3]) == pytest.approx(10.0, rel=1e-4) and float(row[-2]) == pytest.approx(20.0, rel=1e-4)
    rows = list(csv.DictReader(out.open()))
    assert float(rows[0]["peak_drive"]) == pytest.approx(20 * LBF * IN, rel=1e-6)      # SI by default
    assert float(rows[0]["peak_joint_force"]) == pytest.approx(10 * LBF, rel=1e-6)
    # the push does F r 2 pi of work per turn on the crank; the drive takes it out: -F r 2 pi [J]
    assert float(rows[0]["energy_per_cycle"]) == pytest.approx(-20 * LBF * IN * 2 * np.pi, rel=1e-6)
    r = cli_runner.run("sweep", path, "--vary", "omega1=0.001,0.002", "--forces", "--csv", out, "--units", "in")
    assert r.returncode == 0, r.stderr
    rows = list(csv.DictReader(out.open()))
    units = json.loads((tmp_path / "s.csv.units.json").read_text())["units"]
    assert (units["peak_drive"], units["peak_joint_force"], units["energy_per_cycle"]) == ("lbf in", "lbf", "J")
    assert float(rows[0]["peak_drive"]) == pytest.approx(20.0, rel=1e-6)


def test_sweep_forces_bad_load_is_one_line(tmp_path):
    path = crank_file(tmp_path, "inch_pound")
    r = cli_runner.run("sweep", path, "--vary", "omega1=0.001,0.002", "--force", "1,2@Z")
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1 and "Z" in r.stderr
