"""Tolerance analysis: how far a linkage's results move when its dimensions are made to tolerance (SPEC,
"Tolerance").

Each toleranced parameter ``p_i`` deviates from its nominal value by ``d_i``: uniform on [-V, V] (standard
deviation V/sqrt(3)) or normal with standard deviation SIGMA. Three estimates of each output's spread:

- **Monte Carlo**: ``samples`` seeded draws of the deviations, every design solved over one cycle of the
  nominal design's inputs (the same input values for all; rates and accelerations from each design's own
  motion law), many designs per vectorised call (:mod:`analytic.solver.batch`), chunks spread by a
  ``mapper`` (a process pool's or a Dask client's ``map``). A design that cannot assemble at some input
  value, or whose joint forces are unbounded (a singular pose), is *failed*: counted and described, never
  dropped silently; the statistics are over the designs that did assemble.
- **First order** (the linearised estimate): the exact rates dy/dp_i at the nominal design by central
  differences on the solver (step ``STEP`` times the tolerance's standard deviation), and
  std = sqrt(sum (dy/dp_i sigma_i)^2). ``path_deviation`` is a norm, not a linear function of the
  deviations: its linearised value is max_u |J(u) d| with J(u) the rates of the output point's position at
  each input value u, and its first-order spread the standard deviation of that over the same draws.
- **Sobol indices** (variance-based, optional): a Saltelli design (SALib's scrambled Sobol sequence) and
  SALib's estimators of the first-order index S1 and the total index ST of each parameter.

Outputs (SI): ``path_deviation`` [m], the largest distance over the cycle between the output point and its
nominal position at the same input value; ``transmission_min``/``transmission_max`` [rad], the range of every
transmission angle over the cycle; ``peak_torque`` [N m, or N for a slider input], the largest |drive| of
any input; ``peak_joint_force`` [N], the largest joint force; ``speed_fluctuation`` [1], the output point's
(max - min)/mean speed over the cycle.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np

from analytic._common import ParameterError
from analytic.applications.averages import closed_mean

__all__ = ["Tolerance", "Cycle", "Summary", "Result", "OUTPUTS", "DEFAULT_OUTPUTS", "parse", "available",
           "draw", "evaluate", "evaluate_chunk", "rates", "saltelli", "sobol_base", "sobol_indices", "analyse", "CHUNK",
           "STEP", "CYCLE_SAMPLES"]

OUTPUTS = ("path_deviation", "transmission_min", "transmission_max", "peak_torque", "peak_joint_force",
           "speed_fluctuation")
"""Every output a tolerance analysis can report."""

DEFAULT_OUTPUTS = OUTPUTS[:5]
"""What is reported unless ``outputs`` says otherwise (the transmission angles only where the mechanism has
one, the forces only where statics gives them)."""

CHUNK = 256
"""Designs per evaluated chunk (and per worker job): 256 designs x 361 samples x ~40 outputs of 8 bytes is
~30 MB."""

CYCLE_SAMPLES = 361
"""Input values over the cycle (1 deg apart for a crank's turn)."""

STEP = 1e-3
"""Central-difference step as a fraction of each tolerance's standard deviation: the truncation error
(~ step^2 * third derivative) and the rounding error (~ 1e-16 * |y| / step) both stay far below 1e-5 of the
rate for tolerances down to 1e-9 of the dimension."""

_FORCES = ("peak_torque", "peak_joint_force")


# ------------------------------------------------------------------------------------------ tolerances
@dataclass(frozen=True)
class Tolerance:
    """One parameter's tolerance: ``dist`` "uniform" (``width`` = V, the half-width) or "normal" (``width``
    = SIGMA); ``width`` in the parameter's file units (angles rad); ``text`` as the user wrote it."""

    name: str
    dist: str
    width: float
    text: str = ""

    @property
    def std(self) -> float:
        """The standard deviation of the deviation (file units)."""
        return self.width / math.sqrt(3.0) if self.dist == "uniform" else self.width


_FORM = ("write NAME=±V (uniform on [-V, V]; +-V also works), NAME=±V% (relative to the nominal value) or "
         "NAME=normal:SIGMA (SIGMA% relative)")
_PLUS_MINUS = ("±", "+/-", "+-")


def parse(item: str, nominal: dict[str, float], kinds: dict[str, str], mechanism: str = "mechanism") -> Tolerance:
    """One ``--tol`` item, ``NAME=±V``, ``NAME=±V%`` or ``NAME=normal:SIGMA[%]``, against the parameters'
    ``nominal`` values (file units) and ``kinds`` (length, angle, branch, number). A length takes no
    ``deg`` suffix; an angle may (``±0.5deg``).

    Raises ParameterError naming the item and what to write instead."""
    from analytic.format import expr
    if "=" not in item:
        raise ParameterError(f"--tol {item!r}: {_FORM}")
    name, text = (x.strip() for x in item.split("=", 1))
    if name not in nominal:
        raise ParameterError(f"--tol {name}: {name!r} is not a parameter of {mechanism}; parameters: "
                             f"{', '.join(nominal) or '(none)'}")
    if kinds.get(name) == "branch":
        raise ParameterError(f"--tol {name}: {name} picks an assembly branch (+1 or -1), it has no tolerance; "
                             f"tolerance a dimension instead")
    body = text
    if body.lower().startswith("normal:"):
        dist, body = "normal", body[len("normal:"):].strip()
    else:
        sign = next((s for s in _PLUS_MINUS if body.startswith(s)), None)
        if sign is None:
            raise ParameterError(f"--tol {name}={text}: {_FORM}")
        dist, body = "uniform", body[len(sign):].strip()
    relative = body.endswith("%")
    if relative:
        body = body[:-1].strip()
    what = "SIGMA" if dist == "normal" else "V"
    if not re.fullmatch(r"[-+]?[0-9.eE+-]+(deg)?", body):
        raise ParameterError(f"--tol {name}={text}: {what} is not a number; {_FORM}")
    angle = None if kinds.get(name) == "angle" and not relative else False
    try:
        value = expr.parse_value(f"--tol {name}", body, angle=angle)
    except ParameterError as exc:
        raise ParameterError(f"{exc} ({_FORM})") from None
    if not value > 0:
        raise ParameterError(f"--tol {name}={text}: {what} must be > 0 (a tolerance is a width: "
                             f"e.g. {name}=±0.1 or {name}=normal:0.05)")
    if relative:
        base = abs(float(nominal[name]))
        if base == 0:
            raise ParameterError(f"--tol {name}={text}: {name} is 0, so {value:g}% of it is 0; give an absolute "
                                 f"tolerance (e.g. {name}=±0.1)")
        value = value / 100.0 * base
    return Tolerance(name, dist, float(value), text)


def draw(tols: tuple[Tolerance, ...], n: int, seed: int) -> np.ndarray:
    """``n`` seeded draws of the deviations, shape (n, len(tols)) (file units)."""
    rng = np.random.default_rng(seed)
    cols = [rng.uniform(-t.width, t.width, n) if t.dist == "uniform" else rng.normal(0.0, t.width, n)
            for t in tols]
    return np.column_stack(cols) if cols else np.zeros((n, 0))


# ------------------------------------------------------------------------------------------ the cycle
@dataclass(frozen=True)
class Cycle:
    """What every design is evaluated along: the nominal design's times ``t`` [s] (N,) and input values
    ``q`` (N, n_inputs), the loads (``gravity`` [m/s^2], ``force`` [N] on the output point times ``force_on``
    (N,), a cutting force's window), links' ``inertias`` replacing their own ({link: Inertia}, SI) and the
    nominal output point's path ``path`` (N, 2) [m]."""

    t: np.ndarray
    q: np.ndarray
    path: np.ndarray
    gravity: tuple = (0.0, 0.0)
    force: tuple = (0.0, 0.0)
    force_on: np.ndarray | float = 1.0
    inertias: dict | None = None


def available(mech, forces_ok: bool = True) -> tuple[str, ...]:
    """The outputs ``mech`` has: the transmission angles need a group that has one (an RRR), the forces a
    statically determinate linkage (``forces_ok``)."""
    out = ["path_deviation"]
    if mech.transmission_angles:
        out += ["transmission_min", "transmission_max"]
    if forces_ok:
        out += list(_FORCES)
    out.append("speed_fluctuation")
    return tuple(out)


def _wanted(mech, outputs) -> list[str]:
    from analytic.applications import forces as F
    p = mech.output_point
    want = {"x" + p, "y" + p}
    if "speed_fluctuation" in outputs:
        want |= {"vx" + p, "vy" + p}
    if {"transmission_min", "transmission_max"} & set(outputs):
        want |= set(mech.transmission_angles.values())
        want |= {c + x for d in _dyads(mech) for x in d[1:] for c in ("x", "y")}
    if set(_FORCES) & set(outputs):
        want |= set(F.wanted(mech))
        if _has_loads(mech):
            from analytic.loads import kinetostatics as K
            want |= set(K.full_wanted(mech))
    return sorted(want)


def _has_loads(mech) -> bool:
    """Whether the file has ``[[loads]]`` or ``[friction]`` (the forces then go through the loads'
    kinetostatics, :func:`analytic.loads.kinetostatics.solve`, as ``linkage forces`` does)."""
    d = mech.definition
    return bool(getattr(d, "loads", ()) or getattr(d, "friction", None))


def _dyads(mech) -> list[tuple[str, str, str, str]]:
    """(transmission output, P, Q, C) of each group with a transmission angle between links P-C and Q-C."""
    out = []
    for e in mech.geometry.elements:
        name = mech.transmission_angles.get(e["point"])
        if name and isinstance(e.get("from"), (tuple, list)) and len(e["from"]) == 2:
            out.append((name, e["from"][0], e["from"][1], e["point"]))
    return out


def _transmission_range(mech, sol) -> tuple[np.ndarray, np.ndarray]:
    """(min, max) over the cycle and every transmission angle [rad], (K,) each. The angle is folded into
    [0, pi/2]: where the links' dot product changes sign between samples the angle passes pi/2, which is then
    its maximum exactly (not the nearest sample's value: a kink that sampling would blur into a false rate);
    likewise 0 where their cross product changes sign."""
    lo, hi = [], []
    dyads = {d[0]: d for d in _dyads(mech)}
    for name in mech.transmission_angles.values():
        mu = sol[name]
        lo_k, hi_k = np.min(mu, axis=1), np.max(mu, axis=1)
        if name in dyads:
            _, p, q, c = dyads[name]
            ux, uy = sol["x" + c] - sol["x" + p], sol["y" + c] - sol["y" + p]
            vx, vy = sol["x" + c] - sol["x" + q], sol["y" + c] - sol["y" + q]
            dot, det = ux * vx + uy * vy, ux * vy - uy * vx
            hi_k = np.where(np.any(dot > 0, axis=1) & np.any(dot < 0, axis=1), 0.5 * np.pi, hi_k)
            lo_k = np.where(np.any(det > 0, axis=1) & np.any(det < 0, axis=1), 0.0, lo_k)
        lo.append(lo_k)
        hi.append(hi_k)
    return np.min(lo, axis=0), np.max(hi, axis=0)


def evaluate_chunk(job):
    """One chunk of designs: ``job`` = (mechanism or :func:`analytic.applications.studies.recipe`, {name: (K,)
    values in file units}, :class:`Cycle`, outputs, keep_paths). Returns ({output: (K,)}, reasons (K
    strings, "" where the design assembled), paths (K, N, 2) [m] or None); a failed design's outputs are
    NaN."""
    from analytic import mass
    from analytic.applications import forces as F
    from analytic.applications.studies import rebuild
    from analytic.solver import batch
    base, chunk, cycle, outputs, keep_paths = job
    base = rebuild(base)
    designs = batch.resolve(base, chunk)
    k, n = designs.count, cycle.t.size
    _, qd, qdd = batch.drive(designs, np.broadcast_to(cycle.t, (k, n)))
    q = np.broadcast_to(cycle.q, (k,) + cycle.q.shape)
    sol = batch.solve(designs, q, qd, qdd, outputs=_wanted(base, outputs))
    reasons = list(designs.reasons)
    bad = sol.failed >= 0
    first = np.argmax(bad, axis=1)
    for i in np.flatnonzero(designs.valid & bad.any(axis=1)):
        j = int(first[i])
        value = q[i, j, 0]
        at = f"{math.degrees(value):.4g}deg" if base.inputs[0].angular else f"{value:.6g} m"
        reasons[i] = f"{sol.labels[int(sol.failed[i, j])]} cannot assemble at {base.inputs[0].q}={at}"
    ok = np.array([not r for r in reasons])
    p = base.output_point
    x, y = sol["x" + p], sol["y" + p]
    out: dict[str, np.ndarray] = {}
    with np.errstate(invalid="ignore", divide="ignore"):
        if "path_deviation" in outputs:
            out["path_deviation"] = np.max(np.hypot(x - cycle.path[:, 0], y - cycle.path[:, 1]), axis=1)
        if {"transmission_min", "transmission_max"} & set(outputs):
            out["transmission_min"], out["transmission_max"] = _transmission_range(base, sol)
        if "speed_fluctuation" in outputs:
            speed = np.hypot(sol["vx" + p], sol["vy" + p])
            # the mean over the run's interval, each instant once (the closed run's last sample repeats its
            # first: a plain mean counted it twice, 0.28 % high on the slider-crank at 361 samples)
            # the extremes refined between samples (a parabola through the sample and its neighbours: the
            # peak's rate with r on the slider-crank was 2 % low at 361 samples, its position moving in steps)
            speed_max, speed_min = _extreme(speed, 1.0), _extreme(speed, -1.0)
            out["speed_fluctuation"] = (speed_max - speed_min) / closed_mean(speed, axis=1)
    if set(_FORCES) & set(outputs):
        torque, joint = np.full(k, np.nan), np.full(k, np.nan)
        loaded = _has_loads(base)
        if loaded:                                           # the file's loads and friction, as forces applies them
            from analytic import loads as AL
            from analytic.loads import kinetostatics as K
        names = K.full_wanted(base) if loaded else F.wanted(base)
        for i in np.flatnonzero(ok):
            try:
                mech = base.with_values(**{name: float(v[i]) for name, v in chunk.items()})
                model = mass.model(mech, cycle.inertias)
                design = {name: sol[name][i] for name in names}
                if loaded:
                    f = K.solve(mech, cycle.q, qd[i], qdd[i], cycle.t, model, AL.resolve(mech), cycle.gravity,
                                cycle.force, cycle.force_on, sol=design).forces
                else:
                    f = F.solve(mech, cycle.q, qd[i], qdd[i], model, cycle.gravity, cycle.force, cycle.force_on,
                                sol=design)
            except ParameterError as exc:                    # this design's own checks, or its statics
                reasons[i] = str(exc)
                continue
            if F.singular_samples(f).any():
                reasons[i] = "a singular pose: its joint forces are unbounded"
                continue
            torque[i] = max(float(np.max(np.abs(d))) for d in f.drives.values())
            joint[i] = float(np.max(f.magnitude())) if len(f.joints) else 0.0
        out["peak_torque"], out["peak_joint_force"] = torque, joint
    values = {o: np.asarray(out[o], dtype=float).copy() for o in outputs}
    for i in range(k):
        if not reasons[i] and not all(math.isfinite(values[o][i]) for o in outputs):
            what = ", ".join(o for o in outputs if not math.isfinite(values[o][i]))
            reasons[i] = f"{what} not finite (a degenerate pose)"
    failed = np.array([bool(r) for r in reasons], dtype=bool)
    for o in outputs:
        values[o][failed] = np.nan
    paths = None
    if keep_paths:
        paths = np.stack([x, y], axis=-1)
        paths[failed] = np.nan
    return values, tuple(reasons), paths


def evaluate(base, values: dict[str, np.ndarray], cycle: Cycle, outputs, mapper=None, keep_paths=False,
             progress=None):
    """Every design of ``values`` ({name: (K,)} file units) along ``cycle``, in chunks of CHUNK, through
    ``mapper`` (an ordered ``map``; None: in this process); ``progress(designs done)`` after each chunk.
    Returns as :func:`evaluate_chunk`, for all K."""
    from analytic.applications.studies import recipe
    k = len(next(iter(values.values())))
    starts = range(0, k, CHUNK)
    outputs = tuple(outputs)
    if mapper is None:
        jobs = ((base, {n: v[s:s + CHUNK] for n, v in values.items()}, cycle, outputs, keep_paths) for s in starts)
        done = map(evaluate_chunk, jobs)
    else:
        r = recipe(base)
        done = mapper(evaluate_chunk, [(r, {n: v[s:s + CHUNK] for n, v in values.items()}, cycle, outputs,
                                        keep_paths) for s in starts])
    results = []
    for s, chunk_result in zip(starts, done):
        results.append(chunk_result)
        if progress is not None:
            progress(min(s + CHUNK, k))
    out = {o: np.concatenate([r[0][o] for r in results]) for o in outputs}
    reasons = tuple(x for r in results for x in r[1])
    paths = np.concatenate([r[2] for r in results]) if keep_paths else None
    return out, reasons, paths


def _designs(base, tols, deltas: np.ndarray) -> dict[str, np.ndarray]:
    """{name: nominal + deviation} for each row of ``deltas`` (file units)."""
    return {t.name: float(base.values[t.name]) + deltas[:, j] for j, t in enumerate(tols)}


def rates(base, tols, cycle: Cycle, outputs, mapper=None):
    """The nominal outputs and their exact rates by central differences: (nominal {output: value}, rates
    {output: (D,)} per file unit of each parameter, path rates (D, N, 2) [m per file unit]). Raises
    ParameterError where the nominal design or a neighbour does not assemble (a tolerance cannot be
    linearised at a design on the edge of assembly)."""
    d = len(tols)
    h = np.array([STEP * t.std for t in tols])
    deltas = np.zeros((2 * d + 1, d))
    for j in range(d):
        deltas[1 + 2 * j, j], deltas[2 + 2 * j, j] = h[j], -h[j]
    values, reasons, paths = evaluate(base, _designs(base, tols, deltas), cycle, outputs, mapper, keep_paths=True)
    if reasons[0]:
        raise ParameterError(f"the nominal {base.name} fails: {reasons[0]}")
    for j in range(d):
        for r in reasons[1 + 2 * j: 3 + 2 * j]:
            if r:
                raise ParameterError(f"--tol {tols[j].name}: a step of {h[j]:.3g} from the nominal design fails "
                                     f"({r}): the nominal design is at the edge of assembly")
    nominal = {o: float(values[o][0]) for o in outputs}
    out = {o: np.array([(values[o][1 + 2 * j] - values[o][2 + 2 * j]) / (2 * h[j]) for j in range(d)])
           for o in outputs}
    jac = np.stack([(paths[1 + 2 * j] - paths[2 + 2 * j]) / (2 * h[j]) for j in range(d)]) if d else None
    return nominal, out, jac


# ------------------------------------------------------------------------------------------ Sobol
def _problem(tols) -> dict:
    return {"num_vars": len(tols), "names": [t.name for t in tols],
            "bounds": [[-t.width, t.width] if t.dist == "uniform" else [0.0, t.width] for t in tols],
            "dists": ["unif" if t.dist == "uniform" else "norm" for t in tols]}


def saltelli(tols, base_n: int, seed: int) -> np.ndarray:
    """The Saltelli design of deviations for first-order and total indices (SALib, scrambled Sobol
    sequence): shape (base_n (D + 2), D), file units; ``base_n`` a power of 2."""
    from SALib.sample import sobol as sample
    return sample.sample(_problem(tols), base_n, calc_second_order=False, scramble=True, seed=seed)


def sobol_indices(tols, y: np.ndarray, seed: int):
    """First-order and total Sobol indices from the outputs ``y`` of :func:`saltelli`'s design. A block of
    the design (the D + 2 rows that share a base point) with a failed (NaN) row is dropped whole, so the
    estimators keep their structure. Returns ({name: {"S1", "ST", "S1_conf", "ST_conf"}} or None where too
    few blocks are left or the output does not vary, blocks dropped)."""
    from SALib.analyze import sobol as analyze
    d = len(tols)
    blocks = np.asarray(y, dtype=float).reshape(-1, d + 2)
    keep = np.all(np.isfinite(blocks), axis=1)
    dropped = int((~keep).sum())
    if keep.sum() < 16 or np.ptp(blocks[keep]) == 0:
        return None, dropped
    r = analyze.analyze(_problem(tols), blocks[keep].ravel(), calc_second_order=False, seed=seed)
    out = {t.name: {"S1": float(r["S1"][j]), "ST": float(r["ST"][j]), "S1_conf": float(r["S1_conf"][j]),
                    "ST_conf": float(r["ST_conf"][j])} for j, t in enumerate(tols)}
    return out, dropped


# ------------------------------------------------------------------------------------------ analysis
@dataclass(frozen=True)
class Summary:
    """One output's spread (SI): the nominal value, the Monte Carlo mean, standard deviation and 5th/95th
    percentiles (over the designs that assembled), the first-order standard deviation, the rates dy/dp
    (per file unit of each parameter; for ``path_deviation``, which is 0 at the nominal design with no
    derivative there, max_u |dP(u)/dp|: the deviation per unit of that parameter alone), each tolerance's
    first-order share of the variance, and the Sobol indices ({param: {S1, ST, S1_conf, ST_conf}}) when
    asked."""

    nominal: float
    mean: float
    std: float
    p05: float
    p95: float
    first_order_std: float
    rates: dict
    shares: dict
    sobol: dict | None = None


@dataclass(frozen=True)
class Result:
    """A tolerance analysis: the tolerances, the Monte Carlo draws ``deltas`` (N, D) and outputs ``values``
    ({output: (N,)}, NaN where failed), why each failed design failed (``reasons``), the summaries, with
    Sobol indices the number of designs evaluated for them and of blocks dropped for failures, and the
    linearised model's outputs over the same draws (``linearised``: {output: (N,)}, SI)."""

    mechanism: str
    tolerances: tuple
    outputs: tuple
    seed: int
    deltas: np.ndarray
    values: dict
    reasons: tuple
    summaries: dict
    sobol_evaluations: int = 0
    sobol_dropped: int = 0
    linearised: dict = field(default_factory=dict)

    @property
    def samples(self) -> int:
        return int(self.deltas.shape[0])

    @property
    def failed(self) -> int:
        return sum(1 for r in self.reasons if r)


def _linearised_deviation(jac: np.ndarray, deltas: np.ndarray, block: int = 4096) -> np.ndarray:
    """max_u |J(u) d| for each row d of ``deltas`` (K, D), with the path rates ``jac`` (D, N, 2): the path
    deviation of the linearised model [m], ``block`` draws at a time (bounds the (2, N, block) temporary)."""
    out = np.empty(deltas.shape[0])
    for s in range(0, deltas.shape[0], block):
        moved = np.einsum("jnc,kj->cnk", jac, deltas[s:s + block])
        out[s:s + block] = np.max(np.hypot(moved[0], moved[1]), axis=0)
    return out


def _extreme(y: np.ndarray, sign: float) -> np.ndarray:
    """The largest (``sign`` 1) or smallest (-1) value of each row of ``y`` (K, N), refined by the parabola
    through the extreme sample and its two neighbours where it is interior and the three bend its way (its
    vertex lies between the neighbours then); a kink (a speed's zero) is left at its sample."""
    z = sign * y
    k = np.nanargmax(np.where(np.isfinite(z), z, -np.inf), axis=1)
    rows = np.arange(y.shape[0])
    best = z[rows, k]
    inner = (k > 0) & (k < y.shape[1] - 1)
    a = z[rows, np.clip(k - 1, 0, None)]
    b = z[rows, np.clip(k + 1, None, y.shape[1] - 1)]
    bend = a + b - 2 * best                                 # < 0 where the three curve down round the peak
    with np.errstate(invalid="ignore", divide="ignore"):
        vertex = best - (b - a) ** 2 / (8 * bend)
        smooth = inner & (bend < 0) & np.isfinite(vertex) & (np.abs(b - a) < -bend)
    return sign * np.where(smooth, vertex, best)


def _stats(v: np.ndarray) -> tuple[float, float, float, float]:
    v = v[np.isfinite(v)]
    if v.size == 0:
        return (math.nan,) * 4
    std = float(np.std(v, ddof=1)) if v.size > 1 else 0.0
    return float(np.mean(v)), std, float(np.percentile(v, 5)), float(np.percentile(v, 95))


def sobol_base(samples: int) -> int:
    """The Saltelli design's base size for ``samples``: the power of 2 >= samples (at least 16)."""
    return 1 << max(4, math.ceil(math.log2(samples)))


def analyse(base, tols, cycle: Cycle, outputs, samples: int = 1000, seed: int = 1, sobol: bool = False,
            mapper=None, progress=None) -> Result:
    """Monte Carlo, first-order propagation and (``sobol``) Sobol indices of ``outputs`` of ``base`` under
    the tolerances ``tols`` along ``cycle``. The draws depend only on ``seed``: the same answer for any
    ``mapper``. ``progress(done, total)``: designs evaluated so far. See the module docstring for what each
    estimate is."""
    tols = tuple(tols)
    outputs = tuple(outputs)
    if not tols:
        raise ParameterError("give at least one --tol NAME=±V")
    names = [t.name for t in tols]
    if len(set(names)) != len(names):
        twice = next(n for n in names if names.count(n) > 1)
        raise ParameterError(f"--tol {twice} is given twice; give each parameter's tolerance once")
    if not (isinstance(samples, int) and 2 <= samples <= 1_000_000):
        raise ParameterError(f"--samples {samples!r} must be an integer in 2..1000000")
    d = len(tols)
    total = 2 * d + 1 + samples + (sobol_base(samples) * (d + 2) if sobol else 0)

    def step(offset):
        return None if progress is None else (lambda done: progress(offset + done, total))
    nominal, rate, jac = rates(base, tols, cycle, outputs, mapper)
    deltas = draw(tols, samples, seed)
    values, reasons, _ = evaluate(base, _designs(base, tols, deltas), cycle, outputs, mapper,
                                  progress=step(2 * d + 1))
    sigma = np.array([t.std for t in tols])
    linearised = {}
    summaries = {}
    sob: dict[str, dict | None] = {o: None for o in outputs}
    evaluations = dropped = 0
    if sobol:
        x = saltelli(tols, sobol_base(samples), seed)
        evaluations = x.shape[0]
        y, _, _ = evaluate(base, _designs(base, tols, x), cycle, outputs, mapper, progress=step(2 * d + 1 + samples))
        for o in outputs:
            sob[o], dropped_o = sobol_indices(tols, y[o], seed)
            dropped = max(dropped, dropped_o)
    for o in outputs:
        if o == "path_deviation":
            lin = _linearised_deviation(jac, deltas)
            linearised[o] = lin
            fo = float(np.std(lin, ddof=1)) if lin.size > 1 else 0.0
            rate[o] = np.max(np.hypot(jac[..., 0], jac[..., 1]), axis=1)   # one parameter alone: |d| max_u |J_i|
            contrib = rate[o] * sigma
        else:
            linearised[o] = nominal[o] + deltas @ rate[o]
            contrib = np.abs(rate[o]) * sigma
            fo = float(math.sqrt(np.sum(contrib ** 2)))
        variance = float(np.sum(contrib ** 2))
        shares = {t.name: (float(c * c / variance) if variance > 0 else 0.0) for t, c in zip(tols, contrib)}
        rates_o = {t.name: float(r) for t, r in zip(tols, rate[o])}
        summaries[o] = Summary(nominal[o], *_stats(values[o]), fo, rates_o, shares, sob[o])
    return Result(base.name, tols, outputs, seed, deltas, values, reasons, summaries, evaluations, dropped,
                  linearised)
