"""Shared helpers for the analytic solvers: validation, input motion, angle wrapping."""

from __future__ import annotations

import math

import numpy as np


class ParameterError(ValueError):
    """An invalid mechanism parameter; the message is one line that names it and the fix."""


class AssemblyError(ParameterError):
    """A mechanism that cannot be assembled (or locks) at a requested input position."""


def check_length(name: str, value: float) -> float:
    """Return ``value`` as float if it is a finite positive length [m], else raise."""
    v = _finite(name, value)
    if v <= 0.0:
        raise ParameterError(f"{name}={value!r} is not a valid length: it must be finite and > 0 [m]")
    return v


def check_finite(name: str, value: float) -> float:
    """Return ``value`` as float if it is finite, else raise."""
    return _finite(name, value)


def check_branch(name: str, value: int) -> int:
    """Return the assembly branch (+1 or -1), else raise."""
    if value not in (1, -1):
        raise ParameterError(f"{name}={value!r} is not a valid branch: use +1 or -1")
    return int(value)


def _finite(name: str, value: float) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name}={value!r} is not a number") from None
    if not math.isfinite(v):
        raise ParameterError(f"{name}={value!r} must be a finite number")
    return v


def drive(phi_0: float, omega: float, alpha: float, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Input motion phi(t) = phi_0 + omega t + alpha t^2 / 2 (SPEC conventions).

    Returns ``(phi [rad], omega [rad/s], alpha [rad/s^2])`` broadcast to the shape of ``t`` [s].
    """
    t = np.asarray(t, dtype=float)
    return (phi_0 + omega * t + 0.5 * alpha * t * t,
            omega + alpha * t,
            np.full_like(t, alpha))


def wrap(angle: np.ndarray) -> np.ndarray:
    """Wrap angles [rad] to (-pi, pi]."""
    return np.pi - np.mod(np.pi - np.asarray(angle, dtype=float), 2.0 * np.pi)


def fmt_deg(angle: float) -> str:
    """An angle [rad] written in degrees for messages, e.g. ``'41.41deg'``."""
    return f"{math.degrees(angle):.2f}deg"
