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
            q += self.q0                              # the law's own array
            return q, v, a
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
            q += self.q0                              # the law's own array
            return q, v, a, j
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

    def time_at(self, value: float, turn: float, until: float) -> float | None:
        """The first time t in [0, ``until``] at which q(t) passes ``value`` (or ``value`` + k ``turn`` for a
        crank, ``turn`` = 2 pi; 0 for a slide); None when it does not. Exact for a constant speed and for a
        rocking drive (q = mid - amp cos(w t), on its way up from ``lo``, within a part in 1e12 of its ends);
        else the first crossing on 4096 steps of the cycle, bisected to the last bit."""
        targets = [value]
        if self.rock is not None:
            lo, hi = self.rock
            w, amp, mid = abs(self.rate), 0.5 * (hi - lo), 0.5 * (lo + hi)
            if turn:
                targets = [value + k * turn for k in range(math.floor((lo - value) / turn) - 1,
                                                            math.ceil((hi - value) / turn) + 2)]
            slack = 1e-12 * max(abs(lo), abs(hi), amp)
            inside = [v for v in targets if lo - slack <= v <= hi + slack]
            if not inside or w == 0.0:
                return None
            t = min(math.acos(min(1.0, max(-1.0, (mid - v) / amp))) / w for v in inside)
            return t if t <= until else None
        if self.constant and self.rate != 0.0 and not turn:
            t = (value - self.q0) / self.rate
            return t if 0.0 <= t <= until else None
        grid = np.linspace(0.0, until, 4097)
        q = self.at(grid)[0]
        if turn:
            targets = [value + k * turn for k in range(math.floor((float(q.min()) - value) / turn),
                                                        math.ceil((float(q.max()) - value) / turn) + 1)]
        best = None
        for v in targets:
            d = q - v
            hit = np.flatnonzero((d[:-1] == 0.0) | (np.sign(d[:-1]) * np.sign(d[1:]) < 0) | (d[1:] == 0.0))
            if not len(hit):
                continue
            i = int(hit[0])
            if d[i] == 0.0:
                t = float(grid[i])
            elif d[i + 1] == 0.0:
                t = float(grid[i + 1])
            else:
                a, b, da = float(grid[i]), float(grid[i + 1]), float(d[i])
                for _ in range(200):                     # bisection down to adjacent floats
                    mid_t = 0.5 * (a + b)
                    if mid_t in (a, b):
                        break
                    dm = float(self.at(mid_t)[0]) - v
                    if dm == 0.0:
                        a = b = mid_t
                        break
                    if (dm < 0) == (da < 0):
                        a, da = mid_t, dm
                    else:
                        b = mid_t
                t = a if abs(float(self.at(a)[0]) - v) <= abs(float(self.at(b)[0]) - v) else b
            best = t if best is None else min(best, t)
        return best

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
