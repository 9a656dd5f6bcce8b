"""Options every ``linkage synthesize`` type shares (SPEC, "Synthesis constraints and budgets"): the length
unit of its inputs and files (``--units``, ``--unit`` kept as an alias) and the limits every returned design
meets (``--min-transmission``, ``--max-size``, ``--pivot-region``, ``--grashof``)."""

from __future__ import annotations

from pathlib import Path

from sim.front.cli.options import degrees
from sim.service.design import GRASHOF, UNITS


def add_units(p, help_text: str) -> None:
    """``--units`` (and its alias ``--unit``): the length unit of the inputs and of the files written."""
    p.add_argument("--units", "--unit", dest="unit", choices=sorted(UNITS), default="m", help=help_text)


def add_limits(p, pivots: str, min_transmission: float | None = 30.0) -> None:
    """The limits every returned design meets; ``pivots`` names the ground pivots a region may name;
    ``min_transmission`` the default least transmission angle [deg] (None: no limit unless given)."""
    p.add_argument("--min-transmission", metavar="DEG", type=degrees, default=min_transmission,
                   help="least transmission angle over the working range [deg; 30 or 30deg] (default "
                        + (f"{min_transmission:g})" if min_transmission is not None else "none)"))
    p.add_argument("--max-size", metavar="L", type=float, default=None,
                   help="largest side of the mechanism's bounding box over its working range (file units)")
    p.add_argument("--pivot-region", metavar="NAME=x0:x1,y0:y1", action="append", default=[],
                   help=f"a box the ground pivot NAME must lie in (file units; repeatable; pivots: {pivots})")
    p.add_argument("--grashof", choices=GRASHOF, default="any",
                   help="the four-bar type wanted: crank-rocker (the crank turns fully), double-crank, any")


def limits_of(args):
    """The command line's :class:`analytic.synthesis.constraints.Limits` (bad values: ParameterError); None
    where no limit is given and none is the default (two-position: seed 001's own problem)."""
    if args.min_transmission is None and args.max_size is None and not args.pivot_region and args.grashof == "any":
        return None
    from sim.service.design import limits
    return limits(args.min_transmission, args.max_size, args.pivot_region, args.grashof, "--min-transmission")


def measure_words(d: dict, unit: str) -> str:
    """The measures one design prints: transmission range, size, working input range, Grashof type."""
    import math
    lo, hi = d["transmission_deg"]
    a, b = (math.degrees(v) for v in d["input_range"])
    g = f"; {d['grashof']}" if d.get("grashof") else ""
    return (f"transmission {lo:.1f}-{hi:.1f} deg, size {d['size']:.4g} {unit}, input range "
            f"{a:.2f}deg:{b:.2f}deg{g}")


def out_names(out: str | None, k: int) -> list[str | None]:
    """FILE.toml for the best design, FILE_2.toml ... for the next ones."""
    if not out:
        return [None] * k
    p = Path(out)
    return [out] + [str(p.with_name(f"{p.stem}_{i}{p.suffix}")) for i in range(2, k + 1)]
