"""The kinetostatics with the file's loads and friction (SPEC "Loads"), and its energy balance.

:func:`solve` evaluates every load's wrenches along the motion, hands them to the Newton-Euler solve
(:func:`analytic.applications.forces.solve`, ``applied``) and, with friction, solves again with the friction
wrenches of the last joint forces until the joint forces stop changing (a fixed point; FRICTION_TOL). A
prismatic pair's reported force then includes its friction force along the guide (SPEC: "joints' Fx, Fy
include friction's share").

:func:`balance` checks the answer by the power balance, sample by sample: the drives' power plus every
load's, gravity's and friction's power equals the rate of change of the kinetic energy, computed from the
mass model and the kinematics alone (nothing from the joint forces). Over the run the same terms give each
load's work, friction's and the dampers' dissipation, and the changes of kinetic and spring energy.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from analytic.applications import forces as F
from analytic.loads.common import GROUND, LoadError, State, power, wanted

FRICTION_TOL = 1e-12
"""[of the peak joint force] The friction fixed point stops when no joint force changes by more than this
between two solves: the rounding of the solve itself is ~1e-15 of the peak."""
FRICTION_ITERATIONS = 200
"""The most solves: the iteration contracts by about mu r / (the lever arms), 0.1 or less in machines, so
a few dozen reach FRICTION_TOL; one that does not is a joint that locks (a self-locking mechanism)."""


@dataclass(frozen=True)
class Loaded:
    """The kinetostatics with loads: the joint forces (prismatic friction included), the state the loads
    read, each load's wrenches by name, friction's moments ``Mf`` (pin joint index -> N m on b by a) and
    forces ``Ft`` (prismatic joint index -> N along the guide on the block), and the solves it took."""

    forces: F.Forces
    state: State
    applications: dict
    Mf: dict
    Ft: dict
    friction_apps: tuple
    iterations: int


def full_wanted(mech) -> list[str]:
    return sorted(set(F.wanted(mech)) | set(wanted(mech)) | {"vx" + p for p in mech.points}
                  | {"vy" + p for p in mech.points})


def solve(mech, q, qd, qdd, t, inertias: dict, loadset, gravity=(0.0, 0.0), force=(0.0, 0.0), force_on=1.0,
          sol=None, extra_apps=()) -> Loaded:
    """Joint forces of ``mech`` along the motion with ``loadset`` (:class:`analytic.loads.LoadSet`), besides
    gravity and the shorthand ``force`` on the output point; ``sol`` with :func:`full_wanted`'s outputs (solved
    here when None)."""
    from analytic.loads import scales
    if sol is None:
        sol = mech.solve(q, qd, qdd, outputs=full_wanted(mech))
    n = int(np.size(sol["x" + mech.points[0]]))
    sol = {k: np.reshape(np.asarray(sol[k]), n) for k in full_wanted(mech)}
    state = State(mech, sol, q, qd, t)
    variables = state.variables(scales(mech.definition, mech.parameters))
    apps = {}
    for ld in loadset.loads if loadset else ():
        try:
            apps[ld.name] = ld.applications(state, variables)
        except LoadError:
            raise
        except ValueError as exc:
            raise LoadError(f"load {ld.name}: {exc}") from None
    given = [a for v in apps.values() for a in v] + list(extra_apps)
    result = F.solve(mech, q, qd, qdd, inertias, gravity, force, force_on, sol=sol, applied=given)
    fr = loadset.friction if loadset else None
    Mf, Ft, fapps, it = {}, {}, [], 1
    if fr:
        scale = max(F.peak(result), 1e-300)
        for it in range(2, FRICTION_ITERATIONS + 2):
            fapps, Mf, Ft = fr.loads(state, result.joints, result.F)
            new = F.solve(mech, q, qd, qdd, inertias, gravity, force, force_on, sol=sol, applied=given + fapps)
            change = float(np.nanmax(np.abs(new.F - result.F))) if new.F.size else 0.0
            result = new
            if change <= FRICTION_TOL * scale:
                break
        else:
            raise LoadError(f"[friction]: the joint forces do not settle after {FRICTION_ITERATIONS} solves (last "
                            f"change {change:.3g} N): the friction locks the {mech.name} (mu x pin_radius too large "
                            f"for its lever arms); lower mu or pin_radius")
        fapps, Mf, Ft = fr.loads(state, result.joints, result.F)
        if Ft:
            Fo = result.F.copy()
            for k, f in Ft.items():
                _, _, c, s, _ = state.frame(result.joints[k].b)
                Fo[k, 0] += f * c
                Fo[k, 1] += f * s
            result = replace(result, F=Fo)
    return Loaded(result, state, apps, Mf, Ft, tuple(fapps), it)


# ------------------------------------------------------------------------------------- energy balance
def kinetic(mech, sol, inertias: dict):
    """(T [J], dT/dt [W], gravity's power per unit g: (sum m vGx, sum m vGy) [kg m/s]) over the samples."""
    n = int(np.size(sol["x" + mech.points[0]]))
    T, dT, mvx, mvy = (np.zeros(n) for _ in range(4))
    for ln, b in inertias.items():
        o = mech.link_origins[ln]
        c, s = sol["cos" + ln], sol["sin" + ln]
        rx, ry = b.cx * c - b.cy * s, b.cx * s + b.cy * c
        w, a = sol["omega" + ln], sol["alpha" + ln]
        vx, vy = sol["vx" + o] - w * ry, sol["vy" + o] + w * rx
        ax, ay = sol["ax" + o] - a * ry - w * w * rx, sol["ay" + o] + a * rx - w * w * ry
        T = T + 0.5 * b.m * (vx * vx + vy * vy) + 0.5 * b.I * w * w
        dT = dT + b.m * (ax * vx + ay * vy) + b.I * a * w
        mvx, mvy = mvx + b.m * vx, mvy + b.m * vy
    return T, dT, (mvx, mvy)


def _trapz(y, t) -> float:
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(t))) if len(t) > 1 else 0.0


def switched(ld) -> bool:
    """Whether load ``ld`` acts over part of the first input's range only (an ``active`` window)."""
    law = getattr(ld, "law", None)
    return law is not None and law.active is not None


def switched_work(mech, st: State, apps, law) -> float:
    """The work [J] over the run of wrenches ``apps`` (one load's) whose law ``law`` acts only inside its
    ``active`` window, exact for a constant load: over each interval between samples, the mean force times
    its point's displacement and the mean couple times its link's turn (a point fixed on its link: exact
    where the load is constant); where the window opens or closes inside an interval, the load's value on
    its acting side times the displacement up to the edge, the pose at the edge solved there (the other
    inputs interpolated linearly). The trapezoid of the power instead counts half an interval of the load at
    each edge (a -1.5 N m brake over half a turn: -1.16956 J against the exact -1.18437 J)."""
    n = st.n
    if n < 2:
        return 0.0
    q = st.q
    on = law.on(q[:, 0])
    cut = np.flatnonzero(on[:-1] != on[1:])
    edge = law.crossing(q[cut, 0], q[cut + 1, 0]) if len(cut) else np.zeros(0)
    found = np.isfinite(edge)
    cut, edge = cut[found], edge[found]
    pose = None
    if len(cut):
        f = (edge - q[cut, 0]) / np.where(q[cut + 1, 0] != q[cut, 0], q[cut + 1, 0] - q[cut, 0], 1.0)
        qs = q[cut] + f[:, None] * (q[cut + 1] - q[cut])
        qs[:, 0] = edge
        links = sorted({a.link for a in apps if a.link != GROUND})
        outs = sorted({c + mech.link_origins[ln] for ln in links for c in ("x", "y")}
                      | {c + ln for ln in links for c in ("cos", "sin")})
        sol = mech.solve(qs, np.zeros_like(qs), np.zeros_like(qs), outputs=outs)
        pose = {k: np.reshape(np.asarray(sol[k], dtype=float), len(cut)) for k in outs}
    work = 0.0
    for a in apps:
        if a.link == GROUND:
            continue
        fx, fy, px, py, m = (np.broadcast_to(np.asarray(x, dtype=float), (n,)) for x in
                             (a.fx, a.fy, a.px, a.py, a.couple))
        th = st.angle(a.link)
        dth = np.angle(np.exp(1j * np.diff(th)))                # a link's turn between samples, wrapped
        w = (0.5 * (fx[1:] + fx[:-1]) * np.diff(px) + 0.5 * (fy[1:] + fy[:-1]) * np.diff(py)
             + 0.5 * (m[1:] + m[:-1]) * dth)
        if pose is not None:
            ox, oy, c, s, _ = st.frame(a.link)
            k = np.where(on[cut], cut, cut + 1)                 # the sample on the acting side
            u = (px[k] - ox[k]) * c[k] + (py[k] - oy[k]) * s[k]      # the point in its link's frame
            v = -(px[k] - ox[k]) * s[k] + (py[k] - oy[k]) * c[k]
            o = mech.link_origins[a.link]
            cs, ss = pose["cos" + a.link], pose["sin" + a.link]
            xs, ys = pose["x" + o] + u * cs - v * ss, pose["y" + o] + u * ss + v * cs
            ths = np.arctan2(ss, cs)
            sign = np.where(on[cut], 1.0, -1.0)                 # the acting part: sample to edge, or edge to sample
            w[cut] = sign * (fx[k] * (xs - px[k]) + fy[k] * (ys - py[k]) + m[k] * np.angle(np.exp(1j * (ths - th[k]))))
        work += float(np.sum(w))
    return work


def balance(mech, loaded: Loaded, loadset, inertias: dict, gravity=(0.0, 0.0), cycles: float = 1.0,
            force_power=None) -> dict:
    """The energy balance of a run (per cycle: the run's totals divided by ``cycles``) and the power balance's
    worst residual; each load's ``work_per_cycle`` (J, positive where it drives the mechanism).

    drive_work + loads_work = friction_dissipated + damper_dissipated + kinetic_change + spring_change +
    residual, with loads_work the work of the forces, torques, pressures, gravity and the shorthand force
    (trapezoidal rule over the samples; a load with an ``active`` window by :func:`switched_work`, exact for
    a constant load, and the drives' work across its jumps to match), a spring's energy change exact and a
    damper's dissipation integrated from its rate; ``power_residual`` the largest |drive power + loads' power + friction's -
    dT/dt| over the samples as a share of the largest of them (exact but for rounding)."""
    st, f, t = loaded.state, loaded.forces, loaded.state.t
    T, dT, (mvx, mvy) = kinetic(mech, st.sol, inertias)
    p_drive = np.zeros(st.n)
    for k, inp in enumerate(mech.inputs):
        p_drive = p_drive + f.drives[inp.link] * st.qd[:, k]
    p_gravity = gravity[0] * mvx + gravity[1] * mvy
    works, p_loads, spring_change, damper, external = {}, np.zeros(st.n), 0.0, 0.0, 0.0
    p_switched, W_switched = np.zeros(st.n), 0.0
    for ld in loadset.loads if loadset else ():
        p = power(st, loaded.applications[ld.name])
        p_loads = p_loads + p
        e = ld.energy(st)
        d = ld.dissipation(st) if e is None else None
        if switched(ld):                                     # exact at its window's edges (switched_work)
            w = switched_work(mech, st, loaded.applications[ld.name], ld.law)
            external += w
            p_switched, W_switched = p_switched + p, W_switched + w
        elif e is not None:
            change = float(e[-1]) - float(e[0])
            w = -change                                          # exact: minus the change of its energy
            spring_change += change
        elif d is not None:
            w = -_trapz(d, t)
            damper += -w
        else:
            w = _trapz(p, t)
            external += w
        works[ld.name] = w / cycles
    p_friction = power(st, loaded.friction_apps)
    if force_power is not None:
        p_loads = p_loads + force_power
    residual_p = p_drive + p_loads + p_gravity + p_friction - dT
    scale = max(float(np.max(np.abs(p_drive))), float(np.max(np.abs(dT))), float(np.max(np.abs(p_loads))),
                float(np.max(np.abs(p_gravity))), 1e-300)
    # the drives' power jumps where a switched load does, by minus its jump: their sum is integrated, the
    # switched loads' exact work taken out (the trapezoid across a jump would count half an interval of it)
    W_drive = _trapz(p_drive + p_switched, t) - W_switched
    W_gravity = _trapz(p_gravity, t)
    W_force = _trapz(force_power, t) if force_power is not None else 0.0
    friction = -_trapz(p_friction, t)
    kinetic_change = float(T[-1] - T[0])
    loads_work = external + W_gravity + W_force
    residual = W_drive + loads_work - friction - damper - kinetic_change - spring_change
    c = cycles
    return {"work_per_cycle": works, "gravity_work_per_cycle": W_gravity / c, "force_work_per_cycle": W_force / c,
            "friction_dissipated_per_cycle": friction / c,
            "energy": {"drive_work": W_drive / c, "loads_work": loads_work / c, "friction_dissipated": friction / c,
                       "damper_dissipated": damper / c, "kinetic_change": kinetic_change / c,
                       "spring_change": spring_change / c, "residual": residual / c, "per": "cycle", "cycles": c},
            "power_residual": float(np.max(np.abs(residual_p))) / scale}


def generalized(mech, q, state: State, apps, coefficients=None) -> dict:
    """The generalized force [N m per rad or N] of wrenches ``apps`` on each input: sum F . dv_P/dqdot_j +
    M domega/dqdot_j, with the velocity coefficients of the solver at unit input rate (virtual work):
    ``coefficients``, one solution per input at ``q`` (an analytic.cycle.Cycle's), or solved here."""
    k = len(mech.inputs)
    q = np.asarray(q, dtype=float).reshape(state.n, k)
    out = {}
    for j, inp in enumerate(mech.inputs):
        unit = np.zeros_like(q)
        unit[:, j] = 1.0
        coeff = coefficients[j] if coefficients is not None else mech.solve(
            q, unit, 0.0, outputs=[c + p for p in mech.points for c in ("vx", "vy")] + ["omega" + ln for ln in mech.links])
        Q = np.zeros(state.n)
        for a in apps:
            if a.link == "ground":
                continue
            o = mech.link_origins[a.link]
            ox, oy = state.xy(o)
            w = np.asarray(coeff["omega" + a.link]).reshape(state.n)
            vx = np.asarray(coeff["vx" + o]).reshape(state.n) - w * (a.py - oy)
            vy = np.asarray(coeff["vy" + o]).reshape(state.n) + w * (a.px - ox)
            Q = Q + a.fx * vx + a.fy * vy + a.couple * w
        out[inp.link] = Q
    return out
