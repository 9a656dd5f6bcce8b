"""The file's loads on a drawing and in an editor (the app's loads on the canvas; public API): where each
``[[loads]]`` entry acts over a run and how much (:func:`load_geometry`), which fields each kind of load
takes (:func:`load_fields`), and the check that every load of a file resolves (:func:`resolve`), as
``linkage forces`` and ``linkage dynamics`` resolve them."""

from __future__ import annotations

import numpy as np

from analytic import loads as AL
from analytic.kinds import GROUND
from analytic.loads import common as LC


def load_fields() -> dict[str, frozenset]:
    """{kind: the fields a ``[[loads]]`` table of that kind takes}."""
    return {kind: frozenset(cls.FIELDS) for kind, cls in AL.KINDS.items()}


def resolve(mech):
    """The file's loads resolved (:func:`analytic.loads.resolve`; None when it has none): a load the solver
    would refuse raises ParameterError with its one line."""
    return AL.resolve(mech)


def load_geometry(mech, t, q, qd, loadset) -> dict:
    """Where and how much each load of ``loadset`` acts over the samples ``t`` (inputs ``q``, ``qd``):
    {"force_units", "length_unit", "loads": [...], "friction": [...]}. Each load's entry has its
    ``name``, ``kind``, ``link``, ``shape`` and arrays of shape (N,): a spring's or damper's two ends
    (``between``: x1 y1 x2 y2 [m], ``value`` its tension), a pin's position and moment (``pin``), a torque's
    link centre and moment (``moment``), a force's point and components (``arrow``: x y fx fy). Forces are in
    the file's ``force_units``, moments in force unit x the file's length unit."""
    from analytic.loads import damper as D
    from analytic.loads import spring as S
    from analytic.loads import torque as T
    from analytic.loads import torsion_spring as TS
    sol = mech.solve(q, qd, np.zeros_like(q), outputs=AL.wanted(mech))
    n = len(t)
    sol = {k: np.reshape(np.asarray(sol[k]), n) for k in AL.wanted(mech)}
    state = AL.State(mech, sol, q, qd, t)
    variables = state.variables(AL.scales(mech.definition, mech.parameters))
    fu = loadset.force_units if loadset else mech.definition.force_units
    per_force = 1.0 / AL.FORCE_UNITS[fu]                 # N -> the file's force unit
    per_moment = per_force * mech.scale                 # N m -> force unit x length unit
    moment_unit = f"{fu} {mech.units}"

    def s(a):
        return np.broadcast_to(np.asarray(a, dtype=float), (n,))

    def centre(link):
        if link == GROUND:
            return np.zeros(n), np.zeros(n)
        pts = mech.definition.topology.links[link].points
        return (np.mean([sol["x" + p] for p in pts], axis=0), np.mean([sol["y" + p] for p in pts], axis=0))

    out = []
    for ld in loadset.loads if loadset else ():
        try:
            apps = ld.applications(state, variables)
        except ValueError as exc:
            raise LC.LoadError(f"load {ld.name}: {exc}") from None
        entry = {"name": ld.name, "kind": ld.kind, "link": ld.link}
        if isinstance(ld, (S.Spring, D.Damper)) and getattr(ld, "ends", None):
            (x1, y1), (x2, y2), _, _, _ = S.Spring.geometry(ld, state)
            a = apps[0]                                   # on the first end: + tension pulls it to the second
            ex, ey = np.asarray(x2 - x1), np.asarray(y2 - y1)
            tension = (np.asarray(a.fx) * ex + np.asarray(a.fy) * ey) / np.maximum(np.hypot(ex, ey), 1e-300)
            entry.update(shape="between", x1=s(x1), y1=s(y1), x2=s(x2), y2=s(y2), value=s(tension * per_force),
                         unit=fu)
        elif isinstance(ld, (TS.TorsionSpring, D.Damper)):
            x, y = state.xy(ld.joint)
            entry.update(shape="pin", joint=ld.joint, x=s(x), y=s(y), value=s(np.asarray(apps[0].couple) * per_moment),
                         unit=moment_unit)
        elif isinstance(ld, T.Torque):
            x, y = centre(ld.link)
            entry.update(shape="moment", x=s(x), y=s(y), value=s(np.asarray(apps[0].couple) * per_moment),
                         unit=moment_unit)
        else:                                             # force, pressure: one application at the point
            a = apps[0]
            entry.update(shape="arrow", x=s(a.px), y=s(a.py), fx=s(np.asarray(a.fx) * per_force),
                         fy=s(np.asarray(a.fy) * per_force), unit=fu)
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
