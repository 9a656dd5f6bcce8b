"""The dynamics sheet of `linkage dynamics --plot`: speed against angle over the last revolution with the
mean and the Cs band, start-up against time, and the motor's torque; the reduced equation's curves with
MuJoCo's steps over them. Speeds and angles in the display's units (``--speeds rpm``, ``--angles deg``)."""

from __future__ import annotations

import math

import numpy as np

from sim.output.io import atomic_path

RPM = 60 / (2 * math.pi)


def _speed_unit(display) -> tuple[float, str]:
    """Display value per rad/s of the input's speed and its label: rpm, deg/s or rad/s as ``display`` says
    (None: rpm, a motor's usual unit)."""
    if display is None:
        return RPM, "rpm"
    from analytic.quantities import ANGULAR_VELOCITY
    return display.factor(ANGULAR_VELOCITY), display.unit(ANGULAR_VELOCITY)


def last_cycle(d, n: int = 721) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The last revolution's speed against the input's advance from its start: the reduced equation's at
    ``n`` advances (u [rad] in [0, 2 pi], w [rad/s] in the input's turning direction) and MuJoCo's at its
    recorded steps in that revolution (empty arrays without a simulation)."""
    r, s = d.run, d.sim
    red = r.reduced
    end = 2 * math.pi * r.revolutions
    u = np.linspace(end - 2 * math.pi, end, n)
    w = r.speed_at(u)
    if s is None:
        return u - u[0], w, np.empty(0), np.empty(0)
    us = red.direction * (s.phi - red.q0)
    last = us >= end - 2 * math.pi - 1e-9
    return u - u[0], w, us[last] - u[0], red.direction * s.omega[last]


def speed_vs_angle(d, ax=None, display=None):
    """Speed against the input's advance over the last revolution, in ``display``'s units (None: rpm and
    deg); returns the Axes."""
    import matplotlib.pyplot as plt
    ax = ax or plt.gca()
    r, s = d.run, d.sim
    k, unit = _speed_unit(display)
    deg = display is None or display.angle == "deg"
    angle = np.degrees if deg else np.asarray
    u, w, us, ws = last_cycle(d)
    x = angle(u)
    ax.axhspan(r.w_min * k, r.w_max * k, color="tab:blue", alpha=0.12,
               label=f"Cs = {r.fluctuation:.4g}")
    ax.axhline(r.mean_speed * k, color="k", lw=0.8, ls="--", label=f"mean {r.mean_speed * k:.4g} {unit}")
    ax.plot(x, w * k, color="tab:blue", lw=1.5, label="reduced equation")
    if s is not None:
        step = max(1, len(us) // 90)
        ax.plot(angle(us[::step]), ws[::step] * k, ".", color="tab:red", ms=3, label="MuJoCo")
    ax.set_xlabel(f"input angle over the last revolution [{'deg' if deg else 'rad'}]")
    ax.set_ylabel(f"speed [{unit}]")
    ax.set_xlim(0, 360 if deg else 2 * math.pi)
    ax.legend(fontsize=7, loc="best")
    return ax


def startup(d, ax=None, display=None):
    """Speed (in ``display``'s unit, None: rpm) against time [s] over the run, with the start-up time marked;
    returns the Axes."""
    import matplotlib.pyplot as plt
    ax = ax or plt.gca()
    r, s = d.run, d.sim
    k, unit = _speed_unit(display)
    ax.plot(r.t, np.abs(r.omega) * k, color="tab:blue", lw=1.2, label="reduced equation")
    if s is not None:
        step = max(1, len(s.t) // 300)
        ax.plot(s.t[::step], np.abs(s.omega[::step]) * k, ".", color="tab:red", ms=2, label="MuJoCo")
    ax.axvline(r.startup_time, color="k", lw=0.8, ls=":", label=f"start-up {r.startup_time:.3g} s (95 % of mean)")
    ax.axhline(r.mean_speed * k, color="k", lw=0.8, ls="--")
    ax.set_xlabel("time [s]")
    ax.set_ylabel(f"speed [{unit}]")
    ax.legend(fontsize=7, loc="lower right")
    return ax


def torque(d, ax=None, display=None):
    """Motor torque against time [s], in ``display``'s moment unit (the file's force unit x its length unit;
    None: N m); returns the Axes."""
    import matplotlib.pyplot as plt
    from analytic import quantities as Q
    ax = ax or plt.gca()
    f, unit = (display.factor(Q.TORQUE), display.unit(Q.TORQUE)) if display is not None else (1.0, "N m")
    r, s = d.run, d.sim
    ax.plot(r.t, np.asarray(r.torque) * f, color="tab:green", lw=1.2, label="reduced equation")
    if s is not None:
        step = max(1, len(s.t) // 300)
        ax.plot(s.t[::step], np.asarray(s.torque[::step]) * f, ".", color="tab:red", ms=2, label="MuJoCo")
    ax.set_xlabel("time [s]")
    ax.set_ylabel(f"motor torque [{unit}]")
    ax.set_title(f"peak {r.peak_torque * f:.3g} {unit}, peak power {r.peak_power:.3g} W, "
                 f"{r.energy_per_cycle:.3g} J per cycle", fontsize=8)
    ax.legend(fontsize=7, loc="best")
    return ax


def sheet(d, out: str, display=None) -> None:
    """Draw the three panels (:func:`figure`) and save them atomically to ``out`` (.png, .svg or .pdf)."""
    import matplotlib.pyplot as plt
    fig = figure(d, display)
    try:
        with atomic_path(out) as tmp:
            fig.savefig(tmp, dpi=90)
    finally:
        plt.close(fig)


def figure(d, display=None):
    """The three panels as a matplotlib Figure, speeds, angles and the torque in ``display``'s units
    (:class:`analytic.quantities.Display`; None: rpm, deg and N m)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(3, 1, figsize=(7.5, 9.5))
    verdict = "" if d.agreement is None else ("; MuJoCo agrees" if d.agreement.passed else "; MuJoCo DISAGREES")
    fig.suptitle(f"{d.mech.name} under a motor, flywheel {d.flywheel:.4g} kg m²{verdict}", fontsize=10)
    speed_vs_angle(d, axes[0], display)
    startup(d, axes[1], display)
    torque(d, axes[2], display)
    fig.tight_layout()
    from sim.output.fit import fit_titles
    fit_titles(fig)
    return fig
