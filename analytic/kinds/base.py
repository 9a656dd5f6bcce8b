"""The protocol every element kind implements, and what kinds share.

An element kind is one module of :mod:`analytic.kinds` holding one :class:`Kind` subclass and an instance of
it, ``KIND``. The kind owns everything about its elements:

* **format**: its fields (:class:`Field`: a type and a default), extra checks, the points it needs and the
  points it places (one or several);
* **topology**: the links it creates with their points, the points it fixes to links that exist, its
  prismatic pairs and gear couplings (:class:`Structure`);
* **solver**: positions, exact velocities and accelerations of what it places (:meth:`Kind.solve` on
  numpy arrays, every sample at once), its singularity measure and any outputs of its own (the
  transmission angle of an RRR); its compiled row for the numba path where it has one (:attr:`Kind.jit`);
* **simulation**: constraints the MuJoCo model needs besides the tree of revolute and slide joints and the
  loop closures that the topology gives (:meth:`Kind.mjcf`, e.g. a gear's coupling);
* **inputs** (``section = "inputs"``): what its coordinate is (:attr:`Kind.angular`: an angle or a length; its
  column names :attr:`Kind.columns`), from which its unit, periodicity, rate scale, reference rate and its
  drive's quantity and unit follow (a kind may override each), its default rate, and how the links-and-joints
  form recognises it (:meth:`Kind.from_joints`); callers ask the kind (``Input.spec``), never its name;
* **forces**: its joint forces by statics (:meth:`Kind.forces`), in closed form where it has one; the default
  solves the element's Newton-Euler equations assembled from the topology.

Nothing outside a kind's module switches on its name: the format, the topology, the solver, the model
builder and the outputs table ask the kind. Registering a kind is one line in :mod:`analytic.kinds`.

Solved quantities, per sample (arrays of shape (N,), or scalars broadcast against them):

* a point: ``(x, y, vx, vy, ax, ay)`` [m, m/s, m/s^2];
* a link: ``(cos phi, sin phi, omega, alpha)`` of its angle phi (its frame's x-axis) [rad/s, rad/s^2];
* a prismatic pair (named after its block link): ``(s, ds, dds)`` [m, m/s, m/s^2].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

REQUIRED = object()
"""A field with no default: the file must give it."""


class _SizePerSecond:
    def __repr__(self) -> str:
        return "SIZE_PER_SECOND"


SIZE_PER_SECOND = _SizePerSecond()
"""The default of an input's rate that scales with the mechanism: its size (its longest link or its ground's
spread, as :attr:`analytic.mechanism.Mechanism.size`, at the file's parameter values) per second, in file
units to 3 digits (:meth:`Kind.default_rate`); filled in when the file is read."""

GROUND = "ground"
"""The name of the frame link (the ground)."""


@dataclass(frozen=True)
class Field:
    """One field of an element kind.

    ``type`` says what the value is and how it is checked and resolved:

    ========== ===============================================================================
    point      a point defined elsewhere (a name)
    new        the point the element places (a name)
    news       the points the element places (a list of names)
    points     points defined elsewhere (a list of names)
    pair       two different points defined elsewhere
    carrier    a link that exists: two of its points ``["P", "Q"]``, or its name
    link       a new link's name (default: a pattern of the element's point names)
    links2     two new links' names
    linkref    a link that exists (or ``ground``)
    size       a length > 0 (file units, resolved to m)
    length     a length of any sign (an offset, a coordinate)
    lengths2   two sizes
    xy         two lengths (a position in a link's frame)
    angle      an angle (rad, or ``"30deg"``); also a speed per second or acceleration per second^2
    branch     +1 or -1
    number     a pure number (a gear ratio)
    guide      ``["P", "Q"]`` (the line P->Q of a link) or ``{through = "P" or [x, y], angle = ...}``
    linktable  ``{LINK = ["P", "Q", ...], ...}`` (the links of a general group and their points)
    pose       ``{P = [x, y], ...}`` (assembled positions, file units)
    ========== ===============================================================================
    """

    type: str
    default: object = REQUIRED


@dataclass(frozen=True)
class LinkPart:
    """A link an element creates: its ``name``, the ``origin`` of its frame (a point on it), the points it
    carries (``origin`` first), and ``block`` for a sliding block (drawn as a block, light by default)."""

    name: str
    origin: str
    points: tuple[str, ...]
    block: bool = False


@dataclass(frozen=True)
class Attach:
    """A point fixed to a link that exists: the link carrying both points of ``on`` (a pair), or the link
    named ``on`` (a string)."""

    point: str
    on: tuple[str, str] | str


@dataclass(frozen=True)
class Slide:
    """A prismatic pair: the ``block`` link slides relative to the guide link along a line. The guide link is
    the one carrying both points of ``guide`` (a pair), the link named ``guide`` (a string), or the ground
    (None). ``point`` is the block's point on the line (its pin). The pair is named after the block."""

    block: str
    guide: tuple[str, str] | str | None
    point: str
    driven: bool = False


@dataclass(frozen=True)
class Coupling:
    """A gear pair: ``link`` turns relative to ``carrier`` at ``ratio`` times ``mesh``'s rotation relative to
    ``carrier`` (a higher pair: one constraint)."""

    link: str
    mesh: str
    carrier: str
    ratio: object
    """The ratio's resolved field name in the element (it may be a parameter); None for a cam."""
    kind: str = "gear"
    """``gear`` (the relation above) or ``cam`` (a cam's contact with its follower: the kind places the
    follower and solves the contact's force itself)."""


@dataclass(frozen=True)
class Structure:
    """What an element adds to the topology."""

    links: tuple[LinkPart, ...] = ()
    attach: tuple[Attach, ...] = ()
    slides: tuple[Slide, ...] = ()
    couplings: tuple[Coupling, ...] = ()
    pins: tuple[tuple[str, str], ...] = ()
    """Extra (point, link) incidences: a link pinned at a point it did not create."""
    driven_pin: tuple[str, ...] | None = None
    """For a driven revolute: (its point, the driven link) with the ground as its base (a crank), or (its point,
    the driven link, the base link) between two moving links (a motor); the joint is between base and link."""


@dataclass(frozen=True)
class ExtraOutput:
    """An output a kind computes besides its points, links and slides: ``name`` (e.g. ``muC``), its
    ``quantity`` (see :mod:`analytic.quantities`) and what it belongs to."""

    name: str
    quantity: str
    owner: str
    transmission: str | None = None
    """For a transmission angle: the point it is measured at (figures of merit collect these)."""


@dataclass(frozen=True)
class Wheel:
    """A gear as drawn on a link: its pitch circle of ``radius`` [m] about ``centre`` (a point of ``link``)
    with ``teeth`` teeth (inward for a ``ring``), the first centred ``phase`` [rad] from the direction
    ``centre`` -> ``ref`` (a second point of the link; None: from +x, a gear fixed to the ground)."""

    link: str
    centre: str
    ref: str | None
    radius: float
    teeth: int
    phase: float
    ring: bool = False


BARREL = 0.85
"""A cylinder's barrel as drawn (videos, MuJoCo's geoms): this fraction of its retracted pin-to-pin length long."""
ROD_INSIDE = 0.55
"""A cylinder's rod as drawn: from its pin back to this fraction of the retracted length from the barrel's pin."""


@dataclass(frozen=True)
class Cylinder:
    """A linear actuator as drawn: its barrel link pinned at ``base`` and its rod link pinned at ``end`` (point
    names), its retracted and extended pin-to-pin lengths [m] and its bore [m] (0: not given)."""

    barrel: str
    rod: str
    base: str
    end: str
    retracted: float
    extended: float
    bore: float = 0.0


@dataclass(frozen=True)
class JitSpec:
    """A kind's compiled row (see :mod:`analytic.solver.jit`): ``layout(e, L, row, par)`` fills the kind's
    integer row and number row from a resolved element through the layout builder ``L``;
    ``kernel(st, m, e, ops, par, q, qd, qdd, step, i0, need)`` is a plain Python function numba compiles,
    solving the element for ``m`` samples of the state ``st``; ``helpers`` names further functions of the
    kind's module that the kernel calls (compiled with it)."""

    layout: object
    kernel: object
    helpers: tuple[str, ...] = ()


@dataclass
class State:
    """What the solver knows while it works down the elements: points, links, prismatic pairs and extra
    outputs solved so far (see the module docstring), the inputs (``q``, ``qd``, ``qdd``: (n_inputs, N)),
    the number of samples and whether the extra outputs are wanted."""

    n: int
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    extras_wanted: bool = True
    points: dict = field(default_factory=dict)
    links: dict = field(default_factory=dict)
    slides: dict = field(default_factory=dict)
    extras: dict = field(default_factory=dict)
    angles: dict = field(default_factory=dict)
    """Link angles [rad] counted in whole turns (not reduced to (-pi, pi]) where a kind knows them: a gear
    sets its link's, for the gears that mesh with it ({link: array})."""
    start: dict | None = None
    """What the previous block of samples carried over (its ``carry``), for kinds that continue a motion
    from sample to sample (numerically solved groups); None for the first block."""
    carry: dict = field(default_factory=dict)
    """What this block carries over to the next: small, keyed by element label."""


class Kind:
    """An element kind (see the module docstring). Subclasses set the class attributes and override what
    differs; the defaults suit a group that places one point ``point``."""

    name: str = ""
    section: str = "groups"
    """``inputs`` (a driven input) or ``groups`` (an Assur group or a rigid point)."""
    summary: str = ""
    """What it makes, one line (docs, ``linkage check``)."""
    group_class: str = ""
    """The Assur group it is (``dyad RRR``, ``triad``...), shown by ``linkage check``; "" for none."""
    fields: dict[str, Field] = {}
    motion_fields: tuple[str, str, str] = ()
    """For inputs: the fields of its motion law (start, rate, acceleration)."""
    angular: bool = False
    """For inputs: whether its coordinate is an angle (rad, written and shown in degrees, turning fully and
    periodically, driven by a torque on a hinge) or else a length (m, driven by a force along a slide)."""
    columns: tuple[str, str, str] = ()
    """For inputs: the prefixes of its coordinate's, rate's and acceleration's names (``phi omega alpha``:
    ``phi1`` for link 1); the solver's output columns of the same names are the input's own."""
    jit: JitSpec | None = None
    per_design: bool = False
    """Whether its resolved element holds more than numbers (a cam's geometry, built from the ground's and
    its own values): batches of designs then resolve and solve it design by design."""
    continuous: bool = False
    """Whether its solve continues from sample to sample (a numerically solved group): the solver then takes
    a solve's samples as a path from the inputs' start values and fills in samples where the inputs jump
    (:func:`analytic.solver.kinematics.evaluate`), and batches solve such mechanisms design by design."""

    # ------------------------------------------------------------------------------------ format
    def places(self, f: dict) -> tuple[str, ...]:
        """The points the element places."""
        return (f["point"],)

    def needs(self, f: dict) -> tuple[str, ...]:
        """The points that must be known before the element can be solved."""
        raise NotImplementedError

    def needs_links(self, f: dict) -> tuple[str, ...]:
        """Links that must be solved before the element (beyond those that ``needs`` implies)."""
        return ()

    def check(self, f: dict) -> str | None:
        """A problem with the fields as written (one line naming the field), or None."""
        return None

    def check_context(self, f: dict, ground: tuple[str, ...]) -> str | None:
        """A problem with the fields given the ground points (once every name is known to exist), or None."""
        return None

    def check_resolved(self, e: dict, units: str = "m") -> str | None:
        """A problem with the resolved numbers (one line naming the field, its lengths in the file's ``units``, one
        of analytic.quantities.LENGTH_UNITS), or None."""
        return None

    def check_start(self, e: dict, st: "State") -> str | None:
        """A problem with the resolved element given where the elements before it are at the start (``st``:
        every element solved at the inputs' start values, one sample), one line naming the field, or None.
        Asked when a mechanism is built, only of kinds that override it (a group's pose)."""
        return None

    def group_label(self, e: dict) -> str:
        """What ``linkage check`` calls the resolved element's Assur group ("" for none)."""
        return self.group_class

    def extent(self, e: dict) -> float:
        """The resolved element's longest link [m] (the mechanism's size is the largest of these and the
        ground's spread): its ``size`` and ``lengths2`` fields."""
        out = 0.0
        for fname, fld in self.fields.items():
            if fld.type == "size":
                out = max(out, abs(e[fname]))
            elif fld.type == "lengths2":
                out = max([out] + [abs(x) for x in e[fname]])
        return out

    # ---------------------------------------------------------------------------------- topology
    def structure(self, f: dict) -> Structure:
        raise NotImplementedError

    def resolve_extra(self, e: dict, topology) -> None:
        """Add to the resolved element ``e`` what the solver needs from the topology (a link's origin)."""

    def resolve_at(self, e: dict, ground: dict) -> None:
        """Add to the resolved element ``e`` what depends on where the ground points are ({name: (x, y)} [m]):
        a cam's geometry."""

    def rise_measure(self, f: dict) -> str:
        """What the rises of a ``camlaw`` field measure given the element's fields: ``length`` or ``angle``."""
        return "length"

    def rails(self, e: dict) -> tuple[tuple[str, dict, float], ...]:
        """Blocks sliding on ground lines, for drawing their rails: (block, resolved guide, offset) each."""
        return ()

    # ------------------------------------------------------------------------------------ solver
    def solve(self, e: dict, st: State) -> None:
        """Solve the element on every sample: add its points, links, slides and extras to ``st``."""
        raise NotImplementedError

    def singularity(self, e: dict, st: State, size: float) -> np.ndarray | None:
        """A measure in [0, 1] that is 0 where the element is singular (its group cannot transmit motion),
        from the solved state; None for an element that is never singular."""
        return None

    def extra_outputs(self, e: dict) -> tuple[ExtraOutput, ...]:
        return ()

    def measured_extras(self, e: dict, st) -> dict:
        """Its own outputs from a measured state (``st.points``, ``st.links``, ``st.slides``: the simulated
        ones), named as :meth:`extra_outputs` names them."""
        return {}

    def slide_frames(self, e: dict) -> dict:
        """How each of its prismatic pairs is measured: {block: (origin, point, offset)}: ``s`` is the
        distance from the origin (a point's name or fixed (x, y) [m]) to ``point`` along the block's
        direction, the line shifted ``offset`` [m] to its left (see :func:`slide_origin`)."""
        return {}

    # ---------------------------------------------------------------------------------- inputs
    def input_joint(self, e: dict) -> str:
        """For inputs: the point it turns or slides about (its pivot, or the guide's origin)."""
        raise NotImplementedError

    def input_key(self, e: dict) -> str:
        """For inputs: what its columns and its drive are named after (:attr:`analytic.motion.Input.link`): its
        driven link by default (``phi1`` for crank link 1); an input that drives a pair of moving parts (an
        actuator, a motor between two links) is named by its own ``name`` instead."""
        return e["link"]

    def stops(self, e: dict) -> tuple[float, float] | None:
        """For inputs: the ends its coordinate cannot pass whatever the linkage (an actuator's stroke), or None."""
        return None

    def motion_problem(self, e: dict, column: str, t, q, units: str = "m") -> str | None:
        """For inputs: a problem with the input's motion ``q`` at times ``t`` [s] (``t`` None: samples of unknown
        time), one line naming the field (an actuator driven past its stroke), its lengths in the file's
        ``units``, or None."""
        return None

    # ---------------------------------------------------------------------- links-and-joints form
    joints_form: dict[str, str] | None = None
    """For inputs the links-and-joints form (:mod:`analytic.format.joints`) takes: the fields its
    ``[[inputs]]`` entry takes besides ``kind`` and what each is (``point``, ``link``: a name; ``angle``,
    ``length``: a value, whose parameters then measure that); None: not in that form."""
    joints_summary: str = ""
    """For inputs in the links-and-joints form: what it drives, in that form's words (error messages)."""

    def default_rate(self, size: float) -> tuple[str, object]:
        """For inputs: the field of its rate and the value written when a file or an importer gives none
        (``size``: the mechanism's size in file units)."""
        raise NotImplementedError

    def joints_ready(self, item: dict, dec) -> bool:
        """For inputs in the links-and-joints form: whether what the entry's input needs is placed (a crank's
        ground pivot: at once; a motor's carrier link: once the groups before it are found); the decomposer
        asks again after each group until it is."""
        return True

    def from_joints(self, item: dict, where: str, dec) -> None:
        """For inputs in the links-and-joints form: check the entry ``item`` (at ``where``, e.g.
        ``inputs[1]``) against the links and joints and write its element, through the decomposer ``dec``
        (:class:`analytic.format.joints._Decomposer`: ``dec.emit``, ``dec.fail``, its links and pose)."""
        raise NotImplementedError

    # ------------------------------------------------------------------------- other tools' files
    def from_pyslvs(self, pair) -> dict | None:
        """For inputs: the links-and-joints ``[[inputs]]`` entry of a Pyslvs input pair this kind drives
        (``pair``: :class:`analytic.format.pyslvs.Pair`, its joints and links), None where the pair is not of
        this kind; a FileError (``pair.fail``) where it is of this kind but cannot be driven. The importer
        takes the first registered kind's entry."""
        return None

    def from_pmks(self, driver) -> dict | None:
        """For inputs: the links-and-joints ``[[inputs]]`` entry of a PMKS driving joint this kind drives
        (``driver``: :class:`analytic.format.pmks.Driver`, the joint and the form read so far), None where
        it is not of this kind. The importer takes the first registered kind's entry."""
        return None

    @property
    def unit(self) -> str:
        """For inputs: the SI unit of its coordinate (``rad`` or ``m``)."""
        return "rad" if self.angular else "m"

    @property
    def periodic(self) -> bool:
        """For inputs: whether its coordinate repeats after a full turn of 2 pi (a crank's angle)."""
        return self.angular

    @property
    def drive_quantity(self) -> str:
        """For inputs: what its drive exerts, a quantity of :mod:`analytic.quantities` (``torque``,
        ``force``)."""
        return "torque" if self.angular else "force"

    @property
    def drive_unit(self) -> str:
        """For inputs: the SI unit of its drive (``N m`` or ``N``)."""
        return "N m" if self.angular else "N"

    @property
    def reference_rate(self) -> float:
        """For inputs: a typical rate of its coordinate, per second, in units of :meth:`rate_scale`: one turn
        (2 pi rad/s) for an angle, the mechanism's size per second for a length."""
        return 2 * math.pi if self.angular else 1.0

    def rate_scale(self, size: float) -> float:
        """For inputs: what its rates are measured against, given the mechanism's size [m]: 1 for an angle
        (rad/s as they are), the size for a length (a speed in sizes per second)."""
        return 1.0 if self.angular else size

    def turn(self, rate: float) -> float:
        """For inputs: one 'revolution' of its coordinate at the given rate: 2 pi for an angle; for a
        length, its travel in one second (1 when it does not move)."""
        return 2 * math.pi if self.angular else abs(rate) or 1.0

    def wheels(self, e: dict, pose: dict) -> tuple[Wheel, ...]:
        """Gears to draw on links (:class:`Wheel`), given the start pose ({point: (x, y)} [m])."""
        return ()

    def cylinders(self, e: dict) -> tuple[Cylinder, ...]:
        """Linear actuators to draw as a barrel and a rod (:class:`Cylinder`), instead of their two links."""
        return ()

    def describe(self, e: dict, pose: dict, unit: tuple[float, str]) -> str:
        """A line about the resolved element at a pose ({point: (x, y)} [m]) for ``linkage check`` (a gear
        pair's pitch radii), lengths in ``unit`` (metres per unit, its name); "" for nothing to say."""
        return ""

    # ------------------------------------------------------------------------------------ forces
    def forces(self, e: dict, ctx) -> None:
        """Solve the forces in the joints the element adds (and its input's drive, its gear pairs' moments)
        from the known loads on its links (``ctx``: :class:`analytic.applications.forces.Context`), and
        record them with ``ctx.pin``, ``ctx.guide``, ``ctx.drive``, ``ctx.coupling``. The default assembles
        the element's Newton-Euler equations from the topology and solves them per sample; a kind with a
        closed form overrides it."""
        ctx.generic(e)

    report_units: dict = {}
    """For inputs: the units of what :meth:`drive_report` reports, {section: {field: unit}}."""

    def drive_report(self, e: dict, drive, pressure_given=None) -> dict:
        """For inputs: what ``linkage forces --json`` reports of its drive besides the drive itself (``drive``:
        over the samples, SI), as {section: {name: entry}} merged into the record (an actuator's sizing and
        pressure; ``pressure_given`` [Pa]: the supply pressure ``--pressure`` to size it for); {} for nothing."""
        return {}

    def contact(self, e: dict, ctx) -> tuple:
        """For a kind with a cam coupling: its contact point K and unit common normal n (out of the cam)
        over the context's samples, ((kx, ky), (nx, ny)) [m, world]."""
        raise NotImplementedError

    # -------------------------------------------------------------------------------- simulation
    def mjcf(self, e: dict, model) -> None:
        """Add constraints the MuJoCo model needs besides its joints and loop closures (``model`` is the
        builder's context, :class:`sim.model.build.Context`)."""


@dataclass(frozen=True)
class Guide:
    """A guide line as written: the line P->Q of the link carrying both points (``points``), or a ground
    line through a point or coordinates at an angle (``through``, ``angle``)."""

    points: tuple[str, str] | None = None
    through: str | tuple[object, object] | None = None
    angle: object = 0.0

    def uses(self) -> tuple[str, ...]:
        """The points the guide needs."""
        if self.points:
            return self.points
        return (self.through,) if isinstance(self.through, str) else ()


# --------------------------------------------------------------------------------- shared geometry
def cross(ax, ay, bx, by):
    return ax * by - ay * bx


def line(P, Q):
    """A line through points P -> Q of one rigid link: origin P, unit direction (c, s), its angular
    velocity and acceleration (from the relative motion of Q about P)."""
    dx, dy = Q[0] - P[0], Q[1] - P[1]
    L2 = dx * dx + dy * dy
    L = np.sqrt(L2)
    w = cross(dx, dy, Q[2] - P[2], Q[3] - P[3]) / L2
    a = cross(dx, dy, Q[4] - P[4], Q[5] - P[5]) / L2
    return P, dx / L, dy / L, w, a


def on_frame(O, c, s, w, a, u, v):
    """Point at local (u, v) in a frame with origin O, x-axis (c, s), angular velocity w, acceleration a."""
    rx, ry = u * c - v * s, u * s + v * c
    w2 = w * w
    return (O[0] + rx, O[1] + ry, O[2] - w * ry, O[3] + w * rx,
            O[4] - a * ry - w2 * rx, O[5] + a * rx - w2 * ry)


def link_from(P, C, length):
    """The link P -> C of the given length: (cos, sin, omega, alpha)."""
    rx, ry = C[0] - P[0], C[1] - P[1]
    l2 = length * length
    return (rx / length, ry / length, cross(rx, ry, C[2] - P[2], C[3] - P[3]) / l2,
            cross(rx, ry, C[4] - P[4], C[5] - P[5]) / l2)


def fixed_point(x, y, n: int):
    """A point at rest at (x, y), on n samples."""
    zero = np.zeros(n)
    return (zero + x, zero + y, zero, zero, zero, zero)


def guide_line(G: dict, st: State):
    """Origin and motion of a resolved guide (``{"points": (P, Q)}`` or ``{"through": P or (x, y),
    "angle": a}``), as :func:`line` returns them."""
    if "points" in G:
        p, q = G["points"]
        return line(st.points[p], st.points[q])
    through = G["through"]
    O = st.points[through] if isinstance(through, str) else (through[0], through[1], 0.0, 0.0, 0.0, 0.0)
    return O, np.cos(G["angle"]), np.sin(G["angle"]), 0.0, 0.0


def slide_origin(G: dict):
    """Where a resolved guide measures from: its first point, or ``through`` (a point or (x, y))."""
    return G["points"][0] if "points" in G else G["through"]


def guide_link(G: Guide) -> tuple[str, str] | None:
    """The link a guide runs on, for :class:`Slide`: the pair of points, or None for a ground line given
    by a point or coordinates and an angle."""
    return G.points if G.points else None
