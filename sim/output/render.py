"""Offscreen rendering of a simulated run to MP4 (H.264) or GIF, streamed frame by frame to ffmpeg.

Frames are sampled at the video's frame rate from simulation time (the recorded steps around each frame
instant blended), posed by the model's kinematics and drawn in 2-D as the app draws its view
(sim/output/drawing.py): pins, plates, labels, a scale bar, the time and the input, the output point's path.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from analytic import ParameterError
from sim.output.io import atomic_path, check_writable, deferred_signals
from sim.output.progress import Progress

VIDEO_SUFFIXES = (".mp4", ".gif")
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
MIN_FPS = 1
"""The slowest frame rate: ffmpeg is given the rate to two decimals (a tenth of a frame per second would be
written as 0, which ffmpeg refuses in five lines), and a frame per second is already a slide show."""
GIF_MAX_FPS = 50
"""GIF frame delays are whole centiseconds and players clamp delays under 2 cs: 50 fps is the most a GIF
stores faithfully; a higher rate is stored at 50 fps (said in the output)."""
MAX_FRAMES = 100_000


def check_video_args(out: str, fps: float, size: str) -> tuple[Path, tuple[int, int]]:
    """Validate the output path, frame rate and size before any simulation starts."""
    path = check_writable(out, VIDEO_SUFFIXES)
    if not (math.isfinite(fps) and MIN_FPS <= fps <= MAX_FPS):
        raise ParameterError(f"--fps {fps:g} must be a number in [{MIN_FPS}, {MAX_FPS}] frames per second "
                             f"(e.g. --fps 30)")
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
    quaternions), so a blend is a pose; a step turns the fastest link by at most 0.025 rad, so a loop
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
        self.frames = 0
        self._gen = imageio_ffmpeg.write_frames(path, size, fps=float(fps), macro_block_size=1,
                                                ffmpeg_log_level="error", **kw)
        try:
            with deferred_signals():              # a signal while ffmpeg starts is delivered after it
                self._gen.send(None)
        except BaseException:                     # ...and ends it before the temporary file is removed
            self.abort()
            raise

    def __enter__(self):
        return self

    def __exit__(self, exc_type, *exc) -> None:
        if exc_type is None:
            self.close()
        else:
            self.abort()

    def abort(self) -> None:
        """Stop ffmpeg at once (the file is being thrown away): no trailer, nothing on the terminal. The
        process is killed before imageio-ffmpeg closes its input: closed first, ffmpeg would read a frame
        cut short by the interrupt and complain of it on the terminal before the kill reached it."""
        frame = self._gen.gi_frame
        proc = frame.f_locals.get("p") if frame is not None else None
        if proc is not None and hasattr(proc, "kill") and proc.poll() is None:
            proc.kill()
            proc.wait()
        try:
            self._gen.throw(KeyboardInterrupt)     # imageio-ffmpeg kills ffmpeg on a KeyboardInterrupt
        except (KeyboardInterrupt, StopIteration):
            pass

    def append(self, frame: np.ndarray) -> None:
        self._gen.send(np.ascontiguousarray(frame))
        self.frames += 1

    def close(self) -> None:
        import logging
        quiet = logging.getLogger("imageio_ffmpeg")
        level = quiet.level
        if not self.frames:                       # interrupted before the first frame: the file is removed
            quiet.setLevel(logging.ERROR)         # anyway, so imageio's "no frames" warning says nothing
        try:
            self._gen.close()
        finally:
            quiet.setLevel(level)


def _trace(path: np.ndarray, k: int) -> np.ndarray:
    """The output point's path up to step ``k`` [m], at most MAX_PATH_SEGMENTS * 4 segments, ending at k."""
    step = max(1, math.ceil(len(path) / (4 * MAX_PATH_SEGMENTS)))
    pts = path[:k + 1:step]
    return pts if len(pts) and np.array_equal(pts[-1], path[k]) else np.vstack([pts, path[k:k + 1]])


def joint_force_frames(built, tr, instants: np.ndarray) -> tuple[np.ndarray, float]:
    """MuJoCo's force in every joint at the frame instants, blended linearly between the recorded steps
    around each (as the poses), shape (frames, joints, 2) [N], and the peak over every step [N]: the force
    ``links[0]`` exerts on ``links[1]`` (sim.run.forces.measure)."""
    from sim.run import forces as simforces
    f = simforces.measure(built, tr)
    t = tr.t
    k = np.clip(np.searchsorted(t, instants, side="right") - 1, 0, len(t) - 2)
    w = np.clip((instants - t[k]) / (t[k + 1] - t[k]), 0.0, 1.0)
    F = f.F[:, :, k] * (1.0 - w) + f.F[:, :, k + 1] * w                       # (joints, 2, frames)
    mag = f.magnitude()
    peak = float(np.nanmax(mag)) if mag.size else 0.0
    return np.transpose(F, (2, 0, 1)), peak


def render(built, tr, out: str, fps: float = 30.0, size: tuple[int, int] = (640, 480),
           markers: tuple[tuple[float, float], ...] = (), display=None, forces: bool = False) -> RenderStats:
    """Render trajectory ``tr`` of model ``built`` to ``out`` (.mp4 or .gif), atomically, drawn as the
    app draws (sim/output/drawing.py): lengths in ``display`` units (analytic.quantities.Display; None: the file's).

    ``markers`` are extra points [m] drawn as small crosses (e.g. a synthesis task's E1 and E2). ``forces``:
    MuJoCo's joint forces drawn as arrows at the joints, the peak force ARROW_REACH of the size long, with a
    legend giving the scale.
    """
    from analytic.quantities import Display
    from sim.output.drawing import force_arrows, poses, scene

    fps = stored_fps(out, fps)
    mech = built.mech
    instants = frame_instants(tr.t, fps)
    qpos, frames = frame_poses(tr.t, tr.qpos, instants)
    _check_frames(len(frames))
    xy, angles = poses(built, qpos)
    path = output_path(tr, mech)[:, :2]
    sc = scene(built, xy, display or Display(mech.units), path)
    arrows = None
    peak = 0.0
    if forces:
        F, peak = joint_force_frames(built, tr, instants)
        where = [mech.points.index(j.point) for j in mech.topology.joints]
        arrows = np.concatenate([xy[:, where], F], axis=-1)                   # (frames, joints, 4)
    if getattr(built, "loadset", None) is not None:     # the file's forces as arrows at their points too
        from sim.output.load_arrows import load_arrows
        extra = load_arrows(built, instants)
        if extra is not None:
            arrows = extra if arrows is None else np.concatenate([arrows, extra], axis=1)
            peak = max(peak, float(np.nanmax(np.hypot(extra[..., 2], extra[..., 3]))))
    if arrows is not None:
        label = ("joint forces (first link on the second) and loads" if forces and len(arrows[0]) > len(
            mech.topology.joints) else None if forces else "loads (at their points)")
        sc = force_arrows(sc, peak, label)
    q = np.interp(instants, tr.t, tr.inputs[mech.inputs[0].q])
    return _write(out, fps, size, sc, xy, angles, path, frames, instants, q, markers=markers, arrows=arrows)


def _check_frames(n: int) -> None:
    if n > MAX_FRAMES:
        raise ParameterError(f"the video would have {n:,} frames (over {MAX_FRAMES:,}): lower --fps or "
                             f"--revolutions")


MAX_MOTOR_PATH = 20_000
"""Recorded steps of a motor run posed for the output point's path (evenly spread beyond): a path of a few
hundred segments is drawn per frame (MAX_PATH_SEGMENTS), so more would only cost kinematics passes."""


def render_motor(built, run, out: str, fps: float = 30.0, size: tuple[int, int] = (640, 480),
                 display=None) -> RenderStats:
    """Render MuJoCo's motor-driven run ``run`` (:class:`sim.run.motor.MotorRun`, its model ``built``) to
    ``out`` (.mp4 or .gif), atomically, drawn as :func:`render` draws, with the input's speed (in
    ``display``'s angular-speed unit: rad/s, deg/s or rpm) in the corner beside its angle and the time."""
    from analytic.quantities import Display
    from sim.output.drawing import poses, scene

    fps = stored_fps(out, fps)
    mech = built.mech
    t = np.asarray(run.t)
    instants = frame_instants(t, fps)
    qpos, frames = frame_poses(t, run.qpos, instants)
    _check_frames(len(frames))
    xy, angles = poses(built, qpos)
    stride = max(1, math.ceil(len(t) / MAX_MOTOR_PATH))
    steps = np.unique(np.append(np.arange(0, len(t), stride), len(t) - 1))
    path = poses(built, run.qpos[steps])[0][:, mech.points.index(mech.output_point)]
    sc = scene(built, xy, display or Display(mech.units), path)
    k = np.clip(np.searchsorted(steps, frames, side="right") - 1, 0, len(steps) - 1)   # a frame's last path step
    q = np.interp(instants, t, run.phi)
    w = np.interp(instants, t, run.omega)
    return _write(out, fps, size, sc, xy, angles, path, k, instants, q, speeds=w)


def _write(out, fps, size, sc, xy, angles, path, frames, instants, q, markers=(), arrows=None,
           speeds=None) -> RenderStats:
    """Draw and encode the frames: ``xy`` (frames, points, 2) and ``angles`` the poses, ``path`` the output
    point's recorded path [m] and ``frames`` each frame's last step in it, ``q`` the input's value and
    ``speeds`` its speed [rad/s] (None: not shown) at each frame instant."""
    from sim.output.drawing import Painter
    painter = Painter(sc, size)
    whole = _trace(path, len(path) - 1)
    progress = Progress(len(frames), f"rendering {Path(out).name}")
    t0 = time.perf_counter()
    with atomic_path(out) as tmp, _Writer(tmp, fps, size) as writer:     # ffmpeg ends before tmp is removed
        for i, k in enumerate(frames):
            writer.append(painter.frame(xy[i], {ln: a[i] for ln, a in angles.items()}, _trace(path, k), whole,
                                        float(instants[i]), float(q[i]), markers,
                                        None if arrows is None else arrows[i],
                                        None if speeds is None else float(speeds[i])))
            progress.update(i + 1)
    return RenderStats(len(frames), time.perf_counter() - t0, str(out), fps)
