"""The parts as files, at the pose of t = 0 in the file's length unit: DXF (ezdxf; one layer per link, the
outline as a closed polyline with true arcs (bulges), holes as circles, slots as closed polylines; the
ground pivots and the frame on their own layers), STL (one ``LINK.stl`` per link, its solid in its layer,
triangulated here and written by trimesh), STEP (build123d: one solid per link with exact arcs, placed in its
layer) and the bill of materials (CSV). Every file is written whole to a temporary name and renamed."""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

import numpy as np

from analytic.parts import model, shapes
from sim.output.io import atomic_path

DXF_UNITS = {"mm": 4, "cm": 5, "m": 6, "in": 1}
"""$INSUNITS codes of the file units."""


def placed(pm, link: str, k: int = 0) -> tuple[float, float, float]:
    """The link's frame (ox, oy, angle) at sample ``k`` of the sweep (0: the pose of t = 0)."""
    x, y, a = pm.sweep.frames[link][k]
    return float(x), float(y), float(a)


def world_arcs(arcs, frame) -> list[shapes.Arc]:
    ox, oy, a = frame
    c, s = math.cos(a), math.sin(a)
    return [shapes.Arc(ox + r.x * c - r.y * s, oy + r.x * s + r.y * c, r.r, r.a0 + a, r.a1 + a) for r in arcs]


def _bulged(arcs) -> list[tuple[float, float, float]]:
    """A closed boundary as LWPOLYLINE vertices (x, y, bulge): each arc's start with the bulge tan(sweep/4)
    to its end, then its end joined straight to the next arc; a full circle as two half arcs."""
    if len(arcs) == 1 and arcs[0].r > 0:
        a = arcs[0]
        return [(*a.at(a.a0), 1.0), (*a.at(a.a0 + math.pi), 1.0)]
    out = []
    for a in arcs:
        sweep = a.a1 - a.a0
        if a.r > 0 and sweep > 0:
            out.append((*a.start, math.tan(sweep / 4.0)))
            out.append((*a.end, 0.0))
        else:
            out.append((a.x, a.y, 0.0))
    clean = [out[0]]
    for v in out[1:]:
        if math.hypot(v[0] - clean[-1][0], v[1] - clean[-1][1]) > 0.0:
            clean.append(v)
        else:
            clean[-1] = (clean[-1][0], clean[-1][1], v[2])
    return clean


def write_dxf(pm, path) -> None:
    import ezdxf
    mech = pm.mech
    doc = ezdxf.new("R2013", setup=True)
    doc.header["$INSUNITS"] = DXF_UNITS[mech.units]
    doc.header["$MEASUREMENT"] = 0 if mech.units == "in" else 1
    msp = doc.modelspace()
    for n, (ln, part) in enumerate(pm.parts.items()):
        if ln not in doc.layers:
            doc.layers.add(ln, color=1 + n % 6)
        layer = doc.layers.get(ln)
        plates = pm.layout.plates(ln)
        layer.description = (f"link {ln}: layer {plates[0][0]}, {part.thickness:g} {mech.units} thick" if len(plates) == 1
                             else f"link {ln}: two plates of this outline, layers {plates[0][0]} and {plates[1][0]}, "
                                  f"{part.thickness:g} {mech.units} thick each, joined by the pin at "
                                  f"{pm.layout.joined[ln]} fixed in both")
        frame = placed(pm, ln)
        msp.add_lwpolyline(_bulged(world_arcs(part.outline, frame)), format="xyb", close=True,
                           dxfattribs={"layer": ln})
        for h in part.holes:
            (x, y), = model.to_world(frame, [(h.x, h.y)])
            msp.add_circle((x, y), h.r, dxfattribs={"layer": ln})
        for sl in part.slots:
            msp.add_lwpolyline(_bulged(world_arcs(sl.outline, frame)), format="xyb", close=True,
                               dxfattribs={"layer": ln})
    cfg = model.settings(mech)
    doc.layers.add("ground", color=8)
    for g in mech.ground_points:
        x, y = (float(v) for v in pm.sweep.points[g][0])
        msp.add_circle((x, y), cfg.pin_diameter / 2.0, dxfattribs={"layer": "ground"})
        msp.add_text(g, height=cfg.pin_diameter, dxfattribs={"layer": "ground"}).set_placement(
            (x + cfg.pin_diameter, y + cfg.pin_diameter))
    if cfg.frame:
        doc.layers.add("frame_outline", color=8)
        msp.add_lwpolyline(cfg.frame, close=True, dxfattribs={"layer": "frame_outline"})
    with atomic_path(path) as tmp:
        doc.saveas(tmp)


# ------------------------------------------------------------------------------------------------- meshes
def part_region(part, chord: float, frame=None):
    """The part's plane region (shapely, holes and slots cut), in its frame or placed by ``frame``."""
    import shapely
    outer = part.polygon(chord)
    cuts = [shapes.tessellate(shapes.hull([shapes.Disc(h.x, h.y, h.r)]), chord) for h in part.holes]
    cuts += [shapes.tessellate(sl.outline, chord) for sl in part.slots]
    if frame is not None:
        outer = model.to_world(frame, outer)
        cuts = [model.to_world(frame, c) for c in cuts]
    region = shapely.Polygon(outer)
    if cuts:
        region = region.difference(shapely.union_all([shapely.Polygon(c) for c in cuts]))
    return shapely.orient_polygons(region)


def extrude(region, z0: float, z1: float):
    """A closed triangle mesh (trimesh) of the plane region extruded from z0 to z1: its constrained
    Delaunay triangles top and bottom, a wall on every ring (outward normals)."""
    import shapely
    import trimesh
    tris = [np.asarray(t.exterior.coords)[:3] for t in shapely.get_parts(shapely.constrained_delaunay_triangles(region))]
    faces = []
    for t in tris:
        a, b, c = t
        if (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) < 0:
            a, b = b, a
        faces.append([(*a, z1), (*b, z1), (*c, z1)])
        faces.append([(*a, z0), (*c, z0), (*b, z0)])
    for poly in shapely.get_parts(region):
        for ring in [poly.exterior, *poly.interiors]:
            pts = np.asarray(ring.coords)[:-1]
            for p, q in zip(pts, np.roll(pts, -1, axis=0)):
                faces.append([(*p, z0), (*q, z0), (*q, z1)])
                faces.append([(*p, z0), (*q, z1), (*p, z1)])
    tri = np.asarray(faces, dtype=float)
    mesh = trimesh.Trimesh(vertices=tri.reshape(-1, 3), faces=np.arange(len(tri) * 3).reshape(-1, 3), process=True)
    mesh.merge_vertices(digits_vertex=10)
    return mesh


def solid_mesh(pm, link: str):
    """The link's solid at the pose of t = 0, in its layer (file units); a two-plate link's two plates, each in
    its layer, as one mesh of two shells."""
    import trimesh
    part = pm.parts[link]
    region = part_region(part, pm.chord, placed(pm, link))
    meshes = [extrude(region, z0, z1) for _, (z0, z1) in pm.layout.plates(link)]
    return meshes[0] if len(meshes) == 1 else trimesh.util.concatenate(meshes)


def write_stl(pm, folder) -> list[Path]:
    folder = Path(folder)
    folder.mkdir(exist_ok=True)
    written = []
    for ln in pm.parts:
        mesh = solid_mesh(pm, ln)
        target = folder / f"{ln}.stl"
        with atomic_path(target) as tmp:
            mesh.export(tmp, file_type="stl")
        written.append(target)
    return written


# ------------------------------------------------------------------------------------------------- STEP
def _b3d_face(arcs, b3d):
    edges = []
    for piece in shapes.segments(arcs):
        if piece[0] == "line":
            edges.append(b3d.Line(piece[1], piece[2]))
        else:
            a = piece[1]
            if a.a1 - a.a0 >= 2 * math.pi - 1e-12:
                edges.append(b3d.Edge.make_circle(a.r, b3d.Plane.XY.offset(0).move(b3d.Location((a.x, a.y, 0)))))
            else:
                edges.append(b3d.CenterArc((a.x, a.y), a.r, math.degrees(a.a0), math.degrees(a.a1 - a.a0)))
    return b3d.Face(b3d.Wire(edges))


def step_solids(pm) -> dict:
    """{link: build123d Solid} placed at the pose of t = 0 in its layer (imports build123d: seconds)."""
    import build123d as b3d
    out = {}
    for ln, part in pm.parts.items():
        face = _b3d_face(part.outline, b3d)
        for h in part.holes:
            face = face - b3d.Pos(h.x, h.y) * b3d.Circle(h.r)
        for sl in part.slots:
            face = face - _b3d_face(sl.outline, b3d)
        x, y, a = placed(pm, ln)
        plates = []
        for _, (z0, z1) in pm.layout.plates(ln):        # a two-plate link: a compound of its two plates
            solid = b3d.Pos(x, y, z0) * b3d.Rot(0, 0, math.degrees(a)) * b3d.extrude(face, amount=z1 - z0)
            plates.append(solid)
        solid = plates[0] if len(plates) == 1 else b3d.Compound(children=plates)
        solid.label = ln
        out[ln] = solid
    return out


def write_step(pm, path) -> None:
    import build123d as b3d
    solids = step_solids(pm)
    assembly = b3d.Compound(children=list(solids.values()), label=pm.mech.name)
    unit = {"mm": b3d.Unit.MM, "cm": b3d.Unit.CM, "m": b3d.Unit.M, "in": b3d.Unit.IN}[pm.mech.units]
    with atomic_path(path) as tmp:
        b3d.export_step(assembly, tmp, unit=unit)


# ------------------------------------------------------------------------------------------------- BOM
BOM_COLUMNS = ("link", "layer", "mass_kg", "length", "width", "thickness", "holes", "kind", "volume", "density_kg_m3",
               "analysis_mass_kg", "analysis_mass_from", "plates", "upper_layer")
"""``analysis_mass_kg``: the mass ``forces``, ``dynamics`` and the MuJoCo model give the link (counterweights
included); ``analysis_mass_from``: what gave it (:func:`analytic.mass.sources`: ``parts`` where the file has a
``[parts]`` section, else ``[inertia]``, ``[mass]`` or ``default``); ``plates``: 2 for a two-plate link (a
clevis: ``layer`` its lower plate, ``upper_layer`` its upper, ``mass_kg``, ``volume`` and ``holes`` both plates'),
else 1 (``upper_layer`` empty)."""


def bom_rows(pm) -> list[dict]:
    from analytic import mass
    analysis = mass.model(pm.mech, parts=pm.parts, layout=pm.layout)      # the parts and layers built once
    source = mass.sources(pm.mech)
    rows = []
    for ln, part in pm.parts.items():
        mp = model.mass_properties(part, pm.mech.scale)
        plates = pm.layout.plates(ln)
        n = len(plates)
        rows.append({"link": ln, "layer": plates[0][0], "mass_kg": n * mp.m, "length": part.length,
                     "width": part.width, "thickness": part.thickness, "holes": n * len(part.holes), "kind": part.kind,
                     "volume": n * mp.volume, "density_kg_m3": part.density, "analysis_mass_kg": analysis[ln].m,
                     "analysis_mass_from": source[ln], "plates": n, "upper_layer": plates[1][0] if n == 2 else ""})
    return rows


def write_bom(pm, path) -> None:
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=BOM_COLUMNS, lineterminator="\n")
    w.writeheader()
    for row in bom_rows(pm):
        w.writerow({k: (repr(float(v)) if isinstance(v, float) else v) for k, v in row.items()})
    with atomic_path(path) as tmp:
        Path(tmp).write_text(buf.getvalue())
