"""``crank``: a driven link turning about a ground pivot (an input).

Fields: ``pivot`` (a ground point), ``point`` (the crank tip it places), ``length``, ``link`` (default
pivot + point), and its motion law ``phi(t) = phi0 + omega t + alpha t^2 / 2``.
"""

from __future__ import annotations

import math

import numpy as np

from . import compiled as C
from .base import GROUND, Field, JitSpec, Kind, LinkPart, State, Structure


class Crank(Kind):
    name = "crank"
    section = "inputs"
    summary = "a driven link pivot->point turning about a ground pivot"
    angular = True
    columns = ("phi", "omega", "alpha")
    motion_fields = ("phi0", "omega", "alpha")
    fields = {"pivot": Field("point"), "point": Field("new"), "length": Field("size"),
              "link": Field("link", "{pivot}{point}"), "phi0": Field("angle", 0.0),
              "omega": Field("angle", 2 * math.pi), "alpha": Field("angle", 0.0)}

    joints_form = {"pivot": "point", "point": "point", "link": "link", "omega": "angle", "alpha": "angle"}
    joints_summary = "a link turned about a ground pivot"

    def default_rate(self, size):
        """One turn per second, as written."""
        return "omega", "360deg"

    def needs(self, f):
        return (f["pivot"],)

    def check_context(self, f, ground):
        if f["pivot"] not in ground:
            return f"field 'pivot': {f['pivot']!r} must be a ground point"
        return None

    def structure(self, f):
        return Structure(links=(LinkPart(f["link"], f["pivot"], (f["pivot"], f["point"])),),
                         driven_pin=(f["pivot"], f["link"]))

    def input_joint(self, e):
        return e["pivot"]

    def solve(self, e, st: State):
        j = e["input"]
        P = st.points[e["pivot"]]
        r, q, qd, qdd = e["length"], st.q[j], st.qd[j], st.qdd[j]
        c, s = np.cos(q), np.sin(q)
        rx, ry = r * c, r * s
        w2 = qd * qd
        ax = P[4] - qdd * ry
        ax -= w2 * rx
        ay = P[5] + qdd * rx
        ay -= w2 * ry
        st.points[e["point"]] = (P[0] + rx, P[1] + ry, P[2] - qd * ry, P[3] + qd * rx, ax, ay)
        st.links[e["link"]] = (c, s, qd, qdd)

    def from_joints(self, item, where, dec):
        """Drive the link pinned to the ground at ``pivot`` (named by ``link`` or a ``point`` on it)."""
        pivot = dec.point_name(item.get("pivot"), f"{where}: field 'pivot'")
        label, where = where, f"{where} (pivot {pivot})"
        if pivot not in dec.f.links[GROUND]:
            raise dec.fail(where, f"field 'pivot': {pivot!r} is not on the ground; a crank turns about a ground "
                           f"pivot")
        link = item.get("link")
        point = item.get("point")
        if link is not None:
            link = dec.link_name(link, f"{where}: field 'link'")
            if link not in dec.points or link == GROUND:
                raise dec.fail(where, f"field 'link': no moving link named {link!r}")
        elif point is not None:
            point = dec.point_name(point, f"{where}: field 'point'")
            cands = [ln for ln, pts in dec.points.items() if ln != GROUND and pivot in pts and point in pts]
            if len(cands) != 1:
                raise dec.fail(where, f"field 'point': {'no' if not cands else 'more than one'} link carries both "
                               f"{pivot!r} and {point!r}; name the driven link with link = \"...\"")
            link = cands[0]
        else:
            cands = [ln for ln in dec.f.pins.get(pivot, []) if ln != GROUND]
            if len(cands) != 1:
                raise dec.fail(where, f"name the driven link (link = \"...\") or a point on it (point = \"...\"); "
                               f"links at {pivot}: {', '.join(cands) or 'none'}")
            link = cands[0]
        if not {GROUND, link} <= set(dec.f.pins.get(pivot, [])):
            raise dec.fail(where, f"no R joint pins {link!r} to the ground at {pivot!r}; a crank turns a link "
                           f"about its ground pivot")
        if link in dec.known:
            raise dec.fail(where, f"link {link!r} is driven twice (or pinned to the ground at two points); "
                           f"drive each link once")
        if point is None:
            others = [p for p in dec.points[link] if p != pivot]
            slot = next((s for s in dec.f.slides if s.guide == link
                         and (dec.pose[s.point] - dec.pose[pivot]).norm().value > dec.SINGULAR * dec.f.size), None)
            if others:
                point = others[0]
            elif slot is not None:            # a crank that is only a guide: its point under the block
                point = dec.fresh(f"{slot.point}_guide")
                dec.pose[point] = dec.pose[slot.point]
                dec.points[link].append(point)
            else:                             # a crank that is only a gear: its tooth at the pitch point
                point = dec.tooth(link)
                if point is None:
                    raise dec.fail(where, f"link {link!r} carries no point besides {pivot!r}; give it one")
        if point not in dec.points[link] or point == pivot:
            raise dec.fail(where, f"field 'point': {point!r} must be another point of link {link!r}")
        grounded = [p for p in dec.points[link] if p in dec.placed and p != pivot]
        if grounded:
            raise dec.fail(where, f"link {link!r} is pinned to the ground at {pivot} and {grounded[0]}: it cannot "
                           f"turn (a locked loop {link} - ground); remove one of those joints")
        r = dec.pose[point] - dec.pose[pivot]
        length = r.norm()
        if length.value <= dec.SINGULAR * dec.f.size:
            raise dec.fail(where, f"{point!r} and {pivot!r} coincide in the pose; name a point away from the pivot")
        dec.emit({"kind": "crank", "pivot": pivot, "point": point, "link": link,
                  "length": dec.out(length, where, "the crank's length"),
                   "phi0": dec.out(r.angle(), where, "the crank's start angle"),
                   "omega": item.get("omega", self.default_rate(dec.f.size)[1]), "alpha": item.get("alpha", 0.0)}, label)
        dec.placed.add(point)
        dec.pair_frame(link, pivot, point)
        dec.counted.add(link)
        dec.classes.append(f"input crank {link} about {pivot}")
        dec.rigid(link, where)

    def from_pyslvs(self, pair):
        """A pair (base, driver) of two joints turns the link they share about the base, a ground pivot."""
        base, driver = pair.base, pair.driver
        if base == driver:
            return None
        b, d = f"J{base}", f"J{driver}"
        if GROUND not in pair.on.get(b, []):
            raise pair.fail(f"input ({base}, {driver}) turns about {b}, which is not on the ground; only a "
                            f"crank about a ground pivot can be driven")
        shared = [x for x in pair.joints[base][3] if x in pair.joints[driver][3] and x != GROUND]
        if len(shared) != 1:
            raise pair.fail(f"input ({base}, {driver}): {b} and {d} share {len(shared) or 'no'} moving link(s) "
                            f"({', '.join(shared)}); the input turns the one link they share")
        if shared[0] not in pair.on.get(d, []) or shared[0] not in pair.on.get(b, []):
            raise pair.fail(f"input ({base}, {driver}): link {shared[0]} is the slot of a slider at {b} or {d}; "
                            f"drive a link pinned at both")
        return {"kind": "crank", "pivot": b, "point": d, "link": shared[0]}

    def from_pmks(self, driver):
        """An R joint between the ground and a link turns that link about it; its point is the link's next
        joint (the lowest-numbered other one), where it has one."""
        links = driver.links
        if driver.type != "R" or len(links) < 2 or GROUND not in links[:2]:
            return None
        a, b = links[:2]
        p, form = driver.point, driver.form
        driven = b if a == GROUND else a
        pts = next(x.get("points", []) for x in form["links"] if x["name"] == driven)
        pins = [j["point"] for j in form["joints"] if j["kind"] != "G" and driven in j.get("links", [j.get("block")])]
        order = sorted(set(pts) | set(pins), key=lambda q: int(q[1:]))
        other = next((q for q in order if q != p), None)
        return {"kind": "crank", "pivot": p, **({"point": other} if other else {}), "link": driven}

    def forces(self, e, ctx):
        """The pivot carries the crank's whole known load, the drive its moment about the pivot."""
        link, pivot = e["link"], e["pivot"]
        fx, fy = ctx.resultant(link)
        ctx.pin(pivot, link, -fx, -fy)
        ctx.drive(e, -ctx.moment(link, pivot))


def _layout(e, L, row, par):
    row[2], row[4] = L.point(e["pivot"]), e["input"]
    par[0] = e["length"]
    row[3] = L.new_link(e["link"])
    L.new_point(e["point"])


def _sincos_rows(x, s, c):
    """s, c = sin x, cos x over 1-D arrays (separate arrays: the loop vectorises)."""
    for i in range(x.shape[0]):
        s[i], c[i] = C.sincos(x[i])


def _kernel(st, m, e, ops, par, q, qd, qdd, step, i0, need):
    n, p, L, j = ops[e, 1], ops[e, 2], ops[e, 3], ops[e, 4]
    r = par[e, 0]
    if step[0] == 0:                                # the same angle at every sample
        x = q[j, 0]
        s, c = C.sincos(x) if abs(x) <= C.LOSSTH else (math.sin(x), math.cos(x))
        for i in range(m):
            st[L, i] = c
            st[L + 1, i] = s
    else:
        fast = True
        for i in range(m):
            if not abs(q[j, i0 + i]) <= C.LOSSTH:   # beyond 2^30 rad, inf, NaN: the C library's
                fast = False
        if fast:
            _sincos_rows(q[j, i0:i0 + m], st[L + 1, :m], st[L, :m])
        else:
            for i in range(m):
                st[L, i] = math.cos(q[j, i0 + i])
                st[L + 1, i] = math.sin(q[j, i0 + i])
    s1, s2 = step[1], step[2]
    for i in range(m):
        c, s, xd, xdd = st[L, i], st[L + 1, i], qd[j, (i0 + i) * s1], qdd[j, (i0 + i) * s2]
        rx = r * c
        ry = r * s
        w2 = xd * xd
        C.put(st, n, i, st[p, i] + rx, st[p + 1, i] + ry, st[p + 2, i] - xd * ry, st[p + 3, i] + xd * rx,
              st[p + 4, i] - xdd * ry - w2 * rx, st[p + 5, i] + xdd * rx - w2 * ry)
        st[L + 2, i] = xd
        st[L + 3, i] = xdd


KIND = Crank()
KIND.jit = JitSpec(_layout, _kernel, helpers=("_sincos_rows",))
