"""The parts on the command line: layers in ``linkage check``, ``linkage check --interference [--json]`` and
``linkage export --dxf/--svg/--pdf/--step/--stl/--bom`` (SPEC "Parts, drawings and interference")."""

from __future__ import annotations

import os
from pathlib import Path

from analytic import ParameterError
from sim.output.io import check_writable

OUTPUTS = {"dxf": (".dxf",), "svg": (".svg",), "pdf": (".pdf",), "step": (".step", ".stp"), "bom": (".csv",)}


def add_check_options(p) -> None:
    p.add_argument("--interference", action="store_true",
                   help="sweep the link solids over the cycle in MuJoCo (contacts between links of one layer and the "
                        "[parts] frame) with a plane geometric cross-check; exit 1 if any collide")
    p.add_argument("--json", action="store_true", help="with --interference: print one JSON object")
    p.add_argument("--input-range", metavar="LO:HI", help="check over this range of the first input (e.g. -40deg:40deg)")


def add_export_options(p) -> None:
    p.add_argument("--dxf", metavar="PATH.dxf", help="the link outlines with holes, one DXF layer per link (file units)")
    p.add_argument("--svg", metavar="PATH.svg", help="a dimensioned drawing at the pose, with the exploded layers")
    p.add_argument("--pdf", metavar="PATH.pdf", help="the same drawing as PDF")
    p.add_argument("--step", metavar="PATH.step", help="one solid per link, placed at the pose in its layer")
    p.add_argument("--stl", metavar="DIR", help="one LINK.stl per link (file units) in DIR")
    p.add_argument("--bom", metavar="PATH.csv", help="bill of materials: link, layer, mass, dimensions, holes")


def wanted(args) -> bool:
    return any(getattr(args, k, None) for k in (*OUTPUTS, "stl"))


def _range(args, mech):
    from sim.front.cli.options import parse_range
    return parse_range(mech, getattr(args, "input_range", None))


def layer_lines(mech, args=None) -> list[str]:
    """``linkage check``'s lines about the parts; a design that cannot be made into parts (a hole wider
    than its bar) says so in a line: the structure check itself has passed."""
    from sim.service import parts as parts_service
    try:
        return parts_service.layer_lines(parts_service.prepare(mech, _range(args, mech) if args else None))
    except ParameterError as exc:
        if mech.definition.parts:                  # the file's own [parts] values: refused, as export refuses them
            raise
        return [f"  parts: none made: {exc}"]


def cmd_interference(args, mech) -> int:
    """``linkage check MECH --interference``: a summary (or ``--json``); exit 1 if any pair collides."""
    from sim.service import parts as parts_service
    pm = parts_service.prepare(mech, _range(args, mech))
    report = parts_service.interference(pm)
    if args.json:
        from sim.output.jsonout import dumps
        print(dumps(report))
    else:
        unit, q = report["input_unit"], report["input"]
        for line in parts_service.layer_lines(pm):
            print(line)
        if not report["min_clearance"]:
            print("  interference: no two links share a layer (nothing can collide)")
        for key, v in report["min_clearance"].items():
            print(f"  {key.replace('|', ' / ')}: min clearance {v:.6g} {report['units']}"
                  f" (plane test {report['min_clearance_geometric'][key]:.6g})")
        for item in report["interference"]:
            a, b = item["links"]
            geo = item["geometric"]
            print(f"  COLLISION {a} / {b}: first at {q} = {item['first_at']:.6f} {unit} (plane test "
                  f"{geo['first_at']:.6f}), depth {item['depth']:.4g} {report['units']}")
        if not report["interference"]:
            print("  no interference between the links over the cycle"
                  + (f" ({len(report['pin_clashes'])} pin clash(es) above)" if report["pin_clashes"] else ""))
    return 1 if report["interference"] else 0


def check_paths(args) -> None:
    """Every parts output writable with the right type and its library installed, before anything is
    written."""
    from sim.service.parts import check_extras
    check_extras(dxf=getattr(args, "dxf", None), step=getattr(args, "step", None), stl=getattr(args, "stl", None))
    for name, sfx in OUTPUTS.items():
        v = getattr(args, name, None)
        if v:
            check_writable(v, sfx)
    if getattr(args, "stl", None):
        folder = Path(args.stl)
        if folder.exists() and not folder.is_dir():
            raise ParameterError(f"--stl {folder}: not a folder; give a folder for the LINK.stl files")
        parent = folder.parent if str(folder.parent) else Path(".")
        if not parent.is_dir():
            raise ParameterError(f"--stl {folder}: folder {parent} does not exist; create it or choose another path")
    from sim.service.catalog import LIBRARY
    library = os.path.realpath(LIBRARY)
    for name in (*OUTPUTS, "stl"):
        v = getattr(args, name, None)
        if v and (os.path.dirname(os.path.realpath(v)) == library or os.path.realpath(v) == library):
            raise ParameterError(f"--{name} {v} is in the shipped mechanism library, which is never written; "
                                 f"choose an output outside {library}")
    mech = getattr(args, "mechanism", None)
    if isinstance(mech, str) and os.path.exists(mech):
        for name in OUTPUTS:
            v = getattr(args, name, None)
            if v and os.path.realpath(v) == os.path.realpath(mech):
                raise ParameterError(f"--{name} {v} is the mechanism file and would be overwritten; choose another name")


def export(args, mech) -> None:
    from sim.service import parts as parts_service
    pm = parts_service.prepare(mech)
    for path in parts_service.export(pm, dxf=args.dxf, svg=args.svg, pdf=args.pdf, step=args.step, stl=args.stl,
                                     bom=args.bom):
        print(f"wrote {path}")
