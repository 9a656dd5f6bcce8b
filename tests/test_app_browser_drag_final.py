"""A drag's last state is a fresh solve of the values it leaves (issue 31 item 5): while a point is dragged the
page asks for the plotted outputs only (the drag's steps are cheaper), and once it is released the full
answer must bring every output and the figures of merit back, equal to what the server computes for the
saved values from scratch."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

from sim.front import app

pytestmark = pytest.mark.slow
CHROMIUM = os.environ.get("LINKAGE_CHROMIUM", "/usr/bin/chromium")
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--disable-component-update", "--no-first-run"]
TIMEOUT_MS = 30_000
SAME = 1e-9
"""[m, rad and the figures' units] both answers are solved from the same values in the same process and
sent at full precision (JSON keeps 17 digits): only the values' round trip through the page's state
(numbers written back as typed) separates them."""
DRAWN = 2e-6
"""[m] the drag's closure (1e-9 of the size) plus the 7 digits its preview steps are sent with."""


@pytest.fixture
def page(browser, server):
    ctx = browser.new_context(viewport={"width": 1440, "height": 900})
    pg = ctx.new_page()
    pg.set_default_timeout(TIMEOUT_MS)
    errors = []
    pg.on("pageerror", lambda e: errors.append(f"pageerror: {e}"))
    pg.goto(server.url)
    pg.wait_for_function("window.linkageState && window.linkageState.figures")
    yield pg
    ctx.close()
    assert errors == []


def test_after_a_drag_the_page_shows_a_fresh_solve_of_the_values_it_saved(page):
    page.click("#play")
    page.fill("#scrub", "40")
    page.dispatch_event("#scrub", "input")
    n_outputs = page.evaluate("window.linkageState.describe.outputs.length")
    x, y = page.evaluate("""(() => { const s = window.linkageState;
        return window.linkageCanvas.toClient(s.points.C.x[40], s.points.C.y[40]); })()""")
    page.mouse.move(x, y)
    page.mouse.down()
    sizes = []
    for k in range(1, 6):
        r0 = page.evaluate("+document.body.dataset.revision")
        page.mouse.move(x + 6 * k, y - 4 * k)
        page.wait_for_function(f"+document.body.dataset.revision > {r0}")
        sizes.append(page.evaluate("Object.keys(window.linkageState.outputs).length"))
    target = page.evaluate("window.linkageDrag.target")
    page.mouse.up()
    # while dragging: the plotted outputs only (fewer than the four-bar's all)
    assert max(sizes) < n_outputs
    page.wait_for_function(f"Object.keys(window.linkageState.outputs).length === {n_outputs} && "
                           "!document.querySelector('#figures').classList.contains('pending')")
    shown = page.evaluate("({set: window.linkageState.parameters, outputs: window.linkageState.outputs, "
                          "points: window.linkageState.points, figures: window.linkageState.figures, "
                          "frame: +document.querySelector('#scrub').value})")
    assert shown["frame"] == 40                                   # the pose the drag was made in
    assert math.hypot(shown["points"]["C"]["x"][40] - target[0], shown["points"]["C"]["y"][40] - target[1]) < DRAWN
    fresh = app.solve({"mechanism": "fourbar", "set": shown["set"], "samples": 361, "figures": True})
    assert shown["set"]["l2"] != pytest.approx(0.3, rel=1e-3)     # the drag did change the values
    for name, v in fresh["outputs"].items():
        assert np.allclose(np.array(shown["outputs"][name], float), np.array(v, float), atol=SAME, equal_nan=True), name
    for p, xy in fresh["points"].items():
        for c in "xy":
            assert np.allclose(shown["points"][p][c], xy[c], atol=SAME), p
    numbers = {k: v for k, v in fresh["figures"].items() if isinstance(v, (int, float)) and not isinstance(v, bool)}
    assert numbers, "the figures of merit hold numbers to compare"
    for k, v in numbers.items():
        assert shown["figures"][k] == pytest.approx(v, abs=SAME, rel=SAME), k
