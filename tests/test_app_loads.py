"""The app's loads (issue 31, item 3) over HTTP against an in-process server: the Forces tab computes with
the file's ``[[loads]]`` (checked against hand statics by virtual work, with the rocker's angle worked out
here from the four-bar's circles, and against ``linkage forces --json``), the panel's endpoint writes
``[[loads]]`` text that ``linkage check`` accepts, bad load input is one line, and the canvas's load
geometry (``/api/loads/draw``) is where the file says."""

import json
import math
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest
from app_client import post  # tests/app_client.py
from fourbar_text import fourbar_text  # the hand four-bar as text (tests/fourbar_text.py)


HERE = Path(__file__).parent
FOURBAR = fourbar_text("slow_fourbar", 0.001)
"""A four-bar turning at 1e-3 rad/s: the inertia forces (~m r w^2 ~ 1e-7 N) leave statics."""



def ok(srv, path, body):
    status, data = post(srv, path, body)
    assert status == 200, data
    return data


def rocker_angle(phi1, near):
    """phi3 = angle of D->C, C the intersection of |C - B| = 0.3 and |C - D| = 0.25 nearer ``near``."""
    B = np.array([0.1 * math.cos(phi1), 0.1 * math.sin(phi1)])
    D = np.array([0.3, 0.0])
    d = np.linalg.norm(D - B)
    a = (0.3 ** 2 - 0.25 ** 2 + d * d) / (2 * d)
    h = math.sqrt(0.3 ** 2 - a * a)
    e = (D - B) / d
    m = B + a * e
    cands = [m + h * np.array([-e[1], e[0]]), m - h * np.array([-e[1], e[0]])]
    C = min(cands, key=lambda c: np.linalg.norm(c - near))
    return math.atan2(C[1] - D[1], C[0] - D[0]), C


def test_torque_added_in_the_panel_is_balanced_by_the_crank_as_virtual_work_says(server):
    T3 = -2.5                                    # N m on the rocker, clockwise: a brake
    new = ok(server, "/api/loads/edit", {"text": FOURBAR, "action": "add",
                                         "load": {"name": "brake", "kind": "torque", "link": "3", "magnitude": T3}})
    assert [ld["name"] for ld in tomllib.loads(new["text"])["loads"]] == ["brake"]
    body = {"samples": 25, "revolutions": 1}
    loaded = ok(server, "/api/forces", {"text": new["text"], **body})
    plain = ok(server, "/api/forces", {"text": FOURBAR, **body})
    sol = ok(server, "/api/solve", {"text": FOURBAR, **body, "figures": False})
    phi1 = np.array(loaded["inputs"]["phi1"])
    drive = np.array(loaded["drives"]["phi1"])
    h = 1e-6
    ratio = []
    for k, p in enumerate(phi1):
        near = np.array([sol["points"]["C"]["x"][k], sol["points"]["C"]["y"][k]])
        a, C = rocker_angle(p, near)
        assert np.linalg.norm(C - near) < 1e-9          # the same pose as the app's: the geometry agrees
        up, _ = rocker_angle(p + h, C)
        dn, _ = rocker_angle(p - h, C)
        ratio.append(math.remainder(up - dn, 2 * math.pi) / (2 * h))
    # virtual work: T1 w1 + T3 w3 = 0. Central differences err ~h^2 (1e-12); inertia at 1e-3 rad/s ~1e-7 N m
    assert np.allclose(drive, -T3 * np.array(ratio), rtol=0, atol=1e-6)
    assert np.max(np.abs(plain["drives"]["phi1"])) < 1e-6          # without the load: inertia only
    assert [x["name"] for x in loaded["applied"]] == ["brake"]
    # the torque's work per cycle: -T3 x the rocker's net turn (0 for a rocker) = the drive's, with the sign
    assert abs(loaded["applied"][0]["work_per_cycle"]) < 1e-9   # a rocker returns: no net work (rounding)


def test_forces_tab_equals_linkage_forces_json_for_a_file_with_loads(server, tmp_path):
    path = HERE / "mechanisms" / "fourbar_loads.toml"
    text = path.read_text()
    got = ok(server, "/api/forces", {"text": text, "samples": 37})
    cli = subprocess.run([sys.executable, "-m", "sim", "forces", str(path), "--json", "--samples", "37"],
                         capture_output=True, text=True, timeout=120)
    assert cli.returncode == 0, cli.stderr
    ref = json.loads(cli.stdout)
    scale = max(np.max(np.abs(ref["drives"]["phi1"])), 1.0)
    # the same computation on both sides: only JSON rounding of the same doubles (1e-12 of the scale)
    assert np.allclose(got["drives"]["phi1"], ref["drives"]["phi1"], rtol=0, atol=1e-9 * scale)
    for j, r in zip(got["joints"], ref["joints"]):
        assert j["name"] == r["name"]
        assert np.allclose(j["F"], np.hypot(r["Fx"], r["Fy"]), rtol=0, atol=1e-9 * scale)
    assert [x["name"] for x in got["applied"]] == [x["name"] for x in ref["loads"]] == ["s", "d", "brake"]
    for a, b in zip(got["applied"], ref["loads"]):
        assert math.isclose(a["work_per_cycle"], b["work_per_cycle"], abs_tol=1e-12)
    # the loads are really applied: the same file without them needs another drive (by ~2 N m)
    bare = ok(server, "/api/forces", {"text": text.split("[[loads]]")[0], "samples": 37})
    assert np.max(np.abs(np.subtract(bare["drives"]["phi1"], got["drives"]["phi1"]))) > 0.1


def test_panel_writes_loads_that_linkage_check_accepts(server, tmp_path):
    text = FOURBAR
    adds = [
        {"name": "F1", "kind": "force", "link": "2", "point": "C", "direction": [0, -1], "magnitude": 10},
        {"name": "F2", "kind": "force", "link": "2", "at": [0.15, 0.05], "direction": [1, 0], "frame": "link",
         "table": [[0, 1], [180, 3]]},
        {"name": "k", "kind": "spring", "between": [["ground", "D"], ["1", "B"]], "stiffness": 200,
         "free_length": 0.3},
        {"name": "hinge", "kind": "torsion_spring", "joint": "C", "links": ["2", "3"], "stiffness": 0.5,
         "free_angle": "90deg"},
        {"name": "c", "kind": "damper", "joint": "B", "links": ["1", "2"], "damping": 0.1},
    ]
    for ld in adds:
        text = ok(server, "/api/loads/edit", {"text": text, "action": "add", "load": ld})["text"]
    assert text.startswith(FOURBAR.rstrip())       # the file's own text is kept as it was
    written = tomllib.loads(text)["loads"]
    assert [ld["name"] for ld in written] == [ld["name"] for ld in adds]
    assert written[0]["direction"] == [0, -1] and written[1]["table"] == [[0, 1], [180, 3]]
    text = ok(server, "/api/loads/edit", {"text": text, "action": "replace", "name": "F1",
                                          "load": {**adds[0], "magnitude": 25}})["text"]
    text = ok(server, "/api/loads/edit", {"text": text, "action": "remove", "name": "c"})["text"]
    written = tomllib.loads(text)["loads"]
    assert [ld["name"] for ld in written] == ["F1", "F2", "k", "hinge"] and written[0]["magnitude"] == 25
    p = tmp_path / "m.toml"
    p.write_text(text)
    chk = subprocess.run([sys.executable, "-m", "sim", "check", str(p)], capture_output=True, text=True, timeout=120)
    assert chk.returncode == 0, chk.stdout + chk.stderr
    f = subprocess.run([sys.executable, "-m", "sim", "forces", str(p), "--json", "--samples", "9"],
                       capture_output=True, text=True, timeout=120)
    assert [x["name"] for x in json.loads(f.stdout)["loads"]] == ["F1", "F2", "k", "hinge"]
    # a library mechanism by name: written out with its values, then the load added
    lib = ok(server, "/api/loads/edit", {"mechanism": "fourbar", "action": "add",
                                         "load": {"name": "T", "kind": "torque", "link": "3", "magnitude": 1}})
    assert tomllib.loads(lib["text"])["loads"][0]["name"] == "T"


@pytest.mark.parametrize("body, needle", [
    ({"action": "add", "load": {"name": "F", "kind": "force", "link": "9", "point": "C", "direction": [0, 1],
                                "magnitude": 1}}, "(F).link"),
    ({"action": "add", "load": {"name": "F", "kind": "force", "link": "2", "point": "C", "magnitude": 1}},
     "(F).direction"),
    ({"action": "add", "load": {"name": "F", "kind": "force", "link": "2", "point": "C", "direction": [0, 0],
                                "magnitude": 1}}, "(F).direction"),
    ({"action": "add", "load": {"name": "F", "kind": "force", "link": "2", "point": "Z", "direction": [0, 1],
                                "magnitude": 1}}, "(F).point"),
    ({"action": "add", "load": {"name": "F", "kind": "forcee"}}, "load.kind"),
    ({"action": "add", "load": {"name": "1F", "kind": "force"}}, "load.name"),
    ({"action": "add", "load": {"name": "F", "kind": "torque", "link": "3", "magnitude": 1, "point": "C"}},
     "load.point"),
    ({"action": "add", "load": {"name": "F", "kind": "torque", "link": "3", "magnitude": "phi1 +"}},
     "(F).magnitude"),
    ({"action": "add", "load": {"name": "k", "kind": "spring", "between": [["ground", "D"]], "stiffness": 1,
                                "free_length": 1}}, "(k).between"),
    ({"action": "remove", "name": "nope"}, "name \"nope\""),
    ({"action": "delete", "name": "x"}, "action"),
    ({"action": "add", "load": "F=1"}, "load must be an object"),
    ({"action": "add", "load": {"name": "F", "kind": "torque", "link": "3", "magnitude": 1}, "extra": 1},
     "unknown field 'extra'"),
])
def test_bad_load_input_is_one_line_naming_the_field(server, body, needle):
    status, data = post(server, "/api/loads/edit", {"text": FOURBAR, **body})
    assert status == 400, data
    msg = data["error"]
    assert needle in msg and "\n" not in msg and "Traceback" not in msg, msg


def test_a_duplicate_name_is_refused(server):
    one = ok(server, "/api/loads/edit", {"text": FOURBAR, "action": "add",
                                         "load": {"name": "T", "kind": "torque", "link": "3", "magnitude": 1}})
    status, data = post(server, "/api/loads/edit", {"text": one["text"], "action": "add",
                                                     "load": {"name": "T", "kind": "torque", "link": "2",
                                                              "magnitude": 1}})
    assert status == 400 and "'T' is used by another load" in data["error"]


def test_canvas_geometry_puts_each_load_where_the_file_says(server):
    text = (HERE / "mechanisms" / "fourbar_loads.toml").read_text()
    text = ok(server, "/api/loads/edit", {"text": text, "action": "add", "load": {
        "name": "F1", "kind": "force", "link": "2", "point": "C", "direction": [3, -4], "magnitude": 10}})["text"]
    body = {"text": text, "samples": 19}
    d = ok(server, "/api/loads/draw", body)
    sol = ok(server, "/api/solve", {**body, "figures": False})
    by = {ld["name"]: ld for ld in d["loads"]}
    assert [x["name"] for x in d["items"]] == ["s", "d", "brake", "F1"]
    C, D = sol["points"]["C"], sol["points"]["D"]
    f = by["F1"]
    assert f["shape"] == "arrow" and f["unit"] == "N"
    # at C, 10 N along (3, -4)/5 (positions: the same solve; 1e-12 m of rounding)
    assert np.allclose(f["x"], C["x"], atol=1e-12) and np.allclose(f["y"], C["y"], atol=1e-12)
    assert np.allclose(f["fx"], 6.0, atol=1e-12) and np.allclose(f["fy"], -8.0, atol=1e-12)
    s = by["s"]
    assert s["shape"] == "between" and np.allclose(s["x1"], 0.1) and np.allclose(s["y1"], 0.25)
    # the end on link 3 at [0.2, 0] of its frame: 0.2 m from the frame's origin, on the line C-D at 0.2/0.25
    ex, ey = np.array(s["x2"]), np.array(s["y2"])
    L = np.hypot(ex - 0.1, ey - 0.25)
    # the spring's tension by hand: k (L - L0) = 400 (L - 0.12) N (rounding only)
    assert np.allclose(s["value"], 400 * (L - 0.12), rtol=1e-9, atol=1e-9)
    on_line = [abs((x - cx) * (dy - cy) - (y - cy) * (dx - cx)) for x, y, cx, cy, dx, dy
               in zip(ex, ey, C["x"], C["y"], D["x"], D["y"])]
    assert max(on_line) < 1e-12                 # on the rocker's line (cross product, m^2, rounding)
    assert np.allclose(np.hypot(ex - np.array(C["x"]), ey - np.array(C["y"])), 0.2, atol=1e-12) or \
        np.allclose(np.hypot(ex - np.array(D["x"]), ey - np.array(D["y"])), 0.2, atol=1e-12)
    b = by["brake"]
    phi1 = np.array(sol["inputs"]["phi1"])
    assert b["shape"] == "moment" and b["unit"] == "N m"
    assert np.allclose(b["value"], -0.5 * np.cos(phi1), atol=1e-12)      # the file's law, by hand
    assert np.allclose(b["x"], (np.array(C["x"]) + np.array(D["x"])) / 2, atol=1e-12)   # drawn mid-rocker
    assert d["friction"] == []


def test_canvas_geometry_in_the_files_force_units_and_friction(server):
    text = FOURBAR.replace('output = "C"', 'output = "C"\nforce_units = "kN"') + (
        "[friction]\nmu = 0.1\npin_radius = 0.005\n"
        "[[loads]]\nname = \"P\"\nkind = \"force\"\nlink = \"3\"\npoint = \"C\"\ndirection = [0, 1]\nmagnitude = 2\n")
    d = ok(server, "/api/loads/draw", {"text": text, "samples": 5})
    assert d["force_units"] == "kN" and d["loads"][0]["unit"] == "kN"
    assert np.allclose(d["loads"][0]["fy"], 2.0, atol=1e-12)        # written 2 kN, drawn as 2 (kN), not 2000
    assert sorted(f["point"] for f in d["friction"]) == ["A", "B", "C", "D"]
    assert all(math.isclose(f["mu"], 0.1) for f in d["friction"])


def brake_work_by_hand(n=7200):
    """Work per turn of T = -0.5 cos(phi1) on fourbar_loads' rocker (its geometry is FOURBAR's): the integral
    of T dphi3 over a crank turn, phi3(phi1) from the circles above (trapezoid on n steps)."""
    phi = np.linspace(0.0, 2 * math.pi, n + 1)
    _, C = rocker_angle(0.0, np.array([0.28, 0.25]))     # branch 1: C above the frame line
    a = []
    for p in phi:
        ang, C = rocker_angle(p, C)
        a.append(ang)
    a = np.unwrap(a)
    T = -0.5 * np.cos(phi)
    return float(np.sum(0.5 * (T[1:] + T[:-1]) * np.diff(a)))


def test_dynamics_tab_runs_with_the_files_loads(server):
    text = (HERE / "mechanisms" / "fourbar_loads.toml").read_text()
    body = {"motor": {"T0": 5, "W0": 20}, "simulate": False, "revolutions": 5}
    d = ok(server, "/api/dynamics", {"text": text, **body})
    bare = ok(server, "/api/dynamics", {"text": text.split("[[loads]]")[0], **body})
    works = {x["name"]: x["work_per_cycle"] for x in d["loads"]}
    assert list(works) == ["s", "d", "brake"]
    # the brake's work by hand (the trapezoid's error over 7200 steps ~1e-7 J; the app's grid is spectral)
    assert math.isclose(works["brake"], brake_work_by_hand(), abs_tol=1e-5)
    assert abs(works["s"]) < 1e-9                     # a spring returns its energy over a turn (rounding)
    assert works["d"] < 0                             # a damper only takes energy out
    # motor + loads = change of kinetic energy + residual: the residual is rounding next to the works (~0.5 J)
    assert abs(d["energy"]["residual"]) < 1e-6
    assert abs(d["energy_per_cycle"] - bare["energy_per_cycle"]) > 0.01    # the loads change the motor's work


def test_a_json_file_keeps_its_format(server):
    data = tomllib.loads((HERE / "mechanisms" / "fourbar_loads.toml").read_text())
    text = json.dumps(data, indent=2)
    new = ok(server, "/api/loads/edit", {"text": text, "action": "add", "load": {
        "name": "cut", "kind": "force", "link": "2", "point": "C", "direction": [-1, 0], "magnitude": 5,
        "active": "90deg:270deg", "stroke": "+x"}})
    back = json.loads(new["text"])
    assert [ld["name"] for ld in back["loads"]] == ["s", "d", "brake", "cut"]
    assert back["loads"][-1]["active"] == "90deg:270deg" and back["groups"] == data["groups"]
    removed = json.loads(ok(server, "/api/loads/edit", {"text": new["text"], "action": "remove", "name": "d"})["text"])
    assert [ld["name"] for ld in removed["loads"]] == ["s", "brake", "cut"]


@pytest.mark.parametrize("body, needle", [
    ({"text": FOURBAR, "bogus": 1}, "unknown field 'bogus'"),
    ({"text": FOURBAR + "[[loads]]\nname = \"T\"\nkind = \"torque\"\nlink = \"7\"\nmagnitude = 1\n"}, "loads[1] (T).link"),
    ({"text": FOURBAR, "samples": 1}, "samples"),
])
def test_bad_draw_requests_are_one_line(server, body, needle):
    status, data = post(server, "/api/loads/draw", body)
    assert status == 400 and needle in data["error"] and "\n" not in data["error"], data


def test_a_moment_is_drawn_in_force_units_times_the_files_length_unit():
    # issue 41: a -2 kN mm torque was drawn as "-2e-6 kN mm" (N m -> kN mm multiplied by the metre per mm
    # instead of divided); written -2 kN mm, drawn -2 kN mm
    from sim.front import loads_panel
    text = (HERE / "loads" / "spring__mm_kn.toml").read_text() + (
        "\n[[loads]]\nname = \"brake\"\nkind = \"torque\"\nlink = \"3\"\nmagnitude = -2\n")
    d = loads_panel.draw({"text": text, "samples": 5})
    b = next(ld for ld in d["loads"] if ld["name"] == "brake")
    assert b["shape"] == "moment" and b["unit"] == "kN mm"
    assert np.allclose(b["value"], -2.0, rtol=1e-12)                 # as written (rounding of the unit factors)


def test_the_forces_tab_reads_in_the_files_force_units():
    # issue 41: the Forces tab showed N and N m for a kN file; now kN and kN mm, as `linkage forces` prints.
    # By hand from the SI answer: 1 kN = 1000 N; 1 kN mm = 1000 N x 0.001 m = 1 N m
    from sim import service
    from sim.front import app
    path = HERE / "loads" / "spring__mm_kn.toml"
    out = app.forces({"text": path.read_text(), "samples": 13})
    assert out["units"]["force"] == "kN" and out["units"]["moment"] == "kN mm"
    assert out["units"]["drives"] == {"phi1": "kN mm"}
    rec = service.forces_record(service.forces_run(service.load(str(path), {}), 13))      # SI
    for j, si in zip(out["joints"], rec["joints"]):
        assert np.allclose(j["F"], np.hypot(si["Fx"], si["Fy"]) / 1000.0, rtol=1e-12, atol=0)   # rounding
    assert np.allclose(out["drives"]["phi1"], rec["drives"]["phi1"], rtol=1e-12, atol=0)
    assert np.allclose(out["shaking"]["M"], rec["shaking"]["M"], rtol=1e-12, atol=1e-15)
    peak = max(float(np.max(np.hypot(si["Fx"], si["Fy"]))) for si in rec["joints"])
    assert max(e["F"] for e in out["peaks"]["joints"].values()) == pytest.approx(peak / 1000.0, rel=1e-12)
