"""Cost per sample of a numerically solved group with prismatic pairs (analytic/solver/prismatic_group.py)
against a revolute group of the same links (analytic/solver/general_group.py), numpy, N samples of one turn.

    python benchmarks/prismatic_group.py [N]

The revolute group: tests/kinds/group.toml's triad; with prismatic pairs: tests/kinds/group__slides.toml (the
same triad with two of its rods made sliding blocks); and the same revolute triad solved by the prismatic path
(link frames as unknowns: the formulation's cost alone)."""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import analytic  # noqa: E402
from analytic.kinds.group import group  # noqa: E402
from analytic.solver import general_group as gg  # noqa: E402
from analytic.solver import kinematics  # noqa: E402
from analytic.solver import prismatic_group as pg  # noqa: E402


def best(f, k=3):
    out = np.inf
    for _ in range(k):
        t = time.perf_counter()
        f()
        out = min(out, time.perf_counter() - t)
    return out


def known_of(m, n):
    q = np.linspace(0, 2 * np.pi, n, endpoint=False)[None]
    st = kinematics.evaluate(m.geometry, q, np.ones_like(q), np.zeros_like(q))[0]
    e = next(e for e in m.geometry.elements if e["kind"] == "group")
    g = group(e)
    return e, g, {p: st.points[p] for p in g.known}


def main(n: int) -> None:
    rev, e_r = analytic.load(str(ROOT / "tests/kinds/group.toml")), None
    e_r, g_r, k_r = known_of(rev, n)
    e_p, g_p, k_p = known_of(analytic.load(str(ROOT / "tests/kinds/group__slides.toml")), n)
    g_rp = pg.make_group(e_r["links"], g_r.known, g_r.unknown, e_r["pose"], {})
    t_r = best(lambda: gg.solve_group(g_r, k_r))
    t_p = best(lambda: pg.solve_group(g_p, k_p))
    t_rp = best(lambda: pg.solve_group(g_rp, k_r))
    us = 1e6 / n
    print(f"N = {n}: per sample")
    print(f"  revolute triad, general_group:          {t_r * us:7.2f} us")
    print(f"  triad with 2 prismatic pairs:           {t_p * us:7.2f} us ({t_p / t_r:.1f}x)")
    print(f"  revolute triad on the prismatic path:   {t_rp * us:7.2f} us ({t_rp / t_r:.1f}x)")


if __name__ == "__main__":
    main(int(float(sys.argv[1])) if len(sys.argv) > 1 else 100_000)
