"""The file's loads on a drawing and in an editor (the app's loads on the canvas; public API): where each
``[[loads]]`` entry acts over a run and how much (:func:`load_geometry`), which fields each kind of load
takes (:func:`load_fields`), and the check that every load of a file resolves (:func:`resolve`), as
``linkage forces`` and ``linkage dynamics`` resolve them."""

from __future__ import annotations

import numpy as np

from analytic import loads as AL
from analytic.loads import common as LC


def load_fields() -> dict[str, frozenset]:
    """{kind: the fields a ``[[loads]]`` table of that kind takes}."""
    return {name: kind.field_names for name, kind in AL.KINDS.items()}


def editor_fields() -> dict[str, tuple]:
    """{kind: its fields as the editor shows them (analytic.loads.base.Field: name, type, label, hint)}, in the
    registry's order."""
    return {name: kind.fields for name, kind in AL.KINDS.items()}


def resolve(mech):
    """The file's loads resolved (:func:`analytic.loads.resolve`; None when it has none): a load the solver
    would refuse raises ParameterError with its one line."""
    return AL.resolve(mech)


def load_geometry(mech, t, q, qd, loadset) -> dict:
    """Where and how much each load of ``loadset`` acts over the samples ``t`` (inputs ``q``, ``qd``):
    {"force_units", "length_unit", "loads": [...], "friction": [...]}. Each load's entry has its
    ``name``, ``kind``, ``link``, ``shape``, ``symbol`` and arrays of shape (N,), as its kind draws it
    (:meth:`analytic.loads.base.Load.drawing`): a load between two ends (``between``: x1 y1 x2 y2 [m],
    ``value`` its tension), a pin's position and moment (``pin``), a torque's link centre and moment
    (``moment``), a force's point and components (``arrow``: x y fx fy). Forces are in the file's
    ``force_units``, moments in force unit x the file's length unit."""
    sol = mech.solve(q, qd, np.zeros_like(q), outputs=AL.wanted(mech))
    n = len(t)
    sol = {k: np.reshape(np.asarray(sol[k]), n) for k in AL.wanted(mech)}
    state = AL.State(mech, sol, q, qd, t)
    variables = state.variables(AL.scales(mech.definition, mech.parameters))
    fu = loadset.force_units if loadset else mech.definition.force_units
    per_force = 1.0 / AL.FORCE_UNITS[fu]                 # N -> the file's force unit
    per_moment = per_force / mech.scale                 # N m -> force unit x length unit (1 N m = 1000 N mm)
    moment_unit = f"{fu} {mech.units}"

    def s(a):
        return np.broadcast_to(np.asarray(a, dtype=float), (n,))

    out = []
    for ld in loadset.loads if loadset else ():
        try:
            apps = ld.applications(state, variables)
        except LC.LoadError:
            raise
        except ValueError as exc:
            raise LC.LoadError(f"load {ld.name}: {exc}") from None
        drawn = ld.drawing(state, apps)
        per, unit = (per_force, fu) if drawn.pop("quantity") == "force" else (per_moment, moment_unit)
        entry = {"name": ld.name, "kind": ld.kind, "link": ld.link, "shape": drawn.pop("shape"),
                 "symbol": drawn.pop("symbol")}
        for k, v in drawn.items():
            entry[k] = v if isinstance(v, str) else s(np.asarray(v) * (per if k in ("value", "fx", "fy") else 1.0))
        entry["unit"] = unit
        out.append(entry)
    friction = []
    fr = loadset.friction if loadset else None
    if fr:
        joints = mech.definition.topology.joints
        for k, mu, r in fr.pins:
            j = joints[k]
            friction.append({"joint": j.name, "point": j.point, "kind": "R", "mu": mu, "pin_radius": r / mech.scale})
        for k, mu in fr.slides:
            j = joints[k]
            friction.append({"joint": j.name, "point": j.point, "kind": "P", "mu": mu})
    return {"force_units": fu, "length_unit": mech.units, "loads": out, "friction": friction}
