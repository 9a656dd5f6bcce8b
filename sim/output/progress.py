"""A one-line progress bar with the time left, on a terminal only (quiet when output is piped)."""

from __future__ import annotations

import sys
import time


class Progress:
    def __init__(self, total: int, label: str, stream=None, every: float = 0.2):
        self.total, self.label = max(int(total), 1), label
        self.stream = stream or sys.stderr
        self.on = self.stream.isatty()
        self.t0 = time.perf_counter()
        self.last = 0.0
        self.every = every

    def update(self, done: int, total: int | None = None) -> None:
        if total is not None:
            self.total = max(int(total), 1)
        if not self.on:
            return
        now = time.perf_counter()
        if done < self.total and now - self.last < self.every:
            return
        self.last = now
        frac = min(done / self.total, 1.0)
        elapsed = now - self.t0
        left = elapsed * (1 - frac) / frac if frac > 0 else float("nan")
        bar = "#" * int(30 * frac)
        eta = f"{left:5.0f} s left" if left == left else "   ... "
        self.stream.write(f"\r{self.label} [{bar:<30s}] {done}/{self.total}  {eta}")
        if done >= self.total:
            self.stream.write("\n")
        self.stream.flush()
