"""Analysis sheets with matplotlib: simulated samples over the analytic curves, against the input angle,
with the errors on their own axes (after the seeds' MATLAB figures)."""

from __future__ import annotations

import math
import textwrap

import numpy as np

from .compare import Comparison
from .io import atomic_path, check_writable
from .params import OUTPUT_POINT

PLOT_SUFFIXES = (".png", ".svg", ".pdf")
MARK_EVERY = 12
"""Plot every 12th simulated sample as a marker: at 500 steps per revolution, one per ~9 degrees."""

# Panels per mechanism: (title, [(output, legend label, factor)], y label). Angles plotted in degrees.
DEG = 180.0 / math.pi
PANELS = {
    "fourbar": [
        ("Link angles", [("phi2", "coupler $\\varphi_2$", DEG), ("phi3", "rocker $\\varphi_3$", DEG)], "angle [deg]"),
        ("Angular velocities", [("omega2", "$\\omega_2$", 1), ("omega3", "$\\omega_3$", 1)], "[rad/s]"),
        ("Angular accelerations", [("alpha2", "$\\alpha_2$", 1), ("alpha3", "$\\alpha_3$", 1)], "[rad/s$^2$]"),
        ("Transmission angle", [("mu", "$\\mu$", DEG)], "angle [deg]"),
        ("Coupler point E: velocity", [("vxE", "$v_{Ex}$", 1), ("vyE", "$v_{Ey}$", 1)], "[m/s]"),
        ("Coupler point E: acceleration", [("axE", "$a_{Ex}$", 1), ("ayE", "$a_{Ey}$", 1)], "[m/s$^2$]"),
    ],
    "sixbar": [
        ("Guide and rod angles", [("phi3", "guide $\\varphi_3$", DEG), ("phi4", "rod $\\varphi_4$", DEG)], "angle [deg]"),
        ("Angular velocities", [("omega3", "$\\omega_3$", 1), ("omega4", "$\\omega_4$", 1)], "[rad/s]"),
        ("Angular accelerations", [("alpha3", "$\\alpha_3$", 1), ("alpha4", "$\\alpha_4$", 1)], "[rad/s$^2$]"),
        ("Block on the guide bar", [("s", "$s$ [m]", 1), ("ds", "$\\dot s$ [m/s]", 1)], "[m], [m/s]"),
        ("Ram velocity", [("vxC", "$v_C$", 1)], "[m/s]"),
        ("Ram position and acceleration", [("xC", "$x_C$ [m]", 1), ("axC", "$a_C$ / 10 [m/s$^2$]", 0.1)], "[m], [m/s$^2$]"),
    ],
    "fivebar": [
        ("Link 3 angle", [("theta3", "$\\theta_3$", DEG)], "angle [deg]"),
        ("Link 3 angular velocity", [("omega3", "$\\omega_3$", 1)], "[rad/s]"),
        ("Link 3 angular acceleration", [("alpha3", "$\\alpha_3$", 1)], "[rad/s$^2$]"),
        ("Slide S = |BC|", [("S", "$S$ [m]", 1), ("dS", "$\\dot S$ / 10 [m/s]", 0.1)], "[m], [m/s]"),
        ("Point P: velocity", [("vxP", "$v_{Px}$", 1), ("vyP", "$v_{Py}$", 1)], "[m/s]"),
        ("Point P: acceleration", [("axP", "$a_{Px}$", 1), ("ayP", "$a_{Py}$", 1)], "[m/s$^2$]"),
    ],
}
PATH_TITLE = {"fourbar": "Coupler curve of E", "sixbar": "Ram C", "fivebar": "Path of P"}
ERROR_GROUPS = (("Position error", ("rad", "m")), ("Velocity error", ("rad/s", "m/s")),
                ("Acceleration error", ("rad/s^2", "m/s^2")))


def check_plot_path(out: str):
    return check_writable(out, PLOT_SUFFIXES)


def _input_angle(c: Comparison) -> tuple[np.ndarray, str]:
    key = "phi2" if c.trajectory.name == "fivebar" else "phi1"
    phi = np.unwrap(c.trajectory.inputs[key])
    return np.degrees(phi), f"crank angle $\\varphi_{key[-1]}$ [deg]"


def _series(ax, x, c: Comparison, lines, colors) -> None:
    for (name, label, factor), color in zip(lines, colors):
        ref = np.asarray(getattr(c.analytic, name)) * factor
        sim = c.trajectory.outputs[name] * factor
        if factor == DEG and name != "mu":                  # continuous curves for turning links
            ref, sim = np.degrees(np.unwrap(ref / DEG)), np.degrees(np.unwrap(sim / DEG))
        ax.plot(x, ref, color=color, lw=1.6, label=f"{label} analytic")
        ax.plot(x[::MARK_EVERY], sim[::MARK_EVERY], "o", ms=3.5, mfc="none", color=color, label=f"{label} MuJoCo")


def sheet(c: Comparison, mech, out: str):
    """Draw the analysis sheet of comparison ``c`` and save it atomically to ``out`` (.png/.svg/.pdf)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    name = c.trajectory.name
    x, xlabel = _input_angle(c)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    fig, axes = plt.subplots(4, 4, figsize=(17, 14.5), constrained_layout=True)
    panels = PANELS[name]
    slots = [axes[0, 0], axes[0, 1], axes[0, 2], axes[1, 0], axes[1, 1], axes[1, 2]]
    for ax, (title, lines, ylabel) in zip(slots, panels):
        _series(ax, x, c, lines, colors)
        ax.set(title=title, xlabel=xlabel, ylabel=ylabel)
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    if name == "sixbar":
        _mark_strokes(axes[1, 1], x, c.trajectory.outputs["vxC"])
    _path_panel(axes[0, 3], c, mech)
    for ax, (title, units) in zip((axes[2, 0], axes[2, 1], axes[2, 2]), ERROR_GROUPS):
        _error_panel(ax, x, c, units, title, xlabel)
    _summary_panel(axes[1, 3], c, mech)
    _speed_panel(axes[2, 3], x, c, xlabel, colors)
    _torque_panels(axes[3], x, c, xlabel, colors)
    fig.suptitle(f"{name}: MuJoCo simulation (markers) over the analytic solution (lines)", fontsize=14)
    with atomic_path(out) as tmp:
        fig.savefig(tmp, dpi=90)
    plt.close(fig)
    return out


def _mark_strokes(ax, x, vx) -> None:
    """Shade the cutting (slow) and return (fast) strokes of the ram."""
    cutting = vx < 0 if np.sum(vx < 0) > np.sum(vx > 0) else vx > 0
    lo, hi = ax.get_ylim()
    ax.fill_between(x, lo, hi, where=cutting, color="tab:green", alpha=0.10, label="cutting stroke")
    ax.fill_between(x, lo, hi, where=~cutting, color="tab:red", alpha=0.08, label="return stroke")
    ax.set_ylim(lo, hi)
    ax.legend(fontsize=7)


def _path_panel(ax, c: Comparison, mech) -> None:
    (xk, yk), title = OUTPUT_POINT[c.trajectory.name], PATH_TITLE[c.trajectory.name]
    if yk is None:                                           # the ram moves on a line: x against time
        ax.plot(c.trajectory.t, getattr(c.analytic, xk), lw=1.6, label="analytic")
        ax.plot(c.trajectory.t[::MARK_EVERY], c.trajectory.outputs[xk][::MARK_EVERY], "o", ms=3.5, mfc="none",
                label="MuJoCo")
        ax.set(title=f"{title}: position (stroke {np.ptp(getattr(c.analytic, xk)):.4g} m)",
               xlabel="time [s]", ylabel="$x_C$ [m]")
    else:
        ax.plot(getattr(c.analytic, xk), getattr(c.analytic, yk), lw=1.6, label="analytic")
        ax.plot(c.trajectory.outputs[xk][::MARK_EVERY], c.trajectory.outputs[yk][::MARK_EVERY], "o", ms=3.5,
                mfc="none", label="MuJoCo")
        ax.set(title=title, xlabel=f"${xk[0]}_{xk[1:]}$ [m]", ylabel=f"${yk[0]}_{yk[1:]}$ [m]")
        ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)


def _error_panel(ax, x, c: Comparison, units, title, xlabel) -> None:
    for name, e in c.errors.items():
        if e["unit"] not in units:
            continue
        diff = np.abs(c.trajectory.outputs[name] - np.asarray(getattr(c.analytic, name)))
        if name in ("phi2", "phi3", "phi4", "theta3"):
            diff = np.abs(np.angle(np.exp(1j * (c.trajectory.outputs[name] - getattr(c.analytic, name)))))
        ax.semilogy(x, np.maximum(diff, 1e-18), lw=1.0, label=f"{name} [{e['unit']}]")
    tols = sorted({e["tol"] for e in c.errors.values() if e["unit"] in units})
    for tol in tols:
        ax.axhline(tol, color="k", ls="--", lw=0.8)
    ax.set_ylim(bottom=min(tols) * 1e-7)                    # hide the exact zero of the first sample
    ax.set(title=f"{title} (dashed: tolerance)", xlabel=xlabel, ylabel="|MuJoCo - analytic|")
    ax.legend(fontsize=7, ncol=2)
    ax.grid(alpha=0.3, which="both")


def _summary_panel(ax, c: Comparison, mech) -> None:
    from .figures import figures
    ax.axis("off")
    tr = c.trajectory
    fig = figures(mech, c.analytic)
    deg = math.degrees
    lines = [f"{tr.steps} steps of {tr.timestep * 1e3:g} ms ({tr.integrator}), {tr.cpu_seconds * 1e3:.1f} ms CPU",
             f"max loop violation {c.max_loop_violation:.2e} m",
             f"speed ripple {100 * c.speed_ripple:.2f} % of the commanded speed",
             "comparison: " + ("PASSED" if c.passed else "FAILED"), ""]
    if tr.name == "fourbar":
        lines += [f"Grashof: {fig['grashof']}, {fig['inversion']}",
                  f"transmission angle {deg(fig['mu_min']):.2f} .. {deg(fig['mu_max']):.2f} deg",
                  f"rocker swing {deg(fig['phi3_swing']):.2f} deg"]
    elif tr.name == "sixbar":
        lines += [f"stroke H = {fig['stroke'] * 1e3:.2f} mm", f"guide swing = {deg(fig['swing']):.2f} deg",
                  f"quick-return ratio K = {fig['K']:.4f}"]
    else:
        lines += [f"speed ratio i = omega2/omega4 = {fig['speed_ratio']:.4g}",
                  f"S = {fig['S_range'][0] * 1e3:.2f} .. {fig['S_range'][1] * 1e3:.2f} mm",
                  f"|vP| mean {fig['vP_mean']:.4g}, min {fig['vP_min']:.4g}, max {fig['vP_max']:.4g} m/s"]
    params = ", ".join(f"{k}={v:.4g}" for k, v in vars(mech).items())
    lines += ["", "parameters:"] + textwrap.wrap(params, 48)
    ax.text(0.0, 1.0, "\n".join(lines), va="top", family="monospace", fontsize=8.5, transform=ax.transAxes)


def _speed_panel(ax, x, c: Comparison, xlabel, colors) -> None:
    """Speed of the output point (four-bar E, five-bar P) or of the ram, analytic and simulated."""
    name = c.trajectory.name
    if name == "sixbar":
        ref, sim, label = np.abs(c.analytic.vxC), np.abs(c.trajectory.outputs["vxC"]), "ram speed $|v_C|$"
    else:
        p = "E" if name == "fourbar" else "P"
        ref = np.hypot(getattr(c.analytic, f"vx{p}"), getattr(c.analytic, f"vy{p}"))
        sim = np.hypot(c.trajectory.outputs[f"vx{p}"], c.trajectory.outputs[f"vy{p}"])
        label = f"speed of {p} $|v_{p}|$"
    ax.plot(x, ref, color=colors[0], lw=1.6, label="analytic")
    ax.plot(x[::MARK_EVERY], sim[::MARK_EVERY], "o", ms=3.5, mfc="none", color=colors[0], label="MuJoCo")
    ax.set(title=label, xlabel=xlabel, ylabel="[m/s]")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)


def flywheel_energy(t: np.ndarray, power: np.ndarray) -> np.ndarray:
    """Energy [J] a flywheel must absorb: the integral of (power - mean power) over time (trapezoid);
    its max - min is the fluctuation to size the flywheel for."""
    excess = power - np.trapezoid(power, t) / (t[-1] - t[0])
    return np.concatenate([[0.0], np.cumsum(0.5 * np.diff(t) * (excess[1:] + excess[:-1]))])


def _torque_panels(axes, x, c: Comparison, xlabel, colors) -> None:
    """Crank torque(s), simulated over analytic; their error; the flywheel energy; the figures."""
    tr = c.trajectory
    names = sorted(c.torques)
    power = 0.0
    for name, color in zip(names, colors):
        ref, sim = c.torques[name], tr.forces[name]
        axes[0].plot(x, ref, color=color, lw=1.6, label=f"$\\tau_{name[-1]}$ analytic")
        axes[0].plot(x[::MARK_EVERY], sim[::MARK_EVERY], "o", ms=3.5, mfc="none", color=color,
                     label=f"$\\tau_{name[-1]}$ MuJoCo")
        axes[1].plot(x, np.abs(sim - ref), color=color, lw=1.0, label=name)
        axes[1].axhline(c.errors[name]["tol"], color=color, ls="--", lw=0.8)
        power = power + ref * tr.inputs["omega" + name[-1]]
    axes[0].set(title="Driving torque", xlabel=xlabel, ylabel="[N m]")
    axes[1].set(title="Torque error (dashed: 0.5 % of peak)", xlabel=xlabel, ylabel="|MuJoCo - analytic| [N m]")
    axes[1].set_yscale("log")
    energy = flywheel_energy(tr.t, power)
    axes[2].plot(x, energy, color=colors[0], lw=1.6)
    axes[2].set(title=f"Flywheel: excess energy (swing {np.ptp(energy):.4g} J)", xlabel=xlabel,
                ylabel="$\\int (P - \\bar P)\\,dt$ [J]")
    for ax in axes[:3]:
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7)
    axes[1].legend(fontsize=7)
    axes[3].axis("off")
    lines = []
    for name in names:
        ref = c.torques[name]
        lines.append(f"{name}: peak {np.max(np.abs(ref)):.4g} N m, RMS {np.sqrt(np.mean(ref ** 2)):.4g} N m")
    lines += [f"mean drive power {np.trapezoid(power, tr.t) / (tr.t[-1] - tr.t[0]):.4g} W",
              f"flywheel energy swing {np.ptp(energy):.4g} J",
              f"work balance {c.work_balance:.2e} of the KE swing"]
    axes[3].text(0.0, 1.0, "\n".join(lines), va="top", family="monospace", fontsize=9, transform=axes[3].transAxes)
