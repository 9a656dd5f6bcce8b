"""Mechanisms by name or file, with parameter values: what every use case starts from."""

from __future__ import annotations

import math


import analytic
from analytic import ParameterError
from analytic.format import expr
from analytic.mechanism import Mechanism
from sim.service.catalog import list_mechanisms  # noqa: F401 (re-exported)


def parameter_value(mech_or_def, name: str, value) -> float:
    """A parameter value from text or a number: ``"30deg"`` for an angle, refused on a length."""
    d = mech_or_def.definition if isinstance(mech_or_def, Mechanism) else mech_or_def
    if name not in d.parameters:
        raise ParameterError(f"{name!r} is not a parameter of {d.name}; parameters: "
                             f"{', '.join(d.parameter_order) or '(none)'}")
    kind = d.parameter_kind[name]
    if isinstance(value, bool):
        raise ParameterError(f"{name}={value!r} is not a number")
    if isinstance(value, (int, float)):
        v = float(value)
        if not math.isfinite(v) or abs(v) > 1e12:
            raise ParameterError(f"{name}={value!r} is out of range: give a finite value of magnitude <= 1e12")
    else:
        v = expr.parse_value(name, str(value), angle=False if kind == "length" else None)
    if kind == "branch" and v not in (1.0, -1.0):
        raise ParameterError(f"{name}={value} is not a valid branch: use +1 or -1")
    return v


def load(mechanism: str, values: dict | None = None, text: str | None = None) -> Mechanism:
    """A mechanism by name or path (or from a file's ``text``), with parameter ``values`` (numbers or
    strings such as ``"30deg"``, file units). A Pyslvs or PMKS file is driven as ``linkage import`` writes it
    (:func:`sim.service.importing.foreign_definition`: its source's range where it cannot run a turn)."""
    if text is not None:
        d = analytic.format.linkfile.parse(text, "<upload>")
    elif analytic.registry.is_name(mechanism):         # a library name: no other tool's file to look for
        d = analytic.definition(mechanism)
    else:
        from sim.service.importing import foreign_definition
        d = foreign_definition(mechanism) or analytic.definition(mechanism)
    overrides = {k: parameter_value(d, k, v) for k, v in (values or {}).items()}
    builtin = analytic.BUILTINS.get(mechanism) if text is None else None
    return Mechanism.from_definition(d, overrides, builtin)


def parameter_table(mech: Mechanism) -> list[dict]:
    """Each parameter with its value, kind, unit and a slider range for front ends."""
    out = []
    d = mech.definition
    for name in d.parameter_order:
        kind = d.parameter_kind[name]
        v = mech.values[name]
        derived = isinstance(d.parameters[name], str) and expr.quantity(d.parameters[name]) is None
        if kind == "length":
            unit, lo, hi, step = d.units, min(0.0, 2 * v), max(2.0 * abs(v), 1e-9), abs(v) / 200 or 0.001
            if v > 0:
                lo = v / 5
        elif kind == "angle":
            unit, lo, hi, step = "rad", min(-2 * math.pi, -2 * abs(v)), max(2 * math.pi, 2 * abs(v)), 0.001
        elif kind == "branch":
            unit, lo, hi, step = "", -1.0, 1.0, 2.0
        else:
            unit, lo, hi, step = "", -2 * abs(v) - 1, 2 * abs(v) + 1, (abs(v) or 1) / 200
        out.append({"name": name, "value": v, "kind": kind, "unit": unit, "min": lo, "max": hi, "step": step,
                    "derived": derived})
    return out


def describe(mech: Mechanism) -> dict:
    """A JSON-ready description: parameters, inputs, points, links, slides, outputs."""
    return {"name": mech.name, "description": mech.description, "units": mech.units,
            "parameters": parameter_table(mech),
            "inputs": [{"kind": i.kind, "link": i.link, "q": i.q, "qd": i.qd, "qdd": i.qdd, "unit": i.unit,
                        "periodic": i.spec.periodic, "point": i.point, "pivot": i.joint} for i in mech.inputs],
            "points": list(mech.points), "ground": list(mech.ground_points), "links": link_drawing(mech),
            "slides": list(mech.slides), "output_point": mech.output_point, "outputs": list(mech.outputs),
            "size": mech.size}


def link_drawing(mech: Mechanism) -> list[dict]:
    """Each link with the points to draw it through (origin first), for front ends."""
    links = mech.topology.links
    return [{"name": ln, "points": [link.origin] + sorted(set(link.points) - {link.origin}),
             "block": ln in mech.slides} for ln, link in links.items()]
