"""Two-plate links (issue 41, item 5): where no plain layering keeps the links off the pins they pass, the
layering makes one link two plates (a clevis: the plates joined by a pin fixed in both, links between them)
and may hold a ground pin from a top plate. ``check`` names the construction and reports no pin clash; the
exported STL solids, moved by the solver's motion over a dense sweep, never reach into a pin's (x, y, z)
volume; a mechanism without a clash keeps its layering exactly."""

import itertools
import re

import numpy as np
import pytest

from sim import service
from sim.service import parts as parts_service

SOLVED = ["whitworth", "stephenson_ii", "double_butterfly"]
DENSE = 2000
"""Instants of the test's own sweep (2.8 x the layering's 720): a 500 mm link's tip moves 1.6 mm a step, far
less than the 30-40 mm width of any link that could pass a pin between two of them."""


def prepared(name):
    return parts_service.prepare(service.load(name, {}))


@pytest.mark.parametrize("name", SOLVED)
def test_check_reports_no_pin_clash_and_names_the_construction(name):
    lines = parts_service.layer_lines(prepared(name))
    text = "\n".join(lines)
    assert "pin clash" not in text, text
    assert re.search(r"link \S+: two plates \(layers \d+ and \d+\), a clevis at \S+: its pin fixed in both plates", text), text
    if name == "whitworth":                               # the lever's pivot held from above, the crank under it
        assert "pin C: stub from the top plate, links 2, 4 pass under" in text, text


def test_elliptic_trammel_builds_without_a_pin_clash():
    """The trammel's yokes carry the rod's pins c clear of their slots and its crank turns about (-c, -c), so the
    rod never passes over the crank pin K: it runs between the two yokes, so each rod pin reaches its yoke without
    passing the other yoke's plate (which sweeps over it), and K runs through both yokes' slots past the rod's
    layer. check reports no pin clash and no slot running into its own pin."""
    pm = prepared("elliptic_trammel")
    text = "\n".join(parts_service.layer_lines(pm))
    assert "pin clash" not in text and "runs into" not in text, text
    L = pm.layout
    assert not L.clashes and not L.second
    low, high = sorted((L.layers["blockA"], L.layers["blockB"]))
    assert low < L.layers["rod"] < high, L.layers                  # the rod between the yokes


def _plates_from_stl(path):
    """[(z0, z1, region)] of each shell of the STL: its z extent and its top face's plane region (the union of
    the triangles lying on its top, holes and slots left open), in the pose of t = 0."""
    import shapely
    import trimesh
    mesh = trimesh.load(path)
    out = []
    for body in mesh.split(only_watertight=False):
        v = np.asarray(body.vertices)
        z0, z1 = float(v[:, 2].min()), float(v[:, 2].max())
        tri = v[np.asarray(body.faces)]
        top = tri[np.all(np.abs(tri[:, :, 2] - z1) <= 1e-6 * (1 + abs(z1)), axis=1)]
        region = shapely.union_all([shapely.Polygon(t[:, :2]) for t in top]).buffer(0)
        out.append((z0, z1, region))
    return sorted(out, key=lambda p: p[0])


@pytest.mark.parametrize("name", SOLVED + ["elliptic_trammel"])
def test_exported_solids_never_reach_into_a_pin(name, tmp_path):
    """From the STL files alone (each link's plates: z extent and region) and the solver's motion: at every one
    of DENSE instants no plate whose z range overlaps a pin's span comes within the pin's radius of the pin's
    axis (a link the pin holds has its hole there: pin + clearance). And the spans are real: each pin reaches
    a plate of every link it joins (and of the link whose slot it runs in), a ground pin starts at the frame
    (z 0) or ends at the stack's top, and each two-plate link has a pin through both its plates."""
    import shapely

    from analytic.kinds import GROUND
    from analytic.parts import model
    from sim.output import parts_files
    pm = prepared(name)
    mech = pm.mech
    size = mech.size / mech.scale
    parts_files.write_stl(pm, tmp_path)
    plates = {ln: _plates_from_stl(tmp_path / f"{ln}.stl") for ln in pm.parts}
    # the construction is in the files (the trammel needs none: its rod runs between its yokes)
    assert any(len(p) == 2 for p in plates.values()) == (name in SOLVED)
    pin_r = model.settings(mech).pin_diameter / 2
    chord = model.CHORD * size                            # the STL's polygons lie inside the exact arcs by this
    top = max(z1 for ps in plates.values() for _, z1, _ in ps)
    spans = pm.layout.pins

    def overlaps(z0, z1, span):                           # a shared z range of positive length (1e-9 of the size:
        return z0 < span[1] - 1e-9 * size and z1 > span[0] + 1e-9 * size   # float32 STL coordinates)

    revolute = [j for j in mech.joints if j.kind == "revolute"]
    for j in revolute:                                    # every pin reaches what it joins
        assert j.point in spans, j.point
        for ln in (j.a, j.b):
            if ln != GROUND:
                assert any(overlaps(z0, z1, spans[j.point]) for z0, z1, _ in plates[ln]), (j.point, ln)
        if GROUND in (j.a, j.b):
            lo, hi = spans[j.point]
            assert lo == pytest.approx(0.0, abs=1e-9 * size) or hi == pytest.approx(top, abs=1e-6 * size), j.point
    for j in mech.joints:                                 # a block's pin runs in its guide's slot
        if j.kind == "prismatic" and j.a != GROUND and j.point in spans:
            assert any(overlaps(z0, z1, spans[j.point]) for z0, z1, _ in plates[j.a]), (j.point, j.a)
    for ln, ps in plates.items():
        if len(ps) == 2:
            own = [j.point for j in revolute if ln in (j.a, j.b) and GROUND not in (j.a, j.b)]
            assert any(all(overlaps(z0, z1, spans[p]) for z0, z1, _ in ps) for p in own), ln

    ts = np.linspace(0.0, mech.duration(1.0), DENSE + 1)
    _, sol = mech.solve_at(ts)
    assert sol.valid.all()
    s = mech.scale
    xy = {p: np.column_stack([sol["x" + p], sol["y" + p]]) / s for p in mech.points}
    checked = 0
    for ln, ps in plates.items():
        ref = mech.topology.links[ln].points[0]
        ang = np.arctan2(sol["sin" + ln], sol["cos" + ln])
        for p, span in spans.items():
            # the pin's axis in the pose-0 placement of the link: undo the link's motion since t = 0
            d = xy[p] - xy[ref]
            a = ang[0] - ang
            c, si = np.cos(a), np.sin(a)
            q = np.column_stack([d[:, 0] * c - d[:, 1] * si, d[:, 0] * si + d[:, 1] * c]) + xy[ref][0]
            for z0, z1, region in ps:
                if not overlaps(z0, z1, span):
                    continue
                gap = np.asarray(shapely.distance(region, shapely.points(q))) - chord
                assert gap.min() >= pin_r, (name, p, ln, z0, z1, float(gap.min()), float(ts[int(np.argmin(gap))]))
                checked += 1
    assert checked >= len(spans)                          # every pin met at least the plates it runs through


def _derived_layering(links, conflicts):
    """The fewest layers with no conflicting pair in one, the first such assignment in the links' order with the
    smallest layers first (as the layering promises), by exhaustive search."""
    adj = {frozenset(c) for c in conflicts}
    for k in range(1, len(links) + 1):
        for combo in itertools.product(range(k), repeat=len(links)):
            col = dict(zip(links, combo))
            if all(col[a] != col[b] for a, b in map(tuple, adj)):
                return col
    raise AssertionError("no layering")


@pytest.mark.parametrize("name", ["fourbar", "sixbar", "jansen", "klann", "watt_six_bar", "slider_crank",
                                  "inverted_slider_crank"])
def test_a_mechanism_without_a_clash_keeps_its_plain_layering(name):
    """No regression: no two-plate link, and the layers and z of the plain layering the test derives from the
    conflicting pairs (fewest layers, each layer as thick as its parts, layer_gap between)."""
    from analytic.parts import model
    pm = prepared(name)
    L = pm.layout
    assert not L.second and not L.clashes
    links = list(pm.parts)
    want = _derived_layering(links, L.conflicts)
    assert L.layers == want
    gap = model.settings(pm.mech).layer_gap
    level = 0.0
    for k in range(max(want.values()) + 1):
        members = [ln for ln in links if want[ln] == k]
        for ln in members:
            assert L.z[ln][0] == pytest.approx(level, abs=1e-12 * (1 + level))   # sums of the same numbers
            assert L.z[ln][1] - L.z[ln][0] == pytest.approx(pm.parts[ln].thickness, rel=1e-12)
        level += max(pm.parts[ln].thickness for ln in members) + gap
    assert len(L.plates(links[0])) == 1


def test_bom_lists_a_two_plate_link_as_two_plates(tmp_path):
    """The bill of materials: the lever of the Whitworth is two plates (layers 1 and 4 here), twice one plate's
    mass and holes; the drawing's parts list and note say so."""
    import csv

    from analytic.parts import model
    from sim.output import parts_drawing, parts_files
    pm = prepared("whitworth")
    parts_files.write_bom(pm, tmp_path / "b.csv")
    rows = {r["link"]: r for r in csv.DictReader(open(tmp_path / "b.csv"))}
    lever = rows["3"]
    assert lever["plates"] == "2" and lever["layer"] == "1" and lever["upper_layer"] == "4"
    one = model.mass_properties(pm.parts["3"], pm.mech.scale)
    assert float(lever["mass_kg"]) == pytest.approx(2 * one.m, rel=1e-12)
    assert int(lever["holes"]) == 2 * len(pm.parts["3"].holes)
    assert all(rows[ln]["plates"] == "1" and rows[ln]["upper_layer"] == "" for ln in rows if ln != "3")
    assert "3 (layers 1 and 4, pin D)" in parts_drawing.two_plate_note(pm)


def test_mujoco_weighs_both_plates_of_the_lever():
    """The mass comparison of a two-plate link: the parts' figures both plates', and MuJoCo's exact inertia of the
    two plates' triangle meshes (at their layers' z) the same: twice one plate's mass and moment of inertia
    about z, the same in-plane centre."""
    from analytic.parts import model
    pm = prepared("whitworth")
    lever = parts_service.mass_comparison(pm)["3"]
    one = model.mass_properties(pm.parts["3"], pm.mech.scale)
    assert lever["parts"]["m"] == pytest.approx(2 * one.m, rel=1e-12)             # the same sums: rounding
    assert lever["parts"]["I"] == pytest.approx(2 * one.I, rel=1e-12)
    # the meshes' polygons lie inside the exact arcs by the chord: 1.3e-4 in m and 1.6e-4 in I at most over the
    # library's parts (CONVENTIONS, "Mass properties"); 2e-4 of the lever's length for its centre
    assert lever["mujoco"]["m"] == pytest.approx(2 * one.m, rel=2e-4)
    assert lever["mujoco"]["I"] == pytest.approx(2 * one.I, rel=2e-4)
    assert lever["mujoco"]["cx"] == pytest.approx(one.cx * pm.mech.scale, abs=2e-4 * 0.375)


@pytest.mark.slow
def test_step_holds_both_plates(tmp_path):
    """The STEP file: the lever's entry holds two solids, each one plate's exact volume, at its plate's z."""
    pytest.importorskip("build123d")
    import build123d as b3d

    from analytic.parts import model
    from sim.output import parts_files
    pm = prepared("whitworth")
    parts_files.write_step(pm, tmp_path / "w.step")
    solids = b3d.import_step(str(tmp_path / "w.step")).solids()
    assert len(solids) == len(pm.parts) + 1
    one = model.mass_properties(pm.parts["3"], 1.0).volume
    zs = sorted((round(s.bounding_box().min.Z, 6), round(s.bounding_box().max.Z, 6)) for s in solids
                if s.volume == pytest.approx(one, rel=1e-7))   # OpenCASCADE's B-rep volume vs Green's theorem
    assert zs == [(12.0, 22.0), (48.0, 58.0)]


@pytest.mark.slow
def test_interference_checks_every_passed_pin_in_mujoco():
    """``check --interference`` on a two-plate layout: no collision, no pin clash, and each pin a link passes is
    measured in 3-D: MuJoCo's least distance of the pin's cylinder and the link's solids is the z gap between
    the pin's end and the plate (the layer gap here: 2 mm), never a penetration."""
    pm = prepared("whitworth")
    report = parts_service.interference(pm)
    assert report["interference"] == [] and report["pin_clashes"] == []
    assert report["two_plates"] == {"3": {"layers": [1, 4], "joined_by": "D"}}
    passed = {(i["pin"], i["link"]): i["min_distance"] for i in report["pins_passed"]}
    assert set(passed) == {("O", "3"), ("O", "4"), ("C", "2"), ("C", "4"), ("A", "4"), ("D", "2")}
    gap = 2.0                                              # the Whitworth's layer gap [mm]: width 40, 10 thick, /5
    for key, d in passed.items():
        # MuJoCo's solids are inset 1e-3 of their 10 mm thickness per rank in a layer (parts_scene.INSET): 0.02 mm
        assert d >= gap - 0.02, key
    assert min(passed.values()) == pytest.approx(gap, abs=0.02)
