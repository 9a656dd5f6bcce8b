"""How a model looks in MuJoCo's renderer: link capsules and pins, sliding blocks, ground pivots and rails,
the top camera framing every point's path."""

from __future__ import annotations

import math

import mujoco
import numpy as np

from sim.model.frames import point_local, quat

COLORS = ["crank", "coupler", "rocker", "slider", "ground"]


def draw_link(spec, body, mech, points, frames, link, members, radius, material):
    origin = mech.link_origins[link]
    if _draw_cylinder_part(body, mech, points, link, radius):
        return
    if link in mech.slides:
        s = 0.04 * mech.size
        body.add_geom(name=link, type=mujoco.mjtGeom.mjGEOM_BOX, size=[1.6 * s, s, 0.5 * radius],
                      pos=[0, 0, 2 * radius], material="slider", contype=0, conaffinity=0, density=0)
        return
    z = 2.0 * radius * (len(spec.geoms) % 3)
    for k, p in enumerate(sorted(members[link] - {origin})):
        x, y = point_local(points, frames, link, p)
        if math.hypot(x, y) > 1e-6 * mech.size:           # a point on the link's pin gets no bar (MuJoCo refuses it)
            body.add_geom(name=f"{link}_{p}", type=mujoco.mjtGeom.mjGEOM_CAPSULE, size=[radius, 0, 0],
                          fromto=[0, 0, z, x, y, z], material=material, contype=0, conaffinity=0, density=0)
        body.add_geom(name=f"pin_{link}_{p}", type=mujoco.mjtGeom.mjGEOM_CYLINDER,
                      size=[1.4 * radius, 0.7 * radius, 0], pos=[x, y, z + radius], material="pin",
                      contype=0, conaffinity=0, density=0)
    body.add_geom(name=f"pin_{link}_{origin}", type=mujoco.mjtGeom.mjGEOM_CYLINDER,
                  size=[1.4 * radius, 0.7 * radius, 0], pos=[0, 0, z + radius], material="pin",
                  contype=0, conaffinity=0, density=0)


def _draw_cylinder_part(body, mech, points, link, radius) -> bool:
    """A linear actuator's barrel (a wide capsule from its pin along the cylinder) or rod (a thin one from its
    pin back into the barrel), as the videos draw them (sim.output.drawing); False for any other link. Both
    bodies' x-axes point along the cylinder, base -> end."""
    from analytic import kinds
    from analytic.kinds.base import BARREL, ROD_INSIDE
    for e in mech.geometry.elements:
        for c in kinds.get(e["kind"]).cylinders(e):
            if link not in (c.barrel, c.rod):
                continue
            (bx, by), (ex, ey) = points[c.base], points[c.end]
            l0 = math.hypot(ex - bx, ey - by)
            wide = max(1.5 * radius, 0.5 * c.bore)
            x0, x1, r = ((0.0, BARREL * c.retracted, wide) if link == c.barrel
                         else (-(l0 - ROD_INSIDE * c.retracted), 0.0, 0.45 * wide))
            if x1 - x0 > 1e-6 * mech.size:
                body.add_geom(name=f"{link}_{'barrel' if link == c.barrel else 'rod'}", type=mujoco.mjtGeom.mjGEOM_CAPSULE,
                              size=[r, 0, 0], fromto=[x0, 0, -radius, x1, 0, -radius],
                              material="ground" if link == c.barrel else "slider", contype=0, conaffinity=0, density=0)
            body.add_geom(name=f"pin_{link}", type=mujoco.mjtGeom.mjGEOM_CYLINDER, size=[1.4 * radius, 0.7 * radius, 0],
                          pos=[0, 0, radius], material="pin", contype=0, conaffinity=0, density=0)
            return True
    return False


def draw_ground(spec, mech, points, radius, cycle=None):
    world = spec.worldbody
    for g in mech.ground_points:
        x, y = points[g]
        world.add_geom(name=f"ground_{g}", type=mujoco.mjtGeom.mjGEOM_BOX,
                       size=[3 * radius, 2 * radius, 0.7 * radius], pos=[x, y - 2 * radius, -2 * radius],
                       material="ground", contype=0, conaffinity=0)
    # ground guide lines: a rail over the block's travel
    from analytic import kinds
    rails = [r for e in mech.geometry.elements for r in kinds.get(e["kind"]).rails(e)]
    if rails:
        sol = _cycle(mech, cycle).solution
    for block, g, off in rails:
        s = sol["s" + block]
        lo, hi = float(np.nanmin(s)), float(np.nanmax(s))
        ox, oy = (points[g["through"]] if isinstance(g["through"], str) else g["through"])
        c, sn = math.cos(g["angle"]), math.sin(g["angle"])
        mid = 0.5 * (lo + hi)
        world.add_geom(name=f"rail_{block}", type=mujoco.mjtGeom.mjGEOM_BOX,
                       size=[0.5 * (hi - lo) + 3 * radius, 0.4 * radius, 0.2 * radius],
                       pos=[ox + mid * c - off * sn, oy + mid * sn + off * c, -2 * radius],
                       quat=quat(g["angle"]), material="ground", contype=0, conaffinity=0)


def frame_camera(spec, mech, aspect: float = 4 / 3, cycle=None) -> None:
    center, extent = framing(mech, aspect, cycle)
    cam = spec.camera("top")
    cam.pos = [center[0], center[1], 10.0 * extent]
    cam.fovy = extent
    paper = spec.geom("paper")
    paper.pos = [center[0], center[1], -0.1 * extent]
    paper.size = [2 * extent, 2 * extent, 0.01]
    spec.visual.map.znear = 0.001
    spec.stat.extent = extent


def _cycle(mech, cycle=None):
    """The run's cycle (analytic.cycle.Cycle), or where none was handed over, one turn's, made here."""
    from analytic.cycle import Cycle
    return cycle if cycle is not None else Cycle.of(mech)


def path_points(mech, cycle=None) -> np.ndarray:
    """Every point at the samples of the run's ``cycle`` (analytic.cycle.Cycle; one turn's, made here, when
    None), shape (k, 2) [m]: frames the camera."""
    sol = _cycle(mech, cycle).solution
    pts = [np.column_stack([sol["x" + p], sol["y" + p]]) for p in mech.points]
    pts = np.concatenate(pts)
    return pts[np.all(np.isfinite(pts), axis=1)]


def framing(mech, aspect: float, cycle=None) -> tuple[np.ndarray, float]:
    """Centre (x, y) [m] and vertical extent [m] of an orthographic view showing every point of ``mech``
    in an image of width/height ``aspect``, with a 30 % margin (its paths from ``cycle`` where given)."""
    pts = path_points(mech, cycle=cycle)
    lo, hi = pts.min(0), pts.max(0)
    return 0.5 * (lo + hi), float(max(hi[1] - lo[1], (hi[0] - lo[0]) / aspect, 1e-9) * 1.3)


def frame_extent(mech, aspect: float) -> float:
    return framing(mech, aspect)[1]
