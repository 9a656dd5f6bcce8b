"""``linkage import`` of PMKS gear meshes (``a, b, G, x, y``: the pitch point where the gears of links a and b
touch): a two-gear train, an internal (ring) pair, a sun-driven planetary with a fixed ring and a compound
wobbler, each imported, solved over a turn and checked against the motion that rolling contact gives (derived
here from the pitch circles, not from the code); every PMKS joint where the source draws it at the start; and
bad meshes refused in one line naming the joint.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import analytic
from analytic import FileError
from analytic.format import joints, pmks
from sim import service
from test_joints_form import solved_points

HAND = 1e-12       # / size: solver against hand geometry (closed forms on both sides: rounding)
POSE = 1e-9        # / size: the source's pose at the start


def load(tmp_path, text: str, name: str = "gears"):
    path = tmp_path / f"{name}.txt"
    path.write_text(text)
    return analytic.load(str(path))


def xy(p) -> str:
    return f"{float(p[0])!r},{float(p[1])!r}"


def source_pose(text: str) -> dict[str, np.ndarray]:
    return {f"J{k}": np.array(j[2]) for k, j in enumerate(pmks.parse(text, "t")[0])}


def check_pose(m, text: str, size: float):
    """Every PMKS joint (pitch points too) is our point of its name, at the input's start."""
    at0 = solved_points(m, np.array([[m.inputs[0].motion.q0]]))
    for p, want in source_pose(text).items():
        assert np.linalg.norm(at0[p][0] - want) <= POSE * size, p


def circle(c, r, a):
    return np.stack([c[0] + r * np.cos(a), c[1] + r * np.sin(a)], axis=-1)


def turn(m, n: int = 73):
    q0 = m.inputs[0].motion.q0
    return q0, q0 + np.linspace(0.0, 2.0 * np.pi, n)


# ------------------------------------------------------------------------------------ fixed axes
def test_external_pair_turns_the_output_back_at_minus_ra_over_rb(tmp_path):
    """Input gear r_a = 4 about (0, 0), output r_b = 6 about (10, 0), touching at (4, 0). The pitch point's speed
    is the same on both circles and the gears turn opposite ways: omega_b r_b = -omega_a r_a."""
    text = ("ground, input,R,0,0.00\ninput, output,G,4,0.00\noutput ground,R,10,0.00\n"
            "input,R,0,3\noutput,R,10,2\n")
    m = load(tmp_path, text)
    check_pose(m, text, 10)
    q0, q = turn(m)
    assert q0 == pytest.approx(math.pi / 2, abs=1e-15)        # the crank: J0 -> J3
    pts = solved_points(m, q)
    out = math.pi / 2 - 4 / 6 * (q - q0)
    assert np.max(np.linalg.norm(pts["J4"] - circle((10, 0), 2, out), axis=-1)) <= HAND * 10
    assert np.max(np.linalg.norm(pts["J3"] - circle((0, 0), 3, q), axis=-1)) <= HAND * 10
    assert np.max(np.linalg.norm(pts["J1"] - [4, 0], axis=-1)) == 0.0        # the pitch point stays on the ground
    sol = m.solve(q[:1])
    assert sol["omegaoutput"][0] == pytest.approx(-4 / 6 * sol["omegainput"][0], rel=1e-14)


def test_internal_pair_turns_the_ring_the_same_way_at_ra_over_rb(tmp_path):
    """Pinion r_a = 2 about (0, 0) inside a ring r_b = 5 about (3, 0): the pitch point (-2, 0) lies beyond the
    pinion's centre, not between the centres; the ring turns the same way, omega_b r_b = omega_a r_a."""
    text = "ground,input,R,0,0\ninput,ring,G,-2,0\nring,ground,R,3,0\ninput,R,1,0\nring,R,3,4\n"
    m = load(tmp_path, text)
    check_pose(m, text, 7)
    q0, q = turn(m)
    assert q0 == 0.0
    pts = solved_points(m, q)
    assert np.max(np.linalg.norm(pts["J4"] - circle((3, 0), 4, math.pi / 2 + 2 / 5 * q), axis=-1)) <= HAND * 7
    form = pmks.to_form(text, "t")
    assert "gear ring on ground about J2 (mesh input, ratio 0.4)" in joints.structure(form, "t", {})


# ------------------------------------------------------------------------------------ planetary
R_S, R_P = 3.0, 2.0                 # sun and planet pitch radii; the ring's R_S + 2 R_P = 7, the arm R_S + R_P
A0, B0 = 0.4, 1.1                   # the arm's and the planet mark's angles as drawn


def planetary_text() -> str:
    u = np.array([math.cos(A0), math.sin(A0)])
    c = (R_S + R_P) * u
    mark = c + R_P * np.array([math.cos(B0), math.sin(B0)])
    return (f"ground,sun,arm,R,0,0.00\narm,planet,R,{xy(c)},0.00\nsun,planet,G,{xy(R_S * u)}\n"
            f"planet,gnd,G,{xy((R_S + 2 * R_P) * u)}\nplanet,R,{xy(mark)}\n")


def test_sun_driven_planetary_with_a_fixed_ring_against_rolling_contact(tmp_path):
    """The planet touches the fixed ring at a point at rest and the sun at a point moving at omega_s R_S; its
    centre, halfway along that diameter, moves at omega_s R_S / 2 = omega_arm (R_S + R_P), so omega_arm =
    omega_s R_S / (2 (R_S + R_P)) = omega_s R_S / (R_S + R_ring); the planet turns about the point at rest:
    omega_p = -(omega_s R_S / 2) / R_P. The sun carries no point of its own: its crank is marked at the pitch
    point (sun_tooth)."""
    text = planetary_text()
    m = load(tmp_path, text)
    size = 2 * (R_S + 2 * R_P)
    check_pose(m, text, size)
    q0, q = turn(m)
    assert q0 == pytest.approx(A0, abs=1e-15)
    dq = q - q0
    w_arm, w_p = R_S / (R_S + (R_S + 2 * R_P)), -R_S / (2 * R_P)
    assert (w_arm, w_p) == (0.3, -0.75)
    arm = A0 + w_arm * dq
    pts = solved_points(m, q)
    centre = circle((0, 0), R_S + R_P, arm)
    assert np.max(np.linalg.norm(pts["J1"] - centre, axis=-1)) <= HAND * size
    assert np.max(np.linalg.norm(pts["J4"] - circle(centre.T, R_P, B0 + w_p * dq), axis=-1)) <= HAND * size
    for p, r in (("J2", R_S), ("J3", R_S + 2 * R_P)):           # the pitch points ride on the arm
        assert np.max(np.linalg.norm(pts[p] - circle((0, 0), r, arm), axis=-1)) <= HAND * size
    sol = m.solve(q[:1])
    assert sol["omegaarm"][0] == pytest.approx(w_arm * sol["omegasun"][0], rel=1e-13)
    assert sol["omegaplanet"][0] == pytest.approx(w_p * sol["omegasun"][0], rel=1e-13)


def test_planetary_passes_compare(tmp_path):
    """MuJoCo (the gear pairs as tendon equalities over the hinges) agrees with the analytic solution."""
    _, c = service.compare(load(tmp_path, planetary_text()), 1.0)
    assert c.passed


def test_compound_wobbler_output_on_a_pin_coaxial_with_the_arm(tmp_path):
    """PMKS' MirroredWobbler: the arm turns about O; the compound gear on its tip (1 from O) rolls with r = 43 in
    the fixed ring r = 44 and with r = 45 in the output ring r = 46, which turns on its own ground pin at O.
    Relative to the arm, the ring turns at -omega_arm and an internal pair keeps the sense:
    omega_g - omega_arm = (44/43) (0 - omega_arm); omega_out - omega_arm = (45/46) (omega_g - omega_arm), so
    omega_out = (1 - 44 45 / (43 46)) omega_arm = -omega_arm / 989."""
    text = ("ground,arm,R,0,0\narm,gears,R,1,0\ngears,ground,G,44,0\ngears,output,G,46,0\nground,output,R,0,0\n"
            "gears,R, -43,0\noutput,R,47,0\n")
    m = load(tmp_path, text)
    check_pose(m, text, 90)
    _, q = turn(m)
    pts = solved_points(m, q)
    assert np.max(np.linalg.norm(pts["J6"] - circle((0, 0), 47, -q / 989), axis=-1)) <= HAND * 90
    centre = circle((0, 0), 1, q)
    assert np.max(np.linalg.norm(pts["J5"] - circle(centre.T, 44, math.pi - q / 43), axis=-1)) <= HAND * 90


# ------------------------------------------------------------------------------------------ refused
@pytest.mark.parametrize("text,match", [
    ("ground,input,R,0,0\ninput,output,G,0,0\noutput,ground,R,5,0\n",
     r"t\.txt: joints\[3\] \(point J1\): the pitch point J1 is at the centre J0 of input's gear \(a pitch radius of 0\)"),
    ("ground,input,R,0,0\ninput,output,G,5,0\noutput,ground,R,5,0\n",
     r"t\.txt: joints\[3\] \(point J1\): the pitch point J1 is at the centre J2 of output's gear"),
    ("ground,input,R,0,0\ninput,output,G,2,1\noutput,ground,R,5,0\ninput,R,1,1\n",
     r"t\.txt: joints\[3\] \(point J1\): the pitch point J1 is not on the line of the centres J0 \(input\) and J2 "
     r"\(output\) on ground"),
    ("ground,input,R,0,0\ninput,output,G,2,0\noutput,a,R,5,0\na,ground,R,5,5\n",
     r"t\.txt: joints\[4\] \(point J1\): the gears of input and output turn about no common carrier"),
    ("ground,input,R,0,0\ninput,output,ground,G,2,0\noutput,ground,R,5,0\n",
     r"t\.txt: joint J1 is a gear mesh \(G\) on 3 link\(s\) \(input, output, ground\); a mesh joins the gears of two"),
])
def test_bad_mesh_is_refused_in_one_line_naming_the_joint(tmp_path, text, match):
    path = tmp_path / "t.txt"
    path.write_text(text)
    with pytest.raises(FileError, match=match) as err:
        analytic.load(str(path))
    assert "\n" not in str(err.value)


# ------------------------------------------------------------------------------ the form's G joint
GEARED_FIVE_BAR = """
format = "linkage/1"
units = "mm"
[pose]
A = [0, 0]
K = [4, 0]
D = [10, 0]
B = [0, 3]
C = [10, 5]
P = [5, 8]
[[links]]
name = "input"
points = ["A", "B"]
[[links]]
name = "output"
points = ["D", "C"]
[[links]]
name = "c"
[[links]]
name = "d"
[[joints]]
kind = "R"
point = "A"
links = ["ground", "input"]
[[joints]]
kind = "R"
point = "D"
links = ["ground", "output"]
[[joints]]
kind = "G"
point = "K"
links = ["input", "output"]
[[joints]]
kind = "R"
point = "B"
links = ["input", "c"]
[[joints]]
kind = "R"
point = "P"
links = ["c", "d"]
[[joints]]
kind = "R"
point = "C"
links = ["d", "output"]
[[inputs]]
kind = "crank"
pivot = "A"
point = "B"
"""


def test_form_g_joint_places_the_gear_before_the_dyad(tmp_path):
    """A geared five-bar written by hand: the output gear is placed by the mesh (ratio -4/6), then the dyad
    c, d closes the loop; with a second loop that fixes the output too, the mesh is refused as locked."""
    path = tmp_path / "g5.toml"
    path.write_text(GEARED_FIVE_BAR)
    m = analytic.load(str(path))
    _, q = turn(m)
    pts = solved_points(m, q)
    assert np.max(np.linalg.norm(pts["C"] - circle((10, 0), 5, math.pi / 2 - 4 / 6 * (q - math.pi / 2)),
                                 axis=-1)) <= HAND * 12
    import tomllib
    assert joints.structure(tomllib.loads(GEARED_FIVE_BAR), "g5", {})[:3] == (
        "input crank input about A", "gear output on ground about D (mesh input, ratio -0.666666667)",
        "dyad RRR c, d at P")
    locked = (GEARED_FIVE_BAR.replace('links = ["c", "d"]', 'links = ["c", "output"]')
              .replace('[[links]]\nname = "d"\n', '').replace('[[joints]]\nkind = "R"\npoint = "C"\nlinks = ["d", "output"]\n', ''))
    path.write_text(locked)
    with pytest.raises(FileError, match=r"the loop c - output - ground - input cannot move: .*Gruebler: "
                                        r"3 x \(4 - 1\) - 2 x 4 - 1 = 0"):
        analytic.load(str(path))
