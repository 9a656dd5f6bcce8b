"""Springs, torsion springs, dampers and Coulomb friction (SPEC "Loads"): hand statics (virtual work on the
geometry, a friction-circle solve of the connecting rod, the piston's closed form), and the energy balance."""

from __future__ import annotations

import math
import textwrap

import numpy as np
import pytest
from scipy.optimize import brentq

import analytic
from analytic import loads, mass
from analytic.loads import kinetostatics as K

from tests.test_loads import PRESS, write

FOURBAR = textwrap.dedent("""\
    format = "linkage/1"
    name = "fb"
    output = "E"
    [parameters]
    omega1 = {omega}
    [ground]
    A = [0, 0]
    D = [0.3, 0]
    S0 = [0.1, 0.25]
    [[inputs]]
    kind = "crank"
    pivot = "A"
    point = "B"
    length = 0.1
    link = "1"
    phi0 = 0
    omega = "omega1"
    [[groups]]
    kind = "RRR"
    point = "C"
    from = ["B", "D"]
    lengths = [0.3, 0.25]
    links = ["2", "3"]
    branch = 1
    [[groups]]
    kind = "point"
    point = "E"
    on = ["B", "C"]
    at = [0.15, 0.1]
    """)


def run(text, tmp_path, samples=73, name="m.toml"):
    m = analytic.load(str(write(tmp_path, text, name)))
    t = np.linspace(0.0, m.duration(1.0), samples)
    q, qd, qdd = m.drive(t)
    ls = loads.resolve(m)
    inert = mass.model(m)
    return m, t, q, K.solve(m, q, qd, qdd, t, inert, ls), ls, inert


def no_loads(m, t):
    q, qd, qdd = m.drive(t)
    return K.solve(m, q, qd, qdd, t, mass.model(m), loads.LoadSet())


def test_spring_drive_torque_is_the_slope_of_its_energy(tmp_path):
    # A spring from the ground point S0 to the rocker at [0.2, 0] (its frame): at negligible speed the crank
    # holds T1 = dV/dphi1 with V = k (L - L0)^2 / 2, L from the geometry, differentiated by central differences
    spring = '[[loads]]\nname = "s"\nkind = "spring"\nbetween = [["ground", "S0"], ["3", [0.2, 0]]]\n' \
             'stiffness = 400\nfree_length = 0.12\n'
    m, t, q, res, ls, inert = run(FOURBAR.format(omega=1e-3) + spring, tmp_path)
    base = no_loads(m, t)

    def V(phi):
        s = m.solve(phi)
        c, sn = np.asarray(s["cos3"]), np.asarray(s["sin3"])
        x, y = 0.3 + 0.2 * c, 0.2 * sn
        return 0.5 * 400 * (np.hypot(x - 0.1, y - 0.25) - 0.12) ** 2

    h = 1e-6
    dV = (V(q[:, 0] + h) - V(q[:, 0] - h)) / (2 * h)
    # central differences of V: h^2 V''' ~ 1e-10 N m; the inertia cancels against the unloaded run
    assert np.allclose(res.forces.drives["1"] - base.forces.drives["1"], dV, rtol=0, atol=1e-6)
    assert np.max(np.abs(dV)) > 1.0                                   # a real load
    b = K.balance(m, res, ls, inert)
    assert b["work_per_cycle"]["s"] == pytest.approx(0.0, abs=1e-12)  # conservative over a cycle (exact)
    assert b["power_residual"] < 1e-9                                # pointwise power balance: rounding


def test_preload_sets_the_free_length_at_the_start_pose(tmp_path):
    spring = '[[loads]]\nname = "s"\nkind = "spring"\nbetween = [["ground", "S0"], ["3", [0.2, 0]]]\n' \
             'stiffness = 400\npreload = 30\n'
    m, t, q, res, ls, inert = run(FOURBAR.format(omega=1e-3) + spring, tmp_path)
    (a, b) = res.applications["s"]
    assert math.hypot(float(a.fx[0]), float(a.fy[0])) == pytest.approx(30.0, rel=1e-12)   # the preload at t = 0


def test_torsion_spring_at_the_rocker_pivot_by_virtual_work(tmp_path):
    ts = '[[loads]]\nname = "h"\nkind = "torsion_spring"\njoint = "D"\nlinks = ["ground", "3"]\n' \
         'stiffness = 2.0\nfree_angle = "90deg"\n'
    m, t, q, res, ls, inert = run(FOURBAR.format(omega=1e-3) + ts, tmp_path)
    base = no_loads(m, t)
    h = 1e-6
    p3 = np.asarray(m.solve(q[:, 0])["phi3"])
    d3 = (np.asarray(m.solve(q[:, 0] + h)["phi3"]) - np.asarray(m.solve(q[:, 0] - h)["phi3"])) / (2 * h)
    theta = p3 - math.pi / 2
    # the rocker stays within 90 +- 180 deg here; T1 = k theta dphi3/dphi1 (central differences: 1e-9)
    assert np.allclose(res.forces.drives["1"] - base.forces.drives["1"], 2.0 * theta * d3, atol=1e-7)
    b = K.balance(m, res, ls, inert)
    assert b["energy"]["spring_change"] == pytest.approx(0.0, abs=1e-12)


def test_damper_dissipation_equals_the_drive_work_over_a_cycle(tmp_path):
    # A damper S0 -> rocker at 1 turn/s: over a cycle the kinetic energy returns, so the drive's work is the
    # damper's dissipation c * integral of (dL/dt)^2, dL/dt here by finite differences of L(t) (geometry only)
    dmp = '[[loads]]\nname = "d"\nkind = "damper"\nbetween = [["ground", "S0"], ["3", [0.2, 0]]]\ndamping = 50\n'
    m, t, q, res, ls, inert = run(FOURBAR.format(omega='"360deg"') + dmp, tmp_path, samples=2001)
    b = K.balance(m, res, ls, inert)

    def L(tt):
        s = m.solve(m.drive(tt)[0])
        x, y = 0.3 + 0.2 * np.asarray(s["cos3"]), 0.2 * np.asarray(s["sin3"])
        return np.hypot(x - 0.1, y - 0.25)

    tt = np.linspace(0, 1, 20001)
    h = 1e-7
    Ld = (L(tt + h) - L(tt - h)) / (2 * h)
    hand = 50 * np.trapezoid(Ld ** 2, tt)
    assert hand > 0.1
    # two quadratures of a smooth periodic integrand (20001 and 2001 points): ~1e-9 relative
    assert b["energy"]["damper_dissipated"] == pytest.approx(hand, rel=1e-6)
    assert b["energy"]["drive_work"] == pytest.approx(hand, rel=1e-6)   # kinetic energy returns over the cycle
    assert b["work_per_cycle"]["d"] == pytest.approx(-hand, rel=1e-6)


def test_piston_friction_in_closed_form(tmp_path):
    # Prismatic friction mu |N| against the sliding. The massless-rod piston balance at negligible speed:
    # rod force R e (e the unit rod vector B -> C), load (-P, 0), normal (0, N), friction (-mu |N| sgn v, 0):
    # N = -R e_y and R = P / (e_x - mu |e_y| sgn v)  (R > 0 here).
    P, mu = 500.0, 0.15
    text = PRESS.format(top="", omega="1deg") + textwrap.dedent(f"""
        [[loads]]
        name = "punch"
        kind = "force"
        link = "piston"
        point = "C"
        direction = [-1, 0]
        magnitude = {P}
        [friction]
        joints = {{ piston = {{ mu = {mu} }} }}
        """)
    m, t, q, res, ls, inert = run(text, tmp_path)
    s = m.solve(q[:, 0], q[:, 0] * 0 + math.radians(1))
    bx, by, cx, cy = (np.asarray(s[k]) for k in ("xB", "yB", "xC", "yC"))
    lr = np.hypot(cx - bx, cy - by)
    ex, ey = (cx - bx) / lr, (cy - by) / lr
    v = np.sign(np.asarray(s["vxC"]))
    R = P / (ex - mu * np.abs(ey) * v)
    f = res.forces
    kC, kP = f.index("C"), f.index("piston")
    # 1e-5 N: the inertia forces at 1 deg/s
    assert np.allclose(np.hypot(*f.F[kC]), R, atol=1e-5)
    assert np.allclose(f.F[kP, 0], -mu * np.abs(R * ey) * v, atol=1e-5)       # friction's share in the joint
    assert np.allclose(f.F[kP, 1], -R * ey, atol=1e-5)
    b = K.balance(m, res, ls, inert)
    hand = np.trapezoid(mu * np.abs(R * ey) * np.abs(np.asarray(s["vxC"])), t)
    assert b["friction_dissipated_per_cycle"] == pytest.approx(hand, rel=1e-6)  # same samples, inertia 1e-8
    assert b["power_residual"] < 1e-9


def test_pin_friction_of_the_connecting_rod_by_the_friction_circle(tmp_path):
    # Friction in the rod's two pins B and C (mu r |F| against the relative rotation): the massless rod is a
    # two-force member whose moment balance about C reads d x F = mu r |F| (sgn(w2 - w1) + sgn(w2)) with
    # d = B - C and F = (P, Fy) the crank's force on it (the piston's x balance, no guide friction); solved
    # here per sample by bracketing (scipy brentq), independent of the code's fixed point.
    P, mu, r = 500.0, 0.2, 5.0
    text = PRESS.format(top="", omega="1deg") + textwrap.dedent(f"""
        [[loads]]
        name = "punch"
        kind = "force"
        link = "piston"
        point = "C"
        direction = [-1, 0]
        magnitude = {P}
        [friction]
        pin_radius = {r}
        joints = {{ B = {{ mu = {mu} }}, C = {{ mu = {mu} }} }}
        """)
    m, t, q, res, ls, inert = run(text, tmp_path, samples=37)
    s = m.solve(q[:, 0], math.radians(1))
    rho = mu * r * 1e-3
    f = res.forces
    kB, kC = f.index("B"), f.index("C")
    wmax = max(float(np.max(np.abs(s["omega1"]))), float(np.max(np.abs(s["omega2"]))))

    def sgn(x):                 # a rate of rounding size (the rod at 90 deg, sampled exactly) is rest (SPEC's
        return float(np.sign(x)) if abs(x) > 1e-9 * wmax else 0.0    # friction is indeterminate there)
    for i in range(len(t)):
        dx, dy = float(s["xB"][i] - s["xC"][i]), float(s["yB"][i] - s["yC"][i])
        w1, w2 = float(s["omega1"][i]), float(s["omega2"][i])
        k = sgn(w2 - w1) + sgn(w2)

        def g(Fy):
            return dx * Fy - dy * P - rho * math.hypot(P, Fy) * k
        Fy = brentq(g, -5 * P, 5 * P, xtol=1e-12)
        R = math.hypot(P, Fy)
        # the inertia forces at 1 deg/s: 1e-5 N
        assert math.hypot(*f.F[kB, :, i]) == pytest.approx(R, abs=1e-4)
        assert math.hypot(*f.F[kC, :, i]) == pytest.approx(R, abs=1e-4)    # a two-force member
        assert res.Mf[kB][i] == pytest.approx(-rho * R * sgn(w2 - w1), abs=1e-6)
        T = float(s["xB"][i]) * Fy - float(s["yB"][i]) * P - rho * R * sgn(w2 - w1)
        assert f.drives["1"][i] == pytest.approx(T, abs=1e-6)
    assert res.iterations > 2                                          # it did iterate to the fixed point
    without = no_loads(m, t)
    assert np.max(np.abs(f.drives["1"] - without.forces.drives["1"])) > 1.0    # friction matters here


def test_friction_that_locks_is_refused_in_one_line(tmp_path):
    text = PRESS.format(top="", omega="1deg") + textwrap.dedent("""
        [[loads]]
        name = "punch"
        kind = "force"
        link = "piston"
        point = "C"
        direction = [-1, 0]
        magnitude = 500
        [friction]
        mu = 2.0
        pin_radius = 200
        """)
    with pytest.raises(loads.LoadError, match=r"\[friction\].*lower mu or pin_radius"):
        run(text, tmp_path, samples=9)


def test_a_torsion_spring_wound_by_the_crank_keeps_its_winding(tmp_path):
    # At the crank pivot between the ground and the crank (a full turn per cycle): theta grows by 2 pi over the
    # turn, so the spring stores k ((theta0 + 2 pi)^2 - theta0^2) / 2 more at the end, which the drive supplies
    ts = '[[loads]]\nname = "w"\nkind = "torsion_spring"\njoint = "A"\nlinks = ["ground", "1"]\nstiffness = 0.5\n'
    m, t, q, res, ls, inert = run(FOURBAR.format(omega=1e-3) + ts, tmp_path, samples=361)
    b = K.balance(m, res, ls, inert)
    theta0 = 0.0                                                       # phi1(0) = 0, free angle 0
    stored = 0.5 * 0.5 * ((theta0 + 2 * math.pi) ** 2 - theta0 ** 2)
    assert b["energy"]["spring_change"] == pytest.approx(stored, rel=1e-12)
    # the drive's work by the trapezoidal rule over 361 samples of a linear torque: exact but for rounding
    assert b["energy"]["drive_work"] == pytest.approx(stored, rel=1e-6)
    base = no_loads(m, t)
    assert np.allclose(res.forces.drives["1"] - base.forces.drives["1"], 0.5 * (q[:, 0] - q[0, 0]), atol=1e-9)
