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
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic._common import ParameterError
from analytic.synthesis.fourbar import Linkage, branch_of

__all__ = ["Function", "synthesize", "freudenstein", "output_angles"]


@dataclass(frozen=True)
class Function:
    """A function generator. ``linkage``: the four-bar (A at the origin, D = (d, 0)); ``K``: (K1, K2, K3);
    ``input_offset``/``output_offset``: 0 or pi, the link angle minus the user's angle; ``errors``: per pair,
    the linkage's output angle minus psi_i [rad] (closed form on its branch); ``defect``: "" or why the
    crank cannot meet the pairs in order on one branch."""

    linkage: Linkage
    K: tuple[float, float, float]
    input_offset: float
    output_offset: float
    errors: np.ndarray
    defect: str
    exact: bool


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


def synthesize(phi, psi, ground: float = 1.0, tol: float = 1e-9) -> Function:
    """A four-bar with ground AD = ``ground`` whose rocker angle follows ``psi`` at crank angles ``phi``.

    Parameters
    ----------
    phi, psi : array_like
        Precision pairs [rad], angles from the line A -> D; at least three, all distinct.
    ground : float
        |AD| [any length unit; the linkage's lengths come out in it].
    tol : float
        [rad] the output-angle error within which a pair counts as met (for the branch check).

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
    if not exact:
        built = _polish(K, phi, psi, ground, built)
        K = built[4]
        built = built[:4]
    link, off_in, off_out, errors = built
    defect = _defect(phi, errors, tol if exact else np.inf)
    if not defect and not _passes(link, phi, errors):
        defect = "the loop cannot close somewhere between the first and the last pair (the crank cannot travel)"
    return Function(link, tuple(float(k) for k in K), off_in, off_out, errors, defect, exact)


def _polish(K, phi, psi, d, built):
    """Least squares on the output-angle error itself, from Freudenstein's linear estimate."""
    from scipy.optimize import least_squares

    def residual(k):
        b = _build(k, phi, psi, d)
        if b is None:
            return np.full(phi.size, 10.0)
        return np.nan_to_num(b[3], nan=10.0)
    res = least_squares(residual, np.asarray(K, dtype=float), xtol=1e-15, ftol=1e-15, gtol=1e-15)
    best = _build(res.x, phi, psi, d)
    if best is None or np.sum(np.nan_to_num(best[3], nan=10.0) ** 2) > np.sum(np.nan_to_num(built[3], nan=10.0) ** 2):
        return (*built, np.asarray(K))
    return (*best, res.x)
