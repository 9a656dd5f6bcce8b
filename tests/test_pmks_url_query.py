"""PMKS ``mech=`` URLs whose query holds other settings first (``?set=s5&mech=...``), as five of PMKS' own walker
URLs do (issue 32): the first joint sat in the same piece as ``set=`` and was dropped, so the mechanism lost its
ground pivot and was refused (mobility 3, or a driver between two moving links). The URL is ours: a four-bar
(crank 10 at the origin, coupler to (30, 20), rocker pivot at (30, 0)).
"""

from __future__ import annotations

import pytest

from analytic.format import foreign, linkfile
from analytic.mechanism import Mechanism

JOINTS = ("ground input R 0 0 0 ffft|input coupler R 0 10 0 ffff|coupler output R 30 20 0 ffff|"
          "output ground R 30 0 0 ffff|")
PLAIN = "http://example.org/pmks/pmks.html?mech=" + JOINTS
WITH_SETTINGS = "http://example.org/pmks/pmks.html?set=s20|f5&mech=" + JOINTS
ENCODED = "http://example.org/pmks/pmks.html?set=s5&mech=" + JOINTS.replace(" ", "%20")


def read(tmp_path, text, name):
    path = tmp_path / f"{name}.txt"
    path.write_text(text + "\n")
    data = foreign.read(path, None)
    return data, Mechanism.from_definition(linkfile.from_data(data, str(path), name), {})


@pytest.mark.parametrize("text", [PLAIN, WITH_SETTINGS, ENCODED])
def test_the_first_joint_after_other_settings_is_read(tmp_path, text):
    data, m = read(tmp_path, text, "url")
    assert len(data["pose"]) == 4                                   # J0 (the crank's ground pivot) kept
    assert data["pose"]["J0"] == pytest.approx((0.0, 0.0), abs=1e-12)
    assert m.inputs[0].kind == "crank" and m.inputs[0].link == "input"
    sol = m.solve([m.inputs[0].motion.q0])
    # the drawn pose: the rocker's pin at (30, 20), 20 from its pivot; the crank's pin at (0, 10)
    assert (sol["xJ2"][0] / m.scale, sol["yJ2"][0] / m.scale) == pytest.approx((30.0, 20.0), abs=1e-9)
    assert (sol["xJ1"][0] / m.scale, sol["yJ1"][0] / m.scale) == pytest.approx((0.0, 10.0), abs=1e-9)
