"""Closed-form kinematics over a run (``linkage analyze``): the run, its figures of merit, its records."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

import analytic
from analytic import ParameterError
from analytic.applications import figures as _figures
from analytic.applications.figures import of as figures_of
from analytic.checks import check_turns_fully  # noqa: F401 (the service's name; the check reads the run)
from analytic.mechanism import Mechanism
from analytic.quantities import (ANGLE, ANGULAR_VELOCITY, LENGTH, SI, TIME, TORQUE,  # noqa: F401 (re-exported)
                                 Display)


MAX_SAMPLES = 10_000_000
"""Largest analysis accepted (the memory bound, RUN_MEMORY, binds first: 2.9 million on the four-bar)."""


MAX_REVOLUTIONS = 10_000

RUN_MEMORY = 2 * 1024 ** 3
"""[bytes] The most memory one run's samples (or steps) may take: ``analyze``, ``forces``, ``simulate`` and
``compare`` refuse a run that would need more before it starts (:func:`check_memory`): ``forces --samples
10000000`` took 5.7 GB on the four-bar, ``analyze`` 4.6 GB, ``simulate`` 37 GB at its former 2e7-step cap."""

BYTES_PER_VALUE = 16
"""[bytes] Peak memory per value per sample of ``analyze`` (:func:`analysis_values`) and ``forces``
(kinetostatics.full_wanted): measured (peak RSS over 300,000-400,000 samples less that over 2,000), ``forces``
13.6 on the four-bar, 12.5 on Jansen's linkage, 12.1 on Klann's; ``analyze --csv`` 11.1 on the four-bar, 14.5
on Jansen's, 14.1 on the excavator (8.2-8.6 without the CSV); rounded up. ``analyze fourbar`` at 2,581,110
samples (6 % past its bound, 2,440,322) peaked at 1.2 GB, with ``--csv`` 1.5 GB (benchmarks/run_memory.py)."""


def check_memory(option: str, asked: str, count: int, values: int, per_value: float, what: str,
                 unit: str = "sample", most=None) -> None:
    """Refuse a run of ``count`` samples (``unit``: or steps) of ``values`` values each, ``per_value`` bytes a
    value, that would need more than RUN_MEMORY: one line naming the option as given (``option``=``asked``), what
    it is (``what``: "the fourbar's joint forces at that many samples"), the memory it needs and the most that
    fit, in the option's terms (``most``: the largest count that fits -> its text; default the count itself)."""
    limit = int(RUN_MEMORY // (per_value * values))
    if count <= limit:
        return
    need = count * per_value * values / 1024 ** 3
    shown = f"{limit:,}" if most is None else most(limit)
    raise ParameterError(f"{option}={asked}: {what} need about {need:.1f} GB ({values} values a {unit}); at most "
                         f"{shown} fit in the {RUN_MEMORY / 1024 ** 3:.3g} GB a run may use: give fewer")


def analysis_values(mech: Mechanism) -> int:
    """The arrays an analysis keeps a value of per sample, counted from the structure (no solve): the solver's
    (every point's 6, every link's 5 with its cosine and sine, every slide's 3, the kinds' own outputs, the
    aliases, at most 3 of an input's own), the inputs' columns with a motion law's jerk, and the time. Exact
    on the library but for a crank's or slider's own 3 (its link's or slide's), counted again: an upper bound."""
    n = len(mech.inputs)
    solved = (6 * len(mech.points) + 5 * len(mech.links) + 3 * len(mech.slides) + len(mech.extra_outputs)
              + len(mech.aliases) + 3 * n)
    return solved + 4 * n + 1


@dataclass(frozen=True)
class Analysis:
    """One analysed run: time [s], the inputs' motion (columns named phi1, omega1, ...), the solution."""

    t: np.ndarray
    inputs: dict[str, np.ndarray]
    solution: analytic.Solution
    figures: dict


def check_samples(samples) -> int:
    if isinstance(samples, bool) or not isinstance(samples, int) or not 2 <= samples <= MAX_SAMPLES:
        raise ParameterError(f"samples={samples!r} must be an integer in 2..{MAX_SAMPLES:,}")
    return samples


def check_revolutions(revolutions) -> float:
    if isinstance(revolutions, bool) or not isinstance(revolutions, (int, float)) or not (
            math.isfinite(revolutions) and 0 < revolutions <= MAX_REVOLUTIONS):
        raise ParameterError(f"revolutions={revolutions!r} must be a number in (0, {MAX_REVOLUTIONS}]")
    return float(revolutions)


def check_range(mech: Mechanism, lo: float, hi: float) -> tuple[float, float]:
    first = mech.inputs[0]
    fmt = (lambda v: f"{math.degrees(v):.2f}deg") if first.angular else (lambda v: f"{v:.6g}")
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise ParameterError(f"input range {lo}:{hi} must be finite")
    if not hi > lo:
        raise ParameterError(f"input range {fmt(lo)}:{fmt(hi)}: the end must exceed the start")
    if first.angular and hi - lo > 2 * math.pi * MAX_REVOLUTIONS:
        raise ParameterError(f"input range {fmt(lo)}:{fmt(hi)} spans more than {MAX_REVOLUTIONS} turns")
    return lo, hi


def analyze(mech: Mechanism, samples: int = 361, revolutions: float = 1.0,
            input_range: tuple[float, float] | None = None, figures: bool = True) -> Analysis:
    """Closed-form kinematics over one run: ``samples`` instants over ``revolutions`` of the first input,
    or values of the first input evenly spaced over ``input_range`` (other inputs at their motion law).
    ``figures=False`` skips the figures of merit (their scans take 50 ms to 2 s; the curves ~1 ms), as a
    front end does while a value is being dragged."""
    check_samples(samples)
    check_revolutions(revolutions)
    check_memory("samples", f"{samples:,}", samples, analysis_values(mech), BYTES_PER_VALUE,
                 f"the {mech.name}'s outputs at that many samples")
    if input_range is not None:
        lo, hi = check_range(mech, *input_range)
        first = mech.inputs[0]
        q1 = np.linspace(lo, hi, samples)
        rate = first.motion.rate if first.motion.rate != 0 else 1.0
        t = (q1 - lo) / abs(rate)
        q, qd, qdd, jerk = mech.drive(t, jerk=True)
        q[:, 0], qd[:, 0], qdd[:, 0], jerk[:, 0] = q1, first.motion.rate, 0.0, 0.0
    else:
        check_turns_fully(mech)
        t = np.linspace(0.0, mech.duration(revolutions), samples)
        q, qd, qdd, jerk = mech.drive(t, jerk=True)
    sol = mech.solve(q, qd, qdd)
    if sol.first_failure() is not None:      # which samples assemble is the positions' alone: refused as the
        mech.check_assembles(q)              # positions' own check words it
    cols = {}
    for attr, arr in (("q", q), ("qd", qd), ("qdd", qdd)):          # phi2 phi4 omega2 omega4 alpha2 alpha4
        for k, inp in enumerate(mech.inputs):
            cols[getattr(inp, attr)] = arr[:, k]
    for k, inp in enumerate(mech.inputs):                            # a motion law's jerk: jphi2
        if inp.motion.law is not None:
            cols[inp.qddd] = jerk[:, k]
    return Analysis(t, cols, sol, figures_of(mech, sol) if figures else {})


def figures(mech: Mechanism) -> dict:
    """The figures of merit of one cycle, as ``analyze`` computes them (361 samples of one revolution, or
    of the rocking range): what every front end shows, so a figure reads the same everywhere."""
    return analyze(mech, 361, 1.0, mech.rock).figures


def analysis_record(mech: Mechanism, a: Analysis, samples: int, revolutions: float, display=None) -> dict:
    """The JSON of ``linkage analyze --json``: figures and ranges in ``display`` units (default SI), and
    the ``units`` table saying which (analytic.quantities)."""
    from analytic import quantities as Q
    display = display or Q.SI
    outs = mech.outputs
    angular = mech.inputs[0].angular
    ranges = {k: display.convert(Q.quantity(mech, k), _span(a.solution[k])) for k in outs}
    record = {"mechanism": mech.name, "units": units_table(mech, display, outs, a.figures),
              "parameters": Q.parameters_in(mech, display), "samples": samples, "revolutions": revolutions,
              "figures": Q.convert_figures(a.figures, display, angular), "ranges": ranges}
    cams = cams_record(mech, display)
    if cams:
        record["cams"] = cams
    return record


def cams_record(mech: Mechanism, display=None) -> dict:
    """Per cam (SPEC "Cams and followers"): its largest pressure angle, smallest radius of curvature, a flat
    face's required width (the contact's travel along it) and its outline (closed, counter-clockwise, in the
    cam's frame: :func:`analytic.cams.plate`, a given ``profile`` as the file gives it), lengths in ``display``
    units (default SI)."""
    from analytic import cams
    from analytic import quantities as Q
    display = display or Q.SI
    out = {}
    for name, e in cams.elements(mech).items():
        geo = cams.geometry(mech, e)
        entry = {"pressure_angle_max": display.convert(Q.ANGLE, geo.pressure_angle_max),
                 "rho_min": display.convert(Q.LENGTH, geo.rho_min)}
        if geo.setup.contact == "flat":
            entry["face_width"] = display.convert(Q.LENGTH, geo.face_travel)
        entry["profile"] = display.convert(Q.LENGTH, cams.plate(e, geo).tolist())    # a given outline as given
        out[name] = entry
    return out


def units_table(mech: Mechanism, display, outputs=(), figures=None) -> dict:
    """The JSON ``units`` table: the file's length unit, the unit of each quantity in this record, and of
    each output and figure of merit named."""
    from analytic import quantities as Q
    return {"file": mech.units, **{q: display.unit(q) for q in Q.SI_UNIT if q != Q.RATIO},
            "parameters": Q.parameter_units(mech, display),
            "outputs": {k: display.unit(Q.quantity(mech, k)) for k in outputs},
            **({"figures": Q.figure_units(figures, display, mech.inputs[0].angular)} if figures else {})}


def parameters_record(mech: Mechanism, display=None) -> dict:
    """``parameters`` (values in ``display`` units, default SI) and ``parameter_units`` (their unit labels)
    for a machine-readable record (the CSV sidecar)."""
    from analytic import quantities as Q
    display = display or Q.SI
    return {"parameters": Q.parameters_in(mech, display), "parameter_units": Q.parameter_units(mech, display)}


def _span(x) -> list[float]:
    x = np.asarray(x)
    return [float(np.nanmin(x)), float(np.nanmax(x))] if np.any(np.isfinite(x)) else [math.nan, math.nan]


def analysis_columns(mech: Mechanism, a: Analysis) -> dict[str, np.ndarray]:
    """CSV columns of an analysis: t, the inputs, the reported outputs."""
    return {"t": a.t, **a.inputs, **{k: np.asarray(a.solution[k]) for k in mech.outputs}}


def units_of(mech: Mechanism, columns, display=None) -> dict[str, str]:
    """The unit of each CSV column (for the sidecar) in ``display`` units (default SI)."""
    from sim.output.units import column_unit
    return {c: column_unit(mech, c, display or SI) for c in columns}


def summary_lines(mech: Mechanism, figures: dict, display=None) -> list[str]:
    """The figures of merit of an analysis (``Analysis.figures``) as the lines ``linkage analyze`` prints,
    in ``display`` units (an :class:`analytic.quantities.Display`; default the file's)."""
    return _figures.summary(mech, figures, display)


def parameters_text(mech: Mechanism, display=None) -> str:
    """The mechanism's parameters on one line (``l1=0.1 m, ...``) in ``display`` units."""
    from analytic.quantities import parameters_text as text
    return text(mech, display)


def assembly_ranges(mech: Mechanism) -> list:
    """The intervals of the first input over which a one-input mechanism assembles, as (lo, hi) pairs [rad or
    m]; empty where it assembles nowhere (a design to refuse)."""
    return _figures.assembly_ranges(mech)
