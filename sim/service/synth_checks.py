"""The simulation every returned synthesis design goes through (issue 29 item 3): ``linkage compare`` (MuJoCo
following the general solver's motion) and its joint forces simulated in MuJoCo against the analytic ones
under the same loads (:func:`sim.service.simulated_forces`), over the design's working range: a full turn, or
rocking over its file's ``input_range``."""

from __future__ import annotations

from analytic import ParameterError

__all__ = ["simulate_design", "SAMPLES"]

SAMPLES = 181
"""Samples of the working range at which the forces are computed and simulated."""


def simulate_design(mech, input_range=None, loads=None) -> dict:
    """``{"passed", "compare_passed", "forces_passed", "peak_torque" [N m], "peak_bearing" [N], "rms_shaking"
    [N] (MuJoCo's), "analytic": {the same three, the closed-form kinetostatics}, "problem"}`` of one design
    file's mechanism; ``loads``: :class:`sim.model.Loads` (None: none but the links' inertia)."""
    from sim import service
    from sim.model import Loads
    loads = loads or Loads()
    out = {"passed": False, "compare_passed": False, "forces_passed": False, "problem": ""}
    try:
        _, c = service.compare(mech, 1.0, input_range=input_range)
    except (ParameterError, ValueError) as e:
        return {**out, "problem": f"linkage compare cannot run: {str(e).splitlines()[0]}"}
    out["compare_passed"] = bool(c.passed)
    try:
        run = service.forces_run(mech, SAMPLES, input_range=input_range, gravity=loads.gravity, force=loads.force,
                                 slow_stroke_only=loads.slow_stroke_only)
        rec = service.simulated_forces(run, loads=loads)
    except (ParameterError, ValueError) as e:
        return {**out, "problem": f"its forces cannot be simulated: {str(e).splitlines()[0]}"}
    a, s = service.force_peaks(run), rec["peaks"]

    def three(p):
        return {"peak_torque": max(v["value"] for v in p["drives"].values()),
                "peak_bearing": max(v["F"] for v in p["joints"].values()), "rms_shaking": p["shaking"]["F_rms"]}
    out.update(three(s))
    out["analytic"] = three(a)
    out["forces_passed"] = bool(rec["passed"])
    out["passed"] = out["compare_passed"] and out["forces_passed"]
    if not out["passed"]:
        out["problem"] = ("it fails linkage compare" if not out["compare_passed"]
                          else "MuJoCo's joint forces disagree with the analytic ones")
    return out
