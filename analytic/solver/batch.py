"""Many designs at once: K parameter sets of one mechanism solved over N samples each in vectorised calls.

:func:`resolve` turns K parameter sets (arrays with a leading design axis) into :class:`Designs`: the
geometry of :func:`analytic.format.linkfile.resolve` whose numbers are arrays of shape (K,), checked per design
(finite values, lengths > 0, branches +-1, a built-in's own checks) into a validity mask with the reason
of each invalid design, the reason the one-at-a-time path (:meth:`Mechanism.with_values`) gives. Designs
whose branches differ are kept in separate groups (a branch picks a root: it must be one number per call).
A mechanism with a kind that continues its solution from sample to sample (a numerically solved group,
:attr:`analytic.kinds.base.Kind.continuous`) is resolved and solved design by design: each design's samples
are a path from its own pose, never a continuation of the previous design's.

:func:`solve` evaluates :func:`analytic.solver.kinematics.evaluate` on blocks of designs: each block's geometry
numbers are repeated per sample, so every group function does the same arithmetic as for one design, on
arrays; outputs come back as (K, N) arrays with the same names as :meth:`Mechanism.solve`.

With numba installed (the compiled path, :mod:`analytic.solver.jit`, under the same conditions as
:meth:`Mechanism.solve`'s: every kind with a compiled row, at least ``jit.MIN_SAMPLES`` samples in all), the
blocks of designs go through :func:`analytic.solver.jit.solve_designs` instead: one compiled call per block
whose numbers table has a design axis, each thread solving a run of one design's samples; the numbers
equal numpy's to rounding (tests/test_batch_designs.py).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from analytic.format import expr
from analytic.format import linkfile
from analytic._common import BLOCK, ParameterError, keep_freed_memory
from analytic import kinds
from analytic.mechanism import Mechanism, Motion, block

__all__ = ["Designs", "BatchSolution", "resolve", "drive", "solve", "motions", "motion_table"]

JIT_SAMPLES_PER_CALL = 1 << 20
"""Samples per compiled call over designs (whole designs): bounds its output array while every thread has
many chunks to take."""

SAMPLES_PER_BLOCK = 4 * BLOCK
"""Samples per evaluated block (designs x samples): large enough that numpy's per-call overhead is small
against the arithmetic, small enough that the temporaries stay in cache."""


@dataclass(frozen=True)
class Designs:
    """K designs of one mechanism.

    ``values``: every parameter, shape (K,) (file units; angles rad); ``groups``: (design indices,
    Geometry) pairs, each geometry's numbers of shape (len(indices),) and its branches scalars (with a
    continuous kind: one design per pair, its geometry's numbers scalars);
    ``valid``: (K,) bool; ``reasons``: per design, why it is invalid ("" where valid)."""

    base: Mechanism
    values: dict[str, np.ndarray]
    groups: tuple[tuple[np.ndarray, linkfile.Geometry], ...]
    valid: np.ndarray
    reasons: tuple[str, ...]

    @property
    def count(self) -> int:
        return int(self.valid.size)

    def params(self, k: int) -> dict[str, float]:
        """Design k's parameter values (file units)."""
        return {p: float(v[k]) for p, v in self.values.items()}


@dataclass(frozen=True)
class BatchSolution:
    """Outputs of :func:`solve`: ``arrays`` {name: (K, N)} (names as :meth:`Mechanism.solve`), ``failed``
    (K, N) index of the first element that did not assemble (-1 where all did), ``labels`` the elements'."""

    arrays: dict[str, np.ndarray]
    failed: np.ndarray
    labels: tuple[str, ...]

    def __getitem__(self, name: str) -> np.ndarray:
        return self.arrays[name]

    @property
    def valid(self) -> np.ndarray:
        """(K, N): every element assembled at that sample."""
        return self.failed < 0


# ------------------------------------------------------------------------------------------ resolve
def _evaluate(text: str, values: dict) -> np.ndarray:
    """An expression of :mod:`analytic.format.expr` on arrays (its one evaluator; outside a function's domain:
    NaN, which marks the design invalid)."""
    return expr.evaluate_array(text, values)


def _values(d: linkfile.Definition, overrides: dict[str, np.ndarray], k: int) -> dict[str, np.ndarray]:
    """Every parameter as a (K,) array, as :func:`linkfile.parameter_values` (cycles were refused when the
    file was read)."""
    out: dict[str, np.ndarray] = {}

    def value(p):
        if p not in out:
            raw = d.parameters[p]
            if p in overrides:
                v = overrides[p]
            elif isinstance(raw, (int, float)):
                v = float(raw)
            elif expr.quantity(raw) is not None:
                v = expr.quantity(raw)[0]
            else:
                v = _evaluate(raw, {n: value(n) for n in expr.names_in(raw)})
            out[p] = np.broadcast_to(np.asarray(v, dtype=float), (k,))
        return out[p]

    for p in d.parameter_order:
        value(p)
    return out


def _num(d, v, kind, values, k):
    """A field's value for every design, (K,) [SI]."""
    if isinstance(v, (int, float)):
        x = np.full(k, float(v))
    else:
        q = expr.quantity(v)
        if q is not None:
            if q[1] and kind == "length":
                raise ParameterError(f"{d.source}: {v!r} is an angle where a length is expected")
            x = np.full(k, q[0])
        else:
            x = np.broadcast_to(_evaluate(v, values), (k,))
    return x * d.scale if kind == "length" else x


def _fields(d: linkfile.Definition, values: dict, k: int):
    """Ground and element dicts of (K,) arrays, and a (K,) mask of the designs whose numbers pass
    :func:`linkfile.resolve`'s checks."""
    ok = np.ones(k, dtype=bool)
    ground = {}
    for g, (x, y) in d.ground.items():
        ground[g] = (_num(d, x, "length", values, k), _num(d, y, "length", values, k))
        ok &= np.isfinite(ground[g][0]) & np.isfinite(ground[g][1])
    elements = []
    n_inputs = 0
    for e in d.order:
        kind = kinds.get(e.kind)
        out = {"kind": e.kind, "point": e.point, "places": e.places, "label": e.label}
        if kind.section == "inputs":
            out["input"] = n_inputs
            n_inputs += 1
        for fname, fld in kind.fields.items():
            ftype = fld.type
            v = e.fields[fname]
            if ftype in linkfile.NAMES or ftype in ("camlaw", "outline") or (ftype == "guide" and v is None):
                out[fname] = v                       # names; a cam's law and outline (resolved design by design)
                continue
            if ftype == "slidetable":
                out[fname] = {b: (g, p, _num(d, a, "angle", values, k)) for b, (g, p, a) in v.items()}
                for _, _, a in out[fname].values():
                    ok &= np.isfinite(a)
                continue
            if ftype == "pose":
                out[fname] = {p: (_num(d, x, "length", values, k), _num(d, y, "length", values, k))
                              for p, (x, y) in v.items()}
                for x, y in out[fname].values():
                    ok &= np.isfinite(x) & np.isfinite(y)
                continue
            if ftype == "guide":
                if v.points:
                    out[fname] = {"points": v.points}
                    continue
                through = v.through if isinstance(v.through, str) else tuple(
                    _num(d, c, "length", values, k) for c in v.through)
                angle = _num(d, v.angle, "angle", values, k)
                nums = [angle] + ([] if isinstance(through, str) else list(through))
                out[fname] = {"through": through, "angle": angle}
            elif ftype in ("lengths2", "xy"):
                nums = [_num(d, c, "length", values, k) for c in v]
                out[fname] = tuple(nums)
                if ftype == "lengths2":
                    for c in nums:
                        ok &= c > 0
            elif ftype == "branch":
                b = _num(d, v, "number", values, k)
                ok &= (b == 1.0) | (b == -1.0)
                nums = [b]
                out[fname] = b
            elif ftype == "number":
                x = _num(d, v, "number", values, k)
                nums = [x]
                out[fname] = x
            else:
                x = _num(d, v, "length" if ftype in ("length", "size") else "angle", values, k)
                nums = [x]
                out[fname] = x
                if ftype == "size":
                    ok &= x > 0
            for x in nums:
                ok &= np.isfinite(x)
        kind.resolve_extra(out, d.topology)
        elements.append(out)
    return ground, elements, ok


def _pick(x, idx):
    if isinstance(x, np.ndarray):
        return x[idx]
    if isinstance(x, tuple):
        return tuple(_pick(c, idx) for c in x)
    if isinstance(x, dict):
        return {k: _pick(v, idx) for k, v in x.items()}
    return x


def resolve(base: Mechanism, overrides: dict[str, object]) -> Designs:
    """K designs: ``base`` (its ``--set`` overrides kept) with each parameter of ``overrides`` taking one
    value per design (arrays of shape (K,), file units, angles rad; a scalar applies to all).

    Raises ParameterError for an unknown parameter or arrays of different lengths; a design that cannot be
    built is marked invalid (``Designs.valid``) with the reason :meth:`Mechanism.with_values` gives."""
    d = base.definition
    for name in overrides:
        if name not in d.parameters:
            raise ParameterError(f"{name!r} is not a parameter of {base.name}; parameters: "
                                 f"{', '.join(d.parameter_order)}")
    arrays = {n: np.atleast_1d(np.asarray(v, dtype=float)) for n, v in overrides.items()}
    sizes = {a.size for a in arrays.values() if a.size != 1}
    if len(sizes) > 1:
        raise ParameterError(f"the varied parameters have different numbers of values: {sorted(sizes)}")
    k = sizes.pop() if sizes else 1
    merged = {n: np.full(k, float(v)) for n, v in base.overrides.items()}
    merged.update({n: np.broadcast_to(a.ravel(), (k,)) for n, a in arrays.items()})
    values = _values(d, merged, k)
    ok = np.ones(k, dtype=bool)
    for name, v in values.items():
        ok &= np.isfinite(v)
        if d.parameter_kind.get(name) == "length" and linkfile.is_size(d, name):
            ok &= v > 0
    ground, elements, ok_fields = _fields(d, values, k)
    ok &= ok_fields
    reasons = [""] * k
    if base.builtin is not None:                             # the dedicated model's own checks
        for i in np.flatnonzero(ok):
            try:
                base.builtin.parameters({n: float(v[i]) for n, v in values.items()})
            except ParameterError:
                ok[i] = False
    for i in np.flatnonzero(~ok):                            # the one-at-a-time path's own words
        try:
            base.with_values(**{n: float(values[n][i]) for n in merged})
            reasons[i] = "a parameter or field is not a finite number"
        except ParameterError as exc:
            reasons[i] = str(exc)
    if any(kinds.get(e["kind"]).continuous or kinds.get(e["kind"]).per_design for e in base.geometry.elements):
        return _one_by_one(base, values, merged, ok, reasons)
    # group the designs by their branches (one root per call)
    with_branch = [i for i, e in enumerate(elements) if "branch" in e]
    key = np.stack([elements[i]["branch"] for i in with_branch], axis=1) if with_branch else np.zeros((k, 0))
    key = np.where(ok[:, None], key, 1.0)                    # invalid designs: any branch, never solved
    groups = []
    for row in (np.unique(key, axis=0) if with_branch else np.zeros((1, 0))):
        idx = np.flatnonzero(np.all(key == row, axis=1))
        els = [_pick(e, idx) for e in elements]
        for j, i in enumerate(with_branch):
            els[i]["branch"] = int(row[j])
        geo = linkfile.Geometry({g: _pick(xy, idx) for g, xy in ground.items()}, tuple(els),
                                {n: v[idx] for n, v in values.items()})
        groups.append((idx, geo))
    return Designs(base, {n: np.array(v) for n, v in values.items()}, tuple(groups), ok, tuple(reasons))


def _one_by_one(base: Mechanism, values: dict, merged: dict, ok: np.ndarray, reasons: list) -> Designs:
    """Designs resolved one at a time (a group of its own each, the geometry of :meth:`Mechanism.with_values`,
    whose checks, such as a group's pose at the start, make a design invalid with their message)."""
    groups = []
    for i in np.flatnonzero(ok):
        try:
            mech = base.with_values(**{n: float(values[n][i]) for n in merged})
        except ParameterError as exc:
            ok[i], reasons[i] = False, str(exc)
            continue
        groups.append((np.array([i]), mech.geometry))
    return Designs(base, {n: np.array(v) for n, v in values.items()}, tuple(groups), ok, tuple(reasons))


# ------------------------------------------------------------------------------------------ motion
def motion_table(designs: Designs) -> np.ndarray:
    """(K, n_inputs, 3): each design's (q0, rate, acceleration) per input (crank: rad, rad/s, rad/s^2;
    slider: m, m/s, m/s^2), as its file gives them (a rocking drive is the base's: see :func:`motions`)."""
    k = designs.count
    inputs = _input_elements(designs)
    out = np.empty((k, len(inputs), 3))
    for j, (e_index, kind) in enumerate(inputs):
        names = kinds.get(kind).motion_fields
        for idx, geo in designs.groups:
            e = geo.elements[e_index]
            for c, name in enumerate(names):
                out[idx, j, c] = e[name]
    return out


def motions(designs: Designs, row: np.ndarray) -> tuple[Motion, ...]:
    """The input motion laws of one row of :func:`motion_table` (as :attr:`Mechanism.inputs` gives them,
    a rocking drive kept)."""
    out = [Motion(float(q0), float(rate), float(acc)) if i.motion.law is None else replace(i.motion, q0=float(q0))
           for (q0, rate, acc), i in zip(row, designs.base.inputs)]        # a motion law: the base's
    if designs.base.rock is not None:
        out[0] = replace(out[0], rock=designs.base.rock, q0=designs.base.rock[0])
    return tuple(out)


def drive(designs: Designs, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The inputs' motion at times ``t`` [s] of shape (K, N): (q, qd, qdd) each (K, N, n_inputs), the
    motion law of :class:`Motion` with each design's own q0, rate and acceleration."""
    t = np.asarray(t, dtype=float)
    table = motion_table(designs)
    cols: list[list[np.ndarray]] = []
    for j in range(table.shape[1]):
        q0, rate, acc = (table[:, j, c, None] for c in range(3))
        law = designs.base.inputs[j].motion.law
        if law is not None and not (j == 0 and designs.base.rock is not None):    # the base's motion law
            q, v, a, _ = law.at(t)
            q = q0 + q
            cols.append([q, np.broadcast_to(v, q.shape), np.broadcast_to(a, q.shape)])
        elif j == 0 and designs.base.rock is not None:
            lo, hi = designs.base.rock
            w, amp = np.abs(rate), 0.5 * (hi - lo)
            cols.append([0.5 * (lo + hi) - amp * np.cos(w * t), amp * w * np.sin(w * t),
                         amp * w * w * np.cos(w * t)])
        else:
            cols.append([q0 + rate * t + 0.5 * acc * t * t, rate + acc * t, np.broadcast_to(acc, t.shape)])
    return tuple(np.stack([c[j] for c in cols], axis=-1) for j in range(3))


def _input_elements(designs: Designs):
    return [(i, e["kind"]) for i, e in enumerate(designs.base.geometry.elements)
            if kinds.get(e["kind"]).section == "inputs"]


# ------------------------------------------------------------------------------------------- solve
def _per_sample(x, n: int):
    """A block's geometry numbers (one per design) repeated for each of its n samples."""
    if isinstance(x, np.ndarray):
        return np.repeat(x, n)
    if isinstance(x, tuple):
        return tuple(_per_sample(c, n) for c in x)
    if isinstance(x, dict):
        return {k: _per_sample(v, n) for k, v in x.items()}
    return x


def solve(designs: Designs, q, qd=0.0, qdd=0.0, outputs=None) -> BatchSolution:
    """Every design at its own inputs: ``q``, ``qd``, ``qdd`` of shape (K, N, n_inputs) (or (K, N) for one
    input), broadcast together. ``outputs`` as in :meth:`Mechanism.solve` (None: all). Invalid designs
    are not evaluated: their outputs are NaN and ``failed`` is 0 there.

    Returns
    -------
    BatchSolution
        (K, N) arrays; the same numbers as one :meth:`Mechanism.solve` per design, to rounding.
    """
    base = designs.base
    m = len(base.inputs)
    arrays = [np.asarray(x, dtype=float) for x in (q, qd, qdd)]
    if m == 1:
        arrays = [a[..., None] if not (a.ndim == 3 and a.shape[-1] == 1) else a for a in arrays]
    k = designs.count
    q, qd, qdd = np.broadcast_arrays(*arrays)
    if q.ndim != 3 or q.shape[0] != k or q.shape[-1] != m:
        raise ParameterError(f"give q of shape (K, N, {m}) for K={k} designs of {base.name} ({m} inputs)")
    n = q.shape[1]
    want = None if outputs is None else {base.aliases.get(o, o) for o in outputs}
    extras = want is None or any(x in want for x in base.extra_outputs)
    out: dict[str, np.ndarray] | None = None
    failed = np.zeros((k, n), dtype=np.int64)
    from analytic.solver import jit
    compiled = n > 0 and jit.enabled(k * n) and jit.supports(base.geometry)
    per = max(1, (JIT_SAMPLES_PER_CALL if compiled else SAMPLES_PER_BLOCK) // max(n, 1))
    if k * n > BLOCK:
        keep_freed_memory()
    for idx, geo in designs.groups:
        idx_ok = idx[designs.valid[idx]]
        local = np.flatnonzero(designs.valid[idx])
        for s in range(0, idx_ok.size, per):
            rows, loc = idx_ok[s:s + per], local[s:s + per]
            flat = [a[rows].reshape(-1, m).T for a in (q, qd, qdd)]
            if compiled:
                g = linkfile.Geometry(_pick(geo.ground, loc), tuple(_pick(e, loc) for e in geo.elements), {})
                part, f = jit.solve_designs(g, rows.size, *flat, want)
            else:
                g = linkfile.Geometry(_per_sample(_pick(geo.ground, loc), n),
                                      tuple(_per_sample(_pick(e, loc), n) for e in geo.elements), {})
                with np.errstate(invalid="ignore", divide="ignore"):
                    part, f, _ = block(g, *flat, want, None, extras)
            if out is None:
                out = {name: np.full((k, n), np.nan) for name in part}
            for name, v in part.items():
                out[name][rows] = np.broadcast_to(v, (rows.size * n,)).reshape(rows.size, n)
            failed[rows] = f.reshape(rows.size, n)
    if out is None:                                           # no valid design: names from the base
        with np.errstate(invalid="ignore", divide="ignore"):
            part, _, _ = block(base.geometry, *(np.zeros((m, 1)) for _ in range(3)), want, None, extras)
        out = {name: np.full((k, n), np.nan) for name in part}
    labels = tuple(e["label"] for e in base.geometry.elements)
    return BatchSolution(out, failed, labels)
