"""Assur groups with prismatic pairs (the ``group`` kind's ``slides``, analytic/solver/prismatic_group.py),
as PMKS files bring them: import, pose, motion against the independent Newton oracle, MuJoCo, bad input.

``tests/peers_examples/peas_*.txt`` are ours (the topologies of PMKS's examples with sliding blocks inside a
non-dyadic group, our numbers): a triad whose ternary link slides on a pinned link and carries a link sliding
on the crank (a placed guide); a triad with a slot link; a 6-link group with four prismatic pairs, one on
the ground, whose blocks must be chosen so that each link is the block of one pair. The peers' own four
files are checked too where the research collection is on this machine.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import analytic
import oracle_linkage as oracle
from analytic import ParameterError
from analytic.format import foreign
from sim import service
from test_joints_form import (EXAMPLES, JOINT_TOL, POSE_TOL, check_motion, form_and_mech, joint_residuals, pose_of,
                              range_near_start, size_of, solved_points)

PEERS = Path("/tmp/research/examples")
PEER_FILES = ["pmks/fivebarShouldRepeat.txt", "pmks/stevensonWithPeas.txt", "pmks/wackyDoubleFlierWithPeas.txt",
              "pmks_walkers_urls/walkers_10.txt"]
OURS = ["peas_triad.txt", "peas_slot_triad.txt", "peas_6link.txt"]
POS_TOL, RATE_TOL = 1e-12, 1e-9


def _against_oracle(m, q):
    """Worst position error / size and rate errors / their peak of the solver against the oracle, over the
    input values q (N,) at speed 1 and random accelerations."""
    n = len(q)
    rng = np.random.default_rng(7)
    Q, Qd, Qdd = q[:, None], np.ones((n, 1)), rng.uniform(-3, 3, (n, 1))
    sol = m.solve(Q, Qd, Qdd)
    assert sol.valid.all(), sol.first_failure()
    moving = [p for e in m.geometry.elements for p in e["places"]]
    guess = {p: (sol["x" + p] + 1e-4 * m.size, sol["y" + p] - 1e-4 * m.size) for p in moving}
    for name, (ln, p0, D) in oracle.axes(m.geometry).items():
        guess[name] = (sol["x" + p0] + D * np.cos(sol["phi" + ln]), sol["y" + p0] + D * np.sin(sol["phi" + ln]))
    pts, _ = oracle.solve(m.geometry, Q, Qd, Qdd, guess)
    assert sum(oracle.branch_violations(m.geometry, pts).values()) == 0
    pos = rate = 0.0
    for p in moving:
        x, y, vx, vy, ax, ay = pts[p]
        pos = max(pos, np.max(np.hypot(sol["x" + p] - x, sol["y" + p] - y)) / m.size)
        rate = max(rate, np.max(np.hypot(sol["vx" + p] - vx, sol["vy" + p] - vy)) / np.max(np.hypot(vx, vy)),
                   np.max(np.hypot(sol["ax" + p] - ax, sol["ay" + p] - ay)) / np.max(np.hypot(ax, ay)))
    for j, (s, ds, dds) in oracle.slides(m.geometry, pts).items():
        pos = max(pos, np.max(np.abs(sol["s" + j] - s)) / m.size)
        rate = max(rate, np.max(np.abs(sol["ds" + j] - ds)) / max(np.max(np.abs(ds)), 1e-9),
                   np.max(np.abs(sol["dds" + j] - dds)) / max(np.max(np.abs(dds)), 1e-9))
    return pos, rate


SLOW = pytest.mark.slow   # the 6-link group's scans cost 10-25 s each: the slow tier


@pytest.mark.parametrize("name", [pytest.param(n, marks=SLOW) if n == "peas_6link.txt" else n for n in OURS])
def test_groups_with_sliding_blocks_import_reproduce_the_pose_and_agree_with_the_oracle(name):
    form, m = form_and_mech(EXAMPLES / name)
    assert any(e["kind"] == "group" and e["slides"] for e in m.geometry.elements)
    check_motion(m, form)                  # the pose at the start (1e-9 of size), every joint along a range
    pos, rate = _against_oracle(m, range_near_start(m))
    assert pos <= POS_TOL and rate <= RATE_TOL, (pos, rate)


def test_each_block_names_one_prismatic_pair():
    # four pairs among the 6-link group's links BD, DEG, GHI, HR: HR slides on the ground and (as the PMKS
    # file has it) on GHI too; the matching makes GHI the block of that pair, DEG of GHI's, BD of DEG's
    _, m = form_and_mech(EXAMPLES / "peas_6link.txt")
    assert {"BD", "DEG", "GHI", "HR"} <= set(m.slides)
    kinds = {j.name: (j.a, j.b) for j in m.joints if j.kind == "prismatic"}
    assert kinds["HR"] == ("HR", "ground") or set(kinds["HR"]) == {"HR", "ground"}


@pytest.mark.parametrize("name, rng", [("peas_triad.txt", None), ("peas_slot_triad.txt", (-1.2, -0.2))])
def test_mujoco_agrees(name, rng):
    _, m = form_and_mech(EXAMPLES / name)
    _, c = service.compare(m, 1.0 if rng is None else 0.3, input_range=rng)
    assert c.passed, {k: v for k, v in c.errors.items() if not v["passed"]}


@pytest.mark.skipif(not PEERS.exists(), reason="the peers' example collection is not on this machine")
@pytest.mark.parametrize("name", PEER_FILES)
def test_the_peers_examples_with_such_groups_import_and_move(name):
    # the pose, and every joint over 0.3 rad either side of the start: fivebarShouldRepeat's group folds
    # 33 deg below its start (its singularity measure goes to 0 there), where the path stops (NaN)
    path = PEERS / name
    form = foreign.read(path)
    m = analytic.registry.Mechanism.from_definition(foreign.definition(path), {})
    size = size_of(form)
    at0 = solved_points(m, np.array([[m.inputs[0].motion.q0]]))
    for p, xy in pose_of(form).items():
        assert np.linalg.norm(at0[p][0] - xy) <= POSE_TOL * size, p
    pts = solved_points(m, m.inputs[0].motion.q0 + np.linspace(-0.3, 0.3, 61))
    assert all(np.all(np.isfinite(v)) for v in pts.values())
    assert joint_residuals(form, pts) <= JOINT_TOL


CRANK = """
format = "linkage/1"
[ground]
G1 = [0, 0]
[[inputs]]
kind = "crank"
pivot = "G1"
point = "P1"
length = 0.1
link = "1"
"""
GROUP = CRANK + """[[groups]]
kind = "point"
point = "P2"
on = "1"
at = [0.058, 0.043]
[[groups]]
kind = "group"
points = ["Q1", "Q3"]
links = {{ rod1 = ["P1", "Q1"], coupler = ["Q1", "Q3"], slot = ["P2"], blk = ["Q3"] }}
pose = {{ P1 = [0.1, 0], P2 = [0.058, 0.043], Q1 = [0.489, -0.076], Q3 = [0.492, 0.109] }}
slides = {slides}
"""


@pytest.mark.parametrize("slides, match", [
    ('{ slot = { guide = "coupler", point = "P2", angle = "130deg" } }', r"link blk has 1 point\(s\) and no slide"),
    ('{ slot = { guide = "coupler", point = "P2", angle = "130deg" }, blk = { guide = "ground", point = "Q3" }, '
     'rod1 = { guide = "ground", point = "P1" } }', r"not an Assur group: 14 equations for 12 unknowns"),
    ('{ slot = { guide = "coupler", point = "Q1", angle = "130deg" }, blk = { guide = "ground", point = "Q3" } }',
     r"the point Q1 of block slot is not on it"),
    ('{ slot = { guide = "slot", point = "P2" }, blk = { guide = "ground", point = "Q3" } }',
     r"guide slot of block slot is not another link of the group"),
    ('{ slot = { guide = "coupler", point = "P2", angle = "SING" }, blk = { guide = "ground", point = "Q3" } }',
     r"groups\[2\] \(points Q1, Q3\): .*the pose is singular for links rod1, coupler, slot, blk .*give another "
     r"pose or other links"),
])
def test_bad_groups_with_slides_are_one_line(slides, match):
    if "SING" in slides:              # the slot's angle where the group's Jacobian at the pose changes sign
        slides = slides.replace('"SING"', "1.3019243861362306")
    with pytest.raises((ParameterError, analytic.FileError)) as exc:
        analytic.from_text(GROUP.format(slides=slides), "bad.toml").solve([[0.0]])
    msg = str(exc.value)
    assert "\n" not in msg and __import__("re").search(match, msg), msg


SLIDER_CRANK = 'output = "Q"\n' + CRANK + """omega = "360deg"
[[groups]]
{group}
"""
AS_GROUP = """kind = "group"
points = ["Q"]
links = {{ rod = ["P1", "Q"], blk = ["Q"] }}
pose = {{ P1 = [0.1, 0], Q = [{qx!r}, {qy!r}] }}
slides = {{ blk = {{ guide = "ground", point = "Q", angle = "30deg" }} }}"""
AS_RRP = """kind = "RRP"
point = "Q"
from = "P1"
length = 0.2
guide = { through = [0, 0.15], angle = "30deg" }
offset = 0
links = ["rod", "blk"]
branch = 1"""


def test_the_singularity_measure_reads_like_a_dyads_transmission_sine():
    # a slider-crank (crank 0.1, rod 0.2, guide at 30 deg through (0, 0.15)) written twice: as the RRP kind,
    # whose measure is the sine of the rod's angle clear of the guide's normal (closed form), and as a group
    # with one sliding block, measured on the 3 L frame coordinates; the RRP's dead point lies at -14.5 deg
    from analytic.applications import figures
    t, d = np.array([0.0, 0.15]), np.array([np.cos(np.pi / 6), np.sin(np.pi / 6)])
    rel = t - np.array([0.1, 0.0])
    s = -d @ rel + np.sqrt((d @ rel) ** 2 - rel @ rel + 0.04)       # the pose: |Q - P1| = 0.2 on the guide
    qx, qy = (float(v) for v in t + s * d)
    mechs = [analytic.from_text(SLIDER_CRANK.format(group=g), "sc.toml") for g in (AS_GROUP.format(qx=qx, qy=qy), AS_RRP)]
    q = np.radians(np.array([-14.45, -14.0, -12.0, -5.0, 30.0, 120.0, 240.0]))
    group, rrp = (next(iter(figures.singularity(m, m.solve(q)).values())) for m in mechs)
    # same motion: the two solve the same linkage
    assert np.max(np.abs(mechs[0].solve(q)["xQ"] - mechs[1].solve(q)["xQ"])) < 1e-12
    # calibrated within 0.9-1.2 of the sine everywhere (2 sqrt 2 fits the limit at the fold; the 3 L
    # coordinates' other singular values shift it by up to 13 % elsewhere), and vanishing with it
    assert np.all((group / rrp > 0.9) & (group / rrp < 1.2)), group / rrp
    assert rrp[0] < 0.05                                            # the first sample is near the fold


def _held_range_is_where_the_start_branch_goes(m):
    # the range holding the start, against paths solved here from the start in 0.1 deg steps (the branch is
    # carried by continuity along a path: a value's assembly depends on the path to it): up to 1e-6 rad
    # inside either end every value assembles (past an end the solver's Newton and jump checks may give up
    # anywhere up to the fold itself, ~0.1 deg on: no check there)
    from analytic.applications import figures
    q0 = m.inputs[0].motion.q0
    turn = 2 * np.pi
    held = [(a + turn * k, b + turn * k) for a, b in figures.assembly_ranges(m) for k in (-1, 0, 1)
            if a + turn * k <= q0 <= b + turn * k]
    assert len(held) == 1
    a, b = held[0]
    for end in (a, b):
        n = int(abs(end - q0) / np.radians(0.1)) + 2
        assert m.solve(np.linspace(q0, end - 1e-6 * np.sign(end - q0), n), outputs=()).valid.all()
    return a, b


@pytest.mark.parametrize("name", ["peas_slot_triad.txt", "moving_guide.txt",
                                  pytest.param("peas_6link.txt", marks=SLOW)])
def test_the_range_holding_the_start_ends_where_the_branch_from_the_start_does(name):
    _held_range_is_where_the_start_branch_goes(form_and_mech(EXAMPLES / name)[1])


@pytest.mark.skipif(not PEERS.exists(), reason="the peers' example collection is not on this machine")
def test_a_scan_that_rejoins_after_a_gap_does_not_extend_the_start_range():
    # PMKS's fivebarShouldRepeat: the forward scan from the start (-167.34 deg) fails at -91.8 deg, assembles
    # again at 149.6 deg on another assembly and, near -200.06 deg where the start's branch ends, carried on
    # into it: the range holding the start read 149.56 deg..268.05 deg; it is 160.06 deg..268.15 deg
    m = analytic.registry.Mechanism.from_definition(foreign.definition(PEERS / "pmks/fivebarShouldRepeat.txt"), {})
    a, b = _held_range_is_where_the_start_branch_goes(m)
    assert np.degrees(a) % 360 == pytest.approx(160.057, abs=1e-3)
