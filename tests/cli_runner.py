"""The ``linkage`` command run inside the test process: what ``python -m sim ARGS`` prints and returns.

A new interpreter costs about 2 s of CPU before any work (numpy, the solver, MuJoCo); the same command in
this process costs what the command itself does. The tests of what only a real process shows (signals,
pipes, the entry point, ffmpeg's own output, environment variables) start one with ``subprocess`` instead.

An exception that escapes the command is printed as Python would print it (a traceback on stderr, exit
code 1), so that the tests' "one line, no traceback" checks hold in process as they do outside it.
"""

from __future__ import annotations

import contextlib
import io
import os
import subprocess
import traceback


def run(*args, cwd=None, timeout=None) -> subprocess.CompletedProcess:
    """``linkage ARGS`` in ``cwd``; ``timeout`` is accepted for the subprocess signature and not enforced."""
    from sim.front.cli import main
    argv = [str(a) for a in args]
    out, err = io.StringIO(), io.StringIO()
    here = os.getcwd()
    try:
        if cwd is not None:
            os.chdir(cwd)
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                code = main(argv)
            except SystemExit as exc:                  # argparse's usage errors and --help
                code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
                if isinstance(exc.code, str):
                    print(exc.code, file=err)
            except Exception:                          # a traceback, as the interpreter would print it
                traceback.print_exc(file=err)
                code = 1
    finally:
        os.chdir(here)
    return subprocess.CompletedProcess(["linkage", *argv], code, out.getvalue(), err.getvalue())
