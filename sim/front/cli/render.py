"""``linkage render MECH --out PATH``: the simulation rendered offscreen to MP4 or GIF."""

from __future__ import annotations



from sim import service
from sim.output.units import add_unit_options
from sim.front.cli.options import (add_common, add_sim_options, add_video_options, check_outputs, loads_from,
                                   mechanism_from, parse_range, say_start, settings_from)


def register(sub) -> None:
    p = sub.add_parser("render", help="render the simulation offscreen to MP4 or GIF")
    add_common(p)
    add_sim_options(p)
    add_video_options(p)
    p.add_argument("--forces", action="store_true",
                   help="draw MuJoCo's joint forces as arrows (the first link's force on the second; scale in "
                        "the legend)")
    add_unit_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from sim.output.render import check_video_args, render
    path, size = check_video_args(args.out, args.fps, args.size)
    check_outputs(args, {})
    mech = mechanism_from(args)
    built, tr = service.simulate(mech, args.revolutions, settings_from(args), loads_from(args, mech),
                                 parse_range(mech, args.input_range))
    from sim.output.units import shown_units
    say_start(mech, built.mech)
    stats = render(built, tr, str(path), args.fps, size, display=shown_units(args, built.mech),
                   forces=args.forces)
    print(f"wrote {stats.path}: {stats.frames} frames {size[0]}x{size[1]} at {stats.stored_fps:g} fps "
          f"({stats.fps:.1f} frames/s rendered)")
    return 0
