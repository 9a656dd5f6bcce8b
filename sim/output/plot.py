"""Analysis sheets with matplotlib: simulated samples over the analytic curves, against the input angle,
with the errors on their own axes (after the seeds' MATLAB figures)."""

from __future__ import annotations

import math
import textwrap

import numpy as np

from analytic.applications import figures
from sim.run.compare import Comparison
from sim.output.io import atomic_path, check_writable
from sim.output.units import output_kind

PLOT_SUFFIXES = (".png", ".svg", ".pdf")
MARK_EVERY = 12
"""Plot every 12th simulated sample as a marker: at 500 steps per revolution, one per ~9 degrees."""

DEG = 180.0 / math.pi
ERROR_GROUPS = (("Position error", ("rad", "m")), ("Velocity error", ("rad/s", "m/s")),
                ("Acceleration error", ("rad/s^2", "m/s^2")))


def check_plot_path(out: str):
    return check_writable(out, PLOT_SUFFIXES)


def panels(mech, display=None) -> list[tuple[str, list[tuple[str, str, float]], str]]:
    """The six curve panels of a mechanism, from its reported outputs: link angles, their rates and
    accelerations, transmission angles (or slides), the output point's velocity and acceleration; each
    line's factor from SI to ``display`` units (angles always in deg), each axis labelled in them."""
    from analytic import quantities as Q
    u = display or Q.Display(mech.units)
    fL, fV, fA = u.factor(Q.LENGTH), u.factor(Q.VELOCITY), u.factor(Q.ACCELERATION)
    fW, fAl = u.factor(Q.ANGULAR_VELOCITY), u.factor(Q.ANGULAR_ACCELERATION)

    def lab(q):
        return "[" + u.unit(q).replace("^2", "$^2$") + "]"
    outs = [n for n in mech.outputs]
    kinds = {n: output_kind(mech, n)[1] for n in outs}
    inputs = {i.q for i in mech.inputs} | {i.qd for i in mech.inputs} | {i.qdd for i in mech.inputs}
    role = {n: mech.table[n].role for n in outs}
    angles = [n for n in outs if kinds[n] == "angle" and role[n] != "transmission" and n not in inputs][:4]
    rates = [n for n in outs if kinds[n] == "ang_velocity" and n not in inputs][:4]
    accs = [n for n in outs if kinds[n] == "ang_acceleration" and n not in inputs][:4]
    mus = [n for n in outs if role[n] == "transmission"][:4]
    slides = [n for n in outs if kinds[n] == "position" and role[n] == "slide"][:2]
    p = mech.output_point
    vel = [n for n in (f"vx{p}", f"vy{p}") if n in outs or not mech.builtin]
    acc = [n for n in (f"ax{p}", f"ay{p}") if n in outs or not mech.builtin]
    fourth = ("Transmission angle", [(n, f"${n}$", DEG) for n in mus], "angle [deg]") if mus else (
        "Slides", [(n, f"${n}$", fL) for n in slides], lab(Q.LENGTH))
    return [("Link angles", [(n, f"${n}$", DEG) for n in angles], "angle [deg]"),
            ("Angular velocities", [(n, f"${n}$", fW) for n in rates], lab(Q.ANGULAR_VELOCITY)),
            ("Angular accelerations", [(n, f"${n}$", fAl) for n in accs], lab(Q.ANGULAR_ACCELERATION)),
            fourth,
            (f"Point {p}: velocity", [(n, f"${n}$", fV) for n in vel], lab(Q.VELOCITY)),
            (f"Point {p}: acceleration", [(n, f"${n}$", fA) for n in acc], lab(Q.ACCELERATION))]


def _input_angle(c: Comparison, mech, u) -> tuple[np.ndarray, str]:
    first = mech.inputs[0]
    q = c.trajectory.inputs[first.q]
    if first.kind == "crank":
        return np.degrees(np.unwrap(q)), f"input angle ${first.q}$ [deg]"
    return q * u.factor("length"), f"input ${first.q}$ [{u.unit('length')}]"


def _series(ax, x, c: Comparison, lines, colors, mech) -> None:
    for (name, label, factor), color in zip(lines, colors):
        ref = np.asarray(c.analytic[name]) * factor
        sim = c.trajectory.outputs[name] * factor
        if output_kind(mech, name)[1] == "angle" and mech.table[name].role != "transmission":   # turning links
            ref, sim = np.degrees(np.unwrap(ref / DEG)), np.degrees(np.unwrap(sim / DEG))
        ax.plot(x, ref, color=color, lw=1.6, label=f"{label} analytic")
        ax.plot(x[::MARK_EVERY], sim[::MARK_EVERY], "o", ms=3.5, mfc="none", color=color, label=f"{label} MuJoCo")


def sheet(c: Comparison, built, out: str, display=None):
    """Draw the analysis sheet of comparison ``c`` and save it atomically to ``out`` (.png/.svg/.pdf), in
    ``display`` units (analytic.quantities.Display; None: the file's length unit)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from analytic.quantities import Display

    mech = built.mech
    u = display or Display(mech.units)
    x, xlabel = _input_angle(c, mech, u)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    fig, axes = plt.subplots(4, 4, figsize=(17, 14.5), constrained_layout=True)
    slots = [axes[0, 0], axes[0, 1], axes[0, 2], axes[1, 0], axes[1, 1], axes[1, 2]]
    for ax, (title, lines, ylabel) in zip(slots, panels(mech, u)):
        _series(ax, x, c, lines, colors, mech)
        ax.set(title=title, xlabel=xlabel, ylabel=ylabel)
        if lines:
            ax.legend(fontsize=7, loc="best")
        ax.grid(alpha=0.3)
    if built.slow_stroke is not None:
        _mark_strokes(axes[1, 1], x, c.trajectory.load)
    _path_panel(axes[0, 3], c, mech, u)
    for ax, (title, units) in zip((axes[2, 0], axes[2, 1], axes[2, 2]), ERROR_GROUPS):
        _error_panel(ax, x, c, units, title, xlabel, u)
    _summary_panel(axes[1, 3], c, built, u)
    _speed_panel(axes[2, 3], x, c, xlabel, colors, mech, u)
    _torque_panels(axes[3], x, c, xlabel, colors, mech)
    fig.suptitle(f"{mech.name}: MuJoCo simulation (markers) over the analytic solution (lines)", fontsize=14)
    with atomic_path(out) as tmp:
        fig.savefig(tmp, dpi=90)
    plt.close(fig)
    return out


def _mark_strokes(ax, x, load) -> None:
    """Shade the cutting (slow) stroke, where the cutting force acts, and the return stroke."""
    cutting = load > 0.5
    lo, hi = ax.get_ylim()
    ax.fill_between(x, lo, hi, where=cutting, color="tab:green", alpha=0.10, label="cutting stroke")
    ax.fill_between(x, lo, hi, where=~cutting, color="tab:red", alpha=0.08, label="return stroke")
    ax.set_ylim(lo, hi)
    ax.legend(fontsize=7)


def _path_panel(ax, c: Comparison, mech, u) -> None:
    p = mech.output_point
    f, unit = u.factor("length"), u.unit("length")
    xa, ya = np.asarray(c.analytic["x" + p]) * f, np.asarray(c.analytic["y" + p]) * f
    tr = c.trajectory
    ax.plot(xa, ya, lw=1.6, label="analytic")
    ax.plot(tr.outputs["x" + p][::MARK_EVERY] * f, tr.outputs["y" + p][::MARK_EVERY] * f, "o", ms=3.5, mfc="none",
            label="MuJoCo")
    ax.set(title=f"Path of {p} (width {np.ptp(xa):.4g} {unit}, height {np.ptp(ya):.4g} {unit})",
           xlabel=f"$x_{{{p}}}$ [{unit}]", ylabel=f"$y_{{{p}}}$ [{unit}]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)


def _error_panel(ax, x, c: Comparison, units, title, xlabel, u) -> None:
    from sim.run.compare import errors_in
    shown = errors_in(c.errors, u)
    for name, e in c.errors.items():
        if e["unit"] not in units:
            continue
        if e["role"] == "drive":
            continue
        diff = np.abs(c.trajectory.outputs[name] - np.asarray(c.analytic[name]))
        if e["unit"] == "rad":
            diff = np.abs(np.angle(np.exp(1j * (c.trajectory.outputs[name] - np.asarray(c.analytic[name])))))
        f = shown[name]["tol"] / e["tol"] if e["tol"] else 1.0           # SI -> display units
        ax.semilogy(x, np.maximum(diff * f, 1e-18), lw=1.0, label=f"{name} [{shown[name]['unit']}]")
    tols = sorted({shown[n]["tol"] for n, e in c.errors.items() if e["unit"] in units and not n.startswith("tau")})
    for tol in tols:
        ax.axhline(tol, color="k", ls="--", lw=0.8)
    ax.set_ylim(bottom=min(tols) * 1e-7)                    # hide the exact zero of the first sample
    ax.set(title=f"{title} (dashed: tolerance)", xlabel=xlabel, ylabel="|MuJoCo - analytic|")
    ax.legend(fontsize=7, ncol=2, loc="lower right")
    ax.grid(alpha=0.3, which="both")


def _summary_panel(ax, c: Comparison, built, u) -> None:
    ax.axis("off")
    lines = summary_lines(c, built, u)
    ax.text(0.0, 1.0, "\n".join(textwrap.shorten(x, 60) if len(x) > 60 else x for x in lines), va="top",
            family="monospace", fontsize=8.5, transform=ax.transAxes)


def summary_lines(c: Comparison, built, u) -> list[str]:
    """The sheet's summary panel: the run, the verdict, the figures of merit as ``analyze`` prints them
    (in display units ``u``), the parameters and loads."""
    from sim import service
    mech = built.mech
    tr = c.trajectory
    figs = service.figures(mech)                 # the figures `analyze` prints, not the simulated samples'
    lines = [f"{tr.steps} steps of {tr.timestep * 1e3:.3g} ms ({tr.integrator}), {tr.cpu_seconds * 1e3:.1f} ms CPU",
             f"max loop violation {u.convert('length', c.max_loop_violation):.2e} {u.unit('length')}",
             f"drive error {c.drive_error:.2e} (commanded - simulated input)",
             "comparison: " + ("PASSED" if c.passed else "FAILED"), ""]
    lines += [ln.strip() for ln in figures.summary(mech, figs, u)]
    loads = built.loads
    extra = []
    if loads.gravity:
        extra.append(f"gravity {loads.gravity[0]:g},{loads.gravity[1]:g} m/s^2")
    if any(loads.force):
        extra.append(f"force {loads.force[0]:g},{loads.force[1]:g} N on {mech.output_point}"
                     + (" (slow stroke)" if loads.slow_stroke_only else ""))
    if loads.inertias:
        extra.append("inertias: " + ", ".join(loads.inertias))
    if mech.rock:
        first = mech.inputs[0]
        extra.append(f"{first.q} rocks {math.degrees(mech.rock[0]):.2f}..{math.degrees(mech.rock[1]):.2f} deg"
                     if first.kind == "crank" else f"{first.q} rocks {mech.rock[0]:g}..{mech.rock[1]:g} m")
    params = ", ".join(f"{k}={v:.4g}" for k, v in mech.parameters.items())
    return lines + ["", "parameters:"] + textwrap.wrap(params, 48) + (["", "loads:"] + extra if extra else [])


def _speed_panel(ax, x, c: Comparison, xlabel, colors, mech, u) -> None:
    """Speed of the output point, analytic and simulated."""
    p = mech.output_point
    f = u.factor("velocity")
    ref = np.hypot(np.asarray(c.analytic["vx" + p]), np.asarray(c.analytic["vy" + p])) * f
    sim = np.hypot(c.trajectory.outputs["vx" + p], c.trajectory.outputs["vy" + p]) * f
    ax.plot(x, ref, color=colors[0], lw=1.6, label="analytic")
    ax.plot(x[::MARK_EVERY], sim[::MARK_EVERY], "o", ms=3.5, mfc="none", color=colors[0], label="MuJoCo")
    ax.set(title=f"speed of {p} $|v_{{{p}}}|$", xlabel=xlabel, ylabel=f"[{u.unit('velocity')}]")
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)


def flywheel_energy(t: np.ndarray, power: np.ndarray) -> np.ndarray:
    """Energy [J] a flywheel must absorb: the integral of (power - mean power) over time (trapezoid);
    its max - min is the fluctuation to size the flywheel for."""
    excess = power - np.trapezoid(power, t) / (t[-1] - t[0])
    return np.concatenate([[0.0], np.cumsum(0.5 * np.diff(t) * (excess[1:] + excess[:-1]))])


def periodic_window(tr, mech) -> np.ndarray:
    """The samples after the drives' start-up: the last whole period of the first input when the run
    has more than one, else all of it (the drives start on the analytic state, so their start-up is
    already small)."""
    period = mech.duration(1.0)
    if tr.t[-1] >= 2 * period - 1e-9:
        return tr.t >= tr.t[-1] - period - 1e-12
    return np.ones_like(tr.t, dtype=bool)


def _torque_panels(axes, x, c: Comparison, xlabel, colors, mech) -> None:
    """Drive torque(s), simulated over analytic; their error; the flywheel energy; the figures."""
    tr = c.trajectory
    names = sorted(c.torques)
    power = 0.0
    qd_of = {f"tau{i.link}": i.qd for i in mech.inputs}
    for name, color in zip(names, colors):
        ref, sim = c.torques[name], tr.forces[name]
        link = mech.table[name].of
        axes[0].plot(x, ref, color=color, lw=1.6, label=f"$\\tau_{{{link}}}$ analytic")
        axes[0].plot(x[::MARK_EVERY], sim[::MARK_EVERY], "o", ms=3.5, mfc="none", color=color,
                     label=f"$\\tau_{{{link}}}$ MuJoCo")
        axes[1].plot(x, np.abs(sim - ref), color=color, lw=1.0, label=name)
        axes[1].axhline(c.errors[name]["tol"], color=color, ls="--", lw=0.8)
        power = power + ref * tr.inputs[qd_of[name]]
    axes[0].set(title="Driving torque", xlabel=xlabel, ylabel="[N m]")
    axes[1].set(title="Torque error (dashed: tolerance)", xlabel=xlabel, ylabel="|MuJoCo - analytic| [N m]")
    axes[1].set_yscale("log")
    window = periodic_window(tr, mech)
    energy = flywheel_energy(tr.t[window], np.broadcast_to(power, tr.t.shape)[window])
    axes[2].plot(x[window], energy, color=colors[0], lw=1.6)
    axes[2].set(title=f"Flywheel: excess energy (swing {np.ptp(energy):.4g} J)", xlabel=xlabel,
                ylabel="$\\int (P - \\bar P)\\,dt$ [J]")
    for ax in axes[:3]:
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7, loc="best")
    axes[1].legend(fontsize=7, loc="best")
    axes[3].axis("off")
    lines = []
    for name in names:
        ref = c.torques[name]
        unit = c.errors[name]["unit"]
        lines.append(f"{name}: peak {np.max(np.abs(ref)):.4g} {unit}, RMS {np.sqrt(np.mean(ref ** 2)):.4g} {unit}")
    pw = np.broadcast_to(power, tr.t.shape)[window]
    lines += [f"mean drive power {np.trapezoid(pw, tr.t[window]) / (tr.t[window][-1] - tr.t[window][0]):.4g} W",
              f"flywheel energy swing {np.ptp(energy):.4g} J",
              f"work balance {c.work_balance:.2e} of the KE swing per revolution"]
    axes[3].text(0.0, 1.0, "\n".join(lines), va="top", family="monospace", fontsize=9, transform=axes[3].transAxes)
