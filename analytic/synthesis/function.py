"""Function generation by Freudenstein's equation: a four-bar whose rocker angle psi follows the crank
angle phi through given pairs (phi_i, psi_i).

With the crank pivot A at the origin, the rocker pivot D = (d, 0), crank a = |AB|, coupler b = |BC|,
rocker c = |DC|, and both angles measured from the line A -> D, the loop |C - B| = b gives
(Freudenstein 1955)

    K1 cos(psi) - K2 cos(phi) + K3 = cos(phi - psi),
    K1 = d / a,  K2 = d / c,  K3 = (a^2 - b^2 + c^2 + d^2) / (2 a c),

linear in K1, K2, K3: three pairs give them exactly (a 3x3 solve), more pairs by least squares on this
equation, then polished on the output-angle error itself. A negative a (or c) is a crank (rocker)
pointing the other way: its link angle is phi + pi (psi + pi), reported as ``input_offset`` and
``output_offset``; b^2 <= 0 means no four-bar satisfies the pairs.

A design is kept only if the crank meets the pairs in their order turning one way, on one branch of the
loop, assembling everywhere in between (else its ``defect`` says which pair breaks it).

Between the pairs the function wanted is their interpolant (:func:`target_function`: the cubic spline
through them against the crank's travel, not-a-knot; three pairs: the parabola through them), so the
*structural error* over the working range is the linkage's output angle minus that interpolant at every
crank angle from the first pair to the last; the precision pairs alone say nothing about it.

Where only the function's increments matter (the pairs' angles measured from any zero), the start angles
phi0, psi0 of input and output are free: :func:`search` tries a grid of them, each a Freudenstein solve,
keeps those whose closed-form measures meet the limits, ranks them by structural error, then size, and
polishes the best (Nelder-Mead on the start angles), every evaluation of the structural error counted
against one bound.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic._common import ParameterError
from analytic.synthesis.fourbar import Linkage, branch_of

__all__ = ["Function", "synthesize", "freudenstein", "output_angles", "target_function", "Candidate", "search",
           "POLISH_SHARE", "CLOSED_FORM_SAMPLES"]


@dataclass(frozen=True)
class Function:
    """A function generator. ``linkage``: the four-bar (A at the origin, D = (d, 0)); ``K``: (K1, K2, K3);
    ``input_offset``/``output_offset``: 0 or pi, the link angle minus the user's angle; ``errors``: per pair,
    the linkage's output angle minus psi_i [rad] (closed form on its branch); ``defect``: "" or why the
    crank cannot meet the pairs in order on one branch; ``polish_evaluations``: the output-angle polish's
    residual evaluations (more than three pairs)."""

    linkage: Linkage
    K: tuple[float, float, float]
    input_offset: float
    output_offset: float
    errors: np.ndarray
    defect: str
    exact: bool
    polish_evaluations: int = 0


def freudenstein(phi: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """(K1, K2, K3) from pairs [rad]: exact for three, least squares on Freudenstein's equation for more."""
    M = np.column_stack([np.cos(psi), -np.cos(phi), np.ones_like(phi)])
    rhs = np.cos(phi - psi)
    if len(phi) == 3:
        if abs(np.linalg.det(M)) < 1e-12:
            raise ParameterError("the three pairs make Freudenstein's equations singular (two pairs share an "
                                 "input or output cosine); choose other precision pairs")
        return np.linalg.solve(M, rhs)
    K, *_ = np.linalg.lstsq(M, rhs, rcond=None)
    return K


def _lengths(K, d):
    K1, K2, K3 = K
    if K1 == 0 or K2 == 0:
        return None
    a, c = d / K1, d / K2
    b2 = a * a + c * c + d * d - 2 * a * c * K3
    return (a, math.sqrt(b2), c) if b2 > 0 else None


def output_angles(a: float, b: float, c: float, d: float, phi: np.ndarray, branch: int) -> np.ndarray:
    """The rocker's link angle [rad] at crank link angles ``phi`` (lengths > 0, A at the origin, D = (d, 0)):
    C the intersection of the circles about B (radius b) and D (radius c) on ``branch`` (+1: C left of
    B -> D). NaN where the loop does not close."""
    Bx, By = a * np.cos(phi), a * np.sin(phi)
    ux, uy = d - Bx, -By
    L2 = ux * ux + uy * uy
    x = (b * b - c * c + L2) / (2 * L2)
    with np.errstate(invalid="ignore"):
        h = np.sqrt(b * b / L2 - x * x)
    Cx = Bx + x * ux - branch * h * uy
    Cy = By + x * uy + branch * h * ux
    return np.arctan2(Cy, Cx - d)


def _wrap(x):
    return (np.asarray(x) + np.pi) % (2 * np.pi) - np.pi


def _build(K, phi, psi, d):
    """The linkage for (K1, K2, K3) and the checks of the pairs; None if no four-bar has these K."""
    lengths = _lengths(K, d)
    if lengths is None:
        return None
    a, b, c = lengths
    off_in, off_out = (math.pi if a < 0 else 0.0), (math.pi if c < 0 else 0.0)
    a, c = abs(a), abs(c)
    ph = phi + off_in
    B = (a * math.cos(ph[0]), a * math.sin(ph[0]))
    C = (d + c * math.cos(psi[0] + off_out), c * math.sin(psi[0] + off_out))
    branch = branch_of(B, C, (d, 0.0))
    errors = _wrap(output_angles(a, b, c, d, ph, branch) - off_out - psi)
    sense = 1.0 if _wrap(phi[1] - phi[0]) >= 0 else -1.0
    link = Linkage((0.0, 0.0), (float(d), 0.0), float(a), float(b), float(c), float(b), 0.0, branch, float(ph[0]),
                   sense * 2 * math.pi)
    return link, off_in, off_out, errors


def _defect(phi, errors, tol) -> str:
    """Why the pairs are not met in order on one branch ("" if they are)."""
    bad = np.flatnonzero(~(np.abs(errors) <= tol))
    if bad.size:
        i = int(bad[0])
        return (f"pair {i + 1} lies on the other branch of the loop (or the loop cannot close there): the "
                f"linkage assembled for pair 1 cannot reach it")
    sense = 1.0 if _wrap(phi[1] - phi[0]) >= 0 else -1.0
    travel = np.mod(sense * (phi - phi[0]), 2 * np.pi)
    if np.any(np.diff(travel) <= 0):
        i = int(np.flatnonzero(np.diff(travel) <= 0)[0])
        return f"the crank turning one way meets pair {i + 2} before pair {i + 1} (an order defect)"
    return ""


def _passes(link, phi, errors, samples=721):
    """Whether the loop closes everywhere the crank travels from the first pair to the last."""
    sense = math.copysign(1.0, link.omega1)
    travel = np.mod(sense * (phi - phi[0]), 2 * np.pi)
    q = link.phi1_0 + sense * np.linspace(0.0, travel.max(), samples)
    out = output_angles(link.l1, link.l2, link.l3, link.D[0], q, link.branch)
    return bool(np.all(np.isfinite(out)))


def synthesize(phi, psi, ground: float = 1.0, tol: float = 1e-9, polish: bool = True) -> Function:
    """A four-bar with ground AD = ``ground`` whose rocker angle follows ``psi`` at crank angles ``phi``.

    Parameters
    ----------
    phi, psi : array_like
        Precision pairs [rad], angles from the line A -> D; at least three, all distinct.
    ground : float
        |AD| [any length unit; the linkage's lengths come out in it].
    tol : float
        [rad] the output-angle error within which a pair counts as met (for the branch check).
    polish : bool
        more than three pairs: polish Freudenstein's linear least squares on the output angle itself.

    Returns
    -------
    Function
        Raises ParameterError if no four-bar satisfies the pairs (b^2 <= 0, a singular system).
    """
    phi, psi = np.asarray(phi, dtype=float), np.asarray(psi, dtype=float)
    if phi.shape != psi.shape or phi.ndim != 1 or phi.size < 3:
        raise ParameterError(f"function synthesis needs at least 3 (input, output) pairs, got {phi.size}")
    if not (math.isfinite(ground) and ground > 0):
        raise ParameterError(f"ground={ground!r} must be a finite length > 0")
    K = freudenstein(phi, psi)
    exact = phi.size == 3
    built = _build(K, phi, psi, ground)
    if built is None:
        raise ParameterError(f"Freudenstein's K = ({K[0]:.6g}, {K[1]:.6g}, {K[2]:.6g}) give no four-bar "
                             f"(a crank or rocker of infinite length, or coupler length^2 <= 0)")
    nfev = 0
    if not exact and polish:
        built = _polish(K, phi, psi, ground, built)
        K, nfev = built[4], built[5]
        built = built[:4]
    link, off_in, off_out, errors = built
    defect = _defect(phi, errors, tol if exact else np.inf)
    if not defect and not _passes(link, phi, errors):
        defect = "the loop cannot close somewhere between the first and the last pair (the crank cannot travel)"
    return Function(link, tuple(float(k) for k in K), off_in, off_out, errors, defect, exact, int(nfev))


def _polish(K, phi, psi, d, built):
    """Least squares on the output-angle error itself, from Freudenstein's linear estimate."""
    from scipy.optimize import least_squares

    count = [0]

    def residual(k):
        count[0] += 1
        b = _build(k, phi, psi, d)
        if b is None:
            return np.full(phi.size, 10.0)
        return np.nan_to_num(b[3], nan=10.0)
    res = least_squares(residual, np.asarray(K, dtype=float), xtol=1e-15, ftol=1e-15, gtol=1e-15)
    best = _build(res.x, phi, psi, d)
    if best is None or np.sum(np.nan_to_num(best[3], nan=10.0) ** 2) > np.sum(np.nan_to_num(built[3], nan=10.0) ** 2):
        return (*built, np.asarray(K), count[0])
    return (*best, res.x, count[0])


def target_function(phi, psi):
    """The function wanted between the pairs: a callable giving the output angle [rad, unwrapped along the
    pairs] at crank angles in ``phi``'s frame, the cubic spline (not-a-knot) through the pairs against the
    crank's travel from the first pair in its turning sense (three pairs: the parabola through them). None
    where the travel does not meet the pairs in order (an order defect: no function to follow)."""
    from scipy.interpolate import CubicSpline
    phi, psi = np.asarray(phi, dtype=float), np.asarray(psi, dtype=float)
    sense = 1.0 if _wrap(phi[1] - phi[0]) >= 0 else -1.0
    t = np.mod(sense * (phi - phi[0]), 2 * np.pi)
    if np.any(np.diff(t) <= 0):
        return None
    psi_u = psi[0] + np.concatenate([[0.0], np.cumsum(_wrap(np.diff(psi)))])
    spline = CubicSpline(t, psi_u)
    p0 = float(phi[0])

    def target(q):
        # travel from the first pair; rounding just below 0 stays at 0 instead of wrapping to 2 pi
        tq = np.mod(sense * (np.asarray(q, dtype=float) - p0) + 1e-9, 2 * np.pi) - 1e-9
        return spline(tq)
    return target


CLOSED_FORM_SAMPLES = 61
"""Crank angles over the working range at which :func:`search` evaluates each candidate in closed form
(the returned designs are measured again by the general solver, at many more)."""
POLISH_SHARE = 0.2
"""Of :func:`search`'s evaluations, the share kept for polishing the best candidates' start angles."""


@dataclass(frozen=True)
class Candidate:
    """One (phi0, psi0) of :func:`search`: the start angles [rad] (the pairs' zero of input and output from
    the line A -> D), the :class:`Function` built from the shifted pairs, its closed-form structural error
    (max and rms |output - target| over the working range [rad]), least transmission angle [rad], size
    (bounding box's larger side of A, B, C, D over the range) and ``why`` ('' or the first limit broken)."""

    phi0: float
    psi0: float
    function: Function
    error_max: float
    error_rms: float
    mu_min: float
    size: float
    why: str


def _closed_form(f: Function, phi, psi, limits, mu_lim: float) -> tuple[float, float, float, float, str]:
    """(error max, error rms, mu min, size, why) of ``f`` over its working range, in closed form."""
    from analytic.synthesis import constraints as sc
    link = f.linkage
    a, b, c, d = link.l1, link.l2, link.l3, link.D[0]
    target = target_function(phi, psi)
    if f.defect or target is None:
        return math.inf, math.inf, 0.0, math.inf, f.defect or "an order defect"
    sense = math.copysign(1.0, link.omega1)
    travel = float(np.mod(sense * (phi[-1] - phi[0]), 2 * np.pi))
    q = link.phi1_0 + sense * np.linspace(0.0, travel, CLOSED_FORM_SAMPLES)      # link angles
    out = output_angles(a, b, c, d, q, link.branch)
    if not np.all(np.isfinite(out)):
        return math.inf, math.inf, 0.0, math.inf, "the loop cannot close over the working range"
    err = np.abs(_wrap(out - f.output_offset - target(q - f.input_offset)))
    bd2 = a * a + d * d - 2 * a * d * np.cos(q)
    mu = np.arccos(np.clip((b * b + c * c - bd2) / (2 * b * c), -1.0, 1.0))
    mu_min = float(np.min(np.minimum(mu, np.pi - mu)))
    xs = np.concatenate([[0.0, d], a * np.cos(q), d + c * np.cos(out)])
    ys = np.concatenate([[0.0, 0.0], a * np.sin(q), c * np.sin(out)])
    size = float(max(np.ptp(xs), np.ptp(ys)))
    links = (a, b, c, d)
    why = ""
    if mu_min < mu_lim:
        why = "transmission angle below --min-transmission"
    elif limits.max_size is not None and size > limits.max_size * (1 + sc.SLACK_REL):
        why = "size over --max-size"
    elif limits.min_link is not None and min(links) < limits.min_link * (1 - sc.SLACK_REL):
        why = "a link shorter than --min-link"
    elif limits.max_ratio is not None and max(links) > limits.max_ratio * min(links) * (1 + sc.SLACK_REL):
        why = "longest/shortest link over --max-ratio"
    elif limits.grashof != "any" and sc.grashof_type(*links) != limits.grashof:
        why = f"not a {limits.grashof}"
    return float(err.max()), float(np.sqrt(np.mean(err ** 2))), mu_min, size, why


def _candidate(inputs, outputs, phi0: float, psi0: float, ground: float, limits, mu_lim: float):
    """The :class:`Candidate` at start angles (phi0, psi0); None where no four-bar has the pairs."""
    phi, psi = inputs + phi0, outputs + psi0
    try:
        f = synthesize(phi, psi, ground, polish=False)
    except ParameterError:
        return None
    emax, erms, mu, size, why = _closed_form(f, phi, psi, limits, mu_lim)
    return Candidate(float(phi0), float(psi0), f, emax, erms, mu, size, why)


TIE = math.radians(0.01)
"""[rad] Structural errors within this of the best count as equal (0.01 deg: below what a linkage's pin
clearances let anyone measure), so the smallest of them is preferred to a larger one a hair more exact."""


def _compact_first(ranked: list[Candidate]) -> list[Candidate]:
    """``ranked`` (least error first) with the candidates within TIE of the best error moved to the front,
    smallest first: an error-first search otherwise grows the links without bound for a last 1e-4 deg."""
    if not ranked:
        return ranked
    ties = [c for c in ranked if c.error_max <= ranked[0].error_max + TIE]
    return sorted(ties, key=lambda c: c.size) + ranked[len(ties):]


def _same(c: Candidate, s: Candidate) -> bool:
    """One four-bar at one start: its lengths within 1e-6 of the ground and its crank's start angle alike."""
    a, b = c.function.linkage, s.function.linkage
    return (max(abs(a.l1 - b.l1), abs(a.l2 - b.l2), abs(a.l3 - b.l3)) <= 1e-6 * a.D[0] and a.branch == b.branch
            and abs(_wrap(a.phi1_0 - b.phi1_0)) <= 1e-6)


class _Spent(Exception):
    """The polish's evaluations are used up."""


def search(inputs, outputs, ground: float = 1.0, limits=None, evaluations: int = 2000,
           count: int = 1) -> tuple[list[Candidate], list[Candidate], dict]:
    """Function generators for pairs whose start angles are free: ``inputs``, ``outputs`` [rad] the pairs'
    angles from any zero; the crank's link angle is phi0 + input and the rocker's psi0 + output.

    A grid of side floor(sqrt((1 - POLISH_SHARE) evaluations)) over phi0, psi0 in [0, 2 pi) (each cell one
    Freudenstein solve and one closed-form evaluation), the cells meeting ``limits``
    (:class:`analytic.synthesis.constraints.Limits`; the pivots are fixed at A = (0, 0), D = (ground, 0), so
    regions are the caller's) ranked by structural error max (to 1e-9 rad, then the smaller size), the best
    ``count`` polished by Nelder-Mead on (phi0, psi0) sharing the remaining evaluations. No more than
    ``evaluations`` candidates are evaluated in all. Returns (kept best first, the best turned down with
    ``why``, {"evaluations", "grid", "polish_evaluations"})."""
    from analytic.synthesis import constraints as sc
    from scipy.optimize import minimize
    limits = limits or sc.Limits()
    inputs, outputs = np.asarray(inputs, dtype=float), np.asarray(outputs, dtype=float)
    evaluations, count = int(evaluations), int(count)
    if evaluations < 1:
        raise ParameterError(f"--evaluations {evaluations} must be >= 1")
    side = max(1, math.isqrt(int((1 - POLISH_SHARE) * evaluations)))
    angles = np.arange(side) * (2 * np.pi / side)
    mu_lim = math.radians(limits.min_transmission) - 1e-9
    cells = [_candidate(inputs, outputs, p0, s0, ground, limits, mu_lim) for p0 in angles for s0 in angles]
    used = side * side
    cells = [c for c in cells if c is not None]

    def rank(c: Candidate):
        return (round(c.error_max, 9), c.size)
    kept = _compact_first(sorted((c for c in cells if not c.why), key=rank))
    turned = sorted((c for c in cells if c.why), key=rank)
    polish_budget = evaluations - used
    seeds = []
    for c in kept:                                  # distinct seeds: the same four-bar found twice polished once
        if len(seeds) < count and not any(_same(c, s) for s in seeds):
            seeds.append(c)
    polished: list[Candidate] = []
    spent = 0
    for i, c0 in enumerate(seeds):
        cap = (polish_budget - spent) // (len(seeds) - i)
        best = [c0]
        n = [0]

        def objective(x):
            if n[0] >= cap:
                raise _Spent
            n[0] += 1
            c = _candidate(inputs, outputs, float(x[0]), float(x[1]), ground, limits, mu_lim)
            if c is None or c.why or c.size > c0.size * (1 + 1e-9):     # no larger than its seed: compact stays
                return 1e3
            if rank(c) < rank(best[0]):
                best[0] = c
            return c.error_max
        if cap > 0:
            step = 2 * np.pi / side / 2
            try:
                minimize(objective, [c0.phi0, c0.psi0], method="Nelder-Mead",
                         options={"maxfev": cap, "initial_simplex": [[c0.phi0, c0.psi0], [c0.phi0 + step, c0.psi0],
                                                                     [c0.phi0, c0.psi0 + step]],
                                  "xatol": 1e-10, "fatol": 1e-13})
            except _Spent:
                pass
        spent += n[0]
        polished.append(best[0])
    kept = polished + [c for c in kept if not any(c is s for s in seeds)]
    return kept, turned, {"evaluations": used + spent, "grid": used, "polish_evaluations": spent}
