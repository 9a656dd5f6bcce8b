"""The loads of a run besides its drives (:class:`Loads`): what the kinetostatics (``linkage forces``) and the
simulation (:mod:`sim.model`, which gives this class as ``sim.model.Loads``) both read. Kept out of
:mod:`sim.model` so that a command that does not simulate does not import MuJoCo to describe its loads."""

from __future__ import annotations

import math
from dataclasses import dataclass

from analytic import ParameterError


@dataclass(frozen=True)
class Loads:
    """What acts on the mechanism besides its drives: ``gravity`` (gx, gy) [m/s^2] in the plane (None:
    normal to it, no effect); ``force`` (Fx, Fy) [N] on the output point, fixed in the world frame, on
    throughout or (``slow_stroke_only``) only while the output point makes its slow stroke (a cutting
    force); ``inertias``: {link: Inertia} replacing the default masses."""

    gravity: tuple[float, float] | None = None
    force: tuple[float, float] = (0.0, 0.0)
    slow_stroke_only: bool = False
    inertias: dict | None = None
    extra: tuple = ()

    def __post_init__(self):
        for name, v in (("gravity", self.gravity), ("force", self.force)):
            if v is not None and not all(isinstance(x, (int, float)) and math.isfinite(x) and abs(x) <= 1e9
                                         for x in v):
                raise ParameterError(f"{name}={v} must be two finite numbers of magnitude <= 1e9")
