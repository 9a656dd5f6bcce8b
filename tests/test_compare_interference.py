"""``linkage compare MECH --interference``: the parts swept over the same run as the simulation (issue 28
item 3, "and in compare"): a planted collision fails the comparison at the angle the hand geometry gives; the
same design made clear of it passes."""

from __future__ import annotations

import json
import re

import pytest

import cli_runner
from sim import service
from sim.service import parts as parts_service
from test_parts import PLANTED, _oracle_first_contact


def test_a_planted_collision_fails_compare_where_the_geometry_says(tmp_path):
    path = tmp_path / "planted.toml"
    path.write_text(PLANTED)
    r = cli_runner.run("compare", path, "--interference")
    assert r.returncode == 1, r.stderr
    assert "PASSED" in r.stdout                        # the motion itself agrees: the parts fail it
    m = re.search(r"interference: FAILED, 1 and 3 collide first at \w+ = ([-0-9.e]+) deg", r.stdout)
    assert m, r.stdout
    pm = parts_service.prepare(service.load(str(path), {}))
    oracle = _oracle_first_contact(pm.mech, pm.parts["1"].width / 2)
    # the polygons lie inside the exact stadiums' arcs by <= 3 um: 6e-4 deg of crank (test_parts' bound); the
    # printed angle has 6 significant digits (1e-3 deg at 355 deg)
    assert float(m.group(1)) == pytest.approx(oracle, abs=2e-3)


def test_compare_interference_json_and_a_clear_design_passes(tmp_path):
    path = tmp_path / "planted.toml"
    path.write_text(PLANTED)
    r = cli_runner.run("compare", path, "--interference", "--json", "--set", "ext=250")
    assert r.returncode == 0, r.stderr
    data = json.loads(r.stdout)
    assert data["passed"] is True and data["interference"]["interference"] == []
    assert data["interference"]["min_clearance"]["1|3"] > 0
    r = cli_runner.run("compare", path, "--set", "ext=250")
    assert r.returncode == 0 and "interference" not in r.stdout      # only when asked: it costs a sweep
