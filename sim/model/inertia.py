"""Link masses and inertias in the model, from the one mass model (:mod:`analytic.mass`: the slender-bar
default, the file's [mass] and [inertia], --inertia, counterweights), and reading them back from a compiled
model."""

from __future__ import annotations

import mujoco
import numpy as np

from analytic import ParameterError, mass
from analytic.kinds import GROUND
from sim.model.frames import point_local

MIN_MASS, MIN_INERTIA = 1e-9, 1e-14
"""[kg], [kg m^2] The smallest link mass and moment of inertia accepted, a margin above mjMINVAL."""

LINEAR_DENSITY = mass.LINEAR_DENSITY
"""[kg/m] Default mass per length of a link (see :mod:`analytic.mass`, the one mass model)."""


def _local(mech, points, frames, link: str) -> dict[str, tuple[float, float]]:
    return {p: point_local(points, frames, link, p) for p in mech.topology.links[link].points}


def default_inertia(mech, points, frames, link: str):
    """The default model of a link (slender bars of 1 kg/m, see :func:`analytic.mass.default`), in its frame:
    (m, cx, cy, Izz about COM); ``points``/``frames``: world positions and link poses at one instant."""
    return mass.default(mech, link, _local(mech, points, frames, link))


def link_members(mech) -> dict[str, set[str]]:
    topo = mech.topology
    return {GROUND: set(topo.ground), **{ln: set(link.points) for ln, link in topo.links.items()}}


STAND_IN = 1e-6
"""A massless link (m = 0 in [inertia]) gets this share of the other links' total mass in MuJoCo (which needs
a mass on every moving body), spread as a bar of the mechanism's size about its origin (I = m (0.3 size)^2).
The comparisons read the compiled model's masses back (body_inertias), so the analytic side carries the same
stand-in; what it changes against the massless analytic run is 1e-6 of the inertial forces."""


def massless_stand_ins(mech, inertias: dict) -> dict:
    """``inertias`` with each massless link given MuJoCo's stand-in (STAND_IN)."""
    total = sum(b.m for b in inertias.values())
    if all(b.m > 0 for b in inertias.values()):
        return inertias
    m = max(STAND_IN * total, MIN_MASS * 10)
    I = max(m * (0.3 * mech.size) ** 2, MIN_INERTIA * 10)
    return {ln: (b if b.m > 0 else mass.Inertia(m=m, cx=0.0, cy=0.0, I=I)) for ln, b in inertias.items()}


def model_inertias(mech, points, frames, loads) -> dict:
    """Every link's inertia as the model carries it (SI, :class:`analytic.mass.Inertia` in the link's frame at
    the pose ``points``/``frames``): the mass model with ``loads.inertias`` and the massless links' stand-ins.
    :func:`body_inertias` reads the same numbers back from a compiled model (its bodies' principal axes are the
    frame's: no rotation)."""
    local = {ln: _local(mech, points, frames, ln) for ln in mech.links}
    return massless_stand_ins(mech, mass.model(mech, loads.inertias, local))


def add_inertias(spec, mech, points, frames, loads):
    """Every body's inertial data from the mass model (:func:`analytic.mass.model`: --inertia, [inertia],
    [mass], the default; counterweights added), so the model and the analytic forces read the same masses."""
    inertias = model_inertias(mech, points, frames, loads)
    for ln in mech.links:
        b = spec.body(ln)
        inertia = inertias[ln]
        if not (inertia.m >= MIN_MASS and inertia.I >= MIN_INERTIA):
            raise ParameterError(f"{mech.definition.source}: inertia of link {ln}: m = {inertia.m:.3g} kg, I = {inertia.I:.3g} kg m^2; the "
                                 f"simulation needs m >= {MIN_MASS:g} kg and I >= {MIN_INERTIA:g} kg m^2 "
                                 f"(MuJoCo's minimum): give a realistic [inertia] or --inertia")
        b.explicitinertial = True
        b.mass = inertia.m
        b.ipos = [inertia.cx, inertia.cy, 0.0]
        b.iquat = [1.0, 0.0, 0.0, 0.0]
        b.inertia = [inertia.I / 2, inertia.I / 2, inertia.I]   # a thin plate: Ixx + Iyy = Izz


def body_inertias(model: mujoco.MjModel, names) -> dict:
    """The compiled bodies' inertial data as analytic.mass.Inertia (mass, COM in the body frame, Izz
    about the COM)."""
    from analytic.mass import Inertia
    out = {}
    for n in names:
        b = model.body(n)
        rot = np.empty(9)
        mujoco.mju_quat2Mat(rot, b.iquat)
        rot = rot.reshape(3, 3)
        izz = float((rot @ np.diag(b.inertia) @ rot.T)[2, 2])
        out[n] = Inertia(m=float(b.mass[0]), cx=float(b.ipos[0]), cy=float(b.ipos[1]), I=izz)
    return out
