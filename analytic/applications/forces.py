"""Forces in every joint by kinetostatics: Newton-Euler per Assur group along the prescribed motion, every
sample at once (numpy).

The inputs' motion law fixes every link's acceleration, so every joint force follows from statics once each
link carries its d'Alembert load: the inertia force -m a_G at its centre of mass G and the couple -I alpha,
besides gravity m g and the external force on the output point (on its loaded link, Topology.loaded_link, where the MuJoCo
model's load acts). The elements are taken in **reverse solve order**: an element's links then carry every
force that later elements put on them (already solved), and its unknowns are the forces in the joints it
adds (an Assur group is statically determinate: 3 equations per link, 2 unknowns per lower pair), plus the
drive torque or force of an input and the constraint moment of a gear pair. Its reactions go onto the earlier
links (or the ground) it is joined to.

Each kind may solve its element in closed form (:meth:`analytic.kinds.base.Kind.forces`: the dyads, the
inputs, rigid points); the default, :meth:`Context.generic`, assembles the element's Newton-Euler equations
from the topology (its links, the joints it adds, its gear couplings) and solves them per sample
(:func:`numpy.linalg.solve` on the batch), so any kind is covered.

Conventions (SPEC, "Forces"): a joint's force is the force its ``a`` link (``links[0]``) exerts on its ``b``
link at the joint's point (world frame, N); a prismatic pair's is the constraint force across the guide
(normal to it) at the block's pin plus the couple ``M`` [N m] the guide exerts on the block; a driven pair's
drive is reported apart (``drives``: the torque [N m] a crank's drive puts on its link, the force [N] a
slider's drive puts on its block along the guide). A gear pair (a :class:`~analytic.topology.Coupling`)
exchanges couples as its constraint does in the MuJoCo model: ``lambda`` on ``link``, ``-ratio lambda`` on
``mesh`` and ``(ratio - 1) lambda`` on ``carrier``. The shaking force and moment are what the moving links
exert on the ground, about the world origin: the reactions at every ground joint, the drives' reactions
and the guides' couples.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic import kinds
from analytic._common import ParameterError
from analytic.kinds import GROUND

__all__ = ["Forces", "StaticsError", "Plan", "Context", "plan", "check_determinate", "solve", "centres", "wanted",
           "BLOCK"]

BLOCK = 8192
"""Samples per block: arrays of 64 KiB stay in the cache between the few hundred array operations a block
takes (a whole-array pass would stream every operation through main memory)."""


class StaticsError(ParameterError):
    """A linkage whose joint forces statics cannot give: a redundant constraint (named with its loop) or a
    singular pose."""


@dataclass(frozen=True)
class Forces:
    """The joint forces of a run (SI, world frame, arrays over the samples).

    ``F[k]``: (Fx, Fy) the force ``joints[k].a`` exerts on ``joints[k].b`` at its point [N]; ``couples``: {k:
    the couple [N m] the guide of prismatic pair ``joints[k]`` exerts on its block}; ``drives``: by input
    link, the torque [N m] or force [N] each drive puts on its link; ``couplings``: each gear pair's constraint
    moment ``lambda`` [N m]; ``shaking``: (Fx, Fy, M) the moving links exert on the ground (M about the origin);
    ``inertias``: the mass model used."""

    joints: tuple
    F: np.ndarray
    couples: dict
    drives: dict
    couplings: np.ndarray
    shaking: np.ndarray
    inertias: dict

    def index(self, name: str) -> int:
        """The index of the joint called ``name`` (KeyError if there is none)."""
        for k, j in enumerate(self.joints):
            if j.name == name:
                return k
        raise KeyError(name)

    def M(self, k: int) -> np.ndarray:
        """The couple of joint ``k`` [N m]: its guide's on its block (a prismatic pair), 0 (a revolute)."""
        return self.couples[k] if k in self.couples else np.zeros(self.F.shape[-1])

    def magnitude(self) -> np.ndarray:
        """|F| of every joint, shape (n_joints, N)."""
        return np.hypot(self.F[:, 0], self.F[:, 1])


# ------------------------------------------------------------------------------------------- plan
@dataclass(frozen=True)
class Step:
    """One element in the order forces are solved: its position in the solve order, resolved fields, the
    links it creates, the joints and gear couplings it adds (indices), and its label."""

    pos: int
    element: dict
    links: tuple
    joints: tuple
    couplings: tuple


@dataclass(frozen=True)
class Plan:
    """What the force solve needs from the topology, built once per mechanism."""

    steps: tuple
    joints: tuple
    couplings: tuple
    ratios: tuple
    origins: dict
    at: dict
    """(point, link) -> indices of the joints at that point involving that link."""
    slide: dict
    """block link -> index of its prismatic pair."""
    driven: dict
    """input index -> index of its driven pair."""
    inputs: tuple
    loops: tuple
    label_of: dict


def plan(mech) -> Plan:
    """The static part of the force solve of ``mech``: which element owns which joint (the latest in solve
    order of the elements creating its two links), the lookup tables, the gear ratios."""
    topo = mech.topology
    elements = mech.geometry.elements
    pos_of_written = {w: k for k, w in enumerate(topo.order)}
    link_pos = {GROUND: -1, **{ln: pos_of_written[link.element] for ln, link in topo.links.items()}}
    joints = topo.joints
    owner = [max(link_pos[j.a], link_pos[j.b]) for j in joints]
    couplings, ratios, c_owner = [], [], []
    for c in topo.couplings:
        e = elements[pos_of_written[c.element]]
        couplings.append(c)
        ratios.append(float(e[ratio_field(mech, c)]) if c.kind == "gear" else 0.0)
        c_owner.append(max(link_pos[c.link], link_pos[c.mesh], link_pos[c.carrier], pos_of_written[c.element]))
    steps = []
    for k, e in enumerate(elements):
        links = tuple(ln for ln in topo.links if link_pos[ln] == k)
        steps.append(Step(k, e, links, tuple(i for i, o in enumerate(owner) if o == k),
                          tuple(i for i, o in enumerate(c_owner) if o == k)))
    at: dict = {}
    for i, j in enumerate(joints):
        if j.kind == "revolute":
            at.setdefault((j.point, j.a), []).append(i)
            at.setdefault((j.point, j.b), []).append(i)
    slide = {j.slide: i for i, j in enumerate(joints) if j.kind == "prismatic"}
    driven = {j.input: i for i, j in enumerate(joints) if j.input is not None}
    return Plan(tuple(steps), joints, tuple(couplings), tuple(ratios), dict(mech.link_origins),
                {k: tuple(v) for k, v in at.items()}, slide, driven, tuple(mech.inputs), topo.loops,
                {k: e["label"] for k, e in enumerate(elements)})


def unknowns(p: Plan, step: Step) -> int:
    """How many force unknowns an element adds: 2 per lower pair it owns, 1 per drive and per gear pair."""
    return sum(2 + (p.joints[k].input is not None) for k in step.joints) + len(step.couplings)


def check_determinate(mech, p: Plan | None = None) -> Plan:
    """The plan of ``mech``, after checking that every element is statically determinate (as many force
    unknowns as equations of its links); a StaticsError naming the element and its loop otherwise."""
    p = p or plan(mech)
    for step in p.steps:
        k = unknowns(p, step)
        if k != 3 * len(step.links):
            raise indeterminate(p, step, k)
    return p


def ratio_field(mech, c) -> str:
    """The name of the field of its element that holds a topology coupling's ratio (the kind's
    :class:`~analytic.kinds.base.Coupling` says which)."""
    written = mech.definition.elements[c.element]
    for kc in kinds.get(written.kind).structure(written.fields).couplings:
        if (kc.link, kc.mesh, kc.carrier) == (c.link, c.mesh, c.carrier):
            return kc.ratio
    raise KeyError(f"no coupling {c.link}-{c.mesh} in {written.label}")


# ---------------------------------------------------------------------------------------- context
class Context:
    """The state of the force solve on one block of samples, handed to each kind's ``forces(e, ctx)``.

    Read: :meth:`xy` (a point's position), :meth:`direction` (a link's unit x-axis), :meth:`resultant` and
    :meth:`moment` (the known loads on a link: its d'Alembert load, gravity, the external force and every
    force later elements put on it). Record: :meth:`pin` (a revolute's force), :meth:`guide` (a prismatic
    pair's force and couple), :meth:`drive` (an input's torque or force), :meth:`coupling` (a gear pair's
    moment); each puts the reaction on the joint's other link when that link belongs to an earlier element
    (or is the ground)."""

    def __init__(self, plan_: Plan, sol, sl: slice, out: dict):
        self.plan = plan_
        self.sol = sol
        self.sl = sl
        self.out = out
        self.F: dict = {}
        self.M: dict = {}
        self.ground = [0.0, 0.0, 0.0]
        self.step: Step | None = None
        self.done: set = set()

    # ---------------------------------------------------------------- kinematics
    def xy(self, p: str):
        """(x, y) of point ``p`` [m]."""
        return self.sol["x" + p][self.sl], self.sol["y" + p][self.sl]

    def direction(self, link: str):
        """(cos, sin) of link ``link``'s angle (a block's: its guide's direction)."""
        return self.sol["cos" + link][self.sl], self.sol["sin" + link][self.sl]

    # ---------------------------------------------------------------- known loads
    def resultant(self, link: str):
        """(Fx, Fy) of the known loads on ``link`` [N]."""
        return self.F[link]

    def moment(self, link: str, p: str):
        """The moment [N m] of the known loads on ``link`` about point ``p`` (z)."""
        origin = self.plan.origins[link]
        if origin == p:
            return self.M[link]
        ox, oy = self.xy(origin)
        px, py = self.xy(p)
        fx, fy = self.F[link]
        return self.M[link] + (ox - px) * fy - (oy - py) * fx

    def _push(self, link: str, p: str, fx, fy, couple=None):
        """Add a force (fx, fy) at point ``p`` and a couple to the known loads of ``link`` (or the ground's
        reaction), unless ``link`` belongs to the element being solved."""
        if link in self.step.links:
            return
        px, py = self.xy(p)
        if link == GROUND:
            g = self.ground
            g[0] = g[0] + fx
            g[1] = g[1] + fy
            g[2] = g[2] + (px * fy - py * fx)
            if couple is not None:
                g[2] = g[2] + couple
            return
        ox, oy = self.xy(self.plan.origins[link])
        F = self.F[link]
        F[0] += fx
        F[1] += fy
        self.M[link] += (px - ox) * fy - (py - oy) * fx
        if couple is not None:
            self.M[link] += couple

    def _couple(self, link: str, value):
        if link in self.step.links:
            return
        if link == GROUND:
            self.ground[2] = self.ground[2] + value
        else:
            self.M[link] += value

    # ---------------------------------------------------------------- results
    def pin(self, p: str, link: str, fx, fy, other: str | None = None) -> None:
        """The force (fx, fy) [N] that the revolute at ``p`` puts on ``link`` (from ``other``, or from the one
        joint there that involves ``link``)."""
        k = self._revolute(p, link, other)
        j = self.plan.joints[k]
        sign = 1.0 if j.b == link else -1.0
        self._store(k, sign * fx, sign * fy)
        self._push(j.a if j.b == link else j.b, p, -fx, -fy)

    def guide(self, block: str, fx, fy, couple) -> None:
        """The prismatic pair of ``block``: the force (fx, fy) [N] (normal to the guide, at the block's pin)
        and the couple [N m] its guide puts on the block."""
        k = self.plan.slide[block]
        j = self.plan.joints[k]
        self._store(k, fx, fy, couple)
        self._push(j.a, j.point, -fx, -fy, -couple)

    def drive(self, e: dict, value) -> None:
        """Input ``e``'s drive: the torque [N m] on its crank, or the force [N] on its block along the guide."""
        i = e["input"]
        k = self.plan.driven[i]
        j = self.plan.joints[k]
        self.out["drives"][i][self.sl] = value
        self.done.add(("drive", i))
        if j.kind == "revolute":
            self._couple(j.a, -value)
        else:
            c, s = self.direction(j.b)
            self._push(j.a, j.point, -value * c, -value * s)

    def coupling(self, k: int, value) -> None:
        """Gear pair ``k``'s constraint moment lambda [N m] (couples lambda, -ratio lambda, (ratio - 1)
        lambda on its link, mesh and carrier)."""
        c, r = self.plan.couplings[k], self.plan.ratios[k]
        self.out["couplings"][k, self.sl] = value
        self.done.add(("coupling", k))
        for link, f in ((c.link, 1.0), (c.mesh, -r), (c.carrier, r - 1.0)):
            self._couple(link, f * value)

    def contact(self, k: int, e: dict, value) -> None:
        """Cam contact ``k`` of element ``e``: its force N [N] along the common normal n (out of the cam, on
        the follower: the coupling's link) at the contact point K (the kind's :meth:`Kind.contact`); the
        reaction -N n at K goes on the cam's link (the coupling's mesh)."""
        c = self.plan.couplings[k]
        (kx, ky), (nx, ny) = kinds.get(e["kind"]).contact(e, self)
        self.out["couplings"][k, self.sl] = value
        self.done.add(("coupling", k))
        ref = self.plan.origins[c.mesh] if c.mesh != GROUND else self.plan.origins[c.link]
        px, py = self.xy(ref)
        fx, fy = -value * nx, -value * ny
        self._push(c.mesh, ref, fx, fy, (kx - px) * fy - (ky - py) * fx)

    def _revolute(self, p, link, other):
        cands = self.plan.at.get((p, link), ())
        if other is not None:
            cands = [k for k in cands if other in (self.plan.joints[k].a, self.plan.joints[k].b)]
        if len(cands) != 1:
            raise ValueError(f"no single revolute at {p} on link {link}" + (f" and {other}" if other else ""))
        return cands[0]

    def _store(self, k, fx, fy, couple=None):
        self.out["F"][k, 0, self.sl] = fx
        self.out["F"][k, 1, self.sl] = fy
        if couple is not None:
            self.out["M"][k][self.sl] = couple
        self.done.add(("joint", k))

    # ---------------------------------------------------------------- the general solve
    def generic(self, e: dict) -> None:
        """Solve the element being processed from its Newton-Euler equations: 3 per link it creates (force
        and moment about the link's origin), one unknown per force component of the joints it adds (a
        revolute's Fx, Fy; a prismatic pair's normal force and couple; a drive; a gear pair's moment),
        assembled from the topology and solved per sample."""
        step = self.step
        links = step.links
        plan_ = self.plan
        rows = {ln: 3 * i for i, ln in enumerate(links)}
        cols = []
        for k in step.joints:
            j = plan_.joints[k]
            cols += [("Fx", k), ("Fy", k)] if j.kind == "revolute" else [("N", k), ("M", k)]
            if j.input is not None:
                cols.append(("drive", k))
        cols += [("lambda", k) for k in step.couplings]
        if len(cols) != 3 * len(links):
            raise indeterminate(plan_, step, len(cols))
        if not cols:
            return
        n = self.sl.stop - self.sl.start
        size = len(cols)
        A = np.zeros((n, size, size))
        b = np.zeros((n, size))
        for ln, r in rows.items():
            fx, fy = self.F[ln]
            b[:, r] = -fx
            b[:, r + 1] = -fy
            b[:, r + 2] = -self.M[ln]

        def force(col, link, p, ux, uy, sign):
            if link not in rows:
                return
            r = rows[link]
            px, py = self.xy(p)
            ox, oy = self.xy(plan_.origins[link])
            A[:, r, col] += sign * ux
            A[:, r + 1, col] += sign * uy
            A[:, r + 2, col] += sign * ((px - ox) * uy - (py - oy) * ux)

        def couple(col, link, f):
            if link in rows:
                A[:, rows[link] + 2, col] += f

        for col, (what, k) in enumerate(cols):
            if what == "lambda" and plan_.couplings[k].kind == "cam":   # N along the normal at the contact
                c = plan_.couplings[k]
                (kx, ky), (nx, ny) = kinds.get(step.element["kind"]).contact(step.element, self)
                for link, sign in ((c.link, 1.0), (c.mesh, -1.0)):
                    if link in rows:
                        r = rows[link]
                        ox, oy = self.xy(plan_.origins[link])
                        A[:, r, col] += sign * nx
                        A[:, r + 1, col] += sign * ny
                        A[:, r + 2, col] += sign * ((kx - ox) * ny - (ky - oy) * nx)
                continue
            if what == "lambda":
                c, r = plan_.couplings[k], plan_.ratios[k]
                for link, f in ((c.link, 1.0), (c.mesh, -r), (c.carrier, r - 1.0)):
                    couple(col, link, f)
                continue
            j = plan_.joints[k]
            one = np.ones(n)
            zero = np.zeros(n)
            if what == "Fx":
                u = (one, zero)
            elif what == "Fy":
                u = (zero, one)
            elif what == "N":
                c, s = self.direction(j.b)
                u = (-s, c)
            elif what == "drive" and j.kind == "prismatic":
                u = self.direction(j.b)
            else:
                u = None
            if u is None:                              # a couple: the pair's M or a crank's drive
                couple(col, j.b, 1.0)
                couple(col, j.a, -1.0)
            else:
                force(col, j.b, j.point, u[0], u[1], 1.0)
                force(col, j.a, j.point, u[0], u[1], -1.0)
        x = _solve_batch(A, b)
        if x is None:
            raise indeterminate(plan_, step, len(cols), singular=True)
        for k in step.joints:
            j = plan_.joints[k]
            if j.kind == "revolute":
                fx, fy = x[:, cols.index(("Fx", k))], x[:, cols.index(("Fy", k))]
                self._store(k, fx, fy)
                self._push(j.a, j.point, -fx, -fy)
            else:
                N, M = x[:, cols.index(("N", k))], x[:, cols.index(("M", k))]
                c, s = self.direction(j.b)
                self.guide(j.b, -s * N, c * N, M)
            if j.input is not None:
                self.drive(_input_element(plan_, j.input), x[:, cols.index(("drive", k))])
        for k in step.couplings:
            if plan_.couplings[k].kind == "cam":
                self.contact(k, step.element, x[:, cols.index(("lambda", k))])
            else:
                self.coupling(k, x[:, cols.index(("lambda", k))])


def _input_element(plan_: Plan, i: int) -> dict:
    return next(s.element for s in plan_.steps if s.element.get("input") == i)


def _solve_batch(A, b):
    """x with A x = b per sample; NaN rows where A is singular; None when it is singular at every sample of
    the block."""
    try:
        return np.linalg.solve(A, b[..., None])[..., 0]
    except np.linalg.LinAlgError:
        pass
    with np.errstate(invalid="ignore", divide="ignore"):
        sv = np.linalg.svd(A, compute_uv=False)
        bad = ~(sv[:, -1] > 1e-14 * sv[:, 0])
    if bad.all():
        return None
    A = A.copy()
    A[bad] = np.eye(A.shape[1])
    x = np.linalg.solve(A, b[..., None])[..., 0]
    x[bad] = np.nan
    return x


def indeterminate(plan_: Plan, step: Step, unknowns: int, singular: bool = False) -> StaticsError:
    """The one-line error for an element whose forces statics cannot give, naming a loop it closes."""
    links = set(step.links)
    owned = {plan_.joints[k].name for k in step.joints}
    loop = next((lp for lp in plan_.loops if lp.joint.name in owned or links & set(lp.links)), None)
    where = ""
    if loop is not None:
        ring = list(loop.links) + [loop.links[0]]
        where = f" in the loop {'-'.join(ring)} (closed at joint {loop.joint.name})"
    label = plan_.label_of[step.pos]
    equations = 3 * len(step.links)
    if singular:
        return StaticsError(f"{label}: statically indeterminate{where}: its joint forces are not determined by "
                            f"statics at these poses (a redundant constraint, or a group held in a singular pose); "
                            f"free one joint of the loop")
    if unknowns > equations:
        return StaticsError(f"{label}: statically indeterminate{where}: {unknowns} unknown joint forces for "
                            f"{equations} equations of its links {', '.join(step.links)} (a redundant "
                            f"constraint); remove a joint or free one (e.g. a pin in a slot)")
    return StaticsError(f"{label}: {unknowns} unknown joint forces for {equations} equations of its links "
                        f"{', '.join(step.links) or '(none)'}{where}: the group can move by itself; it needs "
                        f"another joint or an input")


# ------------------------------------------------------------------------------------------- solve
def wanted(mech) -> list[str]:
    """The outputs the force solve reads: positions and accelerations of every point, each link's angle
    (cos, sin), angular velocity and acceleration."""
    return ([c + p for p in mech.points for c in ("x", "y", "ax", "ay")]
            + [c + ln for ln in mech.links for c in ("cos", "sin", "omega", "alpha")])


def solve(mech, q, qd, qdd, inertias: dict, gravity=(0.0, 0.0), force=(0.0, 0.0), force_on=1.0,
          point: str | None = None, sol=None, block: int = BLOCK, applied=()) -> Forces:
    """Every joint force, drive and the shaking force and moment of ``mech`` along a motion.

    Parameters
    ----------
    q, qd, qdd : array_like, shape (N,) or (N, n_inputs)
        The inputs' positions [rad or m], rates and accelerations.
    inertias : dict
        {link: :class:`~analytic.mass.Inertia`} (SI; :func:`analytic.mass.model`); links not
        named are massless.
    gravity : (gx, gy)
        [m/s^2] in the plane.
    force : (fx, fy)
        External force [N] on ``point`` (default: the output point), on the link that carries it, times
        ``force_on`` (a scalar or an array over the samples: a cutting force's switch).
    sol : Solution, optional
        The kinematics at these inputs, with at least :func:`wanted`'s outputs (solved here when None).
    applied : sequence of :class:`analytic.loads.Application`
        Further wrenches on links (arrays over the samples; on the ground: reactions the frame feels, added
        to the shaking force and moment): the file's loads, friction.

    Returns
    -------
    Forces
    """
    unknown = set(inertias) - set(mech.links)
    if unknown:
        raise ParameterError(f"no link named {', '.join(sorted(unknown))} in the {mech.name}; links: "
                             f"{', '.join(mech.links)}")
    if sol is None:
        sol = mech.solve(q, qd, qdd, outputs=wanted(mech))
    n = int(np.size(sol["x" + mech.points[0]]))
    sol = {k: np.reshape(sol[k], n) for k in wanted(mech)}
    p = check_determinate(mech)
    nj = len(p.joints)
    out = {"F": np.empty((nj, 2, n)), "M": {k: np.empty(n) for k in p.slide.values()},
           "drives": np.empty((len(p.inputs), n)), "couplings": np.empty((len(p.couplings), n)),
           "shaking": np.empty((3, n))}
    force_on = np.broadcast_to(np.asarray(force_on, dtype=float), (n,))
    point = point or mech.output_point
    carrier = mech.topology.loaded_link(point)
    gx, gy = (float(x) for x in gravity)
    fx, fy = (float(x) for x in force)
    loaded = (fx != 0.0 or fy != 0.0) and carrier != GROUND
    for first in range(0, n, block):
        sl = slice(first, min(first + block, n))
        ctx = Context(p, sol, sl, out)
        _loads(ctx, mech, inertias, gx, gy)
        if loaded:
            on = force_on[sl]
            ctx.step = Step(-2, {}, (), (), ())
            ctx._push(carrier, point, fx * on, fy * on)
        for a in applied:
            _apply(ctx, a)
        for step in reversed(p.steps):
            ctx.step = step
            kinds.get(step.element["kind"]).forces(step.element, ctx)
            if first == 0:
                _check_complete(p, step, ctx)
        for k in range(3):
            out["shaking"][k, sl] = ctx.ground[k]
    drives = {inp.link: out["drives"][i] for i, inp in enumerate(p.inputs)}
    return Forces(p.joints, out["F"], out["M"], drives, out["couplings"], out["shaking"], dict(inertias))


def _apply(ctx: Context, a) -> None:
    """Add a load's wrench (an :class:`analytic.loads.Application`) on this block to its link's known loads,
    or to what the ground feels."""
    sl = ctx.sl

    def part(v):                                       # arrays over all samples, or a constant
        return np.asarray(v, dtype=float)[sl] if np.ndim(v) else float(v)

    fx, fy, px, py, m = (part(v) for v in (a.fx, a.fy, a.px, a.py, a.couple))
    if a.link == GROUND:
        g = ctx.ground
        g[0] = g[0] + fx
        g[1] = g[1] + fy
        g[2] = g[2] + (px * fy - py * fx) + m
        return
    ox, oy = ctx.xy(ctx.plan.origins[a.link])
    F = ctx.F[a.link]
    F[0] = F[0] + fx
    F[1] = F[1] + fy
    ctx.M[a.link] = ctx.M[a.link] + (px - ox) * fy - (py - oy) * fx + m


def _loads(ctx: Context, mech, inertias, gx, gy) -> None:
    """Each link's d'Alembert load and weight: -m a_G + m g at G and the couple -I alpha, as a resultant and
    a moment about the link's origin."""
    sol, sl = ctx.sol, ctx.sl
    for ln in mech.links:
        o = ctx.plan.origins[ln]
        c, s = sol["cos" + ln][sl], sol["sin" + ln][sl]
        b = inertias.get(ln)
        if b is None:
            zero = np.zeros(sl.stop - sl.start)
            ctx.F[ln] = [zero, zero.copy()]
            ctx.M[ln] = zero.copy()
            continue
        w, al = sol["omega" + ln][sl], sol["alpha" + ln][sl]
        rx = b.cx * c - b.cy * s
        ry = b.cx * s + b.cy * c
        w2 = w * w
        agx = sol["ax" + o][sl] - al * ry - w2 * rx
        agy = sol["ay" + o][sl] + al * rx - w2 * ry
        Fx = b.m * (gx - agx)
        Fy = b.m * (gy - agy)
        M = rx * Fy
        M -= ry * Fx
        M -= b.I * al
        ctx.F[ln] = [Fx, Fy]
        ctx.M[ln] = M


def centres(mech, sol, inertias: dict) -> dict:
    """Each link's centre of mass along a solution: {link: (xG, yG)} [m] (a massless link: its origin)."""
    out = {}
    for ln in mech.links:
        o = mech.link_origins[ln]
        b = inertias.get(ln)
        cx, cy = (b.cx, b.cy) if b is not None else (0.0, 0.0)
        c, s = np.asarray(sol["cos" + ln]), np.asarray(sol["sin" + ln])
        out[ln] = (sol["x" + o] + cx * c - cy * s, sol["y" + o] + cx * s + cy * c)
    return out


def _check_complete(p: Plan, step: Step, ctx: Context) -> None:
    """Every joint, drive and coupling the element adds was solved (a kind's closed form must give them all)."""
    missing = [p.joints[k].name for k in step.joints if ("joint", k) not in ctx.done]
    missing += [f"drive of input {p.joints[k].input}" for k in step.joints
                if p.joints[k].input is not None and ("drive", p.joints[k].input) not in ctx.done]
    missing += [f"gear pair {k}" for k in step.couplings if ("coupling", k) not in ctx.done]
    if missing:
        raise RuntimeError(f"{p.label_of[step.pos]}: the {step.element['kind']} kind's forces left "
                           f"{', '.join(missing)} unsolved")


def singular_samples(forces: Forces) -> np.ndarray:
    """Samples where a joint force or drive is not finite (a singular pose)."""
    bad = ~np.isfinite(forces.F).all(axis=(0, 1))
    for v in forces.couples.values():
        bad |= ~np.isfinite(v)
    for v in forces.drives.values():
        bad |= ~np.isfinite(v)
    return bad


def peak(forces: Forces) -> float:
    """The largest joint force magnitude over the run [N] (a scale for tolerances)."""
    m = forces.magnitude()
    return float(np.nanmax(m)) if m.size else 0.0


def angle_text(inp, value: float) -> str:
    """An input value as people read it: a crank's angle in degrees (0..360), a slider's distance in m."""
    return f"{math.degrees(value) % 360:.2f}deg" if inp.angular else f"{value:.6g} m"
