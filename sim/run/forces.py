"""MuJoCo's joint forces: every joint of the topology, each drive, each gear pair and the shaking force and
moment, read from the simulated model and compared with the analytic kinetostatics
(:mod:`analytic.applications.forces`).

Where each comes from, at a recorded instant (the step's state re-evaluated by ``mj_forward``, see
:func:`sim.run.simulate.replay`):

- a loop closure (a ``connect`` equality between site1 on one body and site2 on another): its constraint
  force ``efc_force`` (3 world-frame rows, MuJoCo's residual is pos(site1) - pos(site2)) acts as +f on the
  body of site1 and -f on the body of site2;
- a tree joint (a hinge or a slide between a parent and a child body): the child's ``cfrc_int`` (by
  ``mj_rnePostConstraint``, which the model's acceleration sensors trigger): the spatial force [torque,
  force] the parent exerts on the child, in the world orientation about the subtree's centre of mass
  ``subtree_com[body_rootid]``, moved here onto the joint's point. ``cfrc_int`` is the recursive
  Newton-Euler sum over the child's subtree of (inertial force - external force), where the external forces
  ``cfrc_ext`` hold the loops' constraint forces (measured: the connect's +f and -f appear there) and gravity
  enters as the world's acceleration -g; the external load is a site actuator, which MuJoCo applies in joint
  space (``qfrc_actuator``), not in ``cfrc_ext``: its wrench is taken out of ``cfrc_int`` here for every body
  whose subtree carries it;
- a drive: the actuator's force less its rotor's inertia (``armature x qacc``), i.e. what reaches the link,
  as the analytic drive is defined (a crank's torque on its link, a slider's force on its block along the
  guide);
- a gear pair (a tendon equality over the hinges, sim.model.build.Context.couple): its constraint force
  ``lambda`` (the tendon phi_link - (1 - ratio) phi_carrier - ratio phi_mesh gives couples lambda,
  -ratio lambda, (ratio - 1) lambda on link, mesh and carrier: the analytic convention as it stands);
- the shaking force and moment: minus what the ground exerts on the moving links, i.e. the tree joints at
  the ground (their whole interaction wrench: bearing force, a drive's torque, a guide's couple, a gear's
  couple on a ground hinge) and the loops closed at a ground point.

The joints follow SPEC's convention: ``Fx, Fy`` is the force ``links[0]`` (``a``) exerts on ``links[1]``
(``b``); a prismatic pair's is the whole force across the pair less a driven slider's push, so a force
along an undriven guide (there should be none) shows up as an error, and ``M`` the couple the guide exerts on
the block about the block's pin.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from analytic.applications import forces as F
from analytic.kinds import GROUND

FORCE_TOL = 1e-4
"""[of the peak joint force of the run] MuJoCo's joint forces against the analytic ones at the simulated
inputs, per sample: what separates them is the simulated state's error (accelerations within 1e-3 of their
scale by the verdict, measured 1e-7 to 5e-6: the joint forces are mostly inertial and scale with them) and
the regulariser's leak, R / (J M^-1 J') ~ 1e-10 of the constraint force with R shrunk by
sim.model.REGULARIZATION_SCALE (larger only near a singular pose). Couples, drive torques and gear moments
are judged against the peak joint force times the size L (the scale of a moment), a drive also against its
own peak where that is larger."""

JOINT_FLOOR = 1e-3
"""[of the links' inertial force scale sum_k m_k L Omega^2, Omega at least sim.model.timestep.reference_rate]
the least scale the joint forces are judged against (FORCE_TOL of it): a run far slower than the reference
speed has joint forces falling as the speed squared while MuJoCo's residual falls about linearly (PMKS'
slider_input rocked at 0.1 mm/s: 5e-3 of its 2.6e-8 N peak, 1.3e-10 N); at their default speeds the
library's peaks are 0.26-5.6 of the scale (fourbar 0.45, slider_crank 0.26, whitworth 2.8, jansen 5.6,
sixbar 0.33, fivebar 0.39, peaucellier 0.27), so there the floor never binds."""

IDENTITY_TOL = 1e-8
"""[of a drive's scale (as FORCE_TOL's)] the Newton-Euler drive against the power balance
(analytic/applications/torque.py) at the same inputs: two eliminations of the same equations, whose rounding
(measured 1e-15 of the peak on the library, tests/test_forces.py) grows as 1/sin of a group's transmission
angle; what is left above that is a fault."""

WORLD = "world"


@dataclass(frozen=True)
class Tree:
    """A joint carried by a tree joint of the model: the child body, the parent body, the sign that turns
    the child's interaction force into the force ``a`` exerts on ``b`` (+1 when the child is ``b``)."""

    joint: int
    child: int
    parent: int
    sign: float
    slide: bool


@dataclass(frozen=True)
class Closure:
    """A joint closed by a loop's connect: its efc rows come from equality ``eq``; ``sign`` turns +f (on the
    body of site1) into the force ``a`` exerts on ``b``."""

    joint: int
    eq: int
    sign: float
    ground_body: int
    """The body on the moving side when the other side is the ground (-1 otherwise)."""


@dataclass(frozen=True)
class Layout:
    """Where every force of the model is read, built once per model."""

    trees: tuple
    closures: tuple
    drives: tuple
    """(input link, actuator id, dof, sign onto the driven link) of each input."""
    couplings: tuple
    """Per coupling in the topology's order: ("gear", equality id of its tendon equality) or ("cam", cam body id,
    follower body id)."""
    sites: tuple
    """Site id of each joint's point (its carrier's site)."""
    load_site: int
    load_actuator: int
    load_bodies: np.ndarray
    """1 for every body whose subtree holds the load's site (its cfrc_int carries the load), else 0."""
    roots: np.ndarray
    """body_rootid of every body."""
    ground_children: tuple


def layout(built) -> Layout:
    """The reading plan of ``built``'s model: which tree joint or loop carries each topology joint, with its
    sign, the drives' actuators and dofs, the gear pairs' equalities, the load's site and carrier chain."""
    model, mech = built.model, built.mech
    topo = mech.topology
    index = {j.name: k for k, j in enumerate(topo.joints)}

    def body(link: str) -> int:
        return model.body(WORLD if link == GROUND else link).id

    trees = []
    for parent, child, j in topo.tree:
        sign = 1.0 if child == j.b else -1.0
        trees.append(Tree(index[j.name], body(child), body(parent), sign, j.kind == "prismatic"))
    closures = []
    for lp, tl in zip(built.loops, topo.loops):
        j = tl.joint
        b1 = int(model.site_bodyid[model.site(lp.site1).id])
        b2 = int(model.site_bodyid[model.site(lp.site2).id])
        sign = 1.0 if b1 == body(j.b) else -1.0
        if b1 != body(j.b) and b2 != body(j.b):
            raise RuntimeError(f"loop {lp.name}: neither site is on link {j.b}")
        moving = b2 if b1 == 0 else b1 if b2 == 0 else -1
        closures.append(Closure(index[j.name], model.equality(lp.name).id, sign, moving))
    drives = []
    for d in built.drives:
        jid = model.joint(d.joint).id
        child = int(model.jnt_bodyid[jid])
        jt = next(j for j in topo.joints if j.name == d.joint)
        drives.append((d.input.link, model.actuator(d.actuator).id, int(model.jnt_dofadr[jid]),
                       1.0 if child == body(jt.b) else -1.0))
    couplings = []
    for c in topo.couplings:                  # a gear pair's tendon equality; a cam's contact: its bodies
        if c.kind == "cam":
            couplings.append(("cam", body(c.mesh), body(c.link)))
        else:
            couplings.append(("gear", model.equality(f"couple_gear_{c.link}").id))
    sites = tuple(model.site(j.point).id for j in topo.joints)
    load_site = int(model.actuator_trnid[model.actuator("load").id, 0])   # on the loaded link
    carrier = int(model.site_bodyid[load_site])
    chain = np.zeros(model.nbody)
    b = carrier
    while b != 0:
        chain[b] = 1.0
        b = int(model.body_parentid[b])
    ground_children = tuple(t for t in trees if t.parent == 0)
    return Layout(tuple(trees), tuple(closures), tuple(drives), tuple(couplings), sites, load_site,
                  model.actuator("load").id, chain, np.asarray(model.body_rootid).copy(), ground_children)


@dataclass(frozen=True)
class Record:
    """The raw MuJoCo quantities at each replayed instant (arrays over the instants first)."""

    cfrc_int: np.ndarray      # (N, nbody, 6)
    subtree_com: np.ndarray   # (N, nbody, 3)
    site_xpos: np.ndarray     # (N, nsite, 3)
    efc_force: np.ndarray     # (N, nefc)
    efc_id: np.ndarray        # (nefc,)  equality id of each row (all rows are equality rows)
    actuator_force: np.ndarray  # (N, nu)
    qacc: np.ndarray          # (N, nv)
    xaxis: np.ndarray         # (N, njnt, 3)
    contact: np.ndarray       # (N, cams)  each cam's contact force along its normal [N]


def settle(model, data) -> None:
    """Replace the primal solver's constraint forces of the current ``mj_forward`` by MuJoCo's constraint model
    solved in its dual form, f = (A + R)^-1 (aref - J qacc_smooth), A = J M^-1 J' (MuJoCo's documented
    unconstrained minimiser; all rows are equalities, so it is the solution), then qacc = qacc_smooth +
    M^-1 J' f and ``mj_rnePostConstraint`` again so that ``cfrc_int`` and ``cfrc_ext`` hold these forces.

    Why: the primal Newton solver returns an accurate qacc but gives the force as f = D (aref - J qacc) with
    D = 1/R ~ 5e9 (the regulariser shrunk by sim.model.REGULARIZATION_SCALE): the force is a residual of
    1e-10 times the accelerations, amplified by D, and its rounding left 7 % errors in a loop's force where
    a drive's rotor torque (armature x qacc) reached 1e4 times the link torques (a rocking four-bar at its
    turnaround), with M qacc - qfrc - J' f = 3e-3 N m. The dual solve is conditioned like A itself."""
    n = data.nefc
    if n and data.ne == n:                                    # the rows are equalities only (they come first)
        nv = model.nv
        if mujoco.mj_isSparse(model):
            J = np.zeros((n, nv))
            mujoco.mju_sparse2dense(J, data.efc_J, data.efc_J_rownnz[:n], data.efc_J_rowadr[:n],
                                    data.efc_J_colind)
        else:
            J = data.efc_J[:n * nv].reshape(n, nv)
        X = np.empty((n, nv))
        mujoco.mj_solveM(model, data, X, J)                   # rows: M^-1 J_i'
        A = J @ X.T
        A.flat[::n + 1] += data.efc_R[:n]
        rhs = data.efc_aref[:n] - J @ data.qacc_smooth
        mujoco.mju_cholFactor(A, 0.0)                         # A + R is positive definite (R > 0)
        f = np.empty(n)
        mujoco.mju_cholSolve(f, A, rhs)
        data.efc_force[:n] = f
        data.qacc[:] = data.qacc_smooth + f @ X
        data.qfrc_constraint[:] = f @ J
    mujoco.mj_rnePostConstraint(model, data)


def cam_pairs(model, mech) -> tuple:
    """(cam body id, follower body id) of each cam coupling of ``mech``, in the topology's order."""
    return tuple((model.body(c.mesh).id, model.body(c.link).id) for c in mech.topology.couplings
                 if c.kind == "cam")


def contact_forces(model, data, pairs) -> np.ndarray:
    """The normal force [N] of each cam's contact (``pairs``: :func:`cam_pairs`), summed over its active
    contact rows in their order (frictionless, condim 1: one row per contact, its force along the normal;
    MuJoCo orders the rows equalities first, ``data.ne`` of them, then the others: here contacts only)."""
    return contacts_reader(model, pairs)(data)


def contacts_reader(model, pairs):
    """:func:`contact_forces` as a function of ``data`` alone, its lookups made once (the replay's reader; a
    few rows a step: read as Python lists)."""
    which = {}
    for k, (a, b) in enumerate(pairs):
        which[a, b] = which[b, a] = k
    body = [int(b) for b in model.geom_bodyid]

    def forces(data) -> np.ndarray:
        out = [0.0] * len(pairs)
        n, ne = data.nefc, data.ne
        if n > ne and which:
            geoms = data.contact.geom.tolist()
            for i, f in zip(data.efc_id[ne:n].tolist(), data.efc_force[ne:n].tolist()):   # row: its contact
                g0, g1 = geoms[i]
                k = which.get((body[g0], body[g1]))
                if k is not None:
                    out[k] += f
        return np.array(out)
    return forces


def reader(model, mech=None):
    """The function :func:`sim.run.simulate.replay` calls at each instant: :func:`settle`, then a flat copy of
    what :class:`Record` holds: the equality rows' forces (always the first rows, as many at every step)
    and each cam's contact force (its rows come and go with the contact)."""
    contacts = contacts_reader(model, cam_pairs(model, mech) if mech is not None else ())

    def read(data):
        settle(model, data)
        eq = data.ne                                        # MuJoCo orders the rows: equalities first
        return np.concatenate([data.cfrc_int.ravel(), data.subtree_com.ravel(), data.site_xpos.ravel(),
                               data.efc_force[:eq], data.actuator_force, data.qacc, data.xaxis.ravel(),
                               contacts(data)])
    return read


def unpack(model, rows: np.ndarray, data, ncams: int = 0) -> Record:
    """Split the stacked reads of :func:`reader` into a :class:`Record`."""
    n = len(rows)
    nb, ns, nu, nv, nj = model.nbody, model.nsite, model.nu, model.nv, model.njnt
    ncam = ncams
    nefc = rows.shape[1] - (nb * 9 + ns * 3 + nu + nv + nj * 3 + ncam)
    sizes = [nb * 6, nb * 3, ns * 3, nefc, nu, nv, nj * 3]
    parts = np.split(rows, np.cumsum(sizes), axis=1)
    types = np.asarray(data.efc_type[:nefc])
    if np.any(types != mujoco.mjtConstraint.mjCNSTR_EQUALITY):
        raise RuntimeError("the model has constraint rows other than equalities and cam contacts (limits)")
    return Record(parts[0].reshape(n, nb, 6), parts[1].reshape(n, nb, 3), parts[2].reshape(n, ns, 3), parts[3],
                  np.asarray(data.efc_id[:nefc]).copy(), parts[4], parts[5], parts[6].reshape(n, nj, 3),
                  parts[7])


def record(built, tr, steps, ends=None) -> Record:
    """MuJoCo's raw force data at the trajectory's steps ``steps`` (indices). ``ends``: evaluations the replay
    carries along (sim.run.simulate.Ends: compare's work balance)."""
    from sim.run.simulate import replay
    model = built.model
    rows, data = replay(built, tr, steps, reader(model, built.mech), ends, sensors=False)   # none read
    return unpack(model, rows, data, len(cam_pairs(model, built.mech)))


def _load_wrench(built, lay: Layout, rec: Record):
    """The external load's force (Fx, Fy) [N] and its point (x, y) at each instant, as the load actuator
    applied it (gear in the world frame times its force)."""
    gear = built.model.actuator_gear[lay.load_actuator][:2]
    force = rec.actuator_force[:, lay.load_actuator]
    p = rec.site_xpos[:, lay.load_site, :2]
    return gear[0] * force, gear[1] * force, p[:, 0], p[:, 1]


def joint_forces(built, rec: Record) -> F.Forces:
    """MuJoCo's answer for every joint of the topology, each drive and gear pair, the shaking force and
    moment, at the recorded instants (SI, world frame; the analytic :class:`~analytic.applications.forces.Forces`
    layout and sign convention)."""
    model, mech = built.model, built.mech
    lay = layout(built)
    topo = mech.topology
    n = rec.cfrc_int.shape[0]
    nj = len(topo.joints)
    Fo = np.full((nj, 2, n), np.nan)
    couples: dict = {}
    lx, ly, px, py = _load_wrench(built, lay, rec)
    drives = {}
    drive_of_joint = {}
    for link, act, dof, sign in lay.drives:
        delivered = rec.actuator_force[:, act] - model.dof_armature[dof] * rec.qacc[:, dof]
        drives[link] = sign * delivered
        k = next(i for i, j in enumerate(topo.joints) if j.input is not None and mech.inputs[j.input].link == link)
        drive_of_joint[k] = drives[link]

    def wrench(child: int):
        """(Fx, Fy, Mz about the world origin) the parent exerts on ``child``, the load taken out."""
        w = rec.cfrc_int[:, child]
        c = rec.subtree_com[:, lay.roots[child]]
        fx, fy, mz = w[:, 3].copy(), w[:, 4].copy(), w[:, 2] + c[:, 0] * w[:, 4] - c[:, 1] * w[:, 3]
        if lay.load_bodies[child]:
            fx -= lx
            fy -= ly
            mz -= px * ly - py * lx
        return fx, fy, mz

    for t in lay.trees:
        fx, fy, mz = wrench(t.child)
        j = topo.joints[t.joint]
        p = rec.site_xpos[:, lay.sites[t.joint]]
        mp = mz - (p[:, 0] * fy - p[:, 1] * fx)                 # about the joint's point
        fx, fy, mp = t.sign * fx, t.sign * fy, t.sign * mp
        if t.slide:
            u = rec.xaxis[:, model.joint(j.name).id, :2]
            if t.joint in drive_of_joint:
                push = drive_of_joint[t.joint]
                fx, fy = fx - push * u[:, 0], fy - push * u[:, 1]
            couples[t.joint] = mp
        Fo[t.joint, 0], Fo[t.joint, 1] = fx, fy
    rows = {}
    for r, eq in enumerate(rec.efc_id):
        rows.setdefault(int(eq), []).append(r)
    for c in lay.closures:
        r = rows[c.eq]
        Fo[c.joint, 0] = c.sign * rec.efc_force[:, r[0]]
        Fo[c.joint, 1] = c.sign * rec.efc_force[:, r[1]]
    cams = iter(range(rec.contact.shape[1]))
    couplings = np.array([rec.efc_force[:, rows[c[1]][0]] if c[0] == "gear" else rec.contact[:, next(cams)]
                          for c in lay.couplings]).reshape(len(lay.couplings), n)
    # what the ground exerts on the moving links: its tree joints' wrenches and the loops closed at the ground
    gx, gy, gm = np.zeros(n), np.zeros(n), np.zeros(n)
    for t in lay.ground_children:
        fx, fy, mz = wrench(t.child)
        gx, gy, gm = gx + fx, gy + fy, gm + mz
    for c in lay.closures:
        if c.ground_body < 0:
            continue
        j = topo.joints[c.joint]
        on_moving = 1.0 if (j.b != GROUND) else -1.0          # +F_ab acts on b; -F_ab on a
        fx, fy = on_moving * Fo[c.joint, 0], on_moving * Fo[c.joint, 1]
        p = rec.site_xpos[:, lay.sites[c.joint]]
        gx, gy, gm = gx + fx, gy + fy, gm + p[:, 0] * fy - p[:, 1] * fx
    shaking = np.array([-gx, -gy, -gm])
    return F.Forces(topo.joints, Fo, couples, drives, couplings, shaking, {})


# ------------------------------------------------------------------------------------------ the answers
def measure(built, tr, steps=None, ends=None) -> F.Forces:
    """MuJoCo's joint forces, drives, gear moments and shaking force of run ``tr`` at its steps ``steps``
    (indices; default every step). ``ends``: see :func:`record`."""
    steps = np.arange(len(tr.t)) if steps is None else np.asarray(steps, dtype=int)
    rec = record(built, tr, steps, ends)
    out = joint_forces(built, rec)
    if built.loadset is not None:          # what the loads anchored to the frame put on it (sim.model.loads)
        from dataclasses import replace
        from sim.model.loads import wrenches
        w = wrenches(built, steps * built.timestep)
        F_ = out.F.copy()
        for k, f in w.Ft.items():           # prismatic friction, applied as body wrenches: the joint's share
            u = rec.xaxis[:, built.model.joint(out.joints[k].name).id, :2]
            F_[k, 0] += f * u[:, 0]
            F_[k, 1] += f * u[:, 1]
        out = replace(out, F=F_, shaking=out.shaking + w.ground.T)
    return out


def simulated_inputs(tr, mech, steps) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(q, qd, qdd) of every input at the steps, shape (N, n_inputs): as the simulation moved them."""
    return tuple(np.column_stack([tr.inputs[getattr(i, a)][steps] for i in mech.inputs])
                 for a in ("q", "qd", "qdd"))


def analytic_at(built, tr, steps, solved=None) -> tuple[F.Forces, tuple, dict]:
    """The analytic kinetostatics at the simulated inputs of ``tr``'s steps, with the compiled model's masses,
    gravity and the load as it was applied (its switch included); and the inputs, and the power balance's
    drives (:func:`analytic.applications.torque.drive_forces`) at the same inputs. ``solved``: the solution at
    every step's simulated inputs and its velocity coefficients (:func:`analytic.cycle.solve_with_coefficients`,
    compare's own), read at the steps instead of solving again."""
    from analytic.applications import torque
    from sim.model import body_inertias
    model, mech = built.model, built.mech
    q, qd, qdd = simulated_inputs(tr, mech, steps)
    inertias = body_inertias(model, mech.links)
    gravity = tuple(float(x) for x in model.opt.gravity[:2])
    load = tuple(float(x) for x in model.actuator("load").gear[:2])
    on = np.asarray(tr.load)[steps]
    sol, coefficients = None, None
    if solved is not None:
        from analytic.cycle import take
        sol, coefficients = take(solved[0], steps), tuple(take(c, steps) for c in solved[1])
    if built.loadset is not None:          # the file's loads: the kinetostatics with them, and their virtual work
        from analytic.cycle import solve_with_coefficients
        from analytic.loads import kinetostatics as K
        if sol is None:                    # one solve at the simulated inputs serves all three
            sol, coefficients = solve_with_coefficients(mech, q, qd, qdd)
        t = np.asarray(tr.t)[steps]
        res = K.solve(mech, q, qd, qdd, t, inertias, built.loadset, gravity, load, on, sol=sol)
        apps = [a for v in res.applications.values() for a in v] + list(res.friction_apps)
        Q = K.generalized(mech, q, res.state, apps, coefficients)
        power = torque.drive_forces(mech, q, qd, qdd, inertias, None, gravity, load, on, sol, coefficients)
        return res.forces, (q, qd, qdd), {k: v - Q[k] for k, v in power.items()}
    an = F.solve(mech, q, qd, qdd, inertias, gravity, load, on, sol=sol)
    power = torque.drive_forces(mech, q, qd, qdd, inertias, None, gravity, load, on, sol, coefficients)
    return an, (q, qd, qdd), power


@dataclass(frozen=True)
class Agreement:
    """MuJoCo's forces against the analytic ones over a run: each joint's largest difference [N] (a prismatic
    pair's couple [N m] too) and as a share of its scale, the drives' three answers, the gear moments and
    the shaking force and moment; the worst share, the tolerance and the verdict."""

    peak: float
    """The peak analytic joint force [N] (the scale of every force)."""
    size: float
    joints: dict
    drives: dict
    couplings: tuple
    shaking: dict
    worst: float
    worst_of: str
    median: float
    """The median over the joints of their largest difference as a share of the peak."""
    tol: float = FORCE_TOL
    identity: float = 0.0
    """The largest Newton-Euler vs power-balance drive difference, as a share of its scale."""
    passed: bool = False
    floor: float = 0.0
    """[N] The least scale (see JOINT_FLOOR); the shares are of max(peak, floor)."""
    window: int = 0
    """Steps each compared force is the mean over (a cam's contact: :func:`cam_agreement`); 0: per step."""

    def as_dict(self) -> dict:
        return {"peak": self.peak, "joints": self.joints, "drives": self.drives, "couplings": list(self.couplings),
                "shaking": self.shaking, "worst": self.worst, "worst_of": self.worst_of, "median": self.median,
                "tol": self.tol, "identity": self.identity, "identity_tol": IDENTITY_TOL, "passed": self.passed,
                "floor": self.floor, "window": self.window}

    def means(self) -> str:
        """'' per step, else what the forces are the means over (a cam's contact)."""
        return f"; means over {self.window} steps, a cam's contact ring" if self.window else ""

    def line(self) -> str:
        """One line for a table: the worst share, where, the median and the tolerance."""
        of = (f"the peak {self.peak:.4g} N" if self.peak >= self.floor else
              f"the floor {self.floor:.4g} N (the reference speed's inertial forces; peak {self.peak:.4g} N)")
        return (f"joint forces vs MuJoCo: worst {self.worst:.2e} of {of} ({self.worst_of}), "
                f"median {self.median:.2e} (tol {self.tol:{'.2g' if self.window else '.0e'}}{self.means()}); drive Newton-Euler vs power balance "
                f"{self.identity:.1e}")


def _err(a, b) -> float:
    d = np.abs(np.asarray(a) - np.asarray(b))
    return float(np.max(np.where(np.isfinite(d), d, np.inf))) if d.size else 0.0


def _take(f: F.Forces, keep) -> F.Forces:
    from dataclasses import replace
    return replace(f, F=f.F[..., keep], couples={k: v[keep] for k, v in f.couples.items()},
                   drives={k: v[keep] for k, v in f.drives.items()}, couplings=f.couplings[..., keep],
                   shaking=f.shaking[..., keep])


REVERSAL_WINDOW = 1e-4
"""[of each friction joint's largest relative rate over the run] Coulomb friction changes sign where a joint
with friction reverses; MuJoCo carries the friction evaluated at the commanded motion (sim.model.loads) and
the analytic answer evaluates it at the simulated one, whose rates differ by the drives' tracking error
(~1e-6 of the rates): at a sample that falls that close to a reversal (an offset press's rod at 90 deg,
sampled every 5 deg; a Hoekens rocker at 1e-6 of its peak rate) the two sides differ by 2 mu r |F| (5e-3 of
the peak). The force check skips the samples where a friction joint's relative rate is within this share of
zero (measured: 1e-6 left one such sample in at 1.2e-4 of the peak)."""


def away_from_reversals(built, tr, steps) -> np.ndarray | None:
    """A mask over ``steps``: False where a joint with friction reverses (REVERSAL_WINDOW); None without
    friction."""
    ls = built.loadset
    if ls is None or not ls.friction:
        return None
    joints = built.mech.topology.joints
    keep = np.ones(len(steps), dtype=bool)
    out = tr.outputs

    def omega(ln):
        return np.zeros(len(tr.t)) if ln == GROUND else np.asarray(out["omega" + ln])
    rates = [omega(joints[k].b) - omega(joints[k].a) for k, _, _ in ls.friction.pins]
    rates += [np.asarray(out["ds" + joints[k].slide]) for k, _ in ls.friction.slides]
    for r in rates:
        scale = float(np.max(np.abs(r)))
        keep &= np.abs(r[steps]) > REVERSAL_WINDOW * scale
    return keep if keep.any() else None


def agreement(mech, mj: F.Forces, an: F.Forces, power: dict, keep=None, floor: float = 0.0,
              tol: float = FORCE_TOL) -> Agreement:
    """Compare MuJoCo's forces ``mj`` with the analytic ``an`` (the same instants) and the power balance's
    drives ``power``; every difference is judged against ``tol`` (FORCE_TOL; a cam's: :func:`cam_agreement`)
    of its scale: the peak joint force, at least ``floor`` [N] (see JOINT_FLOOR). ``keep``: a mask of the
    instants to judge (None: all)."""
    if keep is not None and not keep.all():
        mj, an, power = _take(mj, keep), _take(an, keep), {k: np.asarray(v)[keep] for k, v in power.items()}
    peak = F.peak(an)
    scale = max(peak, floor) if max(peak, floor) > 0 else 1.0
    L = mech.size
    shares, joints = {}, {}
    for k, j in enumerate(an.joints):
        e = float(np.max(np.hypot(*(mj.F[k] - an.F[k])))) if mj.F.shape[-1] else 0.0
        e = e if math.isfinite(e) else math.inf
        rec = {"max": e, "share": e / scale}
        shares[j.name] = e / scale
        if k in an.couples:
            m = _err(mj.couples[k], an.couples[k])
            rec.update({"M_max": m, "M_share": m / (scale * L)})
            shares[f"M_{j.name}"] = m / (scale * L)
        joints[j.name] = rec
    drives, identity = {}, 0.0
    for inp in mech.inputs:
        ne = an.drives[inp.link]
        own = float(np.nanmax(np.abs(ne))) if ne.size else 0.0
        dscale = max(own, scale * (L if inp.angular else 1.0))
        m = _err(mj.drives[inp.link], ne)
        pb = _err(power[inp.link], ne)
        drives[inp.q] = {"peak": own, "mujoco_max": m, "mujoco_share": m / dscale, "power_balance_max": pb,
                         "power_balance_share": pb / dscale}
        shares[f"drive {inp.q}"] = m / dscale
        identity = max(identity, pb / dscale)
    couplings = []
    for k, c in enumerate(mech.topology.couplings[:len(an.couplings)]):
        m = _err(mj.couplings[k], an.couplings[k])
        share = m / scale if c.kind == "cam" else m / (scale * L)     # a cam's: a force; a gear's: a moment
        couplings.append({"max": m, "share": share})
        shares[f"cam {c.link}" if c.kind == "cam" else f"gear pair {k}"] = share
    fs = float(np.max(np.hypot(*(mj.shaking[:2] - an.shaking[:2])))) if an.shaking.shape[-1] else 0.0
    fs = fs if math.isfinite(fs) else math.inf
    ms = _err(mj.shaking[2], an.shaking[2])
    shaking = {"F_max": fs, "F_share": fs / scale, "M_max": ms, "M_share": ms / (scale * L)}
    shares["shaking force"] = fs / scale
    shares["shaking moment"] = ms / (scale * L)
    worst_of = max(shares, key=shares.get)
    worst = shares[worst_of]
    median = float(np.median([joints[j.name]["share"] for j in an.joints])) if an.joints else 0.0
    passed = bool(worst <= tol and identity <= IDENTITY_TOL)
    return Agreement(peak, L, joints, drives, tuple(couplings), shaking, worst, worst_of, median,
                     tol, identity, passed, floor)


CHANGE_WINDOW = np.radians(1.0)
"""[rad of the first input; for a slider, times the size L in m] the force check skips the samples this close
to a change point (compare's ``change_points``): there the aligned links carry a self-stress (the loops'
equations lose rank), so the force along them is not fixed by the equations, and MuJoCo's regularised
solution and the analytic one, continuous through the change point, differ by it as 1/distance. Measured on
a parallelogram (pylinkage's Watt example): 3e-4 of the peak at 0.3 deg, 1.6e-5 beyond 0.5 deg, 1.5e-6
beyond 2 deg; the kinematic outputs are still judged at every sample. Compare judges the drive forces away from
the change points too (sim.run.compare): where the crank lies along the aligned links the self-stress turns it
through the small lever left near them (a pylinkage parallelogram: 1.0x the drive's tolerance 0.2 deg past the
change point, below 0.05x of it beyond 0.5 deg)."""

CHECKED_STEPS = 1000
"""The most steps :func:`check` reads by default (evenly spread, both ends kept): every step of a one-turn run
of nearly any design (the trust benchmark's: median 242, at most 874 steps a revolution), a bounded cost
(50 us a step) for long runs, where the forces' error, smooth over the 0.025 rad steps, is sampled every few."""


def spread(n: int, most: int = CHECKED_STEPS) -> np.ndarray:
    """At most ``most`` step indices of ``n``, evenly spread, the first and the last included."""
    if n <= most:
        return np.arange(n)
    return np.unique(np.round(np.linspace(0, n - 1, most)).astype(int))


def check(built, tr, steps=None, solved=None, ends=None) -> Agreement | None:
    """MuJoCo's joint forces of run ``tr`` against the analytic ones at its simulated inputs (by default every
    step, at most CHECKED_STEPS of them: :func:`spread`; with a cam, their means over its contact's ring
    period: :func:`cam_agreement`); None where statics cannot give the joint forces (a redundant constraint:
    MuJoCo shares such a load by its regulariser, the analytic solve refuses it). ``solved``: see
    :func:`analytic_at`; ``ends``: see :func:`record` (not run where there is no check)."""
    mech = built.mech
    try:
        F.check_determinate(mech)
    except F.StaticsError:
        return None
    steps = spread(len(tr.t)) if steps is None else np.asarray(steps, dtype=int)
    steps = away_from_change_points(mech, tr, steps)
    if has_cam(mech):
        return cam_agreement(built, tr, steps, solved, ends)[2]
    mj, an, _, power = both(built, tr, steps, solved, ends)
    return agreement(mech, mj, an, power, away_from_reversals(built, tr, steps), joint_floor(built))


def has_cam(mech) -> bool:
    return any(c.kind == "cam" for c in mech.topology.couplings)


def windowed(f: F.Forces, at) -> F.Forces:
    """``f`` (at every step of a run) as its means over a cam contact's ring period about the steps ``at``
    (sim.run.cams.window_means)."""
    from dataclasses import replace
    from sim.run.cams import window_means as W
    return replace(f, F=W(f.F, at), couples={k: W(v, at) for k, v in f.couples.items()},
                   drives={k: W(v, at) for k, v in f.drives.items()}, couplings=W(f.couplings, at),
                   shaking=W(f.shaking, at))


def cam_agreement(built, tr, steps, solved=None, ends=None) -> tuple[F.Forces, F.Forces, Agreement]:
    """MuJoCo's forces against the analytic ones for a mechanism with a cam, at the steps ``steps``: each as
    its mean over the contact's ring period (50 steps) about the step. The contact's force is a train of
    impulses over the profile's facets (sim.model.cam_contact; on cam_roller 0 to 1.2x the law's force step
    to step): the law fixes the impulse over a window, not each step. Judged against the contact's own bound
    (sim.run.cams.Compliance.mean_force, the largest over the cams) as a share of the scale, for every joint,
    drive and the shaking force too: each is the contact's force carried on by statics plus the links'
    momentum change over the window, which the same ring bounds. Returns (MuJoCo's, the analytic, the
    agreement), the forces at ``steps``. ``ends``: see :func:`record`."""
    from dataclasses import replace
    from sim.run import cams as C
    mech = built.mech
    every = np.arange(len(tr.t))
    mj_all = measure(built, tr, every, ends)
    an_all, _, power_all = analytic_at(built, tr, every, solved)
    steps = np.asarray(steps, dtype=int)
    mj, an = windowed(mj_all, steps), windowed(an_all, steps)
    power = {k: C.window_means(v, steps) for k, v in power_all.items()}
    k_cam = [k for k, c in enumerate(mech.topology.couplings) if c.kind == "cam"]
    bound = max(C.compliance(built, an_all.couplings[k], e).mean_force for k, e in zip(k_cam, C.elements(mech)))
    floor = joint_floor(built)
    scale = max(F.peak(an), floor)
    tol = bound / scale if scale > 0 else math.inf
    agreed = agreement(mech, mj, an, power, away_from_reversals(built, tr, steps), floor, tol)
    return mj, an, replace(agreed, window=C.window_steps())


def joint_floor(built) -> float:
    """[N] JOINT_FLOOR of the links' inertial force scale at the run's speed or the reference speed, whichever
    is faster, from the compiled model's masses."""
    from sim.model import body_inertias, motion_scale
    from sim.model.timestep import reference_rate
    mech = built.mech
    mass = sum(b.m for b in body_inertias(built.model, mech.links).values())
    return JOINT_FLOOR * mass * mech.size * max(motion_scale(mech), reference_rate(mech)) ** 2


def away_from_change_points(mech, tr, steps: np.ndarray) -> np.ndarray:
    """The ``steps`` whose first input is at least :data:`CHANGE_WINDOW` from every change point of ``mech``
    (all of them where it has none, or where none would be left)."""
    at = sorted(f for e in mech.solving_geometry.elements if e.get("flips") for f in e["flips"]["at"])
    if not at or not mech.inputs:
        return steps
    first = mech.inputs[0]
    q = np.asarray(tr.inputs[first.q])[steps]
    rotary = first.angular
    window = CHANGE_WINDOW if rotary else CHANGE_WINDOW * mech.size
    near = np.zeros(len(steps), dtype=bool)
    for c in at:
        d = q - c
        if rotary:
            d = np.pi - np.mod(np.pi - d, 2 * np.pi)
        near |= np.abs(d) < window
    return steps if near.all() else steps[~near]


def both(built, tr, steps=None, solved=None, ends=None) -> tuple[F.Forces, F.Forces, tuple, dict]:
    """MuJoCo's forces and the analytic ones at the simulated inputs of ``tr``'s ``steps`` (default every
    step), the inputs (q, qd, qdd) and the power balance's drives there: what a plot of them needs.
    ``solved``: see :func:`analytic_at`; ``ends``: see :func:`record`."""
    steps = np.arange(len(tr.t)) if steps is None else np.asarray(steps, dtype=int)
    mj = measure(built, tr, steps, ends)
    an, inputs, power = analytic_at(built, tr, steps, solved)
    return mj, an, inputs, power


# ------------------------------------------------------------------------------- linkage forces --simulate
@dataclass(frozen=True)
class Simulated:
    """A forces run (sim.service.ForceRun) simulated: the model, the trajectory, the steps that fall on the
    run's samples, MuJoCo's forces there, the analytic forces at the simulated inputs and their agreement."""

    built: object
    trajectory: object
    steps: np.ndarray
    t: np.ndarray
    inputs: tuple
    """(q, qd, qdd) as simulated at the steps, shape (N, n_inputs) each."""
    forces: F.Forces
    analytic: F.Forces
    agreement: Agreement


def aligned_timestep(spacing: float, wanted: float) -> float:
    """The largest time step <= ``wanted`` [s] that divides the samples' ``spacing`` [s] a whole number of
    times, so every sample is a step's start."""
    k = max(1, math.ceil(spacing / wanted - 1e-9))
    return spacing / k


def simulate_run(run, settings=None, loads=None, cycle=None) -> Simulated:
    """Simulate ``run``'s mechanism over its run (its revolutions, or its rocking range) with ``loads``, the
    time step chosen for the design (or ``settings.timestep``) shortened to fall on the run's samples, and
    read MuJoCo's forces at those samples (a mechanism with a cam: the step capped by
    sim.model.build.cam_capped, the forces their means over the contact's ring period, :func:`cam_agreement`). ``cycle``: the run's motion solved once
    (:class:`analytic.cycle.Cycle`, made by the service; made here when None), read by the time step's choice
    and the model builder."""
    from dataclasses import replace
    from sim.model import Loads, Settings, build, choose_timestep
    from sim.model.build import cam_capped
    from sim.run.simulate import simulate
    mech = run.mech
    settings = settings or Settings()
    loads = loads or Loads()
    t = np.asarray(run.t)
    revolutions = float(t[-1] / mech.duration(1.0))
    spacing = float(t[1] - t[0])
    if cycle is None:
        from analytic.cycle import Cycle
        cycle = Cycle.of(mech, revolutions)
    wanted = settings.timestep or cam_capped(mech, choose_timestep(mech, revolutions, cycle))
    h = aligned_timestep(spacing, wanted)
    built = build(mech, replace(settings, timestep=h), loads, revolutions, cycle=cycle)
    tr = simulate(built, revolutions)
    k = round(spacing / h)
    steps = np.arange(len(t)) * k
    if steps[-1] >= len(tr.t):
        steps = steps[steps < len(tr.t)]
    if has_cam(mech):                      # the forces as their means over the contact's ring period
        mj, an, agreed = cam_agreement(built, tr, steps)
        return Simulated(built, tr, steps, np.asarray(tr.t)[steps], simulated_inputs(tr, mech, steps), mj, an,
                         agreed)
    mj = measure(built, tr, steps)
    an, inputs, power = analytic_at(built, tr, steps)
    keep = away_from_reversals(built, tr, steps)
    return Simulated(built, tr, steps, np.asarray(tr.t)[steps], inputs, mj, an, agreement(mech, mj, an, power, keep))
