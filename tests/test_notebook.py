"""A notebook executed as Jupyter runs it (issue 39, item 4): a mechanism and each result show their drawing
and table as HTML, the runs animated. Slow tier: a kernel starts (2-4 s) and MuJoCo runs."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOK = ROOT / "docs" / "notebooks" / "quickstart.ipynb"


@pytest.mark.slow
def test_the_quickstart_notebook_runs_and_shows_drawings_and_tables(monkeypatch):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])))
    monkeypatch.setenv("MUJOCO_GL", os.environ.get("MUJOCO_GL", "egl"))
    nb = nbformat.read(NOTEBOOK, as_version=4)
    nbclient.NotebookClient(nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(ROOT)}}).execute()
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert all(not any(o.output_type == "error" for o in c.outputs) for c in code)
    html = [next((o.data.get("text/html", "") for o in c.outputs if o.output_type == "execute_result"), "")
            for c in code]
    mech, analysis, comparison, forces = html[:4]
    for page in (mech, analysis, comparison, forces):
        assert page.count("<svg") == 1 and "<table" in page
    assert ">l1<" in mech and "0.12" in mech                         # the parameter table, the value given
    assert "<animate" in analysis and "<animate" in comparison         # the runs move
    assert "PASSED" in comparison
    assert "peak drive phi1" in forces
