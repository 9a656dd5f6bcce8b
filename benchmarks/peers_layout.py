"""Lay out the peers' example files where ``benchmarks/peers.py`` looks for them (they are never part of this
repository): from a checkout of Pyslvs (``git clone https://github.com/KmolYuan/pyslvs``) and of the original
PMKS (``git clone https://github.com/DesignEngrLab/PMKS``; its ``Examples`` folder was removed in 2019, so
check out ``ab2d125^`` or pass the folder of an older copy).

    python benchmarks/peers_layout.py --pyslvs PYSLVS_CHECKOUT --pmks-examples PMKS/Examples [--out DIR]

Writes under DIR (default /tmp/research/examples):

* ``pyslvs/<name>.txt``: each of Pyslvs' examples (``pyslvs/example.py``) as its bare expression, with its input
  pairs in a comment ``# inputs (base, driver): [...]`` (a bare expression carries none);
* ``pyslvs_yaml/<name>.pyslvs``: the same examples as Pyslvs-UI saves a project after loading one (YAML:
  ``mechanism``, ``links``, ``input``; Pyslvs-UI ships no project files, so these are written here, in its
  layout);
* ``pyslvs_collection/<name>.txt``: Pyslvs' synthesis collections (``pyslvs/collection.py``), expression and
  input pairs (renumbered from the collection's graph edges to the expression's joints: :func:`joint_index`);
* ``pmks/``: every PMKS example file as it is; ``pmks_walkers_urls/walkers_<n>.txt``: each ``mech=`` URL of
  PMKS' ``walkers etc.txt`` (several mechanisms in one file) on its own.

The Python sources are read with ``ast.literal_eval`` (nothing of them runs).
"""

from __future__ import annotations

import argparse
import ast
import re
import shutil
import sys
from pathlib import Path

OUT = Path("/tmp/research/examples")


def literal_dict(path: Path, suffix: str) -> dict:
    """The first module-level dict literal whose name ends in ``suffix`` (``_example_list``)."""
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        target = node.targets[0] if isinstance(node, ast.Assign) else getattr(node, "target", None)
        if isinstance(target, ast.Name) and target.id.endswith(suffix):
            return ast.literal_eval(node.value)
    raise SystemExit(f"{path}: no '{suffix}' dict found; pass a Pyslvs checkout")


def snake(name: str) -> str:
    return re.sub(r"_+", "_", re.sub(r"[^a-z0-9]+", "_", name.lower().replace("'", ""))).strip("_")


def links_of(expr: str) -> list[str]:
    names = []
    for group in re.findall(r"L\[([^\]]*)\]", expr):
        for n in (x.strip() for x in group.split(",")):
            if n and n not in names:
                names.append(n)
    return names


def joint_index(k: int, same: dict) -> int:
    """A collection's joint ``k`` as its expression numbers it: a collection numbers its joints by the edges of
    its graph (then its custom points), and ``same`` merges an edge's joint into another's (a pin of three
    links); the expression lists each merged joint once, in order (the eight-bar's input (0, 3) is its J0, J2)."""
    while k in same:
        k = same[k]
    return k - sum(1 for m in same if m < k)


def project_yaml(expr: str, pairs) -> str:
    """A Pyslvs-UI project as its YAML editor saves one (block style, empty entries left out)."""
    import yaml
    data = {"pyslvs_ver": "22.07.0", "file_type": 0, "mechanism": expr,
            "links": {n: "White" if n == "ground" else "Blue" for n in links_of(expr)},
            "input": [[int(b), int(d)] for b, d in pairs]}
    return yaml.safe_dump({k: v for k, v in data.items() if v != []}, default_flow_style=False, sort_keys=False)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--pyslvs", metavar="DIR", help="a checkout of github.com/KmolYuan/pyslvs")
    ap.add_argument("--pmks-examples", metavar="DIR", help="PMKS' Examples folder (DesignEngrLab/PMKS at ab2d125^)")
    ap.add_argument("--out", default=str(OUT), metavar="DIR", help=f"where to write (default {OUT})")
    args = ap.parse_args(argv)
    out = Path(args.out)
    counts = {}
    if args.pyslvs:
        src = Path(args.pyslvs) / "pyslvs"
        examples = literal_dict(src / "example.py", "example_list")
        collections = literal_dict(src / "collection.py", "collection_list")
        for sub in ("pyslvs", "pyslvs_yaml", "pyslvs_collection"):
            (out / sub).mkdir(parents=True, exist_ok=True)
        for name, (expr, pairs) in examples.items():
            pairs = [tuple(p) for p in pairs]
            (out / "pyslvs" / f"{snake(name)}.txt").write_text(
                f"# Pyslvs example '{name}'\n# inputs (base, driver): {pairs}\n{expr}\n")
            (out / "pyslvs_yaml" / f"{snake(name)}.pyslvs").write_text(project_yaml(expr, pairs))
        for name, c in collections.items():
            pairs = [tuple(p[0]) if isinstance(p[0], (tuple, list)) else tuple(p) for p in c.get("input", [])]
            pairs = [tuple(joint_index(j, c.get("same", {})) for j in p) for p in pairs]
            (out / "pyslvs_collection" / f"{snake(name)}.txt").write_text(
                f"# Pyslvs collection '{name}'\n# inputs (base, driver): {pairs}\n{c['expression']}\n")
        counts.update(pyslvs=len(examples), pyslvs_yaml=len(examples), pyslvs_collection=len(collections))
    if args.pmks_examples:
        src = Path(args.pmks_examples)
        (out / "pmks").mkdir(parents=True, exist_ok=True)
        (out / "pmks_walkers_urls").mkdir(parents=True, exist_ok=True)
        files = sorted(src.glob("*.txt"))
        for f in files:
            shutil.copyfile(f, out / "pmks" / f.name)
        walkers = src / "walkers etc.txt"
        urls = [ln.strip() for ln in walkers.read_bytes().decode("latin-1").splitlines() if "mech=" in ln] \
            if walkers.is_file() else []
        for k, url in enumerate(urls, 1):
            (out / "pmks_walkers_urls" / f"walkers_{k}.txt").write_text(url + "\n")
        counts.update(pmks=len(files), pmks_walkers_urls=len(urls))
    if not counts:
        ap.error("give --pyslvs and/or --pmks-examples")
    print(", ".join(f"{k}: {v}" for k, v in counts.items()) + f" (under {out})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
