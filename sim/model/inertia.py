"""Link masses and inertias in the model: the slender-bar default, the file's [inertia] and --inertia, and
reading them back from a compiled model."""

from __future__ import annotations

import math

import mujoco
import numpy as np

from analytic import ParameterError
from sim.model.frames import point_local
from analytic.kinds import GROUND

MIN_MASS, MIN_INERTIA = 1e-9, 1e-14
"""[kg], [kg m^2] The smallest link mass and moment of inertia accepted, a margin above mjMINVAL."""

LINEAR_DENSITY = 1.0
"""[kg/m] Default mass per length of a link: a slender bar (a 12.8 mm steel rod), pinned at its
points; a link with several points is a star of bars from its origin. Blocks weigh as 0.1 size of bar.
Override per link with the file's [inertia] table or --inertia."""


def default_inertia(mech, points, frames, link: str):
    """Slender-bar inertia of a link (see LINEAR_DENSITY), in its frame: (m, cx, cy, Izz about COM)."""
    from analytic.closed_forms.dynamics import Inertia
    size = mech.size
    members = [p for p in link_members(mech)[link] if p != mech.link_origins[link]]
    segs = []
    for p in members:
        x, y = point_local(points, frames, link, p)
        segs.append((math.hypot(x, y), x / 2, y / 2))
    if link in mech.slides or not segs or all(L < 1e-12 * size for L, _, _ in segs):
        m = LINEAR_DENSITY * 0.1 * size
        return Inertia(m=m, cx=0.0, cy=0.0, I=m * (0.1 * size) ** 2 / 6)
    mass = sum(LINEAR_DENSITY * L for L, _, _ in segs)
    cx = sum(LINEAR_DENSITY * L * x for L, x, _ in segs) / mass
    cy = sum(LINEAR_DENSITY * L * y for L, _, y in segs) / mass
    inertia = sum(LINEAR_DENSITY * L * (L * L / 12 + (x - cx) ** 2 + (y - cy) ** 2) for L, x, y in segs)
    return Inertia(m=mass, cx=cx, cy=cy, I=max(inertia, mass * (0.01 * size) ** 2))


def link_members(mech) -> dict[str, set[str]]:
    topo = mech.topology
    return {GROUND: set(topo.ground), **{ln: set(link.points) for ln, link in topo.links.items()}}


def add_inertias(spec, mech, points, frames, loads):
    given = dict(mech.definition.inertia)
    from analytic.closed_forms.dynamics import Inertia
    user = {k: Inertia(m=float(v["m"]), cx=float(v.get("cx", 0.0)) * mech.scale,
                       cy=float(v.get("cy", 0.0)) * mech.scale, I=float(v["I"]) * mech.scale ** 2)
            for k, v in given.items()}
    user.update(loads.inertias or {})
    unknown = set(user) - set(mech.links)
    if unknown:
        raise ParameterError(f"inertia: the {mech.name} has no link {sorted(unknown)[0]!r}; links: "
                             f"{', '.join(mech.links)}")
    for ln in mech.links:
        b = spec.body(ln)
        inertia = user.get(ln) or default_inertia(mech, points, frames, ln)
        if not (inertia.m >= MIN_MASS and inertia.I >= MIN_INERTIA):
            raise ParameterError(f"inertia of link {ln}: m = {inertia.m:.3g} kg, I = {inertia.I:.3g} kg m^2; the "
                                 f"simulation needs m >= {MIN_MASS:g} kg and I >= {MIN_INERTIA:g} kg m^2 "
                                 f"(MuJoCo's minimum): give a realistic [inertia] or --inertia")
        b.explicitinertial = True
        b.mass = inertia.m
        b.ipos = [inertia.cx, inertia.cy, 0.0]
        b.iquat = [1.0, 0.0, 0.0, 0.0]
        b.inertia = [inertia.I / 2, inertia.I / 2, inertia.I]   # a thin plate: Ixx + Iyy = Izz


def body_inertias(model: mujoco.MjModel, names) -> dict:
    """The compiled bodies' inertial data as analytic.closed_forms.dynamics.Inertia (mass, COM in the body frame, Izz
    about the COM)."""
    from analytic.closed_forms.dynamics import Inertia
    out = {}
    for n in names:
        b = model.body(n)
        rot = np.empty(9)
        mujoco.mju_quat2Mat(rot, b.iquat)
        rot = rot.reshape(3, 3)
        izz = float((rot @ np.diag(b.inertia) @ rot.T)[2, 2])
        out[n] = Inertia(m=float(b.mass[0]), cx=float(b.ipos[0]), cy=float(b.ipos[1]), I=izz)
    return out
