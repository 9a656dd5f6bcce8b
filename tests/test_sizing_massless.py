"""`dynamics --target-fluctuation` on a linkage whose reduced inertia vanishes (massless links, SPEC "Loads":
m = 0): the sizing starts from the bare linkage, whose equation of motion is then singular; it is refused in
one line naming the cause (it used to integrate the singular equation without end)."""

from __future__ import annotations

from tests.cli_runner import run as linkage
from tests.test_published_examples import KHURMI_16_12, write


def test_sizing_a_massless_shaft_is_refused_in_one_line(tmp_path):
    path = write(tmp_path, "shaft.toml", KHURMI_16_12)
    r = linkage("dynamics", path, "--motor", "1,150rpm", "--target-fluctuation", "0.061")
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in r.stderr
    assert "--target-fluctuation" in lines[0] and "reduced inertia vanishes" in lines[0]
    assert "phishaft" in lines[0] and "--flywheel" in lines[0]          # where, and the way out
