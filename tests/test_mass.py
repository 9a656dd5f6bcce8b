"""The mass model (analytic/mass.py) against hand formulas: slender bars, bars of a width, triangular and
rectangular plates, blocks, counterweights (parallel-axis theorem), the precedence of --inertia, [inertia] and
[mass]; the MuJoCo model carries the same masses; a bad [mass] section is one line naming the link and field."""

from __future__ import annotations

import re
import math

import numpy as np
import pytest

import analytic
from analytic import mass
from analytic.mass import Inertia
from analytic.format import linkfile
from analytic.registry import LIBRARY

import cli_runner  # the command in this process (tests/cli_runner.py)

REL = 1e-12   # hand formula vs the model: rounding of a few sums of products (|values| ~ 1)


def close(a, b, scale=1.0):
    return abs(a - b) <= REL * max(abs(b), scale)


def _load(text: str) -> analytic.Mechanism:
    return analytic.Mechanism.from_definition(linkfile.parse(text, "m.toml"))


def fourbar_text(extra: str = "") -> str:
    return (LIBRARY / "fourbar.toml").read_text() + extra


def test_default_binary_link_is_a_slender_bar_of_1_kg_per_m():
    m = analytic.load("fourbar")
    b = mass.model(m)["1"]                               # the crank AB, l1 = 0.1 m
    assert close(b.m, 0.1) and close(b.cx, 0.05) and close(b.cy, 0.0, 1e-3)
    assert close(b.I, 0.1 * 0.1 ** 2 / 12)               # m L^2 / 12


def test_default_coupler_with_a_point_is_a_star_of_bars():
    m = analytic.load("fourbar")
    l2, ex, ey = 0.30, 0.15, 0.10
    le = math.hypot(ex, ey)
    # two bars from B: to C (l2 along x) and to E (ex, ey); each bar's mass at its middle
    mtot = l2 + le
    cx = (l2 * l2 / 2 + le * ex / 2) / mtot
    cy = (le * ey / 2) / mtot
    inertia = (l2 * (l2 ** 2 / 12 + (l2 / 2 - cx) ** 2 + cy ** 2)
               + le * (le ** 2 / 12 + (ex / 2 - cx) ** 2 + (ey / 2 - cy) ** 2))
    b = mass.model(m)["2"]
    assert close(b.m, mtot) and close(b.cx, cx) and close(b.cy, cy) and close(b.I, inertia)


def test_default_block_is_a_small_mass_at_its_pin():
    m = analytic.load("slider_crank")
    b = mass.model(m)["piston"]
    a = 0.1 * m.size
    assert close(b.m, a) and b.cx == 0.0 and b.cy == 0.0 and close(b.I, a * a * a / 6)


def test_bars_of_a_material_in_a_mm_file():
    # a mm file: width and thickness in mm; m = rho w t L, I = m (L^2 + w^2) / 12 for the crank (L = 100 mm)
    text = fourbar_text('\n[mass]\ndensity = 7850\nwidth = 10\nthickness = 5\n')
    text = text.replace('format = "linkage/1"', 'format = "linkage/1"\nunits = "mm"', 1)
    for k, v in {"l1 = 0.10": "l1 = 100", "l2 = 0.30": "l2 = 300", "l3 = 0.25": "l3 = 250", "l4 = 0.30": "l4 = 300",
                 "ex = 0.15": "ex = 150", "ey = 0.10": "ey = 100"}.items():
        text = text.replace(k, v, 1)
    b = mass.model(_load(text))["1"]
    L, w, t = 0.1, 0.01, 0.005
    m = 7850 * w * t * L
    assert close(b.m, m) and close(b.cx, L / 2) and close(b.I, m * (L * L + w * w) / 12)


def test_a_ternary_plate_is_a_triangle():
    # Jansen's B-C-E is a rigid triangle: as a plate m = rho t A, centroid = mean of the corners,
    # I about it = m (a^2 + b^2 + c^2) / 36 (a, b, c its sides)
    text = (LIBRARY / "jansen.toml").read_text() + '\n[mass]\ndensity = 2700\nwidth = 8\nthickness = 4\n' \
        '[mass.links.BCE]\nshape = "plate"\n'
    m = _load(text)
    local = mass.local_points(m)["BCE"]
    (x0, y0), (x1, y1), (x2, y2) = local["B"], local["C"], local["E"]
    area = abs((x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)) / 2
    rho_t = 2700 * 0.004
    sides2 = (x1 - x0) ** 2 + (y1 - y0) ** 2 + (x2 - x1) ** 2 + (y2 - y1) ** 2 + (x0 - x2) ** 2 + (y0 - y2) ** 2
    b = mass.model(m)["BCE"]
    mm = rho_t * area
    assert close(b.m, mm) and close(b.cx, (x0 + x1 + x2) / 3, 0.05) and close(b.cy, (y0 + y1 + y2) / 3, 0.05)
    assert close(b.I, mm * sides2 / 36)
    # the other links stay bars of that material: OA is a bar of 15 mm, 8 mm wide, 4 mm thick
    oa = mass.model(m)["OA"]
    mo = 2700 * 0.008 * 0.004 * 0.015
    assert close(oa.m, mo) and close(oa.I, mo * (0.015 ** 2 + 0.008 ** 2) / 12)


def test_polygon_and_hull_of_a_rectangle():
    hull = mass.convex_hull([(0, 0), (2, 0), (2, 1), (0, 1), (1, 0.5), (1, 0)])
    assert len(hull) == 4
    area, cx, cy, J = mass.polygon(hull)
    assert close(area, 2.0) and close(cx, 1.0) and close(cy, 0.5) and close(J, 2.0 * (4 + 1) / 12)


def test_a_block_of_a_material_is_a_square():
    text = (LIBRARY / "slider_crank.toml").read_text() + '\n[mass]\ndensity = 1000\nwidth = 0.02\nthickness = 0.01\n'
    b = mass.model(_load(text))["piston"]
    m = 1000 * 0.02 ** 2 * 0.01
    assert close(b.m, m) and close(b.I, m * 0.02 ** 2 / 6)


def test_a_counterweight_adds_by_the_parallel_axis_theorem():
    text = fourbar_text('\n[mass.counterweights]\n"1" = { m = 0.3, at = [-0.05, 0.01] }\n')
    b = mass.model(_load(text))["1"]
    m0, c0, I0 = 0.1, (0.05, 0.0), 0.1 * 0.01 / 12
    mc, cc = 0.3, (-0.05, 0.01)
    M = m0 + mc
    gx, gy = (m0 * c0[0] + mc * cc[0]) / M, (m0 * c0[1] + mc * cc[1]) / M
    inertia = I0 + m0 * ((c0[0] - gx) ** 2 + (c0[1] - gy) ** 2) + mc * ((cc[0] - gx) ** 2 + (cc[1] - gy) ** 2)
    assert close(b.m, M) and close(b.cx, gx) and close(b.cy, gy) and close(b.I, inertia)


def test_inertia_table_and_the_command_line_take_precedence():
    text = fourbar_text('\n[mass]\ndensity = 7850\nwidth = 0.01\nthickness = 0.005\n'
                        '[inertia]\n"2" = { m = 2.0, cx = 0.1, cy = 0.02, I = 0.05 }\n')
    m = _load(text)
    model = mass.model(m)
    assert model["2"] == Inertia(2.0, 0.1, 0.02, 0.05)            # [inertia] over [mass]
    assert close(model["3"].m, 7850 * 0.01 * 0.005 * 0.25)         # [mass] where [inertia] says nothing
    given = mass.model(m, {"2": Inertia(1.0, 0.0, 0.0, 0.01)})
    assert given["2"] == Inertia(1.0, 0.0, 0.0, 0.01)              # --inertia over [inertia]


def test_the_mujoco_model_carries_the_mass_model():
    from sim.model import body_inertias, build
    text = (LIBRARY / "jansen.toml").read_text() + '\n[mass]\ndensity = 2700\nwidth = 8\nthickness = 4\n' \
        '[mass.links.BCE]\nshape = "plate"\n[mass.counterweights]\nOA = { m = 0.05, at = [-10, 0] }\n'
    m = _load(text)
    got = body_inertias(build(m).model, m.links)
    local = mass.local_points(m)
    (x0, y0), (x1, y1), (x2, y2) = local["BCE"]["B"], local["BCE"]["C"], local["BCE"]["E"]
    area = abs((x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)) / 2
    assert close(got["BCE"].m, 2700 * 0.004 * area)                # the plate (hand formula)
    assert close(got["OA"].m, 2700 * 0.008 * 0.004 * 0.015 + 0.05)   # bar + counterweight
    want = mass.model(m)
    for ln in m.links:                                             # MuJoCo stores what the model says (float32-free)
        assert np.allclose([got[ln].m, got[ln].cx, got[ln].cy, got[ln].I],
                           [want[ln].m, want[ln].cx, want[ln].cy, want[ln].I], rtol=1e-12, atol=1e-15), ln


@pytest.mark.parametrize("extra, pattern", [
    ('\n[mass]\ndensity = -3\nwidth = 0.01\nthickness = 0.005\n', r"mass\.density: -3 must be > 0 \[kg/m\^3\]"),
    ('\n[mass]\ndensity = 7850\nwidth = 0.01\nthickness = 0.005\n[mass.links.2]\nwidth = 0\n',
     r"mass\.links\.2\.width: 0 must be > 0"),
    ('\n[mass]\ndensity = 7850\nwidth = 0.01\nthickness = 0.005\n[mass.links.3]\nthickness = -1e-3\n',
     r"mass\.links\.3\.thickness: -0\.001 must be > 0"),
    ('\n[mass]\ndensity = 7850\nwidth = 0.01\n', r"mass: link 1: a density needs a thickness"),
    ('\n[mass]\nwidth = 0.01\nthickness = 0.01\n', r"mass: link 1: thickness, width without a density"),
    ('\n[mass.counterweights]\n"1" = { m = 0, at = [0, 0] }\n', r"mass\.counterweights\.1\.m: 0 must be > 0 \[kg\]"),
    ('\n[mass.counterweights]\n"7" = { m = 1, at = [0, 0] }\n', r"mass\.counterweights\.7: no link named '7'"),
    ('\n[mass.links.2]\nshape = "disc"\n', r"mass\.links\.2\.shape: 'disc' must be \"bar\" or \"plate\""),
    ('\n[inertia]\n"2" = { m = -1, I = 0.01 }\n', r"inertia\.2\.m: -1 must be >= 0"),    # m = 0 is a massless link (SPEC "Loads")
])
def test_a_bad_mass_section_is_one_line_naming_link_and_field(tmp_path, extra, pattern):
    import re
    path = tmp_path / "m.toml"
    path.write_text(fourbar_text(extra))
    r = cli_runner.run("forces", "m.toml", cwd=tmp_path)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("linkage: error: ") and "Traceback" not in r.stderr, r.stderr
    assert re.search(pattern, lines[0]), lines[0]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.toml"]


def test_a_non_positive_inertia_on_the_command_line_names_the_link_and_field(tmp_path):
    (tmp_path / "i.json").write_text('{"2": {"m": 0, "cx": 0, "cy": 0, "I": 0.01}}')
    r = cli_runner.run("forces", "fourbar", "--inertia", "i.json", cwd=tmp_path)
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert re.search(r"--inertia 2: mass m=0(\.0)? with I=0\.01: a massless link has no moment of inertia", r.stderr), r.stderr


def test_export_writes_the_mass_section_back(tmp_path):
    text = fourbar_text('\n[mass]\ndensity = 7850\nwidth = 0.01\nthickness = 0.005\n[mass.links.2]\nshape = "plate"\n'
                        '[mass.counterweights]\n"1" = [{ m = 0.1, at = [-0.05, 0] }, { m = 0.2, at = [-0.02, 0.01] }]\n')
    m = _load(text)
    from sim.output.tomlout import generate
    back = _load(generate(m))
    assert back.definition.mass == m.definition.mass
    a, b = mass.model(m), mass.model(back)
    assert all(a[k] == b[k] for k in a)
