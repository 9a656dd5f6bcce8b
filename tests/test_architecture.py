"""The architecture as docs/reference.md draws it, read from the source: data flows down (format -> topology ->
solver -> applications -> service -> front ends) with no import circle, the front ends go through the
service layer, and the command line's parser is built without the heavy libraries."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

FRONT_MAY_IMPORT = ("sim.service", "sim.output", "sim.readers", "sim.front", "linkage")
"""What a front end (sim/front/...) imports of the project: the service layer (sim.service, one module per use
case), the door in front of it (``linkage``, whose functions the commands call with keywords), the output
layer, the readers of the command line's small input files and the front ends' own modules; of ``analytic``
only the package's names (``ParameterError``, ``load``, ...)."""

FRONT_DEBT: dict[str, set[str]] = {}
"""Front-end imports that still bypass the service (issue 30's debt: 57 in 20 files when the rule was written,
all paid since): the test fails on any other, and on an entry here that is no longer needed."""


def modules() -> dict[str, Path]:
    out = {}
    for top in ("analytic", "sim", "mjcf", "linkage"):
        for f in (ROOT / top).rglob("*.py"):
            name = ".".join(f.relative_to(ROOT).with_suffix("").parts)
            out[name.removesuffix(".__init__")] = f
    return out


def imports_of(path: Path, known) -> set[str]:
    """The project modules ``path`` imports, anywhere in it (a function's import counts too)."""
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            for a in node.names:
                full = f"{node.module}.{a.name}"
                out.add(full if full in known else node.module)
    return {m for m in out if m in known}


def test_no_module_imports_itself_round_a_circle():
    """Edges into a package's __init__ are left out: a package re-exports its modules' names."""
    known = modules()
    packages = {m for m, f in known.items() if f.name == "__init__.py"}
    graph = {m: imports_of(f, known) - packages for m, f in known.items()}
    state, circles = {}, []

    def visit(m, stack):
        state[m] = "open"
        for n in sorted(graph[m]):
            if state.get(n) == "open":
                circles.append(stack[stack.index(n):] + [n])
            elif n not in state:
                visit(n, stack + [n])
        state[m] = "done"

    for m in sorted(graph):
        if m not in state:
            visit(m, [m])
    assert not circles, circles


def test_front_ends_go_through_the_service_layer():
    known = modules()
    found = {}
    for f in sorted((ROOT / "sim" / "front").rglob("*.py")):
        rel = f.relative_to(ROOT).as_posix()
        bad = {m for m in imports_of(f, known) if m.split(".")[0] in ("analytic", "sim", "mjcf", "linkage")
               and m not in ("analytic", "sim") and not m.startswith(FRONT_MAY_IMPORT)}
        if bad:
            found[rel] = bad
    new = {f: sorted(m - FRONT_DEBT.get(f, set())) for f, m in found.items() if m - FRONT_DEBT.get(f, set())}
    assert not new, f"front ends importing past the service layer (add a service function instead): {new}"
    paid = {f: sorted(m - found.get(f, set())) for f, m in FRONT_DEBT.items() if m - found.get(f, set())}
    assert not paid, f"debts paid: remove them from FRONT_DEBT: {paid}"


def test_the_parser_and_linkage_list_import_no_heavy_library():
    """Building every command's options and listing the mechanisms load neither scipy, matplotlib, MuJoCo
    nor Dask (each costs 0.2-0.7 s of CPU at every start): what keeps ``linkage list`` near 0.3 s."""
    code = ("import sys, io, contextlib\nfrom sim.front.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n    assert main(['list']) == 0\n"
            "print(sorted(m for m in ('scipy', 'matplotlib', 'mujoco', 'dask', 'SALib', 'pymoo', 'shapely', "
            "'ezdxf', 'trimesh', 'build123d') if m in sys.modules))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "[]", r.stdout
