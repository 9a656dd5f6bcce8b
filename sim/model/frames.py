"""Body frames at the assembled pose: each link's world pose, points in a link's frame, quaternions."""

from __future__ import annotations

import math
from analytic.kinds import GROUND


def body_frames(mech, sol) -> dict[str, tuple[float, float, float]]:
    """World pose (x, y, angle) of every body at the solution's first sample."""
    origins = mech.link_origins
    frames = {GROUND: (0.0, 0.0, 0.0)}
    for ln in mech.links:
        p = origins[ln]
        frames[ln] = (float(sol["x" + p][0]), float(sol["y" + p][0]), float(sol["phi" + ln][0]))
    return frames


def local(frame, x, y):
    ox, oy, th = frame
    c, s = math.cos(th), math.sin(th)
    return ((x - ox) * c + (y - oy) * s, -(x - ox) * s + (y - oy) * c)


def quat(angle: float) -> list[float]:
    return [math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2)]


def point_local(points, frames, link, p):
    """Point ``p`` (world position at t = 0 in ``points``) in the frame of ``link``."""
    x, y = points[p]
    return local(frames[link], x, y)
