"""``linkage sweep --forces`` (issue 27, SPEC "Loads"): each design's peak joint force, peak drive torque and
energy per cycle. Checked against virtual work written here from the geometry (finite differences of the
potential energy), the work of a torque on a rocker over its swing (the swing from the dead-centre
geometry), and ``linkage forces`` run on the same design."""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest

import cli_runner  # the command in this process (tests/cli_runner.py)

D_X, B_LEN, C_LEN = 0.3, 0.3, 0.25
"""Ground pivot D at (0.3, 0) [m], coupler BC and rocker DC lengths [m] of the test four-bar."""

FOURBAR = """\
format = "linkage/1"
name = "fb"
output = "C"
{top}
[parameters]
a = 0.1
omega1 = {omega}

[ground]
A = [0, 0]
D = [0.3, 0.0]

[[inputs]]
kind = "crank"
pivot = "A"
point = "B"
length = "a"
link = "1"
phi0 = "0deg"
omega = "omega1"

[[groups]]
kind = "RRR"
point = "C"
from = ["B", "D"]
lengths = [0.3, 0.25]
links = ["2", "3"]
branch = 1
{loads}
"""

CRANKS = (0.08, 0.1, 0.12)


def write(tmp_path, omega=0.001, loads="", top=""):
    p = tmp_path / "fb.toml"
    p.write_text(FOURBAR.format(omega=omega, loads=loads, top=top))
    return p


def sweep_rows(tmp_path, path, *extra, samples=360):
    out = tmp_path / "sweep.csv"
    r = cli_runner.run("sweep", path, "--vary", "a=" + ",".join(map(str, CRANKS)), "--samples", samples,
                       "--csv", out, *extra)
    assert r.returncode == 0, r.stderr
    rows = list(csv.DictReader(out.open()))
    assert [float(x["valid"]) for x in rows] == [1.0] * len(CRANKS)
    return rows, r.stdout


def coupler_point(a, phi):
    """C of the four-bar A(0,0)-B-C-D(0.3,0) on the branch above the ground line: the intersection of the
    circles |C - B| = 0.3 and |C - D| = 0.25 to the left of B -> D."""
    bx, by = a * np.cos(phi), a * np.sin(phi)
    dx, dy = D_X - bx, -by
    d = np.hypot(dx, dy)
    along = (B_LEN ** 2 - C_LEN ** 2 + d * d) / (2 * d)
    h = np.sqrt(B_LEN ** 2 - along ** 2)
    cx = bx + along * dx / d - h * dy / d
    cy = by + along * dy / d + h * dx / d
    return bx, by, cx, cy


def potential(a, phi, g=9.81):
    """Gravity's potential energy [J] of the default mass model (slender bars of 1 kg/m, each bar's mass at
    its middle: docs/CONVENTIONS.md "The mass model")."""
    bx, by, cx, cy = coupler_point(a, phi)
    return g * (a * by / 2 + B_LEN * (by + cy) / 2 + C_LEN * cy / 2)


def test_peak_drive_torque_under_gravity_is_virtual_work(tmp_path):
    rows, _ = sweep_rows(tmp_path, write(tmp_path), "--gravity", "0,-9.81")
    phi = np.linspace(0.0, 2 * math.pi, 361)                  # the sweep's 360 steps over one turn
    h = 1e-6
    for row in rows:
        a = float(row["a"])
        y0 = coupler_point(a, 0.0)[3]
        assert y0 > 0                                           # the oracle's branch is the file's (C above AD)
        tau = (potential(a, phi + h) - potential(a, phi - h)) / (2 * h)      # quasi-static drive: dV/dphi
        # the crank turns at 1e-3 rad/s: inertia adds ~3e-8 of the gravity torque; central differences ~1e-9
        assert float(row["peak_drive"]) == pytest.approx(np.abs(tau).max(), rel=1e-7)
        # gravity is conservative: no net work over a cycle (only rounding of the periodic trapezoid sum)
        assert abs(float(row["energy_per_cycle"])) < 1e-12 * np.abs(tau).max() * 2 * math.pi
    # the crank's own weight grows with its length (each design its own mass model): the peaks differ
    peaks = [float(r["peak_drive"]) for r in rows]
    assert peaks[0] < peaks[1] < peaks[2]


def rocker_swing(a):
    """The rocker's swing [rad]: its angles at the two dead centres, where A, B and C line up (|AC| = b + a
    and b - a)."""
    angles = []
    for r in (B_LEN + a, B_LEN - a):
        # C on |C| = r and |C - D| = c, above the ground line
        x = (r * r - C_LEN ** 2 + D_X ** 2) / (2 * D_X)
        y = math.sqrt(r * r - x * x)
        angles.append(math.atan2(y, x - D_X))
    return abs(angles[0] - angles[1])


TORQUE = """
[[loads]]
name = "{name}"
kind = "torque"
link = "3"
magnitude = {m}
{stroke}
"""


@pytest.mark.parametrize("case", ["one_stroke", "both_strokes", "constant"])
def test_energy_per_cycle_of_a_torque_on_the_rocker(tmp_path, case):
    T = 2.0
    if case == "one_stroke":        # resists only while the rocker turns counter-clockwise: T x swing
        loads, expected = TORQUE.format(name="brake", m=-T, stroke='stroke = "+"'), 1.0
    elif case == "both_strokes":    # resists both ways (a brake on the rocker): 2 T x swing
        loads = (TORQUE.format(name="up", m=-T, stroke='stroke = "+"')
                 + TORQUE.format(name="down", m=T, stroke='stroke = "-"'))
        expected = 2.0
    else:                           # a constant torque on a rocker does no net work over a cycle
        loads, expected = TORQUE.format(name="brake", m=-T, stroke=""), 0.0
    rows, _ = sweep_rows(tmp_path, write(tmp_path, omega=1.0, loads=loads), "--forces", samples=1440)
    for row in rows:
        swing = rocker_swing(float(row["a"]))
        # the switch at the dead centres leaves a kink in the drive's power (the rocker stops there): the
        # trapezoidal rule's O(h^2) error at 1440 steps is ~1e-6 of T x swing (measured 1e-6)
        assert float(row["energy_per_cycle"]) == pytest.approx(expected * T * swing, abs=1e-5 * T * swing)
        assert float(row["peak_drive"]) > 0


def test_spring_energy_per_cycle_is_zero(tmp_path):
    spring = """
[[loads]]
name = "return"
kind = "spring"
between = [["ground", [0.3, 0.3]], ["3", [0.25, 0]]]
stiffness = 200.0
free_length = 0.1
"""
    rows, _ = sweep_rows(tmp_path, write(tmp_path, omega=1.0, loads=spring), "--forces")
    for row in rows:
        # a spring is conservative: the drive's work over a closed cycle is 0 (rounding of the periodic sum);
        # the peak drive (a few N m) sets the scale
        assert abs(float(row["energy_per_cycle"])) < 1e-9 * float(row["peak_drive"]) * 2 * math.pi
        assert float(row["peak_drive"]) > 0.1                  # the spring does load the drive


def test_row_equals_linkage_forces_on_that_design(tmp_path):
    loads = TORQUE.format(name="brake", m=-1.5, stroke='stroke = "+"') + """
[friction]
mu = 0.1
pin_radius = 0.01
"""
    path = write(tmp_path, omega=3.0, loads=loads)
    rows, text = sweep_rows(tmp_path, path, "--gravity", "0,-9.81", "--force", "5,-20")
    assert "peak |F| [N]" in text and "peak drive [N m]" in text
    units = json.loads((tmp_path / "sweep.csv.units.json").read_text())["units"]
    assert (units["peak_joint_force"], units["peak_drive"], units["energy_per_cycle"]) == ("N", "N m", "J")
    for row in rows:
        r = cli_runner.run("forces", path, "--set", f"a={row['a']}", "--gravity", "0,-9.81", "--force", "5,-20",
                           "--json")
        assert r.returncode == 0, r.stderr
        rec = json.loads(r.stdout)
        peak_joint = max(max(np.hypot(j["Fx"], j["Fy"])) for j in rec["joints"])
        peak_drive = max(np.abs(rec["drives"]["phi1"]))
        # the same computation on the same samples: equal to rounding (the CSV keeps 17 digits)
        assert float(row["peak_joint_force"]) == pytest.approx(peak_joint, rel=1e-12)
        assert float(row["peak_drive"]) == pytest.approx(peak_drive, rel=1e-12)
        assert float(row["energy_per_cycle"]) == pytest.approx(rec["energy"]["drive_work"], rel=1e-12)
        assert rec["energy"]["drive_work"] > 0.1               # friction and the brake take work every cycle


def test_forces_columns_absent_without_forces(tmp_path):
    rows, text = sweep_rows(tmp_path, write(tmp_path))
    assert "peak_drive" not in rows[0] and "peak |F|" not in text
