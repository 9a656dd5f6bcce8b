"""``actuator``: a linear actuator (hydraulic, pneumatic or electric cylinder) between two pins (an input).

Fields: ``name`` (its input's name: columns ``s_NAME``, ``ds_NAME``, ``dds_NAME``), ``point`` (the pin it places,
the rod's end D), ``from`` [A, C] (A: the pivot of ``link``, D at ``length`` from it; C: the barrel's pin, on any
link), ``length`` (|AD|), ``link`` (the new link A-D, default A + D), ``l0``, ``v``, ``a`` (the pin-to-pin length
|CD| at t = 0 and its law l(t) = l0 + v t + a t^2 / 2), ``stroke`` [retracted, extended] (the lengths it can
reach: a motion outside them is refused), ``bore`` and ``rod`` (optional diameters, 0: not given; with a bore
the forces report the pressure on the push area pi bore^2 / 4 or the pull area pi (bore^2 - rod^2) / 4) and
``branch`` (+1: D left of the directed line A -> C), ``cylinder`` [barrel, rod] (the two links' names, default
``NAME_barrel``, ``NAME_rod``).

It is the RRR dyad whose second length is driven: D at ``length`` from A and at l(t) from C, in closed form.
The cylinder itself is two links: the barrel pinned at C and the rod pinned at D (``cylinder``),
joined by the driven prismatic pair (named after the rod, measured from C along C -> D); both point C -> D.
Its drive is the force along C -> D the barrel puts on the rod: positive when it pushes (extends).
"""

from __future__ import annotations

import math

import numpy as np

from ..quantities import lengths_in
from .base import GROUND, SIZE_PER_SECOND, Cylinder, Field, Kind, LinkPart, Slide, State, Structure

STROKE_ROUNDING = 1e-12
"""[of the stroke's extended length] A length this far beyond an end of the stroke is at the end (rounding of
the motion law's sum)."""


ALONG = 1e-5
"""[rad] A P joint's written direction this close to the line through the cylinder's pins is along it: an angle
written to 6 significant digits of degrees (as the importers write a peer's slide) is within 5e-4 deg, 8.7e-6
rad, of its value."""


class Actuator(Kind):
    name = "actuator"
    section = "inputs"
    summary = ("a linear actuator (cylinder) between pin C and the pin D it places on link A-D: its pin-to-pin "
               "length l(t) = l0 + v t + a t^2/2 is driven")
    group_class = "dyad RRR with a driven length (class II)"
    angular = False
    columns = ("s", "ds", "dds")
    motion_fields = ("l0", "v", "a")
    fields = {"name": Field("link", "{point}"), "point": Field("new"), "from": Field("pair"),
              "length": Field("size"), "link": Field("link", "{from0}{point}"), "l0": Field("size"),
              "v": Field("length", SIZE_PER_SECOND), "a": Field("length", 0.0), "stroke": Field("lengths2"),
              "bore": Field("length", 0.0), "rod": Field("length", 0.0), "branch": Field("branch", 1),
              "cylinder": Field("links2", ("{name}_barrel", "{name}_rod"))}

    def default_rate(self, size):
        """A tenth of the mechanism's size per second, to 3 digits [file units / s]: a cylinder's stroke is a
        fraction of the machine it moves."""
        return "v", float(f"{0.1 * size:.3g}")

    joints_form = {"joint": "point", "name": "link", "v": "length", "a": "length", "stroke": "lengths",
                   "bore": "length", "rod": "length"}
    joints_summary = "a cylinder: the P joint between its barrel and its rod, pinned at C and D"

    @staticmethod
    def _parts(item, dec):
        """(slide, barrel, rod, driven link, C, A) of the entry's P joint, as far as they are found."""
        s = next((x for x in dec.f.slides if x.point == item.get("joint")), None)
        if s is None:
            return None, None, None, None, None, None
        barrel, rod, d = s.guide, s.block, s.point
        links = [ln for ln in dec.f.pins.get(d, []) if ln not in (barrel, rod)]
        link = links[0] if len(links) == 1 else None
        cs = [p for p in dec.points.get(barrel, []) if p in dec.placed]
        a_ = [p for p in dec.points.get(link, []) if p in dec.placed and p != d] if link else []
        return s, barrel, rod, link, (cs[0] if len(cs) == 1 else None), (a_[0] if len(a_) == 1 else None)

    def joints_ready(self, item, dec):
        """Once the barrel's pin C and the driven link's pivot A are placed."""
        s, _, _, link, c, a = self._parts(item, dec)
        return s is None or (c is not None and a is not None and link not in dec.known)

    def from_joints(self, item, where, dec):
        """The P joint ``joint`` between two moving links is the cylinder: its guide the barrel (pinned at C to
        a placed link), its block the rod, pinned at the joint's point D to the driven link, which turns about
        its one placed point A; lengths, the start length and the branch from the pose."""
        d = dec.point_name(item.get("joint"), f"{where}: field 'joint'")
        label, where = where, f"{where} (joint {d})"
        s, barrel, rod, link, c, a = self._parts(item, dec)
        if s is None:
            raise dec.fail(where, f"field 'joint': no P joint at {d!r}; an actuator drives the P joint between its "
                                  f"barrel and its rod")
        if GROUND in (barrel, rod):
            raise dec.fail(where, f"the P joint at {d!r} slides on the ground; a block driven along a ground guide "
                                  f"is kind = \"slider\"")
        if link is None:
            raise dec.fail(where, f"the rod {rod!r} must be pinned at {d!r} to one link (the one the actuator "
                                  f"turns); links there: {', '.join(dec.f.pins.get(d, [])) or 'none'}")
        if "stroke" not in item:
            raise dec.fail(where, "field 'stroke' is missing: give the retracted and extended pin-to-pin lengths")
        for ln in (barrel, rod, link):
            if ln in dec.known:
                raise dec.fail(where, f"link {ln!r} is already placed by other joints; the actuator places its "
                                      f"barrel, its rod and the link it turns")
        if c is None or a is None:
            which = f"barrel {barrel!r}" if c is None else f"link {link!r}"
            raise dec.fail(where, f"the {which} must be held at exactly one point placed by the rest of the "
                                  f"mechanism (the barrel's pin C; the link's pivot A)")
        rd, rc = dec.pose[d] - dec.pose[a], dec.pose[d] - dec.pose[c]
        size = dec.SINGULAR * dec.f.size
        if rc.norm().value <= size or rd.norm().value <= size:
            raise dec.fail(where, f"{d!r} coincides with {c if rc.norm().value <= size else a!r} in the pose")
        u = rc.unit()
        ux, uy = u.value
        along = math.atan2(uy, ux)
        if abs(math.sin(s.angle.value - along)) > ALONG:
            raise dec.fail(where, f"the P joint at {d!r} slides at {math.degrees(s.angle.value):.6g} deg, not along "
                                  f"the cylinder {c} -> {d} ({math.degrees(along):.6g} deg): its line must pass both pins")
        side = (dec.pose[c] - dec.pose[a]).cross(rd)
        if abs(side.value) <= size * rd.norm().value:
            raise dec.singular(where, f"{a}, {c} and {d} are in a line")
        entry = {"kind": "actuator", "name": item.get("name", d), "point": d, "from": [a, c],
                 "length": dec.out(rd.norm(), where, "the link's length"), "link": link,
                 "l0": dec.out(rc.norm(), where, "the start length"),
                 "v": item.get("v", self.default_rate(dec.f.size)[1]), "a": item.get("a", 0.0),
                 "stroke": item["stroke"], "branch": 1 if side.value > 0 else -1, "cylinder": [barrel, rod]}
        entry.update({k: item[k] for k in ("bore", "rod") if k in item})
        dec.emit(entry, label)
        dec.placed.add(d)
        dec.pair_frame(link, a, d)
        dec.set_frame(barrel, c, u)
        dec.set_frame(rod, d, u)
        dec.classes.append(f"input actuator {barrel}-{rod} from {c} to {d}, turning {link} about {a}")
        for ln in (link, barrel, rod):
            dec.rigid(ln, where)

    def from_pmks(self, driver):
        """An RP joint between two moving links (``barrel link RP x y angle``: the link pinned to a block that
        slides in the barrel's slot) is a cylinder: the barrel pinned at one other point C, the block its rod.
        PMKS gives no stroke: the pose's pin-to-pin length l0 with a quarter of it either way, [0.75, 1.25] l0
        (a cylinder extends to at most about twice its retracted length), and a speed of 0.2 l0 per second, so
        that the run (one second) stays within it."""
        if driver.type != "RP" or len(driver.links) < 2 or GROUND in driver.links[:2]:
            return None
        barrel, d = driver.links[0], driver.point
        form = driver.form
        pins = [j["point"] for j in form["joints"] if j["kind"] == "R" and barrel in j.get("links", ()) and j["point"] != d]
        if len(pins) != 1:
            return None                              # the importer says which joint it cannot drive
        (cx, cy), (dx, dy) = form["pose"][pins[0]], form["pose"][d]
        l0 = math.hypot(dx - cx, dy - cy)
        if not l0 > 0:
            return None
        return {"kind": "actuator", "joint": d, "stroke": [float(f"{0.75 * l0:.6g}"), float(f"{1.25 * l0:.6g}")],
                "v": float(f"{0.2 * l0:.3g}")}

    def input_key(self, e):
        """``_NAME``: its columns are ``s_NAME ds_NAME dds_NAME``, its drive ``tau_NAME``."""
        return "_" + e["name"]

    def needs(self, f):
        return tuple(f["from"])

    def check_resolved(self, e, units="m"):
        lo, hi = e["stroke"]
        u = lengths_in(units)
        if not hi > lo:
            return f"field 'stroke': the extended length {u(hi)} must exceed the retracted {u(lo)}"
        l0 = e["l0"]
        if not lo <= l0 <= hi:
            by = lo - l0 if l0 < lo else l0 - hi
            return (f"field 'l0': {u(l0)} is outside the stroke {u(lo, hi)} by {u(by, digits=4)}; give a start "
                    f"length within it")
        if e["bore"] < 0 or e["rod"] < 0:
            return f"field '{'bore' if e['bore'] < 0 else 'rod'}': a diameter must be >= 0 (0: not given)"
        if e["rod"] > 0 and not e["rod"] < e["bore"]:
            return f"field 'rod': the rod's diameter {u(e['rod'])} must be smaller than the bore {u(e['bore'])}"
        return None

    def stops(self, e):
        return tuple(e["stroke"])

    def motion_problem(self, e, column, t, q, units="m"):
        """Refuse a motion that drives the actuator past either end of its stroke: the first time (or sample)
        it does and the farthest it goes."""
        lo, hi = e["stroke"]
        q = np.asarray(q, dtype=float)
        tol = STROKE_ROUNDING * hi
        out = (q < lo - tol) | (q > hi + tol)
        if not out.any():
            return None
        k = int(np.argmax(out))
        over, under = float(np.max(q)) - hi, lo - float(np.min(q))
        end, by, edge = ("extended", over, hi) if over > under else ("retracted", under, lo)
        u = lengths_in(units)
        if t is not None:                            # the crossing, between the samples on either side of it
            t = np.asarray(t, dtype=float)
            edge_k = hi if q[k] > hi else lo
            at = float(t[k]) if k == 0 else float(t[k - 1] + (edge_k - q[k - 1]) / (q[k] - q[k - 1]) * (t[k] - t[k - 1]))
            when = f"at t = {at:.4g} s"
        else:
            when = f"where {column} reaches {u(q[k], digits=6)}"
        return (f"field 'stroke': the motion leaves the stroke {u(lo, hi)} {when} and goes {u(by, digits=4)} "
                f"beyond the {end} length {u(edge)}; shorten the motion (or its speed) or lengthen the stroke")

    def structure(self, f):
        (a, c), d = f["from"], f["point"]
        barrel, rod = f["cylinder"]
        return Structure(links=(LinkPart(f["link"], a, (a, d)), LinkPart(barrel, c, (c,)),
                                LinkPart(rod, d, (d,), block=True)),
                         slides=(Slide(rod, barrel, d, driven=True),))

    def slide_frames(self, e):
        return {e["cylinder"][1]: (e["from"][1], e["point"], 0.0)}

    def cylinders(self, e):
        barrel, rod = e["cylinder"]
        lo, hi = e["stroke"]
        return (Cylinder(barrel, rod, e["from"][1], e["point"], lo, hi, e["bore"]),)

    def input_joint(self, e):
        return e["from"][1]

    def solve(self, e, st: State):
        j = e["input"]
        a_, c_ = e["from"]
        (D, (cl, sl, w1, al1), (ce, se, w2, al2)), lq = actuated(
            st.points[a_], st.points[c_], e["length"], st.q[j], st.qd[j], st.qdd[j], e["branch"], e["stroke"])
        st.points[e["point"]] = D
        st.links[e["link"]] = (cl, sl, w1, al1)
        barrel, rod = e["cylinder"]
        st.links[barrel] = st.links[rod] = (ce, se, w2, al2)
        st.slides[rod] = lq

    report_units = {"actuators": {"pressure": "Pa", "F": "N", "bore": "m"}}

    def drive_report(self, e, drive, pressure_given=None):
        """``{"actuators": {NAME: entry}}``: the sizing table (:func:`sizing`: the peak push and pull and, with
        ``pressure_given`` [Pa], the bores they need) and with a bore ``"pressure"`` [Pa] and ``"area"``
        ("push"|"pull") per sample."""
        entry = sizing(e, drive, pressure_given)
        p = pressure(e, drive)
        if p is not None:
            value, push = p
            entry.update({"pressure": value, "area": ["push" if x else "pull" for x in push]})
        return {"actuators": {e["name"]: entry}}

    def measured_extras(self, e, st):
        """Its length and rates: the measured rod's slide."""
        s, ds, dds = st.slides[e["cylinder"][1]]
        key = self.input_key(e)
        return dict(zip((c + key for c in self.columns), (s, ds, dds)))

    def singularity(self, e, st, size):
        c1, s1, _, _ = st.links[e["link"]]
        c2, s2, _, _ = st.links[e["cylinder"][0]]
        return np.abs(c1 * s2 - s1 * c2)            # sin of the angle between the link and the cylinder

    def forces(self, e, ctx):
        """Closed form. With r1 = D - A, r2 = D - C and G the force the link puts on the rod at D: the
        cylinder (barrel and rod, their internal forces cancelling) about C gives r2 x G = -(M_barrel(C) +
        M_rod(C)), the link about A gives r1 x G = M_link(A): a 2x2 system of determinant r1 x r2 (zero where
        the link and the cylinder align). The rod's balance along C -> D is the drive, across it the guide's
        normal force, its moment about D the guide's couple; C and A carry the rest of each part's load."""
        (a, c), d, link = e["from"], e["point"], e["link"]
        barrel, rod = e["cylinder"]
        ax, ay = ctx.xy(a)
        cx, cy = ctx.xy(c)
        dx, dy = ctx.xy(d)
        r1x, r1y, r2x, r2y = dx - ax, dy - ay, dx - cx, dy - cy
        m1 = ctx.moment(link, a)
        m2 = -(ctx.moment(barrel, c) + ctx.moment(rod, c))
        det = r1x * r2y - r1y * r2x
        gx = (m1 * r2x - m2 * r1x) / det             # G = (m1 r2 - m2 r1) / det: r1 x G = m1, r2 x G = m2
        gy = (m1 * r2y - m2 * r1y) / det
        fr, fb, fl = ctx.resultant(rod), ctx.resultant(barrel), ctx.resultant(link)
        ux, uy = ctx.direction(rod)
        tx, ty = fr[0] + gx, fr[1] + gy              # what the barrel must balance on the rod
        drive = -(ux * tx + uy * ty)
        normal = uy * tx - ux * ty                   # the guide's force along n = (-uy, ux)
        ctx.pin(d, rod, gx, gy, other=link)
        ctx.guide(rod, -uy * normal, ux * normal, -ctx.moment(rod, d))
        ctx.drive(e, drive)
        # the barrel gets minus the rod's guide force and drive: its pin C takes the rest
        ctx.pin(c, barrel, -(fb[0] + tx), -(fb[1] + ty))
        ctx.pin(a, link, -(fl[0] - gx), -(fl[1] - gy))


def pressure(e: dict, force) -> tuple[np.ndarray, np.ndarray] | None:
    """The pressure [Pa] an actuator's ``force`` [N] needs over its samples, on the push area pi bore^2 / 4 where
    it pushes (force >= 0) and on the pull area pi (bore^2 - rod^2) / 4 where it pulls, and which area (True:
    push); None without a bore."""
    bore, rod = e["bore"], e["rod"]
    if bore <= 0:
        return None
    force = np.asarray(force, dtype=float)
    push = force >= 0
    a_push, a_pull = areas(bore, rod)
    return np.where(push, force / a_push, -force / a_pull), push


def areas(bore: float, rod: float) -> tuple[float, float]:
    """The push area pi bore^2 / 4 (the piston's full face) and the pull area pi (bore^2 - rod^2) / 4 (the
    annulus round the rod) [m^2]."""
    return math.pi * bore * bore / 4, math.pi * (bore * bore - rod * rod) / 4


def sizing(e: dict, force, pressure_given: float | None = None) -> dict:
    """The cylinder sizing table of one actuator from its ``force`` [N, + pushing] over the samples:
    ``push`` and ``pull`` each {"F": the peak force [N, >= 0], "at": its sample} (F = 0 and at None where it
    never pushes or pulls); with the file's bore the peak pressure [Pa] on each one's area (:func:`areas`); with a supply
    ``pressure_given`` [Pa] ``"sizing"``: the bore the peak push needs, D = sqrt(4 F_push / (pi p)), the bore
    the peak pull needs round the rod d (the file's, 0 when not given), D = sqrt(4 F_pull / (pi p) + d^2), the
    larger of the two, and with a bore given whether it is enough."""
    force = np.asarray(force, dtype=float)
    bore, rod = e["bore"], e["rod"]
    out = {}
    for side, f in (("push", force), ("pull", -force)):
        f = np.where(np.isfinite(f), f, -np.inf)
        i = int(np.argmax(f))
        out[side] = {"F": float(f[i]), "at": i} if f[i] > 0 else {"F": 0.0, "at": None}
    if bore > 0:
        a_push, a_pull = areas(bore, rod)
        out["push"]["pressure"] = out["push"]["F"] / a_push
        out["pull"]["pressure"] = out["pull"]["F"] / a_pull
    if pressure_given is not None:
        p = float(pressure_given)
        need_push = math.sqrt(4 * out["push"]["F"] / (math.pi * p))
        need_pull = math.sqrt(4 * out["pull"]["F"] / (math.pi * p) + rod * rod)
        need = max(need_push, need_pull)
        out["sizing"] = {"pressure": p, "bore_push": need_push, "bore_pull": need_pull, "rod": rod, "bore": need}
        if bore > 0:
            out["sizing"]["enough"] = bool(bore >= need)
    return out


def actuated(A, C, a, b, bd, bdd, branch, stroke=None):
    """D with |D - A| = a, |D - C| = b(t) (left of A -> C for branch +1), with the rates of a driven b.

    The position is the RRR's circle-circle intersection. With r1 = D - A, r2 = D - C and det = r1 x r2:
    |r1| = a gives vD = vA + w1 perp(r1), and d(|r2|^2)/dt = 2 b bd gives w1 = (r2.(vC - vA) + b bd) / det;
    twice differentiated, alpha1 = (b bdd + bd^2 - |vD - vC|^2 + r2.(aC - aA) + w1^2 r1.r2) / det. The
    cylinder's angle (C -> D) turns at w2 = r2 x (vD - vC) / b^2 and alpha2 = (r2 x (aD - aC) - 2 b bd w2) / b^2.
    Returns ((D, link A-D, cylinder C-D), (b, bd, bdd)); NaN where the circles do not meet or b is outside
    ``stroke``."""
    b = np.asarray(b, dtype=float)
    if stroke is not None:
        lo, hi = stroke
        tol = STROKE_ROUNDING * hi
        b = np.where((b >= lo - tol) & (b <= hi + tol), b, np.nan)
    ax_, ay_, avx, avy, aax, aay = A
    dx, dy = C[0] - ax_, C[1] - ay_
    L2 = dx * dx + dy * dy
    k1 = (0.5 * (a * a - b * b)) / L2 + 0.5
    k2 = np.sqrt(a * a / L2 - k1 * k1) * branch      # NaN where the circles do not meet
    r1x, r1y = k1 * dx - k2 * dy, k1 * dy + k2 * dx
    r2x, r2y = r1x - dx, r1y - dy
    det = k2 * L2                                    # cross(r1, r2)
    dvx, dvy = C[2] - avx, C[3] - avy
    w1 = (r2x * dvx + r2y * dvy + b * bd) / det
    vx, vy = avx - w1 * r1y, avy + w1 * r1x
    ux, uy = vx - C[2], vy - C[3]                    # vD - vC
    w1s = w1 * w1
    al1 = (b * bdd + bd * bd - (ux * ux + uy * uy) + r2x * (C[4] - aax) + r2y * (C[5] - aay)
           + w1s * (r1x * r2x + r1y * r2y)) / det
    accx, accy = aax - al1 * r1y - w1s * r1x, aay + al1 * r1x - w1s * r1y
    b2 = b * b
    w2 = (r2x * uy - r2y * ux) / b2
    al2 = (r2x * (accy - C[5]) - r2y * (accx - C[4]) - 2 * b * bd * w2) / b2
    D = (ax_ + r1x, ay_ + r1y, vx, vy, accx, accy)
    zero = np.zeros(np.shape(det))
    return (D, (r1x / a, r1y / a, w1, al1), (r2x / b, r2y / b, w2, al2)), (b + zero, bd + zero, bdd + zero)


KIND = Actuator()
