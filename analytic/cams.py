"""Disc cams and their followers (SPEC "Cams and followers"): pure, vectorised geometry.

A cam turns counter-clockwise about its pivot A (a ground point) with its link; theta is the cam link's angle
(its frame's x-axis from +x). The follower is

* **translating**: on a ground line of direction u through a point, its signed distance from A the offset e
  (positive to the left of u); its trace point F = A + e n + d u (n = J u, J the quarter turn), d the
  distance along the guide from A's foot;
* **oscillating**: an arm of length ``arm`` about a ground point B; F = B + arm (cos psi, sin psi).

The trace point is the roller's centre, the knife's edge or (flat face, translating only) the foot of the
face on the guide, the face square to the guide. The follower's **lift** h(theta) (SPEC "Motion laws":
``segments`` over the cam angle, one :class:`analytic.laws.Profile` whose "time" is the cam angle in rad;
or, given a ``profile``, a periodic spline of the lift that profile gives) moves it from its base position:
d = d0 + h (d0 = sqrt((r_b + r_r)^2 - e^2) for a knife (r_r = 0) or roller, d0 = r_b for a flat face), or
psi = psi0 + h (the arm angle where |F - A| = r_b + r_r, on the side where a counter-clockwise turn of the arm
lifts the follower away from A).

With r(theta) = F - A (world, at the follower's place for cam angle theta) the pitch curve in the cam's
frame is P = R(-theta) r; exactly, P' = R(-theta) (r' - J r), P'' = R(-theta) (r'' - 2 J r' - r), with r', r''
from the lift's exact derivatives. As theta grows the pitch curve runs clockwise in the cam's frame, so its
outward normal is J P' / |P'| and its radius of curvature (positive convex) rho_p = -|P'|^3 / (P' x P'').
The profile is the pitch curve moved in by the roller (rho = rho_p - r_r); a knife's is the pitch curve; a
flat face's is the envelope of the face's lines p . u_c = d (u_c = R(-theta) u): p = R(-theta)(d u - d' n),
rho = d + d'' (Norton, *Design of Machinery*, 5th ed., sec. 8.8, eq. 8.31), the contact d' + e... off the
foot along the face. The pressure angle is the signed angle from the follower's direction of motion at F
(u; for an arm J (F - B) / |F - B|) to the contact normal (world, into the follower).

Undercut (refused by :func:`problems`): a roller larger than the pitch curve's radius of curvature on a
convex arc (0 < rho_p <= r_r), a cusp of a knife's pitch curve (rho_p = 0 where |P'| vanishes), or a flat
face's rho = d + d'' <= 0; and a flat face narrower than the contact's travel along it.

Analysis mode (``profile`` given, a closed polyline in the cam's frame): for each cam angle the translating
follower rests where it first touches the outline coming down its guide: a flat face at the support
distance max_k q_k . u_c, a roller's centre at max_k [q_k . u_c + sqrt(r_r^2 - (q_k . n_c - e)^2)] over the
vertices within r_r of its line, a knife at the outermost crossing of its line with the polygon's edges;
the lift on a grid of cam angles is then splined periodically (:func:`analytic.laws.table_law`) and its
derivatives are the spline's. An arm's roller or knife rests likewise at the highest arm angle where it first
touches the outline coming down (:func:`_rest_arm`); a flat-faced arm is not supported (refused).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from analytic import laws

MOTIONS = ("translating", "oscillating")
CONTACTS = ("knife", "roller", "flat")
DENSE = 3600
"""Samples of the cycle for the profile, the checks and the figures of merit (one per 0.1 deg)."""
ANALYSIS_GRID = 1440
"""Cam angles at which a given profile's lift is found before it is splined (one per 0.25 deg)."""


@dataclass(frozen=True)
class Setup:
    """A cam and its follower in SI units, everything :func:`lift` and :func:`build` need.

    ``pivot``: A (x, y) [m]; ``motion``, ``contact``, ``roller`` [m] (0 for a knife or flat face),
    ``face_width`` [m] or None, ``base_radius`` [m]; translating: ``direction`` gamma [rad] of the guide,
    ``offset`` e [m], ``origin`` (x, y) [m] the guide's ``through`` point (the block's s is measured from it);
    oscillating: ``arm_pivot`` B (x, y) [m] and ``arm`` [m]; ``law``: the lift over the cam angle
    (:class:`analytic.laws.Profile` or :class:`~analytic.laws.Table`), in m (translating) or rad (arm)."""

    pivot: tuple[float, float]
    motion: str
    contact: str
    roller: float
    face_width: float | None
    base_radius: float
    law: object
    direction: float = 0.0
    offset: float = 0.0
    origin: tuple[float, float] = (0.0, 0.0)
    arm_pivot: tuple[float, float] = (0.0, 0.0)
    arm: float = 0.0

    @property
    def u(self) -> tuple[float, float]:
        return math.cos(self.direction), math.sin(self.direction)

    @property
    def prime(self) -> float:
        """The prime circle's radius: base + roller."""
        return self.base_radius + (self.roller if self.contact == "roller" else 0.0)

    @property
    def d0(self) -> float:
        """Translating: the trace point's distance along the guide from A's foot at zero lift."""
        if self.contact == "flat":
            return self.base_radius
        return math.sqrt(self.prime ** 2 - self.offset ** 2)

    @property
    def psi0(self) -> float:
        """Oscillating: the arm's angle at zero lift (see the module docstring)."""
        (ax, ay), (bx, by) = self.pivot, self.arm_pivot
        dx, dy = ax - bx, ay - by
        D = math.hypot(dx, dy)
        R, a = self.prime, self.arm
        cosg = (a * a + D * D - R * R) / (2 * a * D)
        g = math.acos(max(-1.0, min(1.0, cosg)))
        base = math.atan2(dy, dx)
        # of the two arm angles base +- g, the one where turning the arm counter-clockwise moves F away from A
        for psi in (base - g, base + g):
            fx, fy = bx + a * math.cos(psi) - ax, by + a * math.sin(psi) - ay
            if fx * (-a * math.sin(psi)) + fy * (a * math.cos(psi)) > 0:
                return psi
        return base - g


def _rot(c, s, x, y):
    return c * x - s * y, s * x + c * y


@dataclass(frozen=True)
class Follow:
    """The follower at cam angles theta: F - A (rx, ry) with its first and second theta-derivatives (world,
    [m]), the direction of its motion at F (tx, ty unit), the lift (h, h', h'', h''') and, oscillating,
    the arm angle psi."""

    theta: np.ndarray
    r: tuple
    r1: tuple
    r2: tuple
    t: tuple
    h: tuple
    psi: np.ndarray | None = None


def follow(setup: Setup, theta) -> Follow:
    """The follower's place over the cam angles ``theta`` [rad] (exact rates from the lift's)."""
    theta = np.asarray(theta, dtype=float)
    h, h1, h2, h3 = setup.law.at(np.mod(theta, 2 * math.pi))
    if setup.motion == "translating":
        c, s = setup.u
        nx, ny = -s, c
        d = setup.d0 + h
        e = setup.offset
        r = (e * nx + d * c, e * ny + d * s)
        return Follow(theta, r, (h1 * c, h1 * s), (h2 * c, h2 * s), (np.full_like(h, c), np.full_like(h, s)),
                      (h, h1, h2, h3))
    psi = setup.psi0 + h
    a = setup.arm
    cw, sw = np.cos(psi), np.sin(psi)
    (ax, ay), (bx, by) = setup.pivot, setup.arm_pivot
    r = (bx - ax + a * cw, by - ay + a * sw)
    r1 = (-a * h1 * sw, a * h1 * cw)
    r2 = (-a * h2 * sw - a * h1 * h1 * cw, a * h2 * cw - a * h1 * h1 * sw)
    return Follow(theta, r, r1, r2, (-sw, cw), (h, h1, h2, h3), psi)


@dataclass(frozen=True)
class CamGeometry:
    """A cam's geometry over one turn (SI). ``theta`` [rad] ascending over [0, 2 pi); per sample: ``pitch``
    (n, 2) the trace point in the cam's frame [m]; ``contact_cam`` (n, 2) the contact point in the cam's
    frame; ``normal_cam`` (n, 2) the unit contact normal in the cam's frame (out of the cam);
    ``pressure_angle`` [rad]; ``rho`` [m] the profile's radius of curvature at the contact (< 0 concave);
    ``rho_pitch`` [m]; ``face_offset`` [m] (flat: the contact's distance along the face from its foot, to the
    guide's left; else zeros); and the setup. :attr:`profile` is the outline as a closed counter-clockwise
    polyline (the first point not repeated)."""

    setup: Setup
    theta: np.ndarray
    pitch: np.ndarray
    contact_cam: np.ndarray
    normal_cam: np.ndarray
    pressure_angle: np.ndarray
    rho: np.ndarray
    rho_pitch: np.ndarray
    face_offset: np.ndarray

    @property
    def profile(self) -> np.ndarray:
        """The cam's outline (x, y) [m] in its frame: closed, counter-clockwise, not repeating its first point."""
        return self.contact_cam[::-1].copy()

    @property
    def pressure_angle_max(self) -> float:
        return float(np.max(np.abs(self.pressure_angle)))

    @property
    def rho_min(self) -> float:
        """The smallest radius of curvature of the profile (the most negative where it is concave)."""
        return float(np.min(self.rho))

    @property
    def face_travel(self) -> float:
        """Flat: the width of face the contact sweeps [m] (max - min of :attr:`face_offset`); else 0."""
        return float(np.ptp(self.face_offset))

    @property
    def face_centre(self) -> float:
        """Flat: the middle of the contact's travel along the face [m], to the guide's left of the foot: where
        a face of ``face_width`` is centred, so that a face as wide as the travel (the least the check
        accepts) covers it; else 0."""
        return 0.5 * float(np.max(self.face_offset) + np.min(self.face_offset))


def at(setup: Setup, theta) -> dict:
    """Everything about the contact at cam angles ``theta`` [rad] (arrays): the follower (:func:`follow`),
    the pitch curve's P, P', P'' in the cam's frame, the contact point and normal (cam frame and world,
    relative to A), the pressure angle, rho, rho_pitch and the face offset."""
    f = follow(setup, theta)
    c, s = np.cos(f.theta), np.sin(f.theta)
    rx, ry = f.r
    r1x, r1y = f.r1
    r2x, r2y = f.r2
    # world-relative derivatives of R(-theta) r: R(-theta) (r' - J r), R(-theta) (r'' - 2 J r' - r)
    q1x, q1y = r1x + ry, r1y - rx
    q2x, q2y = r2x + 2 * r1y - rx, r2y - 2 * r1x - ry
    Px, Py = _rot(c, -s, rx, ry)
    P1x, P1y = _rot(c, -s, q1x, q1y)
    P2x, P2y = _rot(c, -s, q2x, q2y)
    speed = np.hypot(P1x, P1y)
    cross = P1x * P2y - P1y * P2x
    with np.errstate(divide="ignore", invalid="ignore"):
        rho_p = -speed ** 3 / cross
    zero = np.zeros_like(Px)
    if setup.contact == "flat":
        h, h1, h2, _ = f.h
        uc, us = setup.u
        d = setup.d0 + h
        kx, ky = d * uc + h1 * us, d * us - h1 * uc          # d u - d' n (world, from A)
        nwx, nwy = np.full_like(d, uc), np.full_like(d, us)
        rho = d + h2
        face = -h1 - setup.offset
    else:
        with np.errstate(divide="ignore", invalid="ignore"):
            nwx, nwy = -q1y / speed, q1x / speed               # J (r' - J r) / |.|: outward, world
        rr = setup.roller if setup.contact == "roller" else 0.0
        kx, ky = rx - rr * nwx, ry - rr * nwy
        rho = rho_p - rr
        face = zero
    tx, ty = f.t
    pa = np.arctan2(tx * nwy - ty * nwx, tx * nwx + ty * nwy)
    Kx, Ky = _rot(c, -s, kx, ky)
    Nx, Ny = _rot(c, -s, nwx, nwy)
    return {"follow": f, "P": (Px, Py), "P1": (P1x, P1y), "P2": (P2x, P2y), "contact_cam": (Kx, Ky),
            "normal_cam": (Nx, Ny), "contact": (kx, ky), "normal": (nwx, nwy), "pressure_angle": pa, "rho": rho,
            "rho_pitch": rho_p, "face_offset": face}


def build(setup: Setup, n: int = DENSE) -> CamGeometry:
    """The cam's geometry on ``n`` cam angles evenly over a turn."""
    theta = np.arange(n) * (2 * math.pi / n)
    g = at(setup, theta)
    return CamGeometry(setup, theta, np.column_stack(g["P"]), np.column_stack(g["contact_cam"]),
                       np.column_stack(g["normal_cam"]), g["pressure_angle"], g["rho"], g["rho_pitch"],
                       g["face_offset"])


def defects(geo: CamGeometry) -> tuple[np.ndarray, int | None, str]:
    """Where the profile cannot be made: a boolean per sample, the sample :func:`problems` names (None where
    there is none) and what it is: "cusp" (a flat face's profile turning back, rho <= 0, at its most negative;
    or the pitch curve stopping and turning, |P'| = 0, at its first sample), "undercut" (the roller larger than
    the pitch curve's radius of curvature, at its tightest) or ""."""
    st = geo.setup
    if st.contact == "flat":
        bad = geo.rho <= 0
        if not bad.any():
            return bad, None, ""
        return bad, int(np.flatnonzero(bad)[np.argmin(geo.rho[bad])]), "cusp"
    cusp = np.isnan(geo.rho_pitch)
    if cusp.any():
        return cusp, int(np.flatnonzero(cusp)[0]), "cusp"
    rr = st.roller if st.contact == "roller" else 0.0
    bad = (geo.rho_pitch > 0) & (geo.rho_pitch <= rr)
    if not bad.any():
        return bad, None, ""
    return bad, int(np.flatnonzero(bad)[np.argmin(geo.rho_pitch[bad])]), "undercut"


def problems(geo: CamGeometry, unit: tuple[float, str] = (1.0, "m")) -> str | None:
    """Why the cam cannot be made (one line, saying at which cam angle), or None: an undercut, a cusp
    (:func:`defects`), or a flat face narrower than the contact's travel. ``unit``: (metres per display unit,
    its name)."""
    st = geo.setup
    k = unit[0]
    # a given outline is the cam as made: its follower rests on it wherever (analysis mode); undercuts and
    # cusps are of a profile made from a law, and the spline of a polygon's lift has no curvature to judge
    _, i, what = defects(geo) if not isinstance(st.law, Lift) else (None, None, "")
    at = None if i is None else f"{math.degrees(geo.theta[i]):.4g}deg"
    if what == "cusp" and st.contact != "flat":
        return f"the pitch curve has a cusp at cam angle {at}; make the base radius larger or the rise gentler"
    if what == "cusp":
        return (f"the profile has a cusp (undercut) at cam angle {at}: radius of curvature "
                f"{geo.rho[i] / k:.4g} {unit[1]} <= 0; make base_radius at least {(st.base_radius - geo.rho[i]) / k:.4g} "
                f"{unit[1]}")
    if what == "undercut":
        rr = st.roller if st.contact == "roller" else 0.0
        return (f"the profile undercuts at cam angle {at}: the roller ({rr / k:.4g} {unit[1]}) is larger than the "
                f"pitch curve's radius of curvature there ({geo.rho_pitch[i] / k:.4g} {unit[1]}); use a smaller roller or "
                f"a larger base radius")
    if what == "" and not isinstance(st.law, Lift):
        crossing = _crossing(geo.contact_cam)
        if crossing is not None:                     # no undercut in the small, but the outline overlaps itself
            i = int(np.argmin(np.hypot(geo.contact_cam[:, 0] - crossing[0], geo.contact_cam[:, 1] - crossing[1])))
            return (f"the profile crosses itself (undercut) at cam angle {math.degrees(geo.theta[i]):.4g}deg; make the "
                    f"base radius larger or the rise gentler")
    if st.contact == "flat" and st.face_width is not None and st.face_width < geo.face_travel:
        return (f"field 'face_width': {st.face_width / k:.4g} {unit[1]} is narrower than the contact's travel "
                f"along the face, {geo.face_travel / k:.4g} {unit[1]}; make it at least that")
    return None


# ------------------------------------------------------------------------------ analysis from a profile
def polygon_lift(setup: Setup, outline, n: int = ANALYSIS_GRID) -> "Lift":
    """The lift a given outline (m, cam frame, closed polyline) imposes on a translating follower (see the
    module docstring), splined periodically over n cam angles. Raises ValueError (one line) where the
    follower's line misses the outline or the follower is an arm."""
    if setup.motion == "oscillating" and setup.contact == "flat":
        raise ValueError("a flat-faced arm is not supported; give a roller or a knife")
    q = np.asarray(outline, dtype=float)
    theta = np.arange(n + 1) * (2 * math.pi / n)
    if setup.motion == "translating" and setup.contact != "flat":
        d = np.concatenate([_rest_near(setup, q, theta[k:k + BAND]) for k in range(0, n + 1, BAND)])
    else:
        rows = max(1, CHUNK // max(len(q), 1))      # cam angles per block: a block's arrays stay ~CHUNK long
        rest = _rest if setup.motion == "translating" else _rest_arm
        d = np.concatenate([rest(setup, q, theta[k:k + rows]) for k in range(0, n + 1, rows)])
    if not np.all(np.isfinite(d)):
        i = int(np.flatnonzero(~np.isfinite(d))[0])
        what = "line" if setup.motion == "translating" else "arm's circle"
        raise ValueError(f"the follower's {what} misses the profile at cam angle {math.degrees(theta[i]):.4g}deg; "
                         f"check the guide or the arm and the profile's units")
    d[-1] = d[0]
    base = setup.d0 if setup.motion == "translating" else 0.0
    return Lift(laws.table_law(theta, d - base, None), float(d[0] - base))


@dataclass(frozen=True)
class Lift:
    """A lift found from a profile: a periodic spline (:class:`analytic.laws.Table`, which counts from its
    first row) and that row's lift [m]."""

    table: laws.Table
    start: float

    def at(self, theta):
        h, h1, h2, h3 = self.table.at(theta)
        return h + self.start, h1, h2, h3


CHUNK = 1 << 20
"""Cam angles times outline points per block of :func:`polygon_lift` (8 MB per array)."""


BAND = 16
"""Cam angles per block of a translating roller's or knife's search (:func:`_rest_near`)."""


def _rest_near(setup: Setup, q, theta):
    """:func:`_rest` for a roller or a knife on a block of cam angles, over the outline's corners and edges
    that can touch it: the follower's line turned to the block's middle angle tm, a point p of the outline
    is at most |p| |theta - tm| further across it at any angle of the block, and it can touch only within
    r_r of the line; corners and edges farther than that from the line at tm are left out (exactly)."""
    tm = 0.5 * (theta[0] + theta[-1])
    half = 0.5 * (theta[-1] - theta[0]) * (1.0 + 1e-9)
    uc0, us0 = setup.u
    c, s = math.cos(tm), math.sin(tm)
    nx, ny = -(-s * uc0 + c * us0), c * uc0 + s * us0          # n_c = J R(-tm) u
    rr = setup.roller if setup.contact == "roller" else 0.0
    across = q[:, 0] * nx + q[:, 1] * ny - setup.offset
    reach = rr + np.hypot(q[:, 0], q[:, 1]) * half + 1e-12 * (1.0 + np.abs(q).max())
    nxt = np.roll(np.arange(len(q)), -1)
    lo, hi = np.minimum(across, across[nxt]), np.maximum(across, across[nxt])
    edge_reach = np.maximum(reach, reach[nxt])
    edges = np.flatnonzero((lo <= edge_reach) & (hi >= -edge_reach))
    corners = np.flatnonzero(np.abs(across) <= reach)
    if not len(edges) and not len(corners):
        return np.full(len(theta), -np.inf)
    return _rest(setup, q[corners], theta, (q[edges], q[nxt[edges]]))


def _rest(setup: Setup, q, theta, edges=None):
    """Where a translating follower rests on the outline q (cam frame) at cam angles theta: d along the
    guide from A's foot (see :func:`polygon_lift`); ``edges``: (first ends, second ends) of the edges to
    try (default: the closed polygon q's), q then only the corners to try."""
    c, s = np.cos(theta)[:, None], np.sin(theta)[:, None]
    uc0, us0 = setup.u
    ucx, ucy = c * uc0 + s * us0, -s * uc0 + c * us0          # R(-theta) u
    ncx, ncy = -ucy, ucx
    e = setup.offset
    if setup.contact == "flat":
        d = np.max(q[None, :, 0] * ucx + q[None, :, 1] * ucy, axis=1)
    elif setup.contact == "roller":
        rr = setup.roller
        along = q[None, :, 0] * ucx + q[None, :, 1] * ucy
        across = q[None, :, 0] * ncx + q[None, :, 1] * ncy - e
        room = rr * rr - across * across
        d = np.max(np.where(room >= 0, along + np.sqrt(np.maximum(room, 0.0)), -np.inf), axis=1, initial=-np.inf)
        # on an edge's straight run: the centre on the edge's line moved out by r_r (outward: to the right of
        # a counter-clockwise edge), its foot within the edge
        a, b = edges if edges is not None else (q, np.roll(q, -1, axis=0))
        L = np.hypot(*(b - a).T)
        tx, ty = (b - a)[:, 0] / L, (b - a)[:, 1] / L
        mx, my = ty, -tx
        um = ucx * mx[None, :] + ucy * my[None, :]
        nm = ncx * mx[None, :] + ncy * my[None, :]
        am = a[:, 0] * mx + a[:, 1] * my
        with np.errstate(divide="ignore", invalid="ignore"):
            de = (rr + am[None, :] - e * nm) / um
        px, py = e * ncx + de * ucx - a[None, :, 0], e * ncy + de * ucy - a[None, :, 1]
        foot = px * tx[None, :] + py * ty[None, :]
        ok = (um > 0) & (foot >= -1e-9 * L[None, :]) & (foot <= L[None, :] * (1 + 1e-9))
        d = np.maximum(d, np.max(np.where(ok, de, -np.inf), axis=1, initial=-np.inf))
    else:
        a, b = edges if edges is not None else (q, np.roll(q, -1, axis=0))
        ya = a[None, :, 0] * ncx + a[None, :, 1] * ncy - e
        yb = b[None, :, 0] * ncx + b[None, :, 1] * ncy - e
        xa = a[None, :, 0] * ucx + a[None, :, 1] * ucy
        xb = b[None, :, 0] * ucx + b[None, :, 1] * ucy
        crosses = (ya <= 0) != (yb <= 0)
        with np.errstate(divide="ignore", invalid="ignore"):
            x = xa + (xb - xa) * ya / (ya - yb)
        d = np.max(np.where(crosses, x, -np.inf), axis=1, initial=-np.inf)
    return d


def _rest_arm(setup: Setup, q, theta):
    """Where an arm's roller (or knife, r_r = 0) rests on the outline q (cam frame) at cam angles theta: its
    angle from psi0 (rad). World, from A: the outline at R(theta) q, the arm's centre at b = B - A, the
    roller's centre C = b + arm w(psi). A vertex W is within r_r of C where cos(psi - delta) <= k / |D| (D = b
    - W = |D| (cos delta, sin delta), k = (r_r^2 - |D|^2 - arm^2) / (2 arm)); an edge's outer side (normal m
    at angle mu, through a) where cos(psi - mu) <= (r_r - (b - a) . m) / arm, the foot within the edge. The
    arm lowered (psi decreasing) first meets each such arc at its upper end, delta - acos(.) (mu - acos(.));
    it rests at the highest of those within half a turn of psi0."""
    c, s = np.cos(theta)[:, None], np.sin(theta)[:, None]
    bx, by = setup.arm_pivot[0] - setup.pivot[0], setup.arm_pivot[1] - setup.pivot[1]
    a, rr, psi0 = setup.arm, (setup.roller if setup.contact == "roller" else 0.0), setup.psi0

    def upper(angle, ratio):
        with np.errstate(invalid="ignore"):
            u = angle - np.arccos(ratio) - psi0
        u = u - 2 * np.pi * np.round(u / (2 * np.pi))
        return np.where((np.abs(ratio) <= 1) & (np.abs(u) < 0.5 * np.pi), u, -np.inf)

    wx, wy = c * q[None, :, 0] - s * q[None, :, 1], s * q[None, :, 0] + c * q[None, :, 1]
    Dx, Dy = bx - wx, by - wy
    D = np.hypot(Dx, Dy)
    with np.errstate(divide="ignore", invalid="ignore"):
        best = np.max(upper(np.arctan2(Dy, Dx), (rr * rr - D * D - a * a) / (2 * a * D)), axis=1)
    e0, e1 = q, np.roll(q, -1, axis=0)
    L = np.hypot(*(e1 - e0).T)
    tx, ty = (e1 - e0)[:, 0] / L, (e1 - e0)[:, 1] / L
    mx, my = c * ty[None, :] + s * tx[None, :], s * ty[None, :] - c * tx[None, :]   # R(theta) (ty, -tx)
    Tx, Ty = c * tx[None, :] - s * ty[None, :], s * tx[None, :] + c * ty[None, :]
    ax_, ay_ = wx, wy                                           # the edges' first ends, turned
    ratio = (rr - ((bx - ax_) * mx + (by - ay_) * my)) / a
    u = upper(np.arctan2(my, mx), ratio)
    psi = psi0 + np.where(np.isfinite(u), u, 0.0)
    foot = (bx + a * np.cos(psi) - ax_) * Tx + (by + a * np.sin(psi) - ay_) * Ty
    slack = 1e-9 * L[None, :]                                   # a tip on a vertex: on both edges' ends
    u = np.where(np.isfinite(u) & (foot >= -slack) & (foot <= L[None, :] + slack), u, -np.inf)
    return np.maximum(best, np.max(u, axis=1))


def read_outline(text: str, scale: float) -> np.ndarray:
    """The (x, y) rows of a profile's CSV text (header ``x,y``; file units times ``scale`` [m per unit]), as a
    counter-clockwise closed polyline without its first point repeated. Raises ValueError (one line)."""
    lines = [ln.strip() for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines or [h.strip().lower() for h in lines[0].split(",")] != ["x", "y"]:
        raise ValueError("give a header x,y and rows of the outline's points (file units, the cam's frame)")
    rows = []
    for k, ln in enumerate(lines[1:], 2):
        try:
            row = [float(v) for v in ln.split(",")]
        except ValueError:
            raise ValueError(f"line {k}: {ln[:40]!r} is not two numbers") from None
        if len(row) != 2 or not all(math.isfinite(v) for v in row):
            raise ValueError(f"line {k}: {ln[:40]!r} is not two finite numbers")
        rows.append(row)
    q = np.asarray(rows) * scale
    if len(q) > 1:                                   # a point repeated (the first at the end, or in a row)
        same = np.hypot(*(np.roll(q, -1, axis=0) - q).T) <= 1e-12 * max(np.abs(q).max(), 1e-300)
        q = q[~same] if not same.all() else q[:1]
    if len(q) < 8:
        raise ValueError(f"{len(q)} distinct points; an outline needs at least 8")
    area = 0.5 * float(np.sum(q[:, 0] * np.roll(q[:, 1], -1) - np.roll(q[:, 0], -1) * q[:, 1]))
    if area == 0:
        raise ValueError("the outline encloses no area")
    crossing = _crossing(q)
    if crossing is not None:
        x, y = crossing[0] / scale, crossing[1] / scale
        raise ValueError(f"the outline crosses itself near ({x:.6g}, {y:.6g}); give the points once round the "
                         f"cam, in order, without a loop")
    return q if area > 0 else q[::-1].copy()


def _crossing(q: np.ndarray) -> tuple[float, float] | None:
    """A point where the closed polyline ``q`` crosses or touches itself (GEOS's validity test of the polygon
    it bounds, O(n log n)), or None where it is simple. An outline whose every edge turns the same way about
    the origin, once round in all, is a polar graph r(angle) and cannot cross itself: it is passed without
    GEOS (and without importing it)."""
    a, b = q, np.roll(q, -1, axis=0)
    cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    turn = float(np.sum(np.arctan2(cross, np.sum(a * b, axis=1))))
    if (np.all(cross > 0) or np.all(cross < 0)) and abs(abs(turn) - 2 * math.pi) <= 1e-6:
        return None
    from shapely import Polygon
    from shapely.validation import explain_validity
    why = explain_validity(Polygon(q))
    if why == "Valid Geometry":
        return None
    m = re.search(r"\[\s*([-+0-9.eE]+)\s+([-+0-9.eE]+)", why)
    return (float(m[1]), float(m[2])) if m else (float(q[0, 0]), float(q[0, 1]))


__all__ = ["Setup", "Follow", "Lift", "CamGeometry", "follow", "at", "build", "problems", "polygon_lift", "read_outline",
           "elements", "geometry", "plate", "MOTIONS", "CONTACTS", "DENSE"]


# ------------------------------------------------------------------------------------- from a mechanism
def elements(mech) -> dict:
    """The mechanism's cams: {name: resolved element}, in solving order."""
    return {e["name"]: e for e in mech.geometry.elements if e["kind"] == "cam"}


def plate(element: dict, geo: CamGeometry | None = None, n: int = DENSE) -> np.ndarray:
    """The cam plate's outline (x, y) [m] in the cam's frame about its pivot, counter-clockwise: a given
    ``profile`` as the file gives it (analysis mode: the cam as made; the envelope made again from the spline
    of its lift carries the spline's ripple, and on a coarse polygon overlaps itself), else the profile made
    from the law (``geo``'s, or built on ``n`` cam angles)."""
    if element.get("profile"):
        return np.asarray(element["profile"], dtype=float)
    return (geo if geo is not None else build(element["setup"], n)).profile


def geometry(mech, element, n: int = DENSE) -> CamGeometry:
    """The geometry of a cam of ``mech`` (``element``: its name or its resolved element) on ``n`` cam angles:
    plain data (:class:`CamGeometry`; ``.setup`` holds the follower's kind, the guide or arm and the law)."""
    e = elements(mech)[element] if isinstance(element, str) else element
    return build(e["setup"], n)
