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


def force_scale(u) -> tuple[float, str, float, str]:
    """(display value per newton, its label, per newton metre, its label) in display units ``u``: the file's
    ``force_units`` and moments in force unit x length unit (SPEC "Units of results"; N and N m for SI)."""
    from analytic import quantities as Q
    return u.factor(Q.FORCE), u.unit(Q.FORCE), u.factor(Q.TORQUE), u.unit(Q.TORQUE)


def drive_scale(u, inp) -> tuple[float, str]:
    """(display value per SI value, its label) of input ``inp``'s drive: a torque for a turning input, a force
    for a sliding one."""
    from analytic import quantities as Q
    q = Q.TORQUE if inp.angular else Q.FORCE
    return u.factor(q), u.unit(q)


def tex_escape(name: str) -> str:
    """``name`` for matplotlib's math text: its underscores literal (``phiboom_barrel``, ``s_boom``), not
    subscripts that would swallow the next letter."""
    return name.replace("_", r"\_")


def math_name(name: str) -> str:
    """An output's name set in math italics: ``$name$`` with its underscores literal."""
    return f"${tex_escape(name)}$"


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
    fourth = ("Transmission angle", [(n, math_name(n), DEG) for n in mus], "angle [deg]") if mus else (
        "Slides", [(n, math_name(n), fL) for n in slides], lab(Q.LENGTH))
    return [("Link angles", [(n, math_name(n), DEG) for n in angles], "angle [deg]"),
            ("Angular velocities", [(n, math_name(n), fW) for n in rates], lab(Q.ANGULAR_VELOCITY)),
            ("Angular accelerations", [(n, math_name(n), fAl) for n in accs], lab(Q.ANGULAR_ACCELERATION)),
            fourth,
            (f"Point {p}: velocity", [(n, math_name(n), fV) for n in vel], lab(Q.VELOCITY)),
            (f"Point {p}: acceleration", [(n, math_name(n), fA) for n in acc], lab(Q.ACCELERATION))]


def _input_angle(c: Comparison, mech, u) -> tuple[np.ndarray, str]:
    first = mech.inputs[0]
    q = c.trajectory.inputs[first.q]
    if first.angular:
        return np.degrees(np.unwrap(q)), f"input angle {math_name(first.q)} [deg]"
    return q * u.factor("length"), f"input {math_name(first.q)} [{u.unit('length')}]"


def _series(ax, x, c: Comparison, lines, colors, mech) -> None:
    for (name, label, factor), color in zip(lines, colors):
        ref = np.asarray(c.analytic[name]) * factor
        sim = c.trajectory.outputs[name] * factor
        if output_kind(mech, name)[1] == "angle" and mech.table[name].role != "transmission":   # turning links
            ref, sim = np.degrees(np.unwrap(ref / DEG)), np.degrees(np.unwrap(sim / DEG))
        ax.plot(x, ref, color=color, lw=1.6, label=f"{label} analytic")
        ax.plot(x[::MARK_EVERY], sim[::MARK_EVERY], "o", ms=3.5, mfc="none", color=color, label=f"{label} MuJoCo")


def sheet(c: Comparison, built, out: str, display=None):
    """Draw the analysis sheet of comparison ``c`` (:func:`sheet_figure`) and save it atomically to ``out``
    (.png/.svg/.pdf)."""
    import matplotlib.pyplot as plt
    fig = sheet_figure(c, built, display)
    with atomic_path(out) as tmp:
        fig.savefig(tmp, dpi=90)
    plt.close(fig)
    return out


def sheet_figure(c: Comparison, built, display=None):
    """The analysis sheet of comparison ``c`` as a matplotlib Figure, in ``display`` units
    (analytic.quantities.Display; None: the file's length unit, N and N m)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from analytic.quantities import Display

    mech = built.mech
    u = display or Display(mech.units)
    driven = [i for i in mech.inputs if i.motion.law is not None]
    x, xlabel = _input_angle(c, mech, u)
    if driven:                                   # a law's dwells hold the input: time is the abscissa
        x, xlabel = c.trajectory.t, "time $t$ [s]"
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    from analytic import cams as cam_geometry
    has_cams = bool(cam_geometry.elements(mech))
    rows = 4 + bool(driven) + 2 * has_cams
    fig, axes = plt.subplots(rows, 4, figsize=(17, 3.7 * rows), constrained_layout=True)
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
    _torque_panels(axes[3], x, c, xlabel, colors, built, u)
    if driven:
        law_panels(axes[4], mech, driven, u, c.trajectory)
    if has_cams:
        cam_panels(axes[4 + bool(driven):], mech, u)
    fig.suptitle(f"{mech.name}: MuJoCo simulation (markers) over the analytic solution (lines)", fontsize=14)
    from sim.output.fit import fit_titles
    fit_titles(fig)
    return fig


LAW_SAMPLES = 2000
"""Samples of each cycle of a motion law's s-v-a-j curves (besides every segment boundary, from both sides)."""


def law_panels(axes, mech, driven, u, trajectory=None) -> None:
    """The s-v-a-j diagram of each input driven by a motion law (SPEC "Motion laws") on four axes: its
    position, velocity, acceleration and jerk against time over the run (or one cycle), the segments'
    boundaries dotted, each jump in velocity or acceleration marked; the simulated input (MuJoCo) over the
    position and velocity where ``trajectory`` is given. Angles in deg, lengths in display units ``u``."""
    from analytic import laws
    from analytic import quantities as Q
    end = float(trajectory.t[-1]) if trajectory is not None else mech.duration(1.0)
    titles = ("position $s$", "velocity $v$", "acceleration $a$", "jerk $j$")
    colors = ("tab:blue", "tab:orange", "tab:green", "tab:red")
    for k, i in enumerate(driven):
        law = i.motion.law
        T = law.duration
        edges = (np.r_[law.starts] if isinstance(law, laws.Profile) else np.array([0.0, T]))
        cycles = np.arange(int(np.ceil(end / T - 1e-9)))
        bounds = np.unique(np.clip((cycles[:, None] * T + edges[None, :]).ravel(), 0.0, end))
        grid = np.linspace(0.0, end, int(LAW_SAMPLES * max(1.0, end / T)) + 1)
        t = np.sort(np.r_[grid, bounds[1:] - 1e-9 * T, bounds[:-1] + 1e-9 * T])   # each side of a boundary
        q, v, a = i.motion.at(t)
        j = i.motion.jerk(t)
        if i.angular:
            f, unit = DEG, "deg"
        else:
            f, unit = u.factor(Q.LENGTH), u.unit(Q.LENGTH)
        series = (q, v, a, j)
        units = (unit, f"{unit}/s", f"{unit}/s$^2$", f"{unit}/s$^3$")
        color = colors[k % len(colors)] if len(driven) > 1 else None
        for n, (ax, y, yu) in enumerate(zip(axes, series, units)):
            ax.plot(t, y * f, lw=1.4, color=color or colors[n], label=f"{math_name(i.q)} law")
            for b in bounds:
                ax.axvline(b, color="0.6", ls=":", lw=0.8)
            ax.set(title=f"Input law: {titles[n]}", xlabel="time $t$ [s]", ylabel=f"[{yu}]")
            ax.grid(alpha=0.3)
        if trajectory is not None and i.q in trajectory.inputs:
            for ax, name in ((axes[0], i.q), (axes[1], i.qd)):
                if name in trajectory.inputs:
                    ax.plot(trajectory.t[::MARK_EVERY], np.asarray(trajectory.inputs[name])[::MARK_EVERY] * f, "o",
                            ms=3, mfc="none", color="k", label=f"{math_name(name)} MuJoCo")
        for jump in law.jumps():
            for cyc in cycles:
                tj = cyc * T + jump.t
                if tj > end + 1e-9 * T:
                    continue
                for ax, size in ((axes[1], jump.dv), (axes[2], jump.da)):
                    if size:
                        ax.axvline(tj, color="tab:red", lw=1.2, alpha=0.6)
        for ax in axes:
            ax.legend(fontsize=7, loc="best")


def cam_panels(axes, mech, u) -> None:
    """Two rows per mechanism with cams (SPEC "Cams and followers"), of its first cam: the follower's s-v-a-j
    diagram over the cam angle (the lift and its derivatives per radian of cam, segments' ends dotted), then
    the pressure angle and the profile's radius of curvature over the cam angle, and the cam (its outline,
    pitch curve and base circle in its frame). Lengths in display units ``u``, angles in deg."""
    from analytic import cams
    from analytic import quantities as Q
    name, e = next(iter(cams.elements(mech).items()))
    geo = cams.geometry(mech, e)
    st = geo.setup
    deg = np.degrees(geo.theta)
    h = st.law.at(geo.theta)
    if st.motion == "translating":
        f, unit = u.factor(Q.LENGTH), u.unit(Q.LENGTH)
    else:
        f, unit = DEG, "deg"
    titles = ("lift $s$", "velocity $ds/d\\theta$", "acceleration $d^2s/d\\theta^2$", "jerk $d^3s/d\\theta^3$")
    units = (unit, f"{unit}/rad", f"{unit}/rad$^2$", f"{unit}/rad$^3$")
    colors = ("tab:blue", "tab:orange", "tab:green", "tab:red")
    edges = np.degrees(np.r_[st.law.starts]) if hasattr(st.law, "starts") else np.array([])
    for n, ax in enumerate(axes[0]):
        ax.plot(deg, h[n] * f, lw=1.4, color=colors[n], label=e['links'][0])
        for b in edges:
            ax.axvline(b, color="0.6", ls=":", lw=0.8)
        ax.set(title=f"Cam {name}: {titles[n]}", xlabel="cam angle $\\theta$ [deg]", ylabel=f"[{units[n]}]",
               xlim=(0, 360))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    L, Lu = u.factor(Q.LENGTH), u.unit(Q.LENGTH)
    ax = axes[1, 0]
    ax.plot(deg, np.degrees(geo.pressure_angle), lw=1.4)
    k = int(np.argmax(np.abs(geo.pressure_angle)))
    ax.plot(deg[k], np.degrees(geo.pressure_angle[k]), "o", color="tab:red",
            label=f"largest {np.degrees(geo.pressure_angle_max):.3g} deg at {deg[k]:.4g} deg")
    ax.set(title=f"Cam {name}: pressure angle $pa\\_{name}$", xlabel="cam angle $\\theta$ [deg]", ylabel="[deg]",
           xlim=(0, 360))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    ax = axes[1, 1]
    shown = np.where(np.abs(geo.rho) < 20 * st.base_radius, geo.rho, np.nan)     # a flank's straight bits: off scale
    ax.plot(deg, shown * L, lw=1.4, color="tab:purple")
    k = int(np.argmin(geo.rho))
    ax.plot(deg[k], geo.rho[k] * L, "o", color="tab:red",
            label=f"smallest {geo.rho_min * L:.4g} {Lu} at {deg[k]:.4g} deg (< 0: concave)")
    ax.axhline(0, color="0.4", lw=0.8)
    ax.set(title=f"Cam {name}: radius of curvature $rho\\_{name}$", xlabel="cam angle $\\theta$ [deg]",
           ylabel=f"[{Lu}]", xlim=(0, 360))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    ax = axes[1, 2]
    outline = cams.plate(e, geo)                    # a given profile as the file gives it
    prof, pitch = np.vstack([outline, outline[:1]]) * L, np.vstack([geo.pitch, geo.pitch[:1]]) * L
    ax.fill(prof[:, 0], prof[:, 1], color="tab:blue", alpha=0.15)
    ax.plot(prof[:, 0], prof[:, 1], lw=1.4, color="tab:blue", label="profile")
    if st.contact != "flat":
        ax.plot(pitch[:, 0], pitch[:, 1], lw=0.9, ls="--", color="tab:orange", label="pitch curve")
    a = np.linspace(0, 2 * np.pi, 200)
    ax.plot(st.base_radius * L * np.cos(a), st.base_radius * L * np.sin(a), lw=0.8, ls=":", color="0.4",
            label="base circle")
    ax.plot([0], [0], "+", color="k")
    ax.set(title=f"Cam {name} in its frame", xlabel=f"[{Lu}]", ylabel=f"[{Lu}]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    ax = axes[1, 3]
    ax.axis("off")
    lines = [f"cam {name}: {st.motion} {st.contact} follower ({e['links'][0]})",
             f"base radius {st.base_radius * L:.4g} {Lu}" + (f", roller {st.roller * L:.4g} {Lu}" if st.roller else ""),
             f"largest pressure angle {np.degrees(geo.pressure_angle_max):.4g} deg",
             f"smallest radius of curvature {geo.rho_min * L:.4g} {Lu}"]
    if st.contact == "flat":
        lines.append(f"face travel {geo.face_travel * L:.4g} {Lu}")
    ax.text(0.0, 1.0, "\n".join(lines), va="top", family="monospace", fontsize=9, transform=ax.transAxes)


def cam_figure(mech, display=None):
    """The cam rows of the sheet (:func:`cam_panels`) alone, as a matplotlib Figure: what needs no simulation."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from analytic.quantities import Display
    u = display or Display(mech.units)
    fig, axes = plt.subplots(2, 4, figsize=(17, 7.4), constrained_layout=True)
    cam_panels(axes, mech, u)
    fig.suptitle(f"{mech.name}: cam and follower", fontsize=14)
    return fig


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
                     if first.angular else f"{first.q} rocks {mech.rock[0]:g}..{mech.rock[1]:g} m")
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


def flywheel_energy(t: np.ndarray, power: np.ndarray, period: float) -> tuple[np.ndarray, np.ndarray]:
    """(instants, energy [J]) a flywheel must absorb over the last period of the run: the integral of (power -
    mean power) over exactly one period (trapezoid, analytic.applications.averages); its max - min is the
    fluctuation to size the flywheel for."""
    from analytic.applications.averages import excess_energy
    return excess_energy(t, power, period)


def drive_power(c: Comparison, built) -> tuple[np.ndarray, float, float]:
    """(the drives' power at each step [W], its mean over exactly the last turn [W], the flywheel's energy
    swing over that turn [J]) of the design along its commanded motion: the inverse-dynamics drive forces
    (the model's inertias, gravity and load; not the servo's rotor: the power that reaches the links) at the
    commanded inputs times the commanded rates, so that the servo's start-up ripple of the first turn does not
    count; averaged each instant once (analytic.applications.averages)."""
    from dataclasses import replace

    from analytic.applications import averages
    from sim.run.compare import analytic_forces
    mech = built.mech
    tr = c.trajectory
    q, qd, qdd = mech.drive(tr.t)
    commanded = {getattr(i, a): arr[:, k] for k, i in enumerate(mech.inputs)
                 for a, arr in (("q", q), ("qd", qd), ("qdd", qdd))}
    taus = analytic_forces(replace(tr, inputs={**tr.inputs, **commanded}), built, mech)
    power = np.zeros_like(tr.t)
    for k, i in enumerate(mech.inputs):
        power = power + np.ravel(taus[f"tau{i.link}"]) * qd[:, k]
    period = mech.duration(1.0)
    _, energy = flywheel_energy(tr.t, power, period)
    return power, averages.period_mean(tr.t, power, period), float(np.ptp(energy))


def _torque_panels(axes, x, c: Comparison, xlabel, colors, built, u) -> None:
    """Drive torque(s), simulated over analytic; their error; the flywheel energy; the figures; torques and
    forces in display units ``u`` (the file's force unit)."""
    mech = built.mech
    tr = c.trajectory
    names = sorted(c.torques)
    by_link = {i.link: i for i in mech.inputs}
    units = []
    for name, color in zip(names, colors):
        link = mech.table[name].of
        f, unit = drive_scale(u, by_link[link])
        units.append(unit)
        ref, sim = np.asarray(c.torques[name]) * f, np.asarray(tr.forces[name]) * f
        axes[0].plot(x, ref, color=color, lw=1.6, label=f"$\\tau_{{{tex_escape(link)}}}$ analytic")
        axes[0].plot(x[::MARK_EVERY], sim[::MARK_EVERY], "o", ms=3.5, mfc="none", color=color,
                     label=f"$\\tau_{{{tex_escape(link)}}}$ MuJoCo")
        axes[1].plot(x, np.abs(sim - ref), color=color, lw=1.0, label=name)
        axes[1].axhline(c.errors[name]["tol"] * f, color=color, ls="--", lw=0.8)
    unit = " or ".join(dict.fromkeys(units)) or "N m"
    axes[0].set(title="Driving torque", xlabel=xlabel, ylabel=f"[{unit}]")
    axes[1].set(title="Torque error (dashed: tolerance)", xlabel=xlabel, ylabel=f"|MuJoCo - analytic| [{unit}]")
    axes[1].set_yscale("log")
    from analytic.applications import averages
    period = mech.duration(1.0)
    pw, mean_power, _ = drive_power(c, built)
    te, energy = flywheel_energy(tr.t, pw, period)
    axes[2].plot(np.interp(te, tr.t, x), energy, color=colors[0], lw=1.6)
    axes[2].set(title=f"Flywheel: excess energy (swing {np.ptp(energy):.4g} J)", xlabel=xlabel,
                ylabel="$\\int (P - \\bar P)\\,dt$ [J]")
    for ax in axes[:3]:
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7, loc="best")
    axes[1].legend(fontsize=7, loc="best")
    axes[3].axis("off")
    lines = []
    for name in names:
        f, unit = drive_scale(u, by_link[mech.table[name].of])
        ref = np.asarray(c.torques[name]) * f
        lines.append(f"{name}: peak {np.max(np.abs(ref)):.4g} {unit}, "
                     f"RMS {averages.period_rms(tr.t, ref, period):.4g} {unit}")
    lines += [f"mean drive power {mean_power:.4g} W",
              f"flywheel energy swing {np.ptp(energy):.4g} J",
              f"work balance {c.work_balance:.2e} of the KE swing per revolution"]
    axes[3].text(0.0, 1.0, "\n".join(lines), va="top", family="monospace", fontsize=9, transform=axes[3].transAxes)


# ------------------------------------------------------------------------------------------ force sheet
def force_sheet(c: Comparison, built, out: str, display=None):
    """Draw the force sheet of comparison ``c`` (:func:`force_figure`) and save it atomically to ``out``
    (.png/.svg/.pdf)."""
    import matplotlib.pyplot as plt
    fig = force_figure(c, built, display)
    from sim.output.fit import fit_titles
    fit_titles(fig)
    with atomic_path(out) as tmp:
        fig.savefig(tmp, dpi=90)
    plt.close(fig)
    return out


def force_figure(c: Comparison, built, display=None):
    """The force sheet of comparison ``c`` as a matplotlib Figure: the bearing loads at the
    ground pivots as polar diagrams (the locus of the force each pivot's bearing takes from its link), every
    joint's force magnitude against the input, the prismatic pairs' normal forces and couples, each drive's
    three answers (Newton-Euler, power balance, MuJoCo), the shaking force's locus and the shaking moment,
    and MuJoCo's difference from the analytic forces against the tolerance; analytic forces as lines,
    MuJoCo's as markers (sim.run.forces: at the simulated inputs, every step)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from analytic.quantities import Display
    from sim.run import forces as simforces

    mech = built.mech
    u = display or Display(mech.units)
    x, xlabel = _input_angle(c, mech, u)
    mj, an, _, power = simforces.both(built, c.trajectory)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    grounded = [k for k, j in enumerate(an.joints) if j.a == "ground"][:4]
    slides = [k for k, j in enumerate(an.joints) if j.kind == "prismatic"]
    revolute = [k for k, j in enumerate(an.joints) if j.kind == "revolute"]
    draw = [lambda ax, k=k, n=n: _bearing_panel(ax, an, mj, k, colors[n % len(colors)], u)
            for n, k in enumerate(grounded)]
    draw.append(lambda ax: _magnitude_panel(ax, x, xlabel, an, mj, revolute, colors,
                                            "Pin forces $|F|$ (revolute joints)", u))
    if slides:
        draw.append(lambda ax: _slide_panel(ax, x, xlabel, an, mj, slides, colors, u))
    draw += [lambda ax: _drive_panel(ax, x, xlabel, an, mj, power, mech, colors, u),
             lambda ax: _shaking_locus(ax, an, mj, colors[0], c.trajectory.t, mech.duration(1.0), u),
             lambda ax: _shaking_panel(ax, x, xlabel, an, mj, colors, u),
             lambda ax: _force_error_panel(ax, x, xlabel, an, mj, mech, colors),
             lambda ax: _force_summary(ax, c, built, an, mech, x, u),
             lambda ax: _force_summary_agreement(ax, c, u)]
    rows = math.ceil(len(draw) / 4)
    fig, axes = plt.subplots(rows, 4, figsize=(17, 3.9 * rows), constrained_layout=True)
    for n, ax in enumerate(axes.flat):
        if n < len(draw):
            draw[n](ax)
        else:
            ax.axis("off")
    loads = built.loads
    what = ", ".join(s for s in (f"gravity {loads.gravity[0]:g},{loads.gravity[1]:g} m/s$^2$" if loads.gravity else "",
                                 f"force {loads.force[0]:g},{loads.force[1]:g} N on {mech.output_point}"
                                 if any(loads.force) else "",
                                 ", ".join(ld.name for ld in built.loadset.loads) + (" and friction" if
                                 built.loadset.friction else "") if getattr(built, "loadset", None) else "")
                    if s) or "inertia only"
    fig.suptitle(f"{mech.name}: joint forces ({what}); analytic kinetostatics (lines), MuJoCo (markers)",
                 fontsize=14)
    return fig


def _bearing_panel(ax, an, mj, k, color, u) -> None:
    """The polar diagram of ground joint ``k``: the load its bearing takes, -F (F: the ground on the link), in
    the display's force unit."""
    ff, fl, _, _ = force_scale(u)
    j = an.joints[k]
    fx, fy = -an.F[k, 0] * ff, -an.F[k, 1] * ff
    ax.plot(fx, fy, color=color, lw=1.6, label="analytic")
    ax.plot(-mj.F[k, 0][::MARK_EVERY] * ff, -mj.F[k, 1][::MARK_EVERY] * ff, "o", ms=3.5, mfc="none", color=color,
            label="MuJoCo")
    i = int(np.argmax(np.hypot(fx, fy)))
    ax.annotate("", xy=(fx[i], fy[i]), xytext=(0.0, 0.0), arrowprops=dict(arrowstyle="->", color=color, lw=1.2))
    ax.axhline(0.0, color="k", lw=0.6)
    ax.axvline(0.0, color="k", lw=0.6)
    ax.plot([0.0], [0.0], "k+", ms=8)
    kind = "guide" if j.kind == "prismatic" else "bearing"
    ax.set(title=f"{kind.capitalize()} {j.name}: load on the frame from link {j.b}\n(polar diagram; peak "
                 f"{np.max(np.hypot(fx, fy)):.4g} {fl})", xlabel=f"$F_x$ [{fl}]", ylabel=f"$F_y$ [{fl}]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)


def _magnitude_panel(ax, x, xlabel, an, mj, joints, colors, title, u) -> None:
    ff, fl, _, _ = force_scale(u)
    for n, k in enumerate(joints):
        color = colors[n % len(colors)]
        j = an.joints[k]
        ax.plot(x, np.hypot(an.F[k, 0], an.F[k, 1]) * ff, color=color, lw=1.4, label=f"{j.name} ({j.a}-{j.b})")
        ax.plot(x[::MARK_EVERY], np.hypot(mj.F[k, 0], mj.F[k, 1])[::MARK_EVERY] * ff, "o", ms=3, mfc="none",
                color=color)
    ax.set(title=title, xlabel=xlabel, ylabel=f"[{fl}]")
    if joints:
        ax.legend(fontsize=7, ncol=2, loc="best")
    ax.grid(alpha=0.3)


def _slide_panel(ax, x, xlabel, an, mj, slides, colors, u) -> None:
    """Each prismatic pair's normal force (signed, along the guide's normal) and, on the right axis, its couple."""
    ff, fl, mf, ml = force_scale(u)
    right = ax.twinx()
    for n, k in enumerate(slides):
        color = colors[n % len(colors)]
        j = an.joints[k]
        ax.plot(x, np.hypot(an.F[k, 0], an.F[k, 1]) * ff, color=color, lw=1.4, label=f"{j.name}: |N|")
        ax.plot(x[::MARK_EVERY], np.hypot(mj.F[k, 0], mj.F[k, 1])[::MARK_EVERY] * ff, "o", ms=3, mfc="none",
                color=color)
        right.plot(x, an.M(k) * mf, color=color, lw=1.0, ls="--", label=f"{j.name}: M")
        right.plot(x[::MARK_EVERY], mj.M(k)[::MARK_EVERY] * mf, "s", ms=2.5, mfc="none", color=color)
    ax.set(title="Prismatic pairs: normal force (solid), couple (dashed)", xlabel=xlabel, ylabel=f"|N| [{fl}]")
    right.set_ylabel(f"M [{ml}]")
    lines = ax.get_legend_handles_labels()
    more = right.get_legend_handles_labels()
    ax.legend(lines[0] + more[0], lines[1] + more[1], fontsize=7, loc="best")
    ax.grid(alpha=0.3)


def _drive_panel(ax, x, xlabel, an, mj, power, mech, colors, u) -> None:
    """Each drive's three answers: Newton-Euler (line), the power balance (dashed), MuJoCo (markers)."""
    for n, inp in enumerate(mech.inputs):
        color = colors[n % len(colors)]
        f, _ = drive_scale(u, inp)
        ax.plot(x, an.drives[inp.link] * f, color=color, lw=1.8, label=f"{inp.q}: Newton-Euler")
        ax.plot(x, power[inp.link] * f, color="k", lw=0.9, ls="--", label=f"{inp.q}: power balance")
        ax.plot(x[::MARK_EVERY], mj.drives[inp.link][::MARK_EVERY] * f, "o", ms=3.5, mfc="none", color=color,
                label=f"{inp.q}: MuJoCo")
    unit = " or ".join(dict.fromkeys(drive_scale(u, i)[1] for i in mech.inputs))
    ax.set(title="Drives: three answers", xlabel=xlabel, ylabel=f"[{unit}]")
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)


def _force_error_panel(ax, x, xlabel, an, mj, mech, colors) -> None:
    """|MuJoCo - analytic| of every joint force over the peak joint force, with the tolerance."""
    from sim.run.forces import FORCE_TOL
    from analytic.applications.forces import peak
    scale = peak(an) or 1.0
    for k, j in enumerate(an.joints):
        e = np.hypot(mj.F[k, 0] - an.F[k, 0], mj.F[k, 1] - an.F[k, 1]) / scale
        ax.semilogy(x, np.maximum(e, 1e-18), lw=0.9, color=colors[k % len(colors)], label=j.name)
    e = np.hypot(mj.shaking[0] - an.shaking[0], mj.shaking[1] - an.shaking[1]) / scale
    ax.semilogy(x, np.maximum(e, 1e-18), lw=1.2, color="k", ls=":", label="shaking")
    ax.axhline(FORCE_TOL, color="k", ls="--", lw=0.8)
    ax.set_ylim(bottom=FORCE_TOL * 1e-7)
    ax.set(title="MuJoCo - analytic (dashed: tolerance)", xlabel=xlabel, ylabel="|difference| / peak joint force")
    ax.legend(fontsize=7, ncol=2, loc="lower right")
    ax.grid(alpha=0.3, which="both")


def _shaking_locus(ax, an, mj, color, t, period, u) -> None:
    from analytic.applications.averages import period_rms
    ff, fl, _, _ = force_scale(u)
    fx, fy = an.shaking[0] * ff, an.shaking[1] * ff
    ax.plot(fx, fy, color=color, lw=1.6, label="analytic")
    ax.plot(mj.shaking[0][::MARK_EVERY] * ff, mj.shaking[1][::MARK_EVERY] * ff, "o", ms=3.5, mfc="none",
            color=color, label="MuJoCo")
    ax.axhline(0.0, color="k", lw=0.6)
    ax.axvline(0.0, color="k", lw=0.6)
    rms = period_rms(t, np.hypot(fx, fy), period)                  # over exactly one turn
    ax.set(title=f"Shaking force on the frame (RMS {rms:.4g} {fl})", xlabel=f"$F_x$ [{fl}]",
           ylabel=f"$F_y$ [{fl}]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)


def _shaking_panel(ax, x, xlabel, an, mj, colors, u) -> None:
    ff, fl, mf, ml = force_scale(u)
    ax.plot(x, np.hypot(an.shaking[0], an.shaking[1]) * ff, color=colors[0], lw=1.6,
            label=f"|shaking force| [{fl}]")
    ax.plot(x[::MARK_EVERY], np.hypot(mj.shaking[0], mj.shaking[1])[::MARK_EVERY] * ff, "o", ms=3.5, mfc="none",
            color=colors[0])
    right = ax.twinx()
    right.plot(x, an.shaking[2] * mf, color=colors[1], lw=1.4, label=f"shaking moment [{ml}]")
    right.plot(x[::MARK_EVERY], mj.shaking[2][::MARK_EVERY] * mf, "s", ms=3, mfc="none", color=colors[1])
    right.set_ylabel(f"moment about the origin [{ml}]")
    ax.set(title="Shaking force and moment", xlabel=xlabel, ylabel=f"[{fl}]")
    lines, more = ax.get_legend_handles_labels(), right.get_legend_handles_labels()
    ax.legend(lines[0] + more[0], lines[1] + more[1], fontsize=7, loc="best")
    ax.grid(alpha=0.3)


def _force_summary(ax, c, built, an, mech, x, u) -> None:
    """Each joint's peak force and the input where it occurs, each drive's peak."""
    ax.axis("off")
    ff, fl, mf, ml = force_scale(u)
    first = mech.inputs[0]
    deg = first.angular
    mag = an.magnitude() * ff
    lines = [f"peaks (analytic; at {first.q})"]
    for k, j in enumerate(an.joints):
        i = int(np.argmax(mag[k]))
        at = f"{x[i] % 360:.1f} deg" if deg else f"{x[i]:.4g} {u.unit('length')}"
        extra = f", M {np.max(np.abs(an.M(k))) * mf:.3g} {ml}" if j.kind == "prismatic" else ""
        lines.append(f"{j.name:<8s} {j.kind[0].upper()} {j.a}-{j.b}: {mag[k, i]:.4g} {fl} at {at}{extra}")
    for inp in mech.inputs:
        d = an.drives[inp.link]
        f, unit = drive_scale(u, inp)
        lines.append(f"drive {inp.q}: {np.max(np.abs(d)) * f:.4g} {unit}")
    ax.text(0.0, 1.0, "\n".join(textwrap.shorten(s, 58) for s in lines[:26]), va="top", family="monospace",
            fontsize=8, transform=ax.transAxes)


def _force_summary_agreement(ax, c, u) -> None:
    ax.axis("off")
    a = c.forces
    if a is None:
        ax.text(0.0, 1.0, "joint forces: not determined by statics\n(a redundant constraint)", va="top",
                family="monospace", fontsize=9, transform=ax.transAxes)
        return
    lines = [f"MuJoCo vs analytic (tol {a.tol:.0e} of the peak)",
             f"peak joint force {a.peak * force_scale(u)[0]:.4g} {force_scale(u)[1]}",
             f"worst {a.worst:.2e} ({a.worst_of})",
             f"median over the joints {a.median:.2e}",
             f"shaking force {a.shaking['F_share']:.2e}, moment {a.shaking['M_share']:.2e}"]
    for q, d in a.drives.items():
        lines.append(f"drive {q}: MuJoCo {d['mujoco_share']:.1e},")
        lines.append(f"  power balance {d['power_balance_share']:.1e} of its scale")
    lines += ["", "forces: PASSED" if a.passed else "forces: FAILED",
              "comparison: " + ("PASSED" if c.passed else "FAILED")]
    ax.text(0.0, 1.0, "\n".join(lines), va="top", family="monospace", fontsize=9, transform=ax.transAxes)
