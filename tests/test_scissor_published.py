"""A scissor lift's cylinder force against the published scissor-lift relation (issue 37: published numbers).

The relation, for one scissor stage whose bars are crossed at their middles, raised by a horizontal force F
on its rolling foot, holding a payload of weight W with arms of total weight Wa, phi the arms' angle to the
horizontal:

    F = (W + Wa / 2) / tan(phi)

published as the scissor-lift force formula by calculator.academy ("Scissor Lift Force Calculator",
https://calculator.academy/scissor-lift-force-calculator/: "an idealized single-stage scissor mechanism driven
by a horizontal force that changes the base width") and by FIRGELLI Automations ("Scissor Lift Force
Calculation: The Complete Engineering Guide", https://www.firgelliauto.com/blogs/news/scissor-lift-force-
calculation-the-complete-engineering-guide, "F = (W + Wa/2) / tan theta"); Engineers Edge's scissor-lift jack
equations give F = W / tan(phi) without the arms' weight.

* tests/drives/scissor_foot_slider.toml is that configuration: the foot pushed along the ground (a slider,
  its drive the horizontal force): its drive force is the formula's F.
* tests/drives/scissor_cylinder.toml is the same stage raised by a cylinder from a base pin C to bar 1: by
  virtual work the cylinder's force F_c moves through dl while the foot force F would move through dx_B, so
  F_c = F (dx_B / d phi) / (dl / d phi), with dx_B / d phi = -sin(phi) (the foot at x = cos(phi) for 1 m bars)
  and dl / d phi from the pins' positions by hand.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import analytic
from analytic.applications import forces as F
from analytic.mass import Inertia

HERE = Path(__file__).resolve().parent / "drives"
G = 9.81
PAYLOAD, ARM = 200.0, 3.0         # [kg]: the payload at the top pin P; each 1 m bar, its centre at the crossing


def _bar1(cx_payload: float, cx_middle: float) -> Inertia:
    """Bar 1 with the payload at its top end: one body (a static run sees only the weights and where they act)."""
    m = PAYLOAD + ARM
    return Inertia(m=m, cx=(PAYLOAD * cx_payload + ARM * cx_middle) / m, cy=0.0, I=1.0)


def _published(phi):
    return (PAYLOAD * G + 2 * ARM * G / 2) / np.tan(phi)


@pytest.mark.parametrize("x_foot", [0.95, 0.8, 0.6, 0.3])
def test_the_foot_force_is_the_published_formula(x_foot):
    mech = analytic.load(str(HERE / "scissor_foot_slider.toml"))
    q = np.array([x_foot])
    sol = mech.solve(q)
    # bar 1's frame runs from A toward M (its middle at 0.5, its top P at 1.0); bar 2's from B toward M
    inertias = {"bar1": _bar1(1.0, 0.5), "bar2": Inertia(m=ARM, cx=0.5, cy=0.0, I=1.0)}
    f = F.solve(mech, q, 0.0 * q, 0.0 * q, inertias, gravity=(0.0, -G))
    phi = sol["phibar1"][0]
    assert phi == pytest.approx(math.acos(x_foot), rel=1e-12)           # the foot at cos(phi): 1 m bars
    # statics by elimination against the published closed form: rounding
    assert -f.drives["foot"][0] == pytest.approx(_published(phi), rel=1e-12)   # pushed toward A (-x)


@pytest.mark.parametrize("length", [0.47, 0.55, 0.65, 0.78])
def test_the_cylinder_force_is_the_published_foot_force_by_virtual_work(length):
    mech = analytic.load(str(HERE / "scissor_cylinder.toml"))
    q = np.array([length])
    sol = mech.solve(q)
    # bar 1's frame runs from A toward D (the same line); bar 2's from the crossing M (its middle) toward B
    inertias = {"bar1": _bar1(1.0, 0.5), "bar2": Inertia(m=ARM, cx=0.0, cy=0.0, I=1.0)}
    f = F.solve(mech, q, 0.0 * q, 0.0 * q, inertias, gravity=(0.0, -G))
    phi = sol["phibar1"][0]
    (cx, cy), a = mech.geometry.ground["C"], 0.35
    dx, dy = a * math.cos(phi) - cx, a * math.sin(phi) - cy
    assert math.hypot(dx, dy) == pytest.approx(length, rel=1e-12)       # D at 0.35 m along bar 1, |CD| = l
    dl = (dx * -a * math.sin(phi) + dy * a * math.cos(phi)) / length     # d|CD| / d phi
    expected = _published(phi) * math.sin(phi) / dl                      # F |dx_B / d phi| / (dl / d phi)
    # statics by elimination against the published formula carried by virtual work: rounding
    assert f.drives["_lift"][0] == pytest.approx(expected, rel=1e-12)
    assert expected > 0                                                  # the cylinder pushes
