"""The time step a design needs: the fastest rate of its motion over the run (a scan refined at its peaks)
turns at most STEP_ANGLE per step."""

from __future__ import annotations

import math

import numpy as np

from analytic import ParameterError

STEP_ANGLE = 0.025
"""The time step is chosen so that the fastest rate in the motion turns at most this many radians per
step: h = STEP_ANGLE / Omega, with Omega the largest of every link's |omega|, sqrt(|alpha|) and the
sliders' |ds| / size over the run. With the loops held as below, the error is RK4's (it scales as h^4);
over 360 random designs of the dyad-chain library (benchmarks/trust.py's draws, seeds 11-14) the worst
error/target was 0.05 at 0.025 rad per step, 0.12-0.19 at 0.03, 0.37 at 0.04 and 0.6 at 0.05. At 0.03 the
peers' numerically solved groups (Pyslvs' Stephenson II, a PMKS walker) and a PMKS slider linkage rocked
near its limits missed by 1.0-1.3x (a link's speed through a sharp acceleration peak: sqrt(|alpha|) does
not see how fast alpha itself changes); at 0.025 all pass, for about 20 % more steps."""

MAX_TIMESTEP = 0.05

MIN_TIMESTEP = 1e-6
"""Bounds of the chosen step [s]: the largest step a user may set; a design that would need a step
below MIN_TIMESTEP is refused. The drives' and loops' time constants are counted in steps, so a slow
design needs no smaller step than its motion asks for."""

RATE_SAMPLES = 720
"""Samples per revolution of the scan for the fastest rate (at most RATE_SAMPLES_MAX over a run). Each
rate's highest local maxima are then refined by zooming in (RATE_ZOOMS rounds): near a singular pose a
link's speed peaks between samples (a Whitworth lever 0.2 mm from its singular pose peaks 4.5x higher
than a 720-sample scan shows, and the step chosen from the scan failed by 400x)."""

RATE_SAMPLES_MAX = 200_000

RATE_PEAKS = 4
"""Local maxima of each rate refined per revolution (at most 64 per rate)."""

RATE_ZOOMS = 8

FOLD_MEASURE = 0.2
"""A rocking run that comes closer than this to a fold (its groups' smallest singularity measure, e.g. the
sine of a transmission angle, at the ends of its range near a dead point) takes a step shorter by
sqrt(measure / FOLD_MEASURE): near a fold the loops' drift reaches the outputs magnified by about
1/measure while the rates stay finite (the input stops there), so the rate scan alone does not see it.
Measured on a double rocker (l1 = 0.2, l3 = 0.1): at the scan's step the worst error/tolerance is
0.05/measure (measure 0.01-0.04), and it falls as h^2.2; with this factor it stays below 0.35 down to
FOLD_FLOOR."""

FOLD_FLOOR = 0.005
"""The closest to a fold a rocking run is simulated (smallest singularity measure; closer ones are refused
with the range that stays this far away): at 0.002 the error reached 1.4-3x the tolerances at any step,
the drive's tracking error (~1e-6 rad) then being comparable with the distance to the dead point."""

FOLD_MARGIN = 1e-5
"""[rad, or of the size for a slider] The least distance from a rocking range's end to the dead point
beyond it: 10x the drives' deflection budget (1e-6), so that the simulated input never reaches the fold."""


def rates(mech, t: np.ndarray) -> np.ndarray:
    """Every rate of the motion at times ``t`` [1/s], shape (len(t), k): each input's and link's |omega|
    and sqrt(|alpha|), each slide's |ds| / size and sqrt(|dds| / size) (an input slider's over the size);
    NaN where the mechanism cannot be assembled."""
    q, qd, qdd = mech.drive(t)
    size = mech.size
    names = [f"{k}{ln}" for ln in mech.links for k in ("omega", "alpha")]
    names += [f"{k}{j}" for j in mech.slides for k in ("ds", "dds")]
    sol = mech.solve(q, qd, qdd, outputs=names)
    cols = []
    for k, inp in enumerate(mech.inputs):
        scale = inp.spec.rate_scale(size)
        cols += [np.abs(qd[:, k]) / scale, np.sqrt(np.abs(qdd[:, k]) / scale)]
    for ln in mech.links:
        cols += [np.abs(sol["omega" + ln]), np.sqrt(np.abs(sol["alpha" + ln]))]
    for j in mech.slides:
        cols += [np.abs(sol["ds" + j]) / size, np.sqrt(np.abs(sol["dds" + j]) / size)]
    return np.column_stack(cols)


def peaks(r: np.ndarray, keep: int) -> tuple[np.ndarray, np.ndarray]:
    """(sample, column) of the ``keep`` highest local maxima of each column of ``r`` (ends included)."""
    pad = np.pad(r, ((1, 1), (0, 0)), constant_values=-np.inf)
    is_peak = (pad[1:-1] >= pad[:-2]) & (pad[1:-1] >= pad[2:]) & np.isfinite(r)
    rows, cols = [], []
    for c in range(r.shape[1]):
        idx = np.flatnonzero(is_peak[:, c])
        idx = idx[np.argsort(r[idx, c])[-keep:]]
        rows.append(idx)
        cols.append(np.full(len(idx), c))
    return np.concatenate(rows), np.concatenate(cols)


def rate_scale(mech, revolutions: float = 1.0) -> float:
    """Omega [1/s]: the fastest rate over a run of ``revolutions`` (see STEP_ANGLE), NaN if the mechanism
    cannot be assembled somewhere on it. A scan, then each rate's highest peaks refined by zooming in."""
    end = mech.duration(revolutions)
    turns = max(1.0, revolutions)
    t = np.linspace(0.0, end, int(min(RATE_SAMPLES * turns, RATE_SAMPLES_MAX)) + 1)
    r = rates(mech, t)
    if np.isnan(r).any():
        return math.nan
    best = float(r.max())
    rows, cols = peaks(r, min(64, int(math.ceil(RATE_PEAKS * turns))))
    lo, hi = t[np.maximum(rows - 1, 0)], t[np.minimum(rows + 1, len(t) - 1)]
    u = np.linspace(0.0, 1.0, 9)
    for _ in range(RATE_ZOOMS):
        tt = lo[:, None] + (hi - lo)[:, None] * u[None, :]
        rr = rates(mech, tt.ravel())
        if np.isnan(rr).any():
            return math.nan
        best = max(best, float(rr.max()))
        own = rr[np.arange(rr.shape[0]), np.repeat(cols, len(u))].reshape(tt.shape)
        k = np.argmax(own, axis=1)
        lo, hi = tt[np.arange(len(k)), np.maximum(k - 1, 0)], tt[np.arange(len(k)), np.minimum(k + 1, len(u) - 1)]
    return best


def choose_timestep(mech, revolutions: float = 1.0) -> float:
    """The time step for ``mech`` (STEP_ANGLE, MAX_TIMESTEP); refuses a design needing < MIN_TIMESTEP."""
    omega = rate_scale(mech, revolutions)
    if not math.isfinite(omega):
        raise ParameterError(f"the {mech.name} cannot be assembled over the whole run; check its input range")
    h = min(MAX_TIMESTEP, STEP_ANGLE / omega) if omega > 0 else MAX_TIMESTEP
    h *= fold_factor(mech, revolutions)
    if h < MIN_TIMESTEP:
        raise ParameterError(f"the {mech.name} moves too fast to simulate accurately (a link turns at up to "
                             f"{omega:.3g} rad/s, needing a step of {h:.2g} s < {MIN_TIMESTEP:g} s): slow its "
                             f"drives or move it away from its singular pose")
    return h


def fold_measure(mech, revolutions: float = 1.0) -> tuple[float, str]:
    """The smallest singularity measure of a rocking run (its groups' poses over one cycle, both ends of
    the range included) and the group it belongs to; (inf, "") for a run that does not rock."""
    if mech.rock is None:
        return math.inf, ""
    from analytic.applications.figures import min_singularity
    t = np.linspace(0.0, mech.duration(min(revolutions, 1.0)), 1441)       # the range's ends at t = T/2, T
    q, qd, qdd = mech.drive(t)
    return min_singularity(mech, mech.solve(q, qd, qdd))


def fold_factor(mech, revolutions: float = 1.0) -> float:
    """The step's factor near a fold (see FOLD_MEASURE): 1 away from one."""
    m, _ = fold_measure(mech, revolutions)
    return 1.0 if not m < FOLD_MEASURE else math.sqrt(max(m, FOLD_FLOOR) / FOLD_MEASURE)


def motion_scale(mech) -> float:
    """Omega [1/s]: the fastest commanded input speed (a slider's over the size)."""
    t = np.linspace(0.0, mech.duration(1.0), 181)
    qd = mech.drive(t)[1]
    scales = [np.max(np.abs(qd[:, k])) / i.spec.rate_scale(mech.size) for k, i in enumerate(mech.inputs)]
    return float(max(scales))


def reference_rate(mech) -> float:
    """[1/s] The motion the drive-force and joint-force floors (sim.run.compare.TORQUE_FLOOR,
    sim.run.forces.JOINT_FLOOR) are taken at, whatever the run's speed: the fastest of the inputs' kinds'
    :attr:`~analytic.kinds.base.Kind.reference_rate` (a crank's one turn per second, a slider's one size per
    second: a slider's rate is its speed over the size). A run slower than that keeps the floors it would have
    there: its drive forces fall as the speed squared (a slider at 0.1 mm/s in a 70 mm mechanism: 1e-8 N) while
    MuJoCo's constraint solver leaves a residual that falls only about linearly (measured on Pyslvs' slider
    lifter: 2 % of the drive force at 0.1 mm/s, 0.2 % at 7 mm/s), so a floor taken at the run's own speed meets
    that noise."""
    return max(i.spec.reference_rate for i in mech.inputs)

