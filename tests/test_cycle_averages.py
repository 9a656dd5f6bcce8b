"""Averages over one cycle count each instant once (issue 32: "mean drive power" read -0.155 W for a run
with no loads, averaged over slightly more than one turn; a plain mean over linspace(0, T, N) counts the
instant t = 0 = T twice).

Hand values: the mean of cos over a full turn is 0 and its mean square 1/2, whatever the number of
samples; a power A sin(w t) stores and gives back 2 A / w; the mean speed of a point over a turn is its
path's length over the period (the length measured from positions, not from the velocities averaged).
"""

import math

import numpy as np
import pytest

from analytic.applications import averages


@pytest.mark.parametrize("n", [4, 5, 17, 361])
def test_mean_of_cos_over_a_closed_turn_is_zero_whatever_n(n):
    u = np.linspace(0.0, 2 * math.pi, n)
    # the trapezoid rule is exact for cos over whole periods with >= 3 intervals; 1e-12 bounds rounding
    assert abs(averages.closed_mean(np.cos(u + 0.4))) < 1e-12
    assert abs(averages.closed_rms(np.cos(u + 0.4)) ** 2 - 0.5) < 1e-12


def test_closed_mean_leaves_out_the_poses_that_do_not_assemble():
    u = np.linspace(0.0, 2 * math.pi, 361)
    y = np.cos(u) + 3.0
    y[100] = np.nan
    # the two intervals touching the gap are dropped: the rest averages 3 + (mean of cos over them); the
    # missing 2 of 360 intervals move that mean by at most 2/360
    assert abs(averages.closed_mean(y) - 3.0) < 2 / 360


@pytest.mark.parametrize("steps_per_turn", [50.7, 252.3, 1000.1])
@pytest.mark.parametrize("phase", [0.0, 0.3, 1.1])
def test_period_mean_of_a_run_that_ends_past_one_turn(steps_per_turn, phase):
    """A simulated run ends on a whole step, up to one step past the turn: its mean is over exactly T."""
    T = 1.0
    w = 2 * math.pi / T
    h = T / steps_per_turn
    t = np.arange(0.0, T + h, h)
    assert t[-1] > T                                                 # the run does overshoot the turn
    y = 2.0 + np.cos(w * t + phase)
    # the trapezoid rule on a periodic function over one period, its two cut ends interpolated linearly:
    # each cut interval errs by at most (w h)^2 / 8 of the amplitude over a length h, so <= (w h)^2 h / (4 T)
    bound = (w * h) ** 2 * h / (4 * T)
    assert abs(averages.period_mean(t, y, T) - 2.0) < bound
    assert abs(averages.period_rms(t, np.cos(w * t + phase), T) ** 2 - 0.5) < 2 * bound


def test_flywheel_energy_of_a_sine_power_is_2_A_over_w():
    T, A = 0.5, 3.0
    w = 2 * math.pi / T
    h = T / 400.3
    t = np.arange(0.0, 2.2 * T, h)
    tt, e = averages.excess_energy(t, 7.0 + A * np.sin(w * t), T)       # a mean of 7 W is drawn off first
    assert tt[-1] - tt[0] == pytest.approx(T, rel=1e-12)
    # the swing of the integral is 2 A / w; sampled every h, each extremum is missed by <= (w h)^2 / 8 of A / w
    # and the trapezoid sum over the half period errs by <= (w h)^2 / 6 of it: (w h)^2 / 2 of A / w bounds all
    assert np.ptp(e) == pytest.approx(2 * A / w, abs=(w * h) ** 2 / 2 * A / w)
    assert abs(e[-1]) < 1e-9 * A / w                                  # the excess over a period nets to zero


def test_analysis_mean_speed_is_path_length_over_period():
    """The summary's mean speed over a turn equals the coupler curve's length / the period (from positions)."""
    from sim import service
    mech = service.load("fourbar", {})
    a = service.analyze(mech, 361, 1.0)
    p = mech.output_point
    dense = service.analyze(mech, 200001, 1.0, figures=False)
    x, y = dense.solution["x" + p], dense.solution["y" + p]
    length = float(np.sum(np.hypot(np.diff(x), np.diff(y))))
    T = mech.duration(1.0)
    # the chord sum of 200,000 segments underestimates the length by ~1e-10 relative; the 361-sample
    # trapezoid mean of a smooth periodic speed converges faster than any power: 1e-7 bounds both, where
    # counting t = 0 twice (the old mean) is off by (v(0) - mean) / 361, about 1e-3 here
    assert a.figures[f"v{p}_mean"] == pytest.approx(length / T, rel=1e-7)


def test_sweep_mean_speed_is_path_length_over_period():
    from analytic.applications import studies
    from analytic.closed_forms import fourbar
    from sim import service
    mech = service.load("fourbar", {})
    base = fourbar.FourBar(**{k: v for k, v in mech.parameters.items() if k in fourbar.FourBar.__dataclass_fields__})
    rows, _ = studies.sweep(base, {"l1": [0.1]}, samples=90)
    row = rows[0]
    dense = service.analyze(mech, 200001, 1.0, figures=False)
    xd, yd = dense.solution["xE"], dense.solution["yE"]
    length = float(np.sum(np.hypot(np.diff(xd), np.diff(yd))))
    # as above; 90 samples of a smooth periodic speed still converge to 1e-6 (the old mean: ~5e-3 off)
    assert row.values["speed_mean"] == pytest.approx(length / mech.duration(1.0), rel=1e-6)


def test_shaking_force_rms_does_not_depend_on_the_sample_count():
    from sim import service
    mech = service.load("fourbar", {})
    coarse = service.force_peaks(service.forces_run(mech, samples=25))["shaking"]["F_rms"]
    fine = service.force_peaks(service.forces_run(mech, samples=3601))["shaking"]["F_rms"]
    # 24 intervals of a smooth periodic force: the trapezoid rule converges faster than any power (1e-7 is
    # 1e3 times what remains at 25 samples); counting the
    # closed end twice would put the 25-sample RMS ~2 % off
    assert coarse == pytest.approx(fine, rel=1e-7)


def test_least_squares_counterweights_do_not_depend_on_the_sample_count():
    """The least-squares fit minimises the RMS over a turn: each instant weighs once, so a coarse run finds
    the counterweights a fine one does."""
    from sim import service
    mech = service.load("sixbar", {})
    coarse = service.forces_run(mech, samples=25, balance=()).balance.counterweights
    fine = service.forces_run(mech, samples=3601, balance=()).balance.counterweights
    assert [w.link for w in coarse] == [w.link for w in fine]
    for a, b in zip(coarse, fine):
        # as the RMS above: 1e-7 of the counterweight's moment m r; the unweighted fit moves it ~1e-3
        assert math.hypot(a.m * a.u - b.m * b.u, a.m * a.v - b.m * b.v) < 1e-7 * math.hypot(b.m * b.u, b.m * b.v)


def test_the_sheets_mean_drive_power_of_a_run_without_loads_is_zero():
    """No loads, constant speed: the drive only trades kinetic energy with the links, so over a turn its
    mean power is zero, on the first turn as on the second; and the swing of the flywheel energy is the
    swing of the links' kinetic energy (the power's integral, by the work-energy theorem)."""
    from sim import service
    from sim.output.plot import drive_power
    mech = service.load("fourbar", {})
    for revolutions in (1.0, 2.0):
        built, c = service.compare(mech, revolutions)
        power, mean, swing = drive_power(c, built)
        peak = float(np.max(np.abs(power)))
        # one turn of 252 steps of a smooth periodic power: the trapezoid over exactly T leaves ~1e-7 of the
        # peak; averaged over the run (slightly more than a turn, as the sheet did) it read ~3e-3 of it
        assert abs(mean) < 1e-5 * peak, (revolutions, mean, peak)
    from analytic.applications import motor
    from sim.model import body_inertias
    reduced = motor.reduce(built.mech, body_inertias(built.model, mech.links), 0.0)
    u = np.linspace(0.0, 2 * np.pi, 20001)
    w = built.mech.inputs[0].motion.rate
    # the links' kinetic energy 1/2 J(u) w^2 from the reduced inertia (kinematic coefficients, not the
    # inverse dynamics); the power sampled every 0.025 rad misses the extrema by ~(0.025)^2 / 8: 1e-3
    assert swing == pytest.approx(0.5 * w * w * float(np.ptp(reduced.J(u))), rel=1e-3)
