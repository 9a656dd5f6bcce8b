"""Tests whose expectations come from something the code under test does not share: a hand calculation,
a power balance, the SPEC's definitions, a textbook formula (issue 20: "tests that cannot fail").

Each one names the fault it is there to catch (benchmarks/mutation.py applies them): a load or gravity
applied in the wrong direction (both sides of compare read the same model, so compare cannot see it), a
verdict that ignores an output, a guide's coordinates not converted from mm, a sweep metric defined
differently, an input's rate dropped, the compiled path never taken, a tolerance's scale changed."""

import csv
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import analytic
from sim import service
from sim.front.cli import main
from sim.run import compare as C

LIB = Path(analytic.__file__).parent / "library"


def read_csv(path) -> dict[str, np.ndarray]:
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def cli(*args) -> int:
    return main([str(a) for a in args])


# ----------------------------------------------------------------------------- loads, by power balance
def test_a_force_on_the_output_point_is_applied_as_given(tmp_path):
    # slider-crank turning slowly (0.2 rad/s: the links' inertial torques ~1e-5 of the load's) against
    # F = (-50, 0) N on the piston: the drive's power balances the force's, tau omega + F . vC = 0, so
    # tau = 50 vxC / omega (the reported torque is what reaches the crank: the servo's rotor inertia J alpha1 is
    # not in it, tests/test_drive_torque.py)
    out = tmp_path / "s.csv"
    assert cli("simulate", "slider_crank", "--set", "omega1=0.2", "--force", "-50,0", "--csv", out) == 0
    d = read_csv(out)
    expected = 50.0 * d["vxC"] / d["omega1"]
    # the links' inertia: m r omega^2 r ~ 1e-4 N m against F r = 2.5 N m
    np.testing.assert_allclose(d["tau1"], expected, atol=1e-3 * 50 * 0.05)


def test_gravity_is_applied_downwards_as_given(tmp_path):
    # a lone crank of mass 2 kg with its centre 0.05 m out, at constant speed under g = (0, -9.81): the drive
    # holds the weight's moment, tau = m g cx cos(phi) (its centre turns on a circle: no other torque; the
    # servo's rotor is not in the reported torque)
    text = ('format = "linkage/1"\n[ground]\nA = [0, 0]\n[[inputs]]\nkind = "crank"\npivot = "A"\n'
            'point = "B"\nlength = 0.1\nlink = "1"\n[inertia]\n"1" = { m = 2.0, cx = 0.05, cy = 0.0, I = 0.001 }\n')
    path = tmp_path / "lone.toml"
    path.write_text(text)
    out = tmp_path / "g.csv"
    assert cli("simulate", path, "--gravity", "0,-9.81", "--csv", out) == 0
    d = read_csv(out)
    expected = 2.0 * 9.81 * 0.05 * np.cos(d["phi1"])
    np.testing.assert_allclose(d["tau1"], expected, atol=1e-6)       # the rest: rounding and RK4, 1e-9 N m


def test_a_cutting_force_resists_the_slow_stroke(tmp_path):
    # the shaper's ram against a cutting force F over its slow (cutting) stroke of length H: over one
    # revolution the drive supplies F H (kinetic energy and position return to their start)
    F = 80.0
    out = tmp_path / "c.csv"
    assert cli("simulate", "sixbar", "--cutting-force", F, "--csv", out) == 0
    d = read_csv(out)
    power = d["tau1"] * d["omega1"]
    t = d["t"]
    work = float(np.sum(0.5 * (power[1:] + power[:-1]) * np.diff(t)))
    H = service.figures(service.load("sixbar"))["stroke"]
    # the trapezoid rule over steps of 0.03 rad and the load switched between steps: within 2 % of F H
    assert work == pytest.approx(F * H, rel=2e-2)


# -------------------------------------------------------------------------- the verdict sees every output
@pytest.fixture(scope="module")
def run():
    built, c = service.compare(service.load("fourbar"))
    assert c.passed
    return built, c.trajectory


def test_the_verdict_fails_when_the_drive_torque_is_off(run):
    built, tr = run
    forces = {k: v * 1.05 for k, v in tr.forces.items()}              # 5 % off: 10x the torque tolerance
    assert not C.compare(replace(tr, forces=forces), built).passed


def test_the_verdict_fails_when_a_loop_opens(run):
    built, tr = run
    viol = tr.loop_violation + 10 * C.LOOP_TOL * built.mech.size
    assert not C.compare(replace(tr, loop_violation=viol), built).passed


def test_the_verdict_fails_when_the_drive_lags(run):
    built, tr = run
    commanded = {k: v + 10 * C.DRIVE_TOL for k, v in tr.commanded.items()}
    assert not C.compare(replace(tr, commanded=commanded), built).passed


def test_the_verdict_fails_when_an_output_is_off(run):
    built, tr = run
    outputs = dict(tr.outputs)
    outputs["xE"] = outputs["xE"] + 10 * C.POSITION_TOL * built.mech.size
    assert not C.compare(replace(tr, outputs=outputs), built).passed


def test_angles_are_compared_as_poses(run):
    # an angle and the same angle plus a turn are one pose: the comparison measures the difference modulo
    # 2 pi, so a simulated angle reported a turn away is no error
    built, tr = run
    outputs = dict(tr.outputs)
    outputs["phi3"] = outputs["phi3"] + 2 * np.pi
    c = C.compare(replace(tr, outputs=outputs), built)
    assert c.passed and c.errors["phi3"]["max"] <= C.ANGLE_TOL


def test_tolerances_follow_the_spec_scales():
    # SPEC: a velocity's scale is max(peak, L Omega), an acceleration's max(peak, L Omega^2). A lone crank of
    # 0.1 m at 2 pi rad/s: peak |vx| = L Omega, peak |ax| = L Omega^2, by hand
    text = ('format = "linkage/1"\n[ground]\nA = [0, 0]\n[[inputs]]\nkind = "crank"\npivot = "A"\npoint = "B"\n'
            'length = 0.1\nlink = "1"\n')
    built, c = service.compare(service.load("lone", text=text))
    w, L = 2 * math.pi, 0.1
    assert c.errors["vxB"]["tol"] == pytest.approx(1e-5 * L * w, rel=1e-3)      # peak sampled: 1e-3
    assert c.errors["axB"]["tol"] == pytest.approx(1e-3 * L * w * w, rel=1e-3)
    assert c.errors["xB"]["tol"] == pytest.approx(1e-6 * L, rel=1e-12)
    d = c.as_dict(built)
    assert d["drive_tol"] == 1e-4 and d["loop_tol"] == pytest.approx(1e-6 * L) and d["work_tol"] == 1e-3


def test_a_sliders_drive_error_is_measured_against_the_size():
    # SPEC: drive error 1e-4 L for a slider: commanded minus simulated slide over the size
    mech = service.load(str(Path(__file__).parent / "kinds" / "slider.toml"))
    built, c = service.compare(mech, 0.5)
    tr = c.trajectory
    by_hand = np.max(np.abs(tr.inputs["spiston"] - tr.commanded["spiston"])) / built.mech.size
    assert c.drive_error == pytest.approx(by_hand, rel=1e-12)


# --------------------------------------------------------------------------------------- units of a file
def test_a_guide_through_coordinates_in_a_mm_file_is_in_mm(tmp_path):
    # slider_crank written in mm with the piston line 20 mm above the crank axis: by hand the piston pin
    # runs at y = 0.020 m, x = r cos(phi) + sqrt(l^2 - (r sin(phi) - e)^2)
    # (the piston's guide given by coordinates: through = [0, e] on a horizontal line, no offset)
    text = (LIB / "slider_crank.toml").read_text()
    text = text.replace('output = "C"', 'output = "C"\nunits = "mm"')
    for old, new in (("r = 0.05", "r = 50"), ("l = 0.20", "l = 200"), ("e = 0.0", "e = 20"),
                     ('guide = { through = "A", angle = "0deg" }', 'guide = { through = [0, "e"], angle = "0deg" }'),
                     ('offset = "e"', "offset = 0")):
        assert old in text
        text = text.replace(old, new)
    path = tmp_path / "sc_mm.toml"
    path.write_text(text)
    out = tmp_path / "a.csv"
    assert cli("analyze", path, "--samples", 73, "--csv", out) == 0
    d = read_csv(out)
    r, l, e, phi = 0.05, 0.2, 0.02, d["phi1"]
    np.testing.assert_allclose(d["yC"], e, rtol=1e-12)
    np.testing.assert_allclose(d["xC"], r * np.cos(phi) + np.sqrt(l * l - (r * np.sin(phi) - e) ** 2), rtol=1e-12)


# -------------------------------------------------------------------------------------------- sweeps
def test_sweep_metrics_by_hand_from_analyze(tmp_path):
    # fluctuation = (max - min) / mean of |vE|; mu_min from the textbook: a crank-rocker's transmission angle
    # is extreme where the crank is aligned with the ground, cos(mu) = (l2^2 + l3^2 - (l4 -+ l1)^2) / (2 l2 l3)
    out = tmp_path / "sweep.csv"
    assert cli("sweep", "fourbar", "--vary", "l1=0.08,0.1", "--csv", out) == 0
    rows = read_csv(out)
    for k, l1 in enumerate(rows["l1"]):
        a = tmp_path / f"a{k}.csv"
        assert cli("analyze", "fourbar", "--set", f"l1={l1}", "--samples", 361, "--csv", a) == 0
        d = read_csv(a)
        speed = np.hypot(d["vxE"], d["vyE"])
        assert rows["fluctuation"][k] == pytest.approx((speed.max() - speed.min()) / speed.mean(), rel=1e-2)
        l2, l3, l4 = 0.3, 0.25, 0.3
        mus = [math.acos((l2 * l2 + l3 * l3 - (l4 + s * l1) ** 2) / (2 * l2 * l3)) for s in (-1, 1)]
        mus = [min(m, math.pi - m) for m in mus]
        assert rows["mu_min"][k] == pytest.approx(min(mus), rel=1e-4)      # extremes sampled (360 per turn)


def test_set_and_vary_of_one_parameter_is_refused(tmp_path, capsys):
    assert cli("sweep", "fourbar", "--set", "l1=0.1", "--vary", "l1=0.08,0.1") == 2
    assert "--vary l1 and --set l1 both given" in capsys.readouterr().err


# ------------------------------------------------------------------------------------ inputs' rates
def test_an_input_range_moves_the_input_at_its_speed(tmp_path):
    # sampled between two angles, the input keeps its speed (omega1 = 2 pi rad/s), and the rocker's speed is
    # the chain rule dphi3/dphi1 x omega1, dphi3/dphi1 from the positions (central differences)
    out = tmp_path / "r.csv"
    assert cli("analyze", "fourbar", "--set", "l1=0.2", "--set", "l3=0.1", "--input-range", "45deg:100deg",
               "--samples", 2001, "--csv", out) == 0
    d = read_csv(out)
    np.testing.assert_allclose(d["omega1"], 2 * math.pi, rtol=1e-15)
    slope = np.gradient(np.unwrap(d["phi3"]), d["phi1"])
    # central differences on 0.0275 deg steps: O(h^2) ~ 1e-6 of the slope
    np.testing.assert_allclose(d["omega3"][1:-1], (slope * 2 * math.pi)[1:-1], rtol=1e-4, atol=1e-6)


# -------------------------------------------------------------------------------- the compiled path
def test_the_compiled_path_is_taken_when_asked(monkeypatch):
    from analytic.solver import jit
    if not jit.AVAILABLE:
        pytest.skip("numba is not installed")
    calls = []
    real = jit.solve

    def spy(*args, **kw):
        calls.append(1)
        return real(*args, **kw)
    monkeypatch.setattr(jit, "solve", spy)
    monkeypatch.setenv("LINKAGE_JIT", "1")
    mech = analytic.load("fourbar")
    q = np.linspace(0, 1, 11)
    sol = mech.solve(q, 2 * math.pi, 0.0)
    assert calls, "LINKAGE_JIT=1 and numba installed, yet the numpy path solved"
    # and it solves: the crank tip by hand
    np.testing.assert_allclose(sol["xB"] if "xB" in sol else np.cos(q) * 0.1, 0.1 * np.cos(q), rtol=1e-12)


def test_with_values_keeps_the_new_values_over_the_old():
    mech = service.load("fourbar", {"l1": 0.11})
    assert mech.with_values(l1=0.12).values["l1"] == 0.12 and mech.with_values(l2=0.31).values["l1"] == 0.11
