"""Peak memory of a run at the memory bound (sim.service.analysis.RUN_MEMORY, one rule for analyze, forces,
simulate and compare): each command at the most samples (or revolutions) the bound lets through, its peak RSS
printed against the bound.

Run:  python benchmarks/run_memory.py [MECHANISM ...]   (default: fourbar; a minute or two each, ~2 GB at peak)
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
# benchmarks/analytic.py is named like the package: keep this folder off the import path.
sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]


WRAP = ("import resource, subprocess, sys\n"
        "r = subprocess.run([sys.executable, '-m', 'sim', *sys.argv[1:]], capture_output=True, text=True)\n"
        "sys.stderr.write(r.stderr)\n"
        "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)\n"
        "sys.exit(r.returncode)\n")
"""Runs one command and prints its peak RSS [KB]: a fresh parent per command, so each peak is its own."""


def cli(*args: str) -> tuple[int, str, float]:
    """(exit code, stderr, peak RSS [GB]) of ``python -m sim ARGS``."""
    r = subprocess.run([sys.executable, "-c", WRAP, *args], cwd=ROOT, capture_output=True, text=True)
    return r.returncode, r.stderr, int(r.stdout.split()[-1]) * 1024 / 1024 ** 3


def most(args: tuple[str, ...], pattern: str) -> str:
    """The count the refusal of ``args`` names as the most that fit."""
    code, err, _ = cli(*args)
    m = re.search(pattern, err)
    if code != 2 or m is None:
        raise SystemExit(f"expected a refusal from {' '.join(args)}: {err.strip()}")
    return m.group(1).replace(",", "")


def main(names: list[str]) -> None:
    from sim.service.analysis import RUN_MEMORY
    print(f"bound {RUN_MEMORY / 1024 ** 3:.3g} GB")
    for name in names:
        n = most(("analyze", name, "--samples", "10000000"), r"at most ([0-9,]+) fit")
        for extra in ((), ("--csv", "/tmp/run_memory.csv")):
            code, err, gb = cli("analyze", name, "--samples", n, *extra)
            print(f"{name:12s} analyze --samples {n} {' '.join(extra):24s} exit {code}  peak {gb:.2f} GB")
        n = most(("forces", name, "--samples", "10000000"), r"at most ([0-9,]+) fit")
        code, err, gb = cli("forces", name, "--samples", n)
        print(f"{name:12s} forces  --samples {n} {'':24s} exit {code}  peak {gb:.2f} GB")
        turns = most(("compare", name, "--revolutions", "10000"), r"at most ([0-9.]+) revolutions")
        for cmd in ("simulate", "compare"):
            code, err, gb = cli(cmd, name, "--revolutions", turns)
            print(f"{name:12s} {cmd:8s}--revolutions {turns} {'':19s} exit {code}  peak {gb:.2f} GB")
    Path("/tmp/run_memory.csv").unlink(missing_ok=True)
    Path("/tmp/run_memory.csv.units.json").unlink(missing_ok=True)


if __name__ == "__main__":
    main(sys.argv[1:] or ["fourbar"])
