"""Video frames drawn as the app draws its view (sim/front/static/app.js): links in the app's colours, plates
(filled convex hulls) for links of three or more points, blocks as rectangles along their guide, ground
pivots with hatching, pins at every joint with their labels, the output point's path traced in red over
its whole path in pale red, a scale bar in the display unit, and the time and input value in a corner.

The poses are the simulation's: every point is a MuJoCo site, read after ``mj_kinematics`` at each frame's
joint positions. Drawing is 2-D (Pillow, which matplotlib already needs), supersampled 2x for smooth edges.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic.kinds.base import BARREL, ROD_INSIDE

COLORS = ("#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2", "#bcbd22")
"""The app's link colours, in the app's order (sim/front/static/app.js COLORS): no red, the output point's
path's colour."""
PATH = "#d62728"
PATH_PALE = (214, 39, 40, 64)
GRID = "#eceff3"
SUPERSAMPLE = 2
PAD = 0.08
"""Margin around every point's whole path, as a fraction of the larger extent (the app's view)."""


@dataclass(frozen=True)
class Scene:
    """What is drawn, fixed over a run: links (name, points, block), ground and labelled points, the
    output point, the view's world bounds [m], the display units and the input's name."""

    links: tuple
    points: tuple[str, ...]
    ground: tuple[str, ...]
    output_point: str
    bounds: tuple[float, float, float, float]
    size: float
    display: object
    input_name: str
    input_is_angle: bool
    wheels: tuple = ()
    """Gears drawn on links (:class:`analytic.kinds.base.Wheel`), from the kinds."""
    cylinders: tuple = ()
    """Linear actuators drawn as a barrel and a rod (:class:`analytic.kinds.base.Cylinder`), from the kinds."""
    plates: tuple = ()
    """Cam plates (:class:`Plate`): each outline turned with its link, and a roller drawn on its follower."""
    force_scale: float = 0.0
    """[m per N] The length of a joint-force arrow per newton (0: no arrows), see :func:`force_arrows`."""
    force_ref: float = 0.0
    """[N] The force of the legend's arrow: a round value (in the display's force unit) near half the peak."""
    force_label: str = "joint forces (first link on the second)"
    """The legend's words for the arrows (joint forces, the file's loads, or both)."""


@dataclass(frozen=True, eq=False)
class Plate:
    """A cam plate as drawn: its ``outline`` (k, 2) [m] in the cam's frame (origin at ``pivot``, x-axis along the
    link ``link`` from its first point ``ref[0]`` to its second ``ref[1]``: the cam angle is that link's angle)
    and the follower's roller, radius ``roller`` [m] (0: a knife or a face) about the trace point ``point``;
    a flat face: ``face`` = (ux, uy, lo, hi), the guide's direction u (world) and the face's ends [m] along
    n = J u from its foot ``point`` (the face through the foot, square to the guide), else None."""

    link: str
    pivot: str
    ref: tuple
    outline: np.ndarray
    roller: float
    point: str
    face: tuple | None = None


FACE_DEPTH = 0.03
"""A flat face's drawn thickness up its guide, as a fraction of the mechanism's size (only drawn)."""

PLATE_CORNERS = 360
"""The drawn plate's corners (one a degree: a chord of ~1e-4 of a 30 mm cam, under a pixel)."""


def plates_of(mech) -> tuple:
    """The mechanism's cam plates to draw (:class:`Plate`), from its cams' geometry (:mod:`analytic.cams`)."""
    from analytic import cams
    out = []
    for e in cams.elements(mech).values():
        g = cams.geometry(mech, e, n=PLATE_CORNERS)
        pts = mech.topology.links[e["cam"]].points
        out.append(Plate(e["cam"], e["pivot"], (pts[0], pts[1]), np.asarray(cams.plate(e, g), dtype=float),
                         float(e["roller"]) if e["contact"] == "roller" else 0.0, e["point"], face_of(e, g)))
    return tuple(out)


def face_of(e: dict, g) -> tuple | None:
    """A flat-faced follower's face as :class:`Plate` draws it, (ux, uy, lo, hi): a given ``face_width``
    centred on the middle of the contact's travel (:attr:`analytic.cams.CamGeometry.face_centre`, as the
    MuJoCo model builds it, sim.model.cam_contact.add), else the analytic face width (the contact's travel,
    :attr:`analytic.cams.CamGeometry.face_travel`) where the contact sweeps it; None for a roller or a knife."""
    if e["contact"] != "flat":
        return None
    ux, uy = g.setup.u
    if e.get("face_width"):
        w, mid = float(e["face_width"]), g.face_centre
        return (ux, uy, mid - 0.5 * w, mid + 0.5 * w)
    return (ux, uy, float(np.min(g.face_offset)), float(np.max(g.face_offset)))


def face_world(pl: Plate, at: dict):
    """The drawn face's contact edge (2, 2) [m] in the world, its ends at ``lo`` and ``hi`` along n from the
    foot at ``at[pl.point]``; None without a face or where the foot is not placed."""
    if pl.face is None:
        return None
    f = np.asarray(at[pl.point], dtype=float)
    if not np.all(np.isfinite(f)):
        return None
    ux, uy, lo, hi = pl.face
    n = np.array([-uy, ux])
    return np.array([f + lo * n, f + hi * n])


def plate_world(pl: Plate, at: dict):
    """The plate's outline (k, 2) [m] in the world, its points at ``at`` ({point: (x, y)} [m]): turned by its
    link's angle about its pivot; None where a point is not placed."""
    o, a, b = (np.asarray(at[p], dtype=float) for p in (pl.pivot, *pl.ref))
    if not (np.all(np.isfinite(o)) and np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        return None
    ang = math.atan2(b[1] - a[1], b[0] - a[0])
    c, s = math.cos(ang), math.sin(ang)
    return np.column_stack([o[0] + c * pl.outline[:, 0] - s * pl.outline[:, 1],
                            o[1] + s * pl.outline[:, 0] + c * pl.outline[:, 1]])


def cam_drawing(mech) -> list[dict]:
    """:func:`plates_of` as the app's page draws them (sim/front/static/app.js drawCam): each plate's link, pivot,
    reference points (the cam angle is the angle from ``ref[0]`` to ``ref[1]``), ``outline`` [[x, y], ...] [m]
    in the cam's frame, ``roller`` [m] about the trace point ``point``; and a flat face's ``face``: the guide's
    unit direction ``u`` and the face's ends ``[lo, hi]`` [m] along n = (-u_y, u_x) from the trace point (centred
    on the contact's travel; its ``face_width`` where given, else the travel)."""
    from analytic import cams
    els = list(cams.elements(mech).values())
    out = []
    for pl, e in zip(plates_of(mech), els):
        face = None
        if e["contact"] == "flat":
            g = cams.geometry(mech, e)
            lo, hi = float(np.min(g.face_offset)), float(np.max(g.face_offset))
            half = 0.5 * max(e["face_width"] or 0.0, hi - lo)
            mid = 0.5 * (lo + hi)
            st = e["setup"]
            face = {"u": list(st.u), "ends": [mid - half, mid + half]}
        out.append({"name": e["name"], "link": pl.link, "pivot": pl.pivot, "ref": list(pl.ref),
                    "outline": pl.outline.tolist(), "roller": pl.roller, "point": pl.point, "contact": e["contact"],
                    "face": face})
    return out


def poses(built, qpos_frames: np.ndarray) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Every point's position [m] at each frame, shape (frames, points, 2), from the model's sites at
    the frames' joint positions; and each block link's angle [rad] per frame."""
    import mujoco
    model, mech = built.model, built.mech
    data = mujoco.MjData(model)
    sites = [model.site(p).id for p in mech.points]
    blocks = {ln: model.body(ln).id for ln in mech.slides}
    xy = np.empty((len(qpos_frames), len(sites), 2))
    angles = {ln: np.empty(len(qpos_frames)) for ln in blocks}
    for i, q in enumerate(qpos_frames):        # one kinematics pass per video frame
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        xy[i] = data.site_xpos[sites, :2]
        for ln, b in blocks.items():
            m = data.xmat[b]
            angles[ln][i] = math.atan2(m[3], m[0])
    return xy, angles


def wheels_of(mech) -> tuple:
    """The gears drawn on ``mech``'s links (:class:`analytic.kinds.base.Wheel`), as its kinds give them at
    the start pose (the videos here, the app's page from :func:`sim.front.app.describe`)."""
    from analytic import kinds
    hooks = [(kinds.get(e["kind"]), e) for e in mech.geometry.elements]
    if not any(type(k).wheels is not kinds.Kind.wheels for k, _ in hooks):
        return ()                                          # no kind here draws a wheel: no pose needed
    _, start = mech.solve_at([0.0])
    pose = {p: (float(start["x" + p][0]), float(start["y" + p][0])) for p in mech.points}
    return tuple(w for k, e in hooks for w in k.wheels(e, pose))


def cylinders_of(mech) -> tuple:
    """The linear actuators drawn as a barrel and a rod (:class:`analytic.kinds.base.Cylinder`), as ``mech``'s
    kinds give them (the videos here, the app's page from :func:`sim.front.app.describe`)."""
    from analytic import kinds
    return tuple(c for e in mech.geometry.elements for c in kinds.get(e["kind"]).cylinders(e))


def cylinder_drawing(mech) -> list[dict]:
    """:func:`cylinders_of` as the app's page draws them: each cylinder's fields and its drawn barrel's length and
    its rod's inner end from the barrel's pin [m] (BARREL, ROD_INSIDE of the retracted length)."""
    import dataclasses
    return [{**dataclasses.asdict(c), "barrel_length": BARREL * c.retracted, "rod_inside": ROD_INSIDE * c.retracted}
            for c in cylinders_of(mech)]


def scene(built, xy: np.ndarray, display, path: np.ndarray | None = None) -> Scene:
    """The scene of a run whose points move through ``xy`` (frames, points, 2), the view holding them
    and the output point's whole recorded ``path`` (steps, 2) [m] (its tips may fall between frames)."""
    from sim.service import link_drawing
    mech = built.mech
    wheels = wheels_of(mech)
    every = xy.reshape(-1, 2) if path is None else np.vstack([xy.reshape(-1, 2), path])
    index = {p: i for i, p in enumerate(mech.points)}
    for w in wheels:                                   # a gear's teeth reach 2.5 modules past its pitch circle
        reach = w.radius + 5.0 * w.radius / w.teeth
        centre = xy[:, index[w.centre]]
        every = np.vstack([every] + [centre + (dx * reach, dy * reach) for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1))])
    plates = plates_of(mech)
    for pl in plates:                                  # a plate reaches its largest radius in every direction
        reach = float(np.max(np.hypot(pl.outline[:, 0], pl.outline[:, 1])))
        centre = xy[:, index[pl.pivot]]
        every = np.vstack([every] + [centre + (dx * reach, dy * reach) for dx, dy in ((1, 0), (-1, 0), (0, 1), (0, -1))])
    finite = every[np.all(np.isfinite(every), axis=-1)]
    lo, hi = (finite.min(axis=0), finite.max(axis=0)) if len(finite) else (np.array([-1.0, -1]), np.array([1.0, 1]))
    pad = PAD * max(float(np.max(hi - lo)), 1e-9)
    first = mech.inputs[0]
    cylinders = cylinders_of(mech)
    drawn = {ln for c in cylinders for ln in (c.barrel, c.rod)}    # the cylinders draw their own two links
    return Scene(tuple((d["name"], tuple(d["points"]), d["block"]) for d in link_drawing(mech) if d["name"] not in drawn),
                 tuple(mech.points), tuple(mech.ground_points), mech.output_point,
                 (lo[0] - pad, lo[1] - pad, hi[0] + pad, hi[1] + pad), mech.size, display, first.q,
                 first.angular, wheels, cylinders=cylinders, plates=plates)


ARROW_REACH = 0.4
"""The peak joint force's arrow is this fraction of the mechanism's size long: linear in the force, so a
peak that lasts an instant leaves short arrows elsewhere (the Jansen leg's forces are a twentieth of their
peak away from 190-200 deg); the legend gives the scale."""
FORCE_COLOR = "#c51b8a"
CYLINDER = "#5a6470"
"""A cylinder's barrel."""
ROD = "#b8c2cc"
"""A cylinder's rod."""


def force_arrows(sc: Scene, peak: float, label: str | None = None) -> Scene:
    """The scene with joint-force arrows: the peak force [N] drawn ARROW_REACH of the mechanism's size long,
    the legend's arrow a round force in the display's force unit (1, 2 or 5 x 10^k of the file's
    ``force_units``: N, kN, lbf) at most half the peak."""
    from dataclasses import replace
    if not (math.isfinite(peak) and peak > 0):
        return sc
    f = _force_factor(sc)                              # display force units per newton
    half = 0.5 * peak * f
    ref = 10 ** math.floor(math.log10(half))
    ref = max(m * ref for m in (1, 2, 5) if m * ref <= half * (1 + 1e-12))
    return replace(sc, force_scale=ARROW_REACH * sc.size / peak, force_ref=ref / f,
                   force_label=label or sc.force_label)


def _force_factor(sc: Scene) -> float:
    return sc.display.factor("force") if sc.display is not None else 1.0


def force_legend_text(sc: Scene) -> str:
    """The legend's arrow value in the display's force unit (``500 N``, ``2 kN``, ``100 lbf``)."""
    unit = sc.display.unit("force") if sc.display is not None else "N"
    return f"{sc.force_ref * _force_factor(sc):.6g} {unit}"


def nice_step(span: float) -> float:
    """1, 2 or 5 times a power of ten, at least span / 6 (the app's grid step)."""
    raw = span / 6
    p = 10 ** math.floor(math.log10(raw))
    return next(m * p for m in (1, 2, 5, 10) if m * p >= raw * (1 - 1e-12))


def _font(px: int, bold: bool = False):
    from PIL import ImageFont
    try:
        import matplotlib
        from pathlib import Path
        name = "DejaVuSans-Bold.ttf" if bold else "DejaVuSans.ttf"
        return ImageFont.truetype(str(Path(matplotlib.get_data_path()) / "fonts" / "ttf" / name), px)
    except (OSError, ImportError):
        return ImageFont.load_default()


class Painter:
    """Draws frames of one scene at one size; fonts and the world-to-pixel map made once."""

    def __init__(self, sc: Scene, size: tuple[int, int]):
        self.sc, self.size = sc, size
        w, h = size
        k = SUPERSAMPLE
        self.W, self.H = w * k, h * k
        self.u = k * max(h, 240) / 480                     # one app pixel at a 480-px-high frame
        x0, y0, x1, y1 = sc.bounds
        self.s = min(self.W / (x1 - x0), self.H / (y1 - y0))
        self.cx = self.W / 2 - self.s * (x0 + x1) / 2
        self.cy = self.H / 2 + self.s * (y0 + y1) / 2
        self.font = _font(max(8 * k, round(12 * self.u)))       # never under 8 pixels in the video
        self.bold = _font(max(8 * k, round(12 * self.u)), bold=True)
        self.small = _font(max(8 * k, round(11 * self.u)))
        self.index = {p: i for i, p in enumerate(sc.points)}

    def px(self, xy: np.ndarray) -> np.ndarray:
        return np.column_stack([self.cx + self.s * xy[:, 0], self.cy - self.s * xy[:, 1]])

    def frame(self, xy: np.ndarray, angles: dict, trace: np.ndarray, path: np.ndarray, t: float, q: float,
              markers=(), arrows=None, speed: float | None = None) -> np.ndarray:
        """One RGB frame (h, w, 3) uint8: ``xy`` the points at this frame (points, 2) [m], ``trace`` the
        output point's path so far and ``path`` its whole path [m], ``t`` [s], ``q`` the input's value;
        ``arrows`` (joints, 4): each joint's point (x, y) [m] and force (Fx, Fy) [N], drawn to the scene's
        force scale; ``speed`` the input's speed [rad/s, or m/s for a slider] shown in the readout (a
        motor-driven run), None: not shown."""
        from PIL import Image, ImageDraw
        img = Image.new("RGB", (self.W, self.H), "white")
        d = ImageDraw.Draw(img, "RGBA")
        u, sc = self.u, self.sc
        self._grid(d)
        colors = {name: COLORS[k % len(COLORS)] for k, (name, _, _) in enumerate(sc.links)}
        for w in sc.wheels:
            self._wheel(d, w, xy, colors.get(w.link, "#888888"))
        if len(path) > 1:
            d.line([tuple(p) for p in self.px(path)], fill=PATH_PALE, width=max(1, round(1.5 * u)))
        if len(trace) > 1:
            d.line([tuple(p) for p in self.px(trace)], fill=PATH, width=max(2 * SUPERSAMPLE, round(2.4 * u)),
                   joint="curve")                          # at least 2 pixels wide in the smallest frames
        for pl in sc.plates:                                   # under the follower it drives
            self._plate(d, pl, xy, colors.get(pl.link, "#888888"))
        P = self.px(xy)
        at = {p: P[i] for p, i in self.index.items() if np.all(np.isfinite(P[i]))}
        for c in sc.cylinders:                                 # under the links they push
            if c.base in at and c.end in at:
                self._cylinder(d, c, at[c.base], at[c.end])
        for k, (name, pts, block) in enumerate(sc.links):
            self._link(d, [at[p] for p in pts if p in at], COLORS[k % len(COLORS)], block, angles.get(name, 0.0))
        for g in sc.ground:
            if g in at:
                self._ground(d, at[g])
        for p in sc.points:
            if p in at:
                self._joint(d, p, at[p], p == sc.output_point, p in sc.ground)
        if arrows is not None and sc.force_scale > 0:          # over the pins, so short ones still show
            for x, y, fx, fy in arrows:
                self._arrow(d, x, y, fx, fy)
        for mx, my in markers:
            c = self.px(np.array([[mx, my]]))[0]
            r = 6 * u
            d.line([(c[0] - r, c[1] - r), (c[0] + r, c[1] + r)], fill="#1a1a1a", width=round(2 * u))
            d.line([(c[0] - r, c[1] + r), (c[0] + r, c[1] - r)], fill="#1a1a1a", width=round(2 * u))
        self._legend(d)
        if arrows is not None and sc.force_scale > 0:
            self._force_legend(d)
        self._readout(d, t, q, speed)
        self._scale_bar(d)
        return np.asarray(img.resize(self.size, Image.LANCZOS))

    # -------------------------------------------------------------------------------- elements
    def _grid(self, d) -> None:
        x0, y0 = (0 - self.cx) / self.s, (self.cy - self.H) / self.s
        x1, y1 = (self.W - self.cx) / self.s, self.cy / self.s
        step = nice_step(max(x1 - x0, y1 - y0))
        w = max(1, round(self.u))
        for x in np.arange(math.ceil(x0 / step) * step, x1, step):
            px = self.cx + self.s * x
            d.line([(px, 0), (px, self.H)], fill=GRID, width=w)
        for y in np.arange(math.ceil(y0 / step) * step, y1, step):
            py = self.cy - self.s * y
            d.line([(0, py), (self.W, py)], fill=GRID, width=w)

    def _link(self, d, pts, color, block, phi) -> None:
        u = self.u
        if not pts:
            return
        rgb = tuple(int(color[i:i + 2], 16) for i in (1, 3, 5))
        if block:
            w = max(1, round(6 * u))
            for p in pts[1:]:                                 # a point the block carries (a yoke's arm): a bar
                d.line([tuple(pts[0]), tuple(p)], fill=color, width=w)
                d.ellipse([p[0] - w / 2, p[1] - w / 2, p[0] + w / 2, p[1] + w / 2], fill=color)
            size = max(10 * u, 0.06 * self.sc.size * self.s)
            c, s = math.cos(phi), math.sin(phi)
            corners = [(-size, -0.55 * size), (size, -0.55 * size), (size, 0.55 * size), (-size, 0.55 * size)]
            poly = [(pts[0][0] + a * c - b * s, pts[0][1] - (a * s + b * c)) for a, b in corners]
            d.polygon(poly, fill=rgb + (0x33,), outline=color, width=max(1, round(2 * u)))
        elif len(pts) >= 3 and _thickness(convex_hull(np.array(pts))) > 3 * u:
            hull = convex_hull(np.array(pts))
            d.polygon([tuple(p) for p in hull], fill=rgb + (0x2e,), outline=color, width=max(1, round(4 * u)))
            r = 2 * u
            for p in hull:                                    # rounded corners, as the app's lineJoin
                d.ellipse([p[0] - r, p[1] - r, p[0] + r, p[1] + r], fill=color)
        elif len(pts) >= 2:                                   # a bar (or points in a line: its ends)
            pts = _farthest(np.array(pts))
            w = max(1, round(6 * u))
            d.line([tuple(pts[0]), tuple(pts[-1])], fill=color, width=w)
            r = w / 2
            for p in pts:                                     # round caps
                d.ellipse([p[0] - r, p[1] - r, p[0] + r, p[1] + r], fill=color)

    def _cylinder(self, d, c, base, end) -> None:
        """A barrel from its pin ``base`` along the cylinder (BARREL of the retracted length) and a rod from the
        pin ``end`` back into it (to ROD_INSIDE of the retracted length from the base), pixel positions."""
        u = self.u
        dx, dy = end[0] - base[0], end[1] - base[1]
        length = math.hypot(dx, dy)
        if length <= 0:
            return
        ex, ey = dx / length, dy / length
        lo = c.retracted * self.s
        wide = max(9 * u, c.bore * self.s) if c.bore > 0 else max(9 * u, 0.035 * self.sc.size * self.s)
        inside = min(ROD_INSIDE * lo, length)
        d.line([(base[0] + ex * inside, base[1] + ey * inside), tuple(end)], fill=ROD, width=max(1, round(0.45 * wide)))
        barrel = min(BARREL * lo, length)                    # over the rod's end inside it
        d.line([tuple(base), (base[0] + ex * barrel, base[1] + ey * barrel)], fill=CYLINDER, width=round(wide))

    def _plate(self, d, pl, xy, color) -> None:
        """A cam plate: its outline turned with its link about the pivot, filled pale; its roller as a circle
        about the trace point."""
        world = plate_world(pl, {p: xy[i] for p, i in self.index.items()})
        if world is None:
            return
        rgb = tuple(int(color[i:i + 2], 16) for i in (1, 3, 5))
        width = max(1, round(1.5 * self.u))
        d.polygon([tuple(p) for p in self.px(world)], fill=rgb + (0x30,), outline=color, width=width)
        f = xy[self.index[pl.point]]
        if pl.roller > 0 and np.all(np.isfinite(f)):
            cx, cy = self.px(np.array([f]))[0]
            r = pl.roller * self.s
            d.ellipse([cx - r, cy - r, cx + r, cy + r], fill=(255, 255, 255, 0xd0), outline="#1a1a1a", width=width)
        edge = face_world(pl, {pl.point: f})
        if edge is not None:                  # the face: its contact edge on the plate, its back FACE_DEPTH up the guide
            back = edge + FACE_DEPTH * self.sc.size * np.array(pl.face[:2])
            d.polygon([tuple(p) for p in self.px(np.vstack([edge, back[::-1]]))], fill=(255, 255, 255, 0xd0),
                      outline="#1a1a1a", width=width)

    def _wheel(self, d, w, xy, color) -> None:
        """A gear: its toothed outline about its centre, turned with its link (the direction centre -> ref);
        external gears filled pale, ring gears (teeth inward) in outline with their rim."""
        i = self.index[w.centre]
        cx, cy = xy[i]
        if not (math.isfinite(cx) and math.isfinite(cy)):
            return
        base = 0.0
        if w.ref is not None:
            rx, ry = xy[self.index[w.ref]]
            base = math.atan2(ry - cy, rx - cx)
        m = 2.0 * w.radius / w.teeth                       # the module: addendum m, dedendum 1.25 m
        tip, root = (w.radius - m, w.radius + 1.25 * m) if w.ring else (w.radius + m, w.radius - 1.25 * m)
        pitch = 2.0 * math.pi / w.teeth
        outline = []
        for k in range(w.teeth):                           # a trapezoid tooth per pitch, centred on its angle
            a = base + w.phase + k * pitch
            outline += [(root, a - 0.30 * pitch), (tip, a - 0.17 * pitch), (tip, a + 0.17 * pitch),
                        (root, a + 0.30 * pitch), (root, a + 0.5 * pitch)]
        pts = self.px(np.array([[cx + r * math.cos(a), cy + r * math.sin(a)] for r, a in outline]))
        rgb = tuple(int(color[i:i + 2], 16) for i in (1, 3, 5))
        width = max(1, round(1.5 * self.u))
        if w.ring:
            d.polygon([tuple(p) for p in pts], outline=color, width=width)
            c, r = self.px(np.array([[cx, cy]]))[0], (root + 1.5 * m) * self.s
            d.ellipse([c[0] - r, c[1] - r, c[0] + r, c[1] + r], outline=color, width=width)
        else:
            d.polygon([tuple(p) for p in pts], fill=rgb + (0x24,), outline=color, width=width)

    def _ground(self, d, p) -> None:
        u, (x, y) = self.u, p
        w = max(1, round(1.2 * u))
        d.polygon([(x, y), (x - 9 * u, y + 14 * u), (x + 9 * u, y + 14 * u)], fill="#e8e8e8", outline="#444", width=w)
        d.line([(x - 13 * u, y + 14 * u), (x + 13 * u, y + 14 * u)], fill="#444", width=w)
        for k in range(-12, 9, 5):
            d.line([(x + k * u, y + 20 * u), (x + (k + 5) * u, y + 14 * u)], fill="#444", width=w)

    def _joint(self, d, name, p, output, ground) -> None:
        u = self.u
        r = (5 if output else 4) * u
        d.ellipse([p[0] - r, p[1] - r, p[0] + r, p[1] + r], fill="#d62728" if output else "#ffffff",
                  outline="#8b0000" if output else "#222222", width=max(1, round(1.5 * u)))
        dy = 4 * u if ground else -7 * u
        d.text((p[0] + 7 * u, p[1] + dy), name, fill="#222222", font=self.bold if output else self.font,
               anchor="ls")

    def _legend(self, d) -> None:
        u = self.u
        x, y = 8 * u, 12 * u
        d.line([(x, y), (x + 22 * u, y)], fill=PATH, width=max(1, round(2.4 * u)))
        d.text((x + 27 * u, y), f"path of {self.sc.output_point}", fill="#333333", font=self.small, anchor="lm")

    def _arrow(self, d, x: float, y: float, fx: float, fy: float) -> None:
        """A force arrow from the joint at (x, y) [m]: (fx, fy) [N] at the scene's force scale, its head
        sized to the frame; nothing under two pixels."""
        if not all(math.isfinite(v) for v in (x, y, fx, fy)):
            return
        k = self.sc.force_scale * self.s
        x0, y0 = self.cx + self.s * x, self.cy - self.s * y
        dx, dy = k * fx, -k * fy
        n = math.hypot(dx, dy)
        if n < 2 * SUPERSAMPLE:
            return
        self._shaft(d, x0, y0, dx, dy, n)

    def _shaft(self, d, x0, y0, dx, dy, n) -> None:
        u = self.u
        ux, uy = dx / n, dy / n
        head = min(9 * u, 0.45 * n)
        x1, y1 = x0 + dx, y0 + dy
        xb, yb = x1 - head * ux, y1 - head * uy
        d.line([(x0, y0), (xb, yb)], fill=FORCE_COLOR, width=max(1, round(2.2 * u)))
        w = 0.45 * head
        d.polygon([(x1, y1), (xb - w * uy, yb + w * ux), (xb + w * uy, yb - w * ux)], fill=FORCE_COLOR)

    def _force_legend(self, d) -> None:
        """Bottom left: an arrow of the scene's reference force, labelled, and what the arrows are."""
        u, sc = self.u, self.sc
        n = sc.force_ref * sc.force_scale * self.s
        x0, y = 10 * u, self.H - 14 * u
        self._shaft(d, x0, y, n, 0.0, n)
        d.text((x0 + n + 6 * u, y), force_legend_text(sc), fill="#222222", font=self.small, anchor="lm")
        d.text((x0, y - 10 * u), sc.force_label, fill="#333333", font=self.small,
               anchor="ls")

    def _readout(self, d, t: float, q: float, speed: float | None = None) -> None:
        """The app's readout: ``phi1 = 123.4° · t = 0.412 s`` in the top right corner; with a ``speed``
        (a motor-driven run) ``phi1 = 123.4° · 147.1 rpm · t = 0.412 s``, the speed in the display's unit
        of angular speed (rad/s, deg/s or rpm: ``--speeds``) or of velocity for a slider."""
        u, sc = self.u, self.sc
        if sc.input_is_angle:
            value = f"{math.degrees(q):.1f}°"
        else:
            value = f"{sc.display.convert('length', q):.4g} {sc.display.unit('length')}"
        text = f"{sc.input_name} = {value}"
        if speed is not None:
            quantity = "angular_velocity" if sc.input_is_angle else "velocity"
            text += f" · {_speed_text(sc.display.convert(quantity, speed))} {sc.display.unit(quantity)}"
        d.text((self.W - 8 * u, 12 * u), f"{text} · t = {t:.3f} s", fill="#222222", font=self.font, anchor="rm")

    def _scale_bar(self, d) -> None:
        """A bar of a round length in the display unit, bottom right, labelled."""
        u, disp = self.u, self.sc.display
        f = disp.factor("length")                         # display units per metre
        target = 0.2 * self.W / self.s * f                # about a fifth of the frame's width
        length = 10 ** math.floor(math.log10(target)) if target > 0 else 1.0
        length = max(m * length for m in (1, 2, 5) if m * length <= target)    # 1, 2, 5 x 10^k, <= target
        n = length / f * self.s                           # its length in pixels
        x1, y = self.W - 12 * u, self.H - 14 * u
        x0 = x1 - n
        w = max(1, round(2 * u))
        d.line([(x0, y), (x1, y)], fill="#222222", width=w)
        for x in (x0, x1):
            d.line([(x, y - 5 * u), (x, y + 1 * u)], fill="#222222", width=w)
        d.text(((x0 + x1) / 2, y - 6 * u), f"{length:g} {disp.unit('length')}", fill="#222222", font=self.small,
               anchor="mb")


def _speed_text(v: float) -> str:
    """A speed with four significant digits, its width steady while it fluctuates (no exponent under 1e5)."""
    r = float(f"{v:.4g}")
    return f"{r:.4g}" if abs(r) >= 1e5 or abs(r) < 1e-3 else f"{r:.{max(0, 3 - math.floor(math.log10(abs(r))))}f}"


def _thickness(hull: np.ndarray) -> float:
    """A polygon's area over its longest extent [px]: ~0 for points in a line (drawn as a bar)."""
    if len(hull) < 3:
        return 0.0
    x, y = hull[:, 0], hull[:, 1]
    area = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
    return area / max(float(np.max(np.hypot(*(hull[:, None] - hull[None]).transpose(2, 0, 1)))), 1e-12)


def _farthest(pts: np.ndarray) -> np.ndarray:
    """The two points farthest apart."""
    d = np.hypot(*(pts[:, None] - pts[None]).transpose(2, 0, 1))
    i, j = np.unravel_index(np.argmax(d), d.shape)
    return pts[[i, j]]


def convex_hull(pts: np.ndarray) -> np.ndarray:
    """The convex hull of 2-D points, counter-clockwise in the points' own axes (Andrew's monotone
    chain, as the app's ``hull``); fewer than 3 points are returned as given."""
    if len(pts) < 3:
        return pts
    order = np.lexsort((pts[:, 1], pts[:, 0]))
    s = pts[order]

    def half(seq):
        out = []
        for p in seq:
            while len(out) >= 2 and ((out[-1][0] - out[-2][0]) * (p[1] - out[-2][1])
                                     - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])) <= 0:
                out.pop()
            out.append(p)
        return out[:-1]
    return np.array(half(s) + half(s[::-1]))
