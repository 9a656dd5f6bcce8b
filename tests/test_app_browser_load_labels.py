"""The loads' labels on the canvas do not cover each other (issue 31 item 3's picture: near a joint with a
force, a spring, a damper, a torsion spring and friction the labels piled up): every label's box is clear of
every other label's, of every joint and of every joint's name, and stays near the load it names. Screenshots
go to $LINKAGE_SCREENSHOTS when it is set."""

from __future__ import annotations

import math
import os
import threading
from pathlib import Path

import pytest
from fourbar_text import fourbar_text  # the hand four-bar as text (tests/fourbar_text.py)

from sim.front import app

pytestmark = pytest.mark.slow
pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
CHROMIUM = "/usr/bin/chromium"
if not os.path.exists(CHROMIUM):
    pytest.skip(f"{CHROMIUM} is not installed", allow_module_level=True)
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--disable-component-update", "--no-first-run"]
TIMEOUT_MS = 30_000
NEAR = 110
"""[px] the farthest a label may be put from its load: within a few lines of text (13 px) and its own width."""

CROWDED = fourbar_text("crowded", 1.0) + """
[friction]
mu = 0.1
pin_radius = 0.005

[[loads]]
name = "cut"
kind = "force"
link = "2"
point = "C"
direction = [-1, 0]
magnitude = 16

[[loads]]
name = "hinge"
kind = "torsion_spring"
joint = "C"
links = ["2", "3"]
stiffness = 0.5
free_angle = "90deg"

[[loads]]
name = "visc"
kind = "damper"
joint = "C"
links = ["2", "3"]
damping = 0.1

[[loads]]
name = "s"
kind = "spring"
between = [["ground", [0.1, 0.25]], ["3", [0.25, 0]]]
stiffness = 20
free_length = 0.05

[[loads]]
name = "d"
kind = "damper"
between = [["ground", [0.1, 0.25]], ["3", [0.25, 0]]]
damping = 0.5

[[loads]]
name = "brake"
kind = "torque"
link = "3"
magnitude = 0.2
"""


LABELS = ["cut", "hinge", "visc", "s", "d", "brake", "μ", "μ", "μ", "μ"]
"""Every load's label and friction's at each of the four pin joints."""


@pytest.fixture
def page(browser):
    srv = app.AppServer(0, {"name": "crowded", "text": CROWDED})
    threading.Thread(target=srv.serve_forever, daemon=True).start()
    ctx = browser.new_context(viewport={"width": 1440, "height": 1000})
    pg = ctx.new_page()
    pg.set_default_timeout(TIMEOUT_MS)
    errors = []
    pg.on("pageerror", lambda e: errors.append(f"pageerror: {e}"))
    pg.goto(srv.url)
    pg.wait_for_function("window.linkageState && window.linkageState.figures && window.linkageLabels")
    yield pg
    ctx.close()
    srv.shutdown()
    assert errors == []


def overlap(a, b) -> bool:
    return a["x"] < b["x"] + b["w"] and b["x"] < a["x"] + a["w"] and a["y"] < b["y"] + b["h"] and b["y"] < a["y"] + a["h"]


@pytest.mark.parametrize("frame", [0, 40, 100, 200, 300])
def test_no_load_label_covers_another_a_joint_or_a_joints_name(page, frame):
    page.click("#play")
    page.fill("#scrub", str(frame))
    page.dispatch_event("#scrub", "input")
    page.wait_for_function(f"+document.querySelector('#scrub').value === {frame} && "
                           f"window.linkageLabels.labels.length === {len(LABELS)}")
    got = page.evaluate("window.linkageLabels")
    labels, obstacles = got["labels"], got["obstacles"]
    assert sorted(lb["text"].split()[0] for lb in labels) == sorted(LABELS)
    assert len(obstacles) == 2 * 4                    # the four joints and their names
    for k, a in enumerate(labels):
        for b in labels[k + 1:]:
            assert not overlap(a, b), (a, b)
        for o in obstacles:
            assert not overlap(a, o), (a, o)
        # each stays by its load: the box's nearest point to the load's anchor within NEAR
        cx = min(max(a["ax"], a["x"]), a["x"] + a["w"])
        cy = min(max(a["ay"], a["y"]), a["y"] + a["h"])
        assert math.hypot(cx - a["ax"], cy - a["ay"]) <= NEAR, a
    folder = os.environ.get("LINKAGE_SCREENSHOTS")
    if folder:
        Path(folder).mkdir(parents=True, exist_ok=True)
        page.locator("#view").screenshot(path=str(Path(folder) / f"load_labels_{frame}.png"))
