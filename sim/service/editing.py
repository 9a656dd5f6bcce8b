"""Editing a mechanism by its drawing (the app's direct manipulation; public API): :func:`drag` moves a point of
the drawing and gives the file's values that place it there (the inverse of the file's parameterisation), and
:func:`assur_groups` names the groups a drawn linkage was decomposed into.

``drag(mech, text, point, target, q, locked=(), round_to=None)`` returns a :class:`Drag`: the changed
parameter values, the file's new text where a links-and-joints ``[pose]`` changed, the input value to show,
where the point landed, whether it reached the target, and one line for the user.

A point is placed by its element (a ground entry, an input, an Assur group, a point on a link) or, in the
links-and-joints form, by its ``[pose]`` entry. The values that can move it are the parameters its fields
name (a length, an offset, a ground coordinate, a coupler point's ``at``; every parameter an expression
there uses), the pose coordinates written as numbers in a links-and-joints file, and for the point at an
input's tip the input itself (dragging it scrubs the pose). Locked parameters stay. The new values are
found by damped least squares with the smallest change (Gauss-Newton on the point's solved position at the
pose's input value, derivatives by finite differences), so the same code serves every kind of element; a
step that would break assembly is cut back, and a drag that cannot be followed stops at the limit with one
line saying why.
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
import tomllib

import numpy as np

from analytic import ParameterError, kinds
from analytic.format import expr
from analytic.mechanism import Mechanism, block
from sim import service

TOLERANCE = 1e-9
"""Fraction of the mechanism's size within which a point counts as placed (the solver's own closure is
~1e-12 of the size; finite-difference derivatives leave ~1e-8 of a step, which the iterations remove)."""
MAX_ITERATIONS = 40
MAX_CALLS = 40
"""Placements one solve of a drag may spend (a free drag takes ~10; creeping along an assembly limit, where
steps keep failing, would take hundreds: ~0.5 ms each, and a drag step has ~16 ms)."""
FLIP_MISS = 1e-3
"""A miss above this fraction of the size tries the element's other branch too (the pointer crossed the
line of its two joints); below it the miss is a lock's or a limit's, which the other branch does not mend."""
STEP_DONE = 1e-10
"""A step this small (in the values' natural sizes, :func:`scales`) ends the iterations: the point is as near
the target as the free values let it come."""
SKIP_FIELDS = {"point", "points", "link", "links", "from", "on", "pivot", "through", "branch", "change", "kind"}
"""Fields that name points, links or the branch: never a continuous value to change."""


@dataclasses.dataclass(frozen=True)
class Variable:
    """One value a drag may change: a named parameter (``kind="parameter"``), a number in the file's
    ``[pose]``/``[ground]`` table (``kind="pose"``, ``name`` the point, ``axis`` 0 for x, 1 for y), or the
    first input's value (``kind="input"``: the pose shown, not the file)."""

    kind: str
    name: str
    axis: int = 0
    section: str = ""


@dataclasses.dataclass(frozen=True)
class Drag:
    """What a drag did. ``values``: every named parameter it changed (file units, angles in rad);
    ``text``: the file's new text where pose numbers changed (else None); ``input``: the input value to show
    (rad or m; None: unchanged); ``position``: where the point is now [m]; ``reached``: within TOLERANCE of
    the target; ``message``: one line (why it stopped short, or what changed)."""

    point: str
    values: dict
    text: str | None
    input: float | None
    position: tuple[float, float]
    reached: bool
    message: str
    scrub: bool = False
    """Only the input moved (a locked or pose-given crank): the pose turns to the pointer, off its circle."""
    input_name: str | None = None
    """The column of the input whose value ``input`` is (an actuator's pin dragged moves its own input)."""


# ------------------------------------------------------------------------------------ what moves P
def _names(value, params: dict) -> list[str]:
    """The parameter names a field's value uses (a bare name or an expression's names), in order."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return [n for f in dataclasses.fields(value) for n in _names(getattr(value, f.name), params)]
    if isinstance(value, (list, tuple)):
        return [n for v in value for n in _names(v, params)]
    if isinstance(value, dict):
        return [n for v in value.values() for n in _names(v, params)]
    if isinstance(value, str):
        if expr.NAME.match(value):
            return [value] if value in params else []
        try:
            return sorted(n for n in expr.names_in(value) if n in params)
        except (ValueError, ParameterError, SyntaxError):
            return []
    return []


def file_data(text: str | None) -> dict | None:
    """A file's text as its table (TOML, or JSON when it starts with '{'); None for a library mechanism."""
    if text is None:
        return None
    return json.loads(text) if text.lstrip().startswith("{") else tomllib.loads(text)


def variables(mech: Mechanism, point: str, data: dict | None, locked=()) -> tuple[list[Variable], list[str]]:
    """(the values that can move ``point``, the branch parameters of the element that places it)."""
    d = mech.definition
    params = {k: v for k, v in d.parameter_kind.items() if k not in locked}
    out: list[Variable] = []
    branches: list[str] = []

    def add(var: Variable) -> None:
        if var not in out:
            out.append(var)

    pose_form = data is not None and ("pose" in data or "links" in data)
    if pose_form:
        for section in ("ground", "pose"):
            xy = (data.get(section) or {}).get(point)
            if isinstance(xy, list) and len(xy) == 2:
                for axis, v in enumerate(xy):
                    if isinstance(v, (int, float)) and not isinstance(v, bool):
                        add(Variable("pose", point, axis, section))
                    else:
                        for n in _names(v, params):
                            add(Variable("parameter", n))
    if point in d.ground and not pose_form:
        for n in _names(d.ground[point], params):
            if params[n] != "branch":
                add(Variable("parameter", n))
    for e in d.order:
        if point not in e.places:
            continue
        kind = kinds.get(e.kind)
        motion = set(getattr(kind, "motion_fields", ()) or ())
        if kind.section == "inputs":              # the input that places it (each of several: its own)
            add(Variable("input", next((i.q for i in mech.inputs if i.point == point), mech.inputs[0].q)))
        for field, value in e.fields.items():
            if field in motion or field in SKIP_FIELDS:
                if field == "branch":
                    branches += [n for n in _names(value, params) if params[n] == "branch"]
                continue
            if pose_form:                 # the pose places it; a number here was worked out from the pose
                continue
            for n in _names(value, params):
                if params[n] != "branch":
                    add(Variable("parameter", n))
    if pose_form and any(v.kind == "input" for v in out):
        # the input's tip of a links-and-joints file: its pose would move the crank and the coupler at once;
        # the drag turns the input (the lengths follow from the pose: drag the pivot or the far joints)
        out = [v for v in out if v.kind == "input"]
    return out, branches


# ---------------------------------------------------------------------------------- evaluation
def set_pose(data: dict, var: Variable, value: float) -> dict:
    section = dict(data[var.section])
    xy = list(section[var.name])
    xy[var.axis] = float(value)
    section[var.name] = xy
    return {**data, var.section: section}


def upstream(geometry, point: str):
    """``geometry`` up to the element that places ``point`` (the ones after it in solving order cannot move
    it); the whole geometry for a point no element places."""
    for k, e in enumerate(geometry.elements):
        if point in e["places"]:
            return dataclasses.replace(geometry, elements=geometry.elements[:k + 1])
    return geometry


class _Downstream(Exception):
    """A drag solved on the elements up to its point ended where a later element cannot close."""


class _Model:
    """The mechanism with some of its values replaced, solved for one point at one input value.

    ``prune``: place the point by the elements up to it only (:func:`upstream`; a third of the work for a
    jansen's C); the drag places the whole mechanism where it starts and where it ends (``whole=True``)."""

    def __init__(self, mech: Mechanism, values: dict, data: dict | None, point: str, q: np.ndarray,
                 prune: bool = False):
        self.mech, self.values, self.data, self.point, self.q = mech, dict(values), data, point, q
        # no change point on the way round: the file's geometry as it is (the schedule of change points costs
        # ~1.5 ms a build and would be empty again for values this close)
        self.plain = all(not e.get("flips") for e in mech.solving_geometry.elements)
        self.prune = prune and self.plain
        self.calls = 0

    def build(self, vars_: list[Variable], x: np.ndarray) -> tuple[Mechanism, np.ndarray, dict | None]:
        values = dict(self.values)
        data = self.data
        q = self.q.copy()
        for var, v in zip(vars_, x):
            if var.kind == "parameter":
                values[var.name] = float(v)
            elif var.kind == "input":
                q[input_index(self.mech, var)] = float(v)
            else:
                data = set_pose(data, var, v)
        if data is not self.data:
            mech = service.load("<upload>", values, text=json.dumps(data))
        else:
            mech = self.mech.with_values(**{k: v for k, v in values.items() if v != self.mech.values.get(k)}) \
                if values != self.mech.values else self.mech
        return mech, q, data

    def place(self, vars_: list[Variable], x: np.ndarray, whole: bool = False) -> np.ndarray:
        """The point's position [m] at these values; raises ParameterError where it cannot be assembled
        (``whole``: where any element cannot close, also those after the point when pruning)."""
        self.calls += 1
        mech, q, _ = self.build(vars_, x)
        p = self.point
        want = {"x" + p, "y" + p}
        if self.plain:
            zero = np.zeros((len(q), 1))
            geometry = upstream(mech.geometry, p) if self.prune and not whole else mech.geometry
            with np.errstate(invalid="ignore", divide="ignore"):
                out, failed, _ = block(geometry, q[:, None], zero, zero, want, None, False)
            if failed[0] >= 0:
                raise ParameterError(f"{geometry.elements[failed[0]]['label']} cannot close")
            xy = np.array([float(np.ravel(out["x" + p])[0]), float(np.ravel(out["y" + p])[0])])
        else:
            sol = mech.solve(q[None, :], outputs=tuple(want))
            failure = sol.first_failure()
            if failure is not None:
                raise ParameterError(f"{failure[1]} cannot close")
            xy = np.array([float(np.ravel(sol["x" + p])[0]), float(np.ravel(sol["y" + p])[0])])
        if not np.all(np.isfinite(xy)):
            raise ParameterError(f"{p} cannot be assembled")
        return xy


def start_values(mech: Mechanism, data: dict | None, vars_: list[Variable], q: np.ndarray) -> np.ndarray:
    out = []
    for var in vars_:
        if var.kind == "parameter":
            out.append(mech.values[var.name])
        elif var.kind == "input":
            out.append(q[input_index(mech, var)])
        else:
            out.append(float(data[var.section][var.name][var.axis]))
    return np.array(out, dtype=float)


def input_index(mech: Mechanism, var: Variable) -> int:
    """Which of ``mech``'s inputs an input variable is (by its column's name)."""
    return next((k for k, i in enumerate(mech.inputs) if i.q == var.name), 0)


def is_angle(mech: Mechanism, var: Variable) -> bool:
    if var.kind == "input":
        return mech.inputs[input_index(mech, var)].angular
    return var.kind == "parameter" and mech.definition.parameter_kind.get(var.name) == "angle"


def scales(mech: Mechanism, vars_: list[Variable]) -> np.ndarray:
    """Each value's natural size, so a least-norm step weighs a length against an angle fairly: 1 rad, the
    mechanism's size in file units (a slider input's value is in metres)."""
    size = mech.size / mech.scale
    return np.array([1.0 if is_angle(mech, v) else mech.size if v.kind == "input" else size for v in vars_])


# ----------------------------------------------------------------------------------- the drag
def jacobian(model: _Model, vars_: list[Variable], x: np.ndarray, p: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """d(position)/d(values) at ``x`` by forward differences (backward where the forward value cannot be
    assembled), one placement per value."""
    J = np.empty((2, len(x)))
    for j in range(len(x)):
        h = 1e-7 * scale[j]
        xs = x.copy()
        xs[j] += h
        try:
            J[:, j] = (model.place(vars_, xs) - p) / h
        except ParameterError:
            xs[j] -= 2 * h
            J[:, j] = (p - model.place(vars_, xs)) / h
    return J


def solve_drag(model: _Model, vars_: list[Variable], x0: np.ndarray, target: np.ndarray, scale: np.ndarray,
               size: float, p0: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, str | None]:
    """Damped Gauss-Newton with least-norm steps: (values, position, why it stopped short or None).

    The derivatives are taken by finite differences once, then carried from step to step by Broyden's rank-one
    update (what each step's move did to the point corrects them): a drag step moves the point a few pixels,
    where the first derivatives stay good, so the later iterations cost one placement each instead of one
    per value. A step the carried derivatives cannot make better takes them afresh before giving up, so the
    answer (the point within TOLERANCE of the target, or the same limit) is the plain Gauss-Newton's.
    ``p0``: the point's position at ``x0`` where the caller has it already (the same placement)."""
    x = x0.copy()
    p = model.place(vars_, x) if p0 is None else p0
    why = None
    spent = model.calls
    J = None                        # in the scaled values z = x / scale
    for _ in range(MAX_ITERATIONS):
        if model.calls - spent > MAX_CALLS:                      # creeping along a limit: stop there
            break
        r = p - target
        if np.hypot(*r) <= TOLERANCE * size:
            break
        fresh = J is None
        if fresh:
            J = jacobian(model, vars_, x, p, scale) * scale
        dz = np.linalg.lstsq(J, -r, rcond=1e-10)[0]
        if np.linalg.norm(dz) < STEP_DONE:                     # the least miss: a limit, a lock
            if fresh:
                break
            J = None
            continue
        step = dz * scale
        t, moved, before = 1.0, False, np.hypot(*r)
        while t > 1e-4:
            try:
                pn = model.place(vars_, x + t * step)
                if np.hypot(*(pn - target)) < before:
                    dzt = t * dz
                    J = J + np.outer(pn - p - J @ dzt, dzt) / float(dzt @ dzt)     # Broyden's update
                    x, p, moved = x + t * step, pn, True
                    break
            except ParameterError as exc:
                why = str(exc)
            t *= 0.5
        if not moved:
            if fresh:
                break
            J = None                                            # stale derivatives: take them afresh
    return x, p, why


def drag(mech: Mechanism, text: str | None, point: str, target, q, locked=(), round_to: float | None = None) -> Drag:
    """Move ``point`` of ``mech`` (loaded from ``text``, None for a library mechanism, with its values) to
    ``target`` [m] in the pose at input values ``q``; ``locked``: parameters to keep; ``round_to``: round
    the changed lengths and coordinates to multiples of this [file units] (the point then lands near).

    The point is placed by the elements up to it; where the values found leave a later element unable to
    close in this pose, the drag is solved again placing the whole mechanism each time, which stops at that
    element's limit as before."""
    try:
        return _drag(mech, text, point, target, q, locked, round_to, prune=True)
    except _Downstream:
        return _drag(mech, text, point, target, q, locked, round_to, prune=False)


def _drag(mech: Mechanism, text: str | None, point: str, target, q, locked, round_to, prune: bool) -> Drag:
    if point not in mech.points:
        raise ParameterError(f"point {point!r} is not a point of {mech.name}; points: {' '.join(mech.points)}")
    q = np.atleast_1d(np.asarray(q, dtype=float)).copy()
    if q.shape != (len(mech.inputs),) or not np.all(np.isfinite(q)):
        raise ParameterError(f"input must give {len(mech.inputs)} finite input value(s) for the pose")
    target = np.asarray(target, dtype=float)
    data = file_data(text)
    vars_, branches = variables(mech, point, data, locked)
    model = _Model(mech, mech.values, data, point, q, prune)
    size = mech.size
    try:
        here = model.place([], np.array([]), whole=True)
    except ParameterError as exc:
        raise ParameterError(f"{point} is not assembled in this pose ({exc}): pick another pose") from None
    if not vars_:
        return Drag(point, {}, None, None, (float(here[0]), float(here[1])), False,
                    f"{point}: no value of the file places it freely"
                    f"{' (its values are locked)' if locked else ''}: edit the file or unlock a parameter")
    scale = scales(mech, vars_)
    start = start_values(mech, data, vars_, q)
    x0 = start.copy()
    first = mech.inputs[0]
    if first.angular and point == first.point:
        # the crank's tip: start from the pointer's angle about the pivot (the scrub in closed form)
        s = mech.solve(q[None, :], outputs=("x" + first.joint, "y" + first.joint))
        pivot = np.array([float(np.ravel(s["x" + first.joint])[0]), float(np.ravel(s["y" + first.joint])[0])])
        turn = math.atan2(*(target - pivot)[::-1]) - math.atan2(*(here - pivot)[::-1])
        for k, var in enumerate(vars_):
            if var.kind == "input":
                x0[k] += (turn + math.pi) % (2 * math.pi) - math.pi
    # at the file's own values the first placement is the one just made (a pose value would rebuild the file)
    same = np.array_equal(x0, start) and all(v.kind != "pose" for v in vars_)
    x, p, why = solve_drag(model, vars_, x0, target, scale, size, here if same else None)
    flipped = None
    if np.hypot(*(p - target)) > FLIP_MISS * size and branches:       # across the line: the other branch
        for b in branches:
            other = _Model(mech.with_values(**{b: -mech.values[b]}), {**mech.values, b: -mech.values[b]}, data,
                           point, q, prune)
            try:
                if np.hypot(*(other.place(vars_, x0) - target)) >= np.hypot(*(p - target)):
                    continue                            # the other branch starts farther off than this ends
                xb, pb, whyb = solve_drag(other, vars_, x0, target, scale, size)
            except ParameterError:
                continue
            if np.hypot(*(pb - target)) < np.hypot(*(p - target)):
                x, p, why, model, flipped = xb, pb, whyb, other, b
    if round_to:
        xr = np.array([round(v / round_to) * round_to if var.kind != "input" and not is_angle(mech, var) else v
                       for var, v in zip(vars_, x)])
        try:
            p, x = model.place(vars_, xr), xr
        except ParameterError:
            pass
    if model.prune:
        try:
            model.place(vars_, x, whole=True)
        except ParameterError:
            raise _Downstream from None
    reached = bool(np.hypot(*(p - target)) <= TOLERANCE * size)
    final, _, new_data = model.build(vars_, x)
    values = {k: v for k, v in final.values.items() if k in mech.values and v != mech.values[k]}
    new_text = None
    if new_data is not data and new_data is not None:
        new_text = rewrite_pose(text, data, new_data)
    moved = next(((var, float(v)) for var, v in zip(vars_, x) if var.kind == "input"), None)
    q_new, input_name = (moved[1], moved[0].name) if moved else (None, None)
    names = [var.name if var.kind != "pose" else f"{var.name}'s {var.section}" for var in vars_]
    scrub = all(var.kind == "input" for var in vars_)
    if scrub and not reached:
        inp = mech.inputs[input_index(mech, moved[0])]
        shown = f"{math.degrees(q_new):.1f} deg" if inp.angular else f"{q_new:.6g} m"
        return Drag(point, values, new_text, q_new, (float(p[0]), float(p[1])), False,
                    f"{point}: {inp.q} {'turned' if inp.angular else 'moved'} to {shown} (its length stays)", True,
                    input_name)
    if reached or round_to and np.hypot(*(p - target)) < round_to * mech.scale:
        message = f"{point}: {', '.join(dict.fromkeys(names))} changed" + (f"; {flipped} flipped" if flipped else "")
    else:
        held = [n for n in locked if n in mech.values]
        if why:
            message = f"{point} stops at the limit: beyond it {plain(why, mech)}"
        else:
            message = (f"{point} stops at the limit: it moves only as {', '.join(dict.fromkeys(names))} "
                       f"change{'s' if len(set(names)) == 1 else ''} (the file's other values that place it are "
                       f"numbers{', or locked: ' + ', '.join(held) if held else ''})")
    return Drag(point, values, new_text, q_new, (float(p[0]), float(p[1])), reached, message, input_name=input_name)


def plain(why: str, mech: Mechanism) -> str:
    """A loader's or solver's line as the drag's reason: without the file's path, an expression named by its
    field instead of quoted whole."""
    why = why.replace(f"{mech.definition.source}: ", "").replace("<upload>: ", "")
    return re.sub(r"'[^']{24,}'(?:\s*\(\d+ characters\))?", "its expression", why)


# ------------------------------------------------------------------------------ the file's text
def rewrite_pose(text: str, old: dict, new: dict) -> str:
    """``text`` with the ``[pose]``/``[ground]`` entries that differ between ``old`` and ``new`` written
    anew by tomlkit (the numbers in place: every comment and the layout kept, a point written over several
    lines too); JSON is written whole."""
    if text.lstrip().startswith("{"):
        return json.dumps(new, indent=2) + "\n"
    import tomlkit
    doc = tomlkit.parse(text)
    for section in ("ground", "pose"):
        for name, xy in (new.get(section) or {}).items():
            if (old.get(section) or {}).get(name) == xy:
                continue
            entry = (doc.get(section) or {}).get(name)
            if not (isinstance(entry, list) and len(entry) == 2):
                raise ParameterError(f"cannot find {section}.{name} written as [x, y]: edit the file by hand")
            for axis, v in enumerate(xy):
                if entry[axis] != v:
                    entry[axis] = round(float(v), 9)
    return doc.as_string()


def assur_groups(mech: Mechanism) -> list[dict]:
    """The Assur groups ``mech`` was decomposed into, in solving order: the points each places, its links and
    its class (``RRR``, ``RRP``, a triad, ...); inputs and ground entries are left out."""
    out = []
    for e, r in zip(mech.definition.order, mech.geometry.elements):
        cls = kinds.get(e.kind).group_label(r)
        if cls:
            out.append({"places": list(e.places), "links": list(e.links()), "class": cls})
    return out


def cannot_turn_fully(mech: Mechanism) -> bool:
    """True where a quick look already shows that ``mech``'s first input (a single crank, not rocking) cannot
    make a full turn: a stretch of the turn that does not assemble spans two neighbouring samples of the
    scan, so it is wider than a scan step (2 pi / 1440), far wider than the gaps at a fold that
    :func:`sim.service.check_turns_fully` closes (1e-7 rad). False where it cannot tell: that check then
    decides, as it does for groups solved numerically. The scan is the one the change points were found with
    where the mechanism has one (no solve), else one solve of 3600 samples."""
    first = mech.inputs[0]
    if len(mech.inputs) != 1 or mech.rock is not None or not first.angular:
        return False
    if any(kinds.get(e["kind"]).continuous for e in mech.geometry.elements):
        return False
    scan = mech.turn_scan
    if scan is not None:
        bad = ~np.asarray(scan[1].valid).ravel()
    else:
        q0 = first.motion.q0
        bad = ~np.asarray(mech.solve(np.linspace(q0, q0 + 2 * math.pi, 3601), outputs=()).valid).ravel()
    return bool(np.any(bad[1:] & bad[:-1]))


def plain_turn_applies(mech: Mechanism) -> bool:
    """Whether :func:`turns_on_its_geometry` speaks for ``mech``'s kind of drive: one crank turning fully (not
    rocking) and no group solved numerically (those trace their solution along the turn)."""
    first = mech.inputs[0]
    return (len(mech.inputs) == 1 and mech.rock is None and first.angular
            and not any(kinds.get(e["kind"]).continuous for e in mech.geometry.elements))


def turns_on_its_geometry(mech: Mechanism, samples: int = 3600) -> bool:
    """Whether every one of ``samples`` + 1 crank angles over a turn assembles on the file's geometry as it is
    (each group on its declared branch, no change points scheduled: the cheap look, ~1 ms, that a drag's
    search for its limit goes by before the full check, :func:`sim.service.check_turns_fully`, confirms the
    limit it found)."""
    q0 = mech.inputs[0].motion.q0
    q = np.linspace(q0, q0 + 2 * math.pi, samples + 1)[None, :]
    zero = np.zeros_like(q)
    with np.errstate(invalid="ignore", divide="ignore"):
        _, failed, _ = block(mech.geometry, q, zero, zero, set(), None, False)
    return bool(np.all(np.asarray(failed) < 0))
