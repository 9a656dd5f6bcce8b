"""The Dynamics tab's motor speeds in the units ``linkage dynamics --motor T0,W0`` takes (SPEC "Dynamics under a
motor": W0 in rad/s, or with an ``rpm`` suffix): the page's W0 and start speed are a number in the unit chosen
beside W0 (rpm or rad/s) or a number written with its unit, and the request carries rad/s (SI) whichever way
it was given. The request is caught before it reaches the server (no motor run is needed to read it)."""

from __future__ import annotations

import math
import os

import pytest

pytestmark = pytest.mark.slow
pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
CHROMIUM = "/usr/bin/chromium"
if not os.path.exists(CHROMIUM):
    pytest.skip(f"{CHROMIUM} is not installed", allow_module_level=True)
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--disable-component-update", "--no-first-run"]
TIMEOUT_MS = 30_000
SHOWN = 1e-5
"""Relative: a converted box shows 6 significant digits (half a unit in the 6th)."""


@pytest.fixture
def page(browser, server):
    ctx = browser.new_context(viewport={"width": 1440, "height": 900})
    pg = ctx.new_page()
    pg.set_default_timeout(TIMEOUT_MS)
    pg.goto(server.url)
    pg.wait_for_function("window.linkageState && window.linkageState.figures")
    sent = []

    def catch(route):
        sent.append(route.request.post_data_json)
        route.abort()
    pg.route("**/api/dynamics", catch)
    pg.click("#tab-dynamics")
    pg.sent = sent
    yield pg
    ctx.close()


def run(pg, w0: str, start: str = "0") -> dict:
    pg.fill("#dyn-W0", w0)
    pg.fill("#dyn-start", start)
    n = len(pg.sent)
    pg.click("#dynamics-run")
    pg.wait_for_function("document.querySelector('#dynamics-run').disabled === false")
    assert len(pg.sent) == n + 1, pg.inner_text("#dynamics-status")
    return pg.sent[-1]


def test_the_motor_speeds_are_read_in_rpm_or_rad_s_as_the_command_line_reads_them(page):
    rpm = 2 * math.pi / 60                                     # rad/s per rpm
    b = run(page, "150", "30")                                 # the unit beside W0: rpm by default
    assert b["motor"]["W0"] == pytest.approx(150 * rpm, rel=1e-12)
    assert b["start_speed"] == pytest.approx(30 * rpm, rel=1e-12)
    b = run(page, "15.7 rad/s", "100rpm")                      # written with their units, as --motor 2,15.7rad/s
    assert b["motor"]["W0"] == pytest.approx(15.7, rel=1e-12)
    assert b["start_speed"] == pytest.approx(100 * rpm, rel=1e-12)
    page.fill("#dyn-W0", "150")
    page.fill("#dyn-start", "30")
    page.select_option("#dyn-speed-unit", "rad/s")             # the boxes follow: the motor stays the same
    assert float(page.input_value("#dyn-W0")) == pytest.approx(150 * rpm, rel=SHOWN)
    assert page.inner_text("#dyn-start-unit") == "rad/s"
    b = run(page, "20")                                        # a bare number now in rad/s, as on the command line
    assert b["motor"]["W0"] == pytest.approx(20.0, rel=1e-12)
    page.fill("#dyn-W0", "150 rpmx")
    n = len(page.sent)
    page.click("#dynamics-run")
    assert len(page.sent) == n                                 # refused on the page, naming the field
    assert "W0" in page.inner_text("#dynamics-form .param[data-name='W0'] .field-error")
