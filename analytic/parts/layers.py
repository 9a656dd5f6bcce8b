"""Layers: links whose outlines come closer than the clearance at any instant of the cycle never share a
layer, with the fewest layers (an exact graph colouring), and the plane distances between outlines over the
cycle that decide it (shapely polygons of the tessellated outlines, holes filled).

Sampling: the cycle is sampled uniformly; between two samples the distance of two rigid outlines changes by
at most the sum of their largest vertex displacements (the chord of the step), so an interval whose two
ends' distances leave less than that margin above the threshold is bisected (the motion solved at its
middle) until either a sample comes closer than the threshold or every interval is clear.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic.parts import model

FRAME = "frame"
"""The name of the optional frame outline in the pairs (``[parts].frame``, fixed to the ground, layer 0)."""

MAX_EXACT = 40
"""Links up to which the colouring is exact (backtracking); above it DSatur's greedy colouring."""
MAX_LINKS = 40
"""The most links the layering lays out: its pair distances over the cycle grow as the square of the count and
its outlines' memory as the count (31 links all within reach of one another: 5 s, 190 MB)."""
PROBE = 24
"""Deciding whether two outlines come closer than the clearance, every PROBE-th sample where their discs come
near is measured first (two links pinned together touch at every sample: one measurement decides it)."""


@dataclass(frozen=True)
class Outlines:
    """Tessellated outlines (local frame, file units) of every link, and the frame's (world) if any."""

    local: dict
    frame: np.ndarray | None
    chord: float


def outlines(mech, parts: dict) -> Outlines:
    size = mech.size / mech.scale
    chord = model.CHORD * size
    cfg = model.settings(mech)
    frame = np.asarray(cfg.frame, dtype=float) if cfg.frame else None
    return Outlines({ln: p.polygon(chord) for ln, p in parts.items()}, frame, chord)


def world(out: Outlines, sweep: model.Sweep, link: str) -> np.ndarray:
    """(N, k, 2) vertices of ``link``'s outline at every sample of ``sweep``."""
    f = sweep.frames[link]
    uv = out.local[link]
    c, s = np.cos(f[:, 2])[:, None], np.sin(f[:, 2])[:, None]
    x = f[:, 0:1] + uv[None, :, 0] * c - uv[None, :, 1] * s
    y = f[:, 1:2] + uv[None, :, 0] * s + uv[None, :, 1] * c
    return np.stack([x, y], axis=-1)


def _polys(verts) -> np.ndarray:
    import shapely
    return shapely.polygons(verts)


class Swept:
    """Every link's outline over the sweep, as vertices (:func:`world`) and shapely polygons, each made once
    per layout (a pair's distance and a pin's rule read them again for every other link: made per use, they
    cost as much as the distances themselves)."""

    def __init__(self, out: Outlines, sweep: model.Sweep):
        self.out, self.sweep, self._v, self._p, self._s, self._d = out, sweep, {}, {}, {}, {}

    def verts(self, link: str) -> np.ndarray:
        if link not in self._v:
            self._v[link] = (_frame_verts(self.out, len(self.sweep.t)) if link == FRAME
                             else world(self.out, self.sweep, link))
        return self._v[link]

    def polys(self, link: str) -> np.ndarray:
        if link not in self._p:
            self._p[link] = _polys(self.verts(link))
        return self._p[link]

    def step(self, link: str) -> np.ndarray:
        """(N-1,) each step's largest vertex displacement (:func:`_step`); zeros for the frame."""
        if link not in self._s:
            self._s[link] = np.zeros(len(self.sweep.t) - 1) if link == FRAME else _step(self.verts(link))
        return self._s[link]

    def disc(self, link: str) -> tuple[np.ndarray, float]:
        """(N, 2) centres and the radius of a disc that holds the outline at every sample (centred on the
        outline's bounding box in its link's frame)."""
        if link not in self._d:
            uv = self.out.frame if link == FRAME else self.out.local[link]
            c = 0.5 * (uv.min(axis=0) + uv.max(axis=0))
            r = float(np.max(np.hypot(*(uv - c).T)))
            if link == FRAME:
                self._d[link] = (np.broadcast_to(c, (len(self.sweep.t), 2)), r)
            else:
                f = self.sweep.frames[link]
                co, si = np.cos(f[:, 2]), np.sin(f[:, 2])
                self._d[link] = (np.column_stack([f[:, 0] + c[0] * co - c[1] * si, f[:, 1] + c[0] * si + c[1] * co]), r)
        return self._d[link]

    def gap(self, a: str, b: str) -> np.ndarray:
        """(N,) a lower bound of the two outlines' distance at every sample: their discs' gap, less a rounding
        allowance of a few ulps."""
        (ca, ra), (cb, rb) = self.disc(a), self.disc(b)
        reach = ra + rb
        return np.hypot(*(ca - cb).T) - reach - 1e-9 * (reach + float(np.max(np.abs(ca))))


def signed_distance(va: np.ndarray, vb: np.ndarray, depth: bool = True, polys=None) -> np.ndarray:
    """Per sample: the distance between two convex polygons ((N, k, 2) and (N, m, 2) vertices) where
    they are apart, minus their penetration depth where they overlap (the smallest translation that
    separates them, by the separating-axis theorem on both polygons' edge normals); ``depth`` False: 0
    where they overlap. ``polys``: the two polygon arrays if already made."""
    import shapely
    pa, pb = polys if polys is not None else (_polys(va), _polys(vb))
    d = shapely.distance(pa, pb)
    out = np.asarray(d, dtype=float).copy()
    for k in (np.nonzero(out <= 0.0)[0] if depth else ()):
        out[k] = -penetration(va[k], vb[k])
    return out


def penetration(a: np.ndarray, b: np.ndarray) -> float:
    """The penetration depth of two convex polygons (k, 2), (m, 2): min over both polygons' edge normals of
    the overlap of their projections (0 where they only touch)."""
    best = math.inf
    for poly in (a, b):
        e = np.roll(poly, -1, axis=0) - poly
        n = np.column_stack([e[:, 1], -e[:, 0]])
        L = np.hypot(n[:, 0], n[:, 1])
        n = n[L > 0] / L[L > 0, None]
        pa, pb = a @ n.T, b @ n.T
        overlap = np.minimum(pa.max(0) - pb.min(0), pb.max(0) - pa.min(0))
        best = min(best, float(overlap.min()))
    return max(best, 0.0)


def _step(v: np.ndarray) -> np.ndarray:
    """(N-1,): each step's largest vertex displacement."""
    return np.max(np.hypot(*(v[1:] - v[:-1]).transpose(2, 0, 1)), axis=1)


@dataclass(frozen=True)
class PairDistance:
    """The smallest signed distance of two outlines over the cycle and the time and first input where it
    occurs; ``first``: the first sample time where it is below the threshold asked (None if never)."""

    a: str
    b: str
    d: float
    t: float
    first: float | None


REFINE_BUDGET = 2048
"""The most intervals :func:`pair_distance` refines at each level: parts that graze all along the cycle (a
block in its lever's slot with no clearance) put every interval within the threshold, and halving each of 720
twelve times is 2.9 million outlines (memory past 20 GB); the intervals whose bound comes closest are kept."""


def pair_distance(mech, out: Outlines, sweep: model.Sweep, a: str, b: str, threshold: float,
                  depth: int = 12, penetration_depth: bool = True, swept: Swept | None = None) -> PairDistance:
    """Min signed distance of links ``a`` and ``b`` (``b`` may be FRAME) over the sweep, intervals refined
    as the module docstring says, so that a pass closer than ``threshold`` is not missed between samples;
    ``penetration_depth`` False: overlaps count 0 (faster; enough to decide a conflict). ``swept``: the
    outlines over ``sweep`` already made; with ``penetration_depth`` False too (the layering's question:
    does the pair come closer than ``threshold``?) only ``first`` is exact, ``d`` and ``t`` those of the
    samples measured (the discs' gap stands in elsewhere; a conflict returns at its first sample)."""
    t = sweep.t
    if swept is not None and not penetration_depth:
        # the polygons measured only where their discs come near: elsewhere the discs' gap stands in for the
        # distance (a lower bound above threshold + the steps' margin, so the refinement below and ``first``
        # decide as the distances would; ``d`` is then exact only where it is below that)
        step = swept.step(a) + swept.step(b)
        near_margin = np.concatenate([[step[0]], np.maximum(step[1:], step[:-1]), [step[-1]]]) if len(t) > 1 else 0
        d = swept.gap(a, b)
        near = np.nonzero(d < threshold + near_margin)[0]
        if near.size:
            import shapely
            d = d.copy()
            pa, pb = swept.polys(a), swept.polys(b)
            probe = near[::PROBE]                       # a conflict is mostly found among a few samples
            dp = shapely.distance(pa[probe], pb[probe])
            if dp.min() < threshold:                    # the first sample below it: among those up to this one
                upto = near[near <= probe[int(np.argmax(dp < threshold))]]
                du = shapely.distance(pa[upto], pb[upto])
                k = int(np.argmax(du < threshold))
                return PairDistance(a, b, float(du[k]), float(t[upto[k]]), float(t[upto[k]]))
            d[near] = shapely.distance(pa[near], pb[near])
    elif swept is not None:
        va, vb = swept.verts(a), swept.verts(b)
        d = signed_distance(va, vb, penetration_depth, (swept.polys(a), swept.polys(b)))
    else:
        va = world(out, sweep, a)
        vb = _frame_verts(out, len(t)) if b == FRAME else world(out, sweep, b)
        d = signed_distance(va, vb, penetration_depth)
    if not penetration_depth and d.min() < threshold:
        k = int(np.argmin(d))
        return PairDistance(a, b, float(d[k]), float(t[k]), float(t[np.argmax(d < threshold)]))
    margin = (swept.step(a) + swept.step(b)) if swept is not None else _step(va) + (0.0 if b == FRAME else _step(vb))
    ts, ds = list(t), list(d)
    todo = [(t[k], t[k + 1], d[k], d[k + 1], margin[k]) for k in range(len(t) - 1)
            if min(d[k], d[k + 1]) >= threshold and 0.5 * (d[k] + d[k + 1] - margin[k]) < threshold]
    for _ in range(depth):
        if not todo:
            break
        mids = np.array([0.5 * (x[0] + x[1]) for x in todo])
        sw = model.frames_at(mech, mids)
        wa = world(out, sw, a)
        wb = _frame_verts(out, len(mids)) if b == FRAME else world(out, sw, b)
        dm = signed_distance(wa, wb, penetration_depth)
        nxt = []
        for (t0, t1, d0, d1, m), tm, dmid in zip(todo, mids, dm):
            ts.append(tm)
            ds.append(dmid)
            if dmid < threshold:
                continue
            for lo, hi, dl, dh in ((t0, tm, d0, dmid), (tm, t1, dmid, d1)):
                if 0.5 * (dl + dh - 0.5 * m) < threshold:
                    nxt.append((lo, hi, dl, dh, 0.5 * m))
        if len(nxt) > REFINE_BUDGET:                    # the intervals that may come closest, the rest dropped
            nxt.sort(key=lambda x: 0.5 * (x[2] + x[3] - x[4]))
            nxt = nxt[:REFINE_BUDGET]
        todo = nxt
    ts, ds = np.asarray(ts), np.asarray(ds)
    k = int(np.argmin(ds))
    below = ts[ds < threshold]
    return PairDistance(a, b, float(ds[k]), float(ts[k]), float(below.min()) if below.size else None)


def _frame_verts(out: Outlines, n: int) -> np.ndarray:
    return np.broadcast_to(out.frame, (n,) + out.frame.shape)


def frame_parts(out: Outlines) -> list[np.ndarray]:
    """The frame polygon as convex pieces (triangles of its constrained Delaunay triangulation)."""
    import shapely
    poly = shapely.Polygon(out.frame)
    if not poly.is_valid:
        poly = poly.buffer(0)
    return [np.asarray(t.exterior.coords)[:3] for t in shapely.get_parts(shapely.constrained_delaunay_triangles(poly))]


# ---------------------------------------------------------------------------------------------- colouring
@dataclass(frozen=True)
class PinRule:
    """A pin through the links ``members`` (their layers, and those of the links whose slot it runs in) that
    the links ``crossing`` pass over: none of them may sit within the pin's span of layers. A ground pivot's
    pin comes from the frame below (spanning layer 0 up) or from a top plate (spanning up to the top): every
    crossing link above its links, or every one below them."""

    point: str
    members: tuple
    crossing: tuple
    ground: bool

    def holds(self, col: dict) -> bool:
        lo = min(col[m] for m in self.members)
        hi = max(col[m] for m in self.members)
        cs = [col[c] for c in self.crossing]
        if self.ground:
            return all(c > hi for c in cs) or all(c < lo for c in cs)
        return all(c < lo or c > hi for c in cs)

    def side(self, col: dict) -> str:
        """Where a ground pivot's pin is held: "below" (the frame) or "above" (a top plate)."""
        hi = max(col[m] for m in self.members)
        return "below" if all(col[c] > hi for c in self.crossing) else "above"


def colour(nodes, edges, fixed=None, pins=()) -> dict:
    """The fewest colours 0, 1, ... for ``nodes`` (in order) with no edge inside a colour and every
    :class:`PinRule` held, ``fixed`` colours kept (an edge between two fixed nodes is left to the interference
    check): exact by backtracking (the first colouring in node order, smallest colours first) up to
    MAX_EXACT nodes, DSatur's greedy colouring above (pins then unchecked)."""
    nodes = list(nodes)
    fixed = dict(fixed or {})
    adj = {n: set() for n in nodes}
    for a, b in edges:
        if a in adj and b in adj and a != b and not (a in fixed and b in fixed):
            adj[a].add(b)
            adj[b].add(a)
    if len(nodes) > MAX_EXACT:
        return _dsatur(nodes, adj, fixed)
    low = max([0, _clique(nodes, adj)] + [v + 1 for v in fixed.values()])
    free = [n for n in nodes if n not in fixed]
    order = {n: i for i, n in enumerate(free)}
    due: dict = {}                                      # each rule checked once its last node is coloured
    for rule in pins:
        involved = set(rule.members) | set(rule.crossing)
        if not rule.crossing or not involved <= set(nodes):
            continue
        last = max((order[n] for n in involved if n in order), default=-1)
        due.setdefault(last, []).append(rule)
    plain = None
    budget = [PLAIN_SEARCH]
    for k in range(max(1, low), len(nodes) + low + 2):
        out = dict(fixed)
        if _fill(free, 0, adj, out, k, {}, budget):
            plain = out
            break
        if budget[0] < 0:                                # a conflict graph too dense to colour exactly in time
            return _dsatur(nodes, adj, fixed)
    if not due or any(not r.holds(fixed) for r in due.get(-1, [])):
        return plain
    k0 = max(plain.values(), default=-1) + 1
    budget = [PIN_SEARCH]
    for k in range(k0, k0 + 3):                          # pins may cost a layer or two; beyond, they clash
        out = dict(fixed)
        if _fill(free, 0, adj, out, k, due, budget):
            return out
    return plain


PLAIN_SEARCH = 200_000
"""Assignments tried in search of the fewest layers (every count from the largest clique found up), before
DSatur's greedy colouring is taken instead (a dense conflict graph: every one of many links near every other;
the library's designs need a few hundred)."""
PIN_SEARCH = 200_000
"""Assignments tried in search of layers that every pin rule allows, before the plain colouring is kept and
the pins that clash are reported (``Layout.clashes``)."""


def _fill(free, i, adj, out, k, due, budget) -> bool:
    if i == len(free):
        return True
    n = free[i]
    used = {out[m] for m in adj[n] if m in out}
    for c in range(k):
        if c not in used:
            budget[0] -= 1
            if budget[0] < 0:
                return False
            out[n] = c
            if all(r.holds(out) for r in due.get(i, ())) and _fill(free, i + 1, adj, out, k, due, budget):
                return True
            del out[n]
    return False


def _clique(nodes, adj) -> int:
    """The size of a clique of the conflict graph (greedy from each node, the most connected neighbours first):
    a lower bound of the layers needed."""
    best = 0
    for n in nodes:
        clique = [n]
        for m in sorted(adj[n], key=lambda m: -len(adj[m])):
            if all(m in adj[c] for c in clique):
                clique.append(m)
        best = max(best, len(clique))
    return best


def _dsatur(nodes, adj, fixed) -> dict:
    out = dict(fixed)
    while len(out) < len(nodes):
        n = max((m for m in nodes if m not in out), key=lambda m: (len({out[x] for x in adj[m] if x in out}),
                                                                    len(adj[m])))
        used = {out[x] for x in adj[n] if x in out}
        out[n] = next(c for c in range(len(nodes) + 1) if c not in used)
    return out


@dataclass(frozen=True)
class Layout:
    """Each link's layer (z index) and its z range [file units]; the pairs that conflict (closer than the
    clearance at some instant) and the meshing gear pairs (kept on one layer, their pitch discs touch)."""

    layers: dict
    z: dict
    conflicts: tuple
    meshing: tuple
    pins: dict = None
    """{point: (z bottom, z top)} of every pin (a ground pivot's from the frame at 0, or from above the stack
    to its links)."""
    clashes: tuple = ()
    """(point, link): a link that passes over a pin within the pin's span of layers, where no layering of as
    many layers plus two avoids it (the interference check then reports it)."""
    second: dict = None
    """{link: (layer, (z bottom, z top))}: the upper plate of a two-plate link (:func:`two_plates`); ``layers``
    and ``z`` hold its lower plate."""
    joined: dict = None
    """{link: point}: a two-plate link's plates are joined by the pin at that joint, fixed in both plates (the
    links between them turn on it: a clevis)."""
    crossing: dict = None
    """{point: links that pass over the pin's place at some instant (the pin's span keeps clear of them)}."""

    @property
    def count(self) -> int:
        return max([*self.layers.values()] + [lz[0] for lz in (self.second or {}).values()], default=-1) + 1

    def plates(self, link: str) -> tuple:
        """((layer, (z bottom, z top)), ...) of the link's plates: one, or two for a two-plate link."""
        first = (self.layers[link], self.z[link])
        return (first, self.second[link]) if self.second and link in self.second else (first,)


def layout(mech, parts: dict, sweep: model.Sweep | None = None) -> Layout:
    """Layers (see the module docstring): the conflict graph over the cycle, meshing gears merged, the
    frame (if any) fixed on layer 0, ``[parts].layers`` kept; then z: each layer as thick as its thickest
    part, ``layer_gap`` between layers."""
    if len(parts) > MAX_LINKS:
        from analytic._common import ParameterError
        raise ParameterError(f"{mech.definition.source}: {len(parts)} moving links; the parts' layering lays out at "
                             f"most {MAX_LINKS} (its distances over the cycle grow as the square of the count)")
    sweep = sweep if sweep is not None else model.cycle(mech)
    cfg = model.settings(mech)
    out = outlines(mech, parts)
    links = list(parts)
    mesh = model.meshing(mech)
    group = {ln: ln for ln in links}
    for a, b in mesh:
        group[b] = group[a]
    conflicts = []
    swept = Swept(out, sweep)
    pairs = [(a, b) for i, a in enumerate(links) for b in links[i + 1:] if group[a] != group[b]]
    if out.frame is not None:
        pairs += [(a, FRAME) for a in links]
    for a, b in pairs:
        if _bbox_apart(out, sweep, a, b, cfg.clearance):
            continue
        pd = pair_distance(mech, out, sweep, a, b, cfg.clearance, penetration_depth=False, swept=swept)
        if pd.first is not None:
            conflicts.append((a, b))
    nodes = list(dict.fromkeys(group[ln] for ln in links)) + ([FRAME] if out.frame is not None else [])
    edges = [(group[a], FRAME if b == FRAME else group[b]) for a, b in conflicts]
    fixed = {group[ln]: z for ln, z in cfg.layers.items()}
    if out.frame is not None:
        fixed[FRAME] = 0
    for ln, z in cfg.layers.items():                     # meshing gears keep one layer
        if fixed.get(group[ln], z) != z:
            raise ValueError(f"[parts].layers: {ln} meshes with a gear fixed to another layer")
    rules = pin_rules(mech, parts, out, sweep, cfg, group, swept)
    try:
        colours = colour(nodes, edges, fixed, rules)
    except ValueError as exc:
        from analytic._common import ParameterError
        raise ParameterError(f"{mech.definition.source}: [parts].layers: {exc}; give them different layers") from None
    layers = {ln: colours[group[ln]] for ln in links}
    z, level = {}, 0.0
    for k in range(max(layers.values(), default=-1) + 1):
        members = [ln for ln in links if layers[ln] == k]
        thick = max((parts[ln].thickness for ln in members), default=0.0)
        for ln in members:
            z[ln] = (level, level + parts[ln].thickness)
        level += thick + cfg.layer_gap
    top = level - cfg.layer_gap
    pins, clashes = {}, []
    passing = {r.point: tuple(ln for ln in links if group[ln] in r.crossing) for r in rules}
    for rule in rules:
        zs = [z[ln] for ln in links if group[ln] in rule.members]
        lo, hi = min(v[0] for v in zs), max(v[1] for v in zs)
        crossing = [ln for ln in links if group[ln] in rule.crossing]

        def hits(span):                                 # the crossing links whose plates the pin passes
            return [ln for ln in crossing if z[ln][0] < span[1] and z[ln][1] > span[0]]
        spans = [(0.0, hi), (lo, top)] if rule.ground else [(lo, hi)]
        span = min(spans, key=lambda sp: len(hits(sp)))  # a ground pin from below unless above clashes less
        pins[rule.point] = span
        clashes += [(rule.point, ln) for ln in hits(span)]
    if clashes:
        two = _two_plate_layout(mech, parts, sweep, cfg, links, group, nodes, edges, fixed, rules, layers)
        if two is not None:
            return Layout(two[0], two[1], tuple(conflicts), mesh, two[2], (), two[3], two[4], passing)
    return Layout(layers, z, tuple(conflicts), mesh, pins, tuple(clashes), crossing=passing)


# ------------------------------------------------------------------------------------------ two-plate links
TWO_PLATE_SEARCH = 50_000
"""Assignments tried in search of a layering with two-plate links (:func:`two_plates`) before the plain
layering and its pin clashes are kept (the library's Whitworth, Stephenson II and double butterfly need up to
10,000; a design that has none, such as the elliptic trammel with the rod's pins at its yokes' slot crossings,
spends the budget in about a second)."""
MAX_TWO_PLATE = 2
"""The most two-plate links a layering takes (one, then two, each with the fewest layers first)."""


@dataclass(frozen=True)
class Span:
    """A pin's span in layers: from layer ``lo`` to ``hi``; ``side`` "below" (a ground pin from the frame:
    ``lo`` is -1), "above" (from a top plate: ``hi`` is None, the top) or "" (a pin between its links)."""

    lo: int
    hi: int | None
    side: str

    def covers(self, layer: int) -> bool:
        return self.lo <= layer and (self.hi is None or layer <= self.hi)

    def overlaps(self, other: Span) -> bool:
        return (self.hi is None or other.lo <= self.hi) and (other.hi is None or self.lo <= other.hi)


def spans(rule: PinRule, plates: dict) -> list[Span]:
    """The spans a pin may take with the links' ``plates`` ({node: tuple of layers}): through one plate of each
    of its links (or both plates of a two-plate link), no plate of a link that passes over it inside; a ground
    pin from the frame (every crossing plate above) or from a top plate (every one below); shortest first."""
    import itertools
    options = [[(layer,) for layer in plates[m]] + ([tuple(plates[m])] if len(plates[m]) == 2 else [])
               for m in rule.members]
    cross = [layer for c in rule.crossing for layer in plates[c]]
    out = set()
    for pick in itertools.product(*options):
        at = [layer for one in pick for layer in one]
        lo, hi = min(at), max(at)
        if rule.ground:
            if all(c > hi for c in cross):
                out.add(Span(-1, hi, "below"))
            if all(c < lo for c in cross):
                out.add(Span(lo, None, "above"))
        elif all(c < lo or c > hi for c in cross):
            out.add(Span(lo, hi, ""))
    top = max(layer for ls in plates.values() for layer in ls)
    return sorted(out, key=lambda sp: ((sp.hi if sp.hi is not None else top) - sp.lo, sp.side != "below", sp.lo))


def two_plates(nodes, edges, fixed, rules, meets, joints, k0: int):
    """A layering where some links are two plates (``k0`` the plain layering's count): each node one layer or
    two (with at least one layer between: the links there pass between the plates), no edge sharing a layer,
    every pin with a span (:func:`spans`), pins that meet (``meets``: pairs of points whose pins come within
    a pin's width of each other) with disjoint spans, and each two-plate link's plates joined by the pin at
    one of its ``joints`` ({node: moving points where it has a hole}) running through both, fixed in them (a
    clevis: no two two-plate links fixed to one pin). Fewest two-plate links first, then fewest layers;
    ``fixed`` nodes keep their one layer. Returns ({node: layers}, {point: Span}, {node: point}) or None."""
    nodes = list(nodes)
    adj = {n: set() for n in nodes}
    for a, b in edges:
        if a in adj and b in adj and a != b:
            adj[a].add(b)
            adj[b].add(a)
    order = {n: i for i, n in enumerate(nodes)}
    due: dict = {}
    for rule in rules:
        involved = set(rule.members) | set(rule.crossing)
        if rule.crossing and involved <= set(nodes):
            due.setdefault(max(order[n] for n in involved), []).append(rule)
    budget = [TWO_PLATE_SEARCH]
    for most in range(1, MAX_TWO_PLATE + 1):
        for k in range(k0, k0 + 4):
            options = [(c,) for c in range(k)] + [(a, b) for a in range(k) for b in range(a + 2, k)]
            found = _fill_plates(nodes, 0, adj, fixed, {}, options, due, rules, meets, joints, most, budget)
            if found is not None:
                return found
            if budget[0] < 0:
                return None
    return None


def _fill_plates(nodes, i, adj, fixed, out, options, due, rules, meets, joints, most, budget):
    if i == len(nodes):
        if sum(len(v) == 2 for v in out.values()) == 0:
            return None                                  # the plain layering's question: answered already
        return _choose_spans(rules, out, meets, joints)
    n = nodes[i]
    doubled = sum(len(v) == 2 for v in out.values())
    for opt in ([(fixed[n],)] if n in fixed else options):
        if len(opt) == 2 and (doubled >= most or not joints.get(n)):
            continue
        if any(set(opt) & set(out[m]) for m in adj[n] if m in out):
            continue
        budget[0] -= 1
        if budget[0] < 0:
            return None
        out[n] = opt
        if all(spans(r, out) for r in due.get(i, ())):
            found = _fill_plates(nodes, i + 1, adj, fixed, out, options, due, rules, meets, joints, most, budget)
            if found is not None:
                return found
        del out[n]
    return None


def _choose_spans(rules, plates, meets, joints):
    """Each pin's span (shortest first) with the pins that meet apart and every two-plate link joined."""
    cands = [(r.point, spans(r, plates) if r.crossing or any(len(plates[m]) == 2 for m in r.members)
              else spans(r, plates)[:1]) for r in rules]
    if any(not c for _, c in cands):
        return None
    two = [n for n, v in plates.items() if len(v) == 2]
    meet = {p: {q for a, b in meets for p_, q in ((a, b), (b, a)) if p_ == p} for p, _ in cands}
    chosen: dict = {}
    steps = [20_000]

    def joined():
        out, used = {}, set()
        for n in two:
            p = next((p for p in joints[n] if p not in used and p in chosen
                      and all(chosen[p].covers(layer) for layer in plates[n])), None)
            if p is None:
                return None
            out[n] = p
            used.add(p)
        return out

    def go(i):
        if i == len(cands):
            return joined()
        steps[0] -= 1
        if steps[0] < 0:
            return None
        p, options = cands[i]
        for sp in options:
            if any(q in chosen and sp.overlaps(chosen[q]) for q in meet[p]):
                continue
            chosen[p] = sp
            j = go(i + 1)
            if j is not None:
                return j
            del chosen[p]
        return None
    j = go(0)
    return None if j is None else (dict(plates), dict(chosen), j)


def _two_plate_layout(mech, parts, sweep, cfg, links, group, nodes, edges, fixed, rules, plain):
    """The layout with two-plate links where the plain layering leaves pins clashing (:func:`two_plates`), in
    :func:`layout`'s terms: (layers, z, pins, second, joined), or None where none is found."""
    multi = {g for g in group.values() if sum(1 for v in group.values() if v == g) > 1}
    joints = {}
    for ln in links:
        g = group[ln]
        if g in multi or g in fixed:
            continue
        joints[g] = [h.point for h in parts[ln].holes if h.point not in mech.ground_points]
    meets = []
    pts = [r.point for r in rules]
    reach = cfg.pin_diameter + cfg.clearance
    for i, a in enumerate(pts):
        for b in pts[i + 1:]:
            if float(np.min(np.hypot(*(sweep.points[a] - sweep.points[b]).T))) < reach:
                meets.append((a, b))
    k0 = max([*plain.values()] + [v for v in fixed.values()], default=-1) + 1
    found = two_plates(nodes, edges, fixed, rules, meets, joints, k0)
    if found is None:
        return None
    plates, chosen, joins = found
    per_layer: dict = {}
    for ln in links:
        for layer in plates[group[ln]]:
            per_layer.setdefault(layer, []).append(ln)
    zs, level = {}, 0.0
    for k in range(max(per_layer, default=-1) + 1):
        thick = max((parts[ln].thickness for ln in per_layer.get(k, ())), default=0.0)
        zs[k] = level
        level += thick + cfg.layer_gap
    top = level - cfg.layer_gap

    def zspan(ln, layer):
        return (zs[layer], zs[layer] + parts[ln].thickness)
    layers = {ln: plates[group[ln]][0] for ln in links}
    z = {ln: zspan(ln, layers[ln]) for ln in links}
    second = {ln: (plates[group[ln]][1], zspan(ln, plates[group[ln]][1])) for ln in links if len(plates[group[ln]]) == 2}
    pins = {}
    for rule in rules:
        sp = chosen[rule.point]
        members = [ln for ln in links if group[ln] in rule.members]
        ends = [zspan(ln, layer) for ln in members for layer in plates[group[ln]] if sp.covers(layer)]
        lo = 0.0 if sp.side == "below" else min(e[0] for e in ends)
        hi = top if sp.side == "above" else max(e[1] for e in ends)
        pins[rule.point] = (lo, hi)
    joined = {ln: joins[group[ln]] for ln in second}
    return layers, z, pins, second, joined


def pin_rules(mech, parts, out: Outlines, sweep, cfg, group, swept: Swept | None = None) -> list[PinRule]:
    """A :class:`PinRule` per joint: the links pinned there (and those whose slot its pin runs in: the slot
    of a block pinned there), and the other links that pass within the clearance of the pin's circle
    (diameter ``pin_diameter``) at some sample, less a margin of their largest step between samples (a link
    whose bounding disc about its frame's origin never comes that close is passed over without its polygons)."""
    import shapely
    swept = swept if swept is not None else Swept(out, sweep)
    radius = {ln: float(np.max(np.hypot(*out.local[ln].T))) for ln in parts}
    rules = []
    for p in mech.points:
        pinned = [ln for ln, part in parts.items() if any(h.point == p for h in part.holes)]
        if not pinned:
            continue
        slotted = [ln for ln, part in parts.items() if any(sl.block in pinned for sl in part.slots)
                   and any(j.kind == "prismatic" and j.point == p for j in mech.joints)]
        members = set(pinned) | set(slotted)
        at = shapely.points(sweep.points[p])
        step_p = np.max(np.hypot(*np.diff(sweep.points[p], axis=0).T)) if len(sweep.t) > 1 else 0.0
        crossing = []
        for ln in parts:
            if ln in members:
                continue
            # the disc about the frame's origin holds the outline: where it stays clear, so does the outline
            disc = np.hypot(*(sweep.frames[ln][:, :2] - sweep.points[p]).T) - radius[ln] - cfg.pin_diameter / 2
            margin = float(np.max(swept.step(ln))) + step_p if len(sweep.t) > 1 else 0.0
            near = np.nonzero(disc < cfg.clearance + margin)[0]
            if not near.size:
                continue
            polys = swept.polys(ln)
            for idx in (near[::PROBE], near):            # a few samples first: a crossing link is mostly found
                d = np.asarray(shapely.distance(polys[idx], at[idx])) - cfg.pin_diameter / 2
                if d.min() < cfg.clearance + margin:
                    crossing.append(ln)
                    break
        rules.append(PinRule(p, tuple(dict.fromkeys(group[m] for m in members)),
                             tuple(dict.fromkeys(group[c] for c in crossing if group[c] not in
                                                 {group[m] for m in members})), p in mech.ground_points))
    return rules


def _bbox_apart(out: Outlines, sweep, a, b, threshold) -> bool:
    """Whether the two outlines' bounding discs about their frames' origins never come within the
    threshold (a quick exclusion before the polygon distances)."""
    ra = float(np.max(np.hypot(*out.local[a].T)))
    fa = sweep.frames[a][:, :2]
    if b == FRAME:
        c = out.frame.mean(axis=0)
        rb = float(np.max(np.hypot(*(out.frame - c).T)))
        fb = np.broadcast_to(c, fa.shape)
    else:
        rb = float(np.max(np.hypot(*out.local[b].T)))
        fb = sweep.frames[b][:, :2]
    gap = np.hypot(*(fa - fb).T) - ra - rb
    step = np.max(np.hypot(*(np.diff(fa, axis=0)).T)) + np.max(np.hypot(*(np.diff(fb, axis=0)).T)) if len(fa) > 1 else 0
    return bool(np.min(gap) > threshold + step)
