"""One mechanism model behind every command: :class:`Mechanism`.

A mechanism is a :class:`~analytic.format.linkfile.Definition` (from a ``linkage/1`` file, built-in or the
user's) together with its parameter values. It knows its inputs and their motion law, its named points,
links and prismatic pairs, and solves all of them at once::

    mech = analytic.load("fourbar", l1=0.12)
    sol = mech.solve(q, qd, qdd)       # q: (N,) for one input or (N, n_inputs)
    sol["phi3"], sol["xE"], sol.valid

Outputs are named as in SPEC.md: ``xP yP vxP vyP axP ayP`` for every point, ``phiL omegaL alphaL`` for
every link, ``sJ dsJ ddsJ`` for every prismatic pair (named after its block link) and ``muP`` for the
transmission angle of the RRR group at point P. A built-in mechanism adds ``aliases`` that give its
outputs SPEC's names (``s``, ``theta3``, ``mu`` ...) and reports only those.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace

import numpy as np

from analytic.solver import kinematics
from analytic.format import linkfile
from analytic._common import AssemblyError, BLOCK, ParameterError, fmt_deg, keep_freed_memory


# --------------------------------------------------------------------------------------- motion law
@dataclass(frozen=True)
class Motion:
    """The one motion law of a driven input: q(t) = q0 + rate t + accel t^2 / 2 (SPEC), or, with
    ``rock = (lo, hi)``, a rocking drive q(t) = mid - amp cos(|rate| t) that starts at rest at ``lo``."""

    q0: float
    rate: float
    accel: float = 0.0
    rock: tuple[float, float] | None = None

    def at(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(q, dq/dt, d2q/dt2) at times ``t`` [s], broadcast to the shape of ``t``."""
        t = np.asarray(t, dtype=float)
        if self.rock is not None:
            lo, hi = self.rock
            w, amp = abs(self.rate), 0.5 * (hi - lo)
            return (0.5 * (lo + hi) - amp * np.cos(w * t), amp * w * np.sin(w * t), amp * w * w * np.cos(w * t))
        return (self.q0 + self.rate * t + 0.5 * self.accel * t * t, self.rate + self.accel * t,
                np.full_like(t, self.accel))

    def duration(self, cycles: float, turn: float) -> float:
        """Time [s] for ``cycles`` turns of size ``turn`` (2 pi for a crank): the smallest t > 0 with
        |q(t) - q0| = cycles * turn; for a rocking drive, ``cycles`` periods 2 pi / |rate|."""
        if not (math.isfinite(cycles) and cycles > 0):
            raise ParameterError(f"revolutions={cycles!r} must be a finite number > 0")
        if self.rock is not None:
            if self.rate == 0:
                raise ParameterError("a rocking drive needs a non-zero speed")
            return cycles * 2 * math.pi / abs(self.rate)
        omega, alpha = self.rate, self.accel
        if omega == 0.0 and alpha == 0.0:
            raise ParameterError("the input does not move: give it a non-zero speed")
        angle = turn * cycles
        if alpha == 0.0:
            return angle / abs(omega)
        sign = math.copysign(1.0, omega if omega != 0.0 else alpha)
        a, b, c = 0.5 * alpha, omega, -sign * angle
        disc = b * b - 4.0 * a * c
        roots = [] if disc < 0 else [(-b + r) / (2 * a) for r in (math.sqrt(disc), -math.sqrt(disc))]
        roots = [t for t in roots if t > 0]
        if not roots:
            raise ParameterError(f"the input's acceleration {alpha:g} stops it before it completes {cycles:g} "
                                 f"turns; reduce the acceleration or the revolutions")
        return min(roots)


@dataclass(frozen=True)
class Input:
    """A driven input: a crank (angle of its link, rad) or a slider (distance along its guide, m).

    ``q``, ``qd``, ``qdd`` are its column names (``phi1 omega1 alpha1`` for crank link 1, ``sJ dsJ ddsJ``
    for a slider with block link J); ``joint`` is the pivot or guide point it turns or slides about;
    ``parameters`` names the parameters that set its motion law, if any."""

    kind: str
    link: str
    point: str
    joint: str
    motion: Motion
    parameters: tuple[str | None, str | None, str | None] = (None, None, None)

    @property
    def q(self) -> str:
        return f"phi{self.link}" if self.kind == "crank" else f"s{self.link}"

    @property
    def qd(self) -> str:
        return f"omega{self.link}" if self.kind == "crank" else f"ds{self.link}"

    @property
    def qdd(self) -> str:
        return f"alpha{self.link}" if self.kind == "crank" else f"dds{self.link}"

    @property
    def unit(self) -> str:
        return "rad" if self.kind == "crank" else "m"

    @property
    def turn(self) -> float:
        """One 'revolution' of this input: 2 pi for a crank; for a slider, its travel in one second."""
        return 2 * math.pi if self.kind == "crank" else abs(self.motion.rate) or 1.0


@dataclass(frozen=True)
class Joint:
    """A lower pair between links ``a`` and ``b`` (``ground`` for the frame) at ``point``: a revolute
    there, or a prismatic pair whose block link is ``slide`` (direction: the block's angle). ``input`` is
    the Input that drives it, if any."""

    kind: str
    name: str
    a: str
    b: str
    point: str
    input: Input | None
    slide: str | None


# ------------------------------------------------------------------------------------------ solution
class Solution(Mapping):
    """Outputs of one solve: a read-only mapping from output name to array (shape of the inputs).

    ``valid`` marks the samples where every group assembled; ``failed`` names, per sample, the element
    (its point) that could not be assembled first (``""`` where all did)."""

    def __init__(self, arrays: dict[str, np.ndarray], failed: np.ndarray, labels: tuple[str, ...],
                 aliases: dict[str, str] | None = None):
        self._arrays = arrays
        self._aliases = aliases or {}
        self.failed_index = failed
        self.labels = labels

    def __getitem__(self, name: str) -> np.ndarray:
        return self._arrays[self._aliases.get(name, name)]

    def __iter__(self):
        yield from self._arrays
        yield from (a for a in self._aliases if a not in self._arrays)

    def __len__(self) -> int:
        return len(self._arrays) + len(set(self._aliases) - set(self._arrays))

    def __getattr__(self, name: str):            # sol.xE as well as sol["xE"]
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None

    @property
    def valid(self) -> np.ndarray:
        return self.failed_index < 0

    def first_failure(self) -> tuple[int, str] | None:
        """(sample index, element label) of the first sample that did not assemble, or None."""
        bad = np.flatnonzero(self.failed_index.ravel() >= 0)
        if bad.size == 0:
            return None
        k = int(bad[0])
        return k, self.labels[int(self.failed_index.ravel()[k])]


# ----------------------------------------------------------------------------------------- mechanism
@dataclass(frozen=True)
class Builtin:
    """What a built-in mechanism adds to its file: SPEC output names and its dedicated closed form.

    ``aliases`` maps a SPEC name to the general output name; ``outputs`` are the SPEC outputs in CSV
    order; ``module`` is its closed-form module (``analytic.closed_forms.fourbar`` ...) and ``params`` its parameter
    dataclass, used as an independent check and for its own figures of merit."""

    outputs: tuple[str, ...]
    aliases: dict[str, str]
    module: object
    params: type
    figures: object
    """figures(params, solution) -> dict: the mechanism's own figures of merit."""
    summary: object
    """summary(figures) -> list of lines for the analysis summary."""


@dataclass(frozen=True)
class Mechanism:
    """A planar linkage with its parameter values. Build one with :func:`analytic.load`."""

    definition: linkfile.Definition
    values: dict[str, float]
    geometry: linkfile.Geometry
    builtin: Builtin | None = None
    description: str = ""
    rock: tuple[float, float] | None = field(default=None)
    overrides: dict = field(default_factory=dict)

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_definition(cls, definition: linkfile.Definition, overrides: dict | None = None,
                        builtin: Builtin | None = None) -> "Mechanism":
        values = linkfile.parameter_values(definition, overrides)
        for name, kind in definition.parameter_kind.items():
            if kind == "length" and values[name] <= 0 and _is_size(definition, name):
                where = "" if name in (overrides or {}) else f" (parameters.{name} in {definition.source})"
                raise ParameterError(f"{name}={values[name]:g} is not a valid length: it must be > 0 "
                                     f"[{definition.units}]{where}")
        geometry = linkfile.resolve(definition, values)
        mech = cls(definition, values, geometry, builtin, definition.description, None, dict(overrides or {}))
        if builtin is not None:
            mech.closed_form_parameters()            # the dedicated model's own checks
        return mech

    def with_values(self, **overrides) -> "Mechanism":
        """The same mechanism with some parameters changed (file units; angles in rad)."""
        merged = {**self.overrides, **overrides}
        mech = Mechanism.from_definition(self.definition, merged, self.builtin)
        return replace(mech, rock=self.rock)

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
    def parameters(self) -> dict[str, float]:
        """Parameter values in file units (angles in rad), in file order."""
        return dict(self.values)

    @property
    def inputs(self) -> tuple[Input, ...]:
        out = []
        for e_def, e in zip(self.definition.order, self.geometry.elements):
            if e["kind"] == "crank":
                motion = Motion(e["phi0"], e["omega"], e["alpha"])
                names = tuple(_param_name(e_def.fields[f]) for f in ("phi0", "omega", "alpha"))
                out.append(Input("crank", e["link"], e["point"], e["pivot"], motion, names))
            elif e["kind"] == "slider":
                motion = Motion(e["s0"], e["v"], e["a"])
                names = tuple(_param_name(e_def.fields[f]) for f in ("s0", "v", "a"))
                guide = e["guide"]
                joint = guide["points"][0] if "points" in guide else (
                    guide["through"] if isinstance(guide["through"], str) else e["point"])
                out.append(Input("slider", e["link"], e["point"], joint, motion, names))
        if self.rock is not None:
            out[0] = replace(out[0], motion=replace(out[0].motion, rock=self.rock, q0=self.rock[0]))
        return tuple(out)

    def rocking(self, lo: float, hi: float) -> "Mechanism":
        """The same mechanism with its first input rocking between ``lo`` and ``hi`` (rad or m)."""
        if not (math.isfinite(lo) and math.isfinite(hi) and hi > lo):
            raise ParameterError(f"input range {lo:g}:{hi:g}: the end must exceed the start")
        return replace(self, rock=(float(lo), float(hi)))

    @property
    def points(self) -> tuple[str, ...]:
        return tuple(self.geometry.ground) + tuple(e["point"] for e in self.geometry.elements)

    @property
    def ground_points(self) -> tuple[str, ...]:
        return tuple(self.geometry.ground)

    @property
    def links(self) -> tuple[str, ...]:
        out = []
        for e in self.geometry.elements:
            for ln in ((e["link"],) if "link" in e else e.get("links", ())):
                out.append(ln)
        return tuple(out)

    @property
    def slides(self) -> tuple[str, ...]:
        """The prismatic pairs, named after their block links."""
        out = []
        for e in self.geometry.elements:
            if e["kind"] == "slider":
                out.append(e["link"])
            elif e["kind"] in ("RRP", "RPR"):
                out.append(e["links"][1])
        return tuple(out)

    @property
    def link_origins(self) -> dict[str, str]:
        """Each link's frame origin: its first point (a block: the point it is pinned at). The frame's
        x-axis is the link's angle ``phiL``."""
        out = {}
        for e in self.geometry.elements:
            kind = e["kind"]
            if kind == "crank":
                out[e["link"]] = e["pivot"]
            elif kind == "slider":
                out[e["link"]] = e["point"]
            elif kind == "RRR":
                out[e["links"][0]], out[e["links"][1]] = e["from"]
            elif kind == "RRP":
                out[e["links"][0]], out[e["links"][1]] = e["from"], e["point"]
            elif kind == "RPR":
                out[e["links"][0]], out[e["links"][1]] = e["pivot"], e["through"]
        return out

    @property
    def joints(self) -> tuple[Joint, ...]:
        """Every lower pair: revolutes (one per extra link pinned at a point) and prismatic pairs, with
        the inputs' pairs marked driven. Links are named as in the file; the ground is ``ground``."""
        members = linkfile.link_members(self.definition)
        out: list[Joint] = []
        driven_points = {}
        for inp in self.inputs:
            driven_points[inp.link] = inp
        for e in self.geometry.elements:
            kind = e["kind"]
            if kind == "slider":
                inp = driven_points[e["link"]]
                out.append(Joint("prismatic", e["link"], linkfile.GROUND, e["link"], e["point"], inp, e["link"]))
            elif kind == "RRP":
                g = e["guide"]
                if "points" in g:
                    p, q = g["points"]
                    guide_link = next(ln for ln, pts in members.items() if p in pts and q in pts)
                else:
                    guide_link = linkfile.GROUND
                out.append(Joint("prismatic", e["links"][1], guide_link, e["links"][1], e["point"], None,
                                 e["links"][1]))
            elif kind == "RPR":
                out.append(Joint("prismatic", e["links"][1], e["links"][0], e["links"][1], e["through"], None,
                                 e["links"][1]))
        for point, links in linkfile.incidence(self.definition).items():
            for other in links[1:]:
                inp = next((i for i in self.inputs if i.kind == "crank" and i.joint == point and
                            {links[0], other} == {linkfile.GROUND, i.link}), None)
                name = point if len(links) == 2 else f"{point}_{other}"
                out.append(Joint("revolute", name, links[0], other, point, inp, None))
        return tuple(out)

    @property
    def slide_frames(self) -> dict[str, tuple[object, str, float]]:
        """Each prismatic pair's measurement: (guide origin: a point name or fixed (x, y) [m], the block's
        point, offset [m]); the direction is the block link's angle. s = (C - O).u, see kinematics."""
        out = {}
        for e in self.geometry.elements:
            kind = e["kind"]
            if kind in ("slider", "RRP"):
                g = e["guide"]
                origin = g["points"][0] if "points" in g else g["through"]
                block = e["link"] if kind == "slider" else e["links"][1]
                out[block] = (origin, e["point"], e.get("offset", 0.0))
            elif kind == "RPR":
                out[e["links"][1]] = (e["pivot"], e["through"], e["offset"])
        return out

    @property
    def output_point(self) -> str:
        """The point whose path is traced and on which an external load acts."""
        return self.definition.output

    @property
    def aliases(self) -> dict[str, str]:
        return dict(self.builtin.aliases) if self.builtin else {}

    @property
    def general_outputs(self) -> tuple[str, ...]:
        """Every output of the general solver, in a stable order (points, links, slides, mu)."""
        out = []
        for p in self.points:
            out += [f"x{p}", f"y{p}", f"vx{p}", f"vy{p}", f"ax{p}", f"ay{p}"]
        input_links = {i.link for i in self.inputs if i.kind == "crank"}
        for ln in self.links:
            if ln not in input_links:
                out += [f"phi{ln}", f"omega{ln}", f"alpha{ln}"]
        input_slides = {i.link for i in self.inputs if i.kind == "slider"}
        for j in self.slides:
            if j not in input_slides:
                out += [f"s{j}", f"ds{j}", f"dds{j}"]
        out += [f"mu{e['point']}" for e in self.geometry.elements if e["kind"] == "RRR"]
        return tuple(out)

    @property
    def outputs(self) -> tuple[str, ...]:
        """The outputs reported in CSV, JSON and comparisons: SPEC's for a built-in, else all."""
        return self.builtin.outputs if self.builtin else self.general_outputs

    @property
    def size(self) -> float:
        """The mechanism's size [m]: its longest link or the spread of its ground points, whichever is
        larger; sets scale-relative tolerances and drawing sizes."""
        lengths = [abs(v) for e in self.geometry.elements for k, v in e.items()
                   if k in ("length",) and isinstance(v, float)]
        lengths += [abs(x) for e in self.geometry.elements if e["kind"] == "RRR" for x in e["lengths"]]
        xy = np.array(list(self.geometry.ground.values()) or [(0.0, 0.0)])
        spread = float(np.max(np.ptp(xy, axis=0))) if len(xy) > 1 else 0.0
        return max(lengths + [spread, 1e-12])

    # ------------------------------------------------------------------ motion and solving
    def drive(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The inputs' motion at times ``t`` [s]: (q, qd, qdd), each of shape (N, n_inputs)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        cols = [i.motion.at(t) for i in self.inputs]
        return tuple(np.stack([c[k] for c in cols], axis=-1) for k in range(3))

    def duration(self, revolutions: float) -> float:
        """Time [s] for ``revolutions`` turns of the first input (rocking cycles, for a rocking drive)."""
        first = self.inputs[0]
        return first.motion.duration(revolutions, first.turn)

    def solve(self, q, qd=0.0, qdd=0.0, outputs=None) -> Solution:
        """Every point, link, prismatic pair and transmission angle at the given inputs.

        Parameters
        ----------
        q, qd, qdd : array_like
            Input positions [rad or m], rates and accelerations: shape (N,) with one input, or
            (N, n_inputs); broadcast together.
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
        from analytic.solver import jit as _jit                                  # numba, when installed (analytic/solver/jit.py)
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
        if _jit.enabled(n):
            arrays, failed = _jit.solve(self.geometry, *flat, want)
        else:
            if n > BLOCK:
                keep_freed_memory()
            arrays, failed = None, np.empty(n, dtype=np.int64)
            for start in range(0, max(n, 1), BLOCK):
                sl = slice(start, start + BLOCK)
                with np.errstate(invalid="ignore", divide="ignore"):
                    part, failed[sl] = self._block(flat[0][:, sl], flat[1][:, sl], flat[2][:, sl], want)
                if arrays is None:                          # the outputs are the rows of one array
                    arrays = dict(zip(part, np.empty((len(part), n))))
                for key, v in part.items():
                    arrays[key][sl] = v
        arrays = {key: v.reshape(shape) for key, v in arrays.items()}
        labels = tuple(e["label"] for e in self.geometry.elements)
        aliases = self.aliases if want is None else {a: t for a, t in self.aliases.items() if t in arrays}
        return Solution(arrays, failed.reshape(shape), labels, aliases)

    def _block(self, q, qd, qdd, want=None):
        """One block of samples: ({output name: array or scalar}, failed), the outputs in ``want`` (a set
        of names; None: all)."""
        mu = want is None or any(name.startswith("mu") for name in want)
        points, links, slides, mus, failed = kinematics.evaluate(self.geometry, q, qd, qdd, mu=mu)
        out: dict[str, np.ndarray] = {}
        for p, v in points.items():
            for prefix, arr in zip(("x", "y", "vx", "vy", "ax", "ay"), v):
                if want is None or prefix + p in want:
                    out[prefix + p] = arr
        for ln, (c, s, w, a) in links.items():
            for prefix, arr in (("phi", None), ("omega", w), ("alpha", a), ("cos", c), ("sin", s)):
                if want is None or prefix + ln in want:
                    out[prefix + ln] = np.arctan2(s, c) if arr is None else arr
        for j, v in slides.items():
            for prefix, arr in zip(("s", "ds", "dds"), v):
                if want is None or prefix + j in want:
                    out[prefix + j] = arr
        for p, m in mus.items():
            if want is None or "mu" + p in want:
                out["mu" + p] = m
        return out, failed

    def solve_at(self, t) -> tuple[tuple[np.ndarray, np.ndarray, np.ndarray], Solution]:
        """The inputs' motion at times ``t`` and the solution there."""
        q, qd, qdd = self.drive(t)
        return (q, qd, qdd), self.solve(q, qd, qdd)

    def check_assembles(self, q) -> None:
        """Raise AssemblyError naming the first input value (and element) where the mechanism cannot be
        assembled, and the range of the first input where it can."""
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
            from analytic.applications.figures import assembly_ranges, describe_ranges
            ranges = assembly_ranges(self)
            hint = (f"; {first.q} assembles in {describe_ranges(first, ranges)}" if ranges
                    else f"; it assembles at no value of {first.q}")
        raise AssemblyError(f"the {self.name} cannot be assembled at {at}: {label} cannot close{hint}")

    def figures(self, sol: Solution) -> dict:
        """Figures of merit over a sampled solution: the general ones, and a built-in's own."""
        from analytic.applications import figures
        out = figures.general(self, sol)
        if self.builtin is not None:
            out.update(self.builtin.figures(self.closed_form_parameters(), sol))
        return out

    def summary(self, figs: dict, display=None) -> list[str]:
        """The figures of merit (SI) as readable lines, in ``display`` units (analytic.quantities.Display;
        None: the file's length unit)."""
        from analytic.applications import figures
        from analytic.quantities import Display
        display = display or Display(self.units)
        if self.builtin is not None:
            return self.builtin.summary(figs, display)
        return figures.general_summary(self, figs, display)

    # ------------------------------------------------------------------ the dedicated closed form
    def closed_form_parameters(self):
        """A built-in's parameter dataclass (FourBar, SixBar, FiveBar) with this mechanism's values."""
        if self.builtin is None:
            return None
        names = {f for f in self.builtin.params.__dataclass_fields__}
        kw = {k: v for k, v in self.values.items() if k in names}
        if "branch" in kw:
            kw["branch"] = int(kw["branch"])
        return self.builtin.params(**kw)

    def closed_form(self, q, qd=0.0, qdd=0.0) -> dict[str, np.ndarray]:
        """The built-in's dedicated closed form at the same inputs, as {SPEC name: array}."""
        if self.builtin is None:
            raise ParameterError(f"{self.name} has no dedicated closed form (only the built-ins do)")
        mod = self.builtin.module
        p = self.closed_form_parameters()
        q, qd, qdd = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (q, qd, qdd)))
        if len(self.inputs) == 1:
            if q.ndim == 2 and q.shape[-1] == 1:
                q, qd, qdd = q[:, 0], qd[:, 0], qdd[:, 0]
            st = mod.solve(p, q, qd, qdd)
        else:
            st = mod.solve(p, q[..., 0], q[..., 1], qd[..., 0], qd[..., 1], qdd[..., 0], qdd[..., 1])
        return {n: np.asarray(getattr(st, n)) for n in self.builtin.outputs}


def _fmt_q(inp: Input, v: float) -> str:
    return fmt_deg(v) if inp.kind == "crank" else f"{v:.6g}m"


def _param_name(v) -> str | None:
    return v if isinstance(v, str) and linkfile.expr.NAME.match(v) else None


def _is_size(d: linkfile.Definition, name: str) -> bool:
    """A length parameter used directly as a link length (must be > 0), not as a coordinate."""
    for e in d.order:
        for fname in ("length", "lengths"):
            v = e.fields.get(fname)
            vals = v if isinstance(v, tuple) else (v,)
            if name in vals:
                return True
    return False
