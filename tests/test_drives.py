"""Drives between moving parts: the ``actuator`` (a cylinder's pin-to-pin length driven) and the ``motor`` (a
driven revolute between two moving links).

The element-kind conformance suite (tests/test_kinds.py over tests/kinds/actuator.toml and motor.toml) checks
both kinds against the Newton oracle, finite differences, MuJoCo and the whole-linkage Newton-Euler oracle.
Here: what only these kinds do, each against something the code does not share.

* The cylinder force by virtual work, by hand geometry: no printed dump-truck example with enough data was
  found, so the reference is derived here (see :func:`_virtual_work_force`), statically, with the body's
  weight as the only load. (A scissor lift against the published relation F = (W + Wa/2) / tan(phi):
  tests/test_scissor_published.py.)
* The holding torques of a 2R arm at rest, by hand (moments of the weights about the joints).
* The pressure on the push and pull areas from the file's bore and rod diameters, by hand.
* An actuator is solved in closed form: one sample far from the start gives the circle-circle intersection
  computed here, with no path from the start (no Newton continuation).
* Bad input: one line naming the input and the field, exit 2, nothing written.
"""

from __future__ import annotations

import csv
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

import analytic
from analytic import kinds
from analytic.mass import Inertia
from tests.cli_runner import run

EXAMPLES = Path(__file__).resolve().parent / "kinds"
ACTUATOR = EXAMPLES / "actuator.toml"
MOTOR = EXAMPLES / "motor.toml"
G = 9.81


# ------------------------------------------------------------------------------------ columns and JSON
def test_the_inputs_columns_and_drives_are_named_as_the_spec_says():
    mech = analytic.load(str(ACTUATOR))
    (inp,) = mech.inputs
    assert (inp.q, inp.qd, inp.qdd, inp.unit) == ("s_lift", "ds_lift", "dds_lift", "m")
    arm = analytic.load("arm_2r")
    assert [(i.q, i.qd, i.qdd, i.unit) for i in arm.inputs] == [("phiupper", "omegaupper", "alphaupper", "rad"),
                                                                ("q_elbow", "dq_elbow", "ddq_elbow", "rad")]
    r = run("forces", ACTUATOR, "--json", "--samples", "5")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert list(out["drives"]) == ["s_lift"] and list(out["inputs"]) == ["s_lift"]
    assert set(out["actuators"]) == {"lift"} and out["units"]["actuators"] == {"pressure": "Pa", "F": "N", "bore": "m"}


def test_the_rods_slide_is_reported_once_under_the_inputs_name(tmp_path):
    """SPEC "Drives": an actuator's pin-to-pin length is column s_lift (ds_lift, dds_lift); the rod's prismatic pair
    (slift_rod, the same numbers) is not reported again in analyze's CSV and JSON, simulate's CSV or compare."""
    mech = analytic.load(str(ACTUATOR))
    assert "lift_rod" in mech.slides                       # the pair is there, driven by the input
    twice = {"slift_rod", "dslift_rod", "ddslift_rod"}
    csv_a, csv_s = tmp_path / "a.csv", tmp_path / "s.csv"
    r = run("analyze", ACTUATOR, "--csv", csv_a, "--samples", "9")
    assert r.returncode == 0, r.stderr
    with open(csv_a) as fh:
        rows = list(csv.DictReader(fh))
    cols = list(rows[0])
    assert [cols.count(c) for c in ("s_lift", "ds_lift", "dds_lift")] == [1, 1, 1] and not twice & set(cols)
    # s_lift is the pin-to-pin length |CD|: the pins' columns, by Pythagoras here; rounding on ~1 m
    for row in rows:
        cd = math.hypot(float(row["xD"]) - float(row["xC"]), float(row["yD"]) - float(row["yC"]))
        assert float(row["s_lift"]) == pytest.approx(cd, abs=1e-12)
    r = run("analyze", ACTUATOR, "--json", "--samples", "9")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert not twice & set(out["ranges"]) and not twice & set(out["units"]["outputs"])
    assert "lift_rod" not in out["figures"]["slides"]     # its range is the input's, not a figure of its own
    r = run("simulate", ACTUATOR, "--csv", csv_s, "--revolutions", "0.2")
    assert r.returncode == 0, r.stderr
    with open(csv_s) as fh:
        cols = next(csv.reader(fh))
    assert cols.count("s_lift") == 1 and not twice & set(cols)
    assert not twice & set(analytic.load(str(ACTUATOR)).outputs)    # what compare and the app's tables list


def test_the_motor_coordinate_is_the_relative_angle():
    arm = analytic.load("arm_2r")
    t = np.linspace(0.0, 3.0, 7)
    (q, _, _), sol = arm.solve_at(t)
    rel = sol["phifore"] - sol["phiupper"]
    # q_elbow = phi(fore) - phi(upper), both atan2'd: equal modulo 2 pi to rounding
    np.testing.assert_allclose(np.angle(np.exp(1j * (rel - q[:, 1]))), 0.0, atol=1e-12)
    np.testing.assert_allclose(sol["omegafore"] - sol["omegaupper"], math.radians(-180.0), atol=1e-12)


# ------------------------------------------------------------------------------ closed form, not Newton
def test_an_actuator_is_solved_in_closed_form_from_any_sample():
    mech = analytic.load(str(ACTUATOR))
    e = next(x for x in mech.geometry.elements if x["kind"] == "actuator")
    assert not kinds.get("actuator").continuous          # no sample-to-sample (Newton) solve
    lo, hi = e["stroke"]
    for branch in (1, -1):
        m = mech.with_values(branch=branch)
        sol = m.solve(np.array([hi]))                    # one sample at the far end: no path from the start
        # D by hand: |AD| = 0.8, |CD| = hi, A = (0, 0), C = (0.6, -0.25)
        (ax, ay), (cx, cy) = m.geometry.ground["A"], m.geometry.ground["C"]
        d = math.hypot(cx - ax, cy - ay)
        along = (0.8 ** 2 - hi ** 2 + d * d) / (2 * d)
        h = math.sqrt(0.8 ** 2 - along ** 2)
        ux, uy = (cx - ax) / d, (cy - ay) / d
        x, y = ax + along * ux - branch * h * uy, ay + along * uy + branch * h * ux
        # the same intersection by another formula: rounding of a few operations on 1 m
        assert math.hypot(sol["xD"][0] - x, sol["yD"][0] - y) <= 1e-12


# ------------------------------------------------------------------------------ virtual work, by hand
def _virtual_work_force(A, C, D, Gp, weight):
    """The cylinder force [N, + pushing] that holds a body pivoted at A, its weight at G, by virtual work:
    turning the body by d theta moves D by perp(D - A) d theta, so the cylinder lengthens by
    dl = (D - C) . perp(D - A) / |D - C| d theta, and G rises by (G - A)_x d theta; F dl = weight dy_G."""
    dlx, dly = D[0] - C[0], D[1] - C[1]
    l = math.hypot(dlx, dly)
    perp = (-(D[1] - A[1]), D[0] - A[0])
    dl = (dlx * perp[0] + dly * perp[1]) / l
    return weight * (Gp[0] - A[0]) / dl


@pytest.mark.parametrize("length", [1.0, 1.6, 2.2, 2.6])
def test_the_tipper_cylinder_force_equals_virtual_work(length):
    from analytic.applications import forces as F
    mech = analytic.load("dump_tipper")
    body = Inertia(m=6000.0, cx=2.2, cy=-0.8, I=12000.0)  # the loaded body alone: the cylinder massless
    q = np.array([length])
    sol = mech.solve(q)
    f = F.solve(mech, q, 0.0 * q, 0.0 * q, {"body": body}, gravity=(0.0, -G))
    A, C = mech.geometry.ground["A"], mech.geometry.ground["C"]
    D = (sol["xD"][0], sol["yD"][0])
    c, s = math.cos(sol["phibody"][0]), math.sin(sol["phibody"][0])
    Gp = (A[0] + 2.2 * c + 0.8 * s, A[1] + 2.2 * s - 0.8 * c)
    ref = _virtual_work_force(A, C, D, Gp, 6000.0 * G)
    # two derivations of one static balance (statics by elimination vs virtual work): rounding, ~1e-15
    assert f.drives["_tip"][0] == pytest.approx(ref, rel=1e-12)
    assert ref > 0                                       # the cylinder pushes to hold the load up


def test_the_2r_arm_holds_its_weights_with_the_moments_about_its_joints():
    from analytic import mass
    from analytic.applications import forces as F
    arm = analytic.load("arm_2r")
    q = np.array([[0.3, 0.9], [2.0, -1.2], [-1.0, 2.5]])
    sol = arm.solve(q)
    inertias = mass.model(arm)
    f = F.solve(arm, q, 0.0 * q, 0.0 * q, inertias, gravity=(0.0, -G))
    up, fo = inertias["upper"], inertias["fore"]

    def xg(link, b):                                     # x of a link's centre of mass, from its angle
        o = arm.link_origins[link]
        phi = sol["phi" + link]
        return sol["x" + o] + b.cx * np.cos(phi) - b.cy * np.sin(phi)

    elbow = fo.m * G * (xg("fore", fo) - sol["xB"])      # the forearm's weight about B
    shoulder = up.m * G * xg("upper", up) + fo.m * G * xg("fore", fo)     # both about O = (0, 0)
    # statics by elimination vs moments written here: rounding on torques of ~10 N m
    np.testing.assert_allclose(f.drives["_elbow"], elbow, rtol=0, atol=1e-12)
    np.testing.assert_allclose(f.drives["upper"], shoulder, rtol=0, atol=1e-12)


# ----------------------------------------------------------------------------------------- pressure
@pytest.mark.parametrize("gravity, area", [("0,-9.81", "push"), ("0,9.81", "pull")])
def test_the_pressure_is_the_force_over_the_push_or_pull_area(gravity, area):
    r = run("forces", "dump_tipper", "--json", "--samples", "7", "--gravity", gravity)
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    force = np.array(out["drives"]["s_tip"])
    rec = out["actuators"]["tip"]
    assert rec["area"] == [area] * 7
    bore, rod = 0.16, 0.12                               # the file's diameters [m]
    a = math.pi * bore ** 2 / 4 if area == "push" else math.pi * (bore ** 2 - rod ** 2) / 4
    # one division each: rounding
    np.testing.assert_allclose(rec["pressure"], np.abs(force) / a, rtol=1e-12)
    assert np.all(np.sign(force) == (1 if area == "push" else -1))


# ---------------------------------------------------------------------------------------- bad input
def _edit(tmp_path, src, old, new, name="bad.toml"):
    text = src.read_text()
    assert old in text
    path = tmp_path / name
    path.write_text(text.replace(old, new))
    return path


def _refused(r, *needles):
    assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1, r.stderr
    for n in needles:
        assert n in lines[0], (n, lines[0])
    return lines[0]


def test_a_start_length_outside_the_stroke_is_refused(tmp_path):
    bad = _edit(tmp_path, ACTUATOR, "l0 = 0.60", "l0 = 0.40")
    out = tmp_path / "out.csv"
    r = run("analyze", bad, "--csv", out)
    _refused(r, "inputs[1] (point D)", "field 'l0'", "outside the stroke [0.5, 0.95]", "by 0.1 m")
    assert not out.exists()


def test_a_motion_past_the_stroke_is_refused_saying_when_and_by_how_much(tmp_path):
    bad = _edit(tmp_path, ACTUATOR, "v = 0.25", "v = 0.45")      # l(t) = 0.6 + 0.45 t - 0.05 t^2
    out = tmp_path / "f.csv"
    r = run("forces", bad, "--csv", out)
    line = _refused(r, "inputs[1] (point D)", "field 'stroke'", "extended length 0.95 m")
    assert not out.exists()
    # when: the root of 0.6 + 0.45 t - 0.05 t^2 = 0.95, by hand
    t_hand = (0.45 - math.sqrt(0.45 ** 2 - 4 * 0.05 * 0.35)) / (2 * 0.05)
    when = float(re.search(r"at t = ([0-9.]+) s", line).group(1))
    assert when == pytest.approx(t_hand, rel=6e-4)       # printed to 4 digits
    # by how much: the run moves it as far as it travels in a second at its start speed, 0.45 m, so it reaches
    # 0.6 + 0.45 = 1.05 m: 0.1 m past the end
    by = float(re.search(r"goes ([0-9.]+) m beyond", line).group(1))
    assert by == pytest.approx(0.1, rel=1e-3)            # printed to 4 digits
    r = run("compare", bad)
    _refused(r, "field 'stroke'", "at t = ")


def _in_mm(tmp_path, v="450", l0="600"):
    """tests/kinds/actuator.toml written in mm (every length x 1000), with the speed and start length given."""
    text = ACTUATOR.read_text()
    for old, new in (('format = "linkage/1"', 'format = "linkage/1"\nunits = "mm"'), ("C = [0.6, -0.25]", "C = [600, -250]"),
                     ("length = 0.8", "length = 800"), ("l0 = 0.60", f"l0 = {l0}"), ("v = 0.25", f"v = {v}"),
                     ("a = -0.1", "a = -100"), ("stroke = [0.50, 0.95]", "stroke = [500, 950]"),
                     ("bore = 0.063", "bore = 63"), ("rod = 0.036", "rod = 36"), ("at = [1.2, 0.1]", "at = [1200, 100]")):
        assert old in text
        text = text.replace(old, new)
    path = tmp_path / "mm.toml"
    path.write_text(text)
    return path


def test_a_mm_files_stroke_refusals_speak_mm(tmp_path):
    """The stroke's lengths and the overshoot in the file's unit (issue 37): the metres case above, x 1000."""
    r = run("forces", _in_mm(tmp_path), "--csv", tmp_path / "f.csv")
    line = _refused(r, "field 'stroke'", "the stroke [500, 950] mm", "extended length 950 mm")
    by = float(re.search(r"goes ([0-9.]+) mm beyond", line).group(1))
    assert by == pytest.approx(100.0, rel=1e-3)          # 0.1 m past the end, by hand above; printed to 4 digits
    assert not re.search(r"[0-9] m\b", line), line        # no length left in metres
    r = run("analyze", _in_mm(tmp_path, l0="400"))
    line = _refused(r, "field 'l0'", "400 mm is outside the stroke [500, 950] mm", "by 100 mm")
    assert not re.search(r"[0-9] m\b", line), line
    r = run("analyze", _edit(tmp_path, _in_mm(tmp_path), "stroke = [500, 950]", "stroke = [950, 500]", "swapped.toml"))
    _refused(r, "field 'stroke'", "the extended length 500 mm must exceed the retracted 950 mm")


def test_a_motor_whose_carrier_does_not_hold_its_pivot_is_refused(tmp_path):
    bad = _edit(tmp_path, MOTOR, 'pivot = "B"', 'pivot = "H"')
    bad.write_text(bad.read_text().replace("O = [0, 0]\n", "O = [0, 0]\nH = [100, 0]\n"))
    out = tmp_path / "a.csv"
    r = run("analyze", bad, "--csv", out)
    _refused(r, "inputs[2] (point C)", "field 'pivot'", "'H' is not a point of the carrier 'upper'")
    assert not out.exists()


def test_a_motor_on_the_ground_is_refused(tmp_path):
    bad = _edit(tmp_path, MOTOR, 'on = "upper"', 'on = "ground"')
    _refused(run("check", bad), "inputs[2] (point C)", "field 'on'", 'kind = "crank"')


# ------------------------------------------------------------------------------ links and joints
TIPPER_JOINTS = """
format = "linkage/1"
name = "tipper_joints"
output = "E"
[pose]
A = [0, 0]
C = [-2.4, -0.9]
D = [-1.9, 0.4]
E = [-4.6, 1.3]
[[links]]
name = "body"
points = ["A", "D", "E"]
[[links]]
name = "barrel"
points = ["C"]
[[links]]
name = "ram"
points = ["D"]
[[joints]]
kind = "R"
point = "A"
links = ["ground", "body"]
[[joints]]
kind = "R"
point = "C"
links = ["ground", "barrel"]
[[joints]]
kind = "R"
point = "D"
links = ["body", "ram"]
[[joints]]
kind = "P"
point = "D"
guide = "barrel"
block = "ram"
along = "C"
[[inputs]]
kind = "actuator"
joint = "D"
name = "tip"
v = 0.8
stroke = [0.95, 2.70]
"""

ARM_JOINTS = """
format = "linkage/1"
name = "arm_joints"
output = "C"
[pose]
O = [0, 0]
B = [0.34641016151377546, 0.2]
C = [0.34641016151377546, 0.5]
[[links]]
name = "upper"
points = ["O", "B"]
[[links]]
name = "fore"
points = ["B", "C"]
[[joints]]
kind = "R"
point = "O"
links = ["ground", "upper"]
[[joints]]
kind = "R"
point = "B"
links = ["upper", "fore"]
[[inputs]]
kind = "crank"
pivot = "O"
omega = "90deg"
[[inputs]]
kind = "motor"
joint = "B"
name = "elbow"
omega = "-180deg"
"""


def _element_tipper(tmp_path) -> Path:
    """The joints-form tipper written as elements, its numbers from its pose by hand."""
    A, C, D, E = (0.0, 0.0), (-2.4, -0.9), (-1.9, 0.4), (-4.6, 1.3)
    ad, cd = math.hypot(D[0] - A[0], D[1] - A[1]), math.hypot(D[0] - C[0], D[1] - C[1])
    ex, ey = (D[0] - A[0]) / ad, (D[1] - A[1]) / ad
    u, v = ex * (E[0] - A[0]) + ey * (E[1] - A[1]), ex * (E[1] - A[1]) - ey * (E[0] - A[0])
    branch = 1 if (C[0] - A[0]) * (D[1] - A[1]) - (C[1] - A[1]) * (D[0] - A[0]) > 0 else -1
    path = tmp_path / "tipper_elements.toml"
    path.write_text(f"""format = "linkage/1"
output = "E"
[ground]
A = [0, 0]
C = [-2.4, -0.9]
[[inputs]]
kind = "actuator"
name = "tip"
point = "D"
from = ["A", "C"]
length = {ad!r}
link = "body"
l0 = {cd!r}
v = 0.8
stroke = [0.95, 2.70]
branch = {branch}
cylinder = ["barrel", "ram"]
[[groups]]
kind = "point"
point = "E"
on = "body"
at = [{u!r}, {v!r}]
""")
    return path


@pytest.mark.parametrize("text, ref", [(TIPPER_JOINTS, None), (ARM_JOINTS, "arm_2r")], ids=["actuator", "motor"])
def test_the_links_and_joints_form_marks_a_p_or_r_joint_between_moving_links_as_the_input(tmp_path, text, ref):
    path = tmp_path / "joints.toml"
    path.write_text(text)
    m = analytic.load(str(path))
    other = analytic.load(ref) if ref else analytic.load(str(_element_tipper(tmp_path)))
    assert [i.q for i in m.inputs] == [i.q for i in other.inputs]
    t = np.linspace(0.0, 1.0, 9)
    _, a = m.solve_at(t)
    _, b = other.solve_at(t)
    for k in ("x", "y", "vx", "vy", "ax", "ay"):
        p = m.output_point
        # the pose's numbers through the form's symbolic lengths vs the same numbers typed: rounding
        np.testing.assert_allclose(a[k + p], b[k + p], rtol=0, atol=1e-12, err_msg=k + p)
    r = run("check", path)
    said = "D (links body, barrel, ram): dyad RRR with a driven length" if ref is None else "q_elbow (motor at B)"
    assert r.returncode == 0 and said in r.stdout, r.stdout


@pytest.mark.parametrize("old, new, needles", [
    ('joint = "B"', 'joint = "O"', ("inputs[2] (joint O)", "field 'joint'", 'kind = "crank"')),
    ('joint = "B"', 'joint = "C"', ("inputs[2] (joint C)", "field 'joint'", "no R joint")),
])
def test_a_motor_on_a_joint_it_cannot_drive_is_refused(tmp_path, old, new, needles):
    path = tmp_path / "bad.toml"
    path.write_text(ARM_JOINTS.replace(old, new))
    _refused(run("check", path), *needles)


def test_an_actuator_whose_p_joint_is_not_along_its_pins_is_refused(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(TIPPER_JOINTS.replace('along = "C"', 'angle = "10deg"'))
    _refused(run("check", path), "inputs[1] (joint D)", "not along the cylinder C -> D")


# ------------------------------------------------------------------------------------- power balance
@pytest.mark.parametrize("path", [ACTUATOR, EXAMPLES / "actuator__on_links.toml", MOTOR], ids=lambda p: p.stem)
def test_the_drives_equal_the_power_balance(path):
    """Newton-Euler per group (the kinds' closed forms) against the power balance (each input's virtual power
    from the velocity coefficients, analytic.applications.torque): two derivations of one drive."""
    from agreement import drive, rng_for
    from analytic import mass
    from analytic.applications import forces as F
    from analytic.applications import torque
    m = analytic.load(str(path))
    _, q, qd, qdd = drive(m, 41, rng_for(path.stem + "power"))
    inertias = mass.model(m)
    ne = F.solve(m, q, qd, qdd, inertias, gravity=(0.7, -G), force=(30.0, -20.0))
    pb = torque.drive_forces(m, q, qd, qdd, inertias, None, (0.7, -G), (30.0, -20.0))
    for inp in m.inputs:
        peak = float(np.max(np.abs(pb[inp.link])))
        # rounding of two eliminations of one linear system, relative to the drive's peak
        assert np.max(np.abs(ne.drives[inp.link] - pb[inp.link])) <= 1e-9 * peak, inp.q


# ------------------------------------------------------------------------------------------- library
@pytest.mark.parametrize("name", ["arm_2r", "dump_tipper", "excavator", "scissor_lift"])
def test_the_drive_mechanisms_of_the_library_pass_compare_under_gravity(name):
    """MuJoCo (the cylinders as barrel and rod bodies on a driven slide, the elbow a driven hinge between its
    links) against the closed forms, with their joint forces, under gravity."""
    from sim import service
    from sim.model.settings import Loads
    _, c = service.compare(analytic.load(name), loads=Loads(gravity=(0.0, -G)))
    failed = {k: v for k, v in c.errors.items() if not v["passed"]}
    assert c.passed, (failed, c.drive_error, c.work_balance)


@pytest.mark.parametrize("name", ["arm_2r", "dump_tipper", "excavator", "scissor_lift", "servo_press"])
def test_the_drive_mechanisms_of_the_library_pass_compare_without_gravity(name):
    """As above with no weight to stiffen the loops (sim.model.build.regularization): a cylinder's light rod on a
    heavy link is covered by the loops' spread alone (SPREAD_REF)."""
    from sim import service
    _, c = service.compare(analytic.load(name))
    failed = {k: v for k, v in c.errors.items() if not v["passed"]}
    assert c.passed, (failed, c.drive_error, c.work_balance)


def test_the_loop_spread_is_the_light_rod_on_the_heavy_link():
    """sim.model.build.loop_spread against a two-body hand model: a light body (m) on a slide whose rotor
    inertia is J, pinned by the loop to a heavy body (M) on a slide at right angles. In the plane the loop's
    mobility is diag(1 / (m + J), 1 / M) (each direction moves one slide), so lambda_min = 1 / max(m + J, M),
    and MuJoCo's compiled invweight0 (without J) is each body's mobility along its slide, 1 / its mass."""
    import mujoco
    from sim.model.build import Loop, loop_spread
    from sim.model.armature import set_armature
    m, M, J = 0.3, 1500.0, 4.0e6
    xml = f"""<mujoco><option gravity="0 0 0"/><worldbody>
      <body name="rod"><joint name="s" type="slide" axis="1 0 0"/><geom type="sphere" size="0.01" mass="{m}"/>
        <site name="p_rod"/></body>
      <body name="boom"><joint name="b" type="slide" axis="0 1 0"/><geom type="sphere" size="0.01" mass="{M}"/>
        <site name="p_boom"/></body></worldbody>
      <equality><connect site1="p_rod" site2="p_boom"/></equality></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    w = model.body_invweight0[1:, 0].copy()
    # MuJoCo's compile-time estimate (its own arithmetic): 1 / mass for a body on one slide
    assert w == pytest.approx([1 / m, 1 / M], rel=1e-6)
    set_armature(model, "s", J)
    spread = loop_spread(model, (Loop("c", "p", "p_rod", "p_boom"),), np.zeros(2), np.zeros(2))
    # the hand model's eigenvalues; rel: mj_solveM's factorisation rounding on a 1e7 spread of inertias
    assert spread == pytest.approx((w[0] + w[1]) * max(m + J, M), rel=1e-9)


def test_the_model_tree_hangs_a_driven_link_from_its_base():
    """A pair driven between two moving links is measured by MuJoCo's joint as the driven link relative to its
    base, so the spanning tree must have the base as the parent. Joints listed so that, taken in order, the
    tree would reach the driven link b through m and hang the base from it: b's other joint is left out."""
    from analytic.topology import Joint, _spanning_tree
    joints = (Joint("revolute", "P", "on", "b", "P", 0, None),        # driven: b relative to on
              Joint("revolute", "Q", "ground", "m", "Q", None, None),
              Joint("revolute", "R", "m", "b", "R", None, None),
              Joint("revolute", "S", "ground", "on", "S", None, None))
    tree, loops = _spanning_tree(joints, {"on": None, "b": None, "m": None})
    parent = {child: par for par, child, _ in tree}
    assert parent["b"] == "on" and parent["on"] == "ground"
    assert [lp.joint.name for lp in loops] == ["R"]


def test_two_inputs_of_one_name_are_refused(tmp_path):
    # a wrist motor named like the elbow: their columns (q_elbow) would collide
    bad = _edit(tmp_path, MOTOR, "[[groups]]", '[[inputs]]\nkind = "motor"\nname = "elbow"\npivot = "C"\non = "fore"\n'
                                              'point = "W"\nlength = 50\nlink = "wrist"\n\n[[groups]]')
    _refused(run("check", bad), "inputs[3] (point W)", "field 'name'", "'elbow' is already named by inputs[2]")


def test_the_inputs_own_columns_are_converted_to_the_display_units(tmp_path):
    out = tmp_path / "a.csv"
    r = run("analyze", "dump_tipper", "--units", "mm", "--csv", out, "--samples", "3")
    assert r.returncode == 0, r.stderr
    header, first = out.read_text().splitlines()[:2]
    row = dict(zip(header.split(","), first.split(",")))
    assert float(row["s_tip"]) == pytest.approx(1000.0, rel=1e-12)      # l0 = 1.00 m in mm; one product
    assert float(row["ds_tip"]) == pytest.approx(1200.0, rel=1e-12)     # v = 1.2 m/s in mm/s
    units = json.loads((tmp_path / "a.csv.units.json").read_text())["units"]
    assert (units["s_tip"], units["ds_tip"], units["dds_tip"]) == ("mm", "mm/s", "mm/s^2")


def test_forces_prints_the_peak_pressure():
    r = run("forces", "dump_tipper", "--gravity", "0,-9.81", "--samples", "7")
    assert r.returncode == 0, r.stderr
    j = json.loads(run("forces", "dump_tipper", "--gravity", "0,-9.81", "--samples", "7", "--json").stdout)
    peak = max(j["actuators"]["tip"]["pressure"]) / 1e5
    line = next(ln for ln in r.stdout.splitlines() if "pressure of tip" in ln)
    shown = float(re.search(r"peak ([0-9.]+) bar on its push area", line).group(1))
    assert shown == pytest.approx(peak, rel=1e-4)        # printed to 5 digits
