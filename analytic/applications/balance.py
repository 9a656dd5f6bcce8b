"""Balancing the shaking force with counterweights.

The shaking force of the moving links' inertia is F = -sum_k m_k a_Gk = -d^2/dt^2 (sum_k m_k r_Gk): minus the
total mass times the acceleration of the total centre of mass. A point mass m fixed to link L at (u, v) in its
frame adds -m a_c with a_c = a_O + R''(phi) (u, v) (O the link's origin, R(phi) its rotation, R'' = alpha
J R - omega^2 R), that is

    dF = -m a_O - R''(phi) (m u, m v):

linear in the counterweight's mass m and its first moment (m u, m v). On a link pivoted at the ground
(a_O = 0) only the first moment m r enters, so any mass at any radius with the same m r balances alike:
minimising the RMS shaking force over a run is a linear least-squares problem in the counterweights' first
moments (:func:`least_squares`; on a link whose origin moves, the mass m is a third unknown, kept >= 0).
Gravity and the external load add a force that does not depend on the counterweights' first moments (their
weight is m g), so balancing acts on the inertial part; the before/after figures of the full shaking force
are the forces command's.

A four-bar is fully force-balanced by counterweights on its crank and rocker alone (Berkof and Lowen, "A new
method for completely force balancing simple linkages", ASME J. Eng. Ind. 91(1):21-26, 1969: the method of
linearly independent vectors). In complex numbers, with e_k = exp(i phi_k), the crank AB (l1), coupler BC
(l2) and rocker DC (l3) and each link's first moment m_k c_k in its own frame (origins A, B, D; x-axes A->B,
B->C, D->C), the loop B - A + l2 e2 = D + l3 e3 eliminates e2 from the total first moment:

    sum m_k r_Gk = const + e1 [m1 c1 + m2 l1 (1 - c2 / l2)] + e3 [m3 c3 + m2 c2 l3 / l2],

and e1, e3 are independent along the motion, so the total centre of mass stands still if and only if

    m1 c1 = -m2 l1 (1 - c2 / l2),        m3 c3 = -m2 c2 l3 / l2

(:func:`berkof_lowen`), which holds for every four-bar: the full force balance always exists.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic._common import ParameterError
from analytic.applications.averages import closed_mean, closed_weights
from analytic.mass import Counterweight, add_counterweights

__all__ = ["Balance", "inertial_shaking", "rms", "least_squares", "berkof_lowen", "four_bar", "balance",
           "with_counterweights"]


@dataclass(frozen=True)
class Balance:
    """Counterweights (SI, each link's frame) and the RMS and peak of the inertial shaking force [N] before
    and after adding them; ``method``: "Berkof-Lowen" (a four-bar's full force balance) or "least squares"."""

    counterweights: tuple
    method: str
    before: dict
    after: dict


def inertial_shaking(mech, sol, inertias: dict) -> tuple[np.ndarray, np.ndarray]:
    """The shaking force of the links' inertia alone, -sum m_k a_Gk [N] (no gravity, no external load)."""
    fx = fy = 0.0
    for ln, b in inertias.items():
        o = mech.link_origins[ln]
        c, s = sol["cos" + ln], sol["sin" + ln]
        w, al = sol["omega" + ln], sol["alpha" + ln]
        rx, ry = b.cx * c - b.cy * s, b.cx * s + b.cy * c
        fx = fx - b.m * (sol["ax" + o] - al * ry - w * w * rx)
        fy = fy - b.m * (sol["ay" + o] + al * rx - w * w * ry)
    return np.asarray(fx, dtype=float), np.asarray(fy, dtype=float)


def rms(fx, fy) -> dict:
    """{"rms", "peak"} of a force's magnitude over the samples [N]."""
    mag2 = np.asarray(fx) ** 2 + np.asarray(fy) ** 2
    return {"rms": float(np.sqrt(closed_mean(mag2))), "peak": float(np.sqrt(np.max(mag2)))}


def _reach(mech, link: str, local: dict | None) -> float:
    """How far a counterweight sits from the link's origin: its farthest point (the link's length)."""
    from analytic.mass import local_points
    pts = (local or local_points(mech))[link]
    return max((math.hypot(u, v) for u, v in pts.values()), default=0.0) or mech.size


def _weight(link: str, mx: float, my: float, mass: float | None, radius: float, scale: float) -> Counterweight | None:
    """A counterweight of first moment (mx, my): of ``mass`` (a moving link), or at ``radius`` (a pivoted one);
    None when the first moment is negligible."""
    if mass is not None:
        if mass <= 1e-12 * scale:
            return None
        return Counterweight(link, float(mass), float(mx / mass), float(my / mass))
    mr = math.hypot(mx, my)
    if mr <= 1e-12 * scale:
        return None
    return Counterweight(link, float(mr / radius), float(mx / mr * radius), float(my / mr * radius))


def least_squares(mech, sol, inertias: dict, links=None, local=None) -> tuple[Counterweight, ...]:
    """Counterweights on ``links`` (default: every link pivoted at a ground point) minimising the RMS
    inertial shaking force over the samples of ``sol`` (a solution with each link's cos, sin, omega, alpha
    and the points' accelerations). Unknowns: (m u, m v) per pivoted link, (m, m u, m v) per link whose origin
    moves (dropped from the fit, one at a time, while the best m is negative)."""
    origins = mech.link_origins
    ground = set(mech.ground_points)
    links = list(links) if links else [ln for ln in mech.links if origins[ln] in ground]
    unknown = [ln for ln in links if ln not in mech.links]
    if unknown:
        raise ParameterError(f"--balance: the {mech.name} has no link {unknown[0]!r}; links: {', '.join(mech.links)}")
    if not links:
        raise ParameterError(f"--balance: the {mech.name} has no link pivoted at the ground; name the links to "
                             f"carry counterweights (--balance LINK,LINK)")
    fx, fy = inertial_shaking(mech, sol, inertias)
    root = np.sqrt(np.tile(closed_weights(len(np.atleast_1d(fx))), 2))    # the closed run's end counted once
    target = -np.concatenate([fx, fy]) * root
    scale = max(sum(b.m for b in inertias.values()) * mech.size, 1e-300)
    active = list(links)
    while True:
        cols, keys = [], []
        for ln in active:
            c, s = sol["cos" + ln], sol["sin" + ln]
            w, al = sol["omega" + ln], sol["alpha" + ln]
            cols.append(np.concatenate([al * s + w * w * c, -al * c + w * w * s]))      # d F / d(m u)
            cols.append(np.concatenate([al * c - w * w * s, al * s + w * w * c]))       # d F / d(m v)
            keys += [(ln, "mu"), (ln, "mv")]
            if origins[ln] not in ground:
                o = origins[ln]
                cols.append(-np.concatenate([sol["ax" + o], sol["ay" + o]]))           # d F / d m
                keys.append((ln, "m"))
        x = np.linalg.lstsq(np.stack(cols, axis=1) * root[:, None], target, rcond=None)[0] if cols else np.zeros(0)
        got = dict(zip(keys, x))
        negative = [ln for ln in active if got.get((ln, "m"), 0.0) < 0]
        if not negative:
            break
        active.remove(negative[0])
    out = []
    for ln in active:
        cw = _weight(ln, got[(ln, "mu")], got[(ln, "mv")], got.get((ln, "m")), _reach(mech, ln, local), scale)
        if cw is not None:
            out.append(cw)
    return tuple(out)


def four_bar(mech):
    """(crank, coupler, rocker, l1, l2, l3) when ``mech`` is a four-bar (a crank, an RRR joining the crank's
    tip to a ground point, rigid points), else None."""
    elements = mech.geometry.elements
    kinds = [e["kind"] for e in elements]
    if kinds.count("crank") != 1 or kinds.count("RRR") != 1 or set(kinds) - {"crank", "RRR", "point"}:
        return None
    crank = next(e for e in elements if e["kind"] == "crank")
    rrr = next(e for e in elements if e["kind"] == "RRR")
    (p, q), (m, n), (a, b) = rrr["from"], rrr["links"], rrr["lengths"]
    ground = set(mech.ground_points)
    if p == crank["point"] and q in ground:
        coupler, rocker, l2, l3 = m, n, a, b
    elif q == crank["point"] and p in ground:
        coupler, rocker, l2, l3 = n, m, b, a
    else:
        return None
    if len(mech.links) != 3:
        return None
    return crank["link"], coupler, rocker, crank["length"], l2, l3


def berkof_lowen(mech, inertias: dict, local=None) -> tuple[Counterweight, ...] | None:
    """The counterweights on the crank and rocker that fully force-balance a four-bar (Berkof and Lowen
    1969, see the module docstring), each at the link's length from its pivot; None if ``mech`` is not a
    four-bar."""
    fb = four_bar(mech)
    if fb is None:
        return None
    crank, coupler, rocker, l1, l2, l3 = fb
    m1, m2, m3 = (inertias[k] for k in (crank, coupler, rocker))
    c2 = complex(m2.cx, m2.cy)
    need1 = -m2.m * l1 * (1 - c2 / l2)
    need3 = -m2.m * c2 * l3 / l2
    scale = max(sum(b.m for b in inertias.values()) * mech.size, 1e-300)
    out = []
    for link, b, need in ((crank, m1, need1), (rocker, m3, need3)):
        add = need - b.m * complex(b.cx, b.cy)
        cw = _weight(link, add.real, add.imag, None, _reach(mech, link, local), scale)
        if cw is not None:
            out.append(cw)
    return tuple(out)


def with_counterweights(inertias: dict, weights) -> dict:
    """The mass model with counterweights added to their links."""
    out = dict(inertias)
    for w in weights:
        out[w.link] = add_counterweights(out[w.link], [w])
    return out


def balance(mech, sol, inertias: dict, links=None, local=None) -> Balance:
    """Counterweights for ``mech`` with their before/after: a four-bar's full force balance (Berkof-Lowen)
    unless ``links`` names others; else the least-squares counterweights on ``links`` (default: the links
    pivoted at the ground)."""
    fb = four_bar(mech)
    if fb is not None and (not links or set(links) == {fb[0], fb[2]}):
        weights, method = berkof_lowen(mech, inertias, local), "Berkof-Lowen"
    else:
        weights, method = least_squares(mech, sol, inertias, links, local), "least squares"
    before = rms(*inertial_shaking(mech, sol, inertias))
    after = rms(*inertial_shaking(mech, sol, with_counterweights(inertias, weights)))
    return Balance(weights, method, before, after)
