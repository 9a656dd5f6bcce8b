"""Cams and drives at their edges, from outside (the classes benchmarks/fuzz_cams_drives.py found mishandled):
a given profile that is a plain polygon (a coarse circle, points repeated) is the cam as made (checked,
exported, drawn and simulated as given), not an undercut; an outline that crosses itself, given or made from
a law, is refused in one line naming the field; an actuator takes a table law; the simulation's own refusals
(a plate not star-shaped about its pivot or too small to mesh, a link without rotational inertia, a cycle too
long to step, a --speed too fast) name the file and where; a law that only dwells compares without a crash."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
LIBRARY = ROOT / "analytic" / "library"


def run(*args, cwd=None):
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}
    return subprocess.run([sys.executable, "-m", "sim", *map(str, args)], capture_output=True, text=True, env=env,
                          cwd=cwd or ROOT, timeout=300)


def given_profile(tmp_path, base: str, rows) -> Path:
    """The library cam ``base`` with its segments replaced by ``profile = "cam.csv"`` holding ``rows``."""
    text = (LIBRARY / f"{base}.toml").read_text()
    start = text.index("segments = [")
    end = text.index("]\n", text.index("\n]", start)) + 2
    path = tmp_path / f"{base}.toml"
    path.write_text(text[:start] + 'profile = "cam.csv"\n' + text[end:])
    (tmp_path / "cam.csv").write_text("x,y\n" + "".join(f"{x!r},{y!r}\n" for x, y in rows))
    return path


def circle(r, n):
    return [(r * math.cos(2 * math.pi * k / n), r * math.sin(2 * math.pi * k / n)) for k in range(n)]


def refusal(r) -> str:
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2 and len(lines) == 1 and "Traceback" not in r.stderr, (r.returncode, r.stderr[-800:])
    return lines[0]


@pytest.mark.parametrize("base,radius,n", [("cam_flat", 35.0, 720), ("cam_roller", 0.030, 180),
                                           ("cam_rocker", 0.025, 360)])
def test_a_polygon_circle_about_the_pivot_holds_the_follower_still(tmp_path, base, radius, n):
    """By hand: an outline that is a circle of radius R about the cam's pivot keeps the follower where it is,
    whatever the cam's angle (a dwell all round). As an n-gon its radius varies between R cos(pi/n) and R, so
    the follower moves by at most R (1 - cos(pi/n)) (the flat face on the polygon's support, the roller's
    centre on the polygon's offset). Before the fix, check refused these outlines as undercuts or cusps (the
    curvature of the spline through a polygon's lift)."""
    path = given_profile(tmp_path, base, circle(radius, n))
    r = run("check", path)
    assert r.returncode == 0, r.stderr[-600:]
    a = run("analyze", path, "--json")
    assert a.returncode == 0, a.stderr[-600:]
    column = {"cam_flat": "stappet", "cam_roller": "sfollower", "cam_rocker": "phiarm"}[base]
    lo, hi = json.loads(a.stdout)["ranges"][column]          # SI
    travel = hi - lo
    k = 1e-3 if base == "cam_flat" else 1.0                 # cam_flat's file is in mm
    sag = radius * k * (1 - math.cos(math.pi / n))
    if column == "phiarm":                                  # the roller's centre rides the arm's circle
        sag = sag / (0.055 * 0.5)                           # (55 mm): move / 55 mm, times 2 for slack
    # the polygon's sag bounds the true motion; the 1440-point spline through it may overshoot by a few sags
    assert travel <= 4 * sag, (column, travel, sag)


def test_repeated_points_are_the_same_outline(tmp_path):
    """Each point of a 720-gon written twice: the same cam as the 720-gon (the follower's motion identical);
    before the fix, the zero-length edges made check refuse it as a cusp."""
    rows = [(x + 4.0, y) for x, y in circle(35.0, 720)]    # its centre 4 mm off the pivot: a real lift
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    once = given_profile(tmp_path / "a", "cam_flat", rows)
    twice = given_profile(tmp_path / "b", "cam_flat", [p for p in rows for _ in range(2)])
    a, b = run("analyze", once, "--json"), run("analyze", twice, "--json")
    assert a.returncode == 0 and b.returncode == 0, (a.stderr[-400:], b.stderr[-400:])
    ra, rb = json.loads(a.stdout)["ranges"], json.loads(b.stdout)["ranges"]
    lo, hi = ra["stappet"]
    # by hand: a flat face on a circle whose centre is eps = 4 mm off the pivot moves harmonically, stroke
    # 2 eps; the 720-gon's support falls short of the circle's by at most R (1 - cos(pi / 720)) ~ 3e-4 mm
    # (both ends can fall short: twice that; and 1e-9 m for the spline through 1440 samples of the lift)
    assert abs((hi - lo) - 8e-3) <= 2 * 35e-3 * (1 - math.cos(math.pi / 720)) + 1e-9
    # the same polygon read twice: the same arithmetic once the repeats are dropped, so equal to rounding
    for name in ra:
        assert all(abs(x - y) <= 1e-12 * max(1.0, abs(x)) for x, y in zip(ra[name], rb[name])), name


@pytest.mark.parametrize("base", ["cam_roller", "cam_flat", "cam_rocker"])
def test_a_self_crossing_outline_is_refused_naming_the_field(tmp_path, base):
    """A figure-of-eight outline (it crosses itself at the pivot): one line naming the file, the field and
    what is wrong (before: refused as an undercut or cusp 'at cam angle ...', or by the arm missing it)."""
    r = 0.03 if base != "cam_flat" else 30.0
    rows = [(r * math.sin(2 * math.pi * k / 40), r * math.sin(4 * math.pi * k / 40) / 2) for k in range(40)]
    line = refusal(run("check", given_profile(tmp_path, base, rows)))
    assert str(tmp_path / f"{base}.toml") in line and "field 'profile'" in line and "crosses itself" in line, line


def with_segments(tmp_path, base: str, segments: str) -> Path:
    text = (LIBRARY / f"{base}.toml").read_text()
    start = text.index("segments = [")
    end = text.index("]\n", text.index("\n]", start)) + 2
    path = tmp_path / f"{base}.toml"
    path.write_text(text[:start] + f"segments = {segments}\n" + text[end:])
    return path


def test_a_designed_profile_that_crosses_itself_is_refused_before_export_draws_it(tmp_path):
    """cam_rocker's arm swung 170deg within 10deg of the cam: no undercut in the small (the curvature test
    passes) but the outline made from the law overlaps itself. check refuses it in one line naming the file,
    the cam and the cam angle, and export writes nothing (before: check accepted it, and export died on a
    GEOS TopologyException traceback after writing the DXF)."""
    path = with_segments(tmp_path, "cam_rocker", '[{ shape = "dwell", duration = "90deg" }, { shape = "cycloidal", '
                         'duration = "10deg", rise = "170deg" }, { shape = "dwell", duration = "130deg" }, '
                         '{ shape = "poly345", duration = "130deg", rise = "-170deg" }]')
    line = refusal(run("check", path))
    assert str(path) in line and "groups[1]" in line and "crosses itself" in line and "cam angle" in line, line
    out = tmp_path / "out"
    out.mkdir()
    line = refusal(run("export", path, "--dxf", out / "a.dxf", "--stl", out / "stl"))
    assert "crosses itself" in line and list(out.iterdir()) == [], (line, list(out.iterdir()))


def test_a_plate_not_star_shaped_is_refused_by_the_simulation_naming_file_and_field(tmp_path):
    """cam_roller's follower lifted 1.5 m within 10deg of the cam: the outline does not cross itself and
    check accepts it, but it turns back about the pivot, so MuJoCo's convex pieces of the plate cannot be made:
    compare refuses it in one line that names the file, the cam and its segments (before: 'profile: point
    536 of 720 at [...] turns back about the pivot', no file, no field)."""
    path = with_segments(tmp_path, "cam_roller", '[{ shape = "dwell", duration = "90deg" }, { shape = "cycloidal", '
                         'duration = "10deg", rise = 1.5 }, { shape = "dwell", duration = "130deg" }, '
                         '{ shape = "poly345", duration = "130deg", rise = -1.5 }]')
    assert run("check", path).returncode == 0
    line = refusal(run("compare", path))
    assert str(path) in line and "groups[1]" in line and "field 'segments'" in line and "pivot" in line, line


def test_a_link_without_rotational_inertia_is_refused_by_the_simulation_naming_the_file(tmp_path):
    """excavator with its boom's I = 0: the analytic commands take it (a point mass), the simulation cannot
    (MuJoCo's minimum); compare refuses it in one line that names the file (before: no file)."""
    text = (LIBRARY / "excavator.toml").read_text().replace("I = 3500.0", "I = 0.0")
    path = tmp_path / "excavator.toml"
    path.write_text(text)
    line = refusal(run("compare", path))
    assert str(path) in line and "boom" in line and "inertia" in line, line


def test_a_drive_law_that_only_dwells_compares_without_a_crash(tmp_path):
    """servo_press with its crank's law one dwell (the press stands still): every output's tolerance is 0
    and so is its error; compare passes instead of dividing by the zero tolerance (before: a traceback,
    ZeroDivisionError in the printed table)."""
    text = (LIBRARY / "servo_press.toml").read_text()
    start = text.index("segments = [")
    end = text.index("]\n", text.index("\n]", start)) + 2
    path = tmp_path / "servo_press.toml"
    path.write_text(text[:start] + 'segments = [{ shape = "dwell", duration = 1.0 }]\n' + text[end:])
    r = run("compare", path)
    assert r.returncode == 0 and "Traceback" not in r.stderr, r.stderr[-600:]
    assert "PASSED" in r.stdout


def test_a_speed_too_fast_to_simulate_is_refused_naming_the_option():
    """simulate --speed 1e6 on cam_roller: the option alone makes the design too fast to step, so the one-line
    refusal names --speed and asks for a lower one (before: 'lower omega1 (now 1e+06 rad/s)', a parameter the
    user never set); the same command at 30 rad/s runs (the file itself is fine)."""
    line = refusal(run("simulate", LIBRARY / "cam_roller.toml", "--speed", "1e6"))
    assert "cam_roller.toml" in line and "--speed" in line and "omega1" not in line, line
    assert run("simulate", LIBRARY / "cam_roller.toml", "--speed", "30").returncode == 0


def actuator_table(tmp_path, rows) -> Path:
    """scissor_lift with its cylinder driven by a table (t, q: pin-to-pin length [m]) instead of l0 and v."""
    text = (LIBRARY / "scissor_lift.toml").read_text()
    text = text.replace('l0 = "l0"\n', "").replace('v = "v"\n', 'table = "law.csv"\n')
    path = tmp_path / "scissor_lift.toml"
    path.write_text(text)
    (tmp_path / "law.csv").write_text("t,q\n" + "".join(f"{t!r},{q!r}\n" for t, q in rows))
    return path


def test_an_actuator_runs_a_table_law_its_first_row_the_start(tmp_path):
    """SPEC "Motion laws": any input may take a table, its first q the start. Before the fix an actuator could
    not: with l0 it was refused ('drop l0'), without it too ('field l0 is missing'). The periodic spline
    through (0, 1.0), (0.5, 1.1), (1, 1.0) is symmetric about t = 0.5: by hand its extremes are the rows'
    1.0 and 1.1 m."""
    path = actuator_table(tmp_path, [(0.0, 1.0), (0.5, 1.1), (1.0, 1.0)])
    r = run("analyze", path, "--csv", tmp_path / "out.csv")
    assert r.returncode == 0, r.stderr[-600:]
    rows = (tmp_path / "out.csv").read_text().splitlines()
    k = rows[0].split(",").index("s_lift")
    s = [float(row.split(",")[k]) for row in rows[1:]]
    # the run's samples hit t = 0 and t = 0.5 (361 over the 1 s cycle); the rest is the spline's rounding
    assert abs(min(s) - 1.0) <= 1e-9 and abs(max(s) - 1.1) <= 1e-9 and abs(s[0] - 1.0) <= 1e-12, (min(s), max(s))


def test_an_actuator_table_outside_its_stroke_is_refused_naming_the_stroke(tmp_path):
    """The same table reaching 2 m, past the stroke [0.75, 1.25] m: analyze refuses it in one line naming the
    file and the stroke (check prints the range the cylinder assembles in, as for a speed that leaves it)."""
    line = refusal(run("analyze", actuator_table(tmp_path, [(0.0, 1.0), (0.5, 2.0), (1.0, 1.0)])))
    assert "scissor_lift.toml" in line and "stroke" in line, line


def test_a_law_whose_cycle_is_too_long_to_step_is_refused_naming_the_file(tmp_path):
    """servo_press's crank on a table whose cycle lasts 2e12 s: compare cannot step it (4e13 steps), and says so
    in one line naming the file and the cycle as the thing to shorten (before: no file, 'reduce the
    revolutions' only, though one revolution is the least a run has)."""
    text = (LIBRARY / "servo_press.toml").read_text()
    start = text.index("segments = [")
    end = text.index("]\n", text.index("\n]", start)) + 2
    path = tmp_path / "servo_press.toml"
    path.write_text((text[:start] + 'table = "law.csv"\n' + text[end:]).replace('phi0 = "90deg"', ""))
    (tmp_path / "law.csv").write_text("t,q_deg\n0,90\n1e12,270\n2e12,450\n")
    assert run("check", path).returncode == 0
    line = refusal(run("compare", path))
    assert str(path) in line and "cycle" in line, line


def test_a_given_profile_is_the_plate_exported(tmp_path):
    """cam_rocker given a 72-gon circle of 25 mm about its pivot: export draws that outline as the plate (each
    DXF vertex at 25 mm from the pivot A, which the pose puts at the origin, or inside it by at most the
    polygon's sag), not an envelope made again from the spline of its lift (before: that envelope overlapped
    itself and GEOS died on it, a traceback)."""
    import ezdxf
    R = 0.025
    path = given_profile(tmp_path, "cam_rocker", circle(R, 72))
    r = run("export", path, "--dxf", tmp_path / "c.dxf", "--stl", tmp_path / "stl")
    assert r.returncode == 0 and "Traceback" not in r.stderr, r.stderr[-600:]
    doc = ezdxf.readfile(tmp_path / "c.dxf")
    plate = [e for e in doc.modelspace() if e.dxftype() == "LWPOLYLINE" and e.dxf.layer == "1"]
    assert len(plate) == 1
    radius = np.hypot(*np.array([(x, y) for x, y, *_ in plate[0].get_points()]).T)
    tol = 1e-4 * 0.1                                    # SPEC: within 1e-4 of the size (cam_rocker ~0.1 m)
    assert radius.max() <= R + tol and radius.min() >= R * math.cos(math.pi / 72) - tol, (radius.min(), radius.max())
    assert (tmp_path / "stl" / "1.stl").is_file()


def test_a_given_profile_is_the_plate_simulated(tmp_path):
    """cam_flat given a 72-gon circle of 35 mm about its pivot (a dwell all round): compare simulates that
    outline and passes (before: the simulation collided the envelope made from the spline of its lift, which
    turns back about the pivot, and refused 'give a counter-clockwise outline around the pivot' for an outline
    that is one)."""
    r = run("compare", given_profile(tmp_path, "cam_flat", circle(35.0, 72)))
    assert r.returncode == 0 and "PASSED" in r.stdout, (r.stdout[-400:], r.stderr[-400:])


def test_a_plate_too_small_to_mesh_is_refused_naming_the_field(tmp_path):
    """cam_flat given its circle in the wrong units (35e-9 mm): the analytic commands take it (the follower
    barely moves), the simulation cannot mesh a plate of 3.5e-11 m: compare refuses it in one line naming the
    file, the cam and its profile (before: 'MuJoCo cannot compile the cam_flat: mesh surface area is too
    small: cam0_piece0', no file, no field)."""
    path = given_profile(tmp_path, "cam_flat", circle(35e-9, 72))
    assert run("check", path).returncode == 0
    line = refusal(run("compare", path))
    assert str(path) in line and "groups[1]" in line and "field 'profile'" in line and "units" in line, line


def test_a_given_profile_is_the_outline_analyze_reports(tmp_path):
    """cam_rocker given a 72-gon circle of 25 mm about its pivot: ``analyze --json``'s outline (SPEC: "profile":
    [[x, y], ...]) is that polygon, each point 25 mm from the pivot as the file gives it, not the envelope made
    again from the spline of its lift (which ripples and overlaps itself on a coarse polygon)."""
    R = 0.025
    pts = circle(R, 72)
    r = run("analyze", given_profile(tmp_path, "cam_rocker", pts), "--json")
    assert r.returncode == 0, r.stderr[-600:]
    outline = np.asarray(json.loads(r.stdout)["cams"]["rocker"]["profile"])
    # the file's points, read as written (metres both: rounding only)
    assert outline.shape == (72, 2) and np.max(np.abs(outline - np.asarray(pts))) <= 1e-12, outline[:3]
