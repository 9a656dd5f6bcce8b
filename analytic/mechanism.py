"""One mechanism model behind every command: :class:`Mechanism`, a value object.

A mechanism is a :class:`~analytic.format.linkfile.Definition` (from a ``linkage/1`` file, built-in or the
user's) together with its parameter values: its resolved geometry, its topology (built once with the
definition), its inputs and their motion law. It solves every point, link and prismatic pair at once::

    mech = analytic.load("fourbar", l1=0.12)
    sol = mech.solve(q, qd, qdd)       # q: (N,) for one input or (N, n_inputs)
    sol["phi3"], sol["xE"], sol.valid

Outputs are named as in SPEC.md: ``xP yP vxP vyP axP ayP`` for every point, ``phiL omegaL alphaL`` for
every link, ``sJ dsJ ddsJ`` for every prismatic pair (named after its block link) and the kinds' own (``muP``
for the transmission angle of the RRR group at point P); :attr:`Mechanism.table` describes each of them. A
built-in mechanism adds ``aliases`` that give its outputs SPEC's names (``s``, ``theta3``, ``mu`` ...) and
reports only those.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace

import numpy as np

from analytic import kinds
from analytic._common import BLOCK, AssemblyError, ParameterError, fmt_deg, keep_freed_memory
from analytic.format import linkfile
from analytic.motion import Input, Motion, law_rate
from analytic.solution import Solution
from analytic.solver import kinematics
from analytic.topology import Joint

__all__ = ["Mechanism", "Input", "Motion", "Solution", "Joint"]

POINT_COMPONENTS = ("x", "y", "vx", "vy", "ax", "ay")
LINK_COMPONENTS = ("phi", "omega", "alpha")
SLIDE_COMPONENTS = ("s", "ds", "dds")


@dataclass(frozen=True)
class Mechanism:
    """A planar linkage with its parameter values. Build one with :func:`analytic.load`."""

    definition: linkfile.Definition
    values: dict[str, float]
    geometry: linkfile.Geometry
    builtin: object | None = None
    """A built-in's :class:`analytic.closed_forms.Builtin` (SPEC names, its dedicated closed form), or None."""
    description: str = ""
    rock: tuple[float, float] | None = field(default=None)
    overrides: dict = field(default_factory=dict)

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_definition(cls, definition: linkfile.Definition, overrides: dict | None = None,
                        builtin=None) -> "Mechanism":
        values = linkfile.parameter_values(definition, overrides)
        for name, kind in definition.parameter_kind.items():
            if kind == "length" and values[name] <= 0 and linkfile.is_size(definition, name):
                where = "" if name in (overrides or {}) else f" (parameters.{name} in {definition.source})"
                raise ParameterError(f"{name}={values[name]:g} is not a valid length: it must be > 0 "
                                     f"[{definition.units}]{where}")
        geometry = linkfile.resolve(definition, values)
        problem = kinematics.start_problem(geometry)
        if problem:
            raise ParameterError(f"{definition.source}: {problem}")
        mech = cls(definition, values, geometry, builtin, definition.description, None, dict(overrides or {}))
        if builtin is not None:
            builtin.parameters(values)                   # the dedicated model's own checks
        return mech

    def with_values(self, **overrides) -> "Mechanism":
        """The same mechanism with some parameters changed (file units; angles in rad)."""
        merged = {**self.overrides, **overrides}
        mech = Mechanism.from_definition(self.definition, merged, self.builtin)
        return replace(mech, rock=self.rock)

    def rocking(self, lo: float, hi: float) -> "Mechanism":
        """The same mechanism with its first input rocking between ``lo`` and ``hi`` (rad or m)."""
        if not (math.isfinite(lo) and math.isfinite(hi) and hi > lo):
            raise ParameterError(f"input range {lo:g}:{hi:g}: the end must exceed the start")
        return self._same_schedule(replace(self, rock=(float(lo), float(hi))))

    def turning(self) -> "Mechanism":
        """The same mechanism with its first input turning (not rocking)."""
        return self._same_schedule(replace(self, rock=None))

    def _same_schedule(self, other: "Mechanism") -> "Mechanism":
        """``other`` (this mechanism rocking or not: the same geometry) with this one's change points, when
        found already (they do not depend on the rocking: analytic.solver.change_points scans the turn)."""
        if "_scheduled" in self.__dict__:
            other.__dict__["_scheduled"] = self.__dict__["_scheduled"]
        return other

    def starting_at(self, q0: float) -> "Mechanism":
        """The same mechanism with its first input starting at ``q0`` (rad or m) instead of the file's start
        value: the pose the branches are declared at and the motion's origin move there."""
        elements = list(self.geometry.elements)
        i = next(k for k, e in enumerate(elements) if kinds.get(e["kind"]).section == "inputs")
        elements[i] = {**elements[i], kinds.get(elements[i]["kind"]).motion_fields[0]: float(q0)}
        return replace(self, geometry=replace(self.geometry, elements=tuple(elements)))

    # ------------------------------------------------------------------ description
    @property
    def name(self) -> str:
        return self.definition.name

    @property
    def units(self) -> str:
        return self.definition.units

    @property
    def scale(self) -> float:
        """Metres per file length unit."""
        return self.definition.scale

    @property
    def topology(self):
        """The structure (:class:`analytic.topology.Topology`), built once with the definition."""
        return self.definition.topology

    @property
    def parameters(self) -> dict[str, float]:
        """Parameter values in file units (angles in rad), in file order."""
        return dict(self.values)

    @functools.cached_property
    def inputs(self) -> tuple[Input, ...]:
        out = []
        for e_def, e in zip(self.definition.order, self.geometry.elements):
            kind = kinds.get(e["kind"])
            if kind.section != "inputs":
                continue
            q0, rate, accel = kind.motion_fields
            law = e.get("law")
            motion = (Motion(e[q0], e[rate], e[accel]) if law is None
                      else Motion(e[q0], law_rate(law), 0.0, law=law))
            names = tuple(_param_name(e_def.fields[f]) for f in kind.motion_fields)
            out.append(Input(kind.name, kind.input_key(e), e["point"], kind.input_joint(e), motion, names))
        if self.rock is not None:                  # a slider rocks at |v| / size rad/s: its rate over the size
            rate = out[0].motion.rate / out[0].spec.rate_scale(self.size)
            out[0] = replace(out[0], motion=replace(out[0].motion, rock=self.rock, q0=self.rock[0], rate=rate,
                                                                 law=None))
        return tuple(out)

    @property
    def points(self) -> tuple[str, ...]:
        return self.topology.points

    @property
    def ground_points(self) -> tuple[str, ...]:
        return self.topology.ground

    @property
    def links(self) -> tuple[str, ...]:
        return tuple(self.topology.links)

    @property
    def slides(self) -> tuple[str, ...]:
        """The prismatic pairs, named after their block links."""
        return self.topology.slides

    @property
    def link_origins(self) -> dict[str, str]:
        """Each link's frame origin: its first point (a block: the point it is pinned at). The frame's
        x-axis is the link's angle ``phiL``."""
        return self.topology.origins

    @property
    def joints(self) -> tuple[Joint, ...]:
        """Every lower pair: revolutes (one per extra link pinned at a point) and prismatic pairs, with
        the inputs' pairs marked driven (``Joint.input``: the input's index). Links are named as in the
        file; the ground is ``ground``."""
        return self.topology.joints

    @property
    def slide_frames(self) -> dict[str, tuple[object, str, float]]:
        """How each prismatic pair is measured: {block: (origin, point, offset)} (see
        :meth:`analytic.kinds.base.Kind.slide_frames`)."""
        out = {}
        for e in self.geometry.elements:
            out.update(kinds.get(e["kind"]).slide_frames(e))
        return out

    @property
    def output_point(self) -> str:
        """The point whose path is traced and on which an external load acts."""
        return self.definition.output

    @property
    def aliases(self) -> dict[str, str]:
        return dict(self.builtin.aliases) if self.builtin else {}

    @functools.cached_property
    def general_outputs(self) -> tuple[str, ...]:
        """Every output of the general solver, in a stable order (points, links, slides, the kinds' own)."""
        out = [c + p for p in self.points for c in POINT_COMPONENTS]
        own = {n for i in self.inputs for n in (i.q, i.qd, i.qdd)}      # an input's columns are its own
        out += [c + ln for ln in self.links for c in LINK_COMPONENTS if c + ln not in own]
        out += [c + j for j in self.slides for c in SLIDE_COMPONENTS
                if c + j not in own and j not in self.driven_slides]
        out += self.extra_outputs
        return tuple(out)

    @functools.cached_property
    def driven_slides(self) -> frozenset[str]:
        """The prismatic pairs an input drives (an actuator's rod in its barrel, a driven P joint, a slider's
        block): their length and rates are the input's own columns (SPEC "Drives": ``s_lift``, ``ds_lift``,
        ``dds_lift``), reported once under that name, not again under the block's (``slift_rod``)."""
        return frozenset(j.slide for j in self.joints if j.kind == "prismatic" and j.input is not None)

    @functools.cached_property
    def extra_outputs(self) -> tuple[str, ...]:
        """The names of the kinds' own outputs (transmission angles ...)."""
        return tuple(x.name for e in self.geometry.elements for x in kinds.get(e["kind"]).extra_outputs(e))

    @functools.cached_property
    def transmission_angles(self) -> dict[str, str]:
        """{point: output name} of every transmission angle the kinds compute."""
        return {x.transmission: x.name for e in self.geometry.elements
                for x in kinds.get(e["kind"]).extra_outputs(e) if x.transmission}

    @property
    def outputs(self) -> tuple[str, ...]:
        """The outputs reported in CSV, JSON and comparisons: SPEC's for a built-in, else all."""
        return self.builtin.outputs if self.builtin else self.general_outputs

    @functools.cached_property
    def table(self):
        """Every output, input column and drive force by name: {name: :class:`analytic.quantities.Output`}."""
        from analytic.quantities import output_table
        return output_table(self)

    @functools.cached_property
    def size(self) -> float:
        """The mechanism's size [m]: its longest link (every kind's ``extent``) or the spread of its ground points,
        whichever is larger; sets scale-relative tolerances and drawing sizes."""
        return kinematics.size_of(self.geometry)

    # ------------------------------------------------------------------ motion and solving
    def drive(self, t, jerk: bool = False) -> tuple[np.ndarray, ...]:
        """The inputs' motion at times ``t`` [s]: (q, qd, qdd), each of shape (N, n_inputs); ``jerk``: and
        d3q/dt3 (a motion law's evaluated once for the four)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        cols = [i.motion.at_with_jerk(t) if jerk else i.motion.at(t) for i in self.inputs]
        return tuple(np.stack([c[k] for c in cols], axis=-1) for k in range(4 if jerk else 3))

    def duration(self, revolutions: float) -> float:
        """Time [s] for ``revolutions`` turns of the first input (rocking cycles, for a rocking drive)."""
        first = self.inputs[0]
        try:
            return first.motion.duration(revolutions, first.turn)
        except ParameterError:
            if first.motion.rate != 0.0 or first.motion.accel != 0.0 or first.motion.rock is not None:
                raise
        speed = first.parameters[1]                 # a still input: named by what sets its speed
        if speed is None:
            field = kinds.get(first.kind).motion_fields[1]
            raise ParameterError(f"{self.definition.source}: the input {first.q} of the {self.name} does not move (its "
                                 f"{field} is 0): give its [[inputs]] entry a non-zero {field}")
        example = f" (e.g. --set {speed}=360deg)" if first.angular else ""
        raise ParameterError(f"the input {first.q} of the {self.name} does not move ({speed} = 0): give {speed} a "
                             f"non-zero value{example}")

    def solve(self, q, qd=0.0, qdd=0.0, outputs=None) -> Solution:
        """Every point, link, prismatic pair and extra output (transmission angles) at the given inputs.

        Parameters
        ----------
        q, qd, qdd : array_like
            Input positions [rad or m], rates and accelerations: shape (N,) with one input, or
            (N, n_inputs); broadcast together. The samples are taken as a path (a motion in time) by the
            kinds that continue a solution from sample to sample (numerically solved groups).
        outputs : iterable of str, optional
            Only these outputs (general names or a built-in's aliases; others are ignored); None: all.
            Link angles ``phi`` and transmission angles ``mu`` cost an arctan2 each, so leaving them out
            saves much of the time; ``outputs=()`` still gives ``valid`` and ``first_failure()``.

        Returns
        -------
        Solution
            Arrays of shape (N,); NaN where a group cannot be assembled (``Solution.failed``).
            The arrays are rows of one (n_outputs, N) array.
        """
        from analytic.solver import jit                        # numba, when installed
        k = len(self.inputs)
        arrays = [np.asarray(x, dtype=float) for x in (q, qd, qdd)]
        if k == 1:
            arrays = [a if (a.ndim >= 2 and a.shape[-1] == 1) else a[..., None] for a in arrays]
        q, qd, qdd = np.broadcast_arrays(*arrays)
        if q.shape[-1] != k:
            raise ParameterError(f"{self.name} has {k} inputs: give q of shape (N, {k})")
        shape = q.shape[:-1]
        flat = [a.reshape(-1, k).T for a in (q, qd, qdd)]
        n = flat[0].shape[1]
        want = None if outputs is None else {self.aliases.get(o, o) for o in outputs}
        extras = want is None or any(x in want for x in self.extra_outputs)
        geometry = self.solving_geometry
        if jit.enabled(n) and jit.supports(geometry):
            arrays, failed = jit.solve(geometry, *flat, want)
        else:
            if n > BLOCK:
                keep_freed_memory()
            arrays, failed, start = None, np.empty(n, dtype=np.int64), None
            for first in range(0, max(n, 1), BLOCK):
                sl = slice(first, first + BLOCK)
                with np.errstate(invalid="ignore", divide="ignore"):
                    part, failed[sl], start = block(geometry, flat[0][:, sl], flat[1][:, sl],
                                                    flat[2][:, sl], want, start, extras)
                if arrays is None:                          # the outputs are the rows of one array
                    arrays = dict(zip(part, np.empty((len(part), n))))
                for key, v in part.items():
                    arrays[key][sl] = v
        arrays = {key: v.reshape(shape) for key, v in arrays.items()}
        labels = tuple(e["label"] for e in self.geometry.elements)
        aliases = self.aliases if want is None else {a: t for a, t in self.aliases.items() if t in arrays}
        return Solution(arrays, failed.reshape(shape), labels, aliases)

    @functools.cached_property
    def checks(self):
        """What the kinematic checks find of this mechanism (its assembly ranges, its singular poses), from one
        scan of its first input's range, each found once when first asked (:class:`analytic.checks.Checks`)."""
        from analytic.checks import Checks
        return Checks(self)

    @functools.cached_property
    def _scheduled(self):
        from analytic.solver.change_points import schedule_and_scan
        return schedule_and_scan(self)

    @property
    def solving_geometry(self) -> linkfile.Geometry:
        """The geometry the solver uses: :attr:`geometry` with the change points its dyads pass on their
        declared branch (:mod:`analytic.solver.change_points`), found once per mechanism."""
        return self._scheduled[0]

    @property
    def turn_scan(self):
        """The scan of the first input's turn that finding the change points solved (q, the solution there
        at unit rate, on :attr:`solving_geometry`), or None where it solved none."""
        return self._scheduled[1]

    def solve_at(self, t) -> tuple[tuple[np.ndarray, np.ndarray, np.ndarray], Solution]:
        """The inputs' motion at times ``t`` and the solution there."""
        q, qd, qdd = self.drive(t)
        return (q, qd, qdd), self.solve(q, qd, qdd)

    def check_motion(self, q, t=None) -> None:
        """Raise ParameterError where an input's kind refuses the inputs' motion ``q`` ((N, n_inputs), at times
        ``t`` [s] when given): an actuator driven past its stroke, naming the input, the field, when and by how
        much."""
        q = np.asarray(q, dtype=float).reshape(-1, len(self.inputs))
        elements = [e for e in self.geometry.elements if kinds.get(e["kind"]).section == "inputs"]
        for e in sorted(elements, key=lambda x: x["input"]):
            inp = self.inputs[e["input"]]
            problem = kinds.get(e["kind"]).motion_problem(e, inp.q, t, q[:, e["input"]], units=self.units)
            if problem:
                raise ParameterError(f"{self.definition.source}: {e['label']}: {problem}")

    def check_assembles(self, q) -> None:
        """Raise AssemblyError naming the first input value (and element) where the mechanism cannot be
        assembled, and the range of the first input where it can (after :meth:`check_motion`)."""
        self.check_motion(q)
        sol = self.solve(q)
        failure = sol.first_failure()
        if failure is None:
            return
        k, label = failure
        qk = np.asarray(q, dtype=float).reshape(-1, len(self.inputs))[k]
        first = self.inputs[0]
        at = ", ".join(f"{i.q}={_fmt_q(i, v)}" for i, v in zip(self.inputs, qk))
        hint = ""
        if len(self.inputs) == 1:
            from analytic.checks import assembly_ranges, describe_ranges
            ranges = assembly_ranges(self)
            hint = (f"; {first.q} assembles in {describe_ranges(first, ranges)}" if ranges
                    else f"; it assembles at no value of {first.q}")
        raise AssemblyError(f"the {self.name} cannot be assembled at {at}: {label} cannot close{hint}")


def block(geometry, q, qd, qdd, want=None, start=None, extras=True):
    """One block of samples solved on numpy: ({output name: array or scalar}, failed, carry), the outputs
    in ``want`` (a set of names; None: all); ``extras``: compute the kinds' own outputs; ``start``: the
    previous block's carry (see :class:`analytic.kinds.base.State`)."""
    st, failed = kinematics.evaluate(geometry, q, qd, qdd, mu=extras, start=start)
    out: dict[str, np.ndarray] = {}
    for p, v in st.points.items():
        for prefix, arr in zip(POINT_COMPONENTS, v):
            if want is None or prefix + p in want:
                out[prefix + p] = arr
    for ln, (c, s, w, a) in st.links.items():
        for prefix, arr in (("phi", None), ("omega", w), ("alpha", a), ("cos", c), ("sin", s)):
            if want is None or prefix + ln in want:
                out[prefix + ln] = np.arctan2(s, c) if arr is None else arr
    for j, v in st.slides.items():
        for prefix, arr in zip(SLIDE_COMPONENTS, v):
            if want is None or prefix + j in want:
                out[prefix + j] = arr
    for name, arr in st.extras.items():
        if want is None or name in want:
            out[name] = arr
    for e in geometry.elements:                    # an input's own columns, where no link or slide gave them
        kind = kinds.get(e["kind"])
        if kind.section == "inputs":
            for prefix, arr in zip(kind.columns, (q, qd, qdd)):
                name = prefix + kind.input_key(e)
                if name not in out and (want is None or name in want):
                    out[name] = np.broadcast_to(arr, np.shape(q))[e["input"]]
    return out, failed, st.carry


def _fmt_q(inp: Input, v: float) -> str:
    return fmt_deg(v) if inp.angular else f"{v:.6g}m"


def _param_name(v) -> str | None:
    return v if isinstance(v, str) and linkfile.expr.NAME.match(v) else None
