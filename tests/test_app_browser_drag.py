"""Direct manipulation and synthesis control in a real browser (Playwright driving Debian's /usr/bin/chromium):
a joint of the four-bar and of a Pyslvs import dragged with the mouse, the new values checked against the
geometry (circle distances from the other joints, which this file works out), undo and redo, a locked length
stopping at the limit, the input's tip scrubbing the pose, snap to grid, a four-bar drawn on the empty page
and saved, a rigid drawing named on the canvas, and a synthesis cancelled from the page with the server
idle within 1 s. Screenshots of each go to $LINKAGE_SCREENSHOTS when it is set."""

import math
import os
import time
import tomllib
from pathlib import Path

import numpy as np
import pytest

sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
CHROMIUM = "/usr/bin/chromium"
if not os.path.exists(CHROMIUM):
    pytest.skip(f"{CHROMIUM} is not installed", allow_module_level=True)

from sim.front import app  # noqa: E402

pytestmark = pytest.mark.slow
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--disable-component-update", "--no-first-run"]
TIMEOUT_MS = 30_000
PEERS = Path(__file__).parent / "peers_examples"
BOX = 1e-5
"""Relative: the number boxes show 6 significant digits (half a unit in the 6th is 5e-6 of the value)."""
DRAWN = 2e-6
"""[m] the drag's solve arrives as exact float64 (``"arrays": "f64"``; before, 7 significant digits of each
series' peak, ~0.5 m: 5e-8, far below); what is left is the drag's own closure (1e-9 of the size)."""



@pytest.fixture
def page(browser, server):
    ctx = browser.new_context(viewport={"width": 1440, "height": 900}, accept_downloads=True)
    pg = ctx.new_page()
    pg.set_default_timeout(TIMEOUT_MS)
    errors = []
    pg.on("pageerror", lambda e: errors.append(f"pageerror: {e}"))
    pg.on("console", lambda m: errors.append(f"console.{m.type}: {m.text}") if m.type == "error" else None)
    pg.goto(server.url)
    pg.wait_for_function("window.linkageState && window.linkageState.figures")
    yield pg
    ctx.close()
    errors = [e for e in errors if "status of 409" not in e]        # a cancelled synthesis answers 409
    assert errors == []


def shot(pg, name):
    folder = os.environ.get("LINKAGE_SCREENSHOTS")
    if folder:
        Path(folder).mkdir(parents=True, exist_ok=True)
        pg.screenshot(path=str(Path(folder) / f"{name}.png"))


def pause_at(pg, frame: int) -> None:
    pg.click("#play")
    pg.fill("#scrub", str(frame))
    pg.dispatch_event("#scrub", "input")


def point_now(pg, name):
    return pg.evaluate(f"""(() => {{ const s = window.linkageState, i = +document.querySelector('#scrub').value;
        return [s.points[{name!r}].x[i], s.points[{name!r}].y[i]]; }})()""")


def drag(pg, name, dx, dy, steps=6):
    """Drag point ``name`` by (dx, dy) pixels in ``steps`` moves, each waiting for its redraw; returns the
    world point [m] under the pointer at the end."""
    x, y = pg.evaluate("([x, y]) => window.linkageCanvas.toClient(x, y)", point_now(pg, name))
    pg.mouse.move(x, y)
    pg.mouse.down()
    for k in range(1, steps + 1):
        r0 = pg.evaluate("+document.body.dataset.revision")
        pg.mouse.move(x + dx * k / steps, y + dy * k / steps)
        pg.wait_for_function(f"+document.body.dataset.revision > {r0}")
    end = pg.evaluate("([x, y]) => window.linkageCanvas.toWorld(x, y)", [x + dx, y + dy])
    px = np.hypot(*np.subtract(pg.evaluate("([x, y]) => window.linkageCanvas.toWorld(x, y)", [x + dx + 1, y + dy]),
                               end))
    # the page's pointer events round to whole pixels: the last drag is the one within a pixel of the end
    pg.wait_for_function("([x, y, px]) => window.linkageDrag && Math.hypot(window.linkageDrag.target[0] - x, "
                         "window.linkageDrag.target[1] - y) <= px", arg=[*end, 1.5 * px])
    end = pg.evaluate("window.linkageDrag.target")
    pg.mouse.up()
    return np.array(end)


def box(pg, name) -> float:
    return float(pg.input_value(f'#params input[name="{name}"]'))


def test_dragging_the_four_bars_coupler_joint_sets_its_link_lengths_then_undo_and_redo(page):
    pause_at(page, 50)
    q = page.evaluate("window.linkageState.inputs.phi1[50]")
    target = drag(page, "C", 40, -25)
    l1, l4 = box(page, "l1"), box(page, "l4")
    B = l1 * np.array([math.cos(q), math.sin(q)])            # the crank tip at this frame, from l1 alone
    D = np.array([l4, 0.0])
    assert box(page, "l2") == pytest.approx(np.hypot(*(target - B)), rel=BOX)
    assert box(page, "l3") == pytest.approx(np.hypot(*(target - D)), rel=BOX)
    assert np.allclose(point_now(page, "C"), target, atol=DRAWN)     # the drawn joint sits under the pointer
    assert "C: l2, l3 changed" in page.inner_text("#drag-note")
    shot(page, "drag_fourbar_C")
    page.keyboard.press("Control+z")
    page.wait_for_function("window.linkageState.parameters.l2 === 0.3 && window.linkageState.parameters.l3 === 0.25")
    assert box(page, "l2") == pytest.approx(0.3, rel=BOX) and box(page, "l3") == pytest.approx(0.25, rel=BOX)
    page.click("#redo")
    page.wait_for_function("window.linkageState.parameters.l2 !== 0.3")
    assert box(page, "l2") == pytest.approx(np.hypot(*(target - B)), rel=BOX)


def test_a_number_box_edit_is_one_undo_step(page):
    page.fill('#params input[name="l1"]', "0.12")
    page.press('#params input[name="l1"]', "Tab")             # the edit ends: one step
    page.wait_for_function("window.linkageState.parameters.l1 === 0.12 && !document.querySelector('#undo').disabled")
    page.click("#undo")
    page.wait_for_function("window.linkageState.parameters.l1 === 0.1")
    assert box(page, "l1") == pytest.approx(0.1, rel=BOX) and page.is_disabled("#undo")
    page.click("#redo")
    page.wait_for_function("window.linkageState.parameters.l1 === 0.12")


def test_the_forces_panel_follows_a_drag(page):
    page.click("#tab-forces")
    page.wait_for_function("window.linkageForces && window.linkageForces.joints")
    pause_at(page, 20)
    drag(page, "C", 30, 20, steps=3)
    values = {k: box(page, k) for k in ("l2", "l3")}
    page.wait_for_function(f"window.linkageState.parameters.l2 === {page.evaluate('window.linkageDrag.set.l2')}")
    # the panel's last answer is the one for the dragged values: the server's forces for them, sent anew
    expected = app.forces({"mechanism": "fourbar", "set": page.evaluate("window.linkageDrag.set"), "samples": 361})
    # the page asks for 7 significant digits of each series' peak (DRAG_DIGITS): half a unit in the 7th
    peak = max(abs(v) for v in expected["joints"][0]["F"])
    page.wait_for_function("([j, v, tol]) => window.linkageForces && "
                           "Math.abs(window.linkageForces.joints[j].F[100] - v) <= tol",
                           arg=[0, expected["joints"][0]["F"][100], 1e-6 * peak])
    assert values["l2"] != pytest.approx(0.3, rel=BOX)


def test_a_locked_length_stops_the_drag_at_the_limit_and_says_why(page):
    pause_at(page, 90)
    page.check('#params input[data-lock="l3"]')
    page.check('#params input[data-lock="l2"]')
    drag(page, "C", 60, -60, steps=3)
    note = page.locator("#drag-note")
    assert "no value of the file places it" in note.inner_text() and "bad" in note.get_attribute("class")
    assert box(page, "l2") == pytest.approx(0.3, rel=BOX) and box(page, "l3") == pytest.approx(0.25, rel=BOX)
    page.uncheck('#params input[data-lock="l2"]')
    drag(page, "C", 400, -400, steps=3)                       # far beyond what l2 alone can reach
    assert "stops at the limit" in note.inner_text()
    D = np.array([box(page, "l4"), 0.0])
    assert np.hypot(*(np.array(point_now(page, "C")) - D)) == pytest.approx(0.25, rel=BOX)   # on l3's circle
    shot(page, "drag_limit")


def test_dragging_the_crank_tip_scrubs_the_pose(page):
    pause_at(page, 0)
    page.check('#params input[data-lock="l1"]')
    A_to_B = drag(page, "B", -30, -60, steps=4)
    angle = math.degrees(math.atan2(A_to_B[1], A_to_B[0])) % 360
    frame = int(page.input_value("#scrub"))
    shown = math.degrees(page.evaluate(f"window.linkageState.inputs.phi1[{frame}]")) % 360
    assert abs((shown - angle + 180) % 360 - 180) <= 0.5       # the nearest of the 1-degree samples
    assert box(page, "l1") == pytest.approx(0.1, rel=BOX)
    shot(page, "drag_scrub")


def test_snap_to_grid_puts_the_ground_pivot_on_a_round_value(page):
    pause_at(page, 10)
    page.check("#snap-grid")
    drag(page, "D", 23, 0, steps=2)
    l4 = box(page, "l4")
    assert l4 != pytest.approx(0.3, rel=BOX)
    assert l4 / 0.01 == pytest.approx(round(l4 / 0.01), abs=1e-6)    # a multiple of the 0.01 m grid


def test_dragging_a_joint_of_a_pyslvs_import_rewrites_its_pose(page):
    page.set_input_files("#file", str(PEERS / "fourbar.pyslvs"))
    page.wait_for_function("window.linkageState && window.linkageState.mechanism === 'fourbar' && "
                           "window.linkageState.describe.points.includes('J2') && window.linkageState.figures")
    pause_at(page, 40)
    q = page.evaluate("window.linkageState.inputs.phiL1[40]")
    target = drag(page, "J2", -30, 20)
    g = page.evaluate("window.linkageDrag")
    assert g["reached"] and g["text"] is not None
    pose = {k: np.array(v) * 1e-3 for k, v in tomllib.loads(g["text"])["pose"].items()}   # mm -> m
    r = np.hypot(*(pose["J1"] - pose["J0"]))
    J1 = pose["J0"] + r * np.array([math.cos(q), math.sin(q)])    # the crank tip at this frame
    # the new pose keeps the coupler J1-J2 and the rocker J3-J2 at the lengths the pointer asks for
    assert np.hypot(*(pose["J2"] - pose["J1"])) == pytest.approx(np.hypot(*(target - J1)), rel=1e-7)
    assert np.hypot(*(pose["J2"] - pose["J3"])) == pytest.approx(np.hypot(*(target - pose["J3"])), rel=1e-7)
    assert np.allclose(point_now(page, "J2"), target, atol=DRAWN)
    shot(page, "drag_pyslvs_J2")
    page.keyboard.press("Control+z")
    page.wait_for_function(f"Math.abs(window.linkageState.points.J2.x[40] - {target[0]}) > 1e-4")


def draw_click(pg, x, y):
    """Click the drawing at world (x, y) [m] and wait for the page's answer (the drawing checked)."""
    cx, cy = pg.evaluate("([x, y]) => window.linkageCanvas.toClient(x, y)", [x, y])
    r0 = pg.evaluate("+document.body.dataset.revision")
    pg.mouse.click(cx, cy)
    pg.wait_for_function(f"+document.body.dataset.revision > {r0}")


def tool(pg, name):
    pg.check(f"input[name=draw-tool][value={name}]")


def test_draw_a_four_bar_on_an_empty_page_save_it_and_open_it(page, tmp_path):
    from sim import service
    page.click("#draw-new")
    page.check("#snap-grid")                                  # 5 mm grid: the pose is exactly the clicks
    pts = {"O1": (0.0, 0.0), "O2": (0.08, 0.0), "A": (0.02, 0.035), "B": (0.09, 0.06)}
    tool(page, "ground")
    draw_click(page, *pts["O1"])
    draw_click(page, *pts["O2"])
    tool(page, "joint")
    draw_click(page, *pts["A"])
    draw_click(page, *pts["B"])
    tool(page, "link")
    for a, b in (("O1", "A"), ("A", "B"), ("B", "O2")):
        cx, cy = page.evaluate("([x, y]) => window.linkageCanvas.toClient(x, y)", list(pts[a]))
        page.mouse.click(cx, cy)                              # the first end: no request yet
        draw_click(page, *pts[b])
    assert "mark the driven link" in page.inner_text("#draw-note")
    tool(page, "input")
    draw_click(page, 0.01, 0.0175)                            # the middle of O1-A
    page.wait_for_function("window.linkageDrawing && window.linkageDrawing.error === null")
    assert "B (links L2, L3): dyad RRR (class II)" in page.inner_text("#draw-note")
    shot(page, "draw_fourbar")
    with page.expect_download() as dl:
        page.click("#draw-save")
    saved = tmp_path / dl.value.suggested_filename
    dl.value.save_as(saved)
    assert saved.name == "drawn.toml"
    data = tomllib.loads(saved.read_text())
    for name, (x, y) in pts.items():                          # mm, the clicks on the grid
        assert data["pose"][name] == pytest.approx([x * 1e3, y * 1e3], abs=1e-9)
    m = service.load(str(saved))
    assert [i.point for i in m.inputs] == ["A"] and set(m.points) == set(pts)
    page.click("#draw-open")
    page.wait_for_function("window.linkageState.mechanism === 'drawn' && window.linkageState.figures")
    assert "turns fully" in page.inner_text("#figures")
    shot(page, "draw_opened")


def test_a_rigid_drawing_is_named_on_the_canvas(page):
    page.click("#draw-new")
    tool(page, "ground")
    draw_click(page, 0.0, 0.0)
    draw_click(page, 0.1, 0.0)
    tool(page, "joint")
    draw_click(page, 0.05, 0.06)
    tool(page, "link")
    for a, b in (((0.0, 0.0), (0.05, 0.06)), ((0.05, 0.06), (0.1, 0.0))):
        cx, cy = page.evaluate("([x, y]) => window.linkageCanvas.toClient(x, y)", list(a))
        page.mouse.click(cx, cy)
        draw_click(page, *b)
    page.wait_for_function("window.linkageDrawing && window.linkageDrawing.mobility === 0")
    tool(page, "joint")                                       # a placed joint moves with the pointer
    page.check("#snap-grid")
    ax, ay = page.evaluate("([x, y]) => window.linkageCanvas.toClient(x, y)", [0.05, 0.06])
    bx, by = page.evaluate("([x, y]) => window.linkageCanvas.toClient(x, y)", [0.06, 0.08])
    r0 = page.evaluate("+document.body.dataset.revision")
    page.mouse.move(ax, ay)
    page.mouse.down()
    page.mouse.move(bx, by, steps=4)
    page.mouse.up()
    page.wait_for_function(f"+document.body.dataset.revision > {r0}")
    moved = page.evaluate("window.linkageDrawingSent.points.A")
    assert (moved["x"], moved["y"]) == pytest.approx((0.06, 0.08), abs=1e-12)      # on the 5 mm grid
    note = page.locator("#draw-note")
    assert "rigid structure" in note.inner_text() and "bad" in note.get_attribute("class")
    assert page.evaluate("window.linkageDrawing.names") == ["L1", "L2"]
    shot(page, "draw_rigid")


def test_cancel_a_synthesis_from_the_page_and_the_server_is_idle_within_a_second(page, server):
    page.click("#tab-synthesis")
    page.fill("#synth-budget", "60")
    for k in range(10):
        t = 2 * math.pi * k / 10
        x, y = page.evaluate("([x, y]) => window.linkageCanvas.toClient(x, y)",
                             [0.05 + 0.12 * math.cos(t), 0.25 + 0.06 * math.sin(t)])
        page.mouse.click(x, y)
    page.check("#synth-closed")
    page.click("#synth-run")
    page.wait_for_function("document.querySelector('#synth-status').textContent.startsWith('searching')")
    assert page.is_visible("#synth-cancel") and page.is_visible("#synth-progress")
    shot(page, "synthesis_running")
    pgid = server.synthesis.proc.pid
    t0 = time.monotonic()
    page.click("#synth-cancel")
    page.wait_for_function("window.linkageCancel && window.linkageCancel.cancelled")
    while _alive(pgid) and time.monotonic() - t0 < 5:
        time.sleep(0.02)
    assert not _alive(pgid) and time.monotonic() - t0 < 1.0
    page.wait_for_function("document.querySelector('#synth-status').textContent.includes('cancelled')")
    assert page.is_hidden("#synth-cancel") and not page.is_disabled("#synth-run")
    shot(page, "synthesis_cancelled")


def _alive(pgid: int) -> bool:
    for p in os.listdir("/proc"):
        if p.isdigit():
            try:
                fields = open(f"/proc/{p}/stat").read().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[2]) == pgid and fields[0] != "Z":
                return True
    return False
