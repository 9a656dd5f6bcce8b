"""A profile evaluates every sample in one pass (analytic.laws.Compiled: each shape as a polynomial and a sine,
pieces found by one search; long runs of one piece a slice at a time) -- against the segment-by-segment
evaluation through each shape's own closed forms (``Profile.at_segments``, :func:`analytic.laws.shape`), which
shares none of the pieces' coefficients, over every shape, both evaluation paths and several cycles."""

from __future__ import annotations

import numpy as np
import pytest

from analytic import laws


def _profile(seed):
    rng = np.random.default_rng(seed)
    return laws.Profile(tuple(laws.Segment(s, float(rng.uniform(0.1, 1.0)),
                                           0.0 if s == "dwell" else float(rng.uniform(-2.0, 2.0)))
                              for s in rng.permutation(laws.SHAPES)))


@pytest.mark.parametrize("seed", [0, 1])
@pytest.mark.parametrize("how", ["gather", "runs", "shuffled", "boundaries"])
def test_one_pass_equals_segment_by_segment(seed, how):
    law = _profile(seed)
    T = law.duration
    rng = np.random.default_rng(seed + 10)
    t = {"gather": np.linspace(0.0, T, 361),                      # below laws.RUNS: the gather
         "runs": np.linspace(-T, 2.5 * T, 20_001),                 # time order, several cycles: the runs
         "shuffled": rng.uniform(-T, 3 * T, 5000),                 # no runs: the gather at many samples
         "boundaries": np.r_[law.starts, law.starts + T]}[how]     # exactly at each segment's start
    fast, ref = law.at(t), law.at_segments(t)
    for k, (a, b) in enumerate(zip(fast, ref)):
        scale = np.max(np.abs(b))
        # two closed forms of one law (monomials vs nested shapes); the 7th-degree polynomial's jerk cancels
        # terms of ~8400 h/T^3 to its peak: rounding ~1e-13 of the peak
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * scale, err_msg=f"derivative {k}")
    q, v, a, j = law.at(t, jerk=False)
    assert j is None
    np.testing.assert_allclose(a, ref[2], rtol=0, atol=1e-12 * np.max(np.abs(ref[2])))   # as above


def test_both_paths_are_taken(monkeypatch):
    law = _profile(0)
    calls = []
    runs = laws.Compiled._runs
    monkeypatch.setattr(laws.Compiled, "_runs", lambda self, *a: calls.append(1) or runs(self, *a))
    law.at(np.linspace(0.0, law.duration, 361))
    assert calls == []                               # few samples: the gather
    law.at(np.linspace(0.0, law.duration, 20_001))
    assert calls == [1]                              # many in time order: the runs
