"""The solver against the independent Newton oracle (``oracle_linkage``) over one period of a mechanism's
inputs: shared by the library's tests and the element kinds' conformance suite.

The general solver and the oracle share only the file's resolved numbers: the worst error of every point's
position, velocity and acceleration, every prismatic pair's slide and every link's angular rates, each
relative to what its tolerance is relative to.
"""

from __future__ import annotations

import math
import zlib
from fractions import Fraction

import numpy as np

import oracle_linkage as oracle
from analytic import kinds

SAMPLES = 180

# Tolerances (each bounds one error; all relative, as stated)
POS_TOL = 1e-12          # positions, / size: rounding of a closed form vs a Newton solution converged to rounding
RATE_TOL = 1e-9          # velocities, accelerations, slides' and links' rates, / their peak: rounding x 1/sin(mu >= 8 deg)
NEWTON_STEP_TOL = 1e-14  # Newton's last step, / size: the oracle has converged (quadratically) to rounding level
GUESS = 1e-3             # not a tolerance: Newton starts this fraction of the size off the solver's answer
FD_STEPS = 4000          # finite-difference step h = period / FD_STEPS
FD_TOL = 1e-7            # five-point differences, / peak rate: truncation (omega h)^4/30 x harmonics (Jansen 5e-9) + eps size/h
MIN_MU_DEG = 8.0         # dead-centre clearance of a shipped file: Jansen's holy numbers reach 8.6 deg at D, others >= 23
MIN_SLIDE = 0.05         # |s| / size of a slotted link (its rates grow like 1/s): Whitworth's block comes to 0.1
MAX_DENOMINATOR = 64     # two cranks: speed ratio taken as p/q with q <= 64 to find the common period


# ------------------------------------------------------------------------------------------ helpers
def rng_for(name: str, salt: int = 0) -> np.random.Generator:
    return np.random.default_rng(zlib.crc32(name.encode()) + salt)


def _laws(m):
    """Each input's (kind name, q0, rate) as written in the file."""
    out = []
    for e in m.geometry.elements:
        kind = kinds.get(e["kind"])
        if kind.section == "inputs":
            q0, rate, _ = kind.motion_fields
            out.append((kind.name, e[q0], e[rate]))
    return out


def period(m) -> float:
    """The time after which every input is back where it started (a slider: one second)."""
    laws = _laws(m)
    if any(not kinds.get(k).angular for k, _, _ in laws):      # a slider or an actuator
        return 1.0
    turns = [2 * math.pi / abs(w) for _, _, w in laws]
    if len(turns) == 1:
        return turns[0]
    ratio = Fraction(turns[1] / turns[0]).limit_denominator(MAX_DENOMINATOR)  # T1 / T0 = p / q
    return ratio.denominator * turns[1]  # q T1 = p T0


def drive(m, n: int, rng: np.random.Generator | None = None, endpoint: bool = False):
    """Inputs over one period at n samples: (t, q, qd, qdd) with q, qd, qdd of shape (n, n_inputs);
    random accelerations (up to 3 rate^2 / rad, or 3 v^2 / size for a slider) when ``rng`` is given."""
    T = period(m)
    t = np.linspace(0.0, T, n, endpoint=endpoint)
    laws = _laws(m)
    q = np.stack([q0 + w * t for _, q0, w in laws], -1)
    qd = np.stack([np.full(n, w) for _, _, w in laws], -1)
    qdd = np.zeros_like(q)
    if rng is not None:
        qdd = np.stack([rng.uniform(-3, 3, n) * w * w / (1.0 if kinds.get(k).angular else m.size) for k, _, w in laws], -1)
    return t, q, qd, qdd


def compare(m, rng, geometry=None, qdd_scale=1.0) -> dict[str, float]:
    """Worst errors of the solver against the oracle (run on ``geometry``, default the mechanism's own,
    with the input accelerations times ``qdd_scale``), each relative to what its tolerance is relative to."""
    geometry = geometry or m.geometry
    _, q, qd, qdd = drive(m, SAMPLES, rng)
    sol = m.solve(q, qd, qdd)
    assert sol.valid.all(), f"{m.name}: does not assemble at {sol.first_failure()}"
    size = m.size
    moving = [p for e in m.geometry.elements for p in e["places"]]
    guess = {p: (sol["x" + p] + rng.uniform(-1, 1, SAMPLES) * GUESS * size,
                 sol["y" + p] + rng.uniform(-1, 1, SAMPLES) * GUESS * size) for p in moving}
    for name, (ln, p0, D) in oracle.axes(geometry).items():      # a group link's axis point (slides)
        guess[name] = (sol["x" + p0] + D * np.cos(sol["phi" + ln]) + rng.uniform(-1, 1, SAMPLES) * GUESS * size,
                       sol["y" + p0] + D * np.sin(sol["phi" + ln]) + rng.uniform(-1, 1, SAMPLES) * GUESS * size)
    pts, step = oracle.solve(geometry, q, qd, qdd * qdd_scale, guess)
    worst = {"newton_step": step / size, "branch": sum(oracle.branch_violations(geometry, pts).values())}
    pos = vel = acc = 0.0
    for p in m.points:
        x, y, vx, vy, ax, ay = pts[p]
        pos = max(pos, np.max(np.hypot(sol["x" + p] - x, sol["y" + p] - y)) / size)
        if p in moving:
            vpeak, apeak = np.max(np.hypot(vx, vy)), np.max(np.hypot(ax, ay))
            vel = max(vel, np.max(np.hypot(sol["vx" + p] - vx, sol["vy" + p] - vy)) / vpeak)
            acc = max(acc, np.max(np.hypot(sol["ax" + p] - ax, sol["ay" + p] - ay)) / apeak)
    worst.update(position=pos, velocity=vel, acceleration=acc)
    slide = 0.0
    slides = oracle.slides(geometry, pts)       # a slide that does not move: error / 1e-3 of the fastest slide's
    dspeak = max((np.max(np.abs(ds)) for _, ds, _ in slides.values()), default=0.0)
    ddspeak = max((np.max(np.abs(dds)) for _, _, dds in slides.values()), default=0.0)
    for j, (s, ds, dds) in slides.items():
        slide = max(slide, np.max(np.abs(sol["s" + j] - s)) / size,
                    np.max(np.abs(sol["ds" + j] - ds)) / max(np.max(np.abs(ds)), 1e-3 * dspeak, 1e-300),
                    np.max(np.abs(sol["dds" + j] - dds)) / max(np.max(np.abs(dds)), 1e-3 * ddspeak, 1e-300))
    worst["slide"] = slide
    rates = oracle.link_rates(geometry, pts)     # a link that does not turn: error / 1e-3 of the fastest link's
    wpeak = max(np.max(np.abs(w)) for w, _ in rates.values())
    apeak = max(np.max(np.abs(a)) for _, a in rates.values())
    rate = 0.0
    for ln, (w, a) in rates.items():
        rate = max(rate, np.max(np.abs(sol["omega" + ln] - w)) / max(np.max(np.abs(w)), 1e-3 * wpeak),
                   np.max(np.abs(sol["alpha" + ln] - a)) / max(np.max(np.abs(a)), 1e-3 * apeak))
    worst["link_rates"] = rate
    return worst


def assert_agree(name, worst):
    assert worst["newton_step"] <= NEWTON_STEP_TOL, (name, worst)
    assert worst["branch"] == 0, (name, worst)
    assert worst["position"] <= POS_TOL, (name, worst)
    assert worst["slide"] <= RATE_TOL, (name, worst)        # s relative to size, rates to their peaks
    assert worst["velocity"] <= RATE_TOL, (name, worst)
    assert worst["acceleration"] <= RATE_TOL, (name, worst)
    assert worst["link_rates"] <= RATE_TOL, (name, worst)


def skip_without_cam_contact(mech) -> None:
    """Skip a MuJoCo check of a mechanism with a cam while this tree lacks the cam's MuJoCo contact
    (``sim/model/cam_contact.py``, built apart): the cam's model refuses to build without it."""
    import importlib
    import importlib.util

    import pytest
    if any(e["kind"] == "cam" for e in mech.geometry.elements) and (
            importlib.util.find_spec("sim.model.cam_contact") is None
            or not importlib.import_module("sim.model.cam_contact").IN_MECHANISMS):
        pytest.skip("a cam's MuJoCo contact (sim/model/cam_contact.py) is not yet wired into a mechanism's model")
