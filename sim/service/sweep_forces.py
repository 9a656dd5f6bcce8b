"""Figures of merit under loads for ``linkage sweep --forces`` (SPEC "Loads": ``sweep`` reports the peak
bearing load, the peak drive torque and the energy per cycle): every valid row of a sweep run through the
forces application (:func:`sim.service.forces.forces_run`) with the file's ``[[loads]]``/``[friction]`` and
the command line's loads, each design with its own mass model (built from its own geometry)."""

from __future__ import annotations

from dataclasses import replace

from analytic import ParameterError
from analytic.mechanism import Mechanism

__all__ = ["FORCE_FIGURES", "design_of", "figures_of", "sweep_forces"]

FORCE_FIGURES = ("peak_joint_force", "peak_drive", "energy_per_cycle")
"""Per row: the largest |F| of any joint over the cycle [N]; the largest |drive| of the first input [N m for a
crank, N for a slider]; the work every drive does over one cycle of the first input [J]."""


def design_of(base: Mechanism, params: dict) -> Mechanism:
    """The mechanism of one sweep row: ``base`` with the row's varied values (file units, angles in rad)."""
    mech = Mechanism.from_definition(base.definition, {**base.overrides, **params}, base.builtin)
    return replace(mech, rock=base.rock) if base.rock is not None else mech


def figures_of(run) -> dict[str, float]:
    """The three figures of one forces run (:class:`sim.service.forces.ForceRun` over one cycle)."""
    from sim.service.forces import force_peaks
    peaks = force_peaks(run)
    first = run.mech.inputs[0]
    joint = max((j["F"] for j in peaks["joints"].values()), default=float("nan"))
    energy = run.energy["energy"]["drive_work"] if run.energy is not None else float("nan")
    return {"peak_joint_force": float(joint), "peak_drive": float(peaks["drives"][first.q]["value"]),
            "energy_per_cycle": float(energy)}


def sweep_forces(base: Mechanism, rows: list, loads, samples: int, progress=None) -> list:
    """``rows`` (analytic.applications.studies.Row) with :data:`FORCE_FIGURES` added to each valid row's
    values: ``samples + 1`` instants over one cycle of the first input (the sweep's grid), the loads of
    ``loads`` (sim.model.Loads: gravity, the shorthand or cutting force, the command line's loads, --inertia)
    and the file's. A row whose forces cannot be computed (a singular pose on the way) becomes invalid with
    the reason; invalid rows get NaN."""
    from sim.service.forces import forces_run
    out = []
    nan = {k: float("nan") for k in FORCE_FIGURES}
    for i, row in enumerate(rows):
        if not row.valid:
            out.append(replace(row, values={**row.values, **nan}))
        else:
            try:
                mech = design_of(base, row.params)
                run = forces_run(mech, samples + 1, 1.0, mech.rock, loads.gravity, loads.force,
                                 loads.slow_stroke_only, loads.inertias, None, loads.extra)
                out.append(replace(row, values={**row.values, **figures_of(run)}))
            except ParameterError as exc:
                out.append(replace(row, valid=False, reason=f"forces: {exc}", values={**row.values, **nan}))
        if progress is not None:
            progress(i + 1, len(rows))
    return out
