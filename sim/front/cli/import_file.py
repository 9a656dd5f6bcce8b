"""`linkage import SOURCE --out FILE.toml`: a Pyslvs project or expression, or a PMKS text file, written as a
``linkage/1`` file in the links-and-joints form (SPEC, "linkages as users draw them")."""

from __future__ import annotations

from analytic import ParameterError
from sim.service import importing


def parse_input(text: str) -> tuple[int, int]:
    """``BASE,DRIVER``: a Pyslvs input pair of joint numbers."""
    parts = text.split(",")
    try:
        base, driver = (int(x) for x in parts)
    except ValueError:
        raise ParameterError(f"--input {text!r} is not BASE,DRIVER (two joint numbers, e.g. --input 0,1)") from None
    if base < 0 or driver < 0:
        raise ParameterError(f"--input {text!r}: joint numbers start at 0")
    return base, driver


def register(sub) -> None:
    p = sub.add_parser("import", help="write a Pyslvs project or expression, or a PMKS file, as a linkage/1 file")
    p.add_argument("mechanism", metavar="SOURCE",
                   help="a Pyslvs-UI project (.pyslvs), a text file holding a Pyslvs expression M[...], or a PMKS "
                        "text file")
    p.add_argument("--out", required=True, metavar="FILE.toml", help="the linkage/1 file to write")
    p.add_argument("--input", dest="inputs", action="append", default=[], metavar="BASE,DRIVER",
                   help="a Pyslvs input (repeatable): turn the link joints BASE and DRIVER share about BASE "
                        "(BASE,BASE: drive the slider at BASE); replaces a project's inputs")
    p.add_argument("--units", default=importing.DEFAULT_UNITS, choices=importing.UNITS,
                   help=f"the length unit of the source's numbers (default {importing.DEFAULT_UNITS}: neither "
                        f"format stores one)")
    p.set_defaults(func=cmd_import)


def cmd_import(args) -> int:
    from sim.front.cli.options import check_outputs
    from sim.output.io import write_text
    source = args.mechanism
    check_outputs(args, {"out": (".toml",)})
    kind = importing.detect(source)
    if kind is None:
        raise ParameterError(f"{source}: not a Pyslvs project (.pyslvs), a Pyslvs expression (M[...]) or a PMKS text "
                             f"file (joint lines such as 'ground,input,R,0,0')")
    inputs = [parse_input(t) for t in args.inputs] or None
    imported = importing.convert(source, inputs, args.units, kind, args.out)   # a mechanism, read back as one
    data, groups = imported.data, imported.groups
    write_text(args.out, imported.text)
    points = len(data["pose"])
    print(f"wrote {args.out}: {kind} {source} as {points} points, {len(data['links'])} link entries, "
          f"{len(data['joints'])} joints; units {args.units}")
    print("  " + "; ".join(groups))
    if data.get("input_range"):
        print(f"  input_range = {data['input_range']}: the range the source drives it through, which every command "
              f"rocks over (a run over a turn is refused: {imported.why})")
    return 0
