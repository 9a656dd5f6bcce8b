"""The peers' example mechanisms: import every Pyslvs and PMKS example found, check the pose, run compare.

    python benchmarks/peers.py [--pyslvs DIR ...] [--pmks DIR ...] [--pylinkage] [--no-compare] [--json PATH]

For every file in the given folders (default: the research copies under /tmp/research/examples/ where they
exist, as benchmarks/peers_layout.py lays them out from checkouts of Pyslvs and PMKS; the examples are never
part of this repository): import it as ``linkage import`` would, solve it at
the source's own input values and measure how far each source point lies from where the source draws it
(relative to the mechanism's size; the goal is 1e-6), then run ``linkage compare`` (MuJoCo against the
analytic solution) on the file as ``linkage import`` writes it, with no option, as a user outside would: over a
turn of the input (a slider: one second at its default speed, the mechanism's size), or where the source
stops earlier (the input cannot turn fully, leaves its assembly range, passes a singular pose or a change
point where a dyad's pivots meet) over the ``input_range`` the import writes, the range the source moves it
through (sim.service.importing.driven; docs/CONVENTIONS.md). Several inputs are driven as Pyslvs drives them:
each in turn, the others held at their start (the import holds all but the first). A file that is refused
is listed with the one line the tool gives.

Pyslvs' bare expressions carry no inputs: they are read from a comment ``# inputs (base, driver): [...]``
(the research copies have one), or for the synthesis collections from ``classification.json`` beside the
examples folder.

``--pylinkage`` builds pylinkage's own example linkages with pylinkage (installed) and compares their poses and
paths against our files for them, written by hand under benchmarks/peers/pylinkage/ (pylinkage is a Python
library, not a file format). Prints one table and the counts.
"""

from __future__ import annotations

import argparse
import ast
import json
import math
import re
import sys
import time
import tomllib
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks" / "peers"))

from analytic import ParameterError, kinds  # noqa: E402
from analytic.format import foreign, linkfile  # noqa: E402
from analytic.mechanism import Mechanism  # noqa: E402
from sim import service  # noqa: E402
from sim.service import importing  # noqa: E402

RESEARCH = Path("/tmp/research/examples")
POSE_GOAL = 1e-6          # / size: the source's pose reproduced (issue 16)


def reason_class(msg: str) -> str:
    for key, label in (("gear mesh", "needs gears"), ("not a chain of dyads", "needs a general group"),
                       ("with prismatic pairs", "group with prismatic pairs"),
                       ("two prismatic pairs", "needs a PP dyad kind"), ("locks the mechanism", "locked"),
                       ("cannot move", "locked"), ("neither a Pyslvs", "not a mechanism file")):
        if key in msg:
            return label
    return "other"


def run_compare(data: dict, source: str) -> tuple[str, str, tuple[float, float] | None]:
    """(verdict, note, rocking range or None) of ``linkage compare`` on the file ``linkage import`` writes
    for ``data``: over a turn (a slider: a second at its default speed), or where the source stops earlier
    (the input cannot turn fully, leaves its assembly range, passes a singular pose or a change point where a
    dyad's pivots meet) rocking over the ``input_range`` the import writes (sim.service.importing.driven)."""
    data, why = importing.driven(data, source)
    m = Mechanism.from_definition(linkfile.from_data(data, source, Path(source).stem), {})
    text = data.get("input_range")
    rng = importing.range_values(m, text) if text else None
    try:
        _, c = service.compare(m, 1.0, input_range=rng)
    except ParameterError as exc:
        return "not run", str(exc), rng
    note = ""
    if rng is not None:
        first = m.inputs[0]
        if first.angular:
            note = f"rocking {math.degrees(rng[0]):.1f} to {math.degrees(rng[1]):.1f} deg"
        else:
            note = f"rocking {rng[0] / m.scale:.4g} to {rng[1] / m.scale:.4g} {m.units}"
        note += " (the file's input_range"
        if " meet (" in why:
            note += "; between change points: a full run passes one where a dyad's pivots meet, where the source stops"
        note += ")"
    if not c.passed:
        note += finer(m, rng)
    return ("passed" if c.passed else "FAILED"), note, rng


def finer(m: Mechanism, rng) -> str:
    """A failed compare run again at a quarter of the chosen time step: integration accuracy or the model?"""
    from sim.model import Settings, choose_timestep
    h = choose_timestep(m.rocking(*rng) if rng else m, 1.0) / 4
    try:
        _, c = service.compare(m, 1.0, Settings(timestep=h), input_range=rng)
    except ParameterError as exc:
        return f"; at --timestep {h:.3g}: {exc}"
    return f"; {'passes' if c.passed else 'fails too'} at --timestep {h:.3g}"


def pose_error(m: Mechanism, pose: dict) -> float:
    """Largest distance of a source point from its drawn place at the source's input values, / size."""
    sol = m.solve(np.array([[i.motion.q0 for i in m.inputs]]))
    xy = np.array(list(pose.values()), dtype=float)
    size = float(np.max(np.linalg.norm(xy[:, None] - xy[None], axis=-1)))
    err = max(math.hypot(sol["x" + p][0] / m.scale - x, sol["y" + p][0] / m.scale - y) for p, (x, y) in pose.items())
    return err / size


def pyslvs_inputs(path: Path, collections: dict) -> list | None:
    if path.suffix == ".pyslvs":
        return None
    text = path.read_text(errors="replace")
    m = re.search(r"^#\s*inputs \(base, driver\):\s*(\[.*\])\s*$", text, re.M)
    if m:
        return [tuple(p) for p in ast.literal_eval(m.group(1))]
    name = re.search(r"^# Pyslvs collection '([^']+)'", text, re.M)
    if name and name.group(1) in collections:
        return [tuple(p) for p in collections[name.group(1)]]
    return []


def row_for(collection: str, path: Path, inputs, compare: bool) -> dict:
    row = {"collection": collection, "example": path.name, "status": "", "pose": None, "compare": "", "reason": ""}
    try:
        data = foreign.read(path, inputs or None)
        d = linkfile.from_data(data, str(path), path.stem)
        m = Mechanism.from_definition(d, {})
    except ParameterError as exc:
        msg = str(exc).replace(f"{path}: ", "")
        row.update(status="refused", reason=msg, cls=reason_class(msg))
        return row
    row["status"] = "imported"
    row["pose"] = pose_error(m, data["pose"])
    if compare and len(m.inputs) == 1:
        row["compare"], row["reason"], _ = run_compare(data, str(path))
    elif compare:                          # as Pyslvs drives them: each input in turn, the others held
        verdicts, notes = [], []
        for k in range(len(m.inputs)):
            items = [dict(x) for x in data["inputs"]]
            items = [items[k]] + items[:k] + items[k + 1:]
            size = foreign.pose_size(data)
            for j, item in enumerate(items):
                rate, value = kinds.get(item["kind"]).default_rate(size)
                item[rate] = value if j == 0 else 0.0
            verdict, note, _ = run_compare({**data, "inputs": items}, str(path))
            verdicts.append(verdict)
            notes.append(f"input {k + 1} ({items[0].get('link') or items[0].get('point')}), the others held: "
                         f"{verdict}{'; ' + note if note else ''}")
        row["compare"] = ("passed" if all(v == "passed" for v in verdicts) else
                          "FAILED" if "FAILED" in verdicts else "not run")
        row["reason"] = " | ".join(notes)
    return row


def pylinkage_rows(compare: bool) -> list[dict]:
    import pylinkage as pl
    if not hasattr(pl, "Linkage"):           # benchmarks/peers/pylinkage/ (our files) read as a namespace package
        raise SystemExit("peers.py: pylinkage is not installed (pip install pylinkage==1.3.0), or leave out "
                         "--pylinkage")
    import pylinkage_models as models
    rows = []
    here = ROOT / "benchmarks" / "peers" / "pylinkage"
    for name in list(models.MODELS) + list(models.LOCKED):
        row = {"collection": "pylinkage", "example": name, "status": "", "pose": None, "compare": "", "reason": ""}
        rows.append(row)
        try:
            m = Mechanism.from_definition(linkfile.read(here / f"{name}.toml"), {})
        except ParameterError as exc:
            msg = str(exc).split(".toml: ", 1)[-1]
            row.update(status="refused", reason=msg, cls=reason_class(msg))
            continue
        row["status"] = "built"
        linkage, points, (anchor, tip) = models.MODELS[name](pl)
        comps = list(linkage.components)
        steps = [list(linkage.step(iterations=1, dt=0))[0]] + list(linkage.step(iterations=40))
        xy = {p: np.array([[np.nan if v is None else v for v in s[comps.index(c)]] for s in steps], dtype=float)
              for p, c in points.items()}
        d = xy[tip] - xy[anchor]
        q = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
        q += 2 * math.pi * round((m.inputs[0].motion.q0 - q[0]) / (2 * math.pi))
        size = max(float(np.nanmax(np.linalg.norm(v[:, None] - v[None], axis=-1))) for v in xy.values()) or 1.0
        size = max(size, float(np.nanmax([np.linalg.norm(a[0] - b[0]) for a in xy.values() for b in xy.values()])))
        rng = None
        if compare:
            row["compare"], row["reason"], rng = run_compare(tomllib.loads((here / f"{name}.toml").read_text()),
                                                             str(here / f"{name}.toml"))
        sol = m.solve(q)
        keep = np.ones(len(q), bool) if rng is None else (q >= rng[0]) & (q <= rng[1])
        errs = [np.linalg.norm(np.stack([sol["x" + p], sol["y" + p]], axis=-1) / m.scale - v, axis=-1)
                for p, v in xy.items() if "x" + p in sol]
        err = np.max(errs, axis=0) / size
        row["pose"] = float(err[0]) if np.isfinite(err[0]) else None
        compared = keep & np.isfinite(err)
        row["path"] = float(np.max(err[compared])) if compared.any() else None
        row["path_steps"] = f"{int(compared.sum())}/{len(q)}"
        if row["pose"] is None:
            row["reason"] = (row["reason"] + "; " if row["reason"] else "") + "drawn pose not assembled by our file"
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--pyslvs", action="append", default=[], metavar="DIR",
                    help="a folder of Pyslvs projects (.pyslvs) or expressions (.txt); repeatable")
    ap.add_argument("--pmks", action="append", default=[], metavar="DIR", help="a folder of PMKS text files")
    ap.add_argument("--pylinkage", action="store_true", help="pylinkage's examples against our files for them")
    ap.add_argument("--no-compare", action="store_true", help="import and check poses only")
    ap.add_argument("--json", metavar="PATH", help="write the rows as JSON")
    args = ap.parse_args(argv)
    if not (args.pyslvs or args.pmks or args.pylinkage):
        args.pyslvs = [str(RESEARCH / d) for d in ("pyslvs", "pyslvs_yaml", "pyslvs_collection")
                       if (RESEARCH / d).is_dir()]
        args.pmks = [str(RESEARCH / d) for d in ("pmks", "pmks_walkers_urls") if (RESEARCH / d).is_dir()]
        args.pylinkage = True
    warnings.simplefilter("ignore", RuntimeWarning)
    t0 = time.perf_counter()
    rows = []
    for folder in args.pyslvs:
        f = Path(folder)
        cls_file = f.parent.parent / "classification.json"
        collections = {x["name"]: x["input_pairs"] for x in json.loads(cls_file.read_text())
                       if x["collection"] == "pyslvs.collection"} if cls_file.is_file() else {}
        for path in sorted(f.glob("*.txt")) + sorted(f.glob("*.pyslvs")):
            rows.append(row_for(f"pyslvs/{f.name}", path, pyslvs_inputs(path, collections), not args.no_compare))
    for folder in args.pmks:
        f = Path(folder)
        for path in sorted(f.glob("*.txt")):
            rows.append(row_for(f"pmks/{f.name}", path, None, not args.no_compare))
    if args.pylinkage:
        rows += pylinkage_rows(not args.no_compare)

    def fmt(x):
        return "-" if x is None else f"{x:.1e}"

    w = max(len(r["example"]) for r in rows) if rows else 10
    print(f"{'collection':<26s} {'example':<{w}s} {'status':<9s} {'pose err':>8s} {'path err':>8s} "
          f"{'compare':<8s} reason / note")
    for r in rows:
        path = fmt(r.get("path")) + (f" ({r['path_steps']})" if r.get("path_steps") else "") if "path" in r else "-"
        print(f"{r['collection']:<26s} {r['example']:<{w}s} {r['status']:<9s} {fmt(r['pose']):>8s} {path:>8s} "
              f"{r['compare'] or '-':<8s} {r['reason']}")
    n = len(rows)
    ok = [r for r in rows if r["status"] in ("imported", "built")]
    good_pose = [r for r in ok if r["pose"] is not None and r["pose"] <= POSE_GOAL]
    passed = [r for r in ok if r["compare"] == "passed"]
    print(f"\n{n} examples: {len(ok)} imported, {len(good_pose)} reproduce the pose to {POSE_GOAL:g} of the size, "
          f"{len(passed)} pass compare; {n - len(ok)} refused ({time.perf_counter() - t0:.0f} s)")
    by = {}
    for r in rows:
        if r["status"] == "refused":
            by.setdefault(r["cls"], []).append(r["example"])
    for k, v in sorted(by.items()):
        print(f"  refused, {k}: {len(v)} ({', '.join(v)})")
    bad = [r for r in ok if r["compare"] not in ("passed", "")]
    for r in bad:
        print(f"  compare {r['compare']}: {r['collection']}/{r['example']}: {r['reason']}")
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
