"""Drag steps over the page's WebSocket (GET /api/socket, tornado's WebSocket) in a real browser (Playwright driving Debian's
/usr/bin/chromium): the steps go over the socket once a drag opens it, and a page without WebSocket (the
fallback, fetch) ends the same drag at the same values and the same drawn pose."""

import os

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


COUNT_DRAGS = """() => { window.dragRequests = 0;
  if (window.WebSocket) {
    const send = WebSocket.prototype.send;
    WebSocket.prototype.send = function (data) {
      if (String(data).includes('"/api/drag"')) window.dragRequests++;
      return send.call(this, data);
    };
  }
  const fetched = window.fetch;
  window.fetch = (url, opts) => { if (String(url).endsWith("/api/drag")) window.dragRequests++; return fetched(url, opts); };
}"""
"""Counts the page's drag requests (``window.dragRequests``), over the WebSocket and by fetch."""


def _grab_C(browser, server, init_script: str | None = None):
    """(context, page, errors, x, y): the four-bar's page paused at frame 50, the mouse pressed on its joint C at
    client pixel (x, y)."""
    ctx = browser.new_context(viewport={"width": 1440, "height": 900})
    if init_script:
        ctx.add_init_script(init_script)
    pg = ctx.new_page()
    pg.set_default_timeout(TIMEOUT_MS)
    errors = []
    pg.on("pageerror", lambda e: errors.append(str(e)))
    pg.goto(server.url)
    pg.wait_for_function("window.linkageState && window.linkageState.figures")
    pg.click("#play")
    pg.fill("#scrub", "50")
    pg.dispatch_event("#scrub", "input")
    pg.evaluate(COUNT_DRAGS)
    xy = pg.evaluate("(() => { const s = window.linkageState; return [s.points.C.x[50], s.points.C.y[50]]; })()")
    x, y = pg.evaluate("([x, y]) => window.linkageCanvas.toClient(x, y)", xy)
    pg.mouse.move(x, y)
    pg.mouse.down()
    return ctx, pg, errors, x, y


def _drag_fourbar(browser, server, without_socket: bool):
    ctx, pg, errors, x, y = _grab_C(browser, server, "delete window.WebSocket;" if without_socket else None)
    sockets = []
    for k in range(1, 7):
        r0 = pg.evaluate("+document.body.dataset.revision")
        pg.mouse.move(x + 40 * k / 6, y - 25 * k / 6)
        pg.wait_for_function(f"+document.body.dataset.revision > {r0}")
        pg.wait_for_function("window.linkageTiming && window.linkageTiming.kind === 'drag'")
        sockets.append(pg.evaluate("window.linkageTiming.socket"))
    pg.wait_for_function("([x, y]) => { const t = window.linkageCanvas.toClient(...window.linkageDrag.target); "
                         "return Math.hypot(t[0] - x, t[1] - y) < 1.5; }", arg=[x + 40, y - 25])
    pg.mouse.up()
    values = pg.evaluate("window.linkageDrag.set")
    c = pg.evaluate("(() => { const s = window.linkageState, i = +document.querySelector('#scrub').value; "
                    "return [s.points.C.x[i], s.points.C.y[i]]; })()")
    ctx.close()
    assert errors == []
    return sockets, values, np.array(c)


def test_drag_goes_over_the_socket_and_the_fallback_ends_alike(browser, server):
    sockets, values, c = _drag_fourbar(browser, server, without_socket=False)
    assert sockets[-1] is True                      # opened at pointerdown: the later steps travel over it
    fetched, values_f, c_f = _drag_fourbar(browser, server, without_socket=True)
    assert not any(fetched)
    assert values.keys() == values_f.keys() and values
    for k, v in values.items():
        # the same pointer path solved by the same server: only the pointer's whole-pixel rounding could differ,
        # and both pages round alike
        assert values_f[k] == pytest.approx(v, rel=1e-9)
    np.testing.assert_allclose(c_f, c, rtol=1e-9, atol=1e-12)      # as above: the pose drawn at the end


def test_a_real_pointer_move_sends_its_step_as_it_arrives_and_once(browser, server):
    """A mouse move reaches the page twice: as pointerrawupdate when it arrives (the page on 127.0.0.1 is a
    secure context, where Chromium sends it) and as pointermove at the next frame's input phase. The step
    leaves on the first, and the second sends nothing: six moves, six requests."""
    ctx, pg, _, x, y = _grab_C(browser, server)
    assert pg.evaluate("isSecureContext && 'onpointerrawupdate' in window")
    via = []
    for k in range(1, 7):
        r0 = pg.evaluate("+document.body.dataset.revision")
        pg.mouse.move(x + 30 * k / 6, y - 20 * k / 6)
        pg.wait_for_function(f"+document.body.dataset.revision > {r0}")
        via.append(pg.evaluate("window.linkageTiming.via"))
    pg.wait_for_timeout(200)                       # ten frames: a pointermove that sent would have answered
    sent = pg.evaluate("window.dragRequests")
    pg.mouse.up()
    ctx.close()
    assert via == ["pointerrawupdate"] * 6
    assert sent == 6
