"""Batch over designs on the compiled path (analytic/solver/jit.py ``solve_designs``: one numbers table with a
design axis, each thread solving a run of one design's samples) against the numpy path solving each design
on its own (``Mechanism.with_values`` + ``solve`` with LINKAGE_JIT=0): every library mechanism whose kinds
have compiled rows, designs scattered so some do not assemble everywhere, sample counts that are not a
multiple of a chunk."""

import math

import numpy as np
import pytest

import analytic
from analytic import ParameterError
from analytic.solver import batch
from analytic.solver import jit

pytestmark = pytest.mark.skipif(not jit.AVAILABLE, reason="numba is not installed (pip install -e '.[jit]')")

COMPILED = [n for n in analytic.names() if jit.supports(analytic.load(n).solving_geometry)]
K, N = 6, 1201           # 1201 = 2 chunks of 512 + a tail: the chunks of one design never take the next one's
RTOL = 1e-12             # the two paths' rounding (polynomial sin/cos/atan2 within 2 ulp) x 1/sin near a fold


def _scatter(mech, k, seed):
    """Up to three length parameters of ``mech`` scattered by 3 % (seeded), the first design unchanged."""
    rng = np.random.default_rng(seed)
    names = [p for p, kind in mech.definition.parameter_kind.items() if kind == "length"][:3]
    return {p: mech.values[p] * np.r_[1.0, 1 + 0.03 * rng.standard_normal(k - 1)] for p in names}


def _scale(mech, sol, name, omega):
    """What an output's error is judged against: its peak, a point's over both coordinates (one can be zero
    to rounding: a straight-line path), never less than the motion's own scale (L, L Omega, L Omega^2 for
    positions, velocities, accelerations; Omega, Omega^2 for rates: an output that is zero by construction,
    the trammel rod's alpha, is rounding either way); pi for an angle."""
    if name.startswith("phi"):
        return math.pi
    L = mech.size
    floors = (("dds", L * omega ** 2), ("ds", L * omega), ("s", L), ("omega", omega), ("alpha", omega ** 2),
              ("mu", 1.0), ("vx", L * omega), ("vy", L * omega), ("ax", L * omega ** 2), ("ay", L * omega ** 2),
              ("x", L), ("y", L))
    floor = next((f for prefix, f in floors if name.startswith(prefix)), 0.0)
    own = [name]
    for p in mech.points:
        for u, v in (("x", "y"), ("vx", "vy"), ("ax", "ay")):
            if name in (u + p, v + p):
                own = [u + p, v + p]
    return max(max(np.nanmax(np.abs(sol[k])) for k in own), floor, 1e-300)


def test_every_library_mechanism_with_compiled_rows_is_checked():
    # the PP dyads (scotch_yoke, elliptic_trammel) and the dyad chains: not the numeric groups or gears
    assert {"fourbar", "jansen", "scotch_yoke", "elliptic_trammel", "whitworth"} <= set(COMPILED)


@pytest.mark.parametrize("name", COMPILED)
def test_compiled_batch_equals_numpy_one_design_at_a_time(name, monkeypatch):
    mech = analytic.load(name)
    over = _scatter(mech, K, seed=23)
    designs = batch.resolve(mech, over)
    t = np.broadcast_to(np.linspace(0.0, mech.duration(1.0), N), (K, N))
    monkeypatch.setenv("LINKAGE_JIT", "1")
    got = batch.solve(designs, *batch.drive(designs, t))
    monkeypatch.setenv("LINKAGE_JIT", "0")
    checked = 0
    for i in range(K):
        try:
            one = mech.with_values(**{p: float(v[i]) for p, v in over.items()})
        except ParameterError:
            assert not designs.valid[i]
            continue
        q, qd, qdd = one.drive(t[i])
        ref = one.solve(q, qd, qdd)
        qd = np.asarray(qd, dtype=float).reshape(N, -1)
        omega = max(np.max(np.abs(qd[:, j])) / (1.0 if inp.kind == "crank" else one.size)
                    for j, inp in enumerate(one.inputs))
        np.testing.assert_array_equal(got.failed[i], ref.failed_index, err_msg=f"{name} design {i}")
        arrays = {k: np.asarray(v) for k, v in ref._arrays.items()}
        assert set(arrays) == set(got.arrays)
        for key, a in arrays.items():
            b = got[key][i]
            np.testing.assert_array_equal(np.isnan(a), np.isnan(b), err_msg=f"{name} design {i}: {key}")
            if not np.isfinite(a).any():
                continue
            d = b - a
            if key.startswith("phi"):
                d = np.pi - np.mod(np.pi - d, 2 * np.pi)
            worst = np.nanmax(np.abs(d)) / _scale(one, arrays, key, omega)
            assert worst <= RTOL, (name, i, key, worst)
        checked += 1
    assert checked >= K // 2                              # most scattered designs must assemble
