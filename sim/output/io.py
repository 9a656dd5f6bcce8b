"""Atomic output files: written to a temporary name beside the target, then renamed over it."""

from __future__ import annotations

import contextlib
import os
from pathlib import Path

from analytic import ParameterError


def check_writable(path: str | os.PathLike, suffixes: tuple[str, ...] | None = None) -> Path:
    """Fail early, with one line, on an output path that cannot be written or has the wrong extension."""
    p = Path(path)
    if p.is_dir():
        raise ParameterError(f"{p} is a folder; give a file name")
    if suffixes is not None and p.suffix.lower() not in suffixes:
        raise ParameterError(f"{p}: unsupported output type {p.suffix or '(no extension)'!r}; use one of "
                             f"{', '.join(suffixes)}")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise ParameterError(f"{p}: folder {parent} does not exist; create it or choose another path")
    if p.is_dir():
        raise ParameterError(f"{p} is a folder; give a file name")
    try:                                          # the only sure test: make a file there, then remove it
        with deferred_signals():                  # a Ctrl-C between the two would leave the probe behind
            import tempfile                 # a written file only (its modules: ~3 ms of a command's start)
            fd, probe = tempfile.mkstemp(prefix=f".{p.name}.", dir=parent)
            os.close(fd)
            os.remove(probe)
    except OSError as exc:
        raise ParameterError(f"{p}: cannot write in folder {parent} ({exc.strerror or exc}); choose another path") from None
    return p


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike):
    """Yield a temporary path beside ``path``; on success rename it to ``path``, else remove it.

    An interrupted write never leaves a truncated file under the requested name, and an existing file is
    replaced only by a complete one.
    """
    p = Path(path)
    tmp = None
    try:
        with deferred_signals():                  # made and known to the clean-up below as one step
            import tempfile
            fd, tmp = tempfile.mkstemp(prefix=f".{p.stem}.", suffix=p.suffix, dir=p.parent if str(p.parent) else ".")
            os.close(fd)
        yield tmp
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)            # mkstemp makes 0600; give the usual permissions
        os.replace(tmp, p)
    except BaseException:
        if tmp is not None:
            with contextlib.suppress(FileNotFoundError):
                os.remove(tmp)
        raise


@contextlib.contextmanager
def deferred_signals():
    """Hold Ctrl-C and SIGTERM until the block ends, then deliver them: for a step that must not be cut in
    two (starting ffmpeg: interrupted between its start and the writer's clean-up, it would write its file
    after the temporary was removed). Outside the main thread: nothing is held."""
    import signal
    import threading
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[int] = []
    sigs = (signal.SIGINT, signal.SIGTERM)
    old = {s: signal.signal(s, lambda signum, frame: caught.append(signum)) for s in sigs}
    try:
        yield
    finally:
        for s, handler in old.items():
            signal.signal(s, handler)
        for s in caught[:1]:
            signal.raise_signal(s)


@contextlib.contextmanager
def new_files_removed_on_failure():
    """Yield ``made(*paths)``, which notes paths about to be written (returning the last); if the block
    fails (an error, Ctrl-C), every noted path that did not exist before it is removed, so that a command
    writing several files leaves none of its new ones behind. A file that existed is only ever replaced
    whole (atomic_path)."""
    existed: dict[Path, bool] = {}

    def made(*paths):
        for p in paths:
            existed.setdefault(Path(p), Path(p).exists())
        return paths[-1]
    try:
        yield made
    except BaseException:
        for p, was in existed.items():
            if not was:
                with contextlib.suppress(OSError):
                    p.unlink()
        raise


def write_csv(path, columns: dict) -> None:
    """Write named columns as CSV with a header row, atomically. Values in full double precision."""
    import numpy as np
    names = list(columns)
    data = np.column_stack([np.ravel(columns[n]) for n in names])
    with atomic_path(path) as tmp:
        np.savetxt(tmp, data, delimiter=",", header=",".join(names), comments="", fmt="%.17g")


def write_text(path, text: str) -> None:
    with atomic_path(path) as tmp:
        Path(tmp).write_text(text)
