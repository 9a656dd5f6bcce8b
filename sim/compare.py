"""Cross-validation: the analytic solution evaluated at the *simulated* drive inputs against the outputs
the MuJoCo model measures. Evaluating at the simulated crank angle, speed and acceleration keeps the
velocity servo's lag out of the kinematic error; the servo's speed ripple is reported on its own.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic import MECHANISMS
from .params import OUTPUT_POINT
from .simulate import Trajectory, energies

# (unit, kind) of every SPEC output; kind picks the tolerance.
UNITS = {
    "phi2": "rad", "phi3": "rad", "phi4": "rad", "theta3": "rad", "mu": "rad",
    "omega2": "rad/s", "omega3": "rad/s", "omega4": "rad/s",
    "alpha2": "rad/s^2", "alpha3": "rad/s^2", "alpha4": "rad/s^2",
    "s": "m", "S": "m", "xC": "m", "xE": "m", "yE": "m", "xP": "m", "yP": "m",
    "ds": "m/s", "dS": "m/s", "vxC": "m/s", "vxE": "m/s", "vyE": "m/s", "vxP": "m/s", "vyP": "m/s",
    "dds": "m/s^2", "ddS": "m/s^2", "axC": "m/s^2", "axE": "m/s^2", "ayE": "m/s^2", "axP": "m/s^2",
    "ayP": "m/s^2", "tau1": "N m", "tau2": "N m", "tau4": "N m",
}
ANGLES = {"phi2", "phi3", "phi4", "theta3"}

POSITION_TOL = 1e-6
"""[rad or m] RK4's truncation error over one revolution plus the loop violation (~1e-9 m) it carries."""
VELOCITY_TOL = 1e-4
"""[rad/s or m/s] the constraint's velocity stabilisation (time constant a few steps) leaves ~1e-6."""
ACCELERATION_REL_TOL = 1e-3
"""[of the peak] soft constraints (impedance 0.9999) leave ~1e-4 of the constraint acceleration unforced."""
LOOP_TOL = 1e-7
"""[m] the loops' position drift under the stiff constraint's stabilisation."""
TORQUE_REL_TOL = 5e-3
"""[of the peak analytic torque] the servo force is read at each step's start, where the constraint
solver's residual (~1e-8 of the constraint force after the regulariser scaling) is all that separates it
from the inverse dynamics."""
WORK_TOL = 1e-3
"""[of the kinetic-energy swing] Simpson quadrature of the drive power over 2 ms steps (error ~(h w)^4)
and the constraint forces' work on a loop open by ~1e-9 m."""


def tolerance(name: str, peak: float) -> float:
    unit = UNITS[name]
    if unit == "N m":
        return TORQUE_REL_TOL * peak
    if unit.endswith("^2"):
        return ACCELERATION_REL_TOL * peak
    if unit.endswith("/s"):
        return VELOCITY_TOL
    return POSITION_TOL


@dataclass(frozen=True)
class Comparison:
    """Per-output error statistics and the run's verdict."""

    trajectory: Trajectory
    analytic: object
    errors: dict[str, dict]
    speed_ripple: float
    max_loop_violation: float
    torques: dict[str, np.ndarray]
    work_balance: float
    passed: bool

    def as_dict(self) -> dict:
        tr = self.trajectory
        return {"mechanism": tr.name, "timestep": tr.timestep, "integrator": tr.integrator,
                "revolutions": None, "steps": tr.steps, "cpu_seconds": tr.cpu_seconds,
                "errors": self.errors, "speed_ripple": self.speed_ripple,
                "max_loop_violation": self.max_loop_violation, "loop_tol": LOOP_TOL,
                "work_balance": self.work_balance, "work_tol": WORK_TOL, "passed": self.passed}


def analytic_at(tr: Trajectory, mech):
    """The analytic state at the simulated drive inputs."""
    module = MECHANISMS[tr.name]
    i = tr.inputs
    if tr.name == "fivebar":
        return module.solve(mech, i["phi2"], i["phi4"], i["omega2"], i["omega4"], i["alpha2"], i["alpha4"])
    return module.solve(mech, i["phi1"], i["omega1"], i["alpha1"])


def analytic_torques(tr: Trajectory, built, mech=None) -> dict[str, np.ndarray]:
    """Inverse-dynamics torques at the simulated state, with the compiled model's inertias, armature,
    gravity and the load as actually applied."""
    from analytic.dynamics import INPUTS, torques
    from .model import body_inertias
    model = built.model
    mech = mech or built.mech
    names = [model.body(i).name for i in range(1, model.nbody)]
    inputs = INPUTS[tr.name]
    joint = {"fourbar": {"1": "A"}, "sixbar": {"1": "O2"}, "fivebar": {"2": "A", "4": "D"}}[tr.name]
    armature = {j: float(model.dof_armature[model.joint(joint[j]).dofadr[0]]) for j in inputs}
    gear = model.actuator("load").gear[:2]
    return torques(tr.name, mech, {j: tr.inputs[f"phi{j}"] for j in inputs},
                   {j: tr.inputs[f"omega{j}"] for j in inputs}, {j: tr.inputs[f"alpha{j}"] for j in inputs},
                   body_inertias(model, names), armature, tuple(model.opt.gravity[:2]), tuple(gear),
                   tr.load)


def work_balance(tr: Trajectory, built) -> float:
    """max over the run of |work done on the mechanism - change of its energy|, as a fraction of the
    kinetic-energy swing.

    Energy: MuJoCo's kinetic + potential energy at each recorded state. Work of each crank servo over a
    step, during which its command c is constant: the integral of tau omega = kv (c - omega) omega, with
    omega(t) the cubic through the step's end speeds and accelerations (4-point Gauss, exact for that
    polynomial). Where a control changes between steps (the load switches, or an accelerating or rocking
    crank's command moves on) the recorded end acceleration belongs to the next step's controls, so the
    end slope under the step's own controls is found by mj_forward at the step's end state. Work of the
    load: its constant force times the output point's displacement over each step where it is on (exact).
    """
    model = built.model
    h = tr.t[1] - tr.t[0]
    commands = [tr.inputs[key] + tr.forces["tau" + key[5:]] / model.actuator(name).gainprm[0]
                for name, key in zip(built.cranks, tr.commanded)]          # tau = kv (c - omega)
    changed = np.abs(np.diff(tr.load)) > 0
    for c in commands:
        changed |= np.abs(np.diff(c)) > 1e-12 * np.max(np.abs(c))
    ends = _end_accelerations(built, tr, np.flatnonzero(changed), commands)
    work_steps = np.zeros(len(tr.t) - 1)
    nodes, weights = np.polynomial.legendre.leggauss(4)
    u = 0.5 * (nodes + 1.0)
    h00, h10 = 2 * u ** 3 - 3 * u ** 2 + 1, u ** 3 - 2 * u ** 2 + u
    h01, h11 = -2 * u ** 3 + 3 * u ** 2, u ** 3 - u ** 2
    for i, (name, key) in enumerate(zip(built.cranks, tr.commanded)):
        kv = model.actuator(name).gainprm[0]
        w, a, c = tr.inputs[key], tr.inputs["alpha" + key[5:]], commands[i]
        a1 = a[1:].copy()
        for k, acc in ends.items():
            a1[k] = acc[i]
        a0 = a[:-1]
        ws = (np.outer(w[:-1], h00) + np.outer(h * a0, h10) + np.outer(w[1:], h01) + np.outer(h * a1, h11))
        power = kv * (c[:-1, None] - ws) * ws
        work_steps += 0.5 * h * power @ weights
    gear = model.actuator("load").gear[:2]
    if np.any(gear):
        xk, yk = OUTPUT_POINT[tr.name]
        dx = np.diff(tr.outputs[xk])
        dy = np.diff(tr.outputs[yk]) if yk else 0.0
        work_steps += tr.load[:-1] * (gear[0] * dx + gear[1] * dy)
    work = np.concatenate([[0.0], np.cumsum(work_steps)])
    kinetic, potential = energies(built, tr)
    energy = kinetic + potential
    swing = float(np.ptp(kinetic))
    return float(np.max(np.abs(work - (energy - energy[0]))) / swing) if swing > 0 else 0.0


def _end_accelerations(built, tr: Trajectory, steps, commands) -> dict[int, list[float]]:
    """Each crank's angular acceleration at the end of each step in ``steps`` under that step's controls
    (``commands``: each crank's command per step)."""
    import mujoco
    model = built.model
    data = mujoco.MjData(model)
    dofs = [model.jnt_dofadr[model.actuator(n).trnid[0]] for n in built.cranks]
    ids = [model.actuator(n).id for n in built.cranks]
    out = {}
    for k in steps:
        data.qpos[:], data.qvel[:] = tr.qpos[k + 1], tr.qvel[k + 1]
        for i, c in zip(ids, commands):
            data.ctrl[i] = c[k]
        data.ctrl[model.actuator("load").id] = tr.load[k]
        mujoco.mj_forward(model, data)
        out[int(k)] = [float(data.qacc[d]) for d in dofs]
    return out


def compare(tr: Trajectory, built, mech=None) -> Comparison:
    """Every SPEC output, the crank torques and the work balance of run ``tr`` of model ``built`` against
    the analytic solution (of ``mech``, by default the parameters the model was built from)."""
    mech = mech or built.mech
    ref = analytic_at(tr, mech)
    errors = {}
    ok = True
    taus = analytic_torques(tr, built, mech)
    pairs = [(n, np.asarray(getattr(ref, n)), tr.outputs[n]) for n in MECHANISMS[tr.name].OUTPUTS]
    pairs += [(n, taus[n], tr.forces[n]) for n in taus]
    for name, a, s in pairs:
        diff = s - a
        if name in ANGLES:
            diff = np.pi - np.mod(np.pi - diff, 2 * np.pi)
        peak = float(np.max(np.abs(a)))
        tol = tolerance(name, peak)
        e_max, e_rms = float(np.max(np.abs(diff))), float(np.sqrt(np.mean(diff ** 2)))
        passed = bool(e_max <= tol)
        ok &= passed
        errors[name] = {"max": e_max, "rms": e_rms, "peak": peak, "tol": tol, "unit": UNITS[name],
                        "passed": passed}
    ripple = max(float(np.max(np.abs(tr.inputs[k] - v)) / np.max(np.abs(v))) if np.any(v) else 0.0
                 for k, v in tr.commanded.items())
    viol = float(np.max(tr.loop_violation))
    balance = work_balance(tr, built)
    ok &= viol <= LOOP_TOL and balance <= WORK_TOL
    return Comparison(tr, ref, errors, ripple, viol, taus, balance, bool(ok))


def table(c: Comparison) -> str:
    """A readable comparison table."""
    tr = c.trajectory
    lines = [f"{tr.name}: {tr.steps} steps of {tr.timestep:g} s ({tr.integrator}), "
             f"{tr.cpu_seconds * 1e3:.1f} ms CPU",
             f"  {'output':<8s} {'max error':>11s} {'rms error':>11s} {'peak':>11s} {'tolerance':>11s}  unit",
             ]
    for name, e in c.errors.items():
        flag = "" if e["passed"] else "  FAIL"
        lines.append(f"  {name:<8s} {e['max']:11.3e} {e['rms']:11.3e} {e['peak']:11.4g} {e['tol']:11.1e}  "
                     f"{e['unit']}{flag}")
    lines.append(f"  loop violation max {c.max_loop_violation:.3e} m (tol {LOOP_TOL:.0e}); "
                 f"speed ripple {c.speed_ripple:.3e} of the commanded speed")
    lines.append(f"  work balance {c.work_balance:.3e} of the kinetic-energy swing (tol {WORK_TOL:.0e})")
    lines.append(f"  {'PASSED' if c.passed else 'FAILED'}")
    return "\n".join(lines)
