"""Write a mechanism back as a ``linkage/1`` TOML file, with its current parameter values."""

from __future__ import annotations

import json
import math

from analytic.linkfile import KINDS


def _value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return repr(v) if math.isfinite(v) else '"nan"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    return json.dumps(str(v))


def dump(mech) -> str:
    """The mechanism's definition as TOML; parameters hold their current values (file units, angles in
    radians) so the file reproduces this exact design."""
    d = mech.definition
    lines = ['format = "linkage/1"', f"name = {_value(d.name)}", f"units = {_value(d.units)}"]
    if d.description:
        lines.append(f"description = {_value(d.description)}")
    lines.append(f"output = {_value(d.output)}")
    if d.parameters:
        lines += ["", "[parameters]"]
        for p in d.parameter_order:
            v = mech.values[p]
            lines.append(f"{p} = {_value(int(v) if d.parameter_kind[p] == 'branch' else v)}")
    lines += ["", "[ground]"]
    for g, (x, y) in d.ground.items():
        lines.append(f"{g} = [{_value(x)}, {_value(y)}]")
    for section, elements in (("inputs", d.inputs), ("groups", d.groups)):
        for e in elements:
            lines += ["", f"[[{section}]]", f"kind = {_value(e.kind)}"]
            for fname in KINDS[e.kind]:
                v = e.fields[fname]
                if fname == "guide":
                    if v.points:
                        lines.append(f"guide = {_value(list(v.points))}")
                    else:
                        through = v.through if isinstance(v.through, str) else list(v.through)
                        lines.append(f"guide = {{ through = {_value(through)}, angle = {_value(v.angle)} }}")
                else:
                    lines.append(f"{fname} = {_value(v)}")
    if d.inertia:
        lines += ["", "[inertia]"]
        for link, entry in d.inertia.items():
            inner = ", ".join(f"{k} = {_value(float(x))}" for k, x in entry.items())
            lines.append(f"{json.dumps(link)} = {{ {inner} }}")
    return "\n".join(lines) + "\n"
