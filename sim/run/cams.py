"""A mechanism's cams in its MuJoCo run (SPEC "Cams and followers"): the contact's readings (separation, for
``simulate``), the tolerance ``compare`` judges the follower's columns by (the contact's compliance), and the
cam's speed of ``simulate --speed``. The contact itself is :mod:`sim.model.cam_contact`."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic import ParameterError

RING_STATICS = 50.0
"""The follower's error against the law, in static penetrations (sim.model.cam_contact.penetration at the
law's largest contact force): the stiff contact chatters over the profile's facets and rings, measured
5-25x the static penetration in the contact's own sweeps (tests/test_cam_contact.py); 50 covers them twice."""


def impulse_mean(x: np.ndarray) -> np.ndarray:
    """The moving mean of ``x`` over the contact's ring period (2 pi tau, tau = CONTACT_STEPS steps: 50 steps):
    the contact's force is a train of impulses over the profile's facets, the law fixes their sum over a
    window, not each step (cam_roller's drive torque: 98 % of its peak off per step, 9 % over this window)."""
    from sim.model.cam_contact import CONTACT_STEPS
    w = int(round(2 * math.pi * CONTACT_STEPS))
    x = np.asarray(x, dtype=float)
    return np.convolve(x, np.ones(w) / w, "valid") if len(x) > w else x


def window_steps() -> int:
    """The steps of the contact's ring period 2 pi tau (tau = CONTACT_STEPS = 8 steps: a window of 50 steps),
    over which the contact's impulses are summed (:func:`impulse_mean`, :func:`window_means`)."""
    from sim.model.cam_contact import CONTACT_STEPS
    return int(round(2 * math.pi * CONTACT_STEPS))


def window_means(x: np.ndarray, at: np.ndarray, w: int | None = None) -> np.ndarray:
    """The means of ``x`` (last axis: every step of a run) over windows of ``w`` steps (default
    :func:`window_steps`) centred on the steps ``at``, slid inside the run where a centred one would leave
    it (each mean over w steps); ``x`` shorter than w: its mean."""
    x = np.asarray(x, dtype=float)
    n = x.shape[-1]
    w = window_steps() if w is None else w
    at = np.asarray(at, dtype=int)
    if n <= w:
        return np.repeat(np.mean(x, axis=-1, keepdims=True), len(at), axis=-1)
    cs = np.concatenate([np.zeros(x.shape[:-1] + (1,)), np.cumsum(x, axis=-1)], axis=-1)
    start = np.clip(at - (w - 1) // 2, 0, n - w)
    return (cs[..., start + w] - cs[..., start]) / w


def elements(mech) -> list[dict]:
    """The mechanism's cam elements (none: [])."""
    return [e for e in mech.geometry.elements if e["kind"] == "cam"]


@dataclass(frozen=True)
class Compliance:
    """A cam's contact as built: its largest analytic contact force ``n_max`` [N] over the run, the follower's
    effective mass ``m_eff`` [kg] at the trace point, the time step ``h`` [s], the contact's time constant
    ``tau`` [s], the profile's chord sagitta ``sag`` [m], the arm's length (oscillating; 0 translating) and
    ``lever``: the largest moment arm of the contact normal about the cam's pivot [m]."""

    n_max: float
    m_eff: float
    h: float
    tau: float
    sag: float
    arm: float
    lever: float

    @property
    def position(self) -> float:
        """[m] the trace point's tolerance: RING_STATICS static penetrations plus the chord's sagitta."""
        from sim.model.cam_contact import penetration
        return RING_STATICS * float(penetration(self.n_max, self.m_eff, self.h)) + self.sag

    @property
    def mean_force(self) -> float:
        """[N] the contact force's mean over the ring period W = 2 pi tau against the law's: over W the contact
        gives the follower the impulse of its law plus m_eff times the change of its speed error, and the
        follower ringing about the law by at most T = :attr:`position` at the contact's rate 1/tau is off in
        speed by at most T / tau, so the mean is off by at most 2 m_eff T / (tau W) = m_eff T / (pi tau^2):
        RING_STATICS (1 - d) d / pi = 0.16 of N_max plus the sagitta's share (the static penetration's
        (1 - d) / d (d tau)^2 N / m_eff)."""
        return self.m_eff * self.position / (math.pi * self.tau ** 2)


def compliance(built, solved_n: np.ndarray, e: dict) -> Compliance:
    """The contact of cam ``e`` in ``built`` with the analytic contact force ``solved_n`` [N] over the run."""
    from analytic import cams as C
    from sim.model import body_inertias
    from sim.model.cam_contact import CONTACT_STEPS, collision_profile
    geo = C.build(e["setup"])
    link = e["links"][0]
    b = body_inertias(built.model, [link])[link]
    h = built.timestep
    if geo.setup.motion == "translating":
        m_eff, arm = b.m, 0.0
    else:
        # J about the arm pivot / L^2; the links the arm drives add to it: leaving them out overstates the
        # penetration (a looser, not a wrong, bound)
        arm = float(e["arm"])
        m_eff = (b.I + b.m * (b.cx ** 2 + b.cy ** 2)) / arm ** 2
    P = collision_profile(C.plate(e, geo))               # the outline MuJoCo collides
    seg = float(np.max(np.hypot(*(np.roll(P, -1, axis=0) - P).T)))
    rho = np.abs(np.asarray(geo.rho))
    rho = float(np.min(rho[rho > 0])) if np.any(rho > 0) else math.inf
    sag = seg * seg / (8 * rho)                          # a chord of length s on a circle of radius rho
    K, n = np.asarray(geo.contact_cam), np.asarray(geo.normal_cam)
    lever = float(np.max(np.abs(K[:, 0] * n[:, 1] - K[:, 1] * n[:, 0])))
    return Compliance(float(np.max(np.abs(solved_n))), float(m_eff), h, CONTACT_STEPS * h, sag, arm, lever)


def tolerances(built, steps=None) -> dict[str, float] | None:
    """Compare's tolerance floors for a mechanism with cams, by quantity kind (position [m], angle [rad],
    velocity, ang_velocity, acceleration, ang_acceleration, force [N or N m]); None without a cam.

    The follower rides a compliant contact (sim.model.cam_contact): its trace point lags the law by up to
    T = RING_STATICS penetrations + the chord's sagitta, and rings about it with the contact's time constant
    tau (critically damped), so its speed is off by up to T / tau; an arm turns by T / L; every other moving point follows the
    followers within the size times that. Its acceleration feels the contact's force swinging by up to
    2 N_max step to step (chatter over the facets), over m_eff. The drive torque is judged by its mean over
    the ring period (compare's impulse_mean): the contact force's mean is within Compliance.mean_force of the
    law's, at the normal's largest moment arm about the cam's pivot (measured 4-6x inside it on the four
    library cams; the step-to-step swing 2 N_max at that arm, used before, was 70x the measured error)."""
    cams = elements(built.mech)
    if not cams:
        return None
    L = built.mech.size
    out = dict.fromkeys(("position", "angle", "velocity", "ang_velocity", "acceleration", "ang_acceleration",
                         "force"), 0.0)
    an = analytic_contact(built, steps)
    for k, e in enumerate(cams):
        if np.min(an[k]) <= 0:
            raise ParameterError(
                f"{built.mech.definition.source}: cam {e['name']}: at this speed the analytic contact force falls to "
                f"{np.min(an[k]):.3g} N (the follower leaves the cam: above its jump speed, `linkage forces` gives "
                f"it); compare checks the follower against the law below it: slow the cam, or add a return spring "
                f"([[loads]]); `linkage simulate --speed W` shows the jump")
        c = compliance(built, an[k], e)
        T = c.position
        ang = T / c.arm if c.arm > 0 else T / L
        pos = max(T, ang * L)
        out["position"] = max(out["position"], pos)
        out["angle"] = max(out["angle"], ang)
        out["velocity"] = max(out["velocity"], pos / c.tau)
        out["ang_velocity"] = max(out["ang_velocity"], ang / c.tau)
        # the contact's force swings between 0 (a micro-flight over a facet) and ~1.2x the law's from step to
        # step: the follower's acceleration is then off by up to 2 N_max / m_eff (at the trace point)
        swing = 2 * c.n_max / c.m_eff                                   # at the trace point [m/s^2]
        ang_acc = swing / (c.arm if c.arm > 0 else L)
        out["acceleration"] = max(out["acceleration"], pos / c.tau ** 2, max(swing, ang_acc * L))
        out["ang_acceleration"] = max(out["ang_acceleration"], ang / c.tau ** 2, ang_acc)
        # the drive's torque is judged by its mean over the ring period (impulse_mean): the contact force's
        # mean is within Compliance.mean_force of the law's, at the normal's largest arm about the cam's pivot
        out["force"] = max(out["force"], c.mean_force * c.lever)
    return out


def analytic_contact(built, steps=None) -> list[np.ndarray]:
    """The analytic contact force [N] of each cam over one cycle of the run's motion (CONTACT_SAMPLES + 1 samples,
    :func:`_one_cycle`: the run's cycle's own where it is one period), with the file's loads, gravity and the
    compiled model's masses (:func:`analytic.loads.kinetostatics.solve`)."""
    from analytic.loads import kinetostatics as K
    from sim.model import body_inertias
    from sim.service import loads as L
    mech = built.mech
    t, q, qd, qdd, sol = _one_cycle(built)
    loadset = built.loadset if built.loadset is not None else L.loadset(mech, ())
    gravity = tuple(float(x) for x in built.model.opt.gravity[:2])
    res = K.solve(mech, q, qd, qdd, t, body_inertias(built.model, mech.links), loadset, gravity, sol=sol).forces
    return [np.asarray(res.couplings[k]) for k, c in enumerate(mech.topology.couplings) if c.kind == "cam"]


CONTACT_SAMPLES = 720
"""Intervals of one cycle of the motion at which :func:`analytic_contact` weighs the contact force."""


def _one_cycle(built):
    """(t, q, qd, qdd, solution) at CONTACT_SAMPLES + 1 instants evenly over one cycle of the run's motion: every
    (SAMPLES / CONTACT_SAMPLES)-th dense sample of the cycle the model was built from where it is one period
    (analytic.cycle.Cycle, kept in ``built.memo``), else the instants' inputs and None (solved by the caller)."""
    from analytic.cycle import SAMPLES, periodic, take
    mech = built.mech
    cycle = (getattr(built, "memo", None) or {}).get("cycle")
    if (cycle is not None and cycle.mech is mech and periodic(mech) and len(cycle.dense) == SAMPLES + 1
            and SAMPLES % CONTACT_SAMPLES == 0):
        rows = cycle.dense[::SAMPLES // CONTACT_SAMPLES]
        return cycle.t[rows], cycle.q[rows], cycle.qd[rows], cycle.qdd[rows], take(cycle.solution, rows)
    t = np.linspace(0.0, mech.duration(1.0), CONTACT_SAMPLES + 1)
    return (t, *mech.drive(t), None)


def separations(built, sens: np.ndarray, theta: dict[str, np.ndarray]) -> dict:
    """SPEC's ``"cams": {name: {"separated", "first_at"}}`` of a run: from each cam's contact sensors
    (sim.model.cam_contact.readings) and its cam link's angle ``theta[link]`` [rad] at each step; first_at
    in [0, 2 pi) or None."""
    from sim.model.cam_contact import SEPARATION_GAP, readings, separation
    from analytic import cams as C
    out = {}
    for e in elements(built.mech):
        size = float(np.max(np.hypot(*np.asarray(C.build(e["setup"]).profile).T)))
        force, gap = readings(built.model, sens, e["name"], 4 * SEPARATION_GAP * size)
        th = np.unwrap(np.asarray(theta[e["cam"]]))
        sep, first = separation(th, force, gap, SEPARATION_GAP * size)
        out[e["name"]] = {"separated": bool(sep), "first_at": None if first is None else float(first % (2 * math.pi))}
    return out


def speed_sets(mech, speed: float) -> dict[str, str]:
    """``--speed W``: the ``--set`` items that turn the (first) cam at W rad/s, every input's speed scaled by
    the same factor (the cam link's speed at the start over W). Refused in one line without a cam, or where
    an input's speed is not a parameter."""
    cams = elements(mech)
    if not cams:
        raise ParameterError(f"{mech.definition.source}: --speed sets a cam's speed; this mechanism has no cam "
                             f"(use --set on its inputs' speeds)")
    if not (math.isfinite(speed) and speed > 0):
        raise ParameterError(f"--speed {speed!r}: give the cam's speed in rad/s, > 0")
    from analytic.cycle import Cycle
    (_, _, _), sol = Cycle.of(mech, 1.0).at_start()
    w = abs(float(np.asarray(sol["omega" + cams[0]["cam"]])[0]))
    if not w > 0:
        raise ParameterError(f"{mech.definition.source}: the cam's link {cams[0]['cam']} stands still at the start; "
                             f"--speed cannot scale it")
    sets = {}
    for inp, el in zip(mech.inputs, mech.definition.inputs):
        name = el.fields.get("omega")
        if not isinstance(name, str) or name not in mech.definition.parameters:
            raise ParameterError(f"{mech.definition.source}: {el.where}: its 'omega' is not a parameter; --speed "
                                 f"scales the inputs' speed parameters (give omega = \"omega1\" under [parameters])")
        sets[name] = repr(inp.motion.rate * speed / w)
    return sets


def check_speed(before, after, speed: float, revolutions: float = 1.0) -> None:
    """``--speed W`` refused in one line naming the option where it alone makes the design too fast to step
    (:func:`sim.model.timestep.choose_timestep` refuses ``after``, the mechanism at W, and not ``before``, the
    file's own): otherwise the refusal would tell the user to lower a parameter the option set."""
    from sim.model.timestep import choose_timestep
    try:
        choose_timestep(after, revolutions)
    except ParameterError:
        try:
            choose_timestep(before, revolutions)
        except ParameterError:
            return                                   # the file's own problem: its own refusal says it
        raise ParameterError(f"{before.definition.source}: --speed {speed:g}: the cam turns too fast to simulate "
                             f"accurately (the time step it needs is below the simulator's least); give a lower "
                             f"--speed") from None
