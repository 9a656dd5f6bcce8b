"""The mass model: every link's mass, centre of mass and moment of inertia about it (SI), read the same way
by the analytic forces, the drive torques and the MuJoCo model.

A link's frame has its origin at the link's first point (``Mechanism.link_origins``) and its x-axis at its
angle ``phiL``; a centre of mass ``(cx, cy)`` is given in that frame. Per link, the first that applies:

1. ``given`` (the command line's ``--inertia``, already in SI);
2. the file's ``[inertia]`` table (file units: m in kg, cx, cy in the length unit, I in kg unit^2);
3. with a ``[parts]`` section (:mod:`analytic.parts`): the link's part, exactly (its outline less its holes and
   slots, :func:`analytic.parts.model.mass_properties`), made of ``[mass]``'s material where it gives one and of
   the parts' defaults (printed PLA) where not: the bill of materials' masses are the analysis's (:func:`sources`
   says which of these gave each link); a link the parts' layering makes of two plates (a clevis,
   :func:`analytic.parts.layers.layout`) weighs both: twice the mass and the moment of inertia, the same centre;
4. the file's ``[mass]`` section: the link as **bars** (a bar of ``width`` x ``thickness`` from the link's
   origin to each of its other points, density ``density``) or as a **plate** (the convex hull of its points,
   ``thickness`` thick; a hull without area, two points or points on a line, is a bar of ``width``); a sliding
   block is a square of side ``width``, ``thickness`` thick, centred on its pin;
5. the default: slender bars of :data:`LINEAR_DENSITY` (1 kg/m) from the origin to each point (a star of bars
   for a link with several points), a block a small mass at its pin (0.1 size kg), with a floor on the moment
   of inertia (1 % of the size as radius of gyration) that keeps MuJoCo's bodies regular.

Counterweights (``[mass.counterweights]``: a point mass ``m`` at ``at`` in the link's frame, or a list of
them per link) are added to the
link's inertia whichever of the above gave it. Everything here is pure: numbers in, numbers out.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic._common import ParameterError

__all__ = ["Inertia", "Material", "Counterweight", "LINEAR_DENSITY", "BLOCK_FRACTION", "GYRATION_FLOOR",
           "SHAPES", "bars", "plate", "block", "polygon", "convex_hull", "combine", "add_counterweights",
           "materials", "counterweights", "local_points", "default", "link_inertia", "parts_inertias", "sources", "model"]

MAX_MAGNITUDE = 1e12
"""The largest magnitude of an inertial value (as every other number the command line takes): a mass of
1e12 kg or a moment of inertia of 1e12 kg mm^2 is already no linkage; larger overflows the forces."""


@dataclass(frozen=True)
class Inertia:
    """Inertial data of one body: mass ``m`` [kg], centre of mass ``(cx, cy)`` [m] in the body's frame
    (the frames of the MJCF bodies: origin at the body's first joint, x along the link) and moment of
    inertia ``I`` [kg m^2] about the centre of mass, about z."""

    m: float
    cx: float
    cy: float
    I: float

    def __post_init__(self):
        for name in ("m", "cx", "cy", "I"):
            v = getattr(self, name)
            try:                                   # an int past float range (a 400-digit number) overflows
                ok = isinstance(v, (int, float)) and not isinstance(v, bool) and abs(float(v)) <= MAX_MAGNITUDE
            except OverflowError:
                ok = False
            if not ok:
                text = repr(v) if len(repr(v)) <= 40 else repr(v)[:37] + "..."
                raise ParameterError(f"inertia {name}={text} must be a finite number of magnitude <= "
                                     f"{MAX_MAGNITUDE:g}")
        if self.m < 0:
            raise ParameterError(f"mass m={self.m!r} must be >= 0 [kg] (0: a massless link)")
        if self.I < 0:
            raise ParameterError(f"moment of inertia I={self.I!r} must be >= 0 [kg m^2] (about the centre of mass)")
        if self.m == 0 and self.I > 0:
            raise ParameterError(f"mass m={self.m!r} with I={self.I!r}: a massless link has no moment of inertia; give "
                                 f"I = 0 too, or a mass > 0 [kg]")



LINEAR_DENSITY = 1.0
"""[kg/m] Default mass per length of a link: a slender bar (a 12.8 mm steel rod)."""

BLOCK_FRACTION = 0.1
"""A default block weighs as a bar of this fraction of the mechanism's size (its inertia: a square of that
side, I = m a^2 / 6)."""

GYRATION_FLOOR = 0.01
"""The default model's moment of inertia is at least m (GYRATION_FLOOR x size)^2 (a link whose points all
lie on one line through its origin would otherwise have I = 0 in MuJoCo)."""

SHAPES = ("bar", "plate")


@dataclass(frozen=True)
class Material:
    """How a link is made, from the file's ``[mass]`` section (SI): ``shape`` "bar" or "plate", ``density``
    [kg/m^3], ``width`` and ``thickness`` [m]."""

    shape: str
    density: float
    width: float
    thickness: float


@dataclass(frozen=True)
class Counterweight:
    """A point mass ``m`` [kg] fixed to ``link`` at ``(u, v)`` [m] in the link's frame."""

    link: str
    m: float
    u: float
    v: float


# ------------------------------------------------------------------------------------------ shapes
def bars(points, linear_density: float, width: float = 0.0) -> Inertia | None:
    """A star of straight bars from the frame's origin to each of ``points`` ((u, v) [m]), of
    ``linear_density`` [kg/m] and in-plane ``width`` [m]: each bar of length L weighs lambda L, its centre of
    mass at its middle, I = m (L^2 + w^2) / 12 about it (a rectangle L x w). None when every point is at the
    origin (no bar)."""
    segs = [(math.hypot(u, v), u / 2, v / 2) for u, v in points]
    segs = [s for s in segs if s[0] > 0.0]
    if not segs:
        return None
    masses = [linear_density * L for L, _, _ in segs]
    m = sum(masses)
    cx = sum(mi * x for mi, (_, x, _) in zip(masses, segs)) / m
    cy = sum(mi * y for mi, (_, _, y) in zip(masses, segs)) / m
    inertia = sum(mi * ((L * L + width * width) / 12 + (x - cx) ** 2 + (y - cy) ** 2)
                  for mi, (L, x, y) in zip(masses, segs))
    return Inertia(m=m, cx=cx, cy=cy, I=inertia)


def convex_hull(points) -> list[tuple[float, float]]:
    """The convex hull of 2-D points, counter-clockwise, without collinear points (Andrew's monotone chain)."""
    pts = sorted(set((float(u), float(v)) for u, v in points))
    if len(pts) < 3:
        return pts

    def turn(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and turn(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and turn(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def polygon(vertices) -> tuple[float, float, float, float]:
    """(area, cx, cy, J) of a simple polygon (vertices counter-clockwise): its area [m^2], centroid and polar
    second moment of area about the centroid [m^4], by the shoelace sums."""
    a = cx = cy = jo = 0.0
    n = len(vertices)
    for k in range(n):
        x0, y0 = vertices[k]
        x1, y1 = vertices[(k + 1) % n]
        c = x0 * y1 - x1 * y0
        a += c
        cx += (x0 + x1) * c
        cy += (y0 + y1) * c
        jo += (x0 * x0 + x0 * x1 + x1 * x1 + y0 * y0 + y0 * y1 + y1 * y1) * c
    a *= 0.5
    cx /= 6 * a
    cy /= 6 * a
    jo /= 12
    return a, cx, cy, jo - a * (cx * cx + cy * cy)


def plate(points, material: Material, size: float) -> Inertia | None:
    """A flat plate: the convex hull of the link's points (its origin (0, 0) included), ``thickness`` thick;
    m = rho t A, I = rho t J. A hull without area (two points, or points on one line) is a bar of
    ``width``. None when every point is at the origin."""
    pts = [(0.0, 0.0)] + [tuple(p) for p in points]
    hull = convex_hull(pts)
    if len(hull) >= 3:
        area, cx, cy, J = polygon(hull)
        if area > 1e-12 * size * size:
            k = material.density * material.thickness
            return Inertia(m=k * area, cx=cx, cy=cy, I=k * J)
    return bars(points, material.density * material.width * material.thickness, material.width)


def block(material: Material | None, size: float) -> Inertia:
    """A sliding block centred on its pin: with a material, a square of side ``width``, ``thickness`` thick
    (m = rho w^2 t, I = m w^2 / 6); by default a bar of BLOCK_FRACTION x size at LINEAR_DENSITY with the
    inertia of a square of that side."""
    if material is None:
        a = BLOCK_FRACTION * size
        m = LINEAR_DENSITY * a
        return Inertia(m=m, cx=0.0, cy=0.0, I=m * a * a / 6)
    w = material.width
    m = material.density * w * w * material.thickness
    return Inertia(m=m, cx=0.0, cy=0.0, I=m * w * w / 6)


def combine(parts) -> Inertia:
    """One rigid body from several (mass, cx, cy, I about its own centre): masses add, the centre of mass is
    their weighted mean, moments of inertia move to it by the parallel-axis theorem."""
    parts = list(parts)
    m = sum(p[0] for p in parts)
    if m == 0:                                       # massless parts: a massless body
        return Inertia(m=0.0, cx=0.0, cy=0.0, I=0.0)
    cx = sum(p[0] * p[1] for p in parts) / m
    cy = sum(p[0] * p[2] for p in parts) / m
    inertia = sum(p[3] + p[0] * ((p[1] - cx) ** 2 + (p[2] - cy) ** 2) for p in parts)
    return Inertia(m=m, cx=cx, cy=cy, I=inertia)


def add_counterweights(b: Inertia, weights) -> Inertia:
    """The link ``b`` with point masses (Counterweight) fixed to it."""
    weights = list(weights)
    if not weights:
        return b
    return combine([(b.m, b.cx, b.cy, b.I)] + [(w.m, w.u, w.v, 0.0) for w in weights])


# ----------------------------------------------------------------------------------- from a file
def materials(mech) -> dict[str, Material]:
    """Each link's material from the file's ``[mass]`` section (links without one: not listed), SI."""
    section = mech.definition.mass or {}
    s = mech.scale
    top = {k: section[k] for k in ("shape", "density", "width", "thickness") if k in section}
    per = section.get("links", {})
    out = {}
    for ln in mech.links:
        f = {**top, **per.get(ln, {})}
        if "density" not in f:
            continue
        out[ln] = Material(f.get("shape", "bar"), float(f["density"]), float(f["width"]) * s,
                           float(f["thickness"]) * s)
    return out


def counterweights(mech) -> tuple[Counterweight, ...]:
    """The file's counterweights (``[mass.counterweights]``), SI."""
    s = mech.scale
    table = (mech.definition.mass or {}).get("counterweights", {})
    return tuple(Counterweight(ln, float(w["m"]), float(w["at"][0]) * s, float(w["at"][1]) * s)
                 for ln, entry in table.items() for w in (entry if isinstance(entry, list) else [entry]))


def local_points(mech, points=None, frames=None) -> dict[str, dict[str, tuple[float, float]]]:
    """Every link's points in its own frame [m]: from world positions ``points`` {P: (x, y)} and link poses
    ``frames`` {L: (ox, oy, angle)} at one instant, or (None) from the mechanism solved at t = 0."""
    if points is None or frames is None:
        q, qd, qdd = mech.drive(np.array([0.0]))
        sol = mech.solve(q, 0.0, 0.0, outputs=[c + p for p in mech.points for c in ("x", "y")]
                         + [c + ln for ln in mech.links for c in ("cos", "sin")])
        points = {p: (float(sol["x" + p][0]), float(sol["y" + p][0])) for p in mech.points}
        frames = {ln: (points[mech.link_origins[ln]][0], points[mech.link_origins[ln]][1],
                       math.atan2(float(sol["sin" + ln][0]), float(sol["cos" + ln][0]))) for ln in mech.links}
    out = {}
    for ln, link in mech.topology.links.items():
        ox, oy, th = frames[ln]
        c, s = math.cos(th), math.sin(th)
        out[ln] = {p: ((points[p][0] - ox) * c + (points[p][1] - oy) * s,
                       -(points[p][0] - ox) * s + (points[p][1] - oy) * c) for p in link.points}
    return out


def default(mech, link: str, local: dict[str, tuple[float, float]]) -> Inertia:
    """The default model of ``link`` (slender bars of LINEAR_DENSITY; a block: BLOCK_FRACTION x size), from
    its points in its frame ``local``."""
    size = mech.size
    origin = mech.link_origins[link]
    pts = [xy for p, xy in local.items() if p != origin]
    b = None if link in mech.slides else bars(pts, LINEAR_DENSITY)
    if b is None or all(math.hypot(u, v) < 1e-12 * size for u, v in pts):
        return block(None, size)
    return Inertia(m=b.m, cx=b.cx, cy=b.cy, I=max(b.I, b.m * (GYRATION_FLOOR * size) ** 2))


def link_inertia(mech, link: str, local: dict[str, tuple[float, float]],
                 material: Material | None = None) -> Inertia:
    """The inertia of ``link`` made of ``material`` (bars or a plate; None: the default), before any
    counterweight; ``local``: its points in its frame [m]."""
    if material is None:
        return default(mech, link, local)
    size = mech.size
    origin = mech.link_origins[link]
    pts = [xy for p, xy in local.items() if p != origin]
    if link in mech.slides:
        return block(material, size)
    if material.shape == "plate":
        b = plate(pts, material, size)
    else:
        b = bars(pts, material.density * material.width * material.thickness, material.width)
    return b if b is not None else block(material, size)


def model(mech, given: dict | None = None, local=None, parts: dict | None = None,
          layout=None) -> dict[str, Inertia]:
    """Every link's inertia (SI; see the module docstring for the precedence), counterweights included.

    Parameters
    ----------
    mech : analytic.Mechanism
    given : dict, optional
        {link: Inertia} in SI that replace the rest (``--inertia``).
    local : dict, optional
        Every link's points in its frame (:func:`local_points`); computed at t = 0 when None.
    parts : dict, optional
        The links' parts already built ({link: analytic.parts.model.Part}), for a file with ``[parts]``; built
        here when None.
    layout : analytic.parts.layers.Layout, optional
        Their layering (which links are two plates), with ``parts``; made here when None.
    """
    given = dict(given or {})
    unknown = set(given) - set(mech.links)
    if unknown:
        raise ParameterError(f"inertia: the {mech.name} has no link {sorted(unknown)[0]!r}; links: "
                             f"{', '.join(mech.links)}")
    local = local if local is not None else local_points(mech)
    mats = materials(mech)
    s = mech.scale
    table = mech.definition.inertia or {}
    source = sources(mech, given)
    from_parts = parts_inertias(mech, parts, layout) if "parts" in source.values() else {}
    weights: dict[str, list] = {}
    for w in counterweights(mech):
        weights.setdefault(w.link, []).append(w)
    out = {}
    for ln in mech.links:
        if source[ln] == "--inertia":
            b = given[ln]
        elif source[ln] == "[inertia]":
            v = table[ln]
            b = Inertia(m=float(v["m"]), cx=float(v.get("cx", 0.0)) * s, cy=float(v.get("cy", 0.0)) * s,
                        I=float(v["I"]) * s * s)
        elif source[ln] == "parts":
            b = from_parts[ln]
        else:
            b = link_inertia(mech, ln, local[ln], mats.get(ln))
        out[ln] = add_counterweights(b, weights.get(ln, ()))
    return out


def sources(mech, given: dict | None = None) -> dict[str, str]:
    """What gives each link's inertia (the module docstring's order): ``"--inertia"``, ``"[inertia]"``,
    ``"parts"`` (the file has a ``[parts]`` section), ``"[mass]"`` or ``"default"``; counterweights come on top
    of any of them."""
    given = given or {}
    table = mech.definition.inertia or {}
    has_parts = bool(getattr(mech.definition, "parts", None))
    mats = materials(mech)
    return {ln: "--inertia" if ln in given else "[inertia]" if ln in table else "parts" if has_parts
            else "[mass]" if ln in mats else "default" for ln in mech.links}


def parts_inertias(mech, parts: dict | None = None, layout=None) -> dict[str, Inertia]:
    """Every link's inertia (SI, its frame) from its part (:mod:`analytic.parts`): the exact mass properties of
    its outline less its holes and slots, as the bill of materials gives them; a link the layering makes of two
    plates (:meth:`analytic.parts.layers.Layout.plates`) counts both (mass and I twice, the centre the same).
    ``parts`` and ``layout``: as the caller built them (the bill of materials); else built here over one sweep
    of the cycle (the layering needs the sweep: only files whose masses come from ``[parts]`` pay for it)."""
    from analytic.parts import layers
    from analytic.parts import model as parts_model
    if parts is None or layout is None:
        sweep = parts_model.cycle(mech)
        parts = parts if parts is not None else parts_model.build(mech, sweep)
        layout = layers.layout(mech, parts, sweep)
    s = mech.scale
    out = {}
    for ln, part in parts.items():
        mp = parts_model.mass_properties(part, s)
        n = len(layout.plates(ln))
        out[ln] = Inertia(m=n * mp.m, cx=mp.cx * s, cy=mp.cy * s, I=n * mp.I)
    return out
