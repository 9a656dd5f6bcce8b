"""Each load law checked in a second setup, from outside (issue 41, item 2): `linkage forces --json` on a
mm four-bar with massless links (pure statics at any speed) against the drive torque the test derives from
its own geometry (circle intersection, central differences) by virtual work or the power balance.

Nothing here reads the solver's loads, the MuJoCo model or the file's resolved loads: the oracle knows only
the numbers written in the file text below.
"""

from __future__ import annotations

import json
import math
import textwrap

import numpy as np
import pytest

from tests.cli_runner import run

A = np.array([0.0, 0.0])
D = np.array([300.0, 0.0])
S0 = np.array([100.0, 250.0])
R1, L2, L3 = 100.0, 300.0, 250.0          # crank, coupler, rocker [mm]

BASE = textwrap.dedent("""\
    format = "linkage/1"
    name = "fb"
    output = "C"
    units = "mm"
    [parameters]
    omega1 = {omega}
    [ground]
    A = [0, 0]
    D = [300, 0]
    S0 = [100, 250]
    [[inputs]]
    kind = "crank"
    pivot = "A"
    point = "B"
    length = 100
    link = "1"
    phi0 = 0
    omega = "omega1"
    [[groups]]
    kind = "RRR"
    point = "C"
    from = ["B", "D"]
    lengths = [300, 250]
    links = ["2", "3"]
    branch = 1
    [[groups]]
    kind = "point"
    point = "E"
    on = ["D", "C"]
    at = [125, 0]
    [inertia]
    1 = {{ m = 0, cx = 0, cy = 0, I = 0 }}
    2 = {{ m = 0, cx = 0, cy = 0, I = 0 }}
    3 = {{ m = 0, cx = 0, cy = 0, I = 0 }}
    """)


# ------------------------------------------------------------------------------ the test's own geometry
def pose(phi):
    """B, C, E [mm] at crank angles ``phi`` [rad] (arrays (2, N)): C where the circles about B (coupler) and D
    (rocker) meet, on the side above the line B -> D (the file's branch at phi = 0, checked below)."""
    phi = np.asarray(phi, dtype=float)
    B = np.stack([R1 * np.cos(phi), R1 * np.sin(phi)])
    d = D[:, None] - B
    dist = np.hypot(*d)
    a = (L2 ** 2 - L3 ** 2 + dist ** 2) / (2 * dist)
    h = np.sqrt(L2 ** 2 - a ** 2)
    ex, ey = d / dist
    C = np.stack([B[0] + a * ex - h * ey, B[1] + a * ey + h * ex])
    E = D[:, None] + 0.5 * (C - D[:, None])
    return B, C, E


def angles(phi):
    """The coupler's and the rocker's angles [rad] (B -> C, D -> C), unwrapped over ``phi``."""
    B, C, _ = pose(phi)
    return np.unwrap(np.arctan2(C[1] - B[1], C[0] - B[0])), np.unwrap(np.arctan2(C[1] - D[1], C[0] - D[0]))


def ddphi(f, phi, h=1e-6):
    """d f / d phi1 by central differences (f of an array of crank angles)."""
    return (f(phi + h) - f(phi - h)) / (2 * h)


def forces(tmp_path, text, *args):
    path = tmp_path / "m.toml"
    path.write_text(text)
    r = run("forces", path, "--json", "--samples", "73", *args)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


def test_the_oracles_branch_is_the_files():
    # The oracle's C is the solver's at one pose: the two describe the same assembly (the only use of the
    # solver here; it picks the branch, not any value that is checked below).
    import analytic
    from tests.test_loads import write  # noqa: F401  (the same kind of file the other load tests write)
    import tempfile
    from pathlib import Path
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "m.toml"
        p.write_text(BASE.format(omega=1.0))
        s = analytic.load(str(p)).solve(0.7)
    _, C, _ = pose(np.array([0.7]))
    # rounding of a circle intersection, 1e-9 mm
    assert np.hypot(float(np.asarray(s["xC"]).ravel()[0]) * 1e3 - C[0, 0],
                    float(np.asarray(s["yC"]).ravel()[0]) * 1e3 - C[1, 0]) < 1e-6


# ------------------------------------------------------------------------------------ constant torques
@pytest.mark.parametrize("window", ["-60deg:60deg", "300deg:420deg"])
def test_a_brake_active_across_zero_holds_the_crank_inside_its_window_only(tmp_path, window):
    # A -1.5 N mm brake on the crank over 120 deg that straddle phi1 = 0 (written two ways). With massless
    # links the drive holds exactly +1.5 N mm inside the window and nothing outside it.
    text = BASE.format(omega=2.0) + textwrap.dedent(f"""\
        [[loads]]
        name = "brake"
        kind = "torque"
        link = "1"
        magnitude = -1.5
        active = "{window}"
        """)
    out = forces(tmp_path, text)
    phi = np.mod(np.asarray(out["inputs"]["phi1"]), 2 * math.pi)
    T = np.asarray(out["drives"]["phi1"])
    inside = (phi < math.radians(59)) | (phi > math.radians(301))
    outside = (phi > math.radians(61)) & (phi < math.radians(299))
    assert inside.sum() > 20 and outside.sum() > 40
    # rounding of a statics solve, 1e-12 N m
    assert np.allclose(T[inside], 1.5e-3, atol=1e-12)
    assert np.allclose(T[outside], 0.0, atol=1e-12)
    (brake,) = [ld for ld in out["loads"] if ld["name"] == "brake"]
    # exact: T x the window's 120 deg, cut at its switching angles (not at the samples): 1e-9 J of rounding
    assert brake["work_per_cycle"] == pytest.approx(-1.5e-3 * 2 * math.pi / 3, abs=1e-9)
    # the drive does what the brake takes, to the same precision
    assert out["energy"]["drive_work"] == pytest.approx(1.5e-3 * 2 * math.pi / 3, abs=1e-9)


# ------------------------------------------------------------------------------------------ springs
def test_a_spring_preload_pulls_its_ends_together(tmp_path):
    # preload = 20 N of tension at the start pose, k = 0.5 N/mm: T(L) = 20 + 0.5 (L - L(0)) [N], pulling C
    # towards S0. Virtual work: T1 = T(L) dL/dphi1 [N mm], with L = |C - S0| from the test's geometry.
    text = BASE.format(omega=2.0) + textwrap.dedent("""\
        [[loads]]
        name = "s"
        kind = "spring"
        between = [["ground", "S0"], ["3", "C"]]
        stiffness = 0.5
        preload = 20
        """)
    out = forces(tmp_path, text)
    phi = np.asarray(out["inputs"]["phi1"])

    def L(p):
        return np.hypot(*(pose(p)[1] - S0[:, None]))

    tension = 20.0 + 0.5 * (L(phi) - L(np.array([0.0]))[0])
    expected = tension * ddphi(L, phi) * 1e-3                      # N mm -> N m
    # central differences of a smooth pose, h = 1e-6 rad: ~1e-9 relative; the peak is ~5 N m
    assert np.allclose(out["drives"]["phi1"], expected, rtol=1e-6, atol=1e-8)
    assert tension[0] > 0 and np.ptp(expected) > 1.0              # the check sees a real, varying load
    (s,) = [ld for ld in out["loads"] if ld["name"] == "s"]
    # a conservative load does no work over a closed cycle (trapezoid rounding of 73 samples of a periodic
    # integrand: far below 1e-6 J)
    assert abs(s["work_per_cycle"]) < 1e-6


def test_a_table_spring_stores_the_integral_of_its_table(tmp_path):
    # A stiffening spring given by (length, tension) rows [mm, N]; over half a turn its energy changes by
    # the integral of the piecewise-linear table between the start and end lengths, which the test sums
    # exactly (trapezoids between the rows), and the drive's work is that change.
    rows = [(50.0, 0.0), (100.0, 10.0), (150.0, 40.0), (200.0, 100.0), (300.0, 300.0)]
    text = BASE.format(omega=2.0) + textwrap.dedent(f"""\
        [[loads]]
        name = "s"
        kind = "spring"
        between = [["ground", "S0"], ["3", "C"]]
        table = {[list(r) for r in rows]}
        """)
    out = forces(tmp_path, text, "--revolutions", "0.5")
    x, y = np.array(rows).T

    def L(p):
        return np.hypot(*(pose(np.atleast_1d(p))[1] - S0[:, None]))

    L0, L1 = L(0.0)[0], L(math.pi)[0]
    assert x[0] < min(L0, L1) and max(L0, L1) < x[-1]             # inside the table: no extrapolation
    grid = np.sort(np.concatenate([[L0, L1], x[(x > min(L0, L1)) & (x < max(L0, L1))]]))
    energy = np.sum(np.diff(grid) * 0.5 * (np.interp(grid[1:], x, y) + np.interp(grid[:-1], x, y)))
    energy *= math.copysign(1.0, L1 - L0) * 1e-3                   # N mm -> J
    # the balance is stated per cycle (the run's change over its `cycles`, here 0.5); exact sums on both
    # sides: rounding, 1e-9 J
    assert out["energy"]["cycles"] == pytest.approx(0.5, abs=1e-12)
    assert out["energy"]["spring_change"] * out["energy"]["cycles"] == pytest.approx(energy, abs=1e-9)
    assert abs(energy) > 1e-3                                      # the half turn stretches it measurably
    # the work it does on the mechanism is minus the energy it stores (the half turn shortens it: it gives
    # its energy back, positive work)
    (s,) = [ld for ld in out["loads"] if ld["name"] == "s"]
    assert s["work_per_cycle"] * out["energy"]["cycles"] == pytest.approx(-energy, abs=1e-9)
    assert s["work_per_cycle"] > 0
    phi = np.asarray(out["inputs"]["phi1"])
    expected = np.interp(L(phi), x, y) * ddphi(L, phi) * 1e-3
    # central differences, h = 1e-6 rad, away from the table's corners (within 1e-4 mm of a row the
    # difference straddles a kink)
    away = np.min(np.abs(L(phi)[:, None] - x[None, :]), axis=1) > 1e-3
    assert np.allclose(np.asarray(out["drives"]["phi1"])[away], expected[away], rtol=1e-6, atol=1e-8)


@pytest.mark.parametrize("free, same", [("270deg", -90.0), ("-90deg", -90.0), ("630deg", -90.0),
                                        ("460deg", 100.0), ("-260deg", 100.0)])
def test_a_torsion_spring_beyond_half_a_turn_counts_its_angle_once(tmp_path, free, same):
    # At the ground pivot D, between the ground and the rocker: theta = phi3 - free_angle, taken in
    # (-180, 180] deg at the first sample and followed continuously after it (a wound spring keeps its
    # winding: with free -90 deg the rocker's 87..139 deg sweep carries theta across 180 deg). Free angles
    # a whole turn apart are one spring. Virtual work: T1 = k theta dphi3/dphi1.
    k = 800.0                                                        # N mm / rad
    text = BASE.format(omega=2.0) + textwrap.dedent(f"""\
        [[loads]]
        name = "t"
        kind = "torsion_spring"
        joint = "D"
        links = ["ground", "3"]
        stiffness = {k}
        free_angle = "{free}"
        """)
    out = forces(tmp_path, text)
    phi = np.asarray(out["inputs"]["phi1"])

    def phi3(p):
        return angles(p)[1]

    a = phi3(phi)
    first = a[0] - math.radians(same)
    first = first - 2 * math.pi * np.round(first / (2 * math.pi))
    theta = first + (a - a[0])
    expected = k * theta * ddphi(phi3, phi) * 1e-3
    # central differences, h = 1e-6 rad: ~1e-9 relative
    assert np.allclose(out["drives"]["phi1"], expected, rtol=1e-6, atol=1e-8)
    assert np.ptp(expected) > 0.1
    (t,) = [ld for ld in out["loads"] if ld["name"] == "t"]
    # conservative: no work over the closed cycle (73 trapezoids of a periodic integrand)
    assert abs(t["work_per_cycle"]) < 1e-6


# ------------------------------------------------------------------------------------------ dampers
def test_a_damper_between_two_moving_links_in_a_mm_file(tmp_path):
    # c = 0.01 N/(mm/s) = 10 N s/m between the crank tip B and the rocker's middle E. Power balance with
    # massless links: T1 omega1 = c (dL/dt)^2, i.e. T1 = c omega1 (dL/dphi1)^2.
    w = 2.0
    text = BASE.format(omega=w) + textwrap.dedent("""\
        [[loads]]
        name = "d"
        kind = "damper"
        between = [["1", "B"], ["3", "E"]]
        damping = 0.01
        """)
    out = forces(tmp_path, text)
    phi = np.asarray(out["inputs"]["phi1"])

    def L(p):
        B, _, E = pose(p)
        return np.hypot(*(E - B)) * 1e-3                             # m

    expected = 10.0 * w * ddphi(L, phi) ** 2
    # central differences, h = 1e-6 rad: ~1e-9 relative
    assert np.allclose(out["drives"]["phi1"], expected, rtol=1e-6, atol=1e-9)
    (d,) = [ld for ld in out["loads"] if ld["name"] == "d"]
    dissipated = np.trapezoid(expected * w, np.asarray(out["t"]))
    # a damper only takes energy: its work is minus what it dissipates (trapezoids on the same samples of
    # a smooth periodic integrand: 1e-4 relative covers the difference of the two quadratures)
    assert d["work_per_cycle"] < 0
    assert d["work_per_cycle"] == pytest.approx(-dissipated, rel=1e-4)


def test_a_pin_damper_in_a_mm_file_resists_the_relative_turning(tmp_path):
    # c = 50 N mm s/rad at C between the coupler and the rocker: a moment -c (omega3 - omega2) on the
    # rocker. Power balance: T1 omega1 = c (omega3 - omega2)^2, i.e. T1 = c omega1 (dphi3/dphi1 - dphi2/dphi1)^2.
    w = 2.0
    text = BASE.format(omega=w) + textwrap.dedent("""\
        [[loads]]
        name = "p"
        kind = "damper"
        joint = "C"
        links = ["2", "3"]
        damping = 50
        """)
    out = forces(tmp_path, text)
    phi = np.asarray(out["inputs"]["phi1"])

    def rel(p):
        a2, a3 = angles(p)
        return a3 - a2

    expected = 50e-3 * w * ddphi(rel, phi) ** 2                     # N mm s/rad -> N m s/rad
    # central differences, h = 1e-6 rad: ~1e-9 relative
    assert np.allclose(out["drives"]["phi1"], expected, rtol=1e-6, atol=1e-9)
    (p,) = [ld for ld in out["loads"] if ld["name"] == "p"]
    assert p["work_per_cycle"] < 0


# ------------------------------------------------------------------------------------------ tolerance
def _piston_speed_fluctuation(r, l=0.2):
    """(max - min) / mean of the slider-crank's piston speed over a turn, from x = r cos phi + sqrt(l^2 -
    r^2 sin^2 phi) differentiated by hand (omega cancels), on a dense grid."""
    phi = np.linspace(0.0, 2 * math.pi, 72001)[:-1]
    s = np.sin(phi)
    v = np.abs(r * s + r * r * s * np.cos(phi) / np.sqrt(l * l - r * r * s * s))
    return (v.max() - v.min()) / v.mean()


def test_tolerance_speed_fluctuation_and_its_percentiles_by_hand():
    # r ~ normal(50 mm, 0.5 mm) on the library slider-crank: a small spread, over which the fluctuation is
    # linear in r; so its mean, std and 5th/95th percentiles are f(r0), |f'| sigma and f(r0) -+ 1.645 |f'|
    # sigma, f written out by hand above.
    r = run("tolerance", "slider_crank", "--tol", "r=normal:0.0005", "--outputs", "speed_fluctuation",
            "--samples", "2000", "--seed", "1", "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)["outputs"]["speed_fluctuation"]
    f0 = _piston_speed_fluctuation(0.05)
    slope = (_piston_speed_fluctuation(0.0501) - _piston_speed_fluctuation(0.0499)) / 0.0002
    sigma = abs(slope) * 0.0005
    # the tool's 1-degree samples against a 72000-point grid: the trapezoid mean's O(h^2) ~ 3e-5 relative
    # (a mean counting the closed run's repeated end sample is 2.8e-3 high: caught)
    assert out["nominal"] == pytest.approx(f0, rel=1e-4)
    # the peak refined between samples: its rate within 0.5 % (the sampled maximum's was 1.9 % low)
    assert out["first_order_std"] == pytest.approx(sigma, rel=5e-3)
    # 2000 draws: the mean's sampling error is sigma / sqrt(2000) ~ 0.022 sigma, the std's ~ 1.6 %, a 5 %
    # quantile's ~ 0.05 sigma; bounds at ~4 standard errors (and far inside a factor of 10 of the spread)
    assert out["mean"] == pytest.approx(f0, abs=0.1 * sigma)
    assert out["std"] == pytest.approx(sigma, rel=0.07)
    assert out["p05"] == pytest.approx(f0 - 1.6449 * sigma, abs=0.2 * sigma)
    assert out["p95"] == pytest.approx(f0 + 1.6449 * sigma, abs=0.2 * sigma)


def _coupler_point(phi, l1=0.1, l2=0.3, l3=0.25, l4=0.3, ex=0.15, ey=0.1):
    """The library four-bar's coupler point E at crank angles ``phi`` by hand: A = (0, 0), D = (l4, 0), C where
    the circles about B (l2) and D (l3) meet left of B -> D, E at (ex, ey) in the frame of B with x along B -> C."""
    bx, by = l1 * np.cos(phi), l1 * np.sin(phi)
    dx, dy = l4 - bx, -by
    d = np.hypot(dx, dy)
    a = (l2 ** 2 - l3 ** 2 + d * d) / (2 * d)                      # from B along B -> D to the chord
    h = np.sqrt(l2 ** 2 - a * a)
    cx, cy = bx + (a * dx - h * dy) / d, by + (a * dy + h * dx) / d
    ux, uy = (cx - bx) / l2, (cy - by) / l2
    return bx + ex * ux - ey * uy, by + ex * uy + ey * ux


def test_tolerance_speed_fluctuation_of_a_coupler_point_is_of_its_whole_velocity():
    # E moves in x and y (unlike the slider-crank's piston): its speed is |(vx, vy)|. (max - min) / mean of
    # |dE/dphi| (omega cancels) by central differences of the hand position on a 72000-point grid
    phi = np.linspace(0.0, 2 * math.pi, 72001)[:-1]
    step = 2 * math.pi / 72000
    x, y = _coupler_point(phi)
    speed = np.hypot(np.roll(x, -1) - np.roll(x, 1), np.roll(y, -1) - np.roll(y, 1)) / (2 * step)
    f0 = (speed.max() - speed.min()) / speed.mean()
    r = run("tolerance", "fourbar", "--tol", "l1=normal:0.0001", "--outputs", "speed_fluctuation",
            "--samples", "20", "--seed", "1", "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)["outputs"]["speed_fluctuation"]
    # the tool's 1-degree samples (trapezoid mean, extremes refined between samples) against the dense grid:
    # 6e-7 relative measured; bound as for the slider-crank above
    assert out["nominal"] == pytest.approx(f0, rel=1e-4)
    assert f0 > 1.0                                                 # 1.04: E's speed swings by more than its mean


def test_a_crank_tip_dragged_across_180_deg_keeps_turning_the_same_way():
    # From phi1 = 3.1 rad (177.6 deg) the tip of the seed four-bar's crank (l1 = 0.1 m) is dragged to
    # -178 deg (= 182 deg): the input follows continuously (no jump of a turn) and the tip lands there.
    from sim import service
    from sim.service import editing
    fb = service.load("fourbar")
    for start, deg in [(3.1, -178.0), (-3.1, 178.0)]:
        target = 0.1 * np.array([math.cos(math.radians(deg)), math.sin(math.radians(deg))])
        d = editing.drag(fb, None, "B", target, [start])
        assert d.reached
        assert abs(d.input - start) < math.radians(10)                 # 4.4 deg away, not a turn away
        assert math.cos(d.input - math.radians(deg)) == pytest.approx(1.0, abs=1e-12)
        s = fb.with_values(**d.values).solve(np.array([[d.input]]))
        # the tip at the target: rounding of cos/sin, 1e-12 m
        assert np.hypot(float(s["xB"][0]) - target[0], float(s["yB"][0]) - target[1]) < 1e-12
