"""Units of results (SPEC "Units of results"): what people read in the file's length unit (or --units),
angles in deg and speeds in rpm on request; CSV and JSON SI unless asked, their sidecar / units table
saying which; --inertia read in the file's unit like [inertia]; a figure of merit the same everywhere.

The oracle for a mm file is the same design written in metres (the library file with units = "m" and its
lengths divided by 1000 by hand): its numbers, times 1000, are what the mm file must show. Neither side's
expected value comes from the display converter under test."""

import csv
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

import analytic
from analytic import quantities as Q
from analytic.applications import figures

import cli_runner  # the command in this process (tests/cli_runner.py)

LIB = Path(analytic.__file__).parent / "library"
HOEKENS_M = ["--set", "crank=0.05", "--set", "ground=0.1", "--set", "coupler=0.125", "--set", "rocker=0.125",
             "--set", "bp=0.25"]                       # hoekens.toml's lengths (mm) / 1000, typed by hand
REL = 1e-9
"""[relative] the mm and m designs are the same SI geometry, up to the rounding of value * 0.001 (1e-16);
what is left is the printing (6 significant digits: handled by parsing with a relative bound) or float
noise in the solver (1e-15)."""
PRINTED = 5e-6
"""[relative] numbers printed with %.6g differ by at most half a unit in the 6th digit."""


def run(*args, ok=(0,)):
    p = cli_runner.run(*map(str, args))
    assert p.returncode in ok, p.stderr
    return p.stdout


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("units")
    text = (LIB / "hoekens.toml").read_text()
    assert 'units = "mm"' in text
    mm = d / "hoekens_mm.toml"
    m = d / "hoekens_m.toml"
    mm.write_text(text)
    m.write_text(text.replace('units = "mm"', 'units = "m"'))
    return d, mm, m


def numbers(line: str) -> list[float]:
    return [float(x) for x in re.findall(r"-?\d+(?:\.\d+)?(?:e[-+]?\d+)?", line)]


def line_with(text: str, start: str) -> str:
    return next(ln for ln in text.splitlines() if ln.strip().startswith(start))


# ------------------------------------------------------------------------------------ summaries
def test_mm_file_summary_is_the_metre_design_times_1000(files):
    _, mm, m = files
    shown_mm, shown_m = run("analyze", mm), run("analyze", m, *HOEKENS_M)
    path_mm, path_m = line_with(shown_mm, "P path"), line_with(shown_m, "P path")
    assert path_mm.count(" mm,") == 1 and path_mm.count(" mm;") == 1 and "mm/s" in path_mm and " m," in path_m and "m/s" in path_m
    a, b = numbers(path_mm), numbers(path_m)
    assert len(a) == len(b) == 6
    np.testing.assert_allclose(a, np.array(b) * 1000, rtol=PRINTED, atol=1e-9)
    # angles and ratios do not depend on the length unit
    for start in ("transmission angle", "time ratio"):
        np.testing.assert_allclose(numbers(line_with(shown_mm, start)), numbers(line_with(shown_m, start)),
                                   rtol=PRINTED)
    # --units m on the mm file shows the metre design's numbers
    np.testing.assert_allclose(numbers(line_with(run("analyze", mm, "--units", "m"), "P path")), b, rtol=PRINTED)


def test_compare_table_in_mm_and_the_output_point_first(files):
    _, mm, m = files
    t_mm, t_m = run("compare", mm), run("compare", m, *HOEKENS_M)

    def rows(text):
        out = {}
        for ln in text.splitlines():
            parts = ln.split()
            if len(parts) >= 6 and re.fullmatch(r"[a-zA-Z]\w*", parts[0]) and re.fullmatch(r"-?\d.*", parts[1]):
                out[parts[0]] = (list(map(float, parts[1:5])), " ".join(parts[5:]))
        return out
    r_mm, r_m = rows(t_mm), rows(t_m)
    assert r_mm["xP"][1] == "mm" and r_mm["vxP"][1] == "mm/s" and r_mm["axP"][1] == "mm/s^2"
    assert r_m["xP"][1] == "m" and r_mm["phi3"][1] == "rad" and r_mm["tau2"][1] == "N m"
    for name in ("xP", "yP", "vxP", "axP"):
        # peak printed to 4 digits (%.4g): half a unit in the 4th digit, on both sides
        np.testing.assert_allclose(r_mm[name][0][2], r_m[name][0][2] * 1000, rtol=1e-3)
        # tolerance printed to 2 digits (%.1e): a value on a rounding edge can round either way, < 10 %
        np.testing.assert_allclose(r_mm[name][0][3], r_m[name][0][3] * 1000, rtol=0.1)
    np.testing.assert_allclose(r_mm["phi3"][0][2], r_m["phi3"][0][2], rtol=5e-4)
    names = [ln.split()[0] for ln in t_mm.splitlines()[2:] if ln.split() and ln.split()[0] in r_mm]
    assert names[:2] == ["xP", "yP"]                        # led by the output point
    assert "xA" not in r_mm and re.search(r"\d+ fixed outputs \(xA yA", t_mm)    # the ground pivot folded
    assert names[-1] == "tau2"


def test_plot_sheet_figures_are_analyze_figures_and_the_hand_value():
    """Whitworth: the ram's extremes are where the slotted lever is horizontal, the crank pin then on the
    line through C at c below O: the strokes take 180 +- 2 asin(c/r) degrees of crank."""
    from sim.output import plot
    from sim import service
    from sim.model import Settings
    mech = service.load("whitworth")
    # a 10 ms step (100 samples a turn): the simulated samples' own K is then off by 5.6e-3 (measured), so
    # a sheet that read them would fail the first check below whatever step the default becomes
    built, c = service.compare(mech, 1.0, Settings(timestep=0.01))
    k_plot = numbers(next(ln for ln in plot.summary_lines(c, built, Q.Display("mm")) if "K =" in ln))[-1]
    k_analyze = numbers(line_with(run("analyze", "whitworth"), "time ratio"))[-1]
    beta = math.degrees(math.asin(100 / 150))
    hand = (180 + 2 * beta) / (180 - 2 * beta)
    assert abs(k_plot - k_analyze) <= 1e-4           # both print %.4f of the same number
    assert abs(k_analyze - hand) <= 1e-3             # 361 samples, extremes located by linear interpolation
    # the simulated samples' value (what the sheet printed before) is off by more than that
    assert abs(figures.of(mech, c.analytic)["time_ratio"] - hand) > 2e-3


# -------------------------------------------------------------------------------- CSV and JSON
def test_csv_is_si_by_default_and_converted_with_units(files):
    d, mm, m = files
    def read(path):
        with open(path) as f:
            rows = list(csv.DictReader(f))
        return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}
    run("analyze", mm, "--samples", 37, "--csv", d / "mm.csv")
    run("analyze", m, *HOEKENS_M, "--samples", 37, "--csv", d / "m.csv")
    run("analyze", mm, "--samples", 37, "--csv", d / "mm_mm.csv", "--units", "mm", "--speeds", "rpm",
        "--angles", "deg")
    si, ref, conv = read(d / "mm.csv"), read(d / "m.csv"), read(d / "mm_mm.csv")
    for k in ("xP", "yP", "vxP", "axP"):
        np.testing.assert_allclose(si[k], ref[k], rtol=REL, atol=1e-12)          # SI whatever the file says
        np.testing.assert_allclose(conv[k], ref[k] * 1000, rtol=REL, atol=1e-9)
    np.testing.assert_allclose(conv["omega2"], 60.0, rtol=1e-12)      # 360 deg/s is one turn a second: 60 rpm
    np.testing.assert_allclose(conv["phi2"], np.degrees(ref["phi2"]), rtol=REL, atol=1e-9)
    np.testing.assert_allclose(conv["alpha3"], np.degrees(ref["alpha3"]), rtol=REL, atol=1e-6)
    side_si = json.loads((d / "mm.csv.units.json").read_text())
    side = json.loads((d / "mm_mm.csv.units.json").read_text())
    assert side_si["si"] is True and side_si["file_units"] == "mm"
    assert side_si["units"]["xP"] == "m" and side_si["units"]["vxP"] == "m/s" and side_si["units"]["omega2"] == "rad/s"
    assert side["si"] is False and side["units"]["xP"] == "mm" and side["units"]["axP"] == "mm/s^2"
    assert side["units"]["omega2"] == "rpm" and side["units"]["phi2"] == "deg" and side["units"]["t"] == "s"


def test_json_is_si_by_default_and_its_units_table_says_which(files):
    _, mm, m = files
    si = json.loads(run("analyze", mm, "--json"))
    ref = json.loads(run("analyze", m, *HOEKENS_M, "--json"))
    conv = json.loads(run("analyze", mm, "--json", "--units", "in"))
    assert si["units"]["file"] == "mm" and si["units"]["length"] == "m" and si["units"]["outputs"]["vxP"] == "m/s"
    np.testing.assert_allclose(si["ranges"]["xP"], ref["ranges"]["xP"], rtol=REL)
    np.testing.assert_allclose(si["figures"]["xP_range"], ref["figures"]["xP_range"], rtol=REL)
    assert conv["units"]["length"] == "in" and conv["units"]["outputs"]["axP"] == "in/s^2"
    np.testing.assert_allclose(conv["ranges"]["xP"], np.array(ref["ranges"]["xP"]) / 0.0254, rtol=REL)
    np.testing.assert_allclose(conv["figures"]["vP_max"], ref["figures"]["vP_max"] / 0.0254, rtol=REL)
    assert conv["figures"]["time_ratio"] == pytest.approx(ref["figures"]["time_ratio"], rel=REL)  # a ratio: unchanged


def test_display_conversions_by_hand():
    u = Q.Display("cm", "deg", "rpm")
    assert u.convert(Q.LENGTH, 0.25) == pytest.approx(25.0, rel=1e-15)
    assert u.convert(Q.ACCELERATION, 9.81) == pytest.approx(981.0, rel=1e-15)
    assert u.convert(Q.ANGLE, math.pi / 2) == pytest.approx(90.0, rel=1e-15)
    assert u.convert(Q.ANGULAR_VELOCITY, 2 * math.pi) == pytest.approx(60.0, rel=1e-15)     # 1 rev/s
    assert u.convert(Q.ANGULAR_ACCELERATION, math.pi) == pytest.approx(180.0, rel=1e-15)
    assert u.convert(Q.TORQUE, 3.5) == 3.5 and u.unit(Q.TORQUE) == "N m" and u.unit(Q.FORCE) == "N"
    assert Q.Display("in").convert(Q.VELOCITY, 0.0254) == pytest.approx(1.0, rel=1e-15)
    assert Q.Display("mm", "deg").unit(Q.ANGULAR_VELOCITY) == "deg/s"
    with pytest.raises(analytic.ParameterError):
        Q.Display("furlong")


def test_the_table_of_outputs_names_every_output():
    from sim import service
    mech = service.load("fourbar")
    table = {o.name: o for o in Q.outputs(mech)}
    tau = f"tau{mech.inputs[0].link}"
    assert set(table) == set(mech.outputs) | {tau}
    assert table["xE"].quantity == Q.LENGTH and table["vxE"].si_unit == "m/s" and table["mu"].quantity == Q.ANGLE
    assert table["omega3"].quantity == Q.ANGULAR_VELOCITY and table[tau].quantity == Q.TORQUE
    assert table["alpha3"].owner == "link 3"


# ------------------------------------------------------------------------------------- --inertia
def test_inertia_file_is_read_in_the_file_unit_like_the_inertia_table(files):
    d, mm, _ = files
    entry = {"m": 0.8, "cx": 60.0, "cy": 5.0, "I": 900.0}   # mm and kg mm^2, like [inertia] in a mm file
    (d / "with_table.toml").write_text(mm.read_text() + '\n[inertia]\n"3" = { m = 0.8, cx = 60.0, cy = 5.0, I = 900.0 }\n')
    (d / "inertia.json").write_text(json.dumps({"3": entry}))
    table = json.loads(run("compare", d / "with_table.toml", "--json"))
    given = json.loads(run("compare", mm, "--inertia", d / "inertia.json", "--json"))
    plain = json.loads(run("compare", mm, "--json"))
    assert given["passed"] and table["passed"]
    assert given["loads"]["inertias"]["3"]["cx"] == pytest.approx(0.060, rel=1e-12)   # 60 mm in SI
    assert given["loads"]["inertias"]["3"]["I"] == pytest.approx(900e-6, rel=1e-12)   # kg mm^2 -> kg m^2
    peak_t, peak_g, peak_0 = (r["errors"]["tau2"]["peak"] for r in (table, given, plain))
    assert peak_g == pytest.approx(peak_t, rel=1e-9)          # same model, same run: float noise only
    assert abs(peak_g - peak_0) > 1e-3 * peak_0               # and the inertia did change the torque


# ------------------------------------------------------------------------------------------ sweep
def test_sweep_table_in_the_file_unit_and_plot_colours_distinct(files):
    _, mm, m = files

    def rows(text):
        return [numbers(ln) for ln in text.splitlines()[1:] if ".." in ln]
    head = run("sweep", mm, "--vary", "crank=40,50", "--show", 2).splitlines()[0]
    assert "x range [mm]" in head and "area [mm^2]" in head and "mm/s" in head
    a = rows(run("sweep", mm, "--vary", "crank=40,50", "--show", 2))
    b = rows(run("sweep", m, *HOEKENS_M[2:], "--vary", "crank=0.04,0.05", "--show", 2))
    assert len(a) == len(b) == 2
    for ra, rb in zip(a, b):
        # columns: crank, x lo, x hi, y lo, y hi, area, |v| mean, min, max, fluctuation; printed to 5 digits
        factor = np.array([1000] * 5 + [1e6] + [1000] * 3 + [1])
        np.testing.assert_allclose(ra, np.array(rb) * factor, rtol=1e-4)
    from sim.front.cli.sweep import family_styles
    styles = family_styles(45)
    assert len(set(styles)) == 45 and len({c for c, _ in styles[:20]}) == 20


def test_compare_json_is_si_by_default_and_converted_with_units(files):
    _, mm, _ = files
    si = json.loads(run("compare", mm, "--json"))
    conv = json.loads(run("compare", mm, "--json", "--units", "mm", "--speeds", "rpm"))
    assert si["units"]["length"] == "m" and si["errors"]["xP"]["unit"] == "m" and conv["errors"]["xP"]["unit"] == "mm"
    assert si["units"]["file"] == "mm" and conv["units"]["outputs"]["omega3"] == "rpm"
    # the same run twice (deterministic): its SI numbers, times 1000 for lengths, 60 / (2 pi) for speeds;
    # rel 1e-12 bounds the rounding of one multiplication (1e-16)
    for key in ("peak", "tol"):
        assert conv["errors"]["xP"][key] == pytest.approx(si["errors"]["xP"][key] * 1000, rel=1e-12)
        assert conv["errors"]["omega3"][key] == pytest.approx(si["errors"]["omega3"][key] * 60 / (2 * math.pi),
                                                              rel=1e-12)
    assert conv["errors"]["tau2"]["peak"] == pytest.approx(si["errors"]["tau2"]["peak"], rel=1e-12)   # N m stays
    assert conv["loop_tol"] == pytest.approx(si["loop_tol"] * 1000, rel=1e-12)


def test_sweep_csv_si_by_default_converted_with_units_and_its_sidecar(files):
    d, mm, _ = files

    def read(path):
        with open(path) as f:
            rows = list(csv.DictReader(f))
        return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}
    run("sweep", mm, "--vary", "crank=40,50", "--csv", d / "s.csv")
    run("sweep", mm, "--vary", "crank=40,50", "--csv", d / "s_mm.csv", "--units", "mm")
    si, conv = read(d / "s.csv"), read(d / "s_mm.csv")
    np.testing.assert_allclose(conv["x_max"], si["x_max"] * 1000, rtol=REL)
    np.testing.assert_allclose(conv["speed_max"], si["speed_max"] * 1000, rtol=REL)
    np.testing.assert_allclose(conv["area"], si["area"] * 1e6, rtol=REL)
    assert list(si["crank"]) == [40.0, 50.0]    # the varied values as the file gives them (parsed from "40": exact)
    side, side_si = (json.loads((d / n).read_text()) for n in ("s_mm.csv.units.json", "s.csv.units.json"))
    assert side["units"]["x_max"] == "mm" and side["units"]["area"] == "mm^2" and side["si"] is False
    assert side_si["units"]["speed_mean"] == "m/s" and side_si["units"]["crank"] == "mm" and side_si["si"] is True


# ------------------------------------------------------------------------------- parameters
def header_values(line: str) -> dict[str, tuple[float, str]]:
    """``name=value unit, ...`` of analyze's first line as {name: (value, unit)}."""
    body = line.split(": ", 1)[1]
    out = {}
    for item in body.split(", "):
        name, rest = item.split("=", 1)
        parts = rest.split(" ", 1)
        out[name] = (float(parts[0]), parts[1] if len(parts) > 1 else "")
    return out


def test_analyze_header_shows_parameters_in_the_display_units():
    # fivebar's file: phi4_0 = 60 deg, omega2 = 2 pi rad/s = one turn a second = 60 rpm (by hand)
    p = header_values(run("analyze", "fivebar", "--angles", "deg", "--speeds", "rpm").splitlines()[0])
    assert p["phi4_0"][1] == "deg" and p["phi4_0"][0] == pytest.approx(60.0, rel=PRINTED)
    assert p["omega2"] == (pytest.approx(60.0, rel=PRINTED), "rpm") and p["l1"] == (pytest.approx(0.2), "m")
    assert p["alpha2"][1] == "deg/s^2"
    # whitworth.toml is in mm (r = 150): in metres with --units m, above results in metres
    out = run("analyze", "whitworth", "--units", "m").splitlines()
    w = header_values(out[0])
    assert w["r"] == (pytest.approx(0.15, rel=PRINTED), "m") and w["branch"] == (1.0, "")
    assert w["omega1"] == (pytest.approx(2 * math.pi, rel=PRINTED), "rad/s")
    assert " m " in line_with("\n".join(out), "slide sblock") + " "
    # without options: the file's unit (mm), angles in rad
    assert header_values(run("analyze", "whitworth").splitlines()[0])["rod"] == (pytest.approx(500.0), "mm")


def test_json_parameters_are_in_the_units_the_table_names():
    # whitworth: r = 150 mm, omega1 = 360 deg/s (the file's own values, by hand)
    si = json.loads(run("analyze", "whitworth", "--json"))
    shown = json.loads(run("analyze", "whitworth", "--json", "--units", "mm", "--angles", "deg"))
    assert si["units"]["parameters"]["r"] == "m" and si["parameters"]["r"] == pytest.approx(0.15, rel=1e-15)
    assert si["units"]["parameters"]["omega1"] == "rad/s" and si["parameters"]["omega1"] == pytest.approx(2 * math.pi)
    assert shown["units"]["parameters"]["r"] == "mm" and shown["parameters"]["r"] == pytest.approx(150.0, rel=1e-15)
    assert shown["units"]["parameters"]["omega1"] == "deg/s" and shown["parameters"]["omega1"] == pytest.approx(360.0)
    assert shown["units"]["parameters"]["branch"] == "" and shown["parameters"]["branch"] == 1.0
    cmp = json.loads(run("compare", "whitworth", "--json", "--units", "cm", "--speeds", "rpm"))
    assert cmp["units"]["parameters"]["rod"] == "cm" and cmp["parameters"]["rod"] == pytest.approx(50.0, rel=1e-15)
    assert cmp["units"]["parameters"]["omega1"] == "rpm" and cmp["parameters"]["omega1"] == pytest.approx(60.0)


def test_a_parameter_written_in_degrees_is_an_angle():
    # peaucellier.toml: swing = "25deg", used only inside other parameters' expressions
    mech = analytic.load("peaucellier")
    assert Q.parameter_quantity(mech, "swing") == Q.ANGLE
    assert Q.parameters_in(mech, Q.Display("mm", "deg"))["swing"] == pytest.approx(25.0, rel=1e-14)


def test_check_prints_a_slider_range_in_the_file_unit_that_can_be_pasted(tmp_path):
    # tests/kinds/slider.toml (mm): the block B on a line at 10 deg through O, rod BC = 100 to the rocker DC = 40
    # about D = (60, 80). Its range of s ends where C folds: |BD| = 140 or 60 (by hand below).
    path = Path(__file__).parent / "kinds" / "slider.toml"
    text = run("check", path)
    line = line_with(text, "spiston assembles in")
    m = re.search(r"assembles in (-?[\d.]+)\.\.(-?[\d.]+) mm", line)
    assert m, line
    lo, hi = float(m.group(1)), float(m.group(2))
    c, s = math.cos(math.radians(10)), math.sin(math.radians(10))
    # |B - D| = 140 with B = s (c, s), |D| = 100: s^2 - 2 s (60 c + 80 s) + 100^2 - 140^2 = 0, both roots
    b = 60 * c + 80 * s
    ends = sorted([b - math.sqrt(b * b - (100 ** 2 - 140 ** 2)), b + math.sqrt(b * b - (100 ** 2 - 140 ** 2))])
    # printed to 6 digits (1e-4 mm here), rounded inward: strictly inside, by less than a printed digit
    assert ends[0] < lo < ends[0] + 1e-4 and ends[1] - 1e-3 < hi < ends[1]
    in_m = re.search(r"assembles in (-?[\d.]+)\.\.(-?[\d.]+) m ", line_with(run("check", path, "--units", "m"),
                                                                          "spiston") + " ")
    assert float(in_m.group(1)) == pytest.approx(lo / 1000, abs=2e-6)
    # pasted into --input-range (file units, like --set): it assembles at both ends
    csv_path = tmp_path / "s.csv"
    run("analyze", path, "--input-range", f"{lo}:{hi}", "--samples", 5, "--csv", csv_path)
    with open(csv_path) as f:
        rows = list(csv.DictReader(f))
    assert float(rows[0]["spiston"]) == pytest.approx(lo / 1000, rel=1e-12)      # SI: the mm value / 1000
    assert float(rows[-1]["spiston"]) == pytest.approx(hi / 1000, rel=1e-12)
