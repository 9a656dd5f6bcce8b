"""An independent generic solver for the tests: Newton's method on vector-loop equations.

A loop is a list of terms ``(sign, r, theta)``; each of ``r`` and ``theta`` is a float (constant) or the
name of a coordinate. The loop equation is  sum(sign * r * e^{i theta}) = 0  (real and imaginary rows).
Given the input coordinates and their first two derivatives, :func:`solve_loops` finds the dependent
coordinates by Newton iteration with the exact Jacobian, then their rates from the differentiated loops:

    J_dep qd_dep = -J_in qd_in
    J_dep qdd_dep = -J_in qdd_in - sum sign * (2 i rd thetad - r thetad^2) e^{i theta}

It shares nothing with ``analytic/`` beyond the mechanism's loop written as terms.
"""

import numpy as np


def _value(x, coords):
    return coords[x] if isinstance(x, str) else x


def _residual(loops, q):
    rows = []
    for loop in loops:
        z = sum(sign * _value(r, q) * np.exp(1j * _value(th, q)) for sign, r, th in loop)
        rows += [z.real, z.imag]
    return np.stack(rows, -1)


def _jacobian(loops, q, names):
    """d(residual)/d(names), shape (..., 2 * len(loops), len(names))."""
    cols = []
    for name in names:
        rows = []
        for loop in loops:
            dz = 0.0
            for sign, r, th in loop:
                e = np.exp(1j * _value(th, q))
                if r == name:
                    dz = dz + sign * e
                if th == name:
                    dz = dz + sign * 1j * _value(r, q) * e
            dz = dz + np.zeros_like(q[names[0]])
            rows += [dz.real, dz.imag]
        cols.append(np.stack(rows, -1))
    return np.stack(cols, -1)


def solve_loops(loops, inputs, guess, iterations=50):
    """Solve ``loops`` for the dependent coordinates.

    inputs: {name: (q, qd, qdd)} arrays of one shape; guess: {name: q0} for the dependent coordinates.
    Returns ({name: q}, {name: qd}, {name: qdd}) for the dependent coordinates.
    """
    dep = list(guess)
    q = {k: np.asarray(v[0], float) for k, v in inputs.items()}
    q.update({k: np.array(v, float) for k, v in guess.items()})
    for _ in range(iterations):
        f = _residual(loops, q)
        step = np.linalg.solve(_jacobian(loops, q, dep), f[..., None])[..., 0]
        for i, k in enumerate(dep):
            q[k] = q[k] - step[..., i]
        if np.max(np.abs(step)) < 1e-15:
            break
    jd = _jacobian(loops, q, dep)
    ji = _jacobian(loops, q, list(inputs))
    qd_in = np.stack([v[1] * np.ones_like(v[0]) for v in inputs.values()], -1)[..., None]
    qdd_in = np.stack([v[2] * np.ones_like(v[0]) for v in inputs.values()], -1)[..., None]
    qd_dep = np.linalg.solve(jd, -ji @ qd_in)[..., 0]
    qd = {k: np.asarray(v[1], float) * np.ones_like(q[k]) for k, v in inputs.items()}
    qd.update({k: qd_dep[..., i] for i, k in enumerate(dep)})
    rows = []
    for loop in loops:
        z = 0.0
        for sign, r, th in loop:
            rd = qd[r] if isinstance(r, str) else 0.0
            thd = qd[th] if isinstance(th, str) else 0.0
            z = z + sign * (2j * rd * thd - _value(r, q) * thd ** 2) * np.exp(1j * _value(th, q))
        rows += [z.real, z.imag]
    quad = np.stack(rows, -1)[..., None]
    qdd_dep = np.linalg.solve(jd, -ji @ qdd_in - quad)[..., 0]
    return ({k: q[k] for k in dep}, {k: qd_dep[..., i] for i, k in enumerate(dep)},
            {k: qdd_dep[..., i] for i, k in enumerate(dep)})
