"""MuJoCo under a motor (sim/run/motor.py) against the reduced equation of motion, its energy, the flywheel
sizing checked by both, and `linkage dynamics` on the command line."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import analytic
from analytic.applications import motor as am
from sim import model as M
from sim.run import motor as sm
from sim.front.cli import main
from sim.front.cli.options import cutting_direction


def _shaper_loads(F=20.0):
    mech = analytic.load("sixbar")
    return mech, M.Loads(gravity=(0.0, -9.81), force=(cutting_direction(mech) * F, 0.0), slow_stroke_only=True)


@pytest.fixture(scope="module")
def shaper():
    mech, loads = _shaper_loads()
    return sm.dynamics(mech, loads, am.LinearMotor(5.0, 20.0), flywheel=0.01, revolutions=6)


def test_mujoco_matches_reduced_equation_with_cutting_force(shaper):
    a = shaper.agreement
    assert a.mean_speed <= sm.SPEED_TOL and a.fluctuation <= sm.CS_TOL and a.curve <= sm.CURVE_TOL
    assert a.passed and shaper.passed
    # the two runs are compared where they differ: the cutting stroke makes the speed fluctuate
    assert shaper.run.fluctuation > 0.1


def test_mujoco_matches_with_cutting_force_crank_turning_backwards():
    """A crank turning clockwise: the load window's ends map to other advances, and one more switch
    appears where the phase wraps; both answers must switch the force at the same angles."""
    from sim import service
    mech = service.load("sixbar", {"omega1": -2 * math.pi})
    loads = M.Loads(force=(cutting_direction(mech) * 20.0, 0.0), slow_stroke_only=True)
    d = sm.dynamics(mech, loads, am.LinearMotor(5.0, 20.0), flywheel=0.01, revolutions=4)
    assert d.agreement.passed, d.agreement
    assert np.all(np.diff(d.run.phi) < 0)          # it does turn backwards


def test_motor_work_per_cycle_is_cutting_work_plus_kinetic_energy_change(shaper):
    """Power balance from the geometry: over one turn gravity does no net work and the cutting force F
    does -F x stroke (the ram's travel between its extremes), so W_motor = F stroke + dT."""
    mech, r = shaper.mech, shaper.run
    q = np.linspace(0, 2 * math.pi, 20001)
    x = mech.solve(q)["x" + mech.output_point]
    stroke = float(np.nanmax(x) - np.nanmin(x))
    ta, tb = r.last_revolution
    red = r.reduced
    T = [0.5 * float(red.J(r.dense(t)[0])) * float(r.dense(t)[1]) ** 2 for t in (ta, tb)]
    # 1e-6 of the cutting work: the stroke's sampling (2e-5 deg) and the integrator's tolerance
    assert r.energy_per_cycle == pytest.approx(20.0 * stroke + T[1] - T[0], rel=1e-6)


def test_mujoco_energy_coasting_100_revolutions():
    mech = analytic.load("fourbar")
    make, _ = sm.reduced_for(mech, M.Loads())
    red = make(0.0)
    coast = am.Coast(10.0)
    r = am.run(red, coast, 3, 10.0)
    built = sm.build(mech, M.Loads(), red, coast, float(np.abs(r.omega).max()))
    s = sm.simulate(built, red, coast, 100, 10.0)
    T = sm.kinetic_energy(built, s.qpos[::40], s.qvel[::40])
    # the same energy as the reduced equation at the start (same mass model, same state)
    assert T[0] == pytest.approx(0.5 * float(red.J(0.0)) * 100.0, rel=1e-9)
    assert np.max(np.abs(T / T[0] - 1)) < sm.ENERGY_TOL


def test_table_motor_in_both():
    mech = analytic.load("fourbar")
    table = am.TableMotor((0.0, 8.0, 16.0, 24.0), (1.2, 1.1, 0.7, 0.0))
    d = sm.dynamics(mech, M.Loads(gravity=(0.0, -9.81)), table, flywheel=0.003, revolutions=5)
    assert d.agreement.passed, d.agreement
    # the speed sits on the table's falling pieces, not at a row
    assert 8.0 < d.run.mean_speed < 24.0


@pytest.mark.slow
def test_flywheel_sizing_checked_by_both():
    mech, loads = _shaper_loads()
    d = sm.dynamics(mech, loads, am.LinearMotor(5.0, 20.0), None, target=0.05, revolutions=20)
    assert d.flywheel > 0
    # 2 %: the bound, in both answers
    assert d.run.fluctuation == pytest.approx(0.05, rel=sm.SIZING_TOL)
    assert d.sim.fluctuation == pytest.approx(0.05, rel=sm.SIZING_TOL)
    assert d.sizing_passed and d.passed


@pytest.mark.slow
def test_a_heavy_flywheel_is_sized_on_a_run_long_enough_to_start_up():
    # the shaper under a 500 N cutting force and a 200 N m motor: the flywheel for Cs = 0.02 (~12 kg m^2)
    # takes ~3.6 s (~9 turns) to start, so 10 revolutions from rest end before the steady cycle (Cs 0.024)
    mech = analytic.load("sixbar")
    loads = M.Loads(force=(cutting_direction(mech) * 500.0, 0.0), slow_stroke_only=True)
    d = sm.dynamics(mech, loads, am.LinearMotor(200.0, 20.0), None, target=0.02, revolutions=10,
                    simulate_too=False)
    assert d.revolutions_asked == 10 and d.run.revolutions > 10
    # the target, a number the user gave: within the 2 % after the run was extended
    assert d.run.fluctuation == pytest.approx(0.02, rel=sm.SIZING_TOL) and d.sizing_passed


def test_cli_json_fields(capsys):
    rc = main(["dynamics", "fourbar", "--motor", "1,20", "--gravity", "0,-9.81", "--revolutions", "3", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert rc == 0
    for k in ("t", "phi", "omega", "flywheel", "mean_speed", "fluctuation", "startup_time"):
        assert k in out
    for k in ("t", "phi", "omega", "mean_speed", "fluctuation", "passed"):
        assert k in out["simulated"]
    assert len(out["t"]) == len(out["omega"]) and out["simulated"]["passed"] is True
    assert 0 < out["mean_speed"] < 20.0


def test_cli_rpm_and_csv(tmp_path, capsys):
    path = tmp_path / "run.csv"
    rc = main(["dynamics", "slider_crank", "--motor", "0.5,120rpm", "--revolutions", "2", "--csv", str(path)])
    capsys.readouterr()
    assert rc == 0
    data = np.genfromtxt(path, delimiter=",", names=True)
    assert set(data.dtype.names) == {"t", "phi", "omega", "torque"}
    assert np.all(np.diff(data["t"]) > 0) and data["omega"][0] == 0.0      # from rest, in time order
    from sim.front.cli.dynamics import parse_motor
    assert parse_motor("0.5,120rpm").W0 == pytest.approx(4 * math.pi, rel=1e-15)   # 120 rpm = 4 pi rad/s


def test_cli_disagreement_exits_1(capsys):
    # a step ten times too coarse: MuJoCo's Cs is off by more than the tolerance and the verdict says so
    rc = main(["dynamics", "fourbar", "--motor", "1,20", "--gravity", "0,-9.81", "--revolutions", "3",
               "--timestep", "0.01"])
    assert rc == 1 and "FAIL" in capsys.readouterr().out


@pytest.mark.parametrize("argv, word", [
    (["--motor", "0,20"], "T0"),
    (["--motor", "1,-5"], "W0"),
    (["--motor", "1"], "T0,W0"),
    (["--motor", "1,20", "--flywheel", "-1"], "--flywheel"),
    (["--motor", "1,20", "--target-fluctuation", "1.5"], "--target-fluctuation"),
    (["--motor", "1,20", "--target-fluctuation", "0"], "--target-fluctuation"),
    (["--motor", "1,20", "--flywheel", "0.1", "--target-fluctuation", "0.1"], "not both"),
    ([], "--motor"),
    (["--motor", "1,20", "--input-range", "0:1"], "--input-range"),
    (["--motor", "0.05,20", "--force", "0,-50"], "stalls"),
])
def test_cli_bad_inputs(argv, word, capsys):
    rc = main(["dynamics", "fourbar", "--revolutions", "2"] + argv)
    err = capsys.readouterr().err.strip()
    assert rc == 2 and word in err and "\n" not in err and err.startswith("linkage: error:")


def test_cli_table_errors(tmp_path, capsys):
    bad = tmp_path / "m.csv"
    bad.write_text("omega,tau\n0,1\n10,0.5\n5,0\n")
    rc = main(["dynamics", "fourbar", "--motor-table", str(bad)])
    err = capsys.readouterr().err
    assert rc == 2 and "row 3" in err
    rc = main(["dynamics", "fivebar", "--motor", "phi2=1,20"])
    assert rc == 2 and "no motor for phi4" in capsys.readouterr().err
    rc = main(["dynamics", "fivebar", "--motor", "1,20", "--motor", "phi4=1,20"])
    assert rc == 2 and "name each" in capsys.readouterr().err
    rc = main(["dynamics", "fivebar", "--motor", "phi2=1,20", "--motor", "phi9=1,20"])
    assert rc == 2 and "no input 'phi9'" in capsys.readouterr().err


def test_cli_plot_sheet(tmp_path, capsys):
    out = tmp_path / "dyn.png"
    rc = main(["dynamics", "fourbar", "--motor", "1,20", "--revolutions", "2", "--plot", str(out)])
    capsys.readouterr()
    assert rc == 0
    import matplotlib.image
    img = matplotlib.image.imread(str(out))
    assert img.shape[0] > 500 and img.shape[1] > 500
    assert np.ptp(img[..., :3]) > 0.5          # not blank: dark curves and text on white
    assert not list(tmp_path.glob(".dyn.*"))    # no temporary file left behind


def test_the_sheet_speaks_the_display_units(shaper):
    """The dynamics sheet's speeds follow --speeds/--angles: rad/s by default, rpm on request (60 rpm per turn a
    second: 60 / (2 pi) rpm per rad/s, by hand), the same curve; the angle axis in rad or deg."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from analytic.quantities import Display
    from sim.output import dynamics_plot as dp
    fig, (a_si, a_rpm, a_up) = plt.subplots(3, 1)
    try:
        dp.speed_vs_angle(shaper, a_si, Display())
        dp.speed_vs_angle(shaper, a_rpm, Display(angle="deg", speed="rpm"))
        dp.startup(shaper, a_up, Display(speed="rpm"))
        assert a_si.get_ylabel() == "speed [rad/s]" and a_rpm.get_ylabel() == "speed [rpm]"
        assert a_si.get_xlabel().endswith("[rad]") and a_rpm.get_xlabel().endswith("[deg]")
        assert a_up.get_ylabel() == "speed [rpm]"
        curve = {ax: next(ln for ln in ax.lines if ln.get_label() == "reduced equation") for ax in (a_si, a_rpm)}
        x_si, w_si = curve[a_si].get_data()
        x_rpm, w_rpm = curve[a_rpm].get_data()
        # unit conversion of the same samples: rounding only
        np.testing.assert_allclose(w_rpm, np.asarray(w_si) * 60 / (2 * math.pi), rtol=1e-12)
        np.testing.assert_allclose(x_rpm, np.asarray(x_si) * 180 / math.pi, rtol=1e-12, atol=1e-9)
        # the steady speed is in the run's own units: the mean of the last turn lies inside the plotted curve
        assert np.min(w_si) < shaper.run.mean_speed < np.max(w_si)
    finally:
        plt.close(fig)


def test_two_motors_on_the_fivebar_both_answers(capsys):
    rc = main(["dynamics", "fivebar", "--motor", "phi2=1,20", "--motor", "phi4=0.8,15", "--flywheel", "phi2=0.001",
               "--gravity", "0,-9.81", "--revolutions", "3", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert rc == 0 and out["passed"] and out["simulated"]["passed"]
    for n in ("phi2", "phi4"):
        # the bounds for each input
        assert abs(out["simulated"]["mean_speed"][n] / out["mean_speed"][n] - 1) <= sm.SPEED_TOL
        assert abs(out["simulated"]["fluctuation"][n] - out["fluctuation"][n]) <= sm.CS_TOL
    assert out["flywheel"] == {"phi2": 0.001, "phi4": 0.0}
    # two different motors: two different steady speeds, each below its no-load speed on average
    assert out["mean_speed"]["phi4"] < 15.0 and abs(out["mean_speed"]["phi2"] - out["mean_speed"]["phi4"]) > 0.5
