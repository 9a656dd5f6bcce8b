"""Adversarial links-and-joints files through ``linkage check`` and ``linkage analyze``: each must end within
seconds, in bounded memory, with exit 0 or one line and exit 2 (issue 32: some mutated files ran past 20 s or
were killed for memory).

Run:  python benchmarks/fuzz_joints.py [--seed 0] [--random 60] [--seconds 20] [--memory-mb 1500]

The cases: families written to be hard (a chain of N four-bar loops, a ladder of N ternary links that leaves no
dyad, N copies of one joint, coordinates scaled to 1e300 and 1e-300, hundreds of links hung off one pin,
many inputs) at growing N, then ``--random`` seeded mutations of the test suite's links-and-joints files
(tests/peers_examples/stephenson.toml, locked_pantograph.toml: joints duplicated or dropped, links merged,
points renamed, coordinates blown up, tables repeated). Each runs as ``python -m sim check FILE`` and
``python -m sim analyze FILE --samples 37`` in a new process with an address-space limit; prints each case's
seconds, peak memory (ru_maxrss) and the outcome, and every case that was not handled.
"""

from __future__ import annotations

import argparse
import os
import random
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "tests" / "peers_examples"


def toml_of(pose: dict, links: list, joints: list, inputs: list, units: str = "mm") -> str:
    out = ['format = "linkage/1"', f'units = "{units}"', "", "[pose]"]
    out += [f"{p} = [{x!r}, {y!r}]" for p, (x, y) in pose.items()]
    for name, pts in links:
        out += ["", "[[links]]", f'name = "{name}"', "points = [" + ", ".join(f'"{p}"' for p in pts) + "]"]
    for point, a, b in joints:
        out += ["", "[[joints]]", 'kind = "R"', f'point = "{point}"', f'links = ["{a}", "{b}"]']
    for pivot, point in inputs:
        out += ["", "[[inputs]]", 'kind = "crank"', f'pivot = "{pivot}"', f'point = "{point}"']
    return "\n".join(out) + "\n"


def chain(n: int, spacing: float = 100.0) -> str:
    """A crank and n four-bar loops in a row, ``spacing`` apart: each rocker drives the next loop (a long chain
    of RRR dyads; at a small spacing every link passes near every other)."""
    pose = {"G0": (0.0, 0.0), "B0": (10.0, 0.0)}
    links, joints = [("crank", ["G0", "B0"])], [("G0", "ground", "crank")]
    prev, prev_pt = "crank", "B0"
    for k in range(n):
        gx = spacing * (k + 1)
        c, g = f"C{k}", f"G{k + 1}"
        pose[g] = (gx, 0.0)
        pose[c] = (gx - 40.0, 60.0)
        links += [(f"cp{k}", [prev_pt, c]), (f"r{k}", [g, c, f"B{k + 1}"])]
        pose[f"B{k + 1}"] = (gx + 10.0, 0.0)
        joints += [(prev_pt, prev, f"cp{k}"), (c, f"cp{k}", f"r{k}"), (g, "ground", f"r{k}")]
        prev, prev_pt = f"r{k}", f"B{k + 1}"
    return toml_of(pose, links, joints, [("G0", "B0")])


def ladder(n: int) -> str:
    """n ternary links in a ring, each pinned to its neighbours and hung from the ground by a binary link: one
    Assur group of 2n links (no dyad to start from)."""
    import math
    pose, links, joints = {"A": (0.0, 0.0), "B": (10.0, 0.0)}, [("crank", ["A", "B"])], [("A", "ground", "crank")]
    for k in range(n):
        a = 2 * math.pi * k / n
        p, q = f"P{k}", f"Q{k}"
        pose[p] = (200 * math.cos(a), 200 * math.sin(a))
        pose[q] = (300 * math.cos(a), 300 * math.sin(a))
        pose[f"M{k}"] = (250 * math.cos(a + math.pi / n), 250 * math.sin(a + math.pi / n))
        links += [(f"t{k}", [p, f"M{k}", f"P{(k + 1) % n}"]), (f"h{k}", [q, f"M{k}"])]
        joints += [(q, "ground", f"h{k}"), (f"M{k}", f"h{k}", f"t{k}")]
    for k in range(n):
        joints.append((f"P{(k + 1) % n}", f"t{k}", f"t{(k + 1) % n}"))
    links.append(("drive", ["B", "P0"]))
    pose["P0"] = pose["P0"]
    joints += [("B", "crank", "drive"), ("P0", "drive", "t0")]
    return toml_of(pose, links, joints, [("A", "B")])


def fan(n: int) -> str:
    """n links hung off the crank pin, each pinned to the ground at its far end (n - 1 redundant loops)."""
    pose = {"A": (0.0, 0.0), "B": (10.0, 0.0)}
    links, joints = [("crank", ["A", "B"])], [("A", "ground", "crank")]
    for k in range(n):
        pose[f"G{k}"] = (100.0 + k, 50.0 + k)
        links.append((f"f{k}", ["B", f"G{k}"]))
        joints += [("B", "crank", f"f{k}"), (f"G{k}", "ground", f"f{k}")]
    return toml_of(pose, links, joints, [("A", "B")])


def duplicated(n: int) -> str:
    text = (EXAMPLES / "stephenson.toml").read_text()
    block = '\n[[joints]]\nkind = "R"\npoint = "B"\nlinks = ["crank", "l1"]\n'
    return text + block * n


def scaled(factor: float) -> str:
    text = (EXAMPLES / "stephenson.toml").read_text()
    return re.sub(r"\[(-?\d+), (-?\d+)\]", lambda m: f"[{float(m[1]) * factor!r}, {float(m[2]) * factor!r}]", text)


def many_inputs(n: int) -> str:
    text = chain(3)
    return text + ('\n[[inputs]]\nkind = "crank"\npivot = "G0"\npoint = "B0"\n' * n)


def compact(n: int) -> str:
    return chain(n, 3.0)


FAMILIES = [("chain", chain, [10, 60, 200]), ("compact", compact, [10, 30, 120]), ("ladder", ladder, [3, 6, 10, 40]), ("fan", fan, [20, 200]),
            ("duplicated", duplicated, [50, 450]), ("scaled", scaled, [1e300, 1e-300, 1e200]),
            ("many_inputs", many_inputs, [20, 400])]


def mutate(rng: random.Random, text: str) -> str:
    blocks = re.split(r"(?=\n\[\[)", text)
    ops = rng.randint(1, 4)
    for _ in range(ops):
        op = rng.choice(["dup", "drop", "rename", "blow", "repeat", "swap"])
        if op == "dup" and len(blocks) > 1:
            b = rng.choice(blocks[1:])
            blocks += [b] * rng.choice([1, 5, 50, 300])
        elif op == "drop" and len(blocks) > 2:
            blocks.pop(rng.randrange(1, len(blocks)))
        elif op == "rename":
            names = sorted(set(re.findall(r'"([A-Za-z]\w*)"', "".join(blocks))))
            if len(names) > 1:
                a, b = rng.sample(names, 2)
                k = rng.randrange(len(blocks))
                blocks[k] = blocks[k].replace(f'"{a}"', f'"{b}"')
        elif op == "blow":
            k = rng.randrange(len(blocks))
            blocks[k] = re.sub(r"(-?\d+(?:\.\d+)?)", lambda m: rng.choice([m[1], "1e308", "-1e300", "1e-320",
                                                                              m[1] + "e150"]), blocks[k], count=3)
        elif op == "repeat":
            blocks = blocks + blocks[1:] * rng.choice([2, 20])
        elif op == "swap" and len(blocks) > 2:
            i, j = rng.sample(range(1, len(blocks)), 2)
            blocks[i], blocks[j] = blocks[j], blocks[i]
    return "".join(blocks)


def run_case(path: Path, seconds: float, memory_mb: float) -> list[tuple[str, float, float, str]]:
    out = []
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    limit = int(memory_mb * 2 ** 20)

    def cap():
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    for cmd in (["check", str(path)], ["analyze", str(path), "--samples", "37"]):
        t0 = time.time()
        rss = path.with_suffix(".rss")
        timer = ["/usr/bin/time", "-f", "%M", "-o", str(rss)] if Path("/usr/bin/time").exists() else []
        try:
            p = subprocess.run([*timer, sys.executable, "-m", "sim", *cmd], env=env, capture_output=True, text=True,
                               timeout=seconds, preexec_fn=cap)
            dt = time.time() - t0
            err = p.stderr.strip().splitlines()
            if p.returncode == 0:
                verdict = "ok"
            elif p.returncode == 2 and len(err) == 1 and "Traceback" not in p.stderr:
                verdict = "refused: " + err[0][:150]
            else:
                verdict = f"NOT HANDLED (exit {p.returncode}, {len(err)} lines): " + (err[-1][:150] if err else "")
        except subprocess.TimeoutExpired:
            dt, verdict = time.time() - t0, f"NOT HANDLED (past {seconds:g} s)"
        try:
            mb = float(rss.read_text().split()[-1]) / 1024                  # the child's own peak (KB)
        except (OSError, ValueError, IndexError):
            mb = float("nan")
        out.append((cmd[0], dt, mb, verdict))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--random", type=int, default=60)
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--memory-mb", type=float, default=1500.0)
    ap.add_argument("--only", nargs="*", help="family names to run (default: all, and the random mutations)")
    args = ap.parse_args(argv)
    rng = random.Random(args.seed)
    folder = Path(tempfile.mkdtemp(prefix="fuzz-joints-"))
    cases = [(f"{name}({n:g})", fn(n)) for name, fn, ns in FAMILIES if not args.only or name in args.only for n in ns]
    if not args.only:
        bases = [(EXAMPLES / f).read_text() for f in ("stephenson.toml", "locked_pantograph.toml")]
        cases += [(f"random {k}", mutate(rng, rng.choice(bases))) for k in range(args.random)]
    bad, worst, most = 0, (0.0, ""), (0.0, "")
    for label, text in cases:
        path = folder / (re.sub(r"\W", "_", label) + ".toml")
        path.write_text(text)
        for cmd, dt, mb, verdict in run_case(path, args.seconds, args.memory_mb):
            bad += verdict.startswith("NOT")
            worst = max(worst, (dt, f"{cmd} {label}"))
            most = max(most, (mb if mb == mb else 0.0, f"{cmd} {label}"))
            if verdict.startswith("NOT") or not label.startswith("random"):
                print(f"{label:<22s} {cmd:<8s} {dt:6.2f} s {mb:7.0f} MB  {verdict}", flush=True)
    print(f"{len(cases)} files, {2 * len(cases)} runs: {bad} not handled; slowest {worst[0]:.2f} s ({worst[1]}); "
          f"most memory {most[0]:.0f} MB ({most[1]}); files in {folder}")
    return 1 if bad else 0


if __name__ == "__main__":
    raise SystemExit(main())
