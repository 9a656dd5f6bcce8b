"""Constraints every synthesis type applies to what it returns (SPEC, "Synthesis constraints and budgets"),
and the measures a returned design reports.

A design is measured on its own ``linkage/1`` file, solved by the general solver over its working input
range (:func:`measure`): the path generators' full crank turn, or a motion or function generator's travel
from its first target to its last. That is independent of the closed forms the searches use, so a
design that passes :func:`broken` here passes as written.

* ``transmission_deg`` [min, max]: every transmission angle of the file over the working range, each
  folded into [0, 90] deg (an RRR's angle between its two links; an RRP's between the rod and the guide's
  normal, 90 deg when the rod lies along the guide);
* ``size``: the larger side of the bounding box of every point of the mechanism (ground pivots, joints,
  the output point) over the working range, in the file's unit; ``box`` = [x0, y0, x1, y1];
* ``input_range``: the working range of the first input [rad];
* ``grashof``: a four-bar's type from its link lengths (crank a, coupler b, rocker c, ground d; s + l
  against p + q): ``crank-rocker`` (the crank shortest), ``double-crank`` (the ground shortest),
  ``double-rocker`` (the coupler shortest), ``rocker-crank`` (the rocker shortest: the input rocks),
  ``triple-rocker`` (non-Grashof), ``change-point`` (s + l = p + q); "" for other linkages.

Limits (:class:`Limits`): a least transmission angle, a largest size, a box for each named ground pivot,
the Grashof type wanted (``any``, ``crank-rocker`` or ``double-crank``) and, for a four-bar measured with its
link lengths, the shortest link allowed (``min_link``: no link shorter than its own pin hole) and the
longest/shortest ratio (``max_ratio``). :func:`unreachable` says when targets alone break the size limit
(the traced point is one of the points boxed, so targets spanning more than ``max_size`` cannot all be met).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from analytic._common import ParameterError

__all__ = ["GRASHOF", "Region", "Limits", "Measure", "parse_angle_deg", "parse_region", "grashof_type",
           "measure", "broken", "record", "unreachable"]

GRASHOF = ("any", "crank-rocker", "double-crank")
"""``--grashof`` values."""
CHANGE_POINT = 1e-9
"""Relative tolerance of s + l = p + q (a change-point four-bar) against the longest link: rounding."""
SLACK_DEG = 1e-6
"""[deg] A measured transmission angle may fall this far below the limit: the polishes end on an active
bound up to rounding (1e-7 rad seen), far below what anyone can build or measure."""
SLACK_REL = 1e-9
"""Relative slack of the size and region limits: rounding of the solver's positions."""


@dataclass(frozen=True)
class Region:
    """A box for one named ground pivot: ``name`` (a ground point of the written file), x0 <= x <= x1,
    y0 <= y <= y1 [file units]."""

    name: str
    x0: float
    x1: float
    y0: float
    y1: float

    def contains(self, x: float, y: float, slack: float = 0.0) -> bool:
        return self.x0 - slack <= x <= self.x1 + slack and self.y0 - slack <= y <= self.y1 + slack

    def text(self) -> str:
        return f"{self.name}={self.x0:g}:{self.x1:g},{self.y0:g}:{self.y1:g}"


@dataclass(frozen=True)
class Limits:
    """What every returned design must meet: ``min_transmission`` [deg], ``max_size`` [file units] (None:
    none), ``regions`` (one :class:`Region` per named ground pivot), ``grashof`` (one of GRASHOF),
    ``min_link`` [file units] and ``max_ratio`` (None: none; a four-bar's links, :attr:`Measure.links`)."""

    min_transmission: float = 30.0
    max_size: float | None = None
    regions: tuple[Region, ...] = ()
    grashof: str = "any"
    min_link: float | None = None
    max_ratio: float | None = None

    def check(self) -> "Limits":
        if not (0 <= self.min_transmission < 90):
            raise ParameterError(f"--min-transmission {self.min_transmission:g} must be in [0, 90) deg")
        if self.max_size is not None and not (math.isfinite(self.max_size) and self.max_size > 0):
            raise ParameterError(f"--max-size {self.max_size!r} must be a length > 0 (file units)")
        if self.min_link is not None and not (math.isfinite(self.min_link) and self.min_link > 0):
            raise ParameterError(f"--min-link {self.min_link!r} must be a length > 0 (file units)")
        if self.max_ratio is not None and not (math.isfinite(self.max_ratio) and self.max_ratio > 1):
            raise ParameterError(f"--max-ratio {self.max_ratio!r} must be a number > 1 (longest/shortest link)")
        if self.grashof not in GRASHOF:
            raise ParameterError(f"--grashof {self.grashof}: use one of {', '.join(GRASHOF)}")
        names = [r.name for r in self.regions]
        for n in names:
            if names.count(n) > 1:
                raise ParameterError(f"--pivot-region {n} is given twice; give each pivot once")
        return self

    def check_names(self, pivots: tuple[str, ...], what: str) -> None:
        """Refuse a region naming a pivot the design does not have."""
        for r in self.regions:
            if r.name not in pivots:
                raise ParameterError(f"--pivot-region {r.name}: {what} has the ground pivots {', '.join(pivots)}; "
                                     f"name one of them")

    def region(self, name: str) -> Region | None:
        return next((r for r in self.regions if r.name == name), None)


def parse_angle_deg(option: str, text) -> float:
    """An angle option in degrees: ``30`` or ``30deg`` (SPEC: every angle option takes the suffix)."""
    s = str(text).strip()
    if s.lower().endswith("deg"):
        s = s[:-3]
    try:
        v = float(s)
    except ValueError:
        raise ParameterError(f"{option} {text!r} is not an angle in degrees (e.g. 30 or 30deg)") from None
    if not math.isfinite(v):
        raise ParameterError(f"{option} {text!r} must be finite")
    return v


def parse_region(text: str) -> Region:
    """``NAME=x0:x1,y0:y1`` (file units)."""
    usage = f"--pivot-region {text!r} is not NAME=x0:x1,y0:y1 (e.g. A=-10:10,-5:5, file units)"
    if "=" not in text:
        raise ParameterError(usage)
    name, rest = (s.strip() for s in text.split("=", 1))
    parts = rest.split(",")
    if not name.isidentifier() or len(parts) != 2 or any(p.count(":") != 1 for p in parts):
        raise ParameterError(usage)
    try:
        (x0, x1), (y0, y1) = ([float(v) for v in p.split(":")] for p in parts)
    except ValueError:
        raise ParameterError(usage) from None
    if not all(math.isfinite(v) for v in (x0, x1, y0, y1)):
        raise ParameterError(f"--pivot-region {text!r}: give finite numbers")
    if not (x1 > x0 and y1 > y0):
        raise ParameterError(f"--pivot-region {text!r}: each range must go from the smaller to the larger value")
    return Region(name, x0, x1, y0, y1)


def grashof_type(a: float, b: float, c: float, d: float) -> str:
    """A four-bar's type (module doc) from crank ``a``, coupler ``b``, rocker ``c``, ground ``d``."""
    L = [a, b, c, d]
    s, lo = min(L), max(L)
    pq = sum(L) - s - lo
    if abs(s + lo - pq) <= CHANGE_POINT * lo:
        return "change-point"
    if s + lo > pq:
        return "triple-rocker"
    return {0: "crank-rocker", 1: "double-rocker", 2: "rocker-crank", 3: "double-crank"}[L.index(s)]


@dataclass(frozen=True)
class Measure:
    """What one design measures over its working range (module doc); lengths in file units."""

    transmission_deg: tuple[float, float]
    size: float
    box: tuple[float, float, float, float]
    input_range: tuple[float, float]
    pivots: dict = field(default_factory=dict)
    grashof: str = ""
    links: tuple[float, ...] = ()


def _transmissions(mech, sol) -> list[np.ndarray]:
    """Every transmission angle of the solved mechanism [rad], folded into [0, pi/2] (the kinds' ``mu``
    outputs: an RRR's between its links, an RRP's between the rod and the guide's normal)."""
    out = [np.asarray(sol[name]) for name in mech.transmission_angles.values()]
    return [np.minimum(v, math.pi - v) for v in out]


MEASURE_SAMPLES = 1441
"""Values of the first input :func:`measure` solves over a working range (1/8 deg apart over 180 deg)."""


def measure(mech, lo: float, hi: float, n: int = MEASURE_SAMPLES,
            lengths: tuple[float, float, float, float] | None = None, sol=None) -> Measure:
    """Measure ``mech`` (a :class:`analytic.Mechanism` of one input) with its first input over [lo, hi]
    [rad] at ``n`` samples by the general solver; ``lengths`` (a, b, c, d) of a four-bar give its Grashof
    type; ``sol``: the solution at ``n`` values evenly spaced over the range (either way round) already
    solved by the caller, instead of solving here. Raises ParameterError where it cannot assemble somewhere
    in the range."""
    if sol is None:
        sol = mech.solve(np.linspace(lo, hi, n))
    bad = sol.first_failure()
    if bad is not None:
        raise ParameterError(f"the design cannot assemble over its working range ({bad})")
    k = 1.0 / mech.scale
    xs = np.stack([np.asarray(sol["x" + p]) * k for p in mech.points])
    ys = np.stack([np.asarray(sol["y" + p]) * k for p in mech.points])
    box = (float(xs.min()), float(ys.min()), float(xs.max()), float(ys.max()))
    mus = _transmissions(mech, sol)
    tr = ((math.degrees(min(float(v.min()) for v in mus)), math.degrees(max(float(v.max()) for v in mus)))
          if mus else (90.0, 90.0))
    pivots = {p: (float(np.asarray(sol["x" + p])[0] * k), float(np.asarray(sol["y" + p])[0] * k))
              for p in mech.ground_points}
    return Measure(tr, max(box[2] - box[0], box[3] - box[1]), box, (float(lo), float(hi)), pivots,
                   grashof_type(*lengths) if lengths is not None else "",
                   tuple(float(v) for v in lengths) if lengths is not None else ())


def broken(m: Measure, limits: Limits, unit: str = "") -> str:
    """Words for the first limit ``m`` breaks ('' when none)."""
    lo, hi = m.transmission_deg
    if lo < limits.min_transmission - SLACK_DEG:
        return (f"transmission angle {lo:.1f}-{hi:.1f} deg over the working range: below --min-transmission "
                f"{limits.min_transmission:g} deg")
    if limits.max_size is not None and m.size > limits.max_size * (1 + SLACK_REL):
        return (f"size {m.size:.4g} {unit} (its bounding box over the working range) exceeds --max-size "
                f"{limits.max_size:g} {unit}").replace("  ", " ")
    for r in limits.regions:
        p = m.pivots.get(r.name)
        if p is not None and not r.contains(*p, SLACK_REL * max(m.size, 1e-300)):
            return f"ground pivot {r.name} at ({p[0]:.4g}, {p[1]:.4g}) lies outside --pivot-region {r.text()}"
    if limits.grashof != "any" and m.grashof and m.grashof != limits.grashof:
        return f"a {m.grashof} four-bar, not the --grashof {limits.grashof} asked for"
    if m.links and limits.min_link is not None and min(m.links) < limits.min_link * (1 - SLACK_REL):
        return (f"shortest link {min(m.links):.4g} {unit} (crank, coupler, rocker, ground "
                f"{', '.join(f'{v:.4g}' for v in m.links)}) is below --min-link {limits.min_link:g} {unit}"
                ).replace("  ", " ")
    if m.links and limits.max_ratio is not None and max(m.links) > limits.max_ratio * min(m.links) * (1 + SLACK_REL):
        return (f"longest/shortest link {max(m.links) / min(m.links):.4g} (crank, coupler, rocker, ground "
                f"{', '.join(f'{v:.4g}' for v in m.links)}) exceeds --max-ratio {limits.max_ratio:g}")
    return ""


def unreachable(points, limits: Limits, unit: str = "", what: str = "targets") -> str:
    """Words saying why no design can meet ``points`` (N, 2) [file units] within ``limits`` ('' when the
    limits do not rule it out): the traced point is boxed with the mechanism, so targets whose bounding box
    has a side over ``max_size`` cannot all be reached by a design of that size."""
    p = np.asarray(points, dtype=float)
    span = float(np.ptp(p, axis=0).max()) if len(p) else 0.0
    if limits.max_size is not None and span > limits.max_size * (1 + SLACK_REL):
        return (f"the {what} span {span:.4g} {unit} but --max-size {limits.max_size:g} {unit} bounds the whole "
                f"mechanism, its traced point included: no design that size reaches them; raise --max-size to "
                f"at least {span:.4g} {unit}").replace("  ", " ")
    return ""


def record(m: Measure) -> dict:
    """The JSON fields of a measure: ``transmission_deg`` [min, max], ``size`` and ``box`` (file units),
    ``input_range`` [rad], ``grashof``."""
    return {"transmission_deg": [m.transmission_deg[0], m.transmission_deg[1]], "size": m.size,
            "box": list(m.box), "input_range": [m.input_range[0], m.input_range[1]], "grashof": m.grashof}
