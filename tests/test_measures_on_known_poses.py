"""Reported angles and measures on poses worked by hand (issue 32: a transmission angle outside (0, 90]
deg, or a singularity measure built on the wrong trigonometric function, went unnoticed because only
refusals were tested).

Four-bar (library): A=(0,0), D=(0.3,0), crank AB 0.1, coupler BC 0.3, rocker DC 0.25. At phi1 = 0, B =
(0.1, 0) and |BD| = 0.2: the angle at C between the coupler and the rocker has cos = (0.3^2 + 0.25^2 -
0.2^2) / (2 0.3 0.25) = 0.75. At phi1 = 180 deg, |BD| = 0.4: cos = -0.05, an obtuse angle whose
transmission angle is its supplement. Slider-crank (library): crank 0.05, rod 0.2, no offset; at phi1 = 90
deg B = (0, 0.05) and C lies on the x-axis at sqrt(0.2^2 - 0.05^2): the rod makes cos = sqrt(1 - 1/16) with
the guide.
"""

import math

import numpy as np
import pytest

import analytic
from analytic.applications import figures


def _at(mech, phi):
    return mech.solve(np.array([[phi]]), 1.0, 0.0)


@pytest.mark.parametrize("phi, cos_gamma", [(0.0, 0.75), (math.pi, -0.05)])
def test_fourbar_transmission_angle_and_singularity_by_hand(phi, cos_gamma):
    mech = analytic.load("fourbar")
    sol = _at(mech, phi)
    gamma = math.acos(cos_gamma)
    mu = min(gamma, math.pi - gamma)                    # the transmission angle is the acute one, in (0, 90]
    # closed-form solver against the law of cosines: rounding only (1e-12 rad)
    assert float(sol["muC"][0]) == pytest.approx(mu, abs=1e-12)
    (label, measure), = figures.singularity(mech, sol).items()
    # sin of the angle between the links (zero where they fold), not its cos: sqrt(1 - cos^2)
    assert float(np.ravel(measure)[0]) == pytest.approx(math.sqrt(1 - cos_gamma ** 2), abs=1e-12)


def test_slider_crank_singularity_is_the_rod_guide_cosine():
    mech = analytic.load("slider_crank")
    sol = _at(mech, math.pi / 2)
    (label, measure), = figures.singularity(mech, sol).items()
    # |cos| of the rod's angle to the guide: zero where the rod stands across the guide (the dyad folds)
    assert float(np.ravel(measure)[0]) == pytest.approx(math.sqrt(1 - (0.05 / 0.2) ** 2), abs=1e-12)
    assert float(sol["xC"][0]) == pytest.approx(math.sqrt(0.2 ** 2 - 0.05 ** 2), abs=1e-12)


@pytest.mark.parametrize("name", analytic.names())
def test_every_reported_transmission_angle_lies_in_0_to_90_deg(name):
    """Over a run of every library mechanism, each transmission angle lies in (0, pi/2] where it assembles."""
    mech = analytic.load(name)
    if not mech.transmission_angles:
        pytest.skip(f"{name} reports no transmission angle")
    from sim import service
    a = service.analyze(mech, 361, 1.0, figures=False)
    for point, column in mech.transmission_angles.items():
        mu = np.asarray(a.solution[column], dtype=float)
        mu = mu[np.isfinite(mu)]
        assert mu.size and np.all(mu > 0) and np.all(mu <= math.pi / 2 + 1e-12), (column, mu.min(), mu.max())


@pytest.mark.parametrize("phi, e", [(math.pi / 2, 0.0), (0.0, 0.0), (math.pi / 2, 0.02), (-math.pi / 2, 0.02)])
def test_slider_crank_transmission_angle_is_the_rod_to_the_guides_normal(phi, e):
    # B = r (cos phi, sin phi), C on the line y = e: the rod leans sin(beta) = |r sin phi - e| / l off the
    # guide, so its angle to the guide's normal is 90 deg - beta (90 deg at the dead centres, where it pushes
    # straight along the guide)
    mech = analytic.load("slider_crank", e=e)
    sol = _at(mech, phi)
    beta = math.asin(abs(0.05 * math.sin(phi) - e) / 0.2)
    # closed-form solver against the right triangle: rounding only (1e-12 rad)
    assert float(sol["muC"][0]) == pytest.approx(math.pi / 2 - beta, abs=1e-12)
    (label, measure), = figures.singularity(mech, sol).items()
    assert float(np.ravel(measure)[0]) == pytest.approx(math.sin(math.pi / 2 - beta), abs=1e-12)
