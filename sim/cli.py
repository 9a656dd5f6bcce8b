"""The ``linkage`` command (also ``python -m sim``).

Every user error ends in one line on stderr and exit code 2, never a traceback.
"""

from __future__ import annotations

import argparse
import json
import math
import sys

import numpy as np

from analytic import MECHANISMS, ParameterError
from . import params
from .figures import figures
from .io import check_writable, write_csv

MECHS = tuple(MECHANISMS)


class _Parser(argparse.ArgumentParser):
    def error(self, message):            # argparse's own errors: one line, exit 2
        self.exit(2, f"linkage: error: {message}\n")


def _add_common(p: argparse.ArgumentParser, revolutions: float = 1.0) -> None:
    p.add_argument("mechanism", choices=MECHS, help="which mechanism")
    p.add_argument("--set", dest="sets", action="append", default=[], metavar="NAME=VALUE",
                   help="override a SPEC parameter (repeatable); a value may end in deg")
    p.add_argument("--revolutions", type=float, default=revolutions, metavar="R",
                   help=f"revolutions of the first crank (default {revolutions:g})")


def _range(text: str) -> tuple[float, float]:
    if ":" not in text:
        raise ParameterError(f"--input-range {text!r} is not LO:HI (e.g. -40deg:40deg)")
    lo, hi = text.split(":", 1)
    return params.parse_value("--input-range", lo), params.parse_value("--input-range", hi)


def _json_default(x):
    if isinstance(x, np.generic):
        return x.item()
    raise TypeError(type(x))


def dumps(obj) -> str:
    """JSON with non-finite floats written as null (JSON has no NaN)."""
    def clean(v):
        if isinstance(v, float) and not math.isfinite(v):
            return None
        if isinstance(v, dict):
            return {k: clean(x) for k, x in v.items()}
        if isinstance(v, (list, tuple)):
            return [clean(x) for x in v]
        return v
    return json.dumps(clean(obj), indent=2, default=_json_default)


# ----------------------------------------------------------------------------------------- analyze
def cmd_analyze(args) -> int:
    mech = params.build(args.mechanism, args.sets)
    if args.csv:
        check_writable(args.csv, (".csv",))
    inputs = params.sample_inputs(mech, args.samples, args.revolutions,
                                  _range(args.input_range) if args.input_range else None)
    state = params.solve(mech, inputs)
    outputs = MECHANISMS[args.mechanism].OUTPUTS
    if args.csv:
        write_csv(args.csv, {"t": inputs.t, **inputs.columns,
                             **{k: getattr(state, k) for k in outputs}})
    fig = figures(mech, state)
    if args.json:
        print(dumps({"mechanism": args.mechanism, "parameters": _params(mech),
                     "samples": args.samples, "revolutions": args.revolutions,
                     "figures": fig,
                     "ranges": {k: [float(np.nanmin(getattr(state, k))), float(np.nanmax(getattr(state, k)))]
                                for k in outputs},
                     **({"csv": args.csv} if args.csv else {})}))
    else:
        print(summary(args.mechanism, mech, state, fig))
        if args.csv:
            print(f"wrote {args.csv} ({args.samples} rows)")
    return 0


def _params(mech) -> dict:
    import dataclasses
    return {f.name: getattr(mech, f.name) for f in dataclasses.fields(mech)}


def summary(name: str, mech, state, fig: dict) -> str:
    """A short readable summary of one analysis."""
    deg = math.degrees
    p = ", ".join(f"{k}={v:g}" for k, v in _params(mech).items())
    lines = [f"{name}: {p}"]
    if name == "fourbar":
        lines.append(f"  Grashof: {fig['grashof']}, {fig['inversion']}; crank turns fully: "
                     f"{'yes' if fig['crank_turns_fully'] else 'no'}")
        if fig["limit_angles"]:
            lines.append("  limit angles: " + ", ".join(f"{deg(a):.3f} deg" for a in fig["limit_angles"]))
        lo, hi = fig["mu_extremes"]
        lines.append(f"  transmission angle mu: {deg(fig['mu_min']):.3f} .. {deg(fig['mu_max']):.3f} deg over the "
                     f"samples; {deg(lo):.3f} .. {deg(hi):.3f} deg over every crank angle")
        lines.append(f"  rocker swing: {deg(fig['phi3_swing']):.3f} deg;  |vE| max {fig['vE_max']:.6g} m/s")
        lines.append(f"  E path: x {fig['xE_range'][0]:.6g} .. {fig['xE_range'][1]:.6g} m, "
                     f"y {fig['yE_range'][0]:.6g} .. {fig['yE_range'][1]:.6g} m")
    elif name == "sixbar":
        lines.append(f"  ram line h = {fig['h']:.6g} m; stroke H = {fig['stroke']:.6g} m")
        lines.append(f"  guide swing theta = {deg(fig['swing']):.3f} deg; quick-return ratio K = {fig['K']:.4f}")
        lines.append(f"  ram velocity {fig['vxC_range'][0]:.6g} .. {fig['vxC_range'][1]:.6g} m/s; "
                     f"acceleration {fig['axC_range'][0]:.6g} .. {fig['axC_range'][1]:.6g} m/s^2")
    else:
        lines.append(f"  speed ratio i = omega2/omega4 = {fig['speed_ratio']:.6g}")
        lines.append(f"  S: {fig['S_range'][0]:.6g} .. {fig['S_range'][1]:.6g} m (never below "
                     f"{fig['S_min_possible']:.6g} m)")
        lines.append(f"  |vP|: min {fig['vP_min']:.6g}, mean {fig['vP_mean']:.6g}, max {fig['vP_max']:.6g} m/s")
    return "\n".join(lines)


# ------------------------------------------------------------------------------------------ parser
def make_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="linkage", description="Planar linkage kinematics, MuJoCo simulation and rendering.")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    p = sub.add_parser("analyze", help="closed-form kinematics over a run; summary, CSV or JSON")
    _add_common(p)
    p.add_argument("--samples", type=int, default=361, metavar="N", help="samples (default 361)")
    p.add_argument("--input-range", metavar="LO:HI",
                   help="four-bar: sample the crank angle between LO and HI instead (e.g. between its limits)")
    p.add_argument("--csv", metavar="PATH", help="write every sample as CSV")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=cmd_analyze)

    from . import commands, design  # simulation, rendering, the main job; synthesis and sweeps
    commands.register(sub, _add_common)
    design.register(sub, _add_common)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = make_parser()
    args = parser.parse_args(argv)
    try:
        return args.func(args)
    except ParameterError as exc:
        print(f"linkage: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("linkage: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
