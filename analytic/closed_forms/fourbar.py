"""Four-bar linkage (crank-rocker family): closed-form position, velocity and acceleration.

Notation of SPEC.md (after seed 000): ground pivots A = (0, 0) and D = (l4, 0); crank AB = l1 at the
input angle phi1; coupler BC = l2 at phi2 (B->C); rocker DC = l3 at phi3 (D->C). The vector loop is

    l1 e^{i phi1} + l2 e^{i phi2} = l4 + l3 e^{i phi3}.                               (seed 000, 3-1)

Positions follow seed 000 (3-3 ... 3-12): eliminating phi2 gives E cos phi3 + F sin phi3 + G = 0,
solved with the half-angle substitution; phi2 then follows from the loop. Velocities and accelerations
follow the dot-product elimination of seed 002 (seed 000, 3-13 ... 3-22): the differentiated loop is
multiplied by e^{-i phi3} (or e^{-i phi2}) and its real part kept, which removes one unknown at a time.

Positions the crank cannot reach (the dyad B-C-D cannot close) come back as NaN; ``FourBarState.valid``
is the mask of the samples that assembled.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic._common import (AssemblyError, ParameterError, blockwise, check_branch, check_finite, check_length,
                      drive as _drive, fmt_deg)

__all__ = ["FourBar", "FourBarState", "Grashof", "CrankLimits", "solve", "grashof", "crank_limits",
           "check_reachable", "drive", "joints",
           "transmission_extremes"]


@dataclass(frozen=True)
class FourBar:
    """Four-bar parameters (SPEC.md). Lengths [m], angles [rad], speeds [rad/s].

    ``ex, ey`` locate the coupler point E in the coupler frame (origin B, x-axis B->C).
    ``branch`` = +1 puts C to the left of the directed line B->D.
    """

    l1: float = 0.10
    l2: float = 0.30
    l3: float = 0.25
    l4: float = 0.30
    ex: float = 0.15
    ey: float = 0.10
    branch: int = 1
    phi1_0: float = 0.0
    omega1: float = 2.0 * math.pi
    alpha1: float = 0.0

    def __post_init__(self):
        for name in ("l1", "l2", "l3", "l4"):
            object.__setattr__(self, name, check_length(name, getattr(self, name)))
        for name in ("ex", "ey", "phi1_0", "omega1", "alpha1"):
            object.__setattr__(self, name, check_finite(name, getattr(self, name)))
        object.__setattr__(self, "branch", check_branch("branch", self.branch))
        lengths = {"l1": self.l1, "l2": self.l2, "l3": self.l3, "l4": self.l4}
        longest = max(lengths, key=lengths.get)
        if 2.0 * lengths[longest] >= sum(lengths.values()):
            raise ParameterError(
                f"{longest}={lengths[longest]:g} is not shorter than the other three links together "
                f"({sum(lengths.values()) - lengths[longest]:g} m): the four-bar cannot be assembled; "
                f"shorten {longest} or lengthen the others")


@dataclass(frozen=True)
class FourBarState:
    """Kinematic state of a four-bar; every field has the broadcast shape of the inputs.

    Angles [rad] in (-pi, pi], angular velocities [rad/s], accelerations [rad/s^2], points [m],
    point velocities [m/s] and accelerations [m/s^2]. ``mu`` is the transmission angle in [0, pi/2].
    """

    phi1: np.ndarray
    omega1: np.ndarray
    alpha1: np.ndarray
    phi2: np.ndarray
    phi3: np.ndarray
    omega2: np.ndarray
    omega3: np.ndarray
    alpha2: np.ndarray
    alpha3: np.ndarray
    xE: np.ndarray
    yE: np.ndarray
    vxE: np.ndarray
    vyE: np.ndarray
    axE: np.ndarray
    ayE: np.ndarray
    mu: np.ndarray

    @property
    def valid(self) -> np.ndarray:
        """True where the linkage assembled (False where every output is NaN)."""
        return np.isfinite(self.phi3)


def joints(mech: FourBar, state: FourBarState) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """World positions [m] of the named points A, B, C, D, E of a solved state, for drawing and checks."""
    zero = np.zeros_like(state.phi1)
    return {"A": (zero, zero),
            "B": (mech.l1 * np.cos(state.phi1), mech.l1 * np.sin(state.phi1)),
            "C": (mech.l4 + mech.l3 * np.cos(state.phi3), mech.l3 * np.sin(state.phi3)),
            "D": (zero + mech.l4, zero),
            "E": (state.xE, state.yE)}


OUTPUTS = ("phi2", "phi3", "omega2", "omega3", "alpha2", "alpha3",
           "xE", "yE", "vxE", "vyE", "axE", "ayE", "mu")
"""SPEC output names, in CSV column order."""


def drive(mech: FourBar, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Crank motion ``(phi1, omega1, alpha1)`` at times ``t`` [s] from the mechanism's drive data."""
    return _drive(mech.phi1_0, mech.omega1, mech.alpha1, t)


def solve(mech: FourBar, phi1, omega1, alpha1=0.0) -> FourBarState:
    """Position, velocity and acceleration of every link and of the coupler point E.

    Parameters
    ----------
    mech : FourBar
    phi1, omega1, alpha1 : array_like
        Crank angle [rad], angular velocity [rad/s] and acceleration [rad/s^2]; broadcast together.

    Returns
    -------
    FourBarState
        Fields of the broadcast shape; NaN where the crank angle cannot be reached.
    """
    phi1, omega1, alpha1 = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (phi1, omega1, alpha1)))
    return FourBarState(phi1=phi1, omega1=omega1, alpha1=alpha1,
                        **blockwise(_kernel, mech, (phi1, omega1, alpha1)))


def _kernel(mech: FourBar, phi1, omega1, alpha1) -> dict:
    """The closed form on 1-D arrays (see :func:`solve`)."""
    l1, l2, l3, l4 = mech.l1, mech.l2, mech.l3, mech.l4
    c1, s1 = np.cos(phi1), np.sin(phi1)

    # Seed 000 (3-4 ... 3-7) in SPEC's convention: E cos(phi3) + F sin(phi3) + G = 0.
    e = (2.0 * l3) * (l4 - l1 * c1)
    f = (-2.0 * l1 * l3) * s1
    g = (l1 * l1 + l3 * l3 + l4 * l4 - l2 * l2) - (2.0 * l1 * l4) * c1
    disc = e * e + f * f - g * g
    # A sample exactly at a limit position may round to a tiny negative discriminant: clamp those to 0.
    unreachable = disc < -1e-13 * (2.0 * l3 * (l1 + l4)) ** 2
    root = np.sqrt(np.abs(disc))
    if unreachable.any():
        root[unreachable] = np.nan
    # tan(phi3/2) = num/den = (-F -+ sqrt(E^2+F^2-G^2)) / (G - E); the minus root is branch +1 (C left
    # of B->D). The half-angle identities give cos and sin of phi3 without more trigonometry.
    num = -f - mech.branch * root
    den = g - e
    nn, dd = num * num, den * den
    norm = nn + dd
    c3, s3 = (dd - nn) / norm, 2.0 * num * den / norm
    xB, yB = l1 * c1, l1 * s1
    xC, yC = l4 + l3 * c3, l3 * s3
    # |BC| = l2 by construction, so the coupler's direction cosines need no more trigonometry.
    c2, s2 = (xC - xB) / l2, (yC - yB) / l2

    # Velocities (seed 000 3-15, 3-17): real parts after multiplying by e^{-i phi2} and e^{-i phi3}.
    s12 = s1 * c2 - c1 * s2          # sin(phi1 - phi2)
    s13 = s1 * c3 - c1 * s3          # sin(phi1 - phi3)
    s32 = s3 * c2 - c3 * s2          # sin(phi3 - phi2)
    c12 = c1 * c2 + s1 * s2
    c13 = c1 * c3 + s1 * s3
    c23 = c2 * c3 + s2 * s3
    l1w1 = l1 * omega1
    omega2 = l1w1 * s13 / (l2 * s32)
    omega3 = l1w1 * s12 / (l3 * s32)

    # Accelerations (seed 000 3-20, 3-22).
    l1w1w1 = l1w1 * omega1
    l1a1 = l1 * alpha1
    l2w2w2 = l2 * omega2 * omega2
    l3w3w3 = l3 * omega3 * omega3
    alpha2 = (-l1a1 * s13 - l1w1w1 * c13 - l2w2w2 * c23 + l3w3w3) / (-l2 * s32)
    alpha3 = (l1a1 * s12 + l1w1w1 * c12 + l2w2w2 - l3w3w3 * c23) / (l3 * s32)

    # Coupler point E = B + ex u + ey u_perp, u = e^{i phi2}.
    rx = mech.ex * c2 - mech.ey * s2
    ry = mech.ex * s2 + mech.ey * c2
    w2w2 = omega2 * omega2
    return dict(
        phi2=np.arctan2(s2, c2), phi3=np.arctan2(s3, c3), omega2=omega2, omega3=omega3,
        alpha2=alpha2, alpha3=alpha3,
        xE=xB + rx, yE=yB + ry,
        vxE=-l1w1 * s1 - omega2 * ry, vyE=l1w1 * c1 + omega2 * rx,
        axE=-l1a1 * s1 - l1w1w1 * c1 - alpha2 * ry - w2w2 * rx,
        ayE=l1a1 * c1 - l1w1w1 * s1 + alpha2 * rx - w2w2 * ry,
        mu=np.arctan2(np.abs(s32), np.abs(c23)),     # acute angle between coupler and rocker
    )


@dataclass(frozen=True)
class Grashof:
    """Grashof classification of the chain and of the inversion with l4 as ground.

    ``chain``: ``"grashof"`` (s + l < p + q), ``"change-point"`` (equality) or ``"non-grashof"``.
    ``inversion``: ``"double-crank"``, ``"crank-rocker"`` (input l1 turns fully), ``"rocker-crank"``
    (output l3 turns fully), ``"double-rocker"`` or ``"triple-rocker"`` (non-Grashof).
    """

    chain: str
    inversion: str
    s: float
    l: float
    p: float
    q: float


def grashof(mech: FourBar, rtol: float = 1e-12) -> Grashof:
    """Classify the chain (s + l vs p + q) and the inversion by the position of the shortest link."""
    lengths = {"l1": mech.l1, "l2": mech.l2, "l3": mech.l3, "l4": mech.l4}
    s, p, q, l = sorted(lengths.values())
    margin = (p + q) - (s + l)
    if abs(margin) <= rtol * (p + q):
        chain = "change-point"
    elif margin > 0:
        chain = "grashof"
    else:
        chain = "non-grashof"
    shortest = {k for k, v in lengths.items() if abs(v - s) <= rtol * s}
    if chain == "non-grashof":
        inversion = "triple-rocker"
    elif "l4" in shortest or {"l1", "l3"} <= shortest:
        inversion = "double-crank"
    elif "l1" in shortest:
        inversion = "crank-rocker"
    elif "l3" in shortest:
        inversion = "rocker-crank"
    else:
        inversion = "double-rocker"
    return Grashof(chain=chain, inversion=inversion, s=s, l=l, p=p, q=q)


@dataclass(frozen=True)
class CrankLimits:
    """Where the crank can be. ``intervals`` are closed ranges ``(lo, hi)`` [rad], lo < hi, in which the
    linkage assembles; ``limit_angles`` are their ends in (-pi, pi] (dead-centre positions: coupler and
    rocker collinear). A crank that turns fully has one interval of width 2 pi and no limit angles."""

    full_turn: bool
    intervals: tuple[tuple[float, float], ...]
    limit_angles: tuple[float, ...]


def crank_limits(mech: FourBar) -> CrankLimits:
    """The crank's reachable range, from |BD| having to lie in [|l2 - l3|, l2 + l3].

    |BD|^2 = l1^2 + l4^2 - 2 l1 l4 cos(phi1) is monotonic in |phi1|, so the reachable set is
    |phi1| in [a, b] with cos a = (l1^2 + l4^2 - (l2 - l3)^2) / (2 l1 l4) and
    cos b = (l1^2 + l4^2 - (l2 + l3)^2) / (2 l1 l4), each clipped to [-1, 1].
    """
    l1, l2, l3, l4 = mech.l1, mech.l2, mech.l3, mech.l4
    cmax = (l1 * l1 + l4 * l4 - (l2 - l3) ** 2) / (2.0 * l1 * l4)
    cmin = (l1 * l1 + l4 * l4 - (l2 + l3) ** 2) / (2.0 * l1 * l4)
    a = math.acos(min(max(cmax, -1.0), 1.0))
    b = math.acos(min(max(cmin, -1.0), 1.0))
    if a == 0.0 and b == math.pi:
        return CrankLimits(True, ((mech.phi1_0, mech.phi1_0 + 2.0 * math.pi),), ())
    if a == 0.0:
        return CrankLimits(False, ((-b, b),), (-b, b))
    if b == math.pi:
        return CrankLimits(False, ((a, 2.0 * math.pi - a),), (a, -a))
    return CrankLimits(False, ((-b, -a), (a, b)), (-b, -a, a, b))


def transmission_extremes(mech: FourBar) -> tuple[float, float]:
    """Exact (min, max) of the transmission angle mu [rad] over every reachable crank angle.

    mu depends on the diagonal |BD| alone: cos(angle BCD) = (l2^2 + l3^2 - BD^2) / (2 l2 l3), monotonic in
    BD, and BD ranges over [max(|l4 - l1|, |l2 - l3|), min(l1 + l4, l2 + l3)] as the crank moves.
    """
    l1, l2, l3, l4 = mech.l1, mech.l2, mech.l3, mech.l4
    lo, hi = max(abs(l4 - l1), abs(l2 - l3)), min(l1 + l4, l2 + l3)
    cos_ends = [(l2 * l2 + l3 * l3 - bd * bd) / (2.0 * l2 * l3) for bd in (lo, hi)]
    mu_min = math.acos(min(1.0, max(abs(c) for c in cos_ends)))
    crosses = cos_ends[0] >= 0.0 >= cos_ends[1]
    mu_max = math.pi / 2 if crosses else math.acos(min(1.0, min(abs(c) for c in cos_ends)))
    return mu_min, mu_max


def check_reachable(mech: FourBar, phi1) -> None:
    """Raise AssemblyError naming the first crank angle [rad] that cannot be reached, and the range."""
    phi1 = np.atleast_1d(np.asarray(phi1, dtype=float))
    state = solve(mech, phi1, 0.0)
    bad = ~state.valid
    if bad.any():
        first = float(phi1.ravel()[np.argmax(bad.ravel())])
        raise AssemblyError(
            f"the four-bar cannot be assembled at phi1={fmt_deg(first)}: the crank reaches only "
            f"{describe_range(crank_limits(mech))}")


def describe_range(limits: CrankLimits) -> str:
    """The reachable crank range in words, e.g. ``'-41.41deg..41.41deg'``."""
    if limits.full_turn:
        return "every angle"
    return " or ".join(f"{fmt_deg(lo)}..{fmt_deg(hi)}" for lo, hi in limits.intervals)
