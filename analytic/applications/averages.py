"""Averages and integrals over one cycle, each sample interval counted once.

A run sampled at ``linspace(0, T, n)`` holds both ends of the closed interval [0, T]: for a periodic
quantity the last sample repeats the first, and a plain ``np.mean`` counts that instant twice (a bias of
(y[0] - mean) / n). A simulated run holds whole time steps and so ends slightly past one turn. The
functions here weight each sample by the interval it stands for (the trapezoid rule), and a timed run is
cut at exactly one period (the value at the cut interpolated linearly), so a mean over a turn is the mean
over that turn whatever the number of samples.
"""

from __future__ import annotations

import numpy as np


def closed_mean(y, axis: int = -1):
    """Mean over the closed interval sampled evenly by ``y`` (ends included), by the trapezoid rule: the
    end samples count half. Samples that are not finite (poses that do not assemble) are left out, each
    interval being counted only where both of its ends are finite."""
    y = np.moveaxis(np.asarray(y, dtype=float), axis, -1)
    if y.shape[-1] < 2:
        return np.nanmean(y, axis=-1)
    ok = np.isfinite(y)
    z = np.where(ok, y, 0.0)
    both = ok[..., 1:] & ok[..., :-1]                       # an interval counts where both ends are known
    area = np.sum(np.where(both, 0.5 * (z[..., 1:] + z[..., :-1]), 0.0), axis=-1)
    count = np.sum(both, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.where(count > 0, area / np.maximum(count, 1), np.nan)
    single = (count == 0) & (np.sum(ok, axis=-1) > 0)        # isolated finite samples: their plain mean
    if np.any(single):
        out = np.where(single, np.nanmean(np.where(ok, y, np.nan), axis=-1), out)
    return out if np.ndim(out) else float(out)


def closed_weights(n: int) -> np.ndarray:
    """The trapezoid weights of ``n`` evenly spaced samples of a closed interval (ends 1/2, others 1),
    summing to n - 1: the weights of a least-squares fit over a cycle, each instant counted once."""
    w = np.ones(n)
    if n >= 2:
        w[0] = w[-1] = 0.5
    return w


def closed_rms(y, axis: int = -1):
    """Root mean square over the closed interval sampled evenly by ``y`` (:func:`closed_mean` of y^2)."""
    return np.sqrt(closed_mean(np.square(np.asarray(y, dtype=float)), axis))


def last_period(t, period: float) -> tuple[float, float]:
    """The interval [t_end - period, t_end] of a timed run, or the whole run when it is shorter than a
    period (a rocking run, or a part of a turn)."""
    t = np.asarray(t, dtype=float)
    end = float(t[-1])
    start = end - period
    return (start, end) if start >= float(t[0]) - 1e-12 * max(abs(period), 1.0) else (float(t[0]), end)


def integral(t, y, a: float, b: float) -> float:
    """Integral of the piecewise-linear y(t) from a to b (a, b inside the run), by the trapezoid rule with
    the values at a and b interpolated."""
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    inside = (t > a) & (t < b)
    tt = np.concatenate([[a], t[inside], [b]])
    yy = np.concatenate([[np.interp(a, t, y)], y[inside], [np.interp(b, t, y)]])
    return float(np.trapezoid(yy, tt))


def period_mean(t, y, period: float) -> float:
    """Mean of y over the last ``period`` of a timed run (:func:`last_period`)."""
    a, b = last_period(t, period)
    return integral(t, y, a, b) / (b - a)


def period_rms(t, y, period: float) -> float:
    """Root mean square of y over the last ``period`` of a timed run."""
    return float(np.sqrt(period_mean(t, np.square(np.asarray(y, dtype=float)), period)))


def excess_energy(t, power, period: float) -> tuple[np.ndarray, np.ndarray]:
    """(the instants of the last period, the integral of (power - its mean over that period) from its start):
    the energy a flywheel stores and gives back [J]; its max - min is the fluctuation to size one for."""
    t = np.asarray(t, dtype=float)
    p = np.asarray(power, dtype=float)
    a, b = last_period(t, period)
    inside = (t > a) & (t < b)
    tt = np.concatenate([[a], t[inside], [b]])
    pp = np.concatenate([[np.interp(a, t, p)], p[inside], [np.interp(b, t, p)]])
    excess = pp - np.trapezoid(pp, tt) / (b - a)
    return tt, np.concatenate([[0.0], np.cumsum(0.5 * np.diff(tt) * (excess[1:] + excess[:-1]))])
