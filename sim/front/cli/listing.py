"""``linkage list``: the built-in and library mechanisms."""

from __future__ import annotations



from sim import service


def register(sub) -> None:
    p = sub.add_parser("list", help="the built-in and library mechanisms")
    p.set_defaults(func=run)


def run(args) -> int:
    rows = service.list_mechanisms()
    width = max(len(r["name"]) for r in rows)
    for r in rows:
        tag = "built-in" if r["builtin"] else f"{r['inputs']} input" + ("s" if r["inputs"] > 1 else "")
        print(f"{r['name']:<{width}s}  {tag:<9s} {r['description']}")
    return 0
