"""Subcommands that run MuJoCo: simulate, compare, render, plot, run."""

from __future__ import annotations

import math

from analytic import ParameterError, fourbar
from . import params
from .io import check_writable, write_csv


def add_sim_options(p) -> None:
    from .model import DEFAULT_INTEGRATOR, DEFAULT_TIMESTEP, INTEGRATORS
    p.add_argument("--timestep", type=float, default=DEFAULT_TIMESTEP, metavar="H",
                   help=f"physics timestep [s] (default {DEFAULT_TIMESTEP:g})")
    p.add_argument("--integrator", default=DEFAULT_INTEGRATOR, choices=sorted(INTEGRATORS),
                   help=f"MuJoCo integrator (default {DEFAULT_INTEGRATOR})")


def check_full_turn(mech) -> None:
    """A four-bar crank that cannot turn fully is refused before simulating, with its limit angles."""
    if params.mechanism_name(mech) == "fourbar":
        lim = fourbar.crank_limits(mech)
        if not lim.full_turn:
            ends = ", ".join(f"{math.degrees(a):.2f}deg" for a in lim.limit_angles)
            raise ParameterError(
                f"the crank l1={mech.l1:g} cannot turn fully (limit angles {ends}; reachable "
                f"{fourbar.describe_range(lim)}): a velocity-driven simulation would lock at a dead centre")


def run_simulation(mech, revolutions: float, timestep: float, integrator: str):
    """Build, check and simulate; returns the Trajectory."""
    from .model import build
    from .simulate import simulate
    check_full_turn(mech)
    params.duration(mech, revolutions)             # validates revolutions and the drive before building
    return simulate(build(mech, timestep, integrator), revolutions)


def trajectory_columns(tr) -> dict:
    """CSV columns of a trajectory: t, drive inputs, SPEC outputs, loop violation, actuator forces."""
    return {"t": tr.t, **tr.inputs, **tr.outputs, "loop_violation": tr.loop_violation, **tr.forces}


def cmd_simulate(args) -> int:
    mech = params.build(args.mechanism, args.sets)
    if args.csv:
        check_writable(args.csv, (".csv",))
    tr = run_simulation(mech, args.revolutions, args.timestep, args.integrator)
    if args.csv:
        write_csv(args.csv, trajectory_columns(tr))
    print(f"{tr.name}: {tr.steps} steps of {tr.timestep:g} s ({tr.integrator}), {tr.cpu_seconds * 1e3:.1f} ms CPU; "
          f"max loop violation {tr.loop_violation.max():.3e} m")
    if args.csv:
        print(f"wrote {args.csv} ({len(tr.t)} rows)")
    return 0


def cmd_compare(args) -> int:
    from .cli import dumps
    from .compare import compare, table
    mech = params.build(args.mechanism, args.sets)
    tr = run_simulation(mech, args.revolutions, args.timestep, args.integrator)
    c = compare(tr, mech)
    if args.json:
        out = c.as_dict()
        out["revolutions"] = args.revolutions
        print(dumps(out))
    else:
        print(table(c))
    return 0 if c.passed else 1


def register(sub, add_common) -> None:
    p = sub.add_parser("simulate", help="simulate in MuJoCo and record the trajectory")
    add_common(p)
    add_sim_options(p)
    p.add_argument("--csv", metavar="PATH", help="write every step as CSV")
    p.set_defaults(func=cmd_simulate)

    p = sub.add_parser("compare", help="simulate and cross-validate against the analytic solution")
    add_common(p)
    add_sim_options(p)
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=cmd_compare)
