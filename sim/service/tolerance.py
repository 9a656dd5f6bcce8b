"""The tolerance use case (``linkage tolerance MECH``, SPEC "Tolerance"): parse the tolerances, set up the
nominal cycle and its loads, run :func:`analytic.applications.tolerance.analyse` (in this process, on a
process pool or on a Dask scheduler), and give its JSON record and its table.

A script does what the command does::

    from sim import service
    from sim.service import tolerance as ts
    mech = service.load("my_linkage.toml")
    result = ts.tolerance(mech, ["l1=±0.0005", "l2=normal:0.0002"], samples=1000, sobol=True)
    record = ts.tolerance_record(result, mech)
"""

from __future__ import annotations

import math

import numpy as np

from analytic import ParameterError
from analytic import quantities as Q
from analytic.applications import tolerance as T
from sim import service

__all__ = ["cycle_of", "outputs_of", "tolerances_of", "tolerance", "tolerance_record", "tolerance_table",
           "output_quantity"]


def output_quantity(mech, name: str) -> str:
    """The quantity of a tolerance output (:mod:`analytic.quantities`): a slider input's drive is a force."""
    if name == "peak_torque":
        return mech.inputs[0].spec.drive_quantity
    return {"path_deviation": Q.LENGTH, "transmission_min": Q.ANGLE, "transmission_max": Q.ANGLE,
            "peak_joint_force": Q.FORCE, "speed_fluctuation": Q.RATIO}[name]


def _forces_ok(mech) -> bool:
    from analytic.applications import forces as F
    try:
        F.check_determinate(mech)
    except ParameterError:
        return False
    return True


def outputs_of(mech, text: str | None) -> tuple[str, ...]:
    """``--outputs a,b,...`` (None: the defaults the mechanism has), checked against what it has."""
    has = T.available(mech, _forces_ok(mech))
    if text is None:
        outs = tuple(o for o in T.DEFAULT_OUTPUTS if o in has)
        return outs
    names = [x.strip() for x in text.split(",") if x.strip()]
    if not names:
        raise ParameterError(f"--outputs {text!r}: give output names separated by commas; choose from "
                             f"{', '.join(T.OUTPUTS)}")
    for n in names:
        if n not in T.OUTPUTS:
            raise ParameterError(f"--outputs {n}: not an output; choose from {', '.join(T.OUTPUTS)}")
        if n not in has:
            why = ("it has no group with a transmission angle (an RRR)" if n.startswith("transmission")
                   else "statics cannot give its joint forces (see linkage forces)")
            raise ParameterError(f"--outputs {n}: the {mech.name} has no {n}: {why}; drop it")
    if len(set(names)) != len(names):
        raise ParameterError(f"--outputs {text}: an output is named twice")
    return tuple(names)


def tolerances_of(mech, items: list[str]) -> tuple[T.Tolerance, ...]:
    """The ``--tol`` items of ``mech``, parsed (file units; angles rad)."""
    d = mech.definition
    nominal = {n: float(mech.values[n]) for n in d.parameter_order}
    return tuple(T.parse(item, nominal, d.parameter_kind, mech.name) for item in items or [])


def cycle_of(mech, loads=None, input_range=None):
    """The nominal mechanism (rocking over ``input_range`` if given) and the :class:`~analytic.applications.
    tolerance.Cycle` every design is evaluated along: CYCLE_SAMPLES instants over the common period of its
    inputs, with the loads of ``loads`` (a :class:`sim.model.Loads`; a cutting force acts over the nominal
    design's slow stroke)."""
    from analytic.applications.studies import period_of
    if input_range is not None:
        mech = mech.rocking(*service.check_range(mech, *input_range))
    else:
        service.check_turns_fully(mech)
    t = np.linspace(0.0, period_of(mech), T.CYCLE_SAMPLES)
    q, _, _ = mech.drive(t)
    mech.check_motion(q)                     # as check_assembles words it
    sol = mech.solve(q, outputs=["x" + mech.output_point, "y" + mech.output_point])
    if sol.first_failure() is not None:      # which samples assemble is the positions' alone: refused as the
        mech.check_assembles(q)              # positions' own check words it
    path = np.column_stack([sol["x" + mech.output_point], sol["y" + mech.output_point]])
    gravity, force, on, inertias = (0.0, 0.0), (0.0, 0.0), 1.0, None
    if loads is not None:
        gravity = tuple(loads.gravity) if loads.gravity is not None else (0.0, 0.0)
        force = tuple(float(x) for x in loads.force)
        inertias = loads.inertias
        if loads.slow_stroke_only and (force[0] or force[1]):
            from sim.service.forces import _load_window
            on, _ = _load_window(mech, q[:, 0])
    return mech, T.Cycle(t, q, path, gravity, force, on, inertias)


def tolerance(mech, items: list[str], samples: int = 1000, seed: int = 1, outputs: str | None = None,
              sobol: bool = False, scheduler: str | None = None, loads=None, input_range=None,
              workers: int = 1, progress=None) -> T.Result:
    """Monte Carlo, first-order propagation and (``sobol``) Sobol indices of ``mech`` under the tolerances
    ``items`` (``--tol`` texts); the designs in chunks on ``workers`` processes or a Dask ``scheduler``
    address (``"local"``: a LocalCluster here); ``progress(done, total)`` as designs are evaluated."""
    from sim.run.parallel import mapper
    tols = tolerances_of(mech, items)
    if not tols:
        raise ParameterError("give at least one --tol NAME=±V (e.g. --tol l1=±0.1)")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ParameterError(f"--seed {seed!r} must be an integer >= 0")
    outs = outputs_of(mech, outputs)
    nominal, cycle = cycle_of(mech, loads, input_range)
    with mapper(workers, scheduler) as m:
        return T.analyse(nominal, tols, cycle, outs, samples, seed, sobol,
                         m if (workers > 1 or scheduler) else None, progress)


def _parameter_si(mech, name: str) -> float:
    """SI per file unit of parameter ``name``."""
    return mech.scale if Q.parameter_quantity(mech, name) in (Q.LENGTH, Q.VELOCITY, Q.ACCELERATION) else 1.0


def _num(v: float):
    return float(v) if math.isfinite(v) else None


def tolerance_record(result: T.Result, mech, display=None) -> dict:
    """The JSON of ``linkage tolerance --json`` (SPEC "Tolerance"): SI unless ``display`` converts it; the
    ``units`` table says which. Besides SPEC's fields: each output's ``rates`` (per SI unit of each parameter;
    ``path_deviation``: max over the cycle of the output point's rate) and first-order ``shares``, the
    tolerances as given and in SI, and up to five failed designs with their reasons."""
    display = display or Q.SI
    outputs = {}
    units = {}
    for o in result.outputs:
        s = result.summaries[o]
        q = output_quantity(mech, o)
        units[o] = display.unit(q)

        def c(v, q=q):
            return _num(display.convert(q, v)) if v is not None and math.isfinite(v) else None
        outputs[o] = {"nominal": c(s.nominal), "mean": c(s.mean), "std": c(s.std), "p05": c(s.p05),
                      "p95": c(s.p95), "first_order_std": c(s.first_order_std),
                      "sobol": None if s.sobol is None else {p: {k: _num(x) for k, x in v.items()}
                                                             for p, v in s.sobol.items()},
                      "rates": {p: c(r / _parameter_si(mech, p)) for p, r in s.rates.items()},
                      "shares": s.shares}
    tols = {}
    for t in result.tolerances:
        f = _parameter_si(mech, t.name)
        tols[t.name] = {"text": t.text, "dist": t.dist, "nominal": float(mech.values[t.name]) * f,
                        ("half_width" if t.dist == "uniform" else "sigma"): t.width * f, "std": t.std * f}
    failures = [{"parameters": {t.name: float(mech.values[t.name]) + float(result.deltas[i, j])
                                for j, t in enumerate(result.tolerances)}, "reason": r}
                for i, r in enumerate(result.reasons) if r][:5]
    record = {"mechanism": result.mechanism, "samples": result.samples, "seed": result.seed,
              "tolerances": tols, "outputs": outputs, "failed": result.failed, "failures": failures,
              "units": units}
    if result.sobol_evaluations:
        record["sobol_evaluations"] = result.sobol_evaluations
        record["sobol_blocks_dropped"] = result.sobol_dropped
    return record


def _fmt(v: float) -> str:
    return "-" if v is None or not math.isfinite(v) else f"{v:.4g}"


def tolerance_table(result: T.Result, mech, display) -> str:
    """What ``linkage tolerance`` prints: the tolerances, the failures, and per output (in ``display`` units)
    nominal, mean, std, p05, p95, first-order std and the tolerance that drives it most."""
    lines = [f"tolerance analysis of the {result.mechanism}: {result.samples} samples (seed {result.seed})"]
    for t in result.tolerances:
        q = Q.parameter_quantity(mech, t.name)
        f = _parameter_si(mech, t.name)

        def shown(v, q=q, f=f):
            return display.convert(q, v * f) if q else v
        unit = display.unit(q) if q else ""
        form = f"±{shown(t.width):.4g}" if t.dist == "uniform" else f"normal, sigma {shown(t.width):.4g}"
        lines.append(f"  {t.name} = {shown(float(mech.values[t.name])):.6g} {form} {unit}".rstrip()
                     + (f"  (from {t.text})" if t.text.endswith("%") else ""))
    n_ok = result.samples - result.failed
    if result.failed:
        first = next(r for r in result.reasons if r)
        lines.append(f"  {result.failed} of {result.samples} designs failed ({100 * result.failed / result.samples:.1f} %; "
                     f"e.g. {first}); statistics over the {n_ok} that assembled")
    else:
        lines.append("  every design assembled")
    head = f"  {'output':<24s}{'nominal':>11s}{'mean':>11s}{'std':>11s}{'p05':>11s}{'p95':>11s}{'1st-order':>11s}  driven by"
    lines.append(head)
    for o in result.outputs:
        s = result.summaries[o]
        q = output_quantity(mech, o)
        unit = display.unit(q)
        name = f"{o} [{unit}]" if unit else o
        vals = [display.convert(q, v) for v in (s.nominal, s.mean, s.std, s.p05, s.p95, s.first_order_std)]
        scale = 1e-12 * max(abs(s.nominal), abs(s.mean), 1e-300)      # rounding of a constant output
        if not (s.std > scale or s.first_order_std > scale):
            drive = "- (does not vary)"
        elif s.sobol:
            key, val = max(s.sobol.items(), key=lambda kv: kv[1]["ST"])
            drive = f"{key} (Sobol ST {val['ST']:.2f})"
        else:
            key = max(s.shares, key=s.shares.get)
            drive = f"{key} ({100 * s.shares[key]:.0f} % first order)"
        lines.append(f"  {name:<24s}" + "".join(f"{_fmt(v):>11s}" for v in vals) + f"  {drive}")
    if result.sobol_evaluations:
        lines.append(f"  Sobol indices from {result.sobol_evaluations} more designs (Saltelli design)"
                     + (f"; {result.sobol_dropped} blocks dropped for failed designs" if result.sobol_dropped else ""))
    return "\n".join(lines)
