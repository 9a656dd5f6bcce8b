"""``gear``: a gear turning about a pivot on a carrier, meshed with a gear of a link that turns about the same
carrier; a planetary (epicyclic) train when the carrier is a moving arm.

Fields: ``point`` (the point it places, on the new gear at ``length`` from its centre: it gives the gear
link its frame, x-axis pivot -> point), ``pivot`` (the gear's centre, a point of the carrier), ``length``,
``link`` (the new gear link, default pivot + point), ``mesh`` (the link of the gear it meshes with: a link
pinned to the carrier at one point, the centre of that gear; the ground when the carrier is an arm pivoted
on the ground, e.g. a fixed sun or ring gear), ``carrier`` (the link both gears turn on; default the
ground), ``ratio`` and ``phase``. With phi_L the angle of link L (phi_ground = 0), b the new gear, a the mesh
link and c the carrier:

    phi_b - phi_c = phase + ratio (phi_a - phi_c)

(Willis' equation of an epicyclic pair, R. Willis, *Principles of Mechanism*, 1841, ch. on aggregate
motions): ``ratio`` < 0 for an external pair (the gears turn opposite ways relative to the carrier), > 0
for an internal one (a ring gear), |ratio| = r_a / r_b the pitch radii's ratio. ``phase`` is the new gear's
angle relative to the carrier when the mesh gear's relative angle is 0; with a ground carrier and a crank
as the mesh, phi_b = phase + ratio phi_crank.

The pitch radii follow from the centre distance d (pivot to the mesh gear's centre, fixed on the carrier):
external r_a + r_b = d, internal |r_a - r_b| = d (the larger one is the ring). A ratio of 0 (a gear that
cannot turn) or 1 (an internal pair of equal radii) cannot mesh and is refused; d = 0 (coaxial gears) is a
compound train with no single pair of pitch circles and is accepted as a pure ratio.

Angles in the relation are counted in whole turns where they are known so: the ground, a link driven by an
input (its input angle) and a gear's link (this relation). The angle of any other link (a rocker of a dyad)
is taken in (-pi, pi], relative to the carrier when neither is counted: with a ratio that is not an
integer such a mesh link must not swing through that cut.

Structure: the new link, a revolute between it and the carrier at ``pivot``, and a gear coupling (a higher
pair: Gruebler's count takes one freedom for it). Positions, velocities and accelerations are exact:
omega_b = omega_c + ratio (omega_a - omega_c), the same for alpha, and the point on a circle about the pivot,
which moves with the carrier.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np


from .base import GROUND, Coupling, Field, Kind, LinkPart, State, Structure, Wheel, on_frame

RATIO_EPS = 1e-9
"""A ratio within this of 0 or 1 would need a pitch radius over 1e9 times the centre distance: no gear pair."""


class Gear(Kind):
    name = "gear"
    summary = ("a gear link pivot->point turning on a carrier (ground or an arm) at a fixed ratio to the mesh "
               "gear's rotation relative to the carrier (external < 0, internal > 0)")
    group_class = "gear pair (higher pair)"
    fields = {"point": Field("new"), "pivot": Field("point"), "length": Field("size"),
              "link": Field("link", "{pivot}{point}"), "mesh": Field("linkref"),
              "carrier": Field("linkref", GROUND), "ratio": Field("number"), "phase": Field("angle", 0.0)}

    # ------------------------------------------------------------------------------------ format
    def needs(self, f):
        return (f["pivot"],)

    def needs_links(self, f):
        return tuple(ln for ln in (f["mesh"], f["carrier"]) if ln != GROUND)

    def check(self, f):
        if f["mesh"] == f["link"]:
            return f"field 'mesh': the gear cannot mesh with its own link {f['link']!r}; name the driving gear's link"
        if f["carrier"] == f["link"]:
            return f"field 'carrier': the gear cannot turn on its own link {f['link']!r}; name the link its pivot is on"
        if f["mesh"] == f["carrier"]:
            return (f"field 'mesh': {f['mesh']!r} is also the carrier: a gear fixed to the carrier does not turn "
                    f"relative to it; name the link of the gear it meshes with")
        return None

    def check_context(self, f, ground):
        if f["carrier"] == GROUND and f["pivot"] not in ground:
            return (f"field 'pivot': {f['pivot']!r} must be a ground point (the carrier is the ground), or name "
                    f"the link it is on in 'carrier'")
        return None

    def check_resolved(self, e, units="m"):
        if e["problem"]:
            return e["problem"]
        k = e["ratio"]
        if abs(k) <= RATIO_EPS:
            return "field 'ratio': 0 holds the gear still on its carrier (an infinite pitch radius); give a ratio != 0"
        if abs(k - 1.0) <= RATIO_EPS:
            return ("field 'ratio': 1 turns the gear with its mesh as one body (an internal pair of equal pitch "
                    "radii cannot mesh); give a ratio != 1")
        return None

    # ---------------------------------------------------------------------------------- topology
    def structure(self, f):
        return Structure(links=(LinkPart(f["link"], f["pivot"], (f["pivot"], f["point"])),),
                         couplings=(Coupling(f["link"], f["mesh"], f["carrier"], "ratio"),))

    def resolve_extra(self, e, topology):
        """Record the mesh gear's centre (the one point its link shares with the carrier), the links among
        mesh and carrier that an input drives about a ground pivot ({link: input index}: their angles are the
        inputs' counted in turns), and a structural problem if any (reported by :meth:`check_resolved`)."""
        carrier, mesh = e["carrier"], e["mesh"]
        on_carrier = topology.members(carrier)
        e["problem"] = ""
        if e["pivot"] not in on_carrier:
            where = "ground points" if carrier == GROUND else f"points of link {carrier}"
            e["problem"] = (f"field 'pivot': {e['pivot']!r} is not on the carrier {carrier!r} ({where}: "
                            f"{', '.join(on_carrier)}); pivot the gear on a point of its carrier")
        shared = [p for p in topology.members(mesh) if p in on_carrier]
        e["centre"] = shared[0] if len(shared) == 1 else None
        e["mesh_ref"] = next((p for p in topology.members(mesh) if p not in shared), None) if mesh != GROUND else None
        if not e["problem"] and len(shared) != 1:
            how = "shares no point with" if not shared else f"shares {len(shared)} points ({', '.join(shared)}) with"
            e["problem"] = (f"field 'mesh': link {mesh!r} {how} the carrier {carrier!r}; the mesh gear must turn "
                            f"about one pin on the carrier (its centre)")
        driven = {}
        for j in topology.joints:
            if j.kind == "revolute" and j.input is not None and GROUND in (j.a, j.b):
                other = j.b if j.a == GROUND else j.a
                if other in (mesh, carrier):
                    driven[other] = j.input
        e["driven"] = driven

    def describe(self, e, pose, unit):
        scale, name = unit
        (px, py), (cx, cy) = pose[e["pivot"]], pose[e["centre"]]
        d = math.hypot(px - cx, py - cy)
        r_a, r_b = pitch_radii(e["ratio"], d)
        a, b = e["mesh"], e["link"]
        if d == 0.0:
            return f"gear {b}-{a}: coaxial (centre distance 0), a compound train of ratio {e['ratio']:g}"
        kind = "external" if e["ratio"] < 0 else f"internal, {a if r_a > r_b else b} is the ring"
        return (f"gear {b}-{a} on {e['carrier']}: pitch radii {r_b / scale:.6g} ({b}) and {r_a / scale:.6g} ({a}) "
                f"{name} at centre distance {d / scale:.6g} {name} ({kind})")

    def wheels(self, e, pose):
        """The two pitch circles, toothed so that they mesh: teeth in the ratio (as a fraction), a tooth of
        the mesh gear and a gap of the new gear at the contact point at the start."""
        (px, py), (cx, cy) = pose[e["pivot"]], pose[e["centre"]]
        d = math.hypot(px - cx, py - cy)
        if d == 0.0:                                   # coaxial: no pair of pitch circles
            return ()
        k = e["ratio"]
        r_a, r_b = pitch_radii(k, d)
        ux, uy = (px - cx) / d, (py - cy) / d
        if k < 0 or r_a > r_b:                         # contact on the mesh gear's circle towards (or past) b
            kx, ky = cx + r_a * ux, cy + r_a * uy
        else:                                          # b is the ring: contact past a, away from b
            kx, ky = px - r_b * ux, py - r_b * uy
        n_a, n_b = teeth(abs(k))

        def phase(x, y, ref, n, gap):
            base = 0.0 if ref is None else math.atan2(pose[ref][1] - y, pose[ref][0] - x)
            return math.atan2(ky - y, kx - x) - base + (math.pi / n if gap else 0.0)

        return (Wheel(e["mesh"], e["centre"], e["mesh_ref"], r_a, n_a, phase(cx, cy, e["mesh_ref"], n_a, False),
                      k > 0 and r_a > r_b),
                Wheel(e["link"], e["pivot"], e["point"], r_b, n_b, phase(px, py, e["point"], n_b, True),
                      k > 0 and r_b > r_a))

    # ------------------------------------------------------------------------------------ solver
    def solve(self, e, st: State):
        k, link = e["ratio"], e["link"]
        zero = np.zeros(st.n)
        _, _, w_c, a_c = (1.0, 0.0, zero, zero) if e["carrier"] == GROUND else st.links[e["carrier"]]
        _, _, w_a, a_a = (1.0, 0.0, zero, zero) if e["mesh"] == GROUND else st.links[e["mesh"]]
        phi_c, counted_c = _turns(e["carrier"], e, st)
        phi_a, counted_a = _turns(e["mesh"], e, st)
        theta = phi_a - phi_c
        if not (counted_a or counted_c):       # two rockers: their relative angle in (-pi, pi]
            theta = _wrap(theta)
        phi = phi_c + e["phase"] + k * theta + zero
        w = w_c + k * (w_a - w_c) + zero
        a = a_c + k * (a_a - a_c) + zero
        c, s = np.cos(phi), np.sin(phi)
        st.links[link] = (c, s, w, a)
        st.angles[link] = phi
        st.points[e["point"]] = on_frame(st.points[e["pivot"]], c, s, w, a, e["length"], 0.0)

    # -------------------------------------------------------------------------------- simulation
    def mjcf(self, e, ctx):
        """The coupling as a tendon equality over the hinges: the angles' changes from the start satisfy
        d phi_b - (1 - ratio) d phi_c - ratio d phi_a = 0 (each change a sum of hinge positions along the
        spanning tree); the pitch circles drawn on the two gears' bodies."""
        k = e["ratio"]
        terms: dict[str, float] = {}
        for ln, coef in ((e["link"], 1.0), (e["carrier"], -(1.0 - k)), (e["mesh"], -k)):
            for joint, c in ctx.angle_terms(ln).items():
                terms[joint] = terms.get(joint, 0.0) + coef * c
        ctx.couple(f"gear_{e['link']}", terms)
        _draw(e, ctx)


def pitch_radii(ratio: float, d: float) -> tuple[float, float]:
    """(r_mesh, r_gear) [m] of a pair at centre distance d [m] whose relative rotations have ``ratio``
    (r_mesh / r_gear = |ratio|): external (ratio < 0) r_mesh + r_gear = d, internal |r_mesh - r_gear| = d."""
    k = abs(ratio)
    r_b = d / (1.0 + k) if ratio < 0 else d / abs(ratio - 1.0)
    return k * r_b, r_b


def teeth(ratio: float, fewest: int = 20, most: int = 240) -> tuple[int, int]:
    """Teeth of the mesh gear and of the new gear for a drawing: in the ratio r_mesh / r_gear (as a fraction
    of denominator <= 24), the smaller gear with at least ``fewest`` where no gear passes ``most``."""
    f = Fraction(ratio).limit_denominator(24)
    p, q = max(f.numerator, 1), max(f.denominator, 1)
    m = max(1, min(math.ceil(fewest / min(p, q)), most // max(p, q)))
    return p * m, q * m


def _wrap(x):
    """x reduced to [-pi, pi]."""
    return x - (2.0 * np.pi) * np.round(x / (2.0 * np.pi))


def _turns(link: str, e: dict, st: State):
    """(angle of ``link`` [rad], whether it is counted in whole turns): the ground's 0; a gear's from its
    relation; a link an input drives about a ground pivot: the input angle plus the (constant) offset of the
    link's frame from it; any other link's in (-pi, pi]."""
    if link == GROUND:
        return 0.0, True
    if link in st.angles:
        return st.angles[link], True
    c, s = st.links[link][:2]
    phi = np.arctan2(s, c)
    j = e["driven"].get(link)
    if j is None:
        return phi, False
    q = st.q[j]
    return q + _wrap(phi - q), True


# ------------------------------------------------------------------------------------------- drawing
def _draw(e, ctx):
    """Each gear's pitch circle on its body, for MuJoCo's viewer: a thin disc, a ring gear as a rim of short
    bars (no mass: the bodies' inertias are explicit)."""
    import mujoco                                  # only the model builder calls this hook

    size = ctx.mech.size
    for i, w in enumerate(KIND.wheels(e, ctx.points)):
        body = ctx.spec.worldbody if w.link == GROUND else ctx.spec.body(w.link)
        x, y = ctx.points[w.centre]
        ox, oy, th = ctx.frames[w.link]            # the body's world pose at the start
        lx = (x - ox) * math.cos(th) + (y - oy) * math.sin(th)
        ly = (y - oy) * math.cos(th) - (x - ox) * math.sin(th)
        name, z = f"gear_{e['link']}_{'ab'[i]}", -0.02 * size
        rgba = [0.55, 0.55, 0.60, 0.35] if i == 0 else [0.85, 0.60, 0.20, 0.35]
        if not w.ring:
            body.add_geom(name=name, type=mujoco.mjtGeom.mjGEOM_CYLINDER, size=[w.radius, 0.002 * size, 0],
                          pos=[lx, ly, z], rgba=rgba, contype=0, conaffinity=0, density=0)
            continue
        n = 72
        for j in range(n):
            t = 2.0 * math.pi * (j + 0.5) / n
            body.add_geom(name=f"{name}_{j}", type=mujoco.mjtGeom.mjGEOM_BOX,
                          size=[0.01 * size, 1.05 * math.pi * w.radius / n, 0.002 * size],
                          pos=[lx + w.radius * math.cos(t), ly + w.radius * math.sin(t), z],
                          quat=[math.cos(t / 2), 0.0, 0.0, math.sin(t / 2)], rgba=rgba[:3] + [0.8],
                          contype=0, conaffinity=0, density=0)


KIND = Gear()
