"""RRPRR five-bar with two rotary drives: complex-vector and matrix methods (seed 003, section 2).

Notation of SPEC.md: ground pivots A = (0, 0) and D = (l1, 0); crank AB = l2 at phi2, crank DC = l4 at
phi4. Link 3 is pinned at B and slides through a block pinned at C: S = |BC|, theta3 = angle of B->C.
The output point P lies on link 3 at lp from B. The vector loop is

    l2 e^{i phi2} + S e^{i theta3} = l1 + l4 e^{i phi4}.

Complex-vector method: differentiate the loop and multiply by e^{-i theta3}; the real part gives the
sliding rate, the imaginary part the rotation (the Coriolis term 2 dS omega3 appears in the second
derivative). Matrix method: the real and imaginary rows of the differentiated loop form the linear
systems  J [dS, omega3]^T = K [omega2, omega4]^T  and
J [ddS, alpha3]^T = K [alpha2, alpha4]^T + dK [omega2, omega4]^T - dJ [dS, omega3]^T,  solved numerically.
The two share the position solution and must agree to rounding.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic._common import ParameterError, blockwise, check_finite, check_length, drive as _drive

__all__ = ["FiveBar", "FiveBarState", "solve", "drive", "METHODS"]

METHODS = ("complex", "matrix")


@dataclass(frozen=True)
class FiveBar:
    """Five-bar parameters (SPEC.md). Lengths [m], angles [rad], speeds [rad/s].

    Validation requires l1 > l2 + l4, so that B and C can never meet (S > 0 at every phase).
    """

    l1: float = 0.20
    l2: float = 0.06
    l4: float = 0.08
    lp: float = 0.30
    phi2_0: float = 0.0
    phi4_0: float = math.pi / 3
    omega2: float = 2.0 * math.pi
    omega4: float = 2.0 * math.pi
    alpha2: float = 0.0
    alpha4: float = 0.0

    def __post_init__(self):
        for name in ("l1", "l2", "l4", "lp"):
            object.__setattr__(self, name, check_length(name, getattr(self, name)))
        for name in ("phi2_0", "phi4_0", "omega2", "omega4", "alpha2", "alpha4"):
            object.__setattr__(self, name, check_finite(name, getattr(self, name)))
        if self.l1 <= self.l2 + self.l4:
            raise ParameterError(
                f"l1={self.l1:g} must exceed l2 + l4 = {self.l2 + self.l4:g}: otherwise B and C can meet "
                f"(S would reach 0); lengthen l1 or shorten the cranks")


@dataclass(frozen=True)
class FiveBarState:
    """Kinematic state of the five-bar; every field has the broadcast shape of the inputs.

    ``S, dS, ddS`` [m, m/s, m/s^2], ``theta3, omega3, alpha3`` [rad, rad/s, rad/s^2], point P [m, m/s,
    m/s^2]; ``xB..yC`` for drawing.
    """

    phi2: np.ndarray
    phi4: np.ndarray
    omega2: np.ndarray
    omega4: np.ndarray
    alpha2: np.ndarray
    alpha4: np.ndarray
    S: np.ndarray
    theta3: np.ndarray
    dS: np.ndarray
    omega3: np.ndarray
    ddS: np.ndarray
    alpha3: np.ndarray
    xP: np.ndarray
    yP: np.ndarray
    vxP: np.ndarray
    vyP: np.ndarray
    axP: np.ndarray
    ayP: np.ndarray
    xB: np.ndarray
    yB: np.ndarray
    xC: np.ndarray
    yC: np.ndarray

    @property
    def valid(self) -> np.ndarray:
        """True where S > 0 (always, for validated parameters)."""
        return np.isfinite(self.theta3)


OUTPUTS = ("S", "theta3", "dS", "omega3", "ddS", "alpha3",
           "xP", "yP", "vxP", "vyP", "axP", "ayP")
"""SPEC output names, in CSV column order."""


def drive(mech: FiveBar, t):
    """Both cranks' motion ``(phi2, phi4, omega2, omega4, alpha2, alpha4)`` at times ``t`` [s]."""
    phi2, omega2, alpha2 = _drive(mech.phi2_0, mech.omega2, mech.alpha2, t)
    phi4, omega4, alpha4 = _drive(mech.phi4_0, mech.omega4, mech.alpha4, t)
    return phi2, phi4, omega2, omega4, alpha2, alpha4


def solve(mech: FiveBar, phi2, phi4, omega2, omega4, alpha2=0.0, alpha4=0.0,
          method: str = "complex") -> FiveBarState:
    """Position, velocity and acceleration of link 3 and point P.

    Parameters
    ----------
    mech : FiveBar
    phi2, phi4, omega2, omega4, alpha2, alpha4 : array_like
        Both cranks' angles [rad], angular velocities [rad/s] and accelerations [rad/s^2]; broadcast.
    method : {"complex", "matrix"}
        Seed 003's complex-vector method (closed form) or its matrix method (2x2 linear solves).
    """
    if method not in METHODS:
        raise ParameterError(f"method={method!r} is not known: use one of {', '.join(METHODS)}")
    arrays = np.broadcast_arrays(*(np.asarray(x, dtype=float)
                                   for x in (phi2, phi4, omega2, omega4, alpha2, alpha4)))
    kernel = _complex_kernel if method == "complex" else _matrix_kernel
    return FiveBarState(**dict(zip(("phi2", "phi4", "omega2", "omega4", "alpha2", "alpha4"), arrays)),
                        **blockwise(kernel, mech, tuple(arrays)))


def _complex_kernel(mech, *inputs):
    return _kernel(mech, _complex, *inputs)


def _matrix_kernel(mech, *inputs):
    return _kernel(mech, _matrix, *inputs)


def _kernel(mech: FiveBar, rates, phi2, phi4, omega2, omega4, alpha2, alpha4) -> dict:
    """Positions, the chosen method's rates, and point P on 1-D arrays (see :func:`solve`)."""
    l1, l2, l4, lp = mech.l1, mech.l2, mech.l4, mech.lp
    c2, s2, c4, s4 = np.cos(phi2), np.sin(phi2), np.cos(phi4), np.sin(phi4)
    xB, yB = l2 * c2, l2 * s2
    xC, yC = l1 + l4 * c4, l4 * s4
    dx, dy = xC - xB, yC - yB
    S = np.sqrt(dx * dx + dy * dy)
    S = np.where(S > 1e-12 * l1, S, np.nan)      # B on C: theta3 undefined
    c3, s3 = dx / S, dy / S
    dS, omega3, ddS, alpha3 = rates(mech, c2, s2, c4, s4, S, c3, s3, omega2, omega4, alpha2, alpha4)

    # P = B + lp e^{i theta3}: v = vB + i lp omega3 e^{i theta3}, a = aB + lp (i alpha3 - omega3^2) e^{i theta3}.
    vxB, vyB = -l2 * omega2 * s2, l2 * omega2 * c2
    axB = -l2 * (alpha2 * s2 + omega2 * omega2 * c2)
    ayB = l2 * (alpha2 * c2 - omega2 * omega2 * s2)
    return dict(
        S=S, theta3=np.arctan2(s3, c3), dS=dS, omega3=omega3, ddS=ddS, alpha3=alpha3,
        xP=xB + lp * c3, yP=yB + lp * s3,
        vxP=vxB - lp * omega3 * s3, vyP=vyB + lp * omega3 * c3,
        axP=axB - lp * (alpha3 * s3 + omega3 * omega3 * c3),
        ayP=ayB + lp * (alpha3 * c3 - omega3 * omega3 * s3),
        xB=xB, yB=yB, xC=xC, yC=yC,
    )


def _complex(mech, c2, s2, c4, s4, S, c3, s3, omega2, omega4, alpha2, alpha4):
    """Complex-vector method: multiply the differentiated loop by e^{-i theta3}."""
    l2, l4 = mech.l2, mech.l4
    sin23, cos23 = s2 * c3 - c2 * s3, c2 * c3 + s2 * s3      # phi2 - theta3
    sin43, cos43 = s4 * c3 - c4 * s3, c4 * c3 + s4 * s3      # phi4 - theta3
    # (dS + i S omega3) = i l4 omega4 e^{i(phi4-theta3)} - i l2 omega2 e^{i(phi2-theta3)}
    dS = -l4 * omega4 * sin43 + l2 * omega2 * sin23
    omega3 = (l4 * omega4 * cos43 - l2 * omega2 * cos23) / S
    # (ddS - S w3^2) + i (S a3 + 2 dS w3) = l4 (i a4 - w4^2) e^{i(phi4-theta3)} - l2 (i a2 - w2^2) e^{i(phi2-theta3)}
    re = (-l4 * (alpha4 * sin43 + omega4 * omega4 * cos43)
          + l2 * (alpha2 * sin23 + omega2 * omega2 * cos23))
    im = (l4 * (alpha4 * cos43 - omega4 * omega4 * sin43)
          - l2 * (alpha2 * cos23 - omega2 * omega2 * sin23))
    ddS = re + S * omega3 * omega3
    alpha3 = (im - 2.0 * dS * omega3) / S
    return dS, omega3, ddS, alpha3


def _matrix(mech, c2, s2, c4, s4, S, c3, s3, omega2, omega4, alpha2, alpha4):
    """Matrix method: solve J x = K w and J a = K alpha + dK w - dJ x with 2x2 matrices per sample."""
    l2, l4 = mech.l2, mech.l4

    def mat(a, b, c, d):
        return np.stack([np.stack([a, b], -1), np.stack([c, d], -1)], -2)

    def vec(a, b):
        return np.stack([a, b], -1)[..., None]

    J = mat(c3, -S * s3, s3, S * c3)
    K = mat(l2 * s2, -l4 * s4, -l2 * c2, l4 * c4)
    w = vec(omega2, omega4)
    x = np.linalg.solve(J, K @ w)
    dS, omega3 = x[..., 0, 0], x[..., 1, 0]
    dJ = mat(-s3 * omega3, -dS * s3 - S * c3 * omega3, c3 * omega3, dS * c3 - S * s3 * omega3)
    dK = mat(l2 * c2 * omega2, -l4 * c4 * omega4, l2 * s2 * omega2, -l4 * s4 * omega4)
    a = np.linalg.solve(J, K @ vec(alpha2, alpha4) + dK @ w - dJ @ x)
    return dS, omega3, a[..., 0, 0], a[..., 1, 0]
