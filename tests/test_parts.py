"""Parts (issue 28): exact outlines, mass properties against hand formulas, layers, the interference check
against a hand-built oracle, and the files read back by independent readers (one mechanism; the whole
library is in test_parts_library.py)."""

import io
import itertools
import json
import math
from contextlib import redirect_stdout

import numpy as np
import pytest
from scipy.spatial import ConvexHull

from analytic.parts import layers, model, shapes
from sim import service
from sim.service import parts as parts_service

PLANTED = """
format = "linkage/1"
name = "planted"
units = "mm"

[parameters]
ext = 300.0

[ground]
A = [0, 0]
D = [300, 0]

[[inputs]]
kind = "crank"
pivot = "A"
point = "B"
length = 100
link = "1"
phi0 = "30deg"
omega = "360deg"

[[groups]]
kind = "RRR"
point = "C"
from = ["B", "D"]
lengths = [300, 250]
links = ["2", "3"]
branch = 1

[[groups]]
kind = "point"       # the crank extended past B to F: it sweeps into the rocker
point = "F"
on = ["A", "B"]
at = ["ext", 0]

[parts]
layers = { "1" = 0, "2" = 1, "3" = 0 }   # the layers of the four-bar without the extension
"""


# ------------------------------------------------------------------------------------------ shapes
def test_hull_of_discs_matches_a_sampled_convex_hull():
    from shapely.geometry import Polygon
    rng = np.random.default_rng(7)
    t = np.linspace(0, 2 * np.pi, 4000, endpoint=False)
    for _ in range(80):
        ds = [shapes.Disc(*rng.uniform(-1, 1, 2), rng.choice([0.0, rng.uniform(0.01, 0.5)]))
              for _ in range(rng.integers(1, 7))]
        if all(d.r == 0 for d in ds) and len(ds) < 3:
            continue
        pts = np.vstack([np.array([d.x, d.y]) + d.r * np.c_[np.cos(t), np.sin(t)] for d in ds])
        ref = ConvexHull(pts)
        A, Sx, Sy, _ = shapes.moments(shapes.hull(ds))
        # the sampled hull (4000 points per circle) lies inside the exact one by < r (1 - cos(pi/4000)) = 3e-7 r:
        # a relative area deficit below 1e-6, its centroid within 1e-6
        assert A == pytest.approx(ref.volume, rel=1e-6)
        c = Polygon(pts[ref.vertices]).centroid
        assert math.hypot(Sx / A - c.x, Sy / A - c.y) < 1e-6


def test_rounded_plate_obeys_steiner_and_collinear_discs_make_a_stadium():
    tri = [(0.0, 0.0), (4.0, 0.0), (1.0, 3.0)]
    r = 0.7
    A, Sx, Sy, J = shapes.moments(shapes.hull([shapes.Disc(x, y, r) for x, y in tri]))
    perim = sum(math.dist(tri[k], tri[k - 1]) for k in range(3))
    # Steiner's formula for the parallel body of a convex polygon: A + P r + pi r^2 (exact; quadrature 1e-13)
    assert A == pytest.approx(6.0 + perim * r + math.pi * r * r, rel=1e-12)
    # three collinear discs: the middle one adds nothing; a stadium L x 2r plus a disc
    A2, Sx2, _, J2 = shapes.moments(shapes.hull([shapes.Disc(0, 0, r), shapes.Disc(1.5, 0, r), shapes.Disc(5, 0, r)]))
    assert A2 == pytest.approx(5 * 2 * r + math.pi * r * r, rel=1e-12)
    assert Sx2 / A2 == pytest.approx(2.5, rel=1e-12)


# ------------------------------------------------------------------------------------------ one mechanism
@pytest.fixture(scope="module")
def fourbar():
    return parts_service.prepare(service.load("fourbar", {}))


def stadium_minus_holes(L, r, rh, t, rho):
    """Hand formulas: a bar of centre distance L, end radius r, holes of radius rh at both ends, thickness t:
    (area, mass, I about the centre of mass). Rectangle L x 2r, two half discs, two holes; the polar moment
    about the middle: rectangle m (L^2 + w^2) / 12, each half disc pi r^4 / 4 + A_h (L/2)^2 + 2 (L/2) A_h 4r/(3 pi)
    about the middle (its flat side at the end), each hole pi rh^4 / 2 + pi rh^2 (L/2)^2."""
    w = 2 * r
    a_rect, a_half, a_hole = L * w, math.pi * r * r / 2, math.pi * rh * rh
    area = a_rect + 2 * a_half - 2 * a_hole
    j = a_rect * (L * L + w * w) / 12
    j += 2 * (math.pi * r ** 4 / 4 + a_half * (L / 2) ** 2 + 2 * (L / 2) * a_half * 4 * r / (3 * math.pi))
    j -= 2 * (math.pi * rh ** 4 / 2 + a_hole * (L / 2) ** 2)
    return area, rho * t * area, rho * t * j


def test_bar_mass_properties_match_hand_formulas(fourbar):
    part = fourbar.parts["1"]                                 # the crank: a bar A-B of 0.1 m
    cfg = model.settings(fourbar.mech)
    assert part.kind == "bar" and [h.point for h in part.holes] == ["A", "B"]
    assert part.holes[1].x == pytest.approx(0.1, abs=1e-12) and part.holes[1].y == pytest.approx(0, abs=1e-12)
    mp = model.mass_properties(part, 1.0)
    area, m, inertia = stadium_minus_holes(0.1, part.width / 2, cfg.hole / 2, part.thickness, part.density)
    # exact against exact: the quadrature of the arcs, to rounding
    assert mp.area == pytest.approx(area, rel=1e-12)
    assert mp.m == pytest.approx(m, rel=1e-12)
    assert mp.cx == pytest.approx(0.05, abs=1e-12) and mp.cy == pytest.approx(0.0, abs=1e-12)
    assert mp.I == pytest.approx(inertia, rel=1e-11)


def test_mass_properties_against_the_mass_model_and_mujoco(tmp_path):
    """[mass] bars of 20 x 5 mm aluminium: the part weighs the mass model's rectangle L x w plus the two round
    ends (pi w^2 / 4) less the two holes (2 pi rh^2), exactly; MuJoCo's mesh inertia of the written STL agrees
    with the exact part to the tessellation's error."""
    import mujoco

    from sim.output import parts_files
    text = PLANTED.replace('[parts]\nlayers = { "1" = 0, "2" = 1, "3" = 0 }   # the layers of the four-bar without '
                           'the extension', '[mass]\ndensity = 2700\nwidth = 20\nthickness = 5\n\n[parts]\n'
                                            'pin_diameter = 8\nclearance = 0.2')
    path = tmp_path / "alu.toml"
    path.write_text(text.replace("ext = 300.0", "ext = 50.0"))
    pm = parts_service.prepare(service.load(str(path), {}))
    rows = parts_service.mass_comparison(pm)
    r = rows["3"]                                             # the rocker: a bar D-C of 250 mm
    rh = (8 + 0.2) / 2 * 1e-3
    w = 20e-3
    # with [parts] the analysis uses the part itself (one mass truth: the BOM's mass is the analysis's)
    assert r["model"]["m"] == pytest.approx(r["parts"]["m"], rel=1e-12)
    assert r["model"]["I"] == pytest.approx(r["parts"]["I"], rel=1e-12)
    # without [parts], [mass]'s bars: the rectangle L x w, short of the part by the two round ends (pi w^2 / 4)
    # less the two holes (2 pi rh^2), exactly
    from analytic import mass
    bare = tmp_path / "alu_bars.toml"
    bare.write_text(path.read_text().replace("[parts]\npin_diameter = 8\nclearance = 0.2", ""))
    bars = mass.model(service.load(str(bare), {}))["3"]
    correction = 2700 * 5e-3 * (math.pi * w * w / 4 - 2 * math.pi * rh * rh)
    assert r["parts"]["m"] - bars.m == pytest.approx(correction, rel=1e-9)   # hand formula, exact
    _, m_hand, i_hand = stadium_minus_holes(0.25, w / 2, rh, 5e-3, 2700)
    assert r["parts"]["m"] == pytest.approx(m_hand, rel=1e-12)
    assert r["parts"]["I"] == pytest.approx(i_hand, rel=1e-11)
    # MuJoCo's inertia of the STL's triangle mesh: the polygons lie inside the arcs by at most the chord
    # (1e-5 of the size), so the mass is short by at most perimeter x chord / area ~ 1e-5 relative
    for ln, row in rows.items():
        mj = row["mujoco"]
        assert mj["m"] == pytest.approx(row["parts"]["m"], rel=5e-5)
        assert mj["I"] == pytest.approx(row["parts"]["I"], rel=1e-4)
        assert math.hypot(mj["cx"] - row["parts"]["cx"], mj["cy"] - row["parts"]["cy"]) < 1e-5 * 0.3
    # and the STL files themselves, loaded by MuJoCo from disk
    parts_files.write_stl(pm, tmp_path / "stl")
    spec = mujoco.MjSpec()
    spec.compiler.degree = False
    mesh = spec.add_mesh(name="rocker", file=str(tmp_path / "stl" / "3.stl"), scale=[1e-3] * 3)
    mesh.inertia = mujoco.mjtMeshInertia.mjMESH_INERTIA_EXACT    # the default is its convex hull's (no holes)
    body = spec.worldbody.add_body(name="b")
    body.add_freejoint()
    body.add_geom(type=mujoco.mjtGeom.mjGEOM_MESH, meshname="rocker", density=2700)
    mj = spec.compile()
    assert mj.body_mass[1] == pytest.approx(rows["3"]["parts"]["m"], rel=5e-5)


def test_fourbar_layers_keep_same_layer_links_apart_by_hand_geometry(fourbar):
    """Crank and rocker share layer 0 and the coupler (pinned to both) is alone on layer 1: two layers are the
    fewest (pinned links always overlap). Independent check: crank and rocker as stadiums (segment distance
    minus both end radii) never come closer than the clearance over 3600 closed-form poses."""
    from analytic import fourbar as fb
    L = fourbar.layout
    assert L.count == 2 and L.layers["1"] == L.layers["3"] != L.layers["2"]
    cfg = model.settings(fourbar.mech)
    phi = np.linspace(0, 2 * np.pi, 3600)
    sol = fb.solve(fb.FourBar(), phi, 0.0)
    B = np.column_stack([0.1 * np.cos(phi), 0.1 * np.sin(phi)])
    C = np.column_stack([0.3 + 0.25 * np.cos(sol.phi3), 0.25 * np.sin(sol.phi3)])
    d = np.array([seg_dist((0, 0), b, (0.3, 0), c) for b, c in zip(B, C)])
    r = fourbar.parts["1"].width / 2
    assert (d - 2 * r).min() > cfg.clearance


def seg_dist(p0, p1, q0, q1) -> float:
    """Distance of two segments (brute force over a fine parameter grid refined by projection)."""
    p0, p1, q0, q1 = (np.asarray(v, float) for v in (p0, p1, q0, q1))

    def point_seg(x, a, b):
        ab = b - a
        L2 = np.dot(ab, ab)
        t = 0.0 if L2 == 0 else np.clip(np.dot(x - a, ab) / L2, 0.0, 1.0)
        return np.hypot(*(a + t * ab - x))
    return min(point_seg(p0, q0, q1), point_seg(p1, q0, q1), point_seg(q0, p0, p1), point_seg(q1, p0, p1)) \
        if not _cross(p0, p1, q0, q1) else 0.0


def _cross(p0, p1, q0, q1) -> bool:
    def orient(a, b, c):
        return np.sign((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
    return orient(p0, p1, q0) != orient(p0, p1, q1) and orient(q0, q1, p0) != orient(q0, q1, p1)


def test_colouring_is_exact_on_small_graphs():
    rng = np.random.default_rng(3)
    for _ in range(60):
        n = int(rng.integers(1, 7))
        nodes = list(range(n))
        edges = [(a, b) for a, b in itertools.combinations(nodes, 2) if rng.random() < 0.5]
        got = layers.colour(nodes, edges)
        assert all(got[a] != got[b] for a, b in edges)
        best = min(k for k in range(1, n + 1) if any(all(c[a] != c[b] for a, b in edges)
                                                   for c in itertools.product(range(k), repeat=n)))
        assert max(got.values()) + 1 == best                    # brute force over every assignment
    assert max(layers.colour(range(5), [(k, (k + 1) % 5) for k in range(5)]).values()) == 2   # C5: 3 colours


# ------------------------------------------------------------------------------------------ interference
def _oracle_first_contact(mech, r: float) -> float:
    """The first crank angle (deg) where the stadiums A-F and D-C (radius r each) touch: hand segment distance
    on the solver's points, scanned at 0.05 deg and bisected to 1e-9 deg."""
    def gaps(deg):
        t = (np.radians(np.atleast_1d(deg)) - math.radians(30)) / (2 * math.pi)
        _, sol = mech.solve_at(t)
        P = {k: np.column_stack([sol["x" + k], sol["y" + k]]) / mech.scale for k in "AFDC"}
        return np.array([seg_dist(a, f, d, c) for a, f, d, c in zip(P["A"], P["F"], P["D"], P["C"])]) - 2 * r
    grid = np.arange(30.0, 390.0, 0.05)
    vals = gaps(grid)
    k = int(np.argmax(vals < 0))
    lo, hi = grid[k - 1], grid[k]
    while hi - lo > 1e-9:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if gaps(mid)[0] < 0 else (mid, hi)
    return hi


def test_planted_collision_found_where_the_geometry_says(tmp_path):
    path = tmp_path / "planted.toml"
    path.write_text(PLANTED)
    mech = service.load(str(path), {})
    pm = parts_service.prepare(mech)
    report = parts_service.interference(pm)
    assert [i["links"] for i in report["interference"]] == [["1", "3"]]
    hit = report["interference"][0]
    oracle = _oracle_first_contact(pm.mech, pm.parts["1"].width / 2)
    # MuJoCo's contact vs the plane test on the same polygons: their collision tolerances (libccd ~1e-9 of the
    # size) over an approach of ~5 mm/deg: 1e-5 deg
    assert hit["first_at"] == pytest.approx(hit["geometric"]["first_at"], abs=1e-5)
    # vs the exact stadiums: the polygons lie inside the arcs by <= chord 1e-5 x 300 mm = 3 um -> 6e-4 deg
    assert hit["first_at"] == pytest.approx(oracle, abs=1.5e-3)
    assert hit["first_at"] >= oracle - 1e-9                     # inside the arcs: never earlier than exact
    # the depth: MuJoCo's 3-D penetration of two 6 mm plates of one layer is capped by their common
    # thickness (6 mm less the 0.1 % inset of the second on each face: lifted by 6 - 0.006), the plane's is not
    assert hit["depth"] == pytest.approx(6.0 * (1 - 1e-3), rel=1e-6)
    assert hit["geometric"]["depth"] > hit["depth"]
    # shorter extension: clear, and both methods agree on the clearance to 1e-8 of the size
    mech2 = mech.with_values(ext=250.0)
    r2 = parts_service.interference(parts_service.prepare(mech2))
    assert r2["interference"] == []
    assert r2["min_clearance"]["1|3"] == pytest.approx(r2["min_clearance_geometric"]["1|3"], abs=1e-5)
    assert r2["min_clearance"]["1|3"] > 0


def test_check_interference_cli_json_and_exit_code(tmp_path):
    from sim.front.cli import main
    path = tmp_path / "planted.toml"
    path.write_text(PLANTED)
    buf = io.StringIO()
    with redirect_stdout(buf):
        rc = main(["check", str(path), "--interference", "--json"])
    assert rc == 1
    data = json.loads(buf.getvalue())
    assert set(data["interference"][0]) >= {"links", "first_at", "depth"}
    assert "1|3" in data["min_clearance"]
    buf = io.StringIO()
    with redirect_stdout(buf):
        rc = main(["check", "fourbar"])
    assert rc == 0 and "1: layer 0" in buf.getvalue() and "2: layer 1" in buf.getvalue()


def test_bad_parts_input_is_one_line(tmp_path, capsys):
    from sim.front.cli import main
    path = tmp_path / "bad.toml"
    path.write_text(PLANTED.replace('layers = { "1" = 0, "2" = 1, "3" = 0 }', 'pin_diameter = -3'))
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "parts.pin_diameter" in err
    path.write_text(PLANTED.replace('layers = { "1" = 0, "2" = 1, "3" = 0 }', 'pin_diameter = 30'))
    assert main(["check", str(path)]) == 2                    # the file's own [parts] refused, as export refuses it
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "pin_diameter" in err
    assert main(["export", str(path), "--bom", str(tmp_path / "b.csv")]) == 2
    assert "pin_diameter" in capsys.readouterr().err and not (tmp_path / "b.csv").exists()


# ------------------------------------------------------------------------------------------ files
def test_fourbar_dxf_stl_bom_read_back(fourbar, tmp_path):
    import ezdxf
    import trimesh

    from sim.output import parts_files
    mech = fourbar.mech
    cfg = model.settings(mech)
    size = mech.size / mech.scale
    _, sol = mech.solve_at([0.0])
    pose = {p: (sol["x" + p][0] / mech.scale, sol["y" + p][0] / mech.scale) for p in mech.points}
    parts_files.write_dxf(fourbar, tmp_path / "f.dxf")
    doc = ezdxf.readfile(tmp_path / "f.dxf")
    assert doc.dxfversion >= "AC1027"                          # R2013 or later
    msp = doc.modelspace()
    for ln, joints in (("1", "AB"), ("2", "BC"), ("3", "DC")):
        circles = [e for e in msp if e.dxftype() == "CIRCLE" and e.dxf.layer == ln]
        got = sorted((c.dxf.center.x, c.dxf.center.y) for c in circles)
        want = sorted(pose[p] for p in joints)
        assert np.allclose(got, want, atol=1e-6 * size, rtol=0)  # hole centres: the solver's joints
        assert all(c.dxf.radius == pytest.approx(cfg.hole / 2, rel=1e-12) for c in circles)
        poly = next(e for e in msp if e.dxftype() == "LWPOLYLINE" and e.dxf.layer == ln)
        area = bulge_area(poly.get_points("xyb"))
        r = fourbar.parts[ln].width / 2
        if ln == "2":                                          # plate over B, C, E: Steiner
            tri = [pose["B"], pose["C"], pose["E"]]
            a_tri = 0.5 * abs((tri[1][0] - tri[0][0]) * (tri[2][1] - tri[0][1])
                              - (tri[2][0] - tri[0][0]) * (tri[1][1] - tri[0][1]))
            want_a = a_tri + sum(math.dist(tri[k], tri[k - 1]) for k in range(3)) * r + math.pi * r * r
        else:
            L = math.dist(*(pose[p] for p in joints))
            want_a = L * 2 * r + math.pi * r * r
        # the polyline's exact area (chords plus circular segments) against the hand formula: rounding only
        assert area == pytest.approx(want_a, rel=1e-10)
    # STL: watertight solids whose volumes are the hand areas x thickness, to the tessellation (1e-5 of the size
    # chord over the perimeter: < 1e-4 relative)
    parts_files.write_stl(fourbar, tmp_path / "stl")
    crank = trimesh.load(tmp_path / "stl" / "1.stl")
    assert crank.is_watertight
    area, _, _ = stadium_minus_holes(0.1, fourbar.parts["1"].width / 2, cfg.hole / 2, 1, 1)
    assert crank.volume == pytest.approx(area * fourbar.parts["1"].thickness, rel=1e-4)
    z0, z1 = fourbar.layout.z["1"]
    # STL stores float32: coordinates to 1e-7 of the size
    assert crank.bounds[0][2] == pytest.approx(z0, abs=1e-7 * size)
    assert crank.bounds[1][2] == pytest.approx(z1, abs=1e-7 * size)
    for p in "AB":                                            # the holes' walls: vertices on circles round the joints
        r = np.hypot(crank.vertices[:, 0] - pose[p][0], crank.vertices[:, 1] - pose[p][1])
        assert np.sum(np.abs(r - cfg.hole / 2) < 1e-6 * size) >= 32
    parts_files.write_bom(fourbar, tmp_path / "bom.csv")
    lines = (tmp_path / "bom.csv").read_text().splitlines()
    assert lines[0].split(",")[:7] == ["link", "layer", "mass_kg", "length", "width", "thickness", "holes"]
    assert len(lines) == 4


def bulge_area(vertices) -> float:
    """The area inside a closed LWPOLYLINE read back: its chords' shoelace plus each bulged edge's circular
    segment (bulge b: sweep 4 atan b, radius c / (2 sin(sweep / 2)), segment R^2 (s - sin s) / 2)."""
    v = [(x, y, b) for x, y, b in vertices]
    area = 0.0
    for (x0, y0, b), (x1, y1, _) in zip(v, v[1:] + v[:1]):
        area += 0.5 * (x0 * y1 - x1 * y0)
        if b:
            c = math.hypot(x1 - x0, y1 - y0)
            sweep = 4 * math.atan(b)
            R = c / (2 * math.sin(abs(sweep) / 2))
            area += math.copysign(0.5 * R * R * (abs(sweep) - math.sin(abs(sweep))), sweep)
    return abs(area)


def test_export_cli_refuses_a_bad_path_before_writing(tmp_path, capsys):
    from sim.front.cli import main
    out = tmp_path / "a.dxf"
    assert main(["export", "fourbar", "--dxf", str(out), "--bom", str(tmp_path / "nope" / "b.csv")]) == 2
    assert not out.exists()
    assert "does not exist" in capsys.readouterr().err


def test_parts_table_survives_export_toml(tmp_path):
    from analytic.format import linkfile
    mech = service.load(str(_write(tmp_path, PLANTED)), {})
    again = linkfile.parse(service.mechanism_text(mech), "again.toml")
    assert again.parts == {"layers": {"1": 0, "2": 1, "3": 0}}


def _write(tmp_path, text):
    path = tmp_path / "m.toml"
    path.write_text(text)
    return path


def test_frame_is_an_obstacle_on_layer_zero(tmp_path):
    """A frame plate below the crank: chosen layers keep the crank off layer 0; with the crank fixed on layer 0
    it hits the frame's edge y = -95 where its round end's lowest point 100 sin(phi) - 12.5 reaches it:
    phi = 180 deg + asin(82.5 / 100) (the extension F sits 1e-4 mm past B)."""
    frame = 'frame = [[-150, -160], [450, -160], [450, -95], [-150, -95]]'
    free = PLANTED.replace('layers = { "1" = 0, "2" = 1, "3" = 0 }', frame).replace("ext = 300.0", "ext = 100.0001")
    pm = parts_service.prepare(service.load(str(_write(tmp_path, free)), {}))
    assert pm.layout.layers["1"] != 0 and pm.layout.layers["3"] == 0
    report = parts_service.interference(pm)
    assert report["interference"] == [] and set(report["min_clearance"]) == {"3|frame"}
    fixed = free.replace(frame, frame + '\nlayers = { "1" = 0 }')
    pm = parts_service.prepare(service.load(str(_write(tmp_path, fixed)), {}))
    report = parts_service.interference(pm)
    hits = {tuple(i["links"]): i for i in report["interference"]}
    assert set(hits) == {("1", "frame")}
    r = pm.parts["1"].width / 2
    want = 180.0 + math.degrees(math.asin((95.0 - r) / 100.0001))
    # the end's polygon lies inside its arc by <= chord 3e-3 mm; the end drops ~1 mm per degree there: 3e-3 deg
    assert hits[("1", "frame")]["first_at"] == pytest.approx(want, abs=5e-3)
    assert hits[("1", "frame")]["geometric"]["first_at"] == pytest.approx(want, abs=5e-3)


def test_pin_rules_by_hand():
    """A pin through links a (layer 0) and b (layer 2) that link c passes over: c may not sit on layer 1
    (inside the pin's span); a ground pivot's pin comes from below or above, so all the links that pass over
    it must lie on one side of its links."""
    rule = layers.PinRule("P", ("a", "b"), ("c",), False)
    assert not rule.holds({"a": 0, "b": 2, "c": 1})
    assert rule.holds({"a": 0, "b": 1, "c": 2})
    ground = layers.PinRule("O", ("a",), ("c", "d"), True)
    assert ground.holds({"a": 1, "c": 2, "d": 3}) and ground.side({"a": 1, "c": 2, "d": 3}) == "below"
    assert ground.holds({"a": 2, "c": 0, "d": 1}) and ground.side({"a": 2, "c": 0, "d": 1}) == "above"
    assert not ground.holds({"a": 1, "c": 0, "d": 2})
    # the colouring honours the rule: c conflicts with a only, so without the pin it would share b's layer
    # (inside the span [a, b]); with it c must go outside: a third layer
    assert layers.colour(["a", "b", "c"], [("a", "b"), ("a", "c")]) == {"a": 0, "b": 1, "c": 1}
    got = layers.colour(["a", "b", "c"], [("a", "b"), ("a", "c")], pins=[rule])
    assert got["a"] != got["b"] and got["a"] != got["c"] and rule.holds(got)


def test_app_offers_the_parts_files():
    import ezdxf

    from sim.front import app
    data, ctype, name = app.export("dxf", {"mechanism": "fourbar"})
    assert name == "fourbar.dxf" and ctype == "application/dxf"
    doc = ezdxf.read(io.StringIO(data.decode()))
    assert {"1", "2", "3"} <= {layer.dxf.name for layer in doc.layers}
    data, ctype, name = app.export("bom", {"mechanism": "fourbar"})
    assert data.decode().splitlines()[0].startswith("link,layer,mass_kg") and name == "fourbar_bom.csv"
    assert "/api/export/svg" in app.POSTS


def test_slot_follows_the_block_pin_over_the_cycle():
    """The shaper's guide bar 3: its slot, carried by the bar, holds the block's pin A at every instant (the
    pin's world path against the slot's centre line placed by the bar's pose), and the pin reaches both ends."""
    pm = parts_service.prepare(service.load("sixbar", {}))
    (slot,) = pm.parts["3"].slots
    size = pm.mech.size / pm.mech.scale
    a = pm.sweep.points["A"]
    ends = [model.to_world(f, [(slot.x0, slot.y0), (slot.x1, slot.y1)]) for f in pm.sweep.frames["3"]]
    d = np.array([seg_dist(p, p, e[0], e[1]) for p, e in zip(a, ends)])
    assert d.max() < 1e-9 * size                              # on the slot's line, within its length
    reach = [min(math.dist(p, e[0]) for p, e in zip(a, ends)), min(math.dist(p, e[1]) for p, e in zip(a, ends))]
    assert max(reach) < 1e-9 * size                          # the slot is no longer than the pin's travel
    assert slot.r == pytest.approx(model.settings(pm.mech).hole / 2, rel=1e-12)


@pytest.mark.parametrize("option, value, module", [("--dxf", "x.dxf", "ezdxf"), ("--stl", "stl", "trimesh"),
                                                   ("--step", "x.step", "build123d")])
def test_a_missing_extra_is_one_line_naming_the_install(tmp_path, monkeypatch, option, value, module):
    # issue 41: without the parts extra the export raised ModuleNotFoundError (a traceback) after making the
    # --stl folder; now one line with the command to run, exit 2, nothing written (the --toml neither)
    import cli_runner
    monkeypatch.setitem(__import__("sys").modules, module, None)      # as if not installed
    r = cli_runner.run("export", "fourbar", option, value, "--toml", "f.toml", cwd=tmp_path)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "pip install 'linkage[parts]'" in lines[0] and module in lines[0], lines
    assert list(tmp_path.iterdir()) == []
