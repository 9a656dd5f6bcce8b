"""The ``linkage`` entry point: imports the command line inside a guard, so that Ctrl-C while Python is
still loading numpy ends in one line (exit 130), not a traceback.

OpenBLAS (numpy's linear algebra) starts a thread per core when numpy is imported, and those threads spin:
~60 ms of CPU per command on a 2-core machine, more than the command's own work. The solver's algebra is
elementwise or on stacks of 2x2 .. 12x12 matrices, which OpenBLAS runs on one thread, so a command asks for
one unless the user's environment (``OPENBLAS_NUM_THREADS``) says otherwise."""

import os
import sys

BLAS_THREADS = "1"
"""OpenBLAS threads of a command's process, where ``OPENBLAS_NUM_THREADS`` is not set."""


def main() -> int:
    os.environ.setdefault("OPENBLAS_NUM_THREADS", BLAS_THREADS)   # before numpy is imported
    try:
        from sim.front.cli import main as cli_main
        return cli_main()
    except KeyboardInterrupt:
        sys.stderr.write("linkage: interrupted\n")
        return 130
