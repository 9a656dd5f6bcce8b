"""Frames per second of the whole render path (simulate + render + encode) at 640x480, against a bare
``mujoco.Renderer`` loop with MuJoCo's default quality settings on the same scene.

Run:  python benchmarks/render.py [--revolutions R]
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

# benchmarks/analytic.py would shadow the package of that name: keep this folder off the import path.
sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]
import sim  # noqa: E402,F401  (chooses the offscreen GL backend before mujoco is imported)
import mujoco  # noqa: E402

from sim import model  # noqa: E402
from sim.output import render  # noqa: E402
from sim import service  # noqa: E402
from sim.run import simulate  # noqa: E402

W, H, FPS = 640, 480, 30.0


def ours(mech, revolutions: float, out: str) -> tuple[int, float]:
    t0 = time.perf_counter()
    built = model.build(mech)
    tr = simulate.simulate(built, revolutions)
    stats = render.render(built, tr, out, FPS, (W, H))
    return stats.frames, time.perf_counter() - t0


def bare(mech, frames: int) -> float:
    """MuJoCo defaults (4x multisampling, 4096 shadow map), same camera, the state stepped with mj_step."""
    built = model.build(mech)
    m = built.model
    m.vis.quality.offsamples = 4
    m.vis.quality.shadowsize = 4096
    d = mujoco.MjData(m)
    d.qpos[:], d.qvel[:], d.act[:], d.ctrl[:] = built.qpos0, built.qvel0, built.act0, built.ctrl0
    steps_per_frame = max(1, round(1.0 / FPS / m.opt.timestep))
    t0 = time.perf_counter()
    with mujoco.Renderer(m, H, W) as r:
        for _ in range(frames):
            for _ in range(steps_per_frame):
                mujoco.mj_step(m, d)
            r.update_scene(d, camera="top")
            r.render()
    return frames / (time.perf_counter() - t0)


def main() -> None:
    revolutions = float(sys.argv[sys.argv.index("--revolutions") + 1]) if "--revolutions" in sys.argv else 3.0
    print(f"{W}x{H} at {FPS:g} fps, {revolutions:g} revolutions; MUJOCO_GL={__import__('os').environ['MUJOCO_GL']}")
    print(f"{'mechanism':<10s} {'frames':>6s} {'ours: sim+render+encode':>24s} {'bare Renderer (defaults)':>25s}")
    with tempfile.TemporaryDirectory() as tmp:
        for name in ("fourbar", "sixbar", "fivebar", "jansen"):
            mech = service.load(name)
            frames, seconds = ours(mech, revolutions, f"{tmp}/{name}.mp4")
            print(f"{name:<10s} {frames:6d} {frames / seconds:18.1f} fps {bare(mech, frames):19.1f} fps")


if __name__ == "__main__":
    main()
