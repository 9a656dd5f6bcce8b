"""One mass truth (issue 41, item 4): with a ``[parts]`` section the analysis (forces, dynamics, MuJoCo) uses
the parts' mass properties, which the bill of materials lists, unless ``[inertia]`` gives a link's; the BOM and
the drawing say which masses the analysis used. The masses are checked against hand formulas of the plates
(a stadium less its holes; a slotted lever less its slot, and a slot that runs into a hole by the lens the two
cut-outs share), not against the parts code."""

from __future__ import annotations

import csv
import json
import math
import textwrap

import pytest

from tests.cli_runner import run

FOURBAR = textwrap.dedent("""\
    format = "linkage/1"
    name = "fb_parts"
    units = "mm"
    output = "C"
    [ground]
    A = [0, 0]
    D = [300, 0]
    [[inputs]]
    kind = "crank"
    pivot = "A"
    point = "B"
    length = 100
    link = "1"
    [[groups]]
    kind = "RRR"
    point = "C"
    from = ["B", "D"]
    lengths = [300, 250]
    links = ["2", "3"]
    branch = 1
    [mass]
    density = 2700
    width = 20
    thickness = 5
    [parts]
    pin_diameter = 8
    clearance = 0.2
    """)


def stadium_minus_holes(L, r, rh, t, rho):
    """Mass [kg] of a bar: centre distance L, round ends of radius r, two holes of radius rh (m, kg/m^3)."""
    return rho * t * (2 * r * L + math.pi * r * r - 2 * math.pi * rh * rh)


def forces_and_bom(tmp_path, text):
    path = tmp_path / "m.toml"
    path.write_text(text)
    f = run("forces", path, "--json", "--samples", "13")
    assert f.returncode == 0, f.stderr
    b = run("export", path, "--bom", tmp_path / "bom.csv")
    assert b.returncode == 0, b.stderr
    with open(tmp_path / "bom.csv", newline="") as fh:
        bom = {row["link"]: row for row in csv.DictReader(fh)}
    return json.loads(f.stdout), bom


def test_with_parts_the_forces_use_the_bom_masses(tmp_path):
    out, bom = forces_and_bom(tmp_path, FOURBAR)
    rh = (8 + 0.2) / 2 * 1e-3
    for link, L in (("1", 0.1), ("2", 0.3), ("3", 0.25)):
        hand = stadium_minus_holes(L, 0.010, rh, 5e-3, 2700)
        # exact arcs on both sides: rounding (1e-12 relative)
        assert out["links"][link]["m"] == pytest.approx(hand, rel=1e-12)
        assert float(bom[link]["mass_kg"]) == pytest.approx(hand, rel=1e-12)
        assert float(bom[link]["analysis_mass_kg"]) == pytest.approx(hand, rel=1e-12)
        assert bom[link]["analysis_mass_from"] == "parts"


def test_an_inertia_table_overrides_the_part_and_the_bom_says_so(tmp_path):
    text = FOURBAR + '[inertia]\n2 = { m = 0.5, cx = 150, cy = 0, I = 4000 }\n'
    out, bom = forces_and_bom(tmp_path, text)
    assert out["links"]["2"]["m"] == pytest.approx(0.5, rel=1e-12)
    assert bom["2"]["analysis_mass_from"] == "[inertia]"
    assert float(bom["2"]["analysis_mass_kg"]) == pytest.approx(0.5, rel=1e-12)
    assert float(bom["2"]["mass_kg"]) == pytest.approx(stadium_minus_holes(0.3, 0.010, 4.1e-3, 5e-3, 2700),
                                                       rel=1e-12)
    assert bom["3"]["analysis_mass_from"] == "parts"


def test_without_parts_the_bom_says_the_analysis_uses_other_masses(tmp_path):
    text = FOURBAR.split("[parts]")[0]
    out, bom = forces_and_bom(tmp_path, text)
    # [mass]'s bars: rho w t L (no round ends, no holes): the BOM's part weighs more, and says so
    assert out["links"]["3"]["m"] == pytest.approx(2700 * 0.020 * 0.005 * 0.25, rel=1e-12)
    assert bom["3"]["analysis_mass_from"] == "[mass]"
    assert float(bom["3"]["analysis_mass_kg"]) == pytest.approx(out["links"]["3"]["m"], rel=1e-12)
    assert float(bom["3"]["mass_kg"]) > float(bom["3"]["analysis_mass_kg"])


def test_the_drawing_says_which_masses_the_analysis_used(tmp_path):
    from analytic.parts import model  # noqa: F401  (the parts extra is installed with the tests)
    from sim import service
    from sim.output import parts_drawing
    from sim.service import parts as parts_service
    path = tmp_path / "m.toml"
    path.write_text(FOURBAR)
    pm = parts_service.prepare(service.load(str(path), {}))
    assert "uses these parts' masses" in parts_drawing.mass_note(pm)
    path.write_text(FOURBAR.split("[parts]")[0])
    pm = parts_service.prepare(service.load(str(path), {}))
    assert "uses other masses" in parts_drawing.mass_note(pm)


# ----------------------------------------------------------------------------------- slotted parts by hand
def _lever(slot_from, slot_to, rh, re, rs, t, rho):
    """A lever pivoted at u = 0 with a slot along its axis from u = slot_from to slot_to (the pin's centre
    travel), all discs on one line: the outline is the stadium over [0, slot_to] (end radius re), less the
    pivot hole (rh) and the slot (a stadium of radius rs); where the slot's round end overlaps the hole the
    overlap (a lens of two circles) is cut once."""
    L = slot_to - 0.0
    area = 2 * re * L + math.pi * re * re - math.pi * rh * rh - (2 * rs * (slot_to - slot_from) + math.pi * rs * rs)
    d = slot_from                                  # the hole's centre to the slot end's circle centre
    if d < rh + rs:                                # the two cut-outs overlap: add back their lens
        a1 = rh * rh * math.acos((d * d + rh * rh - rs * rs) / (2 * d * rh))
        a2 = rs * rs * math.acos((d * d + rs * rs - rh * rh) / (2 * d * rs))
        tri = 0.5 * math.sqrt((-d + rh + rs) * (d + rh - rs) * (d - rh + rs) * (d + rh + rs))
        area += a1 + a2 - tri
    return rho * t * area


SLOTTED = textwrap.dedent("""\
    format = "linkage/1"
    name = "swing"
    units = "mm"
    output = "B"
    [parameters]
    c = {c}
    [ground]
    A = [0, 0]
    O = [{c}, 0]
    [[inputs]]
    kind = "crank"
    pivot = "A"
    point = "B"
    length = 40
    link = "1"
    [[groups]]
    kind = "RPR"          # the lever about O, its slot through the block pinned at B; D its far end
    pivot = "O"
    through = "B"
    point = "D"
    length = {far}
    links = ["lever", "block"]
    [mass]
    density = 1000
    width = 20
    thickness = 4
    [parts]
    pin_diameter = 6
    clearance = 0
    """)


@pytest.mark.parametrize("c", [100, 44])
def test_a_slotted_lever_weighs_its_outline_less_its_hole_and_slot(tmp_path, c):
    # An inverted slider-crank: the lever turns about O = (c, 0) and its slot carries the crank pin B
    # (crank 40 mm), from c - 40 to c + 40 mm from O, where the lever ends (D). At c = 44 mm the slot's near end (4 mm from O, radius 3)
    # runs into the pivot's hole (radius 3): the two cut-outs share a lens.
    out, bom = forces_and_bom(tmp_path, SLOTTED.format(c=c, far=c + 40))
    hand = _lever((c - 40) * 1e-3, (c + 40) * 1e-3, 3e-3, 10e-3, 3e-3, 4e-3, 1000)
    lever = "lever"
    # exact arcs (Green's theorem) for the clear slot: rounding; the overlapping cut-outs are tessellated at
    # 1e-6 of the part's size: 1e-5 relative covers the chords' lost area
    tol = 1e-9 if c == 100 else 1e-5
    assert float(bom[lever]["mass_kg"]) == pytest.approx(hand, rel=tol)
    assert out["links"][lever]["m"] == pytest.approx(hand, rel=tol)


# ----------------------------------------------------------------------------------------- two-plate links
def _stadium_moments(u0, u1, r):
    """Area, first moment along u and polar second moment about the origin of a stadium on the u-axis: the
    rectangle [u0, u1] x [-r, r] and a half disc of radius r on each end (centroids 4r / 3pi beyond them)."""
    L = u1 - u0
    A = 2 * r * L + math.pi * r * r
    S = 2 * r * L * (u0 + u1) / 2 + math.pi * r * r / 2 * ((u1 + 4 * r / (3 * math.pi)) + (u0 - 4 * r / (3 * math.pi)))
    J = 2 * r * (u1 ** 3 - u0 ** 3) / 3 + L * 2 * r ** 3 / 3            # the rectangle: int x^2 + int y^2
    for u, sign in ((u1, 1), (u0, -1)):                                 # a half disc: J about its circle's centre
        J += math.pi * r ** 4 / 4 + math.pi * r * r / 2 * u * u + 2 * u * sign * math.pi * r * r / 2 * 4 * r / (3 * math.pi)
    return A, S, J


def _disc_moments(u, r):
    return math.pi * r * r, math.pi * r * r * u, math.pi * r ** 4 / 2 + math.pi * r * r * u * u


def test_a_two_plate_link_weighs_both_plates_in_the_bom_and_the_forces(tmp_path):
    """The Whitworth with [parts]: its slotted lever 3 is made two plates (a clevis at D). The BOM's mass for it,
    the BOM's analysis mass and the mass ``forces`` uses all equal twice the plate the test computes from the
    geometry (not the parts code): pivot C at u = 0, the arm's end D at u = -125 (arm), the slot for the crank pin
    A from |CA| = r - c = 50 to r + c = 250 mm (A on the crank circle of 150 about O, 100 from C), so the outline
    is the stadium of radius w/2 over [-125, 250] less the holes at C and D and the slot (its stadium of the hole's
    radius). Its moment of inertia doubles too, its centre stays; a one-plate link (the crank) counts once."""
    from pathlib import Path
    lib = (Path(__file__).resolve().parent.parent / "analytic" / "library" / "whitworth.toml").read_text()
    text = lib + "\n[mass]\ndensity = 2700\nwidth = 40\nthickness = 10\n\n[parts]\npin_diameter = 15\nclearance = 0.5\n"
    out, bom = forces_and_bom(tmp_path, text)
    assert bom["3"]["plates"] == "2" and all(bom[ln]["plates"] == "1" for ln in bom if ln != "3")
    rho, t, re, rh = 2700, 10e-3, 20e-3, (15 + 0.5) / 2 * 1e-3          # SI
    A, S, J = _stadium_moments(-0.125, 0.250, re)
    for cut in (_disc_moments(0.0, rh), _disc_moments(-0.125, rh), _stadium_moments(0.050, 0.250, rh)):
        A, S, J = A - cut[0], S - cut[1], J - cut[2]
    cx = S / A
    m_plate, i_plate = rho * t * A, rho * t * (J - A * cx * cx)
    lever = out["links"]["3"]
    # exact arcs on both sides (Green's theorem against the hand formulas): rounding, 1e-12 relative
    assert float(bom["3"]["mass_kg"]) == pytest.approx(2 * m_plate, rel=1e-12)
    assert float(bom["3"]["analysis_mass_kg"]) == pytest.approx(2 * m_plate, rel=1e-12)
    assert lever["m"] == pytest.approx(2 * m_plate, rel=1e-12)
    assert lever["I"] == pytest.approx(2 * i_plate, rel=1e-11)          # J - A cx^2 cancels a digit: 1e-11
    assert lever["cx"] == pytest.approx(cx, rel=1e-12)
    # the drawing's parts list and note say the analysis's lever is the BOM's two plates
    from sim import service
    from sim.output import parts_drawing, parts_files
    from sim.service import parts as parts_service
    pm = parts_service.prepare(service.load(str(tmp_path / "m.toml"), {}))
    row = next(r for r in parts_files.bom_rows(pm) if r["link"] == "3")
    assert parts_drawing._analysis_mass(row) == "= 2 plates"
    assert "both plates of a two-plate link" in parts_drawing.mass_note(pm)
    # the crank O-A (150 mm) is one plate: a stadium less its two holes, counted once
    crank = stadium_minus_holes(0.150, re, rh, t, rho)
    assert out["links"]["2"]["m"] == pytest.approx(crank, rel=1e-12)
    assert float(bom["2"]["mass_kg"]) == pytest.approx(crank, rel=1e-12)
