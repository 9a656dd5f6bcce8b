"""The user documentation (``docs/``) cannot rot: every Python block of every page runs as written, in page
order, in one namespace per page, in an empty folder; every ``linkage ...`` line of a ``bash`` block runs
(in process) and exits 0 without a traceback, after the page's earlier blocks (which may write its inputs).
``text`` blocks are what a person types that a test cannot (``linkage app`` serves a page; the reference's
lists of commands render videos, run minutes-long searches or read the user's own files) and ``toml``/
``console`` blocks are shown, not run. The slow tier builds the site with Sphinx and ``-W`` (a warning
fails). No page may point outside the repository."""

from __future__ import annotations

import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from tests.cli_runner import run as linkage

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
PAGES = sorted(p for p in DOCS.rglob("*.md") if "_build" not in p.parts)
BLOCK = re.compile(r"^```(\w+)[^\n]*\n(.*?)^```", re.S | re.M)


def _blocks(page: Path) -> list[tuple[str, str]]:
    return [(m.group(1), m.group(2)) for m in BLOCK.finditer(page.read_text())]


def test_the_docs_have_a_page_per_workflow_and_an_api_reference():
    names = {p.relative_to(DOCS).as_posix() for p in PAGES}
    for page in ("index.md", "api.md", "tutorials/analyse.md", "tutorials/simulate-compare.md",
                 "tutorials/loads-forces.md", "tutorials/parts.md", "tutorials/synthesis.md",
                 "tutorials/tolerance.md", "tutorials/app.md"):
        assert page in names, page
    index = (DOCS / "index.md").read_text()
    for page in names - {"index.md"}:
        assert page.removesuffix(".md") in index, f"{page} is in no table of contents"


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(DOCS).as_posix())
def test_every_code_block_of_the_page_runs(page, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__docs__"}
    ran = 0
    for language, code in _blocks(page):
        if language == "python":
            exec(compile(code, f"{page.name} (python block)", "exec"), namespace)
            ran += 1
        elif language == "bash":
            for line in code.splitlines():
                words = shlex.split(line, comments=True)
                if words[:1] != ["linkage"]:
                    continue
                r = linkage(*words[1:], cwd=tmp_path)
                assert r.returncode == 0 and "Traceback" not in r.stderr, (line, r.stderr[-2000:])
                ran += 1
    capsys.readouterr()
    if page.name not in ("CONVENTIONS.md", "api.md", "reference.md"):   # references show; api.md's examples
        assert ran > 0, f"{page.name} runs no block"        # are the docstrings', run by tests/test_api.py


def test_no_page_points_outside_the_repository():
    """A relative link or an include resolves inside the repository; no page cites the contract kept outside
    it (SPEC) for a format a user must read."""
    for page in PAGES:
        text = page.read_text()
        for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", text):
            if not target.startswith(("http://", "https://", "mailto:")):
                resolved = (page.parent / target).resolve()
                assert resolved.is_relative_to(ROOT) and resolved.exists(), (page.name, target)
        assert not re.search(r"\bSPEC\b", text), f"{page.name} cites SPEC, which users cannot read"


@pytest.mark.slow
def test_the_site_builds_without_a_warning(tmp_path):
    pytest.importorskip("sphinx")
    pytest.importorskip("myst_parser")
    r = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html", str(DOCS),
                        str(tmp_path / "html")], capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert r.returncode == 0, r.stderr[-4000:]
    api = (tmp_path / "html" / "api.html").read_text()
    for name in ("linkage.forces", "linkage.Forces", "to_dict", "keyword"):
        assert name in api, name
