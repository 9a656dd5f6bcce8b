"""Periodic samples as a trigonometric series: the interpolant the reduced equation of motion (and the loads'
terms in it) evaluate between the samples of one turn of the input."""

from __future__ import annotations

import numpy as np


class Trig:
    """Trigonometric interpolant of samples ``y`` at u_k = 2 pi k / N (k < N), truncated where the
    harmonics fall below 1e-15 of the largest (round-off); ``(u, nu)`` gives the value (nu=0) or the
    derivative (nu=1)."""

    def __init__(self, y):
        n = len(y)
        c = np.fft.rfft(y) / n
        c[1:] *= 2.0
        if n % 2 == 0:
            c[-1] *= 0.5
        big = np.flatnonzero(np.abs(c) > 1e-15 * max(np.abs(c).max(), 1e-300))
        k = int(big[-1]) + 1 if len(big) else 1
        self.c = c[:k]
        self.k = np.arange(k)
        self.full = k > 0.8 * len(c)       # little room left above the round-off floor: refine the grid

    def __call__(self, u, nu: int = 0):
        u = np.asarray(u, float)
        flat = u.reshape(-1)
        coef = self.c * (1j * self.k) ** nu
        out = np.empty(flat.shape)
        for a in range(0, len(flat), 2048):
            e = np.exp(1j * np.outer(flat[a:a + 2048], self.k))
            out[a:a + 2048] = (e @ coef).real
        return out.reshape(u.shape)

    def grid(self, m: int, nu: int = 0) -> np.ndarray:
        """Values (nu=0) or derivatives (nu=1) at u_j = 2 pi j / m, j < m (m > 2 len(c)), by one inverse FFT."""
        a = np.zeros(m // 2 + 1, complex)
        a[:len(self.c)] = self.c * (1j * self.k) ** nu * m
        a[1:] *= 0.5
        return np.fft.irfft(a, n=m)

    def scalar(self, u: float, nu: int = 0) -> float:
        e = np.exp(1j * u * self.k)
        return float((e @ (self.c * (1j * self.k) ** nu)).real)
