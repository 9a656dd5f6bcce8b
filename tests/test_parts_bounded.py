"""The parts' layering on adversarial links-and-joints files (issue 32: ``check`` of some mutated files ran past
20 s or out of memory): the exact colouring bounded (a clique of the conflict graph starts the search, a budget
ends it with DSatur's colouring), the layering refused in one line past MAX_LINKS links while ``check`` goes
on, and the shortcuts that made it affordable (outlines made once, polygons measured only where bounding discs
come near, a conflict decided at its first sample) giving the conflicts and pin rules a brute-force pass gives.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import analytic
from analytic.parts import layers, model
from sim.service import parts as parts_service

import cli_runner  # the command in this process (tests/cli_runner.py)


def chain_file(n: int, spacing: float) -> str:
    """A crank and n four-bar loops, ``spacing`` mm apart (each rocker drives the next loop), links and joints."""
    pose = {"G0": (0.0, 0.0), "B0": (10.0, 0.0)}
    links, joints = [("crank", ["G0", "B0"])], [("G0", "ground", "crank")]
    prev, prev_pt = "crank", "B0"
    for k in range(n):
        gx = spacing * (k + 1)
        c, g, b = f"C{k}", f"G{k + 1}", f"B{k + 1}"
        pose.update({g: (gx, 0.0), c: (gx - 40.0, 60.0), b: (gx + 10.0, 0.0)})
        links += [(f"cp{k}", [prev_pt, c]), (f"r{k}", [g, c, b])]
        joints += [(prev_pt, prev, f"cp{k}"), (c, f"cp{k}", f"r{k}"), (g, "ground", f"r{k}")]
        prev, prev_pt = f"r{k}", b
    out = ['format = "linkage/1"', 'units = "mm"', "", "[pose]"] + [f"{p} = [{x!r}, {y!r}]" for p, (x, y) in pose.items()]
    for name, pts in links:
        out += ["", "[[links]]", f'name = "{name}"', "points = [" + ", ".join(f'"{p}"' for p in pts) + "]"]
    for point, a, b in joints:
        out += ["", "[[joints]]", 'kind = "R"', f'point = "{point}"', f'links = ["{a}", "{b}"]']
    out += ["", "[[inputs]]", 'kind = "crank"', 'pivot = "G0"', 'point = "B0"']
    return "\n".join(out) + "\n"


def _counting(monkeypatch):
    calls = [0]
    real = layers._fill

    def fill(*a, **k):
        calls[0] += 1
        return real(*a, **k)
    monkeypatch.setattr(layers, "_fill", fill)
    return calls


# ---------------------------------------------------------------------------------------------- colouring
def test_a_complete_conflict_graph_is_coloured_at_once(monkeypatch):
    """K_25 (every link near every other) needs 25 layers: the clique found starts the search there, so it is
    coloured in one pass (it took hours counting up from 1)."""
    calls = _counting(monkeypatch)
    nodes = list(range(25))
    got = layers.colour(nodes, list(itertools.combinations(nodes, 2)))
    assert sorted(got.values()) == list(range(25))
    assert calls[0] <= 2 * len(nodes)                    # one call per node of the single successful pass


def test_a_dense_graph_past_the_budget_gets_a_valid_greedy_colouring(monkeypatch):
    monkeypatch.setattr(layers, "PLAIN_SEARCH", 2000)
    calls = _counting(monkeypatch)
    rng = np.random.default_rng(7)
    nodes = list(range(30))
    edges = [(a, b) for a, b in itertools.combinations(nodes, 2) if rng.random() < 0.6]
    got = layers.colour(nodes, edges)
    assert set(got) == set(nodes) and all(got[a] != got[b] for a, b in edges)
    assert calls[0] <= 2000 + 30                         # the budget bounds the exact search
    # a clique of the graph is a lower bound of any colouring
    assert max(got.values()) + 1 >= layers._clique(nodes, {n: {b for a, b in edges if a == n} |
                                                            {a for a, b in edges if b == n} for n in nodes})


def test_the_clique_bound_keeps_small_graphs_exact():
    """The brute force of tests/test_parts.py on graphs with cliques: the bound never overshoots."""
    rng = np.random.default_rng(11)
    for _ in range(40):
        n = int(rng.integers(2, 7))
        nodes = list(range(n))
        edges = [(a, b) for a, b in itertools.combinations(nodes, 2) if rng.random() < 0.75]
        got = layers.colour(nodes, edges)
        best = min(k for k in range(1, n + 1) if any(all(c[a] != c[b] for a, b in edges)
                                                   for c in itertools.product(range(k), repeat=n)))
        assert all(got[a] != got[b] for a, b in edges) and max(got.values()) + 1 == best


# ----------------------------------------------------------------------------------------- the size limit
def test_past_max_links_check_says_so_in_one_line_and_goes_on(tmp_path):
    f = tmp_path / "chain.toml"
    f.write_text(chain_file(20, 100.0))                  # 41 moving links
    r = cli_runner.run("check", f)
    assert r.returncode == 0, r.stderr
    lines = [ln for ln in r.stdout.splitlines() if "parts" in ln]
    assert len(lines) == 1 and "41 moving links" in lines[0] and f"at most {layers.MAX_LINKS}" in lines[0]
    assert layers.MAX_LINKS == 40                        # the documented bound (5 s, 190 MB at 31 links)
    with pytest.raises(analytic.ParameterError, match="at most 40"):
        parts_service.prepare(analytic.load(str(f)))


# --------------------------------------------------------------------------- the shortcuts change nothing
def _brute(mech, parts, sweep):
    """Every pair's conflict and every pin's crossing links, measured at every sample, no shortcut."""
    import shapely
    cfg = model.settings(mech)
    out = layers.outlines(mech, parts)
    links = list(parts)
    conflicts = set()
    for a, b in itertools.combinations(links, 2):
        if layers.pair_distance(mech, out, sweep, a, b, cfg.clearance, penetration_depth=False).first is not None:
            conflicts.add((a, b))
    crossing = {}
    for p in mech.points:
        pinned = {ln for ln, part in parts.items() if any(h.point == p for h in part.holes)}
        if not pinned:
            continue
        at = shapely.points(sweep.points[p])
        step_p = np.max(np.hypot(*np.diff(sweep.points[p], axis=0).T))
        found = set()
        for ln in links:
            if ln in pinned:
                continue
            v = layers.world(out, sweep, ln)
            d = np.asarray(shapely.distance(shapely.polygons(v), at)) - cfg.pin_diameter / 2
            if d.min() < cfg.clearance + float(np.max(layers._step(v))) + step_p:
                found.add(ln)
        crossing[p] = found
    return conflicts, crossing


@pytest.mark.parametrize("name", ["jansen", "klann", "double_butterfly", "chain"])
def test_conflicts_and_pin_rules_equal_a_brute_force_pass(name, tmp_path):
    if name == "chain":
        f = tmp_path / "chain.toml"
        f.write_text(chain_file(4, 30.0))                 # loops overlapping: many pairs near, some apart
        mech = analytic.load(str(f))
    else:
        mech = analytic.load(name)
    mech = parts_service.cycle_mechanism(mech)
    sweep = model.cycle(mech, 240)
    parts = model.build(mech, sweep)
    lay = layers.layout(mech, parts, sweep)
    conflicts, crossing = _brute(mech, parts, sweep)
    assert {tuple(sorted(c)) for c in lay.conflicts} == {tuple(sorted(c)) for c in conflicts}
    assert conflicts and len(conflicts) < len(parts) * (len(parts) - 1) // 2     # both kinds of pair occur
    rules = layers.pin_rules(mech, parts, layers.outlines(mech, parts), sweep, model.settings(mech),
                             {ln: ln for ln in parts})
    slotted = {r.point: set(r.members) for r in rules}
    for r in rules:
        # the brute force leaves out the pinned links only; the rule leaves out the slotted ones too
        assert set(r.crossing) == crossing[r.point] - slotted[r.point], r.point
