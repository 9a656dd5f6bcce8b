"""Inverse dynamics: hand-checkable cranks, the power balance, and MuJoCo's actuator torques."""

import math

import numpy as np
import pytest

import analytic
from analytic import ParameterError
from analytic.closed_forms import fivebar
from analytic.closed_forms import fourbar
from analytic.closed_forms import sixbar
from analytic.applications import torque
from analytic.mass import Inertia
from builtin_dynamics import body_motions, torques
from sim import model
from sim import service

G = 9.81


def _crank_only(inertia):
    return {"crank": inertia}


def test_a_balanced_crank_needs_no_torque_at_constant_speed():
    mech = fourbar.FourBar()
    phi = np.linspace(0, 2 * math.pi, 73)
    tau = torques("fourbar", mech, {"1": phi}, {"1": 5.0}, {"1": 0.0},
                  _crank_only(Inertia(m=2.0, cx=0.0, cy=0.0, I=0.01)), gravity=(0.0, -G))["tau1"]
    assert np.abs(tau).max() < 1e-15          # only rounding: no term survives


def test_a_point_mass_crank_under_gravity_needs_m_g_r_cos_phi():
    mech = fourbar.FourBar()
    m, r = 1.5, 0.08
    phi = np.linspace(0, 2 * math.pi, 73)
    tau = torques("fourbar", mech, {"1": phi}, {"1": 5.0}, {"1": 0.0},
                  _crank_only(Inertia(m=m, cx=r, cy=0.0, I=1e-12)), gravity=(0.0, -G))["tau1"]
    # centripetal acceleration is normal to the velocity coefficient: only gravity remains
    assert np.allclose(tau, m * G * r * np.cos(phi), atol=1e-13)


def test_crank_inertia_and_armature_give_I_alpha():
    mech = fourbar.FourBar()
    tau = torques("fourbar", mech, {"1": 0.3}, {"1": 2.0}, {"1": 7.0},
                  _crank_only(Inertia(m=1.0, cx=0.0, cy=0.0, I=0.02)), armature={"1": 0.05})["tau1"]
    assert abs(tau - (0.02 + 0.05) * 7.0) < 1e-14


def _kinetic(name, mech, st, inertias):
    motion = body_motions(name, mech, st)
    total = 0.0
    for body, b in inertias.items():
        mo = motion[body]
        c, s = np.cos(mo.theta), np.sin(mo.theta)
        rx, ry = b.cx * c - b.cy * s, b.cx * s + b.cy * c
        vx, vy = mo.vx - mo.omega * ry, mo.vy + mo.omega * rx
        total = total + 0.5 * b.m * (vx ** 2 + vy ** 2) + 0.5 * b.I * mo.omega ** 2
    return total


INERTIAS = {
    "fourbar": {"crank": Inertia(0.3, 0.05, 0.0, 2e-4), "coupler": Inertia(0.8, 0.12, 0.03, 6e-3),
                "rocker": Inertia(0.5, 0.1, -0.01, 3e-3)},
    "sixbar": {"crank": Inertia(0.3, 0.05, 0.0, 2e-4), "guide": Inertia(1.2, 0.27, 0.0, 3e-2),
               "block": Inertia(0.2, 0.0, 0.0, 1e-4), "rod": Inertia(0.3, 0.07, 0.0, 5e-4),
               "ram": Inertia(3.0, 0.0, 0.0, 1e-2)},
}


@pytest.mark.parametrize("name", ["fourbar", "sixbar"])
def test_torque_times_speed_is_the_rate_of_kinetic_energy(name):
    # Power balance, an independent route: tau omega = dT/dt with T from the body motions, by central
    # differences in time (h = 1e-5 s: truncation ~ h^2 T''' ~ 1e-9 of the peak power).
    mech = fourbar.FourBar(alpha1=2.0) if name == "fourbar" else sixbar.SixBar(alpha1=2.0)
    module = fourbar if name == "fourbar" else sixbar
    t = np.linspace(0.05, 0.95, 91)
    h = 1e-5
    phi, w, a = module.drive(mech, t)
    tau = torques(name, mech, {"1": phi}, {"1": w}, {"1": a}, INERTIAS[name])["tau1"]
    T = lambda tt: _kinetic(name, mech, module.solve(mech, *module.drive(mech, tt)), INERTIAS[name])  # noqa
    dT = (T(t + h) - T(t - h)) / (2 * h)
    assert np.abs(tau * w - dT).max() <= 1e-6 * np.abs(dT).max()


def test_fivebar_torques_split_the_power_between_the_two_cranks():
    mech = fivebar.FiveBar(omega4=4 * math.pi, alpha2=1.0)
    inert = {"crank2": Inertia(0.2, 0.03, 0, 1e-4), "link3": Inertia(0.4, 0.15, 0, 4e-3),
             "block": Inertia(0.1, 0, 0, 5e-5), "crank4": Inertia(0.2, 0.04, 0, 1e-4)}
    t = np.linspace(0.05, 0.95, 91)
    h = 1e-5
    d = fivebar.drive(mech, t)
    tau = torques("fivebar", mech, {"2": d[0], "4": d[1]}, {"2": d[2], "4": d[3]}, {"2": d[4], "4": d[5]}, inert)
    T = lambda tt: _kinetic("fivebar", mech, fivebar.solve(mech, *fivebar.drive(mech, tt)), inert)  # noqa
    dT = (T(t + h) - T(t - h)) / (2 * h)
    power = tau["tau2"] * d[2] + tau["tau4"] * d[3]
    assert np.abs(power - dT).max() <= 1e-6 * np.abs(dT).max()


@pytest.mark.parametrize("kw,pattern", [({"m": 0.0, "cx": 0, "cy": 0, "I": 1.0}, "mass m=0.0"),
                                         ({"m": 1.0, "cx": 0, "cy": 0, "I": -1.0}, "moment of inertia I=-1.0"),
                                         ({"m": 1.0, "cx": float("nan"), "cy": 0, "I": 1.0}, "cx=nan")])
def test_unphysical_inertia_is_refused(kw, pattern):
    with pytest.raises(ParameterError, match=pattern):
        Inertia(**kw)


def test_an_unknown_body_is_named():
    with pytest.raises(ParameterError, match="no body named flywheel"):
        torques("fourbar", fourbar.FourBar(), {"1": 0.0}, {"1": 1.0}, {"1": 0.0},
                {"flywheel": Inertia(1, 0, 0, 1)})


BODY_TO_LINK = {"fourbar": {"crank": "1", "coupler": "2", "rocker": "3"},
                "sixbar": {"crank": "1", "guide": "3", "block": "block", "rod": "4", "ram": "ram"},
                "fivebar": {"crank2": "2", "link3": "3", "block": "block", "crank4": "4"}}
FIVE_INERTIAS = {"crank2": Inertia(0.2, 0.03, 0.01, 1e-4), "link3": Inertia(0.4, 0.15, -0.02, 4e-3),
                 "block": Inertia(0.1, 0.01, 0, 5e-5), "crank4": Inertia(0.2, 0.04, 0, 1e-4)}


@pytest.mark.parametrize("name", ["fourbar", "sixbar", "fivebar"])
def test_the_general_drive_forces_equal_the_built_in_torques(name):
    # Two independent routes: analytic.applications.torque works on any mechanism through the general solver and
    # the file's link frames; tests/builtin_dynamics.py on the built-ins' closed forms and their own body frames.
    mech = analytic.load(name, **({"alpha1": 2.0} if name != "fivebar" else {"omega4": 4 * math.pi, "alpha2": 1.0}))
    inertias = FIVE_INERTIAS if name == "fivebar" else INERTIAS[name]
    t = np.linspace(0.0, 0.9, 37)
    q, qd, qdd = mech.drive(t)
    keys = [i.link for i in mech.inputs]
    old = torques(name, mech.builtin.parameters(mech.values), {k: q[:, j] for j, k in enumerate(keys)},
                  {k: qd[:, j] for j, k in enumerate(keys)}, {k: qdd[:, j] for j, k in enumerate(keys)}, inertias,
                  armature={k: 0.03 for k in keys}, gravity=(0.3, -G), force=(4.0, -1.5))
    new = torque.drive_forces(mech, q, qd, qdd, {BODY_TO_LINK[name][b]: v for b, v in inertias.items()},
                              armature={k: 0.03 for k in keys}, gravity=(0.3, -G), force=(4.0, -1.5))
    for k in keys:
        # both are sums of the same physical terms: rounding only (peaks ~1-10 N m)
        assert np.abs(new[k] - old[f"tau{k}"]).max() <= 1e-12 * np.abs(old[f"tau{k}"]).max()


CASES = {
    "fourbar": ("fourbar", {}, model.Loads()),
    "sixbar": ("sixbar", {}, model.Loads()),
    "fivebar": ("fivebar", {}, model.Loads()),
    "fivebar omega4=2omega2": ("fivebar", {"omega4": 4 * math.pi}, model.Loads()),
    "fourbar gravity and force": ("fourbar", {}, model.Loads(gravity=(0.0, -G), force=(3.0, -2.0))),
    "shaper cutting stroke": ("sixbar", {}, model.Loads(force=(-500.0, 0.0), slow_stroke_only=True)),
}


@pytest.mark.parametrize("case", CASES)
def test_mujoco_torque_and_work_balance_match(case):
    name, values, loads = CASES[case]
    built, c = service.compare(service.load(name, values), loads=loads)
    for tau in [k for k in c.errors if k.startswith("tau")]:
        # issue target: within 0.5 % of the peak analytic torque at every sample
        assert c.errors[tau]["max"] <= 5e-3 * c.errors[tau]["peak"], (tau, c.errors[tau])
    assert c.work_balance <= 1e-3                   # issue target: 0.1 % of the kinetic-energy swing
    assert c.passed


def test_the_cutting_force_acts_on_the_slow_stroke_only():
    built, c = service.compare(service.load("sixbar"), loads=model.Loads(force=(-500.0, 0.0), slow_stroke_only=True))
    on = c.trajectory.load > 0.5
    # the shaper's cutting stroke takes K / (1 + K) of the turn (K = 1.4599, SPEC data); the switch is
    # sampled at the steps (each edge within one step, plus the run's closing sample)
    assert abs(on.mean() - 1.4599 / 2.4599) < 3 / len(on)


def test_user_inertias_reach_the_mujoco_model():
    inert = {"2": Inertia(m=0.9, cx=0.1, cy=0.02, I=0.007)}
    built = model.build(analytic.load("fourbar"), loads=model.Loads(inertias=inert))
    got = model.body_inertias(built.model, ["2"])["2"]
    # MuJoCo stores them in single steps of double arithmetic (principal axes): rounding only
    assert (got.m, got.cx, got.cy, got.I) == pytest.approx((0.9, 0.1, 0.02, 0.007), abs=1e-12)
