"""The service layer: what every front end (the ``linkage`` command, the web app) calls. Plain
functions on :class:`analytic.Mechanism`, no argparse; errors are :class:`analytic.ParameterError`
with one-line messages that speak of parameters, not of command-line flags.

MuJoCo and matplotlib are imported only by the functions that need them, so analysis stays fast.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

import analytic
from analytic import ParameterError
from analytic.format import expr
from analytic.applications.figures import of as figures_of
from analytic.mechanism import Mechanism

MAX_SAMPLES = 10_000_000
"""Largest analysis accepted (~1.5 GB of outputs for a four-bar)."""
MAX_REVOLUTIONS = 10_000


# ---------------------------------------------------------------------------------------- mechanisms
def list_mechanisms() -> list[dict]:
    """Every mechanism addressable by name: name, description, number of inputs, built-in or not."""
    out = []
    for name in analytic.names():
        description, inputs = analytic.registry.summary(name)
        out.append({"name": name, "description": description, "inputs": inputs,
                    "builtin": name in analytic.BUILTINS})
    return out


def parameter_value(mech_or_def, name: str, value) -> float:
    """A parameter value from text or a number: ``"30deg"`` for an angle, refused on a length."""
    d = mech_or_def.definition if isinstance(mech_or_def, Mechanism) else mech_or_def
    if name not in d.parameters:
        raise ParameterError(f"{name!r} is not a parameter of {d.name}; parameters: "
                             f"{', '.join(d.parameter_order) or '(none)'}")
    kind = d.parameter_kind[name]
    if isinstance(value, bool):
        raise ParameterError(f"{name}={value!r} is not a number")
    if isinstance(value, (int, float)):
        v = float(value)
        if not math.isfinite(v) or abs(v) > 1e12:
            raise ParameterError(f"{name}={value!r} is out of range: give a finite value of magnitude <= 1e12")
    else:
        v = expr.parse_value(name, str(value), angle=False if kind == "length" else None)
    if kind == "branch" and v not in (1.0, -1.0):
        raise ParameterError(f"{name}={value} is not a valid branch: use +1 or -1")
    return v


def load(mechanism: str, values: dict | None = None, text: str | None = None) -> Mechanism:
    """A mechanism by name or path (or from a file's ``text``), with parameter ``values`` (numbers or
    strings such as ``"30deg"``, file units)."""
    d = analytic.format.linkfile.parse(text, "<upload>") if text is not None else analytic.definition(mechanism)
    overrides = {k: parameter_value(d, k, v) for k, v in (values or {}).items()}
    builtin = analytic.BUILTINS.get(mechanism) if text is None else None
    return Mechanism.from_definition(d, overrides, builtin)


def parameter_table(mech: Mechanism) -> list[dict]:
    """Each parameter with its value, kind, unit and a slider range for front ends."""
    out = []
    d = mech.definition
    for name in d.parameter_order:
        kind = d.parameter_kind[name]
        v = mech.values[name]
        derived = isinstance(d.parameters[name], str) and expr.quantity(d.parameters[name]) is None
        if kind == "length":
            unit, lo, hi, step = d.units, min(0.0, 2 * v), max(2.0 * abs(v), 1e-9), abs(v) / 200 or 0.001
            if v > 0:
                lo = v / 5
        elif kind == "angle":
            unit, lo, hi, step = "rad", min(-2 * math.pi, -2 * abs(v)), max(2 * math.pi, 2 * abs(v)), 0.001
        elif kind == "branch":
            unit, lo, hi, step = "", -1.0, 1.0, 2.0
        else:
            unit, lo, hi, step = "", -2 * abs(v) - 1, 2 * abs(v) + 1, (abs(v) or 1) / 200
        out.append({"name": name, "value": v, "kind": kind, "unit": unit, "min": lo, "max": hi, "step": step,
                    "derived": derived})
    return out


def describe(mech: Mechanism) -> dict:
    """A JSON-ready description: parameters, inputs, points, links, slides, outputs."""
    return {"name": mech.name, "description": mech.description, "units": mech.units,
            "parameters": parameter_table(mech),
            "inputs": [{"kind": i.kind, "link": i.link, "q": i.q, "qd": i.qd, "qdd": i.qdd, "unit": i.unit,
                        "point": i.point, "pivot": i.joint} for i in mech.inputs],
            "points": list(mech.points), "ground": list(mech.ground_points), "links": link_drawing(mech),
            "slides": list(mech.slides), "output_point": mech.output_point, "outputs": list(mech.outputs),
            "size": mech.size}


def link_drawing(mech: Mechanism) -> list[dict]:
    """Each link with the points to draw it through (origin first), for front ends."""
    links = mech.topology.links
    return [{"name": ln, "points": [link.origin] + sorted(set(link.points) - {link.origin}),
             "block": ln in mech.slides} for ln, link in links.items()]


# ------------------------------------------------------------------------------------------ analysis
@dataclass(frozen=True)
class Analysis:
    """One analysed run: time [s], the inputs' motion (columns named phi1, omega1, ...), the solution."""

    t: np.ndarray
    inputs: dict[str, np.ndarray]
    solution: analytic.Solution
    figures: dict


def check_samples(samples) -> int:
    if isinstance(samples, bool) or not isinstance(samples, int) or not 2 <= samples <= MAX_SAMPLES:
        raise ParameterError(f"samples={samples!r} must be an integer in 2..{MAX_SAMPLES:,}")
    return samples


def check_revolutions(revolutions) -> float:
    if isinstance(revolutions, bool) or not isinstance(revolutions, (int, float)) or not (
            math.isfinite(revolutions) and 0 < revolutions <= MAX_REVOLUTIONS):
        raise ParameterError(f"revolutions={revolutions!r} must be a number in (0, {MAX_REVOLUTIONS}]")
    return float(revolutions)


def check_range(mech: Mechanism, lo: float, hi: float) -> tuple[float, float]:
    first = mech.inputs[0]
    fmt = (lambda v: f"{math.degrees(v):.2f}deg") if first.kind == "crank" else (lambda v: f"{v:.6g}")
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise ParameterError(f"input range {lo}:{hi} must be finite")
    if not hi > lo:
        raise ParameterError(f"input range {fmt(lo)}:{fmt(hi)}: the end must exceed the start")
    if first.kind == "crank" and hi - lo > 2 * math.pi * MAX_REVOLUTIONS:
        raise ParameterError(f"input range {fmt(lo)}:{fmt(hi)} spans more than {MAX_REVOLUTIONS} turns")
    return lo, hi


def analyze(mech: Mechanism, samples: int = 361, revolutions: float = 1.0,
            input_range: tuple[float, float] | None = None, figures: bool = True) -> Analysis:
    """Closed-form kinematics over one run: ``samples`` instants over ``revolutions`` of the first input,
    or values of the first input evenly spaced over ``input_range`` (other inputs at their motion law).
    ``figures=False`` skips the figures of merit (their scans take 50 ms to 2 s; the curves ~1 ms), as a
    front end does while a value is being dragged."""
    check_samples(samples)
    check_revolutions(revolutions)
    if input_range is not None:
        lo, hi = check_range(mech, *input_range)
        first = mech.inputs[0]
        q1 = np.linspace(lo, hi, samples)
        rate = first.motion.rate if first.motion.rate != 0 else 1.0
        t = (q1 - lo) / abs(rate)
        q, qd, qdd = mech.drive(t)
        q[:, 0], qd[:, 0], qdd[:, 0] = q1, first.motion.rate, 0.0
        mech.check_assembles(q)
    else:
        check_turns_fully(mech)
        t = np.linspace(0.0, mech.duration(revolutions), samples)
        q, qd, qdd = mech.drive(t)
        mech.check_assembles(q)
    sol = mech.solve(q, qd, qdd)
    cols = {}
    for attr, arr in (("q", q), ("qd", qd), ("qdd", qdd)):          # phi2 phi4 omega2 omega4 alpha2 alpha4
        for k, inp in enumerate(mech.inputs):
            cols[getattr(inp, attr)] = arr[:, k]
    return Analysis(t, cols, sol, figures_of(mech, sol) if figures else {})


def figures(mech: Mechanism) -> dict:
    """The figures of merit of one cycle, as ``analyze`` computes them (361 samples of one revolution, or
    of the rocking range): what every front end shows, so a figure reads the same everywhere."""
    return analyze(mech, 361, 1.0, mech.rock).figures


def check_turns_fully(mech: Mechanism) -> None:
    """A single-input mechanism whose first input cannot make a full turn is refused with its limits
    (a rocking drive, ``input_range``, is the way to run it)."""
    if len(mech.inputs) != 1 or mech.rock is not None or mech.inputs[0].kind != "crank":
        return
    from analytic.applications import figures
    ranges = figures.assembly_ranges(mech)
    if not ranges:
        raise ParameterError(f"the {mech.name} cannot be assembled at any value of {mech.inputs[0].q}: change its "
                             f"lengths")
    if not figures.turns_fully(mech, ranges):
        first = mech.inputs[0]
        ends = ", ".join(sorted({f"{(math.degrees(a) + 180) % 360 - 180:.4f}deg" for r in ranges for a in r},
                                key=lambda x: float(x[:-3])))
        reach = figures.describe_ranges(first, ranges) if ranges else "nowhere"
        raise ParameterError(f"the input {first.q} of the {mech.name} cannot turn fully (limit angles {ends}; "
                             f"reachable {reach}, rounded inward): run it between the limits with an input range LO:HI")


def analysis_record(mech: Mechanism, a: Analysis, samples: int, revolutions: float, display=None) -> dict:
    """The JSON of ``linkage analyze --json``: figures and ranges in ``display`` units (default SI), and
    the ``units`` table saying which (analytic.quantities)."""
    from analytic import quantities as Q
    display = display or Q.SI
    outs = mech.outputs
    kind = mech.inputs[0].kind
    ranges = {k: display.convert(Q.quantity(mech, k), _span(a.solution[k])) for k in outs}
    return {"mechanism": mech.name, "units": units_table(mech, display, outs, a.figures),
            "parameters": Q.parameters_in(mech, display), "samples": samples, "revolutions": revolutions,
            "figures": Q.convert_figures(a.figures, display, kind), "ranges": ranges}


def units_table(mech: Mechanism, display, outputs=(), figures=None) -> dict:
    """The JSON ``units`` table: the file's length unit, the unit of each quantity in this record, and of
    each output and figure of merit named."""
    from analytic import quantities as Q
    return {"file": mech.units, **{q: display.unit(q) for q in Q.SI_UNIT if q != Q.RATIO},
            "parameters": Q.parameter_units(mech, display),
            "outputs": {k: display.unit(Q.quantity(mech, k)) for k in outputs},
            **({"figures": Q.figure_units(figures, display, mech.inputs[0].kind)} if figures else {})}


def parameters_record(mech: Mechanism, display=None) -> dict:
    """``parameters`` (values in ``display`` units, default SI) and ``parameter_units`` (their unit labels)
    for a machine-readable record (the CSV sidecar)."""
    from analytic import quantities as Q
    display = display or Q.SI
    return {"parameters": Q.parameters_in(mech, display), "parameter_units": Q.parameter_units(mech, display)}


def _span(x) -> list[float]:
    x = np.asarray(x)
    return [float(np.nanmin(x)), float(np.nanmax(x))] if np.any(np.isfinite(x)) else [math.nan, math.nan]


def analysis_columns(mech: Mechanism, a: Analysis) -> dict[str, np.ndarray]:
    """CSV columns of an analysis: t, the inputs, the reported outputs."""
    return {"t": a.t, **a.inputs, **{k: np.asarray(a.solution[k]) for k in mech.outputs}}


def units_of(mech: Mechanism, columns, display=None) -> dict[str, str]:
    """The unit of each CSV column (for the sidecar) in ``display`` units (default SI)."""
    from sim.output.units import SI, column_unit
    return {c: column_unit(mech, c, display or SI) for c in columns}


# --------------------------------------------------------------------------------------- simulation
def check_singular(mech: Mechanism) -> None:
    """Refuse a run whose first input would carry a group through a singular (change-point) pose,
    naming the input value: the simulation cannot tell the branches apart there."""
    if len(mech.inputs) != 1:
        from analytic.applications import figures
        t = np.linspace(0.0, mech.duration(1.0), 2001)
        sol = mech.solve(*mech.drive(t))
        m, where = figures.min_singularity(mech, sol)
        if m < figures.SINGULAR:
            raise ParameterError(f"the {mech.name} passes through a singular pose ({where} folds): its motion is "
                                 f"undefined there; change a length or a phase")
        return
    from analytic.applications import figures
    first = mech.inputs[0]
    at = _change_point_at_start(mech)
    if at is not None:
        shown = f"{math.degrees(at) % 360:.2f}deg" if first.kind == "crank" else f"{at:.6g} m"
        raise ParameterError(f"the {mech.name} starts at a change point ({first.q}={shown}, where a dyad's links "
                             f"align): the loops' equations are singular there at the simulation's first step; "
                             f"start it a little away (e.g. {first.parameters[0] or 'its start'} = 1deg)")
    check_change_swing(mech)
    poses = [p for p in figures.singular_poses(mech) if not passes_smoothly(mech, p[1], p[0])]
    if poses:
        first = mech.inputs[0]
        x, label, _ = poses[0]
        at = f"{math.degrees(x) % 360:.2f}deg" if first.kind == "crank" else f"{x:.6g} m"
        element = next(e for e in mech.geometry.elements if e["label"] == label)
        if element.get("change") == -1:
            raise ParameterError(f"the {mech.name} passes a change point at {first.q}={at} ({label} folds) where it is "
                                 f"declared to switch form (change = -1: its branch sign kept), a kink in its motion; "
                                 f"the simulation, carried on by its momentum, keeps the form there: declare change = 1 "
                                 f"to simulate it, or run between two such angles with an input range")
        raise ParameterError(f"the {mech.name} passes through a singular pose at {first.q}={at} ({label} folds: "
                             f"a change point, where it may switch branch); the simulation cannot follow it: "
                             f"change a length by a little, or run between two such angles with an input range")


CHANGE_SWING = 0.1
"""[singularity measure, the sine of a dyad's transmission angle] The least a dyad that passes change points
must swing away from its fold between them for the simulation to follow it: a parallelogram swings to 1 and
passes; a Peaucellier cell whose rhombus stays within 1.9 deg of flat (0.033) over the whole turn, passing 4
change points, opened its loops by 6 mm (the trust benchmark's seed 1, design 832)."""


def check_change_swing(mech: Mechanism) -> None:
    """Refuse a run in which a dyad passing change points stays near its fold over the whole turn."""
    flipping = [e["label"] for e in mech.solving_geometry.elements if e.get("flips")]
    if not flipping:
        return
    from analytic.applications import figures
    t = np.linspace(0.0, mech.duration(1.0), 2001)
    measures = figures.singularity(mech, mech.solve(*mech.drive(t)))
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
    if first.kind != "crank" or sense == 0 or _change_point_at_start(mech) is None:
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
    return (dx + math.pi) % (2 * math.pi) - math.pi if first.kind == "crank" else dx


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


def prepare(mech: Mechanism, revolutions: float, input_range=None) -> Mechanism:
    """Checks before any simulation: revolutions, full turn or rocking range, singular poses."""
    check_revolutions(revolutions)
    if input_range is not None:
        lo, hi = check_range(mech, *input_range)
        mech = mech.rocking(lo, hi)
        q = np.linspace(lo, hi, 721)
        if len(mech.inputs) > 1:                  # the others move as the run moves them: check those poses
            q = mech.drive(np.linspace(0.0, mech.duration(revolutions), 2001))[0]
            try:
                mech.check_assembles(q)
            except ParameterError as exc:
                raise ParameterError(f"{exc}; while the first input rocks, the others keep their own motion "
                                     f"(give one omega = 0 in the file to hold it at its start)") from None
        mech.check_assembles(q)
        check_fold(mech)
        return mech
    mech = clear_of_change_point(mech)
    check_turns_fully(mech)
    check_singular(mech)
    t = np.linspace(0.0, mech.duration(min(revolutions, 1.0) if len(mech.inputs) == 1 else revolutions), 2001)
    check_folded_change_points(mech, mech.drive(t)[0][:, 0])      # before a sample that lands on one
    mech.check_assembles(mech.drive(t)[0])
    return mech


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
        return f"{math.degrees(v) % 360:.2f}deg" if first.kind == "crank" else f"{v / mech.scale:.6g} {mech.units}"
    shown = sorted((math.degrees(v) % 360 if first.kind == "crank" else v, fmt(v)) for v in change_points(mech))
    every = ", ".join(f for _, f in shown)
    raise ParameterError(f"the {mech.name} passes a change point at {first.q}={fmt(x)} where {p} and {q} meet "
                         f"({label}: both links turn about one point there and fold onto each other, free to turn "
                         f"together; Pyslvs' solver stops there too): the simulation cannot carry it through; run it "
                         f"between two of its change points ({every}) with --input-range")


def check_fold(mech: Mechanism) -> None:
    """Refuse a rocking run that comes so close to a dead point that the simulation cannot meet compare's
    tolerances there (:data:`sim.model.timestep.FOLD_FLOOR`, ``FOLD_MARGIN``), naming how far inside to
    stay and the range that can be run (rounded inward)."""
    from analytic.applications import figures
    from sim.model.timestep import FOLD_FLOOR, FOLD_MARGIN, fold_measure
    m, label = fold_measure(mech)
    lo, hi = mech.rock
    first = mech.inputs[0]
    crank = first.kind == "crank"
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
    plain = replace(mech, rock=None)
    ranges = figures.assembly_ranges(plain)
    if figures.turns_fully(plain, ranges):
        return None, None
    turn = 2 * math.pi if mech.inputs[0].kind == "crank" else 0.0
    for a, b in ranges:
        for k in ((range(-3, 4)) if turn else (0,)):
            if a + k * turn <= lo + 1e-12 and hi - 1e-12 <= b + k * turn:
                return a + k * turn, b + k * turn
    return None, None


def _fold_limit(mech: Mechanism, dead: float, end: float, floor: float, margin: float) -> float:
    """The input value between the dead point ``dead`` and the range's ``end`` (or beyond it, towards the
    middle) where the smallest singularity measure reaches ``floor``, at least ``margin`` from ``dead``."""
    from analytic.applications import figures
    plain = replace(mech, rock=None)
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
    """Build and run the MuJoCo model: returns (Built, Trajectory)."""
    from sim.model import Loads, Settings, build
    from sim.run.simulate import simulate as run
    mech = prepare(mech, revolutions, input_range)
    built = build(mech, settings or Settings(), loads or Loads(), revolutions)
    return built, run(built, revolutions)


def compare(mech: Mechanism, revolutions: float = 1.0, settings=None, loads=None, input_range=None):
    """Simulate and cross-validate: returns (Built, Comparison)."""
    from sim.run.compare import compare as cmp
    built, tr = simulate(mech, revolutions, settings, loads, input_range)
    return built, cmp(tr, built, revolutions)


def comparison_record(built, c, display=None) -> dict:
    """The JSON of ``linkage compare --json`` (and the app's simulate): SI unless ``display``."""
    return c.as_dict(built, display)


def trajectory_columns(tr) -> dict:
    """CSV columns of a trajectory: t, inputs, every output, loop violation, drive forces, commanded
    inputs (``cmd_phi1``) and every joint's coordinate and rate (``q_NAME``, ``v_NAME``)."""
    joints = {f"q_{n}": tr.qpos[:, i] for i, n in enumerate(tr.joint_names)}
    joints.update({f"v_{n}": tr.qvel[:, i] for i, n in enumerate(tr.joint_names)})
    outs = {k: np.asarray(v) for k, v in tr.outputs.items() if not k.startswith(("cos", "sin"))}
    return {"t": tr.t, **tr.inputs, **outs, "loop_violation": tr.loop_violation, **tr.forces,
            **{f"cmd_{k}": v for k, v in tr.commanded.items()}, **joints}


def export_mjcf(mech: Mechanism, settings=None, revolutions: float = 1.0) -> str:
    """The generated MJCF of ``mech`` as a standalone document (its time step chosen for ``revolutions``)."""
    from sim.model import Settings, build, export_xml
    return export_xml(build(mech, settings or Settings(), revolutions=revolutions))


def mechanism_text(mech: Mechanism) -> str:
    """The mechanism's file (TOML) with its current parameter values written in."""
    from sim.output.tomlout import dump
    return dump(mech)


# ------------------------------------------------------------------------------------------- forces
@dataclass(frozen=True)
class ForceRun:
    """One run of ``linkage forces``: the motion (``t`` [s], the inputs ``q, qd, qdd`` of shape (N, k) and
    their columns ``inputs``), the mass model, the loads applied (``loads``: a JSON-ready description), the
    joint forces, and with balancing the counterweights (``balance``) and the forces with them (``balanced``)."""

    mech: Mechanism
    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    inputs: dict
    solution: object
    inertias: dict
    sources: dict
    loads: dict
    forces: object
    balance: object = None
    balanced: object = None
    loaded: object = None
    """The kinetostatics with the file's and the command line's loads (:class:`analytic.loads.kinetostatics.Loaded`)."""
    loadset: object = None
    energy: dict | None = None
    """Each load's work per cycle, friction's dissipation and the energy balance (sim.loads.energy_of)."""


def _visited(first, q1: np.ndarray, x: float) -> bool:
    """Whether the first input's run ``q1`` passes the value ``x`` (a crank: any turn of it)."""
    lo, hi = float(np.min(q1)), float(np.max(q1))
    tol = 1e-9 * max(1.0, abs(lo), abs(hi))
    if first.kind != "crank":
        return lo - tol <= x <= hi + tol
    k = math.ceil((lo - tol - x) / (2 * math.pi))
    return x + 2 * math.pi * k <= hi + tol


def check_forces_singular(mech: Mechanism, q: np.ndarray, sol=None) -> None:
    """Refuse a run that passes a singular pose of a group (its joint forces are unbounded there), naming the
    first input's value: the refined singular poses of the first input's range (one input), or the smallest
    singularity measure over the run's samples."""
    from analytic.applications import figures
    first = mech.inputs[0]
    if len(mech.inputs) == 1:
        for x, label, _ in figures.singular_poses(mech):
            if _visited(first, q[:, 0], x):
                raise ParameterError(_singular_text(mech, x, label))
    step = max(1, len(q) // 20001)
    sub = mech.solve(q[::step], 1.0 if len(mech.inputs) == 1 else np.ones(len(mech.inputs)))
    for label, m in figures.singularity(mech, sub).items():
        m = np.where(np.isfinite(m), m, np.inf)
        k = int(np.argmin(m))
        if m[k] < figures.SINGULAR:
            raise ParameterError(_singular_text(mech, float(q[::step][k, 0]), label))


def _singular_text(mech: Mechanism, x: float, label: str) -> str:
    from analytic.applications.forces import angle_text
    first = mech.inputs[0]
    return (f"the {mech.name} passes through a singular pose at {first.q}={angle_text(first, x)} ({label} folds): "
            f"its joint forces are unbounded there; change a length by a little, or run between two such "
            f"values with an input range")


def _load_window(mech: Mechanism, q1: np.ndarray):
    """1 where a cutting force acts (the output point's slow stroke along x), else 0: the simulation's switch
    (sim.model.drives.load_switch) on the first input's phase; and the window (lo, hi) [rad of phase]."""
    from sim.model.drives import slow_stroke
    lo, hi = slow_stroke(mech)
    phase = np.mod(q1 - mech.inputs[0].motion.q0, 2 * math.pi)
    on = ((phase >= lo) & (phase <= hi)) | ((phase + 2 * math.pi >= lo) & (phase + 2 * math.pi <= hi))
    return on.astype(float), (lo, hi)


def mass_sources(mech: Mechanism, given: dict | None) -> dict[str, str]:
    """Where each link's mass comes from: --inertia, [inertia], [mass] or the default; "+ counterweight"."""
    from analytic import mass
    mats = mass.materials(mech)
    weighted = {w.link for w in mass.counterweights(mech)}
    out = {}
    for ln in mech.links:
        src = ("--inertia" if ln in (given or {}) else "[inertia]" if ln in mech.definition.inertia
               else f"[mass] {mats[ln].shape}" if ln in mats else "default (1 kg/m bars)")
        out[ln] = src + (" + counterweight" if ln in weighted else "")
    return out


def forces_run(mech: Mechanism, samples: int = 361, revolutions: float = 1.0, input_range=None,
               gravity=None, force=(0.0, 0.0), slow_stroke_only: bool = False, inertias: dict | None = None,
               balance=None, extra_loads=(), at=None) -> ForceRun:
    """Every joint force of ``mech`` along its motion law: ``samples`` instants over ``revolutions`` of the
    first input (or rocking over ``input_range``), with ``gravity`` (gx, gy) [m/s^2], ``force`` (Fx, Fy) [N]
    on the output point (only on the slow stroke when ``slow_stroke_only``: a cutting force) and the mass
    model with ``inertias`` ({link: Inertia}, SI) replacing links' own. ``balance``: None, or the links to
    carry counterweights (an empty tuple: the default choice, see analytic.applications.balance).
    ``extra_loads``: the command line's loads (analytic.loads dataclasses) besides the file's ``[[loads]]``
    and ``[friction]`` (SPEC "Loads"); ``at``: one value of the first input [rad or m] instead of a run."""
    from analytic import mass
    from analytic.applications import balance as bal
    from analytic.applications import forces as F
    check_samples(samples)
    check_revolutions(revolutions)
    F.check_determinate(mech)
    if input_range is not None:
        lo, hi = check_range(mech, *input_range)
        mech = mech.rocking(lo, hi)
    else:
        check_turns_fully(mech)
    from sim import loads as L
    t, cycles = L.run_times(mech, samples, revolutions, at)
    q, qd, qdd = mech.drive(t)
    mech.check_assembles(q)
    check_forces_singular(mech, q)
    sol = mech.solve(q, qd, qdd, outputs=L.K.full_wanted(mech))
    model = mass.model(mech, inertias)
    gx, gy = gravity if gravity is not None else (0.0, 0.0)
    fx, fy = force
    on, window = (_load_window(mech, q[:, 0]) if slow_stroke_only and (fx or fy) else (1.0, None))
    loadset = L.loadset(mech, extra_loads)
    loaded = L.K.solve(mech, q, qd, qdd, t, model, loadset, (gx, gy), (fx, fy), on, sol=sol)
    result = loaded.forces
    bad = F.singular_samples(result)
    if bad.any():
        k = int(np.argmax(bad))
        raise ParameterError(_singular_text(mech, float(q[k, 0]), "a group"))
    point = mech.output_point
    loads = {"gravity": list(gravity) if gravity is not None else None,
             "force": ({"Fx": fx, "Fy": fy, "point": point, "link": mech.topology.carriers[point],
                        "cutting": bool(slow_stroke_only),
                        **({"window": list(window)} if window is not None else {})} if (fx or fy) else None)}
    cols = {}
    for k, inp in enumerate(mech.inputs):
        cols[inp.q] = q[:, k]
    balance_result = balanced = None
    if balance is not None:
        balance_result = bal.balance(mech, L.whole_cycles(mech, sol, t, revolutions), model, tuple(balance) or None)
        balanced = L.K.solve(mech, q, qd, qdd, t, bal.with_counterweights(model, balance_result.counterweights),
                             loadset, (gx, gy), (fx, fy), on, sol=sol).forces
    energy = L.energy_of(mech, loaded, loadset, model, (gx, gy), (fx, fy), on, cycles)
    return ForceRun(mech, t, q, qd, qdd, cols, sol, model, mass_sources(mech, inertias), loads, result,
                    balance_result, balanced, loaded, loadset, energy)


def force_peaks(run: ForceRun, forces=None) -> dict:
    """Each joint's peak |F| [N] (a prismatic pair's also its peak |M| [N m]), each drive's peak and the
    shaking force's and moment's, with the sample index where each occurs; the RMS over the closed run
    (its end sample counted once)."""
    from analytic.applications.cycle import closed_rms
    f = forces or run.forces
    out = {"joints": {}, "drives": {}, "shaking": {}}
    mag = f.magnitude()
    for k, j in enumerate(f.joints):
        i = int(np.argmax(mag[k]))
        entry = {"F": float(mag[k, i]), "at": i}
        if j.kind == "prismatic":
            m = np.abs(f.M(k))
            entry.update({"M": float(m.max()), "at_M": int(np.argmax(m))})
        out["joints"][j.name] = entry
    for inp in run.mech.inputs:
        d = np.abs(f.drives[inp.link])
        out["drives"][inp.q] = {"value": float(d.max()), "at": int(np.argmax(d))}
    sf = np.hypot(f.shaking[0], f.shaking[1])
    sm = np.abs(f.shaking[2])
    out["shaking"] = {"F": float(sf.max()), "at": int(np.argmax(sf)), "M": float(sm.max()), "at_M": int(np.argmax(sm)),
                      "F_rms": float(closed_rms(sf))}
    return out


def forces_record(run: ForceRun, display=None) -> dict:
    """The JSON of ``linkage forces --json`` (SPEC "Forces"): SI, world frame, arrays over the samples,
    unless ``display`` converts lengths and angles (forces stay N, torques N m)."""
    from analytic import quantities as Q
    from analytic.applications.forces import centres
    display = display or Q.SI
    mech, f = run.mech, run.forces

    def L(v):
        return display.convert(Q.LENGTH, v)

    def inp_q(inp):
        return Q.ANGLE if inp.kind == "crank" else Q.LENGTH

    com = centres(mech, run.solution, run.inertias)
    links = {ln: {"m": b.m, "I": b.I, "cx": L(b.cx), "cy": L(b.cy), "xG": L(com[ln][0]), "yG": L(com[ln][1]),
                  "source": run.sources[ln]} for ln, b in run.inertias.items()}
    joints = []
    for k, j in enumerate(f.joints):
        entry = {"name": j.name, "point": j.point, "kind": "R" if j.kind == "revolute" else "P",
                 "links": [j.a, j.b], "Fx": f.F[k, 0], "Fy": f.F[k, 1]}
        if j.kind == "prismatic":
            entry["M"] = f.M(k)
        if j.input is not None:
            entry["input"] = mech.inputs[j.input].q
        joints.append(entry)
    drives = {inp.q: f.drives[inp.link] for inp in mech.inputs}
    record = {"mechanism": mech.name, "samples": len(run.t), "t": run.t,
              "inputs": {inp.q: display.convert(inp_q(inp), run.inputs[inp.q]) for inp in mech.inputs},
              "links": links, "joints": joints, "drives": drives,
              "shaking": {"Fx": f.shaking[0], "Fy": f.shaking[1], "M": f.shaking[2]},
              "loads": loads_table(run, display), "peaks": _peaks_at(run, force_peaks(run), display),
              "units": {"file": mech.units, "length": display.unit(Q.LENGTH), "angle": display.unit(Q.ANGLE),
                        "time": "s", "force": "N", "torque": "N m", "mass": "kg", "I": "kg m^2",
                        "inputs": {inp.q: display.unit(inp_q(inp)) for inp in mech.inputs},
                        "drives": {inp.q: "N m" if inp.kind == "crank" else "N" for inp in mech.inputs}}}
    if run.balance is not None:
        record["balance"] = balance_record(run, display)
    if run.energy is not None:
        from sim import loads as L
        L.add_to_record(record, run, display)
    return record


def loads_table(run: ForceRun, display=None) -> list:
    """The JSON ``loads`` table (SPEC "Loads"): every load applied with its link, point and work per cycle."""
    from sim import loads as L
    return L.table(run, display)


def _peaks_at(run: ForceRun, peaks: dict, display) -> dict:
    """The peaks with the first input's value (display units) beside each sample index ``at``/``at_M``."""
    from analytic import quantities as Q
    first = run.mech.inputs[0]
    quantity = Q.ANGLE if first.kind == "crank" else Q.LENGTH

    def value(i):
        return display.convert(quantity, float(run.q[i, 0]))

    def walk(d):
        out = {}
        for k, v in d.items():
            out[k] = walk(v) if isinstance(v, dict) else v
            if k in ("at", "at_M") and not isinstance(v, dict):
                out[f"{first.q}{'' if k == 'at' else '_M'}"] = value(v)
        return out
    return walk(peaks)


def balance_record(run: ForceRun, display=None) -> dict:
    """The counterweights (mass [kg], position in the link's frame) and the shaking force before/after."""
    from analytic import quantities as Q
    display = display or Q.SI
    b = run.balance
    after = force_peaks(run, run.balanced)["shaking"]
    before = force_peaks(run)["shaking"]
    return {"method": b.method,
            "counterweights": [{"link": w.link, "m": w.m, "at": [display.convert(Q.LENGTH, w.u),
                                                                display.convert(Q.LENGTH, w.v)]}
                               for w in b.counterweights],
            "inertial_shaking": {"before": b.before, "after": b.after},
            "shaking": {"before": {"rms": before["F_rms"], "peak": before["F"]},
                        "after": {"rms": after["F_rms"], "peak": after["F"]}},
            "shaking_force_after": {"Fx": run.balanced.shaking[0], "Fy": run.balanced.shaking[1]},
            "drives_after": {inp.q: run.balanced.drives[inp.link] for inp in run.mech.inputs}}


def forces_columns(run: ForceRun) -> tuple[dict, dict]:
    """CSV columns of a forces run and their quantities: t, the inputs, each joint's ``Fx_J Fy_J F_J``
    (``M_J`` for a prismatic pair), each drive ``tauL`` (L the input's link, as in simulate's CSV), the shaking
    force and moment."""
    from analytic import quantities as Q
    mech, f = run.mech, run.forces
    cols = {"t": run.t}
    qty = {"t": Q.TIME}
    for inp in mech.inputs:
        cols[inp.q] = run.inputs[inp.q]
        qty[inp.q] = Q.ANGLE if inp.kind == "crank" else Q.LENGTH
    mag = f.magnitude()
    for k, j in enumerate(f.joints):
        for name, v in ((f"Fx_{j.name}", f.F[k, 0]), (f"Fy_{j.name}", f.F[k, 1]), (f"F_{j.name}", mag[k])):
            cols[name], qty[name] = v, Q.FORCE
        if j.kind == "prismatic":
            cols[f"M_{j.name}"], qty[f"M_{j.name}"] = f.M(k), Q.TORQUE
    for inp in mech.inputs:
        cols[f"tau{inp.link}"] = f.drives[inp.link]                 # as simulate's CSV names a drive
        qty[f"tau{inp.link}"] = Q.TORQUE if inp.kind == "crank" else Q.FORCE
    for name, k, quantity in (("Fx_shaking", 0, Q.FORCE), ("Fy_shaking", 1, Q.FORCE), ("M_shaking", 2, Q.TORQUE)):
        cols[name], qty[name] = f.shaking[k], quantity
    return cols, qty


def forces_table(run: ForceRun, display=None) -> str:
    """What ``linkage forces`` prints: each joint's peak force and the first input's value where it occurs,
    the drives' peaks, the shaking force's and moment's (lengths in ``display`` units, forces N, torques N m)."""
    from analytic import quantities as Q
    from analytic.applications.forces import angle_text
    display = display or Q.SI
    mech, f = run.mech, run.forces
    first = mech.inputs[0]
    q1 = run.q[:, 0]

    def at(i):
        if first.kind == "crank":
            return angle_text(first, float(q1[i]))
        return f"{display.convert(Q.LENGTH, float(q1[i])):.6g} {display.unit(Q.LENGTH)}"

    peaks = force_peaks(run)
    loads = run.loads
    parts = []
    if loads["gravity"]:
        parts.append(f"gravity {loads['gravity'][0]:g},{loads['gravity'][1]:g} m/s^2")
    if loads["force"]:
        fl = loads["force"]
        parts.append(f"{'cutting force' if fl['cutting'] else 'force'} {fl['Fx']:g},{fl['Fy']:g} N on {fl['point']} "
                     f"(link {fl['link']})")
    if run.loadset:
        parts.append(f"{len(run.loadset.loads)} load{'s' * (len(run.loadset.loads) != 1)}"
                     + (" and friction" if run.loadset.friction else ""))
    lines = [f"{mech.name}: joint forces over {len(run.t)} samples ({', '.join(parts) or 'inertia only'}); "
             f"masses: {sum(b.m for b in run.inertias.values()):.4g} kg in {len(run.inertias)} links",
             f"  {'joint':<12s} {'kind':<5s} {'links':<22s} {'peak |F| [N]':>13s}  at {first.q}"]
    for k, j in enumerate(f.joints):
        pk = peaks["joints"][j.name]
        kind = "R" if j.kind == "revolute" else "P"
        extra = ""
        if j.kind == "prismatic":
            extra = f"; couple peak {pk['M']:.4g} N m at {at(pk['at_M'])}"
        if j.input is not None:
            extra += " (driven)"
        lines.append(f"  {j.name:<12s} {kind:<5s} {j.a + '-' + j.b:<22s} {pk['F']:13.5g}  {at(pk['at'])}{extra}")
    for inp in mech.inputs:
        d = peaks["drives"][inp.q]
        unit = "N m" if inp.kind == "crank" else "N"
        lines.append(f"  drive of {inp.q}: peak {'torque' if inp.kind == 'crank' else 'force'} {d['value']:.5g} "
                     f"{unit} at {at(d['at'])}")
    s = peaks["shaking"]
    lines.append(f"  shaking force: peak {s['F']:.5g} N at {at(s['at'])} (RMS {s['F_rms']:.5g} N); shaking moment "
                 f"about the origin: peak {s['M']:.5g} N m at {at(s['at_M'])}")
    if run.balance is not None:
        b = run.balance
        lines.append(f"  balance ({b.method}): " + ("; ".join(
            f"{w.m:.4g} kg on link {w.link} at ({display.convert(Q.LENGTH, w.u):.4g}, "
            f"{display.convert(Q.LENGTH, w.v):.4g}) {display.unit(Q.LENGTH)}" for w in b.counterweights)
            or "no counterweight helps"))
        after = force_peaks(run, run.balanced)["shaking"]
        lines.append(f"    shaking force of the inertia: RMS {b.before['rms']:.5g} -> {b.after['rms']:.5g} N, peak "
                     f"{b.before['peak']:.5g} -> {b.after['peak']:.5g} N; with the loads: RMS {s['F_rms']:.5g} -> "
                     f"{after['F_rms']:.5g} N")
    from sim import loads as L
    lines += L.summary(run)
    return "\n".join(lines)


def balanced_mechanism(mech: Mechanism, links=None) -> tuple[Mechanism, object]:
    """``mech`` with the counterweights of :func:`analytic.applications.balance.balance` written into its
    file's ``[mass.counterweights]`` (file units), so every model built from it (MuJoCo's included) carries
    them; and the Balance."""
    from dataclasses import replace
    from analytic import mass
    from analytic.applications import balance as bal
    from analytic.applications import forces as F
    t = np.linspace(0.0, mech.duration(1.0), 360, endpoint=False)      # a turn, its start angle once
    q, qd, qdd = mech.drive(t)
    mech.check_assembles(q)
    sol = mech.solve(q, qd, qdd, outputs=F.wanted(mech))
    result = bal.balance(mech, sol, mass.model(mech), tuple(links or ()) or None)
    d = mech.definition
    section = {k: v for k, v in (d.mass or {}).items()}
    weights = {k: (list(v) if isinstance(v, list) else [v]) for k, v in section.get("counterweights", {}).items()}
    s = mech.scale
    for w in result.counterweights:
        weights.setdefault(w.link, []).append({"m": w.m, "at": [w.u / s, w.v / s]})
    section["counterweights"] = {k: (v[0] if len(v) == 1 else v) for k, v in weights.items()}
    new = replace(d, mass=section)
    return Mechanism.from_definition(new, mech.overrides, mech.builtin), result


def simulated_forces_run(run: ForceRun, settings=None, loads=None):
    """``run`` simulated in MuJoCo, its joint forces read at the run's samples and compared with the analytic
    ones at the simulated inputs (:class:`sim.run.forces.Simulated`)."""
    from sim.run import forces as simforces
    return simforces.simulate_run(run, settings, loads)


def simulated_forces(run: ForceRun, settings=None, loads=None, display=None) -> dict:
    """The ``simulated`` object of ``linkage forces --simulate --json``: MuJoCo's answer in the fields of
    :func:`forces_record` (at the run's samples, the inputs as simulated, the model's masses), the time step
    and steps, the agreement with the analytic forces (``agreement``: each joint's largest difference [N] and
    its share of the peak joint force, the drives' three answers, the shaking force) and ``passed``."""
    from dataclasses import replace
    from sim.model import body_inertias
    s = simulated_forces_run(run, settings, loads)
    mech, tr = run.mech, s.trajectory
    q, qd, qdd = s.inputs
    sol = {k: np.asarray(v)[s.steps] for k, v in tr.outputs.items() if k[:1] in ("x", "y", "c", "s")}
    sim_run = replace(run, t=run.t[:len(s.steps)], q=q, qd=qd, qdd=qdd, inputs={inp.q: q[:, k] for k, inp in enumerate(mech.inputs)},
                      solution=sol, inertias=body_inertias(s.built.model, mech.links), forces=s.forces,
                      balance=None, balanced=None)
    record = forces_record(sim_run, display)
    for key in ("mechanism", "loads", "units"):
        record.pop(key, None)
    record.update({"timestep": s.built.timestep, "steps": int(tr.steps), "agreement": s.agreement.as_dict(),
                   "passed": s.agreement.passed})
    return record
