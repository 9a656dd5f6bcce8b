"""The cam panel in a real browser (Playwright driving Debian's /usr/bin/chromium, never a downloaded one): the
Cam tab shows the follower's segments, the SVAJ plots and the profile; an edit of a segment is written into
the file and the plots change to the new law; a bad edit shows the analytic side's one line in the page and
writes nothing; an undercutting edit is drawn with its undercut. Screenshots go to $LINKAGE_SCREENSHOTS when
it is set."""

import os
import threading
from pathlib import Path

import pytest

sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
CHROMIUM = "/usr/bin/chromium"
if not os.path.exists(CHROMIUM):
    pytest.skip(f"{CHROMIUM} is not installed", allow_module_level=True)

pytestmark = pytest.mark.slow
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--disable-component-update", "--no-first-run"]
TIMEOUT_MS = 30_000


@pytest.fixture(scope="module")
def cam_server():
    from sim.front import app
    srv = app.AppServer(0, {"name": "cam_roller"})
    threading.Thread(target=srv.serve_forever, daemon=True).start()
    yield srv
    srv.shutdown()
    srv.server_close()


@pytest.fixture
def page(cam_server, browser):
    """A fresh page on the Cam tab (``browser``: tests/conftest.py, launched with this module's CHROMIUM and
    ARGS); no page error or console error may have been logged by its end."""
    ctx = browser.new_context(viewport={"width": 1500, "height": 1700})
    pg = ctx.new_page()
    pg.set_default_timeout(TIMEOUT_MS)
    errors = []
    pg.on("pageerror", lambda e: errors.append(f"pageerror: {e}"))
    # a refused edit is a 400 answer, which the browser logs as a failed resource: not a page error
    pg.on("console", lambda m: errors.append(f"console.{m.type}: {m.text}")
          if m.type == "error" and "status of 400" not in m.text else None)
    pg.goto(cam_server.url)
    pg.wait_for_function("window.linkageState && window.linkageState.figures")
    pg.click("#tab-cam")
    pg.wait_for_function("window.linkageCam && window.linkageCamPlots && window.linkageCamPlots.length === 4")
    yield pg
    ctx.close()
    assert errors == []


def shot(pg, name, selector="#analysis-panel"):
    folder = os.environ.get("LINKAGE_SCREENSHOTS")
    if folder:
        Path(folder).mkdir(parents=True, exist_ok=True)
        pg.locator(selector).screenshot(path=str(Path(folder) / f"{name}.png"))


def plotted(pg, k):
    """The k-th SVAJ plot's y values as uPlot holds them (0: s, 1: v, 2: a, 3: j)."""
    return pg.evaluate(f"Array.from(window.linkageCamPlots[{k}].data[1])")


def set_rows(pg, values):
    """Type ``values`` {(row, key): text} into the segment table, then one change event (as leaving the last box)."""
    pg.evaluate("""(vals) => { for (const [r, k, v] of vals)
        document.querySelector(`#cam-segments tbody tr:nth-child(${r}) [data-key=${k}]`).value = v;
      const [r, k] = vals[vals.length - 1];
      document.querySelector(`#cam-segments tbody tr:nth-child(${r}) [data-key=${k}]`)
        .dispatchEvent(new Event('change', {bubbles: true})); }""", [[r, k, v] for (r, k), v in values.items()])


def test_the_cam_tab_shows_the_law_its_svaj_and_the_profile(page):
    rows = page.locator("#cam-segments tbody tr")
    assert rows.count() == 4
    assert page.input_value("#cam-segments tbody tr:nth-child(2) [data-key=rise]") == "0.02"
    s = plotted(page, 0)
    assert max(s) == pytest.approx(0.020, abs=1e-12)       # the file's 20 mm rise, as the plot holds it
    marks = page.text_content("#cam-marks")
    assert "largest pressure angle" in marks and "smallest convex radius of curvature" in marks
    # the profile canvas is drawn: some of its pixels are the ramp's green (a low pressure angle)
    green = page.evaluate("""() => { const c = document.querySelector('#cam-profile'); const g = c.getContext('2d');
        const d = g.getImageData(0, 0, c.width, c.height).data; let n = 0;
        for (let i = 0; i < d.length; i += 4) if (d[i + 1] > 140 && d[i] < 120 && d[i + 2] < 80) n++; return n; }""")
    assert green > 200
    shot(page, "app-cam-panel")


def test_editing_a_segment_writes_the_file_and_changes_the_plots(page):
    before_s, before_a = plotted(page, 0), plotted(page, 2)
    set_rows(page, {(2, "rise"): "0.03", (4, "rise"): "-0.03"})
    page.wait_for_function("Math.max(...window.linkageCamPlots[0].data[1]) > 0.029")
    after_s = plotted(page, 0)
    assert max(after_s) == pytest.approx(0.030, abs=1e-12) and max(before_s) == pytest.approx(0.020, abs=1e-12)
    # the file the page now carries holds the new law, and the animation runs it (F rises 30 mm on its guide)
    text = page.evaluate("document.querySelector('#mechanism').selectedOptions[0].dataset.text")
    assert "rise = 0.03" in text and "# the cam's shaft" in text
    page.wait_for_function("(() => { const y = window.linkageState.points.F.y;"
                           " return Math.max(...y) - Math.min(...y) > 0.0299; })()")
    # a shape chosen from the menu: the acceleration plot changes (harmonic: a jump at the rise's ends)
    page.select_option("#cam-segments tbody tr:nth-child(2) [data-key=shape]", "harmonic")
    page.wait_for_function("window.linkageCam.written.segments[1].shape === 'harmonic'")
    after_a = plotted(page, 2)
    assert max(abs(x - y) for x, y in zip(after_a, before_a)) > 0.1 * max(abs(x) for x in before_a)
    shot(page, "app-cam-edited")
    # Undo steps back through the written law like any edit: the rows and the plots follow the file again
    page.click("#undo")
    page.wait_for_function("window.linkageCam.written.segments[1].shape === 'cycloidal'")
    assert page.input_value("#cam-segments tbody tr:nth-child(2) [data-key=shape]") == "cycloidal"


def test_a_bad_edit_shows_the_one_line_and_writes_nothing(page):
    text_before = page.evaluate("document.querySelector('#mechanism').selectedOptions[0].dataset.text || null")
    page.fill("#cam-segments tbody tr:nth-child(1) [data-key=duration]", "80deg")
    page.press("#cam-segments tbody tr:nth-child(1) [data-key=duration]", "Enter")
    page.wait_for_function("document.querySelector('#cam-error').textContent.includes('sum to 350deg')")
    line = page.text_content("#cam-error")
    assert "add 10deg" in line and "\n" not in line and "<upload>" not in line
    after = page.evaluate("document.querySelector('#mechanism').selectedOptions[0].dataset.text || null")
    assert after == text_before                                  # nothing written
    # a rise on a dwell cannot be typed (the box is off); a negative roller is refused in one line
    assert page.is_disabled("#cam-segments tbody tr:nth-child(1) [data-key=rise]")
    page.fill("#cam-segments tbody tr:nth-child(1) [data-key=duration]", "90deg")
    page.fill("#cam-roller", "-0.01")
    page.press("#cam-roller", "Enter")
    page.wait_for_function("document.querySelector('#cam-error').textContent.includes('roller')")
    assert "must be > 0" in page.text_content("#cam-error")


def test_an_undercutting_edit_is_drawn_with_its_undercut(page):
    set_rows(page, {(2, "duration"): "30deg", (2, "rise"): "0.04", (3, "duration"): "120deg", (4, "rise"): "-0.04"})
    page.wait_for_function("window.linkageCam.undercut !== null")
    assert "undercuts at cam angle" in page.text_content("#cam-error")
    # red (the undercut's colour, #d00000) on the profile canvas
    red = page.evaluate("""() => { const c = document.querySelector('#cam-profile'); const g = c.getContext('2d');
        const d = g.getImageData(0, 0, c.width, c.height).data; let n = 0;
        for (let i = 0; i < d.length; i += 4) if (d[i] > 190 && d[i + 1] < 40 && d[i + 2] < 40) n++; return n; }""")
    assert red > 50
    shot(page, "app-cam-undercut")


def test_rows_are_removed_and_added_as_a_draft_until_the_law_makes_a_turn(page):
    def segment_count():
        text = page.evaluate("document.querySelector('#mechanism').selectedOptions[0].dataset.text || ''")
        return text.count('{ shape = "') if text else None

    page.click("#cam-segments tbody tr:nth-child(3) button[data-remove]")      # the 30deg dwell goes
    page.wait_for_function("document.querySelector('#cam-error').textContent.includes('sum to 330deg')")
    assert page.locator("#cam-segments tbody tr").count() == 3                  # the draft keeps the removal
    page.fill("#cam-segments tbody tr:nth-child(3) [data-key=duration]", "150deg")
    page.press("#cam-segments tbody tr:nth-child(3) [data-key=duration]", "Enter")
    page.wait_for_function("window.linkageCam.written.segments.length === 3")
    assert page.text_content("#cam-error") == ""
    assert segment_count() == 3
    # the return now starts at 210deg: the displacement plotted there is the rise's top, falling after
    theta = page.evaluate("Array.from(window.linkageCamPlots[0].data[0])")
    s = plotted(page, 0)
    at = {round(t, 6): v for t, v in zip(theta, s)}
    assert at[210.0] == pytest.approx(0.020, abs=1e-12) and at[240.0] < 0.019
    page.click("#cam-add")
    assert page.locator("#cam-segments tbody tr").count() == 4
    set_rows(page, {(3, "duration"): "120deg", (4, "duration"): "30deg"})
    page.wait_for_function("window.linkageCam.written.segments.length === 4")
    assert segment_count() == 4
    assert page.evaluate("window.linkageCam.written.segments[3]") == {"shape": "dwell", "duration": "30deg"}
