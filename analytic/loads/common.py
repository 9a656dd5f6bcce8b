"""What every load kind shares: force units, the ends a load acts at, the kinematic state it reads and the
wrenches it puts on links (:class:`Application`).

A link's frame is the mass model's (:mod:`analytic.mass`): origin at the link's first point
(``Mechanism.link_origins``), x-axis at its angle ``phiL``. The ground's frame is the world's. Everything here
is SI (m, N, rad, s) once resolved; the file's numbers are converted by :class:`Scales`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic._common import ParameterError
from analytic.kinds import GROUND
from analytic.quantities import FORCE_UNITS  # noqa: F401  re-exported: Newtons per force unit of ``force_units``

MAX_VALUE = 1e12
"""Largest magnitude of any number in a load (file units): past it a value is a typing slip."""


class LoadError(ParameterError):
    """A load that cannot be read or applied: one line naming the file, the load and the field."""


@dataclass(frozen=True)
class Scales:
    """How to read a file's numbers: metres per length unit, newtons per force unit, the file's name (for
    messages), its parameter values (file units) and the topology (links, points, inputs)."""

    length: float
    force: float
    source: str
    parameters: dict
    topology: object
    input_names: tuple = ()
    """Per input: (q, qd, kind) names, e.g. ("phi1", "omega1", "crank") (the kind's name)."""
    folder: str = "."

    def fail(self, where: str, what: str) -> LoadError:
        return LoadError(f"{self.source}: {where}: {what}")

    def number(self, value, where: str, angle: bool | None = False) -> float:
        """A finite number, a quantity ("30deg") or an expression of the parameters (file units)."""
        from analytic.format import expr
        if isinstance(value, bool) or not isinstance(value, (int, float, str)):
            raise self.fail(where, f"{value!r} must be a number or an expression")
        if isinstance(value, str):
            q = expr.quantity(value)
            if q is not None:
                v, deg = q
                if deg and angle is False:
                    raise self.fail(where, f"{value!r} is not an angle; drop the 'deg' suffix")
            else:
                try:
                    v = expr.evaluate(value, self.parameters)
                except ValueError as exc:
                    raise self.fail(where, str(exc)) from None
        else:
            v = float(value)
        if not (math.isfinite(v) and abs(v) <= MAX_VALUE):
            raise self.fail(where, f"{value!r} must be finite and of magnitude <= {MAX_VALUE:g}")
        return float(v)

    def pair(self, value, where: str) -> tuple[float, float]:
        if not (isinstance(value, (list, tuple)) and len(value) == 2):
            raise self.fail(where, f"{value!r} must be [u, v]: two numbers")
        return self.number(value[0], where), self.number(value[1], where)

    def link(self, value, where: str, ground: bool = False) -> str:
        links = self.topology.links
        if value == GROUND and ground:
            return GROUND
        if not isinstance(value, str) or value not in links:
            extra = " or ground" if ground else ""
            raise self.fail(where, f"{value!r} is not a link; links: {', '.join(links)}{extra}")
        return value


@dataclass(frozen=True)
class End:
    """Where a load acts: on ``link`` (or the ground) at the fixed point (u, v) [m] of the link's frame,
    and its name as written (``point``: a point's name, or None for coordinates)."""

    link: str
    u: float
    v: float
    point: str | None = None

    def record(self, scale: float = 1.0) -> dict:
        """``{"point": name}`` or ``{"at": [u, v]}`` (lengths divided by ``scale``)."""
        return {"point": self.point} if self.point else {"at": [self.u / scale, self.v / scale]}


def end(sc: Scales, link: str, point=None, at=None, where: str = "", pose=None) -> End:
    """An :class:`End` from a point name on ``link`` or coordinates ``at`` in its frame; ``pose`` gives each
    point's position in the link's frame when a point is named ({(link, point): (u, v)} [m])."""
    if (point is None) == (at is None):
        raise sc.fail(where, "give either point = \"NAME\" or at = [u, v] (in the link's frame)")
    if point is not None:
        topo = sc.topology
        members = topo.ground if link == GROUND else topo.links[link].points
        if point not in members:
            raise sc.fail(f"{where}.point", f"{point!r} is not a point of link {link}; its points: "
                                            f"{', '.join(members)}")
        return End(link, math.nan, math.nan, point)
    u, v = sc.pair(at, f"{where}.at")
    return End(link, u * sc.length, v * sc.length, None)


@dataclass(frozen=True)
class Application:
    """A wrench a load puts on one link (or the ground: a reaction the frame feels), arrays over the samples:
    the force (fx, fy) [N] at the point (px, py) [m] and a couple [N m]."""

    link: str
    fx: object
    fy: object
    px: object
    py: object
    couple: object = 0.0


class State:
    """The kinematics a load reads, over N samples: every point's position and velocity, every link's
    (cos, sin), angle rate and angle, prismatic pairs' slide rates, the inputs and time. Built from a
    solution with :func:`wanted`'s outputs."""

    def __init__(self, mech, sol, q, qd, t):
        self.mech = mech
        self.sol = sol
        self.q = np.atleast_2d(np.asarray(q, dtype=float).reshape(len(np.atleast_1d(t)), -1))
        self.qd = np.atleast_2d(np.asarray(qd, dtype=float).reshape(self.q.shape))
        self.t = np.atleast_1d(np.asarray(t, dtype=float))
        self.n = len(self.t)

    def xy(self, p: str):
        return np.asarray(self.sol["x" + p]), np.asarray(self.sol["y" + p])

    def frame(self, link: str):
        """(ox, oy, cos, sin, omega) of a link's frame (the ground: the world at rest)."""
        if link == GROUND:
            z = np.zeros(self.n)
            return z, z, np.ones(self.n), z, z
        o = self.mech.link_origins[link]
        return (np.asarray(self.sol["x" + o]), np.asarray(self.sol["y" + o]), np.asarray(self.sol["cos" + link]),
                np.asarray(self.sol["sin" + link]), np.asarray(self.sol["omega" + link]))

    def position(self, e: End):
        """(x, y) of an end [m]."""
        if e.point is not None:
            return self.xy(e.point)
        ox, oy, c, s, _ = self.frame(e.link)
        return ox + e.u * c - e.v * s, oy + e.u * s + e.v * c

    def velocity_at(self, link: str, px, py):
        """Velocity (vx, vy) [m/s] of the point of ``link`` at (px, py) (the ground: 0)."""
        if link == GROUND:
            z = np.zeros(self.n)
            return z, z
        o = self.mech.link_origins[link]
        ox, oy = self.xy(o)
        w = np.asarray(self.sol["omega" + link])
        return (np.asarray(self.sol["vx" + o]) - w * (py - oy), np.asarray(self.sol["vy" + o]) + w * (px - ox))

    def velocity(self, e: End):
        px, py = self.position(e)
        return self.velocity_at(e.link, px, py)

    def omega(self, link: str):
        return np.zeros(self.n) if link == GROUND else np.asarray(self.sol["omega" + link])

    def angle(self, link: str):
        if link == GROUND:
            return np.zeros(self.n)
        return np.arctan2(np.asarray(self.sol["sin" + link]), np.asarray(self.sol["cos" + link]))

    def variables(self, scales: Scales) -> dict:
        """The names an expression of a load may use: the parameters (file units), every input's position
        and rate by its own name (``phi1``/``omega1``, ``sJ``/``dsJ``; a slide in file units) and as
        ``phiK``/``omegaK`` or ``sK``/``dsK`` by its index K, and the time ``t``."""
        out = dict(scales.parameters)
        for k, inp in enumerate(self.mech.inputs):
            unit = 1.0 if inp.angular else self.mech.scale
            qk, qdk = self.q[:, k] / unit, self.qd[:, k] / unit
            short = inp.spec.columns[:2]
            for a, b in ((f"{short[0]}{k + 1}", f"{short[1]}{k + 1}"), (inp.q, inp.qd)):
                out[a], out[b] = qk, qdk
        out["t"] = self.t
        return out


def wanted(mech) -> list[str]:
    """The outputs a :class:`State` reads: positions and velocities of every point, each link's (cos, sin)
    and angular velocity, each prismatic pair's slide rate."""
    return ([c + p for p in mech.points for c in ("x", "y", "vx", "vy")]
            + [c + ln for ln in mech.links for c in ("cos", "sin", "omega")]
            + ["ds" + j for j in mech.slides])


def power(state: State, apps) -> np.ndarray:
    """The power [W] of wrenches on the moving links (the ground's share does no work)."""
    p = np.zeros(state.n)
    for a in apps:
        if a.link == GROUND:
            continue
        vx, vy = state.velocity_at(a.link, a.px, a.py)
        p = p + a.fx * vx + a.fy * vy + a.couple * state.omega(a.link)
    return p
