"""Units of outputs and CSV columns (no MuJoCo needed)."""

from __future__ import annotations


def output_kind(mech, name: str) -> tuple[str, str]:
    """(unit, kind) of an output: kind is angle, position, ang_velocity, velocity, ang_acceleration,
    acceleration or force. Raises KeyError for a name that is not an output of ``mech``."""
    g = mech.aliases.get(name, name)
    if g.startswith("tau"):
        return ("N m" if any(i.kind == "crank" and i.link == g[3:] for i in mech.inputs) else "N"), "force"
    for prefix, unit, kind, pool in (("phi", "rad", "angle", mech.links), ("mu", "rad", "angle", mech.points),
                                     ("omega", "rad/s", "ang_velocity", mech.links),
                                     ("alpha", "rad/s^2", "ang_acceleration", mech.links),
                                     ("vx", "m/s", "velocity", mech.points), ("vy", "m/s", "velocity", mech.points),
                                     ("ax", "m/s^2", "acceleration", mech.points),
                                     ("ay", "m/s^2", "acceleration", mech.points),
                                     ("x", "m", "position", mech.points), ("y", "m", "position", mech.points),
                                     ("dds", "m/s^2", "acceleration", mech.slides),
                                     ("ds", "m/s", "velocity", mech.slides), ("s", "m", "position", mech.slides)):
        if g.startswith(prefix) and g[len(prefix):] in pool:
            return unit, kind
    raise KeyError(name)


def column_unit(mech, column: str) -> str:
    """The unit of a CSV column of analyze/simulate."""
    if column in ("t",):
        return "s"
    if column == "loop_violation":
        return "m"
    for prefix in ("cmd_", "q_", "v_"):
        if column.startswith(prefix):
            rest = column[len(prefix):]
            try:
                unit = output_kind(mech, rest)[0]
            except KeyError:
                return "rad or m" if prefix == "q_" else "rad/s or m/s"
            return unit
    try:
        return output_kind(mech, column)[0]
    except KeyError:
        return ""
