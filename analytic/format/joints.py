"""The links-and-joints form of ``linkage/1``: a linkage as users draw it, converted into Assur groups.

A file in this form gives its links (``[[links]]``: a name and the points it carries), its joints
(``[[joints]]``: ``R`` where links are pinned together at a point, ``P`` where a block slides on a guide
link, ``G`` where the gears of two links mesh at their pitch point), an assembled pose (``[pose]``: every point's x, y in the file's unit) and its inputs (``[[inputs]]``:
a crank turning a link about a ground pivot, or a slider driving a block along a ground guide). The link
``ground`` is the frame. :func:`convert` finds the Assur groups itself and writes the same mechanism in the
ordinary form (``[ground]``, ``[[inputs]]``, ``[[groups]]``), so every command reads it unchanged:

1. the inputs (their lengths and start angles from the pose; a motor whose two links nothing else places but
   which close a loop with one more link between placed points: a ``motor_dyad``, the three links at once);
2. before any dyad, a link turned by gears: pinned at one placed point, its angle fixed by the meshes'
   relations (Willis', linear in the link angles) as a linear form of placed links' angles: a ``gear``
   element on the link it is pinned to (docs/CONVENTIONS.md, "Gears");
3. repeatedly, a dyad: two links not yet placed, each joined once to what is placed and once to the
   other, solved in closed form (``RRR``, ``RRP``, ``RPR``, and the dyads with two prismatic pairs where
   those kinds are registered);
4. where no dyad is left, the smallest set of links with as many constraints as freedoms: one general
   Assur group (kind ``group``; its prismatic pairs as the group's ``slides``);
5. every further point of a placed link: a ``point`` element in the link's frame.

Lengths, offsets, start angles and local coordinates follow from the pose; where the pose uses parameters
they are expressions of them (:mod:`analytic.format.sym`), so ``--set`` moves the mechanism. Branches are
taken from the pose at the file's values. Problems (a link with no joint, a point two links share
without a joint, a redundant or locked loop, a mobility that differs from the inputs, a singular pose, a
pose that breaks a given length) are one line naming the links and points and what to change.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from itertools import combinations

import numpy as np

from analytic import kinds
from analytic._common import FileError
from analytic.format import expr
from analytic.format.lawfield import FIELDS as LAW_FIELDS
from analytic.format.sym import Sym, Vec, const, direction
from analytic.kinds.base import GROUND

FIELDS = ("links", "joints", "pose")
"""Top-level fields that mark a file in the links-and-joints form."""

LINK_NAME = re.compile(r"^[A-Za-z0-9_]+$")     # as linkfile.LINK_NAME (a link name may start with a digit)
MAX_ITEMS = 500                                # as linkfile.MAX_ITEMS
MAX_GROUP = 12                                 # the largest set of links searched for one Assur group
MAX_SETS = 200_000                             # connected sets of links tried per size (bounds a hostile file's
#                                                search to about a second)
SINGULAR = 1e-9    # a pose within this fraction of the size of a dead centre has no branch: the sign is noise
RIGID = 1e-6       # a given length may differ from the pose by this fraction of the size (poses are written
#                    with about 7 significant digits; the same bound as the peers' pose reproduction)


def is_form(data: dict) -> bool:
    """Whether a file's top-level table is in the links-and-joints form."""
    return any(k in data for k in FIELDS)


@dataclass(frozen=True)
class Converted:
    """The ordinary form of a links-and-joints file: ``data`` (the top-level table, as a file would hold
    it), ``labels`` (where each element of ``data["inputs"] + data["groups"]`` comes from, for messages)
    and ``kinds`` (what each parameter measures: ``length``, ``angle`` or ``number``)."""

    data: dict
    labels: tuple[str, ...]
    kinds: dict[str, str]


@dataclass(frozen=True)
class _Slide:
    """A ``P`` joint: ``block`` slides on ``guide`` along ``angle`` (world, at the pose) through ``point``
    (a point of the block)."""

    point: str
    guide: str
    block: str
    angle: Sym
    where: str


@dataclass(frozen=True)
class _Mesh:
    """A ``G`` joint: the gears of links ``a`` and ``b`` mesh at ``point`` (the pitch point, where their
    pitch circles touch). Resolved from the pose: ``carrier`` (the link both gears turn on), the centres
    ``ca``, ``cb`` and Willis' ``ratio`` (phi_b - phi_c = phase + ratio (phi_a - phi_c); -r_a / r_b for an
    external pair, + r_a / r_b for an internal one)."""

    point: str
    a: str
    b: str
    where: str
    carrier: str = ""
    ca: str = ""
    cb: str = ""
    ratio: float = 0.0


@dataclass(frozen=True)
class _Frame:
    """A placed link's frame as the element that places it defines it: origin, unit x-axis at the pose,
    and the pair of points that spans it (None where the frame is the link's own, e.g. a block's)."""

    origin: str
    e: Vec
    pair: tuple[str, str] | None


# -------------------------------------------------------------------------------------------- reading
def _short(value, limit: int = 60) -> str:
    """``repr(value)`` cut to ``limit`` characters (a message stays one readable line)."""
    text = repr(value)
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _fail(source: str, where: str, what: str) -> FileError:
    return FileError(f"{source}: {where}: {what}")


def _table(data, key: str, source: str) -> dict:
    value = data.get(key, {})
    if not isinstance(value, dict):
        raise _fail(source, key, "must be a table NAME = [x, y]")
    if len(value) > MAX_ITEMS:
        raise _fail(source, key, f"{len(value)} entries; a mechanism file holds at most {MAX_ITEMS}")
    return value


def _array(data, key: str, source: str) -> list:
    value = data.get(key, [])
    if not isinstance(value, list):
        raise _fail(source, key, f"must be an array of tables ([[{key}]])")
    if len(value) > MAX_ITEMS:
        raise _fail(source, key, f"{len(value)} entries; a mechanism file holds at most {MAX_ITEMS}")
    return value


def _point_name(v, source: str, where: str) -> str:
    if not (isinstance(v, str) and expr.NAME.match(v)):
        raise _fail(source, where, f"{_short(v)} must be a point name (letters, digits and _, starting with a letter)")
    return v


def _link_name(v, source: str, where: str) -> str:
    if not (isinstance(v, str) and LINK_NAME.match(v)):
        raise _fail(source, where, f"{_short(v)} must be a link name (letters, digits and _)")
    return v


def _sym(raw, values: dict, source: str, where: str, angle: bool = False) -> Sym:
    """A value as written (a number, ``"30deg"``, a parameter name or an expression) at the file's values."""
    if isinstance(raw, bool) or not isinstance(raw, (int, float, str)):
        raise _fail(source, where, f"{raw!r} must be a number, a parameter name or an expression")
    if isinstance(raw, (int, float)):
        if not (math.isfinite(raw) and abs(raw) <= 1e12):
            raise _fail(source, where, f"{raw!r} must be finite, of magnitude <= 1e12")
        return const(raw)
    q = expr.quantity(raw)
    if q is not None:
        if q[1] and not angle:
            raise _fail(source, where, f"{raw!r} is an angle where a length is expected")
        return const(q[0])
    try:
        return Sym(expr.evaluate(raw, values), f"({raw})")
    except ValueError as exc:
        raise _fail(source, where, str(exc)) from None


def _fields(item, where: str, allowed: set, source: str, what: str) -> dict:
    if not isinstance(item, dict):
        raise _fail(source, where, "must be a table of fields")
    unknown = sorted(set(item) - allowed)
    if unknown:
        raise _fail(source, where, f"unknown field {unknown[0]!r}; {what} takes {', '.join(sorted(allowed))}")
    return item


@dataclass
class _Form:
    """A links-and-joints file, read and checked (names, references, the pose)."""

    source: str
    links: dict[str, list[str]]                 # every link (the ground first) -> its points
    pins: dict[str, list[str]]                  # point -> the links pinned together there (R joints)
    slides: list[_Slide]
    pose: dict[str, Vec]
    ground: list[str]
    inputs: list[tuple[dict, str]]
    where_link: dict[str, str]
    size: float = 0.0
    kinds: dict[str, str] = field(default_factory=dict)
    meshes: list[_Mesh] = field(default_factory=list)


class _Measures:
    """What each parameter measures (``length`` or ``angle``), from where the form uses it."""

    def __init__(self, source: str):
        self.source = source
        self.kinds: dict[str, str] = {}

    def use(self, raw, kind: str, where: str):
        if not (isinstance(raw, str) and expr.quantity(raw) is None):
            return
        try:
            names = expr.names_in(raw)
        except ValueError as exc:
            raise _fail(self.source, where, str(exc)) from None
        for n in names:
            if self.kinds.get(n, kind) != kind:
                raise _fail(self.source, where, f"parameter {n!r} is used as a {self.kinds[n]} elsewhere and as a "
                                                f"{kind} here; use two parameters")
            self.kinds[n] = kind


def _read_links(data: dict, source: str, values: dict, measures: _Measures):
    """``[[links]]``: each link's listed points, where it is written, and the lengths it gives."""
    links: dict[str, list[str]] = {GROUND: []}
    where_link = {GROUND: "ground"}
    lengths = []
    for i, item in enumerate(_array(data, "links", source), 1):
        where = f"links[{i}]"
        _fields(item, where, {"name", "points", "lengths"}, source, "a link")
        if "name" not in item:
            raise _fail(source, where, "field 'name' is missing")
        name = _link_name(item["name"], source, f"{where}: field 'name'")
        where = f"links[{i}] ({name})"
        if name in links and name != GROUND:
            raise _fail(source, where, f"link {name!r} is given twice; give each link once")
        pts = item.get("points", [])
        if not isinstance(pts, list):
            raise _fail(source, where, "field 'points' must be a list of point names")
        pts = [_point_name(p, source, f"{where}: field 'points'") for p in pts]
        if len(set(pts)) != len(pts):
            raise _fail(source, where, "field 'points': a point is listed twice")
        links.setdefault(name, [])
        links[name] += [p for p in pts if p not in links[name]]
        where_link[name] = where
        given = item.get("lengths", [])
        if not isinstance(given, list):
            raise _fail(source, where, "field 'lengths' must be a list of [\"P\", \"Q\", length]")
        for entry in given:
            if not (isinstance(entry, list) and len(entry) == 3):
                raise _fail(source, where, f"field 'lengths': {entry!r} must be [\"P\", \"Q\", length]")
            p = _point_name(entry[0], source, f"{where}: field 'lengths'")
            q = _point_name(entry[1], source, f"{where}: field 'lengths'")
            measures.use(entry[2], "length", f"{where}: field 'lengths'")
            lengths.append((name, p, q, _sym(entry[2], values, source, f"{where}: field 'lengths'"), where))
    return links, where_link, lengths


def _read_joints(data: dict, source: str, values: dict, measures: _Measures, links: dict):
    """``[[joints]]``: the links pinned at each point, the P joints (a direction ``along`` a point kept as
    that point's name until the pose is read), and every link that has a joint."""
    def known_link(name, where):
        _link_name(name, source, where)
        if name not in links:
            raise _fail(source, where, f"no link named {name!r}; declare it under [[links]] (links: "
                                       f"{', '.join(links)})")
        return name

    pins: dict[str, list[str]] = {}
    slides: list[_Slide] = []
    meshes: list[_Mesh] = []
    joint_links: set[str] = set()
    for i, item in enumerate(_array(data, "joints", source), 1):
        where = f"joints[{i}]"
        if not isinstance(item, dict):
            raise _fail(source, where, "must be a table of fields")
        kind = item.get("kind")
        point = _point_name(item.get("point"), source, f"{where}: field 'point'")
        where = f"joints[{i}] (point {point})"
        if kind == "R":
            _fields(item, where, {"kind", "point", "links"}, source, "an R joint")
            ls = item.get("links")
            if not (isinstance(ls, list) and len(ls) >= 2):
                raise _fail(source, where, "field 'links' must list the two (or more) links pinned at the point")
            ls = [known_link(x, f"{where}: field 'links'") for x in ls]
            if len(set(ls)) != len(ls):
                raise _fail(source, where, "field 'links': a link is listed twice")
            at = pins.setdefault(point, [])
            at += [x for x in ls if x not in at]
            joint_links.update(ls)
        elif kind == "P":
            _fields(item, where, {"kind", "point", "guide", "block", "angle", "along"}, source, "a P joint")
            for f in ("guide", "block"):
                if f not in item:
                    raise _fail(source, where, f"field {f!r} is missing (the block slides on the guide link)")
            guide = known_link(item["guide"], f"{where}: field 'guide'")
            block = known_link(item["block"], f"{where}: field 'block'")
            if guide == block:
                raise _fail(source, where, "the guide and the block must be two links")
            if block == GROUND:
                raise _fail(source, where, "the block is the ground: make the ground the guide and the moving "
                                           "link the block (a P joint is the same either way round)")
            if ("angle" in item) == ("along" in item):
                raise _fail(source, where, "give the slide direction: angle = \"30deg\" (in the pose) or "
                                           "along = \"Q\" (a point the line runs towards in the pose)")
            if "angle" in item:
                measures.use(item["angle"], "angle", f"{where}: field 'angle'")
                angle = _sym(item["angle"], values, source, f"{where}: field 'angle'", angle=True)
            else:
                angle = _point_name(item["along"], source, f"{where}: field 'along'")
            if any(s.point == point for s in slides):
                raise _fail(source, where, f"point {point!r} already has a P joint; give each its own point")
            slides.append(_Slide(point, guide, block, angle, where))
            joint_links.update((guide, block))
        elif kind == "G":
            _fields(item, where, {"kind", "point", "links"}, source, "a G joint")
            ls = item.get("links")
            if not (isinstance(ls, list) and len(ls) == 2):
                raise _fail(source, where, "field 'links' must name the two links whose gears mesh at the point")
            a, b = (known_link(x, f"{where}: field 'links'") for x in ls)
            if a == b:
                raise _fail(source, where, "field 'links': a gear meshes with another link's gear; name two links")
            if any(m.point == point for m in meshes) or point in pins or any(s.point == point for s in slides):
                raise _fail(source, where, f"point {point!r} already has a joint; give each gear mesh its own pitch "
                                           f"point")
            meshes.append(_Mesh(point, a, b, where))
        else:
            raise _fail(source, where, f"unknown kind {kind!r}; a joint is kind = \"R\" (links pinned at a point), "
                                       f"\"P\" (a block sliding on a guide link) or \"G\" (two gears meshing at "
                                       f"their pitch point)")
    return pins, slides, meshes, joint_links


def _read_pose(data: dict, source: str, values: dict, measures: _Measures) -> tuple[dict[str, Vec], dict]:
    """``[pose]`` and ``[ground]``: every point's position; and the ``[ground]`` table."""
    ground_table = _table(data, "ground", source)
    pose: dict[str, Vec] = {}
    for section, table in (("ground", ground_table), ("pose", _table(data, "pose", source))):
        for p, xy in table.items():
            where = f"{section}.{p}"
            _point_name(p, source, where)
            if p in pose:
                raise _fail(source, where, f"point {p!r} is given in both [ground] and [pose]; give it once")
            if not (isinstance(xy, list) and len(xy) == 2):
                raise _fail(source, where, f"{xy!r} must be [x, y]")
            for v in xy:
                measures.use(v, "length", where)
            pose[p] = Vec(_sym(xy[0], values, source, where), _sym(xy[1], values, source, where))
    return pose, ground_table


def _complete(source, links, pins, slides, pose, ground_table) -> None:
    """Every point on its links (listed, pinned by an R joint, a P joint's block point), the ground's
    points, and each P joint's direction (from ``along``), in place."""
    for p, ls in pins.items():
        for ln in ls:
            if p not in links[ln]:
                links[ln].append(p)
    for s in slides:
        if s.point in links[s.guide] and s.point not in pins.get(s.point, ()):
            raise _fail(source, s.where, f"point {s.point!r} belongs to the block {s.block!r}, which slides on "
                                         f"{s.guide!r}: remove it from the points of {s.guide!r}")
        if s.point not in links[s.block]:
            links[s.block].append(s.point)
    for g in ground_table:
        if g not in links[GROUND]:
            links[GROUND].append(g)
    for k, s in enumerate(slides):
        if isinstance(s.angle, str):
            if s.angle not in pose or s.point not in pose:
                raise _fail(source, s.where, f"field 'along': points {s.point!r} and {s.angle!r} need positions in "
                                             f"[pose]")
            d = pose[s.angle] - pose[s.point]
            if d.norm().value == 0.0:
                raise _fail(source, s.where, f"field 'along': {s.angle!r} and {s.point!r} coincide in the pose; "
                                             f"name a point along the slide")
            slides[k] = _Slide(s.point, s.guide, s.block, d.angle(), s.where)


def _check_points(source, links, pins, pose, joint_links, where_link) -> None:
    """Every point has a position and is on a link; a point shared by links is pinned there; every link has
    a joint and a point."""
    carriers: dict[str, list[str]] = {}
    for ln, pts in links.items():
        for p in pts:
            carriers.setdefault(p, []).append(ln)
    for p, ls in carriers.items():
        if p not in pose:
            raise _fail(source, where_link.get(ls[0], "links"), f"point {p!r} has no position; give it under "
                                                                 f"[pose] as {p} = [x, y]")
        missing = [ln for ln in ls if ln not in pins.get(p, ())] if len(ls) > 1 else []
        if missing:
            names = ", ".join(f'"{x}"' for x in ls)
            raise _fail(source, where_link.get(missing[-1], "links"),
                        f"point {p!r} is on links {', '.join(ls)} but no R joint pins {', '.join(missing)} there; "
                        f"add {{kind = \"R\", point = \"{p}\", links = [{names}]}} under [[joints]], or give "
                        f"each link its own point")
    for p in pose:
        if p not in carriers:
            raise _fail(source, f"pose.{p}", f"point {p!r} is on no link; add it to a link's points or remove it")
    for ln in links:
        if ln != GROUND and ln not in joint_links:
            raise _fail(source, where_link[ln], f"link {ln!r} has no joint; join it to the mechanism under "
                                                f"[[joints]] or remove it")
        if ln != GROUND and not links[ln]:
            raise _fail(source, where_link[ln], f"link {ln!r} carries no point; give its points")


def _check_lengths(source, links, pose, lengths, size) -> None:
    """Each given length agrees with the pose (to :data:`RIGID` of the size)."""
    for ln, p, q, length, where in lengths:
        for x in (p, q):
            if x not in links[ln]:
                raise _fail(source, where, f"field 'lengths': link {ln!r} does not carry {x!r}")
        d = (pose[q] - pose[p]).norm().value
        if abs(d - length.value) > RIGID * size:
            raise _fail(source, where, f"the pose puts {p} and {q} {d:.9g} apart but 'lengths' gives "
                                       f"{length.value:.9g}: the pose is not rigid with the link; move {p} or {q}, "
                                       f"or change the length")


def _read_inputs(data: dict, source: str, measures: _Measures) -> list[tuple[dict, str]]:
    """``[[inputs]]`` as written (checked against the links when they are placed)."""
    inputs = []
    for i, item in enumerate(_array(data, "inputs", source), 1):
        where = f"inputs[{i}]"
        if not isinstance(item, dict):
            raise _fail(source, where, "must be a table of fields")
        kind = item.get("kind")
        own = kinds.KINDS.get(kind) if isinstance(kind, str) else None
        if own is None or own.section != "inputs" or own.joints_form is None:
            known = [k for k in kinds.KINDS.values() if k.section == "inputs" and k.joints_form is not None]
            listed = " or ".join(f"\"{k.name}\" ({k.joints_summary})" for k in known)
            raise _fail(source, where, f"unknown kind {kind!r}; an input is kind = {listed}")
        _fields(item, where, {"kind", *own.joints_form, *LAW_FIELDS}, source, f"a {kind}")
        for f, what in own.joints_form.items():
            if what in ("angle", "length"):
                measures.use(item.get(f), what, f"{where}: field {f!r}")
        inputs.append((item, where))
    if not inputs:
        raise _fail(source, "inputs", "none given; add [[inputs]] (kind = \"crank\", pivot = \"A\", point = \"B\")")
    return inputs


def _read(data: dict, source: str, values: dict) -> _Form:
    """A links-and-joints file read and checked: names, references, positions, given lengths."""
    measures = _Measures(source)
    links, where_link, lengths = _read_links(data, source, values, measures)
    pins, slides, meshes, joint_links = _read_joints(data, source, values, measures, links)
    pose, ground_table = _read_pose(data, source, values, measures)
    _complete(source, links, pins, slides, pose, ground_table)
    xy = np.array([v.value for v in pose.values()] or [(0.0, 0.0)])
    size = float(np.sqrt(np.max(np.sum((xy[:, None, :] - xy[None, :, :]) ** 2, axis=-1))))
    if not size > 0:
        raise _fail(source, "pose", "every point is at the same place; give the assembled positions")
    meshes = [_resolve_mesh(source, m, links, pins, pose, size) for m in meshes]
    _check_points(source, links, pins, pose, joint_links, where_link)
    _check_lengths(source, links, pose, lengths, size)
    inputs = _read_inputs(data, source, measures)
    return _Form(source, links, pins, slides, pose, links[GROUND], inputs, where_link, size, measures.kinds, meshes)


def _centre(g: str, c: str, pins: dict, pose: dict, size: float) -> str | None:
    """The point gear ``g`` turns about that is fixed on link ``c``: a pin of ``g`` and ``c``, or a pin of
    ``g`` and a link Z where ``c`` too is pinned to Z, at the same place in the pose (coaxial pins)."""
    for p, ls in pins.items():
        if g in ls and c in ls:
            return p
    for p, ls in pins.items():
        if g not in ls:
            continue
        for z in ls:
            for q, lq in pins.items():
                if (z != g and z in lq and c in lq and p in pose and q in pose
                        and (pose[q] - pose[p]).norm().value <= RIGID * size):
                    return p
    return None


def _resolve_mesh(source, m: _Mesh, links, pins, pose, size) -> _Mesh:
    """A G joint's carrier, centres and ratio from the pose; the pitch point becomes a point of the carrier
    (it lies on the line of centres, fixed on the carrier)."""
    where = m.where
    if m.point not in pose:
        raise _fail(source, where, f"point {m.point!r} has no position; give the pitch point (where the pitch "
                                   f"circles touch) under [pose]")
    cands = [(c, ca, cb) for c in links if c not in (m.a, m.b)
             for ca in [_centre(m.a, c, pins, pose, size)] for cb in [_centre(m.b, c, pins, pose, size)]
             if ca is not None and cb is not None]
    if not cands:
        raise _fail(source, where, f"the gears of {m.a} and {m.b} turn about no common carrier: pin each gear's "
                                   f"link by an R joint to the link that carries both centres (the ground, or an arm)")
    K = pose[m.point]
    problem = ""
    for c, ca, cb in cands:
        for x in (ca, cb):
            if x not in pose:
                raise _fail(source, where, f"point {x!r} has no position; give it under [pose] as {x} = [x, y]")
        r_a, r_b = (K - pose[ca]).norm().value, (K - pose[cb]).norm().value
        for g, r, centre in ((m.a, r_a, ca), (m.b, r_b, cb)):
            if r <= SINGULAR * size:
                raise _fail(source, where, f"the pitch point {m.point} is at the centre {centre} of {g}'s gear (a "
                                           f"pitch radius of 0); put it where the two pitch circles touch")
        d = (pose[cb] - pose[ca]).norm().value
        external = (K - pose[ca]).dot(K - pose[cb]).value < 0
        if abs((r_a + r_b if external else abs(r_a - r_b)) - d) > RIGID * size:
            problem = (f"the pitch point {m.point} is not on the line of the centres {ca} ({m.a}) and {cb} ({m.b}) "
                       f"on {c} (radii {r_a:.9g} and {r_b:.9g}, centre distance {d:.9g}); put it where the pitch "
                       f"circles touch")
            continue
        if not external and abs(r_a - r_b) <= SINGULAR * size:
            raise _fail(source, where, f"the gears of {m.a} and {m.b} have equal pitch radii about one centre: an "
                                       f"internal pair of ratio 1 cannot mesh")
        if m.point not in links[c]:
            links[c].append(m.point)
        return _Mesh(m.point, m.a, m.b, where, c, ca, cb, (-1.0 if external else 1.0) * r_a / r_b)
    raise _fail(source, where, problem)


# ------------------------------------------------------------------------------------- decomposition
def gruebler(form: _Form) -> tuple[int, str]:
    """Gruebler's count 3 (n - 1) - 2 j - h over the links (the ground included), lower pairs (a point
    where k links are pinned: k - 1 pairs) and gear meshes (higher pairs), and the count written out."""
    n = len(form.links)
    j = sum(len(ls) - 1 for ls in form.pins.values()) + len(form.slides)
    h = len(form.meshes)
    m = 3 * (n - 1) - 2 * j - h
    return m, f"3 x ({n} - 1) - 2 x {j}{f' - {h}' if h else ''} = {m}"


class _Decomposer:
    """Finds the Assur groups of a form and writes the ordinary form's elements (one call of
    :func:`convert`: its state lives only during it)."""

    def __init__(self, form: _Form, data: dict):
        self.f = form
        self.source = form.source
        self.pose = dict(form.pose)
        self.points = {ln: list(p) for ln, p in form.links.items()}
        self.known: set[str] = {GROUND}
        self.placed: set[str] = set(form.links[GROUND])
        self.frames: dict[str, _Frame] = {}
        self.items: list[tuple[dict, str]] = []
        self.classes: list[str] = []
        params = data.get("parameters", {})
        self.taken = set(params) | set(form.pose) | set(form.links)
        self.mobility, self.count = gruebler(form)
        self.turns: dict[str, dict[str, float]] = {GROUND: {}}   # a placed link's angle as a linear form of
        #                                                         the angles of the links not placed by gears
        self.geared = 0                                         # gear elements written
        self.counted: set[str] = {GROUND}                       # links whose angle the gear kind counts in turns

    # ------------------------------------------------------------------------------------ helpers
    def fail(self, where: str, what: str) -> FileError:
        return _fail(self.source, where, what)

    def out(self, s: Sym, where: str, what: str):
        try:
            return s.out()
        except ValueError:
            raise self.fail(where, f"the expression for {what} derived from the pose is over the format's limit "
                                   f"(400 characters, 40 levels); give the pose's coordinates as numbers or "
                                   f"single parameters") from None

    def xy(self, p: str, where: str) -> list:
        v = self.pose[p]
        return [self.out(v.x, where, f"x of {p}"), self.out(v.y, where, f"y of {p}")]

    def fresh(self, base: str) -> str:
        name, k = base, 2
        while name in self.taken:
            name, k = f"{base}{k}", k + 1
        self.taken.add(name)
        return name

    def emit(self, item: dict, where: str):
        self.items.append((item, where))

    def slides_of(self, ln: str) -> list[_Slide]:
        return [s for s in self.f.slides if ln in (s.guide, s.block)]

    def other(self, s: _Slide, ln: str) -> str:
        return s.block if s.guide == ln else s.guide

    def known_points(self, ln: str) -> list[str]:
        return [p for p in self.points[ln] if p in self.placed]

    def known_slides(self, ln: str) -> list[_Slide]:
        return [s for s in self.slides_of(ln) if self.other(s, ln) in self.known]

    def ext(self, ln: str) -> int:
        """Constraints between a link not placed and what is placed: 2 per placed point it carries, 2 per
        prismatic pair with a placed link."""
        return 2 * len(self.known_points(ln)) + 2 * len(self.known_slides(ln))

    def between(self, a: str, b: str) -> tuple[list[str], list[_Slide]]:
        """The joints between two links not placed: shared points not placed, prismatic pairs."""
        shared = [p for p in self.points[a] if p in self.points[b] and p not in self.placed]
        return shared, [s for s in self.f.slides if {s.guide, s.block} == {a, b}]

    def loop_through(self, starts: set[str], ends: set[str]) -> list[str]:
        """The shortest chain of placed links from one of ``starts`` to one of ``ends``."""
        prev = {s: None for s in starts}
        queue = list(starts)
        while queue:
            ln = queue.pop(0)
            if ln in ends:
                chain = [ln]
                while prev[chain[-1]] is not None:
                    chain.append(prev[chain[-1]])
                return chain
            for other in self.known:
                if other not in prev and (set(self.points[ln]) & set(self.points[other]) or any(
                        {s.guide, s.block} == {ln, other} for s in self.f.slides)):
                    prev[other] = ln
                    queue.append(other)
        return []

    def gruebler_note(self) -> str:
        n = len(self.f.inputs)
        return f"Gruebler: {self.count}, with {n} input{'s' if n != 1 else ''}"

    # ---------------------------------------------------------------------------------- frames
    def set_frame(self, ln: str, origin: str, e: Vec, pair: tuple[str, str] | None = None):
        self.frames[ln] = _Frame(origin, e, pair)
        self.known.add(ln)
        self.turns.setdefault(ln, {ln: 1.0})

    def pair_frame(self, ln: str, p: str, q: str):
        self.set_frame(ln, p, (self.pose[q] - self.pose[p]).unit(), (p, q))

    def local(self, ln: str, p: str) -> tuple[Sym, Sym]:
        fr = self.frames[ln]
        r = self.pose[p] - self.pose[fr.origin]
        return fr.e.dot(r), fr.e.cross(r)

    def rigid(self, ln: str, where: str):
        """Every point of a placed link not yet placed: a point fixed in the link's frame."""
        fr = self.frames[ln]
        for p in self.points[ln]:
            if p in self.placed:
                continue
            u, v = self.local(ln, p)
            on = list(fr.pair) if fr.pair else ln
            self.emit({"kind": "point", "point": p, "on": on,
                       "at": [self.out(u, where, f"u of {p}"), self.out(v, where, f"v of {p}")]},
                      f"link {ln}")
            self.placed.add(p)

    def aux_point(self, ln: str, base: str, at: Vec) -> str:
        """A helper point fixed on placed link ``ln`` at pose position ``at`` (a guide's direction)."""
        name = self.fresh(base)
        self.pose[name] = at
        self.points[ln].append(name)
        self.rigid(ln, f"link {ln}")
        return name

    # ---------------------------------------------------------------------------------- inputs
    def inputs(self) -> bool:
        """Place every input whose kind says it is ready (each input kind places its own); the others wait for
        the groups that place what they need (a motor's carrier). Whether one was placed. A motion law on the
        entry (SPEC "Motion laws") replaces the kind's own: its rates dropped, a table's start too."""
        placed = False
        for item, where in list(self.waiting):
            kind = kinds.get(item["kind"])
            if kind.joints_ready(item, self):
                self.waiting.remove((item, where))
                n = len(self.items)
                kind.from_joints(item, where, self)
                law = {f: item[f] for f in LAW_FIELDS if f in item}
                if law and len(self.items) > n:
                    emitted, w = self.items[n]
                    drop = kind.motion_fields[1:] if "segments" in law else kind.motion_fields
                    self.items[n] = ({**{k: v for k, v in emitted.items() if k not in drop}, **law}, w)
                placed = True
        return placed

    # what the input kinds' from_joints use (analytic.kinds.base.Kind.from_joints)
    SINGULAR = SINGULAR

    def point_name(self, v, where: str) -> str:
        return _point_name(v, self.source, where)

    def link_name(self, v, where: str) -> str:
        return _link_name(v, self.source, where)

    def slide_frame(self, block: str, point: str, angle: Sym):
        """The frame of a block sliding at ``angle`` (to the ground), its origin at ``point``."""
        self.set_frame(block, point, direction(angle))

    # ------------------------------------------------------------------------------------ groups
    def run(self) -> None:
        self.waiting = list(self.f.inputs)
        self.inputs()
        while True:
            if self.waiting and self.inputs():
                continue
            todo = [ln for ln in self.points if ln not in self.known]
            if not todo:
                break
            for ln in todo:
                self.check_single(ln)
            if not (self.gears(todo) or self.dyad(todo)):
                try:
                    self.group(todo)
                except FileError:
                    for item, where in self.waiting:      # an input still waiting says what it lacks first
                        kinds.get(item["kind"]).from_joints(item, where, self)
                    raise
        for item, where in self.waiting:                  # an input whose links other groups placed
            kinds.get(item["kind"]).from_joints(item, where, self)
        if self.geared != len(self.f.meshes):
            names = ", ".join(f"{m.point} ({m.a}, {m.b})" for m in self.f.meshes)
            raise self.fail(f"gear meshes {names}", f"{len(self.f.meshes)} gear meshes but only {self.geared} links "
                                                    f"turn by them: the others' links are already fixed by joints "
                                                    f"(a locked or redundant loop; {self.gruebler_note()}); remove a "
                                                    f"mesh or a joint")

    # ------------------------------------------------------------------------------------- gears
    def tooth(self, ln: str) -> str | None:
        """A helper point on a gear link that carries no point besides its centre: ``<link>_tooth``, at its
        first mesh's pitch point in the pose (it gives the link its frame)."""
        m = next((m for m in self.f.meshes if ln in (m.a, m.b)), None)
        if m is None:
            return None
        name = self.fresh(f"{ln}_tooth")
        self.pose[name] = self.pose[m.point]
        self.points[ln].append(name)
        return name

    def gears(self, todo: list[str]) -> bool:
        """Place one link that gears turn: a link not placed, pinned at one placed point (its centre) and
        whose angle Willis' relations of the meshes fix as a linear form of placed links' angles. Tried
        before the dyads, so that a gear's link is never placed as if it were free."""
        for x in todo:
            pts = self.known_points(x)
            if len(pts) != 1 or self.known_slides(x) or not any(x in (m.a, m.b, m.carrier) for m in self.f.meshes):
                continue
            w = self.geared_turns(x)
            if w is not None:
                self.gear(x, pts[0], w)
                return True
        return False

    def geared_turns(self, x: str) -> dict[str, float] | None:
        """The angle of link ``x`` as a linear form (coefficients over the angles of the links not placed by
        gears) where the meshes' relations phi_b - phi_c - ratio (phi_a - phi_c) = phase fix it, else None."""
        unknown = list(dict.fromkeys(ln for m in self.f.meshes for ln in (m.a, m.b, m.carrier)
                                     if ln not in self.known))
        if x not in unknown:
            return None
        rows, rhs = [], []
        for m in self.f.meshes:
            coef: dict[str, float] = {}
            for ln, c in ((m.b, 1.0), (m.a, -m.ratio), (m.carrier, m.ratio - 1.0)):
                coef[ln] = coef.get(ln, 0.0) + c
            if all(ln in self.known for ln in coef):
                continue
            known: dict[str, float] = {}
            for ln, c in coef.items():
                for base, v in self.turns.get(ln, {}).items() if ln in self.known else ():
                    known[base] = known.get(base, 0.0) + c * v
            rows.append([coef.get(u, 0.0) for u in unknown])
            rhs.append(known)
        if not rows:
            return None
        A = np.array(rows)
        e = np.zeros(len(unknown))
        e[unknown.index(x)] = 1.0
        y = np.linalg.lstsq(A.T, e, rcond=None)[0]
        if np.linalg.norm(A.T @ y - e) > 1e-9:
            return None
        w: dict[str, float] = {}
        for yi, known in zip(y, rhs):
            for base, v in known.items():
                w[base] = w.get(base, 0.0) - yi * v
        return w

    def gear(self, x: str, pivot: str, w: dict[str, float]):
        """Write link ``x`` as a ``gear`` element: on the placed link ``y`` it is pinned to at ``pivot`` (the
        carrier), meshed with a placed link that turns about one pin on ``y``, preferably a link its own gear
        meshes with on ``y``; ratio and phase such that the element's relation is the meshes' one."""
        mesh_of_x = next(m for m in self.f.meshes if x in (m.a, m.b, m.carrier))
        label = mesh_of_x.where
        ys = [ln for ln in self.f.pins.get(pivot, []) if ln in self.known and ln != x]
        if not ys:
            raise self.fail(label, f"link {x!r} is on the placed point {pivot} without a pin; pin it by an R joint")
        y = ys[0]
        wy = self.turns[y]

        def minus(p, q):
            return {k: p.get(k, 0.0) - q.get(k, 0.0) for k in set(p) | set(q)}

        def dot(p, q):
            return sum(v * q.get(k, 0.0) for k, v in p.items())

        d = minus(w, wy)
        if dot(d, d) <= 1e-24:
            raise self.fail(label, f"the gear meshes hold {x} still relative to {y} (it cannot turn on its pin "
                                   f"{pivot}): a locked train; check the meshes' links")
        partners = [m.a if m.b == x else m.b for m in self.f.meshes if x in (m.a, m.b) and m.carrier == y]
        found = None
        for mesh in dict.fromkeys(partners + sorted(self.known)):
            if mesh in (x, y) or mesh not in self.known:
                continue
            if len([p for p in self.points[mesh] if p in self.points[y]]) != 1:
                continue
            dm = minus(self.turns[mesh], wy)
            if dot(dm, dm) <= 1e-24:
                continue
            k = dot(d, dm) / dot(dm, dm)
            res = minus(d, {key: k * v for key, v in dm.items()})
            if math.sqrt(dot(res, res)) <= 1e-9 * max(1.0, math.sqrt(dot(d, d))):
                found = mesh, k
                break
        if found is None:
            raise self.fail(label, f"link {x!r} turns on {y} about {pivot}, but no placed link that turns about one "
                                   f"pin on {y} drives it at a fixed ratio; this train cannot be written as gear "
                                   f"pairs")
        mesh, k = found
        point = next((p for p in self.points[x] if p not in self.placed), None) or self.tooth(x)
        where = f"{label} (link {x})"

        def angle(ln):
            return 0.0 if ln == GROUND else self.frames[ln].e.angle().value

        r = self.pose[point] - self.pose[pivot]
        if r.norm().value <= SINGULAR * self.f.size:
            raise self.singular(where, f"{point} is at the gear's centre {pivot}")
        theta = angle(mesh) - angle(y)
        if mesh not in self.counted and y not in self.counted:       # as the gear kind measures two rockers
            theta = (theta + math.pi) % (2.0 * math.pi) - math.pi
        phase = r.angle().value - angle(y) - k * theta
        self.emit({"kind": "gear", "point": point, "pivot": pivot,
                   "length": self.out(r.norm(), where, f"|{pivot}{point}|"), "link": x, "mesh": mesh,
                   "carrier": y, "ratio": k, "phase": phase}, label)
        self.turns[x] = w
        self.counted.add(x)
        self.geared += 1
        self.placed.add(point)
        self.pair_frame(x, pivot, point)
        self.classes.append(f"gear {x} on {y} about {pivot} (mesh {mesh}, ratio {k:.9g})")
        self.rigid(x, label)

    def check_single(self, ln: str):
        if self.ext(ln) <= 3:
            return
        pts, sl = self.known_points(ln), self.known_slides(ln)
        holds = [{x for x, ps in self.points.items() if x in self.known and p in ps} for p in pts]
        holds += [{self.other(s, ln)} for s in sl]
        fixers = sorted(set().union(*holds))
        chain = self.loop_through(holds[0], holds[1])
        loop = " - ".join([ln] + chain)
        held = ", ".join(pts + [f"the P joint at {s.point}" for s in sl])
        raise self.fail(self.f.where_link.get(ln, ln),
                        f"the loop {loop} cannot move: link {ln!r} is held at {held}, which {', '.join(fixers)} "
                        f"already fix (a redundant or locked loop; {self.gruebler_note()}); remove one of those "
                        f"joints or add a link")

    def dyad(self, todo: list[str]) -> bool:
        ready = [ln for ln in todo if self.ext(ln) == 2]
        for a, b in combinations(ready, 2):
            shared, sl = self.between(a, b)
            if len(shared) + len(sl) != 1:
                continue
            ea = self.known_points(a) or self.known_slides(a)
            eb = self.known_points(b) or self.known_slides(b)
            ta = "R" if isinstance(ea[0], str) else "P"
            tb = "R" if isinstance(eb[0], str) else "P"
            mid = "R" if shared else "P"
            label = f"links {a}, {b}"
            if (ta, mid, tb) == ("R", "R", "R"):
                self.rrr(a, b, ea[0], eb[0], shared[0], label)
            elif mid == "R" and {ta, tb} == {"R", "P"}:
                rod, block = (a, b) if ta == "R" else (b, a)
                self.rrp(rod, block, (ea if ta == "R" else eb)[0], shared[0],
                         (eb if ta == "R" else ea)[0], label)
            elif (ta, mid, tb) == ("R", "P", "R"):
                self.rpr(sl[0], {a: ea[0], b: eb[0]}, label)
            elif (ta, mid, tb) == ("P", "P", "P"):
                self.locked_ppp(a, b, ea[0], sl[0], eb[0])
            else:
                self.pp_dyad(a, b, ta + mid + tb, label)
            return True
        return False

    def singular(self, where: str, what: str) -> FileError:
        return self.fail(where, f"the pose is singular: {what}, so it gives no branch; draw the mechanism in "
                                f"another pose")

    def rrr(self, m: str, n: str, p: str, q: str, c: str, label: str):
        P, Q, C = self.pose[p], self.pose[q], self.pose[c]
        where = f"{label} (point {c})"
        if (Q - P).norm().value <= SINGULAR * self.f.size:
            raise self.singular(where, f"{m} and {n} are pinned at {p} and {q}, which coincide")
        turn = (Q - P).cross(C - P)
        if abs(turn.value) <= SINGULAR * self.f.size ** 2:
            raise self.singular(where, f"{p}, {c} and {q} are in line (a dead centre of {m} and {n})")
        self.emit({"kind": "RRR", "point": c, "from": [p, q],
                   "lengths": [self.out((C - P).norm(), where, f"|{p}{c}|"),
                               self.out((C - Q).norm(), where, f"|{q}{c}|")],
                   "links": [m, n], "branch": 1 if turn.value > 0 else -1}, label)
        self.placed.add(c)
        self.pair_frame(m, p, c)
        self.pair_frame(n, q, c)
        self.classes.append(f"dyad RRR {m}, {n} at {c}")
        self.rigid(m, label)
        self.rigid(n, label)

    def guide_of(self, s: _Slide, known: str, pin: str, where: str):
        """The guide of a link sliding (by the P joint ``s``) on the placed link ``known``, whose pin ``pin``
        moves on a line of ``known`` parallel to the slide: (the field's value, origin, unit direction,
        offset of the pin's line). A P joint is the same either way round: ``known`` may be its block."""
        u = direction(s.angle)
        if known == GROUND:
            return ({"through": self.xy(pin, where), "angle": self.out(s.angle, where, "the slide angle")},
                    self.pose[pin], u, const(0.0))
        pts = self.known_points(known)
        if not pts:
            raise self.fail(where, f"link {known!r} carries no point to draw its guide from; give it one")
        g0 = self.frames[known].origin if self.frames[known].origin in pts else pts[0]
        g1 = None
        for q in pts:
            d = self.pose[q] - self.pose[g0]
            n = d.norm().value
            if n > SINGULAR * self.f.size and abs(d.cross(u).value) <= SINGULAR * n:
                g1 = q
                if d.dot(u).value < 0:
                    g0, g1 = g1, g0
                break
        if g1 is None:
            g1 = self.aux_point(known, f"{s.point}_guide", self.pose[g0] + u.scaled(const(self.f.size)))
        e = (self.pose[g1] - self.pose[g0]).unit()
        offset = e.cross(self.pose[pin] - self.pose[g0])
        return [g0, g1], self.pose[g0], e, offset

    def rrp(self, rod: str, block: str, p: str, c: str, s: _Slide, label: str):
        where = f"{label} (point {c})"
        guide, O, e, offset = self.guide_of(s, self.other(s, block), c, where)
        Oe = O + e.perp().scaled(offset)
        along = (self.pose[c] - Oe).dot(e) - (self.pose[p] - Oe).dot(e)
        if abs(along.value) <= SINGULAR * self.f.size:
            raise self.singular(where, f"the rod {p}-{c} is square to the guide of {block}")
        self.emit({"kind": "RRP", "point": c, "from": p,
                   "length": self.out((self.pose[c] - self.pose[p]).norm(), where, f"|{p}{c}|"),
                   "guide": guide, "offset": self.out(offset, where, "the guide's offset"),
                   "links": [rod, block], "branch": 1 if along.value > 0 else -1}, label)
        self.placed.add(c)
        self.pair_frame(rod, p, c)
        self.set_frame(block, c, e)
        self.classes.append(f"dyad RRP {rod}, {block} at {c}")
        self.rigid(rod, label)
        self.rigid(block, label)

    def rpr(self, s: _Slide, pivots: dict, label: str):
        slotted, block = s.guide, s.block
        p, q = pivots[slotted], pivots[block]
        where = f"{label} (point {s.point})"
        u = direction(s.angle)
        r = self.pose[q] - self.pose[p]
        along = r.dot(u)
        if abs(along.value) <= SINGULAR * self.f.size:
            raise self.singular(where, f"the slot of {slotted} is square to {p}-{q}")
        if along.value < 0:
            u, along = -u, -along
        offset = u.cross(r)
        point, length = None, along
        for x in self.points[slotted]:
            if x not in self.placed:
                rx = self.pose[x] - self.pose[p]
                lu, lv = u.dot(rx), u.cross(rx)
                if abs(lv.value) <= SINGULAR * self.f.size and lu.value > SINGULAR * self.f.size:
                    point, length = x, lu
                    break
        if point is None:
            point = self.fresh(f"{slotted}_slot")
            self.pose[point] = self.pose[p] + u.scaled(along)
            self.points[slotted].append(point)
        self.emit({"kind": "RPR", "pivot": p, "through": q, "point": point,
                   "length": self.out(length, where, "the slot point's distance"),
                   "offset": self.out(offset, where, "the slot's offset"), "links": [slotted, block], "branch": 1},
                  label)
        self.placed.add(point)
        self.set_frame(slotted, p, u)
        self.set_frame(block, q, u)
        self.classes.append(f"dyad RPR {slotted}, {block} at {s.point}")
        self.rigid(slotted, label)
        self.rigid(block, label)

    def locked_ppp(self, a: str, b: str, sa: _Slide, mid: _Slide, sb: _Slide):
        ga, gb = self.other(sa, a), self.other(sb, b)
        chain = self.loop_through({ga}, {gb})            # from gb back to ga
        loop = [ga, a, b] + (chain[:-1] if chain else [gb])
        joints = ", ".join(s.point for s in (sa, mid, sb))
        raise self.fail(f"links {a}, {b}",
                        f"the loop {' - '.join(loop)} locks the mechanism: the prismatic pairs at {joints} keep "
                        f"{ga} and {gb} at a fixed angle to each other{' although ' + ga + ' turns' if ga != gb else ''}"
                        f" and leave {a} and {b} free to slide; make one of them a pin in a slot (an R joint on a "
                        f"block) or an R joint")

    def pp_dyad(self, a: str, b: str, shape: str, label: str):
        """A dyad with two prismatic pairs, where those kinds are registered: ``PRP`` (two blocks on two guides
        pinned together) or ``RPP`` (a link pinned at a placed point sliding in the slot of a link that slides
        on a guide; ``PPR`` is the same chain read from its other end)."""
        canon = "PRP" if shape == "PRP" else "RPP"
        if canon not in kinds.KINDS:
            raise self.fail(label, f"a dyad with two prismatic pairs ({canon}), which this version cannot solve yet "
                                   f"(no kind {canon!r})")
        if canon == "PRP":
            c = self.between(a, b)[0][0]
            where = f"{label} (point {c})"
            (s1,), (s2,) = self.known_slides(a), self.known_slides(b)
            g1, O1, e1, off1 = self.guide_of(s1, self.other(s1, a), c, where)
            g2, O2, e2, off2 = self.guide_of(s2, self.other(s2, b), c, where)
            if abs(e1.cross(e2).value) <= SINGULAR:
                raise self.singular(where, f"the guides of {a} and {b} are parallel")
            self.emit({"kind": "PRP", "point": c, "guide1": g1, "offset1": self.out(off1, where, "offset1"),
                       "guide2": g2, "offset2": self.out(off2, where, "offset2"), "links": [a, b]}, label)
            self.placed.add(c)
            self.set_frame(a, c, e1)
            self.set_frame(b, c, e2)
            self.classes.append(f"dyad PRP {a}, {b} at {c}")
        else:
            pinned, yoke = (a, b) if shape[0] == "R" else (b, a)
            p = self.known_points(pinned)[0]
            (ext,) = self.known_slides(yoke)
            (mid,) = self.between(a, b)[1]
            where = f"{label} (the P joint at {mid.point})"
            u_ext, u_mid = direction(ext.angle), direction(mid.angle)
            if abs(u_ext.cross(u_mid).value) <= SINGULAR:
                raise self.singular(where, f"the slot of {yoke} is parallel to its guide")
            c = self.fresh(f"{yoke}_slot")             # the yoke's point where its slot crosses its line
            self.pose[c] = self.pose[p]
            self.points[yoke].append(c)
            guide, O, e, offset = self.guide_of(ext, self.other(ext, yoke), c, where)
            self.emit({"kind": "RPP", "point": c, "through": p, "guide": guide,
                       "offset": self.out(offset, where, "the yoke's offset"),
                       "angle": self.out(mid.angle - ext.angle, where, "the slot's angle"), "links": [pinned, yoke]},
                      label)
            self.placed.add(c)
            self.set_frame(yoke, c, e)
            self.set_frame(pinned, p, u_mid)
            self.classes.append(f"dyad RPP {pinned}, {yoke} at {c}")
        self.rigid(a, label)
        self.rigid(b, label)

    def group(self, todo: list[str]):
        adj = {ln: {x for x in todo if x != ln and any(self.between(ln, x))} for ln in todo}
        for k in range(2, min(len(todo), MAX_GROUP) + 1):
            found = None
            try:
                sets = list(_connected(todo, adj, k))
            except OverflowError:
                raise self.fail(f"links {_few(todo, 6)}",
                                f"no dyad is left among {len(todo)} links and they are too many to search for an "
                                f"Assur group of {k} links; check their joints (mobility: {self.count})") from None
            for S in sets:
                ext = sum(self.ext(ln) for ln in S)
                internal = self.internal(S)
                if internal > 3 * (k - 1) or ext + internal > 3 * k:
                    raise self.fail(f"links {', '.join(S)}",
                                    f"links {', '.join(S)} are over-constrained ({ext + internal} constraints on "
                                    f"{3 * k} freedoms: a redundant loop; {self.gruebler_note()}); remove a joint "
                                    f"or add a link")
                if ext + internal == 3 * k and found is None:
                    found = S
            if found is not None:
                return self.general(found)
        stuck = _few(todo)
        n = len(self.f.inputs)
        if self.mobility != n:
            raise self.fail("inputs", f"the mechanism has mobility {self.mobility} (Gruebler: {self.count}) but "
                                      f"{n} input{'s' if n != 1 else ''}: links {stuck} are not fixed by them; "
                                      f"give one input per degree of freedom, or add joints or links")
        raise self.fail(f"links {stuck}", f"links {stuck} cannot be placed from the ground and the inputs "
                                          f"(no Assur group of at most {MAX_GROUP} links); check their joints")

    def internal(self, S: tuple[str, ...]) -> int:
        n = 0
        for p in {p for ln in S for p in self.points[ln] if p not in self.placed}:
            on = sum(p in self.points[ln] for ln in S)
            n += 2 * (on - 1) if on > 1 else 0
        return n + 2 * sum(s.guide in S and s.block in S for s in self.f.slides)

    def general(self, S: tuple[str, ...]):
        label = f"links {', '.join(S)}"
        if "group" not in kinds.KINDS:
            raise self.fail(label, f"these {len(S)} links form an Assur group that is not a chain of dyads, and this "
                                   f"version has no general group kind to solve it")
        new = [p for p in dict.fromkeys(p for ln in S for p in self.points[ln]) if p not in self.placed
               and sum(p in self.points[ln] for ln in S) > 1]
        table = {}
        for ln in S:
            table[ln] = [p for p in self.points[ln] if p in self.placed or p in new]
        slides = [s for s in self.f.slides if s.guide in S or s.block in S]
        blocks = self.match_blocks(S, slides, label)
        spec = {}
        for s, b in zip(slides, blocks):
            other = self.other(s, b)
            where = f"{label} (the P joint at {s.point})"
            if s.point in self.points[b] and s.point not in table[b]:
                table[b].append(s.point)                       # the block's own point on the slide
            if not table[b]:                                   # a block with no point: one where the pose has the joint
                name = self.fresh(f"{b}_slot")
                self.pose[name] = self.pose[s.point]
                self.points[b].append(name)
                table[b].append(name)
            point = s.point if s.point in table[b] else table[b][0]
            if other == GROUND:
                guide = GROUND
            elif other in S:
                guide = other
            else:
                guide = self.guide_of(s, other, point, where)[0]
            spec[b] = {"guide": guide, "point": point, "angle": self.out(s.angle, where, "the slide's angle")}
        for ln in S:
            if len(table[ln]) < 2 and ln not in spec and not any(v["guide"] == ln for v in spec.values()):
                raise self.fail(label, f"link {ln!r} is joined at one point only inside the group; it cannot be "
                                       f"placed")
            if not table[ln]:
                raise self.fail(label, f"link {ln!r} carries no point of the group; give it a point where it is "
                                       f"joined")
        placed_here = [p for p in dict.fromkeys(p for pts in table.values() for p in pts) if p not in self.placed]
        where = f"{label} (points {', '.join(placed_here)})"
        used = list(dict.fromkeys(p for pts in table.values() for p in pts))
        used += [p for v in spec.values() if isinstance(v["guide"], list) for p in v["guide"] if p not in used]
        pose = {p: self.xy(p, where) for p in used}
        item = {"kind": "group", "points": placed_here, "links": table, "pose": pose}
        if spec:
            item["slides"] = spec
        self.emit(item, label)
        self.placed.update(placed_here)
        by_guide = {}
        for s, b in zip(slides, blocks):
            if isinstance(spec[b]["guide"], str):
                by_guide.setdefault(spec[b]["guide"], s)
        angle_of = {b: s.angle for s, b in zip(slides, blocks)}
        for ln, pts in table.items():
            if ln in angle_of:
                self.set_frame(ln, pts[0], direction(angle_of[ln]))
            elif len(pts) >= 2:
                self.pair_frame(ln, pts[0], pts[1])
            else:
                self.set_frame(ln, pts[0], direction(by_guide[ln].angle))
        kind = "group with prismatic pairs" if spec else "group"
        self.classes.append(f"{kind} of {len(S)} links {', '.join(S)}")
        for ln in S:
            self.rigid(ln, label)

    def match_blocks(self, S, slides, label) -> list[str]:
        """For each prismatic pair of a group, the link of the group named as its block (its ``s`` is named
        after it and its frame runs along the slide): each link the block of one pair at most, the joint's own
        block where it can be."""
        owner: dict[str, int] = {}

        def options(k):
            s = slides[k]
            return [x for x in (s.block, s.guide) if x in S]

        def place(k, seen):
            for x in options(k):
                if x in seen:
                    continue
                seen.add(x)
                if x not in owner or place(owner[x], seen):
                    owner[x] = k
                    return True
            return False

        for k in range(len(slides)):
            if not place(k, set()):
                pts = ", ".join(s.point for s in slides)
                raise self.fail(label, f"the prismatic pairs at {pts} need a block each among links "
                                       f"{', '.join(S)} and these are too few (a link that slides on two guides "
                                       f"in one group); make one of them an R joint on a block")
        out = [""] * len(slides)
        for x, k in owner.items():
            out[k] = x
        return out


def _few(names, n: int = 8) -> str:
    """Names for a message: the first ``n`` and how many more."""
    names = list(names)
    return ", ".join(names[:n]) + (f" and {len(names) - n} more" if len(names) > n else "")


def _connected(nodes: list[str], adj: dict[str, set[str]], k: int):
    """Every connected set of ``k`` nodes (as tuples in ``nodes`` order), each once."""
    rank = {n: i for i, n in enumerate(nodes)}
    seen = set()
    frontier = [frozenset([n]) for n in nodes]
    for _ in range(k - 1):
        grown = set()
        for s in frontier:
            for n in s:
                for x in adj[n] - s:
                    grown.add(s | {x})
            if len(grown) > MAX_SETS:
                raise OverflowError(k)
        frontier = list(grown)
    for s in frontier:
        if s not in seen:
            seen.add(s)
            yield tuple(sorted(s, key=rank.__getitem__))


# ------------------------------------------------------------------------------------------- convert
def convert(data: dict, source: str, values: dict[str, float]) -> Converted:
    """The ordinary form of a links-and-joints file's top-level table ``data``, with the parameters at
    their file ``values`` (see :func:`analytic.format.linkfile.parameter_values`)."""
    form = _read(data, source, values)
    dec = _Decomposer(form, data)
    dec.run()
    ground = {g: dec.xy(g, f"ground.{g}") for g in form.ground}
    out = {k: v for k, v in data.items() if k not in FIELDS + ("inputs", "groups", "ground")}
    if "output" not in out:
        moving = [p for p in form.pose if p not in form.ground]
        if moving:
            out["output"] = moving[-1]
    items = dec.items
    user = data.get("groups", [])
    if not isinstance(user, list):
        raise _fail(source, "groups", "must be an array of tables ([[groups]])")
    inputs = [(i, w) for i, w in items if kinds.get(i["kind"]).section == "inputs"]
    groups = [(i, w) for i, w in items if kinds.get(i["kind"]).section != "inputs"]
    out.update(ground=ground, inputs=[i for i, _ in inputs], groups=[i for i, _ in groups] + list(user))
    labels = tuple(w for _, w in inputs + groups) + tuple(f"groups[{k}]" for k in range(1, len(user) + 1))
    return Converted(out, labels, dict(form.kinds))


def structure(data: dict, source: str, values: dict[str, float]) -> tuple[str, ...]:
    """The Assur groups a links-and-joints file decomposes into, in solving order (for reports)."""
    form = _read(data, source, values)
    dec = _Decomposer(form, data)
    dec.run()
    return tuple(dec.classes)
