"""The two defects issue 27 found: the slider-crank counterweight fitted over samples holding the start angle
twice, and the motor run of near-massless links beside a large flywheel."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest


def linkage(*args):
    return subprocess.run([sys.executable, "-m", "sim", *map(str, args)], capture_output=True, text=True, timeout=600)


@pytest.mark.parametrize("samples", [37, 361])
def test_slider_crank_counterweight_is_the_textbook_one_at_any_sampling(samples):
    # Least-squares balance of a slider-crank by a counterweight on the crank (radius r, opposite the pin):
    # the rotating masses at the crank pin (the crank's own moment m1 cx1 / r, the rod's share at B
    # m2 (1 - cx2 / l)) in full plus half the reciprocating mass m_rec (the rod's share at C and the piston):
    # with k of it in the counterweight the primary shaking force is r w^2 ((m_rec - k) cos, -k sin), whose
    # mean square over a turn, ((m_rec - k)^2 + k^2) / 2, is least at k = m_rec / 2. The secondary harmonics
    # are orthogonal to it over whole turns sampled evenly, which the fix restores (the start angle once).
    d = json.loads(linkage("forces", "slider_crank", "--balance", "--samples", samples, "--json").stdout)
    links = d["links"]
    r, l = 0.05, 0.20
    m1, m2, mp = links["1"]["m"], links["2"]["m"], links["piston"]["m"]
    rot = m1 * links["1"]["cx"] / r + m2 * (1 - links["2"]["cx"] / l)
    rec = m2 * links["2"]["cx"] / l + mp
    (w,) = d["balance"]["counterweights"]
    assert w["link"] == "1"
    assert w["m"] * abs(w["at"][0]) == pytest.approx((rot + rec / 2) * r, rel=1e-12)   # rounding of the fit
    assert abs(w["at"][1]) < 1e-15                                    # no sideways offset for a centric crank
