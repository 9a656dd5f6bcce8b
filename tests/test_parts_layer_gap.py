"""The layers' heights (issue 41, item 2): each layer as thick as its thickest part, ``[parts].layer_gap``
between layers, read back from the exported STL solids (trimesh reads them; nothing of the export is shared)
against the stack the test adds up by hand from the BOM's layers and thicknesses."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from tests.cli_runner import run
from tests.test_one_mass_truth import FOURBAR

trimesh = pytest.importorskip("trimesh")


@pytest.mark.parametrize("gap, thick2", [(1.5, 5), (4.0, 8)])
def test_each_layer_sits_a_gap_above_the_thickest_part_below(tmp_path, gap, thick2):
    text = FOURBAR.replace("clearance = 0.2", f"clearance = 0.2\nlayer_gap = {gap}")
    text = text.replace("[parts]", f"[mass.links.2]\nthickness = {thick2}\n\n[parts]")
    path = tmp_path / "m.toml"
    path.write_text(text)
    r = run("export", path, "--stl", tmp_path / "stl", "--bom", tmp_path / "bom.csv")
    assert r.returncode == 0, r.stderr
    with open(tmp_path / "bom.csv", newline="") as fh:
        rows = {row["link"]: row for row in csv.DictReader(fh)}
    layers = {ln: int(row["layer"]) for ln, row in rows.items()}
    thick = {ln: float(row["thickness"]) for ln, row in rows.items()}
    assert thick["2"] == pytest.approx(thick2)
    assert len(set(layers.values())) >= 2                   # a stack to check: the coupler lies over the rest
    base, level = {}, 0.0
    for k in range(max(layers.values()) + 1):
        base[k] = level
        level += max(thick[ln] for ln in layers if layers[ln] == k) + gap
    for ln, k in layers.items():
        mesh = trimesh.load(tmp_path / "stl" / f"{ln}.stl")
        zmin, zmax = float(np.min(mesh.vertices[:, 2])), float(np.max(mesh.vertices[:, 2]))
        # the STL's float32 vertices: 1e-5 mm on heights of tens of mm
        assert zmin == pytest.approx(base[k], abs=1e-4), (ln, k)
        assert zmax == pytest.approx(base[k] + thick[ln], abs=1e-4), (ln, k)
