"""``cam``: a disc cam on a turning link driving a follower (SPEC "Cams and followers"); its geometry is
:mod:`analytic.cams`.

Fields: ``point`` F (the trace point: roller centre, knife edge or the flat face's foot on the guide),
``cam`` (the cam's link) and ``pivot`` A (the point of it the cam turns about: a ground point),
``follower`` (``translating``: a block on the ground line ``guide``; ``oscillating``: an arm about the
ground point ``arm_pivot``, of length ``arm``), ``contact`` (``knife``, ``roller`` of radius ``roller``,
``flat`` with an optional ``face_width``), ``base_radius``, ``links`` [the follower], and the follower's law:
``segments`` over the cam angle (design: the tool makes the profile) or ``profile`` (a CSV of the outline in
the cam's frame, file units: the tool finds the motion, :func:`analytic.cams.polygon_lift`).

The cam angle theta is the cam link's angle (its frame's x-axis from +x); the follower's lift is an
explicit function of it (:func:`analytic.cams.follow`), so positions, velocities (theta' = the cam link's
omega) and accelerations (h'' omega^2 + h' alpha) are exact. The cam and the follower make a higher pair: a
topology coupling of kind ``cam`` (one constraint in Gruebler's count), its force solved in closed form
(:meth:`Cam.forces`) along the contact's common normal.

Its own outputs: ``pa_NAME`` (the pressure angle [rad]) and ``rho_NAME`` (the profile's radius of curvature
at the contact [m], < 0 concave), NAME the cam's ``name`` (default: its point's).
"""

from __future__ import annotations

import math

import numpy as np

from analytic import cams as C
from ..quantities import ANGLE, LENGTH, LENGTH_UNITS, lengths_in
from .base import GROUND, Coupling, ExtraOutput, Field, Kind, LinkPart, Slide, State, Structure, slide_origin

GEOMETRY = "profile"
"""The marker of a problem the profile's geometry has (an undercut, a cusp, a narrow face): its text is made
where the file's units are known (:meth:`Cam.check_resolved`)."""


class Cam(Kind):
    name = "cam"
    summary = ("a disc cam on a turning link driving a translating (block on a guide) or oscillating (arm) "
               "follower through a knife, roller or flat face; the law as segments over the cam angle, or a "
               "profile")
    group_class = "cam pair (higher pair)"
    per_design = True
    fields = {"point": Field("new"), "name": Field("word", "{point}"), "cam": Field("linkref"), "pivot": Field("point"),
              "follower": Field("word", "translating"), "guide": Field("guide", None),
              "arm_pivot": Field("word", ""), "arm": Field("length", 0.0), "contact": Field("word", "roller"),
              "roller": Field("length", 0.0), "face_width": Field("length", 0.0), "base_radius": Field("size"),
              "links": Field("links1", ("{point}_follower",)), "segments": Field("camlaw", None),
              "profile": Field("outline", "")}

    # ------------------------------------------------------------------------------------ format
    def needs(self, f):
        pts = (f["pivot"],)
        if f["follower"] == "oscillating" and f["arm_pivot"]:
            pts += (f["arm_pivot"],)
        if f["guide"] is not None:
            pts += f["guide"].uses()
        return pts

    def needs_links(self, f):
        return (f["cam"],) if f["cam"] != GROUND else ()

    def rise_measure(self, f):
        return "angle" if f.get("follower") == "oscillating" else "length"

    def check(self, f):
        if f["follower"] not in C.MOTIONS:
            return f"field 'follower': {f['follower']!r} is not a follower kind; give \"translating\" or \"oscillating\""
        if f["contact"] not in C.CONTACTS:
            return f"field 'contact': {f['contact']!r} is not a contact; give \"knife\", \"roller\" or \"flat\""
        if (f["segments"] is None) == (f["profile"] == ""):
            return "fields 'segments' and 'profile': give one (the follower's law over the cam angle, or the cam's outline)"
        if f["cam"] == GROUND:
            return "field 'cam': the cam must be a turning link, not the ground"
        if f["follower"] == "translating":
            if f["guide"] is None:
                return "field 'guide': a translating follower needs its line: guide = {through = [x, y], angle = \"90deg\"}"
            if f["guide"].points:
                return "field 'guide': the follower's guide must be a ground line {through = ..., angle = ...}"
            if f["arm_pivot"]:
                return "field 'arm_pivot': only an oscillating follower has an arm; drop it (or set follower = \"oscillating\")"
        else:
            if not f["arm_pivot"]:
                return "field 'arm_pivot': an oscillating follower needs the ground point its arm turns about"
            if f["guide"] is not None:
                return "field 'guide': an oscillating follower has no guide; drop it"
            if f["contact"] == "flat":
                return "field 'contact': a flat-faced oscillating follower is not supported; use \"roller\" or \"knife\""
        if f["contact"] != "roller" and f["roller"] != 0.0:
            return "field 'roller': only a roller contact has a radius; drop it (or set contact = \"roller\")"
        if f["contact"] != "flat" and f["face_width"] != 0.0:
            return "field 'face_width': only a flat face has a width; drop it (or set contact = \"flat\")"
        return None

    def check_context(self, f, ground):
        if f["pivot"] not in ground:
            return f"field 'pivot': {f['pivot']!r} must be a ground point (the cam turns about a fixed pivot)"
        if f["follower"] == "oscillating" and f["arm_pivot"] not in ground:
            return f"field 'arm_pivot': {f['arm_pivot']!r} must be a ground point"
        return None

    def resolve_extra(self, e, topology):
        e["problem"] = ""
        if e["pivot"] not in topology.members(e["cam"]):
            e["problem"] = (f"field 'pivot': {e['pivot']!r} is not a point of the cam's link {e['cam']!r} "
                            f"({', '.join(topology.members(e['cam']))})")

    def resolve_at(self, e, ground):
        if e["problem"]:
            return
        if e["contact"] == "roller" and not e["roller"] > 0:
            e["problem"] = ("field 'roller': {0}; a roller's radius must be > 0", e["roller"])
            return
        if e["contact"] == "flat" and e["face_width"] < 0:
            e["problem"] = ("field 'face_width': {0} must be >= 0 (0: not given)", e["face_width"])
            return
        A = ground[e["pivot"]]
        kw = dict(pivot=A, motion=e["follower"], contact=e["contact"], roller=e["roller"],
                  face_width=e["face_width"] or None, base_radius=e["base_radius"], law=e["segments"])
        if e["follower"] == "translating":
            G = e["guide"]
            O = ground[G["through"]] if isinstance(G["through"], str) else G["through"]
            gam = G["angle"]
            offset = (O[0] - A[0]) * -math.sin(gam) + (O[1] - A[1]) * math.cos(gam)
            kw.update(direction=gam, offset=offset, origin=tuple(O))
            prime = e["base_radius"] + (e["roller"] if e["contact"] == "roller" else 0.0)
            if e["contact"] != "flat" and abs(offset) >= prime:
                circle = "prime" if e["contact"] == "roller" else "base"
                e["problem"] = (f"field 'guide': the guide passes {{0}} from the pivot, outside the {circle} circle "
                                f"({{1}}); move it closer or make base_radius larger", abs(offset), prime)
                return
        else:
            B = ground[e["arm_pivot"]]
            D = math.dist(A, B)
            prime = e["base_radius"] + (e["roller"] if e["contact"] == "roller" else 0.0)
            if not e["arm"] > 0 or not D > 0 or not abs(e["arm"] - D) < prime < e["arm"] + D:
                e["problem"] = (f"field 'arm': an arm of {{0}} about {e['arm_pivot']} ({{1}} from the pivot) cannot "
                                f"reach the prime circle ({{2}}); give an arm between {{3}} and {{4}}",
                                e["arm"], D, prime, abs(D - prime), D + prime)
                return
            kw.update(arm_pivot=tuple(B), arm=e["arm"])
        setup = C.Setup(**kw)
        if e["profile"] != "":
            try:
                setup = C.Setup(**{**kw, "law": C.polygon_lift(setup, e["profile"])})
            except ValueError as exc:
                e["problem"] = f"field 'profile': {exc}"
                return
        e["setup"] = setup
        e["problem"] = (GEOMETRY,) if C.problems(C.build(setup)) else ""

    def check_resolved(self, e, units="m"):
        """The problem found when resolving, its lengths in the file's ``units``: a text, a (template, lengths
        [m]...) pair, or the profile's own (:func:`analytic.cams.problems`, built again in those units)."""
        problem = e["problem"]
        if not problem or isinstance(problem, str):
            return problem or None
        if problem[0] is GEOMETRY:
            return C.problems(C.build(e["setup"]), (LENGTH_UNITS[units], units))
        say = lengths_in(units)
        return problem[0].format(*(say(x, digits=4) for x in problem[1:]))

    def extent(self, e):
        return max(abs(e["base_radius"]) + abs(e["roller"]) + abs(e["arm"]), 0.0)

    # ---------------------------------------------------------------------------------- topology
    def structure(self, f):
        (link,), F = f["links"], f["point"]
        coupling = Coupling(link, f["cam"], GROUND, None, kind="cam")
        if f["follower"] == "translating":
            return Structure(links=(LinkPart(link, F, (F,), block=True),), slides=(Slide(link, None, F),),
                             couplings=(coupling,))
        return Structure(links=(LinkPart(link, f["arm_pivot"], (f["arm_pivot"], F)),), couplings=(coupling,))

    def rails(self, e):
        return ((e["links"][0], e["guide"], 0.0),) if e["follower"] == "translating" else ()

    def slide_frames(self, e):
        return {e["links"][0]: (slide_origin(e["guide"]), e["point"], 0.0)} if e["follower"] == "translating" else {}

    def extra_outputs(self, e):
        name = e["name"]
        return (ExtraOutput("pa_" + name, ANGLE, "pressure angle of cam follower " + name),
                ExtraOutput("rho_" + name, LENGTH, "cam's radius of curvature at the contact with " + name))

    def describe(self, e, pose, unit):
        geo = C.build(e["setup"])
        k, name = unit
        out = (f"cam {e['cam']}-{e['links'][0]}: largest pressure angle {math.degrees(geo.pressure_angle_max):.4g}deg, "
               f"smallest radius of curvature {geo.rho_min / k:.6g} {name}")
        if e["contact"] == "flat":
            out += f", face travel {geo.face_travel / k:.6g} {name}"
        return out

    # ------------------------------------------------------------------------------------ solver
    def solve(self, e, st: State):
        setup = e["setup"]
        cc, cs, w, a = st.links[e["cam"]]
        theta = np.arctan2(cs, cc) + np.zeros(st.n)
        g = C.at(setup, theta)
        f = g["follow"]
        h, h1, h2, _ = f.h
        w = w + np.zeros(st.n)
        a = a + np.zeros(st.n)
        Ax, Ay = setup.pivot
        rx, ry = f.r
        vx, vy = f.r1[0] * w, f.r1[1] * w
        ax = f.r2[0] * w * w + f.r1[0] * a
        ay = f.r2[1] * w * w + f.r1[1] * a
        st.points[e["point"]] = (Ax + rx, Ay + ry, vx, vy, ax, ay)
        link, name = e["links"][0], e["name"]
        zero = np.zeros(st.n)
        if setup.motion == "translating":
            c, s = setup.u
            ox, oy = setup.origin
            st.links[link] = (zero + c, zero + s, zero, zero)
            st.slides[link] = ((Ax + rx - ox) * c + (Ay + ry - oy) * s, h1 * w, h2 * w * w + h1 * a)
        else:
            st.links[link] = (np.cos(f.psi), np.sin(f.psi), h1 * w, h2 * w * w + h1 * a)
        if st.extras_wanted:
            st.extras["pa_" + name] = g["pressure_angle"]
            st.extras["rho_" + name] = g["rho"]

    def measured_extras(self, e, st):
        cc, cs = st.links[e["cam"]][:2]
        g = C.at(e["setup"], np.arctan2(cs, cc))
        return {"pa_" + e["name"]: g["pressure_angle"], "rho_" + e["name"]: g["rho"]}

    # ------------------------------------------------------------------------------------ forces
    def contact(self, e, ctx):
        setup = e["setup"]
        cc, cs = ctx.direction(e["cam"])
        g = C.at(setup, np.arctan2(cs, cc))
        Ax, Ay = setup.pivot
        return (Ax + g["contact"][0], Ay + g["contact"][1]), g["normal"]

    def forces(self, e, ctx):
        """Closed form. The contact pushes the follower with N along the common normal n (out of the cam) at
        the contact point K. Translating: the loads W on the block along the guide u balance N n: N = -W.u /
        (n.u); the guide takes the rest across it and the couple about F. Oscillating: moments about the arm
        pivot B: N = -M_B / ((K - B) x n); the pin at B takes the rest. The reaction -N n acts on the cam at
        K (:meth:`analytic.applications.forces.Context.contact`)."""
        setup = e["setup"]
        link, F = e["links"][0], e["point"]
        (kx, ky), (nx, ny) = self.contact(e, ctx)
        W = ctx.resultant(link)
        if setup.motion == "translating":
            c, s = setup.u
            fx, fy = ctx.xy(F)
            N = -(W[0] * c + W[1] * s) / (nx * c + ny * s)
            Gx, Gy = -W[0] - N * nx, -W[1] - N * ny
            couple = -(ctx.moment(link, F) + (kx - fx) * N * ny - (ky - fy) * N * nx)
            ctx.guide(link, Gx, Gy, couple)
        else:
            B = e["arm_pivot"]
            bx, by = ctx.xy(B)
            N = -ctx.moment(link, B) / ((kx - bx) * ny - (ky - by) * nx)
            ctx.pin(B, link, -W[0] - N * nx, -W[1] - N * ny)
        ctx.contact(ctx.step.couplings[0], e, N)

    # -------------------------------------------------------------------------------- simulation
    def mjcf(self, e, ctx):
        """The cam's contact in MuJoCo is :mod:`sim.model.cam_contact` (the profile's collision geometry and
        the roller or face, contacts on between them only), given the element and its geometry
        (:func:`analytic.cams.build` of ``e["setup"]``: the outline in the cam's frame, the follower's kind,
        guide or arm, and the law). Where that module is not installed the model cannot hold the follower
        (its law is not a joint relation MuJoCo can write) and the build is refused in one line."""
        from analytic._common import ParameterError
        try:
            from sim.model import cam_contact
        except ImportError:
            cam_contact = None
        if cam_contact is None or not getattr(cam_contact, "IN_MECHANISMS", False):
            raise ParameterError(f"{ctx.mech.definition.source}: {e['label']}: a cam's contact is simulated on its own "
                                 f"(sim.model.cam_contact) but not yet inside a mechanism's model (compare, simulate, "
                                 f"plot); the analytic commands (analyze, check, forces, export) work") from None
        cam_contact.add(e, ctx, C.build(e["setup"]))


KIND = Cam()
