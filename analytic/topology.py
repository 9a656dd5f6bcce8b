"""The structure of a mechanism, built once from its elements: solve order, links and their points, joints,
loops, Assur groups and Gruebler's count.

Every element kind says what it adds (:class:`analytic.kinds.base.Structure`): links it creates, points it
fixes to links that exist, prismatic pairs and gear couplings. From those this module derives

* the **solve order**: elements in an order where each one's points (and links) are known before it;
* the **links**: each link's frame origin and every point it carries, and each point's **carrier** (the
  link it is first part of: its body in the simulation);
* the **joints**: a revolute wherever several links meet at a point (k links: k - 1 revolutes, each
  between the first link there and another), a prismatic pair per slide, the inputs' pairs marked driven;
* **Gruebler's count** M = 3 (n - 1) - 2 j - h over n links (the ground included), j lower pairs and h gear
  couplings;
* a **spanning tree** of the joints rooted at the ground (driven and prismatic pairs first: MuJoCo closes
  loops at revolutes only) and the **loops**, one per joint left out of it.

Problems are :class:`StructureError` naming the element (its label) and what to change.
"""

from __future__ import annotations

from dataclasses import dataclass

from ._common import ParameterError
from .kinds import GROUND, KINDS


class StructureError(ParameterError):
    """A mechanism whose structure is not valid; ``where`` names the element, ``what`` the problem."""

    def __init__(self, where: str, what: str):
        super().__init__(f"{where}: {what}")
        self.where, self.what = where, what


@dataclass(frozen=True)
class Link:
    """A rigid link: its frame ``origin`` (a point on it), every point it carries (origin first), the index of
    the element that creates it (-1: the ground) and whether it is a sliding block."""

    name: str
    origin: str
    points: tuple[str, ...]
    element: int
    block: bool = False


@dataclass(frozen=True)
class Joint:
    """A lower pair between links ``a`` and ``b`` (``ground`` for the frame) at ``point``: a revolute there, or
    a prismatic pair whose block link is ``slide`` (its direction: the block's angle). ``input`` is the index
    of the input that drives it, or None."""

    kind: str
    name: str
    a: str
    b: str
    point: str
    input: int | None
    slide: str | None


@dataclass(frozen=True)
class Coupling:
    """A gear pair (see :class:`analytic.kinds.base.Coupling`), with its element's index."""

    link: str
    mesh: str
    carrier: str
    element: int
    kind: str = "gear"
    """``gear`` or ``cam`` (see :class:`analytic.kinds.base.Coupling`)."""


@dataclass(frozen=True)
class Loop:
    """An independent loop: the joint left out of the spanning tree that closes it, and the links around it
    (from the joint's ``a`` side through the tree back to its ``b`` side)."""

    joint: Joint
    links: tuple[str, ...]


@dataclass(frozen=True)
class Topology:
    """The structure of a mechanism (see the module docstring)."""

    order: tuple[int, ...]
    """Element indices (as written: inputs, then groups) in solving order."""
    ground: tuple[str, ...]
    points: tuple[str, ...]
    """Ground points, then the points the elements place, in solving order."""
    links: dict[str, Link]
    """The moving links in the order their elements are solved."""
    carriers: dict[str, str]
    joints: tuple[Joint, ...]
    slides: tuple[str, ...]
    """The prismatic pairs, named after their block links."""
    couplings: tuple[Coupling, ...]
    inputs: tuple[int, ...]
    """Element indices of the inputs, in solving order (input k drives joint.input == k)."""
    tree: tuple[tuple[str, str, Joint], ...]
    """(parent, child, joint) of the spanning tree, from the ground outwards."""
    loops: tuple[Loop, ...]

    @property
    def counts(self) -> tuple[int, int, int]:
        """(links including the ground, lower pairs, gear couplings)."""
        return len(self.links) + 1, len(self.joints), len(self.couplings)

    @property
    def mobility(self) -> int:
        """Gruebler's count 3 (n - 1) - 2 j - h."""
        n, j, h = self.counts
        return 3 * (n - 1) - 2 * j - h

    def gruebler(self) -> str:
        """Gruebler's count written out."""
        n, j, h = self.counts
        higher = f" - {h}" if h else ""
        return f"3 x ({n} - 1) - 2 x {j}{higher} = {self.mobility}"

    def members(self, link: str) -> tuple[str, ...]:
        """The points of a link (the ground's: its fixed points)."""
        return self.ground if link == GROUND else self.links[link].points

    def link_of(self, p: str, q: str) -> str | None:
        """The link carrying both points (the ground for two ground points), or None."""
        if p in self.ground and q in self.ground:
            return GROUND
        return next((ln for ln, link in self.links.items() if p in link.points and q in link.points), None)

    def loaded_link(self, point: str) -> str:
        """The link a force given at ``point`` acts on (``--force``, plain or ``@POINT``): a block pinned there
        where one is (a slider-crank's piston, a shaper's ram: the part a press or a cutting force pushes,
        issue 41), else the point's carrier."""
        block = next((ln for ln, link in self.links.items() if link.block and point in link.points), None)
        return block if block is not None else self.carriers[point]

    @property
    def origins(self) -> dict[str, str]:
        return {ln: link.origin for ln, link in self.links.items()}


# ------------------------------------------------------------------------------------------- build
def solve_order(ground, elements) -> tuple[int, ...]:
    """Element indices in an order where every element's points and links are known before it."""
    known_points = set(ground)
    creates = {}
    for i, e in enumerate(elements):
        for part in KINDS[e.kind].structure(e.fields).links:
            creates[part.name] = i
    known_links = set()
    pending = list(range(len(elements)))
    order = []
    while pending:
        ready = []
        for i in pending:
            e = elements[i]
            kind = KINDS[e.kind]
            if all(p in known_points for p in kind.needs(e.fields)) and all(
                    ln in known_links for ln in kind.needs_links(e.fields)):
                ready.append(i)
        if not ready:
            e = elements[pending[0]]
            kind = KINDS[e.kind]
            missing = [p for p in kind.needs(e.fields) if p not in known_points]
            missing += [f"link {ln}" for ln in kind.needs_links(e.fields) if ln not in known_links]
            for ln in kind.needs_links(e.fields):
                if ln not in creates and ln != GROUND:
                    raise StructureError(e.label, f"no link named {ln!r}; name a link of the mechanism")
            chain = " -> ".join(list(e.places) + missing)
            raise StructureError(e.label, f"a cycle: {chain} depend on each other; each element must use only "
                                          f"points defined without it (a group that places several points at "
                                          f"once is kind = \"group\")")
        for i in ready:
            order.append(i)
            e = elements[i]
            known_points.update(e.places)
            known_links.update(p.name for p in KINDS[e.kind].structure(e.fields).links)
            pending.remove(i)
    return tuple(order)


def build(ground, elements) -> Topology:
    """The topology of a mechanism from its ground point names and its elements (objects with ``kind``,
    ``fields``, ``label`` and ``places``: :class:`analytic.format.linkfile.Element`), as written."""
    order = solve_order(ground, elements)
    links: dict[str, Link] = {}
    members: dict[str, list[str]] = {GROUND: list(ground)}
    carriers = {g: GROUND for g in ground}
    incidence: dict[str, list[str]] = {g: [GROUND] for g in ground}
    slides, couplings, inputs = [], [], []
    raw_slides, driven_pins = [], {}

    def touch(point, link):
        lst = incidence.setdefault(point, [])
        if link not in lst:
            lst.append(link)

    for i in order:
        e = elements[i]
        kind = KINDS[e.kind]
        st = kind.structure(e.fields)
        if kind.section == "inputs":
            inputs.append(i)
        if st.driven_pin is not None:
            driven_pins[st.driven_pin] = len(inputs) - 1
        for part in st.links:
            links[part.name] = Link(part.name, part.origin, tuple(dict.fromkeys(part.points)), i, part.block)
            members[part.name] = list(dict.fromkeys(part.points))
            for p in part.points:
                touch(p, part.name)
                carriers.setdefault(p, part.name)
        for point, link in st.pins:
            touch(point, link)
        for a in st.attach:
            if isinstance(a.on, str):
                link = a.on
                if link != GROUND and link not in links:
                    raise StructureError(e.label, f"field 'on': no link named {link!r}; links: "
                                                  f"{', '.join(links) or '(none)'}")
            else:
                p, q = a.on
                link = next((ln for ln, pts in members.items() if p in pts and q in pts), None)
                if link is None:
                    raise StructureError(e.label, f"field 'on': no link carries both {p!r} and {q!r}; name two "
                                                  f"points of one link")
            members.setdefault(link, []).append(a.point)
            if link in links:
                links[link] = Link(link, links[link].origin, links[link].points + (a.point,), links[link].element,
                                   links[link].block)
            touch(a.point, link)
            carriers.setdefault(a.point, link)
        raw_slides += [(i, s, len(inputs) - 1 if s.driven else None) for s in st.slides]
        couplings += [(i, c) for c in st.couplings]

    def guide_owner(i, guide) -> str:
        if guide is None:
            return GROUND
        if isinstance(guide, str):
            return guide
        p, q = guide
        owner = next((ln for ln, pts in members.items() if p in pts and q in pts), None)
        if owner is None:
            raise StructureError(elements[i].label, f"field 'guide': no link carries both {p!r} and {q!r}")
        return owner

    joints: list[Joint] = []
    for i, s, driven in raw_slides:
        owner = guide_owner(i, s.guide)
        joints.append(Joint("prismatic", s.block, owner, s.block, s.point, driven, s.block))
        slides.append(s.block)
    for point, at in incidence.items():
        for other in at[1:]:
            first, driven = at[0], None
            for pin_, k in driven_pins.items():
                pin, link, base = (tuple(pin_) + (GROUND,))[:3]
                if pin == point and other == link and base in at:
                    first, driven = base, k            # a driven revolute joins its link to its base
            name = point if len(at) == 2 else f"{point}_{other}"
            joints.append(Joint("revolute", name, first, other, point, driven, None))
    coup = []
    for i, c in couplings:
        for ln in (c.link, c.mesh, c.carrier):
            if ln != GROUND and ln not in links:
                raise StructureError(elements[i].label, f"no link named {ln!r}; links: {', '.join(links)}")
        coup.append(Coupling(c.link, c.mesh, c.carrier, i, c.kind))
    points = tuple(ground) + tuple(p for i in order for p in elements[i].places)
    tree, loops = _spanning_tree(joints, links)
    return Topology(order, tuple(ground), points, links, carriers, tuple(joints), tuple(slides), tuple(coup),
                    tuple(inputs), tree, loops)


def _spanning_tree(joints, links):
    """(tree, loops): the tree's (parent, child, joint) from the ground outwards, driven and prismatic pairs
    taken first (and the other joints of a link driven relative to a moving link last), and a Loop for every
    joint left out."""
    # a pair driven between two moving links (a motor, an actuator's slide) hangs its driven side b from its
    # base a: b's other joints are left out first, so that the model measures b relative to a
    hung = {j.b for j in joints if j.input is not None and GROUND not in (j.a, j.b)}
    ranked = sorted(joints, key=lambda j: (j.input is None, j.kind != "prismatic",
                                           j.input is None and bool(hung & {j.a, j.b})))
    parent = {GROUND: GROUND}

    def root(x):
        while parent.setdefault(x, x) != x:
            x = parent[x]
        return x

    kept, cuts = [], []
    for j in ranked:
        ra, rb = root(j.a), root(j.b)
        if ra == rb:
            cuts.append(j)
        else:
            parent[ra] = rb
            kept.append(j)
    adj: dict[str, list] = {}
    for j in kept:
        adj.setdefault(j.a, []).append((j.b, j))
        adj.setdefault(j.b, []).append((j.a, j))
    tree, seen, queue, up = [], {GROUND}, [GROUND], {GROUND: None}
    while queue:
        body = queue.pop(0)
        for other, j in adj.get(body, []):
            if other not in seen:
                seen.add(other)
                up[other] = body
                tree.append((body, other, j))
                queue.append(other)

    def path(x):
        out = [x]
        while up.get(x) is not None:
            x = up[x]
            out.append(x)
        return out

    loops = []
    for j in cuts:
        pa, pb = path(j.a), path(j.b)
        common = next((x for x in pa if x in pb), GROUND)
        ring = pa[:pa.index(common) + 1] + list(reversed(pb[:pb.index(common)]))
        loops.append(Loop(j, tuple(ring)))
    return tuple(tree), tuple(loops)


def disconnected(topology: Topology) -> set[str]:
    """Links that no chain of joints connects to the ground."""
    reached = {GROUND} | {child for _, child, _ in topology.tree}
    return set(topology.links) - reached
