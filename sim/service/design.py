"""Design use cases, for every front end (the ``linkage`` command now, the web app later): path, motion and
function synthesis, seed 001's two-position method and parameter sweeps. Plain functions on arrays and
:class:`analytic.Mechanism`; no argparse, no printing, no files written (the front ends write what these
return). Errors are :class:`analytic.ParameterError` with one-line messages.

Every synthesised design is checked before it is returned: its ``linkage/1`` text is read back by the
general solver and passed through ``linkage compare`` (MuJoCo against the analytic solution). Synthesis
restarts, those checks and sweep chunks run through :func:`sim.run.parallel.mapper` (``workers`` processes
or a Dask ``scheduler``); their items carry their own seeds, so the answer does not depend on the count.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from analytic import ParameterError
from analytic.applications import studies
from analytic.format import expr
from analytic.format.linkfile import UNITS as _LENGTH_UNITS
from analytic.synthesis import constraints as _sc
from analytic.synthesis import path as sp
from analytic.synthesis.curves import DEFAULT_TYPE, FAMILIES, TYPES
from sim.run.parallel import mapper

__all__ = ["read_table", "check_repeats", "read_target", "PathOptions", "synthesize_path", "check_path_design",
           "curve", "synthesize_motion", "synthesize_function", "structural_error", "two_position", "parse_vary", "sweep",
           "sweep_columns", "MAX_COMBOS", "STATS", "DEFAULT_TYPE", "TYPES", "UNITS", "GRASHOF", "limits", "unreachable",
           "two_position_task", "two_position_design", "two_position_feasible", "two_position_mechanism"]


# ------------------------------------------------------------------------------------------- tables
def read_table(path: str, columns: tuple[str, ...], angle_columns: tuple[str, ...], degrees: bool,
               minimum: int) -> tuple[np.ndarray, list[int]]:
    """Rows of the named ``columns`` of a CSV file, angles converted to rad; one-line ParameterError
    naming the file, line and column of anything wrong.

    Lines starting with ``#`` are comments. The first other line is the header naming the columns (any
    order, others ignored); a file whose first line is already numbers has no header, and then must have
    exactly the columns ``columns`` in that order (the literature's target files, benchmarks/data)."""
    p = Path(path)
    if not p.is_file():
        raise ParameterError(f"{path}: no such file")
    from sim.readers import csv_rows
    numbered = [(i, r) for i, r in csv_rows("", path) if any(c.strip() for c in r) and not r[0].lstrip().startswith("#")]
    if not numbered:
        raise ParameterError(f"{path}: empty; give a header row {','.join(columns)} and one row per target")
    head_line, head = numbered[0]
    if _numeric(head):
        if len(head) != len(columns):
            raise ParameterError(f"{path}: line {head_line}: no header and {len(head)} column(s); a file "
                                 f"without a header must have exactly the columns {','.join(columns)} (or add "
                                 f"the header row {','.join(columns)})")
        idx, body = list(range(len(columns))), numbered
    else:
        names = [h.strip().lower() for h in head]
        for c in columns:
            if c not in names:
                raise ParameterError(f"{path}: line {head_line}: missing column {c!r} (header: {','.join(names)}); "
                                     f"the header must name {','.join(columns)}")
        idx, body = [names.index(c) for c in columns], numbered[1:]
    if len(body) > MAX_TARGET_ROWS:
        raise ParameterError(f"{path}: {len(body):,} rows; a synthesis takes at most {MAX_TARGET_ROWS:,} (thin them "
                             f"out: every target is matched at every evaluation)")
    out = []
    for line, r in body:
        vals = []
        for c, j in zip(columns, idx):
            text = r[j].strip() if j < len(r) else ""
            try:
                v = float(text)
            except ValueError:
                raise ParameterError(f"{path}: line {line}, column {c}: {text!r} is not a number") from None
            if not math.isfinite(v):
                raise ParameterError(f"{path}: line {line}, column {c}: {text!r} is not a finite number")
            if abs(v) > MAX_TARGET:                # 1e300 made every other point 'the same point'
                raise ParameterError(f"{path}: line {line}, column {c}: {text[:40]!r} is out of range; give a "
                                     f"magnitude <= {MAX_TARGET:g}")
            vals.append(math.radians(v) if (degrees and c in angle_columns) else v)
        out.append((line, vals))
    if len(out) < minimum:
        raise ParameterError(f"{path}: {len(out)} row(s); this method needs at least {minimum}")
    return np.array([v for _, v in out]), [line for line, _ in out]


MAX_TARGET = 1e12
MAX_TARGET_ROWS = 10_000
"""The most rows of a target, pose or pair file: a path search matches every target at every evaluation."""
"""The largest magnitude of a target's value (a coordinate in any unit, an angle in degrees), as every number
of a mechanism file (analytic.format.linkfile.MAX_MAGNITUDE)."""


def _numeric(row) -> bool:
    try:
        [float(c) for c in row]
    except ValueError:
        return False
    return True


def check_repeats(path, data, lines, key, what) -> None:
    """Refuse two rows that give the same target (to 1e-9 of the data's spread)."""
    k = np.asarray(key(data), dtype=float)
    scale = max(float(np.ptp(k, axis=0).max()), 1e-12) if len(k) else 1.0
    tol = 1e-9 * scale
    order = np.argsort(k[:, 0], kind="stable")      # sorted on the first column: a pair within tol of each
    ks = k[order]                                   # other lies within tol there, so few offsets are looked at
    pairs = []                                      # (the double loop it replaces took 4 s on 1,000 targets)
    for d in range(1, len(ks)):
        near = ks[d:, 0] - ks[:-d, 0] <= tol
        if not near.any():
            break
        same = near & np.all(np.abs(ks[d:] - ks[:-d]) <= tol, axis=1)
        for a in np.flatnonzero(same):
            i, j = int(order[a + d]), int(order[a])
            pairs.append((max(i, j), min(i, j)))
    if pairs:
        i, j = min(pairs)                           # the first repeat in the file's order, as it reads
        raise ParameterError(f"{path}: lines {lines[j]} and {lines[i]} give the same {what}; remove one")


def read_target(path: str, timing: bool = False, closed: bool = False, ordered: bool = True) -> sp.Target:
    """The target CSV (columns x,y and, with timing, phi in degrees) as a :class:`Target`."""
    cols = ("x", "y", "phi") if timing else ("x", "y")
    data, lines = read_table(path, cols, ("phi",), True, 4)
    check_repeats(path, data, lines, lambda d: d[:, :2], "point")
    if float(np.ptp(data[:, :2], axis=0).max()) <= 0:
        raise ParameterError(f"{path}: all points coincide; give points spread over the path")
    return sp.Target(data[:, :2].copy(), data[:, 2].copy() if timing else None, closed, ordered)


def error_record(e) -> dict:
    """``{"sum_sq", "max", "rms"}`` of errors ``e``."""
    e = np.abs(np.asarray(e, dtype=float))
    return {"sum_sq": float(np.sum(e ** 2)), "max": float(np.max(e)), "rms": float(np.sqrt(np.mean(e ** 2)))}


# ---------------------------------------------------------------------------------- path synthesis
CHECK_RESERVE = (0.3, 0.5)
"""[s] Of a ``--budget``, the share kept for checking the returned designs (read back, solved, compared in
MuJoCo) and ending the process: this plus this per design on an idle machine (a four-bar's checks take
0.1-0.2 s here; the interpreter's exit 0.1-0.2 s), times :func:`slowdown`."""


class BudgetSpent(ParameterError):
    """A ``--budget`` too short for a first restart on this machine now: no design (the command exits 1)."""


def slowdown() -> float:
    """How much slower than idle this machine runs now: its 1-minute load average per core, at least 1 (on
    2 cores at load 8, a four-bar's checks took 1.8 s instead of 0.4 s, and the exit 0.7 s)."""
    import os
    try:
        return max(1.0, os.getloadavg()[0] / (os.cpu_count() or 1))
    except OSError:
        return 1.0

MAX_BUDGET = 7 * 24 * 3600.0
"""[s] The longest --budget: a week (inf or 1e308 is no budget at all)."""
OPTION_RANGES = {"seed": (0, 2 ** 32 - 1), "popsize": (5, 10_000), "restarts": (1, 10_000),
                 "generations": (1, 1_000_000), "designs": (1, 100), "workers": (1, 1024)}
"""What the search's integer options may be: numpy's seeds are 32-bit and non-negative, differential
evolution needs a population of at least 5, and past these sizes a run would never end."""


@dataclass(frozen=True)
class PathOptions:
    """What a path synthesis run may change (SPEC, "Synthesis"): ``types`` (``--type``), ``seed``,
    ``restarts`` (None: eight per family branch for the four-bar and slider-crank, one for the six-bars),
    differential-evolution ``generations`` (None: the family's default, ``sp.generations_of``) and
    ``popsize`` per restart, ``budget`` [s] (None: none; a hard wall-clock limit on the whole run, the
    checks included: the search stops early and the best so far is returned), ``evaluations`` (None: the
    default counts; N: the global search's evaluations, N / restarts per restart, its atlas and
    differential evolution, polishes: every design evaluated on the targets, at most N in all, each design's
    ``evaluations``; the hops' and final polishes' share also as ``polish_evaluations``),
    ``designs`` returned, ``min_transmission`` [deg], ``max_ratio``, ``region`` [target sizes], ``max_size``
    [length] (None: none), ``boxes`` (:class:`analytic.synthesis.constraints.Region` per named ground pivot),
    ``grashof``, ``workers``, ``scheduler``. Without ``budget`` the answer depends on the seed only."""

    types: tuple[str, ...] = (DEFAULT_TYPE,)
    seed: int = 0
    restarts: int | None = None
    generations: int | None = None
    popsize: int = 40
    budget: float | None = None
    designs: int = 1
    min_transmission: float = 30.0
    max_ratio: float = 20.0
    region: float = 3.0
    workers: int = 1
    scheduler: str | None = None
    evaluations: int | None = None
    max_size: float | None = None
    boxes: tuple = ()
    grashof: str = "any"

    def check(self) -> "PathOptions":
        for t in self.types:
            if t not in TYPES:
                raise ParameterError(f"--type {t}: use one of {', '.join(TYPES)}")
        for name in ("designs", "generations", "popsize", "workers"):
            if getattr(self, name) is not None and getattr(self, name) < 1:
                raise ParameterError(f"--{name} {getattr(self, name)} must be >= 1")
        if self.restarts is not None and self.restarts < 1:
            raise ParameterError(f"--restarts {self.restarts} must be >= 1")
        if not (0 <= self.min_transmission < 90):
            raise ParameterError(f"--min-transmission {self.min_transmission} must be in [0, 90) deg")
        if not (self.max_ratio > 1 and math.isfinite(self.max_ratio)):
            raise ParameterError(f"--max-ratio {self.max_ratio} must be a number > 1")
        if not (self.region > 0 and math.isfinite(self.region)):
            raise ParameterError(f"--region {self.region} must be a number > 0 (target sizes)")
        if self.budget is not None and not (0 < self.budget <= MAX_BUDGET):
            raise ParameterError(f"--budget {self.budget:g} must be a number of seconds in (0, {MAX_BUDGET:g}]")
        if self.evaluations is not None and self.evaluations < 1:
            raise ParameterError(f"--evaluations {self.evaluations} must be >= 1")
        if self.evaluations is not None and self.budget is not None:
            raise ParameterError("--evaluations and --budget both given: give one (a count is reproducible, "
                                 "seconds are not)")
        if self.grashof != "any" and not any(FAMILIES[f].fourbar_loop for t in self.types for f in TYPES[t]):
            raise ParameterError(f"--grashof {self.grashof} applies to a four-bar loop; a slider-crank has none "
                                 f"(its crank turns fully by --min-transmission): drop --grashof")
        self.limits.check_names(tuple(dict.fromkeys(n for t in self.types for f in TYPES[t]
                                                     for n in FAMILIES[f].pivot_names)), f"--type {'/'.join(self.types)}")
        for name, (least, most) in OPTION_RANGES.items():        # sizes that would never finish, or crash
            v = getattr(self, name)
            if v is not None and not least <= v <= most:
                raise ParameterError(f"--{name} {v} must be an integer in {least}..{most:,}")
        return self

    @property
    def limits(self):
        from analytic.synthesis import constraints as sc
        return sc.Limits(self.min_transmission, self.max_size, tuple(self.boxes), self.grashof).check()

    @property
    def generations_value(self) -> int | None:
        """The differential-evolution generations per restart: ``generations`` (with ``evaluations``: the
        restarts' caps set them, :func:`analytic.synthesis.path.synthesize`)."""
        return self.generations

    @property
    def constraints(self) -> sp.Constraints:
        return sp.Constraints(mu_min=math.radians(self.min_transmission), max_ratio=self.max_ratio,
                              region=self.region, max_size=self.max_size,
                              boxes=tuple((b.name, b.x0, b.x1, b.y0, b.y1) for b in self.boxes), grashof=self.grashof)

    @property
    def restart_count(self) -> int:
        if self.restarts is not None:
            return self.restarts
        n = len(sp.combos(self.types))
        return n if n >= 8 else sp.RESTARTS          # six-bars: one per chain and branches


def sense_of(d: sp.Design) -> float:
    """+1 when the crank turns counter-clockwise from one target to the next (the order), else -1."""
    if len(d.phis) > 1:
        steps = np.angle(np.exp(1j * np.diff(d.phis)))
        return 1.0 if steps.sum() >= 0 else -1.0
    return 1.0


def design_text(d: sp.Design, unit: str, target: sp.Target, seed: int) -> str:
    """The ``linkage/1`` file of a design: the crank starts at the first target's angle and turns the
    sense that meets the targets in order (timing: the sense of the targets' input angles)."""
    fam = d.family
    timing = ("timed" if target.phi is not None else "closed path" if target.closed
              else "open path" if target.ordered else "any order")
    desc = (f"{fam.label} path generator through {len(target.xy)} targets ({timing}), seed {seed}; "
            f"traced point {'Q' if fam.name in ('watt', 'stephenson') else 'E'}")
    return fam.text(d.x, d.branch, unit, f"path_{fam.name}", desc, float(d.phis[0]), sense_of(d) * 2 * math.pi)


def check_path_design(job: tuple) -> dict:
    """The checks of one synthesised design (a mapper item): ``job`` = (family name, x, branch, text,
    phi1_0 [rad], sense, size [length]).

    The design's file is read back and solved by the general solver over a full turn (the dense grid of a
    cycle, analytic.cycle.SAMPLES + 1 samples, measured from the same solve): it
    must assemble everywhere, its traced point must coincide with the family's closed form to 1e-9 of the
    targets' size (the same branches all the way round), and its transmission angles (the solver's RRR
    outputs; a slider-crank's from its closed form) give ``mu_min_deg``. Then ``linkage compare`` over a
    full turn: MuJoCo must follow it."""
    from analytic.registry import from_text
    name, x, branch, text, phi1_0, sense, size, *rest = job
    limits = rest[0] if rest else None
    fam = FAMILIES[name]
    mech = from_text(text, f"<synthesised {name}>")
    from analytic.cycle import SAMPLES
    q = phi1_0 + sense * np.linspace(0.0, 2 * math.pi, SAMPLES + 1)
    sol = mech.solve(q)
    out = {"compare_passed": False, "compare_mode": "full turn", "solver_deviation": float("nan"),
           "mu_min_deg": float("nan"), "problem": "", "measure": None, "simulated": None}
    bad = sol.first_failure()
    if bad is not None:
        out["problem"] = f"the general solver cannot assemble it over the whole turn ({bad})"
        return out
    p = mech.output_point
    E, _ = fam.points(np.asarray(x)[None], q, branch)
    dev = np.hypot(sol["x" + p] / mech.scale - E[0, :, 0], sol["y" + p] / mech.scale - E[0, :, 1]).max()
    out["solver_deviation"] = float(dev / size)
    mus = [sol[m] for m in mech.transmission_angles.values()]
    mu = min(float(np.min(v)) for v in mus) if mus else float(fam.mu_min(np.asarray(x)[None], branch)[0])
    if fam.closed_form_mu:
        mu = min(mu, float(fam.mu_min(np.asarray(x)[None], branch)[0]))
    out["mu_min_deg"] = math.degrees(mu)
    from analytic.synthesis import constraints as sc
    lo, hi = sorted((phi1_0, phi1_0 + sense * 2 * math.pi))
    x = np.asarray(x, dtype=float)
    m = sc.measure(mech, lo, hi, len(q), fam.fourbar_lengths(x), sol=sol)
    out["measure"] = sc.record(m)
    if limits is not None and sc.broken(m, limits, mech.units):
        out["problem"] = sc.broken(m, limits, mech.units)
        return out
    # two double-precision evaluations of the same geometry: rounding only (1e-9 of size is far above it)
    if not dev <= 1e-9 * size:
        out["problem"] = (f"the general solver's curve leaves the synthesised one by {dev / size:.2g} of the "
                          f"targets' size (a branch changes over the turn)")
        return out
    from sim.service.synth_checks import simulate_design
    sim = simulate_design(mech)                   # compare and the forces in MuJoCo (the links' inertia)
    out["compare_passed"], out["simulated"] = sim["compare_passed"], sim
    out["problem"] = sim["problem"] if sim["compare_passed"] else ""
    return out


def curve(record: dict, n: int = 1441) -> np.ndarray:
    """(n, 2) the traced point of a returned design over one turn [its length unit], for drawing."""
    d: sp.Design = record["design"]
    E, _ = d.family.points(d.x[None], np.linspace(0.0, 2 * math.pi, n), d.branch)
    return E[0]


GRASHOF_WORDS = {"double-crank": "a drag link: the ground the shortest link, both cranks turning fully",
                 "double-rocker": "the coupler the shortest link: neither crank nor rocker turns fully",
                 "rocker-crank": "the rocker the shortest link: the output turns fully, the input rocks",
                 "triple-rocker": "non-Grashof: no link turns fully",
                 "change-point": "s + l = p + q: it can fold into a line"}


def type_notes(grashof: str, wanted: str) -> list[str]:
    """A note when a returned four-bar's type is not the crank-rocker a path's full crank turn suggests and
    ``--grashof`` did not ask for it (``any``): say which type it is and how to ask for a crank-rocker."""
    if not grashof or grashof == "crank-rocker" or wanted != "any":
        return []
    return [f"a {grashof} four-bar ({GRASHOF_WORDS.get(grashof, grashof)}), not a crank-rocker: --grashof any "
            f"(the default) takes the type that fits best; give --grashof crank-rocker for one whose crank alone "
            f"turns fully"]


def synthesize_path(target: sp.Target, options: PathOptions = PathOptions(), unit: str = "m",
                    progress=None, started: float | None = None) -> list[dict]:
    """Path synthesis (SPEC, "Synthesis"): the best ``options.designs`` designs, best first, each checked
    (:func:`check_path_design`). A record: ``type`` (family), ``error`` {sum_sq, max, rms} and
    ``error_unit``, ``parameters`` (the family's, its branch(es), ``phi1_0`` [rad], ``omega1`` [rad/s],
    ``mu_min_deg``), ``compare_passed``, ``compare_mode``, ``failed`` ('' or the first broken constraint
    or check), ``solver_deviation``, ``stats``, ``file`` (None: the front end sets it when it writes),
    ``text`` (the ``linkage/1`` file) and ``design`` (the :class:`Design`, not serialisable)."""
    options.check()
    if target.phi is not None and target.closed:
        raise ParameterError("--closed applies to free timing: with --timing the input angles (column phi) "
                             "fix where the crank meets each target; drop one of the two")
    if not target.ordered and (target.phi is not None or target.closed):
        raise ParameterError("--any-order applies to an open path with free timing: with --timing the input "
                             "angles fix the order, and --closed asks for it; drop one of them")
    if len(target.xy) < 4:
        raise ParameterError(f"{len(target.xy)} target points; path synthesis needs at least 4")
    restarts = max(options.restart_count, options.designs)
    total = restarts + options.designs
    import time
    start = time.time()
    budget = end = None
    if options.budget is not None:       # the whole run ends by then, counted from ``started`` (the command's start)
        end = (start if started is None else started) + options.budget
        reserve = slowdown() * (CHECK_RESERVE[0] + CHECK_RESERVE[1] * options.designs)
        if end - time.time() <= reserve:     # said before the search's and the checks' imports take more
            raise BudgetSpent(f"--budget {options.budget:g} s: the start took {time.time() - end + options.budget:.1f} "
                              f"s and the checks and exit need about {reserve:.1f} s on this machine now (load "
                              f"{slowdown():.1f} per core): no restart could run; give more")
        import scipy.optimize  # noqa: F401 (what the search and the checks load, loaded before their shares are set)
        import sim.service.synth_checks  # noqa: F401

    def step(done, _n=None):
        if progress is not None:
            progress(done, total)
    with mapper(options.workers, options.scheduler) as m:
        if end is not None:              # the checks' share of what is left: the search stops before it
            left = end - time.time()
            budget = max(left - reserve, 1e-3)
        try:
            designs = sp.synthesize(target, options.constraints, seed=options.seed, restarts=restarts,
                                    generations=options.generations_value, popsize=options.popsize, budget=budget,
                                    mapper=m, progress=step, types=options.types,
                                    designs=options.designs, evaluations=options.evaluations)[:options.designs]
        except ParameterError as e:
            if end is None or "ran out before the first restart" not in str(e):
                raise
            raise BudgetSpent(f"--budget {options.budget:g} s: the start took {options.budget - left:.1f} s "
                                 f"and the checks and exit need about {reserve:.1f} s on this machine now (load "
                                 f"{slowdown():.1f} per core), leaving {budget:.2f} s: no restart could run; give "
                                 f"more") from None
        designs = [d for i, d in enumerate(designs)          # one design found twice is returned once
                   if not any(sp.same_design(d, e, target.size) for e in designs[:i])]
        texts = [design_text(d, unit, target, options.seed) for d in designs]
        jobs = [(d.family.name, d.x, d.branch, t, float(d.phis[0]), sense_of(d), target.size, options.limits)
                for d, t in zip(designs, texts)]
        checks = []
        todo = [j for j, d in zip(jobs, designs) if not d.failed]
        if end is None:
            for i, c in enumerate(m(check_path_design, todo)):
                checks.append(c)
                step(restarts + i + 1)
        else:                            # one at a time: a check the time left cannot hold is not started
            took = 0.0
            for i, j in enumerate(todo):
                t = time.time()
                if i and t + took > end:
                    checks.append({"compare_passed": False, "compare_mode": "not run: --budget ran out",
                                   "solver_deviation": float("nan"), "mu_min_deg": float("nan"), "measure": None,
                                   "simulated": None, "problem": f"not checked: --budget {options.budget:g} s "
                                                                 f"ran out before its checks"})
                    continue
                checks.append(next(iter(m(check_path_design, [j]))))
                took = max(took, time.time() - t)
                step(restarts + i + 1)
    it = iter(checks)
    found = []
    for d, text, job in zip(designs, texts, jobs):
        c = next(it) if not d.failed else {"compare_passed": False, "compare_mode": "not run: " + d.failed,
                                           "solver_deviation": float("nan"), "problem": "", "measure": None,
                                           "simulated": None,
                                           "mu_min_deg": math.degrees(float(d.family.mu_min(d.x[None], d.branch)[0]))}
        params = {**d.parameters(), "phi1_0": job[4], "omega1": job[5] * 2 * math.pi, "mu_min_deg": c["mu_min_deg"]}
        lo, hi = sorted((job[4], job[4] + job[5] * 2 * math.pi))
        meas = c["measure"] or {"transmission_deg": [c["mu_min_deg"], float("nan")], "size": float("nan"),
                                "box": [float("nan")] * 4, "input_range": [lo, hi], "grashof": ""}
        notes = type_notes(meas.get("grashof", ""), options.grashof)
        found.append({"file": None, "type": d.family.name, "error": error_record(d.err), "error_unit": unit,
                      "notes": notes,
                      "parameters": params, "compare_passed": c["compare_passed"], "compare_mode": c["compare_mode"],
                      "failed": d.failed or c["problem"], "solver_deviation": c["solver_deviation"], **meas,
                      "evaluations": int(d.stats.get("run_evaluations", 0)),
                      "polish_evaluations": int(d.stats.get("polish_evaluations", 0)), "simulated": c["simulated"],
                      "stats": d.stats, "text": text,
                      "design": d})
    elapsed = time.time() - start
    for f in found:
        f["stats"] = {**f["stats"], "seconds": elapsed}
    return found


# ------------------------------------------------------------------------------ exact synthesis
MIN_ROWS = {"motion": 3, "function": 3}
MOTION_POOL = 2000
"""Motion synthesis: candidate four-bars (pairs of dyads) ranked before the limits pick the returned ones."""
DISTINCT = 0.02
"""Two returned designs are distinct when a ground pivot or a link length differs by more than this share of
the task's size (closer ones are one design found twice: a neighbouring grid point of the same basin)."""


def working_range(link, inputs) -> tuple[float, float]:
    """The crank's travel from the first target to the last in its turning sense, (lo, hi) [rad]."""
    sense = math.copysign(1.0, link.omega1)
    inputs = np.asarray(inputs, dtype=float)
    travel = np.mod(sense * (inputs - inputs[0]), 2 * math.pi)
    ends = (float(inputs[0]), float(inputs[0] + sense * travel.max()))
    return min(ends), max(ends)


def check_fourbar(mech, lo: float, hi: float) -> tuple[bool, str, dict]:
    """``linkage compare`` and the forces in MuJoCo of an exact design over its working range (the file's
    ``input_range``): MuJoCo rocking the crank from ``lo`` to ``hi`` [rad] must follow the general solver
    (:func:`sim.service.synth_checks.simulate_design`). Returns (compare passed, what was compared, the simulated
    record: its ``passed`` both)."""
    from sim.service.synth_checks import simulate_design
    sim = simulate_design(mech, (lo, hi))
    return sim["compare_passed"], "rocking over the working range (the file's input_range)", sim


def _fourbar_lengths(link) -> tuple[float, float, float, float]:
    return (link.l1, link.l2, link.l3, math.dist(link.A, link.D))


def _travel_box(link, lo: float, hi: float, n: int = 91) -> float:
    """The larger side of the bounding box of A, B, C, D, E over [lo, hi] (closed form, for ranking; the
    returned designs are measured by the general solver)."""
    q = np.linspace(lo, hi, n)
    A, D = np.asarray(link.A, dtype=float), np.asarray(link.D, dtype=float)
    B = A + link.l1 * np.stack([np.cos(q), np.sin(q)], -1)
    d = D - B
    L2 = np.sum(d * d, axis=1)
    x = (link.l2 ** 2 - link.l3 ** 2 + L2) / (2 * L2)
    with np.errstate(invalid="ignore"):
        h = np.sqrt(link.l2 ** 2 / L2 - x * x)
    C = B + x[:, None] * d + link.branch * h[:, None] * np.stack([-d[:, 1], d[:, 0]], -1)
    u = (C - B) / link.l2
    E = B + link.ex * u + link.ey * np.stack([-u[:, 1], u[:, 0]], -1)
    P = np.concatenate([A[None], D[None], B, C, E])
    return float(np.nanmax(np.ptp(P, axis=0))) if np.all(np.isfinite(P)) else math.inf


def _distinct(link, chosen: list, scale: float) -> bool:
    """Whether ``link`` differs from every chosen linkage by more than DISTINCT of ``scale`` in a pivot or a
    link length (the same four-bar with its dyads swapped counts as the same)."""
    def key(k):
        return np.array([*k.A, *k.D, k.l1, k.l2, k.l3])

    def swapped(k):
        return np.array([*k.D, *k.A, k.l3, k.l2, k.l1])
    v = key(link)
    return all(np.abs(v - key(c)).max() > DISTINCT * scale and np.abs(v - swapped(c)).max() > DISTINCT * scale
               for c in chosen)


def _exact_record(link, text: str, unit: str, m, error: dict, error_unit: str, params: dict, passed: bool,
                  mode: str, evaluations: int, notes: list[str], **extra) -> dict:
    from analytic.synthesis import constraints as sc
    return {"file": None, "error": error, "error_unit": error_unit, "parameters": params,
            "compare_passed": passed, "compare_mode": mode, **sc.record(m), "evaluations": int(evaluations),
            "notes": notes, "defect": "", **extra, "text": text}


def read_poses(path: str, degrees: bool) -> np.ndarray:
    """Poses x,y,theta (3 or more, distinct) from a CSV."""
    data, lines = read_table(path, ("x", "y", "theta"), ("theta",), degrees, MIN_ROWS["motion"])
    check_repeats(path, data, lines, lambda d: np.column_stack([d[:, :2], np.mod(d[:, 2], 2 * math.pi)]), "pose")
    return data


def read_pairs(path: str, degrees: bool) -> np.ndarray:
    """(input, output) angle pairs (3 or more, distinct inputs) from a CSV."""
    data, lines = read_table(path, ("input", "output"), ("input", "output"), degrees, MIN_ROWS["function"])
    check_repeats(path, data, lines, lambda d: np.mod(d[:, :1], 2 * math.pi), "input angle")
    return data


def _region_centres(poses: np.ndarray, limits, per_side: int = 9) -> np.ndarray | None:
    """3 poses with a region for A or D: a grid of centre points over each region (their circle points follow
    exactly), so designs with pivots there are among the candidates whatever the circle-point grid holds."""
    boxes = [r for r in limits.regions if r.name in ("A", "D")]
    if len(poses) != 3 or not boxes:
        return None
    pts = []
    for r in boxes:
        X, Y = np.meshgrid(np.linspace(r.x0, r.x1, per_side), np.linspace(r.y0, r.y1, per_side))
        pts.append(np.column_stack([X.ravel(), Y.ravel()]))
    return np.concatenate(pts)


MAX_MOTION_COUNT = 20
"""The most designs ``synthesize motion`` returns: each is read back and compared in MuJoCo (0.4-0.6 s a
design here), so 20 keep a run near 15 s."""


def synthesize_motion(poses: np.ndarray, unit: str = "m", count: int = 3, circle_points=None,
                      limits=None, evaluations: int = MOTION_POOL) -> tuple[list[dict], list[dict]]:
    """Burmester motion generation (3-5 poses exact, more by least squares) under ``limits``
    (:class:`analytic.synthesis.constraints.Limits`): up to ``count`` distinct designs, best first (the
    least pose error, then the smallest), each one's file holding its working range (the crank's travel from
    the first pose to the last), measured there by the general solver (:func:`constraints.measure`) and
    passed through ``linkage compare`` over it. ``evaluations``: the candidate four-bars evaluated at most
    (pairs of dyads). Returns (designs, rejected): the candidates turned down, each ``{"parameters", "why"}``
    (at most ``count`` of them, the best first)."""
    from analytic.synthesis import constraints as sc
    from analytic.synthesis import fourbar as synth_fourbar
    from analytic.synthesis import motion as synthesis_motion
    limits = (limits or sc.Limits()).check()
    limits.check_names(("A", "D"), "a four-bar (A: the crank's pivot, D: the rocker's)")
    if not 1 <= count <= MAX_MOTION_COUNT:
        raise ParameterError(f"--count {count} must be in 1..{MAX_MOTION_COUNT}: every design returned is checked by "
                             f"a MuJoCo run (about 0.5 s each; --count 100 took 55 s)")
    if evaluations < 1:
        raise ParameterError(f"--evaluations {evaluations} must be >= 1")
    if circle_points is not None:
        circle_points = np.asarray(circle_points, dtype=float).reshape(2, 2)
        if len(poses) != 3:
            raise ParameterError(f"--circle-points applies to 3 poses (given {len(poses)})")
        if not np.all(np.isfinite(circle_points)):
            raise ParameterError("--circle-points: give finite numbers")
    designs, cand = synthesis_motion.synthesize(poses, circle_points=circle_points, count=int(evaluations),
                                                centres=None if circle_points is not None
                                                else _region_centres(poses, limits))
    method = ("Burmester, exact" if len(poses) <= 5 else "Burmester dyads by least squares")
    scale = float(max(np.ptp(poses[:, :2], axis=0).max(), 1e-12))
    mu_lim = math.radians(limits.min_transmission) - 1e-9

    boxes = {id(d): _travel_box(d.linkage, *working_range(d.linkage, d.inputs)) for d in designs}

    def rank(d):
        rms = float(np.sqrt(np.mean(d.errors ** 2)))
        return (bool(d.defect), round(rms / scale, 9), boxes[id(d)])

    def early(d) -> str:
        """What the closed forms already show broken (the general solver measures the rest): the sampled
        travel's box is inside the true one, so a sampled size over the limit is over it."""
        if d.defect:
            return d.defect
        if d.mu_min < mu_lim:
            return (f"transmission angle {math.degrees(d.mu_min):.1f} deg over the working range: below "
                    f"--min-transmission {limits.min_transmission:g} deg")
        if limits.max_size is not None and boxes[id(d)] > limits.max_size * (1 + sc.SLACK_REL):
            return (f"size at least {boxes[id(d)]:.4g} {unit} (its bounding box over the working range) exceeds "
                    f"--max-size {limits.max_size:g} {unit}")
        for name, p in (("A", d.linkage.A), ("D", d.linkage.D)):
            r = limits.region(name)
            if r is not None and not r.contains(*p, sc.SLACK_REL * scale):
                return f"ground pivot {name} at ({p[0]:.4g}, {p[1]:.4g}) lies outside --pivot-region {r.text()}"
        return ""
    designs = sorted(designs, key=rank)
    found, rejected, chosen = [], [], []
    for d in designs:
        if len(found) >= count:
            break
        lo, hi = working_range(d.linkage, d.inputs)
        why = early(d)
        m = None
        if not why:
            mech = synth_fourbar.mechanism(d.linkage, unit)
            try:
                m = sc.measure(mech, lo, hi, lengths=_fourbar_lengths(d.linkage))
                why = sc.broken(m, limits, unit)
            except ParameterError as e:
                why = str(e)
        if why:
            if len(rejected) < count:
                rejected.append({"parameters": d.linkage.parameters(), "why": why})
            continue
        if not _distinct(d.linkage, chosen, scale):
            continue
        text = synth_fourbar.text(d.linkage, unit, "motion_fourbar",
                                  f"four-bar through {len(poses)} coupler poses ({method}); output E = the pose "
                                  f"point; the crank rocks over input_range, its travel from the first pose to "
                                  f"the last", (lo, hi))
        mech = synth_fourbar.mechanism(d.linkage, unit)
        sol = mech.solve(d.inputs)                           # the general solver at the poses' input angles
        err = np.hypot(sol["xE"] / mech.scale - poses[:, 0], sol["yE"] / mech.scale - poses[:, 1])
        ang = synthesis_motion._wrap((sol["phi2"] - sol["phi2"][0]) - (poses[:, 2] - poses[0, 2]))
        passed, mode, sim = check_fourbar(synth_fourbar.mechanism(d.linkage, unit), lo, hi)
        params = {**d.linkage.parameters(), "mu_min_deg": m.transmission_deg[0],
                  "angle_error_max": float(np.max(np.abs(ang)))}
        notes = [f"the crank turns {'counter-clockwise' if d.linkage.omega1 > 0 else 'clockwise'} from "
                 f"{math.degrees(d.inputs[0]):.2f} deg (pose 1) to {math.degrees(d.inputs[-1]):.2f} deg (pose "
                 f"{len(poses)}); branch {d.linkage.branch:+d} (C {'left' if d.linkage.branch > 0 else 'right'} "
                 f"of B->D) at every pose"]
        found.append(_exact_record(d.linkage, text, unit, m, error_record(err), unit, params, passed, mode,
                                   len(designs), notes, inputs=[float(q) for q in d.inputs], simulated=sim))
        chosen.append(d.linkage)
    return found, rejected


START_ANGLES = ("given", "search")
"""``--start-angles``: the pairs' angles are from the line A -> D (given), or from any zero (search)."""
FUNCTION_EVALUATIONS = 2000
"""Function synthesis with free start angles: candidates evaluated at most by default (a 40 x 40 grid of
start angles, 9 deg apart, then 400 for the polish)."""


FUNCTION_MOST = 200_000
"""The most --evaluations a function search takes (about 1 ms each here: past this a run takes minutes)."""


def structural_error(mech, link_off_in: float, link_off_out: float, phi, psi, lo: float, hi: float,
                     sol=None, n: int | None = None) -> dict | None:
    """The structural error of a function generator over its working range [lo, hi] [rad, crank link
    angles]: ``mech`` solved there by the general solver (or its solution ``sol`` at ``n`` evenly spaced
    values, either way round), its output angle (``phi3`` - ``link_off_out``) minus the target function
    (:func:`analytic.synthesis.function.target_function` through the pairs ``phi``, ``psi`` in the user's
    frame, at crank angle - ``link_off_in``). ``{"max", "rms" [rad], "max_deg", "rms_deg", "at_input" [rad,
    the user's input angle of the max], "samples", "target"}``; None where the pairs are not in order."""
    from analytic.synthesis import constraints as sc
    from analytic.synthesis import function as synthesis_function
    target = synthesis_function.target_function(phi, psi)
    if target is None:
        return None
    n = n or sc.MEASURE_SAMPLES
    q = np.linspace(lo, hi, n)
    if sol is None:
        sol = mech.solve(q)
    e = np.abs(synthesis_function._wrap(np.asarray(sol["phi3"]) - link_off_out - target(q - link_off_in)))
    k = int(np.argmax(e))
    return {"max": float(e[k]), "rms": float(np.sqrt(np.mean(e ** 2))), "max_deg": math.degrees(float(e[k])),
            "rms_deg": math.degrees(float(np.sqrt(np.mean(e ** 2)))), "at_input": float(q[k] - link_off_in),
            "samples": int(n), "target": ("the parabola through the 3 pairs" if len(phi) == 3 else
                                          f"the cubic spline through the {len(phi)} pairs")}


def synthesize_function(pairs: np.ndarray, ground: float = 1.0, unit: str = "m", limits=None,
                        start_angles: str = "given", evaluations: int = FUNCTION_EVALUATIONS,
                        count: int = 1) -> tuple[list[dict], list[dict]]:
    """Freudenstein function generation (3 pairs exact, more by least squares) under ``limits``: its file
    holds its working range (the crank's travel from the first pair to the last), where it is measured by
    the general solver, its structural error taken (:func:`structural_error`: the output against the pairs'
    interpolant at every crank angle of the range, not only at the pairs) and passed through ``linkage
    compare``. ``start_angles`` "given": the pairs' angles are from the line A -> D and fix the one design
    (``evaluations`` and ``count`` unused); "search": they are from any zero and the start angles are
    searched (:func:`analytic.synthesis.function.search`, at most ``evaluations`` candidates, the polish's
    included), up to ``count`` distinct designs returned, best first. Returns (designs, rejected) as
    :func:`synthesize_motion`. Where Freudenstein's solution has a negative crank (or rocker) length, the
    crank (rocker) points the other way: its link angle is the given angle + 180 deg, said in ``notes``."""
    from analytic.synthesis import constraints as sc
    from analytic.synthesis import function as synthesis_function
    limits = (limits or sc.Limits()).check()
    limits.check_names(("A", "D"), "a function generator (A: the crank's pivot, D: the rocker's)")
    if not (math.isfinite(ground) and ground > 0):
        raise ParameterError(f"--ground {ground!r} must be a length > 0")
    if start_angles not in START_ANGLES:
        raise ParameterError(f"--start-angles {start_angles}: use one of {', '.join(START_ANGLES)}")
    if count < 1:
        raise ParameterError(f"--count {count} must be >= 1")
    if start_angles == "given":
        f = synthesis_function.synthesize(pairs[:, 0], pairs[:, 1], ground)
        return _function_designs([(f, 0.0, 0.0)], pairs, ground, unit, limits, 1,       # one solve and its polish
                                 {"evaluations": 1 + f.polish_evaluations, "grid": 0,
                                  "polish_evaluations": f.polish_evaluations})
    if not 1 <= evaluations <= FUNCTION_MOST:
        raise ParameterError(f"--evaluations {evaluations} must be an integer in 1..{FUNCTION_MOST:,}")
    for r in limits.regions:       # the search moves no pivot: A = (0, 0), D = (ground, 0)
        p = (0.0, 0.0) if r.name == "A" else (ground, 0.0)
        if not r.contains(*p):
            return [], [{"parameters": {}, "why": f"ground pivot {r.name} at ({p[0]:.4g}, {p[1]:.4g}) lies outside "
                                                  f"--pivot-region {r.text()} (a function generator's pivots are "
                                                  f"A = (0, 0), D = (--ground, 0))", "notes": []}]
    kept, turned, stats = synthesis_function.search(pairs[:, 0], pairs[:, 1], ground, limits, evaluations, count)
    found, rejected = _function_designs([(c.function, c.phi0, c.psi0) for c in kept], pairs, ground, unit, limits,
                                        count, stats)
    if not found and not rejected:
        if turned:
            c = turned[0]
            rejected = [{"parameters": c.function.linkage.parameters(), "why": f"the best of the {stats['grid']} "
                         f"start angles tried: {c.why}", "notes": []}]
        else:
            rejected = [{"parameters": {}, "why": f"none of the {stats['grid']} start angles tried gives a "
                         f"four-bar through the pairs", "notes": []}]
    return found, rejected


def _function_designs(functions, pairs, ground, unit, limits, count, stats) -> tuple[list[dict], list[dict]]:
    """The checked records of function generators ``functions`` [(Function, phi0, psi0)], best first: up to
    ``count`` distinct ones meeting ``limits`` by the general solver and passing ``linkage compare``."""
    from analytic.synthesis import constraints as sc
    from analytic.synthesis import fourbar as synth_fourbar
    from analytic.synthesis import function as synthesis_function
    found, rejected, chosen = [], [], []
    for f, phi0, psi0 in functions:
        if len(found) >= count:
            break
        if not _distinct(f.linkage, chosen, ground):
            continue
        phi, psi = pairs[:, 0] + phi0, pairs[:, 1] + psi0          # the pairs from the line A -> D
        inputs = phi + f.input_offset
        lo, hi = working_range(f.linkage, inputs)
        notes = []
        if phi0 or psi0:
            notes.append(f"start angles searched: input 0 at {math.degrees(phi0):.3f} deg and output 0 at "
                         f"{math.degrees(psi0):.3f} deg from the line A->D (the file's angles are the pairs' + these)")
        if f.input_offset:
            notes.append("input offset 180 deg: Freudenstein's crank length came out negative, so the crank AB "
                         "points opposite to the given input angle: the file's phi1 = input + 180 deg")
        if f.output_offset:
            notes.append("output offset 180 deg: the rocker length came out negative, so the rocker DC points "
                         "opposite to the given output angle: output = phi3 - 180 deg")
        notes.append(f"the crank turns {'counter-clockwise' if f.linkage.omega1 > 0 else 'clockwise'} from pair 1 "
                     f"to pair {len(pairs)}; branch {f.linkage.branch:+d} (C "
                     f"{'left' if f.linkage.branch > 0 else 'right'} of B->D)")
        params = {**f.linkage.parameters(), "K1": f.K[0], "K2": f.K[1], "K3": f.K[2],
                  "input_offset": f.input_offset, "output_offset": f.output_offset,
                  "start_angles": [float(phi0), float(psi0)]}
        why, m, structural = f.defect, None, None
        mech = synth_fourbar.mechanism(f.linkage, unit)
        if not why:
            try:
                sol = mech.solve(np.linspace(lo, hi, sc.MEASURE_SAMPLES))     # the general solver over the range
                m = sc.measure(mech, lo, hi, lengths=_fourbar_lengths(f.linkage), sol=sol)
                why = sc.broken(m, limits, unit)
                structural = structural_error(mech, phi0 + f.input_offset, psi0 + f.output_offset, pairs[:, 0],
                                              pairs[:, 1], lo, hi, sol=sol)
            except ParameterError as e:
                why = str(e)
        if why:
            if len(rejected) < count:
                rejected.append({"parameters": params, "why": why, "notes": notes})
            continue
        text = synth_fourbar.text(f.linkage, unit, "function_fourbar",
                                  f"Freudenstein function generator through {len(pairs)} (input, output) pairs; "
                                  f"input 0 at {math.degrees(phi0 + f.input_offset):g} deg, output 0 at "
                                  f"{math.degrees(psi0 + f.output_offset):g} deg from A->D; the crank rocks over "
                                  f"input_range, its travel from the first pair to the last", (lo, hi))
        sol = mech.solve(inputs)                                   # the general solver at the given inputs
        err = synthesis_function._wrap(sol["phi3"] - f.output_offset - psi)
        passed, mode, sim = check_fourbar(mech, lo, hi)
        found.append(_exact_record(f.linkage, text, unit, m, error_record(err), "rad", params, passed, mode,
                                   stats["evaluations"], notes, structural_error=structural,
                                   polish_evaluations=stats["polish_evaluations"], simulated=sim))
        chosen.append(f.linkage)
    return found, rejected


# --------------------------------------------------------------------------------- two-position
def check_scale(points: dict, unit: str) -> None:
    """Refuse points whose distances span over 1000x: a coordinate typed in another unit (metres given
    with --unit mm) makes a degenerate 'optimum' with links of a few thousandths of the others."""
    names = list(points)
    dist = {(a, b): math.dist(points[a], points[b]) for i, a in enumerate(names) for b in names[i + 1:]}
    (a0, b0), lo = min(dist.items(), key=lambda kv: kv[1])
    (a1, b1), hi = max(dist.items(), key=lambda kv: kv[1])
    if lo < 1e-3 * hi:
        raise ParameterError(f"{a0} and {b0} are {lo:.3g} {unit} apart but {a1} and {b1} {hi:.3g} {unit}: give every "
                             f"coordinate in {unit} (--unit), with the points distinct")


def two_position_row(task, dsg) -> dict:
    """A paper-style row: angles in degrees, lengths in the task's unit."""
    from analytic.synthesis import two_position as synthesis
    g = "-"
    if synthesis.feasibility(task, dsg) is None:
        g = synthesis.grashof_chain(task, dsg)
    return {"theta_deg": math.degrees(dsg.theta), "phi0_deg": math.degrees(dsg.phi0),
            "psi0_deg": math.degrees(dsg.psi0), "l1": dsg.l1, "l2": dsg.l2, "l3": dsg.l3, "l4": dsg.l4,
            "total": dsg.total, "grashof": g}


TWO_POSITION_GRID = 721
"""Coupler rotations tried over the range when the unconstrained optimum breaks a limit (0.25 deg apart over
the default 180 deg): the least total length among those that meet every limit is returned."""


def two_position_measure(task, dsg):
    """A two-position design's measures over its working range (the crank's travel from position 1 to 2) in
    the task's frame (:class:`analytic.synthesis.constraints.Measure`): the transmission angle and the Grashof
    type by the general solver, the bounding box of every point (A, B, C, D and E) and the pivots as the task
    places them."""
    from analytic.synthesis import constraints as sc
    from analytic.synthesis import two_position as synthesis
    mech = synthesis.mechanism(task, dsg)
    lo, hi = sorted((dsg.phi0, dsg.phi0 + task.phi12))
    sol = mech.solve(np.linspace(lo, hi, sc.MEASURE_SAMPLES))
    m = sc.measure(mech, lo, hi, sc.MEASURE_SAMPLES, (dsg.l1, dsg.l2, dsg.l3, dsg.l4), sol=sol)
    pts = np.concatenate([np.column_stack([sol["x" + p], sol["y" + p]]) for p in mech.points])
    world = np.array([task.world(p) for p in pts])
    box = (float(world[:, 0].min()), float(world[:, 1].min()), float(world[:, 0].max()), float(world[:, 1].max()))
    return replace(m, size=max(box[2] - box[0], box[3] - box[1]), box=box,
                   pivots={"A": tuple(map(float, task.A)), "D": tuple(map(float, task.D))})


def two_position(task, lo: float, hi: float, unit: str, limits=None) -> dict:
    """Seed 001: the rows at the paper's coupler rotations in [lo, hi] [rad], the optimum (least total
    length) and the rotations excluded with their reasons. ``search`` holds the optimiser's result.

    ``limits`` (:class:`analytic.synthesis.constraints.Limits`; None: none, the seed's own problem): the
    optimum must meet them over its working range (:func:`two_position_measure`); where the unconstrained
    one does not, the least total length among TWO_POSITION_GRID rotations over the range that do is
    returned (``"limited"``: what the unconstrained optimum broke), or none, with the reason."""
    from analytic.synthesis import constraints as sc
    from analytic.synthesis import two_position as synthesis
    check_scale({"--E1": task.E1, "--E2": task.E2, "--A": task.A, "--D": task.D}, unit)
    search = synthesis.optimum(task, lo, hi)
    thetas = [math.radians(t) for t in synthesis.SEED_THETAS if lo <= math.radians(t) <= hi]
    rows = [two_position_row(task, synthesis.design(task, th)) for th in thetas]
    optimum, limited = search.optimum, None
    if limits is not None:
        limits = limits.check()
        limits.check_names(("A", "D"), "the two-position four-bar (A: the crank's pivot, D: the rocker's)")

        def why(dsg):
            if synthesis.feasibility(task, dsg) is not None:
                return "infeasible"
            try:
                return sc.broken(two_position_measure(task, dsg), limits, unit)
            except ParameterError as exc:
                return str(exc)

        limited = why(optimum) if optimum is not None else "no unconstrained optimum"
        if limited:
            good = [d for d in (synthesis.design(task, th) for th in np.linspace(lo, hi, TWO_POSITION_GRID))
                    if math.isfinite(d.total) and not why(d)]
            optimum = min(good, key=lambda d: d.total) if good else None
    best = two_position_row(task, optimum) if optimum else None
    if best is not None and limits is not None:
        best.update(sc.record(two_position_measure(task, optimum)))
    excluded = [{"theta_deg": math.degrees(th), "reason": why_} for th, why_ in search.excluded]
    out = {"rows": rows, "optimum": best, "excluded": excluded, "unit": unit, "search": search}
    if limits is not None:
        out["limited"] = limited or ""
    return out


# ------------------------------------------------------------------------------------------ sweep
MAX_COMBOS = studies.MAX_COMBOS
"""Largest parameter grid a sweep evaluates without being told to (``allow_large``)."""
STATS = studies.STATS
"""The figures of a sweep's row that are lengths, speeds or areas (``row.values``): x_min ... fluctuation."""
SECONDS_PER_COMBO = 1e-4
"""Measured cost of one combination at 360 samples (a five-bar, this machine, batch path: 10,000 in 0.7-1.3 s,
benchmarks/batch.py): sets the estimate shown."""


def parse_vary(items: list[str], mech=None) -> dict[str, list[float]]:
    """``NAME=V1,V2,...`` or ``NAME=start:stop:count`` (count evenly spaced values, ends included)."""
    from sim import service
    out: dict[str, list[float]] = {}
    for item in items:
        if "=" not in item:
            raise ParameterError(f"--vary {item!r} is not NAME=V1,V2,... or NAME=start:stop:count")
        name, text = (x.strip() for x in item.split("=", 1))
        if name in out:
            raise ParameterError(f"--vary {name} is given twice; give it once")
        angle = None
        if mech is not None:
            service.parameter_value(mech, name, mech.values.get(name, 0.0))       # a known parameter
            if name in mech.overrides:
                raise ParameterError(f"--vary {name} and --set {name} both given: --vary would override "
                                     f"--set; give only one")
            angle = False if mech.definition.parameter_kind[name] == "length" else None
        if text.count(":") == 2:
            a, b, n = text.split(":")
            start, stop = expr.parse_value(name, a, angle), expr.parse_value(name, b, angle)
            try:
                count = int(n)
            except ValueError:
                raise ParameterError(f"--vary {name}: count {n!r} must be an integer >= 1") from None
            if not 1 <= count <= 1_000_000:
                raise ParameterError(f"--vary {name}: count {count} must be in 1..1000000")
            if count > 1 and not stop > start:
                raise ParameterError(f"--vary {name}={text}: the range is empty or inverted (stop must exceed start)")
            out[name] = [float(v) for v in np.linspace(start, stop, count)]
        else:
            vals = [v for v in text.split(",") if v.strip()]
            if not vals:
                raise ParameterError(f"--vary {name}: no values given")
            out[name] = [expr.parse_value(name, v, angle) for v in vals]
    return out


def check_grid(vary: dict, allow_large: bool = False) -> int:
    """The number of combinations; refused over MAX_COMBOS unless ``allow_large``."""
    if not vary:
        raise ParameterError("give at least one --vary NAME=V1,V2,... (or NAME=start:stop:count)")
    n = math.prod(len(v) for v in vary.values())
    if n > MAX_COMBOS and not allow_large:
        raise ParameterError(f"the grid has {n:,} combinations (over {MAX_COMBOS:,}; about "
                             f"{n * SECONDS_PER_COMBO:,.0f} s): narrow it, or add --yes")
    return n


def sweep(base, vary: dict[str, list[float]], samples: int = 360, keep_paths: int = 0, progress=None,
          workers: int = 1, scheduler: str | None = None, allow_large: bool = False):
    """Every combination of ``vary`` on ``base`` (:func:`analytic.applications.studies.sweep_mechanism`),
    its chunks spread over ``workers`` processes or a Dask ``scheduler``: the same rows in the same order
    for any count. Returns (rows, paths)."""
    from analytic.applications import studies
    check_grid(vary, allow_large)
    with mapper(workers, scheduler) as m:
        return studies.sweep_mechanism(base, vary, samples, keep_paths=keep_paths, progress=progress,
                                       mapper=m if (workers > 1 or scheduler) else None)


SWEEP_QUANTITY = {"x_min": "length", "x_max": "length", "y_min": "length", "y_max": "length",
                  "speed_mean": "velocity", "speed_min": "velocity", "speed_max": "velocity", "mu_min": "angle",
                  "period": "time", "fluctuation": "ratio", "valid": "ratio", "peak_joint_force": "force"}
"""The quantity of each sweep column; ``peak_drive`` is a torque or a force by the first input's kind and
``energy_per_cycle`` is in J (sim.service.sweep_forces)."""


def sweep_stat_names(rows) -> list[str]:
    from analytic.applications import studies
    from sim.service.sweep_forces import FORCE_FIGURES
    return [s for s in list(studies.STATS) + ["mu_min", "period", *FORCE_FIGURES] if any(s in r.values for r in rows)]


def sweep_columns(base, keys, rows, display=None) -> tuple[dict, dict]:
    """The sweep's columns in ``display`` units (None: SI) and the unit of each: the varied values as the
    file gives them (file units, angles in rad), the path's box and speeds by quantity, the area in the
    length unit squared, ``valid`` 1/0."""
    from analytic.quantities import SI
    stat_names = sweep_stat_names(rows)
    cols = {k: np.array([r.params[k] for r in rows]) for k in keys}
    cols.update({s: np.array([r.values.get(s, np.nan) for r in rows]) for s in stat_names})
    cols["valid"] = np.array([1.0 if r.valid else 0.0 for r in rows])
    u = display or SI
    f = u.factor("length")
    kinds = base.definition.parameter_kind
    units = {k: (base.units if kinds.get(k) == "length" else "rad" if kinds.get(k) == "angle" else "") for k in keys}
    out = {k: cols[k] for k in keys}
    for name, v in cols.items():
        if name in keys:
            continue
        if name == "area":
            out[name], units[name] = v * f * f, f"{u.unit('length')}^2"
        elif name == "energy_per_cycle":
            out[name], units[name] = v, "J"
        elif name == "peak_drive":
            q = "torque" if base.inputs[0].angular else "force"
            out[name], units[name] = u.convert(q, v), u.unit(q)
        else:
            q = SWEEP_QUANTITY.get(name, "")
            out[name], units[name] = (u.convert(q, v), u.unit(q)) if q else (v, "")
    return out, units


# --------------------------------------------------------------------- what the front ends ask for
UNITS = tuple(sorted(_LENGTH_UNITS))
"""The length units a synthesis reads its data in and writes its designs' files in (a file's ``units``)."""
GRASHOF = _sc.GRASHOF
"""The four-bar types a synthesis may be limited to: any, crank-rocker, double-crank."""


def limits(min_transmission_deg=None, max_size: float | None = None, pivot_regions=(), grashof: str = "any",
           name: str = "min_transmission"):
    """The limits every returned design meets (:class:`analytic.synthesis.constraints.Limits`), checked: the
    least transmission angle [deg; a number or text such as ``"30deg"``; None: no limit], the largest side of
    the bounding box (file units), the boxes ``NAME=x0:x1,y0:y1`` the ground pivots must lie in, the Grashof
    type wanted. ``name`` names the angle in an error message."""
    mu = 0.0 if min_transmission_deg is None else _sc.parse_angle_deg(name, min_transmission_deg)
    return _sc.Limits(mu, max_size, tuple(_sc.parse_region(t) for t in pivot_regions), grashof).check()


def unreachable(points, limits, unit: str = "", what: str = "targets") -> str:
    """Why no design can meet ``points`` (N, 2) [file units] within ``limits`` ('' when nothing rules it
    out): :func:`analytic.synthesis.constraints.unreachable`."""
    return _sc.unreachable(points, limits, unit, what) if limits is not None else ""


def two_position_task(E1, E2, A, D, phi12: float, psi12: float):
    """Seed 001's two-position problem (:class:`analytic.synthesis.two_position.Task`): the coupler point E at
    ``E1`` then ``E2``, the crank pivot ``A`` and the rocker pivot ``D`` (x, y; one length unit), the crank's
    rotation ``phi12`` and the rocker's ``psi12`` [rad] between the positions."""
    from analytic.synthesis import two_position as synthesis
    return synthesis.Task(E1=E1, E2=E2, A=A, D=D, phi12=phi12, psi12=psi12)


def two_position_design(task, theta: float):
    """The four-bar solving ``task`` at coupler rotation ``theta`` [rad] (its lengths and start angles)."""
    from analytic.synthesis import two_position as synthesis
    return synthesis.design(task, theta)


def two_position_feasible(task, dsg, samples: int = 721) -> bool:
    """Whether the design moves E from E1 to E2 on one branch without locking (checked at ``samples`` crank
    angles over its travel)."""
    from analytic.synthesis import two_position as synthesis
    return synthesis.feasibility(task, dsg, samples) is None


def two_position_mechanism(task, dsg, scale: float = 1.0, omega1: float = 1.0):
    """The design as a :class:`analytic.Mechanism`, lengths times ``scale`` (metres per unit), the crank at
    ``omega1`` [rad/s], starting in position 1."""
    from analytic.synthesis import two_position as synthesis
    return synthesis.mechanism(task, dsg, scale=scale, omega1=omega1)
