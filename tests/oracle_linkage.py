"""An independent oracle for any ``linkage/1`` mechanism: Newton's method on the whole constraint system.

It shares nothing with ``analytic/solver/kinematics.py`` or its group formulas. It reads only the resolved data
of a file (``Mechanism.geometry``: ground points and the elements' numeric fields, SI units) and writes
two scalar constraint equations per element, in the element's own point (x, y):

* ``crank``   P = pivot + r (cos q, sin q)
* ``slider``  P = O + q u                              (u: unit direction of the ground guide)
* ``actuator`` |D - A|^2 = length^2,  |D - C|^2 = q^2  (the cylinder's pin-to-pin length is the input)
* ``motor``   P = pivot + r (cos psi, sin psi), psi = phi_on + q (the carrier's angle as for a gear)
* ``motor_dyad`` (two points, four rows) |J - P|^2 = a^2,  R - J = (b / a) rot(theta) (J - P),  |R - C|^2 = c^2
              (J its pivot, R its point, theta = q where ``on`` is its first link, -q where its second)
* ``RRR``     |C - P|^2 = a^2,  |C - Q|^2 = b^2
* ``RRP``     |C - P|^2 = l^2,  cross(u, C - O) = offset   (O, u: the guide line, possibly moving)
* ``RPR``     |R - P|^2 = l^2,  cross(R - P, Q - P) = l * offset
              (Q - P = s u + offset u_perp with u = (R - P)/l, so cross(u, Q - P) = offset)
* ``point``   R = P + u e + v e_perp                   (e: unit vector P -> Q, or a named link's x-axis)
* ``gear``    R = pivot + l (cos psi, sin psi), psi = phi_c + phase + ratio (phi_a - phi_c): the gear's
              angle from the relation between the carrier's (c) and the mesh link's (a) angles, each
              measured from its own points (a crank's: its input angle, counted in turns; a gear's: its
              own psi; the ground's 0; any other link's atan2 of its frame, in (-pi, pi], relative to the
              carrier when neither angle counts turns)
* ``cam``     translating: R = A + e n + (d0 + h(theta)) u (u the guide's direction, n = u turned a quarter,
              e = cross(u, O - A) the guide's offset, d0 = sqrt((r_b + r_r)^2 - e^2), or r_b for a flat face);
              oscillating: R = B + arm (cos psi, sin psi), psi = psi0 + h(theta), psi0 the arm angle where
              |R - A| = r_b + r_r on the side where a counter-clockwise turn of the arm moves R away from A
              (law of cosines, here); theta the cam link's angle and h the file's lift law evaluated with
              :mod:`analytic.laws` (its own tests check it against Norton's closed forms), composed with the
              jet: h(theta) = h + h' theta1 t + (h' theta2 + h'' theta1^2 / 2) t^2
* ``PRP``     cross(u1, C - O1) = offset1,  cross(u2, C - O2) = offset2   (C on both shifted guide lines)
* ``RPP``     cross(u, C - O) = offset,  cross(v, P - C) = 0   (C on the shifted guide; the pin P on the slot
              through C, v = u turned by the slot's angle); ``PPR`` the same with its pin Q
* ``group``   per link p0, p1, p2...: |p1 - p0|^2 = L^2 and pk = p0 + u e + v e_perp (e: unit p0 -> p1), with
              L, u, v measured here from the file's pose; two rows per point the group places.
              With ``slides`` (prismatic pairs), a link whose frame is not p0 -> p1 (a block: along its slide;
              a link of one point: along the slide it guides) gets an axis point X (two more unknowns):
              |X - p0|^2 = D^2 (D: the pose's size) and pk = p0 + u e + v e_perp for k >= 1 with
              e = (X - p0) / D; each pair (block b, guide g: a link of the group, a placed link's points
              P -> Q, or the ground) adds cross(R(rel) e_g, e_b) = 0 (the block keeps its angle rel to the
              guide, both from the pose) and cross(e_b, B - O_g - c_u e_g - c_v e_g_perp) = 0 (the block's
              point B on the guide's line through where the pose puts it; c: its pose coordinates in the
              guide's frame)

All unknowns are solved together: ``F(x; q) = 0`` for all samples at once (batched 2n x 2n systems).

Derivatives are exact, with no finite differences: every equation is evaluated on truncated Taylor
series in time (:class:`Jet`, coefficients of 1, t, t^2). Along a motion x(t) = x + xd t + xdd t^2/2,
q(t) = q + qd t + qdd t^2/2 the constraint's coefficients are

    F1 = J xd + F_q qd                 = 0   ->  xd  = -J^-1 (F_q qd)
    F2 = (J xdd + F_q qdd + D2F[w, w])/2 = 0  ->  xdd = -2 J^-1 F2|_(xdd = 0)

and the Jacobian J itself is F1 with unit seeds (forward-mode differentiation). Newton starts from a
given guess (the caller perturbs the analytic solution) and the branch it lands on is then checked
against the file's conventions independently of the solver: RRR branch +1 puts C left of P->Q
(cross(Q - P, C - P) > 0); RRP branch +1 takes the intersection farther along the guide
(dot(C - P, u) > 0); RPR branch +1 puts R on the side of Q (dot(R - P, Q - P) > 0); a group keeps the
sign its equations' Jacobian (in the points it places, rows as written above) has at the file's pose.
"""

from __future__ import annotations

import math

import numpy as np


# ----------------------------------------------------------------------------------------------- jets
class Jet:
    """A truncated Taylor series c0 + c1 t + c2 t^2 with array coefficients (one per sample)."""

    __slots__ = ("c0", "c1", "c2")

    def __init__(self, c0, c1=0.0, c2=0.0):
        self.c0, self.c1, self.c2 = c0, c1, c2

    @staticmethod
    def lift(x):
        return x if isinstance(x, Jet) else Jet(x)

    def __add__(self, o):
        o = Jet.lift(o)
        return Jet(self.c0 + o.c0, self.c1 + o.c1, self.c2 + o.c2)

    __radd__ = __add__

    def __sub__(self, o):
        o = Jet.lift(o)
        return Jet(self.c0 - o.c0, self.c1 - o.c1, self.c2 - o.c2)

    def __rsub__(self, o):
        return Jet.lift(o) - self

    def __neg__(self):
        return Jet(-self.c0, -self.c1, -self.c2)

    def __mul__(self, o):
        o = Jet.lift(o)
        return Jet(self.c0 * o.c0, self.c0 * o.c1 + self.c1 * o.c0,
                   self.c0 * o.c2 + self.c1 * o.c1 + self.c2 * o.c0)

    __rmul__ = __mul__

    def __truediv__(self, o):
        o = Jet.lift(o)
        q0 = self.c0 / o.c0
        q1 = (self.c1 - q0 * o.c1) / o.c0
        q2 = (self.c2 - q0 * o.c2 - q1 * o.c1) / o.c0
        return Jet(q0, q1, q2)


def jsqrt(a: Jet) -> Jet:
    s0 = np.sqrt(a.c0)
    s1 = a.c1 / (2.0 * s0)
    return Jet(s0, s1, (a.c2 - s1 * s1) / (2.0 * s0))


def jcos(a: Jet) -> Jet:
    c, s = np.cos(a.c0), np.sin(a.c0)
    return Jet(c, -s * a.c1, -s * a.c2 - 0.5 * c * a.c1 * a.c1)


def jsin(a: Jet) -> Jet:
    c, s = np.cos(a.c0), np.sin(a.c0)
    return Jet(s, c * a.c1, c * a.c2 - 0.5 * s * a.c1 * a.c1)


def jatan2(ex: Jet, ey: Jet) -> Jet:
    """The angle of a unit vector (ex, ey): e1 = th1 e_perp and e2 = th2 e_perp - th1^2 e / 2 give
    th1 = cross(e0, e1), th2 = cross(e0, e2)."""
    ex, ey = Jet.lift(ex), Jet.lift(ey)
    return Jet(np.arctan2(ey.c0, ex.c0), ex.c0 * ey.c1 - ey.c0 * ex.c1, ex.c0 * ey.c2 - ey.c0 * ex.c2)


def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


def _dot(ax, ay, bx, by):
    return ax * bx + ay * by


def _unit(P, Q):
    dx, dy = Q[0] - P[0], Q[1] - P[1]
    n = jsqrt(Jet.lift(dx * dx + dy * dy))
    return dx / n, dy / n


# ---------------------------------------------------------------------------------------- equations
def _slot(e, u):
    """The slot's unit direction of an RPP or PPR: the guide's ``u`` turned by its ``angle``."""
    ca, sa = math.cos(e["angle"]), math.sin(e["angle"])
    return u[0] * ca - u[1] * sa, u[0] * sa + u[1] * ca


def _guide(G, pts):
    """(origin, unit direction) of a guide: the line P->Q of two points, or a ground line."""
    if "points" in G:
        p, q = G["points"]
        return pts[p], _unit(pts[p], pts[q])
    through = G["through"]
    O = pts[through] if isinstance(through, str) else (Jet(float(through[0])), Jet(float(through[1])))
    return O, (Jet(math.cos(G["angle"])), Jet(math.sin(G["angle"])))


def _frame(geometry, on, pts):
    """(origin, unit x-axis) of the frame a ``point`` is given in: two points P -> Q, or a link by name (SPEC:
    origin its first point, x-axis its angle: the direction first point -> second point as the file lists
    them; a block's: its pin, along its guide; the slotted link of an RPR: pivot, along the slot)."""
    if not isinstance(on, str):
        P, Qp = (pts[n] for n in on)
        return P, _unit(P, Qp)
    for e in geometry.elements:
        k = e["kind"]
        if k == "crank" and e["link"] == on:
            return pts[e["pivot"]], _unit(pts[e["pivot"]], pts[e["point"]])
        if k == "actuator" and on == e["link"]:
            return pts[e["from"][0]], _unit(pts[e["from"][0]], pts[e["point"]])
        if k == "actuator" and on in e["cylinder"]:
            P = pts[e["from"][1]] if on == e["cylinder"][0] else pts[e["point"]]
            return P, _unit(pts[e["from"][1]], pts[e["point"]])
        if k == "motor" and e["link"] == on:
            return pts[e["pivot"]], _unit(pts[e["pivot"]], pts[e["point"]])
        if k == "slider" and e["link"] == on:
            return pts[e["point"]], _guide(e["guide"], pts)[1]
        if k == "RRR" and on in e["links"]:
            P = pts[e["from"][e["links"].index(on)]]
            return P, _unit(P, pts[e["point"]])
        if k == "RRP" and on == e["links"][0]:
            return pts[e["from"]], _unit(pts[e["from"]], pts[e["point"]])
        if k == "RRP" and on == e["links"][1]:
            return pts[e["point"]], _guide(e["guide"], pts)[1]
        if k == "RPR" and on in e["links"]:
            P = pts[e["pivot"]] if on == e["links"][0] else pts[e["through"]]
            return P, _unit(pts[e["pivot"]], pts[e["point"]])
        if k == "gear" and e["link"] == on:
            return pts[e["pivot"]], _unit(pts[e["pivot"]], pts[e["point"]])
        if k == "cam" and on == e["links"][0]:
            if e["follower"] == "translating":
                return pts[e["point"]], _guide(e["guide"], pts)[1]
            return pts[e["arm_pivot"]], _unit(pts[e["arm_pivot"]], pts[e["point"]])
        if k == "PRP" and on in e["links"]:            # a block: its pin, along its guide
            return pts[e["point"]], _guide(e["guide" + str(e["links"].index(on) + 1)], pts)[1]
        if k in ("RPP", "PPR") and on in e["links"]:   # the link on the guide: C, along it; the pin block: its pin, along the slot
            u = _guide(e["guide"], pts)[1]
            on_guide = on == e["links"][1 if k == "RPP" else 0]
            return (pts[e["point"]], u) if on_guide else (pts[e["through"]], _slot(e, u))
        if k == "group" and on in e["links"]:
            return _group_frame(e, on, pts)
    raise ValueError(f"no link named {on!r}")


def _link_angle(geometry, link, pts, Q):
    """(angle of ``link`` as a Jet, whether it counts whole turns): the ground 0; a crank its input angle
    (its equation is written with it); a gear its psi; any other link atan2 of its frame's x-axis."""
    if link == "ground":
        return Jet(0.0), True
    for e in geometry.elements:
        if e["kind"] == "crank" and e["link"] == link:
            return Q[e["input"]], True
        if e["kind"] == "gear" and e["link"] == link:
            return _gear_angle(geometry, e, pts, Q), True
    _, (ex, ey) = _frame(geometry, link, pts)
    return jatan2(ex, ey), False


def _gear_angle(geometry, e, pts, Q):
    """psi = phi_c + phase + ratio (phi_a - phi_c) of a gear element (see the module docstring)."""
    phi_c, turns_c = _link_angle(geometry, e["carrier"], pts, Q)
    phi_a, turns_a = _link_angle(geometry, e["mesh"], pts, Q)
    theta = phi_a - phi_c
    if not (turns_a or turns_c):           # both in (-pi, pi]: their difference reduced to (-pi, pi]
        theta = Jet(theta.c0 - 2 * np.pi * np.round(theta.c0 / (2 * np.pi)), theta.c1, theta.c2)
    return phi_c + e["phase"] + e["ratio"] * theta


def _cam_lift(e, theta: Jet) -> Jet:
    """The file's lift law h(theta) composed with the cam angle's jet."""
    h, h1, h2, _ = e["segments"].at(np.mod(theta.c0, 2 * np.pi))
    return Jet(h, h1 * theta.c1, h1 * theta.c2 + 0.5 * h2 * theta.c1 * theta.c1)


def _cam_rows(geometry, e, pts, Q, R):
    A = pts[e["pivot"]]
    (_, (ex, ey)) = _frame(geometry, e["cam"], pts)
    theta = jatan2(ex, ey)
    h = _cam_lift(e, theta)
    prime = e["base_radius"] + (e["roller"] if e["contact"] == "roller" else 0.0)
    if e["follower"] == "translating":
        O, (ux, uy) = _guide(e["guide"], pts)
        off = _cross(ux.c0, uy.c0, O[0].c0 - A[0].c0, O[1].c0 - A[1].c0)
        d0 = e["base_radius"] if e["contact"] == "flat" else np.sqrt(prime ** 2 - off ** 2)
        d = h + d0
        return [R[0] - A[0] + off * uy - d * ux, R[1] - A[1] - off * ux - d * uy]
    B = pts[e["arm_pivot"]]
    bx, by = float(np.ravel(B[0].c0)[0]), float(np.ravel(B[1].c0)[0])
    ax, ay = float(np.ravel(A[0].c0)[0]), float(np.ravel(A[1].c0)[0])
    D, a = math.hypot(ax - bx, ay - by), e["arm"]
    g = math.acos((a * a + D * D - prime * prime) / (2 * a * D))
    base = math.atan2(ay - by, ax - bx)
    psi0 = next(p for p in (base - g, base + g)
                if _cross(math.cos(p), math.sin(p), bx + a * math.cos(p) - ax, by + a * math.sin(p) - ay) > 0)
    psi = h + psi0
    return [R[0] - B[0] - a * jcos(psi), R[1] - B[1] - a * jsin(psi)]


def _group_theta0(e) -> dict:
    """Each group link's frame angle at the pose by the file's conventions, and which links need an axis
    point (a block: its slide's angle; two or more points: p0 -> p1; one point: the slide it guides)."""
    pose, sl = e["pose"], e.get("slides", {})
    out, aux = {}, set()
    for ln, names in e["links"].items():
        if ln in sl:
            out[ln] = float(sl[ln][2])
            aux.add(ln)
        elif len(names) >= 2:
            (ax, ay), (bx, by) = pose[names[0]], pose[names[1]]
            out[ln] = math.atan2(by - ay, bx - ax)
        else:
            out[ln] = float(next(a for g, _, a in sl.values() if g == ln))
            aux.add(ln)
    return out, aux


def _size(e) -> float:
    xy = np.array([[float(x), float(y)] for x, y in e["pose"].values()])
    return float(np.max(np.hypot(*(xy[:, None, :] - xy[None, :, :]).transpose(2, 0, 1))))


def axes(geometry) -> dict:
    """The oracle's extra unknowns: an axis point per group link whose frame is not p0 -> p1,
    {name: (link, origin point, distance D)}."""
    out = {}
    for e in geometry.elements:
        if e["kind"] == "group" and e.get("slides"):
            _, aux = _group_theta0(e)
            for ln in aux:
                out[f"axis_{e['label']}_{ln}"] = (ln, e["links"][ln][0], _size(e))
    return out


def _axis_name(e, ln):
    return f"axis_{e['label']}_{ln}"


def _group_frame(e, ln, pts):
    """(origin, unit x-axis) of a group link's frame in the oracle's unknowns."""
    names = e["links"][ln]
    P = pts[names[0]]
    if e.get("slides"):
        _, aux = _group_theta0(e)
        if ln in aux:
            X, D = pts[_axis_name(e, ln)], _size(e)
            return P, ((X[0] - P[0]) / D, (X[1] - P[1]) / D)
    return P, _unit(P, pts[names[1]])


def _slide_group_rows(e, pts):
    """A ``group`` with ``slides`` (see the module docstring)."""
    pose = {p: (float(x), float(y)) for p, (x, y) in e["pose"].items()}
    th0, aux = _group_theta0(e)
    D = _size(e)
    rows = []
    for ln, names in e["links"].items():
        P, (ex, ey) = _group_frame(e, ln, pts)
        c, s_ = math.cos(th0[ln]), math.sin(th0[ln])
        ax, ay = pose[names[0]]
        if ln in aux:
            X = pts[_axis_name(e, ln)]
            rows.append(_dot(X[0] - P[0], X[1] - P[1], X[0] - P[0], X[1] - P[1]) - D * D)
            rest = names[1:]
        else:
            bx, by = pose[names[1]]
            L = math.hypot(bx - ax, by - ay)
            Q = pts[names[1]]
            rows.append(_dot(Q[0] - P[0], Q[1] - P[1], Q[0] - P[0], Q[1] - P[1]) - L * L)
            rest = names[2:]
        for k in rest:
            rx, ry = pose[k][0] - ax, pose[k][1] - ay
            u, v = c * rx + s_ * ry, c * ry - s_ * rx
            R = pts[k]
            rows += [R[0] - P[0] - (u * ex - v * ey), R[1] - P[1] - (u * ey + v * ex)]
    for b, (g, p, _) in e["slides"].items():
        _, (bx_, by_) = _group_frame(e, b, pts)
        if g is None:
            O, (gx, gy), gth, (ox, oy) = (Jet(0.0), Jet(0.0)), (Jet(1.0), Jet(0.0)), 0.0, (0.0, 0.0)
        elif isinstance(g, str):
            O, (gx, gy) = _group_frame(e, g, pts)
            gth, (ox, oy) = th0[g], pose[e["links"][g][0]]
        else:
            O, (gx, gy) = pts[g[0]], _unit(pts[g[0]], pts[g[1]])
            (ox, oy), (qx, qy) = pose[g[0]], pose[g[1]]
            gth = math.atan2(qy - oy, qx - ox)
        rel = th0[b] - gth
        cr, sr = math.cos(rel), math.sin(rel)
        rows.append(_cross(gx * cr - gy * sr, gx * sr + gy * cr, bx_, by_))
        rx, ry = pose[p][0] - ox, pose[p][1] - oy
        cu, cv = math.cos(gth) * rx + math.sin(gth) * ry, math.cos(gth) * ry - math.sin(gth) * rx
        B = pts[p]
        lx, ly = O[0] + cu * gx - cv * gy, O[1] + cu * gy + cv * gx
        rows.append(_cross(bx_, by_, B[0] - lx, B[1] - ly))
    return rows


def _group_rows(e, pts):
    """A ``group``'s equations (see the module docstring): lengths and frame coordinates from its pose."""
    if e.get("slides"):
        return _slide_group_rows(e, pts)
    pose = {p: (float(x), float(y)) for p, (x, y) in e["pose"].items()}
    rows = []
    for names in e["links"].values():
        (ax, ay), (bx, by) = pose[names[0]], pose[names[1]]
        L = math.hypot(bx - ax, by - ay)
        P, Q = pts[names[0]], pts[names[1]]
        rows.append(_dot(Q[0] - P[0], Q[1] - P[1], Q[0] - P[0], Q[1] - P[1]) - L * L)
        ex, ey = _unit(P, Q)
        for k in names[2:]:
            rx, ry = pose[k][0] - ax, pose[k][1] - ay
            u, v = ((bx - ax) * rx + (by - ay) * ry) / L, ((bx - ax) * ry - (by - ay) * rx) / L
            R = pts[k]
            rows += [R[0] - P[0] - (u * ex - v * ey), R[1] - P[1] - (u * ey + v * ex)]
    return rows


def residual(geometry, X, Q):
    """The constraint residuals (list of Jets, two per element) at unknown points ``X`` {name: (Jet, Jet)}
    and inputs ``Q`` (list of Jets, in input order)."""
    pts = {g: (Jet(float(x)), Jet(float(y))) for g, (x, y) in geometry.ground.items()}
    pts.update(X)
    rows = []
    k = 0
    for e in geometry.elements:
        kind, R = e["kind"], pts[e["point"]]
        if kind == "crank":
            P, q = pts[e["pivot"]], Q[k]
            k += 1
            rows += [R[0] - P[0] - e["length"] * jcos(q), R[1] - P[1] - e["length"] * jsin(q)]
        elif kind == "slider":
            O, (ux, uy) = _guide(e["guide"], pts)
            q = Q[k]
            k += 1
            rows += [R[0] - O[0] - q * ux, R[1] - O[1] - q * uy]
        elif kind == "actuator":
            (P, Qp), a, q = (pts[n] for n in e["from"]), e["length"], Q[k]
            k += 1
            rows += [_dot(R[0] - P[0], R[1] - P[1], R[0] - P[0], R[1] - P[1]) - a * a,
                     _dot(R[0] - Qp[0], R[1] - Qp[1], R[0] - Qp[0], R[1] - Qp[1]) - q * q]
        elif kind == "motor":
            P, q = pts[e["pivot"]], Q[k]
            k += 1
            psi = _link_angle(geometry, e["on"], pts, Q)[0] + q
            rows += [R[0] - P[0] - e["length"] * jcos(psi), R[1] - P[1] - e["length"] * jsin(psi)]
        elif kind == "motor_dyad":
            (P, Cp), (a, b), J = (pts[n] for n in e["from"]), e["lengths"], pts[e["pivot"]]
            th = Q[k] if (e["on"] or e["links"][0]) == e["links"][0] else -1.0 * Q[k]
            k += 1
            ux, uy = J[0] - P[0], J[1] - P[1]
            ct, st_ = jcos(th), jsin(th)
            rows += [_dot(ux, uy, ux, uy) - a * a,
                     R[0] - J[0] - (b / a) * (ux * ct - uy * st_), R[1] - J[1] - (b / a) * (ux * st_ + uy * ct),
                     _dot(R[0] - Cp[0], R[1] - Cp[1], R[0] - Cp[0], R[1] - Cp[1]) - e["length"] ** 2]
        elif kind == "RRR":
            (P, Qp), (a, b) = (pts[n] for n in e["from"]), e["lengths"]
            rows += [_dot(R[0] - P[0], R[1] - P[1], R[0] - P[0], R[1] - P[1]) - a * a,
                     _dot(R[0] - Qp[0], R[1] - Qp[1], R[0] - Qp[0], R[1] - Qp[1]) - b * b]
        elif kind == "RRP":
            P, l = pts[e["from"]], e["length"]
            O, (ux, uy) = _guide(e["guide"], pts)
            rows += [_dot(R[0] - P[0], R[1] - P[1], R[0] - P[0], R[1] - P[1]) - l * l,
                     _cross(ux, uy, R[0] - O[0], R[1] - O[1]) - e["offset"]]
        elif kind == "RPR":
            P, Qp, l = pts[e["pivot"]], pts[e["through"]], e["length"]
            rows += [_dot(R[0] - P[0], R[1] - P[1], R[0] - P[0], R[1] - P[1]) - l * l,
                     _cross(R[0] - P[0], R[1] - P[1], Qp[0] - P[0], Qp[1] - P[1]) - l * e["offset"]]
        elif kind == "PRP":
            for g, off in (("guide1", "offset1"), ("guide2", "offset2")):
                O, (ux, uy) = _guide(e[g], pts)
                rows.append(_cross(ux, uy, R[0] - O[0], R[1] - O[1]) - e[off])
        elif kind in ("RPP", "PPR"):
            O, u = _guide(e["guide"], pts)
            vx, vy = _slot(e, u)
            P = pts[e["through"]]
            rows += [_cross(u[0], u[1], R[0] - O[0], R[1] - O[1]) - e["offset"],
                     _cross(vx, vy, P[0] - R[0], P[1] - R[1])]
        elif kind == "point":
            P, (ex, ey) = _frame(geometry, e["on"], pts)
            u, v = e["at"]
            rows += [R[0] - P[0] - (u * ex - v * ey), R[1] - P[1] - (u * ey + v * ex)]
        elif kind == "gear":
            P, psi = pts[e["pivot"]], _gear_angle(geometry, e, pts, Q)
            rows += [R[0] - P[0] - e["length"] * jcos(psi), R[1] - P[1] - e["length"] * jsin(psi)]
        elif kind == "cam":
            rows += _cam_rows(geometry, e, pts, Q, R)
        elif kind == "group":
            rows += _group_rows(e, pts)
        else:
            raise ValueError(f"unknown element kind {kind!r}")
    return rows


# ------------------------------------------------------------------------------------------- solving
def _names(geometry):
    return [p for e in geometry.elements for p in e["places"]] + list(axes(geometry))


def _pack(names, x, xd=None, xdd2=None):
    """{name: (Jet, Jet)} from arrays of shape (N, 2 n)."""
    zero = 0.0
    out = {}
    for i, n in enumerate(names):
        cols = []
        for c in (2 * i, 2 * i + 1):
            cols.append(Jet(x[:, c], zero if xd is None else xd[:, c], zero if xdd2 is None else xdd2[:, c]))
        out[n] = tuple(cols)
    return out


def jacobian(geometry, x, q):
    """dF/dx, shape (N, 2n, 2n), by forward-mode differentiation (one unit seed per unknown)."""
    names = _names(geometry)
    N, n2 = x.shape
    Q = [Jet(q[:, j]) for j in range(q.shape[1])]
    cols = []
    for c in range(n2):
        seed = np.zeros((N, n2))
        seed[:, c] = 1.0
        rows = residual(geometry, _pack(names, x, seed), Q)
        cols.append(np.stack([np.broadcast_to(r.c1, (N,)) for r in rows], -1))
    return np.stack(cols, -1)


def solve(geometry, q, qd, qdd, guess, iterations=60):
    """Positions, velocities and accelerations of every point.

    ``q, qd, qdd``: arrays (N, n_inputs); ``guess``: {point: (x, y)} arrays (N,) for every element's
    point. Returns ({point: (x, y, vx, vy, ax, ay)} for every point, ground included; the final
    Newton step size [m]).
    """
    names = _names(geometry)
    q, qd, qdd = (np.asarray(a, float) for a in (q, qd, qdd))
    N = q.shape[0]
    x = np.stack([np.asarray(guess[n][c], float) * np.ones(N) for n in names for c in (0, 1)], -1)
    Q0 = [Jet(q[:, j]) for j in range(q.shape[1])]
    scale = float(np.max(np.abs(x))) or 1.0
    step, converged = np.inf, False
    for _ in range(iterations):
        F = np.stack([np.broadcast_to(r.c0, (N,)) for r in residual(geometry, _pack(names, x), Q0)], -1)
        dx = np.linalg.solve(jacobian(geometry, x, q), F[..., None])[..., 0]
        x = x - dx
        step = float(np.max(np.abs(dx)))
        if converged:             # one more step once converged: what is left is rounding
            break
        converged = step < 1e-13 * scale
    J = jacobian(geometry, x, q)
    # velocities: F1 with xd = 0 is F_q qd
    Qv = [Jet(q[:, j], qd[:, j]) for j in range(q.shape[1])]
    rhs = np.stack([np.broadcast_to(r.c1, (N,)) for r in residual(geometry, _pack(names, x), Qv)], -1)
    xd = -np.linalg.solve(J, rhs[..., None])[..., 0]
    # accelerations: F2 with xdd = 0 is (F_q qdd + D2F[w, w]) / 2
    Qa = [Jet(q[:, j], qd[:, j], 0.5 * qdd[:, j]) for j in range(q.shape[1])]
    rhs = np.stack([np.broadcast_to(r.c2, (N,)) for r in residual(geometry, _pack(names, x, xd), Qa)], -1)
    xdd = -2.0 * np.linalg.solve(J, rhs[..., None])[..., 0]
    zero = np.zeros(N)
    out = {g: (zero + gx, zero + gy, zero, zero, zero, zero) for g, (gx, gy) in geometry.ground.items()}
    for i, n in enumerate(names):
        a, b = 2 * i, 2 * i + 1
        out[n] = (x[:, a], x[:, b], xd[:, a], xd[:, b], xdd[:, a], xdd[:, b])
    return out, step


def branch_violations(geometry, points):
    """Per element with a branch, the number of samples whose root is not the one the file's branch
    names (by the conventions in the module docstring)."""
    P = {n: (v[0], v[1]) for n, v in points.items()}
    bad = {}
    for e in geometry.elements:
        if e["kind"] == "group":
            bad[e["label"]] = _group_branch_violations(e, P)
            continue
        R = P[e["point"]]
        if e["kind"] in ("RRR", "actuator", "motor_dyad"):
            A, B = (P[n] for n in e["from"])
            side = _cross(B[0] - A[0], B[1] - A[1], R[0] - A[0], R[1] - A[1])
        elif e["kind"] == "RRP":
            A = P[e["from"]]
            G = e["guide"]
            if "points" in G:
                g0, g1 = (P[n] for n in G["points"])
                ux, uy = g1[0] - g0[0], g1[1] - g0[1]
            else:
                ux, uy = math.cos(G["angle"]), math.sin(G["angle"])
            side = _dot(R[0] - A[0], R[1] - A[1], ux, uy)
        elif e["kind"] == "RPR":
            A, B = P[e["pivot"]], P[e["through"]]
            side = _dot(R[0] - A[0], R[1] - A[1], B[0] - A[0], B[1] - A[1])
        else:
            continue
        bad[e["label"]] = int(np.sum(e["branch"] * side <= 0))
    return bad


def _group_det(e, P):
    """det of a group's equations' Jacobian in the points it places (and its axis points), at positions P
    {name: (x, y)}."""
    unknown = list(e["places"]) + [_axis_name(e, ln) for ln in (_group_theta0(e)[1] if e.get("slides") else ())]
    n = 2 * len(unknown)
    N = np.size(np.asarray(P[unknown[0]][0]))
    cols = []
    for c in range(n):
        pts = {p: (Jet(np.asarray(xy[0], float)), Jet(np.asarray(xy[1], float))) for p, xy in P.items()}
        p = unknown[c // 2]
        x, y = pts[p]
        pts[p] = (Jet(x.c0, float(c % 2 == 0)), Jet(y.c0, float(c % 2 == 1)))
        cols.append(np.stack([np.broadcast_to(r.c1, (N,)) for r in _group_rows(e, pts)], -1))
    return np.linalg.det(np.stack(cols, -1))


def _group_branch_violations(e, P):
    """Samples where a group's Jacobian determinant has another sign than at the file's pose."""
    pose = {p: (np.array([x]), np.array([y])) for p, (x, y) in e["pose"].items()}
    if e.get("slides"):
        th0, aux = _group_theta0(e)
        for ln in aux:
            (x, y), D = e["pose"][e["links"][ln][0]], _size(e)
            pose[_axis_name(e, ln)] = (np.array([x + D * math.cos(th0[ln])]), np.array([y + D * math.sin(th0[ln])]))
    at_pose = _group_det(e, pose)[0]
    return int(np.sum(np.sign(_group_det(e, P)) != np.sign(at_pose)))


def slides(geometry, points):
    """(s, ds, dds) of every prismatic pair, named after its block link, from the oracle's points:
    RRP: distance of C from the guide's origin along the guide; RPR: Q - P along the slot; slider: its
    input, recovered from the point; PRP: C from each guide's origin along it; RPP, PPR: C from the guide's
    origin along the guide (the link on it), the pin - C along the slot (the block in it)."""
    J = {n: (Jet(v[0], v[2], 0.5 * v[4]), Jet(v[1], v[3], 0.5 * v[5])) for n, v in points.items()}
    out = {}
    for e in geometry.elements:
        if e["kind"] == "group":
            for b, (g, p, _) in e.get("slides", {}).items():
                _, (ux, uy) = _group_frame(e, b, J)
                if g is None:
                    ox, oy = (float(c) for c in e["pose"][p])
                    O = (Jet(ox), Jet(oy))
                else:
                    O = J[g[0] if isinstance(g, tuple) else e["links"][g][0]]
                B = J[p]
                s = _dot(B[0] - O[0], B[1] - O[1], ux, uy)
                out[b] = (s.c0, s.c1, 2.0 * s.c2)
            continue
        R = J[e["point"]]
        if e["kind"] == "actuator":                 # the rod's pin D from the barrel's C along C -> D
            Cp = J[e["from"][1]]
            ux, uy = _unit(Cp, R)
            s = _dot(R[0] - Cp[0], R[1] - Cp[1], ux, uy)
            out[e["cylinder"][1]] = (s.c0, s.c1, 2.0 * s.c2)
            continue
        if e["kind"] in ("RRP", "slider"):
            O, (ux, uy) = _guide(e["guide"], J)
            s = _dot(R[0] - O[0], R[1] - O[1], ux, uy)
            name = e["links"][1] if e["kind"] == "RRP" else e["link"]
        elif e["kind"] == "RPR":
            P, Qp = J[e["pivot"]], J[e["through"]]
            ux, uy = _unit(P, R)
            s = _dot(Qp[0] - P[0], Qp[1] - P[1], ux, uy)
            name = e["links"][1]
        elif e["kind"] == "PRP":
            for link, g in zip(e["links"], ("guide1", "guide2")):
                O, (ux, uy) = _guide(e[g], J)
                s = _dot(R[0] - O[0], R[1] - O[1], ux, uy)
                out[link] = (s.c0, s.c1, 2.0 * s.c2)
            continue
        elif e["kind"] in ("RPP", "PPR"):
            O, u = _guide(e["guide"], J)
            vx, vy = _slot(e, u)
            P = J[e["through"]]
            on_guide, in_slot = e["links"] if e["kind"] == "PPR" else e["links"][::-1]
            s = _dot(R[0] - O[0], R[1] - O[1], u[0], u[1])
            out[on_guide] = (s.c0, s.c1, 2.0 * s.c2)
            s = _dot(P[0] - R[0], P[1] - R[1], vx, vy)
            name = in_slot
        else:
            continue
        out[name] = (s.c0, s.c1, 2.0 * s.c2)
    return out


def link_rates(geometry, points):
    """(omega, alpha) of every link, from the motion of two of its points (or 0 for a ground guide)."""
    J = {n: (Jet(v[0], v[2], 0.5 * v[4]), Jet(v[1], v[3], 0.5 * v[5])) for n, v in points.items()}

    def rates(p, q):
        ex, ey = _unit(J[p], J[q])
        # e(t) = (cos th, sin th): e1 = th' e_perp, e2 = (th'' e_perp - th'^2 e) / 2
        return (_cross(ex.c0, ey.c0, ex.c1, ey.c1), 2.0 * _cross(ex.c0, ey.c0, ex.c2, ey.c2))

    out = {}
    for e in geometry.elements:
        k, pt = e["kind"], e["point"]
        if k in ("crank", "motor"):
            out[e["link"]] = rates(e["pivot"], pt)
        elif k == "actuator":
            out[e["link"]] = rates(e["from"][0], pt)
            out[e["cylinder"][0]] = out[e["cylinder"][1]] = rates(e["from"][1], pt)
        elif k == "slider":
            G = e["guide"]
            out[e["link"]] = rates(*G["points"]) if "points" in G else (0.0, 0.0)
        elif k == "motor_dyad":
            out[e["links"][0]] = rates(e["from"][0], e["pivot"])
            out[e["links"][1]] = rates(e["pivot"], pt)
            out[e["closing"]] = rates(e["from"][1], pt)
        elif k == "RRR":
            out[e["links"][0]] = rates(e["from"][0], pt)
            out[e["links"][1]] = rates(e["from"][1], pt)
        elif k == "RRP":
            out[e["links"][0]] = rates(e["from"], pt)
            G = e["guide"]
            out[e["links"][1]] = rates(*G["points"]) if "points" in G else (0.0, 0.0)
        elif k == "RPR":
            out[e["links"][0]] = out[e["links"][1]] = rates(e["pivot"], pt)
        elif k == "gear":
            out[e["link"]] = rates(e["pivot"], pt)
        elif k == "cam":                      # a block keeps its guide's angle; an arm turns B -> R
            out[e["links"][0]] = (0.0, 0.0) if e["follower"] == "translating" else rates(e["arm_pivot"], pt)
        elif k == "PRP":                      # each block turns with its guide
            for link, g in zip(e["links"], ("guide1", "guide2")):
                G = e[g]
                out[link] = rates(*G["points"]) if "points" in G else (0.0, 0.0)
        elif k in ("RPP", "PPR"):             # both turn with the guide (the slot is fixed in the link on it)
            G = e["guide"]
            out[e["links"][0]] = out[e["links"][1]] = rates(*G["points"]) if "points" in G else (0.0, 0.0)
        elif k == "group":
            aux = _group_theta0(e)[1] if e.get("slides") else ()
            for ln, names in e["links"].items():
                out[ln] = rates(names[0], _axis_name(e, ln) if ln in aux else names[1])
    return out
