"""Shared helpers for the analytic solvers: validation, input motion, angle wrapping."""

from __future__ import annotations

import ctypes
import importlib
import math
import os
import sys

from collections.abc import Iterator, MutableMapping

import numpy as np

from analytic.errors import AssemblyError, FileError, ParameterError  # noqa: F401 (defined there, light)


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


BLOCK = 8192
"""Samples per block in :func:`blockwise` and the general solver's numpy path: small enough that a
kernel's temporaries stay in cache, large enough that numpy's per-call overhead (about 1 us per array
operation) is small against the arithmetic. 8192 measured 5-30 % faster than 4096 for the closed forms and
the general solver alike (CPU time, 2-core machine; 16384 about the same as 8192)."""


def blockwise(kernel, mech, inputs: tuple[np.ndarray, ...]) -> dict[str, np.ndarray]:
    """Evaluate ``kernel(mech, *inputs)`` (1-D arrays in, dict of 1-D arrays out) block by block.

    The inputs are broadcast together; the outputs take their shape. Working in blocks of
    :data:`BLOCK` samples keeps the dozens of temporaries of a closed form in the CPU cache instead of
    allocating full-size arrays for each; the loop is over blocks, not samples.
    """
    arrays = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in inputs))
    shape = arrays[0].shape
    flat = [np.ravel(a) for a in arrays]
    n = flat[0].size
    if n <= BLOCK:
        with np.errstate(invalid="ignore", divide="ignore"):    # NaN marks unreachable samples
            return {k: v.reshape(shape) for k, v in kernel(mech, *flat).items()}
    keep_freed_memory()
    out = None
    for start in range(0, n, BLOCK):
        with np.errstate(invalid="ignore", divide="ignore"):
            part = kernel(mech, *(a[start:start + BLOCK] for a in flat))
        if out is None:
            out = {k: np.empty(n) for k in part}
        for k, v in part.items():
            out[k][start:start + BLOCK] = v
    return {k: v.reshape(shape) for k, v in out.items()}


_MALLOPT_DONE = False


def keep_freed_memory() -> bool:
    """Ask glibc to keep freed memory for reuse instead of returning it to the OS at once.

    Each block of a closed form allocates and frees a few MB of temporaries; with glibc's default
    thresholds (trim at 128 KiB, mmap from 128 KiB) every block then page-faults its memory afresh,
    which costs more than the arithmetic (measured: 7 vs 11 M four-bar samples/s, see
    benchmarks/analytic.py). This raises the trim threshold to 256 MiB and the mmap threshold to 32 MiB,
    once per process, at the first evaluation larger than one block. The process may then hold up to
    256 MiB of freed memory. Set the environment variable ``LINKAGE_MALLOPT=0`` to leave malloc alone.
    Returns True if the thresholds were changed.
    """
    global _MALLOPT_DONE
    if _MALLOPT_DONE or os.environ.get("LINKAGE_MALLOPT", "1") == "0" or not sys.platform.startswith("linux"):
        return False
    _MALLOPT_DONE = True
    try:
        libc = ctypes.CDLL("libc.so.6")
        m_trim_threshold, m_mmap_threshold = -1, -3          # <malloc.h>
        return bool(libc.mallopt(m_trim_threshold, 256 << 20) and libc.mallopt(m_mmap_threshold, 32 << 20))
    except (OSError, AttributeError):                        # not glibc (e.g. musl): nothing to tune
        return False


def module_getattr(package: str, modules: tuple[str, ...]):
    """A package's ``__getattr__`` (PEP 562) that gives each of its ``modules`` as an attribute, imported on
    first use as :class:`LazyKinds` imports it (``analytic.loads.torque`` reads as when the package imported
    every kind up front)."""
    def __getattr__(name: str):
        if name in modules:
            return importlib.import_module(f"{package}.{name}")
        raise AttributeError(f"module {package!r} has no attribute {name!r}")
    return __getattr__


class LazyKinds(MutableMapping):
    """{name: the ``KIND`` of module ``package.NAME`` (lower case)} for ``names``, in their order, each module
    imported when its kind is first asked for (a command loads the modules of the kinds its mechanism uses).
    A kind set here (a plug-in's, or one replaced) is held as given."""

    def __init__(self, package: str, names: tuple[str, ...]):
        self._package = package
        self._entries: dict[str, object] = dict.fromkeys(names)      # None: its module not imported yet

    def __getitem__(self, name: str):
        kind = self._entries[name] if isinstance(name, str) else None
        if kind is None:
            if name not in self:
                raise KeyError(name)
            kind = importlib.import_module(f"{self._package}.{name.lower()}").KIND
            if kind.name != name:
                raise RuntimeError(f"{self._package}.{name.lower()}: its KIND is named {kind.name!r}, not "
                                   f"{name!r}: make them agree")
            self._entries[name] = kind
        return kind

    def loaded(self, name: str):
        """The kind called ``name`` if its module is imported or it was set here, else None (nothing imported)."""
        return self._entries.get(name)

    def __setitem__(self, name: str, kind) -> None:
        self._entries[name] = kind

    def __delitem__(self, name: str) -> None:
        del self._entries[name]

    def __contains__(self, name) -> bool:
        return isinstance(name, str) and name in self._entries

    def __iter__(self) -> Iterator[str]:
        return iter(self._entries)

    def __len__(self) -> int:
        return len(self._entries)
