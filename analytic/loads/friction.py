"""``[friction]``: Coulomb friction in the joints (SPEC "Loads").

A pin (revolute) of radius r with coefficient mu resists the relative rotation with the moment
Mf = -mu r |F| sign(omega_b - omega_a) that its ``a`` link exerts on its ``b`` link (``model = "linear"``, the
default: the friction circle's radius r sin(atan mu) taken as mu r, for small mu), F the pin's force; with
``model = "circle"`` the friction circle itself, radius r sin(atan mu) = r mu / sqrt(1 + mu^2) (a journal
bearing whose resultant leans at the friction angle atan mu: Khurmi, Theory of Machines, ch. 10; Beer &
Johnston, Vector Mechanics for Engineers: Statics, sec. 8.7 "journal bearings"; Hibbeler, Engineering
Mechanics: Statics, sec. 8.7), 0.5 % below mu r at mu = 0.1, 2 % at 0.2. A prismatic
pair resists the sliding with the force -mu |N| sign(ds) along the guide at the block's pin, N its normal
force. Both depend on the reactions they change, so the kinetostatics is solved again with the friction
loads of the previous solve until they stop changing (a fixed point: :func:`analytic.loads.kinetostatics.solve`).
At rest in a joint (relative rate 0) the friction is taken as 0 (static friction is indeterminate there).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from analytic.loads.common import Application, Scales

FIELDS = {"mu", "pin_radius", "joints", "model"}
MODELS = ("linear", "circle")
"""``[friction] model``: a pin's friction moment mu r |F| (linear) or r sin(atan mu) |F| (circle)."""
JOINT_FIELDS = {"mu", "pin_radius"}


@dataclass(frozen=True)
class Friction:
    """``pins``: (joint index, mu, r [m]); ``slides``: (joint index, mu); only joints with friction;
    ``model``: a pin's lever arm, ``"linear"`` (mu r) or ``"circle"`` (r sin(atan mu))."""

    pins: tuple
    slides: tuple
    model: str = "linear"

    def __bool__(self) -> bool:
        return bool(self.pins or self.slides)

    def loads(self, state, joints, F) -> tuple[list, dict, dict]:
        """The friction wrenches for the joint forces ``F`` (n_joints, 2, N): the applications, each pin's Mf
        [N m] (on b by a) and each prismatic pair's friction force along its guide [N] (on the block)."""
        apps, Mf, Ft = [], {}, {}
        w_scale = max((float(np.max(np.abs(state.omega(ln)))) for ln in state.mech.links), default=0.0)
        v_scale = max((float(np.max(np.hypot(*(np.asarray(state.sol[c + p]) for c in ("vx", "vy")))))
                       for p in state.mech.points), default=0.0)
        for k, mu, r in self.pins:
            j = joints[k]
            rel = state.omega(j.b) - state.omega(j.a)
            m = -circle_radius(mu, r, self.model) * np.hypot(F[k, 0], F[k, 1]) * _sign(rel, w_scale)
            Mf[k] = m
            z = np.zeros(state.n)
            apps.append(Application(j.b, z, z, z, z, m))
            apps.append(Application(j.a, z, z, z, z, -m))
        for k, mu in self.slides:
            j = joints[k]
            _, _, c, s, _ = state.frame(j.b)                      # a block's angle is its guide's
            normal = np.abs(-s * F[k, 0] + c * F[k, 1])
            ds = np.asarray(state.sol["ds" + j.slide])
            f = -mu * normal * _sign(ds, v_scale)
            Ft[k] = f
            px, py = state.xy(j.point)
            apps.append(Application(j.b, f * c, f * s, px, py))
            apps.append(Application(j.a, -f * c, -f * s, px, py))
        return apps, Mf, Ft

    def record(self, joints) -> dict:
        return {"pins": {joints[k].name: {"mu": mu, "pin_radius": r} for k, mu, r in self.pins},
                "prismatic": {joints[k].name: {"mu": mu} for k, mu in self.slides}, "model": self.model}


def circle_radius(mu: float, r: float, model: str = "linear") -> float:
    """A pin's friction lever arm [m]: mu r (``linear``) or the friction circle's r sin(atan mu) (``circle``)."""
    return r * mu / np.hypot(1.0, mu) if model == "circle" else mu * r


AT_REST = 1e-9
"""A joint's relative rate below this share of the mechanism's fastest link rate (or point speed, for a
slide) is rest: a pair that never turns (a block on a fixed guide, links moving together) has rates of
rounding size whose sign means nothing."""


def _sign(rate, scale: float):
    """sign(rate), 0 where |rate| <= AT_REST x scale."""
    return np.where(np.abs(rate) > AT_REST * scale, np.sign(rate), 0.0)


def parse(section, sc: Scales, joints) -> Friction | None:
    """The ``[friction]`` table: a default ``mu`` and ``pin_radius`` (file units) for every joint and
    per-joint overrides ``joints = {NAME = {mu = ..., pin_radius = ...}}`` (NAME a joint's name: that joint;
    or a point's that names no joint: every joint at it)."""
    if section is None:
        return None
    if not isinstance(section, dict):
        raise sc.fail("friction", "must be a table (mu = ..., pin_radius = ..., joints = {NAME = {mu = ...}})")
    unknown = sorted(set(section) - FIELDS)
    if unknown:
        raise sc.fail(f"friction.{unknown[0]}", f"unknown field; [friction] takes {', '.join(sorted(FIELDS))}")

    def values(table, where):
        mu = sc.number(table["mu"], f"{where}.mu") if "mu" in table else None
        r = sc.number(table["pin_radius"], f"{where}.pin_radius") * sc.length if "pin_radius" in table else None
        if mu is not None and not 0 <= mu <= 2:
            raise sc.fail(f"{where}.mu", f"{mu:g} must be in [0, 2] (a Coulomb coefficient)")
        if r is not None and not r >= 0:
            raise sc.fail(f"{where}.pin_radius", "must be >= 0")
        return mu, r

    mu0, r0 = values(section, "friction")
    kind = section.get("model", "linear")
    if kind not in MODELS:
        raise sc.fail("friction.model", f"{kind!r} is not a pin friction model; give \"linear\" (mu r |F|) or "
                                        f"\"circle\" (the friction circle, r sin(atan mu) |F|)")
    per = section.get("joints", {})
    if not isinstance(per, dict):
        raise sc.fail("friction.joints", "must be a table NAME = {mu = ..., pin_radius = ...}")
    over = {}
    names = {j.name for j in joints} | {j.point for j in joints}
    for name, table in per.items():
        where = f"friction.joints.{name}"
        if name not in names:
            raise sc.fail(where, f"no joint or point named {name!r}; joints: {', '.join(j.name for j in joints)}")
        if not isinstance(table, dict) or set(table) - JOINT_FIELDS:
            raise sc.fail(where, "give {mu = ..., pin_radius = ...}")
        over[name] = values(table, where)
    pins, slides = [], []
    named = {j.name for j in joints}
    for k, j in enumerate(joints):
        mu, r = mu0, r0
        # a key that names a joint means that joint only; a point's name (not a joint's) every joint there
        for key in ((j.point,) if j.point not in named else ()) + (j.name,):
            if key in over:
                mu = over[key][0] if over[key][0] is not None else mu
                r = over[key][1] if over[key][1] is not None else r
        if not mu:
            continue
        if j.kind == "revolute":
            if r is None:
                raise sc.fail("friction.pin_radius", f"joint {j.name} has mu = {mu:g} but no pin_radius: give "
                                                     f"pin_radius (file length unit)")
            if r > 0:
                pins.append((k, mu, r))
        else:
            slides.append((k, mu))
    return Friction(tuple(pins), tuple(slides), kind)


__all__ = ["Friction", "parse", "FIELDS", "MODELS", "circle_radius"]
