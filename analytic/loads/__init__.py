"""Loads as machines meet them (SPEC "Loads: [[loads]], and friction"): forces and torques on any link with a
law over the motion, pressure on a piston, springs (linear, by a force-deflection table, gas springs),
torsion springs, dampers, and Coulomb friction in the joints. One module per kind, listed once in
:data:`MODULES` (:mod:`.friction` for ``[friction]``); each implements the protocol of :mod:`.base`: its
``[[loads]]`` tables are parsed once (when the file is read, :attr:`Definition.loadset`) into frozen records
in SI whose hooks give the wrenches they put on links (:class:`~analytic.loads.common.Application`), their
energy and dissipation, their MuJoCo form, their drawing and their table as written. Nothing outside a
kind's module switches on its class or name.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path

from analytic._common import LazyKinds, module_getattr
from analytic.loads import friction
from analytic.loads.base import Load, LoadKind
from analytic.loads.common import FORCE_UNITS, Application, LoadError, Scales, State, wanted

MODULES = (
    "force",
    "torque",
    "pressure",
    "spring",
    "torsion_spring",
    "damper",
    "gas_spring",
    "table_spring",
)
"""The load kinds' modules, in the order the docs and the editor list them: adding a kind is one line here."""

KINDS: LazyKinds = LazyKinds(__name__, MODULES)
"""Every load kind by name (its module's name), each module imported when its kind is first asked for."""
TOP_LEVEL = ("force_units", "loads", "friction")
MAX_LOADS = 200


@dataclass(frozen=True)
class LoadSet:
    """The loads of a mechanism (SI): ``loads`` (the kinds' dataclasses, file order then the command
    line's), ``friction`` (or None) and the file's force unit."""

    loads: tuple = ()
    friction: object = None
    force_units: str = "N"
    parameters: dict = field(default_factory=dict, compare=False)
    """The parameter values (file units) the file's loads were resolved with."""

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
        if not isinstance(kind, str) or kind not in KINDS:
            raise sc.fail(f"{where}.kind", f"{kind!r} is not a load kind; use one of {', '.join(KINDS)}")
        k = KINDS[kind]
        unknown = sorted(set(item) - k.field_names)
        if unknown:
            raise sc.fail(f"{where}.{unknown[0]}", f"unknown field for a {kind}; it takes "
                                                   f"{', '.join(sorted(k.field_names))}")
        out.append(k.parse(item, where, sc))
    fr = friction.parse(definition.friction, sc, definition.topology.joints)
    return LoadSet(tuple(out), fr if fr else None, definition.force_units, dict(parameters))


def tables(loadset: LoadSet, sc: Scales) -> list[dict]:
    """The ``[[loads]]`` tables (file units of ``sc``) that read back to ``loadset``'s records."""
    return [ld.file_table(sc) for ld in loadset.loads]


def parsed(mech) -> LoadSet:
    """The file's loads as parsed at ``mech``'s parameter values: those the definition holds (parsed when the
    file was read) where the values are the file's, else parsed here."""
    d = mech.definition
    held = getattr(d, "loadset", None)
    return held if held is not None and held.parameters == mech.parameters else parse(d, mech.parameters)


def resolve(mech, extra=()) -> LoadSet:
    """The loads of ``mech`` (its file's, with its parameter values: those parsed when the file was read
    where the values are the file's) plus ``extra`` (the command line's), completed at the start pose (t = 0:
    a spring given by its preload)."""
    ls = parsed(mech).with_loads(extra)
    if any(ld.needs_start for ld in ls.loads):
        import numpy as np
        (q, qd, _), _ = mech.solve_at([0.0])
        sol = mech.solve(q, qd, 0.0, outputs=wanted(mech))
        state = State(mech, sol, q, qd, np.zeros(1))
        ls = replace(ls, loads=tuple(ld.at_start(state) for ld in ls.loads))
    return ls


def get(name: str) -> LoadKind:
    """The load kind called ``name`` (KeyError if there is none)."""
    return KINDS[name]


__all__ = ["KINDS", "MODULES", "Load", "LoadKind", "get", "tables", "parsed", "LoadSet", "LoadError", "Application", "State", "Scales", "FORCE_UNITS", "parse", "resolve",
           "wanted", "input_names", "check_units"]

__getattr__ = module_getattr(__name__, MODULES)
