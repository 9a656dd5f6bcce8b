"""The ``linkage`` entry point: imports the command line inside a guard, so that Ctrl-C while Python is
still loading numpy ends in one line (exit 130), not a traceback."""

import sys


def main() -> int:
    try:
        from sim.front.cli import main as cli_main
        return cli_main()
    except KeyboardInterrupt:
        sys.stderr.write("linkage: interrupted\n")
        return 130
