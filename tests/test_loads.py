"""Loads in the file and on the command line (SPEC "Loads"): forces and torques on any link, laws over the
motion, force units; checked by hand statics, virtual work and the energy balance (nothing from the code
under test)."""

from __future__ import annotations

import json
import math
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

import analytic
from analytic import loads, mass
from analytic.loads import kinetostatics as K

PRESS = textwrap.dedent("""\
    format = "linkage/1"
    name = "press"
    units = "mm"
    output = "C"
    {top}
    [parameters]
    r = 50.0
    l = 150.0
    e = 20.0
    omega1 = "{omega}"

    [ground]
    A = [0, 0]

    [[inputs]]
    kind = "crank"
    pivot = "A"
    point = "B"
    length = "r"
    link = "1"
    phi0 = "30deg"
    omega = "omega1"

    [[groups]]
    kind = "RRP"
    point = "C"
    from = "B"
    length = "l"
    guide = {{ through = "A", angle = "0deg" }}
    offset = "e"
    links = ["2", "piston"]
    branch = 1
    """)


def write(tmp_path, text, name="m.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def _cli(*args):
    """The command in this process (tests/cli_runner.py): what a test of the numbers needs, without 2 s of start."""
    import cli_runner
    return cli_runner.run(*args)


def linkage(*args):
    return subprocess.run([sys.executable, "-m", "sim", *map(str, args)], capture_output=True, text=True, timeout=300)


def solve_file(path, samples=73, extra=()):
    m = analytic.load(str(path))
    t = np.linspace(0.0, m.duration(1.0), samples)
    q, qd, qdd = m.drive(t)
    ls = loads.resolve(m, extra)
    inert = mass.model(m)
    return m, t, (q, qd, qdd), K.solve(m, q, qd, qdd, t, inert, ls), ls, inert


PUNCH = """
[[loads]]
name = "punch"
kind = "force"
link = "piston"
point = "C"
direction = [-1, 0]
magnitude = {P}
"""


def test_wrist_pin_carries_the_piston_load_by_hand_statics(tmp_path):
    # An offset press in mm turning 1 deg/s: the inertia forces are ~m r w^2 ~ 1e-5 N, so statics holds. The
    # rod is a two-force member: the piston's balance along x gives the rod force R = P / |cos(beta)| (beta the
    # rod's angle), which is the wrist-pin force; the crank's torque is R (B - A) x e_rod.
    P = 500.0
    path = write(tmp_path, PRESS.format(top="", omega="1deg") + PUNCH.format(P=P))
    m, t, (q, qd, qdd), res, _, _ = solve_file(path)
    sol = m.solve(q)
    bx, by, cx, cy = (np.asarray(sol[k]) for k in ("xB", "yB", "xC", "yC"))
    ex, ey = (cx - bx) / np.hypot(cx - bx, cy - by), (cy - by) / np.hypot(cx - bx, cy - by)
    R = P / ex                                                    # compression along B -> C
    f = res.forces
    kC = f.index("C")
    # 1e-6 of P bounds the inertia forces (~1e-5 N) left in at 1 deg/s
    assert np.allclose(np.hypot(*f.F[kC]), np.abs(R), rtol=0, atol=1e-6 * P)
    T_hand = R * (bx * ey - by * ex)                              # (B - A) x (R e), A at the origin
    assert np.allclose(f.drives["1"], T_hand, rtol=0, atol=1e-6 * P * 0.05)
    # the defect: the same force on the rod's end (the output point's carrier) loads the pin C only
    # with the guide's normal force (the piston, unloaded, balances the pin by the guide alone): no x part
    on_rod = K.solve(m, q, qd, qdd, t, mass.model(m), loads.LoadSet(
        (loads.force.constant("f", "2", "C", -P, 0.0),)))
    assert np.max(np.abs(on_rod.forces.F[kC, 0])) < 1e-6 * P     # inertia only (1e-5 N)
    assert np.all(np.hypot(*on_rod.forces.F[kC]) < np.abs(R))


def test_command_line_force_at_a_point_on_a_link_equals_the_file_load(tmp_path):
    path = write(tmp_path, PRESS.format(top="", omega="1deg"))
    cli = json.loads(linkage("forces", path, "--samples", 19, "--force", "-500,0@C:piston", "--json").stdout)
    path2 = write(tmp_path, PRESS.format(top="", omega="1deg") + PUNCH.format(P=500), "f.toml")
    fil = json.loads(linkage("forces", path2, "--samples", 19, "--json").stdout)
    for a, b in zip(cli["joints"], fil["joints"]):
        assert np.allclose(a["Fx"], b["Fx"], rtol=1e-12, atol=1e-9)  # the same load, two ways of giving it
    entry = next(ld for ld in cli["loads"] if ld["name"] == "force")
    assert entry["kind"] == "force" and entry["link"] == "piston" and entry["point"] == "C"
    assert set(entry) >= {"name", "kind", "link", "point", "work_per_cycle"}


def test_torque_on_the_rocker_by_virtual_work(tmp_path):
    # A resisting torque T3 on a four-bar's rocker at negligible speed: the crank needs T1 = -T3 dphi3/dphi1;
    # dphi3/dphi1 here by central differences of the rocker's angle (the geometry, not the force solve).
    m0 = analytic.load("fourbar").with_values(omega1=1e-3)
    T3 = -2.5
    extra = (loads.torque.constant("brake", "3", T3),)
    t = np.linspace(0.0, m0.duration(1.0), 37)
    q, qd, qdd = m0.drive(t)
    res = K.solve(m0, q, qd, qdd, t, mass.model(m0), loads.resolve(m0, extra))
    h = 1e-6
    d3 = (np.unwrap(np.asarray(m0.solve(q + h)["phi3"])) - np.unwrap(np.asarray(m0.solve(q - h)["phi3"]))) / (2 * h)
    # central differences: error ~h^2 phi3''' ~1e-12; the inertia left at 1e-3 rad/s: ~1e-7 N m
    assert np.allclose(res.forces.drives["1"], -T3 * d3, rtol=0, atol=1e-6)


def test_force_units_lbf_scale_every_force(tmp_path):
    # The same press and load, once in N and once in lbf: every joint force scales by 4.4482216152605 N/lbf
    # (the international pound-force, exactly 0.45359237 kg x 9.80665 m/s^2)
    pn = write(tmp_path, PRESS.format(top="", omega="1deg") + PUNCH.format(P=100), "n.toml")
    pl = write(tmp_path, PRESS.format(top='force_units = "lbf"', omega="1deg") + PUNCH.format(P=100), "l.toml")
    _, _, _, rn, _, _ = solve_file(pn)
    _, _, _, rl, _, _ = solve_file(pl)
    k = rn.forces.index("C")
    # the 1 deg/s inertia (1e-5 N) is the only part that does not scale
    assert np.allclose(np.hypot(*rl.forces.F[k]), 4.4482216152605 * np.hypot(*rn.forces.F[k]), rtol=1e-6)
    assert 0.45359237 * 9.80665 == pytest.approx(4.4482216152605, rel=1e-14)


def test_a_punching_force_active_over_part_of_the_stroke_does_the_work_of_its_window(tmp_path):
    # A punch of 1000 N against the piston's motion only while it moves in +x (the press stroke) and only
    # between 120 and 240 deg of the crank (the piston turns back near 185 deg, inside the window): its work is
    # -1000 N x the piston's travel in +x inside the window (read off the geometry), per cycle.
    text = PRESS.format(top="", omega="360deg") + textwrap.dedent("""
        [[loads]]
        name = "punch"
        kind = "force"
        link = "piston"
        point = "C"
        direction = [-1, 0]
        magnitude = 1000
        active = "120deg:240deg"
        stroke = "+x"
        """)
    path = write(tmp_path, text)
    m, t, _, res, ls, inert = solve_file(path, samples=7201)
    b = K.balance(m, res, ls, inert)
    phi = np.radians(np.linspace(120, 240, 20001))
    xs = np.asarray(m.solve(phi)["xC"])
    dx = np.diff(xs)
    travel_plus = np.sum(dx[dx > 0])                              # [m] the +x travel inside the window
    expected = -1000.0 * travel_plus
    # the trapezoidal rule over 7201 samples at the window's two jumps: ~2 samples x 1000 N x 0.05 mm
    assert b["work_per_cycle"]["punch"] == pytest.approx(expected, rel=2e-3)
    assert expected < -1.0 and np.any(dx < 0)                      # a real stroke, and a reversal inside
    # the drive supplies it: energy balance over the cycle (kinetic energy returns to its start)
    e = b["energy"]
    assert e["drive_work"] == pytest.approx(-e["loads_work"], rel=1e-3)  # the same trapezoid error at the jumps
    assert b["power_residual"] < 1e-9                              # pointwise power balance: rounding only


def test_expression_and_table_laws_agree_with_their_hand_values(tmp_path):
    # A torque 3 sin(phi1) N mm (the mm file's moment unit) on the crank, and the same as a 5 deg table: the
    # drive must cancel it at 1e-3 rad/s
    text = PRESS.format(top="", omega="0.001") + textwrap.dedent("""
        [[loads]]
        name = "wave"
        kind = "torque"
        link = "1"
        magnitude = "3*sin(phi1)"
        """)
    m, t, (q, _, _), res, ls, _ = solve_file(write(tmp_path, text), samples=37)
    ref = K.solve(m, *m.drive(t), t, mass.model(m), loads.LoadSet())
    # the same inertia in both: only rounding (1e-10 N m) is left
    assert np.allclose(res.forces.drives["1"] - ref.forces.drives["1"], -3e-3 * np.sin(q[:, 0]), atol=1e-12)
    rows = "\n".join(f"{a},{3 * math.sin(math.radians(a))}" for a in range(0, 361, 5))
    (tmp_path / "wave.csv").write_text("phi,T\n" + rows + "\n")
    text2 = text.replace('magnitude = "3*sin(phi1)"', 'table = "wave.csv"')
    m2, _, _, res2, _, _ = solve_file(write(tmp_path, text2, "t.toml"), samples=37)
    # every sample (30, 40, ... deg) is a node of the 5 deg table: the table's value is sin's there (rounding)
    assert np.allclose(res2.forces.drives["1"], res.forces.drives["1"], atol=1e-12)
    # between nodes, linear interpolation: at 32.5 deg the chord lies below sin by ~3 (5 deg)^2 / 8 sin
    mid = K.solve(m2, *m2.drive(np.array([math.radians(2.5) / 1e-3])), np.array([math.radians(2.5) / 1e-3]),
                  mass.model(m2), loads.resolve(m2))
    chord = 3e-3 * (math.sin(math.radians(30)) + math.sin(math.radians(35))) / 2
    hand = -chord + (ref.forces.drives["1"][0])             # inertia as at 30 deg (1e-10 N m apart)
    assert mid.forces.drives["1"][0] == pytest.approx(hand, abs=1e-9)


@pytest.mark.parametrize("body,needle", [
    ('[[loads]]\nname = "x"\nkind = "rope"\nlink = "2"\n', "loads[1] (x).kind"),
    ('[[loads]]\nname = "x"\nkind = "force"\nlink = "9"\npoint = "C"\ndirection = [1, 0]\nmagnitude = 1\n',
     "loads[1] (x).link"),
    ('[[loads]]\nname = "x"\nkind = "force"\nlink = "2"\npoint = "A"\ndirection = [1, 0]\nmagnitude = 1\n',
     "loads[1] (x).point"),
    ('[[loads]]\nname = "x"\nkind = "force"\nlink = "2"\npoint = "C"\ndirection = [0, 0]\nmagnitude = 1\n',
     "loads[1] (x).direction"),
    ('[[loads]]\nname = "x"\nkind = "torque"\nlink = "2"\nmagnitude = "3*psi"\n', "loads[1] (x).magnitude"),
])
def test_bad_loads_are_one_line_naming_the_field(tmp_path, body, needle):
    path = write(tmp_path, PRESS.format(top="", omega="1deg") + body)
    r = linkage("forces", path, "--samples", 5)
    assert r.returncode == 2 and needle in r.stderr and len(r.stderr.strip().splitlines()) == 1, r.stderr


def test_force_units_unknown_is_refused(tmp_path):
    r = linkage("forces", write(tmp_path, PRESS.format(top='force_units = "kgf"', omega="1deg")), "--samples", 5)
    assert r.returncode == 2 and "force_units" in r.stderr and "lbf" in r.stderr


def test_pressure_table_times_area_pushes_the_piston(tmp_path):
    # An indicator diagram in N/mm^2 (the mm file's pressure unit) on a 1000 mm^2 piston: the load is p(phi) x A
    # along -x, so the rod force is p A / cos(beta) (hand statics as above), with p interpolated in the table
    rows = "crank,p\n0,0\n90,1.5\n180,0.5\n270,0.2\n"
    (tmp_path / "ind.csv").write_text(rows)
    text = PRESS.format(top="", omega="1deg") + textwrap.dedent("""
        [[loads]]
        name = "gas"
        kind = "pressure"
        link = "piston"
        area = 1000
        table = "ind.csv"
        direction = [-1, 0]
        """)
    m, t, (q, _, _), res, _, _ = solve_file(write(tmp_path, text), samples=37)
    phi = np.degrees(np.mod(q[:, 0], 2 * math.pi))
    p_hand = np.interp(phi, [0, 90, 180, 270, 360], [0, 1.5, 0.5, 0.2, 0])       # N/mm^2, periodic
    sol = m.solve(q)
    bx, by, cx, cy = (np.asarray(sol[k]) for k in ("xB", "yB", "xC", "yC"))
    ex = (cx - bx) / np.hypot(cx - bx, cy - by)
    R = p_hand * 1000.0 / ex
    # inertia at 1 deg/s: 1e-5 N
    assert np.allclose(np.hypot(*res.forces.F[res.forces.index("C")]), np.abs(R), atol=1e-4)
    assert np.max(np.abs(R)) > 1000                                    # 1.5 N/mm^2 x 1000 mm^2 = 1500 N


def test_at_one_pose_equals_the_runs_sample(tmp_path):
    path = write(tmp_path, PRESS.format(top="", omega="360deg") + PUNCH.format(P=500))
    one = json.loads(linkage("forces", path, "--at", "90deg", "--json").stdout)
    run = json.loads(linkage("forces", path, "--samples", 361, "--json").stdout)
    assert one["samples"] == 1 and one["inputs"]["phi1"][0] == pytest.approx(math.radians(90), abs=1e-12)
    k = 60                                                             # 30 deg + 60 x 1 deg
    assert run["inputs"]["phi1"][k] == pytest.approx(math.radians(90), abs=1e-12)
    # the same pose, time and speed: the same numbers up to rounding
    assert one["drives"]["phi1"][0] == pytest.approx(run["drives"]["phi1"][k], rel=1e-9)
    assert "energy" not in one                                          # one pose has no cycle
    r = linkage("forces", path, "--at", "90deg", "--simulate")
    assert r.returncode == 2 and "--at" in r.stderr


def test_at_under_an_acceleration_by_the_quadratic():
    # issue 41: phi1 = w t + a t^2 / 2 (w = 2 pi, a = 3 rad/s^2) passes 200deg at the quadratic's positive root;
    # its speed there is w + a t (by hand, not by the code's motion law)
    w, a, phi = 2 * math.pi, 3.0, math.radians(200)
    r = _cli("analyze", "fourbar", "--set", "alpha1=3", "--at", "200deg", "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    t = (-w + math.sqrt(w * w + 2 * a * phi)) / a
    assert d["t"] == pytest.approx(t, rel=1e-12)                     # bisection to the last bits of t
    assert d["outputs"]["phi1"] == pytest.approx(phi, rel=1e-12)
    assert d["outputs"]["omega1"] == pytest.approx(w + a * t, rel=1e-12)
    # a second turn's value: the first pass of 200deg + k 360deg within the cycle (here k = 0) is the same pose
    assert json.loads(_cli("analyze", "fourbar", "--set", "alpha1=3", "--at", "-160deg", "--json").stdout)["t"] \
        == pytest.approx(t, rel=1e-12)


def test_at_on_a_rocking_crank_by_the_cosine_law():
    # issue 41: a crank that cannot turn fully (l1 = 0.4: non-Grashof) rocks over --input-range -90:90deg as
    # q = -amp cos(w t) (amp = 90deg, w = 2 pi); --at 10deg is where it first passes 10deg, on its way up
    amp, w, phi = math.pi / 2, 2 * math.pi, math.radians(10)
    t = math.acos(-phi / amp) / w
    r = _cli("analyze", "fourbar", "--set", "l1=0.4", "--input-range=-90deg:90deg", "--at", "10deg", "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["t"] == pytest.approx(t, rel=1e-12)                     # acos: a few ulps
    assert d["outputs"]["omega1"] == pytest.approx(amp * w * math.sin(w * t), rel=1e-12)
    f = json.loads(_cli("forces", "fourbar", "--set", "l1=0.4", "--input-range=-90deg:90deg", "--at", "10deg",
                           "--json").stdout)
    assert f["t"][0] == pytest.approx(t, rel=1e-12) and f["inputs"]["phi1"][0] == pytest.approx(phi, rel=1e-12)
    # a value the rocking crank never reaches: one line naming the range
    r = _cli("forces", "fourbar", "--set", "l1=0.4", "--input-range=-90deg:90deg", "--at", "100deg")
    assert r.returncode == 2 and "-90..90 deg" in r.stderr and len(r.stderr.strip().splitlines()) == 1


def test_analyze_at_one_angle_by_the_four_bar_geometry():
    # SPEC four-bar defaults: l1 0.10, l2 0.30, l3 0.25, l4 0.30; C is where the circles about B (l2) and D (l3)
    # meet, left of B -> D (branch +1): the triangle B-C-D by the law of cosines
    r = linkage("analyze", "fourbar", "--at", "30deg", "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)["outputs"]
    b = np.array([0.1 * math.cos(math.radians(30)), 0.1 * math.sin(math.radians(30))])
    d = np.array([0.30, 0.0])
    bd = d - b
    L = np.linalg.norm(bd)
    a = (0.30 ** 2 - 0.25 ** 2 + L ** 2) / (2 * L)                 # from B along B -> D
    h = math.sqrt(0.30 ** 2 - a ** 2)
    c = b + a * bd / L + h * np.array([-bd[1], bd[0]]) / L           # the left side
    assert out["phi1"] == pytest.approx(math.radians(30), abs=1e-15)
    assert out["phi2"] == pytest.approx(math.atan2(*(c - b)[::-1]), abs=1e-12)   # rounding
    assert out["phi3"] == pytest.approx(math.atan2(*(c - d)[::-1]), abs=1e-12)


def test_an_inch_pound_press_needs_no_hand_conversion(tmp_path):
    # The same press in inches (r = 2 in, l = 6 in, e = 0.8 in) with a 100 lbf punch and a 50 lbf in brake on
    # the crank: the crank torque in lbf in is P R_arm + 50 by hand statics in inches, SI in the JSON
    text = textwrap.dedent("""\
        format = "linkage/1"
        name = "press_in"
        units = "in"
        force_units = "lbf"
        output = "C"
        [parameters]
        omega1 = "1deg"
        [ground]
        A = [0, 0]
        [[inputs]]
        kind = "crank"
        pivot = "A"
        point = "B"
        length = 2
        link = "1"
        phi0 = "30deg"
        omega = "omega1"
        [[groups]]
        kind = "RRP"
        point = "C"
        from = "B"
        length = 6
        guide = { through = "A", angle = "0deg" }
        offset = 0.8
        links = ["2", "piston"]
        branch = 1
        [[loads]]
        name = "punch"
        kind = "force"
        link = "piston"
        point = "C"
        direction = [-1, 0]
        magnitude = 100
        [[loads]]
        name = "brake"
        kind = "torque"
        link = "1"
        magnitude = -50
        """)
    d = json.loads(linkage("forces", write(tmp_path, text), "--samples", 13, "--json").stdout)
    phi = np.array(d["inputs"]["phi1"])
    bx, by = 2 * np.cos(phi), 2 * np.sin(phi)                          # inches
    cx = bx + np.sqrt(36 - (0.8 - by) ** 2)
    ex, ey = (cx - bx) / 6, (0.8 - by) / 6
    R = 100 / ex                                                        # lbf along the rod
    T_lbf_in = R * (bx * ey - by * ex) + 50                             # the drive holds the punch and the brake
    N_m_per_lbf_in = 4.4482216152605 * 0.0254
    # inertia at 1 deg/s (1e-6 N m) is what separates them
    assert np.allclose(np.array(d["drives"]["phi1"]) / N_m_per_lbf_in, T_lbf_in, atol=1e-4)
    kC = [j["name"] for j in d["joints"]].index("C")
    assert np.allclose(np.hypot(d["joints"][kC]["Fx"], d["joints"][kC]["Fy"]) / 4.4482216152605, np.abs(R), atol=1e-5)


def test_the_loads_table_has_specs_fields_for_every_kind(tmp_path):
    # SPEC "Loads": each entry {"name", "kind", "link", "point" or "at", "work_per_cycle"}
    press = (Path(__file__).parent / "mechanisms" / "press_loads.toml")
    d = json.loads(linkage("forces", press, "--samples", 37, "--gravity", "0,-9.81", "--torque", "1@2",
                           "--json").stdout)
    kinds = set()
    for e in d["loads"]:
        assert {"name", "kind", "link", "work_per_cycle"} <= set(e), e
        assert ("point" in e) or ("at" in e), e
        assert e["work_per_cycle"] is None or math.isfinite(e["work_per_cycle"])
        kinds.add(e["kind"])
    assert kinds == {"gravity", "force", "spring", "damper", "torsion_spring", "torque"}
    assert d["friction"]["dissipated_per_cycle"] > 0


FRICTION_FOURBAR = """format = "linkage/1"
name = "rubbing"
output = "C"
[ground]
A = [0, 0]
D = [0.3, 0]
[[inputs]]
kind = "crank"
pivot = "A"
point = "B"
length = 0.1
link = "1"
omega = "360deg"
[[groups]]
kind = "RRR"
point = "C"
from = ["B", "D"]
lengths = [0.3, 0.25]
links = ["2", "3"]
branch = 1
[friction]
mu = 0.3
pin_radius = 0.02
"""


@pytest.mark.parametrize("model", ["linear", "circle"])
def test_pin_friction_by_the_friction_circle(tmp_path, model):
    # issue 41: a journal of radius r whose resultant F leans at the friction angle atan(mu) from the line of
    # centres has the friction moment |Mf| = r sin(atan mu) |F| (Khurmi, Theory of Machines, ch. 10; Beer &
    # Johnston, Statics, sec. 8.7; Hibbeler, Statics, sec. 8.7): 0.0057470 N m per N at mu 0.3, r 0.02 m;
    # the default (linear) model takes sin(atan mu) as mu: 0.006 N m per N
    text = FRICTION_FOURBAR + ("" if model == "linear" else 'model = "circle"\n')
    path = write(tmp_path, text)
    r = _cli("forces", path, "--samples", 73, "--gravity", "0,-9.81", "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    lever = 0.02 * (math.sin(math.atan(0.3)) if model == "circle" else 0.3)
    for j in d["joints"]:
        F = np.hypot(j["Fx"], j["Fy"])
        Mf = np.abs(j["Mf"])
        turning = Mf > 0                                       # a joint at a reversal carries none
        assert turning.sum() > 60, j["point"]
        # 1e-9: the fixed point stops when no joint force changes by more than 1e-12 of the peak; |Mf| is
        # the lever arm times the last iterate's |F|
        np.testing.assert_allclose(Mf[turning], lever * F[turning], rtol=1e-9, atol=1e-9 * F.max())
    assert d["friction"]["model"] == model


def test_an_unknown_friction_model_is_one_line(tmp_path):
    path = write(tmp_path, FRICTION_FOURBAR + 'model = "viscous"\n')
    r = _cli("forces", path)
    assert r.returncode == 2 and "friction.model" in r.stderr and '"circle"' in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1


def test_at_along_a_motion_law_by_its_segments(tmp_path):
    # issue 41: --at along a law (SPEC "Motion laws"): a dwell of 0.2 s, then 180deg at constant speed in 0.5 s,
    # then 180deg in 0.3 s; q0 + 90deg is passed at 0.2 + 0.25 s, q0 + 270deg at 0.7 + 0.15 s (by hand)
    import re
    library = Path(analytic.__file__).parent / "library" / "servo_press.toml"
    text = re.sub(r"segments = \[.*?\n\]\n", 'segments = [\n  { shape = "dwell", duration = 0.2 },\n'
                  '  { shape = "constant", duration = 0.5, rise = "180deg" },\n'
                  '  { shape = "constant", duration = 0.3, rise = "180deg" },\n]\n', library.read_text(), flags=re.S)
    path = write(tmp_path, text)
    q0 = analytic.load(str(path)).inputs[0].motion.q0             # the file's start angle
    for extra, t in ((90, 0.45), (270, 0.85)):
        at = f"{math.degrees(q0) + extra!r}deg"
        r = _cli("analyze", path, "--at", at, "--json")
        assert r.returncode == 0, r.stderr
        # 1e-12 s: bisection to adjacent floats of t; the value's degrees read back within an ulp or two
        assert json.loads(r.stdout)["t"] == pytest.approx(t, abs=1e-12), (extra, r.stdout[:200])
