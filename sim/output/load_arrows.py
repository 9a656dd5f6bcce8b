"""The file's loads in a video (issue 27: loads drawn in every picture): each force, pressure, spring and
damper as an arrow at the point it acts on, (frames, loads, 4) rows [x, y, fx, fy] for
:func:`sim.output.render.render`, drawn with the joint forces' scale (sim.output.drawing.force_arrows)."""

from __future__ import annotations

import numpy as np

from analytic.kinds import GROUND


def load_arrows(built, instants) -> np.ndarray | None:
    """The loads' forces on moving links at the frames' instants (the commanded motion, which the drives hold
    to 1e-6 rad), or None when no load is a force."""
    from sim.model.loads import applications
    apps, _, _, _ = applications(built, np.asarray(instants, dtype=float))
    n = len(instants)
    rows = []
    for a in apps:
        if a.link == GROUND:
            continue
        fx, fy = np.broadcast_to(a.fx, (n,)), np.broadcast_to(a.fy, (n,))
        if not np.any(np.hypot(fx, fy) > 0):
            continue
        rows.append(np.stack([np.broadcast_to(a.px, (n,)), np.broadcast_to(a.py, (n,)), fx, fy], axis=-1))
    return np.stack(rows, axis=1) if rows else None
