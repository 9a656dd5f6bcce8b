"""``linkage synthesize motion POSES.csv`` (Burmester) and ``linkage synthesize function PAIRS.csv``
(Freudenstein): exact synthesis of a four-bar, every returned design simulated by ``linkage compare``."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from analytic import ParameterError
from analytic.synthesis import fourbar as synth_fourbar
from analytic.synthesis import function as synthesis_function
from analytic.synthesis import motion as synthesis_motion
from analytic.format.linkfile import UNITS
from sim import service
from sim.output.io import check_writable, write_text
from sim.output.jsonout import dumps

MIN_ROWS = {"motion": 3, "function": 3}


def read_table(path: str, columns: tuple[str, ...], angle_columns: tuple[str, ...], degrees: bool,
               minimum: int) -> tuple[np.ndarray, list[int]]:
    """Rows of the named ``columns`` of a CSV with a header row, angles converted to rad; one-line
    ParameterError naming the file, line and column of anything wrong."""
    p = Path(path)
    if not p.is_file():
        raise ParameterError(f"{path}: no such file")
    try:
        lines = p.read_text().splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise ParameterError(f"{path}: cannot read it ({exc})") from None
    rows = [r for r in csv.reader(lines)]
    numbered = [(i + 1, r) for i, r in enumerate(rows) if any(c.strip() for c in r)]
    if not numbered:
        raise ParameterError(f"{path}: empty; give a header row {','.join(columns)} and one row per target")
    head_line, head = numbered[0]
    names = [h.strip().lower() for h in head]
    for c in columns:
        if c not in names:
            raise ParameterError(f"{path}: line {head_line}: missing column {c!r} (header: {','.join(names)}); "
                                 f"the header must name {','.join(columns)}")
    idx = [names.index(c) for c in columns]
    out = []
    for line, r in numbered[1:]:
        vals = []
        for c, j in zip(columns, idx):
            text = r[j].strip() if j < len(r) else ""
            try:
                v = float(text)
            except ValueError:
                raise ParameterError(f"{path}: line {line}, column {c}: {text!r} is not a number") from None
            if not math.isfinite(v):
                raise ParameterError(f"{path}: line {line}, column {c}: {text!r} is not a finite number")
            vals.append(math.radians(v) if (degrees and c in angle_columns) else v)
        out.append((line, vals))
    if len(out) < minimum:
        raise ParameterError(f"{path}: {len(out)} row(s); this method needs at least {minimum}")
    return np.array([v for _, v in out]), [line for line, _ in out]


def _repeats(path, data, lines, key, what) -> None:
    """Refuse two rows that give the same target (to 1e-9 of the data's spread)."""
    k = key(data)
    scale = max(float(np.ptp(k, axis=0).max()), 1e-12)
    for i in range(len(k)):
        for j in range(i):
            if np.all(np.abs(k[i] - k[j]) <= 1e-9 * scale):
                raise ParameterError(f"{path}: lines {lines[j]} and {lines[i]} give the same {what}; remove one")


def _err(e) -> dict:
    e = np.abs(np.asarray(e, dtype=float))
    return {"sum_sq": float(np.sum(e ** 2)), "max": float(np.max(e)), "rms": float(np.sqrt(np.mean(e ** 2)))}


def _check(mech, link, inputs):
    """``linkage compare`` of a design: a full turn where the crank turns fully, else rocking over the
    travel from the first target to the last. Returns (passed, comparison record)."""
    q = np.linspace(0.0, 2 * math.pi, 721)
    full = mech.solve(q).first_failure() is None
    if full:
        built, c = service.compare(mech, 1.0)
    else:
        sense = math.copysign(1.0, link.omega1)
        travel = np.mod(sense * (np.asarray(inputs) - inputs[0]), 2 * math.pi)
        ends = (inputs[0], inputs[0] + sense * travel.max())
        built, c = service.compare(mech, 1.0, input_range=(min(ends), max(ends)))
    return bool(c.passed), ("full turn" if full else "rocking between the first and last target")


def _designs_out(args, kind: str, found: list[dict]) -> int:
    """Write the best design, print a table or JSON; exit 1 when none is free of defects and passes
    compare."""
    ok = [d for d in found if not d["defect"] and d["compare_passed"]]
    best = ok[0] if ok else (found[0] if found else None)
    if best is not None and args.out:
        write_text(args.out, best["text"])
        best["file"] = args.out
    if args.json:
        print(dumps({"designs": [{k: v for k, v in d.items() if k != "text"} for d in found]}))
    else:
        for n, d in enumerate(found, 1):
            e = d["error"]
            state = "ok" if not d["defect"] and d["compare_passed"] else (d["defect"] or "compare failed")
            print(f"{n}. error max {e['max']:.3e} rms {e['rms']:.3e} {d['error_unit']}; "
                  f"compare {'passed' if d['compare_passed'] else 'FAILED'} ({d['compare_mode']}); {state}")
            print("   " + ", ".join(f"{k}={v:.6g}" for k, v in d["parameters"].items()))
        if best is not None and args.out:
            print(f"wrote {args.out}")
    if not ok:
        why = (best["defect"] or "it fails linkage compare") if best else "no candidate"
        print(f"linkage: no {kind} design meets the constraints; the best found: {why}")
        return 1
    return 0


def cmd_motion(args) -> int:
    if args.out:
        check_writable(args.out, (".toml",))
    if args.count < 1:
        raise ParameterError(f"--count {args.count} must be >= 1")
    data, lines = read_table(args.poses, ("x", "y", "theta"), ("theta",), args.angles == "deg",
                             MIN_ROWS["motion"])
    _repeats(args.poses, data, lines, lambda d: np.column_stack([d[:, :2], np.mod(d[:, 2], 2 * math.pi)]),
             "pose")
    circle = None
    if args.circle_points:
        if len(data) != 3:
            raise ParameterError(f"--circle-points applies to 3 poses ({args.poses} has {len(data)})")
        parts = args.circle_points.split(",")
        try:
            circle = np.array([float(v) for v in parts]).reshape(2, 2)
        except ValueError:
            raise ParameterError(f"--circle-points {args.circle_points!r} is not X1,Y1,X2,Y2 (crank and "
                                 f"rocker circle points at pose 1, in --unit)") from None
        if not np.all(np.isfinite(circle)):
            raise ParameterError(f"--circle-points {args.circle_points!r}: give finite numbers")
    designs, _ = synthesis_motion.synthesize(data, circle_points=circle, count=args.count)
    method = ("Burmester, exact" if len(data) <= 5 else "Burmester dyads by least squares")
    found = []
    for d in designs:
        text = synth_fourbar.text(d.linkage, args.unit, "motion_fourbar",
                                  f"four-bar through {len(data)} coupler poses ({method}); output E = the pose point")
        mech = synth_fourbar.mechanism(d.linkage, args.unit)
        sol = mech.solve(d.inputs)                           # the general solver at the poses' input angles
        err = np.hypot(sol["xE"] / mech.scale - data[:, 0], sol["yE"] / mech.scale - data[:, 1])
        ang = synthesis_motion._wrap((sol["phi2"] - sol["phi2"][0]) - (data[:, 2] - data[0, 2]))
        passed, mode = _check(mech, d.linkage, d.inputs) if not d.defect else (False, "not run: " + d.defect)
        params = {**d.linkage.parameters(), "mu_min_deg": math.degrees(d.mu_min),
                  "angle_error_max": float(np.max(np.abs(ang)))}
        found.append({"file": None, "error": _err(err), "error_unit": args.unit, "parameters": params,
                      "compare_passed": passed, "compare_mode": mode, "defect": d.defect,
                      "inputs": [float(q) for q in d.inputs], "text": text})
    return _designs_out(args, "motion", found)


def cmd_function(args) -> int:
    if args.out:
        check_writable(args.out, (".toml",))
    data, lines = read_table(args.pairs, ("input", "output"), ("input", "output"), args.angles == "deg",
                             MIN_ROWS["function"])
    _repeats(args.pairs, data, lines, lambda d: np.mod(d[:, :1], 2 * math.pi), "input angle")
    if not (math.isfinite(args.ground) and args.ground > 0):
        raise ParameterError(f"--ground {args.ground!r} must be a length > 0")
    f = synthesis_function.synthesize(data[:, 0], data[:, 1], args.ground)
    text = synth_fourbar.text(f.linkage, args.unit, "function_fourbar",
                              f"Freudenstein function generator through {len(data)} (input, output) pairs; "
                              f"input offset {f.input_offset:g} rad, output offset {f.output_offset:g} rad")
    mech = synth_fourbar.mechanism(f.linkage, args.unit)
    sol = mech.solve(data[:, 0] + f.input_offset)            # the general solver at the given inputs
    err = synthesis_function._wrap(sol["phi3"] - f.output_offset - data[:, 1])
    passed, mode = _check(mech, f.linkage, data[:, 0] + f.input_offset) if not f.defect else (
        False, "not run: " + f.defect)
    params = {**f.linkage.parameters(), "K1": f.K[0], "K2": f.K[1], "K3": f.K[2],
              "input_offset": f.input_offset, "output_offset": f.output_offset}
    found = [{"file": None, "error": _err(err), "error_unit": "rad", "parameters": params,
              "compare_passed": passed, "compare_mode": mode, "defect": f.defect, "text": text}]
    return _designs_out(args, "function", found)


def register(problems, add_video_options) -> None:
    """``synthesize motion`` and ``synthesize function`` under ``linkage synthesize``."""
    units = sorted(UNITS)
    p = problems.add_parser("motion", help="four-bar through 3-5 coupler poses (Burmester), more by least squares")
    p.add_argument("poses", metavar="POSES.csv", help="CSV with columns x,y,theta (one pose per row, in order)")
    p.add_argument("--unit", choices=units, default="m", help="length unit of x, y and of the file written")
    p.add_argument("--angles", choices=("deg", "rad"), default="deg", help="unit of theta (default deg)")
    p.add_argument("--count", type=int, default=3, help="designs to return, best first (default 3)")
    p.add_argument("--circle-points", metavar="X1,Y1,X2,Y2",
                   help="3 poses: the moving pivots at pose 1 (the free parameters; default: a grid searched)")
    p.add_argument("--out", metavar="FILE.toml", help="write the best design as a linkage/1 file")
    p.add_argument("--json", action="store_true", help="print one JSON object (SPEC: designs)")
    p.set_defaults(func=cmd_motion)
    p = problems.add_parser("function", help="four-bar function generator through (input, output) pairs (Freudenstein)")
    p.add_argument("pairs", metavar="PAIRS.csv", help="CSV with columns input,output: crank and rocker angles "
                                                      "from the line A->D")
    p.add_argument("--unit", choices=units, default="m", help="length unit of the file written")
    p.add_argument("--angles", choices=("deg", "rad"), default="deg", help="unit of the angles (default deg)")
    p.add_argument("--ground", type=float, default=1.0, help="ground link |AD| in --unit (default 1)")
    p.add_argument("--out", metavar="FILE.toml", help="write the design as a linkage/1 file")
    p.add_argument("--json", action="store_true", help="print one JSON object (SPEC: designs)")
    p.set_defaults(func=cmd_function)
