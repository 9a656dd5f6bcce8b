"""Every library mechanism becomes printable parts (issue 28): no interference at its default layers, and
DXF, STL and STEP files that independent readers load, with the holes on the solver's joints (1e-6 of the
size) and the areas and volumes of hand formulas. Slow: the whole library, and build123d for STEP."""

import math
from functools import lru_cache

import numpy as np
import pytest
from scipy.spatial import ConvexHull

from analytic.parts import model
from sim import service
from sim.service import parts as parts_service
from test_parts import bulge_area

NAMES = [r["name"] for r in service.list_mechanisms()]


@lru_cache(maxsize=None)
def prepared(name):
    return parts_service.prepare(service.load(name, {}))


def joints_at_pose(pm):
    """{link: {point: (x, y)}} of every revolute joint of each link, from the solver at t = 0 (file units)."""
    mech = pm.mech
    _, sol = mech.solve_at([0.0])
    pose = {p: (sol["x" + p][0] / mech.scale, sol["y" + p][0] / mech.scale) for p in mech.points}
    out = {ln: {} for ln in mech.links}
    for j in mech.joints:
        if j.kind == "revolute":
            for ln in (j.a, j.b):
                if ln in out:
                    out[ln][j.point] = pose[j.point]
    return out, pose


def hand_area(pm, ln, pose):
    """The outline's area by hand where the part is a plain bar or plate (its points' hull grown by the end
    radius, Steiner: A + P r + pi r^2); None for blocks, slotted links and gears."""
    part = pm.parts[ln]
    if part.kind not in ("bar", "plate") or part.slots:
        return None
    pts = np.array([pose[p] for p in pm.mech.topology.links[ln].points])
    pts = np.unique(np.round(pts, 12), axis=0)
    r = part.width / 2
    if len(pts) == 1:
        return math.pi * r * r
    try:
        h = ConvexHull(pts)
        a, perim = h.volume, h.area
    except Exception:                                   # collinear points: a segment, area 0, perimeter 2 L
        d = pts - pts[0]
        s = d @ (d[-1] / np.linalg.norm(d[-1]))
        a, perim = 0.0, 2 * (s.max() - s.min())
    return a + perim * r + math.pi * r * r


@pytest.mark.slow
@pytest.mark.parametrize("name", NAMES)
def test_library_has_no_interference_at_default_layers(name):
    pm = prepared(name)
    report = parts_service.interference(pm)
    assert report["interference"] == [], report["interference"]
    cfg = model.settings(pm.mech)
    size = pm.mech.size / pm.mech.scale
    for key, v in report["min_clearance"].items():
        assert v >= cfg.clearance - 1e-6 * size              # layers keep the clearance (plane test, refined)
        # MuJoCo's distance against the plane test's: the same polygons, 1e-6 of the size
        assert v == pytest.approx(report["min_clearance_geometric"][key], abs=1e-6 * size)
    # pins some link must cross (four designs): MuJoCo's cylinder meets the link's solid where the plane test's
    # circle meets its outline (bisections 1e-10 of the cycle; 1e-4 deg allows their collision tolerances)
    for clash in report["pin_clashes"]:
        assert clash["first_at"] is not None and clash["geometric"]["first_at"] is not None, clash
        assert clash["first_at"] == pytest.approx(clash["geometric"]["first_at"], abs=1e-4), clash
    # the three with a pin clash in plain layers get a two-plate link, the trammel's rod runs between its yokes
    # (test_parts_two_plates.py): no design has a pin clash
    assert report["pin_clashes"] == []


@pytest.mark.slow
@pytest.mark.parametrize("name", NAMES)
def test_library_pins_clear_the_links_they_pass(name):
    """Independent of the layering's rules: where a link passes within the clearance of a pin's circle at a
    sample, its z range stays out of the pin's span, except the clashes the layout reports."""
    import shapely
    pm = prepared(name)
    cfg = model.settings(pm.mech)
    from analytic.parts import layers as lay
    out = lay.outlines(pm.mech, pm.parts)
    clashes = set(pm.layout.clashes)
    for p, (lo, hi) in pm.layout.pins.items():
        pinned = {ln for ln, part in pm.parts.items() if any(h.point == p for h in part.holes)}
        slotted = {ln for ln, part in pm.parts.items() if any(sl.block in pinned for sl in part.slots)}
        for ln in set(pm.parts) - pinned - slotted:
            if (p, ln) in clashes or all(z1 <= lo or z0 >= hi for _, (z0, z1) in pm.layout.plates(ln)):
                continue                                 # every plate of a two-plate link out of the span
            d = shapely.distance(shapely.polygons(lay.world(out, pm.sweep, ln)), shapely.points(pm.sweep.points[p]))
            assert np.min(d) - cfg.pin_diameter / 2 >= cfg.clearance, (p, ln)


@pytest.mark.slow
@pytest.mark.parametrize("name", NAMES)
def test_library_dxf_and_stl_read_back(name, tmp_path):
    import ezdxf
    import mujoco
    import trimesh

    from sim.output import parts_files
    pm = prepared(name)
    mech = pm.mech
    size = mech.size / mech.scale
    joints, pose = joints_at_pose(pm)
    parts_files.write_dxf(pm, tmp_path / "p.dxf")
    doc = ezdxf.readfile(tmp_path / "p.dxf")
    msp = doc.modelspace()
    for ln, part in pm.parts.items():
        circles = [e for e in msp if e.dxftype() == "CIRCLE" and e.dxf.layer == ln]
        got = sorted((c.dxf.center.x, c.dxf.center.y) for c in circles)
        want = sorted(joints[ln].values())
        assert len(got) == len(want)
        assert np.allclose(got, want, atol=1e-6 * size, rtol=0), ln
        polys = [e for e in msp if e.dxftype() == "LWPOLYLINE" and e.dxf.layer == ln]
        outline = max(bulge_area(p.get_points("xyb")) for p in polys)   # the outline encloses its slots
        exact = model.mass_properties(part, 1.0)
        want_a = hand_area(pm, ln, pose)
        if want_a is not None:
            assert outline == pytest.approx(want_a, rel=1e-9), ln    # the DXF's exact arcs vs Steiner's formula
        elif part.kind == "block" and not part.slots and len(part.points) == 1:
            assert outline == pytest.approx(part.width ** 2, rel=1e-12), ln
        slots = sum(bulge_area(p.get_points("xyb")) for p in polys) - outline
        holes = sum(math.pi * c.dxf.radius ** 2 for c in circles)
        if not part.crossings:                           # overlapping cut-outs: the sum counts them twice
            assert outline - slots - holes == pytest.approx(exact.area, rel=1e-9), ln
    folder = tmp_path / "stl"
    parts_files.write_stl(pm, folder)
    spec = mujoco.MjSpec()
    for ln, part in pm.parts.items():
        mesh = trimesh.load(folder / f"{ln}.stl")
        assert mesh.is_watertight, ln
        exact = model.mass_properties(part, 1.0)
        n = len(pm.layout.plates(ln))                    # a two-plate link's file holds both plates
        # the triangles lie inside the arcs by <= the chord (1e-5 of the size); float32 coordinates
        assert mesh.volume == pytest.approx(n * exact.volume, rel=2e-4), ln
        m = spec.add_mesh(name=f"m_{ln}", file=str(folder / f"{ln}.stl"))
        m.inertia = mujoco.mjtMeshInertia.mjMESH_INERTIA_EXACT
        b = spec.worldbody.add_body(name=ln)
        b.add_freejoint()
        b.add_geom(type=mujoco.mjtGeom.mjGEOM_MESH, meshname=f"m_{ln}", density=1.0)
    compiled = spec.compile()                                # MuJoCo reads every STL
    for ln, part in pm.parts.items():
        exact = model.mass_properties(part, 1.0)
        n = len(pm.layout.plates(ln))
        assert compiled.body_mass[compiled.body(ln).id] == pytest.approx(n * exact.volume, rel=2e-4), ln


@pytest.mark.slow
@pytest.mark.parametrize("name", NAMES)
def test_library_step_reads_back(name, tmp_path):
    import build123d as b3d

    from sim.output import parts_files
    pm = prepared(name)
    mech = pm.mech
    size = mech.size / mech.scale
    joints, pose = joints_at_pose(pm)
    path = tmp_path / "p.step"
    parts_files.write_step(pm, path)
    shape = b3d.import_step(str(path))
    k = {"mm": 1.0, "cm": 10.0, "m": 1000.0, "in": 25.4}[mech.units]   # the reader works in mm: the file says its unit
    shape = b3d.scale(shape, 1.0 / k)
    solids = shape.solids()
    assert len(solids) == sum(len(pm.layout.plates(ln)) for ln in pm.parts)   # a two-plate link: two solids
    unused = list(solids)
    for ln, part, (z0, z1) in [(ln, part, zs) for ln, part in pm.parts.items() for _, zs in pm.layout.plates(ln)]:
        exact = model.mass_properties(part, 1.0)
        swallowed = {p for _, p in part.crossings}          # a hole inside a slot leaves no circle of its own

        def fits(solid):
            bb = solid.bounding_box()
            # OpenCASCADE's volume of the B-rep (exact arcs) against Green's theorem on the same arcs; where a
            # slot runs into a hole the part's moments come from its polygon (chord 1e-6 of its size)
            return (solid.volume == pytest.approx(exact.volume, rel=1e-5 if part.crossings else 1e-7)
                    and bb.min.Z == pytest.approx(z0, abs=1e-9 * size) and bb.max.Z == pytest.approx(z1, abs=1e-9 * size)
                    and all(any(math.hypot(c[0] - x, c[1] - y) < 1e-6 * size for c in hole_centres(solid, part))
                            for p, (x, y) in joints[ln].items() if p not in swallowed))
        match = next((s_ for s_ in unused if fits(s_)), None)
        assert match is not None, ln
        unused.remove(match)


def hole_centres(solid, part):
    import build123d as b3d
    r = part.holes[0].r if part.holes else None
    return [(e.arc_center.X, e.arc_center.Y) for e in solid.edges()
            if r is not None and e.geom_type == b3d.GeomType.CIRCLE and abs(e.radius - r) < 1e-9 * (1 + r)]
