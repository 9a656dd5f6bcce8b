"""How the inputs move: the one motion law of a driven input (:class:`Motion`) and the input itself
(:class:`Input`: a crank's angle or a slider's distance, with its column names)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic import kinds
from analytic._common import ParameterError


@dataclass(frozen=True)
class Motion:
    """The one motion law of a driven input: q(t) = q0 + rate t + accel t^2 / 2 (SPEC), or, with
    ``rock = (lo, hi)``, a rocking drive q(t) = mid - amp cos(|rate| t) that starts at rest at ``lo``
    (``rate`` then a frequency [rad/s]: a crank's own speed, a slider's speed over the mechanism's size, set by
    ``Mechanism.inputs``)."""

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
    """A driven input: a crank (angle of its link, rad), a slider (distance along its guide, m), or any input
    kind of :mod:`analytic.kinds` (``kind``: its name; what it is, ask :attr:`spec`).

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
    def spec(self):
        """Its kind (:class:`analytic.kinds.base.Kind`): what its coordinate is, its units, its drive."""
        return kinds.get(self.kind)

    @property
    def angular(self) -> bool:
        """Whether its coordinate is an angle (rad) rather than a length (m): asked of its kind."""
        return self.spec.angular

    @property
    def q(self) -> str:
        return self.spec.columns[0] + self.link

    @property
    def qd(self) -> str:
        return self.spec.columns[1] + self.link

    @property
    def qdd(self) -> str:
        return self.spec.columns[2] + self.link

    @property
    def unit(self) -> str:
        return self.spec.unit

    @property
    def turn(self) -> float:
        """One 'revolution' of this input: 2 pi for a crank; for a slider, its travel in one second."""
        return self.spec.turn(self.motion.rate)
