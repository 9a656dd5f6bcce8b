"""``linkage simulate`` and ``linkage compare`` from the command line."""

import json

import numpy as np
import pytest

import cli_runner  # the command in this process (tests/cli_runner.py)


def run(*args):
    return cli_runner.run(*args)


def test_compare_json_has_the_documented_fields_and_passes():
    r = run("compare", "fivebar", "--set", "omega4=720deg", "--json")
    assert r.returncode == 0, r.stdout + r.stderr
    out = json.loads(r.stdout)
    assert {"mechanism", "parameters", "units", "loads", "input_range", "timestep", "integrator", "revolutions",
            "steps", "cpu_seconds", "errors", "drive_error", "drive_tol", "max_loop_violation", "loop_tol",
            "work_balance", "work_tol", "passed"} <= set(out)
    assert out["parameters"]["omega4"] == pytest.approx(4 * 3.141592653589793)   # the context travels along
    assert out["passed"] is True and out["integrator"] == "rk4"
    assert set(out["errors"]) == {"S", "theta3", "dS", "omega3", "ddS", "alpha3",
                                  "xP", "yP", "vxP", "vyP", "axP", "ayP", "tau2", "tau4"}
    for e in out["errors"].values():
        assert {"max", "rms", "peak", "tol", "unit"} <= set(e) and e["max"] <= e["tol"]


def test_compare_exits_1_when_a_tolerance_fails():
    # A 20 ms step leaves ~5e-6 rad of position error: over the 1e-6 tolerance.
    r = run("compare", "fourbar", "--timestep", "0.02")
    assert r.returncode == 1 and "FAIL" in r.stdout


def test_simulate_writes_a_csv_of_every_step(tmp_path):
    out = tmp_path / "sim.csv"
    r = run("simulate", "sixbar", "--revolutions", "0.5", "--csv", str(out))
    assert r.returncode == 0, r.stderr
    data = np.genfromtxt(out, delimiter=",", names=True)
    h = data["t"][1] - data["t"][0]
    assert abs(data["t"][-1] - 0.5) < h and len(data) == round(data["t"][-1] / h) + 1   # 0.5 s, both ends
    for col in ("t", "phi1", "s", "xC", "vxC", "axC", "loop_violation", "tau1", "cmd_phi1"):
        assert col in data.dtype.names
    units = json.loads((tmp_path / "sim.csv.units.json").read_text())["units"]
    assert units["t"] == "s" and units["phi1"] == "rad" and units["vxC"] == "m/s" and units["tau1"] == "N m"


def test_simulate_refuses_a_crank_that_cannot_turn():
    r = run("simulate", "fourbar", "--set", "l1=0.2", "--set", "l3=0.1")
    assert r.returncode == 2 and "limit angles" in r.stderr and "Traceback" not in r.stderr


def test_compare_reports_torque_and_work_balance_with_a_cutting_force():
    r = run("compare", "sixbar", "--cutting-force", "500", "--json")
    assert r.returncode == 0, r.stdout + r.stderr
    out = json.loads(r.stdout)
    assert out["errors"]["tau1"]["peak"] > 40          # 500 N on a ~0.1 m effective lever
    assert out["work_balance"] <= 1e-3


@pytest.mark.parametrize("args,pattern", [
    (["fourbar", "--cutting-force", "-10"], "must be >= 0"),
    (["fourbar", "--gravity", "1"], "is not two numbers"),
    (["fourbar", "--inertia", "/no/such.json"], "--inertia /no/such.json: cannot read it"),
])
def test_bad_load_arguments(args, pattern):
    r = run("compare", *args)
    assert r.returncode == 2 and pattern in r.stderr and "Traceback" not in r.stderr


def test_inertia_file_with_a_bad_value_names_it(tmp_path):
    f = tmp_path / "inertia.json"
    f.write_text(json.dumps({"2": {"m": -1, "cx": 0, "cy": 0, "I": 0.01}}))
    r = run("compare", "fourbar", "--inertia", str(f))
    assert r.returncode == 2 and "2: mass m=-1" in r.stderr
    f.write_text(json.dumps({"flywheel": {"m": 1, "cx": 0, "cy": 0, "I": 0.01}}))
    r = run("compare", "fourbar", "--inertia", str(f))
    assert r.returncode == 2 and "no link 'flywheel'" in r.stderr
