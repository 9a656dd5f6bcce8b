"""An independent Newton-Euler oracle for joint forces: the whole linkage as one linear system per sample.

It shares nothing with ``analytic/applications/forces.py`` or the kinds' ``forces`` methods (no per-group
elimination, no reverse order, no star of joints): it reads the structure (which points each link carries,
the prismatic pairs, the inputs, the gear pairs), the kinematics (positions and accelerations from the
analytic solver, which ``tests/oracle_linkage.py`` checks) and a mass model, and writes

* unknowns: for every moving link L and every point p it carries, the force f(p, L) that the pin at p puts on
  L; for every prismatic pair, the normal force N (along the block's left normal) and the couple M its guide
  puts on the block, at the block's pin; each input's drive (a couple on a crank, a force along the guide on
  a slider block); each gear pair's constraint moment;
* equations: every moving link's Newton (sum of forces = m a_G, gravity and the external load included) and
  Euler about its centre of mass (sum of moments about G = I alpha); every pin off the ground is massless
  (the forces on the links it joins sum to zero); a ground pin takes whatever its links need.

All equations of all links are solved together, per sample (batched dense solves). The force a joint (a, b)
at p transmits to b is then f(p, b): b is joined at p to a only.
"""

from __future__ import annotations

import numpy as np

GROUND = "ground"


def _ratio(mech, c, elements) -> float:
    """A gear pair's ratio: the value of the field its kind names for it (the kind's Coupling)."""
    from analytic import kinds
    written = mech.definition.elements[c.element]
    field = next(k.ratio for k in kinds.get(written.kind).structure(written.fields).couplings
                 if (k.link, k.mesh) == (c.link, c.mesh))
    return float(elements[mech.topology.order.index(c.element)][field])


def _cam_contact(mech, c, sol):
    """The contact point K and the unit common normal n (out of the cam) of a cam coupling, from the solved
    motion alone: with r = F - A (F the trace point, A the cam's pivot) and r' = dF/dtheta = v_F / omega_cam
    (the follower's velocity per cam rate; the cam turns about the fixed A), the pitch curve's normal in the
    world is r + J r' (J the quarter turn: the cam-frame curve R(-theta) r has tangent R(-theta)(r' - J r));
    a roller touches at K = F - r_r n, a knife at F; a flat face square to the guide u has n = u and touches
    where its line envelops the cam: K = A + (r . u) u - (r' . u) J u."""
    e = next(x for x in mech.geometry.elements if x["kind"] == "cam" and x["links"][0] == c.link)
    F, (ax, ay) = e["point"], mech.geometry.ground[e["pivot"]]
    rx, ry = sol["x" + F] - ax, sol["y" + F] - ay
    w = sol["omega" + c.mesh]
    r1x, r1y = sol["vx" + F] / w, sol["vy" + F] / w
    if e["contact"] == "flat":
        ux, uy = np.cos(e["guide"]["angle"]), np.sin(e["guide"]["angle"])
        d, d1 = rx * ux + ry * uy, r1x * ux + r1y * uy
        return (ax + d * ux + d1 * uy, ay + d * uy - d1 * ux), (ux + 0 * rx, uy + 0 * rx)
    nx, ny = rx - r1y, ry + r1x
    norm = np.hypot(nx, ny)
    nx, ny = nx / norm, ny / norm
    rr = e["roller"] if e["contact"] == "roller" else 0.0
    return (ax + rx - rr * nx, ay + ry - rr * ny), (nx, ny)


def solve(mech, sol, inertias, gravity=(0.0, 0.0), force=(0.0, 0.0), force_on=1.0):
    """Joint forces from the whole linkage's Newton-Euler equations.

    Returns a dict: ``joints`` {joint name: (Fx, Fy, M)} (force ``a`` exerts on ``b``; M the guide's couple on
    a prismatic pair's block, 0 for a revolute), ``drives`` {input link: torque or force}, ``shaking``
    (Fx, Fy, M about the origin) the moving links put on the ground."""
    topo = mech.topology
    n = np.size(sol["x" + mech.points[0]])
    g = np.asarray(gravity, dtype=float)
    fe = np.asarray(force, dtype=float)[:, None] * np.broadcast_to(np.asarray(force_on, dtype=float), (n,))
    links = list(topo.links)
    carried = {ln: list(dict.fromkeys(link.points)) for ln, link in topo.links.items()}
    unknowns = []                                      # (kind, key)
    for ln in links:
        for p in carried[ln]:
            unknowns += [("fx", (p, ln)), ("fy", (p, ln))]
    prismatic = [j for j in topo.joints if j.kind == "prismatic"]
    for j in prismatic:
        unknowns += [("N", j.name), ("M", j.name)]
    for inp in mech.inputs:
        unknowns.append(("drive", inp.link))
    elements = mech.geometry.elements
    for k, c in enumerate(topo.couplings):
        unknowns.append(("lambda", k))
    col = {u: i for i, u in enumerate(unknowns)}
    pins = [p for p in topo.points if p not in topo.ground and any(p in carried[ln] for ln in links)]
    rows = 3 * len(links) + 2 * len(pins)
    assert rows == len(unknowns), (rows, len(unknowns), "the linkage is not statically determinate")
    K = len(unknowns)
    A = np.zeros((n, K, K))
    b = np.zeros((n, K))

    def P(p):
        return sol["x" + p], sol["y" + p]

    G, aG = {}, {}
    for ln in links:
        o = topo.links[ln].origin
        c, s = sol["cos" + ln], sol["sin" + ln]
        ine = inertias.get(ln)
        cx, cy = (ine.cx, ine.cy) if ine is not None else (0.0, 0.0)
        rx, ry = cx * c - cy * s, cx * s + cy * c
        w, al = sol["omega" + ln], sol["alpha" + ln]
        G[ln] = (sol["x" + o] + rx, sol["y" + o] + ry)
        aG[ln] = (sol["ax" + o] - al * ry - w * w * rx, sol["ay" + o] + al * rx - w * w * ry)

    def add_force(r, ln, p, column, ux, uy, sign=1.0):
        """Force ``sign * (ux, uy) * unknown`` at point p on link ln (rows r, r+1, r+2)."""
        gx, gy = G[ln]
        px, py = P(p)
        A[:, r, column] += sign * ux
        A[:, r + 1, column] += sign * uy
        A[:, r + 2, column] += sign * ((px - gx) * uy - (py - gy) * ux)

    row_of = {ln: 3 * i for i, ln in enumerate(links)}
    one, zero = np.ones(n), np.zeros(n)
    for ln in links:
        r = row_of[ln]
        ine = inertias.get(ln)
        m, I = (ine.m, ine.I) if ine is not None else (0.0, 0.0)
        for p in carried[ln]:
            add_force(r, ln, p, col[("fx", (p, ln))], one, zero)
            add_force(r, ln, p, col[("fy", (p, ln))], zero, one)
        b[:, r] = m * aG[ln][0] - m * g[0]
        b[:, r + 1] = m * aG[ln][1] - m * g[1]
        b[:, r + 2] = I * sol["alpha" + ln]
    out_p = mech.output_point
    host = topo.loaded_link(out_p)                # the block where the point is its pin (SPEC: --force, issue 41)
    if host != GROUND:
        r = row_of[host]
        gx, gy = G[host]
        px, py = P(out_p)
        b[:, r] -= fe[0]
        b[:, r + 1] -= fe[1]
        b[:, r + 2] -= (px - gx) * fe[1] - (py - gy) * fe[0]
    for j in prismatic:
        c, s = sol["cos" + j.b], sol["sin" + j.b]
        for ln, sign in ((j.b, 1.0), (j.a, -1.0)):
            if ln == GROUND:
                continue
            add_force(row_of[ln], ln, j.point, col[("N", j.name)], -s, c, sign)
            A[:, row_of[ln] + 2, col[("M", j.name)]] += sign
    for inp in mech.inputs:                            # a couple on a driven revolute's link b (a crank, a
        jt = next(j for j in topo.joints if j.input is not None and mech.inputs[j.input].link == inp.link)
        if jt.kind == "revolute":                      # motor), minus on its base a; a force along a driven
            A[:, row_of[jt.b] + 2, col[("drive", inp.link)]] += 1.0     # slide's block b (a slider, an actuator's rod)
            if jt.a != GROUND:
                A[:, row_of[jt.a] + 2, col[("drive", inp.link)]] -= 1.0
        else:
            c, s = sol["cos" + jt.b], sol["sin" + jt.b]
            add_force(row_of[jt.b], jt.b, jt.point, col[("drive", inp.link)], c, s)
            if jt.a != GROUND:
                add_force(row_of[jt.a], jt.a, jt.point, col[("drive", inp.link)], c, s, -1.0)
    for k, c in enumerate(topo.couplings):
        if c.kind == "cam":                            # N n at the contact K on the follower, -N n on the cam
            (kx, ky), (nx, ny) = _cam_contact(mech, c, sol)
            for ln, sign in ((c.link, 1.0), (c.mesh, -1.0)):
                if ln != GROUND:
                    gx, gy = G[ln]
                    r, cl = row_of[ln], col[("lambda", k)]
                    A[:, r, cl] += sign * nx
                    A[:, r + 1, cl] += sign * ny
                    A[:, r + 2, cl] += sign * ((kx - gx) * ny - (ky - gy) * nx)
            continue
        ratio = _ratio(mech, c, elements)
        for ln, f in ((c.link, 1.0), (c.mesh, -ratio), (c.carrier, ratio - 1.0)):
            if ln != GROUND:
                A[:, row_of[ln] + 2, col[("lambda", k)]] += f
    for i, p in enumerate(pins):
        r = 3 * len(links) + 2 * i
        for ln in links:
            if p in carried[ln]:
                A[:, r, col[("fx", (p, ln))]] = 1.0
                A[:, r + 1, col[("fy", (p, ln))]] = 1.0
    x = np.linalg.solve(A, b[..., None])[..., 0]

    def f(p, ln):
        return x[:, col[("fx", (p, ln))]], x[:, col[("fy", (p, ln))]]

    joints = {}
    for j in topo.joints:
        if j.kind == "revolute":
            fx, fy = f(j.point, j.b)
            joints[j.name] = (fx, fy, zero)
        else:
            c, s = sol["cos" + j.b], sol["sin" + j.b]
            N = x[:, col[("N", j.name)]]
            joints[j.name] = (-s * N, c * N, x[:, col[("M", j.name)]])
    drives = {inp.link: x[:, col[("drive", inp.link)]] for inp in mech.inputs}
    # what the moving links put on the ground: minus every ground pin's forces, the guides' reactions, the
    # drives' reactions (about the origin)
    sx, sy, sm = zero.copy(), zero.copy(), zero.copy()
    for p in topo.ground:
        px, py = P(p)
        for ln in links:
            if p in carried[ln]:
                fx, fy = f(p, ln)
                sx, sy, sm = sx - fx, sy - fy, sm - (px * fy - py * fx)
    for j in prismatic:
        if j.a == GROUND:
            fx, fy, M = joints[j.name]
            px, py = P(j.point)
            sx, sy, sm = sx - fx, sy - fy, sm - (px * fy - py * fx) - M
    for inp in mech.inputs:
        jt = next(j for j in topo.joints if j.input is not None and mech.inputs[j.input].link == inp.link)
        if jt.a != GROUND:
            continue
        d = drives[inp.link]
        if jt.kind == "revolute":
            sm = sm - d
        else:
            c, s = sol["cos" + jt.b], sol["sin" + jt.b]
            px, py = P(jt.point)
            sx, sy, sm = sx - d * c, sy - d * s, sm - (px * d * s - py * d * c)
    for k, c in enumerate(topo.couplings):
        if c.kind == "cam":                            # between two moving links: nothing on the ground
            continue
        ratio = _ratio(mech, c, elements)
        for ln, fct in ((c.link, 1.0), (c.mesh, -ratio), (c.carrier, ratio - 1.0)):
            if ln == GROUND:
                sm = sm + fct * x[:, col[("lambda", k)]]   # the gear pair's couple on the ground carrier
    return {"joints": joints, "drives": drives, "shaking": (sx, sy, sm)}


def compare(mech, q, qd, qdd, gravity=(0.0, 0.0), force=(0.0, 0.0)) -> dict:
    """The force solver (``analytic.applications.forces``, on the mass model) against this oracle on the
    same motion: the worst error of every joint force relative to the peak joint force, of every prismatic
    pair's couple relative to that peak times the mechanism's size, of every drive relative to its peak, and
    of the shaking force and moment (same scales)."""
    from analytic import mass
    from analytic.applications import forces as F
    inertias = mass.model(mech)
    sol = mech.solve(q, qd, qdd, outputs=F.wanted(mech) + [c + p for p in mech.points for c in ("vx", "vy")])
    got = F.solve(mech, q, qd, qdd, inertias, gravity, force, sol=sol)
    ref = solve(mech, sol, inertias, gravity, force)
    peak = max(float(np.max(np.hypot(fx, fy))) for fx, fy, _ in ref["joints"].values())
    moment = peak * mech.size
    worst = {"joints": 0.0, "couples": 0.0, "drives": 0.0, "shaking": 0.0, "peak": peak}
    for k, j in enumerate(got.joints):
        fx, fy, M = ref["joints"][j.name]
        worst["joints"] = max(worst["joints"], float(np.max(np.hypot(got.F[k, 0] - fx, got.F[k, 1] - fy))) / peak)
        worst["couples"] = max(worst["couples"], float(np.max(np.abs(got.M(k) - M))) / moment)
    for link, d in ref["drives"].items():
        scale = max(float(np.max(np.abs(d))), 1e-300)
        worst["drives"] = max(worst["drives"], float(np.max(np.abs(got.drives[link] - d))) / scale)
    sx, sy, sm = ref["shaking"]
    worst["shaking"] = max(float(np.max(np.hypot(got.shaking[0] - sx, got.shaking[1] - sy))) / peak,
                           float(np.max(np.abs(got.shaking[2] - sm))) / moment)
    return worst
