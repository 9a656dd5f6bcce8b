"""Six-bar shaper: crank + slotted guide bar (loop 1) followed by a slider-crank ram (loop 2).

Notation of SPEC.md (after seed 000, chapter 5): guide-bar pivot O4 = (0, 0), crank pivot O2 = (0, l6).
The crank O2A = l1 turns at phi1; a block pinned at A slides along the guide bar O4B (length l3) at
s = |O4A|, phi3 = angle of O4->B. The rod BC = l4 (phi4 = angle of B->C) drives the ram C along y = h.

Loop 1 (guide bar):   s e^{i phi3} = i l6 + l1 e^{i phi1}
    velocity:  (ds + i s omega3) e^{i phi3} = i l1 omega1 e^{i phi1}
    accel.:    (dds - s omega3^2 + i (s alpha3 + 2 ds omega3)) e^{i phi3} = l1 (i alpha1 - omega1^2) e^{i phi1}
  each multiplied by e^{-i phi3}: the real part gives the sliding terms, the imaginary part the rotation;
  2 ds omega3 is the Coriolis term.
Loop 2 (ram):        l3 e^{i phi3} + l4 e^{i phi4} = xC + i h
  the imaginary part gives phi4, the real part xC; differentiated twice for the rates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic._common import ParameterError, blockwise, check_branch, check_finite, check_length, drive as _drive

__all__ = ["SixBar", "SixBarState", "Shaper", "solve", "figures", "drive", "default_h"]


def default_h(l1: float, l6: float, l3: float) -> float:
    """SPEC's ram height: the ram line halves the sagitta of B's arc, h = l3 (1 + cos psi) / 2,
    sin psi = l1 / l6 [m]."""
    return l3 * (1.0 + math.sqrt(1.0 - (l1 / l6) ** 2)) / 2.0


@dataclass(frozen=True)
class SixBar:
    """Shaper parameters (SPEC.md). Lengths [m], angles [rad], speeds [rad/s].

    ``h`` (the ram line's height) defaults to :func:`default_h` of the link lengths when left as None.
    ``branch`` = +1 puts the ram C to the right of B.
    """

    l6: float = 0.38
    l1: float = 0.11
    l3: float = 0.54
    l4: float = 0.135
    h: float | None = None
    branch: int = 1
    phi1_0: float = 0.0
    omega1: float = 2.0 * math.pi
    alpha1: float = 0.0

    def __post_init__(self):
        for name in ("l6", "l1", "l3", "l4"):
            object.__setattr__(self, name, check_length(name, getattr(self, name)))
        if self.l1 >= self.l6:
            raise ParameterError(
                f"l1={self.l1:g} must be shorter than l6={self.l6:g}: otherwise the guide bar does not "
                f"swing (s would reach 0 at O4); choose l1 < l6")
        if self.l6 + self.l1 > self.l3:
            raise ParameterError(
                f"l3={self.l3:g} is shorter than l6 + l1 = {self.l6 + self.l1:g}: the block would run off "
                f"the guide bar; make l3 >= {self.l6 + self.l1:g}")
        if self.h is None:
            object.__setattr__(self, "h", default_h(self.l1, self.l6, self.l3))
        for name in ("h", "phi1_0", "omega1", "alpha1"):
            object.__setattr__(self, name, check_finite(name, getattr(self, name)))
        object.__setattr__(self, "branch", check_branch("branch", self.branch))
        # B moves on the arc of radius l3 between the guide's limit angles pi/2 -+ psi.
        y_lo = self.l3 * math.sqrt(1.0 - (self.l1 / self.l6) ** 2)
        reach = max(abs(self.h - y_lo), abs(self.h - self.l3))
        if reach >= self.l4:
            raise ParameterError(
                f"l4={self.l4:g} cannot reach the ram line y=h={self.h:g} from every position of B "
                f"(needs l4 > {reach:.6g} m); lengthen l4 or move h between {y_lo:.6g} and {self.l3:.6g}")


@dataclass(frozen=True)
class SixBarState:
    """Kinematic state of the shaper; every field has the broadcast shape of the inputs.

    ``s, ds, dds`` [m, m/s, m/s^2] slide the block along the guide bar; ``phi3, phi4`` [rad] with their
    rates; ``xC, vxC, axC`` the ram; ``xA..yB`` the points A and B [m] for drawing.
    """

    phi1: np.ndarray
    omega1: np.ndarray
    alpha1: np.ndarray
    s: np.ndarray
    phi3: np.ndarray
    phi4: np.ndarray
    xC: np.ndarray
    ds: np.ndarray
    omega3: np.ndarray
    omega4: np.ndarray
    vxC: np.ndarray
    dds: np.ndarray
    alpha3: np.ndarray
    alpha4: np.ndarray
    axC: np.ndarray
    xA: np.ndarray
    yA: np.ndarray
    xB: np.ndarray
    yB: np.ndarray

    @property
    def valid(self) -> np.ndarray:
        """True where both loops closed (validated parameters always close; kept for symmetry)."""
        return np.isfinite(self.xC)


OUTPUTS = ("s", "phi3", "phi4", "xC", "ds", "omega3", "omega4", "vxC",
           "dds", "alpha3", "alpha4", "axC")
"""SPEC output names, in CSV column order."""


def drive(mech: SixBar, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Crank motion ``(phi1, omega1, alpha1)`` at times ``t`` [s] from the mechanism's drive data."""
    return _drive(mech.phi1_0, mech.omega1, mech.alpha1, t)


def solve(mech: SixBar, phi1, omega1, alpha1=0.0) -> SixBarState:
    """Position, velocity and acceleration of the guide bar, rod and ram.

    Parameters
    ----------
    mech : SixBar
    phi1, omega1, alpha1 : array_like
        Crank angle [rad], angular velocity [rad/s] and acceleration [rad/s^2]; broadcast together.
    """
    phi1, omega1, alpha1 = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (phi1, omega1, alpha1)))
    return SixBarState(phi1=phi1, omega1=omega1, alpha1=alpha1,
                       **blockwise(_kernel, mech, (phi1, omega1, alpha1)))


def _kernel(mech: SixBar, phi1, omega1, alpha1) -> dict:
    """Both loops on 1-D arrays (see :func:`solve`)."""
    l1, l3, l4, l6, h = mech.l1, mech.l3, mech.l4, mech.l6, mech.h
    c1, s1 = np.cos(phi1), np.sin(phi1)

    # Loop 1: the block A on the guide bar.
    xA, yA = l1 * c1, l6 + l1 * s1
    s = np.sqrt(xA * xA + yA * yA)
    c3, s3 = xA / s, yA / s
    sin13 = s1 * c3 - c1 * s3            # sin(phi1 - phi3)
    cos13 = c1 * c3 + s1 * s3
    ds = -l1 * omega1 * sin13
    omega3 = l1 * omega1 * cos13 / s
    re = -l1 * (alpha1 * sin13 + omega1 * omega1 * cos13)
    im = l1 * (alpha1 * cos13 - omega1 * omega1 * sin13)
    dds = re + s * omega3 * omega3
    alpha3 = (im - 2.0 * ds * omega3) / s

    # Loop 2: the ram. B = l3 e^{i phi3}; yB + l4 sin(phi4) = h.
    xB, yB = l3 * c3, l3 * s3
    vxB, vyB = -l3 * omega3 * s3, l3 * omega3 * c3
    axB = -l3 * (alpha3 * s3 + omega3 * omega3 * c3)
    ayB = l3 * (alpha3 * c3 - omega3 * omega3 * s3)
    s4 = (h - yB) / l4
    c4 = mech.branch * np.sqrt(1.0 - s4 * s4)
    omega4 = -vyB / (l4 * c4)
    alpha4 = (-ayB + l4 * s4 * omega4 * omega4) / (l4 * c4)
    return dict(
        s=s, phi3=np.arctan2(s3, c3), phi4=np.arctan2(s4, c4), xC=xB + l4 * c4,
        ds=ds, omega3=omega3, omega4=omega4, vxC=vxB - l4 * s4 * omega4,
        dds=dds, alpha3=alpha3, alpha4=alpha4, axC=axB - l4 * (s4 * alpha4 + c4 * omega4 * omega4),
        xA=xA, yA=yA, xB=xB, yB=yB,
    )


@dataclass(frozen=True)
class Shaper:
    """Figures of merit of the shaper.

    ``psi`` [rad]: half the guide's swing, sin psi = l1/l6; ``swing`` = 2 psi [rad] is the guide bar's
    swing angle and also the crank angle between the two limit positions (theta); ``K`` the quick-return
    ratio (pi + theta) / (pi - theta); ``stroke`` H [m] the ram's travel; ``phi1_limits`` [rad] the crank
    angles of the two limit positions (guide at its right and left extremes); ``xC_limits`` [m] the ram
    positions there.
    """

    psi: float
    swing: float
    K: float
    stroke: float
    phi1_limits: tuple[float, float]
    xC_limits: tuple[float, float]


def figures(mech: SixBar) -> Shaper:
    """Swing angle, quick-return ratio and stroke.

    The guide bar is at a limit when the crank is perpendicular to it: phi1 = -psi (right) and
    pi + psi (left). The stroke is max - min of xC over the guide's swing, evaluated on a fine grid of
    phi3 plus the two limits (xC depends on phi3 alone), so it is exact for a ram monotonic in phi3
    (the usual case) and accurate to O(grid^2) otherwise.
    """
    psi = math.asin(mech.l1 / mech.l6)
    theta = 2.0 * psi
    limits = (-psi, math.pi + psi)
    phi3 = np.linspace(math.pi / 2 - psi, math.pi / 2 + psi, 20001)
    yB = mech.l3 * np.sin(phi3)
    xC = mech.l3 * np.cos(phi3) + mech.branch * np.sqrt(mech.l4 ** 2 - (mech.h - yB) ** 2)
    return Shaper(psi=psi, swing=theta, K=(math.pi + theta) / (math.pi - theta),
                  stroke=float(xC.max() - xC.min()), phi1_limits=limits,
                  xC_limits=(float(xC[0]), float(xC[-1])))
