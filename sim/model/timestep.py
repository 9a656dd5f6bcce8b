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

FOLD_MEASURE = 0.2
"""A rocking run that comes closer than this to a fold (its groups' smallest singularity measure, e.g. the
sine of a transmission angle, at the ends of its range near a dead point) takes a step shorter by
sqrt(measure / FOLD_MEASURE): near a fold the loops' drift reaches the outputs magnified by about
1/measure while the rates stay finite (the input stops there), so the rate scan alone does not see it.
Measured on a double rocker (l1 = 0.2, l3 = 0.1): at the scan's step the worst error/tolerance is
0.05/measure (measure 0.01-0.04), and it falls as h^2.2; with this factor it stays below 0.35 down to
FOLD_FLOOR."""

CHANGE_FACTOR = 0.125
"""A run that passes a change point (a dyad's links aligned while the input moves on, compare's ``change
points``) takes a step this much shorter: there the loops' equations lose rank and MuJoCo's regularised
constraint force along the aligned links (a self-stress the equations do not fix) is kicked by the steps that
cross it, the more the longer the step; the rates' scan sees nothing there (a parallelogram's rates are
smooth). Measured on pylinkage's two parallelograms (all four links collinear at 0 deg), 2 deg past that change
point: the joint forces 1.7e-4 and 2.6e-3 of the peak at the scan's step (the Watt's rocker rate 1.1x its
tolerance, its work balance 2.3x), 4e-5 and 7e-5 at a quarter of it, 1.2e-5 and 2.2e-6 at an eighth
(tolerance 1e-4); a parallelogram's run is cheap (2000 steps a turn at an eighth)."""

FOLD_FLOOR = 0.005
"""The closest to a fold a rocking run is simulated (smallest singularity measure; closer ones are refused
with the range that stays this far away): at 0.002 the error reached 1.4-3x the tolerances at any step,
the drive's tracking error (~1e-6 rad) then being comparable with the distance to the dead point."""

FOLD_MARGIN = 1e-5
"""[rad, or of the size for a slider] The least distance from a rocking range's end to the dead point
beyond it: 10x the drives' deflection budget (1e-6), so that the simulated input never reaches the fold."""


def rates(mech, t: np.ndarray) -> np.ndarray:
    """Every rate of the motion at times ``t`` [1/s], shape (len(t), k) (see :func:`analytic.cycle.rates`)."""
    from analytic.cycle import rate_names
    from analytic.cycle import rates as of
    q, qd, qdd = mech.drive(t)
    return of(mech, qd, qdd, mech.solve(q, qd, qdd, outputs=rate_names(mech)))


def peak_rates(cycle) -> float:
    """The largest rate over the cycle's samples and, at each sampled local maximum, over an interpolant
    through it and its neighbours: a link's omega (a slide's ds) by the cubic Hermite interpolant with its
    exact derivative alpha (dds), the others by the parabola through the three samples. NaN where the
    mechanism cannot be assembled somewhere."""
    mech, t = cycle.mech, cycle.t
    r = cycle.rates()
    if np.isnan(r).any():
        return math.nan
    best = float(r.max())
    if len(t) < 3:
        return best
    sol, size = cycle.solution, mech.size
    pad = np.pad(r, ((1, 1), (0, 0)), constant_values=-np.inf)
    top = (pad[1:-1] >= pad[:-2]) & (pad[1:-1] >= pad[2:])
    top[0] = top[-1] = False
    hermite = {}                                      # column -> (signed value, its time derivative)
    c = 2 * len(mech.inputs)
    for ln in mech.links:
        hermite[c] = (np.asarray(sol["omega" + ln]), np.asarray(sol["alpha" + ln]))
        c += 2
    for j in mech.slides:
        hermite[c] = (np.asarray(sol["ds" + j]) / size, np.asarray(sol["dds" + j]) / size)
        c += 2
    u = np.linspace(0.0, 1.0, 65)
    for col in range(r.shape[1]):
        i = np.flatnonzero(top[:, col])
        if i.size == 0:
            continue
        if col in hermite:
            y, dy = hermite[col]
            a = np.union1d(i - 1, i)                 # the interval either side of each maximum, each once (a
            if y.min() == y.max() and not dy.any():  # plateau's maxima share theirs: a dwell's are thousands);
                a = a[:1]                            # a steady rate's intervals are all the same one
            b = a + 1
            h = (t[b] - t[a])[:, None]
            h00, h10, h01, h11 = (2 * u ** 3 - 3 * u ** 2 + 1, u ** 3 - 2 * u ** 2 + u, -2 * u ** 3 + 3 * u ** 2,
                                  u ** 3 - u ** 2)
            v = (y[a][:, None] * h00 + h * dy[a][:, None] * h10 + y[b][:, None] * h01 + h * dy[b][:, None] * h11)
            best = max(best, float(np.max(np.abs(v))))
            continue
        if r[:, col].min() == r[:, col].max():       # a constant: no parabola has a maximum inside
            continue
        t0, t1, t2 = t[i - 1], t[i], t[i + 1]
        y0, y1, y2 = r[i - 1, col], r[i, col], r[i + 1, col]
        d1, d2 = (y1 - y0) / (t1 - t0), (y2 - y1) / (t2 - t1)
        curv = (d2 - d1) / (t2 - t0)
        with np.errstate(invalid="ignore", divide="ignore"):
            tv = 0.5 * (t0 + t1) - d1 / (2 * curv)
            inside = (curv < 0) & (tv >= t0) & (tv <= t2)
            yv = y1 + d1 * (tv - t1) + curv * (tv - t0) * (tv - t1)
        if np.any(inside):
            best = max(best, float(np.max(yv[inside])))
    return best


def rate_scale(mech, revolutions: float = 1.0, cycle=None) -> float:
    """Omega [1/s]: the fastest rate over a run of ``revolutions`` (see STEP_ANGLE), NaN if the mechanism
    cannot be assembled somewhere on it: :func:`peak_rates` over the run's cycle (``cycle``, made here when
    None).

    The cycle is a scan of the run (analytic.cycle.SAMPLES per revolution, or for a crank at constant speed
    the change points' scan of its turn, 1440 per turn) whose rates' highest local maxima are refined
    (analytic.cycle.REFINE samples around each, one solve), their value read from an interpolant: near a
    singular pose a link's speed peaks between samples (a Whitworth lever 0.2 mm from its singular pose peaks
    4.5x higher than a 720-sample scan shows, and the step chosen from the scan failed by 400x). Against the
    former scan (720 per revolution, then 8 rounds of zooming on each peak, a solve each) the rate is the
    same on every library mechanism to 1e-9, the Whitworth lever's peak within 1e-8."""
    from analytic.cycle import Cycle
    return peak_rates(cycle if cycle is not None else Cycle.of(mech, revolutions))


def _slower(mech) -> str:
    """The fix for a design too fast to step: its inputs' speeds by the parameters that set them."""
    named = [(i.parameters[1], i.motion.rate, i.unit) for i in mech.inputs if i.parameters[1]]
    if not named:
        return "slow its drives (the inputs' omega),"
    return "lower " + " or ".join(f"{name} (now {abs(rate):.3g} {unit}/s)" for name, rate, unit in named) + ","


def choose_timestep(mech, revolutions: float = 1.0, cycle=None) -> float:
    """The time step for ``mech`` (STEP_ANGLE, MAX_TIMESTEP); refuses a design needing < MIN_TIMESTEP.
    ``cycle``: the run's :class:`analytic.cycle.Cycle` (made here when None)."""
    from analytic.cycle import Cycle
    cycle = cycle if cycle is not None else Cycle.of(mech, revolutions)
    omega = rate_scale(mech, revolutions, cycle)
    if not math.isfinite(omega):
        raise ParameterError(f"the {mech.name} cannot be assembled over the whole run; check its input range")
    h = min(MAX_TIMESTEP, STEP_ANGLE / omega) if omega > 0 else MAX_TIMESTEP
    h *= fold_factor(mech, revolutions, cycle)
    h *= CHANGE_FACTOR if passes_change_point(mech, cycle) else 1.0
    if h < MIN_TIMESTEP:
        raise ParameterError(f"the {mech.name} moves too fast to simulate accurately (a link turns at up to "
                             f"{omega:.3g} rad/s, needing a time step of {h:.2g} s < {MIN_TIMESTEP:g} s): "
                             f"{_slower(mech)} or move it away from its singular pose")
    return h


def passes_change_point(mech, cycle) -> bool:
    """Whether the first input's run (the cycle's samples, both ends included) reaches one of the change points
    its dyads flip their branch at (the resolved elements' ``flips``), any turn of it for a crank."""
    at = [f for e in mech.solving_geometry.elements if e.get("flips") for f in e["flips"]["at"]]
    if not at or not mech.inputs:
        return False
    q = np.asarray(cycle.q)[:, 0]
    lo, hi = float(np.min(q)), float(np.max(q))
    tol = 1e-9 * max(1.0, abs(lo), abs(hi))
    turn = 2 * math.pi if mech.inputs[0].angular else None
    for f in at:
        if turn is None:
            if lo - tol <= f <= hi + tol:
                return True
        elif f + turn * math.ceil((lo - tol - f) / turn) <= hi + tol:
            return True
    return False


def fold_measure(mech, revolutions: float = 1.0, cycle=None) -> tuple[float, str]:
    """The smallest singularity measure of a rocking run (its groups' poses over one cycle, both ends of
    the range included: the cycle's samples at t = T/2 and T) and the group it belongs to; (inf, "") for a
    run that does not rock. ``cycle``: the run's :class:`analytic.cycle.Cycle` (made here when None)."""
    if mech.rock is None:
        return math.inf, ""
    from analytic.applications.figures import min_singularity
    from analytic.cycle import Cycle
    cycle = cycle if cycle is not None else Cycle.of(mech, revolutions)
    return min_singularity(mech, cycle.solution)


def fold_factor(mech, revolutions: float = 1.0, cycle=None) -> float:
    """The step's factor near a fold (see FOLD_MEASURE): 1 away from one."""
    m, _ = fold_measure(mech, revolutions, cycle)
    return 1.0 if not m < FOLD_MEASURE else math.sqrt(max(m, FOLD_FLOOR) / FOLD_MEASURE)


def motion_scale(mech) -> float:
    """Omega [1/s]: the fastest commanded input speed (a slider's over the size) over one turn of the first
    input: at its ends (a speed linear in time, q0 + rate t + accel t^2 / 2) or a quarter period in (a rocking
    drive's amp w; only the first input rocks); with a motion law, the largest of 4097 samples of its cycle (a
    segment's peak speed lies within 1/4096 of a cycle of one, so within 1e-5 of it for any smooth shape)."""
    laws = any(i.motion.law is not None for i in mech.inputs)
    t = (np.linspace(0.0, 1.0, 4097) if laws else np.array([0.0, 0.25, 1.0])) * mech.duration(1.0)
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

