"""The ``gear`` kind beyond the conformance suite (tests/test_kinds.py runs it against the Newton oracle, finite
differences and MuJoCo): what its two library mechanisms are famous for, checked against closed forms from
the geometry; counting turns; the pitch radii; and every way a gear element can be written wrong refused in
one line naming the field.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import analytic
from agreement import POS_TOL, RATE_TOL, drive
from analytic import ParameterError
from analytic.kinds.gear import pitch_radii

import cli_runner  # the command in this process (tests/cli_runner.py)

KINDS = Path(__file__).resolve().parent / "kinds"


# ------------------------------------------------------------------------- what the library files show
def test_geared_five_bar_draws_an_exact_straight_line_at_ratio_minus_one_and_phase_pi():
    """Norton's geared five-bar: the gears mirror crank DC onto AB about x = d/2, so the joint P of the equal
    links stays on that line; at another phase it does not."""
    m = analytic.load("geared_five_bar")
    t, *_ = drive(m, 721, endpoint=True)
    _, sol = m.solve_at(t)
    x_line = m.values["d"] / 2 * m.scale
    assert np.max(np.abs(sol["xP"] - x_line)) <= POS_TOL * m.size            # rounding only
    assert np.max(np.abs(sol["vxP"])) <= RATE_TOL * np.max(np.abs(sol["vyP"]))
    assert np.max(np.abs(sol["axP"])) <= RATE_TOL * np.max(np.abs(sol["ayP"]))
    _, off = m.with_values(phase=math.radians(150)).solve_at(t)
    assert np.max(np.abs(off["xP"] - x_line)) > 0.1 * m.size                  # the phase makes the line


def _hypocycloid(R, r, e, theta):
    """A point at e from the centre of a circle of radius r rolling inside one of radius R, its arm (centre
    to centre) at theta, the point on the arm's line beyond the planet's centre at theta = 0."""
    return ((R - r) * np.cos(theta) + e * np.cos((R - r) / r * theta),
            (R - r) * np.sin(theta) - e * np.sin((R - r) / r * theta))


@pytest.mark.parametrize("r", [50.0, 100 / 3, 25.0])     # Tusi couple (a diameter), deltoid, astroid
def test_planetary_linkage_traces_the_hypocycloid_of_its_radii(r):
    m = analytic.load("planetary_linkage", r=r)
    t, q, *_ = drive(m, 721, endpoint=True)
    _, sol = m.solve_at(t)
    R, k = m.values["R"], m.scale
    for p, e in (("P", r), ("E", r / 2)):
        x, y = _hypocycloid(R * k, r * k, e * k, q[:, 0])
        assert np.max(np.hypot(sol["x" + p] - x, sol["y" + p] - y)) <= POS_TOL * m.size, (r, p)


def test_tusi_couple_rim_point_runs_on_a_diameter_and_inner_point_on_an_ellipse():
    m = analytic.load("planetary_linkage")
    t, q, *_ = drive(m, 721, endpoint=True)
    _, sol = m.solve_at(t)
    r, e = m.values["r"] * m.scale, m.values["e"] * m.scale
    assert np.max(np.abs(sol["yP"])) <= POS_TOL * m.size
    assert np.max(np.abs(sol["xP"] - 2 * r * np.cos(q[:, 0]))) <= POS_TOL * m.size
    ellipse = (sol["xE"] / (r + e)) ** 2 + (sol["yE"] / (r - e)) ** 2
    assert np.max(np.abs(ellipse - 1)) <= 10 * POS_TOL                        # rounding of squares near 1
    area = 0.5 * abs(np.sum(sol["xE"][:-1] * sol["yE"][1:] - sol["xE"][1:] * sol["yE"][:-1]))
    n = len(q) - 1                          # E at equal steps of the arm's angle: an n-gon of area n a b sin(2 pi/n)/2
    assert area == pytest.approx(n / 2 * (r + e) * (r - e) * math.sin(2 * math.pi / n), rel=1e-12)   # rounding


# --------------------------------------------------------------------------------- counting turns
def test_the_gear_counts_the_cranks_turns():
    """Ratio -1/2: one more turn of the crank turns gear 2 half a turn, which puts its pin C opposite D."""
    m = analytic.load(str(KINDS / "gear.toml"))
    q = np.linspace(0.0, 2 * math.pi, 13)
    D = np.array(m.geometry.ground["D"])
    for turns in (1, 2, 3):
        a, b = m.solve(q), m.solve(q + 2 * math.pi * turns)
        if turns % 2:
            assert np.max(np.hypot(b["xC"] + a["xC"] - 2 * D[0], b["yC"] + a["yC"] - 2 * D[1])) <= POS_TOL * m.size
        else:
            assert np.max(np.hypot(b["xC"] - a["xC"], b["yC"] - a["yC"])) <= 1e-11 * m.size   # |q| ~ 20: rounding


def test_phase_and_ratio_as_documented_on_a_ground_carrier():
    """phi_gear = phase + ratio phi_crank (docs/CONVENTIONS.md), read from the points."""
    m = analytic.load(str(KINDS / "gear.toml"))
    q = np.linspace(-7.0, 9.0, 17)
    sol = m.solve(q)
    phi = np.arctan2(sol["yC"], sol["xC"] - m.geometry.ground["D"][0])
    want = math.radians(30) - 0.5 * q
    assert np.max(np.abs(np.angle(np.exp(1j * (phi - want))))) <= 1e-14 * 20    # atan2 of coordinates ~ 0.1 m


# ------------------------------------------------------------------------------------ pitch radii
@pytest.mark.parametrize("ratio, d, want", [
    (-0.5, 0.2, (0.2 / 3, 0.4 / 3)),      # external: r_mesh + r_gear = d, r_mesh / r_gear = 1/2
    (-1.0, 0.2, (0.1, 0.1)),
    (2.0, 0.05, (0.1, 0.05)),             # internal, the mesh is the ring: r_mesh - r_gear = d
    (0.25, 0.3, (0.1, 0.4)),              # internal, the new gear is the ring: r_gear - r_mesh = d
])
def test_pitch_radii(ratio, d, want):
    assert pitch_radii(ratio, d) == pytest.approx(want, rel=1e-15)


def test_check_reports_the_pitch_radii_in_the_files_unit():
    out = cli_runner.run("check", "planetary_linkage")
    assert out.returncode == 0, out.stderr
    assert ("gear planet-ground on arm: pitch radii 50 (planet) and 100 (ground) mm at centre distance 50 mm "
            "(internal, ground is the ring)") in out.stdout


def test_gruebler_counts_a_gear_pair_as_a_higher_pair():
    """Without the - h term these one-input files would count two freedoms and be refused."""
    five = analytic.load("geared_five_bar").topology
    assert five.counts == (5, 5, 1) and five.gruebler() == "3 x (5 - 1) - 2 x 5 - 1 = 1"
    planetary = analytic.load(str(KINDS / "gear__planetary.toml")).topology
    assert planetary.counts == (6, 6, 2) and planetary.gruebler() == "3 x (6 - 1) - 2 x 6 - 2 = 1"


# ------------------------------------------------------------------------------------ bad input
GEAR = (KINDS / "gear.toml").read_text()
PLANETARY = (KINDS / "gear__planetary.toml").read_text()
BAD = [
    ("ratio 0", GEAR.replace("ratio = -0.5", "ratio = 0"), "field 'ratio': 0 holds the gear still"),
    ("ratio 1", GEAR.replace("ratio = -0.5", "ratio = 1"), "field 'ratio': 1 turns the gear with its mesh"),
    ("mesh is itself", GEAR.replace('mesh = "1"', 'mesh = "2"'), "field 'mesh': the gear cannot mesh with its own"),
    ("mesh is the carrier", GEAR.replace('mesh = "1"', 'mesh = "ground"'), "field 'mesh': 'ground' is also the carrier"),
    ("no such mesh", GEAR.replace('mesh = "1"', 'mesh = "7"'), "no link named '7'"),
    ("mesh not pinned to the carrier", GEAR.replace('mesh = "1"', 'mesh = "3"').replace(
        'from = ["B", "C"]', 'from = ["B", "D"]'), "the mesh gear must turn about one pin on the carrier"),
    ("pivot off the ground", GEAR.replace('pivot = "D"', 'pivot = "B"'), "field 'pivot': 'B' must be a ground point"),
    ("pivot off the arm", PLANETARY.replace('pivot = "G"', 'pivot = "F"'),
     "field 'pivot': 'F' is not on the carrier 'arm' (points of link arm: O, B, G)"),
]


@pytest.mark.parametrize("text, message", [(t, m) for _, t, m in BAD], ids=[c for c, _, _ in BAD])
def test_a_wrong_gear_is_refused_in_one_line_naming_the_field(text, message):
    with pytest.raises(ParameterError) as err:
        analytic.from_text(text, "bad")
    line = str(err.value)
    assert "\n" not in line and message in line, line


def test_a_wrong_gear_file_exits_2_with_one_line(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(GEAR.replace("ratio = -0.5", "ratio = 1"))
    out = cli_runner.run("check", str(path))
    assert out.returncode == 2 and out.stdout == ""
    assert out.stderr.count("\n") == 1 and "groups[1] (point C): field 'ratio'" in out.stderr, out.stderr


# ------------------------------------------------------------------------------------------- drawing
@pytest.mark.parametrize("name", ["gear.toml", "gear__planetary.toml"])
def test_drawn_gears_mesh_at_the_contact_point(name):
    """Teeth in the ratio with one module, the mesh gear's tooth and the new gear's gap both centred on the
    pitch point (on the line of centres, r_mesh from the mesh's centre) at the start."""
    m = analytic.load(str(KINDS / name))
    _, start = m.solve_at([0.0])
    pose = {p: (float(start["x" + p][0]), float(start["y" + p][0])) for p in m.points}
    for e in (e for e in m.geometry.elements if e["kind"] == "gear"):
        a, b = analytic.kinds.get("gear").wheels(e, pose)
        assert a.teeth * 1.0 / b.teeth == pytest.approx(abs(e["ratio"]), rel=1e-12)
        assert a.radius / a.teeth == pytest.approx(b.radius / b.teeth, rel=1e-12)      # one module
        (ax, ay), (bx, by) = pose[a.centre], pose[b.centre]
        d = math.hypot(bx - ax, by - ay)
        assert a.radius + b.radius == pytest.approx(d, rel=1e-12)                       # external examples
        kx, ky = ax + a.radius * (bx - ax) / d, ay + a.radius * (by - ay) / d
        for w, offset in ((a, 0.0), (b, math.pi / b.teeth)):
            cx, cy = pose[w.centre]
            ref = 0.0 if w.ref is None else math.atan2(pose[w.ref][1] - cy, pose[w.ref][0] - cx)
            toward = math.atan2(ky - cy, kx - cx)
            assert abs(math.remainder(ref + w.phase - offset - toward, 2 * math.pi)) <= 1e-12
