"""``motor``: a driven revolute between two moving links (an input): a robot's elbow.

Fields: ``name`` (its input's name: columns ``q_NAME``, ``dq_NAME``, ``ddq_NAME``), ``pivot`` (the joint, a
point of the carrier link ``on``), ``on`` (the carrier: a moving link that exists), ``point`` (the new point at
``length`` from the pivot on the driven link), ``link`` (the driven link, default pivot + point) and its motion
law ``q(t) = q0 + omega t + alpha t^2 / 2`` of the relative angle ``q = phi(link) - phi(on)``.

Its drive is the torque the motor puts on ``link``; the reaction (the motor's housing) acts on ``on``. In the
links-and-joints form (and from a PMKS driver on two moving links) a motor whose carrier no group places but
whose two links close a loop with a third is written as a ``motor_dyad`` (:mod:`analytic.kinds.motor_dyad`).
"""

from __future__ import annotations

import math

import numpy as np

from .base import GROUND, Field, Kind, LinkPart, State, Structure, on_frame


class Motor(Kind):
    name = "motor"
    section = "inputs"
    summary = "a driven revolute between two moving links: link turned about pivot (a point of on) by q = phi(link) - phi(on)"
    angular = True
    columns = ("q", "dq", "ddq")
    motion_fields = ("q0", "omega", "alpha")
    fields = {"name": Field("link", "{point}"), "pivot": Field("point"), "on": Field("linkref"),
              "point": Field("new"), "length": Field("size"), "link": Field("link", "{pivot}{point}"),
              "q0": Field("angle", 0.0), "omega": Field("angle", 2 * math.pi), "alpha": Field("angle", 0.0)}

    joints_form = {"joint": "point", "link": "link", "name": "link", "omega": "angle", "alpha": "angle"}
    joints_summary = "a link turned by a motor at an R joint with another moving link"

    def joints_ready(self, item, dec):
        """Once one of the two moving links at the joint is placed (its carrier) and the other is not, or when
        neither is but they close a loop with one more link (:meth:`bent_loop`)."""
        at = [ln for ln in dec.f.pins.get(item.get("joint"), []) if ln != GROUND]
        link = item.get("link")
        if self.bent_loop(item, dec) is not None:
            return True
        if link in at:
            return any(ln in dec.known for ln in at if ln != link) and link not in dec.known
        return len(at) == 2 and sum(ln in dec.known for ln in at) == 1

    @staticmethod
    def bent_loop(item, dec):
        """Where the R joint ``joint`` pins exactly two links, neither placed: (first, second, closing, P, C,
        point) when the first is held at one placed point P, the second at none, and the second is pinned at
        ``point`` to a third link not placed (``closing``) held at one placed point C: with the motor's angle
        given, the first and second are one rigid body (the bent link P-joint-point) and the three links an
        RRR dyad (kind ``motor_dyad``). None otherwise."""
        j = item.get("joint")
        on_joint = dec.f.pins.get(j, [])
        at = [ln for ln in on_joint if ln != GROUND]
        if GROUND in on_joint or len(at) != 2 or any(ln in dec.known for ln in at):
            return None
        shared, sl = dec.between(*at)
        if shared != [j] or sl:
            return None
        for first, second in (at, at[::-1]):
            held = dec.known_points(first)
            if len(held) != 1 or dec.known_slides(first) or dec.ext(second) != 0:
                continue
            for n in dec.points:
                if n in dec.known or n in at or any(dec.between(first, n)):
                    continue
                pins, slides = dec.between(second, n)
                cs = dec.known_points(n)
                if len(pins) == 1 and not slides and len(cs) == 1 and not dec.known_slides(n):
                    return first, second, n, held[0], cs[0], pins[0]
        return None

    def from_joints(self, item, where, dec):
        """Drive the link at the R joint ``joint`` that is not yet placed (or ``link``) relative to the other,
        its carrier; its point is its next point, its start angle the pose's. Where neither is placed but
        the two close a loop with a third link (:meth:`bent_loop`), a ``motor_dyad`` element places all three."""
        from analytic.format import sym
        pivot = dec.point_name(item.get("joint"), f"{where}: field 'joint'")
        label, where = where, f"{where} (joint {pivot})"
        at = list(dec.f.pins.get(pivot, []))
        if len(at) < 2:
            raise dec.fail(where, f"field 'joint': no R joint at {pivot!r}; a motor drives an R joint between two "
                                  f"moving links")
        if GROUND in at:
            raise dec.fail(where, f"field 'joint': the R joint at {pivot!r} is on the ground; a link turned about a "
                                  f"ground pivot is kind = \"crank\"")
        link = item.get("link")
        if link is not None:
            link = dec.link_name(link, f"{where}: field 'link'")
            if link not in at:
                raise dec.fail(where, f"field 'link': {link!r} is not pinned at {pivot!r} (links there: "
                                      f"{', '.join(at)})")
        loop = self.bent_loop(item, dec)
        if loop is not None:
            return self._bent_from_joints(item, label, where, pivot, link, loop, dec)
        if link is None:
            free = [ln for ln in at if ln not in dec.known]
            if len(at) != 2 or len(free) != 1:
                raise dec.fail(where, f"name the driven link (link = \"...\"): links at {pivot}: {', '.join(at)}"
                                      f"{'' if free else ', each already placed by other joints'}")
            link = free[0]
        if link in dec.known:
            raise dec.fail(where, f"link {link!r} is already placed by other joints (or driven twice; "
                                  f"{dec.gruebler_note()}); drive a link that only this joint turns")
        on = next((ln for ln in at if ln != link and ln in dec.known), None)
        if on is None:
            raise dec.fail(where, f"no link at {pivot!r} besides {link!r} is placed: a motor turns its link "
                                  f"relative to a link placed by the rest of the mechanism, or closes a loop "
                                  f"P-{pivot}-Q-C with a third link (P, C placed)")
        grounded = [p for p in dec.points[link] if p in dec.placed and p != pivot]
        if grounded:
            raise dec.fail(where, f"link {link!r} is also held at {grounded[0]}: it cannot turn about {pivot}; "
                                  f"remove that joint")
        point = next((p for p in dec.points[link] if p != pivot), None)
        if point is None:
            raise dec.fail(where, f"link {link!r} carries no point besides {pivot!r}; give it one")
        r = dec.pose[point] - dec.pose[pivot]
        if r.norm().value <= dec.SINGULAR * dec.f.size:
            raise dec.fail(where, f"{point!r} and {pivot!r} coincide in the pose; name a point away from the joint")
        e = dec.frames[on].e
        q0 = sym.atan2(e.cross(r), e.dot(r))
        dec.emit({"kind": "motor", "name": item.get("name", pivot), "pivot": pivot, "on": on, "point": point,
                  "length": dec.out(r.norm(), where, "the motor link's length"), "link": link,
                  "q0": dec.out(q0, where, "the motor's start angle"),
                  "omega": item.get("omega", self.default_rate(dec.f.size)[1]), "alpha": item.get("alpha", 0.0)},
                 label)
        dec.placed.add(point)
        dec.pair_frame(link, pivot, point)
        dec.classes.append(f"input motor {link} on {on} at {pivot}")
        dec.rigid(link, where)

    def _bent_from_joints(self, item, label, where, pivot, link, loop, dec):
        """The motor whose two links close a loop with a third (:meth:`bent_loop`): a ``motor_dyad`` element,
        its lengths, start angle and branch from the pose; the driven link is ``link``, by default the one
        not held at a placed point."""
        from analytic.format import sym
        first, second, closing, p, c, q = loop
        link = link or second
        on = first if link == second else second
        P, J, Q, C = (dec.pose[x] for x in (p, pivot, q, c))
        size = dec.SINGULAR * dec.f.size
        for x, y in ((p, pivot), (pivot, q), (q, c)):
            if (dec.pose[y] - dec.pose[x]).norm().value <= size:
                raise dec.fail(where, f"{x!r} and {y!r} coincide in the pose; the motor's loop needs links of "
                                      f"non-zero length")
        turn = (C - P).cross(Q - P)
        if abs(turn.value) <= size * dec.f.size:
            raise dec.singular(where, f"{p}, {q} and {c} are in line (a dead centre of the loop {first}-{second}-"
                                      f"{closing})")
        r1, r2 = J - P, Q - J
        theta = sym.atan2(r1.cross(r2), r1.dot(r2))
        q0 = theta if on == first else -theta
        dec.emit({"kind": "motor_dyad", "name": item.get("name", pivot), "pivot": pivot, "point": q,
                  "from": [p, c], "lengths": [dec.out(r1.norm(), where, f"|{p}{pivot}|"),
                                              dec.out(r2.norm(), where, f"|{pivot}{q}|")],
                  "length": dec.out((C - Q).norm(), where, f"|{q}{c}|"), "links": [first, second],
                  "closing": closing, "on": on, "q0": dec.out(q0, where, "the motor's start angle"),
                  "omega": item.get("omega", self.default_rate(dec.f.size)[1]), "alpha": item.get("alpha", 0.0),
                  "branch": 1 if turn.value > 0 else -1}, label)
        dec.placed.update((pivot, q))
        dec.pair_frame(first, p, pivot)
        dec.pair_frame(second, pivot, q)
        dec.pair_frame(closing, c, q)
        dec.classes.append(f"input motor {link} on {on} at {pivot}, closing the loop {first}-{second}-{closing} "
                           f"(dyad RRR over the bent link)")
        for ln in (first, second, closing):
            dec.rigid(ln, where)

    def from_pmks(self, driver):
        """An R joint of exactly two moving links (``a b R x y``): PMKS drives its first two links relative to
        each other, here the second (b, ``link``) turned relative to the first (a, its carrier ``on``)."""
        links = driver.links
        if driver.type != "R" or len(links) != 2 or GROUND in links:
            return None
        return {"kind": "motor", "joint": driver.point, "link": links[1]}

    def default_rate(self, size):
        """One turn per second, as a crank's."""
        return "omega", "360deg"

    def input_key(self, e):
        """``_NAME``: its columns are ``q_NAME dq_NAME ddq_NAME``, its drive ``tau_NAME``."""
        return "_" + e["name"]

    def needs(self, f):
        return (f["pivot"],)

    def needs_links(self, f):
        return (f["on"],) if f["on"] != GROUND else ()

    def check(self, f):
        if f["on"] == GROUND:
            return ("field 'on': a motor turns its link relative to a moving link; a link turned about a ground "
                    "pivot is kind = \"crank\"")
        if f["on"] == f["link"]:
            return f"field 'on': the motor cannot turn its own link {f['link']!r}; name the link its pivot is on"
        return None

    def structure(self, f):
        return Structure(links=(LinkPart(f["link"], f["pivot"], (f["pivot"], f["point"])),),
                         driven_pin=(f["pivot"], f["link"], f["on"]))

    def resolve_extra(self, e, topology):
        """Whether the carrier holds the pivot (reported by :meth:`check_resolved`)."""
        held = topology.members(e["on"])
        e["problem"] = "" if e["pivot"] in held else (
            f"field 'pivot': {e['pivot']!r} is not a point of the carrier {e['on']!r} (its points: "
            f"{', '.join(held)}); pivot the motor on a point of the link named in 'on'")

    def check_resolved(self, e, units="m"):
        return e.get("problem") or None

    def input_joint(self, e):
        return e["pivot"]

    def solve(self, e, st: State):
        j = e["input"]
        q, qd, qdd = st.q[j], st.qd[j], st.qdd[j]
        c0, s0, w0, a0 = st.links[e["on"]]
        cq, sq = np.cos(q), np.sin(q)
        c = c0 * cq - s0 * sq
        s = s0 * cq + c0 * sq
        w, a = w0 + qd, a0 + qdd
        st.points[e["point"]] = on_frame(st.points[e["pivot"]], c, s, w, a, e["length"], 0.0)
        st.links[e["link"]] = (c, s, w, a)

    def measured_extras(self, e, st):
        """Its rate and acceleration from the measured links (its angle is the hinge's)."""
        _, _, w, a = st.links[e["link"]]
        _, _, w0, a0 = st.links[e["on"]]
        key = self.input_key(e)
        return {self.columns[1] + key: w - w0, self.columns[2] + key: a - a0}

    def forces(self, e, ctx):
        """The pivot carries the link's whole known load, the drive its moment about the pivot; the pin's
        reaction and the drive's (the housing) go onto the carrier."""
        link, pivot = e["link"], e["pivot"]
        fx, fy = ctx.resultant(link)
        ctx.pin(pivot, link, -fx, -fy)
        ctx.drive(e, -ctx.moment(link, pivot))


KIND = Motor()
