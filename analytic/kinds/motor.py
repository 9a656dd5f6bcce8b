"""``motor``: a driven revolute between two moving links (an input): a robot's elbow.

Fields: ``name`` (its input's name: columns ``q_NAME``, ``dq_NAME``, ``ddq_NAME``), ``pivot`` (the joint, a
point of the carrier link ``on``), ``on`` (the carrier: a moving link that exists), ``point`` (the new point at
``length`` from the pivot on the driven link), ``link`` (the driven link, default pivot + point) and its motion
law ``q(t) = q0 + omega t + alpha t^2 / 2`` of the relative angle ``q = phi(link) - phi(on)``.

Its drive is the torque the motor puts on ``link``; the reaction (the motor's housing) acts on ``on``.
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
        """Once one of the two moving links at the joint is placed (its carrier) and the other is not."""
        at = [ln for ln in dec.f.pins.get(item.get("joint"), []) if ln != GROUND]
        link = item.get("link")
        if link in at:
            return any(ln in dec.known for ln in at if ln != link) and link not in dec.known
        return len(at) == 2 and sum(ln in dec.known for ln in at) == 1

    def from_joints(self, item, where, dec):
        """Drive the link at the R joint ``joint`` that is not yet placed (or ``link``) relative to the other,
        its carrier; its point is its next point, its start angle the pose's."""
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
        else:
            free = [ln for ln in at if ln not in dec.known]
            if len(at) != 2 or len(free) != 1:
                raise dec.fail(where, f"name the driven link (link = \"...\"): links at {pivot}: {', '.join(at)}"
                                      f"{'' if free else ', each already placed by other joints'}")
            link = free[0]
        if link in dec.known:
            raise dec.fail(where, f"link {link!r} is already placed by other joints (or driven twice); drive a "
                                  f"link that only this joint turns")
        on = next((ln for ln in at if ln != link and ln in dec.known), None)
        if on is None:
            raise dec.fail(where, f"no link at {pivot!r} besides {link!r} is placed: a motor turns its link "
                                  f"relative to a link placed by the rest of the mechanism")
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
