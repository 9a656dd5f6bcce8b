"""The two paths of the general solver give the same numbers: numpy (analytic/solver/kinematics.py, always there)
and the compiled one (analytic/solver/jit.py, with numba; LINKAGE_JIT=1 forces it, 0 turns it off). Every output of every
named mechanism, NaN included where a group cannot assemble; and ``solve(..., outputs=...)`` returns the
same values as the full solve on either path."""

import math

import numpy as np
import pytest

import analytic
from analytic.solver import jit as _jit

CASES = [(name, {}) for name in analytic.names()] + [
    ("fourbar", {"l1": 0.2, "l3": 0.1}),          # a crank that cannot turn fully: NaN over part of the turn
    ("fourbar", {"branch": -1}),
]
N = 3001                                          # not a multiple of a block or chunk: the tails are exercised


def _inputs(mech, seed=11):
    rng = np.random.default_rng(seed)
    k = len(mech.inputs)
    return (rng.uniform(-math.pi, math.pi, (N, k)), rng.normal(0.0, 5.0, (N, k)),
            rng.normal(0.0, 30.0, (N, k)))


def _solve(mech, monkeypatch, jit, *args, **kw):
    monkeypatch.setenv("LINKAGE_JIT", "1" if jit else "0")
    assert _jit.enabled(N) == jit
    return mech.solve(*args, **kw)


def _assert_same(mech, a, b, rtol):
    """Same outputs in the same order, NaN at the same samples, the rest within rtol of the largest
    magnitude of the output (of the vector, for a point's coordinates, velocity and acceleration: one
    component can be zero up to rounding; of every slide's, for a slide's rates); angles within rtol of pi,
    compared modulo 2 pi."""
    assert list(a) == list(b)
    assert np.array_equal(a.failed_index, b.failed_index)
    pair = {}
    for p in mech.points:
        for u, v in (("x", "y"), ("vx", "vy"), ("ax", "ay")):
            pair[u + p] = pair[v + p] = (u + p, v + p)
    for c in ("ds", "dds"):               # a slide at rest (a relieved redundancy) is rounding: judged by all slides'
        for j in mech.slides:
            pair[c + j] = tuple(c + k for k in mech.slides)
    for name in a:
        x, y = np.asarray(a[name]), np.asarray(b[name])
        assert x.shape == y.shape, name
        assert np.array_equal(np.isnan(x), np.isnan(y)), name
        ok = ~np.isnan(x)
        if not ok.any():
            continue
        d = x[ok] - y[ok]
        if name.startswith("phi"):
            d, scale = np.pi - np.mod(np.pi - d, 2 * np.pi), np.pi
        else:
            scale = max(np.nanmax(np.abs(np.asarray(a[k]))) for k in pair.get(name, (name,)))
        assert np.abs(d).max() <= rtol * max(scale, 1e-300), (name, np.abs(d).max() / scale)


@pytest.mark.parametrize("name,values", CASES, ids=[f"{n}-{v}" if v else n for n, v in CASES])
def test_the_compiled_path_equals_numpy(name, values, monkeypatch):
    pytest.importorskip("numba")
    mech = analytic.load(name, **values)
    q, qd, qdd = _inputs(mech)
    ref = _solve(mech, monkeypatch, False, q, qd, qdd)
    jit = _solve(mech, monkeypatch, True, q, qd, qdd)
    _assert_same(mech, ref, jit, 1e-12)
    if values.get("l3") == 0.1:
        assert 0 < (~ref.valid).sum() < N                       # the NaN case is really exercised
        assert ref.first_failure() == jit.first_failure()


@pytest.mark.parametrize("jit", [False, True], ids=["numpy", "jit"])
@pytest.mark.parametrize("name", ["fourbar", "sixbar", "fivebar"])
def test_a_subset_of_outputs_equals_the_full_solve(name, jit, monkeypatch):
    if jit:
        pytest.importorskip("numba")
    mech = analytic.load(name)
    q, qd, qdd = _inputs(mech, seed=3)
    full = _solve(mech, monkeypatch, jit, q, qd, qdd)
    pick = [o for o in full if o.startswith(("x", "ay", "omega", "mu", "s"))][::2] + [mech.outputs[0]]
    part = _solve(mech, monkeypatch, jit, q, qd, qdd, outputs=pick)
    assert set(part) >= {o for o in pick if o in full}
    for o in pick:
        assert np.array_equal(part[o], full[o], equal_nan=True), o
    assert np.array_equal(part.failed_index, full.failed_index)
    none = _solve(mech, monkeypatch, jit, q, qd, qdd, outputs=())
    assert len(none) == 0 and np.array_equal(none.valid, full.valid)


def test_the_jit_switch(monkeypatch):
    monkeypatch.setenv("LINKAGE_JIT", "0")
    assert not _jit.enabled(10**7)
    monkeypatch.setenv("LINKAGE_JIT", "1")
    assert _jit.enabled(1) == _jit.AVAILABLE
    monkeypatch.delenv("LINKAGE_JIT")                   # by default only large solves are compiled
    assert not _jit.enabled(_jit.MIN_SAMPLES - 1)
    assert _jit.enabled(_jit.MIN_SAMPLES) == _jit.AVAILABLE


def test_the_compiled_sin_cos_atan2_are_within_2_ulp_of_numpy():
    numba = pytest.importorskip("numba")
    from analytic.kinds import compiled as C
    _jit.compile_kernel()

    @numba.njit
    def run(x, y, s, c, a):
        for i in range(x.shape[0]):
            s[i], c[i] = C.sincos(x[i])
            a[i] = C.atan2(y[i], x[i])

    rng = np.random.default_rng(5)
    edges = [0.0, -0.0, 1.0, -1.0, 2.0, 1e-310, -1e-310, math.pi / 4, math.pi / 2, math.pi, -math.pi]
    x = np.concatenate([rng.uniform(-10, 10, 200_000), rng.uniform(-1e9, 1e9, 100_000),
                        rng.normal(size=100_000) * np.exp(rng.uniform(-30, 30, 100_000)), np.repeat(edges, 11)])
    y = np.concatenate([rng.normal(size=x.size - 121) * np.exp(rng.uniform(-30, 30, x.size - 121)),
                        np.tile(edges, 11)])
    s, c, a = np.empty_like(x), np.empty_like(x), np.empty_like(x)
    run(x, y, s, c, a)
    small = np.abs(x) <= C.LOSSTH                          # beyond 2^30 the kernel calls the C library
    # sin and cos: to 2 ulp of 1 (absolute: the reduction modulo pi/4 is exact to that)
    assert np.abs(s - np.sin(x))[small].max() <= 2 * np.spacing(1.0)
    assert np.abs(c - np.cos(x))[small].max() <= 2 * np.spacing(1.0)
    ref = np.arctan2(y, x)
    assert np.array_equal(np.signbit(a), np.signbit(ref))      # signed zeros and the +-pi cut as IEEE
    assert np.all(np.abs(a - ref) <= 2 * np.spacing(np.abs(ref)))
    run(np.array([np.nan, 1.0, np.nan]), np.array([1.0, np.nan, np.nan]), s[:3], c[:3], a[:3])
    assert np.isnan(a[:3]).all()                               # NaN in either argument: NaN
