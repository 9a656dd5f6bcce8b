"""Path generators for synthesis: each family's coupler point for whole batches of designs at once,
its full-turn and transmission constraints, its normalised shapes and its ``linkage/1`` file.

A family is a frozen value (picklable: it travels to worker processes) whose design vector ``x`` holds
lengths in the targets' unit and angles [rad]. Every family is driven by a crank A-B of length ``a``
turning about the ground pivot A = (ax, ay); ``phi`` is B's absolute angle about A, from +x. ``branch`` is a
tuple of +-1, one per dyad, each with the solver's meaning (RRR: the free joint left of the directed line
between its known points; RRP: the intersection farther along the guide).

Families (the names are ``--type``'s; ``sixbar`` searches both chains):

``fourbar``      ``(ax, ay, theta0, d, a, b, c, ex, ey)``: D = A + d (cos theta0, sin theta0); coupler
                 B-C = b, rocker D-C = c; E = B + ex u + ey n in the coupler frame (u along B->C).
``slider_crank`` ``(ax, ay, theta0, a, b, e, ex, ey)``: the slider C runs on the line through
                 A + e n0 along u0 = (cos theta0, sin theta0) (n0 = u0 turned +90 deg); rod B-C = b;
                 E on the rod's frame.
``watt``         Watt II six-bar ``(ax, ay, theta0, d, a, b, c, eu, ev, l5, l6, gx, gy, qx, qy)``: the
                 four-bar A-B-C-D whose rocker D-C is ternary, carrying E = D + eu u + ev n (frame D->C);
                 the second loop's coupler E-F = l5 and rocker G-F = l6 about G = (gx, gy); the traced
                 point Q on the frame E->F.
``stephenson``   Stephenson III six-bar, the same vector with E on the four-bar's coupler (frame B->C,
                 ``eu, ev`` = ex, ey): the dyad E-F-G follows the coupler curve, Q on E->F.

Constraint closed forms: a four-bar loop turns its crank fully on one branch with the transmission angle
mu in ``[mu_min, 180 deg - mu_min]`` iff both extremes of |BD| (``|d - a|``, ``d + a``) satisfy it
(Grashof crank-rocker and double-crank pass, nothing else can); a slider-crank iff the crank pin's largest
distance from the slider line, ``a + |e|``, is at most ``b cos mu_min`` (mu: between the rod and the
line's normal). The six-bars' second dyad has no closed form: |E - G| is sampled over the turn and its
transmission angle at F must stay in the same band at every sample. A dyad whose transmission angle stays
above mu_min > 0 never reaches a singular (folded or stretched) pose, so it cannot change branch: that is
the whole cycle on one branch.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Family", "FourBar", "SliderCrank", "SixBar", "FAMILIES", "family", "TYPES", "fourbar_from_slider_crank"]

RATIO = 8.0
"""Normalised shapes: link lengths searched in [1/RATIO, RATIO] crank lengths (log scale)."""
REACH = (1 / 8, 16.0)
"""Normalised shapes: a coupler point's distance from its link's origin, [min, max] crank lengths (log
scale; its direction over the full turn). The literature's designs reach 9.6 (Ullah and Kota)."""
SIXBAR_SAMPLES = 96
"""Crank angles at which the six-bars' second dyad is checked during the search (the final designs are
checked on 4096, and by the general solver)."""


def _col(x, i):
    return x[:, i:i + 1]


def _signs(branch, k: int, nb: int) -> np.ndarray:
    """Branches as a (K, nb) float array (a tuple for all designs, or one row per design)."""
    b = np.asarray(branch, dtype=float)
    if b.ndim == 0:
        b = b.reshape(1)
    if b.ndim == 1:
        b = b[None, :] if b.size == nb else b[:, None]
    return np.broadcast_to(b, (k, nb))


def _rrr(px, py, qx, qy, a, b, br):
    """X with |X - P| = a and |X - Q| = b, left of P->Q where ``br`` = +1 (arrays broadcast).

    Returns (unit vector P->X (ux, uy), ok, |P - Q|^2)."""
    vx, vy = qx - px, qy - py
    r2 = vx * vx + vy * vy
    r = np.sqrt(r2)
    with np.errstate(divide="ignore", invalid="ignore"):
        ca = (a * a + r2 - b * b) / (2 * a * r)              # cos of the angle Q-P-X
        ok = np.abs(ca) <= 1.0
        sa = br * np.sqrt(np.clip(1.0 - ca * ca, 0.0, None))
        ux, uy = vx / r, vy / r
    return (ca * ux - sa * uy, sa * ux + ca * uy), ok, r2


def _fourbar_cos(d, a, b, c):
    """cos mu at the least and largest |BD| of a four-bar loop (mu between coupler and rocker)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        lo = (b * b + c * c - (d - a) ** 2) / (2 * b * c)
        hi = (b * b + c * c - (d + a) ** 2) / (2 * b * c)
    return lo, hi


def _fourbar_mu(d, a, b, c):
    """Least transmission angle [rad] over a full turn of a four-bar loop (NaN where it cannot turn)."""
    lo, hi = _fourbar_cos(d, a, b, c)
    turns = (lo <= 1) & (hi >= -1)
    with np.errstate(invalid="ignore"):
        mu = np.minimum(np.arccos(np.clip(lo, -1, 1)), math.pi - np.arccos(np.clip(hi, -1, 1)))
    return np.where(turns, mu, np.nan)


def _fourbar_margins(d, a, b, c, cm):
    """(K, 2) how far a four-bar loop's cos mu stays inside [-cm, cm] at its extremes (signed: >= 0
    inside; smooth in the lengths)."""
    lo, hi = _fourbar_cos(d, a, b, c)
    return np.stack([cm - lo, hi + cm], axis=-1)


def _fourbar_excess(d, a, b, c, cm):
    """How far a four-bar loop's cos mu leaves [-cm, cm] at its extremes (0 inside; continuous)."""
    return np.maximum(-_fourbar_margins(d, a, b, c, cm), 0).sum(axis=-1)


@dataclass(frozen=True)
class Family:
    """What the search needs of a kind of path generator (see the module doc for each vector)."""

    name: str = ""
    names: tuple[str, ...] = ()
    ground: tuple[tuple[int, int], ...] = ()     # (x, y) columns of ground positions (moved by a similarity)
    angles: tuple[int, ...] = ()                 # absolute angles (turned by a similarity)
    links: tuple[int, ...] = ()                  # link lengths bounded by the ratio constraint
    branches: tuple[tuple[int, ...], ...] = ((1,), (-1,))
    shape_dim: int = 0
    label: str = ""

    pareto_front: bool = False
    """Whether a multi-objective front is searched for the family (one crank, one loop: its forces are
    evaluated in batches, sim.service.pareto)."""

    closed_form_mu: bool = False
    """Whether a transmission angle of the family (a slider-crank's rod against its slider line) is not one
    the general solver's groups report, so its closed form is taken beside theirs."""

    @property
    def size(self) -> int:
        return len(self.names)

    @property
    def fourbar_loop(self) -> bool:
        """Whether its designs close a four-bar loop A-B-C-D (the four-bar, the six-bars' first loop)."""
        return {"a", "b", "c", "d"} <= set(self.names)

    def fourbar_lengths(self, x) -> tuple[float, float, float, float] | None:
        """The crank, coupler, rocker and ground (a, b, c, d) of the design's four-bar loop, for its Grashof
        type; None for a family without one (a slider-crank)."""
        if not self.fourbar_loop:
            return None
        return tuple(float(x[self.names.index(k)]) for k in ("a", "b", "c", "d"))

    @property
    def scaled(self) -> tuple[int, ...]:
        """Columns scaled by a similarity: every one that is not a ground coordinate or an angle."""
        fixed = {i for p in self.ground for i in p} | set(self.angles)
        return tuple(i for i in range(self.size) if i not in fixed)

    # --- geometry ------------------------------------------------------------------------------
    def points(self, x, phi, branch):
        """The traced point of K designs at crank angles ``phi`` ((K, N) or (N,)) [rad].

        Returns (E (K, N, 2) [length], NaN where a loop does not close; ok (K, N) bool)."""
        raise NotImplementedError

    def excess(self, x, branch, mu_min: float, n: int = 0) -> np.ndarray:
        """(K,) how far the designs break "the crank turns fully with every transmission angle in
        [mu_min, pi - mu_min]" (0: it holds; dimensionless, continuous). ``n``: crank angles sampled where
        a family has no closed form (0: SIXBAR_SAMPLES, each extreme refined by a parabola)."""
        raise NotImplementedError

    def margins(self, x, branch, mu_min: float, n: int = 0) -> np.ndarray:
        """(K, C) the same constraint as :meth:`excess`, signed: each extreme's distance inside its bound
        (>= 0 where it holds; smooth in x where the family has a closed form), for a constrained
        optimiser. ``excess`` is 0 exactly where every margin is >= 0."""
        raise NotImplementedError

    def mu_min(self, x, branch, n: int = 4096) -> np.ndarray:
        """(K,) least transmission angle over a full turn [rad]; NaN where the crank cannot turn."""
        raise NotImplementedError

    def pivots(self, x) -> np.ndarray:
        """(K, P, 2) the ground pivots (and a slider line's reference point) [length]."""
        x = np.atleast_2d(x)
        return np.stack([x[:, [i, j]] for i, j in self.ground], axis=1)

    pivot_names: tuple[str, ...] = ("A", "D")
    """The names of the ground pivots in the written file, in the order of :meth:`pivots` (a slider line's
    reference point has none: it is no part of the mechanism)."""

    def joints(self, x, phi, branch) -> np.ndarray:
        """(K, N, J, 2) every moving point of K designs (joints and the traced point) at crank angles ``phi``
        (NaN where a loop does not close)."""
        raise NotImplementedError

    def extent(self, x, branch, n: int = 512) -> np.ndarray:
        """(K, 4) the bounding box [x0, y0, x1, y1] of every point of K designs (ground pivots, joints, the
        traced point) over a full turn sampled at ``n`` crank angles (an extreme between two samples is
        missed by at most 1 - cos(pi / n) of its radius: 2e-5 at 512)."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        phi = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
        J = self.joints(x, phi, branch).reshape(len(x), -1, 2)
        P = np.concatenate([J, self.pivots(x)[:, :len(self.pivot_names)]], axis=1)
        with np.errstate(invalid="ignore"):
            return np.concatenate([P.min(axis=1), P.max(axis=1)], axis=1)

    def shape(self, u) -> np.ndarray:
        """(K, size) designs from points of the unit cube (K, shape_dim): A at the origin, a unit crank,
        theta0 = 0."""
        raise NotImplementedError

    def move(self, x, z, t) -> np.ndarray:
        """Designs (K, size) moved by the similarity p -> z p + t (complex z = scale e^(i angle), t)."""
        x = np.array(np.atleast_2d(x), dtype=float)
        z = np.broadcast_to(np.asarray(z, dtype=complex), (len(x),))
        t = np.broadcast_to(np.asarray(t, dtype=complex), (len(x),))
        for i, j in self.ground:
            p = (x[:, i] + 1j * x[:, j]) * z + t
            x[:, i], x[:, j] = p.real, p.imag
        for i in self.angles:
            x[:, i] = x[:, i] + np.angle(z)
        s = np.abs(z)[:, None]
        x[:, list(self.scaled)] = x[:, list(self.scaled)] * s
        return x

    def parameters(self, x, branch) -> dict:
        """One design's parameters by name, with its branches."""
        out = {k: float(v) for k, v in zip(self.names, np.asarray(x, dtype=float))}
        out["branch"] = [int(b) for b in branch] if len(branch) > 1 else int(branch[0])
        return out

    def text(self, x, branch, units: str, name: str, description: str, phi1_0: float = 0.0,
             omega1: float = 2 * math.pi) -> str:
        """The ``linkage/1`` TOML of one design, output = the traced point."""
        raise NotImplementedError


def _ln(u, lo_hi=RATIO):
    """Unit-interval values on a log scale over [1/lo_hi, lo_hi]."""
    return np.exp((2 * u - 1) * math.log(lo_hi))


def _sym(u, half):
    return (2 * u - 1) * half


def _polar(u2, reach=REACH):
    """(K, 2) unit-interval pairs -> points at a log-uniform distance in ``reach`` and any direction."""
    r = np.exp(np.log(reach[0]) + u2[:, 0] * (np.log(reach[1]) - np.log(reach[0])))
    a = (2 * u2[:, 1] - 1) * math.pi
    return np.column_stack([r * np.cos(a), r * np.sin(a)])


def _file(name, units, description, output, parameters: dict, phi1_0, omega1, ground: dict, crank_length: str,
          groups: list[dict]) -> str:
    """A design's ``linkage/1`` text (:func:`analytic.format.writing.dumps`): its parameters (the crank's
    motion last), ground pivots, the crank at A and its groups."""
    from analytic.format.writing import commented, dumps
    motion = {"phi1_0": commented(float(phi1_0), "input angle at the first target [rad]"),
              "omega1": commented(float(omega1), "[rad/s]"), "alpha1": 0.0}
    crank = {"kind": "crank", "pivot": "A", "point": "B", "length": crank_length, "link": "1", "phi0": "phi1_0",
             "omega": "omega1", "alpha": "alpha1"}
    return dumps({"format": "linkage/1", "name": name, "units": units, "description": description, "output": output,
                  "parameters": {**parameters, **motion}, "ground": ground, "inputs": [crank], "groups": groups})


def _check_finite(names, x) -> None:
    from analytic._common import ParameterError
    for k, v in zip(names, x):
        if not math.isfinite(float(v)):
            raise ParameterError(f"the synthesised {k} is not finite")


@dataclass(frozen=True)
class FourBar(Family):
    name: str = "fourbar"
    names: tuple[str, ...] = ("ax", "ay", "theta0", "d", "a", "b", "c", "ex", "ey")
    ground: tuple[tuple[int, int], ...] = ((0, 1),)
    angles: tuple[int, ...] = (2,)
    links: tuple[int, ...] = (3, 4, 5, 6)
    shape_dim: int = 5
    label: str = "four-bar"
    pareto_front: bool = True

    def points(self, x, phi, branch):
        x = np.atleast_2d(np.asarray(x, dtype=float))
        ax, ay, th, d, a, b, c, ex, ey = (_col(x, i) for i in range(9))
        br = _signs(branch, len(x), 1)
        phi = np.asarray(phi, dtype=float)
        bx, by = ax + a * np.cos(phi), ay + a * np.sin(phi)
        dx, dy = ax + d * np.cos(th), ay + d * np.sin(th)
        (cx, cy), ok, _ = _rrr(bx, by, dx, dy, b, c, br[:, 0:1])
        with np.errstate(invalid="ignore", over="ignore"):
            E = np.stack([bx + ex * cx - ey * cy, by + ex * cy + ey * cx], axis=-1)
        ok = np.broadcast_to(ok, E.shape[:2])
        E[~ok] = np.nan
        return E, ok

    def pivots(self, x):
        x = np.atleast_2d(x)
        D = x[:, :2] + x[:, 3:4] * np.column_stack([np.cos(x[:, 2]), np.sin(x[:, 2])])
        return np.stack([x[:, :2], D], axis=1)

    def joints(self, x, phi, branch):
        x = np.atleast_2d(np.asarray(x, dtype=float))
        ax, ay, th, d, a, b, c, ex, ey = (_col(x, i) for i in range(9))
        br = _signs(branch, len(x), 1)
        phi = np.asarray(phi, dtype=float)
        bx, by = ax + a * np.cos(phi), ay + a * np.sin(phi)
        dx, dy = ax + d * np.cos(th), ay + d * np.sin(th)
        (ux, uy), ok, _ = _rrr(bx, by, dx, dy, b, c, br[:, 0:1])
        bx, by = np.broadcast_to(bx, ux.shape), np.broadcast_to(by, ux.shape)
        with np.errstate(invalid="ignore", over="ignore"):
            J = np.stack([np.stack([bx, by], -1), np.stack([bx + b * ux, by + b * uy], -1),
                          np.stack([bx + ex * ux - ey * uy, by + ex * uy + ey * ux], -1)], axis=2)
        J[~np.broadcast_to(ok, ux.shape)] = np.nan
        return J

    def excess(self, x, branch, mu_min, n=0):
        x = np.atleast_2d(x)
        return _fourbar_excess(x[:, 3], x[:, 4], x[:, 5], x[:, 6], math.cos(mu_min))

    def margins(self, x, branch, mu_min, n=0):
        x = np.atleast_2d(x)
        return _fourbar_margins(x[:, 3], x[:, 4], x[:, 5], x[:, 6], math.cos(mu_min))

    def mu_min(self, x, branch, n=4096):
        x = np.atleast_2d(x)
        return _fourbar_mu(x[:, 3], x[:, 4], x[:, 5], x[:, 6])

    def shape(self, u):
        x = np.zeros((len(u), 9))
        x[:, 4] = 1.0
        x[:, [3, 5, 6]] = _ln(u[:, 0:3])
        x[:, 7:9] = _polar(u[:, 3:5])
        return x

    def linkage(self, x, branch, phi1_0=0.0, omega1=2 * math.pi):
        """The design as :class:`analytic.synthesis.fourbar.Linkage` (shared with motion and function)."""
        from analytic.synthesis.fourbar import Linkage
        ax, ay, th, d, a, b, c, ex, ey = (float(v) for v in x)
        return Linkage(A=(ax, ay), D=(ax + d * math.cos(th), ay + d * math.sin(th)), l1=a, l2=b, l3=c,
                       ex=ex, ey=ey, branch=int(branch[0]), phi1_0=float(phi1_0), omega1=float(omega1))

    def text(self, x, branch, units, name, description, phi1_0=0.0, omega1=2 * math.pi):
        from analytic.synthesis import fourbar
        return fourbar.text(self.linkage(x, branch, phi1_0, omega1), units, name, description)


@dataclass(frozen=True)
class SliderCrank(Family):
    name: str = "slider_crank"
    names: tuple[str, ...] = ("ax", "ay", "theta0", "a", "b", "e", "ex", "ey")
    ground: tuple[tuple[int, int], ...] = ((0, 1),)
    angles: tuple[int, ...] = (2,)
    links: tuple[int, ...] = (3, 4)
    shape_dim: int = 4
    label: str = "slider-crank"
    pivot_names: tuple[str, ...] = ("A",)
    pareto_front: bool = True
    closed_form_mu: bool = True

    def joints(self, x, phi, branch):
        x = np.atleast_2d(np.asarray(x, dtype=float))
        E, _ = self.points(x, phi, branch)
        ax, ay, th, a, b = (_col(x, i) for i in range(5))
        phi = np.asarray(phi, dtype=float)
        bx, by = np.broadcast_to(ax + a * np.cos(phi), E.shape[:2]), np.broadcast_to(ay + a * np.sin(phi), E.shape[:2])
        C, _ = self.points(np.column_stack([x[:, :6], x[:, 4], np.zeros(len(x))]), phi, branch)   # E at C
        return np.stack([np.stack([bx, by], -1), C, E], axis=2)

    def points(self, x, phi, branch):
        x = np.atleast_2d(np.asarray(x, dtype=float))
        ax, ay, th, a, b, e, ex, ey = (_col(x, i) for i in range(8))
        br = _signs(branch, len(x), 1)[:, 0:1]
        phi = np.asarray(phi, dtype=float)
        c0, s0 = np.cos(th), np.sin(th)
        rx, ry = a * np.cos(phi), a * np.sin(phi)          # B - A
        h = -rx * s0 + ry * c0 - e                          # B's height above the slider line
        disc = b * b - h * h
        ok = disc >= 0
        with np.errstate(invalid="ignore"):
            w = br * np.sqrt(disc)                          # C - B along the line
        ux, uy = (w * c0 + h * s0) / b, (w * s0 - h * c0) / b   # unit B->C (C - B = w u0 - h n0)
        bx, by = ax + rx, ay + ry
        with np.errstate(invalid="ignore", over="ignore"):
            E = np.stack([bx + ex * ux - ey * uy, by + ex * uy + ey * ux], axis=-1)
        ok = np.broadcast_to(ok, E.shape[:2])
        E[~ok] = np.nan
        return E, ok

    def pivots(self, x):
        x = np.atleast_2d(x)
        F = x[:, :2] + x[:, 5:6] * np.column_stack([-np.sin(x[:, 2]), np.cos(x[:, 2])])
        return np.stack([x[:, :2], F], axis=1)

    def excess(self, x, branch, mu_min, n=0):
        return np.maximum(-self.margins(x, branch, mu_min, n)[:, 0], 0)

    def margins(self, x, branch, mu_min, n=0):
        x = np.atleast_2d(x)
        a, b, e = x[:, 3], x[:, 4], x[:, 5]
        with np.errstate(divide="ignore", invalid="ignore"):
            return (math.cos(mu_min) - (a + np.abs(e)) / b)[:, None]

    def mu_min(self, x, branch, n=4096):
        x = np.atleast_2d(x)
        with np.errstate(divide="ignore", invalid="ignore"):
            r = (x[:, 3] + np.abs(x[:, 5])) / x[:, 4]
            return np.where(r < 1, np.arccos(np.clip(r, -1, 1)), np.nan)

    def shape(self, u):
        x = np.zeros((len(u), 8))
        x[:, 3] = 1.0
        x[:, 4] = _ln(u[:, 0])
        x[:, 5] = _sym(u[:, 1], 2.0)
        x[:, 6:8] = _polar(u[:, 2:4])
        return x

    def text(self, x, branch, units, name, description, phi1_0=0.0, omega1=2 * math.pi):
        _check_finite(self.names, x)
        from analytic.format.writing import commented
        ax, ay, th, a, b, e, ex, ey = (float(v) for v in x)
        parameters = {"ax": ax, "ay": ay, "theta0": commented(th, "direction of the slider line [rad]"),
                      "r": commented(a, "crank AB"), "l": commented(b, "rod BC"),
                      "e": commented(e, "the slider line passes e to the left of A (along theta0)"),
                      "ex": commented(ex, "E in the rod frame (origin B, x-axis B->C)"), "ey": ey,
                      "branch": int(branch[0])}
        groups = [{"kind": "RRP", "point": "C", "from": "B", "length": "l", "guide": {"through": "A", "angle": "theta0"},
                   "offset": "e", "links": ["2", "slider"], "branch": "branch"},
                  {"kind": "point", "point": "E", "on": ["B", "C"], "at": ["ex", "ey"]}]
        return _file(name, units, description, "E", parameters, phi1_0, omega1, {"A": ["ax", "ay"]}, "r", groups)


def fourbar_from_slider_crank(xs, branch, length, side) -> tuple[np.ndarray, np.ndarray]:
    """Four-bars near their slider-crank limit: each slider-crank ``xs`` (K, 8) on its ``branch`` (K,)
    with the slider C replaced by a rocker of ``length`` (K,) [length] pivoted ``side`` (K,) (+1: on the
    n0 side of the slider line) at that distance from the line, square to it over the middle of C's travel;
    the crank, coupler and traced point kept. The longer the rocker, the nearer C's arc to the line and the
    coupler curve to the slider-crank's. Returns (x (K, 9), branch (K,)): the branch on which C stays on
    the slider-crank's side of B (C left of B->D iff -side w > 0, w = C - B along the line)."""
    xs = np.atleast_2d(np.asarray(xs, dtype=float))
    k = len(xs)
    br, L, sd = (np.broadcast_to(np.asarray(v, dtype=float).reshape(-1), (k,)) for v in (branch, length, side))
    ax, ay, th, a, b, e = (xs[:, i] for i in range(6))
    phi = np.linspace(0.0, 2 * math.pi, 256, endpoint=False)
    C, _ = FAMILIES["slider_crank"].points(np.column_stack([xs[:, :5], e, b, np.zeros(k)]), phi, br[:, None])
    u0 = np.stack([np.cos(th), np.sin(th)], axis=1)
    n0 = np.stack([-np.sin(th), np.cos(th)], axis=1)
    travel = np.einsum("knj,kj->kn", C - np.stack([ax, ay], axis=1)[:, None], u0)
    ok = np.isfinite(travel)
    mid = 0.5 * (np.where(ok, travel, np.inf).min(axis=1) + np.where(ok, travel, -np.inf).max(axis=1))
    mid = np.where(np.isfinite(mid), mid, 0.0)                 # a slider-crank that never closes: any point
    D = np.stack([ax, ay], axis=1) + (e + sd * L)[:, None] * n0 + mid[:, None] * u0
    AD = D - np.stack([ax, ay], axis=1)
    x = np.column_stack([ax, ay, np.arctan2(AD[:, 1], AD[:, 0]), np.hypot(AD[:, 0], AD[:, 1]), a, b, L,
                         xs[:, 6], xs[:, 7]])
    return x, -sd * br


@dataclass(frozen=True)
class SixBar(Family):
    """Watt II (``chain="watt"``, E on the rocker D-C) or Stephenson III (``"stephenson"``, E on the
    coupler B-C); the dyad E-F-G and the traced point Q on E->F."""

    chain: str = "watt"
    name: str = "watt"
    names: tuple[str, ...] = ("ax", "ay", "theta0", "d", "a", "b", "c", "eu", "ev", "l5", "l6", "gx", "gy",
                              "qx", "qy")
    ground: tuple[tuple[int, int], ...] = ((0, 1), (11, 12))
    angles: tuple[int, ...] = (2,)
    links: tuple[int, ...] = (3, 4, 5, 6, 9, 10)
    branches: tuple[tuple[int, ...], ...] = ((1, 1), (1, -1), (-1, 1), (-1, -1))
    shape_dim: int = 11
    label: str = "Watt II six-bar"
    pivot_names: tuple[str, ...] = ("A", "D", "G")

    def joints(self, x, phi, branch):
        x = np.atleast_2d(np.asarray(x, dtype=float))
        ax, ay, th, d, a, b, c = (_col(x, i) for i in range(7))
        br = _signs(branch, len(x), 2)
        phi = np.asarray(phi, dtype=float)
        bx, by = ax + a * np.cos(phi), ay + a * np.sin(phi)
        dx, dy = ax + d * np.cos(th), ay + d * np.sin(th)
        (ux, uy), _, _ = _rrr(bx, by, dx, dy, b, c, br[:, 0:1])
        (ex, ey), (vx, vy), ok, _ = self._joints(x, phi, branch)
        l5 = _col(x, 9)
        Q, _ = self.points(x, phi, branch)
        sh = Q.shape[:2]
        pts = [(bx, by), (bx + b * ux, by + b * uy), (ex, ey), (ex + l5 * vx, ey + l5 * vy)]
        with np.errstate(invalid="ignore", over="ignore"):
            J = np.stack([np.stack([np.broadcast_to(u, sh), np.broadcast_to(v, sh)], -1) for u, v in pts] + [Q], axis=2)
        J[~np.broadcast_to(ok, sh)] = np.nan
        return J

    def _joints(self, x, phi, branch):
        """E, G and the unit vector E->F: ((ex, ey), (gx, gy), (fx, fy) unit, ok, |E - G|^2)."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        ax, ay, th, d, a, b, c, eu, ev, l5, l6, gx, gy = (_col(x, i) for i in range(13))
        br = _signs(branch, len(x), 2)
        phi = np.asarray(phi, dtype=float)
        bx, by = ax + a * np.cos(phi), ay + a * np.sin(phi)
        dx, dy = ax + d * np.cos(th), ay + d * np.sin(th)
        (ux, uy), ok1, _ = _rrr(bx, by, dx, dy, b, c, br[:, 0:1])       # unit B->C
        cx, cy = bx + b * ux, by + b * uy
        if self.chain == "watt":                                         # frame D->C
            ox, oy, fx, fy = dx, dy, (cx - dx) / c, (cy - dy) / c
        else:                                                            # frame B->C
            ox, oy, fx, fy = bx, by, ux, uy
        ex, ey = ox + eu * fx - ev * fy, oy + eu * fy + ev * fx
        (vx, vy), ok2, r2 = _rrr(ex, ey, gx, gy, l5, l6, br[:, 1:2])      # unit E->F
        return (ex, ey), (vx, vy), ok1 & ok2, r2

    def points(self, x, phi, branch):
        x = np.atleast_2d(np.asarray(x, dtype=float))
        (ex, ey), (vx, vy), ok, _ = self._joints(x, phi, branch)
        qx, qy = _col(x, 13), _col(x, 14)
        with np.errstate(invalid="ignore", over="ignore"):
            E = np.stack([ex + qx * vx - qy * vy, ey + qx * vy + qy * vx], axis=-1)
        ok = np.broadcast_to(ok, E.shape[:2])
        E[~ok] = np.nan
        return E, ok

    def _second_cos(self, x, branch, n):
        """cos of the second dyad's transmission angle at F on n crank angles, (K, n)."""
        x = np.atleast_2d(x)
        phi = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
        _, _, _, r2 = self._joints(x, phi, branch)
        l5, l6 = x[:, 9:10], x[:, 10:11]
        with np.errstate(divide="ignore", invalid="ignore"):
            return (l5 * l5 + l6 * l6 - r2) / (2 * l5 * l6)

    def _second_worst(self, x, branch, n):
        """(K,) the largest |cos mu| of the second dyad over the turn: the largest of n samples, refined
        by the parabola through it and its two neighbours (|cos mu| is smooth where the dyad closes, so
        the vertex is within O(h^4) of the true extreme; NaN where a sample does not close)."""
        cs = np.abs(self._second_cos(x, branch, n))
        j = np.nanargmax(np.where(np.isfinite(cs), cs, np.inf), axis=1)[:, None]
        f0 = np.take_along_axis(cs, j, 1)[:, 0]
        fm = np.take_along_axis(cs, (j - 1) % n, 1)[:, 0]
        fp = np.take_along_axis(cs, (j + 1) % n, 1)[:, 0]
        den = fm - 2 * f0 + fp
        with np.errstate(divide="ignore", invalid="ignore"):
            peak = np.where(den < 0, f0 - (fp - fm) ** 2 / (8 * den), f0)
        peak = np.maximum(peak, f0)
        return np.where(np.all(np.isfinite(cs), axis=1), peak, np.nan)

    def excess(self, x, branch, mu_min, n=0):
        x = np.atleast_2d(x)
        cm = math.cos(mu_min)
        first = _fourbar_excess(x[:, 3], x[:, 4], x[:, 5], x[:, 6], cm)
        out = first.copy()
        ok = first == 0                       # the second dyad only where the first loop turns
        if ok.any():
            worst = self._second_worst(x[ok], _signs(branch, len(x), 2)[ok], n or SIXBAR_SAMPLES)
            out[ok] = np.maximum(worst - cm, 0)
        return np.where(np.isfinite(out), out, 1e3)

    def margins(self, x, branch, mu_min, n=0):
        """The first loop's closed form and the second dyad's sampled worst (each extreme refined by a
        parabola; smooth only between the samples)."""
        x = np.atleast_2d(x)
        cm = math.cos(mu_min)
        first = _fourbar_margins(x[:, 3], x[:, 4], x[:, 5], x[:, 6], cm)
        worst = self._second_worst(x, _signs(branch, len(x), 2), n or SIXBAR_SAMPLES)
        return np.column_stack([first, cm - worst])

    def mu_min(self, x, branch, n=4096):
        x = np.atleast_2d(x)
        first = _fourbar_mu(x[:, 3], x[:, 4], x[:, 5], x[:, 6])
        worst = self._second_worst(x, _signs(branch, len(x), 2), n)
        with np.errstate(invalid="ignore"):
            second = np.where(worst <= 1, math.pi / 2 - np.arcsin(np.clip(worst, 0, 1)), np.nan)
        return np.minimum(first, second)

    def pivots(self, x):
        x = np.atleast_2d(x)
        D = x[:, :2] + x[:, 3:4] * np.column_stack([np.cos(x[:, 2]), np.sin(x[:, 2])])
        return np.stack([x[:, :2], D, x[:, 11:13]], axis=1)

    def shape(self, u):
        x = np.zeros((len(u), 15))
        x[:, 4] = 1.0
        x[:, [3, 5, 6]] = _ln(u[:, 0:3])
        x[:, 7:9] = _polar(u[:, 3:5], (1 / 8, 8.0))
        x[:, 9:11] = _ln(u[:, 5:7])
        x[:, 11:13] = _sym(u[:, 7:9], 2 * RATIO)
        x[:, 13:15] = _polar(u[:, 9:11])
        return x

    def text(self, x, branch, units, name, description, phi1_0=0.0, omega1=2 * math.pi):
        _check_finite(self.names, x)
        from analytic.format.writing import commented
        ax, ay, th, d, a, b, c, eu, ev, l5, l6, gx, gy, qx, qy = (float(v) for v in x)
        on = ["D", "C"] if self.chain == "watt" else ["B", "C"]
        where = "the rocker D-C (frame D->C)" if self.chain == "watt" else "the coupler B-C (frame B->C)"
        parameters = {"ax": ax, "ay": ay, "dx": ax + d * math.cos(th), "dy": ay + d * math.sin(th), "gx": gx, "gy": gy,
                      "l1": commented(a, "crank AB"), "l2": commented(b, "coupler BC"), "l3": commented(c, "rocker DC"),
                      "eu": commented(eu, f"E on {where}"), "ev": ev, "l5": commented(l5, "link EF"),
                      "l6": commented(l6, "rocker GF"), "qx": commented(qx, "Q, the traced point, on link EF (frame E->F)"),
                      "qy": qy, "branch1": int(branch[0]), "branch2": int(branch[1])}
        groups = [{"kind": "RRR", "point": "C", "from": ["B", "D"], "lengths": ["l2", "l3"], "links": ["2", "3"],
                   "branch": "branch1"},
                  {"kind": "point", "point": "E", "on": on, "at": ["eu", "ev"]},
                  {"kind": "RRR", "point": "F", "from": ["E", "G"], "lengths": ["l5", "l6"], "links": ["5", "6"],
                   "branch": "branch2"},
                  {"kind": "point", "point": "Q", "on": ["E", "F"], "at": ["qx", "qy"]}]
        return _file(name, units, description, "Q", parameters, phi1_0, omega1,
                     {"A": ["ax", "ay"], "D": ["dx", "dy"], "G": ["gx", "gy"]}, "l1", groups)


FAMILIES = {"fourbar": FourBar(), "slider_crank": SliderCrank(),
            "watt": SixBar(), "stephenson": SixBar(chain="stephenson", name="stephenson",
                                                   label="Stephenson III six-bar")}
TYPES = {"fourbar": ("fourbar",), "slider_crank": ("slider_crank",), "sixbar": ("watt", "stephenson")}
"""``--type`` -> the families searched."""
DEFAULT_TYPE = "fourbar"
"""The ``--type`` searched when none is named."""


def family(name: str) -> Family:
    return FAMILIES[name]
