"""The command line's loads (SPEC "Loads"): ``--force FX,FY@POINT[:LINK]`` (a constant world-frame force [N]
at a named point, on the named link or the point's carrier), ``--torque T@LINK`` (a constant couple [N m],
+ counter-clockwise, repeatable) and ``--at VALUE`` (one pose). ``--force FX,FY`` without ``@`` keeps its
meaning (on the file's output point), read by :func:`sim.front.cli.loads_from`."""

from __future__ import annotations

from analytic import ParameterError
from sim.service.values import parse_value


def add_options(p) -> None:
    p.add_argument("--torque", action="append", default=[], metavar="T@LINK",
                   help="a constant couple T [N m] (+ counter-clockwise) on link LINK (repeatable)")


def add_at(p) -> None:
    p.add_argument("--at", metavar="VALUE",
                   help="one pose: the first input's angle (rad, or deg with a deg suffix) or a slider's position "
                        "(file units)")


def split_force(text: str | None) -> tuple[str | None, str | None, str | None]:
    """``FX,FY@POINT[:LINK]`` -> ("FX,FY", POINT, LINK or None); without ``@``: (text, None, None)."""
    if text is None or "@" not in text:
        return text, None, None
    value, where = text.split("@", 1)
    point, _, link = where.partition(":")
    if not point.strip():
        raise ParameterError(f"--force {text!r}: give the point after @ (e.g. --force -500,0@C:piston)")
    return value, point.strip(), (link.strip() or None)


def command_loads(args, mech) -> tuple[str | None, tuple]:
    """The ``--force`` text that keeps today's meaning (None when it names a point) and the loads the
    command line adds (analytic.loads dataclasses)."""
    from sim.service.loads import GROUND, force_load, torque_load
    extra = []
    text, point, link = split_force(getattr(args, "force", None))
    if point is not None:
        if getattr(args, "cutting_force", None) is not None:
            raise ParameterError("give either --force or --cutting-force, not both")
        fx, fy = _pair("--force", text)
        topo = mech.topology
        if point not in topo.points:
            raise ParameterError(f"--force ...@{point}: no point named {point!r}; points: {', '.join(topo.points)}")
        link = link or topo.loaded_link(point)
        if link == GROUND or link not in topo.links:
            raise ParameterError(f"--force ...@{point}:{link}: no moving link named {link!r}; links: "
                                 f"{', '.join(topo.links)}")
        if point not in topo.links[link].points:
            raise ParameterError(f"--force ...@{point}:{link}: {point} is not a point of link {link}; its points: "
                                 f"{', '.join(topo.links[link].points)}")
        extra.append(force_load("force", link, point, fx, fy))
        text = None
    for k, item in enumerate(getattr(args, "torque", None) or [], 1):
        if "@" not in item:
            raise ParameterError(f"--torque {item!r}: write T@LINK (e.g. --torque -2.5@4)")
        value, ln = item.split("@", 1)
        ln = ln.strip()
        if ln not in mech.topology.links:
            raise ParameterError(f"--torque {item!r}: no moving link named {ln!r}; links: "
                                 f"{', '.join(mech.topology.links)}")
        extra.append(torque_load(f"torque{k}" if len(args.torque) > 1 else "torque", ln,
                                 parse_value("--torque", value.strip(), angle=False)))
    return text, tuple(extra)


def at_value(args, mech) -> float | None:
    """``--at``: the first input's value [rad or m] (a slider's given in file units)."""
    text = getattr(args, "at", None)
    if text is None:
        return None
    first = mech.inputs[0]
    if first.angular:
        return parse_value("--at", text, angle=None)
    return parse_value("--at", text, angle=False) * mech.scale


def _pair(option, text):
    parts = text.split(",")
    if len(parts) != 2:
        raise ParameterError(f"{option} {text!r} is not two numbers FX,FY (e.g. {option} -500,0@C)")
    return parse_value(option, parts[0], angle=False), parse_value(option, parts[1], angle=False)


def analyze_at(args, mech) -> int:
    """``linkage analyze MECH --at VALUE``: every output at one value of the first input (the others at their
    motion law at the same time): a table in the shown units, or ``--json`` {"mechanism", "at", "t",
    "outputs": {name: value}, "units": {name: unit}} (SI unless --units/--angles/--speeds)."""
    import numpy as np
    from sim.service import loads as L
    from sim.output.jsonout import dumps
    from sim.output.units import column_unit, convert_columns, machine_units, shown_units
    if args.csv:
        raise ParameterError("--at evaluates one pose: it does not combine with --csv")
    at = at_value(args, mech)
    t = np.array([L.at_time(mech, at)])
    q, qd, qdd = mech.drive(t)
    mech.check_assembles(q)
    sol = mech.solve(q, qd, qdd)
    cols = {"t": t}
    for attr, arr in (("q", q), ("qd", qd), ("qdd", qdd)):
        for k, inp in enumerate(mech.inputs):
            cols[getattr(inp, attr)] = arr[:, k]
    cols.update({k: np.asarray(sol[k]).reshape(-1) for k in mech.outputs})
    display = machine_units(args) if args.json else shown_units(args, mech)
    shown = convert_columns(mech, cols, display)
    units = {c: column_unit(mech, c, display) for c in cols}
    if args.json:
        print(dumps({"mechanism": mech.name, "at": float(shown[mech.inputs[0].q][0]), "t": float(t[0]),
                     "outputs": {c: float(v[0]) for c, v in shown.items()}, "units": units}))
        return 0
    first = mech.inputs[0]
    print(f"{mech.name} at {first.q} = {float(shown[first.q][0]):.6g} {units[first.q]} (t = {float(t[0]):.6g} s)")
    for c, v in shown.items():
        if c != "t":
            print(f"  {c:<14s} {float(v[0]):15.8g} {units[c]}")
    return 0
