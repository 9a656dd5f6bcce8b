"""Loads as machines meet them (SPEC "Loads: [[loads]], and friction"): forces and torques on any link with a
law over the motion, pressure on a piston, springs, torsion springs, dampers, and Coulomb friction in the
joints. One module per kind (:mod:`.force`, :mod:`.torque`, :mod:`.pressure`, :mod:`.spring`,
:mod:`.torsion_spring`, :mod:`.damper`; :mod:`.friction` for ``[friction]``); each load resolves to a
frozen dataclass in SI whose ``applications(state, variables)`` gives the wrenches it puts on links
(:class:`~analytic.loads.common.Application`), which the kinetostatics adds to the links' known loads
(:mod:`analytic.loads.kinetostatics`), the power balance to the generalized forces and MuJoCo to its bodies.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

from analytic.loads import damper, force, friction, pressure, spring, torque, torsion_spring
from analytic.loads.common import FORCE_UNITS, Application, LoadError, Scales, State, wanted

KINDS = {"force": force, "torque": torque, "pressure": pressure, "spring": spring,
         "torsion_spring": torsion_spring, "damper": damper}
TOP_LEVEL = ("force_units", "loads", "friction")
MAX_LOADS = 200


@dataclass(frozen=True)
class LoadSet:
    """The loads of a mechanism (SI): ``loads`` (the kinds' dataclasses, file order then the command
    line's), ``friction`` (or None) and the file's force unit."""

    loads: tuple = ()
    friction: object = None
    force_units: str = "N"

    def __bool__(self) -> bool:
        return bool(self.loads) or bool(self.friction)

    def with_loads(self, extra) -> "LoadSet":
        names = {ld.name for ld in self.loads}
        for ld in extra:
            if ld.name in names:
                raise LoadError(f"load {ld.name!r} is given twice; name it differently")
            names.add(ld.name)
        return replace(self, loads=self.loads + tuple(extra))


def input_names(definition) -> tuple:
    """(q, qd, kind) of each input of a definition, in order (``phi1``/``omega1`` for crank link 1; the kind's name)."""
    from analytic import kinds
    out = []
    for e in definition.order:
        kind = kinds.get(e.kind)
        if kind.section != "inputs":
            continue
        link = e.links()[0]
        out.append((kind.columns[0] + link, kind.columns[1] + link, kind.name))
    return tuple(out)


def scales(definition, parameters: dict) -> Scales:
    units = definition.force_units
    folder = str(Path(definition.source).parent) if definition.source and not definition.source.startswith("<") \
        else "."
    return Scales(definition.scale, FORCE_UNITS[units], definition.source, dict(parameters), definition.topology,
                  input_names(definition), folder)


def check_units(source: str, units) -> str:
    if units is None:
        return "N"
    if not isinstance(units, str) or units not in FORCE_UNITS:
        raise LoadError(f"{source}: force_units: {units!r} is not known; use one of {', '.join(FORCE_UNITS)}")
    return units


def parse(definition, parameters: dict) -> LoadSet:
    """The file's ``[[loads]]`` and ``[friction]`` resolved with ``parameters`` (file units), in SI; a
    :class:`LoadError` naming the file, the load and the field for anything wrong."""
    sc = scales(definition, parameters)
    raw = definition.loads
    if not isinstance(raw, (list, tuple)):
        raise sc.fail("loads", "must be an array of tables ([[loads]])")
    if len(raw) > MAX_LOADS:
        raise sc.fail("loads", f"{len(raw)} loads; at most {MAX_LOADS}")
    out, names = [], set()
    for i, item in enumerate(raw, 1):
        where = f"loads[{i}]"
        if not isinstance(item, dict):
            raise sc.fail(where, "must be a table (name, kind, ...)")
        name = item.get("name")
        from analytic.format import expr
        if not (isinstance(name, str) and expr.NAME.match(name)):
            raise sc.fail(f"{where}.name", f"{name!r}: give each load a name (letters, digits and _)")
        where = f"loads[{i}] ({name})"
        if name in names:
            raise sc.fail(f"{where}.name", "is used by another load; names are unique")
        names.add(name)
        kind = item.get("kind")
        if kind not in KINDS:
            raise sc.fail(f"{where}.kind", f"{kind!r}: use one of {', '.join(KINDS)}")
        unknown = sorted(set(item) - KINDS[kind].FIELDS)
        if unknown:
            raise sc.fail(f"{where}.{unknown[0]}", f"unknown field for a {kind}; it takes "
                                                   f"{', '.join(sorted(KINDS[kind].FIELDS))}")
        out.append(KINDS[kind].parse(item, where, sc))
    fr = friction.parse(definition.friction, sc, definition.topology.joints)
    return LoadSet(tuple(out), fr if fr else None, definition.force_units)


def resolve(mech, extra=()) -> LoadSet:
    """The loads of ``mech`` (its file's, with its parameter values) plus ``extra`` (the command line's),
    springs given by a preload fixed at the start pose (t = 0)."""
    d = mech.definition
    ls = parse(d, mech.parameters).with_loads(extra)
    if any(isinstance(ld, spring.Spring) and ld.free_length is None and ld.table is None for ld in ls.loads):
        import numpy as np
        (q, qd, _), _ = mech.solve_at([0.0])
        sol = mech.solve(q, qd, 0.0, outputs=wanted(mech))
        state = State(mech, sol, q, qd, np.zeros(1))
        new = []
        for ld in ls.loads:
            if isinstance(ld, spring.Spring):
                _, _, length, _, _ = ld.geometry(state)
                ld = ld.at_start(float(length[0]))
            new.append(ld)
        ls = replace(ls, loads=tuple(new))
    return ls


__all__ = ["KINDS", "LoadSet", "LoadError", "Application", "State", "Scales", "FORCE_UNITS", "parse", "resolve",
           "wanted", "input_names", "check_units"]
