"""``point``: a point fixed on a link that exists (a rigid point: a coupler point, a ternary link's third
pin, a point on a block).

Fields: ``point`` (placed), ``on`` (the link: two of its points ``["P", "Q"]``, frame origin P and x-axis
P -> Q; or the link's name, frame as the link's own: origin its first point, x-axis its angle ``phiL``; a
block's frame has its origin at the pin and its x-axis along the guide), ``at`` [u, v] in that frame.
"""

from __future__ import annotations

from . import compiled as C
from .base import Attach, Field, JitSpec, Kind, State, Structure, line, on_frame


class Point(Kind):
    name = "point"
    summary = ("a point fixed on a link: on = [P, Q] (frame: origin P, x-axis P->Q) or a link's name (its own "
               "frame)")
    fields = {"point": Field("new"), "on": Field("carrier"), "at": Field("xy")}

    def needs(self, f):
        return tuple(f["on"]) if isinstance(f["on"], tuple) else ()

    def needs_links(self, f):
        return () if isinstance(f["on"], tuple) else (f["on"],)

    def structure(self, f):
        return Structure(attach=(Attach(f["point"], f["on"]),))

    def resolve_extra(self, e, topology):
        if isinstance(e["on"], str):
            e["origin"] = topology.links[e["on"]].origin

    def solve(self, e, st: State):
        u, v = e["at"]
        if isinstance(e["on"], str):
            c, s, w, a = st.links[e["on"]]
            st.points[e["point"]] = on_frame(st.points[e["origin"]], c, s, w, a, u, v)
        else:
            p, q = e["on"]
            O, c, s, w, a = line(st.points[p], st.points[q])
            st.points[e["point"]] = on_frame(O, c, s, w, a, u, v)

    def forces(self, e, ctx):
        """A rigid point adds no link and no joint: the loads at it are already its link's."""


def _layout(e, L, row, par):
    if isinstance(e["on"], str):
        row[2], row[3], row[5] = L.point(e["origin"]), L.link(e["on"]), 1
    else:
        row[2], row[3] = L.point(e["on"][0]), L.point(e["on"][1])
    par[0], par[1] = e["at"]
    L.new_point(e["point"])


def _kernel(st, m, e, ops, par, q, qd, qdd, step, i0, need):
    n, p, pq = ops[e, 1], ops[e, 2], ops[e, 3]
    u, v = par[e, 0], par[e, 1]
    on_link = ops[e, 5] == 1
    for i in range(m):
        if on_link:
            c, s, w, a = st[pq, i], st[pq + 1, i], st[pq + 2, i], st[pq + 3, i]
        else:
            c, s, w, a = C.line(st, p, pq, i)
        x0, x1, x2, x3, x4, x5 = C.frame(st[p, i], st[p + 1, i], st[p + 2, i], st[p + 3, i], st[p + 4, i],
                                         st[p + 5, i], c, s, w, a, u, v)
        C.put(st, n, i, x0, x1, x2, x3, x4, x5)


KIND = Point()
KIND.jit = JitSpec(_layout, _kernel)
