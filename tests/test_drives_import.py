"""Peers' files that drive a linkage by a linear actuator open with it (issue 37, item 8): a PMKS text whose
driving joint is an RP joint between two moving links (``barrel body RP``: the body pinned to a block sliding in
the barrel's slot) imports as an ``actuator``, its start length the pins' distance in the pose, its stroke a
quarter of it either way. Checked against the pose's numbers by hand; a P joint between moving links is refused
saying how to write a cylinder."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import analytic
from analytic.format import foreign
from tests.cli_runner import run

TIPPER = Path(__file__).resolve().parent / "peers_examples" / "cylinder_tipper.txt"


def test_a_pmks_cylinder_imports_as_an_actuator(tmp_path):
    out = tmp_path / "tipper.toml"
    r = run("import", TIPPER, "--out", out)
    assert r.returncode == 0, r.stderr
    mech = analytic.load(str(out))
    (e,) = [x for x in mech.geometry.elements if x["kind"] == "actuator"]
    assert tuple(e["from"]) == ("J0", "J1") and e["point"] == "J2" and e["link"] == "body"
    l0 = math.hypot(2.0 - 1.5, 0.5 + 0.5)                # |J1 J2| in the pose [m] (the file is mm)
    assert e["l0"] == pytest.approx(l0, rel=1e-12)       # a distance from the pose: rounding
    assert e["length"] == pytest.approx(math.hypot(2.0, 0.5), rel=1e-12)     # |J0 J2|
    # the stroke written to 6 significant digits: [0.75, 1.25] l0 within half a unit of the 6th, 5e-6
    assert e["stroke"] == pytest.approx([0.75 * l0, 1.25 * l0], rel=5e-6)
    # at another length, J2 at |J0 J2| from J0 and l from J1 (the circles' intersection on the pose's side)
    l = 1.3
    sol = mech.solve(np.array([l]))
    a, c = np.array([0.0, 0.0]), np.array([1.5, -0.5])
    r1, d = math.hypot(2.0, 0.5), float(np.linalg.norm(c - a))
    along = (r1 ** 2 - l ** 2 + d ** 2) / (2 * d)
    u = (c - a) / d
    j2 = a + along * u + math.sqrt(r1 ** 2 - along ** 2) * np.array([-u[1], u[0]])   # left of J0 -> J1
    # two formulas for one intersection on a 2 m figure: rounding
    assert math.hypot(sol["xJ2"][0] - j2[0], sol["yJ2"][0] - j2[1]) <= 1e-12
    # the run stays in the stroke: one second at the written speed
    assert r.returncode == 0 and run("compare", out).returncode == 0


def test_a_pmks_p_joint_between_moving_links_is_refused_saying_how_to_write_a_cylinder(tmp_path):
    src = tmp_path / "p.txt"
    src.write_text("ground body R 0 0\nground barrel R 1500 -500\nbarrel rod P 2000 500 63.43494882\n"
                   "rod body R 2000 500\nbody R 3000 1000\nd=2\n")
    with pytest.raises(analytic.FileError, match="RP joint"):
        foreign.read(src)
