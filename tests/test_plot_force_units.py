"""Plots and render overlays in the file's force units (SPEC "Units of results", issue 27 item 4): an
inch-pound file's force sheet, analysis sheet, dynamics sheet and video legend show lbf and lbf in, and SI
(N, N m) with ``--units SI``. The plotted data (the matplotlib artists' data) is checked against hand statics
in the file's units and against the JSON's SI numbers converted by hand (1 lbf = 4.4482216152605 N,
1 in = 0.0254 m), never against the code's own conversion."""

from __future__ import annotations

import json
import re
from types import SimpleNamespace

import numpy as np
import pytest

import analytic
import cli_runner
from test_force_units_display import CRANK

LBF = 4.4482216152605               # N per lbf (0.45359237 kg x 9.80665 m/s^2, exact)
IN = 0.0254                         # m per inch, exact
LBF_IN = LBF * IN                   # N m per lbf in


@pytest.fixture
def inch_pound(tmp_path):
    # a crank of 2 in pushed by 10 lbf at its pin, square to it (frame = link): by hand statics the drive
    # holds -F r = -20 lbf in at every angle; the crank turns at 60 deg/s, its inertia adds ~1e-4 of that
    p = tmp_path / "ip.toml"
    p.write_text(CRANK.format(units="in", force_line='force_units = "lbf"', omega='"60deg"', d=6.0, r=2.0, b=6.0,
                              c=5.0, F=10.0))
    return p


def display(path, units=None):
    from sim.output.units import shown_units
    return shown_units(SimpleNamespace(units=units, angles=None, speeds=None), analytic.load(str(path)))


def lines_of(ax):
    return [np.asarray(ln.get_ydata(), dtype=float) for ln in ax.get_lines()]


def test_the_force_sheet_is_in_lbf_and_lbf_in_or_si(inch_pound):
    from sim import service
    from sim.output.plot import force_figure
    import matplotlib.pyplot as plt
    mech = analytic.load(str(inch_pound))
    built, c = service.compare(mech, 1.0)
    rec = json.loads(cli_runner.run("forces", inch_pound, "--json").stdout)              # SI
    tau_si = np.asarray(rec["drives"]["phi1"])
    phi = np.mod(np.asarray(rec["inputs"]["phi1"]), 2 * np.pi)
    a = next(j for j in rec["joints"] if j["point"] == "A")
    bearing_si = float(np.max(np.hypot(a["Fx"], a["Fy"])))
    for units, f_force, f_moment, moment in ((None, 1 / LBF, 1 / LBF_IN, "lbf in"), ("SI", 1.0, 1.0, "N m")):
        fig = force_figure(c, built, display(inch_pound, units))
        try:
            axes = {ax.get_title().split(":")[0].split("\n")[0]: ax for ax in fig.axes if ax.get_title()}
            drive = axes["Drives"]
            assert drive.get_ylabel() == f"[{moment}]"
            newton_euler = lines_of(drive)[0]
            # hand statics: -20 lbf in (inertia at 60 deg/s ~1e-4 of it)
            assert np.allclose(newton_euler, -20.0 * LBF_IN * f_moment, rtol=1e-3)
            # the JSON's SI drive converted by hand, at the plot's crank angles (linear interpolation between
            # the JSON's 1 deg samples of a 1e-4 ripple: ~1e-9; the plot's are MuJoCo's inputs, 1e-6 rad off)
            x = np.asarray(drive.get_lines()[0].get_xdata(), dtype=float)
            at = np.interp(np.mod(x, 360.0), np.degrees(phi), tau_si, period=360.0)
            assert np.allclose(newton_euler, at * f_moment, rtol=1e-6)
            bearing = next(ax for t, ax in axes.items() if t.startswith("Bearing A"))
            unit = "lbf" if units is None else "N"
            assert bearing.get_xlabel() == f"$F_x$ [{unit}]"
            fx, fy = bearing.get_lines()[0].get_xdata(), bearing.get_lines()[0].get_ydata()
            # |F| at A is the 10 lbf push (the coupler and rocker carry nothing): 1e-3 (inertia)
            assert np.max(np.hypot(fx, fy)) == pytest.approx(10.0 * LBF * f_force, rel=1e-3)
            assert np.max(np.hypot(fx, fy)) == pytest.approx(bearing_si * f_force, rel=1e-4)
        finally:
            plt.close(fig)


def test_the_analysis_sheets_torque_is_in_the_files_units(inch_pound):
    # the sheet's torque row (sim.output.plot._torque_panels, as sheet_figure draws it) on a figure of its own:
    # the whole 16-panel sheet costs ~15 s of matplotlib layout (test_the_sheets_are_drawn, slow tier)
    from sim import service
    from sim.output.plot import _torque_panels
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    mech = analytic.load(str(inch_pound))
    built, c = service.compare(mech, 1.0)
    ref_si = np.asarray(c.torques["tau1"])                       # the comparison's analytic torque, SI
    x = np.degrees(c.trajectory.inputs["phi1"])
    for units, f, label in ((None, 1 / LBF_IN, "[lbf in]"), ("SI", 1.0, "[N m]")):
        fig, axes = plt.subplots(1, 4)
        try:
            _torque_panels(axes, x, c, "phi1 [deg]", ["C0", "C1"], built, display(inch_pound, units))
            assert axes[0].get_title() == "Driving torque" and axes[0].get_ylabel() == label
            y = lines_of(axes[0])[0]
            assert np.allclose(y, ref_si * f, rtol=1e-12)                        # rounding
            assert np.allclose(y, -20.0 * LBF_IN * f, rtol=1e-3)                   # hand statics (inertia)
            # the figures' line, 4 significant digits, in the file's unit: 20 lbf in, or 2.26 N m, within the
            # links' inertia ripple (2.6e-4 of it: the peak reads 20.01 lbf in) and the 4 digits' rounding
            m = re.search(r"tau1: peak (\S+) (.+?),", axes[3].texts[0].get_text())
            assert m and m.group(2) == label[1:-1]
            assert float(m.group(1)) == pytest.approx(20.0 * LBF_IN * f, rel=1e-3)
        finally:
            plt.close(fig)


@pytest.mark.slow
@pytest.mark.parametrize("extra", [("--forces",), ()])
def test_the_sheets_are_drawn(inch_pound, extra):
    out = inch_pound.parent / "sheet.png"
    r = cli_runner.run("plot", inch_pound, "--out", out, "--units", "SI", *extra)
    assert r.returncode == 0, r.stderr
    assert out.stat().st_size > 10_000


def test_the_dynamics_sheet_torque_is_in_lbf_in(inch_pound):
    from analytic.applications import motor as amotor
    from sim.model import Loads
    from sim.output.dynamics_plot import figure
    from sim.run import motor as smotor
    import matplotlib.pyplot as plt
    mech = analytic.load(str(inch_pound))
    T0, W0 = 5.0, 120 * 2 * np.pi / 60                 # N m, rad/s
    d = smotor.dynamics(mech, Loads(), amotor.LinearMotor(T0, W0), 0.01, revolutions=2)
    for units, f, label in ((None, 1 / LBF_IN, "motor torque [lbf in]"), ("SI", 1.0, "motor torque [N m]")):
        fig = figure(d, display(inch_pound, units))
        try:
            ax = fig.axes[2]
            assert ax.get_ylabel() == label
            t, y = np.asarray(ax.get_lines()[0].get_xdata()), lines_of(ax)[0]
            # the motor's law T0 (1 - w / W0) at the run's speeds, converted by hand: rounding
            w = np.interp(t, d.run.t, d.run.omega)
            assert np.allclose(y, T0 * (1 - w / W0) * f, rtol=1e-9, atol=1e-9 * T0 * f)
            assert np.max(np.abs(y)) > 0.5 * T0 * f                 # the start-up's torque, near stall, is there
        finally:
            plt.close(fig)


def test_the_videos_force_legend_is_a_round_value_in_the_files_unit(inch_pound):
    from sim.model import build
    from sim.output.drawing import force_arrows, force_legend_text, poses, scene
    mech = analytic.load(str(inch_pound))
    built = build(mech)
    xy, _ = poses(built, built.qpos0[None])
    for units, text, newtons in ((None, "100 lbf", 100 * LBF), ("SI", "500 N", 500.0)):
        sc = force_arrows(scene(built, xy, display(inch_pound, units)), 1000.0)
        # half the 1000 N peak is 112.4 lbf: the round value below it is 100 lbf (444.8 N); in N: 500 N
        assert force_legend_text(sc) == text
        assert sc.force_ref == pytest.approx(newtons, rel=1e-12)                  # rounding


def test_units_si_prints_newtons_for_a_pound_file(inch_pound):
    # the printed table with --units SI: the 10 lbf push is 44.48 N at A, the drive 20 lbf in = 2.2597 N m
    # (inertia at 60 deg/s adds ~3e-4 at the peak: the table's 5 digits show it)
    text = cli_runner.run("forces", inch_pound, "--units", "SI").stdout
    a = re.search(r"^\s+A\s+R\s+ground-1\s+(\S+)", text, re.M)
    m = re.search(r"drive of phi1: peak torque (\S+) (.+?) at", text)
    assert "peak |F| [N]" in text and float(a.group(1)) == pytest.approx(10 * LBF, rel=1e-3)
    assert m.group(2) == "N m" and float(m.group(1)) == pytest.approx(20 * LBF_IN, rel=1e-3)
    rec = json.loads(cli_runner.run("forces", inch_pound, "--units", "SI", "--json").stdout)
    assert rec["units"]["force"] == "N" and rec["units"]["drives"]["phi1"] == "N m"
