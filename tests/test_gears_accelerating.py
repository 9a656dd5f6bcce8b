"""Gears at non-zero input acceleration (issue 32: the gears' acceleration terms were tested only at
constant speed): every link's angle, rate and acceleration, and every point's, against five-point finite
differences of the positions the solver gives at neighbouring instants."""

import numpy as np
import pytest

import analytic

KINDS = __import__("pathlib").Path(__file__).resolve().parent / "kinds"
CASES = [(str(KINDS / "gear.toml"), {}), (str(KINDS / "gear__planetary.toml"), {}),
         (str(KINDS / "gear__differential.toml"), {}), (str(KINDS / "gear__rocker.toml"), {}),
         ("geared_five_bar", {"alpha2": 7.0}), ("planetary_linkage", {"alpha1": 5.0})]


def _five_point(f, h):
    return (f[0] - 8 * f[1] + 8 * f[3] - f[4]) / (12 * h)


@pytest.mark.parametrize("name, values", CASES, ids=[c[0].rsplit("/", 1)[-1] for c in CASES])
def test_gear_link_rates_and_accelerations_match_finite_differences(name, values):
    m = analytic.load(name)
    m = m.with_values(**values) if values else m
    assert any(i.motion.accel != 0 for i in m.inputs), "the run must accelerate"
    T = m.duration(1.0)
    t = np.linspace(0.05 * T, 0.95 * T, 37)
    h = T / 4000
    sols = [m.solve_at(t + k * h)[1] for k in (-2, -1, 0, 1, 2)]
    mid = sols[2]
    assert mid.valid.all()
    checked = 0
    for link in m.links:
        for d, dd in (("phi", "omega"), ("omega", "alpha")):
            if d + link not in mid or dd + link not in mid:
                continue
            series = [np.unwrap(np.asarray(s[d + link])) if d == "phi" else np.asarray(s[d + link]) for s in sols]
            fd = _five_point(series, h)
            ref = np.asarray(mid[dd + link])
            scale = max(float(np.max(np.abs(ref))), 1.0)
            # five-point differences at h = T/4000: truncation ~ h^4 f^(5) (1e-10 of the scale) and rounding
            # ~ eps f / h (1e-12 x 4000 / (2 pi)); 1e-6 of the scale bounds both, far below a missing alpha term
            assert np.max(np.abs(fd - ref)) <= 1e-6 * scale, (link, dd)
            checked += 1
    assert checked >= 2 * len(m.links) - 2

