"""CPU time of a cam's MuJoCo contact run (sim/model/cam_contact.py) against the four-bar's ``compare``, and
the cam plate's collision geometry options (convex pieces vs one mesh SDF): surface error and step cost.

    PYTHONPATH=. MUJOCO_GL=egl python benchmarks/cam_contact.py [--sdf] [--render renders/cam_contact_jump.png]

``--render PATH``: the same cam at 1.3x the roller's jump speed, drawn at the step where the roller is
furthest off the cam (MuJoCo's offscreen renderer, from above).

The cam: an eccentric disc (R = 30 mm, e = 10 mm, 720 points), a roller follower (r = 10 mm, 0.1 kg,
1000 N/m, 10 N preload) at half its jump speed; one revolution.

Issue 38 (a cam's ``compare`` within 3x the four-bar's): ``python benchmarks/cycle.py fourbar cam_roller
--repeats 5`` (the command in process, least CPU of 5), two runs: main at efa21bc 0.043 / 0.044 s and 0.247 /
0.238 s (5.5x); after 0.037 / 0.035 s and 0.130 / 0.125 s (3.5x: not met). What is left is MuJoCo's: 2001 steps
(the cap, STEPS_PER_TURN; 1500 fails cam_fourbar's compare) x 4 RK4 evaluations + 2000 end-of-step
evaluations at ~7.3 us, 4.4 us of them the roller against the plate's pieces; the meshes' compile 14.6 ms.
benchmarks/RESULTS-2026-12-02.md.

Since then a cam's forces check replays every step (its forces as window means), and a second pass:
``python benchmarks/cycle.py fourbar cam_roller cam_flat cam_rocker cam_fourbar --repeats 3`` (least CPU of 3),
two runs, main at 69be754: fourbar 0.035 / 0.034 s, cam_roller 0.186 / 0.184 (5.4x), cam_flat 0.266 / 0.269,
cam_rocker 0.182 / 0.183, cam_fourbar 0.242 / 0.242; after (the replay's per-step Python cut: contact rows
read as lists, equality rows counted by ``data.ne``, each state set by one ``mj_setState``, no sensors; the
work balance's end-of-step evaluations carried by that replay, only the acceleration stage redone,
``mj_forwardSkip`` from mjSTAGE_VEL): fourbar 0.027 / 0.028, cam_roller 0.140 / 0.140 (5.0x; 4.0x the four-bar's
0.035 before), cam_flat 0.182 / 0.183, cam_rocker 0.139 / 0.141, cam_fourbar 0.175 / 0.175; every number of
``compare NAME --json`` identical (not met: 3x). cam_roller's 140 ms after (a ``process_time`` wrapper on each
function, least of 5): the rollout 50, the forces replay with the carried evaluations 36 (2001 x [mj_forward
6 us + the acceleration stage again 1.1 us + the reads 5.4 us]), the build 27 (the meshes' compile 14: ~9 us a
mesh vertex, the same with the hull's faces given or any mesh inertia mode), the rest ~26. As whole commands
(``python -m sim compare NAME``, median wall of 5): cam_roller / fourbar 0.548 / 0.398 s before, 0.511 / 0.395
after.
"""

from __future__ import annotations

import math
import sys
import time

from pathlib import Path

# benchmarks/analytic.py would shadow the package of that name: keep this folder off the import path.
sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]

import mujoco  # noqa: E402
import numpy as np  # noqa: E402

R, E, RR, M, K, F0 = 0.03, 0.01, 0.01, 0.1, 1000.0, 10.0
PROBES = 997
"""Cam angles the surface error is probed at: 997 (prime), so that the probes do not fall on the outline's
vertices (73 angles, 5 deg apart, all fell on the 720-point outline's vertices and read only rounding:
benchmarks/cam_primitives.py)."""


def disc(n=720):
    th = np.linspace(0, 2 * math.pi, n, endpoint=False)
    return np.c_[R * np.cos(th), -E + R * np.sin(th)]


def best(fn, repeat=5):
    out = []
    for _ in range(repeat):
        t0 = time.process_time()
        fn()
        out.append(time.process_time() - t0)
    return min(out)


def cam_times():
    from sim.model import cam_contact as cc
    wj = math.sqrt((F0 + 2 * K * E) / (M * E))        # the flat-faced disc's jump speed: a speed scale here
    cam = cc.CamFollower(disc(), (0.0, 0.0), 0.5 * wj, contact="roller", roller=RR, mass=M, stiffness=K,
                         preload=F0)
    built = cc.build(cam)
    t_build = best(lambda: cc.build(cam))
    t_run = best(lambda: cc.run(built, 1.0))
    return t_build, t_run, built


def fourbar_time():
    """``compare fourbar`` through the command line in this process (as benchmarks/cycle.py), warm."""
    import contextlib
    import io

    from sim.front.cli import main

    def once():
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            main(["compare", "fourbar"])
    once()
    return best(once)


def sdf_option(depth):
    """One mesh (the extruded plate, its caps fanned from the pivot) with MuJoCo's octree SDF: surface error
    of the roller pressed 0.1 mm in at PROBES cam angles, and CPU per step."""
    P = disc()
    n, t = len(P), 0.004
    v = [0, 0, -t, 0, 0, t]
    for z in (-t, t):
        for x, y in P:
            v += [x, y, z]
    f = []
    for i in range(n):
        j = (i + 1) % n
        bi, bj, ti, tj = 2 + i, 2 + j, 2 + n + i, 2 + n + j
        f += [0, bj, bi, 1, ti, tj, bi, bj, tj, bi, tj, ti]
    spec = mujoco.MjSpec()
    spec.option.gravity = [0, 0, 0]
    spec.add_mesh(name="plate", uservert=v, userface=f, needsdf=True, octree_maxdepth=depth)
    cam = spec.worldbody.add_body(name="cam")
    cam.add_joint(name="cam", type=mujoco.mjtJoint.mjJNT_HINGE, axis=[0, 0, 1], armature=100)
    cam.add_geom(type=mujoco.mjtGeom.mjGEOM_SDF, meshname="plate", contype=1, conaffinity=0, condim=1)
    fol = spec.worldbody.add_body(name="fol")
    fol.add_joint(name="s", type=mujoco.mjtJoint.mjJNT_SLIDE, axis=[0, 1, 0], stiffness=K, springref=-0.05)
    fol.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[RR, 0, 0], pos=[0, 0.05, 0], mass=M, contype=0,
                 conaffinity=1, condim=1)
    t0 = time.process_time()
    m = spec.compile()
    t_compile = time.process_time() - t0
    d = mujoco.MjData(m)
    errs = []
    for ang in np.linspace(0, 2 * math.pi, PROBES):
        cx, cy = E * math.sin(ang), -E * math.cos(ang)
        d.qpos[:] = [ang, cy + math.sqrt((R + RR) ** 2 - cx ** 2) - 0.05 - 1e-4]
        mujoco.mj_forward(m, d)
        errs.append(min(d.contact.dist[:d.ncon]) + 1e-4 if d.ncon else math.nan)
    mujoco.mj_resetData(m, d)
    d.qpos[1] = math.sqrt((R + RR) ** 2 - E ** 2) - 0.05
    d.qvel[0] = 40.0
    t0 = time.process_time()
    for _ in range(500):
        mujoco.mj_step(m, d)
    return float(np.nanmax(np.abs(errs))), t_compile, (time.process_time() - t0) / 500


def pieces_error():
    """The convex pieces' surface error measured the same way, and CPU per step of the module's run."""
    from sim.model import cam_contact as cc
    cam = cc.CamFollower(disc(), (0.0, 0.0), 40.0, contact="roller", roller=RR, mass=M, stiffness=K, preload=F0)
    b = cc.build(cam)
    m, d = b.model, mujoco.MjData(b.model)
    errs = []
    for ang in np.linspace(0, 2 * math.pi, PROBES):
        cx, cy = E * math.sin(ang), -E * math.cos(ang)
        d.qpos[:] = [ang, cy + math.sqrt((R + RR) ** 2 - cx ** 2) - 1e-4]
        mujoco.mj_forward(m, d)
        errs.append(min(d.contact.dist[:d.ncon]) + 1e-4)
    return float(np.max(np.abs(errs))), len(b.pieces)


def render(path):
    import imageio.v3 as iio

    from sim.model import cam_contact as cc
    wj = 154.92                                          # the roller's jump speed [rad/s] (tests/test_cam_contact.py)
    cam = cc.CamFollower(disc(), (0.0, 0.0), 1.3 * wj, contact="roller", roller=RR, mass=M, stiffness=K, preload=F0)
    built = cc.build(cam)
    run = cc.run(built, 1.0)
    cx, cy = E * np.sin(run.theta), -E * np.cos(run.theta)
    off = run.q - (cy + np.sqrt((R + RR) ** 2 - cx ** 2))
    k = int(np.argmax(off))
    iio.imwrite(path, cc.render_frame(built, run, k))
    print(f"{path}: cam angle {run.theta[k]:.3f} rad, the roller {off[k] * 1e3:.1f} mm off the cam; separation "
          f"from {run.first_at:.3f} rad")


def main():
    t_build, t_run, built = cam_times()
    steps = built.steps_per_turn
    t_fb = fourbar_time()
    print(f"cam (roller on an eccentric disc, {len(built.pieces)} convex pieces): build {t_build * 1e3:.1f} ms, "
          f"one revolution {t_run * 1e3:.1f} ms CPU ({steps} steps, {t_run / steps * 1e6:.1f} us/step); "
          f"build + run {(t_build + t_run) * 1e3:.1f} ms")
    print(f"four-bar `compare fourbar` (in process, warm): {t_fb * 1e3:.1f} ms CPU; cam build + one revolution / "
          f"four-bar compare = {(t_build + t_run) / t_fb:.2f}")
    err, npieces = pieces_error()
    print(f"convex pieces: surface error {err:.1e} m ({npieces} pieces)")
    if "--render" in sys.argv:
        render(sys.argv[sys.argv.index("--render") + 1])
    if "--sdf" in sys.argv:
        for depth in (5, 7):
            e, tc, ts = sdf_option(depth)
            print(f"mesh SDF octree depth {depth}: surface error {e:.1e} m, compile {tc:.2f} s, {ts * 1e6:.0f} us/step")


if __name__ == "__main__":
    main()
