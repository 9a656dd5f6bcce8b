"""Cross-validation: the analytic solution evaluated at the *simulated* drive inputs against the outputs
the MuJoCo model measures. Evaluating at the simulated crank angle, speed and acceleration keeps the
velocity servo's lag out of the kinematic error; the servo's speed ripple is reported on its own.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic import MECHANISMS
from .simulate import Trajectory

# (unit, kind) of every SPEC output; kind picks the tolerance.
UNITS = {
    "phi2": "rad", "phi3": "rad", "phi4": "rad", "theta3": "rad", "mu": "rad",
    "omega2": "rad/s", "omega3": "rad/s", "omega4": "rad/s",
    "alpha2": "rad/s^2", "alpha3": "rad/s^2", "alpha4": "rad/s^2",
    "s": "m", "S": "m", "xC": "m", "xE": "m", "yE": "m", "xP": "m", "yP": "m",
    "ds": "m/s", "dS": "m/s", "vxC": "m/s", "vxE": "m/s", "vyE": "m/s", "vxP": "m/s", "vyP": "m/s",
    "dds": "m/s^2", "ddS": "m/s^2", "axC": "m/s^2", "axE": "m/s^2", "ayE": "m/s^2", "axP": "m/s^2",
    "ayP": "m/s^2",
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


def tolerance(name: str, peak: float) -> float:
    unit = UNITS[name]
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
    passed: bool

    def as_dict(self) -> dict:
        tr = self.trajectory
        return {"mechanism": tr.name, "timestep": tr.timestep, "integrator": tr.integrator,
                "revolutions": None, "steps": tr.steps, "cpu_seconds": tr.cpu_seconds,
                "errors": self.errors, "speed_ripple": self.speed_ripple,
                "max_loop_violation": self.max_loop_violation, "loop_tol": LOOP_TOL, "passed": self.passed}


def analytic_at(tr: Trajectory, mech):
    """The analytic state at the simulated drive inputs."""
    module = MECHANISMS[tr.name]
    i = tr.inputs
    if tr.name == "fivebar":
        return module.solve(mech, i["phi2"], i["phi4"], i["omega2"], i["omega4"], i["alpha2"], i["alpha4"])
    return module.solve(mech, i["phi1"], i["omega1"], i["alpha1"])


def compare(tr: Trajectory, mech) -> Comparison:
    ref = analytic_at(tr, mech)
    errors = {}
    ok = True
    for name in MECHANISMS[tr.name].OUTPUTS:
        a, s = np.asarray(getattr(ref, name)), tr.outputs[name]
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
    ripple = max(float(np.max(np.abs(tr.inputs[k] - v))) / abs(v) if v else 0.0
                 for k, v in tr.commanded.items())
    viol = float(np.max(tr.loop_violation))
    ok &= viol <= LOOP_TOL
    return Comparison(tr, ref, errors, ripple, viol, bool(ok))


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
    lines.append(f"  {'PASSED' if c.passed else 'FAILED'}")
    return "\n".join(lines)
