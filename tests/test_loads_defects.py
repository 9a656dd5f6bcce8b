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


ROD_MASSLESS = """
[inertia]
2 = { m = 0, I = 0 }
"""


def test_a_massless_rod_is_a_two_force_member_at_speed(tmp_path):
    # With m = 0 the rod carries no inertia: at 10 turns a second (inertia forces of the crank and the piston
    # are ~5 N) the pin forces at B and C still lie along the rod, equal and opposite.
    import numpy as np
    from pathlib import Path
    src = (Path(__file__).parents[1] / "analytic" / "library" / "slider_crank.toml").read_text()
    p = tmp_path / "sc.toml"
    p.write_text(src.replace('omega1 = "360deg"', 'omega1 = "3600deg"') + ROD_MASSLESS)
    d = json.loads(linkage("forces", p, "--samples", 73, "--json", "--simulate").stdout)
    assert d["links"]["2"]["m"] == 0
    j = {e["name"]: e for e in d["joints"]}
    run = __import__("analytic").load(str(p))
    sol = run.solve(np.array(d["inputs"]["phi1"]))
    ex, ey = np.asarray(sol["xC"]) - np.asarray(sol["xB"]), np.asarray(sol["yC"]) - np.asarray(sol["yB"])
    fb = np.array([j["B"]["Fx"], j["B"]["Fy"]])
    fc = np.array([j["C"]["Fx"], j["C"]["Fy"]])
    peak = float(np.max(np.hypot(*fb)))
    assert peak > 1.0                                                  # the piston's inertia (~5 N)
    # rounding (1e-15 of the peak) in the cross product with the unit rod vector
    assert np.max(np.abs(fb[0] * ey - fb[1] * ex) / np.hypot(ex, ey)) < 1e-10 * peak
    assert np.allclose(fb, fc, atol=1e-10 * peak)                   # B: crank on rod; C: rod on piston
    # MuJoCo needs a mass on the rod: a stand-in of 1e-6 of the others, read back on both sides
    assert d["simulated"]["passed"] is True


def test_massless_links_with_no_flywheel_are_refused_by_dynamics(tmp_path):
    from pathlib import Path
    src = (Path(__file__).parents[1] / "analytic" / "library" / "slider_crank.toml").read_text()
    p = tmp_path / "sc.toml"
    p.write_text(src + "\n[inertia]\n1 = { m = 0, I = 0 }\n2 = { m = 0, I = 0 }\npiston = { m = 0, I = 0 }\n")
    r = linkage("dynamics", p, "--motor", "2,150rpm")
    assert r.returncode == 2 and "reduced inertia vanishes" in r.stderr and "--flywheel" in r.stderr, r.stderr
