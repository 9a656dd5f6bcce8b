"""The app shows results in the file's length unit, with deg and rpm toggles (SPEC "Units of results"),
in a real browser (Playwright driving /usr/bin/chromium; skipped where either is missing)."""

import os
import threading

import pytest

sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
CHROMIUM = "/usr/bin/chromium"
if not os.path.exists(CHROMIUM):
    pytest.skip(f"{CHROMIUM} is not installed", allow_module_level=True)

from sim.front import app  # noqa: E402

ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking"]


def titles(pg):
    return pg.evaluate("[...document.querySelectorAll('#charts .u-title')].map((e) => e.textContent)")


def test_a_mm_file_shows_mm_and_the_toggles_switch_angles_and_speeds():
    srv = app.AppServer(0, {"name": "hoekens"})
    threading.Thread(target=srv.serve_forever, daemon=True).start()
    try:
        with sync_api.sync_playwright() as p:
            b = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
            pg = b.new_page(viewport={"width": 1440, "height": 900})
            pg.set_default_timeout(20_000)
            errors = []
            pg.on("pageerror", lambda e: errors.append(str(e)))
            pg.goto(srv.url)
            pg.wait_for_function("window.linkageState && window.linkageState.figures && "
                                 "document.querySelectorAll('#charts .u-title').length > 0")
            shown = titles(pg)
            assert "xP [mm]" in shown, shown                              # SI in the API, mm on the page
            options = pg.evaluate("[...document.querySelectorAll('#output-picker option')].map((o) => o.textContent)")
            assert "vxP [mm/s]" in options and "axP [mm/s^2]" in options, options
            assert any(t.endswith("[deg]") for t in shown), shown
            pg.uncheck("input[name=units-deg]")
            assert any(t.endswith("[rad]") for t in titles(pg)) and not any("[deg]" in t for t in titles(pg))
            # an angular speed: pick omega3, shown in rad/s, then in rpm
            pg.evaluate("""() => { const s = document.querySelector('#output-picker select');
                                   s.value = 'omega3'; s.dispatchEvent(new Event('change', {bubbles: true})); }""")
            pg.wait_for_function("[...document.querySelectorAll('#charts .u-title')].some((e) => "
                                 "e.textContent.startsWith('omega3'))")
            assert "omega3 [rad/s]" in titles(pg)
            pg.check("input[name=units-rpm]")
            assert "omega3 [rpm]" in titles(pg)
            assert errors == []
            b.close()
    finally:
        srv.shutdown()
        srv.server_close()
