"""A four-bar with its pivots anywhere, as exact synthesis returns it, written as a ``linkage/1`` file.

Crank AB about ground pivot A, coupler BC carrying the output point E, rocker DC about ground pivot D:
the file's points and links are those of the library's ``fourbar`` (crank link ``1``, coupler ``2``,
rocker ``3``), but A and D are free, so the input angle ``phi1`` is the crank's absolute angle from +x.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic._common import ParameterError
from analytic.format.linkfile import UNITS

__all__ = ["Linkage", "text", "mechanism", "branch_of"]


@dataclass(frozen=True)
class Linkage:
    """A four-bar in one length unit (lengths in it, angles [rad]).

    ``A``, ``D``: ground pivots (x, y); ``l1`` crank AB, ``l2`` coupler BC, ``l3`` rocker DC; ``ex``,
    ``ey``: E in the coupler frame (origin B, x-axis B->C); ``branch``: +1 when C is left of B->D;
    ``phi1_0``: the input angle at the first target; ``omega1``: input speed [rad/s] (its sign: the turning
    sense that meets the targets in order)."""

    A: tuple[float, float]
    D: tuple[float, float]
    l1: float
    l2: float
    l3: float
    ex: float
    ey: float
    branch: int
    phi1_0: float = 0.0
    omega1: float = 2 * math.pi

    def parameters(self) -> dict[str, float]:
        return {"ax": self.A[0], "ay": self.A[1], "dx": self.D[0], "dy": self.D[1], "l1": self.l1,
                "l2": self.l2, "l3": self.l3, "ex": self.ex, "ey": self.ey, "branch": self.branch,
                "phi1_0": self.phi1_0, "omega1": self.omega1}


def branch_of(B, C, D) -> int:
    """+1 if C is left of the line B -> D (the solver's RRR branch), else -1."""
    cross = (D[0] - B[0]) * (C[1] - B[1]) - (D[1] - B[1]) * (C[0] - B[0])
    return 1 if cross > 0 else -1


def text(link: Linkage, units: str, name: str, description: str, input_range: tuple[float, float] | None = None) -> str:
    """The ``linkage/1`` TOML of ``link`` (every number written with 17 significant digits); ``input_range``
    (lo, hi) [rad]: the crank's working range, written as the file's ``input_range`` (every command rocks
    over it)."""
    if units not in UNITS:
        raise ParameterError(f"unknown unit {units!r}; use one of {', '.join(UNITS)}")
    for k, v in link.parameters().items():
        if not math.isfinite(v):
            raise ParameterError(f"the synthesised {k} is not finite")
    from analytic.format.writing import commented, dumps
    p = {k: float(v) for k, v in link.parameters().items()}
    head = {"format": "linkage/1", "name": name, "units": units, "description": description, "output": "E"}
    if input_range is not None:
        head["input_range"] = commented(f"{float(input_range[0])!r}:{float(input_range[1])!r}", "[rad]")
    parameters = {"ax": p["ax"], "ay": p["ay"], "dx": p["dx"], "dy": p["dy"], "l1": commented(p["l1"], "crank AB"),
                  "l2": commented(p["l2"], "coupler BC"), "l3": commented(p["l3"], "rocker DC"),
                  "ex": commented(p["ex"], "E in the coupler frame (origin B, x-axis B->C)"), "ey": p["ey"],
                  "branch": int(p["branch"]),
                  "phi1_0": commented(p["phi1_0"], "input angle at the first target [rad]"),
                  "omega1": commented(p["omega1"], "[rad/s]"), "alpha1": 0.0}
    crank = {"kind": "crank", "pivot": "A", "point": "B", "length": "l1", "link": "1", "phi0": "phi1_0",
             "omega": "omega1", "alpha": "alpha1"}
    groups = [{"kind": "RRR", "point": "C", "from": ["B", "D"], "lengths": ["l2", "l3"], "links": ["2", "3"],
               "branch": "branch"},
              {"kind": "point", "point": "E", "on": ["B", "C"], "at": ["ex", "ey"]}]
    return dumps({**head, "parameters": parameters, "ground": {"A": ["ax", "ay"], "D": ["dx", "dy"]},
                  "inputs": [crank], "groups": groups})


def mechanism(link: Linkage, units: str = "m", name: str = "synthesised_fourbar", description: str = ""):
    """The :class:`analytic.Mechanism` of ``link`` (read back from its own file text)."""
    from analytic.registry import from_text
    return from_text(text(link, units, name, description), f"<{name}>")


def coupler_frame(B, C, E) -> tuple[float, float]:
    """E's coordinates (ex, ey) in the coupler frame with origin B and x-axis B -> C."""
    B, C, E = (np.asarray(v, dtype=float) for v in (B, C, E))
    u = (C - B) / np.hypot(*(C - B))
    r = E - B
    return float(r @ u), float(u[0] * r[1] - u[1] * r[0])
