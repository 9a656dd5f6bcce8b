"""Rendering to MP4 and GIF, the plot sheets and the main job, at small sizes so CI stays fast."""

import subprocess
import sys

import numpy as np
import pytest

import sim  # noqa: F401  (chooses the offscreen GL backend before mujoco is imported)
import imageio.v3 as iio

from sim.output import render
from sim import service


def run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "sim", *args], capture_output=True, text=True, cwd=cwd)


@pytest.mark.parametrize("ext", ["mp4", "gif"])
def test_render_decodes_with_expected_frames_and_content(tmp_path, ext):
    out = tmp_path / f"fourbar.{ext}"
    built, tr = service.simulate(service.load("fourbar"), 0.5)
    stats = render.render(built, tr, str(out), fps=20, size=(160, 120))
    frames = iio.imread(out, index=None)
    # 0.5 s at 20 fps: frames at 0, 0.05, ..., 0.5 s.
    assert stats.frames == 11 and frames.shape[0] == 11
    assert frames.shape[1:3] == (120, 160)
    assert frames.std() > 10                                 # not blank
    # The crank turns 90 degrees in 0.25 s: consecutive frames differ.
    assert all(np.abs(frames[i].astype(int) - frames[i + 1]).mean() > 0.5 for i in range(len(frames) - 1))
    # The traced path is drawn in red: more red pixels at the end than at the start.
    red = lambda f: np.sum((f[..., 0] > 180) & (f[..., 1] < 90) & (f[..., 2] < 90))  # noqa: E731
    assert red(frames[-1]) > red(frames[0]) + 20


def test_frames_are_posed_at_their_own_instants():
    # 1 s recorded every 7 ms (frames fall between steps); a joint turning 3 rad/s and one moving at
    # 0.5 m/s, recorded exactly: each frame must show the pose at k/30 s, to rounding (a linear motion
    # is blended exactly), not the nearest step's (up to 3.5 ms = 0.0105 rad off).
    t = np.arange(0, 144) * 0.007
    qpos = np.column_stack([3.0 * t, 0.5 * t])
    poses, last = render.frame_poses(t, qpos, render.frame_instants(t, 30.0))
    instants = np.arange(31) / 30.0                                  # t[-1] = 1.001 s: 0 .. 1 s
    assert len(poses) == 31
    assert np.abs(poses - np.column_stack([3.0 * instants, 0.5 * instants])).max() < 1e-12
    assert np.all(t[last] <= instants + 1e-12) and np.all(t[np.minimum(last + 1, len(t) - 1)] > instants - 1e-12)


@pytest.mark.parametrize("args,pattern", [
    (["--out", "x.avi"], "unsupported output type"),
    (["--out", "x.mp4", "--size", "640by480"], "is not WxH"),
    (["--out", "x.mp4", "--size", "641x480"], "even number"),
    (["--out", "x.mp4", "--fps", "0"], "--fps"),
    (["--out", "/no/such/dir/x.mp4"], "does not exist"),
])
def test_bad_render_arguments_fail_before_simulating(tmp_path, args, pattern):
    r = run("render", "fourbar", *args, cwd=tmp_path)
    assert r.returncode == 2 and pattern in r.stderr and "Traceback" not in r.stderr


def test_an_existing_file_survives_a_failed_render(tmp_path):
    out = tmp_path / "keep.mp4"
    out.write_bytes(b"precious")
    r = run("render", "fourbar", "--out", str(out), "--set", "l1=0.2", "--set", "l3=0.1")
    assert r.returncode == 2 and out.read_bytes() == b"precious"
    assert [p.name for p in tmp_path.iterdir()] == ["keep.mp4"]         # no temporary left behind


@pytest.mark.parametrize("name", ["fourbar", pytest.param("sixbar", marks=pytest.mark.slow),
                                  pytest.param("fivebar", marks=pytest.mark.slow)])
def test_plot_writes_a_sheet(tmp_path, name):
    out = tmp_path / f"{name}.png"
    r = run("plot", name, "--out", str(out), "--revolutions", "0.5")
    assert r.returncode == 0, r.stderr
    img = iio.imread(out)
    assert img.shape[0] > 500 and img.shape[1] > 800 and img.std() > 10


def test_run_end_to_end_reduced(tmp_path):
    r = run("run", "--out-dir", str(tmp_path), "--revolutions", "0.25", "--size", "160x120", "--fps", "12",
            "--format", "gif")
    assert r.returncode == 0, r.stdout + r.stderr
    for name in ("fourbar", "sixbar", "fivebar"):
        for ext in ("csv", "png", "gif"):
            assert (tmp_path / f"{name}.{ext}").stat().st_size > 0
        assert iio.imread(tmp_path / f"{name}.gif", index=None).shape[0] == 4     # 0.25 s at 12 fps
    assert r.stdout.count("PASSED") == 6                    # three tables and three summary lines


def test_a_signal_while_ffmpeg_starts_stops_it_before_the_temporary_is_removed(tmp_path, monkeypatch):
    """Ctrl-C arriving while ffmpeg starts (the window where an orphaned ffmpeg used to write its file after
    the temporary was removed): it is delivered once the writer can stop ffmpeg, ffmpeg is stopped at once
    (no trailer written), and nothing is left in the folder."""
    import signal

    import imageio_ffmpeg

    from sim.output import render

    events = []

    def fake_write_frames(path, *args, **kwargs):
        open(path, "wb").close()                  # ffmpeg opens its output
        events.append("started")
        signal.raise_signal(signal.SIGINT)        # the user presses Ctrl-C now
        try:
            while True:
                yield
        except KeyboardInterrupt:
            events.append("killed")               # imageio-ffmpeg's kill path
            raise
        except GeneratorExit:
            events.append("closed")               # would wait for ffmpeg and let it write its trailer
            with open(path, "wb"):
                pass

    monkeypatch.setattr(imageio_ffmpeg, "write_frames", fake_write_frames)
    out = tmp_path / "v.mp4"
    with pytest.raises(KeyboardInterrupt):
        with render.atomic_path(out) as tmp, render._Writer(tmp, 30.0, (64, 48)):
            pass
    assert events == ["started", "killed"]
    assert list(tmp_path.iterdir()) == []


def test_a_block_draws_the_arm_to_the_points_it_carries():
    """A yoke (a block) carrying a point off its pin, as the elliptic trammel's carry the rod's pins: the video
    draws a bar of the block's colour from the pin to that point (its midpoint's pixels), besides the block's box
    at the pin; a block with its pin alone draws nothing there."""
    from analytic.quantities import Display
    from sim.output.drawing import COLORS, Painter, Scene
    xy = np.array([[0.0, 0.0], [0.1, 0.0]])                       # the pin P, the carried point A [m]
    rgb = np.array([int(COLORS[0][i:i + 2], 16) for i in (1, 3, 5)])
    mids = []
    for pts in (("P", "A"), ("P",)):
        sc = Scene(((("yoke", pts, True)),), ("P", "A"), (), "A", (-0.05, -0.1, 0.15, 0.1), 0.1, Display("m"),
                   "q", True)
        painter = Painter(sc, (320, 320))
        frame = painter.frame(xy, {"yoke": 0.0}, np.empty((0, 2)), np.empty((0, 2)), 0.0, 0.0).astype(int)
        mid = painter.px(np.array([[0.06, 0.0]]))[0] / 2           # supersampled 2x; past the box (0.006 m)
        r, c = int(round(mid[1])), int(round(mid[0]))
        mids.append(np.all(np.abs(frame[r - 1:r + 2, c - 1:c + 2] - rgb) <= 40, axis=-1).any())
    assert mids == [True, False]
