"""The loads a script gives as keywords (``gravity=``, ``force=``, ``cutting_force=``, ``torque=``,
``inertia=``), checked and turned into the loads of a run (``sim.model.Loads``): what the command line's
``--gravity``, ``--force FX,FY[@POINT[:LINK]]``, ``--cutting-force``, ``--torque T@LINK`` and ``--inertia``
become once their text is read (SPEC "Loads")."""

from __future__ import annotations

import math
import os

from analytic.errors import ParameterError

LOAD_KEYWORDS = ("gravity", "force", "cutting_force", "torque", "inertia")
"""The keywords of :func:`run_loads`, which every simulating function of the door takes."""


def _number(name: str, v) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(float(v)):
        raise ParameterError(f"{name}={v!r} is not a finite number")
    return float(v)


def _pair(name: str, v) -> tuple[float, float]:
    if not isinstance(v, (tuple, list)) or len(v) != 2:
        raise ParameterError(f"{name}={v!r} is not two numbers (x, y), e.g. {name}=(0, -9.81)")
    return _number(name, v[0]), _number(name, v[1])


def _force(mech, force) -> tuple[tuple[float, float], object]:
    """``force=(fx, fy)`` on the output point, or ``(fx, fy, POINT)`` / ``(fx, fy, POINT, LINK)``: (the
    shorthand's (fx, fy), None) or ((0, 0), the extra load at the named point)."""
    from sim.service.loads import GROUND, force_load
    if not isinstance(force, (tuple, list)) or len(force) not in (2, 3, 4):
        raise ParameterError(f"force={force!r}: give (fx, fy) [N] on the output point, or (fx, fy, POINT) or "
                             f"(fx, fy, POINT, LINK), e.g. force=(-500, 0, 'C')")
    fx, fy = _pair("force", tuple(force[:2]))
    if len(force) == 2:
        return (fx, fy), None
    topo = mech.topology
    point = force[2]
    if point not in topo.points:
        raise ParameterError(f"force=(..., {point!r}): no point named {point!r}; points: {', '.join(topo.points)}")
    link = force[3] if len(force) == 4 else topo.carriers[point]
    if link == GROUND or link not in topo.links:
        raise ParameterError(f"force=(..., {point!r}, {link!r}): no moving link named {link!r}; links: "
                             f"{', '.join(topo.links)}")
    if point not in topo.links[link].points:
        raise ParameterError(f"force=(..., {point!r}, {link!r}): {point} is not a point of link {link}; its "
                             f"points: {', '.join(topo.links[link].points)}")
    return (0.0, 0.0), force_load("force", link, point, fx, fy)


def _torques(mech, torque) -> list:
    """``torque={LINK: T}`` [N m, + counter-clockwise] (or ``[(LINK, T), ...]``, a link twice): one constant
    couple each (named ``torque``, or ``torque1, torque2, ...`` when there are several, as the command line
    names them)."""
    from sim.service.loads import torque_load
    items = list(torque.items()) if isinstance(torque, dict) else torque
    if not isinstance(items, (list, tuple)) or not all(isinstance(x, (list, tuple)) and len(x) == 2 for x in items):
        raise ParameterError(f"torque={torque!r}: give {{LINK: T}} in N m, e.g. torque={{'4': -2.5}}")
    out = []
    for k, (link, value) in enumerate(items, 1):
        if link not in mech.topology.links:
            raise ParameterError(f"torque={{{link!r}: ...}}: no moving link named {link!r}; links: "
                                 f"{', '.join(mech.topology.links)}")
        out.append(torque_load(f"torque{k}" if len(items) > 1 else "torque", link, _number("torque", value)))
    return out


def inertias_of(mech, inertia) -> dict | None:
    """``inertia=``: {LINK: {"m", "cx", "cy", "I"}} in the file's units (as ``--inertia PATH.json`` holds
    them), or the path of such a JSON file: {link: analytic.mass.Inertia} (SI)."""
    from sim.service.loads import inertia as one
    if inertia is None:
        return None
    if isinstance(inertia, (str, os.PathLike)):
        from sim.readers import read_json
        path = os.fspath(inertia)
        inertia = read_json("inertia", path)
        if not isinstance(inertia, dict):
            raise ParameterError(f"inertia={path!r}: expected an object of links")
    if not isinstance(inertia, dict):
        raise ParameterError(f"inertia={inertia!r}: give {{LINK: {{'m': kg, 'cx': .., 'cy': .., 'I': ..}}}} or a "
                             f"JSON file's path")
    out = {}
    for link, data in inertia.items():
        if not isinstance(data, dict):
            raise ParameterError(f"--inertia {link}: give an object with m, cx, cy and I")
        try:                                   # file units, like the file's [inertia]: m kg, cx cy, I kg unit^2
            out[link] = one(data, mech.scale)
        except TypeError:
            raise ParameterError(f"--inertia {link}: give m, cx, cy and I (got {sorted(data)})") from None
        except ParameterError as exc:
            raise ParameterError(f"--inertia {link}: {exc}") from None
    return out


def run_loads(mech, *, gravity=None, force=None, cutting_force=None, torque=None, inertia=None):
    """The loads of a run (``sim.model.Loads``) from the keywords: ``gravity`` (gx, gy) [m/s^2]; ``force``
    (fx, fy) [N] on the output point, or (fx, fy, POINT[, LINK]) at a named point; ``cutting_force`` F [N]
    resisting the output point's slow stroke along x; ``torque`` {LINK: T} [N m]; ``inertia`` the links'
    inertial data (file units) or a JSON file's path."""
    from sim.service.simulation import run_loads as loads
    g = _pair("gravity", gravity) if gravity is not None else None
    shorthand, extra = (0.0, 0.0), []
    if force is not None:
        shorthand, at_point = _force(mech, force)
        if at_point is not None:
            extra.append(at_point)
    slow = False
    if cutting_force is not None:
        if force is not None:
            raise ParameterError("give either force= or cutting_force=, not both")
        c = _number("cutting_force", cutting_force)
        if c < 0:
            raise ParameterError(f"cutting_force={c:g} must be >= 0 [N] (it always resists the motion)")
        from sim.service.loads import cutting_direction
        shorthand, slow = (cutting_direction(mech) * c, 0.0), True
    if torque:
        extra += _torques(mech, torque)
    return loads(gravity=g, force=shorthand, slow_stroke_only=slow, inertias=inertias_of(mech, inertia),
                 extra=tuple(extra))
