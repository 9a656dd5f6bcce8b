"""Slider-move-to-redraw latency of ``linkage app`` in a real browser (Playwright + /usr/bin/chromium).

Starts the server in-process on a free port, opens the page headless, and moves one parameter's slider
N times (waiting each time for the redraw and the next animation frame), then prints the median and the
90th percentile, with the request (server + transfer + JSON parse) and drawing shares of the median::

    python benchmarks/app_latency.py [--mechanism fourbar] [--param l1] [--moves 30] [--panel forces]
                                     [--gravity GX,GY] [--screenshot PNG]

The target is 50 ms. ``--panel forces`` measures with the forces panel open: each move's joint forces are
asked for beside its curves and the redraw waits for both (the timing says so). ``--screenshot`` saves the
page after a simulation (the README's picture).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import threading
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from sim.front import app  # noqa: E402

CHROMIUM = "/usr/bin/chromium"
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync"]

MOVE = """async ([name, value]) => {
  const r0 = +document.body.dataset.revision;
  const slider = document.querySelector(`input[data-param="${name}"]`);
  const t0 = performance.now();
  slider.value = value;
  slider.dispatchEvent(new Event("input", { bubbles: true }));
  await new Promise((resolve) => {
    const obs = new MutationObserver(() => {
      if (+document.body.dataset.revision > r0) { obs.disconnect(); resolve(); }
    });
    obs.observe(document.body, { attributes: true, attributeFilter: ["data-revision"] });
  });
  await new Promise((resolve) => requestAnimationFrame(() => resolve()));
  return [performance.now() - t0, window.linkageTiming];
}"""


def settle(page, after: int) -> None:
    page.wait_for_function(f"+document.body.dataset.revision > {after} && window.linkageState && "
                           "window.linkageState.figures && !document.querySelector('#figures.pending')")


def values(lo: float, hi: float, n: int) -> list[float]:
    """n slider positions sweeping the middle of the range back and forth, as a drag does."""
    mid, amp = 0.5 * (lo + hi), 0.15 * (hi - lo)
    return [mid + amp * ((k % 10) / 5.0 - 1.0) for k in range(n)]


def open_panel(page, panel: str, gravity: str | None) -> None:
    """Open the right column's ``panel`` tab (and set the gravity load) and wait for its first answer."""
    page.click(f"#tab-{panel}")
    if panel == "forces":
        if gravity:
            page.fill("#gravity", gravity)
        page.wait_for_function("window.linkageForces && window.linkageForces.joints")


def measure(page, param: str, moves: int) -> tuple[list[float], list[dict]]:
    p = next(x for x in page.evaluate("window.linkageState.describe.parameters") if x["name"] == param)
    totals, parts = [], []
    for v in values(p["min"], p["max"], moves):
        total, timing = page.evaluate(MOVE, [param, v])
        totals.append(total)
        parts.append(timing)
        time.sleep(0.02)                     # a drag's events come ~16 ms apart; the figures' timer waits longer
    return totals, parts


def screenshot(page, out: str) -> None:
    page.click("#simulate")
    page.locator("#verdict.passed, #verdict.failed").wait_for(timeout=60_000)
    page.click("#play")
    page.fill("#scrub", "120")
    page.dispatch_event("#scrub", "input")
    page.screenshot(path=out, type="png")
    print(f"screenshot: {out} ({Path(out).stat().st_size // 1024} KB)")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--mechanism", default="fourbar")
    ap.add_argument("--param", default="l1")
    ap.add_argument("--moves", type=int, default=30)
    ap.add_argument("--panel", choices=("curves", "forces"), default="curves",
                    help="the right column's tab while measuring (forces: the joint forces redraw with each move)")
    ap.add_argument("--gravity", metavar="GX,GY", default="0,-9.81", help="with --panel forces (default 0,-9.81)")
    ap.add_argument("--screenshot", metavar="PNG")
    args = ap.parse_args()
    from playwright.sync_api import sync_playwright

    srv = app.AppServer(0, {"name": args.mechanism})
    threading.Thread(target=srv.serve_forever, daemon=True).start()
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        page = browser.new_page(viewport={"width": 1440, "height": 900})
        page.goto(srv.url)
        settle(page, 0)
        if args.panel != "curves":
            open_panel(page, args.panel, args.gravity)
        measure(page, args.param, 3)         # warm-up: first requests, JIT of the page's code
        totals, parts = measure(page, args.param, args.moves)
        q = statistics.quantiles(totals, n=10)
        req = statistics.median(t["request_ms"] for t in parts)
        draw = statistics.median(t["draw_ms"] for t in parts)
        with_forces = sum(bool(t.get("forces")) for t in parts)
        if args.panel == "forces" and with_forces < len(parts):
            print(f"warning: only {with_forces} of {len(parts)} redraws carried the joint forces")
        print(f"{args.mechanism} {args.param}{' (forces panel open)' if args.panel == 'forces' else ''}: "
              f"slider-to-redraw over {args.moves} moves: median "
              f"{statistics.median(totals):.1f} ms, p90 {q[8]:.1f} ms (min {min(totals):.1f}, max {max(totals):.1f}); "
              f"median request {req:.1f} ms, drawing {draw:.1f} ms; target 50 ms")
        if args.screenshot:
            screenshot(page, args.screenshot)
        browser.close()
    srv.shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
