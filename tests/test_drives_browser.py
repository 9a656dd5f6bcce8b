"""The excavator in a real browser (Playwright driving /usr/bin/chromium): dragging a cylinder's pin moves that
cylinder, and the page shows the frame whose length of that cylinder is nearest the one the drag found (not the
first input's: the stick's pin sets the frame by the stick's length)."""

from __future__ import annotations

import os

import numpy as np
import pytest

pytestmark = pytest.mark.slow
CHROMIUM = os.environ.get("LINKAGE_CHROMIUM", "/usr/bin/chromium")
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--disable-component-update", "--no-first-run"]
TIMEOUT_MS = 30_000


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


def test_dragging_the_stick_cylinders_pin_shows_the_frame_of_its_length(page):
    r0 = page.evaluate("+document.body.dataset.revision")
    page.select_option("#mechanism", "excavator")
    page.wait_for_function(f"+document.body.dataset.revision > {r0} && window.linkageState.mechanism === 'excavator'")
    page.click("#play")                                    # paused
    page.fill("#scrub", "20")
    page.dispatch_event("#scrub", "input")
    x, y = page.evaluate("""(() => { const s = window.linkageState;
        return window.linkageCanvas.toClient(s.points.D2.x[20], s.points.D2.y[20]); })()""")
    page.mouse.move(x, y)
    page.mouse.down()
    r0 = page.evaluate("+document.body.dataset.revision")
    page.mouse.move(x - 25, y - 25, steps=3)
    page.wait_for_function(f"+document.body.dataset.revision > {r0} && window.linkageDrag")
    page.mouse.up()
    drag = page.evaluate("window.linkageDrag")
    assert drag["input_name"] == "s_stick" and drag["input"] is not None
    s_stick = np.array(page.evaluate("window.linkageState.inputs.s_stick"), dtype=float)
    frame = int(page.evaluate("+document.querySelector('#scrub').value"))
    assert frame == int(np.argmin(np.abs(s_stick - drag["input"])))     # the stick's own length picks the frame
    assert frame != 20                                                   # and the drag did move it


def test_the_forces_panel_lists_each_cylinders_peak_push_and_pull(page):
    r0 = page.evaluate("+document.body.dataset.revision")
    page.select_option("#mechanism", "dump_tipper")
    page.wait_for_function(f"+document.body.dataset.revision > {r0} && window.linkageState.mechanism === 'dump_tipper'")
    page.click("#tab-forces")
    page.fill("#gravity", "0,-9.81")
    page.wait_for_function("window.linkageForces && window.linkageForces.mechanism === 'dump_tipper' && "
                           "window.linkageForces.loads.gravity !== null")
    data = page.evaluate("window.linkageForces")
    drive = np.array(data["drives"]["s_tip"], dtype=float)
    push = data["actuators"]["tip"]["push"]
    # the peak is a sample of the drawn drive force, which the page asks to 7 significant digits of its peak
    assert push["F"] == pytest.approx(drive.max(), rel=1e-6)
    # its pressure on the file's bore of 160 mm, by hand: F / (pi 0.16^2 / 4); one division
    assert push["pressure"] == pytest.approx(push["F"] / (np.pi * 0.16 ** 2 / 4), rel=1e-12)
    row = page.locator('#force-peaks tr[data-cylinder="tip push"]')
    assert row.count() == 1
    cells = row.locator("td").all_inner_texts()
    assert cells[1] == "cylinder tip push" and "bar" in cells[4]
    assert page.locator('#force-peaks tr[data-cylinder="tip pull"] td').all_inner_texts()[5] == "never"
