"""Each link as a part: its outline in its own frame (file units), holes, slots, thickness and material; and
the motion of every link's frame over the cycle.

A part is one plate, the convex hull of its features (:func:`analytic.parts.shapes.hull`), a cam plate aside:

* a disc of ``end_radius`` around every point the link carries (a bar between two joints is the hull of
  two discs; three or more points make a plate over their hull);
* a sliding block: a square of side ``width`` centred on its pin, along its guide;
* a link that guides a block (a slotted lever, a yoke) carries the slot: the pin's path in the link's frame
  over the cycle, ``pin_diameter + clearance`` wide, and material of ``end_radius`` around its ends;
* a gear: its pitch disc (of the kinds' :class:`~analytic.kinds.base.Wheel`);
* a cam's link: the cam plate, its profile (:func:`analytic.cams.geometry`) as a polygon of straight edges
  (not convex in general), joined with the link's own bosses where they reach outside it.

Holes of ``pin_diameter + clearance`` sit on every revolute joint of the link. Widths and thicknesses come
from ``[mass]`` (per link, else file-wide), else the defaults of :func:`defaults`; ``end_radius`` is
``width / 2`` unless ``[parts]`` gives it. Lengths are in the file's unit throughout (the frames' origins too).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic._common import ParameterError
from analytic.kinds import GROUND
from analytic.parts import shapes
from analytic.parts.shapes import Arc, Disc

DEFAULT_DENSITY = 1250.0
"""[kg/m^3] The density of a part without ``[mass]``: printed PLA (about 1240-1250 kg/m^3)."""

CHORD = 1e-5
"""The tessellation's chord error as a fraction of the mechanism's size: the polygons used for distances,
meshes and drawings lie within this of the exact arcs (1e-5 x 300 mm = 3 um, far below any clearance)."""

MAX_PART_FACTOR = 10.0
"""A ``[parts]`` size (pin, clearance, end radius, layer gap) at most this many times the mechanism's size:
past it the value is a unit slip, and arcs of 1e12 x the size tessellated at CHORD x the size never end."""

_NICE = (1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0)


def nice(x: float) -> float:
    """The largest of 1, 1.5, 2, 2.5, 3, 4, 5, 6, 8 x 10^k not above ``x``: a round default size."""
    if not x > 0:
        return x
    k = math.floor(math.log10(x))
    m = x / 10 ** k
    return max(v for v in _NICE if v <= m + 1e-9) * 10 ** k


@dataclass(frozen=True)
class Settings:
    """``[parts]`` with its defaults (file units): hole = pin_diameter + clearance."""

    pin_diameter: float
    clearance: float
    end_radius: float | None
    layer_gap: float
    frame: tuple[tuple[float, float], ...] | None
    layers: dict

    @property
    def hole(self) -> float:
        return self.pin_diameter + self.clearance


@dataclass(frozen=True)
class Material:
    width: float
    thickness: float
    density: float
    given: bool
    """Whether ``[mass]`` gave it (else the parts' defaults)."""


def defaults(size: float) -> dict[str, float]:
    """The default sizes for a mechanism of ``size`` (its longest link, file units): width size/12,
    thickness width/4, pin width*0.4, clearance pin/20, layer gap thickness/5, each rounded down to a round
    number; a 300 mm four-bar gets 25 x 6 mm bars on 10 mm pins with 0.5 mm clearance. (With ``[mass]``
    bars narrower than the default width, the pin is 0.4 of the narrowest: :func:`settings`.)"""
    width = nice(size / 12.0)
    thickness = nice(width / 4.0)
    pin = nice(width * 0.4)
    return {"width": width, "thickness": thickness, "pin_diameter": pin, "clearance": nice(pin / 20.0),
            "layer_gap": nice(thickness / 5.0)}


def settings(mech) -> Settings:
    section = mech.definition.parts or {}
    d = defaults(mech.size / mech.scale)
    narrowest = min((m.width for m in materials(mech).values()), default=d["width"])
    if narrowest < d["width"]:                       # [mass] bars narrower than the default: pins to suit
        d["pin_diameter"] = nice(narrowest * 0.4)
        d["clearance"] = nice(d["pin_diameter"] / 20.0)
    frame = section.get("frame")
    size = mech.size / mech.scale
    for key in ("pin_diameter", "clearance", "end_radius", "layer_gap"):
        if key in section and not float(section[key]) <= MAX_PART_FACTOR * size:
            raise ParameterError(f"{mech.definition.source}: parts.{key}: {float(section[key]):g} is more than "
                                 f"{MAX_PART_FACTOR:g} times the mechanism's size ({size:.4g} {mech.units}); give it "
                                 f"in the file's units ({mech.units})")
    return Settings(float(section.get("pin_diameter", d["pin_diameter"])),
                    float(section.get("clearance", d["clearance"])),
                    float(section["end_radius"]) if "end_radius" in section else None,
                    float(section.get("layer_gap", d["layer_gap"])),
                    tuple((float(x), float(y)) for x, y in frame) if frame else None,
                    dict(section.get("layers", {})))


def materials(mech) -> dict[str, Material]:
    """Each link's width, thickness (file units) and density: ``[mass]`` (link, else file-wide), else the
    defaults (and :data:`DEFAULT_DENSITY`)."""
    section = mech.definition.mass or {}
    d = defaults(mech.size / mech.scale)
    top = {k: section[k] for k in ("density", "width", "thickness") if k in section}
    per = section.get("links", {})
    out = {}
    for ln in mech.links:
        f = {**top, **per.get(ln, {})}
        if "density" in f:
            out[ln] = Material(float(f["width"]), float(f["thickness"]), float(f["density"]), True)
        else:
            out[ln] = Material(d["width"], d["thickness"], DEFAULT_DENSITY, False)
    return out


# ----------------------------------------------------------------------------------------------- motion
@dataclass(frozen=True)
class Sweep:
    """The links' frames over the samples: ``t`` [s], ``q`` the first input's value (rad or m),
    ``frames`` {link: (N, 3) array of origin x, y (file units) and angle [rad]}, ``points`` {P: (N, 2)}."""

    t: np.ndarray
    q: np.ndarray
    frames: dict
    points: dict


def frames_at(mech, t) -> Sweep:
    """Every link's frame at times ``t`` (file units)."""
    t = np.atleast_1d(np.asarray(t, dtype=float))
    (q, _, _), sol = mech.solve_at(t)
    if not sol.valid.all():
        mech.check_assembles(q[~sol.valid][:1])
    s = mech.scale
    pts = {p: np.column_stack([sol["x" + p], sol["y" + p]]) / s for p in mech.points}
    frames = {}
    for ln in mech.links:
        o = pts[mech.link_origins[ln]]
        ang = np.arctan2(sol["sin" + ln], sol["cos" + ln])
        frames[ln] = np.column_stack([o, ang])
    return Sweep(t, q[:, 0], frames, pts)


def cycle(mech, samples: int = 720) -> Sweep:
    """The frames over one cycle of the first input (a turn, or a rocking cycle), ``samples`` instants."""
    t = np.linspace(0.0, mech.duration(1.0), samples + 1)
    return frames_at(mech, t)


def to_local(frame, xy) -> np.ndarray:
    """World points ``xy`` (N, 2) in the frames (N, 3)."""
    d = np.asarray(xy) - frame[:, :2]
    c, s = np.cos(frame[:, 2]), np.sin(frame[:, 2])
    return np.column_stack([d[:, 0] * c + d[:, 1] * s, -d[:, 0] * s + d[:, 1] * c])


def to_world(frame, uv) -> np.ndarray:
    """Local points ``uv`` (k, 2) placed by one frame (ox, oy, angle): (k, 2)."""
    c, s = math.cos(frame[2]), math.sin(frame[2])
    uv = np.asarray(uv, dtype=float)
    return np.column_stack([frame[0] + uv[:, 0] * c - uv[:, 1] * s, frame[1] + uv[:, 0] * s + uv[:, 1] * c])


# ----------------------------------------------------------------------------------------------- parts
@dataclass(frozen=True)
class Hole:
    point: str
    x: float
    y: float
    r: float


@dataclass(frozen=True)
class Slot:
    """A slot of radius ``r`` from (x0, y0) to (x1, y1) (the pin centre's travel) for ``block``'s pin."""

    block: str
    x0: float
    y0: float
    x1: float
    y1: float
    r: float

    @property
    def outline(self) -> tuple[Arc, ...]:
        return shapes.hull([Disc(self.x0, self.y0, self.r), Disc(self.x1, self.y1, self.r)])


@dataclass(frozen=True)
class Part:
    """One link as a plate in its own frame (file units): ``outline`` (exact, counter-clockwise), holes,
    slots, the points it carries, its material; ``kind`` bar, plate, block or gear."""

    link: str
    kind: str
    outline: tuple[Arc, ...]
    holes: tuple[Hole, ...]
    slots: tuple[Slot, ...]
    points: dict
    width: float
    thickness: float
    density: float
    gear_radius: float | None = None

    @property
    def crossings(self) -> tuple[tuple[str, str], ...]:
        """(block, point) where the slot for block's pin runs into the hole at point (the two pins meet in
        the slot: a design that cannot be built as layered plates)."""
        return tuple((sl.block, h.point) for sl in self.slots for h in self.holes
                     if _segment_distance((h.x, h.y), (sl.x0, sl.y0), (sl.x1, sl.y1)) < sl.r + h.r)

    @property
    def length(self) -> float:
        """The largest distance between two of its points and slot ends (a bar's centre distance; a block: at
        least its side)."""
        pts = list(self.points.values()) + [(s.x0, s.y0) for s in self.slots] + [(s.x1, s.y1) for s in self.slots]
        out = max((math.hypot(a[0] - b[0], a[1] - b[1]) for a in pts for b in pts), default=0.0)
        return out if self.kind != "block" else max(out, self.width)

    def polygon(self, chord: float) -> np.ndarray:
        return shapes.tessellate(self.outline, chord)


def _joints_of(mech) -> dict[str, set[str]]:
    """{link: points where a revolute joint pins it}."""
    out: dict[str, set[str]] = {ln: set() for ln in mech.links}
    for j in mech.joints:
        if j.kind == "revolute":
            for ln in (j.a, j.b):
                if ln != GROUND:
                    out[ln].add(j.point)
    return out


def _wheels(mech) -> dict[str, tuple[str, float]]:
    """{link: (centre point, pitch radius [file units])} of the gears drawn on moving links."""
    from analytic import kinds
    (_, _, _), sol = mech.solve_at([0.0])
    pose = {p: (float(sol["x" + p][0]), float(sol["y" + p][0])) for p in mech.points}
    out = {}
    for e in mech.geometry.elements:
        for w in kinds.get(e["kind"]).wheels(e, pose):
            if w.link != GROUND:
                out[w.link] = (w.centre, w.radius / mech.scale)
    return out


PLATE_POINTS = 720
"""Corners of a cam plate's outline: chords of 0.5 deg sag (2 pi R / 720)^2 / (8 rho), under 1e-5 of R for a
radius of curvature down to R / 5 (the drawing, the DXF and the solids need nothing finer)."""


def _cam_plates(mech) -> tuple[dict, dict]:
    """({cam link: its outline (k, 2) in the cam's frame [file units], counter-clockwise}, {cam link: the
    pivot the outline is about}) of the mechanism's cams (:func:`analytic.cams.plate`: a given profile as given)."""
    from analytic import cams
    plates, pivots = {}, {}
    for e in cams.elements(mech).values():
        plates[e["cam"]] = cams.plate(e, n=PLATE_POINTS) / mech.scale
        pivots[e["cam"]] = e["pivot"]
    return plates, pivots


def _cam_outline(profile, pivot, hull, chord: float) -> tuple[Arc, ...]:
    """A cam plate's outline in its link's frame: the profile about the pivot (the link's frame and the cam's
    share their x-axis), as corners joined by straight lines; where the link's own hull of bosses reaches
    outside it (a pin beyond the cam), the union of the two, the hull tessellated within 1e-4 of its radius."""
    poly = np.asarray(profile) + np.asarray(pivot)
    import shapely
    cam = shapely.Polygon(poly)
    own = shapely.Polygon(shapes.tessellate(hull, 1e-4 * max(a.r for a in hull) if hull else chord)) if hull else None
    if own is not None and not cam.buffer(1e-9 * chord).contains(own):
        union = cam.union(own)
        if union.geom_type == "Polygon":
            poly = np.asarray(union.exterior.coords)[:-1]
            if shapely.Polygon(poly).exterior.is_ccw is False:
                poly = poly[::-1]
    return tuple(Arc(float(x), float(y), 0.0, 0.0, 0.0) for x, y in poly)


def _inside(arcs, p, tol: float) -> bool:
    """Whether point p lies in the convex shape (within tol): below its support in every edge normal."""
    normals = [a.a0 for a in arcs] + [a.a1 for a in arcs]
    return all(p[0] * math.cos(t) + p[1] * math.sin(t) <= shapes.support(arcs, math.cos(t), math.sin(t)) + tol
               for t in normals + list(np.linspace(0, 2 * math.pi, 64, endpoint=False)))


def _segment_distance(p, a, b) -> float:
    ax, ay = b[0] - a[0], b[1] - a[1]
    L2 = ax * ax + ay * ay
    t = 0.0 if L2 == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * ax + (p[1] - a[1]) * ay) / L2))
    return math.hypot(p[0] - a[0] - t * ax, p[1] - a[1] - t * ay)


def meshing(mech) -> tuple[tuple[str, str], ...]:
    """Pairs of moving links whose gears mesh (their pitch discs touch by design)."""
    return tuple((c.link, c.mesh) for c in mech.topology.couplings
                 if c.kind == "gear" and GROUND not in (c.link, c.mesh))


def build(mech, sweep: Sweep | None = None) -> dict[str, Part]:
    """Every link's part (see the module docstring), from the pose at t = 0 and, for slots, the cycle."""
    cfg = settings(mech)
    mats = materials(mech)
    sweep = sweep if sweep is not None else cycle(mech)
    size = mech.size / mech.scale
    joints = _joints_of(mech)
    wheels = _wheels(mech)
    plates, cam_pivots = _cam_plates(mech)
    hole_r = cfg.hole / 2.0
    local = {ln: {p: tuple(to_local(sweep.frames[ln][:1], sweep.points[p][:1])[0])
                  for p in mech.topology.links[ln].points} for ln in mech.links}
    slots: dict[str, list[Slot]] = {ln: [] for ln in mech.links}
    for j in mech.joints:
        if j.kind != "prismatic" or j.a == GROUND:
            continue
        path = to_local(sweep.frames[j.a], sweep.points[j.point])
        path = path[np.all(np.isfinite(path), axis=1)]
        c = path.mean(axis=0)
        u, sv, vt = np.linalg.svd(path - c, full_matrices=False)
        axis = vt[0]
        s = (path - c) @ axis
        lo, hi = c + s.min() * axis, c + s.max() * axis
        slots[j.a].append(Slot(j.b, float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]), hole_r))
    parts = {}
    for ln in mech.links:
        m = mats[ln]
        end_r = cfg.end_radius if cfg.end_radius is not None else m.width / 2.0
        if hole_r >= end_r - 1e-9 * size:
            raise ParameterError(
                f"{mech.definition.source}: parts: link {ln}: the hole (pin_diameter + clearance = {cfg.hole:g}) "
                f"leaves no material inside the end radius {end_r:g} [{mech.units}]; give a smaller [parts] "
                f"pin_diameter or a larger end_radius (or [mass] width)")
        block = ln in mech.slides and mech.topology.links[ln].block
        discs = []
        pts = local[ln]
        origin = mech.link_origins[ln]
        if block:
            h = m.width / 2.0
            discs += [Disc(sx * h, sy * h, 0.0) for sx in (-1, 1) for sy in (-1, 1)]
        carried = [p for p in pts if not (block and p == origin)]
        pinned = [p for p in carried if p in joints[ln]] or ([] if block else carried)
        discs += [Disc(*pts[p], end_r) for p in pinned]
        for sl in slots[ln]:
            discs += [Disc(sl.x0, sl.y0, end_r), Disc(sl.x1, sl.y1, end_r)]
        gear_r = None
        if ln in wheels:
            centre, gear_r = wheels[ln]
            discs.append(Disc(*pts[centre], gear_r))
        # a point that is no joint (a tracer) gets material round it unless it already lies on the part
        base = shapes.hull(discs, eps=1e-12 * size) if discs else ()
        for p in carried:
            if p not in pinned and not (base and _inside(base, pts[p], 1e-9 * size)):
                discs.append(Disc(*pts[p], end_r))
        outline = shapes.hull(discs, eps=1e-12 * size)
        if ln in plates:                               # a cam plate: its profile, with the link's bosses
            outline = _cam_outline(plates[ln], pts[cam_pivots[ln]], outline, cfg.end_radius or end_r)
        holes = tuple(Hole(p, pts[p][0], pts[p][1], hole_r) for p in mech.topology.links[ln].points if p in joints[ln])
        kind = "block" if block else "cam" if ln in plates else "gear" if gear_r else "bar" if len(pts) <= 2 and not slots[ln] else "plate"
        parts[ln] = Part(ln, kind, outline, holes, tuple(slots[ln]), dict(pts), 2.0 * end_r if not block else m.width,
                         m.thickness, m.density, gear_r)
    return parts


# ----------------------------------------------------------------------------------------------- mass
@dataclass(frozen=True)
class MassProperties:
    """A part's area [file units^2], volume [file units^3], mass [kg], centre of mass (cx, cy) in its frame
    [file units] and moment of inertia about it, about z [kg m^2]."""

    area: float
    volume: float
    m: float
    cx: float
    cy: float
    I: float


def mass_properties(part: Part, scale: float) -> MassProperties:
    """Exact area moments of the outline less holes and slots (Green's theorem on lines and arcs), times
    the thickness and density; ``scale``: metres per file unit. Where a slot runs into a hole (see
    :attr:`Part.crossings`) the cut-outs overlap: then the moments of the tessellated region (chord 1e-6
    of the part's size)."""
    if part.crossings:
        return _polygon_mass(part, scale)
    A, Sx, Sy, J = shapes.moments(part.outline)
    for h in part.holes:
        a, sx, sy, j = shapes.disc_moments(Disc(h.x, h.y, h.r))
        A, Sx, Sy, J = A - a, Sx - sx, Sy - sy, J - j
    for sl in part.slots:
        a, sx, sy, j = shapes.moments(sl.outline)
        A, Sx, Sy, J = A - a, Sx - sx, Sy - sy, J - j
    cx, cy = Sx / A, Sy / A
    Jc = J - A * (cx * cx + cy * cy)
    rho_t = part.density * part.thickness * scale           # kg per file unit^2
    return MassProperties(A, A * part.thickness, rho_t * A * scale * scale, cx, cy, rho_t * Jc * scale ** 4)


def _polygon_mass(part: Part, scale: float) -> MassProperties:
    import shapely
    size = max(abs(a.x) + a.r for a in part.outline) + max(abs(a.y) + a.r for a in part.outline)
    chord = 1e-6 * size
    cuts = [shapely.Polygon(shapes.tessellate(shapes.hull([Disc(h.x, h.y, h.r)]), chord)) for h in part.holes]
    cuts += [shapely.Polygon(shapes.tessellate(sl.outline, chord)) for sl in part.slots]
    region = shapely.Polygon(part.polygon(chord)).difference(shapely.union_all(cuts))
    tri = shapely.get_parts(shapely.constrained_delaunay_triangles(region))
    A = Sx = Sy = J = 0.0
    for t in tri:
        (x0, y0), (x1, y1), (x2, y2) = list(t.exterior.coords)[:3]
        a = 0.5 * abs((x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0))
        xs, ys = (x0, x1, x2), (y0, y1, y2)
        A += a
        Sx += a * sum(xs) / 3
        Sy += a * sum(ys) / 3
        J += a / 6 * (sum(x * x for x in xs) + xs[0] * xs[1] + xs[1] * xs[2] + xs[2] * xs[0]
                      + sum(y * y for y in ys) + ys[0] * ys[1] + ys[1] * ys[2] + ys[2] * ys[0])
    cx, cy = Sx / A, Sy / A
    rho_t = part.density * part.thickness * scale
    return MassProperties(A, A * part.thickness, rho_t * A * scale * scale, cx, cy,
                          rho_t * (J - A * (cx * cx + cy * cy)) * scale ** 4)
