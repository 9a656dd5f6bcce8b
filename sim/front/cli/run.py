"""``linkage run [MECH ...]``: the main job: simulate, cross-validate, render, plot and save."""

from __future__ import annotations

import contextlib
import os
import sys


import analytic
from analytic import ParameterError
from sim import service
from sim.output.units import add_unit_options
from sim.front.cli.options import (add_sim_options, add_video_options, loads_from,
                                   parse_range, say_start, sets_of, settings_from, write_columns)


def register(sub) -> None:
    p = sub.add_parser("run", help="the main job: simulate, cross-validate, render, plot and save")
    p.add_argument("mechanisms", nargs="*", metavar="MECH", help="mechanisms (default: the three built-ins)")
    p.add_argument("--set", dest="sets", action="append", default=[], metavar="NAME=VALUE",
                   help="override a parameter (only with a single mechanism)")
    p.add_argument("--revolutions", type=float, default=1.0, metavar="R", help="revolutions (default 1)")
    p.add_argument("--out-dir", default="renders", metavar="DIR", help="output folder (default renders/)")
    p.add_argument("--format", choices=("mp4", "gif"), default="mp4", help="video format (default mp4)")
    p.add_argument("--no-video", action="store_true", help="skip the animations")
    add_sim_options(p)
    add_video_options(p, out_required=False)
    add_unit_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    """The main job: simulate, cross-validate, render, plot and write CSV for each mechanism."""
    from pathlib import Path
    from sim.output.render import check_video_args, parse_size
    names = args.mechanisms or list(analytic.BUILTINS)
    if len(set(names)) != len(names):
        raise ParameterError("a mechanism is named twice; name each once")
    if (args.sets or args.inertia or args.cutting_force is not None or args.input_range) and len(names) != 1:
        raise ParameterError("--set, --inertia, --cutting-force and --input-range apply to one mechanism at a time: "
                             "name it (e.g. linkage run fourbar --set l1=0.12)")
    out_dir = Path(args.out_dir)
    if out_dir.exists() and not out_dir.is_dir():
        raise ParameterError(f"--out-dir {out_dir} is a file, not a folder; choose a folder")
    mechs = []
    for name in names:
        mech = service.load(name, sets_of(args.sets))
        mechs.append((mech, service.prepare(mech, args.revolutions, parse_range(mech, args.input_range))))
    ext = "." + args.format
    _guard_tables(mechs, out_dir, ext)
    size = parse_size(args.size)
    created = not out_dir.exists()
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ParameterError(f"--out-dir {out_dir}: cannot create it ({exc.strerror or exc})") from None
    if not os.access(out_dir, os.W_OK):
        raise ParameterError(f"--out-dir {out_dir} is not writable; choose another folder")
    if not args.no_video:
        check_video_args(str(out_dir / f"{mechs[0][0].name}{ext}"), args.fps, args.size)
    code = None
    try:
        code = _run_all(args, mechs, out_dir, ext, size)
        return code
    finally:
        if code != 0 and created:                  # a folder this run made, left empty: removed too
            with contextlib.suppress(OSError):
                out_dir.rmdir()


def _guard_tables(mechs, out_dir, ext) -> None:
    """No file this run writes is a load table one of its mechanisms reads."""
    from sim.service.loads import table_files
    tables = {os.path.realpath(p) for mech, _ in mechs for p in table_files(mech)}
    for mech, _ in mechs:
        for x in (".csv", ".csv.units.json", ".png", ext):
            out = out_dir / f"{mech.name}{x}"
            if os.path.realpath(out) in tables:
                raise ParameterError(f"--out-dir {out_dir}: {out} is a load table this run reads and would be "
                                     f"overwritten; choose another folder")


def _run_all(args, mechs, out_dir, ext, size) -> int:
    """``linkage run`` after its checks: compare every mechanism, then write every file."""
    import time
    from pathlib import Path
    from sim.output.io import new_files_removed_on_failure
    from sim.output.plot import sheet
    from sim.output.render import render
    from sim.service.simulation import comparison_table
    t_start = time.perf_counter()
    from sim.output.units import machine_units, shown_units
    compared = []                                  # every comparison first: a failure writes nothing
    for k, (mech, _) in enumerate(mechs):
        if len(mechs) > 1 and sys.stderr.isatty():
            sys.stderr.write(f"[{k + 1}/{len(mechs)}] {mech.name}\n")
        built, c = service.compare(mech, args.revolutions, settings_from(args), loads_from(args, mech),
                                   parse_range(mech, args.input_range))
        say_start(mech, built.mech)
        print(comparison_table(c, mech.size, shown_units(args, mech), mech.output_point))
        print()
        compared.append((mech, built, c))
    failed = [(mech, c) for mech, _, c in compared if not c.passed]
    if failed:                                     # a failed verdict writes no file (exit 1)
        return _say_failed(args, compared, failed, out_dir, ext, t_start)
    results = []
    with new_files_removed_on_failure() as made:   # then the files; cut short, none of the new ones stays
        for mech, built, c in compared:
            shown = shown_units(args, mech)
            files = [out_dir / f"{mech.name}.csv", out_dir / f"{mech.name}.png"]
            made(files[0], Path(f"{files[0]}.units.json"), files[1])
            write_columns(files[0], mech, service.trajectory_columns(c.trajectory, mech), machine_units(args))
            sheet(c, built, str(files[1]), shown)
            if not args.no_video:
                files.append(made(out_dir / f"{mech.name}{ext}"))
                render(built, c.trajectory, str(files[-1]), args.fps, size, display=shown)
            results.append((mech, c, files))
    _summary(args, results, t_start)
    return 0 if all(c.passed for _, c, _ in results) else 1


def _summary(args, results, t_start) -> None:
    import time
    from sim.service.simulation import errors_in
    from sim.output.units import shown_units
    print(f"summary ({time.perf_counter() - t_start:.1f} s):")
    for mech, c, files in results:
        u = shown_units(args, mech)
        worst = max(c.errors, key=lambda k: c.errors[k]["max"] / c.errors[k]["tol"])
        e = errors_in({worst: c.errors[worst]}, u)[worst]
        print(f"  {mech.name:<8s} {'PASSED' if c.passed else 'FAILED'}  worst {worst}: {e['max']:.2e} {e['unit']} "
              f"(tol {e['tol']:.1e}); loop {u.convert('length', c.max_loop_violation):.1e} {u.unit('length')}; "
              f"drive {c.drive_error:.1e}")
        for f in files:
            print(f"           {f}")


def _say_failed(args, compared, failed, out_dir, ext, t_start) -> int:
    """A run with a failed comparison: its verdicts, and one line on stderr: no file written, which failed,
    and the fix (a --timestep coarser than the design needs: drop it)."""
    from sim.front.cli.options import say_not_written, timestep_advice
    _summary(args, [(mech, c, []) for mech, _, c in compared], t_start)
    names = [out_dir / f"{mech.name}{x}" for mech, _, _ in compared
             for x in (".csv", ".png") + (() if args.no_video else (ext,))]
    advice = next((a for a in (timestep_advice(args, mech, args.revolutions) for mech, _ in failed) if a), None)
    say_not_written(names, f"{', '.join(m.name for m, _ in failed)} FAILED the comparison: a failed run writes no "
                           f"files", advice)
    return 1
