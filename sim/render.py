"""Offscreen rendering of a simulated run to MP4 (H.264) or GIF, streamed frame by frame to ffmpeg.

Frames are sampled at the video's frame rate from simulation time (the recorded step nearest each frame
instant; steps are 2 ms by default, so a frame is at most 1 ms off), drawn from the model's ``top``
camera (orthographic, looking straight down on the plane), with the output point's path traced so far.
"""

from __future__ import annotations

import math
import os
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from analytic import ParameterError
from .gl import ensure_gl_backend
from .io import atomic_path, check_writable
from .progress import Progress

VIDEO_SUFFIXES = (".mp4", ".gif")
PATH_RGBA = np.array([0.89, 0.10, 0.11, 1.0], np.float32)
MAX_PATH_SEGMENTS = 250


def parse_size(text: str) -> tuple[int, int]:
    """``'640x480'`` -> (640, 480); even sizes from 16 to 4096 px (H.264's 4:2:0 needs even sizes)."""
    try:
        w, h = (int(x) for x in text.lower().split("x"))
    except ValueError:
        raise ParameterError(f"--size {text!r} is not WxH (e.g. --size 640x480)") from None
    for v, name in ((w, "width"), (h, "height")):
        if not (16 <= v <= 4096 and v % 2 == 0):
            raise ParameterError(f"--size {text}: {name} {v} must be an even number of pixels in 16..4096")
    return w, h


MAX_FPS = 240
GIF_MAX_FPS = 50
"""GIF frame delays are whole centiseconds and players clamp delays under 2 cs: 50 fps is the most a GIF
stores faithfully; a higher rate is stored at 50 fps (said in the output)."""
MAX_FRAMES = 100_000


def check_video_args(out: str, fps: float, size: str) -> tuple[Path, tuple[int, int]]:
    """Validate the output path, frame rate and size before any simulation starts."""
    path = check_writable(out, VIDEO_SUFFIXES)
    if not (math.isfinite(fps) and 0 < fps <= MAX_FPS):
        raise ParameterError(f"--fps {fps!r} must be a number in (0, {MAX_FPS}] (e.g. --fps 30)")
    return path, parse_size(size)


def stored_fps(out: str, fps: float) -> float:
    """The frame rate the file will carry (GIF: at most GIF_MAX_FPS)."""
    return min(fps, GIF_MAX_FPS) if str(out).lower().endswith(".gif") else fps


@dataclass(frozen=True)
class RenderStats:
    frames: int
    seconds: float
    path: str
    stored_fps: float

    @property
    def fps(self) -> float:
        return self.frames / self.seconds if self.seconds > 0 else math.inf


def frame_instants(t: np.ndarray, fps: float) -> np.ndarray:
    """The frame instants 0, 1/fps, ... <= t[-1] [s]."""
    return np.arange(0.0, t[-1] + 1e-9, 1.0 / fps)


def frame_poses(t: np.ndarray, qpos: np.ndarray, instants: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Joint positions at each frame instant, blended linearly between the recorded steps around it, and
    the last recorded step at or before it (for the traced path). The joints are hinges and slides (no
    quaternions), so a blend is a pose; a step turns the fastest link by at most 0.03 rad, so a loop
    opens by ~1e-4 of the size between steps: far below a pixel, where taking the nearest step instead
    would jerk the fastest link by up to half a step."""
    k = np.clip(np.searchsorted(t, instants, side="right") - 1, 0, len(t) - 2)
    w = np.clip((instants - t[k]) / (t[k + 1] - t[k]), 0.0, 1.0)[:, None]
    return qpos[k] * (1.0 - w) + qpos[k + 1] * w, np.where(w[:, 0] >= 1.0, k + 1, k)


def output_path(tr, mech) -> np.ndarray:
    """The output point's recorded path, shape (steps, 3) [m] (z = 0)."""
    p = mech.output_point
    x, y = tr.outputs["x" + p], tr.outputs["y" + p]
    return np.column_stack([x, y, np.zeros_like(x)])


class _Writer:
    """Frames streamed to an ffmpeg process (imageio-ffmpeg): H.264 MP4, or GIF with a palette made
    per frame (``stats_mode=single``), so neither side ever holds more than one frame.

    x264's ``ultrafast`` preset: the encoder shares two cores with the software rasteriser, and on this
    machine it raised the whole path from 33 to 38 frames/s (files ~3x larger than ``veryfast``)."""

    def __init__(self, path: str, fps: float, size: tuple[int, int]):
        import imageio_ffmpeg
        if path.lower().endswith(".gif"):
            kw = dict(codec="gif", pix_fmt_out="pal8", quality=None, output_params=[
                "-vf", "split[a][b];[a]palettegen=stats_mode=single:max_colors=64[p];"
                       "[b][p]paletteuse=new=1:dither=none", "-loop", "0"])
        else:
            kw = dict(codec="libx264", pix_fmt_out="yuv420p", quality=None,
                      output_params=["-crf", "23", "-preset", "ultrafast", "-movflags", "+faststart"])
        self._gen = imageio_ffmpeg.write_frames(path, size, fps=float(fps), macro_block_size=1,
                                                ffmpeg_log_level="error", **kw)
        self._gen.send(None)                      # start ffmpeg

    def append(self, frame: np.ndarray) -> None:
        self._gen.send(np.ascontiguousarray(frame))

    def close(self) -> None:
        self._gen.close()


def _line(scene, a, b, width_px: float, rgba) -> None:
    """Append a line segment from a to b [m, world] to the scene (width in pixels), if there is room."""
    import mujoco
    if scene.ngeom >= scene.maxgeom:
        return
    g = scene.geoms[scene.ngeom]
    mujoco.mjv_initGeom(g, mujoco.mjtGeom.mjGEOM_LINE, np.zeros(3), np.zeros(3), np.eye(3).ravel(),
                        np.asarray(rgba, np.float32))
    mujoco.mjv_connector(g, mujoco.mjtGeom.mjGEOM_LINE, width_px, np.asarray(a, float), np.asarray(b, float))
    scene.ngeom += 1


def _add_path(scene, points: np.ndarray, width_px: float) -> None:
    """The traced path, at most MAX_PATH_SEGMENTS segments, drawn above every link."""
    if len(points) < 2:
        return
    step = max(1, math.ceil((len(points) - 1) / MAX_PATH_SEGMENTS))
    pts = points[::step]
    if not np.array_equal(pts[-1], points[-1]):
        pts = np.vstack([pts, points[-1]])
    pts = pts + np.array([0.0, 0.0, 0.03])
    for a, b in zip(pts[:-1], pts[1:]):
        _line(scene, a, b, width_px, PATH_RGBA)


def render(built, tr, out: str, fps: float = 30.0, size: tuple[int, int] = (640, 480),
           markers: tuple[tuple[float, float], ...] = (), display=None) -> RenderStats:
    """Render trajectory ``tr`` of model ``built`` to ``out`` (.mp4 or .gif), atomically.

    ``markers`` are extra points [m] drawn as small crosses (e.g. a synthesis task's E1 and E2).
    """
    ensure_gl_backend()
    import mujoco
    from .model import frame_extent

    w, h = size
    fps = stored_fps(out, fps)
    model = built.model
    model.vis.global_.offwidth = max(model.vis.global_.offwidth, w)
    model.vis.global_.offheight = max(model.vis.global_.offheight, h)
    cam = model.camera("top").id
    model.cam_fovy[cam] = frame_extent(built.mech, w / h)
    data = mujoco.MjData(model)
    poses, frames = frame_poses(tr.t, tr.qpos, frame_instants(tr.t, fps))
    if len(frames) > MAX_FRAMES:
        raise ParameterError(f"the video would have {len(frames):,} frames (over {MAX_FRAMES:,}): lower --fps or "
                             f"--revolutions")
    path = output_path(tr, built.mech)
    progress = Progress(len(frames), f"rendering {Path(out).name}")
    opt = mujoco.MjvOption()
    t0 = time.perf_counter()
    try:
        renderer = mujoco.Renderer(model, h, w)
    except Exception as exc:                      # no usable OpenGL: say so in one line
        raise ParameterError(
            f"offscreen rendering is unavailable (MUJOCO_GL={os.environ.get('MUJOCO_GL')}): "
            f"{str(exc).splitlines()[0]}; install Mesa's EGL (Debian: libegl1) or set MUJOCO_GL=osmesa") from None
    with renderer, atomic_path(out) as tmp:
        writer = _Writer(tmp, fps, size)
        try:
            for i, (k, qpos) in enumerate(zip(frames, poses)):
                data.qpos[:] = qpos
                mujoco.mj_kinematics(model, data)
                mujoco.mj_camlight(model, data)          # the fixed camera's pose
                renderer.update_scene(data, camera=cam, scene_option=opt)
                _add_path(renderer.scene, path[:k + 1], width_px=max(2.0, h / 200))
                for mx, my in markers:
                    _add_cross(renderer.scene, mx, my, 0.015 * model.cam_fovy[cam])
                writer.append(renderer.render())
                progress.update(i + 1)
        finally:
            writer.close()
    return RenderStats(len(frames), time.perf_counter() - t0, str(out), fps)


def _add_cross(scene, x: float, y: float, r: float) -> None:
    """A cross of half-size r [m] centred on (x, y), e.g. a synthesis task's E1 or E2."""
    for (ax, ay), (bx, by) in (((x - r, y - r), (x + r, y + r)), ((x - r, y + r), (x + r, y - r))):
        _line(scene, (ax, ay, 0.04), (bx, by, 0.04), 3.0, (0.1, 0.1, 0.1, 1.0))
