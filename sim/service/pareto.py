"""Multi-objective path synthesis (SPEC, "Synthesis constraints and budgets": ``--objectives``): a Pareto set
of path generators trading the path error against the peak drive torque, the peak bearing (joint) load, the
RMS shaking force and the size, under the command's loads, found by pymoo's NSGA-II over the batch
evaluation of :mod:`analytic.synthesis.path` (errors, limits and sizes of a whole population at once) and
the closed-form joint forces of :func:`sim.service.forces_run` (the general solver and the mass model, at
``samples`` crank angles during the search).

Every design of the returned front is then checked: its ``linkage/1`` file read back, measured over the turn
by the general solver (:func:`analytic.synthesis.constraints.measure`, the limits), its forces recomputed at
361 samples, ``linkage compare`` (MuJoCo against the analytic motion) and the forces simulated in MuJoCo
against the analytic ones under the same loads (:func:`sim.service.simulated_forces`). Designs that fail a
check are dropped; the front is the non-dominated set of the checked numbers, best error first.

Objectives (each minimised): ``error`` the path error (the sum of squared target distances during the
search; reported as the RMS distance, file units), ``torque`` the peak drive torque [N m], ``bearing`` the
peak joint force over all joints [N], ``shaking`` the RMS of the shaking force's magnitude over the turn [N],
``size`` the larger side of the mechanism's bounding box over the turn (file units).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic import ParameterError
from analytic.cycle import SAMPLES
from analytic.synthesis import constraints as sc
from analytic.synthesis import path as sp
from analytic.synthesis.curves import FAMILIES

__all__ = ["OBJECTIVES", "parse_objectives", "ParetoOptions", "pareto", "non_dominated"]

OBJECTIVES = {"error": "error", "torque": "peak_torque", "bearing": "peak_bearing", "shaking": "rms_shaking",
              "size": "size"}
"""``--objectives`` names -> the front's fields."""
FORCES = ("torque", "bearing", "shaking")
BAD = 1e30
"""Objective value of a design whose forces cannot be computed (a singular pose): dominated by any other."""
CHECK_SAMPLES = 361
"""Samples of the turn at which the returned designs' forces are recomputed and simulated."""


def parse_objectives(text: str) -> tuple[str, ...]:
    """``error,torque,...`` (two or more distinct names of OBJECTIVES)."""
    names = tuple(n.strip() for n in str(text).split(",") if n.strip())
    for n in names:
        if n not in OBJECTIVES:
            raise ParameterError(f"--objectives {n}: use two or more of {', '.join(OBJECTIVES)}")
    if len(set(names)) != len(names) or len(names) < 2:
        raise ParameterError(f"--objectives {text!r}: give two or more distinct names of {', '.join(OBJECTIVES)}")
    return names


FRONT_TYPES = tuple(name for name, fam in FAMILIES.items() if fam.pareto_front)
"""The ``--type`` values a front is searched for (their forces and sizes are evaluated in batches here): the
families that say so (:attr:`analytic.synthesis.curves.Family.pareto_front`)."""


@dataclass(frozen=True)
class ParetoOptions:
    """``objectives``; ``family`` (a path family with one crank, one of FRONT_TYPES); ``seed``;
    NSGA-II ``popsize`` and ``generations`` (the evaluations: their product, plus the starting atlas), or
    ``evaluations`` (a bound on every design evaluated, the generations following from it);
    ``samples`` per turn for the search's forces; ``front`` designs returned at most (spread along the
    error); the loads: ``force`` (Fx, Fy) [N] on the traced point (``cutting``: only on its slow stroke),
    ``gravity`` (gx, gy) [m/s^2]; ``constraints`` (:class:`analytic.synthesis.path.Constraints`);
    ``max_error``: the RMS target distance a design of the front may have at most (file units; None: any),
    a constraint of the search like the limits."""

    objectives: tuple[str, ...] = ("error", "torque")
    family: str = FRONT_TYPES[0]
    seed: int = 0
    popsize: int = 40
    generations: int = 30
    samples: int = 73
    front: int = 6
    force: tuple[float, float] = (0.0, 0.0)
    cutting: bool = False
    gravity: tuple[float, float] | None = None
    constraints: sp.Constraints = sp.Constraints()
    max_error: float | None = None
    evaluations: int | None = None

    def check(self) -> "ParetoOptions":
        parse_objectives(",".join(self.objectives))
        if self.family not in FRONT_TYPES:
            raise ParameterError(f"--objectives: --type {self.family} is not searched for a front; use "
                                 f"{' or '.join(FRONT_TYPES)}")
        for name in ("popsize", "generations", "front"):
            if getattr(self, name) < 1:
                raise ParameterError(f"--{name} {getattr(self, name)} must be >= 1")
        if self.popsize < 4:
            raise ParameterError(f"--popsize {self.popsize}: NSGA-II needs at least 4")
        if self.max_error is not None and not (math.isfinite(self.max_error) and self.max_error > 0):
            raise ParameterError(f"--max-error {self.max_error!r} must be a length > 0 (file units)")
        if self.evaluations is not None and self.evaluations < 1:
            raise ParameterError(f"--evaluations {self.evaluations} must be >= 1")
        if not 12 <= self.samples <= 3601:
            raise ParameterError(f"--samples {self.samples} must be in 12..3601")
        return self


def non_dominated(F: np.ndarray) -> np.ndarray:
    """Indices of the rows of F (K, m) no other row dominates (<= in every objective, < in one)."""
    F = np.asarray(F, dtype=float)
    keep = []
    for i in range(len(F)):
        dom = np.all(F <= F[i], axis=1) & np.any(F < F[i], axis=1)
        if not dom.any():
            keep.append(i)
    return np.array(keep, dtype=int)


# ----------------------------------------------------------------------------------------- evaluation
def _split(X, family, timing: bool):
    """Design rows (K, size [+ offset]) and branches (K, 1) from NSGA-II's variables (the last: the branch
    selector, +1 above 0.5)."""
    nx = family.size + (1 if timing else 0)
    return X[:, :nx], np.where(X[:, nx] > 0.5, 1, -1)[:, None]


def forces_of(family, x, branch, unit: str, opts: ParetoOptions, samples: int):
    """(peak drive torque [N m], peak joint force [N], RMS shaking force [N], ForceRun) of one design under
    the options' loads, over one turn at ``samples`` instants; (BAD, BAD, BAD, None) where the forces cannot
    be computed (a singular pose, a loop that does not close)."""
    from analytic.registry import from_text
    from sim import service
    try:
        mech = from_text(family.text(x, tuple(int(b) for b in branch), unit, "candidate", "pareto candidate"),
                         "<pareto candidate>")
        run = service.forces_run(mech, samples, gravity=opts.gravity, force=opts.force,
                                 slow_stroke_only=opts.cutting)
    except (ParameterError, ValueError, FloatingPointError):
        return BAD, BAD, BAD, None
    p = service.force_peaks(run)
    torque = max(d["value"] for d in p["drives"].values())
    bearing = max(j["F"] for j in p["joints"].values())
    return torque, bearing, p["shaking"]["F_rms"], run


def evaluate(X, target: sp.Target, opts: ParetoOptions, unit: str) -> tuple[np.ndarray, np.ndarray]:
    """Objectives F (K, m) and the constraint violation G (K, 1) (<= 0 where every limit and the targets'
    order hold) of K designs; forces only where G <= 0."""
    family = FAMILIES[opts.family]
    timing = target.phi is not None
    x, br = _split(np.atleast_2d(X), family, timing)
    nx = family.size
    err, order = sp.batch_error(x, target, br, 192, family)
    v = sp.violation(x[:, :nx], opts.constraints, target, br, family) + order
    if opts.max_error is not None:
        v = v + np.maximum(np.sqrt(err / len(target.xy)) / opts.max_error - 1, 0)
    G = np.where(np.isfinite(v) & np.isfinite(err), v, 1e3)
    cols = {"error": np.where(np.isfinite(err), err, BAD)}
    if "size" in opts.objectives:
        e = family.extent(x[:, :nx], br, 256)
        s = np.maximum(e[:, 2] - e[:, 0], e[:, 3] - e[:, 1])
        cols["size"] = np.where(np.isfinite(s), s, BAD)
    if any(o in FORCES for o in opts.objectives):
        f = np.full((len(x), 3), BAD)
        for i in np.flatnonzero(G <= 0):
            f[i] = forces_of(family, x[i, :nx], br[i], unit, opts, opts.samples)[:3]
        cols.update(torque=f[:, 0], bearing=f[:, 1], shaking=f[:, 2])
    return np.column_stack([cols[o] for o in opts.objectives]), G[:, None]


# ------------------------------------------------------------------------------------------- search
def atlas(target: sp.Target, opts: ParetoOptions, rng: np.random.Generator, count: int,
          posed: list | None = None) -> np.ndarray:
    """NSGA-II's first population: random shapes meeting the shape limits, posed on the targets (as the
    single-objective restarts' atlas), the least error first, both branches in turn; rows of variables.
    ``posed``: a one-item list the count of shapes posed on the targets is added to."""
    family = FAMILIES[opts.family]
    timing = target.phi is not None
    dim = family.shape_dim + (1 if timing else 0)
    rows = []
    for k, b in enumerate(family.branches):
        want = count // len(family.branches) + (1 if k < count % len(family.branches) else 0)
        U = rng.random((20 * max(want, 10), dim))
        U = U[sp.shape_violation(family.shape(U[:, :family.shape_dim]), opts.constraints, b, family) == 0]
        if not len(U):
            continue
        if posed is not None:
            posed[0] += len(U)
        if timing:
            x, e, o = sp._pose_timed(U, target, b, family)
        else:
            x, e, o = sp._pose(family.shape(U), target, b, 128, family)
        v = sp.region_violation(x[:, :family.size], opts.constraints, target, family, b)
        key = np.where(v == 0, e / target.size ** 2 + sp.ORDER_WEIGHT * o, 1e6 + v)
        pick = x[np.argsort(key, kind="stable")[:want]]
        rows.append(np.column_stack([pick, np.full(len(pick), 0.75 if b[0] > 0 else 0.25)]))
    if not rows:
        raise ParameterError("no random shape meets the limits (--min-transmission, --grashof): relax them")
    return np.concatenate(rows)


POLISHED = 2
"""Starting designs per branch polished on the path error alone (the best of the atlas): they anchor the
front's low-error end, where random shapes rarely land (an exact design through the targets, if any)."""


ANCHOR_CAP = 100
"""With ``--evaluations``: the designs each anchoring polish may evaluate (residuals, Jacobians, finishes)."""


def anchor(start: np.ndarray, target: sp.Target, opts: ParetoOptions) -> tuple[np.ndarray, int]:
    """The starting population with its best POLISHED rows per branch polished (:func:`sp.polish`, the
    limits kept) and appended in place of the population's last rows; and the evaluations they took."""
    family = FAMILIES[opts.family]
    timing = target.phi is not None
    nx = family.size + (1 if timing else 0)
    out, spent = [], 0
    for sel in (0.75, 0.25):
        rows = start[np.isclose(start[:, -1], sel)][:POLISHED]
        for r in rows:
            d = sp.polish(r[:nx], (1 if sel > 0.5 else -1,), target, opts.constraints, family,
                          cap=None if opts.evaluations is None else ANCHOR_CAP)
            spent += d.stats["evaluations"]
            if d.violation == 0:
                out.append(np.concatenate([d.x, [d.phi_offset] if timing else [], [sel]]))
    if not out:
        return start, spent
    return np.concatenate([start[:len(start) - len(out)], np.array(out)]), spent


def bounds(target: sp.Target, opts: ParetoOptions, start: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Variable bounds: the starting population's span widened by half its width and by a tenth of the
    target size each way (angles by pi), lengths kept positive; the branch selector in [0, 1]."""
    family = FAMILIES[opts.family]
    lo, hi = start.min(axis=0), start.max(axis=0)
    w = hi - lo
    s = target.size
    lo, hi = lo - 0.5 * w - 0.1 * s, hi + 0.5 * w + 0.1 * s
    angles = list(family.angles) + ([family.size] if target.phi is not None else [])
    lo[angles], hi[angles] = start[:, angles].min(axis=0) - math.pi, start[:, angles].max(axis=0) + math.pi
    links = list(family.links)
    lo[links] = np.maximum(lo[links], 1e-3 * s)
    lo[-1], hi[-1] = 0.0, 1.0
    return lo, hi


def search(target: sp.Target, opts: ParetoOptions, unit: str, progress=None):
    """NSGA-II (pymoo) from :func:`atlas`: returns (X, F) of the final non-dominated feasible set, the
    count of designs evaluated on the targets (the atlas's posed shapes, the anchors' polishes, every member
    of every generation) and the generations run. ``opts.evaluations`` N: the anchors' polishes capped
    (ANCHOR_CAP each) and the generations those leave of N, so the count is at most N."""
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.core.problem import Problem
    from pymoo.optimize import minimize

    rng = np.random.default_rng(np.random.SeedSequence([opts.seed, 29]))
    posed = [0]
    start = atlas(target, opts, rng, opts.popsize, posed)
    start, spent = anchor(start, target, opts)
    lo, hi = bounds(target, opts, start)
    counter = {"n": spent + posed[0], "gen": 0}
    generations = opts.generations
    if opts.evaluations is not None:       # each generation evaluates popsize designs (the first: the start)
        generations = (opts.evaluations - counter["n"]) // opts.popsize
        if generations < 1:
            raise ParameterError(f"--evaluations {opts.evaluations}: the starting atlas and its anchors took "
                                 f"{counter['n']}, leaving less than one generation of {opts.popsize}; give at "
                                 f"least {counter['n'] + opts.popsize}")

    class Synthesis(Problem):
        def __init__(self):
            super().__init__(n_var=len(lo), n_obj=len(opts.objectives), n_ieq_constr=1, xl=lo, xu=hi)

        def _evaluate(self, X, out, *args, **kwargs):
            out["F"], out["G"] = evaluate(X, target, opts, unit)
            counter["n"] += len(X)
            counter["gen"] += 1
            if progress is not None:
                progress(min(counter["gen"], generations), generations)

    res = minimize(Synthesis(), NSGA2(pop_size=opts.popsize, sampling=start), ("n_gen", generations),
                   seed=int(rng.integers(2 ** 31)), verbose=False)
    pop = res.pop
    X, F, G = pop.get("X"), pop.get("F"), pop.get("G")
    ok = (G[:, 0] <= 0) & np.all(F < BAD, axis=1)
    X, F = X[ok], F[ok]
    nd = non_dominated(F) if len(F) else np.array([], dtype=int)
    return X[nd], F[nd], counter["n"], counter["gen"]


def spread(F: np.ndarray, k: int) -> list[int]:
    """Up to ``k`` indices of front F spread along its first objective (the ends kept), distinct rows."""
    order = np.argsort(F[:, 0], kind="stable")
    if len(order) <= k:
        return [int(i) for i in order]
    return [int(order[j]) for j in np.unique(np.round(np.linspace(0, len(order) - 1, k)).astype(int))]


def distinct(X: np.ndarray, idx: list[int], scale: float, tol: float = 1e-3) -> list[int]:
    """Those of ``idx`` whose design differs from every earlier one by more than ``tol`` of ``scale`` in some
    variable (copies of one design are one design)."""
    keep: list[int] = []
    for i in idx:
        if all(np.abs(X[i, :-1] - X[j, :-1]).max() > tol * scale or (X[i, -1] > 0.5) != (X[j, -1] > 0.5)
               for j in keep):
            keep.append(i)
    return keep


# -------------------------------------------------------------------------------------------- checks
def check(x, branch, target: sp.Target, opts: ParetoOptions, unit: str, limits: sc.Limits) -> dict:
    """One front design's checked numbers (module doc): its file text, the general solver's measures, the
    objectives at CHECK_SAMPLES, ``simulated`` {passed, compare_passed, forces_passed, peak_torque,
    peak_bearing, rms_shaking (MuJoCo's)}; ``problem`` '' or why it is dropped."""
    from analytic.registry import from_text
    from sim import service
    from sim.model import Loads
    family = FAMILIES[opts.family]
    nx = family.size
    timing = target.phi is not None
    d = sp.Design(x[:nx], tuple(int(b) for b in branch), float(x[nx]) if timing else 0.0, np.zeros(1),
                  np.zeros(1), 0.0, opts.seed, family=family)
    e, ph = sp.errors(x[:nx], d.branch, target, d.phi_offset, family)
    d = sp.Design(d.x, d.branch, d.phi_offset, e, ph, 0.0, opts.seed, family=family)
    from sim.service.design import design_text, error_record, sense_of
    text = design_text(d, unit, target, opts.seed)
    out = {"text": text, "design": d, "type": family.name, "problem": "", "error_record": error_record(e)}
    mech = from_text(text, "<pareto design>")
    phi0, sense = float(ph[0]), sense_of(d)
    lo, hi = sorted((phi0, phi0 + sense * 2 * math.pi))
    try:
        m = sc.measure(mech, lo, hi, SAMPLES + 1, family.fourbar_lengths(x))   # a cycle's dense grid of a turn
    except ParameterError as exc:
        return {**out, "problem": str(exc)}
    out["measure"] = sc.record(m)
    why = sc.broken(m, limits, unit)
    rms = float(np.sqrt(np.mean(e ** 2)))
    if not why and opts.max_error is not None and rms > opts.max_error * (1 + 1e-9):
        why = f"RMS error {rms:.4g} {unit} above --max-error {opts.max_error:g} {unit}"
    if why:
        return {**out, "problem": why}
    torque, bearing, shaking, run = forces_of(family, x[:nx], branch, unit, opts, CHECK_SAMPLES)
    if run is None:
        return {**out, "problem": "its forces cannot be computed (a singular pose)"}
    out.update(peak_torque=torque, peak_bearing=bearing, rms_shaking=shaking, size=m.size,
               error=float(np.sqrt(np.mean(e ** 2))))
    _, c = service.compare(mech, 1.0)
    loads = Loads(gravity=opts.gravity, force=opts.force, slow_stroke_only=opts.cutting)
    rec = service.simulated_forces(run, loads=loads)
    pk = rec["peaks"]
    sim = {"passed": bool(c.passed and rec["passed"]), "compare_passed": bool(c.passed),
           "forces_passed": bool(rec["passed"]),
           "peak_torque": max(v["value"] for v in pk["drives"].values()),
           "peak_bearing": max(v["F"] for v in pk["joints"].values()), "rms_shaking": pk["shaking"]["F_rms"]}
    out["simulated"] = sim
    if not sim["passed"]:
        out["problem"] = ("linkage compare fails" if not c.passed else
                          "MuJoCo's joint forces disagree with the analytic ones")
    return out


def pareto(target: sp.Target, opts: ParetoOptions, unit: str = "m", limits: sc.Limits | None = None,
           progress=None) -> dict:
    """The checked Pareto front (module doc): ``{"front": [record...], "rejected": [{"why", ...}],
    "evaluations": designs evaluated in the search, "objectives"}``; each record has ``type``, ``parameters``,
    the objective fields (OBJECTIVES' values; ``error`` the RMS target distance), the measures
    (``transmission_deg``, ``size``, ``box``, ``input_range``, ``grashof``), ``error_detail`` {sum_sq, max,
    rms}, ``simulated``, ``text`` and ``design``."""
    opts.check()
    limits = limits or sc.Limits(math.degrees(opts.constraints.mu_min), opts.constraints.max_size, (),
                                 opts.constraints.grashof)
    X, F, n, gens = search(target, opts, unit, progress)
    if not len(X):
        raise ParameterError("the search found no design meeting the limits: relax them or raise --generations")
    idx = distinct(X, spread(F, 4 * opts.front), target.size)
    family = FAMILIES[opts.family]
    timing = target.phi is not None
    checked, rejected = [], []
    for i in idx:
        x, br = _split(X[i:i + 1], family, timing)
        c = check(x[0], br[0], target, opts, unit, limits)
        if c["problem"]:
            rejected.append({"parameters": family.parameters(x[0, :family.size], br[0]), "why": c["problem"]})
            continue
        checked.append(c)
    if not checked:
        return {"front": [], "rejected": rejected, "evaluations": n, "generations": gens,
                "objectives": list(opts.objectives)}
    keys = [OBJECTIVES[o] for o in opts.objectives]
    Fc = np.array([[c[k] for k in keys] for c in checked])
    nd = sorted(non_dominated(Fc), key=lambda j: (Fc[j, 0], j))
    front = [checked[j] for j in nd]
    if len(front) > opts.front:
        front = [front[j] for j in np.unique(np.round(np.linspace(0, len(front) - 1, opts.front)).astype(int))]
    records = []
    for c in front:
        d = c["design"]
        records.append({"type": c["type"], "parameters": {**d.parameters(), "mu_min_deg": c["measure"]["transmission_deg"][0]},
                        "error": c["error"], "peak_torque": c["peak_torque"], "peak_bearing": c["peak_bearing"],
                        "rms_shaking": c["rms_shaking"], "size": c["size"], **{k: v for k, v in c["measure"].items()
                                                                                 if k != "size"},
                        "error_detail": c["error_record"], "simulated": c["simulated"], "file": None,
                        "text": c["text"], "design": d})
    return {"front": records, "rejected": rejected, "evaluations": n, "generations": gens,
            "objectives": list(opts.objectives)}
