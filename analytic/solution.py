"""The outputs of one solve: :class:`Solution`, a read-only mapping from output name to array."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np


class Solution(Mapping):
    """Outputs of one solve: a read-only mapping from output name to array (shape of the inputs).

    ``valid`` marks the samples where every group assembled; ``failed`` names, per sample, the element
    (its point) that could not be assembled first (``""`` where all did)."""

    def __init__(self, arrays: dict[str, np.ndarray], failed: np.ndarray, labels: tuple[str, ...],
                 aliases: dict[str, str] | None = None):
        self._arrays = arrays
        self._aliases = aliases or {}
        self.failed_index = failed
        self.labels = labels

    def __getitem__(self, name: str) -> np.ndarray:
        return self._arrays[self._aliases.get(name, name)]

    def __iter__(self):
        yield from self._arrays
        yield from (a for a in self._aliases if a not in self._arrays)

    def __len__(self) -> int:
        return len(self._arrays) + len(set(self._aliases) - set(self._arrays))

    def __getattr__(self, name: str):            # sol.xE as well as sol["xE"]
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None

    @property
    def valid(self) -> np.ndarray:
        return self.failed_index < 0

    def first_failure(self) -> tuple[int, str] | None:
        """(sample index, element label) of the first sample that did not assemble, or None."""
        bad = np.flatnonzero(self.failed_index.ravel() >= 0)
        if bad.size == 0:
            return None
        k = int(bad[0])
        return k, self.labels[int(self.failed_index.ravel()[k])]


class StateView:
    """Named outputs (a :class:`Solution`, or any mapping of output names to arrays: a simulation's) seen
    as the solver's state: ``points[P]``, ``links[L]`` and ``slides[J]`` give the tuples the kinds use
    (see :mod:`analytic.kinds.base`)."""

    def __init__(self, outputs: Mapping):
        self.points = _Lazy(lambda p: tuple(outputs[c + p] for c in ("x", "y", "vx", "vy", "ax", "ay")))
        self.links = _Lazy(lambda ln: tuple(outputs[c + ln] for c in ("cos", "sin", "omega", "alpha")))
        self.slides = _Lazy(lambda j: tuple(outputs[c + j] for c in ("s", "ds", "dds")))


class _Lazy:
    def __init__(self, get):
        self.get = get

    def __getitem__(self, key):
        return self.get(key)
