"""Hostile but plausible cams and drives through the ``linkage`` commands, from outside (seeded): every case is
accepted and runs, or is refused in one line naming the file and a field (exit 2), and never mishandled.

Run:  python benchmarks/fuzz_cams_drives.py [--seed 0] [--cases 150] [--seconds 60] [--plot-every 6] [-v]

The cases are edits of the library's cam files (cam_roller, cam_flat, cam_rocker, cam_fourbar) and drive files
(excavator, dump_tipper, scissor_lift, servo_press, arm_2r), each valid TOML with one to three values at or
beyond an edge: a roller larger than the base circle or than the pitch curve's curvature, zero, negative or
huge rollers and base circles, a guide offset beyond the base circle, a face 0, tiny or huge, an arm that
cannot reach the cam or pivoted at the cam's pivot, segments of zero or negative duration, rises that do not
return, durations summing to 359.9 or 360.1deg, unknown shapes, profile CSVs of too few, duplicate,
self-crossing or non-star-shaped points or NaN text; actuator strokes min >= max, a start outside the stroke,
zero-area pistons, rods as wide as the bore; laws of zero duration, tables of one row or non-monotonic time;
speeds 0, negative, 1e6; nan/inf literals; and a few sound designs (:data:`VALID`). There are 386 single
edits: ``--cases`` below that runs a seeded sample of them (the sound designs always), above it every one
and then seeded pairs and triples; 16 ``simulate --speed`` 0, -30, 1e6, nan cases on the library cams follow.

Each case's file (and CSV) is written to a temp folder and run in fresh processes
(``python -m sim ...``, PYTHONPATH this checkout): ``check``; where check accepts, also ``analyze --json``,
``forces --json``, ``compare``, ``simulate --speed W --json`` (cams), ``export --dxf --stl`` into an empty
folder and, every ``--plot-every``-th accepted case, ``plot``; where check refuses, ``export`` (the same
refusal, nothing written). A case is

* ``accepted``: every command exits 0 (compare 0 or 1: its verdict), no NaN or Infinity in a JSON output
  (``accepted, later refused``: check accepts, a later command refuses properly: a design that cannot
  move over its run, or cannot be simulated);
* ``refused``: exit 2 with one line on stderr naming the file and a field (``field '...'``, a segment, ...);
* ``MISHANDLED``: a traceback, any other exit code, a refusal of several lines or naming no file or field,
  exit 0 with NaN in the JSON, a refused command that left files in its output folder, an input file changed,
  a command past ``--seconds``, or a sound design (:data:`VALID`: a polygon circle as the profile, a table
  law inside the stroke) refused.

Prints the counts per class, every mishandled case (its edits, command and the last line it printed) grouped
by a short signature, and exits 1 if any case was mishandled.
"""

from __future__ import annotations

import argparse
import hashlib
import math
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time
from collections import Counter, defaultdict
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
LIBRARY = ROOT / "analytic" / "library"
CAMS = ("cam_roller", "cam_flat", "cam_rocker", "cam_fourbar")
DRIVES = ("excavator", "dump_tipper", "scissor_lift", "servo_press", "arm_2r")
NAMES_A_FIELD = re.compile(r"field|segment|stroke|'\w+'|\bl0\b|bore|rod|roller|base_radius|arm|guide|profile|"
                           r"face_width|duration|rise|table|omega|\bv\b|length|speed|parameters|inertia|loads|the input \w+",
                           re.I)
"""What a refusal must name besides the file: a field (or the element's part a field sets)."""
VALID = ("profile circle", "profile duplicate points", "table ok", "motor table ok", "crank table ok")
"""Edits that leave a sound design (a circle's outline about the pivot, each of its points written twice; a
table law inside the stroke): check must accept them, a refusal is mishandled. Every plan holds them all."""


# ------------------------------------------------------------------------------------------ text edits
def _blocks(text: str) -> list[list[str]]:
    out, cur = [], []
    for ln in text.splitlines():
        if ln.startswith("[") and cur:
            out.append(cur)
            cur = []
        cur.append(ln)
    out.append(cur)
    return out


def set_field(text: str, where: str, key: str, value: str | None) -> str:
    """``text`` with ``key = value`` in the first block whose lines contain ``where`` (a header like
    "[parameters]" or a line like 'kind = "cam"'); a multi-line array value is replaced whole; None drops
    the key. Unchanged where no block matches."""
    blocks = _blocks(text)
    for b in blocks:
        if not any(ln.strip().startswith(where) for ln in b):
            continue
        for i, ln in enumerate(b):
            if re.match(rf"\s*{re.escape(key)}\s*=", ln):
                j = i
                if re.match(rf"\s*{re.escape(key)}\s*=\s*\[\s*(#.*)?$", ln):
                    while not b[j].strip().startswith("]"):
                        j += 1
                b[i:j + 1] = [] if value is None else [f"{key} = {value}"]
                break
        else:
            if value is not None:
                b.insert(1, f"{key} = {value}")
        break
    return "\n".join(ln for b in blocks for ln in b) + "\n"


def get_field(text: str, where: str, key: str) -> str | None:
    for b in _blocks(text):
        if any(ln.strip().startswith(where) for ln in b):
            for ln in b:
                m = re.match(rf"\s*{re.escape(key)}\s*=\s*(.*?)\s*(#.*)?$", ln)
                if m:
                    return m[1]
    return None


def num_of(text: str, where: str, key: str, default: float = 1.0) -> float:
    v = get_field(text, where, key)
    try:
        return float(v)
    except (TypeError, ValueError):
        return default


CAM = 'kind = "cam"'


def segs(*items) -> str:
    parts = []
    for shape, dur, rise in items:
        s = f'{{ shape = "{shape}", duration = {dur}'
        parts.append(s + ("" if rise is None else f", rise = {rise}") + " }")
    return "[" + ", ".join(parts) + "]"


def circle_csv(r: float, n: int = 72, cx: float = 0.0, cy: float = 0.0) -> str:
    return "x,y\n" + "".join(f"{cx + r * math.cos(2 * math.pi * k / n):.9g},{cy + r * math.sin(2 * math.pi * k / n):.9g}\n"
                             for k in range(n))


def star_csv(r: float) -> str:
    """A non-star-shaped outline (a C: a disc with a deep notch bent round the pivot)."""
    pts = []
    for k in range(60):
        a = 2 * math.pi * k / 60
        rr = r if not 0.3 < a < 1.2 else 0.3 * r
        pts.append((rr * math.cos(a), rr * math.sin(a)))
    pts[10] = (1.4 * r * math.cos(0.2), -0.5 * r)        # a spike folded back across the notch
    return "x,y\n" + "".join(f"{x:.9g},{y:.9g}\n" for x, y in pts)


def bowtie_csv(r: float) -> str:
    """A self-crossing outline: a figure of eight."""
    return "x,y\n" + "".join(f"{r * math.sin(2 * math.pi * k / 40):.9g},{r * math.sin(4 * math.pi * k / 40) / 2:.9g}\n"
                             for k in range(40))


def cam_edits(base: str, text: str) -> list[tuple[str, object]]:
    """(label, edit) pairs for a cam file; an edit maps (text) to (text, {csv name: csv text})."""
    rb = num_of(text, CAM, "base_radius")
    rr = num_of(text, CAM, "roller", 0.0)
    osc = get_field(text, CAM, "follower") == '"oscillating"'
    rise = "12deg" if osc else f"{rb / 2:g}"

    def f(key, value):
        return lambda t: (set_field(t, CAM, key, value), {})

    def seg(*items):
        return lambda t: (set_field(t, CAM, "segments", segs(*items)), {})

    def profile(csv, name="cam.csv"):
        return lambda t: (set_field(set_field(t, CAM, "segments", None), CAM, "profile", f'"{name}"'), {name: csv})
    q = (lambda v: f'"{v}deg"') if osc else (lambda v: repr(v))
    r_ = (lambda v: f'"{v}"') if osc else (lambda v: v)
    out = [
        ("base_radius tiny", f("base_radius", f"{rb * 1e-9:g}")),
        ("base_radius huge", f("base_radius", f"{rb * 1e6:g}")),
        ("base_radius 0", f("base_radius", "0")),
        ("base_radius negative", f("base_radius", f"{-rb:g}")),
        ("base_radius nan", f("base_radius", "nan")),
        ("base_radius inf", f("base_radius", "inf")),
        ("base_radius text", f("base_radius", '"NaN"')),
        ("segments unknown shape", seg(("dwell", '"90deg"', None), ("trapezoid", '"130deg"', r_(rise)),
                                       ("dwell", '"10deg"', None), ("cycloidal", '"130deg"', r_("-" + rise)))),
        ("segments zero duration", seg(("dwell", '"0deg"', None), ("cycloidal", '"180deg"', r_(rise)),
                                       ("cycloidal", '"180deg"', r_("-" + rise)))),
        ("segments negative duration", seg(("dwell", '"-10deg"', None), ("cycloidal", '"190deg"', r_(rise)),
                                           ("cycloidal", '"180deg"', r_("-" + rise)))),
        ("segments do not return", seg(("dwell", '"90deg"', None), ("cycloidal", '"270deg"', r_(rise)))),
        ("segments sum 359.9", seg(("dwell", '"89.9deg"', None), ("cycloidal", '"135deg"', r_(rise)),
                                   ("poly345", '"135deg"', r_("-" + rise)))),
        ("segments sum 360.1", seg(("dwell", '"90.1deg"', None), ("cycloidal", '"135deg"', r_(rise)),
                                   ("poly345", '"135deg"', r_("-" + rise)))),
        ("segments one dwell", seg(("dwell", '"360deg"', None))),
        ("segments empty", f("segments", "[]")),
        ("segments nan rise", seg(("dwell", '"90deg"', None), ("cycloidal", '"135deg"', "nan"),
                                  ("poly345", '"135deg"', "nan"))),
        ("segments nan duration", seg(("dwell", "nan", None), ("cycloidal", '"180deg"', r_(rise)),
                                      ("poly345", '"180deg"', r_("-" + rise)))),
        ("segments huge rise", seg(("dwell", '"90deg"', None), ("cycloidal", '"10deg"', q(rb * 50) if not osc else '"170deg"'),
                                   ("dwell", '"130deg"', None), ("poly345", '"130deg"', q(-rb * 50) if not osc else '"-170deg"'))),
        ("segments tiny durations", seg(("dwell", '"1e-9deg"', None), ("cycloidal", '"179.999999999deg"', r_(rise)),
                                        ("poly345", '"180deg"', r_("-" + rise)))),
        ("segments missing rise", seg(("dwell", '"90deg"', None), ("cycloidal", '"135deg"', None),
                                      ("poly345", '"135deg"', None))),
        ("segments and profile", lambda t: (set_field(t, CAM, "profile", '"cam.csv"'), {"cam.csv": circle_csv(rb)})),
        ("profile circle", profile(circle_csv(rb))),
        ("profile 3 points", profile("x,y\n" + f"{rb},0\n0,{rb}\n{-rb},0\n")),
        ("profile 7 points", profile(circle_csv(rb, 7))),
        ("profile duplicate points", profile("x,y\n" + "".join(ln + "\n" + ln + "\n" for ln in circle_csv(rb, 36).splitlines()[1:]))),
        ("profile all one point", profile("x,y\n" + f"{rb},0\n" * 20)),
        ("profile self-crossing", profile(bowtie_csv(rb))),
        ("profile not star-shaped", profile(star_csv(rb))),
        ("profile NaN text", profile(circle_csv(rb).replace("\n0,", "\nNaN,", 1) + "nan,nan\n")),
        ("profile pivot outside", profile(circle_csv(rb, cx=3 * rb))),
        ("profile tiny", profile(circle_csv(rb * 1e-9))),
        ("profile huge", profile(circle_csv(rb * 1e6))),
        ("profile empty", profile("")),
        ("profile missing file", lambda t: (set_field(set_field(t, CAM, "segments", None), CAM, "profile", '"nowhere.csv"'), {})),
        ("profile collinear", profile("x,y\n" + "".join(f"{rb * k / 10:g},0\n" for k in range(12)))),
        ("follower unknown", f("follower", '"rotating"')),
        ("contact unknown", f("contact", '"ball"')),
        ("omega 0", lambda t: (set_field(t, "[parameters]", "omega1", "0"), {})),
        ("omega negative", lambda t: (set_field(t, "[parameters]", "omega1", '"-360deg"'), {})),
        ("omega 1e6", lambda t: (set_field(t, "[parameters]", "omega1", "1e6"), {})),
        ("spring stiffness negative", lambda t: (set_field(t, "[[loads]]", "stiffness", "-5"), {})),
        ("inertia mass negative", lambda t: (re.sub(r"\bm = [\d.]+", "m = -1.0", t, count=1), {})),
    ]
    if get_field(text, CAM, "contact") == '"roller"':
        out += [("roller 0", f("roller", "0")), ("roller negative", f("roller", f"{-rr:g}")),
                ("roller tiny", f("roller", f"{rr * 1e-9:g}")), ("roller huge", f("roller", f"{rr * 1e6:g}")),
                ("roller = base", f("roller", f"{rb:g}")), ("roller 3x base", f("roller", f"{3 * rb:g}")),
                ("roller nan", f("roller", "nan")),
                ("roller on knife", lambda t: (set_field(t, CAM, "contact", '"knife"'), {})),
                ("roller to flat", lambda t: (set_field(set_field(t, CAM, "roller", None), CAM, "contact", '"flat"'), {}))]
    if get_field(text, CAM, "contact") == '"flat"':
        out += [("face_width 0", f("face_width", "0")), ("face_width tiny", f("face_width", "1e-9")),
                ("face_width huge", f("face_width", "1e9")), ("face_width negative", f("face_width", "-40")),
                ("face_width nan", f("face_width", "nan")),
                ("flat with roller", f("roller", "5"))]
    if not osc:
        out += [("guide offset beyond base", lambda t: (set_field(t, CAM, "guide", '{ through = [%g, 0], angle = "90deg" }' % (-2 * rb - 2 * rr)), {})),
                ("guide offset at prime", lambda t: (set_field(t, CAM, "guide", '{ through = [%g, 0], angle = "90deg" }' % (-rb - rr)), {})),
                ("guide angle nan", lambda t: (set_field(t, CAM, "guide", '{ through = [0, 0], angle = nan }'), {})),
                ("guide through cam pivot", lambda t: (set_field(t, CAM, "guide", '{ through = "A", angle = "90deg" }'), {})),
                ("guide two points", lambda t: (set_field(t, CAM, "guide", '["A", "A"]'), {}))]
    else:
        arm = num_of(text, CAM, "arm")
        out += [("arm cannot reach", f("arm", f"{arm * 1e-3:g}")), ("arm huge", f("arm", f"{arm * 1e3:g}")),
                ("arm 0", f("arm", "0")), ("arm negative", f("arm", f"{-arm:g}")), ("arm nan", f("arm", "nan")),
                ("arm pivot at cam pivot", f("arm_pivot", '"A"')),
                ("arm pivot unknown", f("arm_pivot", '"Z"')),
                ("arm with guide", f("guide", '{ through = [0, 0], angle = "90deg" }')),
                ("arm rise past 180deg", seg(("dwell", '"90deg"', None), ("cycloidal", '"135deg"', '"200deg"'),
                                             ("poly345", '"135deg"', '"-200deg"'))),
                ("arm flat", lambda t: (set_field(set_field(t, CAM, "roller", None), CAM, "contact", '"flat"'), {}))]
    return out


def table_csv(rows: list[tuple[float, float]], head: str = "t,q") -> str:
    return head + "\n" + "".join(f"{a},{b}\n" for a, b in rows)


def drive_edits(base: str, text: str) -> list[tuple[str, object]]:
    out = []
    if 'kind = "actuator"' in text:
        A = 'kind = "actuator"'
        lo, hi = [float(x) for x in re.findall(r"[\d.]+", get_field(text, A, "stroke"))[:2]]
        mid, span = (lo + hi) / 2, hi - lo

        def a(key, value):
            return lambda t: (set_field(t, A, key, value), {})

        def law(items):                             # segments instead of v (l0 stays the start)
            return lambda t: (set_field(set_field(t, A, "v", None), A, "segments", segs(*items)), {})

        def table(rows, head="t,q"):                # a table instead of v (its first row is the start: no l0)
            return lambda t: (set_field(set_field(set_field(t, A, "v", None), A, "l0", None), A, "table", '"law.csv"'),
                              {"law.csv": table_csv(rows, head)})

        def p(key, value):                          # a parameter the actuator names, or the field itself
            return lambda t: ((set_field(t, "[parameters]", key, value) if get_field(t, "[parameters]", key)
                               else set_field(t, A, key, value)), {})
        out += [("stroke min = max", a("stroke", f"[{lo}, {lo}]")), ("stroke min > max", a("stroke", f"[{hi}, {lo}]")),
                ("stroke negative", a("stroke", f"[{-hi}, {-lo}]")), ("stroke nan", a("stroke", f"[nan, {hi}]")),
                ("stroke one value", a("stroke", f"[{lo}]")),
                ("l0 below stroke", p("l0", f"{lo * 0.5:g}")), ("l0 above stroke", p("l0", f"{hi * 2:g}")),
                ("l0 at stroke end", p("l0", f"{hi:g}")), ("l0 negative", p("l0", f"{-hi:g}")),
                ("l0 nan", p("l0", "nan")),
                ("bore 0", a("bore", "0")), ("bore negative", a("bore", "-0.1")), ("rod = bore", a("rod", get_field(text, A, "bore"))),
                ("rod > bore", a("rod", "1.0")), ("rod negative", a("rod", "-0.01")), ("bore nan", a("bore", "nan")),
                ("bore without rod", a("rod", None)),
                ("v 0", p("v" if "[parameters]" in text and get_field(text, "[parameters]", "v") else "v", "0")),
                ("v 1e6", a("v", "1e6")), ("v -1e6", a("v", "-1e6")), ("v nan", a("v", "nan")),
                ("length 0", a("length", "0")), ("length negative", a("length", "-1")),
                ("from same pin", a("from", '["A", "A"]')),
                ("branch 0", a("branch", "0")),
                ("law zero duration", law((("dwell", "0", None), ("cycloidal", "1.0", f"{(hi - lo) / 2:g}")))),
                ("law all zero", law((("cycloidal", "0", "0.1"), ("cycloidal", "0", "-0.1")))),
                ("law negative duration", law((("cycloidal", "-1", "0.1"),))),
                ("law past stroke", law((("cycloidal", "1.0", f"{(hi - lo) * 3:g}"),))),
                ("law unknown shape", law((("jerky", "1.0", "0.1"),))),
                ("law angle rise", law((("cycloidal", "1.0", '"30deg"'),))),
                ("law with v", lambda t: (set_field(t, A, "segments", segs(("cycloidal", "1.0", "0.1"))), {})),
                ("table one row", table([(0, mid)])),
                ("table non-monotonic", table([(0, mid), (0.5, mid + 0.1 * span), (0.4, mid), (1, mid - 0.1 * span)])),
                ("table NaN", table([(0, mid), (0.5, "nan"), (1, mid), (2, mid)])),
                ("table deg on length", table([(0, 1), (0.5, 1), (1, 2)], "t,q_deg")),
                ("table ok", table([(0, mid), (0.5, mid + 0.2 * span), (1, mid)])),
                ("table past stroke", table([(0, mid), (0.5, hi + 3 * span), (1, mid)])),
                ("table huge t", table([(0, mid), (1e12, mid + 0.1 * span), (2e12, mid)])),
                ("table zero length", table([(0, 0), (0.5, 0), (1, 0)])),
                ("inertia mass negative", lambda t: (re.sub(r"\bm = [\d.]+", "m = -1.0", t, count=1), {})),
                ("inertia I 0", lambda t: (re.sub(r"\bI = [\d.]+", "I = 0.0", t, count=1), {})),
                ]
    if 'kind = "motor"' in text:
        M = 'kind = "motor"'

        def m(key, value):
            return lambda t: (set_field(t, M, key, value), {})

        def pm(key, value):
            return lambda t: (set_field(t, "[parameters]", key, value), {})
        out += [("motor omega 0", pm("omega2", "0")), ("motor omega 1e6", pm("omega2", "1e6")),
                ("motor omega -1e6", pm("omega2", "-1e6")), ("motor omega nan", pm("omega2", "nan")),
                ("motor q0 nan", pm("q0", "nan")), ("motor q0 huge", pm("q0", "1e300")),
                ("motor length 0", pm("l2", "0")), ("motor length negative", pm("l2", "-0.3")),
                ("motor on itself", m("on", '"fore"')), ("motor on ground", m("on", '"ground"')),
                ("motor pivot unknown", m("pivot", '"Z"')),
                ("motor law zero duration", lambda t: (set_field(set_field(t, M, "omega", None), M, "segments",
                                                       segs(("dwell", "0", None), ("cycloidal", "2", '"90deg"'))), {})),
                ("motor law unknown shape", lambda t: (set_field(set_field(t, M, "omega", None), M, "segments",
                                                       segs(("wobble", "2", '"90deg"'))), {})),
                ("motor table one row", lambda t: (set_field(set_field(set_field(t, M, "omega", None), M, "q0", None), M, "table", '"law.csv"'),
                                                   {"law.csv": table_csv([(0, 0)], "t,q_deg")})),
                ("motor table non-monotonic", lambda t: (set_field(set_field(set_field(t, M, "omega", None), M, "q0", None), M, "table", '"law.csv"'),
                                                         {"law.csv": table_csv([(0, 0), (1, 30), (1, 60), (2, 0)], "t,q_deg")})),
                ("motor table ok", lambda t: (set_field(set_field(set_field(t, M, "omega", None), M, "q0", None), M, "table", '"law.csv"'),
                                              {"law.csv": table_csv([(0, 0), (1, 30), (2, 60), (4, 0)], "t,q_deg")})),
                ("shoulder omega 0", pm("omega1", "0")), ("shoulder omega 1e6", pm("omega1", "1e6")),
                ("inertia I negative", lambda t: (re.sub(r"\bI = [\d.]+", "I = -0.1", t, count=1), {}))]
    if "segments = [" in text and 'kind = "crank"' in text:        # servo_press's crank law
        C = 'kind = "crank"'

        def c(*items):
            return lambda t: (set_field(t, C, "segments", segs(*items)), {})
        out += [("crank law zero duration", c(("cycloidal", "0", '"180deg"'), ("dwell", "0.5", None), ("poly345", "0.5", '"180deg"'))),
                ("crank law all zero", c(("cycloidal", "0", '"180deg"'), ("poly345", "0", '"180deg"'))),
                ("crank law negative duration", c(("cycloidal", "-0.3", '"180deg"'), ("poly345", "1.3", '"180deg"'))),
                ("crank law not a turn", c(("cycloidal", "0.3", '"180deg"'), ("poly345", "0.3", '"170deg"'))),
                ("crank law nan", c(("cycloidal", "nan", '"180deg"'), ("poly345", "0.3", '"180deg"'))),
                ("crank law huge", c(("cycloidal", "1e-9", '"1e6deg"'), ("poly345", "1.0", '"-1e6deg"'))),
                ("crank law length rise", c(("cycloidal", "0.5", "0.1"), ("poly345", "0.5", "-0.1"))),
                ("crank law one dwell", c(("dwell", "1.0", None))),
                ("crank law empty", lambda t: (set_field(t, C, "segments", "[]"), {})),
                ("crank table one row", lambda t: (set_field(set_field(set_field(t, C, "segments", None), C, "phi0", None), C, "table", '"law.csv"'),
                                                   {"law.csv": table_csv([(0, 0)], "t,q_deg")})),
                ("crank table non-monotonic", lambda t: (set_field(set_field(set_field(t, C, "segments", None), C, "phi0", None), C, "table", '"law.csv"'),
                                                         {"law.csv": table_csv([(0, 0), (0.5, 180), (0.4, 200), (1, 360)], "t,q_deg")})),
                ("crank table ok", lambda t: (set_field(set_field(set_field(t, C, "segments", None), C, "phi0", None), C, "table", '"law.csv"'),
                                              {"law.csv": table_csv([(0, 0), (0.3, 180), (0.6, 200), (1, 360)], "t,q_deg")})),
                ("ram rod too short", lambda t: (set_field(t, "[parameters]", "l", "0.01"), {}))]
    return out


def plan(rng: random.Random, n: int) -> list[tuple[str, str, list[tuple[str, object]]]]:
    """(base, label, edits): every single edit of every base once, then seeded pairs and triples, to n cases
    in all (the singles shuffled and cut when n is smaller, the sound designs of :data:`VALID` kept)."""
    singles, by_base = [], {}
    for base in CAMS + DRIVES:
        text = (LIBRARY / f"{base}.toml").read_text()
        edits = cam_edits(base, text) if base in CAMS else drive_edits(base, text)
        by_base[base] = edits
        singles += [(base, label, [(label, fn)]) for label, fn in edits]
    rng.shuffle(singles)
    singles.sort(key=lambda c: c[1] not in VALID)   # the sound designs first (a stable sort: seeded order)
    cases = singles[:n]
    while len(cases) < n:
        base = rng.choice(CAMS + DRIVES)
        if not by_base[base]:
            continue
        pick = rng.sample(by_base[base], min(len(by_base[base]), rng.choice([2, 2, 3])))
        cases.append((base, " + ".join(lb for lb, _ in pick), pick))
    return cases


# ------------------------------------------------------------------------------------------ running
def _digest(folder: Path) -> dict:
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in folder.iterdir() if p.is_file()}


def _judge(cmd: str, rc: int | None, out: str, err: str, path: Path, leftover: list[str]) -> tuple[str, str]:
    """(class, detail) of one command's run: ok, refused, or MISHANDLED."""
    lines = [ln for ln in err.strip().splitlines() if ln.strip()]
    last = lines[-1][:200] if lines else ""
    if rc is None:
        return "MISHANDLED", "hang"
    if "Traceback" in err:
        return "MISHANDLED", "traceback: " + last
    if rc == 0 or (cmd == "compare" and rc == 1):
        if re.search(r"\bNaN\b|\bInfinity\b", out) and "--json" in cmd:
            return "MISHANDLED", "exit 0 with NaN/Infinity in the JSON"
        return "ok", ""
    if leftover:
        return "MISHANDLED", f"exit {rc} but wrote {', '.join(leftover[:3])}"
    if rc != 2:
        return "MISHANDLED", f"exit {rc}: " + last
    if len(lines) != 1:
        return "MISHANDLED", f"{len(lines)}-line message: " + last
    if path.name not in last and path.stem not in last:
        return "MISHANDLED", "names no file: " + last
    if not NAMES_A_FIELD.search(lines[-1].replace(str(path), "")):
        return "MISHANDLED", "names no field: " + last
    return "refused", last


def run_case(folder: Path, base: str, label: str, edits, seconds: float, state: dict, env: dict):
    """Writes the case's files into ``folder`` and runs the commands; returns (class, [(cmd, class, detail,
    seconds)], whether it was plotted)."""
    text = (LIBRARY / f"{base}.toml").read_text()
    extra = {}
    for _, fn in edits:
        text, more = fn(text)
        extra.update(more)
    for p in folder.iterdir():
        shutil.rmtree(p) if p.is_dir() else p.unlink()
    path = folder / f"{base}.toml"
    path.write_text(text)
    for name, csv in extra.items():
        (folder / name).write_text(csv)
    before = _digest(folder)
    outdir = folder / "out"
    results = []

    def run(cmd: str, args: list[str], timeout: float = seconds) -> str:
        if outdir.exists():
            shutil.rmtree(outdir)
        outdir.mkdir()
        t0 = time.perf_counter()
        try:
            p = subprocess.run([sys.executable, "-m", "sim", *args], env=env, capture_output=True, text=True,
                               timeout=timeout, cwd=folder)
            rc, out, err = p.returncode, p.stdout, p.stderr
        except subprocess.TimeoutExpired:
            rc, out, err = None, "", ""
        dt = time.perf_counter() - t0
        leftover = sorted(str(q.relative_to(outdir)) for q in outdir.rglob("*")) if rc not in (0, None) else []
        cls, detail = _judge(cmd, rc, out, err, path, leftover)
        results.append((cmd, cls, detail, dt))
        return cls

    first = run("check", ["check", str(path)])
    if first == "refused" and label in VALID:
        cmd, _, detail, dt = results[-1]
        results[-1] = (cmd, "MISHANDLED", "a sound design refused: " + detail, dt)
    accepted = first == "ok"
    plot = False
    if accepted:
        state["accepted"] += 1
        plot = state["accepted"] % state["plot_every"] == 1 % state["plot_every"]
        run("analyze --json", ["analyze", str(path), "--json"])
        run("forces --json", ["forces", str(path), "--json"])
        run("compare", ["compare", str(path)])
        if base in CAMS:
            run("simulate --speed --json", ["simulate", str(path), "--speed", "30", "--json"])
        run("export", ["export", str(path), "--dxf", str(outdir / "a.dxf"), "--stl", str(outdir / "stl")])
        if plot:
            run("plot", ["plot", str(path), "--out", str(outdir / "p.png")])
    else:
        run("export", ["export", str(path), "--dxf", str(outdir / "a.dxf"), "--stl", str(outdir / "stl")])
    if outdir.exists():
        shutil.rmtree(outdir)
    after = _digest(folder)
    if after != before:
        changed = sorted(k for k in set(before) | set(after) if before.get(k) != after.get(k))
        results.append(("(inputs)", "MISHANDLED", "input files changed: " + ", ".join(changed), 0.0))
    classes = [c for _, c, _, _ in results]
    cls = ("MISHANDLED" if "MISHANDLED" in classes else "refused" if not accepted else
           "accepted, later refused" if "refused" in classes else "accepted")
    return cls, results, plot


def speed_cases(folder: Path, seconds: float, env: dict) -> list[tuple[str, str, list]]:
    """``simulate --speed`` 0, negative, 1e6, nan on the library cams (the option, not the file)."""
    out = []
    for base in CAMS:
        for w in ("0", "-30", "1e6", "nan"):
            path = folder / f"{base}.toml"
            for p in folder.iterdir():
                shutil.rmtree(p) if p.is_dir() else p.unlink()
            path.write_text((LIBRARY / f"{base}.toml").read_text())
            t0 = time.perf_counter()
            try:
                p = subprocess.run([sys.executable, "-m", "sim", "simulate", str(path), "--speed", w, "--json"], env=env,
                                   capture_output=True, text=True, timeout=seconds, cwd=folder)
                rc, o, e = p.returncode, p.stdout, p.stderr
            except subprocess.TimeoutExpired:
                rc, o, e = None, "", ""
            cls, detail = _judge("simulate --json", rc, o, e, path, [])
            if detail.startswith(("names no file", "names no field")) or cls == "refused":
                line = detail.split(": ", 1)[-1] if cls != "refused" else detail
                cls, detail = ("refused", line) if "--speed" in line else ("MISHANDLED", "names no option: " + line)
            out.append((base, f"--speed {w}", [("simulate --speed --json", cls, detail, time.perf_counter() - t0)]))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--cases", type=int, default=150, help="file cases (default 150; 16 --speed cases besides)")
    ap.add_argument("--seconds", type=float, default=60.0, help="the longest a command may run")
    ap.add_argument("--plot-every", type=int, default=6, help="plot every N-th accepted case")
    ap.add_argument("-v", "--verbose", action="store_true", help="print every case, not only the mishandled")
    args = ap.parse_args(argv)
    rng = random.Random(args.seed)
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""),
           "MUJOCO_GL": os.environ.get("MUJOCO_GL", "egl")}
    folder = Path(tempfile.mkdtemp(prefix="fuzz-cams-"))
    t_all = time.perf_counter()
    counts, per_cmd, groups = Counter(), Counter(), defaultdict(list)
    state, slowest = {"accepted": 0, "plot_every": max(args.plot_every, 1)}, (0.0, "")
    for k, (base, label, edits) in enumerate(plan(rng, args.cases)):
        cls, results, plot = run_case(folder, base, label, edits, args.seconds, state, env)
        counts[cls] += 1
        for cmd, c, detail, dt in results:
            per_cmd[(cmd, c)] += 1
            slowest = max(slowest, (dt, f"{cmd} {base}: {label}"))
            if c == "MISHANDLED":
                sig = re.sub(r"[-+]?\d[\d.e+-]*", "#", detail.split(":")[0] + ":" + detail.split(":")[-1])[:90]
                groups[sig].append(f"{base}: {label} [{cmd}] {detail}")
        if args.verbose or cls == "MISHANDLED":
            worst = next((r for r in results if r[1] == "MISHANDLED"), results[0])
            print(f"{k:4d} {cls:<10s} {base}: {label}{' (plotted)' if plot else ''} | {worst[0]}: {worst[2][:160]}",
                  flush=True)
    for base, label, results in speed_cases(folder, args.seconds, env):
        cls = results[0][1]
        counts[cls if cls != "ok" else "accepted"] += 1
        per_cmd[(results[0][0], cls)] += 1
        if cls == "MISHANDLED":
            groups[results[0][2][:60]].append(f"{base}: {label} {results[0][2]}")
        if args.verbose or cls == "MISHANDLED":
            print(f"     {cls:<10s} {base}: {label} | {results[0][2][:160]}", flush=True)
    shutil.rmtree(folder, ignore_errors=True)
    total = sum(counts.values())
    print(f"\n{total} cases (seed {args.seed}, {args.cases} files + 16 --speed) in {time.perf_counter() - t_all:.0f} s: "
          f"{counts['accepted']} accepted and ran, {counts['accepted, later refused']} accepted by check and refused "
          f"properly by a later command, {counts['refused']} refused properly, "
          f"{counts['MISHANDLED']} MISHANDLED; slowest command {slowest[0]:.1f} s ({slowest[1]})")
    print("per command: " + ", ".join(f"{c} {k}={v}" for (c, k), v in sorted(per_cmd.items())))
    for sig, items in sorted(groups.items(), key=lambda kv: -len(kv[1])):
        print(f"\nMISHANDLED x{len(items)}: {sig}\n  e.g. {items[0][:300]}")
    return 1 if counts["MISHANDLED"] else 0


if __name__ == "__main__":
    raise SystemExit(main())
