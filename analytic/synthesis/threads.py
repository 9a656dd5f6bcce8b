"""One BLAS thread while a synthesis restart runs.

The polish factorises small Jacobians (tens to a few hundred columns) hundreds of times. OpenBLAS's
threads only cost time on matrices that small, and on a shared machine, or with ``--workers`` processes
each starting its own threads, they oversubscribe the cores: measured on this project's 2-core machine
under load, an SVD of a 106 x 44 matrix took 6.9 ms with the default threads and 0.46 ms with one (a
mcgarva polish: 29 s against 0.6 s).

:func:`one_blas_thread` sets every OpenBLAS loaded in this process (numpy's and scipy's copies) to one
thread and restores the previous counts on exit. It finds them in ``/proc/self/maps`` (Linux); elsewhere,
or for another BLAS, it does nothing.
"""

from __future__ import annotations

import contextlib
import ctypes

_SETTERS = ("openblas_set_num_threads", "scipy_openblas_set_num_threads64_", "scipy_openblas_set_num_threads")
_GETTERS = ("openblas_get_num_threads", "scipy_openblas_get_num_threads64_", "scipy_openblas_get_num_threads")


def _openblas_libraries() -> list[tuple]:
    """(get, set) of each OpenBLAS mapped into this process."""
    try:
        with open("/proc/self/maps") as f:
            paths = sorted({line.split()[-1] for line in f if "openblas" in line.lower() and "/" in line})
    except OSError:
        return []
    out = []
    for path in paths:
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        get = next((getattr(lib, n) for n in _GETTERS if hasattr(lib, n)), None)
        put = next((getattr(lib, n) for n in _SETTERS if hasattr(lib, n)), None)
        if get is not None and put is not None:
            get.restype = ctypes.c_int
            out.append((get, put))
    return out


@contextlib.contextmanager
def one_blas_thread():
    """Run the body with every loaded OpenBLAS on one thread (restored afterwards)."""
    libs = _openblas_libraries()
    before = [get() for get, _ in libs]
    for _, put in libs:
        put(ctypes.c_int(1))
    try:
        yield
    finally:
        for (_, put), n in zip(libs, before):
            put(ctypes.c_int(n))
