"""``linkage app``: seed 000's interactive workflow as a local web page.

A small JSON API over :mod:`sim.service` (served by tornado, the drag steps over its WebSocket) and one static page
(``sim/front/static``). The page sends a mechanism (a name from ``linkage list`` or an uploaded file's text)
with parameter values; the server answers curves, point paths and figures of merit, runs the MuJoCo
cross-validation, renders the video and produces the exports as downloads.

The server is for the local user only: it binds 127.0.0.1, refuses a Host header other than its own
loopback address (DNS rebinding) and POSTs from another origin, accepts bounded JSON bodies only and never
opens a path that came from a request. Every refusal and every failure to compute is a 4xx with
``{"error": "one line"}``; nothing a request holds can stop the server or print a traceback.
"""

from __future__ import annotations

import concurrent.futures
import dataclasses
import functools
import html
import json
import math
import os
import re
import sys
import tempfile
import threading
import webbrowser
from http import HTTPStatus
from pathlib import Path

import numpy as np

import analytic
from analytic import Mechanism, ParameterError
from sim import service
from sim.service import dynamics as sdyn, path_targets, viewing
from sim.front import cam_panel, loads_panel
from sim.front.fields import (MAX_DYNAMICS_REVOLUTIONS, MAX_FLYWHEEL, MAX_LOAD, MAX_MOTOR,  # noqa: F401
                              MAX_RENDER_REVOLUTIONS, accepted, arguments, check_fields as check_door_fields,
                              for_door)
from sim.front.requests import (MAX_REVOLUTIONS, MAX_SAMPLES, Mechanisms, RequestError, _short,  # noqa: F401
                                Seeded, input_range_of, mechanism_of, number, packed, run_options, series)
from sim.output.jsonout import clean
from sim.output.units import output_kind

MAX_BODY = 1_000_000
WORKERS = 16
"""Requests served at once; more wait in the listen queue (a page uses a few keep-alive connections)."""
"""[bytes] the largest request body: an uploaded mechanism file travels inside it."""
MAX_RENDER_SIZE = (640, 480)
MAX_RENDER_FPS = 60.0
MAX_RENDER_FRAMES = 900
"""Frames of one rendered video (30 s at 30 fps): rendering runs at ~35 frames/s on two cores."""
OVERLAY_POINTS = 1000
"""Simulated samples sent back per series: enough for markers and error curves, small for the page."""
MAX_ERROR_CHARS = 1000
MAX_DYNAMICS_STEPS = 200_000
"""MuJoCo steps of one motor run from the page (~40 s at the ~5000 steps/s of a six-bar on this machine);
the reduced equation's run gives the duration and the step before any is taken."""
MAX_SYNTH_BUDGET = 120.0
"""[s] The longest synthesis search the page may ask for (the issue's per-case bound)."""
MAX_TARGETS = 500
"""Target points of one synthesis request."""
DYNAMICS_POINTS = 1500
"""Samples sent back per time series of a motor run; the last revolution is sent at CYCLE_POINTS angles."""
CYCLE_POINTS = 361

STATIC = Path(__file__).parent / "static"
FILES = {
    "/app.js": ("app.js", "text/javascript; charset=utf-8"),
    "/app.css": ("app.css", "text/css; charset=utf-8"),
    "/vendor/uPlot.iife.min.js": ("vendor/uPlot.iife.min.js", "text/javascript; charset=utf-8"),
    "/vendor/uPlot.min.css": ("vendor/uPlot.min.css", "text/css; charset=utf-8"),
    "/vendor/uPlot.LICENSE": ("vendor/uPlot.LICENSE", "text/plain; charset=utf-8"),
}
"""Every static file served besides the page itself, by URL path: a fixed list, so no request can name a
file."""

SECURITY_HEADERS = {
    # 'unsafe-eval' only because browser test drivers (Playwright's wait_for_function) evaluate their
    # predicates in the page; the page itself never evaluates text and builds its DOM with textContent.
    "Content-Security-Policy": "default-src 'self'; script-src 'self' 'unsafe-eval'; img-src 'self' data: blob:; "
                               "media-src 'self' blob:; style-src 'self' 'unsafe-inline'; frame-ancestors 'none'; "
                               "base-uri 'none'; form-action 'none'",
    "X-Content-Type-Options": "nosniff",
    "X-Frame-Options": "DENY",
    "Referrer-Policy": "no-referrer",
    "Cache-Control": "no-store",
}

FIELDS = {
    "open": {"text", "filename"},
    "targets": {"text", "filename", "unit"},
    "synthesize": {"targets", "type", "closed", "budget", "unit"},
    "draw": {"drawing"},
}
"""The fields of the POSTs that run no door function (:mod:`linkage.api`); those that do take their door
functions' keywords (:mod:`sim.front.fields`). Any other field is refused, so a misspelt field is never silently
ignored."""

_RENDER_LOCK = threading.Lock()
"""One offscreen GL context at a time: two renders would only compete for the same two cores."""


# ---------------------------------------------------------------------------------- request fields
def parse_json(raw: bytes) -> dict:
    """A request body as a JSON object; NaN/Infinity tokens, deep nesting and bad UTF-8 are refused."""
    def refuse_constant(token):
        raise RequestError(400, f"the body holds {token}, which is not JSON: send numbers or text")
    try:
        body = json.loads(raw.decode("utf-8"), parse_constant=refuse_constant)
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise RequestError(400, f"the body is not valid JSON ({_first_line(str(exc))})") from None
    if not isinstance(body, dict):
        raise RequestError(400, "the body must be a JSON object")
    return body


def check_fields(body: dict, action: str) -> None:
    check_door_fields(body, action, FIELDS[action])


def outputs_of(body: dict, mech: Mechanism) -> list[str]:
    """The outputs asked for (the page asks for the plotted ones only); default: every reported output."""
    v = body.get("outputs")
    if v is None:
        return list(mech.outputs)
    if not isinstance(v, list) or not all(isinstance(x, str) for x in v):
        raise RequestError(400, "outputs must be a list of output names")
    known = set(mech.outputs)
    for name in v:
        if name not in known:
            raise RequestError(400, f"{_short(name)} is not an output of {mech.name}; outputs: "
                                    f"{' '.join(mech.outputs[:20])}{' ...' if len(mech.outputs) > 20 else ''}")
    return list(dict.fromkeys(v))


def size_of(body: dict) -> tuple[int, int]:
    v = body.get("size", "%dx%d" % MAX_RENDER_SIZE)
    m = re.fullmatch(r"(\d{2,4})x(\d{2,4})", v) if isinstance(v, str) else None
    w, h = (int(m[1]), int(m[2])) if m else (0, 0)
    if not (16 <= w <= MAX_RENDER_SIZE[0] and 16 <= h <= MAX_RENDER_SIZE[1] and w % 2 == 0 and h % 2 == 0):
        raise RequestError(400, f"size {_short(v)} must be WxH with even sizes up to %dx%d" % MAX_RENDER_SIZE)
    return w, h


# ------------------------------------------------------------------------------------- computation
@dataclasses.dataclass(frozen=True)
class Run:
    """The analysed run a request describes."""

    analysis: service.Analysis
    samples: int
    revolutions: float
    input_range: tuple[float, float] | None


def analysis(mech: Mechanism, body: dict, figures: bool, action: str = "solve") -> Run:
    """The door's analysis (:func:`linkage.analyze`) of the run ``body`` asks ``action`` for."""
    args = {**arguments(body, action), "figures": figures}
    return analysis_of(mech, args)


def analysis_of(mech: Mechanism, args: dict) -> Run:
    """:func:`linkage.analyze` called with the keywords of ``args`` it takes; the run's range as the door
    reads it (absent: the file's own)."""
    import linkage as lk
    from linkage._inputs import input_range_of as door_range
    a = lk.analyze(mech, **for_door(args, lk.analyze))
    return Run(a.analysis, a.samples, a.revolutions, door_range(mech, args["input_range"]))


def point_paths(mech: Mechanism, sol, n: int, stride: int = 1, digits: int | None = None) -> dict:
    """Each point's path {P: {"x": [...], "y": [...]}} [m]: the page draws the links through them."""
    return {p: {c: series(np.broadcast_to(sol[c + p], (n,))[::stride], digits=digits) for c in "xy"}
            for p in mech.points}


def solve(body: dict, cache: Mechanisms | None = None) -> dict:
    """Curves of the outputs against the input, every point's path, block angles, figures of merit.
    ``cache``: the server's recently loaded mechanisms (:class:`sim.front.requests.Mechanisms`)."""
    args = arguments(body, "solve")
    figures = args["figures"]
    digits = int(number(body, "digits", 15, 3, 15, integer=True)) if "digits" in body else None
    if body.get("arrays", "lists") not in ("lists", "f64"):
        raise RequestError(400, "arrays must be \"lists\" (JSON numbers) or \"f64\" (base64 float64, exact)")
    ser = (lambda v, m=None: packed(v, m)) if body.get("arrays") == "f64" else \
        (lambda v, m=None: series(v, m, digits))
    mech = mechanism_of(body, cache)
    names = outputs_of(body, mech)
    run = analysis_of(mech, args)
    a = run.analysis
    n, sol = len(a.t), a.solution
    return {
        "mechanism": mech.name, "samples": run.samples, "revolutions": run.revolutions,
        "input_range": list(run.input_range) if run.input_range else None,
        "describe": describe(mech), "parameters": clean(mech.parameters),
        "input": mech.inputs[0].q, "units": units(mech, body.get("text") or body["mechanism"], cache),
        "t": series(a.t) if body.get("arrays") != "f64" else packed(a.t),
        "inputs": {k: ser(v, n) for k, v in a.inputs.items()},
        "outputs": {k: ser(sol[k], n) for k in names},
        "points": {p: {c: ser(np.broadcast_to(sol[c + p], (n,))) for c in "xy"} for p in mech.points},
        "angles": {ln: ser(sol["phi" + ln], n) for ln in mech.slides if "phi" + ln in sol},
        "figures": clean(a.figures) if figures else None,
        "summary": viewing.figures_summary(mech, a.figures) if figures else None,
    }


def units(mech: Mechanism, key: str, cache: Mechanisms | None = None) -> dict[str, str]:
    """The unit of every input and output column; a server's ``cache`` keeps them per file text or library name
    (``key``), since units follow from the mechanism's structure, not its values."""
    def make() -> dict[str, str]:
        columns = [q for i in mech.inputs for q in (i.q, i.qd, i.qdd)] + list(mech.outputs)
        return service.units_of(mech, columns)
    return cache.units(key, make) if cache else make()


def describe(mech: Mechanism) -> dict:
    """:func:`service.describe` for the page: the drives' speed and acceleration parameters in rad/s and
    rad/s^2 (a slider's in length/s, length/s^2) where the table gives every angle-kind parameter 'rad', and a
    slider range for a length that is zero (an offset), whose table range is empty."""
    d = clean(service.describe(mech))
    rates = {}
    for i in mech.inputs:
        base = "rad" if i.angular else mech.units
        _, speed, accel = i.parameters
        rates.update({name: unit for name, unit in ((speed, f"{base}/s"), (accel, f"{base}/s^2")) if name})
    from sim.output.drawing import cam_drawing, cylinder_drawing, wheels_of
    d["wheels"] = [dataclasses.asdict(w) for w in wheels_of(mech)]      # gears, drawn as the videos draw them
    d["cylinders"] = cylinder_drawing(mech)                             # actuators, drawn as the videos draw them
    d["cams"] = cam_drawing(mech)                                       # cam plates, drawn as the videos draw them
    size = mech.size / mech.scale                   # [file units]
    for p in d["parameters"]:
        p["unit"] = rates.get(p["name"], p["unit"])
        if p["kind"] == "length" and p["max"] - p["min"] < 1e-6 * size:    # a zero offset: +-size to play with
            p.update(min=-size, max=size, step=size / 200)
    return d


def simulate(body: dict) -> dict:
    """``compare --json`` plus the overlay: simulated outputs, their errors and the output point's path,
    at most OVERLAY_POINTS samples each."""
    import linkage as lk
    args = arguments(body, "simulate")
    mech = mechanism_of(body)
    names = outputs_of(body, mech)
    compared = lk.compare(mech, **for_door(args, lk.compare))
    built, c = compared.built, compared.comparison
    tr = c.trajectory
    n = len(tr.t)
    k = max(1, math.ceil(n / OVERLAY_POINTS))
    record = clean(service.comparison_record(built, c))
    record["simulated"] = {
        "t": series(tr.t[::k]), "inputs": {q: series(v[::k]) for q, v in tr.inputs.items()},
        "outputs": {name: series(np.broadcast_to(tr.outputs[name], (n,))[::k]) for name in names},
        "errors": {name: series(error(built.mech, name, tr.outputs[name], c.analytic[name], n)[::k])
                   for name in names},
        "points": point_paths(built.mech, tr.outputs, n, k),
    }
    return record


def error(mech: Mechanism, name: str, simulated, reference, n: int) -> np.ndarray:
    """Simulated minus analytic, angles wrapped into (-pi, pi] as the comparison measures them."""
    diff = np.broadcast_to(np.asarray(simulated, float) - np.asarray(reference, float), (n,))
    return np.pi - np.mod(np.pi - diff, 2 * np.pi) if output_kind(mech, name)[1] == "angle" else diff


def render_video(body: dict) -> bytes:
    """The MuJoCo animation as MP4 bytes, rendered into a private temporary folder."""
    import linkage as lk
    from sim.output.render import render
    args = arguments(body, "render")
    mech = mechanism_of(body)
    fps = float(number(body, "fps", 30.0, 1.0, MAX_RENDER_FPS))
    size = size_of(body)
    s = lk.simulate(mech, **for_door(args, lk.simulate))
    built, tr = s.built, s.trajectory
    frames = int(tr.t[-1] * fps) + 1
    if frames > MAX_RENDER_FRAMES:
        raise RequestError(400, f"the video would have {frames} frames (at most {MAX_RENDER_FRAMES}): lower the "
                                f"revolutions or the frame rate, or raise the input speed")
    with tempfile.TemporaryDirectory(prefix="linkage-app-") as folder, _RENDER_LOCK:
        out = Path(folder) / "linkage.mp4"
        render(built, tr, str(out), fps, size)
        return out.read_bytes()


def synthesis_types() -> tuple[str, ...]:
    """The linkage types path synthesis offers (``linkage synthesize path --type``)."""
    return path_targets.types()


def length_unit(body: dict) -> str:
    unit = body.get("unit", "m")
    if unit not in path_targets.LENGTH_UNITS:
        raise RequestError(400, f"unit must be one of {', '.join(path_targets.LENGTH_UNITS)} (got {_short(unit)})")
    return unit


def targets(body: dict) -> dict:
    """Target points loaded on the page: a CSV's text (columns x,y in ``unit``, read as ``linkage synthesize
    path`` reads its file) as points [m]."""
    from sim.service import design as design_service
    check_fields(body, "targets")
    text, filename, unit = body.get("text"), body.get("filename", "targets.csv"), length_unit(body)
    if not isinstance(text, str) or not isinstance(filename, str):
        raise RequestError(400, "text must be the CSV's contents and filename its name, as strings")
    base = Path(filename.replace("\\", "/")).name or "targets.csv"
    with tempfile.TemporaryDirectory(prefix="linkage-app-") as folder:
        path = Path(folder) / "targets.csv"
        path.write_text(text, encoding="utf-8")
        try:
            target = design_service.read_target(str(path))
        except ParameterError as exc:        # the message names the temporary file: name the user's instead
            raise RequestError(400, str(exc).replace(str(path), base)) from None
    if len(target.xy) > MAX_TARGETS:
        raise RequestError(400, f"{base}: {len(target.xy)} target points; the page takes at most {MAX_TARGETS}")
    return {"targets": (target.xy * path_targets.LENGTH_UNITS[unit]).tolist()}


def synthesize(body: dict, server: "AppServer") -> dict:
    """Path synthesis from the page: ``targets`` [[x, y], ...] [m], ``type``, ``closed``, ``budget`` [s]
    (:func:`sim.service.design.synthesize_path`, in metres), run as a job the page can cancel
    (:class:`sim.front.synth_job.Job`: its own process group, killed at the budget plus 1 s); each distinct
    candidate with its error [m^2, m], its least transmission angle, its checks, its ``linkage/1`` text and its
    coupler curve [m] to draw; ``seconds``: the wall time of the search (what the budget bounds, from its
    start to the answer); ``startup``: the job's process start before it, not counted in the budget."""
    from sim.front import synth_job
    check_fields(body, "synthesize")
    pts = body.get("targets")
    if not (isinstance(pts, list) and 4 <= len(pts) <= MAX_TARGETS
            and all(isinstance(p, list) and len(p) == 2 and all(isinstance(c, (int, float)) and not isinstance(c, bool)
                                                               and math.isfinite(c) for c in p) for p in pts)):
        raise RequestError(400, f"targets must be 4 to {MAX_TARGETS} points [[x, y], ...] in metres")
    kind = body.get("type", path_targets.default_type())
    if kind not in synthesis_types():
        raise RequestError(400, f"type must be one of {', '.join(synthesis_types())} (got {_short(kind)})")
    budget = number(body, "budget", 30.0, 1.0, MAX_SYNTH_BUDGET)
    xy = np.asarray(pts, dtype=float)
    if float(np.ptp(xy, axis=0).max()) <= 0:
        raise RequestError(400, "the target points all coincide: place them along the path")
    closed = flag(body, "closed", False)
    with server.synthesis_lock:
        if server.synthesis is not None and server.synthesis.running:
            raise RequestError(409, "a synthesis is already running: cancel it first")
        job = server.synthesis = synth_job.Job({"targets": xy.tolist(), "type": kind, "closed": closed,
                                                    "workers": synth_job.WORKERS}, budget)
    out = job.wait()
    if out["state"] == "cancelled":
        raise RequestError(409, f"synthesis cancelled after {out['seconds']:.1f} s")
    if out["state"] != "done":
        raise RequestError(400, out["error"] or "the synthesis failed")
    return {**out["answer"], "seconds": out["seconds"], "startup": out["startup"], "budget": budget}


def synthesis_status(server: "AppServer") -> dict:
    """What the running synthesis is doing: ``state`` (idle when none runs), ``stage`` (starting, search,
    check), ``done`` of ``total``, ``elapsed`` and ``budget`` [s]."""
    job = server.synthesis
    if job is None:
        return {"state": "idle"}
    st = job.status()
    return {**st, "state": "running" if job.running else "idle", "last": st["state"]}


def cancel_synthesis(server: "AppServer") -> dict:
    """Stop the running synthesis now: its process group (the job and its workers) is killed before this
    answers."""
    job = server.synthesis
    if job is None or not job.running:
        return {"cancelled": False, "state": "idle"}
    job.cancel()
    return {"cancelled": True, "state": "idle", "elapsed": job.seconds}


def flag(body: dict, key: str, default: bool) -> bool:
    v = body.get(key, default)
    if not isinstance(v, bool):
        raise RequestError(400, f"{key} must be true or false (got {_short(v)})")
    return v


def pair_of(body: dict, key: str, example: str) -> tuple[float, float] | None:
    """A field holding two finite numbers [x, y] (None or absent: not given)."""
    v = body.get(key)
    if v is None:
        return None
    ok = (isinstance(v, list) and len(v) == 2
          and all(isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) and abs(x) <= MAX_LOAD
                  for x in v))
    if not ok:
        raise RequestError(400, f"{key} {_short(v)} must be two numbers [x, y] of magnitude <= {MAX_LOAD:g}, "
                                f"e.g. {example}")
    return float(v[0]), float(v[1])


def force_series(rec: dict, digits: int | None) -> dict:
    """What the forces panel draws from a :func:`service.forces_record` (SI): the first input's values, each
    joint's |F| [N] (a prismatic pair's couple M [N m] too), each drive [N m or N], the shaking force's
    magnitude [N] and moment [N m]."""
    n = len(rec["t"])
    first = next(iter(rec["inputs"]))
    joints = []
    for j in rec["joints"]:
        entry = {"name": j["name"], "point": j["point"], "kind": j["kind"], "links": j["links"],
                 "F": series(np.hypot(j["Fx"], j["Fy"]), n, digits)}
        if "M" in j:
            entry["M"] = series(j["M"], n, digits)
        if "input" in j:
            entry["input"] = j["input"]
        joints.append(entry)
    sh = rec["shaking"]
    return {"input": first, "inputs": {q: series(v, n, digits) for q, v in rec["inputs"].items()},
            "joints": joints, "drives": {q: series(v, n, digits) for q, v in rec["drives"].items()},
            "shaking": {"F": series(np.hypot(sh["Fx"], sh["Fy"]), n, digits), "M": series(sh["M"], n, digits)}}


def shown_forces(out: dict, mech: Mechanism) -> dict:
    """The forces panel's answer (SI from :func:`forces`) in the units people read (SPEC "Units of results",
    as ``linkage forces`` prints them): forces in the file's ``force_units``, moments in that unit x the file's
    length unit (N m for a file in N), a drive in its input's (torque or force); the inputs stay SI (the page
    shows them as its curves do). ``units`` says which: ``force``, ``moment`` and ``drives``."""
    from sim.service.forces import force_factors
    kF, kM, force, moment = force_factors(mech)
    drive_k = {inp.q: kM if inp.angular else kF for inp in mech.inputs}

    def times(v, k):
        return None if v is None else (v * k if isinstance(v, (int, float)) else [None if x is None else x * k
                                                                                   for x in v])

    def series_in(s: dict) -> None:
        for j in s["joints"]:
            j["F"] = times(j["F"], kF)
            if "M" in j:
                j["M"] = times(j["M"], kM)
        s["drives"] = {q: times(v, drive_k[q]) for q, v in s["drives"].items()}
        s["shaking"] = {"F": times(s["shaking"]["F"], kF), "M": times(s["shaking"]["M"], kM)}
    series_in(out)
    pk = out["peaks"]
    for e in pk["joints"].values():
        e["F"], e["M"] = times(e["F"], kF), times(e.get("M"), kM)
        if e["M"] is None:
            e.pop("M")
    for q, e in pk["drives"].items():
        e["value"] = times(e["value"], drive_k[q])
    for key, k in (("F", kF), ("F_rms", kF), ("M", kM)):
        if key in pk["shaking"]:
            pk["shaking"][key] = times(pk["shaking"][key], k)
    sim = out.get("simulated")
    if sim:
        series_in(sim)
        a = sim["agreement"]
        for e in a["joints"].values():
            e["max"] = times(e["max"], kF)
            if "M_max" in e:
                e["M_max"] = times(e["M_max"], kM)
        for q, e in a["drives"].items():
            for key in ("peak", "mujoco_max", "power_balance_max"):
                if key in e:
                    e[key] = times(e[key], drive_k[q])
        for key, k in (("F_max", kF), ("M_max", kM)):
            if key in a["shaking"]:
                a["shaking"][key] = times(a["shaking"][key], k)
        if "peak" in a:
            a["peak"] = times(a["peak"], kF)
    out["units"] = {**out["units"], "force": force, "torque": moment, "moment": moment,
                    "drives": {inp.q: moment if inp.angular else force for inp in mech.inputs}}
    return out


def forces(body: dict) -> dict:
    """The forces panel: every joint's force, the drives and the shaking force along the analysed run under
    the request's loads (:func:`service.forces_run`); with ``simulate`` MuJoCo's forces and their agreement
    (:func:`service.simulated_forces`)."""
    import linkage as lk
    from sim.service.forces import simulated_forces
    args = arguments(body, "forces")
    digits = int(number(body, "digits", 15, 3, 15, integer=True)) if "digits" in body else None
    mech = mechanism_of(body)
    f = lk.forces(mech, **for_door(args, lk.forces))
    run = f.run
    rec = service.forces_record(run)
    out = {"mechanism": mech.name, "samples": args["samples"], "revolutions": args["revolutions"],
           **force_series(rec, digits), "peaks": clean(rec["peaks"]), "loads": clean(run.loads),
           "applied": clean(rec["loads"]), "friction": clean(rec.get("friction")), "energy": clean(rec.get("energy")),
           "units": clean(rec["units"]), "simulated": None,
           "actuators": clean({name: {k: v for k, v in entry.items() if k not in ("pressure", "area")}
                               for name, entry in rec.get("actuators", {}).items()})}   # the sizing table
    if f.simulated_run is not None:
        sim = simulated_forces(run, *f.simulation, simulated=f.simulated_run)
        out["simulated"] = {**force_series(sim, None), "agreement": clean(sim["agreement"]),
                            "passed": bool(sim["passed"]), "timestep": sim["timestep"], "steps": sim["steps"]}
    return shown_forces(out, mech)


def dynamics(body: dict) -> dict:
    """The dynamics panel: the linkage driven by a motor through the door (:func:`linkage.dynamics`, as the
    command line), the reduced equation's answer and, with ``simulate`` (default), MuJoCo's and the verdict;
    with ``target_fluctuation`` the flywheel sized for that Cs. The door refuses the MuJoCo run before it starts
    when it would take more than MAX_DYNAMICS_STEPS steps (the reduced equation's run gives its duration)."""
    import linkage as lk
    args = arguments(body, "dynamics")
    mech = mechanism_of(body)
    if len(mech.inputs) != 1:
        raise RequestError(400, f"the {mech.name} has {len(mech.inputs)} inputs; the dynamics panel drives one "
                                f"(run `linkage dynamics` with --motor per input)")
    target = args["target_fluctuation"]
    if target is not None:
        if not 0 < target < 1:
            raise RequestError(400, f"target_fluctuation={target:g} must be in (0, 1), e.g. 0.05")
        if args["flywheel"] not in (None, 0, 0.0):
            raise RequestError(400, "give flywheel or target_fluctuation (which sizes the flywheel), not both")
    keywords = {**for_door(args, lk.dynamics), "flywheel": None if target is not None else float(args["flywheel"] or 0.0)}
    return dynamics_view(lk.dynamics(mech, **keywords, max_steps=MAX_DYNAMICS_STEPS).run)


def dynamics_view(d) -> dict:
    """What the dynamics panel shows of a :class:`sim.run.motor.Dynamics` (SI): the design answers, the run
    against time (at most DYNAMICS_POINTS samples), the last revolution's speed against the input's advance
    [rad from its start], MuJoCo's the same and the verdict."""
    from sim.output.dynamics_plot import last_cycle
    rec = sdyn.record(d)
    r = d.run
    u, w, us, ws = last_cycle(d, CYCLE_POINTS)

    def thin(*arrays):
        k = max(1, math.ceil(len(arrays[0]) / DYNAMICS_POINTS))
        return [series(a[::k]) for a in arrays]

    t, omega, torque = thin(r.t, r.omega, r.torque)
    keys = ("mechanism", "input", "motor", "flywheel", "mean_speed", "fluctuation", "startup_time", "peak_torque",
            "peak_power", "energy_per_cycle", "revolutions", "units", "sizing", "passed", "loads", "energy")
    out = {k: clean(rec[k]) for k in keys if k in rec}
    out.update({"w_min": r.w_min, "w_max": r.w_max, "run": {"t": t, "omega": omega, "torque": torque},
                "cycle": {"advance": series(u), "omega": series(w)}, "simulated": None})
    if d.sim is not None:
        s = d.sim
        t, omega, torque = thin(s.t, s.omega, s.torque)
        k = max(1, math.ceil(len(us) / CYCLE_POINTS))
        out["simulated"] = {"t": t, "omega": omega, "torque": torque,
                            "cycle": {"advance": series(us[::k]), "omega": series(ws[::k])},
                            **{key: clean(rec["simulated"][key]) for key in (
                                "mean_speed", "fluctuation", "startup_time", "timestep", "loop_violation",
                                "agreement", "passed")},
                            "steps": len(s.t)}
    return out


def open_file(body: dict) -> dict:
    """A file the user opened on the page: a ``linkage/1`` file's text as it is, or a Pyslvs project or
    expression or a PMKS text file (told apart as ``linkage import`` does, by the file name's extension and
    the content) converted to ``linkage/1`` text. The text goes into a private temporary folder under a name
    made here (only the extension and a cleaned stem come from the request)."""
    from sim.service import opening
    check_fields(body, "open")
    text, filename = body.get("text"), body.get("filename", "mechanism.toml")
    if not isinstance(text, str):
        raise RequestError(400, "text must be the file's contents as a string")
    if not isinstance(filename, str) or not filename:
        raise RequestError(400, "filename must be the opened file's name, e.g. \"crank.pyslvs\"")
    base = Path(filename.replace("\\", "/")).name
    suffix = Path(base).suffix.lower()
    stem = re.sub(r"[^A-Za-z0-9_-]", "_", Path(base).stem)[:64] or "mechanism"
    if suffix in (".toml", ".json"):
        return {"mechanism": service.load("<upload>", text=text).name, "text": text, "kind": "linkage/1"}
    with tempfile.TemporaryDirectory(prefix="linkage-app-") as folder:
        path = Path(folder) / f"{stem}{suffix if re.fullmatch(r'[.][a-z0-9]{1,8}', suffix) else '.txt'}"
        path.write_text(text, encoding="utf-8")
        try:
            found = opening.foreign_text(path)
        except ParameterError as exc:        # the message names the temporary file: name the user's instead
            raise RequestError(400, str(exc).replace(str(path), base)) from None
    if found is None:
        return {"mechanism": service.load("<upload>", text=text).name, "text": text, "kind": "linkage/1"}
    kind, converted = found
    return {"mechanism": service.load("<upload>", text=converted).name, "text": converted, "kind": kind}


def export(kind: str, body: dict) -> tuple[bytes, str, str]:
    """A download: (bytes, content type, file name) of the CSV, JSON, mechanism file or MJCF."""
    import linkage as lk
    args = arguments(body, "export")                # a bad field is refused whichever file is asked for
    mech = mechanism_of(body)
    stem = re.sub(r"[^A-Za-z0-9_.-]", "_", mech.name)[:64] or "mechanism"
    if kind == "toml":
        return service.mechanism_text(mech, body.get("text")).encode(), "application/toml", f"{stem}.toml"
    if kind == "mjcf":
        return lk.export(mech, **for_door(args, lk.export)).mjcf.encode(), "application/xml", f"{stem}.xml"
    if kind in PARTS_EXPORTS:                       # the parts (issue 28), written to a temporary folder
        return parts_export(mech, kind, stem)
    if kind == "csv":
        run = analysis_of(mech, {**args, "figures": False})
        return csv_text(service.analysis_columns(mech, run.analysis)).encode(), "text/csv", f"{stem}.csv"
    run = analysis_of(mech, {**args, "figures": True})
    record = service.analysis_record(mech, run.analysis, run.samples, run.revolutions)
    return json.dumps(clean(record), indent=2, allow_nan=False).encode(), "application/json", f"{stem}.json"


PARTS_EXPORTS = {"dxf": ("application/dxf", ".dxf"), "svg": ("image/svg+xml", ".svg"),
                 "pdf": ("application/pdf", ".pdf"), "step": ("application/step", ".step"),
                 "bom": ("text/csv", "_bom.csv")}
"""The parts' files the app offers: the outlines (DXF), the drawing (SVG, PDF), the solids (STEP), the bill
of materials (CSV), as ``linkage export`` writes them."""


def parts_export(mech, kind: str, stem: str) -> tuple[bytes, str, str]:
    import tempfile
    from pathlib import Path

    from sim.service import parts as parts_service
    ctype, suffix = PARTS_EXPORTS[kind]
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"{stem}{suffix}"
        pm = parts_service.prepare(mech)
        parts_service.export(pm, **{"bom" if kind == "bom" else kind: str(path)})
        return path.read_bytes(), ctype, path.name


def csv_text(columns: dict) -> str:
    """The CSV of ``linkage analyze --csv`` (header row, full precision), in memory."""
    import io
    data = np.column_stack([np.ravel(v) for v in columns.values()])
    buf = io.StringIO()
    np.savetxt(buf, data, delimiter=",", header=",".join(columns), comments="", fmt="%.17g")
    return buf.getvalue()


def page(initial: dict) -> bytes:
    """index.html with the first mechanism's parameter rows written in, so the page as served already
    holds every ``<input name=PARAM>`` (the script rebuilds the rows when the mechanism changes)."""
    mech = service.load(initial["name"], text=initial.get("text"))
    rows = "".join(parameter_row(p) for p in describe(mech)["parameters"])
    return (STATIC / "index.html").read_text().replace("<!--PARAMETERS-->", rows).replace(
        "<!--LOAD_FORM-->", loads_panel.form_html()).encode()


def parameter_row(p: dict) -> str:
    """One parameter's row: label, slider, number box, unit, range; the markup app.js builds too."""
    name, unit = html.escape(p["name"]), html.escape(p["unit"])
    hint = "branch: +1 or -1" if p["kind"] == "branch" else f"range {p['min']:.4g} … {p['max']:.4g} {unit}"
    hint += " · derived from the others until set" if p["derived"] else ""
    return (f'<div class="param" data-name="{name}"><label for="p-{name}">{name}</label>'
            f'<input type="range" data-param="{name}" aria-label="{name} slider" min="{p["min"]!r}" '
            f'max="{p["max"]!r}" step="{p["step"]!r}" value="{p["value"]!r}">'
            f'<input type="text" id="p-{name}" name="{name}" value="{p["value"]:.6g}" inputmode="decimal" '
            f'autocomplete="off" spellcheck="false"><span class="unit">{unit}</span>'
            f'<p class="hint">{hint}</p><p class="field-error" role="alert"></p></div>')


def mechanisms(initial: dict) -> dict:
    listing = service.list_mechanisms()
    return {"names": [m["name"] for m in listing], "mechanisms": listing, "initial": initial,
            "synthesis": {"types": list(synthesis_types()), "max_budget": MAX_SYNTH_BUDGET,
                          "max_targets": MAX_TARGETS}}


def drag(body: dict, cache: Mechanisms | None = None) -> dict:
    """A point dragged on the drawing (:func:`sim.service.editing.drag`): ``point``, ``target`` [x, y] m, the
    pose's ``input`` values, ``locked`` parameters, ``round`` (a step in file units, or absent). Answers the
    drag (the new ``set`` and ``text``, the input value to show, where the point is, whether it got there,
    one line) and the solve of the new values, in one round trip; a drag whose values cannot run the cycle
    keeps the old ones and says why. ``cache``: the server's recently loaded mechanisms (a step starts from the
    values the last one solved)."""
    from sim.service import editing as dragging
    arguments(body, "drag")
    mech = mechanism_of(body, cache)
    point = body.get("point")
    if not isinstance(point, str):
        raise RequestError(400, "point must be the dragged point's name")
    target = pair_of(body, "target", "[0.1, 0.2]")
    if target is None:
        raise RequestError(400, "target must be [x, y] in metres")
    q = body.get("input")
    if not (isinstance(q, list) and len(q) == len(mech.inputs) and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in q)):
        raise RequestError(400, f"input must be the pose's {len(mech.inputs)} input value(s) [rad or m], e.g. [0.5]")
    locked = body.get("locked", [])
    if not (isinstance(locked, list) and all(isinstance(n, str) for n in locked)):
        raise RequestError(400, "locked must be a list of parameter names")
    step = body.get("round")
    step = None if step is None else float(number(body, "round", 1.0, 1e-12, 1e12))
    text = body.get("text")
    d = dragging.drag(mech, text, point, target, q, locked, step)
    new_set = {**body.get("set", {}), **d.values}
    answer = {"point": d.point, "target": list(target), "set": new_set, "text": d.text, "input": d.input, "position": list(d.position),
              "reached": d.reached, "scrub": d.scrub, "message": d.message, "changed": d.values,
              "input_name": d.input_name}
    solve_body = {k: v for k, v in body.items() if k in accepted("solve")}
    solve_body["set"] = new_set
    if d.text is not None:
        solve_body["text"] = d.text
    try:
        solved = solve(solve_body, cache) if (d.values or d.text is not None) else None
    except (ParameterError, RequestError, ValueError) as exc:
        reason = _first_line(str(exc))
        limit = drag_limit(mech, body, solve_body, d.values, cache) if d.text is None else None
        if limit is None:
            answer.update(set=body.get("set", {}), text=None, input=None, reached=False, changed={}, position=None,
                          message=f"{point} stops here: {reason}")
            solved = None
        else:
            values, solved = limit
            answer.update(set={**body.get("set", {}), **values}, changed=values, reached=False, position=None,
                          message=f"{point} stops at the limit: beyond it {reason}")
    return {"drag": answer, "solve": solved}


LIMIT_STEPS = 8
"""Halvings of the way from the values before a drag step to those it asked for, when those cannot run the
cycle: the step stops within 1/256 of the way of the limit."""


def drag_limit(mech: Mechanism, body: dict, solve_body: dict, values: dict, cache: Mechanisms | None = None):
    """(values, solve) as far along the way from ``mech``'s values to ``values`` as the cycle still runs (the
    input turns fully, every group closes), or None when none of it does or a branch had to flip.

    A crank turning fully is first searched for by the cheap look on the file's geometry
    (:func:`sim.service.editing.turns_on_its_geometry`, ~1 ms a trial where the full check schedules the
    change points of every trial, up to 20 ms); the limit it finds is taken only when the full check agrees
    on both sides of it (the values it gives run the cycle, a step of the way further does not); otherwise,
    and for other drives, the halving goes by the full check itself."""
    from sim.service import editing as dragging
    if not values or any(mech.definition.parameter_kind.get(k) == "branch" for k in values):
        return None
    old = mech.values
    trials = Mechanisms(2 * LIMIT_STEPS + 2)        # both halvings often try the same values: built once
    seeded = Seeded(cache, trials) if cache else trials

    def trial(f: float) -> dict:
        return {**solve_body, "set": {**body.get("set", {}), **{k: old[k] + f * (v - old[k]) for k, v in values.items()}}}

    def runs(b: dict, m=None) -> bool:
        try:
            m = m or mechanism_of(b, trials)
            analysis(m, b, figures=False)
            return True
        except (ParameterError, RequestError, ValueError):
            return False

    def full(b: dict) -> bool:
        try:
            m = mechanism_of(b, trials)
            # a stretch of the turn that plainly does not assemble: refused without the full check's refinement
            return not (input_range_of(b, m) is None and dragging.cannot_turn_fully(m)) and runs(b, m)
        except (ParameterError, RequestError, ValueError):
            return False

    best = None
    def turns(f: float) -> bool:
        try:
            return dragging.turns_on_its_geometry(mechanism_of(trial(f), trials))
        except (ParameterError, RequestError, ValueError):
            return False

    # the geometry's halving is skipped where its smallest step already fails to turn (a point pressed on its
    # limit): it could find nothing the full check below would not refuse at once
    if input_range_of(body, mech) is None and dragging.plain_turn_applies(mech) and turns(0.5 ** LIMIT_STEPS):
        lo, hi = 0.0, 1.0
        for _ in range(LIMIT_STEPS):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if turns(mid) else (lo, mid)
        if lo > 0 and (hi >= 1.0 or not full(trial(hi))):
            try:                                    # its solve is its full check: refused, the halving decides
                return {k: trial(lo)["set"][k] for k in values}, solve(trial(lo), seeded)
            except (ParameterError, RequestError, ValueError):
                pass
    # the smallest step the full halving could take fails: the point is at the limit already (a drag pressing
    # on it, the common case there: one full check instead of LIMIT_STEPS), and the way is not taken past a
    # stretch that does not run to values beyond it that would
    if best is None and not full(trial(0.5 ** LIMIT_STEPS)):
        return None
    if best is None:
        lo, hi = 0.0, 1.0
        for _ in range(LIMIT_STEPS):                # the analysis alone decides; the answer is solved once
            mid = 0.5 * (lo + hi)
            b = trial(mid)
            if full(b):
                best, lo = b, mid
            else:
                hi = mid
    if best is None:
        return None
    return {k: best["set"][k] for k in values}, solve(best, seeded)


def draw(body: dict) -> dict:
    """A linkage drawn on the empty page (:func:`sim.front.draw.check`): its ``linkage/1`` text, mobility,
    Assur groups, or the one line that says what is wrong and the names it concerns."""
    from sim.front import draw as drawing
    check_fields(body, "draw")
    return drawing.check(body.get("drawing"))


def render(body: dict) -> tuple[bytes, str, None]:
    """The rendered video as the page shows it (not a download)."""
    return render_video(body), "video/mp4", None


ACTIONS = {"/api/draw": draw, "/api/drag": drag, "/api/forces": forces, "/api/dynamics": dynamics, "/api/open": open_file,
           "/api/targets": targets, "/api/loads/draw": loads_panel.draw, "/api/loads/edit": loads_panel.edit,
           "/api/cam": cam_panel.cam}
"""The panels' JSON actions (forces, dynamics, opening a file), by path."""
ROUTES = {"/api/solve": solve, "/api/simulate": simulate, "/api/render": render, "/api/synthesize": synthesize,
          "/api/synthesize/status": synthesis_status, "/api/synthesize/cancel": cancel_synthesis, **ACTIONS,
          **{f"/api/export/{k}": functools.partial(export, k) for k in ("csv", "json", "toml", "mjcf", *PARTS_EXPORTS)},
          "/api/exit": None}
"""Every POST route and its action, called with what its signature names (:func:`call`): a JSON answer, or
(bytes, content type, file name) for a download. /api/exit (None) answers and stops the server."""
POSTS = set(ROUTES)


SOCKET_ACTIONS = {"/api/drag": drag, "/api/solve": solve}
"""What the page's WebSocket answers (GET /api/socket, :func:`application`): the requests a drag repeats."""


def socket_answer(text: str, cache: Mechanisms | None = None) -> bytes:
    """One WebSocket message's answer: the JSON its POST would answer, or its one-line error, with its id."""
    ident = None
    try:
        message = parse_json(text.encode("utf-8"))
        ident = message.get("id")
        if not isinstance(ident, int) or isinstance(ident, bool):
            raise RequestError(400, "id must be an integer")
        path = message.get("path")
        action = SOCKET_ACTIONS.get(path) if isinstance(path, str) else None
        if action is None:
            raise RequestError(404, f"path must be one of {', '.join(SOCKET_ACTIONS)}")
        body = message.get("body")
        if not isinstance(body, dict):
            raise RequestError(400, "body must be a JSON object")
        data = _json_bytes(action(body, cache))
        return b'{"id":%d,"status":200,"answer":%s}' % (ident, data)
    except RequestError as exc:
        status, error = exc.status, _first_line(str(exc))
    except MemoryError:
        status, error = 400, "out of memory: lower the samples or revolutions"
    except Exception as exc:                  # ParameterError, and any failure to compute: the page's message
        status, error = 400, _first_line(str(exc)) or type(exc).__name__
    return _json_bytes({"id": ident if isinstance(ident, int) else None, "status": status, "error": error})


def _json_bytes(obj) -> bytes:
    return json.dumps(obj, separators=(",", ":"), allow_nan=False).encode()


def _first_line(text: str) -> str:
    line = (text.strip().splitlines() or [""])[0]
    return line if len(line) <= MAX_ERROR_CHARS else line[:MAX_ERROR_CHARS - 3] + "..."


# ------------------------------------------------------------------------------------------- HTTP
MAX_HEADERS = 65_536
"""[bytes] The request line and headers of one request: more is refused (431); a URL over MAX_URL (414)."""
MAX_URL = 8_192
TIMEOUT = 10.0
"""[s] A connection idle this long between requests, or a body stalled this long, is closed."""


def _limit_arenas(n: int = 2) -> None:
    """At most ``n`` glibc malloc arenas (M_ARENA_MAX = -8): with one per worker thread the heap fragments
    and the resident size grows over repeated rounds; a no-op where mallopt does not exist."""
    try:
        import ctypes
        ctypes.CDLL(None).mallopt(-8, n)
    except (OSError, AttributeError):
        pass


def _trim() -> None:
    """Give freed heap back to the system after a request (glibc keeps large freed arenas otherwise and
    the resident size creeps up over repeated rounds); a no-op where malloc_trim does not exist."""
    try:
        import ctypes
        ctypes.CDLL(None).malloc_trim(0)
    except (OSError, AttributeError):
        pass


class AppServer:
    """The app's server (tornado): bound to 127.0.0.1 when made (``port`` 0 picks a free one), serving in the
    thread that calls :meth:`serve_forever` until :meth:`shutdown` or POST /api/exit. The event loop reads and
    writes the connections; each action runs on a fixed pool of WORKERS threads (threads, their malloc arenas,
    MuJoCo and GL contexts reused, so memory stays flat over repeated rounds; further requests queue), so a
    long one (a render, a motor run) never holds up the others."""

    def __init__(self, port: int, initial: dict):
        from tornado import netutil
        self.sockets = netutil.bind_sockets(port, "127.0.0.1")    # listen backlog 128: a burst waits
        self.server_address = self.sockets[0].getsockname()[:2]
        self.port = self.server_address[1]
        self.hosts = {f"127.0.0.1:{self.port}", f"localhost:{self.port}"}
        self.origins = {f"http://{h}" for h in self.hosts}
        self.initial = initial
        self.page = page(initial)
        self.synthesis = None                   # the page's synthesis job (sim.front.synth_job.Job), if any
        self.mechanisms = Mechanisms()          # the last ones loaded: a drag's next step starts from them
        self.synthesis_lock = threading.Lock()
        _limit_arenas()
        self.pool = concurrent.futures.ThreadPoolExecutor(max_workers=WORKERS, thread_name_prefix="linkage-app")
        self._loop = None
        self._stopped = threading.Event()

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.port}/"

    def serve_forever(self) -> None:
        """Serve in this thread (its own event loop) until :meth:`shutdown`, POST /api/exit or Ctrl-C."""
        import asyncio
        from tornado.httpserver import HTTPServer
        from tornado.ioloop import IOLoop
        loop = asyncio.new_event_loop()
        asyncio.set_event_loop(loop)
        # the body's own bound is MAX_BODY, refused (413) from its Content-Length before it is read; tornado's
        # bound is far above so that its bare 400 never follows that answer on the same connection
        http = HTTPServer(application(self), max_header_size=4 * MAX_HEADERS, max_body_size=1 << 50,
                          idle_connection_timeout=TIMEOUT, body_timeout=TIMEOUT)
        http.add_sockets(self.sockets)
        self._loop = IOLoop.current()
        try:
            loop.run_forever()
        finally:
            http.stop()
            try:
                loop.run_until_complete(http.close_all_connections())
                pending = asyncio.all_tasks(loop)
                for task in pending:
                    task.cancel()
                loop.run_until_complete(asyncio.gather(*pending, return_exceptions=True))
            finally:
                loop.close()
                asyncio.set_event_loop(None)
                self._stopped.set()

    def stop_soon(self) -> None:
        """End :meth:`serve_forever` (from the serving thread)."""
        self._loop.stop()

    def shutdown(self) -> None:
        """End :meth:`serve_forever` from another thread and wait until it has returned."""
        if self._loop is not None and not self._stopped.is_set():
            self._loop.add_callback(self._loop.stop)
            self._stopped.wait()

    def server_close(self) -> None:
        if self.synthesis is not None and self.synthesis.running:
            self.synthesis.cancel()
        for s in self.sockets:
            s.close()
        self.pool.shutdown(wait=False, cancel_futures=True)


def call(action, body: dict, server: AppServer):
    """``action`` called with what its signature names: ``body`` (the request's JSON object), ``cache`` (the
    server's recently loaded mechanisms), ``server``; the one way the HTTP and the WebSocket routes call one."""
    import inspect
    given = {"body": body, "cache": server.mechanisms, "server": server}
    return action(**{name: given[name] for name in inspect.signature(action).parameters})


def answered(action, raw: bytes, server: AppServer) -> tuple[int, bytes, str, dict]:
    """(status, bytes, content type, extra headers) of one POST's ``raw`` body given to ``action`` (on a worker
    thread: parsing, the work and the encoding all off the event loop): its JSON, a download (an action that
    answers (bytes, content type, file name or None)), or the one-line refusal."""
    try:
        out = call(action, parse_json(raw), server)
        if isinstance(out, tuple):
            data, ctype, filename = out
            return 200, data, ctype, ({"Content-Disposition": f'attachment; filename="{filename}"'} if filename else {})
        return 200, _json_bytes(out), "application/json", {}
    except Exception as exc:                      # ParameterError, and any failure to compute: the page's message
        status, message = failure(exc)
        return status, _json_bytes({"error": message}), "application/json", {}
    finally:
        _trim()


def failure(exc: BaseException) -> tuple[int, str]:
    """(status, one line) of a request that raised: a refusal's own status (a RequestError's, tornado's), else
    400 with the reason (a ParameterError, any failure to compute)."""
    status = getattr(exc, "status", None) or getattr(exc, "status_code", None)
    if isinstance(status, int) and 400 <= status < 500:
        return status, _first_line(exc.log_message if status == 405 and hasattr(exc, "log_message") and
                                   exc.log_message else str(exc)) or HTTPStatus(status).phrase
    if isinstance(exc, MemoryError):
        return 400, "out of memory: lower the samples or revolutions"
    return 400, _first_line(str(exc)) or type(exc).__name__


def request_problem(request, server: AppServer, socket: bool = False) -> tuple[int, str] | None:
    """(status, one line) refusing a request before it reaches its action, or None: a URL over MAX_URL, headers
    over MAX_HEADERS, a Host other than this loopback address and port (DNS rebinding), an Origin other than
    this page's (cross-site requests; the WebSocket must send one: a browser always does, and no same-origin
    policy guards a socket, this does)."""
    if len(request.uri) > MAX_URL:
        return 414, f"the URL is {len(request.uri):,} characters; at most {MAX_URL:,} are accepted"
    if len(request.uri) + sum(len(k) + len(v) + 4 for k, v in request.headers.get_all()) > MAX_HEADERS:
        return 431, f"the request's headers are over {MAX_HEADERS:,} bytes"
    host = (request.headers.get("Host") or "").strip().lower()
    if host not in server.hosts:
        return 403, f"Host {host or '(none)'!r} refused: open {server.url}"
    origin = request.headers.get("Origin")
    if socket and origin is None:
        return 403, "WebSocket without an Origin refused: only the page's own origin may connect"
    if origin is not None and origin.strip().lower() not in server.origins:
        return 403, f"cross-origin request from {_short(origin)} refused"
    return None


def application(server: AppServer):
    """The tornado application of ``server``: the page and its files, GET /api/mechanisms, a POST route for
    every action of ROUTES, the WebSocket; any other path 404, any other method 405. Every handler refuses a
    request by :func:`request_problem` first, and answers a refusal or a failure as a 4xx with one JSON line
    ``{"error": ...}``, closing the connection after it; nothing is logged."""
    from tornado import web, websocket
    from tornado.ioloop import IOLoop

    class Checked:
        """What every handler shares (mixed into tornado's): the checks, the security headers, the refusals."""

        socket = False

        def initialize(self, server: AppServer, action=None) -> None:
            self.server, self.action = server, action
            self.chunks, self.size = [], 0

        def set_default_headers(self) -> None:
            self.clear_header("Server")
            for k, v in SECURITY_HEADERS.items():
                self.set_header(k, v)

        def compute_etag(self):
            return None

        def problem(self) -> tuple[int, str] | None:
            return request_problem(self.request, self.server, self.socket)

        def prepare(self) -> None:
            problem = self.problem()
            if problem:
                self.refuse(*problem)

        def refuse(self, status: int, message: str):
            return self.answer(status, _json_bytes({"error": _first_line(message)}), "application/json")

        def answer(self, status: int, data: bytes, ctype: str, extra: dict | None = None):
            """Send the answer; after a 4xx the connection is closed (an unread body must not be taken for
            the next request)."""
            self.set_status(status)
            self.set_header("Content-Type", ctype)
            for k, v in (extra or {}).items():
                self.set_header(k, v)
            if status >= 400:
                self.set_header("Connection", "close")
            done = self.finish(data)
            if status >= 400:
                done.add_done_callback(lambda _: self.request.connection.close())
            return done

        def write_error(self, status_code: int, **kwargs) -> None:
            """tornado's own refusals (an unknown method: 405) and anything a handler raised."""
            exc = kwargs.get("exc_info", (None, None, None))[1]
            if status_code == 405:
                self.refuse(405, f"method {self.request.method} is not allowed: use GET or POST")
            else:
                self.refuse(*(failure(exc) if exc is not None else (400, HTTPStatus(status_code).phrase)))

        def log_exception(self, typ, value, tb) -> None:
            """Quiet: a refusal or a failure is the page's one line, never a traceback on the terminal."""

    @web.stream_request_body
    class Base(Checked, web.RequestHandler):
        """A body is taken as it arrives, so that one declared too large is refused (413) from its
        Content-Length before any of it is read."""

        def problem(self) -> tuple[int, str] | None:
            length = self.request.headers.get("Content-Length", "")
            if length.isdigit() and int(length) > MAX_BODY:
                return 413, f"the body is {int(length):,} bytes; at most {MAX_BODY:,} are accepted"
            return super().problem()

        def data_received(self, chunk: bytes) -> None:
            self.size += len(chunk)
            if self.size > MAX_BODY:                   # a chunked body to a path that takes none
                self.request.connection.close()
            else:
                self.chunks.append(chunk)

    class NotFound(Base):
        def get(self):
            path = self.request.path
            if path.startswith("/api/"):
                return self.refuse(404, f"{path}: unknown path or use POST")
            self.refuse(404, f"{path}: not found")

        def post(self):
            self.refuse(404, f"{self.request.path}: no such action (POST to {', '.join(ROUTES)})")

    class Files(Base):
        """GET / (the page, its parameter rows written in) and the fixed list of static files (FILES)."""

        def get(self):
            path = self.request.path
            if path == "/":
                return self.answer(200, self.server.page, "text/html; charset=utf-8")
            name, ctype = FILES[path]
            self.answer(200, (STATIC / name).read_bytes(), ctype)

    class Listing(Base):
        async def get(self):
            data = await IOLoop.current().run_in_executor(self.server.pool, _listing, self.server)
            self.answer(200, data, "application/json")

    class Action(Base):
        """POST of one action: its body a bounded JSON object, its answer the action's (JSON or a download)."""

        def problem(self) -> tuple[int, str] | None:
            problem = super().problem()
            if problem or self.request.method != "POST":
                return problem
            ctype = (self.request.headers.get("Content-Type") or "").split(";", 1)[0].strip().lower()
            if ctype != "application/json":
                return 415, "send the request body as JSON (Content-Type: application/json)"
            if self.request.headers.get("Transfer-Encoding"):
                return 411, "send the body with a Content-Length, not chunked"
            if not self.request.headers.get("Content-Length", "").isdigit():
                return 411, "a Content-Length is required"
            return None

        async def get(self):
            self.refuse(405, f"{self.request.path}: use POST")

        async def post(self):
            raw = b"".join(self.chunks)
            if self.action is None:                           # /api/exit: answered, then the server stops
                try:
                    parse_json(raw)
                except RequestError as exc:
                    return self.refuse(exc.status, str(exc))
                await self.answer(200, _json_bytes({"stopped": True}), "application/json")
                IOLoop.current().add_callback(self.server.stop_soon)
                return
            self.answer(*await IOLoop.current().run_in_executor(self.server.pool, answered, self.action, raw,
                                                                self.server))

    class Socket(Checked, websocket.WebSocketHandler):
        """GET /api/socket: a WebSocket for drag steps, from this page only; each text message ``{"id", "path":
        "/api/drag" or "/api/solve", "body"}`` is answered ``{"id", "status", "answer"}`` (or ``"error"``), as
        the POST of that path would; one message at a time, in order (tornado waits for each answer)."""

        socket = True

        def check_origin(self, origin: str) -> bool:
            return True                         # request_problem (prepare) let in the page's own origin only

        async def on_message(self, message) -> None:
            if isinstance(message, bytes):
                self.close(1003, "text frames only")
                return
            try:
                answer = await IOLoop.current().run_in_executor(self.server.pool, socket_answer, message,
                                                                self.server.mechanisms)
                await self.write_message(answer)
            except (websocket.WebSocketClosedError, RuntimeError):      # the page went away, the server stops
                self.close()

    args = {"server": server}
    routes = [(r"/api/socket", Socket, args), (r"/api/mechanisms", Listing, args),
              *((re.escape(p), Files, args) for p in ("/", *FILES)),
              *((re.escape(p), Action, {**args, "action": a}) for p, a in ROUTES.items())]
    return web.Application(routes, default_handler_class=NotFound, default_handler_args=args,
                           websocket_max_message_size=MAX_BODY, log_function=lambda handler: None)


def _listing(server: AppServer) -> bytes:
    return _json_bytes(mechanisms(server.initial))


# -------------------------------------------------------------------------------------- command
def initial_mechanism(name: str) -> dict:
    """The page's first mechanism: a name, or a file the user named on the command line (sent to the page
    as text, so requests never carry paths). Checked here, so a bad one fails before the server starts."""
    if name in analytic.names():
        service.load(name)
        return {"name": name}
    if not Path(name).exists():
        raise ParameterError(f"{name!r} is neither a mechanism (linkage list) nor a linkage/1 file")
    from sim.service import opening
    text = opening.file_text(name)      # a Pyslvs or PMKS file as its linkage/1 (links and joints) text
    return {"name": service.load(name, text=text).name, "text": text}


def start(port: int, initial: dict) -> AppServer:
    try:
        return AppServer(port, initial)
    except OSError as exc:
        raise ParameterError(f"cannot listen on 127.0.0.1:{port} ({exc.strerror or exc}): choose another "
                             f"--port (0 picks a free one)") from None


def has_display() -> bool:
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def cmd_app(args) -> int:
    if not 0 <= args.port <= 65535:
        raise ParameterError(f"--port {args.port} must be in 0..65535 (0 picks a free one)")
    server = start(args.port, initial_mechanism(args.mechanism))
    print(f"linkage app: {server.url}  (Exit on the page or Ctrl-C stops it)", flush=True)
    if has_display() and not args.no_browser:
        webbrowser.open(server.url)
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        print("\nlinkage app: stopped", file=sys.stderr)
        return 130
    finally:
        server.server_close()
    print("linkage app: stopped")
    return 0

