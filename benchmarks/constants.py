"""The numerical constants the simulation adds, and how much each one moves what compare judges.

Run:  python benchmarks/constants.py [NAME_OR_FILE ...]

The MuJoCo model carries constants that are not part of the design (docs/CONVENTIONS.md "What the
simulation adds"): each drive's rotor inertia (armature J = kp (h / SERVO_RATE)^2), its servo gains (kp sized
so the peak load deflects it by DRIVE_ERROR_BUDGET, kv for critical damping), the loops' connect
constraints' regulariser (REGULARIZATION_SCALE, solimp at MuJoCo's cap 0.9999) and drift correction
(solref[0] = LOOP_TIMECONST steps), and the time step h (0.025 rad of the fastest rate per step, RK4). For
each design it prints compare's errors (each as a share of its tolerance) with the constants as chosen,
then with one constant changed at a time: the armature x2, kp x1/10 (the armature follows kp, so the
servo's frequency stays), the regulariser x10, the drift correction's time constant x2, the step /2. What a
constant changes is its effect on that quantity; a quantity whose reference shared the constant would not
move (it moves with the simulated state instead). It also prints the rotor's term J qdd against the drive
torque's peak (what compare's drive torque carried before issue 41) and the kinetic-energy swing of the
rotors against the links' (the work balance is measured against the swing with the rotors in it).
"""

from __future__ import annotations

import argparse
import contextlib
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

# benchmarks/analytic.py would shadow the package of that name: keep this folder off the import path.
sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]
import analytic  # noqa: E402
from sim import model as _model  # noqa: E402,F401  (loads sim.model.build and sim.model.drives)
from sim import service  # noqa: E402
from sim.model import Settings  # noqa: E402
from sim.run import compare as C  # noqa: E402
from sim.run.simulate import energies  # noqa: E402

B = sys.modules["sim.model.build"]                 # the module: sim.model's own `build` is the function
D = sys.modules["sim.model.drives"]
ROOT = Path(__file__).resolve().parent.parent
DEFAULT = ["fourbar", "slider_crank", "sixbar", "whitworth", "fivebar", "jansen",
           str(ROOT / "tests" / "mechanisms" / "press_loads.toml"), str(ROOT / "tests" / "mechanisms" / "press_5kn.toml")]


@contextlib.contextmanager
def patched(module, name, value):
    old = getattr(module, name)
    setattr(module, name, value)
    try:
        yield
    finally:
        setattr(module, name, old)


def figures(built, c) -> dict:
    """compare's errors as shares of their tolerances: the worst output by kind, each drive torque, the drive
    error, the loops, the work balance, the joint forces."""
    mech = built.mech
    out = {}
    for name, e in c.errors.items():
        if e["role"] == "drive":
            key = "torque"
        else:
            key = {"rad": "angle", "m": "position", "rad/s": "velocity", "m/s": "velocity",
                   "rad/s^2": "acceleration", "m/s^2": "acceleration"}.get(e["unit"], "other")
        out[key] = max(out.get(key, 0.0), e["max"] / e["tol"])
    out["drive"] = c.drive_error / C.DRIVE_TOL
    out["loops"] = c.max_loop_violation / (C.LOOP_TOL * mech.size)
    out["work"] = c.work_balance / C.WORK_TOL
    if c.forces is not None:
        out["joints"] = c.forces.worst / c.forces.tol
    return out


def run(mech, settings=None):
    built, c = service.compare(mech, 1.0, settings=settings)
    return built, c


def rotor(built, c) -> tuple[float, float]:
    """(max |J qdd| / the drive's peak, the rotors' kinetic-energy swing / the links')."""
    tr = c.trajectory
    share = 0.0
    spin = np.zeros(len(tr.t))
    for d in built.drives:
        qdd = tr.inputs[d.input.qdd]
        peak = max(float(np.max(np.abs(tr.forces[f"tau{d.input.link}"]))), 1e-300)
        share = max(share, float(np.max(np.abs(d.armature * qdd))) / peak)
        spin = spin + 0.5 * d.armature * tr.inputs[d.input.qd] ** 2
    kinetic, _ = energies(built, tr)
    return share, float(np.ptp(kinetic)) / max(float(np.ptp(kinetic - spin)), 1e-300)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", default=DEFAULT)
    args = ap.parse_args(argv)
    keys = ["angle", "position", "velocity", "acceleration", "torque", "drive", "loops", "work", "joints"]
    variants = [("as chosen", None, None),
                ("armature x2", (D, "SERVO_RATE", D.SERVO_RATE / np.sqrt(2.0)), None),
                ("kp x1/10", (D, "DRIVE_ERROR_BUDGET", D.DRIVE_ERROR_BUDGET * 10.0), None),
                ("regulariser x10", (B, "REGULARIZATION_SCALE", B.REGULARIZATION_SCALE * 10.0), None),
                ("solref x2", None, "timeconst"),
                ("step /2", None, "step")]
    for name in args.names:
        mech = analytic.load(name)
        base_built, base = run(mech)
        share, swing = rotor(base_built, base)
        print(f"\n{mech.name}: {base.trajectory.steps} steps of {base.trajectory.timestep:.3g} s; armature "
              f"{', '.join(f'{d.armature:.3g}' for d in base_built.drives)}; rotor term J qdd up to {share:.3g} of "
              f"the drive's peak; KE swing with the rotors {swing:.3g}x the links'")
        print(f"  {'variant':<16s} " + " ".join(f"{k:>12s}" for k in keys) + "   (error / tolerance)")
        for label, patch, setting in variants:
            settings = None
            if setting == "timeconst":
                settings = replace(Settings(), timeconst=2 * Settings().timeconst)
            elif setting == "step":
                settings = Settings(timestep=base.trajectory.timestep / 2)
            with patched(*patch) if patch else contextlib.nullcontext():
                built, c = (base_built, base) if label == "as chosen" else run(mech, settings)
            f = figures(built, c)
            print(f"  {label:<16s} " + " ".join(f"{f.get(k, float('nan')):12.3e}" for k in keys)
                  + ("" if c.passed else "   FAILED"))


if __name__ == "__main__":
    main()
