"""Drag-step latency of ``linkage app`` in a real browser (Playwright + /usr/bin/chromium), the app's server in
a process of its own as ``linkage app`` runs it: a joint of each library mechanism dragged round a small
circle; each step is a pointer move on the canvas -> /api/drag over the page's WebSocket (the file's values
inverted and the cycle solved on the server) -> the redraw of the animation, curves and figures -> the next
animation frame, which shows it.

Per mechanism, two figures of a step, each as its median and 95th percentile: **redrawn**, from the input to
the end of the redraw (the step itself: parameter change, solve, redraw), and **shown**, to the next animation
frame after the redraw (what the screen shows; the wait for that frame is up to one frame, 16.7 ms at 60 Hz,
at a phase no page controls). Then the medians of the step's shares (the request's, the drawing's, the wait
for the frame, the rest: the pointer event to the request, the page's bookkeeping), the server's CPU time for
the same requests replayed in one thread (the part of a step that does not depend on how loaded the machine
is), and the share of steps shown in the first frame after their input and within two (counted from the
page's own requestAnimationFrame times). Then the same over all steps, and an empty request's round trip by
fetch and over the WebSocket (the transport's own share of every request)::

    python benchmarks/app_drag.py [--mechanisms fourbar,jansen] [--steps 30] [--input synthetic|real|both]
                                  [--screenshot PNG]

Two ways of moving the pointer (``--input``): ``synthetic`` (the default) dispatches a PointerEvent on the
canvas from the page's own script and times from that call (its phase in the frame follows Playwright's
evaluate, not a user's hand); ``real`` moves the mouse through Playwright's ``page.mouse.move`` (CDP
Input.dispatchMouseEvent: a real input event, at any phase of the frame) and times from the event's own
``timeStamp`` (when the browser received the input, on the performance.now clock); ``both`` prints each
mechanism's two rows. In the real mode the "other" column includes the wait from the input's arrival to the
page's handler (printed apart): Chromium holds a pointermove for the next frame's input phase (up to a
frame), which is why the page drags on pointerrawupdate (delivered as the input arrives) where the browser
sends it.

Target (issue 31): a drag step takes at most one frame, 16 ms median, 33 ms p95.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import subprocess
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import analytic  # noqa: E402
from sim.front import app  # noqa: E402

CHROMIUM = "/usr/bin/chromium"
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--disable-component-update", "--no-first-run"]

FRAME_CLOCK = """() => { if (window.framesSince) return;
  const times = [];
  const tick = (now) => { times.push(now); if (times.length > 600) times.splice(0, 300); requestAnimationFrame(tick); };
  requestAnimationFrame(tick);
  // the animation frames after t0 up to and including end (end: a frame's own callback): 1, the step was drawn
  // in the first frame after the input
  window.framesSince = (t0, end) => times.filter((f) => f > t0 && f <= end + 0.01).length || 1;
}"""
"""The page's frames, counted from requestAnimationFrame's own times (the frame's start): how many frames a step
spanned, from the input to the frame that showed its redraw."""

STEP = """async ([x, y]) => {
  const canvas = document.querySelector("#view");
  const r0 = +document.body.dataset.revision;
  const t0 = performance.now();
  let drawn = t0;
  canvas.dispatchEvent(new PointerEvent("pointermove", { clientX: x, clientY: y, bubbles: true, pointerId: 1 }));
  await new Promise((resolve) => {
    const obs = new MutationObserver(() => {
      if (+document.body.dataset.revision > r0) { obs.disconnect(); drawn = performance.now(); resolve(); }
    });
    obs.observe(document.body, { attributes: true, attributeFilter: ["data-revision"] });
  });
  await new Promise((resolve) => requestAnimationFrame(() => resolve()));
  const end = performance.now();
  return [end - t0, { ...window.linkageTiming, frame_ms: end - drawn, redrawn_ms: drawn - t0,
                      frames: framesSince(t0, end) }];
}"""


REAL_ARM = """() => { const r0 = +document.body.dataset.revision;
  window.linkageBenchStep = new Promise((resolve) => {
    const timer = setTimeout(() => { obs.disconnect(); resolve(null); }, 2000);   // no move came: left out
    let t0 = null, handled = null, drawn = null;
    const seen = (ev) => { if (t0 === null) { t0 = ev.timeStamp; handled = performance.now(); } };
    for (const kind of ["pointerrawupdate", "pointermove"]) window.addEventListener(kind, seen, { capture: true });
    const obs = new MutationObserver(() => {
      if (t0 === null || +document.body.dataset.revision <= r0) return;
      obs.disconnect(); drawn = performance.now();
      for (const kind of ["pointerrawupdate", "pointermove"]) window.removeEventListener(kind, seen, { capture: true });
      requestAnimationFrame(() => { clearTimeout(timer); const end = performance.now();
        resolve([end - t0, { ...window.linkageTiming, frame_ms: end - drawn, delivered_ms: handled - t0,
                             redrawn_ms: drawn - t0, frames: framesSince(t0, end) }]); });
    });
    obs.observe(document.body, { attributes: true, attributeFilter: ["data-revision"] });
  }); }"""
"""``--input real``: armed before the mouse moves; the step runs from the input's timeStamp (its arrival) through
its delivery to the page (the first of pointerrawupdate and pointermove, which carry the same timeStamp; the
page drags on the first), the request and the redraw, to the next animation frame."""


def pick_point(page) -> str:
    """The first point a drag can move freely: not on the ground, not an input's tip."""
    d = page.evaluate("window.linkageState.describe")
    tips = {i["point"] for i in d["inputs"]}
    return next(p for p in d["points"] if p not in d["ground"] and p not in tips)


def percentile(values: list[float], q: float) -> float:
    s = sorted(values)
    k = (len(s) - 1) * q
    lo, hi = math.floor(k), math.ceil(k)
    return s[lo] + (s[hi] - s[lo]) * (k - lo)


def measure(page, name: str, steps: int, mode: str = "synthetic") -> tuple[str, list[float], list[dict]]:
    page.evaluate("(n) => { const s = document.querySelector('#mechanism'); s.value = n; "
                  "s.dispatchEvent(new Event('change')); }", name)
    page.wait_for_function(f"window.linkageState && window.linkageState.mechanism === {name!r} && "
                           "window.linkageState.figures && !document.querySelector('#figures.pending')")
    page.click("#play")                                  # paused: the pose the drag starts from holds still
    page.fill("#scrub", "30")
    page.dispatch_event("#scrub", "input")
    point = pick_point(page)
    x, y = page.evaluate(f"""(() => {{ const s = window.linkageState, i = 30;
        return window.linkageCanvas.toClient(s.points[{point!r}].x[i], s.points[{point!r}].y[i]); }})()""")
    page.mouse.move(x, y)
    page.mouse.down()
    radius = 6.0                                         # [px] a small circle: every step reachable
    totals, parts = [], []
    for k in range(steps + 3):
        a = 2 * math.pi * (k + (mode == "real")) / 12    # real input: no move to where the mouse already is
        tx, ty = x + radius * math.sin(a), y + radius * (1 - math.cos(a))
        if mode == "real":
            page.evaluate(REAL_ARM)
            page.mouse.move(tx, ty)
            step = page.evaluate("window.linkageBenchStep")
            if step is None:
                continue
            total, timing = step
        else:
            total, timing = page.evaluate(STEP, [tx, ty])
        if k >= 3:                                       # the first moves warm up the page's code paths
            totals.append(total)
            parts.append({**(timing or {}), "body": page.evaluate("window.linkageDragBody")})
        time.sleep(0.016)                                # a drag's events come a frame apart
    page.mouse.up()
    return point, totals, parts


FLOOR = """async (n) => { const out = [];
  for (let i = 0; i < n; i++) { const t0 = performance.now();
    const r = await fetch("/api/synthesize/status", { method: "POST", headers: { "Content-Type": "application/json" },
                                                       body: "{}" });
    await r.json(); out.push(performance.now() - t0); await new Promise((ok) => setTimeout(ok, 16)); }
  out.sort((a, b) => a - b); return out[n >> 1]; }"""
"""The round trip of a request the server answers at once (~0.2 ms of its CPU), on the page's keep-alive
connection: the part of every step's request that is the browser's and the loopback's, not the work."""

SOCKET_FLOOR = """async (n) => { const s = window.linkageSocket, out = [];
  if (!s || !s.ws || s.ws.readyState !== 1) return null;
  for (let i = 0; i < n; i++) { const t0 = performance.now(), id = s.next++;
    await new Promise((ok) => { s.waiting.set(id, { resolve: ok, reject: ok, retry: ok });
                                s.ws.send(JSON.stringify({ id, path: "/none", body: {} })); });
    out.push(performance.now() - t0); await new Promise((ok) => setTimeout(ok, 16)); }
  out.sort((a, b) => a - b); return out[n >> 1]; }"""
"""The same over the page's WebSocket (opened by the drags): a message the server refuses at once."""


def server_cpu(parts: list[dict]) -> float:
    """Median CPU time [ms] of the server's work for the same drag requests (/api/drag and the JSON of its
    answer), replayed in this thread: what the step costs without the other processes' load."""
    out = []
    cache = app.Mechanisms()                             # as the server keeps them from step to step
    for p in parts:
        if p.get("body"):
            c0 = time.thread_time()
            app._json_bytes(app.drag(p["body"], cache))
            out.append((time.thread_time() - c0) * 1e3)
    return statistics.median(out) if out else float("nan")


SERVER = ("import sys; from sim.front import app; srv = app.AppServer(0, {'name': 'fourbar'}); "
          "print(srv.url, flush=True); srv.serve_forever()")


class serve:
    """The app's server in a process of its own, as ``linkage app`` runs it: in this process its thread would
    share the interpreter's lock with Playwright's, whose handling of each step's protocol messages would then
    be timed as the server's work."""

    def __init__(self):
        root = Path(__file__).resolve().parents[1]
        self.proc = subprocess.Popen([sys.executable, "-c", SERVER], cwd=root, stdout=subprocess.PIPE, text=True)
        self.url = self.proc.stdout.readline().strip()
        if not self.url.startswith("http://"):
            raise SystemExit("app_drag: the app's server did not start")

    def stop(self) -> None:
        self.proc.terminate()
        self.proc.wait(timeout=10)


def share(frames: list[int], most: int) -> str:
    """The share of steps drawn within ``most`` frames of their input, as a percentage."""
    return f"{100 * sum(1 <= f <= most for f in frames) / max(len(frames), 1):.0f}%"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--mechanisms", default=",".join(analytic.names()),
                    help="comma-separated library mechanisms (default: all)")
    ap.add_argument("--steps", type=int, default=30)
    ap.add_argument("--input", choices=("synthetic", "real", "both"), default="synthetic",
                    help="pointer moves dispatched by the page's script (synthetic) or real input events through "
                         "CDP, timed from the event's timeStamp (real); both: each mechanism's two rows")
    ap.add_argument("--screenshot", metavar="PNG", help="the page after the last mechanism's drag")
    args = ap.parse_args()
    from playwright.sync_api import sync_playwright

    srv = serve()
    modes = ("synthetic", "real") if args.input == "both" else (args.input,)
    shown, redrawn, spans = ({m: [] for m in modes} for _ in range(3))
    cpus = []
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        page = browser.new_page(viewport={"width": 1440, "height": 900})
        page.goto(srv.url)
        page.wait_for_function("window.linkageState && window.linkageState.figures")
        floor = page.evaluate(FLOOR, 40)
        page.evaluate(FRAME_CLOCK)
        print(f"{'':27s} {'redrawn':>17s} {'shown':>17s}")
        print(f"{'mechanism':20s} {'point':6s} {'median':>8s} {'p95':>8s} {'median':>8s} {'p95':>8s} {'request':>8s} "
              f"{'drawing':>8s} {'frame':>8s} {'other':>8s} {'server CPU':>10s}  [ms]  {'1 frame':>7s} {'<=2':>5s}")
        for name in args.mechanisms.split(","):
            for mode in modes:
                point, totals, parts = measure(page, name, args.steps, mode)
                frames = [p.get("frames", 0) for p in parts]
                done = [p.get("redrawn_ms", float("nan")) for p in parts]
                shown[mode] += totals
                redrawn[mode] += done
                spans[mode] += frames
                req = statistics.median(p.get("request_ms", float("nan")) for p in parts)
                draw = statistics.median(p.get("draw_ms", float("nan")) for p in parts)
                frame = statistics.median(p.get("frame_ms", float("nan")) for p in parts)
                other = statistics.median(t - p.get("request_ms", 0) - p.get("draw_ms", 0) - p.get("frame_ms", 0)
                                          for t, p in zip(totals, parts))
                cpu = server_cpu(parts)
                if mode == modes[0]:
                    cpus.append(cpu)
                label = name if len(modes) == 1 else f"{name[:15]} {mode[:4]}"
                delivered = [p["delivered_ms"] for p in parts if "delivered_ms" in p]
                print(f"{label:20s} {point:6s} {statistics.median(done):8.1f} {percentile(done, 0.95):8.1f} "
                      f"{statistics.median(totals):8.1f} {percentile(totals, 0.95):8.1f} "
                      f"{req:8.1f} {draw:8.1f} {frame:8.1f} {other:8.1f} {cpu:10.1f}       {share(frames, 1):>7s} "
                      f"{share(frames, 2):>5s}"
                      + (f"  (of other: input to handler {statistics.median(delivered):.1f})" if delivered else ""),
                      flush=True)
        sfloor = page.evaluate(SOCKET_FLOOR, 40)
        sockets = sum(bool(p.get("socket")) for p in parts)
        for mode in modes:
            done, totals = redrawn[mode], shown[mode]
            print(f"{'all ' + mode:27s} {statistics.median(done):8.1f} {percentile(done, 0.95):8.1f} "
                  f"{statistics.median(totals):8.1f} {percentile(totals, 0.95):8.1f}   ({len(totals)} steps; drawn in "
                  f"the first frame after the input: {share(spans[mode], 1)}, within two: {share(spans[mode], 2)})")
        print(f"target 16 ms median, 33 ms p95. Server CPU per step: median over the mechanisms "
              f"{statistics.median(cpus):.1f} ms, at most {max(cpus):.1f}; an empty request's round trip {floor:.1f} "
              f"ms by fetch, {'-' if sfloor is None else f'{sfloor:.1f}'} ms over the WebSocket (median); the last "
              f"mechanism's steps over the WebSocket: {sockets} of {len(parts)}")
        if args.screenshot:
            page.screenshot(path=args.screenshot)
        browser.close()
    srv.stop()
    return 0


if __name__ == "__main__":
    sys.exit(main())
