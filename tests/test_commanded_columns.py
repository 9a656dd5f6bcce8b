"""Columns of commanded values (the inputs' motion law) converted by --angles / --units like the rest (issue
32: such columns were left in SI while the others were converted). Each value is checked against the motion law
written here in the chosen unit, not against the SI file times the unit's factor that the code uses:

* the four-bar's crank: phi1 = 360 deg/s x t (phi1_0 = 0, one turn per second, no acceleration);
* tests/mechanisms/slider_driven.toml (a mm file): s = 60 mm + 30 mm/s t - 2.5 mm/s^2 t^2;
* a motor run: the input's angle ends at 360 deg x revolutions, and the integral of the speed column over
  the time column is the angle column's change (both columns in the same unit).
"""

import json
from pathlib import Path

import numpy as np
import pytest

import cli_runner  # the command in this process (tests/cli_runner.py)

SLIDER = str(Path(__file__).parent / "mechanisms" / "slider_driven.toml")
ROUND = 1e-9        # relative: the motion law evaluated twice in floating point (and %.17g CSV text)
DRIVE_DEG = 1e-4 * 180 / np.pi   # the drive error bound of compare (1e-4 rad), in degrees


def _csv(path):
    return np.genfromtxt(path, delimiter=",", names=True)


def _units(path):
    return json.loads(Path(f"{path}.units.json").read_text())["units"]


def test_simulate_csv_commanded_crank_angle_in_degrees(tmp_path):
    p = cli_runner.run("simulate", "fourbar", "--revolutions", "0.2", "--csv", "a.csv", "--angles", "deg",
                       "--units", "mm", cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    c = _csv(tmp_path / "a.csv")
    assert _units(tmp_path / "a.csv")["cmd_phi1"] == "deg"
    np.testing.assert_allclose(c["cmd_phi1"], 360.0 * c["t"], rtol=ROUND, atol=1e-9)
    assert c["cmd_phi1"][-1] >= 72.0                                       # 0.2 turn (to the step past it)
    # the simulated angle follows the command within the drive bound, in the same unit
    assert np.max(np.abs(c["phi1"] - c["cmd_phi1"])) <= DRIVE_DEG


@pytest.mark.parametrize("unit, per_mm", [("mm", 1.0), ("in", 1 / 25.4), ("m", 1e-3)])
def test_simulate_csv_commanded_slider_position_in_the_chosen_unit(tmp_path, unit, per_mm):
    p = cli_runner.run("simulate", SLIDER, "--revolutions", "0.5", "--csv", "s.csv", "--units", unit, cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    c = _csv(tmp_path / "s.csv")
    assert _units(tmp_path / "s.csv")["cmd_spiston"] == unit
    t = c["t"]
    assert t[-1] > 0.5              # the quadratic term shows: 2.5 t^2 > 0.6 mm, 1e-2 of s, far above ROUND
    np.testing.assert_allclose(c["cmd_spiston"], (60 + 30 * t - 2.5 * t * t) * per_mm, rtol=ROUND)
    # the simulated slider follows the command within the drive bound (1e-4 of the size, ~100 mm)
    assert np.max(np.abs(c["spiston"] - c["cmd_spiston"])) <= 1e-4 * 120 * per_mm


def test_forces_json_inputs_in_degrees_and_inches(tmp_path):
    p = cli_runner.run("forces", "fourbar", "--samples", "9", "--json", "--angles", "deg")
    d = json.loads(p.stdout)
    assert d["units"]["inputs"]["phi1"] == "deg"
    np.testing.assert_allclose(d["inputs"]["phi1"], 360.0 * np.asarray(d["t"]), rtol=ROUND, atol=1e-9)
    p = cli_runner.run("forces", SLIDER, "--samples", "9", "--json", "--units", "in")
    d = json.loads(p.stdout)
    t = np.asarray(d["t"])
    assert d["units"]["inputs"]["spiston"] == "in"
    np.testing.assert_allclose(d["inputs"]["spiston"], (60 + 30 * t - 2.5 * t * t) / 25.4, rtol=ROUND)


@pytest.mark.parametrize("speeds, per_deg_s", [([], 1.0), (["--speeds", "rpm"], 60 / 360)])
def test_dynamics_json_angle_and_speed_columns_agree_in_the_chosen_units(speeds, per_deg_s):
    p = cli_runner.run("dynamics", "fourbar", "--motor", "2,15.7", "--revolutions", "3", "--json", "--angles", "deg",
                       *speeds)
    assert p.returncode == 0, p.stderr
    d = json.loads(p.stdout)
    for run in (d, d["simulated"]):                      # the reduced equation's run and MuJoCo's, alike
        t, phi, w = (np.asarray(run[k], dtype=float) for k in ("t", "phi", "omega"))
        # the run ends at 3 turns: 1080 deg (MuJoCo's samples end within a step of it: 1 deg)
        assert phi[-1] == pytest.approx(1080.0, abs=1.0)
        # the speed column integrates to the angle column: trapezoid over ~360 samples a turn, 1e-5
        assert np.trapezoid(w / per_deg_s, t) == pytest.approx(phi[-1] - phi[0], rel=1e-5)
        # the mean speed: a turn over the last turn's time, in the speed column's unit; under 15.7 rad/s
        assert 0.8 * 15.7 * 180 / np.pi < run["mean_speed"] / per_deg_s < 15.7 * 180 / np.pi
