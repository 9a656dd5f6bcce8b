"""``linkage export MECH``: the generated MuJoCo model (MJCF) and/or the mechanism file."""

from __future__ import annotations

import argparse
import sys


from analytic import ParameterError
from sim import service
from sim.front.cli.options import (add_common, check_outputs, mechanism_from, settings_from)


def register(sub) -> None:
    p = sub.add_parser("export", help="write the generated MuJoCo model (MJCF) and/or the mechanism file")
    add_common(p)
    p.add_argument("--mjcf", metavar="PATH.xml", help="the MuJoCo model, its home keyframe closing every loop")
    p.add_argument("--toml", metavar="PATH.toml", help="the mechanism file with the current parameter values")
    p.add_argument("--timestep", type=float, default=None, metavar="H", help="time step written into the model")
    p.add_argument("--integrator", default="rk4", help=argparse.SUPPRESS)
    p.add_argument("--balance", nargs="?", const="", default=None, metavar="LINK,LINK",
                   help="add counterweights that balance the shaking force ([mass.counterweights]; see forces)")
    from sim.front.cli import parts
    parts.add_export_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from sim.output.io import write_text
    from sim.front.cli import parts
    if not (args.mjcf or args.toml or parts.wanted(args)):
        raise ParameterError("give --mjcf PATH (the MuJoCo model), --toml PATH (the mechanism file) and/or parts: "
                             "--dxf, --svg, --pdf, --step, --stl DIR, --bom")
    check_outputs(args, {"mjcf": (".xml",), "toml": (".toml",)})
    parts.check_paths(args)
    mech = mechanism_from(args)
    text = None
    if args.balance is not None:                   # counterweights written into the model (issue 17)
        from sim.front.cli.forces import balance_links
        from sim.service.export import balanced_text
        user, (mech, _) = mech, service.balanced_mechanism(mech, balance_links(args.balance))
        text = balanced_text(user, mech) if args.toml else None   # the user's text with them added (issue 41)
    if args.mjcf:
        write_text(args.mjcf, service.export_mjcf(mech, settings_from(args), getattr(args, "revolutions", 1.0)))
        print(f"wrote {args.mjcf}")
        from sim.service.export import loads_left_out
        left = loads_left_out(mech)
        if left:                                   # the file says so too (custom text, header comment)
            print(f"note: {args.mjcf} leaves out the loads MJCF cannot hold (simulate/compare apply them each "
                  f"step): {'; '.join(left)}", file=sys.stderr)
    if args.toml:
        write_text(args.toml, text if text is not None else service.mechanism_text(mech))
        print(f"wrote {args.toml}")
    if parts.wanted(args):                         # link solids, drawings, bill of materials (issue 28)
        parts.export(args, mech)
    return 0
