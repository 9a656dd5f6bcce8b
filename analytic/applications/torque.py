"""Driving forces of any mechanism by virtual work (inverse dynamics from the kinematics).

For driven inputs q_j and rigid links k of mass m_k, centre of mass G_k and moment of inertia I_k
about G_k (z axis), the force (torque for a crank, force for a slider) on input j is

    tau_j = sum_k [ m_k (a_Gk - g) . dv_Gk/dqdot_j  +  I_k alpha_k  domega_k/dqdot_j ]
            + J_j qdd_j  -  F . dv_P/dqdot_j

The velocity coefficients dv/dqdot_j are the velocities with input j at unit rate, the others at rest
and no acceleration (the general solver evaluated so); J_j is the drive's rotor inertia, g the gravity
in the plane and F an external force on the output point P. It is the power balance
tau . qdot = dT/dt + dV/dt - F . v_P written per input, and stays regular where an input is at rest.
Each link's frame is its origin point and its angle (:attr:`Mechanism.link_origins`).
"""

from __future__ import annotations

import numpy as np

from analytic._common import ParameterError


def _com(sol, origin: str, link: str, b):
    """Velocity and acceleration of link ``link``'s centre of mass ``b`` (cx, cy in its frame)."""
    c, s = sol["cos" + link], sol["sin" + link]
    rx, ry = b.cx * c - b.cy * s, b.cx * s + b.cy * c
    w, a = sol["omega" + link], sol["alpha" + link]
    return (sol["vx" + origin] - w * ry, sol["vy" + origin] + w * rx,
            sol["ax" + origin] - a * ry - w * w * rx, sol["ay" + origin] + a * rx - w * w * ry)


def drive_forces(mech, q, qd, qdd, inertias: dict, armature: dict | None = None, gravity=(0.0, 0.0),
                 force=(0.0, 0.0), force_on=1.0, sol=None, coefficients=None) -> dict[str, np.ndarray]:
    """Force of each input [N m for a crank, N for a slider], keyed by the input's link name.

    Parameters
    ----------
    q, qd, qdd : array_like, shape (N,) or (N, n_inputs)
        The inputs' positions, rates and accelerations.
    inertias : dict
        :class:`~analytic.mass.Inertia` per link name (links not named are massless).
    armature : dict, optional
        Rotor inertia [kg m^2 or kg] of each input's drive, keyed by its link.
    gravity, force : (x, y)
        Gravity in the plane [m/s^2]; external force [N] on the output point, times ``force_on``.
    sol, coefficients : optional
        The solution at (q, qd, qdd) and each input's velocity coefficients there (the solution with that
        input at unit rate, the others at rest, no acceleration), as
        :func:`analytic.cycle.solve_with_coefficients` gives them; solved here when None.
    """
    unknown = set(inertias) - set(mech.links)
    if unknown:
        raise ParameterError(f"no link named {', '.join(sorted(unknown))} in the {mech.name}; links: "
                             f"{', '.join(mech.links)}")
    k = len(mech.inputs)
    q, qd, qdd = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (q, qd, qdd)))
    if k == 1 and not (q.ndim >= 2 and q.shape[-1] == 1):
        q, qd, qdd = q[..., None], qd[..., None], qdd[..., None]
    shape = q.shape[:-1]
    q, qd, qdd = (x.reshape(-1, k) for x in (q, qd, qdd))
    force_on = np.broadcast_to(np.asarray(force_on, dtype=float), shape).reshape(-1)
    if sol is None or coefficients is None:
        from analytic.cycle import solve_with_coefficients
        sol, coefficients = solve_with_coefficients(mech, q, qd, qdd)
    origins = mech.link_origins
    gx, gy = gravity
    fx, fy = force
    p = mech.output_point
    out = {}
    for j, inp in enumerate(mech.inputs):
        coeff = coefficients[j]
        tau = np.zeros(q.shape[:-1])
        for link, b in inertias.items():
            _, _, agx, agy = _com(sol, origins[link], link, b)
            cvx, cvy, _, _ = _com(coeff, origins[link], link, b)
            tau = tau + b.m * ((agx - gx) * cvx + (agy - gy) * cvy) + b.I * sol["alpha" + link] * coeff["omega" + link]
        if armature:
            tau = tau + armature.get(inp.link, 0.0) * qdd[..., j]
        tau = tau - force_on * (fx * coeff["vx" + p] + fy * coeff["vy" + p])
        out[inp.link] = tau.reshape(shape)
    return out
