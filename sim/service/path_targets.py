"""Path synthesis from points the user placed (the app's Synthesis tab; public API): the linkage types it
offers, the length units target files may be written in, the target itself, and a found design's coupler
curve to draw. The search is :func:`sim.service.design.synthesize_path`."""

from __future__ import annotations

import numpy as np

from analytic import quantities as Q

LENGTH_UNITS = dict(Q.LENGTH_UNITS)
"""[m per unit] The units a target file's x, y may be given in."""


def types() -> tuple[str, ...]:
    """The linkage types path synthesis offers (``linkage synthesize path --type``)."""
    from analytic.synthesis.curves import TYPES
    return tuple(TYPES)


def default_type() -> str:
    from analytic.synthesis.curves import DEFAULT_TYPE
    return DEFAULT_TYPE


def target(xy, closed: bool):
    """Target points ``xy`` (M, 2) [m], without timing, on an open or ``closed`` path: what
    :func:`sim.service.design.synthesize_path` takes."""
    from analytic.synthesis import path as sp
    return sp.Target(np.asarray(xy, dtype=float), None, bool(closed))


def coupler_curve(design, samples: int = 361) -> tuple[np.ndarray, np.ndarray]:
    """(x, y) [the design's length unit] of a found design's coupler point over one turn of its input,
    ``samples`` evenly spaced angles."""
    phi = np.linspace(0.0, 2 * np.pi, samples)
    E, _ = design.family.points(np.asarray(design.x)[None, :design.family.size], phi[None], design.branch)
    return E[0, :, 0], E[0, :, 1]
