"""``linkage synthesize motion POSES.csv`` (Burmester) and ``linkage synthesize function PAIRS.csv``
(Freudenstein): exact synthesis of a four-bar, every returned design simulated by ``linkage compare``."""

from __future__ import annotations

import math
import lazy_loader

from analytic import ParameterError
from sim.output.io import check_writable, write_text
from sim.front.cli.synth_options import add_limits, add_units, limits_of, measure_words, out_names
from sim.output.jsonout import dumps

# loaded by the command, not by its options (suppress_warning: the parent, sim.service, is light and loaded)
design_service = lazy_loader.load("sim.service.design", suppress_warning=True)  # scipy's optimisers


def _designs_out(args, kind: str, found: list[dict], rejected: list[dict]) -> int:
    """Write the best design, print a table or JSON (SPEC: ``designs``, each with its measures; ``rejected``:
    the candidates turned down and why); exit 1 when no design meets the limits and passes compare."""
    import sys
    ok = [d for d in found if d["compare_passed"] and d["simulated"]["passed"]]
    best = ok[0] if ok else None
    for d, name in zip(ok, out_names(args.out, len(ok))):   # every returned design: FILE, FILE_2, FILE_3 ...
        if name:
            write_text(name, d["text"])
            d["file"] = name
    if args.json:
        print(dumps({"designs": [{k: v for k, v in d.items() if k != "text"} for d in found],
                     "rejected": rejected}))
    else:
        for n, d in enumerate(found, 1):
            e = d["error"]
            print(f"{n}. error max {e['max']:.3e} rms {e['rms']:.3e} {d['error_unit']}; "
                  f"{measure_words(d, args.unit)}; compare {'passed' if d['compare_passed'] else 'FAILED'} "
                  f"({d['compare_mode']}), forces in MuJoCo "
                  f"{'passed' if d['simulated']['forces_passed'] else 'FAILED'}; "
                  f"{'ok' if d in ok else d['simulated']['problem']}")
            se = d.get("structural_error")
            if se:
                print(f"   structural error over the working range: max {se['max_deg']:.4g} deg at input "
                      f"{math.degrees(se['at_input']):.2f} deg, rms {se['rms_deg']:.4g} deg (the output against "
                      f"{se['target']}, the general solver at {se['samples']} crank angles)")
            print("   " + ", ".join(f"{k}={v:.6g}" for k, v in d["parameters"].items() if isinstance(v, (int, float))))
            for note in d["notes"]:
                print("   note: " + note)
            if d.get("file"):
                print(f"   wrote {d['file']} (its input_range is the working range: every command runs it so)")
    if best is None:
        why = rejected[0]["why"] if rejected else (found[0]["simulated"]["problem"] if found else "no candidate")
        for note in (rejected[0].get("notes", []) if rejected and not found else []):
            print("note: " + note, file=sys.stderr if args.json else sys.stdout)
        lead = "the best candidate: " if found or (rejected and rejected[0].get("parameters")) else ""
        print(f"linkage: no {kind} design meets the constraints; {lead}{why}",
              file=sys.stderr if args.json else sys.stdout)
        return 1
    return 0


def cmd_motion(args) -> int:
    if args.out:
        check_writable(args.out, (".toml",))
    if args.count < 1:
        raise ParameterError(f"--count {args.count} must be >= 1")
    poses = design_service.read_poses(args.poses, args.angles == "deg")
    limits = limits_of(args)
    why = design_service.unreachable(poses[:, :2], limits, args.unit, "poses")
    if why:                                 # limits no design can meet: say so, search nothing, write nothing
        return _designs_out(args, "motion", [], [{"parameters": {}, "why": why}])
    circle = None
    if args.circle_points:
        if len(poses) != 3:
            raise ParameterError(f"--circle-points applies to 3 poses ({args.poses} has {len(poses)})")
        try:
            circle = [float(v) for v in args.circle_points.split(",")]
            if len(circle) != 4:
                raise ValueError
        except ValueError:
            raise ParameterError(f"--circle-points {args.circle_points!r} is not X1,Y1,X2,Y2 (crank and "
                                 f"rocker circle points at pose 1, in --unit)") from None
    import linkage as lk
    s = lk.synthesize("motion", poses=poses, angles="rad", unit=args.unit, count=args.count, circle_points=circle,
                      evaluations=args.evaluations, **limit_keywords(args))
    return _designs_out(args, "motion", s.designs, s.rejected)


def cmd_function(args) -> int:
    if args.out:
        check_writable(args.out, (".toml",))
    pairs = design_service.read_pairs(args.pairs, args.angles == "deg")
    if args.start_angles == "given" and (args.evaluations is not None or args.count != 1):
        raise ParameterError("--evaluations and --count apply to --start-angles search (given start angles fix "
                             "the one design); add --start-angles search or drop them")
    import linkage as lk
    s = lk.synthesize("function", pairs=pairs, angles="rad", ground=args.ground, unit=args.unit,
                      start_angles=args.start_angles, evaluations=args.evaluations, count=args.count,
                      min_link=args.min_link, max_ratio=args.max_ratio, **limit_keywords(args))
    return _designs_out(args, "function", s.designs, s.rejected)


def limit_keywords(args) -> dict:
    """The limits' options as :func:`linkage.synthesize`'s keywords (``min_transmission`` 0: no limit)."""
    return {"min_transmission": 0.0 if args.min_transmission is None else args.min_transmission,
            "max_size": args.max_size, "pivot_region": args.pivot_region, "grashof": args.grashof}


def register(problems) -> None:
    """``synthesize motion`` and ``synthesize function`` under ``linkage synthesize``."""
    p = problems.add_parser("motion", help="four-bar through 3-5 coupler poses (Burmester), more by least squares")
    p.add_argument("poses", metavar="POSES.csv", help="CSV with columns x,y,theta (one pose per row, in order)")
    add_units(p, "length unit of x, y and of the file written")
    add_limits(p, "A (the crank's), D (the rocker's)")
    p.add_argument("--angles", choices=("deg", "rad"), default="deg", help="unit of theta (default deg)")
    p.add_argument("--count", type=int, default=3, help="designs to return, best first (default 3)")
    p.add_argument("--evaluations", type=int, default=design_service.MOTION_POOL, metavar="N",
                   help=f"candidate four-bars (pairs of dyads) ranked at most (default {design_service.MOTION_POOL}; "
                        f"deterministic)")
    p.add_argument("--circle-points", metavar="X1,Y1,X2,Y2",
                   help="3 poses: the moving pivots at pose 1 (the free parameters; default: a grid searched)")
    p.add_argument("--out", metavar="FILE.toml", help="write every returned design as a linkage/1 file: the best "
                                                      "to FILE.toml, the next ones to FILE_2.toml, FILE_3.toml ...")
    p.add_argument("--json", action="store_true", help="print one JSON object (SPEC: designs)")
    p.set_defaults(func=cmd_motion)
    p = problems.add_parser("function", help="four-bar function generator through (input, output) pairs (Freudenstein)")
    p.add_argument("pairs", metavar="PAIRS.csv", help="CSV with columns input,output: crank and rocker angles "
                                                      "from the line A->D")
    add_units(p, "length unit of --ground and of the file written")
    add_limits(p, "A (the crank's, at the origin), D (the rocker's, at (ground, 0))")
    p.add_argument("--angles", choices=("deg", "rad"), default="deg", help="unit of the angles (default deg)")
    p.add_argument("--ground", type=float, default=1.0, help="ground link |AD| in --unit (default 1)")
    p.add_argument("--min-link", metavar="L", type=float, default=None,
                   help="shortest link allowed, ground included (--unit; e.g. no link shorter than its own pin "
                        "hole; default none)")
    p.add_argument("--max-ratio", metavar="R", type=float, default=20.0,
                   help="longest/shortest link at most, ground included (default 20)")
    p.add_argument("--start-angles", choices=design_service.START_ANGLES, default="given",
                   help="given (default): the pairs' angles are from the line A->D and fix the design; search: "
                        "they are from any zero (only the function's increments matter) and the start angles of "
                        "input and output are searched for the least structural error over the working range")
    p.add_argument("--evaluations", type=int, default=None, metavar="N",
                   help="with --start-angles search: candidates evaluated at most, each one Freudenstein solve and "
                        "its structural error over the range (a grid of start angles, then the polish's share, "
                        f"reported as polish_evaluations; default {design_service.FUNCTION_EVALUATIONS}; "
                        "deterministic)")
    p.add_argument("--count", type=int, default=1,
                   help="with --start-angles search: distinct designs to return, best first (default 1)")
    p.add_argument("--out", metavar="FILE.toml", help="write every returned design as a linkage/1 file: the best "
                                                      "to FILE.toml, the next ones to FILE_2.toml, FILE_3.toml ...")
    p.add_argument("--json", action="store_true", help="print one JSON object (SPEC: designs)")
    p.set_defaults(func=cmd_function)
