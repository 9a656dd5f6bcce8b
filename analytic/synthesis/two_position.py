"""Two-position synthesis of a four-bar with minimum total link length (seed 001).

A coupler point E must move from E1 to E2 while the crank AB turns by ``phi12`` and the rocker DC by
``psi12`` about the fixed pivots A and D; the coupler turns by theta, the free design variable. The
coupler is a rigid body, so any of its points X moves as  X2 = E2 + R(theta) (X1 - E1). With B on the
crank circle (B2 = A + R(phi12)(B1 - A)) and C on the rocker circle, the pivots in position 1 follow in
closed form from 2x2 linear systems:

    (R(phi12) - R(theta)) (B1 - A) = (E2 - A) - R(theta) (E1 - A)
    (R(psi12) - R(theta)) (C1 - D) = (E2 - D) - R(theta) (E1 - D)

whose right-hand sides are the seed's auxiliaries (A, B) and (C, D) (with A at the origin and D on the
x axis); |R(a) - R(b)| = 2 |sin((a - b) / 2)| gives the seed's l1 and l3. The total length
f = l1 + l2 + l3 + l4 is then minimised over theta.

Work is done in the frame with A at the origin and D on the +x axis, so that the result is a
:class:`analytic.closed_forms.fourbar.FourBar` directly; angles phi0, psi0 are measured from the line A->D.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic.closed_forms import fourbar
from analytic._common import ParameterError

__all__ = ["Task", "Design", "design", "feasibility", "optimum", "SEED_THETAS"]

SEED_THETAS = (0.0, 5.0, -5.0, -15.0, -35.0, -55.0, -60.0, -54.0, -56.0)
"""The coupler rotations [deg] of seed 001's Table 1, in its order."""


def _rot(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s], [s, c]])


@dataclass(frozen=True)
class Task:
    """The synthesis task (SPEC.md's seed 001 data by default; lengths in any one unit, angles [rad])."""

    E1: tuple[float, float] = (30.0, 31.0)
    E2: tuple[float, float] = (10.0, 35.0)
    A: tuple[float, float] = (0.0, 0.0)
    D: tuple[float, float] = (36.0, 0.0)
    phi12: float = math.radians(35.0)
    psi12: float = math.radians(50.0)

    def __post_init__(self):
        for name in ("E1", "E2", "A", "D"):
            v = getattr(self, name)
            if len(v) != 2 or not all(math.isfinite(float(x)) for x in v):
                raise ParameterError(f"{name}={v!r} must be two finite coordinates x,y")
        for name in ("phi12", "psi12"):
            if not math.isfinite(getattr(self, name)):
                raise ParameterError(f"{name} must be finite")
        if math.dist(self.E1, self.E2) == 0:
            raise ParameterError(f"E1 and E2 coincide at {self.E1}: give two different positions of E")
        if math.dist(self.A, self.D) == 0:
            raise ParameterError(f"A and D coincide at {self.A}: the ground link needs a length")
        for name, label in (("phi12", "crank"), ("psi12", "rocker")):
            if abs(math.remainder(getattr(self, name), 2 * math.pi)) < 1e-9:
                raise ParameterError(f"{name}=0: the {label} must turn between the two positions (give a non-zero rotation)")

    @property
    def l4(self) -> float:
        return math.dist(self.A, self.D)

    def local(self, p) -> np.ndarray:
        """Point ``p`` in the frame with A at the origin and D on the +x axis."""
        d = np.subtract(self.D, self.A)
        return _rot(-math.atan2(d[1], d[0])) @ np.subtract(p, self.A)

    def world(self, p) -> np.ndarray:
        d = np.subtract(self.D, self.A)
        return _rot(math.atan2(d[1], d[0])) @ np.asarray(p) + np.asarray(self.A)


@dataclass(frozen=True)
class Design:
    """One synthesised linkage (lengths in the task's unit, angles [rad] from the line A->D)."""

    theta: float
    phi0: float
    psi0: float
    l1: float
    l2: float
    l3: float
    l4: float
    B1: tuple[float, float]
    C1: tuple[float, float]

    @property
    def total(self) -> float:
        return self.l1 + self.l2 + self.l3 + self.l4


def design(task: Task, theta: float) -> Design:
    """Closed-form pivots B1, C1 for coupler rotation ``theta`` [rad] (see the module docstring)."""
    e1, e2 = task.local(task.E1), task.local(task.E2)
    d = np.array([task.l4, 0.0])
    rt = _rot(theta)
    with np.errstate(all="ignore"):
        try:
            b1 = np.linalg.solve(_rot(task.phi12) - rt, e2 - rt @ e1)
            c1 = np.linalg.solve(_rot(task.psi12) - rt, (e2 - d) - rt @ (e1 - d)) + d
        except np.linalg.LinAlgError:      # theta equal to a rotation: that pivot is at infinity
            nan = float("nan")
            return Design(theta, nan, nan, math.inf, math.inf, math.inf, task.l4, (nan, nan), (nan, nan))
    return Design(theta=theta, phi0=math.atan2(b1[1], b1[0]), psi0=math.atan2(c1[1], c1[0] - task.l4),
                  l1=float(np.hypot(*b1)), l2=float(np.hypot(*(c1 - b1))), l3=float(np.hypot(*(c1 - d))),
                  l4=task.l4, B1=(float(b1[0]), float(b1[1])), C1=(float(c1[0]), float(c1[1])))


def linkage(task: Task, dsg: Design, omega1: float = 1.0) -> fourbar.FourBar:
    """The four-bar of a design, in position 1, with E as its coupler point and the branch of position 1."""
    b1, c1 = np.array(dsg.B1), np.array(dsg.C1)
    e1 = task.local(task.E1)
    u = (c1 - b1) / dsg.l2
    rel = e1 - b1
    cross = (task.l4 - b1[0]) * (c1[1] - b1[1]) - (0.0 - b1[1]) * (c1[0] - b1[0])
    return fourbar.FourBar(l1=dsg.l1, l2=dsg.l2, l3=dsg.l3, l4=dsg.l4,
                           ex=float(rel @ u), ey=float(u[0] * rel[1] - u[1] * rel[0]),
                           branch=1 if cross > 0 else -1, phi1_0=dsg.phi0,
                           omega1=math.copysign(abs(omega1), task.phi12))


def feasibility(task: Task, dsg: Design, samples: int = 721) -> str | None:
    """None if the design carries E from E1 to E2 as asked, else why not.

    The crank is swept from phi0 through phi12 on the assembly branch of position 1: every sample must
    assemble (no dead point is passed: the transmission angle stays above 1e-6 rad) and the rocker must
    arrive at psi0 + psi12 (not at the other branch's position).
    """
    if not all(math.isfinite(x) for x in (dsg.l1, dsg.l2, dsg.l3)) or max(dsg.l1, dsg.l3) > 1e6 * dsg.l4:
        return "a pivot at infinity (theta equals the crank or rocker rotation)"
    try:
        mech = linkage(task, dsg)
    except ParameterError as exc:
        return f"not a four-bar ({exc})"
    phi = dsg.phi0 + np.linspace(0.0, task.phi12, samples)
    st = fourbar.solve(mech, phi, 1.0)
    if not np.all(st.valid):
        k = int(np.argmin(st.valid))
        return f"cannot be assembled at crank angle {math.degrees(phi[k]):.2f}deg between the positions"
    if np.min(st.mu) < 1e-6:
        return f"passes a dead point at crank angle {math.degrees(phi[int(np.argmin(st.mu))]):.2f}deg"
    end = math.remainder(float(st.phi3[-1]) - (dsg.psi0 + task.psi12), 2 * math.pi)
    if abs(end) > 1e-6:
        return (f"reaches position 2 on the other assembly branch (rocker at {math.degrees(st.phi3[-1]):.2f}deg, "
                f"not {math.degrees(dsg.psi0 + task.psi12):.2f}deg)")
    return None


def _golden(f, lo: float, hi: float, tol: float) -> float:
    """Golden-section minimum of a unimodal f on [lo, hi] to within tol."""
    g = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = lo, hi
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = f(c), f(d)
    while b - a > tol:
        if fc <= fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = f(d)
    return 0.5 * (a + b)


@dataclass(frozen=True)
class Search:
    """Result of the search over theta: the optimum and the excluded coupler rotations with reasons."""

    optimum: Design | None
    scanned: tuple[float, ...]
    excluded: tuple[tuple[float, str], ...]


def optimum(task: Task, lo: float = math.radians(-90.0), hi: float = math.radians(90.0),
            step: float = math.radians(1.0), tol: float = 1e-9) -> Search:
    """Minimise the total length over theta in [lo, hi] [rad] among feasible designs.

    A scan at ``step`` locates the best feasible interval (feasibility and the poles at theta = phi12,
    psi12 split the range); a golden-section search then refines theta to ``tol`` [rad] between the
    scan's neighbours, and the refined design is checked for feasibility again.
    """
    if not (math.isfinite(lo) and math.isfinite(hi) and hi > lo):
        raise ParameterError(f"the theta range {math.degrees(lo):g}..{math.degrees(hi):g} deg is empty or inverted; "
                             f"give LO:HI with LO < HI")
    grid = np.linspace(lo, hi, max(3, int(math.ceil((hi - lo) / step)) + 1))
    excluded, totals = [], []
    for th in grid:
        dsg = design(task, float(th))
        why = feasibility(task, dsg)
        if why:
            excluded.append((float(th), why))
            totals.append(math.inf)
        else:
            totals.append(dsg.total)
    totals = np.array(totals)
    if not np.isfinite(totals).any():
        return Search(None, tuple(grid), tuple(excluded))
    k = int(np.argmin(totals))
    a, b = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]

    def f(th):
        dsg = design(task, th)
        return dsg.total if feasibility(task, dsg, 181) is None else math.inf

    best = design(task, _golden(f, float(a), float(b), tol))
    if feasibility(task, best) is not None or best.total > totals[k]:
        best = design(task, float(grid[k]))
    return Search(best, tuple(grid), tuple(excluded))


def mechanism(task: Task, dsg: Design, scale: float = 1.0, omega1: float = 1.0):
    """The designed four-bar as a :class:`~analytic.mechanism.Mechanism` (lengths times ``scale``, e.g.
    1e-3 for a task in mm), its crank turning at ``omega1`` [rad/s]."""
    from analytic.registry import load
    p = linkage(task, dsg, omega1)
    return load("fourbar", l1=p.l1 * scale, l2=p.l2 * scale, l3=p.l3 * scale, l4=p.l4 * scale, ex=p.ex * scale,
                ey=p.ey * scale, branch=p.branch, phi1_0=p.phi1_0, omega1=omega1)


def grashof_chain(task: Task, dsg: Design) -> str:
    """The designed four-bar's Grashof type (grashof, change-point or non-grashof)."""
    return fourbar.grashof(linkage(task, dsg)).chain
