"""``slider``: a block driven along a ground line (an input).

Fields: ``point`` (the block's pin it places), ``guide`` (a ground line), ``link`` (the block, default
point + ``_block``) and its motion law ``s(t) = s0 + v t + a t^2 / 2``, measured from the guide's origin; ``v``
by default the mechanism's size per second (:data:`analytic.kinds.base.SIZE_PER_SECOND`), as in the
links-and-joints form.
"""

from __future__ import annotations

import numpy as np

from . import compiled as C
from .base import (GROUND, SIZE_PER_SECOND, Field, JitSpec, Kind, LinkPart, Slide, State, Structure, guide_line,
                   guide_link, on_frame, slide_origin)


class Slider(Kind):
    name = "slider"
    section = "inputs"
    summary = "a block driven along a ground line: s(t) = s0 + v t + a t^2/2 from the guide's origin"
    angular = False
    columns = ("s", "ds", "dds")
    motion_fields = ("s0", "v", "a")
    fields = {"point": Field("new"), "guide": Field("guide"), "s0": Field("length", 0.0),
              "v": Field("length", SIZE_PER_SECOND), "a": Field("length", 0.0), "link": Field("link", "{point}_block")}

    joints_form = {"point": "point", "v": "length", "a": "length"}
    joints_summary = "a block driven along a ground guide"

    def default_rate(self, size):
        """The mechanism's size (the largest distance between two of its pose's points) per second, to 3
        digits [file units / s], so that a run of one second moves it as far as the mechanism is large, in any
        unit (as a crank's default turns it once a second)."""
        return "v", float(f"{size:.3g}")

    def needs(self, f):
        return f["guide"].uses()

    def check_context(self, f, ground):
        if any(p not in ground for p in f["guide"].uses()):
            return "field 'guide': a driven slider runs on a ground line"
        return None

    def structure(self, f):
        link = f["link"]
        return Structure(links=(LinkPart(link, f["point"], (f["point"],), block=True),),
                         slides=(Slide(link, guide_link(f["guide"]), f["point"], driven=True),))

    def rails(self, e):
        return ((e["link"], e["guide"], 0.0),) if "points" not in e["guide"] else ()

    def slide_frames(self, e):
        return {e["link"]: (slide_origin(e["guide"]), e["point"], 0.0)}

    def input_joint(self, e):
        g = e["guide"]
        if "points" in g:
            return g["points"][0]
        return g["through"] if isinstance(g["through"], str) else e["point"]

    def solve(self, e, st: State):
        j = e["input"]
        x, xd, xdd = st.q[j], st.qd[j], st.qdd[j]
        O, c, s, w, a = guide_line(e["guide"], st)
        P = on_frame(O, c, s, 0.0, 0.0, x, 0.0)
        st.points[e["point"]] = (P[0], P[1], O[2] + xd * c, O[3] + xd * s, O[4] + xdd * c, O[5] + xdd * s)
        zero = np.zeros(np.shape(x))
        st.links[e["link"]] = (zero + c, zero + s, zero, zero)
        st.slides[e["link"]] = (x, xd, xdd)

    def from_joints(self, item, where, dec):
        """Drive the block of the P joint at ``point`` along its ground guide."""
        point = dec.point_name(item.get("point"), f"{where}: field 'point'")
        label, where = where, f"{where} (point {point})"
        s = next((x for x in dec.f.slides if x.point == point), None)
        if s is None:
            raise dec.fail(where, f"field 'point': no P joint at {point!r}; a slider drives a P joint's block")
        if s.guide != GROUND:
            raise dec.fail(where, f"the P joint at {point!r} slides on {s.guide!r}; a driven slider needs the ground "
                           f"as its guide")
        if s.block in dec.known:
            raise dec.fail(where, f"link {s.block!r} is driven twice; drive each link once")
        grounded = [p for p in dec.points[s.block] if p in dec.placed]
        if grounded:
            raise dec.fail(where, f"block {s.block!r} is also pinned to the ground at {grounded[0]}: it cannot "
                           f"slide; remove that joint")
        dec.emit({"kind": "slider", "point": point, "link": s.block,
                  "guide": {"through": dec.xy(point, where), "angle": dec.out(s.angle, where, "the slide angle")},
                   "s0": 0.0, "v": item.get("v", self.default_rate(dec.f.size)[1]), "a": item.get("a", 0.0)}, label)
        dec.placed.add(point)
        dec.slide_frame(s.block, point, s.angle)
        dec.classes.append(f"input slider {s.block} at {point}")
        dec.rigid(s.block, where)

    def from_pyslvs(self, pair):
        """A pair (base, base) drives the block of the P or RP joint at the base along its ground guide."""
        base, driver = pair.base, pair.driver
        if base != driver:
            return None
        b = f"J{base}"
        pj = next((j for j in pair.pjoints if j["point"] == b), None)
        if pj is None:
            raise pair.fail(f"input ({base}, {driver}) drives J{base} along a slot, but J{base} is no P or RP joint")
        if pj["guide"] != GROUND:
            raise pair.fail(f"input ({base}, {driver}) drives the slider at {b} along link {pj['guide']}; only a "
                            f"slider on a ground guide can be driven")
        return {"kind": "slider", "point": b}

    def from_pmks(self, driver):
        """A P joint between the ground and a block drives the block along it."""
        if driver.type != "P" or len(driver.links) < 2 or GROUND not in driver.links[:2]:
            return None
        return {"kind": "slider", "point": driver.point}

    def forces(self, e, ctx):
        """The drive takes the block's known load along the guide, the guide the normal part and the
        moment about the pin."""
        block, point = e["link"], e["point"]
        c, s = ctx.direction(block)
        fx, fy = ctx.resultant(block)
        normal = s * fx - c * fy                 # -(F . n), n = (-s, c): the guide's force along n
        ctx.guide(block, -s * normal, c * normal, -ctx.moment(block, point))
        ctx.drive(e, -(c * fx + s * fy))


def _layout(e, L, row, par):
    row[4] = e["input"]
    L.guide(row, par, e["guide"])
    row[3] = L.new_link(e["link"])
    row[8] = L.new_slide(e["link"])
    L.new_point(e["point"])


def _kernel(st, m, e, ops, par, q, qd, qdd, step, i0, need):
    n, o, L, j, sl = ops[e, 1], ops[e, 6], ops[e, 3], ops[e, 4], ops[e, 8]
    s0, s1, s2 = step[0], step[1], step[2]
    for i in range(m):
        x, xd, xdd = q[j, (i0 + i) * s0], qd[j, (i0 + i) * s1], qdd[j, (i0 + i) * s2]
        c, s, w, a = C.guide(st, e, ops, par, i)
        C.put(st, n, i, st[o, i] + (x * c - 0.0 * s), st[o + 1, i] + (x * s + 0.0 * c), st[o + 2, i] + xd * c,
              st[o + 3, i] + xd * s, st[o + 4, i] + xdd * c, st[o + 5, i] + xdd * s)
        C.put4(st, L, i, c, s, 0.0, 0.0)
        st[sl, i] = x
        st[sl + 1, i] = xd
        st[sl + 2, i] = xdd


KIND = Slider()
KIND.jit = JitSpec(_layout, _kernel)
