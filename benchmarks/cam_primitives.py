"""Issue 38: would a cam plate made of many primitive geoms (one capsule or one thin box per outline segment)
collide a roller more cheaply than the convex mesh pieces of sim/model/cam_contact.py? Measured, not built.

    PYTHONPATH=. python benchmarks/cam_primitives.py [--counts 180,360,720] [--repeats 3] [--mechanism]

Two cams: the eccentric disc of benchmarks/cam_contact.py (R = 30 mm, e = 10 mm, roller 10 mm, 0.1 kg,
1000 N/m, 10 N preload, at half its jump speed) and cam_roller's outline (analytic.cams.build of
analytic/library/cam_roller.toml's cam: 0.2 kg, 2000 N/m, 40 N at the lowest position, 1 turn/s). Each as a
standalone sim.model.cam_contact model (cc.build: the cam on a hinge, the roller a sphere on a slide) whose
plate geoms are swapped for the option's, integrated with RK4 at the model's time step (STEPS_PER_TURN a turn).

The options, on the outline thinned to N vertices (every k-th of the dense one):

* ``pieces``: the module's convex mesh pieces (fans from the pivot, MuJoCo's GJK/EPA on their hulls).
* ``capsules``: one capsule of radius rc per segment, its axis the segment moved inward by rc: the axes
  join end to end into the outline's inward offset polyline (each vertex moved along its angle's bisector by
  rc / cos(half the turn)), so the union is that polyline swept by a disc of radius rc, whose outer surface is
  the outline's segments themselves, rounded into each convex vertex by rc (1 / cos(b / 2) - 1) ~ rc b^2 / 8
  (b the turn at the vertex: 1.9e-8 m on the disc at 720 segments, as measured) and exact at concave ones. No cap sticks out.
* ``boxes``: one box per segment, its outer face on the segment, rc deep: the union's surface is the
  polyline (a box cannot stick out past its neighbour's face at a convex vertex, and at a concave one the two
  outer faces meet at the vertex).

Per option: the compile time of the whole model (``spec.compile``, least of the repeats); the CPU of one
``mj_step`` (RK4: 4 evaluations) and of one ``mj_forward`` (one evaluation) while the roller rides the cam
(least of the repeats, a revolution's steps each); the surface error: a free sphere of the roller's radius
placed at 73 cam angles 0.1 mm into the cam along the law's contact normal (analytic: the law's pitch point
and normal), max |min contact dist + 1e-4| (the polyline's chord sagitta included, as in cam_contact.py);
over one revolution: the share of steps with two or more active contacts (dist < 0) at the step's last
evaluation, the contacts generated (active or within the roller's gap, which the gap sensor reads), the
contact force's ripple (the force less its moving mean over the contact's ring period, 50 steps,
sim.run.cams.impulse_mean: rms and largest, over the mean force), and the follower's largest error against
the rigid polyline's kinematics (cc.follower_position on the dense outline) next to the tolerance compare
allows it (sim.run.cams.Compliance.position: 50 static penetrations at the largest mean force plus the
chord's sagitta).

Result (2026-12-02, main at efee162, MuJoCo 4.0.0, 2 shared cores, load ~0.7; ``--repeats 3``), CPU per RK4
step / per evaluation [us]; surface error at 73 / 997 probes [m]; steps with 2+ active contacts [%]; follower's
largest error [m] (compare's tolerance: 1.0e-5 disc, 3.2e-3 cam_roller)::

    cam         option     N    geoms compile  step  eval  kin+coll  surface          2+   ripple     track
    disc        pieces     720    6   13.5     21.9   5.41  3.62    1.6e-09/2.9e-07   0.4  0.45/1.90  4.9e-06
    disc        capsules   180  182    0.5     34.4   8.06  7.07    4.6e-06/4.6e-06  51.4  1.28/4.29  7.9e-06
    disc        capsules   720  722    1.8    108.4  27.73 26.02    1.9e-08/2.9e-07  74.6  0.55/1.45  1.4e-06
    disc        boxes      720  722    1.9    108.0  25.75 23.81    9.3e-18/2.9e-07  70.1  0.59/1.71  1.6e-06
    cam_roller  pieces     720    6   12.9     22.6   4.57  2.62    3.3e-07/6.4e-07   1.6  0.00/0.04  3.2e-05
    cam_roller  capsules   180  182    0.5     35.2   9.34  7.36    1.0e-05/1.0e-05  82.0  0.12/1.38  1.8e-04
    cam_roller  capsules   720  722    1.9    108.8  28.23 25.38    3.3e-07/6.4e-07  95.7  0.16/1.39  1.5e-04
    cam_roller  boxes      720  722    1.8    108.8  28.39 25.70    3.3e-07/6.4e-07  95.0  0.19/1.42  1.5e-04
    disc flat   pieces     720    6   13.2     35.6  10.44  8.58    1.6e-09/2.9e-07  82.8  0.60/1.73  1.9e-06
    disc flat   capsules   720  722    2.1    174.2  42.16 39.67    1.9e-08/2.9e-07  92.0  0.43/1.25  1.4e-06
    disc flat   boxes      720  722    1.8    127.7  32.26 28.34    9.3e-18/2.9e-07  91.2  0.44/1.26  1.3e-06

``--mechanism`` (cam_roller's own mechanism model, its plate swapped): pieces 720: compile 13.5 ms, 4.62 us
per evaluation; capsules 180: 0.7 ms, 9.24 us; capsules 720: 2.0 ms, 27.15 us; boxes 720: 2.0 ms, 27.60 us.

No option pays: every primitive plate is slower per evaluation than the 6 mesh pieces, 1.7-2.5x at 180
segments and 5-6x at 720. MuJoCo's cost is per geom, not per pair tested: ~8 ns a geom in mj_kinematics (each
geom's world pose) and ~25 ns a geom in mj_collision (the bounding boxes the broad/midphase sorts), 33 ns a
geom an evaluation (7 us for 180 capsules, 26 us for 720; the 6 pieces' whole collision is 2.6-3.6 us), and
the narrowphase of 4-15 contacts a step instead of 1 (the roller is within the gap of several primitives).
Spreading 720 capsules over 24 or 90 welded child bodies (the broadphase then sorts bodies) did not help
(fwd 28.8 / 32.8 us against 28.1). A line through the 180 and 720 rows (eval = a + 33 ns x N; a = 2.1 us
disc, 3.4 us cam_roller) breaks even with the pieces at N ~ 100 (disc) and ~ 35 (cam_roller), where the chord's
sagitta is 1.5e-5 m (1.5x the disc's tolerance) and 3e-4 m; half the pieces' cost (2.7 / 2.3 us) is below
cam_roller's a even at N = 0. What primitives do save is the compile: 0.5-1.9 ms against the pieces' 2.5-13.5 ms
(qhull, ~9 us a vertex): 12 ms a build at 720, against ~230 ms more stepping on cam_roller's 2001 x 5
evaluations. The surface error is the polyline's (the chord's sagitta) for all three: capsules round each
convex vertex by rc b^2 / 8 (1.9e-8 m at 720 on the disc, 7.6e-8 at 360: the 73 probes there land on
vertices), boxes are exact to rounding. Two or more contacts act at once on 50-95 % of the
steps (the neighbouring primitives share the contact point); the force ripple is then no worse than the
pieces' on the disc (0.55 vs 0.45 rms at 720) but the follower tracks cam_roller 5x worse (1.5e-4 vs 3.2e-5 m,
inside the 3.2e-3 tolerance).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

# benchmarks/analytic.py would shadow the package of that name: keep this folder off the import path.
sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]

import mujoco  # noqa: E402
import numpy as np  # noqa: E402

G = mujoco.mjtGeom
KINDS = ("pieces", "capsules", "boxes")
RC = 0.05
"""The capsules' radius and the boxes' depth as a fraction of the cam's size (2 mm on the disc)."""
PROBES = 997
"""A second, denser probe (a prime count: the probes do not line up with the outline's vertices)."""
PRESS = 1e-4
"""How far [m] the probe sphere is pressed into the cam (benchmarks/cam_contact.py's 0.1 mm)."""


# --------------------------------------------------------------------------------------------- cams
def disc_case(contact="roller"):
    """The eccentric disc: (CamFollower maker taking a profile, dense outline, probes: the law's pitch points
    and normals in the cam's frame at m cam angles, for a probe sphere of the roller's radius)."""
    from sim.model import cam_contact as cc
    R, E, RR, M, K, F0 = 0.03, 0.01, 0.01, 0.1, 1000.0, 10.0
    wj = math.sqrt((F0 + 2 * K * E) / (M * E))
    th = np.linspace(0, 2 * math.pi, 3600, endpoint=False)
    dense = np.c_[R * np.cos(th), -E + R * np.sin(th)]

    def probes(m):
        a = np.linspace(0, 2 * math.pi, m)
        normal = np.c_[np.cos(a), np.sin(a)]
        return np.array([0.0, -E]) + (R + RR) * normal, normal, RR

    def make(profile):
        return cc.CamFollower(profile, (0.0, 0.0), 0.5 * wj, contact=contact, roller=RR, face_width=0.08, mass=M,
                              stiffness=K, preload=F0)
    return make, dense, probes


def roller_case():
    """cam_roller's cam (analytic/library/cam_roller.toml), the same three things."""
    import analytic
    from analytic import cams as C
    from sim.model import cam_contact as cc
    mech = analytic.load("cam_roller")
    e = next(e for e in mech.geometry.elements if e["kind"] == "cam")
    geo = C.build(e["setup"])
    s = geo.setup
    stiffness, free, anchor = 2000.0, 0.10, 0.12                   # the file's return spring
    # the lowest trace point: on the guide (offset e from the pivot) at the pitch curve's least radius
    low = math.sqrt(float(np.min(np.sum(geo.pitch ** 2, axis=1))) - s.offset ** 2)

    def make(profile):
        return cc.CamFollower(profile, s.pivot, 2 * math.pi, contact="roller", roller=s.roller, through=s.origin,
                              angle=s.direction, mass=0.2, stiffness=stiffness,
                              preload=stiffness * (free - (anchor - low)))

    def probes(m):
        g = C.build(e["setup"], m - 1)                                # m - 1 angles over the turn, and 0 again
        k = np.r_[np.arange(m - 1), 0]
        return g.pitch[k], g.normal_cam[k], s.roller
    return make, geo.profile, probes


def thinned(dense, n):
    return dense[::len(dense) // n]


# -------------------------------------------------------------------------------------------- plates
def add_plate(spec, body, P, kind, size, attrs, prefix):
    """The plate of outline ``P`` (cam frame = ``body``'s frame) as the option's geoms."""
    from sim.model import cam_contact as cc
    t = 0.5 * cc.THICKNESS * size
    rc = RC * size
    n = len(P)
    if kind == "pieces":
        for j, (i0, i1) in enumerate(cc.convex_pieces(P)):
            ring = np.vstack([np.zeros(2), P[np.arange(i0, i1 + 1) % n]])
            vert = np.concatenate([np.c_[ring, np.full(len(ring), z)] for z in (-t, t)])
            spec.add_mesh(name=f"{prefix}{j}", uservert=vert.ravel().tolist())
            body.add_geom(name=f"{prefix}{j}", type=G.mjGEOM_MESH, meshname=f"{prefix}{j}", **attrs)
        return
    Q = np.roll(P, -1, axis=0)
    e = Q - P
    L = np.hypot(*e.T)
    tan = e / L[:, None]
    out = np.c_[tan[:, 1], -tan[:, 0]]                              # outward: the outline is counter-clockwise
    if kind == "capsules":
        bis = out + np.roll(out, 1, axis=0)                         # the bisector at each vertex
        bis /= np.hypot(*bis.T)[:, None]
        A = P - bis * (rc / np.sum(bis * out, axis=1))[:, None]     # the inward offset line's vertices
        B = np.roll(A, -1, axis=0)
        for k in range(n):
            body.add_geom(name=f"{prefix}{k}", type=G.mjGEOM_CAPSULE, size=[rc, 0, 0],
                          fromto=[A[k, 0], A[k, 1], 0, B[k, 0], B[k, 1], 0], **attrs)
        return
    mid = 0.5 * (P + Q) - rc * out
    ang = np.arctan2(tan[:, 1], tan[:, 0])
    for k in range(n):
        body.add_geom(name=f"{prefix}{k}", type=G.mjGEOM_BOX, size=[0.5 * L[k], rc, t], pos=[mid[k, 0], mid[k, 1], 0],
                      quat=[math.cos(ang[k] / 2), 0, 0, math.sin(ang[k] / 2)], **attrs)


def dynamic_model(make, P, kind):
    """cc.build's model of the cam with outline P, its plate swapped for the option's, RK4."""
    from sim.model import cam_contact as cc
    cam = make(P)
    built = cc.build(cam)
    spec = built.spec
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_RK4
    if kind != "pieces":
        g0 = spec.geom("cam0")
        attrs = dict(contype=g0.contype, conaffinity=g0.conaffinity, condim=g0.condim, solref=list(g0.solref),
                     solimp=list(g0.solimp), density=0)
        for g in [g for g in spec.geoms if g.type == G.mjGEOM_MESH]:
            spec.delete(g)
        for m in list(spec.meshes):
            spec.delete(m)
        add_plate(spec, spec.body("cam"), P, kind, cam.size, attrs, "prim")
    return cam, built, spec


def surface_error(P, kind, pitch, normal, radius):
    """The probe: a free sphere at the law's pitch point pressed PRESS into the plate along its normal."""
    size = float(np.max(np.hypot(*P.T)))
    spec = mujoco.MjSpec()
    spec.option.gravity = [0, 0, 0]
    add_plate(spec, spec.worldbody, P, kind, size, dict(contype=1, conaffinity=0, condim=1), "plate")
    ball = spec.worldbody.add_body(name="ball")
    ball.add_freejoint()
    ball.add_geom(type=G.mjGEOM_SPHERE, size=[radius, 0, 0], contype=0, conaffinity=1, condim=1, mass=0.1)
    m = spec.compile()
    d = mujoco.MjData(m)
    errs = []
    for p, nrm in zip(pitch, normal):
        c = p - PRESS * nrm
        d.qpos[:7] = [c[0], c[1], 0, 1, 0, 0, 0]
        mujoco.mj_kinematics(m, d)
        mujoco.mj_collision(m, d)
        errs.append(min(d.contact.dist[:d.ncon]) + PRESS if d.ncon else math.inf)
    return float(np.max(np.abs(errs)))


def least(fn, repeats):
    out = []
    for _ in range(repeats):
        t0 = time.process_time()
        fn()
        out.append(time.process_time() - t0)
    return min(out)


def measure(make, dense, probes, kind, n, repeats):
    from sim.model import cam_contact as cc
    from sim.run.cams import impulse_mean
    P = thinned(dense, n)
    cam, built, spec = dynamic_model(make, P, kind)
    compile_s = least(spec.compile, repeats)
    m = spec.compile()
    d = mujoco.MjData(m)
    steps = built.steps_per_turn

    def revolution(fn):
        mujoco.mj_resetDataKeyframe(m, d, 0)
        for _ in range(steps):
            fn(m, d)
    step_s = least(lambda: revolution(mujoco.mj_step), repeats) / steps
    mujoco.mj_resetDataKeyframe(m, d, 0)
    fwd_s = least(lambda: revolution(mujoco.mj_forward), repeats) / steps

    def geoms(m, d):
        mujoco.mj_kinematics(m, d)
        mujoco.mj_collision(m, d)
    geoms_s = least(lambda: revolution(geoms), repeats) / steps
    # one revolution, read at every step
    adr = {m.sensor(i).name: int(m.sensor_adr[i]) for i in range(m.nsensor)}
    mujoco.mj_resetDataKeyframe(m, d, 0)
    theta, q, force, active, found = (np.empty(steps) for _ in range(5))
    for k in range(steps):
        mujoco.mj_step(m, d)
        theta[k], q[k] = d.qpos
        fa = adr["contact_force"]
        force[k] = np.linalg.norm(d.sensordata[fa + 1:fa + 4]) if d.sensordata[fa] > 0 else 0.0
        active[k] = int(np.sum(d.contact.dist[:d.ncon] < 0))
        found[k] = d.ncon
    ref = cc.follower_position(make(dense), theta)
    mean = impulse_mean(force)
    w = len(force) - len(mean)
    ripple = force[w // 2:w // 2 + len(mean)] - mean
    fbar = float(np.mean(mean))
    n_max = float(np.max(mean))
    rho = _rho_min(dense)
    seg = float(np.max(np.hypot(*(np.roll(P, -1, axis=0) - P).T)))
    bound = 50 * float(cc.penetration(n_max, built.m_eff, built.timestep)) + seg * seg / (8 * rho)
    return dict(kind=kind, n=n, ngeom=m.ngeom, compile_ms=compile_s * 1e3, step_us=step_s * 1e6,
                fwd_us=fwd_s * 1e6, geoms_us=geoms_s * 1e6, surface=surface_error(P, kind, *probes(73)),
                surface_dense=surface_error(P, kind, *probes(PROBES)),
                double=float(np.mean(active >= 2)), found=float(np.mean(found)),
                ripple_rms=float(np.sqrt(np.mean(ripple ** 2))) / fbar, ripple_max=float(np.max(np.abs(ripple))) / fbar,
                track=float(np.max(np.abs(q - ref))), bound=bound)


def _rho_min(dense):
    """The dense outline's smallest radius of curvature (three-point circles) [m]."""
    a, b, c = np.roll(dense, 1, axis=0), dense, np.roll(dense, -1, axis=0)
    ab, bc, ca = (np.hypot(*(x - y).T) for x, y in ((a, b), (b, c), (c, a)))
    cross = np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    return float(np.min(ab * bc * ca / np.maximum(2 * cross, 1e-300)))


def mechanism_check(repeats):
    """cam_roller's own mechanism model (sim.model.build, its MJCF as exported), its plate's pieces swapped for
    the options' (on the cam link's body, whose frame is the cam's here: the pivot at its origin, angle 0):
    compile and CPU per evaluation (mj_forward) at the start pose."""
    import analytic
    from analytic import cams as C
    from sim.model.build import build
    mech = analytic.load("cam_roller")
    built = build(mech, export=True)
    geo = C.build(next(e for e in mech.geometry.elements if e["kind"] == "cam")["setup"])
    for kind, n in (("pieces", 720), ("capsules", 180), ("capsules", 720), ("boxes", 720)):
        spec = mujoco.MjSpec.from_string(built.spec_xml)
        spec.compiler.balanceinertia = True                  # the MJCF's printed inertias round off A + B >= C
        pieces = [g for g in spec.geoms if g.name.startswith("cam0_piece")]
        g0 = pieces[0]
        attrs = dict(contype=g0.contype, conaffinity=g0.conaffinity, condim=1, solref=list(g0.solref),
                     solimp=list(g0.solimp), density=0)
        body = g0.parent
        for g in pieces:
            spec.delete(g)
        for m in [m for m in spec.meshes if m.name.startswith("cam0_piece")]:
            spec.delete(m)
        P = thinned(geo.profile, n)
        add_plate(spec, body, P, kind, float(np.max(np.hypot(*P.T))), attrs, "plate")
        compile_s = least(spec.compile, repeats)
        m = spec.compile()
        d = mujoco.MjData(m)
        d.qpos[:], d.qvel[:] = built.qpos0, built.qvel0

        def evals():
            for _ in range(2000):
                mujoco.mj_forward(m, d)
        fwd = least(evals, repeats) / 2000
        print(f"cam_roller's mechanism model, {kind} {n}: {m.ngeom} geoms, compile {compile_s * 1e3:.1f} ms, "
              f"{fwd * 1e6:.2f} us per evaluation, {d.ncon} contacts found")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--counts", default="180,360,720")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--mechanism", action="store_true", help="also cam_roller's own mechanism model")
    args = ap.parse_args()
    counts = [int(c) for c in args.counts.split(",")]
    print("N: outline vertices; compile: the whole model [ms]; step: one RK4 mj_step, eval: one mj_forward, coll: "
          "mj_kinematics + mj_collision [us];\nsurface: max |contact dist + 0.1 mm| of the probe pressed 0.1 mm in "
          f"at 73 / {PROBES} cam angles [m]; 2+: steps with two or more active contacts [%]; found: contacts "
          "per step (active or in the gap);\nripple: the force less its 50-step mean, rms / largest [x the mean "
          "force]; track: the follower's largest error [m] / compare's tolerance (50 penetrations + sagitta)")
    print(f"{'cam':<12}{'option':<10}{'N':>5}{'geoms':>6}{'compile':>8}{'step':>7}{'eval':>7}{'coll':>7}"
          f"{'surface 73 / ' + str(PROBES):>20}{'2+':>6}{'found':>6}{'ripple':>12}{'track / tol':>18}")
    cases = (("disc", disc_case), ("cam_roller", roller_case), ("disc flat", lambda: disc_case("flat")))
    for name, case in cases:
        make, dense, probes = case()
        for kind in KINDS:
            for n in counts:
                r = measure(make, dense, probes, kind, n, args.repeats)
                print(f"{name:<12}{kind:<10}{n:>5}{r['ngeom']:>6}{r['compile_ms']:>8.1f}{r['step_us']:>7.1f}"
                      f"{r['fwd_us']:>7.2f}{r['geoms_us']:>7.2f}{r['surface']:>11.1e} /{r['surface_dense']:>7.1e}"
                      f"{100 * r['double']:>6.1f}{r['found']:>6.1f}{r['ripple_rms']:>6.2f}/{r['ripple_max']:<5.2f}"
                      f"{r['track']:>9.1e}/{r['bound']:<8.1e}", flush=True)
    if args.mechanism:
        mechanism_check(args.repeats)


if __name__ == "__main__":
    main()
