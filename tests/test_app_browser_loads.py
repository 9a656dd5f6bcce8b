"""Loads on the canvas in a real browser (Playwright driving Debian's /usr/bin/chromium): a force added in the
panel is written into the file, drawn as an arrow at its point, and changes the Forces tab by the work it
does (virtual work: the drive changes by -F . dC/dphi1, dC/dphi1 from the solve's path of C by central
differences). Screenshots go to $LINKAGE_SCREENSHOTS when it is set."""

import os
from pathlib import Path

import numpy as np
import pytest

sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
CHROMIUM = "/usr/bin/chromium"
if not os.path.exists(CHROMIUM):
    pytest.skip(f"{CHROMIUM} is not installed", allow_module_level=True)


pytestmark = pytest.mark.slow
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--disable-component-update", "--no-first-run"]
TIMEOUT_MS = 30_000
LOAD_RGB = (0xC2, 0x18, 0x5B)
"""The canvas's load colour (app.js LOAD_COLOR)."""



@pytest.fixture
def page(server):
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        ctx = b.new_context(viewport={"width": 1440, "height": 1000})
        pg = ctx.new_page()
        pg.set_default_timeout(TIMEOUT_MS)
        errors = []
        pg.on("pageerror", lambda e: errors.append(f"pageerror: {e}"))
        pg.on("console", lambda m: errors.append(f"console.{m.type}: {m.text}") if m.type == "error" else None)
        pg.goto(server.url)
        pg.wait_for_function("window.linkageState && window.linkageState.figures")
        yield pg
        ctx.close()
        b.close()
        assert errors == []


def shot(pg, name):
    folder = os.environ.get("LINKAGE_SCREENSHOTS")
    if folder:
        Path(folder).mkdir(parents=True, exist_ok=True)
        pg.screenshot(path=str(Path(folder) / f"{name}.png"))


def load_pixels(pg, centre, direction, reach):
    """How many canvas pixels of the load colour lie along the ray from ``centre`` (client px) in
    ``direction`` (a unit vector, client px) up to ``reach`` px, and how many in the opposite direction."""
    return pg.evaluate("""([c, d, reach, rgb]) => {
        const cv = document.querySelector('#view'); const r = cv.getBoundingClientRect();
        const k = cv.width / r.width; const g = cv.getContext('2d');
        const count = (sx, sy) => { let n = 0;
          for (let s = 8; s <= reach; s += 1) { for (let w = -1; w <= 1; w++) {
            const x = Math.round((c[0] - r.left + s * sx - w * sy) * k), y = Math.round((c[1] - r.top + s * sy + w * sx) * k);
            const p = g.getImageData(x, y, 1, 1).data;
            if (Math.abs(p[0] - rgb[0]) < 40 && Math.abs(p[1] - rgb[1]) < 40 && Math.abs(p[2] - rgb[2]) < 40) n++; } }
          return n; };
        return [count(d[0], d[1]), count(-d[0], -d[1])]; }""", [centre, direction, reach, list(LOAD_RGB)])


def test_a_force_added_in_the_panel_is_drawn_at_its_point_and_changes_the_forces(page):
    page.click("#tab-forces")
    page.wait_for_function("window.linkageForces && window.linkageForces.drives")
    before = page.evaluate("window.linkageForces")
    assert before["applied"] == []
    page.click("#play")                                  # pause, then a fixed pose
    page.fill("#scrub", "60")
    page.dispatch_event("#scrub", "input")
    F = 50.0                                             # N, straight down at C on the rocker
    page.fill("#load-name", "push")
    page.select_option("#load-kind", "force")
    page.fill("#load-link", "3")
    page.fill("#load-point", "C")
    page.fill("#load-direction", "0,-1")
    page.fill("#load-magnitude", str(F))
    page.click("#load-add")
    page.wait_for_function("window.linkageLoads && window.linkageLoads.loads.some((l) => l.name === 'push')")
    page.wait_for_function("window.linkageForces && (window.linkageForces.applied || []).some((l) => l.name === 'push')")
    # the file now holds the load, as the panel wrote it
    items = page.evaluate("window.linkageLoads.items")
    assert items == [{"name": "push", "kind": "force", "link": "3", "point": "C", "direction": [0, -1],
                      "magnitude": 50}]
    assert "push" in page.inner_text("#file-loads")
    assert page.input_value("#load-name") == "push2"            # ready for the next, under a new name
    assert "file loads push" in page.inner_text("#forces-status")
    # the arrow: load-coloured pixels straight below C (the force's direction on screen), none above
    page.fill("#scrub", "60")
    page.dispatch_event("#scrub", "input")
    page.wait_for_timeout(100)
    C = page.evaluate("[window.linkageState.points.C.x[60], window.linkageState.points.C.y[60]]")
    c = page.evaluate("([x, y]) => window.linkageCanvas.toClient(x, y)", C)
    down, up = load_pixels(page, c, [0, 1], 60)          # canvas y points down: the world's -y
    assert down > 60 and up < 5, (down, up)
    label = page.evaluate("window.linkageLoads.loads[0]")
    assert label["unit"] == "N" and np.allclose(label["fy"], -F)
    page.locator("#view").scroll_into_view_if_needed()
    shot(page, "loads_force_arrow")
    # the Forces tab under the load: the drive changes by -F . dC/dphi1 (virtual work at the pose; the
    # inertia terms are the same with and without it)
    after = page.evaluate("window.linkageForces")
    sol = page.evaluate("window.linkageState")
    phi = np.unwrap(np.array(sol["inputs"]["phi1"]))
    yC = np.array(sol["points"]["C"]["y"])
    dy = np.gradient(yC, phi)                            # 361 samples: error ~(1 deg)^2 / 6 of y''' ~ 1e-4
    change = np.subtract(after["drives"]["phi1"], before["drives"]["phi1"])
    expect = -(-F) * dy
    inner = slice(5, -5)                                 # np.gradient is one-sided at the ends
    # 2e-3 x F x 0.25 m: the central difference's error (above) and the 7 significant digits the page asks for
    assert np.allclose(change[inner], expect[inner], rtol=0, atol=2e-3 * F * 0.25)
    assert np.max(np.abs(change)) > 0.2 * F * np.max(np.abs(dy))   # a real change: the load is in the forces
    # edited in the panel: the arrow's force follows
    page.click("#file-loads button[title='edit push']")
    assert page.input_value("#load-magnitude") == "50" and page.is_visible("#load-save")
    page.fill("#load-magnitude", "80")
    page.click("#load-save")
    page.wait_for_function("window.linkageLoads && window.linkageLoads.loads.length === 1 "
                           "&& Math.abs(window.linkageLoads.loads[0].fy[0] + 80) < 1e-9")
    page.wait_for_function("window.linkageForces && window.linkageForces.applied.length === 1 "
                           "&& Math.abs(window.linkageForces.drives.phi1[60] - %r) > 1e-3" % after["drives"]["phi1"][60])
    edited = np.subtract(page.evaluate("window.linkageForces.drives.phi1"), before["drives"]["phi1"])
    # statics is linear in the load: 80 N changes the drive 80/50 times as much (7 digits sent: 1e-5 N m)
    assert np.allclose(edited, 80 / 50 * change, rtol=0, atol=1e-4)
    # removing it restores the forces
    page.click("#file-loads button[title='remove push']")
    page.wait_for_function("window.linkageForces && (window.linkageForces.applied || []).length === 0")
    restored = page.evaluate("window.linkageForces")
    assert np.allclose(restored["drives"]["phi1"], before["drives"]["phi1"], rtol=0, atol=1e-5)
