"""The MuJoCo model simulated and cross-checked (``simulate``, ``compare``): the run's preparation
(its input range, change points and folds refused or passed in words), the model built and run, its records."""

from __future__ import annotations

import math

import numpy as np

from analytic import ParameterError
from analytic.mechanism import Mechanism
from analytic.checks import visited as _visited
from sim.service.analysis import check_memory, check_range, check_revolutions, check_turns_fully


def check_singular(mech: Mechanism, cycle=None) -> None:
    """Refuse a run whose first input would carry a group through a singular (change-point) pose,
    naming the input value: the simulation cannot tell the branches apart there. ``cycle``: the run's
    (analytic.cycle.Cycle), whose poses are read instead of solving them again (one turn's, made here, when
    None)."""
    if len(mech.inputs) != 1:
        from analytic.applications import figures
        from analytic.cycle import Cycle
        sol = (cycle if cycle is not None else Cycle.of(mech)).solution
        m, where = figures.min_singularity(mech, sol)
        if m < figures.SINGULAR:
            raise ParameterError(f"the {mech.name} passes through a singular pose ({where} folds): its motion is "
                                 f"undefined there; change a length or a phase")
        return
    from analytic.applications import figures
    first = mech.inputs[0]
    at = _change_point_at_start(mech)
    if at is not None:
        shown = f"{math.degrees(at) % 360:.2f}deg" if first.angular else f"{at:.6g} m"
        raise ParameterError(f"the {mech.name} starts at a change point ({first.q}={shown}, where a dyad's links "
                             f"align): the loops' equations are singular there at the simulation's first step; "
                             f"start it a little away (e.g. {first.parameters[0] or 'its start'} = 1deg)")
    check_change_swing(mech, cycle)
    scan = turn_scan(mech, cycle) if cycle is not None else None
    if scan is not None and cycle.solution.valid.all():   # a full turn that assembles: its scan is the cycle's
        lo, hi = figures._first_range(mech)
        found = figures.singular_poses(mech, ranges=[(lo, hi)], scan=scan)
    else:
        found = figures.singular_poses(mech)
    poses = [p for p in found if not passes_smoothly(mech, p[1], p[0])]
    if poses:
        first = mech.inputs[0]
        x, label, _ = poses[0]
        at = f"{math.degrees(x) % 360:.2f}deg" if first.angular else f"{x:.6g} m"
        element = next(e for e in mech.geometry.elements if e["label"] == label)
        if element.get("change") == -1:
            raise ParameterError(f"the {mech.name} passes a change point at {first.q}={at} ({label} folds) where it is "
                                 f"declared to switch form (change = -1: its branch sign kept), a kink in its motion; "
                                 f"the simulation, carried on by its momentum, keeps the form there: declare change = 1 "
                                 f"to simulate it, or run between two such angles with an input range")
        raise ParameterError(f"the {mech.name} passes through a singular pose at {first.q}={at} ({label} folds: "
                             f"a change point, where it may switch branch); the simulation cannot follow it: "
                             f"change a length by a little, or run between two such angles with an input range")


def turn_scan(mech: Mechanism, cycle):
    """For a cycle that sweeps a lone crank's turn (:attr:`analytic.cycle.Cycle.covers_turn`): (the crank's values
    ascending, from its start over a turn, {group label: singularity measure} there), the scan
    analytic.applications.figures.singular_poses reads; else None. A motion law's values are taken into the turn
    from the start, each once (a dwell holds one), the start's pose repeated a turn on."""
    if not cycle.covers_turn:
        return None
    from analytic.applications.figures import singularity
    q = cycle.q[:, 0]
    measures = singularity(mech, cycle.solution)
    if not cycle.full_turn:
        q0 = mech.inputs[0].motion.q0
        x, first = np.unique(q0 + np.mod(q - q0, 2 * math.pi), return_index=True)
        return np.r_[x, x[0] + 2 * math.pi], {k: np.r_[v[first], v[first[0]]] for k, v in measures.items()}
    if q[-1] < q[0]:                                      # turning backwards: the same poses, in reverse
        q, measures = q[::-1] + 2 * math.pi, {k: v[::-1] for k, v in measures.items()}
    return q, measures


CHANGE_SWING = 0.1
"""[singularity measure, the sine of a dyad's transmission angle] The least a dyad that passes change points
must swing away from its fold between them for the simulation to follow it: a parallelogram swings to 1 and
passes; a Peaucellier cell whose rhombus stays within 1.9 deg of flat (0.033) over the whole turn, passing 4
change points, opened its loops by 6 mm (the trust benchmark's seed 1, design 832)."""


def check_change_swing(mech: Mechanism, cycle=None) -> None:
    """Refuse a run in which a dyad passing change points stays near its fold over the whole turn (its poses
    read from the run's ``cycle``; one turn's, made here, when None)."""
    flipping = [e["label"] for e in mech.solving_geometry.elements if e.get("flips")]
    if not flipping:
        return
    from analytic.applications import figures
    from analytic.cycle import Cycle
    measures = figures.singularity(mech, (cycle if cycle is not None else Cycle.of(mech)).solution)
    for label in flipping:
        m = measures.get(label)
        if m is not None and np.any(np.isfinite(m)) and float(np.nanmax(m)) < CHANGE_SWING:
            deg = math.degrees(math.asin(min(1.0, float(np.nanmax(m)))))
            raise ParameterError(f"the {mech.name}'s {label} stays within {deg:.2g} deg of folded over the whole "
                                 f"turn while passing its change points: the simulation cannot hold a dyad that near "
                                 f"its fold (its loops open); change a length so that it swings at least "
                                 f"{math.degrees(math.asin(CHANGE_SWING)):.0f} deg away between them")


CHANGE_START = 1e-6
"""[rad, or m for a slider] A change point this close to the start is at the start."""


CHANGE_SHIFT = math.radians(1.0)
"""[rad] A crank that starts at a change point is simulated from this far past it, in its sense of turning
(:func:`clear_of_change_point`). At the change point itself the loops' equations are singular at the
simulation's first step: the run diverged or its errors rang far past compare's tolerances (measured); from
1 deg on, the motion carries the linkage through the change point when the turn comes back to it."""


def _change_point_at_start(mech: Mechanism) -> float | None:
    """The change point the first input starts at, or None."""
    first = mech.inputs[0]
    at = [x for x in change_points(mech) if abs(_wrapped(x - first.motion.q0, first)) < CHANGE_START]
    return at[0] if at else None


def clear_of_change_point(mech: Mechanism) -> Mechanism:
    """``mech``, or where its one crank starts at a change point and turns, the same mechanism starting
    :data:`CHANGE_SHIFT` past it in its sense of turning (the same cycle, the change point passed at the end
    of the turn; see :func:`start_note`)."""
    if len(mech.inputs) != 1 or mech.rock is not None:
        return mech
    first = mech.inputs[0]
    sense = first.motion.rate or first.motion.accel
    if not first.spec.periodic or sense == 0 or _change_point_at_start(mech) is None:
        return mech
    return mech.starting_at(first.motion.q0 + math.copysign(CHANGE_SHIFT, sense))


def start_note(mech: Mechanism, run: Mechanism) -> str | None:
    """The sentence telling that ``run`` (what was simulated) starts elsewhere than ``mech``, or None."""
    a, b = mech.inputs[0], run.inputs[0]
    if mech.rock is not None or run.rock is not None or abs(a.motion.q0 - b.motion.q0) < 1e-12:
        return None
    return (f"the {mech.name} starts at a change point ({a.q}={math.degrees(a.motion.q0) % 360:.2f}deg); "
            f"simulated from {math.degrees(b.motion.q0) % 360:.2f}deg, through the change point at the end of the "
            f"turn (the loops' equations are singular at a change point, so no run starts on one)")


def _wrapped(dx: float, first) -> float:
    return (dx + math.pi) % (2 * math.pi) - math.pi if first.spec.periodic else dx


def change_points(mech: Mechanism) -> list[float]:
    """The first input's values (over one turn from its start) where a dyad passes a change point on its
    declared branch (:mod:`analytic.solver.change_points`)."""
    return sorted(f for e in mech.solving_geometry.elements if e.get("flips") for f in e["flips"]["at"])


def passes_smoothly(mech: Mechanism, label: str, x: float) -> bool:
    """Whether element ``label`` passes its change point at first-input value ``x`` on its declared branch
    (``change = 1``: scheduled in :attr:`Mechanism.solving_geometry`)."""
    for e in mech.solving_geometry.elements:
        flips = e.get("flips")
        if e["label"] == label and flips:
            period = flips["period"]
            for f in flips["at"]:
                gap = abs(x - f) if not period else abs((x - f + 0.5 * period) % period - 0.5 * period)
                if gap < 1e-6 * (1.0 if period else mech.size):
                    return True
    return False


RANGE_CHECK = 721
"""Values of the first input, evenly spaced over a rocking range from its start, checked in turn for the first
that does not assemble where the run's cycle does not (the value the refusal names; one every 0.25 deg of a
180 deg range)."""


def prepare(mech: Mechanism, revolutions: float, input_range=None) -> Mechanism:
    """Checks before any simulation: revolutions, full turn or rocking range, singular poses."""
    return prepare_run(mech, revolutions, input_range)[0]


def prepare_run(mech: Mechanism, revolutions: float, input_range=None):
    """:func:`prepare`'s checks, and the motion of the run solved once (:class:`analytic.cycle.Cycle`), which
    they read: (the mechanism as it will run, its cycle)."""
    from analytic.cycle import Cycle
    check_revolutions(revolutions)
    if input_range is not None:
        from sim.model.timestep import FOLD_MARGIN
        lo, hi = check_range(mech, *input_range)
        mech = mech.rocking(lo, hi)
        margin = FOLD_MARGIN * (1.0 if mech.inputs[0].angular else mech.size)    # check_fold's, beyond the ends
        try:
            cycle = Cycle.of(mech, revolutions, margin)
        except ParameterError:                    # the assembly checks below say first what they see
            cycle = None
        if cycle is None or not cycle.solution.valid.all():     # where it does not assemble: which pose, in words
            q = np.linspace(lo, hi, RANGE_CHECK)
            if len(mech.inputs) > 1:              # the others move as the run moves them: check those poses
                q = cycle.q if cycle is not None else mech.drive(np.linspace(0.0, mech.duration(revolutions),
                                                                             RANGE_CHECK))[0]
                try:
                    mech.check_assembles(q)
                except ParameterError as exc:
                    raise ParameterError(f"{exc}; while the first input rocks, the others keep their own motion "
                                         f"(give one omega = 0 in the file to hold it at its start)") from None
            mech.check_assembles(q)
            if cycle is None:
                cycle = Cycle.of(mech, revolutions, margin)
            elif not cycle.solution.valid.all():
                mech.check_assembles(cycle.q)
        check_fold(mech, cycle)
        return mech, cycle
    mech = clear_of_change_point(mech)
    try:
        cycle = Cycle.of(mech, revolutions)
    except ParameterError:                        # (a motion that does not move) the checks say first what they see
        cycle = None
    check_turns_fully(mech, cycle)
    check_singular(mech, cycle)
    if cycle is None:
        cycle = Cycle.of(mech, revolutions)
    check_folded_change_points(mech, cycle.q[:, 0])      # before a sample that lands on one
    if not cycle.solution.valid.all():
        mech.check_assembles(cycle.q)
    return mech, cycle


def check_folded_change_points(mech: Mechanism, q1: np.ndarray) -> None:
    """Refuse a run whose first input (values ``q1``) passes a change point where a dyad's known points meet
    (:func:`analytic.solver.change_points.folded`), naming it and the change points to run between."""
    from analytic.solver.change_points import folded
    first = mech.inputs[0]
    hit = [f for f in folded(mech) if _visited(first, q1, f[0])]
    if not hit:
        return
    x, label, p, q = hit[0]

    def fmt(v):
        return f"{math.degrees(v) % 360:.2f}deg" if first.angular else f"{v / mech.scale:.6g} {mech.units}"
    shown = sorted((math.degrees(v) % 360 if first.angular else v, fmt(v)) for v in change_points(mech))
    every = ", ".join(f for _, f in shown)
    raise ParameterError(f"the {mech.name} passes a change point at {first.q}={fmt(x)} where {p} and {q} meet "
                         f"({label}: both links turn about one point there and fold onto each other, free to turn "
                         f"together; Pyslvs' solver stops there too): the simulation cannot carry it through; run it "
                         f"between two of its change points ({every}) with --input-range")


def check_fold(mech: Mechanism, cycle=None) -> None:
    """Refuse a rocking run that comes so close to a dead point that the simulation cannot meet compare's
    tolerances there (:data:`sim.model.timestep.FOLD_FLOOR`, ``FOLD_MARGIN``), naming how far inside to
    stay and the range that can be run (rounded inward). Where the ``cycle`` solved the poses FOLD_MARGIN beyond
    both ends (:attr:`analytic.cycle.Cycle.beyond`) and they assemble, no dead point is that close and the
    assembly range is not searched for its ends."""
    from analytic.applications import figures
    from sim.model.timestep import FOLD_FLOOR, FOLD_MARGIN, fold_measure
    m, label = fold_measure(mech, cycle=cycle)
    if m >= FOLD_FLOOR and cycle is not None and cycle.beyond is not None and cycle.beyond.valid.all():
        return
    lo, hi = mech.rock
    first = mech.inputs[0]
    crank = first.angular
    unit = 1.0 if crank else mech.size
    dead = _dead_points_around(mech, lo, hi) if len(mech.inputs) == 1 else (None, None)
    close = [d for d, end in zip(dead, (lo, hi)) if d is not None and abs(end - d) < FOLD_MARGIN * unit]
    if m >= FOLD_FLOOR and not close:
        return
    fmt = (lambda v: f"{math.degrees(v):.4f}deg") if crank else (lambda v: f"{v / mech.scale:.6g} {mech.units}")
    why = (f"near a fold the loops' drift and the drives' tracking error (~1e-6 rad) reach the outputs magnified by "
           f"1/sin(transmission angle), past compare's tolerances; the simulation keeps sin >= {FOLD_FLOOR:g} and "
           f"{FOLD_MARGIN:g} {'rad' if crank else 'of the size'} from a dead point")
    if dead == (None, None):
        raise ParameterError(f"the input range {fmt(lo)}:{fmt(hi)} brings {label} within sin = {m:.2g} of a fold: "
                             f"{why}; narrow the range")
    safe = [_fold_limit(mech, d, end, FOLD_FLOOR, FOLD_MARGIN * unit) if d is not None else end
            for d, end in zip(dead, (lo, hi))]
    a, b = max(lo, safe[0]), min(hi, safe[1])
    if crank:
        shown = f"{figures.round_inward(math.degrees(a), True, 2)}deg:{figures.round_inward(math.degrees(b), False, 2)}deg"
    else:
        shown = f"{figures.round_inward(a / mech.scale, True)}:{figures.round_inward(b / mech.scale, False)}"
    near = [(d, end) for d, end in zip(dead, (lo, hi)) if d is not None]
    d, end = min(near, key=lambda x: abs(x[1] - x[0]))
    raise ParameterError(f"the input range {fmt(lo)}:{fmt(hi)} comes within {fmt(abs(end - d))} of the dead point at "
                         f"{fmt(d)}, where {label} folds (sin of its transmission angle {m:.2g}): {why}; stay "
                         f"{fmt(abs(safe[dead.index(d)] - d))} inside it: an input range of {shown}"
                         + ("" if crank else f" [{mech.units}]"))


def _dead_points_around(mech: Mechanism, lo: float, hi: float) -> tuple[float | None, float | None]:
    """The dead points just below ``lo`` and just above ``hi`` (the ends of the assembly range holding the
    rocking range), None where there is none (a crank that turns fully)."""
    from analytic.applications import figures
    plain = mech.turning()
    ranges = figures.assembly_ranges(plain)
    if figures.turns_fully(plain, ranges):
        return None, None
    turn = 2 * math.pi if mech.inputs[0].spec.periodic else 0.0
    for a, b in ranges:
        for k in ((range(-3, 4)) if turn else (0,)):
            if a + k * turn <= lo + 1e-12 and hi - 1e-12 <= b + k * turn:
                return a + k * turn, b + k * turn
    return None, None


def _fold_limit(mech: Mechanism, dead: float, end: float, floor: float, margin: float) -> float:
    """The input value between the dead point ``dead`` and the range's ``end`` (or beyond it, towards the
    middle) where the smallest singularity measure reaches ``floor``, at least ``margin`` from ``dead``."""
    from analytic.applications import figures
    plain = mech.turning()
    lo, hi = mech.rock
    inner = 0.5 * (lo + hi)
    far = inner if abs(inner - dead) > abs(end - dead) else end

    def measure(x):
        return figures.min_singularity(plain, plain.solve(np.array([x])))[0]

    near = dead + math.copysign(margin, far - dead)
    if measure(far) < floor:
        return far
    a, b = near, far
    if measure(a) < floor:
        for _ in range(60):                            # bisection: the measure grows away from the fold
            mid = 0.5 * (a + b)
            a, b = (mid, b) if measure(mid) < floor else (a, mid)
        return b
    return near


def simulate(mech: Mechanism, revolutions: float = 1.0, settings=None, loads=None, input_range=None):
    """Build and run the MuJoCo model: returns (Built, Trajectory). The motion over the run is solved once
    (:class:`analytic.cycle.Cycle`) and handed to the model builder."""
    from sim.model import Loads, Settings, build
    from sim.run.simulate import simulate as run
    mech, cycle = prepare_run(mech, revolutions, input_range)
    built = build(mech, settings or Settings(), loads or Loads(), revolutions, cycle=cycle)
    check_run_memory(built, revolutions)
    return built, run(built, revolutions)


BYTES_PER_STEP_VALUE = 24
"""[bytes] Peak memory per recorded value (the model's sensors and state, nsensordata + nq + nv + na) per step
of ``compare`` (the larger user: the analytic solution at every step and the comparison besides the run):
measured (peak RSS over 800 turns less that over 4) 21.8 on the four-bar, 20.4 on Jansen's linkage; ``simulate``
11-12, with ``--csv`` 18; rounded up. ``simulate --json`` writes every step as text, 107 a value
(BYTES_PER_JSON_VALUE)."""

BYTES_PER_JSON_VALUE = 128
"""[bytes] The same for ``simulate --json``'s record of every step (107 on the four-bar, rounded up)."""


def check_run_memory(built, revolutions: float, per_value: float = BYTES_PER_STEP_VALUE) -> None:
    """Refuse a run of ``revolutions`` whose recorded steps would need more than RUN_MEMORY (the runs' one rule,
    :func:`sim.service.analysis.check_memory`), naming the most revolutions that fit."""
    from sim.run.simulate import steps_for
    model, mech = built.model, built.mech
    steps, h = steps_for(built, revolutions), built.timestep
    per_turn = mech.duration(1.0) / h                       # steps a revolution (a cycle of a motion law)

    def most(limit: int) -> str:
        turns = float(f"{max(limit - 1, 0) / per_turn:.3g}")
        turns = turns if turns * per_turn <= limit - 1 else float(f"{turns * (1 - 1e-3):.3g}")
        return f"{turns:g} revolutions ({limit:,} steps)"
    check_memory("revolutions", f"{revolutions:g}", steps, model.nsensordata + model.nq + model.nv + model.na,
                 per_value, f"the {mech.name}'s {steps:,} steps of {h:.3g} s", unit="step", most=most)


def compare(mech: Mechanism, revolutions: float = 1.0, settings=None, loads=None, input_range=None):
    """Simulate and cross-validate: returns (Built, Comparison)."""
    from sim.run.compare import compare as cmp
    built, tr = simulate(mech, revolutions, settings, loads, input_range)
    return built, cmp(tr, built, revolutions)


def comparison_record(built, c, display=None) -> dict:
    """The JSON of ``linkage compare --json`` (and the app's simulate): SI unless ``display``."""
    return c.as_dict(built, display)


def simulation_record(built, tr, revolutions: float, display=None) -> dict:
    """The JSON of ``linkage simulate --json``: the run's settings and cost, the largest loop violation and
    every column of ``--csv`` (SI unless ``display``) with its unit."""
    from analytic.quantities import SI
    from sim.output.units import convert_columns
    from sim.service.analysis import units_of
    display = display or SI
    mech = built.mech
    check_run_memory(built, revolutions, BYTES_PER_JSON_VALUE)          # before its text is made
    cols = trajectory_columns(tr, mech)
    return {"mechanism": tr.name, "revolutions": revolutions, "timestep": tr.timestep, "integrator": tr.integrator,
            "steps": int(tr.steps), "cpu_seconds": tr.cpu_seconds,
            "max_loop_violation": display.convert("length", float(np.max(tr.loop_violation))),
            "columns": convert_columns(mech, cols, display), "units": units_of(mech, cols, display),
            **({"cams": tr.cams} if tr.cams else {})}


def trajectory_columns(tr, mech) -> dict:
    """CSV columns of a trajectory of ``mech``: t, inputs, every output, loop violation, drive forces, commanded
    inputs (``cmd_phi1``) and every joint's coordinate and rate (``q_NAME``, ``v_NAME``). A driven slide's
    measured columns are its input's (``s_lift``), not repeated under the block's name (Mechanism.driven_slides)."""
    from analytic.mechanism import SLIDE_COMPONENTS
    joints = {f"q_{n}": tr.qpos[:, i] for i, n in enumerate(tr.joint_names)}
    joints.update({f"v_{n}": tr.qvel[:, i] for i, n in enumerate(tr.joint_names)})
    again = {c + j for j in mech.driven_slides for c in SLIDE_COMPONENTS} - set(tr.inputs)
    outs = {k: np.asarray(v) for k, v in tr.outputs.items() if not k.startswith(("cos", "sin")) and k not in again}
    return {"t": tr.t, **tr.inputs, **outs, "loop_violation": tr.loop_violation, **tr.forces,
            **{f"cmd_{k}": v for k, v in tr.commanded.items()}, **joints}


def comparison_table(c, size: float, display=None, output_point: str | None = None) -> str:
    """A comparison (:func:`compare`'s second value) as the readable table ``linkage compare`` prints, in
    ``display`` units (an :class:`analytic.quantities.Display`; None: SI): the output point's coordinates
    first, the other moving outputs, then the drive forces. ``size``: the mechanism's size [m]."""
    from sim.run.compare import table
    return table(c, size, display, output_point)


def errors_in(errors: dict, display) -> dict:
    """A comparison's per-output error records (``c.errors``, SI) in ``display`` units: max, rms, peak and
    tolerance converted by each output's quantity, ``unit`` relabelled."""
    from sim.run.compare import errors_in as convert
    return convert(errors, display)


def chosen_timestep(mech: Mechanism, revolutions: float = 1.0) -> float:
    """The physics time step [s] :func:`simulate` chooses for ``mech`` over ``revolutions`` when none is given
    (from its fastest rate): to tell a user whose own time step is too coarse."""
    from sim.model import choose_timestep
    return choose_timestep(mech, revolutions)


def settings(timestep: float | None = None, integrator: str | None = None):
    """The simulation settings :func:`simulate` and :func:`compare` take (``sim.model.Settings``):
    ``timestep`` [s] (None: chosen from the design), the MuJoCo ``integrator`` by name (None: the default)."""
    from sim.model import Settings
    return Settings(timestep=timestep) if integrator is None else Settings(timestep=timestep, integrator=integrator)


def run_loads(gravity=None, force=(0.0, 0.0), slow_stroke_only: bool = False, inertias=None, extra=()):
    """The loads of a simulated run (``sim.model.Loads``): ``gravity`` (gx, gy) [m/s^2] or None, a constant
    ``force`` (fx, fy) [N] on the output point (only over its slow stroke with ``slow_stroke_only``), the
    links' ``inertias`` ({link: analytic.mass.Inertia}, SI; None: the default bars) and ``extra`` loads
    (analytic.loads dataclasses, as :func:`sim.service.loads.force_load` makes)."""
    from sim.loading import Loads
    return Loads(gravity=gravity, force=force, slow_stroke_only=slow_stroke_only, inertias=inertias, extra=extra)


def simulate_part(mech: Mechanism, revolutions: float):
    """(built model, trajectory) of ``mech`` simulated over part of a turn, ``revolutions`` of its crank from
    the file's start, without :func:`simulate`'s checks that the crank turns fully (a two-position design
    only goes from position 1 to position 2)."""
    from sim.model import build
    from sim.run.simulate import simulate as run
    built = build(mech, revolutions=revolutions)
    return built, run(built, revolutions)


def cam_speed_sets(mech: Mechanism, speed: float) -> dict[str, str]:
    """``simulate --speed W``: the ``--set`` items that turn the mechanism's cam at W rad/s
    (:func:`sim.run.cams.speed_sets`)."""
    from sim.run.cams import speed_sets
    return speed_sets(mech, speed)


def check_cam_speed(before: Mechanism, after: Mechanism, speed: float, revolutions: float = 1.0) -> None:
    """``simulate --speed W``: refused naming the option where W alone makes the design too fast to simulate
    (:func:`sim.run.cams.check_speed`)."""
    from sim.run.cams import check_speed
    check_speed(before, after, speed, revolutions)
