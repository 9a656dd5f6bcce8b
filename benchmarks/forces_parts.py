"""CPU time of ``forces`` (:func:`sim.service.forces.forces_run`) on a file whose masses come from its
``[parts]`` section (the parts built over the cycle, and the layering that decides which links are two plates)
against a file without one (the four-bar: no parts, no layering), and of the mass model alone. Each figure the
best of ``--repeats`` runs of :func:`time.process_time` (this process's CPU, all threads), so that a shared
machine's load changes it less than wall time.

    python benchmarks/forces_parts.py [--repeats 3] [--parts FILE] [--plain fourbar]

``--parts`` defaults to the library's Whitworth with a ``[parts]`` section added (its slotted lever is made
two plates: a clevis).
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

# benchmarks/analytic.py would shadow the package of that name: keep this folder off the import path.
sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]

from analytic import mass  # noqa: E402
from sim import service  # noqa: E402
from sim.service import forces as sf  # noqa: E402


def best(fn, repeats: int) -> float:
    out = math.inf
    for _ in range(repeats):
        t0 = time.process_time()
        fn()
        out = min(out, time.process_time() - t0)
    return out


def whitworth_with_parts(folder: Path) -> str:
    src = Path(__file__).resolve().parent.parent / "analytic" / "library" / "whitworth.toml"
    path = folder / "whitworth_parts.toml"
    path.write_text(src.read_text() + "\n[parts]\nclearance = 0.5\n")
    return str(path)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--parts", default=None)
    ap.add_argument("--plain", default="fourbar")
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        files = [args.parts or whitworth_with_parts(Path(tmp)), args.plain]
        for name in files:
            mech = service.load(name, {})
            sf.forces_run(mech)                               # warm up (imports, caches)
            t_run = best(lambda: sf.forces_run(mech), args.repeats)
            t_mass = best(lambda: mass.model(mech), args.repeats)
            src = sorted(set(mass.sources(mech).values()))
            print(f"{Path(name).stem:20s} masses from {','.join(src):10s}  forces_run {t_run:7.3f} s CPU   "
                  f"mass.model {t_mass:7.3f} s CPU")


if __name__ == "__main__":
    main()
