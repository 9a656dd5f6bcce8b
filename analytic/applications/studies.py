"""Parameter studies (seed 003): families of five-bar output paths and speeds, and four-bar coupler curves,
computed for whole grids of parameter sets at once.

Each parameter set is one row; the samples of its period are the columns, so every closed form runs on
(rows, samples) arrays. Rows are processed in chunks to bound memory. A row that cannot be assembled
(B and C meeting in the five-bar, a crank that cannot turn in the four-bar, a length <= 0) is reported
invalid with its reason, never raised.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, fields, replace
from fractions import Fraction
from types import SimpleNamespace

import numpy as np

from analytic.applications.averages import closed_mean
from analytic.closed_forms import fivebar
from analytic.closed_forms import fourbar
from analytic._common import ParameterError

__all__ = ["grid", "common_period", "sweep", "CHUNK"]

CHUNK = 256
MAX_COMBOS = 100_000
"""Largest sweep grid evaluated without an explicit yes (about a minute of work)."""
"""Parameter sets per chunk: 256 x 360 samples x ~40 temporaries of 8 bytes = ~30 MB at most."""
MAX_DENOMINATOR = 64
"""A speed ratio is taken as the nearest fraction p/q with q <= 64 to find the common period."""


def grid(base, vary: dict[str, list[float]]) -> list[dict[str, float]]:
    """Every combination of the varied values (the first parameter varies slowest)."""
    names = [f.name for f in fields(base)]
    for name in vary:
        if name not in names:
            raise ParameterError(f"--vary {name}: not a {type(base).__name__} parameter; valid names: {', '.join(names)}")
        if not vary[name]:
            raise ParameterError(f"--vary {name}: no values")
    keys = list(vary)
    return [dict(zip(keys, map(float, combo))) for combo in itertools.product(*(vary[k] for k in keys))]


def common_period(omega_a: float, omega_b: float) -> tuple[float, int, int]:
    """The shortest time [s] after which both cranks are back where they started, and the turns each
    makes in it: T = q * 2 pi/|omega_a| = p * 2 pi/|omega_b| with |omega_b/omega_a| ~ p/q."""
    if omega_a == 0 and omega_b == 0:
        raise ParameterError("omega2=omega4=0: neither crank turns")
    if omega_a == 0 or omega_b == 0:
        w = omega_a or omega_b
        return 2 * math.pi / abs(w), int(omega_a != 0), int(omega_b != 0)
    ratio = Fraction(abs(omega_b / omega_a)).limit_denominator(MAX_DENOMINATOR)
    p, q = ratio.numerator, ratio.denominator
    return q * 2 * math.pi / abs(omega_a), q, p


@dataclass(frozen=True)
class Row:
    params: dict
    valid: bool
    reason: str
    values: dict


def _path_area(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """|shoelace area| of closed sampled paths, rows of (x, y) [m^2] (self-crossing loops partly cancel)."""
    return 0.5 * np.abs(np.sum(x * np.roll(y, -1, axis=-1) - np.roll(x, -1, axis=-1) * y, axis=-1))


def _stats(x, y, vx, vy) -> dict[str, np.ndarray]:
    speed = np.hypot(vx, vy)
    mean = closed_mean(speed)                         # the samples close the period: its end counted once
    with np.errstate(divide="ignore", invalid="ignore"):
        fluct = (speed.max(axis=-1) - speed.min(axis=-1)) / mean
    return {"x_min": x.min(axis=-1), "x_max": x.max(axis=-1), "y_min": y.min(axis=-1), "y_max": y.max(axis=-1),
            "area": _path_area(x[..., :-1], y[..., :-1]),
            "speed_mean": mean, "speed_min": speed.min(axis=-1), "speed_max": speed.max(axis=-1),
            "fluctuation": fluct}


STATS = ("x_min", "x_max", "y_min", "y_max", "area", "speed_mean", "speed_min", "speed_max", "fluctuation")
"""Per parameter set: the output path's bounding box [m] and enclosed area [m^2], its speed's mean, min and
max [m/s] and fluctuation coefficient (max - min) / mean."""


def _check(cls, params: dict) -> str:
    try:
        cls(**params)
    except ParameterError as exc:
        return str(exc)
    return ""


def sweep(base, vary: dict[str, list[float]], samples: int = 360, keep_paths: int = 0):
    """Evaluate every combination of ``vary`` on top of ``base`` (a FiveBar or FourBar).

    Five-bar: P over the common period of the two cranks; four-bar: E over one crank revolution.
    Returns (rows, paths): ``rows`` a list of :class:`Row` with STATS in ``values``; ``paths`` for the
    first ``keep_paths`` valid rows, each (t, x, y, speed) arrays for plotting.
    """
    if not (isinstance(samples, int) and samples >= 8):
        raise ParameterError(f"--samples {samples!r} must be an integer >= 8")
    combos = grid(base, vary)
    is_five = isinstance(base, fivebar.FiveBar)
    cls = type(base)
    base_params = {f.name: getattr(base, f.name) for f in fields(base)}
    rows: list[Row] = [None] * len(combos)
    paths = []
    for start in range(0, len(combos), CHUNK):
        chunk = combos[start:start + CHUNK]
        full = [{**base_params, **c} for c in chunk]
        reasons = [_check(cls, p) for p in full]
        if not is_five:
            for i, p in enumerate(full):
                if not reasons[i]:
                    lim = fourbar.crank_limits(cls(**p))
                    if not lim.full_turn:
                        reasons[i] = (f"the crank cannot turn fully (limit angles "
                                      f"{', '.join(f'{math.degrees(a):.2f}deg' for a in lim.limit_angles)})")
        ok = [i for i, r in enumerate(reasons) if not r]
        if ok:
            values, chunk_paths = (_five if is_five else _four)([full[i] for i in ok], samples)
            for j, i in enumerate(ok):
                rows[start + i] = Row(chunk[i], True, "", {k: float(v[j]) for k, v in values.items()})
            for j, path in enumerate(chunk_paths):
                if len(paths) < keep_paths:
                    paths.append((chunk[ok[j]], *path))
        for i, r in enumerate(reasons):
            if r:
                rows[start + i] = Row(chunk[i], False, r, {k: float("nan") for k in STATS})
    return rows, paths


def _column(params: list[dict], name: str) -> np.ndarray:
    return np.array([p[name] for p in params], dtype=float)[:, None]


def _five(params: list[dict], samples: int):
    mech = SimpleNamespace(**{k: _column(params, k) for k in ("l1", "l2", "l4", "lp")})
    periods = [common_period(p["omega2"], p["omega4"])[0] for p in params]
    u = np.linspace(0.0, 1.0, samples + 1)[None, :]
    t = np.array(periods)[:, None] * u
    c = {k: _column(params, k) for k in ("phi2_0", "phi4_0", "omega2", "omega4", "alpha2", "alpha4")}
    phi2 = c["phi2_0"] + c["omega2"] * t + 0.5 * c["alpha2"] * t * t
    phi4 = c["phi4_0"] + c["omega4"] * t + 0.5 * c["alpha4"] * t * t
    w2, w4 = c["omega2"] + c["alpha2"] * t, c["omega4"] + c["alpha4"] * t
    a2, a4 = np.broadcast_to(c["alpha2"], t.shape), np.broadcast_to(c["alpha4"], t.shape)
    with np.errstate(invalid="ignore", divide="ignore"):
        st = fivebar._kernel(mech, fivebar._complex, phi2, phi4, w2, w4, a2, a4)
    values = _stats(st["xP"], st["yP"], st["vxP"], st["vyP"])
    values["S_min"] = np.nanmin(st["S"], axis=-1)
    values["period"] = np.array(periods)
    paths = [(t[i], st["xP"][i], st["yP"][i], np.hypot(st["vxP"][i], st["vyP"][i])) for i in range(len(params))]
    return values, paths


def _four(params: list[dict], samples: int):
    mechs = [fourbar.FourBar(**p) for p in params]
    u = np.linspace(0.0, 1.0, samples + 1)[None, :]
    w = _column(params, "omega1")
    t = 2 * math.pi / np.abs(w) * u
    phi = _column(params, "phi1_0") + w * t
    # FourBar carries scalars: one closed-form call per set over its samples, the sets stacked.
    states = [fourbar.solve(m, phi[i], m.omega1, 0.0) for i, m in enumerate(mechs)]
    st = {k: np.stack([getattr(s, k) for s in states]) for k in ("xE", "yE", "vxE", "vyE", "mu")}
    values = _stats(st["xE"], st["yE"], st["vxE"], st["vyE"])
    values["mu_min"] = st["mu"].min(axis=-1)
    values["period"] = (2 * math.pi / np.abs(w))[:, 0]
    paths = [(t[i], st["xE"][i], st["yE"][i], np.hypot(st["vxE"][i], st["vyE"][i])) for i in range(len(params))]
    return values, paths


def period_of(mech) -> float:
    """The shortest time [s] after which every crank input is back where it started (one turn of the
    first input for a single input)."""
    cranks = [i.motion.rate for i in mech.inputs if i.spec.periodic and i.motion.rate != 0]
    if len(cranks) < 2:
        return mech.duration(1.0)
    T = common_period(cranks[0], cranks[1])[0]
    for w in cranks[2:]:
        T = common_period(2 * math.pi / T, w)[0]
    return T


def _periods(designs) -> tuple[np.ndarray, list[str]]:
    """Each design's period [s] (:func:`period_of`), computed once per distinct set of motion laws, and
    per design why it has none ("" where it has one; NaN period there)."""
    from analytic.solver import batch
    k = designs.count
    out, why = np.full(k, np.nan), [""] * k
    table = batch.motion_table(designs).reshape(k, -1)
    ok = np.flatnonzero(designs.valid)
    if ok.size == 0:
        return out, why
    rows, inverse = np.unique(table[ok], axis=0, return_inverse=True)
    for r, row in enumerate(rows):
        try:
            T = _period_of_motions(designs.base, batch.motions(designs, row.reshape(-1, 3)))
            reason = ""
        except ParameterError as exc:
            T, reason = float("nan"), str(exc)
        members = ok[inverse.ravel() == r]
        out[members] = T
        for i in members:
            why[i] = reason
    return out, why


def _period_of_motions(base, ms) -> float:
    """:func:`period_of` for input motion laws ``ms`` of ``base``'s inputs."""
    cranks = [m.rate for m, i in zip(ms, base.inputs) if i.spec.periodic and m.rate != 0]
    if len(cranks) < 2:
        first = base.inputs[0]
        turn = first.spec.turn(ms[0].rate)
        return float(ms[0].duration(1.0, turn))
    T = common_period(cranks[0], cranks[1])[0]
    for w in cranks[2:]:
        T = common_period(2 * math.pi / T, w)[0]
    return float(T)


DESIGNS_PER_CHUNK = 2048
"""Designs evaluated per batch call in :func:`sweep_mechanism` (with 361 samples: ~0.7 M samples); also the
unit of work handed to a worker process."""


def recipe(base) -> tuple:
    """What rebuilds ``base`` in another process (a built-in's closed form holds a module, which does not
    pickle): (definition, overrides, built-in name or None, rocking range)."""
    return (base.definition, dict(base.overrides), base.name if base.builtin is not None else None, base.rock)


def rebuild(r) -> "object":
    """The mechanism of :func:`recipe` ``r`` (or ``r`` itself when it is one)."""
    if not isinstance(r, tuple):
        return r
    import analytic
    from analytic.mechanism import Mechanism
    definition, overrides, builtin, rock = r
    mech = Mechanism.from_definition(definition, overrides, analytic.BUILTINS[builtin] if builtin else None)
    return replace(mech, rock=rock)


def sweep_mechanism(base, vary: dict[str, list[float]], samples: int = 360, keep_paths: int = 0,
                    progress=None, mapper=None):
    """Evaluate every combination of ``vary`` on top of mechanism ``base`` (any :class:`Mechanism`):
    its output point over the common period of its cranks. Returns (rows, paths) as :func:`sweep`, with
    ``mu_min`` (smallest transmission angle, rad; only for a mechanism with RRR groups) and ``period``
    added to each row's values. The designs are solved many at a time (:mod:`analytic.solver.batch`), in
    chunks of DESIGNS_PER_CHUNK; ``mapper`` (an ordered ``map(fn, items)``, e.g. a process pool's) spreads
    the chunks over workers, the rows coming back in the grid's order. A row is valid only if every sample
    assembled and every figure is finite."""
    if not (isinstance(samples, int) and 8 <= samples <= 100_000):
        raise ParameterError(f"samples={samples!r} must be an integer in 8..100000")
    for name, values in vary.items():
        if name not in base.definition.parameters:
            raise ParameterError(f"{name!r} is not a parameter of {base.name}; parameters: "
                                 f"{', '.join(base.definition.parameter_order)}")
        if not values:
            raise ParameterError(f"{name}: no values to vary")
    keys = list(vary)
    total = math.prod(len(vary[k]) for k in keys)
    mesh = np.meshgrid(*(np.asarray(vary[k], dtype=float) for k in keys), indexing="ij")
    columns = {k: m.ravel() for k, m in zip(keys, mesh)}      # the first parameter varies slowest
    starts = range(0, total, DESIGNS_PER_CHUNK)
    chunks = [{k: c[s:s + DESIGNS_PER_CHUNK] for k, c in columns.items()} for s in starts]
    if mapper is None:
        results = map(sweep_chunk, ((base, c, samples, keep_paths) for c in chunks))
    else:
        r = recipe(base)
        results = mapper(sweep_chunk, [(r, c, samples, keep_paths) for c in chunks])
    rows, paths = [], []
    if progress is not None:
        progress(0, total)
    for start, (r_rows, r_paths) in zip(starts, results):
        rows += r_rows
        paths += r_paths[:max(keep_paths - len(paths), 0)]
        if progress is not None:
            progress(min(start + DESIGNS_PER_CHUNK, total), total)
    return rows, paths


def sweep_chunk(job):
    """One chunk of :func:`sweep_mechanism`: ``job`` = (mechanism or its :func:`recipe`, {name: (k,)
    values}, samples, keep_paths). Returns (rows, up to keep_paths paths of its valid rows)."""
    from analytic.solver import batch
    base, chunk, samples, keep_paths = job
    base = rebuild(base)
    mus = list(base.transmission_angles.values())
    names = STATS + (("mu_min",) if mus else ()) + ("period",)
    p = base.output_point
    want = ["x" + p, "y" + p, "vx" + p, "vy" + p] + mus
    u = np.linspace(0.0, 1.0, samples + 1)
    designs = batch.resolve(base, chunk)
    reasons = list(designs.reasons)
    T, why = _periods(designs)
    for i in np.flatnonzero(designs.valid & ~np.isfinite(T)):
        reasons[i] = why[i]
    t = np.where(np.isfinite(T), T, 1.0)[:, None] * u
    sol = batch.solve(replace(designs, valid=designs.valid & np.isfinite(T)), *batch.drive(designs, t),
                      outputs=want)
    x, y, vx, vy = (sol[k + p] for k in ("x", "y", "vx", "vy"))
    with np.errstate(invalid="ignore", divide="ignore"):
        stats = _stats(x, y, vx, vy)
        if mus:
            stats["mu_min"] = np.min([sol[n] for n in want[4:]], axis=(0, 2))
    stats["period"] = T
    table = np.stack([stats[n] for n in names], axis=1)
    bad = sol.failed >= 0
    first = np.where(bad.any(axis=1), np.argmax(bad, axis=1), -1)     # first sample that failed
    finite = np.all(np.isfinite(table), axis=1)
    keys_ = list(chunk)
    params_rows = np.column_stack([chunk[k] for k in keys_]).tolist()
    table_rows = table.tolist()
    nan_values = {n: float("nan") for n in names}
    rows, paths = [], []
    for i in range(designs.count):
        params = dict(zip(keys_, params_rows[i]))
        if not reasons[i]:
            if first[i] >= 0:
                j = int(first[i])
                reasons[i] = f"{sol.labels[int(sol.failed[i, j])]} cannot close at t={t[i, j]:.4g} s"
            elif not finite[i]:
                what = ", ".join(n for n, v in zip(names, table_rows[i]) if not math.isfinite(v))
                reasons[i] = f"{what} not finite (a degenerate path: the output point does not move?)"
        if reasons[i]:
            rows.append(Row(params, False, reasons[i], dict(nan_values)))
            continue
        rows.append(Row(params, True, "", dict(zip(names, table_rows[i]))))
        if len(paths) < keep_paths:
            paths.append((params, t[i], x[i], y[i], np.hypot(vx[i], vy[i])))
    return rows, paths
