"""Issue 32, consistency a user meets: the same option names and value forms in every command, units
said and kept, an implausible size warned of by check and analyze, every file written announced."""

import re
import subprocess
import sys

import pytest


def run(folder, *args, timeout=120):
    return subprocess.run([sys.executable, "-m", "sim", *args], capture_output=True, text=True, cwd=folder,
                          timeout=timeout)


def _parse(*argv):
    from sim.front.cli import _join_negative_values, make_parser
    parser = make_parser()
    return parser.parse_args(_join_negative_values(parser, list(argv)))


@pytest.mark.parametrize("problem, extra", [("two-position", []), ("motion", ["p.csv"]), ("function", ["p.csv"]),
                                            ("path", ["t.csv"])])
def test_synthesize_takes_units_like_every_other_command_and_keeps_unit(problem, extra):
    assert _parse("synthesize", problem, *extra, "--units", "cm").unit == "cm"
    assert _parse("synthesize", problem, *extra, "--unit", "cm").unit == "cm"      # the old spelling still works


@pytest.mark.parametrize("text, deg", [("30", 30.0), ("30deg", 30.0), ("0.5rad", 28.64788975654116)])
def test_min_transmission_takes_deg_like_every_other_angle(text, deg):
    # 1e-12: rounding of the radian conversion only
    assert _parse("synthesize", "path", "t.csv", "--min-transmission", text).min_transmission == pytest.approx(
        deg, abs=1e-12)


def test_min_transmission_nonsense_is_one_line(tmp_path):
    r = run(tmp_path, "synthesize", "path", "t.csv", "--min-transmission", "thirty")
    assert r.returncode == 2 and re.fullmatch(r"linkage: error: argument --min-transmission: 'thirty' is not an "
                                              r"angle in degrees .*\n", r.stderr), r.stderr


@pytest.mark.parametrize("text, si", [("0.01", 0.01), ("0.01kg*m^2", 0.01), ("10000kg*mm^2", 0.01),
                                      ("10000 kgmm2", 0.01), ("100kg*cm^2", 0.01), ("1kg*in^2", 0.0254 ** 2)])
def test_flywheel_bare_is_kg_m2_and_a_suffix_gives_a_files_inertia_unit(text, si):
    from sim.front.cli.dynamics import parse_flywheel
    # 1e-15 relative: one multiplication by the unit's factor
    assert parse_flywheel(text) == pytest.approx(si, rel=1e-15)


@pytest.mark.parametrize("text, si", [("15", 15.0), ("15rad/s", 15.0), ("150rpm", 150 * 2 * 3.141592653589793 / 60)])
def test_motor_speed_in_rad_s_or_rpm_as_the_app(text, si):
    from sim.front.cli.dynamics import parse_speed
    # 1e-15 relative: one multiplication by the unit's factor
    assert parse_speed("--motor W0", text) == pytest.approx(si, rel=1e-15)


def _mm_fourbar(folder):
    from analytic.registry import LIBRARY
    text = (LIBRARY / "fourbar.toml").read_text().replace('output = "E"', 'output = "E"\nunits = "mm"', 1)
    (folder / "mm.toml").write_text(text)


@pytest.mark.parametrize("cmd", [["check"], ["analyze"], ["analyze", "--json"]])
def test_metres_typed_into_a_mm_file_are_warned_of_by_check_and_analyze(tmp_path, cmd):
    _mm_fourbar(tmp_path)
    r = run(tmp_path, cmd[0], "mm.toml", *cmd[1:])
    assert r.returncode == 0, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and re.fullmatch(r"linkage: warning: the fourbar spans 0\.3 mm, too small to simulate .*"
                                            r"were metres typed into a mm file\? give the lengths in mm", lines[0])


def test_a_plausible_design_gets_no_warning(tmp_path):
    r = run(tmp_path, "check", "fourbar")
    assert r.returncode == 0 and r.stderr == "", r.stderr


def test_the_size_bounds_are_the_simulations():
    from sim.front.cli.options import SMALLEST_SIZE
    from sim.model.build import MIN_SIZE
    assert SMALLEST_SIZE == MIN_SIZE


def test_no_chart_series_in_the_app_goes_without_a_label():
    """uPlot shows "Value" for a series without a label (the stray "Value" in the Dynamics legend)."""
    from pathlib import Path
    import sim
    js = (Path(sim.__file__).parent / "front" / "static" / "app.js").read_text()
    assert not re.search(r"""label:\s*(""|''|``)""", js)


def test_a_long_title_is_wrapped_inside_the_figure():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from sim.output.fit import fit_titles
    fig, axes = plt.subplots(2, 2, figsize=(7.5, 6))
    fig.suptitle("a_rather_long_mechanism_name_from_an_import_of_pyslvs under a motor, flywheel 0.001 kg m^2; "
                 "MuJoCo agrees")
    axes[0, 0].set_title("Path of E (width 191.5 mm, height 183.5 mm, over the rocking range 42..104 deg)")
    fig.tight_layout()
    fit_titles(fig)
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    width = fig.get_figwidth() * fig.dpi
    for t in (fig._suptitle, axes[0, 0].title):
        box = t.get_window_extent(r)
        assert 0 <= box.x0 and box.x1 <= width, (t.get_text(), box)          # nothing cut at the edges
    mid = axes[0, 1].get_window_extent(r)
    assert axes[0, 0].title.get_window_extent(r).x1 <= mid.x0 + 0.03 * width  # nor over the next panel
    plt.close(fig)


def test_dynamics_says_every_file_it_writes(tmp_path):
    r = run(tmp_path, "dynamics", "fourbar", "--motor", "2,150rpm", "--plot", "d.png", "--csv", "d.csv",
            "--revolutions", "3")
    assert r.returncode == 0, r.stderr
    assert "wrote d.csv" in r.stdout.splitlines() and "wrote d.png" in r.stdout.splitlines()
    assert (tmp_path / "d.png").stat().st_size > 0 and (tmp_path / "d.csv").stat().st_size > 0


def test_two_motors_refuse_the_files_they_do_not_write(tmp_path):
    r = run(tmp_path, "dynamics", "fivebar", "--motor", "phi2=2,150rpm", "--motor", "phi4=2,150rpm", "--csv", "x.csv")
    assert r.returncode == 2 and re.fullmatch(r"linkage: error: --csv: the fivebar's two-motor run writes no files "
                                              r"yet.*\n", r.stderr), r.stderr
    assert list(tmp_path.iterdir()) == []


FACTOR = {"s": 1.0, "m": 1.0, "mm": 1e3, "m/s": 1.0, "mm/s": 1e3, "m/s^2": 1.0, "mm/s^2": 1e3, "rad": 1.0,
          "deg": 180 / 3.141592653589793, "rad/s": 1.0, "deg/s": 180 / 3.141592653589793, "rad/s^2": 1.0,
          "deg/s^2": 180 / 3.141592653589793, "N": 1.0, "N m": 1.0}
"""Each unit's value of one SI unit, written out here (not taken from the code under test)."""


@pytest.mark.parametrize("mech", ["slider_crank", "fourbar"])
def test_every_csv_column_is_converted_with_angles_and_units(tmp_path, mech):
    """Every column of ``simulate --csv`` with --angles deg --units mm, the commanded inputs and the joints'
    own coordinates and rates included, is its SI value times its unit's factor; no column is left SI under
    a vague unit ("rad or m")."""
    import json

    import numpy as np
    common = ["simulate", mech, "--revolutions", "0.1"]
    assert run(tmp_path, *common, "--csv", "si.csv").returncode == 0
    assert run(tmp_path, *common, "--csv", "mm.csv", "--angles", "deg", "--units", "mm").returncode == 0
    si = np.genfromtxt(tmp_path / "si.csv", delimiter=",", names=True)
    mm = np.genfromtxt(tmp_path / "mm.csv", delimiter=",", names=True)
    units = json.loads((tmp_path / "mm.csv.units.json").read_text())["units"]
    assert any(c.startswith("q_") for c in units) and any(c.startswith("cmd_") for c in units)
    for column, unit in units.items():
        assert unit in FACTOR, (column, unit)
        # the same run written twice: the conversion's rounding only (1e-12 relative, 1e-9 of a unit absolute)
        np.testing.assert_allclose(mm[column], si[column] * FACTOR[unit], rtol=1e-12, atol=1e-9, err_msg=column)
