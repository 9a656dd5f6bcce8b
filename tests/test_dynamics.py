"""Inverse dynamics: hand-checkable cranks, the power balance, and MuJoCo's actuator torques."""

import math

import numpy as np
import pytest

from analytic import ParameterError, fivebar, fourbar, sixbar
from analytic.dynamics import Inertia, body_motions, torques
from sim import compare, model, simulate

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


CASES = {
    "fourbar": (fourbar.FourBar(), model.Loads()),
    "sixbar": (sixbar.SixBar(), model.Loads()),
    "fivebar": (fivebar.FiveBar(), model.Loads()),
    "fivebar omega4=2omega2": (fivebar.FiveBar(omega4=4 * math.pi), model.Loads()),
    "fourbar gravity and force": (fourbar.FourBar(), model.Loads(gravity=(0.0, -G), force=(3.0, -2.0))),
    "shaper cutting stroke": (sixbar.SixBar(), model.Loads(force=(500.0, 0.0), cutting_only=True)),
}


@pytest.mark.parametrize("case", CASES)
def test_mujoco_torque_and_work_balance_match(case):
    mech, loads = CASES[case]
    built = model.build(mech, loads=loads)
    c = compare.compare(simulate.simulate(built, 1.0), built)
    for tau in [k for k in c.errors if k.startswith("tau")]:
        # issue target: within 0.5 % of the peak analytic torque at every sample
        assert c.errors[tau]["max"] <= 5e-3 * c.errors[tau]["peak"], (tau, c.errors[tau])
    assert c.work_balance <= 1e-3                   # issue target: 0.1 % of the kinetic-energy swing
    assert c.passed


def test_user_inertias_reach_the_mujoco_model():
    inert = {"coupler": Inertia(m=0.9, cx=0.1, cy=0.02, I=0.007)}
    built = model.build(fourbar.FourBar(), loads=model.Loads(inertias=inert))
    got = model.body_inertias(built.model, ["coupler"])["coupler"]
    # MuJoCo stores them in single steps of double arithmetic (principal axes): rounding only
    assert (got.m, got.cx, got.cy, got.I) == pytest.approx((0.9, 0.1, 0.02, 0.007), abs=1e-12)
