"""The parts in MuJoCo: every link's solid (its outline extruded to its thickness, at its layer's height) on
a free body posed from the analytic motion, contacts on between the solids of one layer only (a contype /
conaffinity bit per layer) and against the optional frame (on layer 0); meshing gears excluded (their pitch
discs touch by design). MuJoCo collides a mesh as its convex hull: every part is one convex plate (holes do
not change its hull), the frame a set of triangles.

:func:`sweep` poses the solids at given instants and reads MuJoCo's contacts (``mj_collision``) and its
signed distances (``mj_geomDistance``, negative: penetration) of every same-layer pair. Lengths are in the
file's unit (MuJoCo does not care which)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from analytic.parts import layers as lay
from analytic.parts import model

MAX_LAYERS_BITS = 31

NATIVE_OFF = int(mujoco.mjtDisableBit.mjDSBL_NATIVECCD)
"""Contacts (``mj_collision``) come from libccd, distances (``mj_geomDistance``) from MuJoCo's native convex
collider: the native one missed about 1 % of the contacts between these flat prisms (no contact and a distance
of exactly 0 at 0.003 mm penetration, at any tolerance; 4 of 400 poses of a planted collision), libccd found
every one that the plane test finds (721 poses); libccd's ``mj_geomDistance`` is not a distance (53 mm
"penetration" of 6 mm plates), the native one agrees with the plane test to 1e-8 of the size."""

INSET = 1e-3
"""The k-th solid of a layer is inset k x INSET of its thickness at both faces: solids of one layer with
coplanar faces make MuJoCo's convex collision degenerate (face on face), and it then misses contacts now
and then (a four-bar's crank and rocker: no contact reported at 0.0025 mm penetration). The plane geometry
is untouched; a penetration deeper than the solids' common thickness reads as that thickness."""


@dataclass(frozen=True)
class Scene:
    model: mujoco.MjModel
    links: tuple[str, ...]
    pairs: tuple[tuple[str, str], ...]
    """The pairs in contact range: a layer in common (and FRAME with each layer-0 link), meshing gears left out."""
    geoms: dict
    """{link: geom id, or a tuple of one per plate for a two-plate link}; FRAME: the frame triangles' geom ids
    (a tuple); ``pin_P``: the pin at P (:func:`ids` reads either)."""
    pins: tuple = ()
    """The points whose pins are solids here (cylinders of ``pin_diameter`` over the pin's span, posed at the
    point, touching only the links of the layers they pass, not those pinned on them)."""


def _prism(poly: np.ndarray, z0: float, z1: float) -> np.ndarray:
    return np.vstack([np.column_stack([poly, np.full(len(poly), z0)]), np.column_stack([poly, np.full(len(poly), z1)])])


PIN_BIT = 1 << 30


def build(mech, parts: dict, layout: lay.Layout, chord: float, pins=()) -> Scene:
    spec = mujoco.MjSpec()
    spec.modelname = f"{mech.name}_parts"
    spec.option.ccd_tolerance = 1e-10
    spec.option.ccd_iterations = 500
    spec.option.disableflags = NATIVE_OFF
    spec.option.gravity = [0.0, 0.0, 0.0]
    links = tuple(parts)
    if layout.count > MAX_LAYERS_BITS:
        raise ValueError(f"{layout.count} layers: the contact bits hold {MAX_LAYERS_BITS}")
    rank: dict[int, int] = {}
    names: dict = {}
    for ln in links:
        body = spec.worldbody.add_body(name=ln)
        body.add_freejoint(name=ln)
        body.explicitinertial = True                 # posed, never simulated: any regular inertia will do
        body.mass = 1.0
        body.inertia = [1.0, 1.0, 1.0]
        for n, (layer, (z0, z1)) in enumerate(layout.plates(ln)):   # a two-plate link: a solid per plate
            name = ln if n == 0 else f"{ln}#{n + 1}"
            k = rank[layer] = rank.get(layer, -1) + 1
            inset = INSET * k * (z1 - z0)            # no two solids of a layer share a face plane
            z0, z1 = z0 + inset, z1 - inset
            mesh = spec.add_mesh(name=f"solid_{name}")
            mesh.uservert = _prism(parts[ln].polygon(chord), z0, z1).ravel().tolist()
            bit = 1 << layer
            body.add_geom(name=name, type=mujoco.mjtGeom.mjGEOM_MESH, meshname=f"solid_{name}", contype=bit,
                          conaffinity=bit, density=0.0, margin=0.0)
            names.setdefault(ln, []).append(name)
    for a, b in layout.meshing:
        spec.add_exclude(bodyname1=a, bodyname2=b)
    cfg = model.settings(mech)
    frame_geoms = []
    if cfg.frame:
        out = lay.Outlines({}, np.asarray(cfg.frame, dtype=float), chord)
        zs = [zz for ln in links for k, zz in layout.plates(ln) if k == 0]
        z0, z1 = (min(z[0] for z in zs), max(z[1] for z in zs)) if zs else (0.0, 1.0)
        for k, tri in enumerate(lay.frame_parts(out)):
            mesh = spec.add_mesh(name=f"frame_{k}")
            mesh.uservert = _prism(tri, z0, z1).ravel().tolist()
            spec.worldbody.add_geom(name=f"frame_{k}", type=mujoco.mjtGeom.mjGEOM_MESH, meshname=f"frame_{k}",
                                    contype=1, conaffinity=1, margin=0.0)
            frame_geoms.append(f"frame_{k}")
    for p in pins:
        lo, hi = layout.pins[p]
        body = spec.worldbody.add_body(name=f"pin_{p}")
        body.add_freejoint(name=f"pin_{p}")
        body.explicitinertial = True
        body.mass = 1.0
        body.inertia = [1.0, 1.0, 1.0]
        bits = 0
        for ln in links:
            for layer, (z0, z1) in layout.plates(ln):
                if z0 < hi and z1 > lo:
                    bits |= 1 << layer
        body.add_geom(name=f"pin_{p}", type=mujoco.mjtGeom.mjGEOM_CYLINDER, size=[cfg.pin_diameter / 2, (hi - lo) / 2, 0],
                      pos=[0, 0, (lo + hi) / 2], contype=PIN_BIT, conaffinity=bits, density=0.0, margin=0.0)
        spec.add_exclude(bodyname1="world", bodyname2=f"pin_{p}")
        for ln, part in parts.items():                # the links it passes through, in their holes or slots
            held = pins_of(mech, parts, p)
            if ln in held:
                spec.add_exclude(bodyname1=ln, bodyname2=f"pin_{p}")
    m = spec.compile()
    geoms = {ln: m.geom(ln).id if len(names[ln]) == 1 else tuple(m.geom(g).id for g in names[ln]) for ln in links}
    geoms[lay.FRAME] = tuple(m.geom(g).id for g in frame_geoms)
    geoms.update({f"pin_{p}": m.geom(f"pin_{p}").id for p in pins})
    mesh_pairs = {frozenset(p) for p in layout.meshing}
    on = {ln: {k for k, _ in layout.plates(ln)} for ln in links}
    pairs = [(a, b) for i, a in enumerate(links) for b in links[i + 1:]
             if on[a] & on[b] and frozenset((a, b)) not in mesh_pairs]
    if frame_geoms:
        pairs += [(ln, lay.FRAME) for ln in links if 0 in on[ln]]
    return Scene(m, links, tuple(pairs), geoms, tuple(pins))


def pins_of(mech, parts: dict, point: str) -> set:
    """The links a pin at ``point`` runs through: those with a hole there and those whose slot it slides in."""
    pinned = {ln for ln, part in parts.items() if any(h.point == point for h in part.holes)}
    return pinned | {ln for ln, part in parts.items() if any(sl.block in pinned for sl in part.slots)}


@dataclass(frozen=True)
class Swept:
    """Per pair (in ``Scene.pairs`` order): MuJoCo's signed distance at each instant (N,), and the
    contacts ``mj_collision`` found: {pair index: (N,) bool}."""

    distance: np.ndarray
    contact: np.ndarray


def pose(scene: Scene, data: mujoco.MjData, sweep: model.Sweep, k: int) -> None:
    for ln in scene.links:
        x, y, a = sweep.frames[ln][k]
        adr = scene.model.jnt_qposadr[scene.model.joint(ln).id]
        data.qpos[adr:adr + 7] = [x, y, 0.0, math.cos(a / 2), 0.0, 0.0, math.sin(a / 2)]
    for p in scene.pins:
        x, y = sweep.points[p][k]
        adr = scene.model.jnt_qposadr[scene.model.joint(f"pin_{p}").id]
        data.qpos[adr:adr + 7] = [x, y, 0.0, 1.0, 0.0, 0.0, 0.0]
    mujoco.mj_kinematics(scene.model, data)
    mujoco.mj_collision(scene.model, data)


def ids(scene: Scene, name: str) -> tuple:
    """The geom ids of a link (one per plate), the frame's triangles or a pin."""
    g = scene.geoms[name]
    return tuple(g) if isinstance(g, tuple) else (g,)


def in_contact(scene: Scene, data: mujoco.MjData, a: str, b: str) -> bool:
    """Whether ``mj_collision`` found a penetrating contact between ``a`` and ``b`` (after :func:`pose`)."""
    ga = set(ids(scene, a))
    gb = set(ids(scene, b))
    for c in data.contact[:data.ncon]:
        g = {int(c.geom[0]), int(c.geom[1])}
        if c.dist < 0 and g & ga and g & gb:
            return True
    return False


def distance(scene: Scene, data: mujoco.MjData, a: str, b: str, distmax: float) -> float:
    opt = scene.model.opt
    opt.disableflags = opt.disableflags & ~NATIVE_OFF
    try:
        return min(mujoco.mj_geomDistance(scene.model, data, ga, gb, distmax, None)
                   for ga in ids(scene, a) for gb in ids(scene, b))
    finally:
        opt.disableflags = opt.disableflags | NATIVE_OFF


def sweep(scene: Scene, sw: model.Sweep, distmax: float) -> Swept:
    """MuJoCo's distances and contacts of the scene's pairs at every instant of ``sw``."""
    data = mujoco.MjData(scene.model)
    n = len(sw.t)
    dist = np.full((len(scene.pairs), n), np.nan)
    contact = np.zeros((len(scene.pairs), n), dtype=bool)
    body_of = {g: name for name in scene.geoms for g in ids(scene, name)}
    index = {frozenset(p): i for i, p in enumerate(scene.pairs)}
    for k in range(n):
        pose(scene, data, sw, k)
        for c in data.contact[:data.ncon]:
            key = frozenset((body_of.get(int(c.geom[0])), body_of.get(int(c.geom[1]))))
            if key in index and c.dist < 0:
                contact[index[key], k] = True
        for i, (a, b) in enumerate(scene.pairs):
            dist[i, k] = distance(scene, data, a, b, distmax)
    return Swept(dist, contact)
