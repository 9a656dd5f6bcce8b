"""How many times each command solves the mechanism, over every library design and every file of
tests/mechanisms and tests/drives (issue 39: ``analyze``, ``forces``, ``compare``, ``simulate`` at most 3).

Run:  python benchmarks/solve_counts.py [NAME ...] [--commands analyze,forces,compare,simulate]

Each command runs once in this process through the command line (``sim.front.cli.main([COMMAND, NAME,
"--json"])``, ``--revolutions 0.25`` for compare and simulate, as tests/test_solve_counts.py runs them) with
``analytic.mechanism.Mechanism.solve`` wrapped by a counter; a command over 3 lists each solve's sample count
and its caller (the first frame outside the solver). A refused run (exit 2) is listed with its count too: the
rule is about runs. Takes about 6 s of CPU on the development machine (0.25 revolutions each).
"""

from __future__ import annotations

import argparse
import contextlib
import glob
import io
import os
import sys
import traceback

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[0] = ROOT                       # the project, not benchmarks/analytic.py, is ``analytic``

MOST = 3


@contextlib.contextmanager
def counting():
    """A list receiving (samples, caller) of every ``Mechanism.solve`` while the block runs."""
    import numpy as np
    from analytic.mechanism import Mechanism
    calls: list = []
    original = Mechanism.solve

    def solve(self, q, *a, **k):
        frames = traceback.extract_stack(limit=10)[:-1]
        caller = next((f for f in reversed(frames) if not f.filename.endswith(("analytic/mechanism.py",
                                                                                 "functools.py"))), frames[-1])
        calls.append((int(np.size(q)) // len(self.inputs),
                      f"{os.path.relpath(caller.filename, ROOT)}:{caller.lineno}:{caller.name}"))
        return original(self, q, *a, **k)

    Mechanism.solve = solve
    try:
        yield calls
    finally:
        Mechanism.solve = original


def designs() -> list[str]:
    from analytic.registry import names
    files = sorted(glob.glob(os.path.join(ROOT, "tests", "mechanisms", "*.toml"))
                   + glob.glob(os.path.join(ROOT, "tests", "drives", "*.toml")))
    return list(names()) + [os.path.relpath(f, ROOT) for f in files]


def run(command: str, name: str) -> int:
    from sim.front.cli import main
    extra = ["--revolutions", "0.25"] if command in ("compare", "simulate") else []
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        try:
            return main([command, name, "--json", *extra])
        except SystemExit as exc:
            return exc.code if isinstance(exc.code, int) else 1


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", help="library names or files (default: the library and the test files)")
    ap.add_argument("--commands", default="analyze,forces,compare,simulate")
    args = ap.parse_args()
    os.chdir(ROOT)
    over = 0
    for name in args.names or designs():
        for command in args.commands.split(","):
            with counting() as calls:
                rc = run(command, name)
            flag = "" if len(calls) <= MOST else f"  over {MOST}"
            over += bool(flag) and rc == 0
            print(f"{command:9s} {name:44s} exit {rc}  {len(calls):3d} solves{flag}", flush=True)
            if flag:
                for n, caller in calls:
                    print(f"      {n:7d}  {caller}")
    print(f"{over} runs that exit 0 over {MOST} solves")
    return 0


if __name__ == "__main__":
    sys.exit(main())
