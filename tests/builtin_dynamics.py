"""The built-ins' own inverse dynamics (their textbook closed forms and body frames), an independent check of
the general drive forces (analytic/applications/torque.py) used by tests only.

Inverse dynamics: the driving torque of each crank from the kinematics, by virtual work.

For a mechanism with driven inputs q_j (one crank, or two for the five-bar) and rigid bodies k of mass
m_k, centre of mass G_k and moment of inertia I_k about G_k (z axis), the torque on input j is

    tau_j = sum_k [ m_k (a_Gk - g) . dv_Gk/dqdot_j  +  I_k alpha_k  domega_k/dqdot_j ]
            + J_j alpha_j  -  F . dv_P/dqdot_j

where the velocity coefficients dv/dqdot_j are the velocities with input j at unit speed, every other
input at rest and all accelerations zero (the closed-form velocity solution evaluated so); J_j is the
rotor inertia (armature) of drive j, g the gravity in the plane, and F an external force on the output
point P (four-bar E, shaper ram C, five-bar P). It is the power balance tau . qdot = dT/dt + dV/dt - F . v_P
written per input, and stays regular where an input speed is zero.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from analytic.closed_forms import fivebar
from analytic.closed_forms import fourbar
from analytic.closed_forms import sixbar
from analytic._common import ParameterError
from analytic.mass import Inertia  # noqa: F401  (the bodies' data, as the general code reads it)

__all__ = ["Motion", "INPUTS", "torques", "body_motions"]

INPUTS = {"fourbar": ("1",), "sixbar": ("1",), "fivebar": ("2", "4")}
"""The driven inputs of each mechanism; their torques are named ``tau1`` or ``tau2``/``tau4``."""


@dataclass(frozen=True)
class Motion:
    """Motion of a body frame: origin position, velocity, acceleration [m, m/s, m/s^2] and orientation
    angle, angular velocity, angular acceleration [rad, rad/s, rad/s^2]; arrays of one shape."""

    ox: np.ndarray
    oy: np.ndarray
    vx: np.ndarray
    vy: np.ndarray
    ax: np.ndarray
    ay: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    alpha: np.ndarray


def _fixed(x, y, theta, omega, alpha) -> Motion:
    z = np.zeros_like(theta)
    return Motion(z + x, z + y, z, z, z, z, theta, omega, alpha)


def _on_circle(cx, cy, r, theta, omega, alpha) -> Motion:
    """Frame at the end of a radius r turning about the fixed point (cx, cy)."""
    c, s = np.cos(theta), np.sin(theta)
    return Motion(cx + r * c, cy + r * s, -r * omega * s, r * omega * c,
                  -r * (alpha * s + omega ** 2 * c), r * (alpha * c - omega ** 2 * s),
                  theta, omega, alpha)


def _sliding(base: Motion, s, ds, dds, theta, omega, alpha) -> Motion:
    """Frame at distance s along a line through ``base``'s origin at angle theta (a prismatic pair):
    v = v_base + ds u + s omega u_perp, a = a_base + (dds - s omega^2) u + (s alpha + 2 ds omega) u_perp."""
    c, s_ = np.cos(theta), np.sin(theta)
    along, across = dds - s * omega ** 2, s * alpha + 2 * ds * omega
    return Motion(base.ox + s * c, base.oy + s * s_,
                  base.vx + ds * c - s * omega * s_, base.vy + ds * s_ + s * omega * c,
                  base.ax + along * c - across * s_, base.ay + along * s_ + across * c,
                  theta, omega, alpha)


def body_motions(name: str, mech, st) -> dict[str, Motion]:
    """Motion of every moving body of the MJCF model ``name`` (same body names) for solved state ``st``."""
    if name == "fourbar":
        return {"crank": _fixed(0.0, 0.0, st.phi1, st.omega1, st.alpha1),
                "coupler": replace(_on_circle(0.0, 0.0, mech.l1, st.phi1, st.omega1, st.alpha1),
                                   theta=st.phi2, omega=st.omega2, alpha=st.alpha2),
                "rocker": _fixed(mech.l4, 0.0, st.phi3, st.omega3, st.alpha3)}
    if name == "sixbar":
        guide = _fixed(0.0, 0.0, st.phi3, st.omega3, st.alpha3)
        zero = np.zeros_like(st.xC)
        return {"crank": _fixed(0.0, mech.l6, st.phi1, st.omega1, st.alpha1),
                "guide": guide,
                "block": _sliding(guide, st.s, st.ds, st.dds, st.phi3, st.omega3, st.alpha3),
                "rod": replace(_on_circle(0.0, 0.0, mech.l3, st.phi3, st.omega3, st.alpha3),
                               theta=st.phi4, omega=st.omega4, alpha=st.alpha4),
                "ram": Motion(st.xC, zero + mech.h, st.vxC, zero, st.axC, zero, zero, zero, zero)}
    crank2 = _fixed(0.0, 0.0, st.phi2, st.omega2, st.alpha2)
    link3 = replace(_on_circle(0.0, 0.0, mech.l2, st.phi2, st.omega2, st.alpha2),
                    theta=st.theta3, omega=st.omega3, alpha=st.alpha3)
    return {"crank2": crank2, "link3": link3,
            "block": _sliding(link3, st.S, st.dS, st.ddS, st.theta3, st.omega3, st.alpha3),
            "crank4": _fixed(mech.l1, 0.0, st.phi4, st.omega4, st.alpha4)}


OUTPUT_VELOCITY = {"fourbar": ("vxE", "vyE"), "sixbar": ("vxC", None), "fivebar": ("vxP", "vyP")}


def _solve(name: str, mech, phi: dict, omega: dict, alpha: dict):
    if name == "fivebar":
        return fivebar.solve(mech, phi["2"], phi["4"], omega["2"], omega["4"], alpha["2"], alpha["4"])
    module = fourbar if name == "fourbar" else sixbar
    return module.solve(mech, phi["1"], omega["1"], alpha["1"])


def _com(m: Motion, b: Inertia):
    """Velocity and acceleration of the centre of mass of body ``b`` moving as ``m``."""
    c, s = np.cos(m.theta), np.sin(m.theta)
    rx, ry = b.cx * c - b.cy * s, b.cx * s + b.cy * c
    return (m.vx - m.omega * ry, m.vy + m.omega * rx,
            m.ax - m.alpha * ry - m.omega ** 2 * rx, m.ay + m.alpha * rx - m.omega ** 2 * ry)


def torques(name: str, mech, phi: dict, omega: dict, alpha: dict, inertias: dict[str, Inertia],
            armature: dict[str, float] | None = None, gravity=(0.0, 0.0), force=(0.0, 0.0),
            force_on=1.0) -> dict[str, np.ndarray]:
    """Driving torque [N m] of each input of mechanism ``name`` (see the module docstring).

    Parameters
    ----------
    phi, omega, alpha : dict
        Input angles [rad], speeds [rad/s] and accelerations [rad/s^2] keyed by input ("1", or "2" and
        "4"), arrays broadcast together.
    inertias : dict
        :class:`Inertia` of each body, keyed by MJCF body name (missing bodies are massless).
    armature : dict, optional
        Rotor inertia [kg m^2] of each input's drive, keyed like ``phi``.
    gravity : (gx, gy)
        Gravity in the plane [m/s^2].
    force : (Fx, Fy)
        External force [N] on the output point, scaled by ``force_on`` (array or scalar; e.g. 1 during the
        shaper's cutting stroke and 0 on its return).

    Returns
    -------
    dict
        ``{"tau1": ...}`` or ``{"tau2": ..., "tau4": ...}``.
    """
    inputs = INPUTS[name]
    unknown = set(inertias) - set(_BODIES[name])
    if unknown:
        raise ParameterError(f"no body named {', '.join(sorted(unknown))} in the {name}; "
                             f"bodies: {', '.join(_BODIES[name])}")
    st = _solve(name, mech, phi, omega, alpha)
    motion = body_motions(name, mech, st)
    gx, gy = gravity
    fx, fy = force
    vk = OUTPUT_VELOCITY[name]
    out = {}
    for j in inputs:
        unit = {k: (1.0 if k == j else 0.0) for k in inputs}
        zero = {k: 0.0 for k in inputs}
        cst = _solve(name, mech, phi, unit, zero)
        coeff = body_motions(name, mech, cst)
        tau = 0.0
        for body, b in inertias.items():
            _, _, agx, agy = _com(motion[body], b)
            cvx, cvy, _, _ = _com(coeff[body], b)
            tau = tau + b.m * ((agx - gx) * cvx + (agy - gy) * cvy) + b.I * motion[body].alpha * coeff[body].omega
        if armature:
            tau = tau + armature.get(j, 0.0) * np.asarray(alpha[j], float)
        pvx = getattr(cst, vk[0])
        pvy = getattr(cst, vk[1]) if vk[1] else 0.0
        tau = tau - force_on * (fx * pvx + fy * pvy)
        out[f"tau{j}"] = np.broadcast_to(tau, np.shape(st.phi1 if name != "fivebar" else st.phi2)).copy()
    return out


_BODIES = {"fourbar": ("crank", "coupler", "rocker"), "sixbar": ("crank", "guide", "block", "rod", "ram"),
           "fivebar": ("crank2", "link3", "block", "crank4")}
