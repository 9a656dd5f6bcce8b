"""``motor_dyad``: a motor between two moving links that no earlier element places (an input): the bent link
P-pivot-point, its two links at the driven angle q, closed to a placed pin C by a third link point-C.

Fields: ``name`` (its input's name: columns ``q_NAME``, ``dq_NAME``, ``ddq_NAME``), ``pivot`` (the motor's
joint, a new point), ``point`` (the new point where the closing link is pinned), ``from`` [P, C] (placed
points: P the first link's pivot, C the closing link's), ``lengths`` [|P pivot|, |pivot point|], ``length``
(|point C|), ``links`` [first, second] (P-pivot and pivot-point, default ``{P}{pivot}``, ``{pivot}{point}``),
``closing`` (the link point-C, default ``{point}{C}``), ``on`` (which of ``links`` the motor's housing is on,
default the first; the other is the driven ``link``), ``branch`` (+1: point left of the directed line P -> C)
and the motion law ``q(t) = q0 + omega t + alpha t^2 / 2`` of the relative angle ``q = phi(link) - phi(on)``.

At each sample the two links are one rigid body of known shape: its side |P point| = d(q) by the law of
cosines, d^2 = a^2 + b^2 + 2 a b cos(theta) (theta = phi(second) - phi(first), +q or -q as ``on`` says). The
point is then the RRR dyad's circle-circle intersection from P (radius d(q), driven) and C (radius
``length``), in closed form with exact rates (:func:`analytic.kinds.actuator.actuated`), and the first link's
angle that of P -> point less the angle gamma(theta) the side makes with the first link. Its drive is the
torque the motor puts on ``link``; the reaction (the motor's housing) acts on ``on``.
"""

from __future__ import annotations

import math

import numpy as np

from .actuator import actuated
from .base import Field, Kind, LinkPart, State, Structure, on_frame


def roles(f: dict) -> tuple[str, str, int]:
    """(on, link, s): the motor's carrier and driven link, and s = +1 where the carrier is the first link
    (theta = phi(second) - phi(first) = s q)."""
    first, second = f["links"]
    on = f["on"] or first
    return (first, second, 1) if on == first else (second, first, -1)


def bent(a, b, th, thd, thdd):
    """The side d = |P point| of the bent link (|P pivot| = a, |pivot point| = b at the angle theta between
    them) and the angle gamma of P -> point from the first link, each with its first two time derivatives.

    d^2 = a^2 + b^2 + 2 a b cos(theta), so d' = -a b sin(theta) theta' / d and
    d'' = (-a b (cos(theta) theta'^2 + sin(theta) theta'') - d'^2) / d. gamma = atan2(b sin, a + b cos):
    gamma' = g theta' with g = b (b + a cos(theta)) / d^2, gamma'' = g theta'' + a b sin(theta) (b^2 - a^2)
    theta'^2 / d^4."""
    c, s = np.cos(th), np.sin(th)
    d2 = a * a + b * b + 2 * a * b * c
    d = np.sqrt(d2)
    dd = -a * b * s * thd / d
    ddd = (-a * b * (c * thd * thd + s * thdd) - dd * dd) / d
    g = b * (b + a * c) / d2
    gd = g * thd
    gdd = g * thdd + a * b * s * (b * b - a * a) * thd * thd / (d2 * d2)
    return (d, dd, ddd), (np.arctan2(b * s, a + b * c), gd, gdd)


class MotorDyad(Kind):
    name = "motor_dyad"
    section = "inputs"
    summary = ("a motor between two moving links no earlier element places: the bent link P-pivot-point (its "
               "two links at the driven angle q = phi(link) - phi(on)) closed to C by the link point-C")
    group_class = "dyad RRR over a bent link with a driven angle (class II)"
    angular = True
    columns = ("q", "dq", "ddq")
    motion_fields = ("q0", "omega", "alpha")
    fields = {"name": Field("link", "{pivot}"), "pivot": Field("new"), "point": Field("new"),
              "from": Field("pair"), "lengths": Field("lengths2"), "length": Field("size"),
              "links": Field("links2", ("{from0}{pivot}", "{pivot}{point}")),
              "closing": Field("link", "{point}{from1}"), "on": Field("word", ""),
              "q0": Field("angle", 0.0), "omega": Field("angle", 2 * math.pi), "alpha": Field("angle", 0.0),
              "branch": Field("branch", 1)}

    def default_rate(self, size):
        """One turn per second, as a crank's."""
        return "omega", "360deg"

    def input_key(self, e):
        """``_NAME``: its columns are ``q_NAME dq_NAME ddq_NAME``, its drive ``tau_NAME``."""
        return "_" + e["name"]

    def places(self, f):
        return (f["pivot"], f["point"])

    def needs(self, f):
        return tuple(f["from"])

    def check(self, f):
        if f["pivot"] == f["point"]:
            return f"field 'point': the motor's pivot and the closing link's pin are both {f['point']!r}; name two points"
        if f["on"] and f["on"] not in f["links"]:
            return (f"field 'on': {f['on']!r} is not one of the motor's links {', '.join(f['links'])}; name the link "
                    f"its housing is on")
        if f["closing"] in f["links"]:
            return f"field 'closing': {f['closing']!r} is also one of 'links'; name the closing link apart"
        return None

    def structure(self, f):
        (p, c), j, q = f["from"], f["pivot"], f["point"]
        first, second = f["links"]
        on, link, _ = roles(f)
        parts = (LinkPart(first, p, (p, j)), LinkPart(second, j, (j, q)))
        if on == second:            # the carrier first at the pivot: the topology joins a driven pin's base to it
            parts = parts[::-1]
        return Structure(links=parts + (LinkPart(f["closing"], c, (c, q)),), driven_pin=(j, link, on))

    def input_joint(self, e):
        return e["pivot"]

    def solve(self, e, st: State):
        j = e["input"]
        _, _, sign = roles(e)
        th, thd, thdd = sign * st.q[j], sign * st.qd[j], sign * st.qdd[j]
        (p, c) = e["from"]
        a, b = e["lengths"]
        (d, dd, ddd), (gam, gd, gdd) = bent(a, b, th, thd, thdd)
        # the point at |point C| = length and |point P| = d(q): the actuator's dyad (C first: the point is left of
        # C -> P for its branch +1, i.e. right of P -> C, hence -branch)
        (Q, closing, side), _ = actuated(st.points[c], st.points[p], e["length"], d, dd, ddd, -e["branch"])
        ce, se, w2, al2 = side                       # P -> point
        cg, sg = np.cos(gam), np.sin(gam)
        c1, s1 = ce * cg + se * sg, se * cg - ce * sg
        w1, a1 = w2 - gd, al2 - gdd
        ct, stt = np.cos(th), np.sin(th)
        first, second = e["links"]
        st.points[e["pivot"]] = on_frame(st.points[p], c1, s1, w1, a1, a, 0.0)
        st.points[e["point"]] = Q
        st.links[first] = (c1, s1, w1, a1)
        st.links[second] = (c1 * ct - s1 * stt, s1 * ct + c1 * stt, w1 + thd, a1 + thdd)
        st.links[e["closing"]] = closing

    def measured_extras(self, e, st):
        """Its rate and acceleration from the measured links (its angle is the hinge's)."""
        on, link, _ = roles(e)
        _, _, w, a = st.links[link]
        _, _, w0, a0 = st.links[on]
        key = self.input_key(e)
        return {self.columns[1] + key: w - w0, self.columns[2] + key: a - a0}

    def singularity(self, e, st, size):
        """The dyad's: the sine of the angle between the closing link and the side P -> point."""
        c1, s1, _, _ = st.links[e["closing"]]
        p = st.points[e["from"][0]]
        q = st.points[e["point"]]
        rx, ry = q[0] - p[0], q[1] - p[1]
        r = np.hypot(rx, ry)
        return np.abs(c1 * ry - s1 * rx) / r


KIND = MotorDyad()
