"""CPU time of a command line's start and of short commands (issue 30's targets), in fresh processes.

Run:  python benchmarks/startup.py [--repeats 5] [--tree PATH]

Each command runs as ``python -m sim ...`` in a new interpreter; the figure is its CPU time (user +
system, from ``resource.getrusage(RUSAGE_CHILDREN)``), the least of the repeats, so that another process
on the machine changes it little (it still shares caches and cores: the machine's load is printed).
``--tree`` measures another checkout of the project (e.g. a worktree of an older commit) the same way.

Bytecode: an installed package runs from its cached bytecode (.pyc), so the children write and read theirs in
a temporary PYTHONPYCACHEPREFIX (the warm-up run writes it) even where PYTHONDONTWRITEBYTECODE is set, as on
the development machines; ``--no-bytecode`` keeps the environment's setting (with PYTHONDONTWRITEBYTECODE
every run compiles every module it imports from source: about 0.1-0.2 s more per command).

``import linkage`` (issue 39's door) is measured beside ``python -c pass``: it loads no numpy.

``forces fourbar`` (issue 39, item 2: one solved run, no MuJoCo) is measured beside ``analyze fourbar``.

Targets (issue 30): ``list`` and ``check`` at most 0.3 s, ``compare fourbar`` at most 1.5 s, a numerically
solved group's compare (``stephenson_ii``) at most 2.5 s. Issue 39: ``analyze fourbar`` and ``forces fourbar``
at most half of their CPU when it was filed.

Measured (issue 39; ``--repeats 5`` on each tree back to back, load 0.6, s CPU): main at efa21bc ``list`` /
``check`` / ``analyze`` / ``forces`` / ``compare fourbar`` 0.053 / 0.328 / 0.269 / 0.285 / 0.465; after (the
kinds, built-ins, formats, laws and loads imported when used; OpenBLAS asked for one thread by the entry
point) 0.043 / 0.167 / 0.118 / 0.134 / 0.281. ``python -c pass`` 0.019; ``import numpy`` 0.144 with OpenBLAS'
threads, 0.084 with one: the floor under ``analyze``. Medians of alternating pairs and the tree the issue was
filed on: benchmarks/RESULTS-2026-12-02.md.
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile

COMMANDS = [("list", 0.3), ("check fourbar", 0.3), ("analyze fourbar", None), ("forces fourbar", None),
            ("compare fourbar", 1.5), ("compare stephenson_ii", 2.5)]


def cpu_of(argv: list[str], env: dict, cwd: str) -> float:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(argv, env=env, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--tree", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap.add_argument("--no-bytecode", action="store_true",
                    help="keep the environment's PYTHONDONTWRITEBYTECODE (compile from source on every run)")
    args = ap.parse_args()
    env = dict(os.environ, PYTHONPATH=args.tree)
    env.setdefault("MUJOCO_GL", "egl")
    with tempfile.TemporaryDirectory(prefix="linkage-pyc-") as cache:
        if not args.no_bytecode:
            env.pop("PYTHONDONTWRITEBYTECODE", None)
            env["PYTHONPYCACHEPREFIX"] = cache
        return measure(args, env)


def measure(args, env) -> int:
    bytecode = "from source each run" if "PYTHONDONTWRITEBYTECODE" in env else "cached bytecode"
    print(f"tree {args.tree}; load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; "
          f"least of {args.repeats} runs; {bytecode}")
    cpu_of([sys.executable, "-c", "pass"], env, args.tree)           # warm the file cache
    bare = min(cpu_of([sys.executable, "-c", "pass"], env, args.tree) for _ in range(args.repeats))
    print(f"  {'python -c pass':<24s} {bare:6.3f} s CPU")
    for label, code in (("import linkage", "import linkage"),
                        ("lk.load('fourbar')", "import linkage as lk; lk.load('fourbar')")):
        argv = [sys.executable, "-c", code]                  # the Python door (issue 39): lazy names
        cpu_of(argv, env, args.tree)
        best = min(cpu_of(argv, env, args.tree) for _ in range(args.repeats))
        print(f"  {label:<24s} {best:6.3f} s CPU")
    for command, target in COMMANDS:
        argv = [sys.executable, "-m", "sim", *command.split()]
        cpu_of(argv, env, args.tree)
        best = min(cpu_of(argv, env, args.tree) for _ in range(args.repeats))
        verdict = "" if target is None else f"  (target {target:g} s: {'met' if best <= target else 'MISSED'})"
        print(f"  {command:<24s} {best:6.3f} s CPU{verdict}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
