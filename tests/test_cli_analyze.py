"""``linkage analyze``: CSV columns, JSON figures, and one-line errors with exit code 2."""

import csv
import json
import math

import numpy as np
import pytest

import cli_runner  # the command in this process (tests/cli_runner.py)



def run(*args):
    return cli_runner.run(*args)


SPEC_COLUMNS = {   # SPEC.md's output names, written out here so that dropping one from the code fails
    "fourbar": "phi2 phi3 omega2 omega3 alpha2 alpha3 xE yE vxE vyE axE ayE mu",
    "sixbar": "s phi3 phi4 xC ds omega3 omega4 vxC dds alpha3 alpha4 axC",
    "fivebar": "S theta3 dS omega3 ddS alpha3 xP yP vxP vyP axP ayP",
}


@pytest.mark.parametrize("mech,inputs", [
    ("fourbar", ["phi1", "omega1", "alpha1"]),
    ("sixbar", ["phi1", "omega1", "alpha1"]),
    ("fivebar", ["phi2", "phi4", "omega2", "omega4", "alpha2", "alpha4"])])
def test_csv_has_time_inputs_and_every_spec_output(tmp_path, mech, inputs):
    out = tmp_path / "run.csv"
    r = run("analyze", mech, "--samples", "9", "--csv", str(out))
    assert r.returncode == 0, r.stderr
    rows = list(csv.reader(out.open()))
    assert rows[0] == ["t", *inputs, *SPEC_COLUMNS[mech].split()]
    assert len(rows) == 10
    t = np.array([float(r[0]) for r in rows[1:]])
    assert t[0] == 0 and abs(t[-1] - 1.0) < 1e-15          # one revolution at 2 pi rad/s lasts 1 s


def test_set_accepts_degrees_and_json_reports_figures():
    r = run("analyze", "sixbar", "--set", "phi1_0=30deg", "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert out["parameters"]["phi1_0"] == pytest.approx(math.pi / 6, abs=1e-15)
    f = out["figures"]
    # Hand check: the guide swings by 2 asin(l1/l6); the stroke is close to 2 l3 sin(psi).
    assert f["swing"] == pytest.approx(2 * math.asin(0.11 / 0.38), abs=1e-15)
    assert f["stroke"] == pytest.approx(2 * 0.54 * 0.11 / 0.38, rel=1e-3)   # rod tilt changes it slightly


def test_fourbar_json_has_grashof_and_transmission_angle():
    out = json.loads(run("analyze", "fourbar", "--json").stdout)["figures"]
    assert (out["grashof"], out["inversion"], out["crank_turns_fully"]) == ("grashof", "crank-rocker", True)
    # mu_min of a crank-rocker is at phi1 = 0 (B nearest D): cos = (l2^2 + l3^2 - (l4-l1)^2) / (2 l2 l3)
    assert out["mu_min"] == pytest.approx(math.acos((0.09 + 0.0625 - 0.04) / (2 * 0.3 * 0.25)), abs=1e-12)


@pytest.mark.parametrize("args,pattern", [
    (["fourbar", "--set", "l1=-1"], r"l1=-1(\.0)? is not a valid length"),
    (["fourbar", "--set", "bogus=1"], "parameters: l1, l2"),
    (["fourbar", "--set", "l1=abc"], "is not a number"),
    (["fourbar", "--set", "l1=0.2", "--set", "l3=0.1"], "cannot turn fully .*limit angles"),
    (["fivebar", "--set", "l1=0.1"], "B and C can meet"),
    (["sixbar", "--set", "l3=0.3"], "run off the guide bar"),
    (["sixbar", "--set", "l4=0.001"], "cannot reach the ram line"),
    (["fourbar", "--samples", "1"], "samples=1 must be an integer"),
    (["fourbar", "--csv", "/nonexistent/x.csv"], "does not exist"),
])
def test_bad_input_is_one_line_exit_2(args, pattern):
    r = run("analyze", *args)
    assert r.returncode == 2
    assert "Traceback" not in r.stderr and len(r.stderr.strip().splitlines()) == 1
    assert __import__("re").search(pattern, r.stderr), r.stderr


def test_between_the_limits_when_asked_explicitly(tmp_path):
    out = tmp_path / "rocker.csv"
    r = run("analyze", "fourbar", "--set", "l1=0.2", "--set", "l3=0.1", "--input-range", "45deg:100deg",
            "--csv", str(out))
    assert r.returncode == 0, r.stderr
    data = np.genfromtxt(out, delimiter=",", names=True)
    assert np.all(np.isfinite(data["phi3"]))
