"""Path synthesis: a linkage whose traced point passes through (or nearest to) target points, found by a
seeded global search over normalised shapes, a least-squares polish (the constraints as penalties, then
exact: :func:`polish`), a multi-start stage of briefly polished random shapes (:func:`multistart`), for
the four-bar a stage from the slider-crank's best designs (:func:`slider_limit`), and basin hopping on
the best (:func:`hopping`), many designs evaluated at once.

The kinds of linkage (four-bar, slider-crank, Watt II and Stephenson III six-bars) are the families of
:mod:`analytic.synthesis.curves`; this module is the same search for all of them.

Error of a design (what ``sum_sq``, ``max`` and ``rms`` report):

* free timing: each target's distance to the coupler curve (the traced point over a full crank turn),
  at the crank angle ``phis[i]`` where the curve passes nearest to it;
* timing: each target's distance to the traced point at crank angle ``phi_i + phi_offset`` (the targets'
  input angles, up to one common free offset).

Order, open and closed targets (free timing): the targets are the points of a path, in the order given,
and the coupler point must meet them in that order while the crank turns one way: the crank-angle steps
from each target to the next, wrapped to (-180, 180] deg, all have the sign of the turning sense (so
each step is less than half a turn).

* open path (the default): the steps from the first target to the last must go less than a full turn;
  the stretch from the last target back to the first is free (it may take any part of the turn: the ends
  of the path are free, the targets may occupy a small part of the cycle);
* closed path (``closed=True``): the targets go once round a loop, so the closing step from the last
  target back to the first is a step like the others: the same sense and less than half a turn, and all
  the steps together make exactly one turn;
* any order (``ordered=False``): no order at all, each target's distance to the curve alone (SPEC's free
  timing error, the metric of the literature's benchmarks whose reported designs do not meet their targets
  in order); the search still starts from shapes matched to the targets in their given order.

Constraints (every returned design; :func:`violation` measures them, :func:`failed_constraint` names the
first broken): the crank turns fully on one branch with every transmission angle in [mu_min, 180 deg -
mu_min] (the family's closed form or samples, see :mod:`analytic.synthesis.curves`), the longest link at
most ``max_ratio`` times the shortest, the ground pivots within ``region`` target sizes of the targets'
centre, the order above.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from analytic._common import ParameterError
from analytic.synthesis.curves import FAMILIES, TYPES, Family, FourBar, fourbar_from_slider_crank

__all__ = ["Target", "Constraints", "Design", "coupler_points", "violation", "curve_distance", "errors",
           "order_violation", "margins", "synthesize", "restart", "jobs", "hop", "multistart", "from_four_bar_rs", "failed_constraint"]

FOURBAR = FAMILIES["fourbar"]
NAMES = FOURBAR.names
STARTS = 8
"""Free timing: starting points on each curve for matching the targets by arc length (:func:`_arc_starts`)."""
SPANS = (1.0, 0.6, 0.35)
"""Open targets: the fractions of the curve's length they are tried on."""
ARC_GRID = 64
"""Points of each curve, evenly spaced by arc length, the matches pick from."""
KEEP = 2
"""Starts (least matching residual) refined by nearest-point alignment."""
ALIGN_STEPS = 5
"""Rounds of nearest-point alignment."""
SEARCH_TARGETS = 40
"""Targets the global search uses at most (:func:`search_target`)."""
PRESCREEN = 20000
"""Random shapes drawn per restart; the least constraint-breaking are posed on the targets and the best
seed the population (a computed atlas, see :func:`restart`)."""
ATLAS = 200
"""Of those, the least constraint-breaking shapes posed on the targets (the best ``popsize`` seed the
population)."""
ORDER_WEIGHT = 0.1
"""Search objective: error / size^2 plus this times the order violation (in half turns; the polish then
puts the targets in order exactly)."""
POLISH_STAGES = (("trf", 100),)
"""The polish's penalised least-squares runs in turn: (scipy method, residual evaluations at most). The
constrained stage finishes what they leave on a bound: with it, 100 reach the same basins as 300 on the
literature's targets (McGarva, Ullah and Kota: every restart's and multi-start's basin the same) in a
third less time (a restart's penalised run used all 300 creeping along a bound)."""
PENALTY = 1e3
"""Weight of the constraint and order rows in the polish (against target distances / target size)."""
DE_STRATEGY = "best1bin"
"""scipy's differential-evolution strategy."""
ORDER_SLACK = 1e-6
"""[rad] A returned design may meet a target this much of a crank turn before the previous one (the
polish's order penalty leaves steps back of that order; two targets met within 1e-6 rad are met
together)."""
TURN_ROUNDING = 1e-9
"""[rad] A sum of wrapped steps is a whole number of turns up to rounding (1e-16 seen): below this, none."""
FINAL_SAMPLES = 4096
"""Crank angles at which a returned design's sampled constraints (six-bars' second dyad) are checked."""
RESTARTS = 16
"""Restarts at least where ``--restarts`` is not given (the four-bar and slider-crank: 8 per branch)."""
GENERATIONS = {"fourbar": 80, "slider_crank": 80}
"""Differential-evolution generations per restart where ``--generations`` is not given, by family (the
others: 400). A four-bar's 5 shape parameters settle in their basin early: on the literature's targets
(benchmarks/synthesis_path.py) every one of 16 restarts of mkh3 reached the same basin at 80 generations
as at 150, and 150 as at 400; more, shorter restarts reach the best basin more often for the same time."""
GENERATIONS_OTHER = 400
HOP_ROUNDS = 4
"""Rounds of basin hopping on the best design the restarts found (:func:`hop`)."""
HOP_JUMPS = 16
"""Perturbed copies of the best design polished per hopping round."""
HOP_SIGMAS = (0.05, 0.1, 0.2)
"""Relative sizes of the hops' perturbations, in turn (link lengths by a factor exp(sigma N(0, 1)), other
lengths and the ground pivots by sigma times the mean link length, angles by sigma rad)."""
MULTISTART = 12
"""Multi-start stage (:func:`multistart`): random feasible shapes posed on the targets and polished
briefly, this many per restart (the command's 16 restarts: 192)."""
MULTISTART_POOL = 10
"""Random feasible shapes drawn per start kept; the best posed of them are the starts."""
SHORT_POLISH = 40
"""Residual evaluations of the multi-start stage's brief polish."""
START_COST = 100
"""With ``--evaluations``: the designs a full polish of the multi-start and slider-crank limit stages may
evaluate (without it, as many as it takes: POLISH_STAGES' 100 residuals, their Jacobians, SLSQP)."""
STAGE_SHARES = {"restarts": 0.6, "multistart": 0.12, "slider_limit": 0.08, "hopping": 0.12, "refine": 0.08}
"""With ``--evaluations N``: each stage's share of N, in the order they run; a stage gets its share or what
the earlier ones left, whichever is less, and ends within it (so N bounds the whole run)."""
MULTISTART_KEEP = 8
"""One start in this many, the best after the brief polish, is polished in full."""
MULTISTART_CHUNK = 16
"""Starts per job of the multi-start stage (one seeded job draws, poses and briefly polishes them)."""
LIMIT_MULTISTART = 12
"""The slider-crank limit stage (:func:`slider_limit`): slider-crank starts per restart (Ullah and Kota's
targets, 16 restarts: its four-bars reached the best basin for 6 of 6 seeds at 6 and 5 of 6 at 3, but the
command's seed 8 missed it at 6 and reaches it at 12)."""
LIMIT_KEEP = 2
"""Of its slider-cranks, the best distinct ones turned into four-bars."""
LIMIT_LENGTHS = (6.0, 12.0)
"""The rocker lengths they are given [crank lengths], each on either side of the slider line."""
POLISH_MARGIN = (math.radians(0.02), 1e-4)
"""The polish's penalties aim inside the bounds by this much (transmission angle [rad]; ratio and region,
relative), so the penalty method's slight overshoot still lands inside them."""
SLSQP_MARGIN = (1e-7, 1e-9)
"""The polish's constrained stage aims inside the bounds by this much (transmission angle [rad]; ratio
and region, relative): SLSQP ends on an active bound up to rounding (1e-16 outside it seen)."""
SLSQP_ITERATIONS = 300
"""The constrained stage's SLSQP iterations at most (a restart's polish on the literature's targets: 100
to 200)."""
SLSQP_FTOL = 1e-11
"""SLSQP's stopping tolerance on half the sum of squared residuals over the target size squared (ten
polishes on Ullah and Kota's targets: the same errors to 1e-7 as at 1e-12, in 30 % less time)."""


@dataclass(frozen=True)
class Target:
    """Target points ``xy`` (M, 2) [length]; ``phi`` (M,) input angles [rad] with timing, else None;
    ``closed``: the points go once round a closed path; ``ordered``: met in their order (free timing; see
    the module doc)."""

    xy: np.ndarray
    phi: np.ndarray | None = None
    closed: bool = False
    ordered: bool = True

    @property
    def in_order(self) -> bool:
        """Whether the order is a constraint: free timing with ordered targets."""
        return self.phi is None and self.ordered

    @property
    def centre(self) -> np.ndarray:
        return 0.5 * (self.xy.min(axis=0) + self.xy.max(axis=0))

    @property
    def size(self) -> float:
        """The larger side of the targets' bounding box [length]."""
        return float(np.ptp(self.xy, axis=0).max())


@dataclass(frozen=True)
class Constraints:
    """``mu_min``: least transmission angle [rad]; ``max_ratio``: longest/shortest link;
    ``region``: ground pivots within this many target sizes of the targets' centre; ``max_size``: the
    largest side of the mechanism's bounding box over the turn [length] (None: none; :meth:`Family.extent`);
    ``boxes``: (name, x0, x1, y0, y1) a box for the ground pivot of that name [length]; ``grashof``: "any",
    "crank-rocker" (the crank the shortest of the first loop's links) or "double-crank" (the ground)."""

    mu_min: float = math.radians(30.0)
    max_ratio: float = 20.0
    region: float = 3.0
    max_size: float | None = None
    boxes: tuple[tuple[str, float, float, float, float], ...] = ()
    grashof: str = "any"


@dataclass(frozen=True)
class Design:
    """One synthesised design: ``family``, ``x`` its parameters, ``branch`` one +-1 per dyad,
    ``phi_offset`` (timing) [rad], ``err`` (M,) the distance of each target [length], ``phis`` (M,) the
    crank angle of each target's nearest (or timed) point [rad], ``violation`` (0 when every constraint
    holds), ``seed``, ``failed`` (the first broken constraint in words, '' if none)."""

    x: np.ndarray
    branch: tuple[int, ...]
    phi_offset: float
    err: np.ndarray
    phis: np.ndarray
    violation: float
    seed: int
    failed: str = ""
    stats: dict = field(default_factory=dict)
    family: Family = FOURBAR

    @property
    def sum_sq(self) -> float:
        return float(np.sum(self.err ** 2))

    def parameters(self) -> dict:
        return self.family.parameters(self.x, self.branch)


def coupler_points(x, phi, branch, family: Family = FOURBAR):
    """The traced point of K designs at crank angles ``phi`` ((K, N) or (N,)); see
    :meth:`analytic.synthesis.curves.Family.points`. Returns (E (K, N, 2), ok (K, N))."""
    return family.points(x, phi, branch)


def _branch(branch) -> tuple[int, ...]:
    return tuple(int(b) for b in np.atleast_1d(branch))


# --- constraints -------------------------------------------------------------------------------------
def shape_violation(x, cons: Constraints, branch, family: Family = FOURBAR, n: int = 0) -> np.ndarray:
    """(K,) the constraints a similarity does not change (turn, transmission, link ratio, positive
    lengths); 0 = they hold, dimensionless. ``n``: samples where the family needs them (0: its default;
    the final checks use 4096)."""
    x = np.atleast_2d(x)
    L = x[:, list(family.links)]
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = L.max(axis=1) / L.min(axis=1)
        out = (family.excess(x, branch, cons.mu_min, n) + np.maximum(ratio / cons.max_ratio - 1, 0)
               + np.maximum(-L.min(axis=1), 0) / np.maximum(L.max(axis=1), 1e-300)
               + np.maximum(-_grashof_margins(x, cons, family), 0).sum(axis=1))
    return np.where(np.isfinite(out), out, 1e3)


def _grashof_margins(x, cons: Constraints, family: Family) -> np.ndarray:
    """(K, 3) the Grashof type asked for, as margins over the longest link (>= 0 where it holds): the first
    loop's crank (crank-rocker) or ground (double-crank) no longer than each of its other three links; none
    for "any" or a family without a four-bar loop."""
    x = np.atleast_2d(x)
    if cons.grashof == "any" or family.name == "slider_crank":
        return np.zeros((len(x), 0))
    d, a, b, c = x[:, 3], x[:, 4], x[:, 5], x[:, 6]
    s, others = (a, (b, c, d)) if cons.grashof == "crank-rocker" else (d, (a, b, c))
    top = np.maximum(np.maximum(np.maximum(np.abs(a), np.abs(b)), np.maximum(np.abs(c), np.abs(d))), 1e-300)
    return np.column_stack([(o - s) / top for o in others])


SIZE_MARGIN = 1e-4
"""The search keeps the size this much (relative) inside ``--max-size``: the extent's samples can miss an
extreme by 2e-5 of its radius (:meth:`Family.extent` at 512), the general solver's check must not."""


def _box_margins(x, cons: Constraints, target: Target, family: Family, branch) -> np.ndarray:
    """(K, C) the pivot boxes and the size limit as margins over the target size (>= 0 where they hold)."""
    x = np.atleast_2d(x)
    s = max(target.size, 1e-300)
    cols = []
    if cons.boxes:
        piv = family.pivots(x)
        for name, x0, x1, y0, y1 in cons.boxes:
            if name in family.pivot_names:
                p = piv[:, family.pivot_names.index(name)]
                cols += [(p[:, 0] - x0) / s, (x1 - p[:, 0]) / s, (p[:, 1] - y0) / s, (y1 - p[:, 1]) / s]
    if cons.max_size is not None:
        e = family.extent(x, branch, 512)
        cols += [(cons.max_size - (e[:, 2] - e[:, 0])) / s, (cons.max_size - (e[:, 3] - e[:, 1])) / s]
    return np.column_stack(cols) if cols else np.zeros((len(x), 0))


def region_violation(x, cons: Constraints, target: Target, family: Family = FOURBAR, branch=None) -> np.ndarray:
    """(K,) how far the ground pivots lie beyond ``region`` target sizes of the targets' centre, outside
    their boxes, and the mechanism beyond ``max_size`` (over the target size; ``branch`` needed for that)."""
    x = np.atleast_2d(x)
    piv = family.pivots(x)
    s = max(target.size, 1e-300)
    far = np.abs(piv - target.centre).max(axis=(1, 2))
    out = np.maximum(far / (cons.region * s) - 1, 0)
    if cons.boxes or cons.max_size is not None:
        out = out + np.maximum(-_box_margins(x, cons, target, family, family.branches[0] if branch is None
                                             else branch), 0).sum(axis=1)
    return np.where(np.isfinite(out), out, 1e3)


def violation(x, cons: Constraints, target: Target, branch=(1,), family: Family = FOURBAR, n: int = 0) -> np.ndarray:
    """How far K designs break the constraints (0 = all hold; dimensionless, >= 0), (K,)."""
    return shape_violation(x, cons, branch, family, n) + region_violation(x, cons, target, family, branch)


def _wrap(a):
    return np.angle(np.exp(1j * np.asarray(a, dtype=float)))


def order_violation(phis, closed: bool, slack: float = 0.0) -> np.ndarray:
    """(K,) how far matched crank angles ``phis`` (K, M) [rad] break the targets' order (module doc):
    backward steps beyond ``slack`` [rad] in half turns, plus (closed) the steps' total's distance from one
    turn or (open) its excess over one turn, in turns. 0 = in order. The search passes a slack of about
    one curve sample (targets nearer together than the samples may pick them in either order)."""
    phis = np.atleast_2d(phis)
    d = _wrap(np.diff(phis, axis=1))
    if closed:
        d = np.concatenate([d, _wrap(phis[:, :1] - phis[:, -1:])], axis=1)
    total = d.sum(axis=1)
    s = np.where(total < 0, -1.0, 1.0)[:, None]
    back = np.maximum(-s * d - slack, 0).sum(axis=1) / math.pi
    tot = (s * d).sum(axis=1)
    turn = np.abs(tot - 2 * math.pi) if closed else np.maximum(tot - 2 * math.pi, 0)
    return back + np.maximum(turn - TURN_ROUNDING, 0) / (2 * math.pi)


def _order_words(phis, closed: bool) -> str:
    """Which targets break the order ('' if none)."""
    if order_violation(phis[None], closed, ORDER_SLACK)[0] <= 0:
        return ""
    d = _wrap(np.diff(phis))
    dd = np.concatenate([d, _wrap(phis[:1] - phis[-1:])]) if closed else d
    s = -1.0 if dd.sum() < 0 else 1.0
    bad = np.flatnonzero(s * dd < -ORDER_SLACK)
    m = len(phis)
    if bad.size:
        i = int(bad[0])
        return (f"the traced point meets targets {i + 1} and {(i + 1) % m + 1} out of order"
                + (" (--closed: the last target and the first are neighbours too)" if i == m - 1 else ""))
    return ("the traced point does not go round the targets once (--closed)" if closed
            else "the targets take more than one crank turn")


def failed_constraint(x, cons: Constraints, target: Target, branch=(1,), family: Family = FOURBAR,
                      phis=None) -> str:
    """Words for the first constraint one design breaks ('' when none)."""
    x = np.asarray(x, dtype=float)
    L = x[list(family.links)]
    if L.min() <= 0:
        return "a link length is not positive"
    mu = float(family.mu_min(x[None], branch)[0])
    if not math.isfinite(mu):
        why = {"fourbar": " (not a Grashof crank-rocker or double-crank)",
               "slider_crank": " (the rod is shorter than the crank plus the offset)"}.get(
            family.name, " (a loop cannot close over the whole turn)")
        return "the crank does not turn fully on one branch" + why
    if mu < cons.mu_min - 1e-12:       # the closed forms' rounding
        return (f"transmission angle {math.degrees(mu):.1f} deg is below --min-transmission "
                f"{math.degrees(cons.mu_min):.1f} deg")
    if L.max() / L.min() > cons.max_ratio:
        return f"link-length ratio above {cons.max_ratio:g}"
    g = _grashof_margins(x[None], cons, family)
    if g.size and g.min() < 0:
        return f"not a {cons.grashof} (--grashof): its {'crank' if cons.grashof == 'crank-rocker' else 'ground'} " \
               f"is not the shortest link of the four-bar loop"
    from dataclasses import replace
    if region_violation(x[None], replace(cons, boxes=(), max_size=None), target, family)[0] > 0:
        return f"a ground pivot lies outside {cons.region:g} target sizes of the targets' centre"
    if region_violation(x[None], cons, target, family, branch)[0] > 0:
        m = _box_margins(x[None], cons, target, family, branch)[0]
        k = 4 * sum(1 for b in cons.boxes if b[0] in family.pivot_names)
        if k and m[:k].min() < 0:
            b = [b for b in cons.boxes if b[0] in family.pivot_names][int(np.argmin(m[:k])) // 4]
            return f"ground pivot {b[0]} lies outside --pivot-region {b[0]}={b[1]:g}:{b[2]:g},{b[3]:g}:{b[4]:g}"
        return f"its bounding box over the turn exceeds --max-size {cons.max_size:g}"
    if phis is not None and target.in_order:
        return _order_words(np.asarray(phis, dtype=float), target.closed)
    return ""


# --- errors ------------------------------------------------------------------------------------------
def _nearest_sample(E: np.ndarray, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Squared distance (K, M) from each target to the nearest curve sample and that sample's index.

    The search uses |e|^2 - 2 e.t on coordinates taken from the targets' mean (|t|^2 is the same for
    every sample; a sample that does not close is put 1e150 away), laid out (K, M, N) so the arg-min runs
    along contiguous memory; the returned distance is recomputed directly at the chosen sample."""
    c = xy.mean(axis=0)
    Ec = np.where(np.isnan(E), 1e150, E - c)
    t = xy - c
    G = (Ec * Ec).sum(-1)[:, None, :] - 2.0 * (t[None, :, 0, None] * Ec[:, None, :, 0]
                                                + t[None, :, 1, None] * Ec[:, None, :, 1])   # (K, M, N)
    k = G.argmin(axis=2)
    P = np.take_along_axis(E, k[:, :, None], axis=1)                  # (K, M, 2)
    d2 = ((P - xy[None]) ** 2).sum(-1)
    return np.where(np.isfinite(d2), d2, np.inf), k


def batch_error(x, target: Target, branch, n: int = 192, family: Family = FOURBAR):
    """Sum of squared distances (K,) from the targets to each design's curve sampled at n crank angles
    (free timing), or to its timed points (timing: x carries one more column, the crank offset), and the
    order violation (K,) of the nearest samples' angles (0 with timing)."""
    x = np.atleast_2d(x)
    nx = family.size
    if target.phi is not None:
        E, _ = family.points(x[:, :nx], x[:, nx:nx + 1] + target.phi[None, :], branch)
        e = ((E - target.xy[None]) ** 2).sum(-1).sum(-1)
        return np.where(np.isfinite(e), e, np.inf), np.zeros(len(x))
    out, order = np.empty(x.shape[0]), np.empty(x.shape[0])
    phi = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    step = max(1, int(4e6 // (n * len(target.xy))))           # keep (K, N, M) arrays near 32 MB
    br = np.asarray(branch)
    for i in range(0, x.shape[0], step):
        b = br[i:i + step] if br.ndim == 2 else br
        E, _ = family.points(x[i:i + step], phi, b)
        d2, k = _nearest_sample(E, target.xy)
        out[i:i + step] = d2.sum(-1)
        order[i:i + step] = (order_violation(phi[k], target.closed, 1.5 * 2 * math.pi / n) if target.ordered
                             else 0.0)
    return out, order


def align(x, target: Target, branch, n: int = 160, steps: int = 2, family: Family = FOURBAR):
    """Move, turn and scale K designs (free timing) so their curves lie nearest the targets: ``steps``
    rounds of nearest-sample correspondence and the least-squares similarity (Umeyama, in complex form)."""
    x = np.atleast_2d(np.asarray(x, dtype=float)).copy()
    phi = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    q = target.xy[:, 0] + 1j * target.xy[:, 1]
    for _ in range(steps):
        E, _ = family.points(x, phi, branch)
        _, k = _nearest_sample(E, target.xy)
        P = np.take_along_axis(E, k[:, :, None], axis=1)          # (K, M, 2) corresponding curve points
        p = P[..., 0] + 1j * P[..., 1]
        pc = p - p.mean(axis=1, keepdims=True)
        qc = q - q.mean()
        with np.errstate(divide="ignore", invalid="ignore"):
            z = (np.conj(pc) * qc[None]).sum(1) / (np.abs(pc) ** 2).sum(1)
        good = np.isfinite(z) & (np.abs(z) > 0.5) & (np.abs(z) < 2.0)
        z = np.where(good, z, 1.0)
        t = np.where(good, q.mean() - z * p.mean(axis=1), 0.0)
        x = family.move(x, z, t)
    return x


def curve_distance(x, branch, xy: np.ndarray, n: int = 4096, iters: int = 60, family: Family = FOURBAR):
    """Distance from each target to one design's closed coupler curve: nearest of n samples, refined by
    a golden-section search over the neighbouring two sample intervals (vectorised over targets).

    Returns (dist (M,) [length], phi (M,) [rad])."""
    x = np.asarray(x, dtype=float)[None, :family.size]
    phi = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    E, _ = family.points(x, phi, branch)
    _, k = _nearest_sample(E, xy)
    h = 2 * math.pi / n
    lo, hi = phi[k[0]] - h, phi[k[0]] + h
    g = (math.sqrt(5) - 1) / 2

    def f(p):
        P, _ = family.points(x, p[None, :], branch)
        v = ((P[0] - xy) ** 2).sum(-1)
        return np.where(np.isnan(v), np.inf, v)
    for _ in range(iters):
        p1, p2 = hi - g * (hi - lo), lo + g * (hi - lo)
        left = f(p1) < f(p2)
        hi, lo = np.where(left, p2, hi), np.where(left, lo, p1)
    p = 0.5 * (lo + hi)
    d2 = f(p)
    # the sample itself may be better where the curve has a gap (a NaN neighbour)
    d2s = ((E[0, k[0]] - xy) ** 2).sum(-1)
    use = ~(d2 <= d2s)
    return np.sqrt(np.where(use, d2s, d2)), np.where(use, phi[k[0]], p)


def errors(x, branch, target: Target, phi_offset: float = 0.0, family: Family = FOURBAR):
    """Each target's distance to the nearest point of the curve (free timing) or to its timed point
    [length], and the crank angles [rad] (see the module doc)."""
    if target.phi is None:
        return curve_distance(x, branch, target.xy, family=family)
    phis = target.phi + phi_offset
    E, _ = family.points(np.asarray(x)[None, :family.size], phis[None], branch)
    return np.hypot(*(E[0] - target.xy).T), phis


# --- normalised design space -------------------------------------------------------------------------
def _target_fractions(target: Target) -> np.ndarray:
    """Each target's place along the targets' polygon as a fraction of its length (closed: the closing
    side counted)."""
    xy = target.xy
    sides = np.hypot(*np.diff(np.vstack([xy, xy[:1]]) if target.closed else xy, axis=0).T)
    cum = np.concatenate([[0.0], np.cumsum(sides)])
    return cum[:len(xy)] / max(cum[-1], 1e-300)


def _arc_starts(E: np.ndarray, target: Target) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Similarities (z, t) (K, S) that put each sampled curve E (K, n, 2) on the targets when the targets,
    spaced by their polygon's length, are matched to the curve spaced by its arc length from STARTS
    starting points, in both senses, the targets spanning the whole curve (closed) or SPANS of it (open);
    and the residual (K, S) of each match (squared, [length^2])."""
    K, n, _ = E.shape
    Ef = np.nan_to_num(E)
    seg = np.hypot(*(np.roll(Ef, -1, axis=1) - Ef).transpose(2, 0, 1))          # (K, n)
    cum = np.cumsum(seg, axis=1) - seg
    cum = cum / np.maximum(cum[:, -1:] + seg[:, -1:], 1e-300)                    # (K, n) in [0, 1)
    grid = np.arange(ARC_GRID) / ARC_GRID
    idx = np.minimum((cum[:, None, :] < grid[None, :, None]).sum(-1), n - 1)   # (K, G): uniform in arc length
    U = np.take_along_axis(Ef, idx[:, :, None], axis=1)
    u = U[..., 0] + 1j * U[..., 1]                                            # (K, G)
    f = _target_fractions(target)
    spans = (1.0,) if target.closed else SPANS
    cols = [np.round(ARC_GRID * (k / STARTS + d * s * f)).astype(int) % ARC_GRID
            for s in spans for d in (1, -1) for k in range(STARTS)]
    cols = np.stack(cols)                                                       # (S, M)
    p = u[:, cols]                                                              # (K, S, M)
    q = target.xy[:, 0] + 1j * target.xy[:, 1]
    pc, qc = p - p.mean(-1, keepdims=True), q - q.mean()
    with np.errstate(divide="ignore", invalid="ignore"):
        z = (np.conj(pc) * qc).sum(-1) / (np.abs(pc) ** 2).sum(-1)
    z = np.where(np.isfinite(z) & (z != 0), z, 1.0)
    t = q.mean() - z * p.mean(-1)
    res = (np.abs(z[..., None] * p + t[..., None] - q) ** 2).sum(-1)
    return z, t, np.where(np.isfinite(res), res, np.inf)


def _pose(xn, target: Target, branch, n: int, family: Family):
    """Each shape moved, turned and scaled onto the targets: starts from matching arc-length fractions
    (:func:`_arc_starts`), the best KEEP by their matching residual aligned (``align``), the best of
    those kept.

    Returns (x (K, size), sum_sq (K,), order violation (K,))."""
    K = len(xn)
    nb = len(family.branches[0])
    phi = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    E, _ = family.points(xn, phi, branch)
    z, t, res = _arc_starts(E, target)
    keep = np.argsort(res, axis=1, kind="stable")[:, :KEEP]                    # (K, KEEP)
    r = np.arange(K)[:, None]
    xs = family.move(np.repeat(xn, KEEP, axis=0), z[r, keep].ravel(), t[r, keep].ravel())
    br = np.broadcast_to(np.asarray(branch), (K, nb))
    brk = np.repeat(br, KEEP, axis=0)
    xs = align(xs, target, brk, n, steps=ALIGN_STEPS, family=family)
    f, o = batch_error(xs, target, brk, n, family)
    f = np.where(np.isfinite(f), f, np.inf).reshape(K, KEEP)
    o = o.reshape(K, KEEP)
    score = f / max(target.size, 1e-300) ** 2 + ORDER_WEIGHT * o
    j = np.argmin(score, axis=1)
    r = np.arange(K)
    return xs.reshape(K, KEEP, -1)[r, j], f[r, j], o[r, j]


def _pose_timed(u, target: Target, branch, family: Family):
    """Timing: shapes (first ``shape_dim`` columns) with a crank offset (the last), posed by the exact
    least-squares similarity onto the timed targets (the correspondences are known). Returns (x (K, size
    + 1) with the offset last, sum_sq (K,), zeros (K,)); a turn of the design adds its angle to the offset."""
    xn = family.shape(u[:, :family.shape_dim])
    off = (2 * u[:, family.shape_dim] - 1) * math.pi
    E, _ = family.points(xn, off[:, None] + target.phi[None, :], branch)
    p = E[..., 0] + 1j * E[..., 1]
    q = target.xy[:, 0] + 1j * target.xy[:, 1]
    pc, qc = p - p.mean(1, keepdims=True), q - q.mean()
    with np.errstate(divide="ignore", invalid="ignore"):
        z = (np.conj(pc) * qc[None]).sum(1) / (np.abs(pc) ** 2).sum(1)
    z = np.where(np.isfinite(z) & (z != 0), z, 1.0)
    t = q.mean() - z * p.mean(1)
    t = np.where(np.isfinite(t), t, 0.0)
    x = np.column_stack([family.move(xn, z, t), off + np.angle(z)])
    e = (np.abs(z[:, None] * p + t[:, None] - q[None]) ** 2).sum(1)
    return x, np.where(np.isfinite(e), e, np.inf), np.zeros(len(x))


def _shape_objective(u, target: Target, cons: Constraints, branch, n: int, family: Family):
    """Deb's rule on the posed shapes: error / size^2 plus the order violation where the constraints
    hold; 1e6 + violation where they do not."""
    xn = family.shape(u[:, :family.shape_dim])
    v = shape_violation(xn, cons, branch, family)
    f = 1e6 + v
    ok = v == 0
    if ok.any():
        if target.phi is None:
            x, e, o = _pose(xn[ok], target, branch, n, family)
        else:
            x, e, o = _pose_timed(u[ok], target, branch, family)
        v2 = region_violation(x[:, :family.size], cons, target, family, branch)
        f[ok] = np.where(v2 == 0, np.minimum(e / target.size ** 2 + ORDER_WEIGHT * o, 1e6), 1e6 + v2)
    return f


def search_target(target: Target) -> Target:
    """The targets the global search sees: at most SEARCH_TARGETS of them, evenly spaced in the given
    order (a dense path is represented by a subset; the polish and every reported error use all)."""
    m = len(target.xy)
    if m <= SEARCH_TARGETS:
        return target
    idx = np.unique(np.round(np.linspace(0, m - 1, SEARCH_TARGETS)).astype(int))
    return Target(target.xy[idx], None if target.phi is None else target.phi[idx], target.closed, target.ordered)


def restart(job: tuple) -> Design:
    """One seeded restart (:func:`_restart`) with one BLAS thread (:mod:`analytic.synthesis.threads`)."""
    import scipy.optimize  # noqa: F401 (its OpenBLAS must be loaded before its threads are set)
    from analytic.synthesis.threads import one_blas_thread
    with one_blas_thread():
        return _restart(job)


def _restart(job: tuple) -> Design:
    """One seeded restart: a computed atlas of random feasible shapes posed on the targets seeds the
    population, differential evolution searches the normalised shapes, the best distinct members of the
    final population are polished by least squares on the search's targets (:func:`search_target`) and
    the best kept. ``job`` = (family name, target,
    cons, seed, branch, generations, popsize, deadline, n_polish[, cap]).

    ``cap`` (``--evaluations``): the designs the restart may evaluate on the targets in all (at least
    :func:`least_restart`): an atlas of at most a fifth of it, differential evolution's generations from the
    rest of 60 % of it (each generation ``popsize`` designs), the polishes sharing what is left (each pick
    posed once and polished within its share), so the restart's count never exceeds it.

    The search runs on the family's shape parameters (crank = 1, A at the origin), each shape posed onto
    the targets by a similarity: free timing by nearest-point alignment, timing (plus a crank offset) by
    the exact least squares."""
    from scipy.optimize import differential_evolution

    name, target, cons, seed, branch, generations, popsize, deadline, n_polish, *rest = job
    cap = rest[0] if rest else None
    family = FAMILIES[name]
    if deadline is not None and time.time() > deadline:
        return skipped(family, branch, int(seed))
    free = target.phi is None
    dim = family.shape_dim + (0 if free else 1)
    rng = np.random.default_rng(seed)
    search = search_target(target)

    def obj(u, n):
        return _shape_objective(u, search, cons, branch, n, family)

    def to_x(u):
        if free:
            return _pose(family.shape(u[None]), search, branch, 256, family)[0][0]
        return _pose_timed(u[None], search, branch, family)[0][0]
    if PRESCREEN:
        U = rng.random((PRESCREEN, dim))
        pre = shape_violation(family.shape(U[:, :family.shape_dim]), cons, branch, family)
        # the computed atlas: random shapes, the least constraint-breaking posed and ranked by error
        U = U[np.argsort(pre, kind="stable")][:atlas_size(popsize, cap)]
        f = obj(U, 96)
        init = U[np.argsort(f, kind="stable")[:popsize]]
    else:                          # no atlas (for measuring what it brings): a random population
        init = rng.random((popsize, dim))

    def stop(*_a, **_k):
        return deadline is not None and time.time() > deadline
    atlas = atlas_size(popsize, cap) if PRESCREEN else 0
    if cap is not None:            # the generations 60 % of the cap leaves after the atlas (the first: the init)
        generations = max(0, (int(0.6 * cap) - atlas) // popsize - 1)
    res = differential_evolution(
        lambda u: obj(u.T, 128), [(0.0, 1.0)] * dim, init=init,
        maxiter=generations, tol=0, atol=0, seed=int(rng.integers(2 ** 31)), polish=False,
        vectorized=True, updating="deferred", mutation=(0.5, 1.0), recombination=0.9, callback=stop,
        strategy=DE_STRATEGY)
    # polish the best distinct members of the final population, keep the best polished one
    order = np.argsort(res.population_energies, kind="stable")
    picks = []
    for j in order:
        if res.population_energies[j] >= 1e6 or len(picks) == n_polish:
            break
        if all(np.abs(res.population[j] - res.population[p]).max() > 1e-3 for p in picks):
            picks.append(j)
    de_evaluations = int(res.nfev) * popsize      # vectorised: scipy counts calls, each one the population
    picks = picks or list(order[:1])
    caps = [None] * len(picks)
    if cap is not None:            # each pick: posed once, then polished within an even share of the rest
        room = cap - atlas - de_evaluations
        picks = picks[:max(1, room // 3)]
        caps = [(room - len(picks)) // len(picks)] * len(picks)
    cands = [polish(to_x(res.population[j]), branch, search, cons, family, deadline=deadline, cap=c)
             for j, c in zip(picks, caps)]
    d = min(cands, key=lambda c: (c.violation > 0, c.violation if c.violation > 0 else c.sum_sq))
    return Design(d.x, d.branch, d.phi_offset, d.err, d.phis, d.violation, int(seed), d.failed,
                  {"de_generations": int(res.nit), "de_evaluations": de_evaluations,
                   "evaluations": atlas + de_evaluations + len(cands) + sum(c.stats["evaluations"] for c in cands),
                   "stopped_by_budget": bool(stop())}, family)


def atlas_size(popsize: int, cap: int | None = None) -> int:
    """Shapes of a restart's atlas posed on the targets: max(4 popsize, ATLAS), or with a ``cap`` at most a
    fifth of it (at least the population)."""
    full = max(popsize * 4, ATLAS)
    return full if cap is None else min(full, max(popsize, cap // 5))


def least_restart(popsize: int) -> int:
    """The least cap a restart can keep to: an atlas and the first generation of ``popsize`` each within
    60 % of it, and one pick posed and its start finished (3 designs)."""
    return math.ceil((2 * popsize) / 0.6) + 3


def spent_only(family: Family, spent: int) -> Design:
    """No design, only the evaluations a stage spent before it found none to return (counted by
    :func:`synthesize`, then dropped like a skipped restart)."""
    return Design(np.full(family.size, np.nan), _branch(family.branches[0]), 0.0, np.array([np.inf]),
                  np.array([0.0]), np.inf, 0, "nothing found", {"evaluations": int(spent), "skipped": True}, family)


def skipped(family: Family, branch, seed: int) -> Design:
    """A restart the budget left no time for: no design (ranked last, dropped by :func:`synthesize`)."""
    return Design(np.full(family.size, np.nan), _branch(branch), 0.0, np.array([np.inf]), np.array([0.0]), np.inf,
                  seed, "not run: the budget ran out", {"evaluations": 0, "skipped": True, "stopped_by_budget": True},
                  family)


def _finish(x, branch, target: Target, cons: Constraints, family: Family, off: float, phis_fit):
    """Errors, violation and words of a final design: free timing takes each target's nearest curve
    point when those are in order, else the fitted (ordered) angles ``phis_fit``."""
    nx = family.size
    if target.phi is None:
        e, ph = curve_distance(x, branch, target.xy, family=family)
        if not target.ordered:
            o = 0.0
        elif phis_fit is not None and order_violation(ph[None], target.closed, ORDER_SLACK)[0] > 0:
            E, _ = family.points(np.asarray(x)[None, :nx], np.asarray(phis_fit)[None], branch)
            e2 = np.hypot(*(E[0] - target.xy).T)
            if np.all(np.isfinite(e2)):
                e, ph = e2, np.asarray(phis_fit, dtype=float)
        if target.ordered:
            o = order_violation(ph[None], target.closed, ORDER_SLACK)[0]
    else:
        e, ph = errors(x, branch, target, off, family)
        o = 0.0
    v = float(violation(np.asarray(x)[None, :nx], cons, target, branch, family, FINAL_SAMPLES)[0] + o)
    return e, ph, v, failed_constraint(x, cons, target, branch, family, ph)


class _Deadline(Exception):
    """Raised inside a polish's evaluation past its deadline (``--budget``): the polish returns its best."""


@dataclass(frozen=True)
class _Fit:
    """One polish's problem: the parameters ``p`` are the design's and its crank angles (timing: the
    design's and one offset; free timing: each target's own crank angle, unwrapped in the sense of
    travel ``sense``)."""

    family: Family
    branch: tuple[int, ...]
    target: Target
    sense: float
    count: list = field(default_factory=lambda: [0], compare=False)
    """Designs evaluated on the targets so far (a residual: 1; a Jacobian: its finite-difference designs)."""
    deadline: float | None = None
    """Wall-clock time [s, time.time()] after which an evaluation raises :class:`_Deadline`."""
    cap: int | None = None
    """Designs the whole polish may evaluate (``--evaluations``): an evaluation that would leave fewer than
    one for the polish's closing finish raises :class:`_Deadline` instead, the best so far kept."""

    def tick(self, k: int) -> None:
        if self.deadline is not None and time.time() > self.deadline:
            raise _Deadline
        if self.cap is not None and self.count[0] + k > self.cap - 1:
            raise _Deadline
        self.count[0] += k

    @property
    def nx(self) -> int:
        return self.family.size

    @property
    def timing(self) -> bool:
        return self.target.phi is not None

    def design(self, p):
        """(x, offset, crank angle of each target)."""
        nx = self.nx
        if self.timing:
            return p[:nx], p[nx], self.target.phi + p[nx]
        return p[:nx], 0.0, p[nx:]

    def steps(self, ph):
        """Each step in the sense of travel (and the return, closed), [rad]; negative = backwards."""
        d = np.diff(ph)
        if self.target.closed:
            d = np.concatenate([d, ph[:1] + self.sense * 2 * math.pi - ph[-1:]])
        return self.sense * d

    def steps_jac(self, n: int) -> np.ndarray:
        """d steps / d p (exact: each step is a difference of two of the angles), (steps, n)."""
        m, nx = len(self.target.xy), self.nx
        k = m if self.target.closed else m - 1
        J = np.zeros((k, n))
        i = np.arange(k)
        J[i, nx + (i + 1) % m] += self.sense
        J[i, nx + i] -= self.sense
        return J

    def residuals(self, p):
        """Each target's offset from its point, over the target size, (2M,) (a loop that does not close: 10)."""
        self.tick(1)
        x, _, ph = self.design(p)
        E, _ = self.family.points(x[None], ph[None], self.branch)
        return np.nan_to_num(((E[0] - self.target.xy) / self.target.size).ravel(), nan=10.0)

    def jacobian(self, p):
        """d residuals / d p by forward differences, batched: the design columns (and the offset) in one
        call, each target's own crank angle (which touches its own target only) in another, (2M, n)."""
        x, _, ph = self.design(p)
        family, s, m, nx = self.family, self.target.size, len(self.target.xy), self.nx
        nd = nx + 1 if self.timing else nx
        self.tick(nd + (1 if self.timing else 2))
        h = 1e-7 * np.maximum(1.0, np.abs(p[:nd]))
        X = np.repeat(x[None], nd, axis=0)
        X[np.arange(nx), np.arange(nx)] += h[:nx]
        PH = np.repeat(ph[None], nd, axis=0)
        if self.timing:
            PH[nx] += h[nx]
        E0, _ = family.points(x[None], ph[None], self.branch)
        E, _ = family.points(X, PH, self.branch)
        J = np.zeros((2 * m, len(p)))
        J[:, :nd] = ((E - E0) / s).reshape(nd, -1).T / h
        if not self.timing:
            hp = 1e-7 * np.maximum(1.0, np.abs(ph))
            E1, _ = family.points(x[None], (ph + hp)[None], self.branch)
            dE = (E1[0] - E0[0]) / s / hp[:, None]                    # (m, 2): d position / d own angle
            J[2 * np.arange(m), nx + np.arange(m)] = dE[:, 0]
            J[2 * np.arange(m) + 1, nx + np.arange(m)] = dE[:, 1]
        return np.nan_to_num(J)

    def design_jac(self, f, p, f0):
        """d f / d design by forward differences, batched (``f`` maps designs (K, size) to (K, C)), (C, n)."""
        x, nx = p[:self.nx], self.nx
        h = 1e-7 * np.maximum(1.0, np.abs(x))
        X = np.repeat(x[None], nx, axis=0)
        X[np.arange(nx), np.arange(nx)] += h
        F = np.reshape(f(X), (nx, -1))
        J = np.zeros((F.shape[1], len(p)))
        J[:, :nx] = ((F - np.reshape(f0, (1, -1))) / h[:, None]).T
        return np.nan_to_num(J)


def margins(x, cons: Constraints, target: Target, branch, family: Family = FOURBAR, n: int = 0) -> np.ndarray:
    """(K, C) every constraint on K designs as a signed margin (>= 0 where it holds, dimensionless; all
    >= 0 exactly where :func:`violation` is 0): the family's transmission margins, each link at least
    1/max_ratio of each other one and positive (over the longest), and each ground pivot's coordinates
    within ``region`` target sizes of the targets' centre (over the size)."""
    x = np.atleast_2d(np.asarray(x, dtype=float))
    L = x[:, list(family.links)]
    k = L.shape[1]
    with np.errstate(divide="ignore", invalid="ignore"):
        top = np.abs(L).max(axis=1, keepdims=True)
        pairs = (cons.max_ratio * L[:, None, :] - L[:, :, None])[:, ~np.eye(k, dtype=bool)] / top
        s = max(target.size, 1e-300)
        piv = (family.pivots(x) - target.centre).reshape(len(x), -1) / s
        out = np.column_stack([family.margins(x, branch, cons.mu_min, n), pairs, L / top,
                               cons.region - piv, cons.region + piv, _grashof_margins(x, cons, family),
                               _box_margins(x, cons, target, family, branch)])
    return np.where(np.isfinite(out), out, -1e3)


def _inside(cons: Constraints, margin: tuple[float, float]) -> Constraints:
    """The bounds a polish stage aims at: ``margin`` = (transmission angle [rad], ratio and region
    relative) inside the constraints."""
    from dataclasses import replace
    return replace(cons, mu_min=cons.mu_min + margin[0], max_ratio=cons.max_ratio * (1 - margin[1]),
                   region=cons.region * (1 - margin[1]),
                   max_size=None if cons.max_size is None else cons.max_size * (1 - max(margin[1], SIZE_MARGIN)))


def _penalised(fit: _Fit, p0, cons: Constraints, evaluations: int | None):
    """The polish's first stage: least squares (POLISH_STAGES, or one run of ``evaluations``) on the
    residuals with the constraints as penalty rows aimed POLISH_MARGIN inside the bounds (the order: a
    row per step that goes backwards). It reaches the feasible region from anywhere, and converges where
    no bound is active; along an active bound it creeps (the penalty wall shrinks its trust region)."""
    from scipy.optimize import least_squares

    family, target, branch = fit.family, fit.target, fit.branch
    tight = _inside(cons, POLISH_MARGIN)
    ordered, w = target.in_order, PENALTY

    def resid(p):
        x, _, ph = fit.design(p)
        out = [fit.residuals(p), [w * violation(x[None], tight, target, branch, family)[0]]]
        if ordered:
            out.append(w * np.maximum(-fit.steps(ph), 0))
        return np.concatenate(out)

    def jac(p):
        x, _, ph = fit.design(p)
        v0 = violation(x[None], tight, target, branch, family)
        rows = [fit.jacobian(p), w * fit.design_jac(lambda X: violation(X, tight, target, branch, family), p, v0)]
        if ordered:
            rows.append(-w * fit.steps_jac(len(p)) * (fit.steps(ph) < 0)[:, None])
        return np.vstack(rows)

    p = p0
    seen = {"p": p0}

    def resid_seen(q):
        r = resid(q)
        seen["p"] = np.array(q)
        return r
    for method, most in (POLISH_STAGES if evaluations is None else (("trf", evaluations),)):
        try:
            p = least_squares(resid_seen, p, jac=jac, x_scale="jac", max_nfev=most, ftol=1e-13, xtol=1e-13,
                              gtol=1e-13, method=method).x
        except (ValueError, np.linalg.LinAlgError):
            break
        except _Deadline:               # the budget ran out: the last point evaluated (the polish keeps the better)
            return seen["p"]
    return p


def _constrained(fit: _Fit, p0, cons: Constraints):
    """The polish's second stage: SLSQP on half the sum of squared residuals with every constraint
    exact (:func:`margins` aimed SLSQP_MARGIN inside the bounds, the order as linear steps >= 0), from
    the first stage's result. It follows an active bound (a least transmission angle, most often) to
    the constrained minimum where the penalty stage stops short of it."""
    from scipy.optimize import minimize

    family, target, branch = fit.family, fit.target, fit.branch
    tight = _inside(cons, SLSQP_MARGIN)

    last: dict = {}

    def resid(p):
        """The residuals at p (SLSQP asks for the value and the gradient at each point: computed once)."""
        if last.get("p") is None or not np.array_equal(last["p"], p):
            last["p"], last["r"] = np.array(p), fit.residuals(p)
        return last["r"]

    def f(p):
        r = resid(p)
        return 0.5 * float(r @ r)

    def grad(p):
        return fit.jacobian(p).T @ resid(p)

    def con(p):
        x, _, ph = fit.design(p)
        c = margins(x, tight, target, branch, family)[0]
        return np.concatenate([c, fit.steps(ph)]) if target.in_order else c

    def con_jac(p):
        x = p[:fit.nx]
        c0 = margins(x, tight, target, branch, family)[0]
        J = fit.design_jac(lambda X: margins(X, tight, target, branch, family), p, c0)
        return np.vstack([J, fit.steps_jac(len(p))]) if target.in_order else J

    try:
        with np.errstate(all="ignore"):
            return minimize(f, p0, jac=grad, method="SLSQP", constraints=[{"type": "ineq", "fun": con, "jac": con_jac}],
                            options={"maxiter": SLSQP_ITERATIONS, "ftol": SLSQP_FTOL}).x
    except (ValueError, np.linalg.LinAlgError):
        return p0
    except _Deadline:                   # the budget ran out: the last point evaluated (the polish keeps the better)
        return last.get("p", p0)


def polish(x0, branch, target: Target, cons: Constraints, family: Family = FOURBAR,
           evaluations: int | None = None, deadline: float | None = None, cap: int | None = None) -> Design:
    """Least squares on the design and its crank angles in two stages: the constraints as penalty rows
    (:func:`_penalised`), then, where that ends feasible, as exact constraints (:func:`_constrained`).
    Timing: the angles are the targets' plus one offset. Free timing: each target's own crank angle
    (unwrapped in the sense of travel), kept in the targets' order (``--closed``: the return from the last
    target to the first too). A step that breaks a bound is cut back to the last feasible point; each
    stage's result replaces the start only if it ranks better (:func:`rank_key`). ``evaluations``: a brief
    polish, one penalised run of at most this many residual evaluations and no second stage. ``deadline``
    (``--budget``): past it an evaluation stops the stage in progress, the best so far kept and no stage
    started. ``cap``: the designs it may evaluate in all, its start's and end's finishes and every Jacobian's
    difference designs included (at least 2: then the start alone; ``--evaluations``). The design's
    ``stats["evaluations"]``: the designs it evaluated on the targets."""
    branch = _branch(branch)
    timing = target.phi is not None
    nx = family.size
    x0 = np.asarray(x0, dtype=float)
    _, ph0 = errors(x0[:nx], branch, target, x0[nx] if timing else 0.0, family)
    fit = _Fit(family, branch, target, -1.0 if _wrap(np.diff(ph0)).sum() < 0 else 1.0, deadline=deadline,
               cap=None if cap is None else max(int(cap), 2))
    fit.count[0] = 1                # the start's angles above: one design evaluated on the targets

    def room(k):
        return fit.cap is None or fit.count[0] + k <= fit.cap
    if timing:
        p0 = np.concatenate([x0[:nx], [x0[nx]]])
    else:                           # the nearest points' angles, unwrapped along the targets
        p0 = np.concatenate([x0[:nx], ph0[0] + np.concatenate([[0.0], np.cumsum(_wrap(np.diff(ph0)))])])

    def finish(q):
        fit.count[0] += 1
        x, off, ph = fit.design(q)
        return (q, x, off) + _finish(x, branch, target, cons, family, off, None if timing else ph)

    def key(c):
        return (c[5] > 0, c[5] if c[5] > 0 else float(np.sum(c[3] ** 2)))

    def step(best, p):
        """The stage's result, or where it breaks a bound the last feasible point on the way to it."""
        end = finish(p)
        if end[5] > 0 and best[5] == 0:        # back along the step to the last feasible point (bisection)
            lo, hi = 0.0, 1.0
            for _ in range(30):
                if not room(2):             # a cap: the next point and the closing finish must fit
                    break
                mid = 0.5 * (lo + hi)
                if finish(best[0] + mid * (p - best[0]))[5] == 0:
                    lo = mid
                else:
                    hi = mid
            end = finish(best[0] + lo * (p - best[0]))
        return end if (np.all(np.isfinite(end[3])) and key(end) <= key(best)) else best

    def late():
        return deadline is not None and time.time() > deadline
    best = finish(p0)
    if not late() and room(2):
        best = step(best, _penalised(fit, p0, cons, evaluations))
    if evaluations is None and best[5] == 0 and not late() and room(2):
        best = step(best, _constrained(fit, best[0], cons))
    _, x, off, e, ph, v, words = best
    return Design(np.asarray(x, float).copy(), branch, float(off), e, ph, float(v), 0, words,
                  {"evaluations": fit.count[0]}, family)


def perturb(x, sigma: float, rng: np.random.Generator, family: Family = FOURBAR) -> np.ndarray:
    """One design (size, or size + 1 with a crank offset last) moved at random by a relative ``sigma``:
    link lengths times exp(sigma N(0, 1)), the other lengths and the ground pivots plus sigma times the
    mean link length times N(0, 1), angles (and the offset) plus sigma N(0, 1) [rad]."""
    x = np.array(x, dtype=float)
    nx = family.size
    links = list(family.links)
    ref = float(np.mean(np.abs(x[links])))
    angles = [*family.angles, *range(nx, len(x))]
    rest = [i for i in range(len(x)) if i not in links and i not in angles]
    x[links] = x[links] * np.exp(sigma * rng.standard_normal(len(links)))
    x[rest] = x[rest] + sigma * ref * rng.standard_normal(len(rest))
    x[angles] = x[angles] + sigma * rng.standard_normal(len(angles))
    return x


def hop(job: tuple) -> Design:
    """One basin hop (:func:`_hop`) with one BLAS thread (:mod:`analytic.synthesis.threads`)."""
    import scipy.optimize  # noqa: F401 (its OpenBLAS must be loaded before its threads are set)
    from analytic.synthesis.threads import one_blas_thread
    with one_blas_thread():
        return _hop(job)


def _hop(job: tuple) -> Design:
    """One seeded hop from a design: perturbed (:func:`perturb`), posed on the targets again (free
    timing: nearest-point alignment) and polished (:func:`polish`). ``job`` = (family name, target, cons,
    seed, branch, x (with the crank offset last, timing), sigma)."""
    name, target, cons, seed, branch, x, sigma, *rest = job
    deadline = rest[0] if rest else None
    cap = rest[1] if len(rest) > 1 else None
    family = FAMILIES[name]
    x1 = perturb(x, sigma, np.random.default_rng(seed), family)
    posed = 0
    if target.phi is None:
        x1 = align(x1[None], target, branch, 160, ALIGN_STEPS, family)[0]
        posed = 1
    d = polish(x1, branch, target, cons, family, deadline=deadline, cap=None if cap is None else cap - posed)
    return Design(d.x, d.branch, d.phi_offset, d.err, d.phis, d.violation, d.seed, d.failed,
                  {**d.stats, "evaluations": d.stats["evaluations"] + posed}, d.family)


def _start(d: Design, target: Target) -> np.ndarray:
    """A design's parameters as a polish starts from them (timing: the crank offset last)."""
    return d.x if target.phi is None else np.concatenate([d.x, [d.phi_offset]])


def hop_jobs(d: Design, target: Target, cons: Constraints, seeds, deadline: float | None = None,
             cap: int | None = None) -> list[tuple]:
    """The jobs of one hopping round from design ``d``: one per seed, the sizes HOP_SIGMAS in turn, each
    evaluating at most ``cap`` designs (None: no cap)."""
    return [(d.family.name, target, cons, int(sd), d.branch, _start(d, target), HOP_SIGMAS[i % len(HOP_SIGMAS)],
             deadline, cap) for i, sd in enumerate(seeds)]


def refine(job: tuple) -> Design:
    """The final polish of one design on all the targets, with one BLAS thread: ``job`` = (design, target,
    cons[, deadline[, cap]]); the design keeps its seed and stats."""
    import scipy.optimize  # noqa: F401 (its OpenBLAS must be loaded before its threads are set)
    from analytic.synthesis.threads import one_blas_thread
    d, target, cons, *rest = job
    with one_blas_thread():
        c = polish(_start(d, target), d.branch, target, cons, d.family, deadline=rest[0] if rest else None,
                   cap=rest[1] if len(rest) > 1 else None)
    stats = {**d.stats, "evaluations": d.stats.get("evaluations", 0) + c.stats["evaluations"]}
    return Design(c.x, c.branch, c.phi_offset, c.err, c.phis, c.violation, d.seed, c.failed, stats, d.family)


def multistart_chunk(job: tuple) -> list[Design]:
    """One seeded job of the multi-start stage (:func:`multistart`), with one BLAS thread: ``job`` =
    (family name, target, cons, seed, branch, count, deadline[, short]; ``short``: each brief polish's cap).
    Random shapes that meet the shape constraints are
    drawn until there are ``count`` x MULTISTART_POOL (or 64 draws of that many are spent), posed on the
    targets and ranked like the search's objective; the best ``count`` are posed finely and polished
    briefly (SHORT_POLISH evaluations), none after the deadline. Returns those designs (the seed each
    one's job's)."""
    import scipy.optimize  # noqa: F401 (its OpenBLAS must be loaded before its threads are set)
    from analytic.synthesis.threads import one_blas_thread
    name, target, cons, seed, branch, count, deadline, *rest = job
    short = rest[0] if rest else SHORT_POLISH
    family = FAMILIES[name]
    free = target.phi is None
    dim = family.shape_dim + (0 if free else 1)
    rng = np.random.default_rng(seed)
    want = count * MULTISTART_POOL
    pool = []
    for _ in range(64):
        U = rng.random((want, dim))
        pool.append(U[shape_violation(family.shape(U[:, :family.shape_dim]), cons, branch, family) == 0])
        if sum(len(u) for u in pool) >= want:
            break
    U = np.concatenate(pool)[:want]
    if not len(U) or (deadline is not None and time.time() > deadline):
        return []
    f = _shape_objective(U, target, cons, branch, 128, family)
    pool = len(U)
    U = U[np.argsort(f, kind="stable")[:count]]
    X = (_pose(family.shape(U), target, branch, 256, family)[0] if free
         else _pose_timed(U, target, branch, family)[0])
    found = []
    with one_blas_thread():
        for x in X:
            if deadline is not None and time.time() > deadline:
                break
            found.append(polish(x, branch, target, cons, family, short, deadline, cap=short if rest else None))
    return [Design(d.x, d.branch, d.phi_offset, d.err, d.phis, d.violation, int(seed), d.failed,
                   {"multistart": True, "evaluations": d.stats["evaluations"] + 1 + (pool if i == 0 else 0)}, family)
            for i, d in enumerate(found)]


def multistart_count(name: str, restarts: int, per_restart: int = MULTISTART) -> int:
    """Starts of the multi-start stage for one family: ``per_restart`` per restart for the four-bar and the
    slider-crank (measured on the literature's four-bar targets), none for the six-bars (not measured)."""
    return per_restart * restarts if name in ("fourbar", "slider_crank") else 0


def multistart(target: Target, cons: Constraints, seed: int, restarts: int, types=("fourbar",), mapper=map,
               deadline: float | None = None, per_restart: int = MULTISTART, cap: int | None = None) -> list[Design]:
    """The multi-start stage: many random shapes posed on the targets and polished briefly
    (:func:`multistart_chunk`, the families' branches in turn, MULTISTART_CHUNK starts a job, seeds spawned
    from ``seed``), then the best one in MULTISTART_KEEP polished in full (:func:`refine`). Returns those
    designs, best first. The deadline (``--budget``) stops it between polishes; no full polish starts
    after it. ``cap`` (``--evaluations``): the designs it may evaluate in all: each start costs at most
    MULTISTART_POOL + 1 + SHORT_POLISH and each full polish START_COST, the starts cut to fit.

    It complements the restarts: differential evolution settles in the basin its (approximate, posed)
    objective favours, and on some targets a deeper basin that objective cannot tell apart is reached from
    random starts only (mkh1: none of 64 restarts; about 1 random start in 27 polished in full, and a
    quarter of the best eighth after the brief polish)."""
    cs = combos(types)
    if cap is not None:            # as many starts as fit: each start and its share of the full polishes
        per_start = MULTISTART_POOL + 1 + SHORT_POLISH + START_COST / MULTISTART_KEEP
        fit = int((cap - START_COST) // per_start)
        total = sum(multistart_count(c[0], restarts, per_restart) // len(cs) for c in cs)
        if fit < MULTISTART_KEEP or total == 0:
            return []
        per_restart = min(per_restart, max(1, fit * per_restart // max(total, 1)))
    per = {c: multistart_count(c[0], restarts, per_restart) // len(cs) for c in cs}
    if cap is not None and sum(per.values()) * (MULTISTART_POOL + 1 + SHORT_POLISH) > cap:
        return []
    js = [(name, br, min(MULTISTART_CHUNK, n - k)) for (name, br), n in per.items() for k in range(0, n, MULTISTART_CHUNK)]
    if not js or (deadline is not None and time.time() > deadline):
        return []
    seeds = np.random.SeedSequence([seed, 2]).generate_state(len(js))
    extra = () if cap is None else (SHORT_POLISH,)
    short = [d for ds in mapper(multistart_chunk, [(name, target, cons, int(sd), br, k, deadline, *extra)
                                                   for (name, br, k), sd in zip(js, seeds)]) for d in ds]
    spent = sum(d.stats["evaluations"] for d in short)
    short = [d for _, d in sorted(enumerate(short), key=lambda t: rank_key(*t))]
    keep = short[:max(1, len(short) // MULTISTART_KEEP)]
    if not (deadline is not None and time.time() > deadline):
        full_cap = None if cap is None else (cap - spent) // len(keep)
        if full_cap is None or full_cap >= 3:
            full = list(mapper(refine, [(d, target, cons, deadline, full_cap) for d in keep]))
            spent += sum(d.stats["evaluations"] - k.stats["evaluations"] for d, k in zip(full, keep))
            keep = [d for _, d in sorted(enumerate(full), key=lambda t: rank_key(*t))]
    return _carry(keep, spent)


def _carry(designs: list[Design], spent: int) -> list[Design]:
    """A stage's designs with its whole count of evaluations carried by the first (the list sums to it)."""
    return [Design(d.x, d.branch, d.phi_offset, d.err, d.phis, d.violation, d.seed, d.failed,
                   {**d.stats, "evaluations": spent if i == 0 else 0}, d.family) for i, d in enumerate(designs)]


def limit_polish(job: tuple) -> Design:
    """One four-bar near a slider-crank's limit (:func:`analytic.synthesis.curves.fourbar_from_slider_crank`),
    posed on the targets again and polished, with one BLAS thread: ``job`` = (target, cons, slider-crank
    design, rocker length in crank lengths, side). Timing: the slider-crank's crank offset kept (the crank
    is the same)."""
    import scipy.optimize  # noqa: F401 (its OpenBLAS must be loaded before its threads are set)
    from analytic.synthesis.threads import one_blas_thread
    target, cons, sc, length, side, *rest = job
    deadline = rest[0] if rest else None
    cap = rest[1] if len(rest) > 1 else None
    x, br = fourbar_from_slider_crank(sc.x[None], sc.branch, length * abs(sc.x[3]), side)
    branch = (int(br[0]),)
    with one_blas_thread():
        if target.phi is None:
            d = polish(align(x, target, branch, 160, ALIGN_STEPS)[0], branch, target, cons, deadline=deadline,
                       cap=None if cap is None else cap - 1)
            return Design(d.x, d.branch, d.phi_offset, d.err, d.phis, d.violation, d.seed, d.failed,
                          {**d.stats, "evaluations": d.stats["evaluations"] + 1}, d.family)      # the pose
        return polish(np.concatenate([x[0], [sc.phi_offset]]), branch, target, cons,   # the same crank angles
                      deadline=deadline, cap=cap)


def slider_limit(target: Target, cons: Constraints, seed: int, restarts: int, mapper=map,
                 deadline: float | None = None, cap: int | None = None) -> list[Design]:
    """The four-bar's slider-crank limit stage: a multi-start search of slider-crank designs
    (:func:`multistart`, LIMIT_MULTISTART starts per restart), the best LIMIT_KEEP distinct ones turned
    into four-bars with long rockers (LIMIT_LENGTHS, on either side of the slider line) and polished as
    four-bars (:func:`limit_polish`). Returns those four-bars, best first.

    A four-bar with a long ground and rocker draws nearly its slider-crank's curve. On some targets the best
    four-bar is of that kind, at the edge of the search's box of shapes (Ullah and Kota's: ground 7.3 and
    rocker 6.3 cranks, the box's edge at 8), where neither the evolution nor random shapes reach it, while
    the slider-crank's own search, on four shape parameters, does. ``cap`` (``--evaluations``): the designs
    it may evaluate in all, 60 % for its multi-start, the rest shared by the four-bars' polishes."""
    if deadline is not None and time.time() > deadline:
        return []
    sub = int(np.random.SeedSequence([seed, 3]).generate_state(1)[0])
    scs = multistart(target, cons, sub, restarts, ("slider_crank",), mapper, deadline, LIMIT_MULTISTART,
                     None if cap is None else int(0.6 * cap))
    spent = sum(d.stats["evaluations"] for d in scs)
    scs = [d for d in scs if d.violation == 0]
    picks: list[Design] = []
    for d in scs:
        if len(picks) < LIMIT_KEEP and all(abs(d.sum_sq - p.sum_sq) > 1e-6 * p.sum_sq for p in picks):
            picks.append(d)
    if not picks or (deadline is not None and time.time() > deadline):
        return [spent_only(FOURBAR, spent)] if spent else []
    each = None if cap is None else (cap - spent) // (len(picks) * len(LIMIT_LENGTHS) * 2)
    if each is not None and each < 3:
        return [spent_only(FOURBAR, spent)]
    found = list(mapper(limit_polish, [(target, cons, d, length, side, deadline, each) for d in picks
                                       for length in LIMIT_LENGTHS for side in (1, -1)]))
    spent += sum(d.stats["evaluations"] for d in found)
    return _carry([Design(d.x, d.branch, d.phi_offset, d.err, d.phis, d.violation, seed, d.failed,
                          {"slider_limit": True}, d.family)
                   for _, d in sorted(enumerate(found), key=lambda t: rank_key(*t))], spent)


def hopping(best: Design, target: Target, cons: Constraints, seed: int, rounds: int, jumps: int, mapper=map,
            deadline: float | None = None, cap: int | None = None) -> Design:
    """Basin hopping on the best design: ``rounds`` rounds of ``jumps`` seeded hops (:func:`hop`) from the
    best so far, run through ``mapper`` (the same answer for any worker count); a hop replaces the best
    when it ranks better (:func:`rank_key`). The deadline is a safety net: no round starts after it.
    ``cap`` (``--evaluations``): the designs all the hops may evaluate, an even share each (a hop needs 4:
    fewer rounds where the share would be smaller)."""
    each = None
    if cap is not None:
        rounds = min(rounds, cap // (4 * jumps)) if jumps else 0
        each = cap // (rounds * jumps) if rounds else None
    seeds = np.random.SeedSequence([seed, 1]).generate_state(rounds * jumps).reshape(rounds, jumps) if rounds else ()
    better, done, cut, spent = 0, 0, False, 0
    for r in range(rounds):
        if deadline is not None and time.time() > deadline:
            cut = True
            break
        found = list(mapper(hop, hop_jobs(best, target, cons, seeds[r], deadline, each)))
        spent += sum(c.stats["evaluations"] for c in found)
        done += 1
        i, c = min(enumerate(found), key=lambda t: rank_key(*t))
        if rank_key(0, c) < rank_key(0, best):
            best = Design(c.x, c.branch, c.phi_offset, c.err, c.phis, c.violation, best.seed, c.failed,
                          best.stats, best.family)
            better += 1
    stats = {**best.stats, "hop_rounds": done, "hop_improved": better, "hop_evaluations": spent,
             "stopped_by_budget": bool(best.stats.get("stopped_by_budget")) or cut}
    return Design(best.x, best.branch, best.phi_offset, best.err, best.phis, best.violation, best.seed,
                  best.failed, stats, best.family)


def evaluate(d: Design, target: Target, cons: Constraints) -> Design:
    """One design's errors, violation and words on all the targets, not polished (free timing: each
    target's nearest curve point)."""
    e, ph, v, words = _finish(d.x, d.branch, target, cons, d.family, d.phi_offset, None)
    return Design(d.x, d.branch, d.phi_offset, e, ph, v, d.seed, words, d.stats, d.family)


def combos(types=("fourbar",)) -> list[tuple[str, tuple[int, ...]]]:
    """(family, branch) pairs the restarts cycle through, for ``--type`` names."""
    out = []
    for t in types:
        for name in TYPES[t]:
            out += [(name, b) for b in FAMILIES[name].branches]
    return out


def generations_of(name: str, generations: int | None = None) -> int:
    """The differential-evolution generations of one family's restart: ``generations``, or where None
    the family's default (:data:`GENERATIONS`)."""
    return int(generations) if generations is not None else GENERATIONS.get(name, GENERATIONS_OTHER)


def jobs(target: Target, cons: Constraints, seed: int, restarts: int, generations: int | None = None,
         popsize: int = 40, deadline: float | None = None, n_polish: int = 6, types=("fourbar",),
         cap: int | None = None) -> list[tuple]:
    """The restarts' jobs: the families' branches in turn, seeds spawned from ``seed`` (the same for any
    worker count); ``generations`` None: each family's default (:func:`generations_of`); ``cap``: each
    restart's designs at most (``--evaluations``; None: none)."""
    seeds = np.random.SeedSequence(seed).generate_state(restarts)
    cs = combos(types)
    return [(cs[i % len(cs)][0], target, cons, int(sd), cs[i % len(cs)][1],
             generations_of(cs[i % len(cs)][0], generations), popsize, deadline, n_polish, cap)
            for i, sd in enumerate(seeds)]


def rank_key(i: int, d: Design):
    """Best first: feasible, then by sum of squared distances (infeasible: by violation); ties by order."""
    return (d.violation > 0, d.violation if d.violation > 0 else d.sum_sq, i)


def synthesize(target: Target, cons: Constraints = Constraints(), seed: int = 0, restarts: int = 4,
               generations: int | None = None, popsize: int = 40, budget: float | None = None, mapper=map,
               progress=None, n_polish: int = 6, types=("fourbar",), hops: int = HOP_ROUNDS,
               jumps: int = HOP_JUMPS, designs: int = 1, multistarts: bool = True,
               evaluations: int | None = None) -> list[Design]:
    """Run ``restarts`` seeded restarts through ``mapper`` (``map`` or an executor's) and (``multistarts``)
    the multi-start stage (:func:`multistart`; where the four-bar is searched, the slider-crank limit stage
    too, :func:`slider_limit`), then ``hops`` rounds of basin hopping on the best
    (:func:`hopping`, ``jumps`` hops a round; it replaces the best), and return the designs best first
    (:func:`rank_key`).

    The restarts and hops polish on the search's targets (:func:`search_target`); where those are a
    subset, the best ``designs`` are polished again on all the targets (:func:`refine`) and the others
    only evaluated on them (:func:`evaluate`).

    ``evaluations`` (``--evaluations N``): every design evaluated on the targets counts (the atlas,
    differential evolution's populations, each pose and each polish's residuals, Jacobian difference
    designs and finishes), and the run evaluates N at most: each stage gets its STAGE_SHARES share of N or
    what the earlier ones left, the restarts cut to as many as get :func:`least_restart` each, and every
    polish runs within a cap (``generations`` is then set by the cap). The random shapes screened against
    the limits before any is posed (PRESCREEN a restart) are not evaluated on the targets and not counted.
    Each design's ``stats``: ``run_evaluations`` (the whole run's) and ``polish_evaluations`` (the hops' and
    the final polishes')."""
    m = len(target.xy)
    if m < 4:
        raise ParameterError(f"{m} target points; path synthesis needs at least 4")
    for t in types:
        if t not in TYPES:
            raise ParameterError(f"unknown linkage type {t!r}; use one of {', '.join(TYPES)}")
    start = time.time()
    deadline = None if budget is None else start + float(budget)
    out = []
    share = {}
    if evaluations is not None:
        evaluations = int(evaluations)
        share = {k: int(v * evaluations) for k, v in STAGE_SHARES.items()}
        restarts = min(restarts, share["restarts"] // least_restart(popsize))
        if restarts < 1:
            raise ParameterError(f"--evaluations {evaluations} is too few for one restart of a population of "
                                 f"{popsize} (at least {math.ceil(least_restart(popsize) / STAGE_SHARES['restarts'])}"
                                 f"); give more, or a smaller --popsize")
    cap_r = share["restarts"] // restarts if share else None
    js = jobs(target, cons, seed, restarts, generations, popsize, deadline, n_polish, types, cap_r)
    for i, d in enumerate(mapper(restart, js)):
        out.append((i, d))
        if progress is not None:
            progress(i + 1, restarts)
    search = search_target(target)

    def left(stage):                   # a stage's cap: its share, or what the earlier stages left
        if not share:
            return None
        used = sum(d.stats.get("evaluations", 0) for _, d in out)
        return max(0, min(share[stage], evaluations - used - sum(share[k] for k in list(STAGE_SHARES)
                                                                  [list(STAGE_SHARES).index(stage) + 1:])))
    if multistarts:
        out += list(enumerate(multistart(search, cons, seed, restarts, types, mapper, deadline,
                                         cap=left("multistart")), len(out)))
        if any("fourbar" in TYPES[t] for t in types):
            out += list(enumerate(slider_limit(search, cons, seed, restarts, mapper, deadline,
                                               cap=left("slider_limit")), len(out)))
    spent = sum(d.stats.get("evaluations", 0) for _, d in out)
    cut = any(d.stats.get("stopped_by_budget") for _, d in out)
    out = [(i, d) for i, d in out if not d.stats.get("skipped")]
    if not out:
        raise ParameterError(f"--budget {budget:g} s ran out before the first restart could start; give more")
    out.sort(key=lambda t: rank_key(*t))
    found = compact_first([d for _, d in out], target)
    polish_spent = 0
    if hops and jumps:
        hop_cap = None if not share else max(0, min(share["hopping"], evaluations - spent - share["refine"]))
        found[0] = hopping(found[0], search, cons, seed, hops, jumps, mapper, deadline, hop_cap)
        spent += found[0].stats["hop_evaluations"]
        polish_spent += found[0].stats["hop_evaluations"]
    found = distinct_first(found, designs, target.size)
    if search is not target:           # the restarts and hops saw a subset: the first designs polished on all
        k = min(designs, len(found))
        ref_cap = None if not share else (evaluations - spent - (len(found) - k)) // max(k, 1)
        if ref_cap is not None and ref_cap < 2:
            raise ParameterError(f"--evaluations {evaluations} leaves nothing for the final polish on all "
                                 f"{len(target.xy)} targets; give more")
        refined = list(mapper(refine, [(d, target, cons, deadline, ref_cap) for d in found[:designs]]))
        spent += sum(r.stats["evaluations"] - d.stats.get("evaluations", 0) for r, d in zip(refined, found))
        polish_spent += sum(r.stats["evaluations"] - d.stats.get("evaluations", 0) for r, d in zip(refined, found))
        found = refined + [evaluate(d, target, cons) for d in found[designs:]]
        spent += len(found) - len(refined)
        found = distinct_first([d for _, d in sorted(enumerate(found), key=lambda t: rank_key(*t))], designs,
                               target.size)
    found = distinct_first(compact_first(found, target), designs, target.size)
    cut = cut or (deadline is not None and time.time() > deadline)
    run = {"run_evaluations": int(spent), "polish_evaluations": int(polish_spent), "restarts": restarts,
           "search_seconds": time.time() - start, "stopped_by_budget": bool(cut)}
    return [Design(d.x, d.branch, d.phi_offset, d.err, d.phis, d.violation, d.seed, d.failed, {**d.stats, **run},
                   d.family) for d in found]


DISTINCT = 1e-3
"""Two designs of one family and branch whose parameters all differ by less than this share of the target
size are one design found twice (one basin reached from two starts)."""


COMPACT_TIE = 1e-4
"""Designs whose RMS target distance is within this share of the target size of the best one's are equally
good (1e-4: 0.03 mm on a 300 mm path, below what pins and links can be made to): the smallest of them (its
mechanism's extent over a turn) is ranked first. A search ranked on the error alone returned a drag link 20
times the size of the crank-rocker that drew the targets (issue 41)."""


def compact_first(found: list[Design], target: Target) -> list[Design]:
    """``found`` (best first, :func:`rank_key`) with the feasible designs tied with the best (COMPACT_TIE)
    moved to the front, smallest first; the others keep their order."""
    ok = [d for d in found if d.violation == 0 and not d.failed and np.all(np.isfinite(d.err))]
    if len(ok) < 2:
        return found
    rms = {id(d): float(np.sqrt(np.mean(np.asarray(d.err) ** 2))) for d in ok}
    best = min(rms.values())
    ties = [d for d in ok if rms[id(d)] <= best + COMPACT_TIE * target.size]
    if len(ties) < 2:
        return found
    def side(d):                   # the larger side of the mechanism's box over a turn
        b = d.family.extent(np.asarray(d.x)[None], d.branch, 512)[0]
        return float(max(b[2] - b[0], b[3] - b[1]))
    size = {id(d): side(d) for d in ties}
    head = sorted(ties, key=lambda d: size[id(d)])
    return head + [d for d in found if not any(d is h for h in head)]


def same_design(a: Design, b: Design, scale: float) -> bool:
    """Whether ``a`` and ``b`` are one design (:data:`DISTINCT`)."""
    return (a.family.name == b.family.name and a.branch == b.branch
            and bool(np.all(np.abs(np.asarray(a.x) - np.asarray(b.x)) <= DISTINCT * scale)))


def distinct_first(found: list[Design], k: int, scale: float) -> list[Design]:
    """``found`` (best first) with its best ``k`` distinct designs first (a copy of a better one moved
    behind them, in order): the designs returned are different basins, not copies."""
    head: list[Design] = []
    tail: list[Design] = []
    for d in found:
        (tail if len(head) >= k or any(same_design(d, h, scale) for h in head) else head).append(d)
    return head + tail


def from_four_bar_rs(p1x, p1y, a, l1, l2, l3, l4, l5, g, stat: str) -> tuple[np.ndarray, int]:
    """A design given in four-bar-rs's parameters (crank pivot p1, ground angle a, ground l1, crank l2,
    coupler l3, follower l4, coupler point at l5 and angle g from the coupler line; stat c1* / c2*) as
    this module's four-bar (x, branch): circuit 1 turns B->D counter-clockwise onto B->C, i.e. branch +1."""
    x = np.array([p1x, p1y, a, l1, l2, l3, l4, l5 * math.cos(g), l5 * math.sin(g)], dtype=float)
    return x, (1 if stat.lower().startswith("c1") else -1)


assert isinstance(FOURBAR, FourBar)
