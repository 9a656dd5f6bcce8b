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
    ``Mechanism.inputs``), or, with ``law`` (an :class:`analytic.laws.Profile` or :class:`~analytic.laws.Table`,
    SPEC "Motion laws"), q(t) = q0 + law(t), its cycle the law's duration (``rate`` then the law's mean speed
    over a cycle, or where it returns to its start, the sense of its first move times its mean |speed|)."""

    q0: float
    rate: float
    accel: float = 0.0
    rock: tuple[float, float] | None = None
    law: object = None

    @property
    def constant(self) -> bool:
        """Whether the input moves at the constant speed ``rate`` (no acceleration, not rocking, no law)."""
        return self.rock is None and self.law is None and self.accel == 0.0

    def at(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(q, dq/dt, d2q/dt2) at times ``t`` [s], broadcast to the shape of ``t``."""
        t = np.asarray(t, dtype=float)
        if self.law is not None and self.rock is None:
            q, v, a, _ = self.law.at(t, jerk=False)
            return self.q0 + q, v, a
        if self.rock is not None:
            lo, hi = self.rock
            w, amp = abs(self.rate), 0.5 * (hi - lo)
            return (0.5 * (lo + hi) - amp * np.cos(w * t), amp * w * np.sin(w * t), amp * w * w * np.cos(w * t))
        return (self.q0 + self.rate * t + 0.5 * self.accel * t * t, self.rate + self.accel * t,
                np.full_like(t, self.accel))

    def at_with_jerk(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(q, dq/dt, d2q/dt2, d3q/dt3) at times ``t`` [s], a law evaluated once."""
        if self.law is not None and self.rock is None:
            q, v, a, j = self.law.at(t)
            return self.q0 + q, v, a, j
        return (*self.at(t), self.jerk(t))

    def jerk(self, t) -> np.ndarray:
        """d3q/dt3 at times ``t`` [s] (zero for a constant acceleration)."""
        t = np.asarray(t, dtype=float)
        if self.law is not None and self.rock is None:
            return self.law.at(t)[3]
        if self.rock is not None:
            w, amp = abs(self.rate), 0.5 * (self.rock[1] - self.rock[0])
            return -amp * w ** 3 * np.sin(w * t)
        return np.zeros_like(t)

    def duration(self, cycles: float, turn: float) -> float:
        """Time [s] for ``cycles`` turns of size ``turn`` (2 pi for a crank): the smallest t > 0 with
        |q(t) - q0| = cycles * turn; for a rocking drive, ``cycles`` periods 2 pi / |rate|; for a law,
        ``cycles`` of its cycles."""
        if not (math.isfinite(cycles) and cycles > 0):
            raise ParameterError(f"revolutions={cycles!r} must be a finite number > 0")
        if self.law is not None and self.rock is None:
            return cycles * self.law.duration
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


def law_rate(law) -> float:
    """The ``rate`` of a motion with ``law``: its mean speed over a cycle, or where the cycle returns to
    its start, the sense of its first move times the mean of its |speed|."""
    if law.rise != 0.0:
        return law.rise / law.duration
    t = np.linspace(0.0, law.duration, 2001)
    v = law.at(t)[1]
    moving = np.flatnonzero(np.abs(v) > 1e-12 * max(np.abs(v).max(), 1e-300))
    if not len(moving):
        return 0.0
    return math.copysign(float(np.mean(np.abs(v))), v[moving[0]])


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
    def qddd(self) -> str:
        """Its jerk column: ``j`` + its coordinate's (``jphi1``, ``jsJ``; SPEC "Motion laws")."""
        return "j" + self.q

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
