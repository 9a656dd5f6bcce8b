"""Use cases of the parts (SPEC "Parts, drawings and interference"): layers for ``linkage check``, the
interference check over the cycle (MuJoCo contacts, cross-checked by plane polygon distances), the
exports (DXF, SVG/PDF drawing, STEP, STL, bill of materials) and the parts' mass properties against the
mass model. Front ends call these; the geometry is :mod:`analytic.parts`."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic import ParameterError
from analytic.parts import layers as lay
from analytic.parts import model

SAMPLES = 720
"""Instants per cycle before refinement (half a degree of a crank)."""

BISECT = 1e-10
"""Bisection of the first contact: to this fraction of the cycle's duration (3.6e-8 deg of a crank)."""


@dataclass(frozen=True)
class PartsModel:
    mech: object
    sweep: model.Sweep
    parts: dict
    layout: lay.Layout

    @property
    def chord(self) -> float:
        return model.CHORD * self.mech.size / self.mech.scale


def cycle_mechanism(mech, input_range=None):
    """The mechanism moving over its cycle: rocking over ``input_range`` (rad or m) when given; a single
    crank that cannot turn fully rocks over its assembly range around its start."""
    if input_range is not None:
        return mech.rocking(*input_range)
    if len(mech.inputs) == 1 and mech.inputs[0].angular:
        from analytic.applications import figures
        ranges = figures.assembly_ranges(mech)
        if ranges and not figures.turns_fully(mech, ranges):
            q0 = mech.inputs[0].motion.q0
            lo, hi = min(ranges, key=lambda r: 0.0 if r[0] <= q0 <= r[1] else min(abs(q0 - r[0]), abs(q0 - r[1])))
            pad = 1e-6 * (hi - lo)
            return mech.rocking(lo + pad, hi - pad)
    return mech


def prepare(mech, input_range=None, samples: int = SAMPLES) -> PartsModel:
    mech = cycle_mechanism(mech, input_range)
    sweep = model.cycle(mech, samples)
    parts = model.build(mech, sweep)
    return PartsModel(mech, sweep, parts, lay.layout(mech, parts, sweep))


def layer_lines(pm: PartsModel) -> list[str]:
    """``linkage check``'s lines about the parts: each link's layer and z, and the pins through layers."""
    L = pm.layout
    u = pm.mech.units
    lines = [f"  parts layers: {L.count} (z index, 0 = against the frame)"]
    for ln, p in pm.parts.items():
        plates = L.plates(ln)
        if len(plates) == 1:
            z0, z1 = L.z[ln]
            lines.append(f"    {ln}: layer {L.layers[ln]} (z {z0:.4g}..{z1:.4g} {u}; {p.kind}, {p.thickness:g} {u} thick)")
        else:
            (a, (a0, a1)), (b, (b0, b1)) = plates
            lines.append(f"    {ln}: layers {a} and {b} (z {a0:.4g}..{a1:.4g} and {b0:.4g}..{b1:.4g} {u}; {p.kind}, two "
                         f"plates {p.thickness:g} {u} thick)")
    lines += construction_lines(pm)
    if L.meshing:
        lines.append("    meshing gears share a layer: " + ", ".join(f"{a}-{b}" for a, b in L.meshing))
    pins = []
    for point, (lo, hi) in pin_spans(pm).items():
        pins.append(f"{point} {lo:.4g}..{hi:.4g}")
    if pins:
        lines.append(f"    pins (z from..to, {u}; ground pivots from the frame at 0, or from a top plate): " + ", ".join(pins))
    for point, ln in L.clashes:
        lines.append(f"    pin clash: link {ln} passes over the pin at {point} within its layers (no layering of up to "
                     f"{L.count + 2} layers avoids it, nor one with up to {lay.MAX_TWO_PLATE} two-plate links: offset the joint "
                     f"or shorten the link)")
    for p in pm.parts.values():
        for block, point in p.crossings:
            lines.append(f"    note: link {p.link}'s slot for {block} runs into its joint {point} (the pins meet)")
    return lines


def construction_lines(pm: PartsModel) -> list[str]:
    """How the layering gets the links past the pins it could not keep them off by layers alone: each
    two-plate link (a clevis at the pin that joins its plates; which plate each of its other pins takes) and
    each ground pin held from a top plate with links passing under it. Empty for a plain layering."""
    L = pm.layout
    if not L.second:
        return []
    lines = []
    spans = L.pins
    for ln, point in L.joined.items():
        (a, za), (b, zb) = L.plates(ln)
        between = [m for m in pm.parts if m != ln and any(a < k < b for k, _ in L.plates(m))]
        lines.append(f"    link {ln}: two plates (layers {a} and {b}), a clevis at {point}: its pin fixed in both plates, "
                     f"{', '.join(between) or 'nothing'} between them")
        for h in pm.parts[ln].holes:
            if h.point == point:
                continue
            lo, hi = spans[h.point]
            held = [k for k, (z0, z1) in L.plates(ln) if z0 < hi and z1 > lo]
            which = "both plates" if len(held) == 2 else f"the layer-{held[0]} plate only" if held else "no plate"
            lines.append(f"    link {ln}: pin {h.point} through {which}")
    for point in pm.mech.ground_points:
        if point not in spans:
            continue
        lo, hi = spans[point]
        under = [m for m in (L.crossing or {}).get(point, ()) if all(z1 <= lo for _, (z0, z1) in L.plates(m))]
        if lo > 0 and under:
            lines.append(f"    pin {point}: stub from the top plate, link{'s' if len(under) > 1 else ''} "
                         f"{', '.join(under)} pass{'es' if len(under) == 1 else ''} under")
    return lines


def pin_spans(pm: PartsModel) -> dict:
    """{point: (z bottom, z top)} of every pin: through the holes of the links pinned there (and the slot it
    runs in), a ground pivot's from the frame (z = 0) or, where links pass below its own, from a top plate."""
    return dict(pm.layout.pins)


# ------------------------------------------------------------------------------------------ interference
def _input_value(mech, t: float) -> float:
    q = mech.drive(np.array([t]))[0][0, 0]
    first = mech.inputs[0]
    return math.degrees(q) if first.angular else q / mech.scale


def _bisect(f, t0: float, t1: float, tol: float) -> float:
    """The first time in (t0, t1] where f(t) < 0, given f(t0) >= 0 > f(t1)."""
    while t1 - t0 > tol:
        tm = 0.5 * (t0 + t1)
        if f(tm) < 0:
            t1 = tm
        else:
            t0 = tm
    return t1


def interference(pm: PartsModel) -> dict:
    """The check (SPEC): MuJoCo's contacts and distances between same-layer solids at the instants of the
    plane test (the uniform samples plus its refinements), the first contact bisected in each; JSON-ready."""
    import mujoco

    from sim.model import parts_scene
    mech = pm.mech
    passing = pin_passes(pm)
    clash_pins = tuple(dict.fromkeys([p for p, _ in pm.layout.clashes] + [p for p, _ in passing]))
    scene = parts_scene.build(mech, pm.parts, pm.layout, pm.chord, clash_pins)
    out = lay.outlines(mech, pm.parts)
    size = mech.size / mech.scale
    distmax = 10.0 * size
    tol = BISECT * (pm.sweep.t[-1] - pm.sweep.t[0])
    data = mujoco.MjData(scene.model)
    items, clear, clear2d = [], {}, {}
    for a, b in scene.pairs:
        plane = lay.pair_distance(mech, out, pm.sweep, a, b, 0.0)
        ts = np.unique(np.concatenate([pm.sweep.t, [plane.t] + ([plane.first] if plane.first is not None else [])]))
        sw = model.frames_at(mech, ts)
        sw = model.Sweep(ts, sw.q, sw.frames, sw.points)
        va = lay.world(out, sw, a)
        vb = lay._frame_verts(out, len(ts)) if b == lay.FRAME else lay.world(out, sw, b)
        d2 = lay.signed_distance(va, vb)
        single = parts_scene.Scene(scene.model, scene.links, ((a, b),), scene.geoms)
        mj = parts_scene.sweep(single, sw, distmax)
        dm = mj.distance[0]
        key = f"{a}|{b}"
        clear[key] = float(np.min(dm))
        clear2d[key] = float(np.min(d2))
        hit = np.nonzero(mj.contact[0] | (dm < 0))[0]
        if not hit.size:
            continue

        def f_mj(t):                                   # MuJoCo's contact, else its signed distance
            s = model.frames_at(mech, [t])
            parts_scene.pose(single, data, s, 0)
            if parts_scene.in_contact(single, data, a, b):
                return -1.0
            return parts_scene.distance(single, data, a, b, distmax)

        def f_2d(t):
            s = model.frames_at(mech, [t])
            wa = lay.world(out, s, a)
            wb = lay._frame_verts(out, 1) if b == lay.FRAME else lay.world(out, s, b)
            return float(lay.signed_distance(wa, wb, depth=False)[0]) - (1e-12 * size)

        k = int(hit[0])
        t_mj = ts[0] if k == 0 else _bisect(f_mj, ts[k - 1], ts[k], tol)
        h2 = np.nonzero(d2 < 0)[0]
        t_2d = None
        if h2.size:
            k2 = int(h2[0])
            t_2d = ts[0] if k2 == 0 else _bisect(f_2d, ts[k2 - 1], ts[k2], tol)
        items.append({"links": [a, b], "first_at": _input_value(mech, t_mj), "depth": float(-np.min(dm)),
                      "geometric": {"first_at": None if t_2d is None else _input_value(mech, t_2d),
                                    "depth": float(max(0.0, -np.min(d2)))}})
    pin_items = [pin_clash(pm, scene, data, out, p, ln, distmax, tol) for p, ln in pm.layout.clashes]
    passed = []
    for p, ln in passing:                             # two-plate layouts: every pin a link passes over, in 3-D
        item = pin_clash(pm, scene, data, out, p, ln, distmax, tol, plane=False)
        passed.append({"pin": p, "link": ln, "min_distance": item["min_distance"]})
        if item["first_at"] is not None:
            pin_items.append(pin_clash(pm, scene, data, out, p, ln, distmax, tol))
    first = mech.inputs[0]
    return {"mechanism": mech.name, "units": mech.units,
            "input": first.q, "input_unit": "deg" if first.angular else mech.units,
            "samples": len(pm.sweep.t), "layers": dict(pm.layout.layers),
            "interference": items, "min_clearance": clear, "min_clearance_geometric": clear2d,
            "pins": {p: list(span) for p, span in pm.layout.pins.items()},
            "pin_clashes": pin_items,
            **({"pins_passed": passed,
                "two_plates": {ln: {"layers": [pm.layout.layers[ln], pm.layout.second[ln][0]],
                                    "joined_by": pm.layout.joined[ln]} for ln in pm.layout.second}}
               if pm.layout.second else {})}


def pin_passes(pm: PartsModel) -> list[tuple[str, str]]:
    """(point, link) of every link passing over a pin's place, where the layout has two-plate links (their
    pins' spans are the layering's own, checked again in MuJoCo over the cycle); none for a plain layering
    (its spans hold by the pin rules, and its clashes are checked as such)."""
    L = pm.layout
    if not L.second:
        return []
    return [(p, ln) for p, links in (L.crossing or {}).items() for ln in links]


def pin_clash(pm: PartsModel, scene, data, out, point: str, link: str, distmax: float, tol: float,
              plane: bool = True) -> dict:
    """A link passing over a pin within its span: where MuJoCo's pin cylinder first touches the link's solid
    (bisected) and where the plane test's circle first comes within the pin's radius of the outline; and
    MuJoCo's least distance of the two over the sweep (``min_distance``, negative: penetration). ``plane``
    False: the plane test left out (a link passing over a pin's place above or below it: the plane test finds
    the overlap in plan that the layers keep apart)."""
    import shapely

    from sim.model import parts_scene
    mech = pm.mech
    r = model.settings(mech).pin_diameter / 2
    name = f"pin_{point}"
    single = parts_scene.Scene(scene.model, scene.links, ((link, name),), scene.geoms, scene.pins)

    def f_mj(t):
        s = model.frames_at(mech, [t])
        parts_scene.pose(single, data, s, 0)
        if parts_scene.in_contact(single, data, link, name):
            return -1.0
        return parts_scene.distance(single, data, link, name, distmax)

    def f_2d(t):
        s = model.frames_at(mech, [t])
        return float(shapely.distance(shapely.polygons(lay.world(out, s, link))[0],
                                      shapely.points(s.points[point])[0])) - r

    ts = pm.sweep.t
    d2 = np.asarray(shapely.distance(shapely.polygons(lay.world(out, pm.sweep, link)),
                                     shapely.points(pm.sweep.points[point]))) - r if plane else None
    dm = np.empty(len(ts))
    for k in range(len(ts)):                          # the sweep's poses, as solved (no re-solve per instant)
        parts_scene.pose(single, data, pm.sweep, k)
        dm[k] = -1.0 if parts_scene.in_contact(single, data, link, name) else \
            parts_scene.distance(single, data, link, name, distmax)

    def first(d, f):
        hit = np.nonzero(d < 0)[0]
        if not hit.size:
            return None
        k = int(hit[0])
        return _input_value(mech, ts[0] if k == 0 else _bisect(f, ts[k - 1], ts[k], tol))
    item = {"pin": point, "link": link, "first_at": first(dm, f_mj), "min_distance": float(np.min(dm))}
    if plane:
        item["geometric"] = {"first_at": first(d2, f_2d)}
    return item


# ------------------------------------------------------------------------------------------ exports
EXTRAS = {"dxf": "ezdxf", "step": "build123d", "stl": "trimesh"}
"""The outputs that need a library of the ``[parts]`` extra (pyproject.toml), and which."""

INSTALL_PARTS = "pip install 'linkage[parts]'"


def check_extras(**asked) -> None:
    """Refuse in one line, before anything is written, the asked outputs (``dxf=PATH``, ...) whose library of
    the ``[parts]`` extra is not installed."""
    import importlib
    missing = []
    for option, module in EXTRAS.items():
        if asked.get(option):
            try:
                importlib.import_module(module)
            except ImportError:
                missing.append((option, module))
    if missing:
        raise ParameterError(f"{', '.join('--' + o for o, _ in missing)} need{'s' if len(missing) == 1 else ''} "
                             f"{', '.join(m for _, m in missing)} (the parts extra): {INSTALL_PARTS}")


def export(pm: PartsModel, dxf=None, svg=None, pdf=None, step=None, stl=None, bom=None) -> list[str]:
    """Write the asked files (paths checked by the caller); returns what was written."""
    from sim.output import parts_files
    check_extras(dxf=dxf, step=step, stl=stl)
    written = []
    if dxf:
        parts_files.write_dxf(pm, dxf)
        written.append(str(dxf))
    for path in (svg, pdf):
        if path:
            from sim.output import parts_drawing
            parts_drawing.write(pm, path)
            written.append(str(path))
    if step:
        parts_files.write_step(pm, step)
        written.append(str(step))
    if stl:
        written += [str(p) for p in parts_files.write_stl(pm, stl)]
    if bom:
        parts_files.write_bom(pm, bom)
        written.append(str(bom))
    return written


# ------------------------------------------------------------------------------------------ mass properties
def mass_comparison(pm: PartsModel) -> dict:
    """Per link, in SI and the link's frame (origin its first point, x along it): the part's exact mass
    properties (:func:`analytic.parts.model.mass_properties`; both plates of a two-plate link), the mass
    model's (:func:`analytic.mass.model`, what ``forces`` and ``dynamics`` use) and MuJoCo's inertia of the
    part's triangle meshes (the STL's solids, one per plate at its z, density from the part): {link:
    {"parts"|"model"|"mujoco": {"m", "cx", "cy", "I"}}}."""
    import mujoco

    from analytic import mass
    from sim.output import parts_files
    mech = pm.mech
    s = mech.scale
    local = {ln: {p: tuple(np.asarray(uv) * s) for p, uv in part.points.items()} for ln, part in pm.parts.items()}
    analytic_model = mass.model(mech, local=local, parts=pm.parts, layout=pm.layout)
    spec = mujoco.MjSpec()
    for ln, part in pm.parts.items():
        region = parts_files.part_region(part, pm.chord)
        b = spec.worldbody.add_body(name=ln)
        b.add_freejoint()
        for k, (_, (z0, z1)) in enumerate(pm.layout.plates(ln)):
            mesh = parts_files.extrude(region, z0, z1)
            m = spec.add_mesh(name=f"m_{ln}_{k}")
            m.uservert = (np.asarray(mesh.vertices) * s).ravel().tolist()
            m.userface = np.asarray(mesh.faces).ravel().tolist()
            m.inertia = mujoco.mjtMeshInertia.mjMESH_INERTIA_EXACT
            b.add_geom(type=mujoco.mjtGeom.mjGEOM_MESH, meshname=f"m_{ln}_{k}", density=part.density)
    model_mj = spec.compile()
    data = mujoco.MjData(model_mj)
    mujoco.mj_forward(model_mj, data)
    out = {}
    for ln, part in pm.parts.items():
        mp = model.mass_properties(part, s)
        n = len(pm.layout.plates(ln))
        bid = model_mj.body(ln).id
        com = data.xipos[bid]
        R = data.ximat[bid].reshape(3, 3)
        inertia = R @ np.diag(model_mj.body_inertia[bid]) @ R.T
        a = analytic_model[ln]
        out[ln] = {"parts": {"m": n * mp.m, "cx": mp.cx * s, "cy": mp.cy * s, "I": n * mp.I},
                   "model": {"m": a.m, "cx": a.cx, "cy": a.cy, "I": a.I},
                   "mujoco": {"m": float(model_mj.body_mass[bid]), "cx": float(com[0]), "cy": float(com[1]),
                              "I": float(inertia[2, 2])}}
    return out
