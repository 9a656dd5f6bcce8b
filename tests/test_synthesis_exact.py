"""Motion (Burmester) and function (Freudenstein) synthesis: targets taken from known four-bars by the
general solver, the synthesised linkage/1 file solved again by the general solver at the targets' input
angles (an independent check of the closed forms used in synthesis), defects refused, bad CSVs refused."""

import json
import math

import numpy as np
import pytest

import analytic
from analytic import ParameterError
from analytic.synthesis import fourbar as synth_fourbar
from analytic.synthesis import function as synthesis_function
from analytic.synthesis import motion as synthesis_motion

import cli_runner  # the command in this process (tests/cli_runner.py)

KNOWN = dict(l1=0.10, l2=0.30, l3=0.25, l4=0.30, ex=0.15, ey=0.10)
"""The library four-bar's own crank-rocker (A = (0, 0), D = (l4, 0)): a reference whose poses any design
must reproduce."""


def run(*args):
    return cli_runner.run(*args)


def wrap(x):
    return (np.asarray(x) + np.pi) % (2 * np.pi) - np.pi


def known_poses(angles_deg, branch=1, **over):
    m = analytic.load("fourbar", branch=branch, **{**KNOWN, **over})
    sol = m.solve(np.radians(angles_deg))
    return np.column_stack([sol["xE"], sol["yE"], sol["phi2"]])


def solver_pose_errors(design, poses):
    """The design's linkage/1 file solved by the general solver at its input angles: coupler point
    distance and coupler angle change error at each pose."""
    mech = synth_fourbar.mechanism(design.linkage)
    sol = mech.solve(design.inputs)
    dist = np.hypot(sol["xE"] - poses[:, 0], sol["yE"] - poses[:, 1])
    ang = wrap((sol["phi2"] - sol["phi2"][0]) - (poses[:, 2] - poses[0, 2]))
    return dist, ang


SIZE = 0.30          # the known four-bar's longest link [m]
TOL = 1e-9 * SIZE    # issue 19: poses reproduced to 1e-9 of the size (bounds rounding of the dyad solves)


def test_five_poses_give_the_known_pivots_among_the_burmester_points_and_are_reproduced():
    poses = known_poses(np.linspace(10, 250, 5))
    designs, dyads = synthesis_motion.synthesize(poses)
    centres = np.array([d.centre for d in dyads])
    for pivot in ((0.0, 0.0), (KNOWN["l4"], 0.0)):       # the known linkage's ground pivots A and D
        assert np.min(np.hypot(*(centres - pivot).T)) < TOL
    assert len(designs) >= 2 and not designs[0].defect
    for d in designs:
        if d.defect:
            continue
        dist, ang = solver_pose_errors(d, poses)
        assert dist.max() < TOL
        assert np.abs(ang).max() < 1e-9                    # [rad] same bound on the coupler's angle


@pytest.mark.parametrize("n", [3, 4])
def test_three_and_four_poses_reproduced_by_the_general_solver(n):
    poses = known_poses(np.linspace(20, 200, n), branch=-1)
    designs, dyads = synthesis_motion.synthesize(poses)
    assert dyads and designs
    good = [d for d in designs if not d.defect]
    assert good
    for d in good:
        dist, ang = solver_pose_errors(d, poses)
        assert dist.max() < TOL and np.abs(ang).max() < 1e-9
        # each dyad's circle point stays on its circle through the poses (geometry, not the solver)
        for dy in (d.crank, d.rocker):
            P = poses[:, :2] + np.stack([np.cos(poses[:, 2]) * dy.circle[0] - np.sin(poses[:, 2]) * dy.circle[1],
                                         np.sin(poses[:, 2]) * dy.circle[0] + np.cos(poses[:, 2]) * dy.circle[1]], -1)
            r = np.hypot(*(P - dy.centre).T)
            assert np.ptp(r) < TOL


def test_four_pose_centre_points_lie_on_the_cubic():
    poses = known_poses([0, 60, 130, 220])
    pts = synthesis_motion.centre_point_curve(poses, rays=90)
    assert len(pts) > 90
    # the 3x2 system in z is consistent on the curve: its least-squares circle point solves all three
    for c in pts[::7]:
        alpha, beta, gamma, G = synthesis_motion.dyad_equations(poses)
        M = beta - np.einsum("jab,a->jb", G, c)
        rhs = gamma @ c - alpha
        z = np.linalg.lstsq(M, rhs, rcond=None)[0]
        # residual relative to the equations' scale (size^2); 1e-8 bounds the cubic's root finding
        assert np.abs(M @ z - rhs).max() < 1e-8 * max(1.0, np.abs(rhs).max())


def test_three_poses_centre_point_of_a_chosen_circle_point():
    poses = known_poses([0, 70, 150])
    # the known crank's tip B: its centre point must be A (hand-checkable: B turns about A)
    th = poses[0, 2]
    B1 = np.array([KNOWN["l1"], 0.0])                    # crank at phi = 0: B = (l1, 0)
    z = np.array([[math.cos(th), math.sin(th)], [-math.sin(th), math.cos(th)]]) @ (B1 - poses[0, :2])
    c = synthesis_motion.centre_point(poses, z)
    assert np.hypot(*c) < TOL


def test_order_and_branch_defects_are_reported():
    poses = known_poses(np.linspace(10, 250, 5))
    swapped = poses[[0, 2, 1, 3, 4]]                      # the crank meets pose 3 before pose 2
    designs, _ = synthesis_motion.synthesize(swapped, count=20)
    known = [d for d in designs if np.hypot(*d.linkage.A) < TOL and abs(d.linkage.D[0] - 0.3) < TOL]
    assert known and all(d.defect for d in known)
    assert any("order" in d.defect or "branch" in d.defect for d in known)


def test_more_poses_by_least_squares_on_consistent_data():
    poses = known_poses(np.linspace(0, 300, 7))
    designs, _ = synthesis_motion.synthesize(poses)
    dist, ang = solver_pose_errors(designs[0], poses)
    assert dist.max() < 1e-7 * SIZE                      # consistent data: Gauss-Newton converges to it


# ----------------------------------------------------------------------------------------- function
def known_pairs(phi_deg, branch=1, **over):
    p = dict(l1=0.3, l2=1.1, l3=0.8, l4=1.0, branch=branch, **over)
    m = analytic.load("fourbar", **p)
    phi = np.radians(phi_deg)
    return phi, np.asarray(m.solve(phi, outputs=["phi3"])["phi3"]), p


@pytest.mark.parametrize("branch", [1, -1])
def test_three_pairs_give_the_known_linkage_and_the_solver_meets_them(branch):
    phi, psi, p = known_pairs([30, 75, 140], branch)
    f = synthesis_function.synthesize(phi, psi, ground=p["l4"])
    assert not f.defect
    link = f.linkage
    # Freudenstein's three equations determine the ratios uniquely: the known lengths come back
    for got, want in ((link.l1, p["l1"]), (link.l2, p["l2"]), (link.l3, p["l3"])):
        assert got == pytest.approx(want, abs=1e-9 * p["l2"])  # rounding of a 3x3 solve
    mech = synth_fourbar.mechanism(link)
    out = mech.solve(phi + f.input_offset, outputs=["phi3"])["phi3"] - f.output_offset
    assert np.abs(wrap(out - psi)).max() < 1e-9          # issue 19: three pairs to 1e-9 rad


def test_freudenstein_coefficients_by_hand():
    # a = 2, b = 3, c = 4, d = 5: K1 = d/a = 2.5, K2 = d/c = 1.25, K3 = (4 - 9 + 16 + 25)/(2*2*4) = 2.25
    a, b, c, d = 2.0, 3.0, 4.0, 5.0
    phi = np.radians([40.0, 90.0, 150.0])
    psi = synthesis_function.output_angles(a, b, c, d, phi, 1)
    K = synthesis_function.freudenstein(phi, psi)
    np.testing.assert_allclose(K, [2.5, 1.25, 2.25], atol=1e-12)      # rounding of a 3x3 solve


def test_negative_crank_length_is_an_offset_of_pi():
    phi, psi, p = known_pairs([30, 75, 140])
    # the same linkage with the user's input measured from the other end of the crank
    f = synthesis_function.synthesize(phi + np.pi, psi, ground=1.0)
    assert f.input_offset == pytest.approx(np.pi) and not f.defect
    mech = synth_fourbar.mechanism(f.linkage)
    out = mech.solve(phi + np.pi + f.input_offset, outputs=["phi3"])["phi3"] - f.output_offset
    assert np.abs(wrap(out - psi)).max() < 1e-9          # [rad] rounding


def test_more_pairs_least_squares_on_y_equals_log_x():
    # y = log10(x), 1 <= x <= 2 over 60 deg of crank and 90 deg of rocker (the classic textbook task)
    x = np.linspace(1, 2, 9)
    phi = np.radians(45 + 60 * (x - 1))
    psi = np.radians(135 + 90 * np.log10(x) / np.log10(2))
    f = synthesis_function.synthesize(phi, psi)
    mech = synth_fourbar.mechanism(f.linkage)
    out = mech.solve(phi + f.input_offset, outputs=["phi3"])["phi3"] - f.output_offset
    err = np.abs(wrap(out - psi))
    assert np.max(err) == pytest.approx(np.max(np.abs(f.errors)), abs=1e-9)   # solver agrees with fit
    lin = synthesis_function.synthesize(phi[[0, 4, 8]], psi[[0, 4, 8]])
    mech3 = synth_fourbar.mechanism(lin.linkage)
    err3 = np.abs(wrap(mech3.solve(phi + lin.input_offset, outputs=["phi3"])["phi3"] - lin.output_offset - psi))
    assert np.sqrt(np.mean(err ** 2)) <= np.sqrt(np.mean(err3 ** 2)) + 1e-12   # LS beats 3 points on rms


def test_mirror_pairs_make_a_singular_system_and_are_refused():
    # pairs (phi, psi) and (-phi, -psi) give the same row of Freudenstein's equations: no unique K
    with pytest.raises(ParameterError, match="singular"):
        synthesis_function.synthesize([0.3, -0.3, 1.0], [0.5, -0.5, 2.0])


# ----------------------------------------------------------------------------------------------- CLI
def write(path, header, rows):
    path.write_text(header + "\n" + "\n".join(",".join(repr(float(v)) for v in r) for r in rows) + "\n")
    return str(path)


def test_cli_motion_writes_a_file_that_reproduces_the_poses(tmp_path):
    poses = known_poses(np.linspace(10, 250, 5))
    rows = np.column_stack([poses[:, :2] * 1000, np.degrees(poses[:, 2])])
    csv = write(tmp_path / "p.csv", "x,y,theta", rows)
    out = tmp_path / "m.toml"
    r = run("synthesize", "motion", csv, "--unit", "mm", "--out", str(out), "--json")
    assert r.returncode == 0, r.stderr
    data = json.loads(r.stdout)
    best = data["designs"][0]
    assert best["file"] == str(out) and best["compare_passed"] is True
    assert set(best["error"]) == {"sum_sq", "max", "rms"} and best["error"]["max"] < 1e-9 * 300
    mech = analytic.load(str(out))
    sol = mech.solve(np.array(best["inputs"]))
    assert np.hypot(sol["xE"] * 1000 - rows[:, 0], sol["yE"] * 1000 - rows[:, 1]).max() < 1e-9 * 300  # [mm]


def test_cli_function_three_pairs(tmp_path):
    phi, psi, _ = known_pairs([30, 75, 140])
    csv = write(tmp_path / "f.csv", "input,output", np.degrees(np.column_stack([phi, psi])))
    r = run("synthesize", "function", csv, "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)["designs"][0]
    assert d["compare_passed"] is True and d["error"]["max"] < 1e-9


@pytest.mark.parametrize("text,needle", [
    ("x,y\n1,2\n3,4\n5,6\n", "missing column 'theta'"),
    ("x,y,theta\n0,0,0\n1,0,10\n", "needs at least 3"),
    ("x,y,theta\n0,0,0\n1,0,10\n1,nan,20\n", "line 4, column y"),
    ("x,y,theta\n0,0,0\n1,0,10\n0,0,0\n", "lines 2 and 4"),
    ("x,y,theta\n0,0,0\n1,0,abc\n2,1,20\n", "line 3, column theta"),
])
def test_cli_bad_poses_one_line_exit_2(tmp_path, text, needle):
    p = tmp_path / "bad.csv"
    p.write_text(text)
    r = run("synthesize", "motion", str(p))
    assert r.returncode == 2 and needle in r.stderr and "Traceback" not in r.stderr
    assert str(p) in r.stderr and len(r.stderr.strip().splitlines()) == 1


def test_cli_poses_no_four_bar_reaches(tmp_path):
    # five poses of a pure translation along a line: every moving point moves on a line, no circle
    rows = [(float(i), 0.0, 0.0) for i in range(5)]
    p = write(tmp_path / "line.csv", "x,y,theta", rows)
    r = run("synthesize", "motion", p)
    assert r.returncode == 2 and "0 real Burmester" in r.stderr and "Traceback" not in r.stderr


def test_cli_three_poses_with_chosen_circle_points_give_the_known_pivots(tmp_path):
    poses = known_poses([0, 70, 150])
    B1 = (KNOWN["l1"], 0.0)                               # crank at phi = 0
    m = analytic.load("fourbar", **KNOWN)
    C1 = (float(m.solve(np.array([0.0]))["xC"][0]), float(m.solve(np.array([0.0]))["yC"][0]))
    csv = write(tmp_path / "p3.csv", "x,y,theta", np.column_stack([poses[:, :2], np.degrees(poses[:, 2])]))
    r = run("synthesize", "motion", csv, "--circle-points", f"{B1[0]!r},{B1[1]!r},{C1[0]!r},{C1[1]!r}", "--json")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)["designs"][0]["parameters"]
    pivots = sorted([(d["ax"], d["ay"]), (d["dx"], d["dy"])])
    np.testing.assert_allclose(pivots, [(0.0, 0.0), (KNOWN["l4"], 0.0)], atol=TOL)


def test_cli_function_pairs_out_of_order_exit_1(tmp_path):
    phi, psi, _ = known_pairs([30, 140, 75])              # the crank turning one way meets 75 before 140
    csv = write(tmp_path / "f.csv", "input,output", np.degrees(np.column_stack([phi, psi])))
    r = run("synthesize", "function", csv)
    assert r.returncode == 1 and "order defect" in r.stdout and "Traceback" not in r.stderr
