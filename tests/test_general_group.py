"""A numerically solved Assur group (analytic/solver/general_group.py, the kind ``group``) against oracles
that share nothing with it.

The engine's group: a class III triad (a ternary link D E F with three binary links pinned at A, O1, O2), the
group a Stephenson six-bar leaves when its crank is the link that makes the rest indecomposable into dyads.
The oracle solves the six distance equations |D-A|, |D-E|, |E-F|, |D-F|, |E-O1|, |F-O2| (written from the
geometry, not from the solver's link-frame equations) with scipy's fsolve sample by sample, and its rates are
finite differences of it along the crank angle. The kind's tests use the whole-mechanism Newton oracle
(tests/oracle_linkage.py), the closed-form RRR, np.linalg and hand-written structure checks.
"""

import math
import re
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import fsolve

import analytic
import oracle_linkage
from agreement import GUESS, POS_TOL
from analytic import ParameterError, kinds
from analytic.applications import figures
from analytic.format import linkfile
from analytic.kinds.group import assur_class
from analytic.solver import batch
from analytic.solver import general_group as gg
from analytic.solver.general_group import make_group, solve_group
from analytic.kinds.base import line, on_frame
from analytic.kinds.rrr import rrr as _rrr

import cli_runner  # the command in this process (tests/cli_runner.py)


def _point(P, Q, u, v):
    """The closed-form rigid point at (u, v) in the frame of P -> Q."""
    return on_frame(*line(P, Q), u, v)

Q0 = 0.5
R = 1.0
O1, O2 = np.array([4.0, 3.5]), np.array([3.5, -0.5])
POSE = dict(A=(R * np.cos(Q0), R * np.sin(Q0)), O1=tuple(O1), O2=tuple(O2), D=(1.5, 2.0), E=(3.0, 2.5), F=(2.6, 1.2))
LINKS = {"2": ("A", "D"), "T": ("D", "E", "F"), "4": ("O1", "E"), "5": ("O2", "F")}
PAIRS = [("A", "D"), ("D", "E"), ("E", "F"), ("D", "F"), ("O1", "E"), ("O2", "F")]
LEN = {p: float(np.hypot(*np.subtract(POSE[p[0]], POSE[p[1]]))) for p in PAIRS}
QD, QDD = 2.0, 0.5                  # crank speed [rad/s] and acceleration [rad/s^2] at every sample
Q = Q0 + np.linspace(0.0, 0.8, 161)  # within the assembly range of both branches (it locks near Q0 + 0.96)


def _crank(q):
    return np.array([R * np.cos(q), R * np.sin(q)])


def _eqs(z, q):
    pts = dict(A=_crank(q), O1=O1, O2=O2, D=z[0:2], E=z[2:4], F=z[4:6])
    return [np.sum((pts[a] - pts[b]) ** 2) - LEN[(a, b)] ** 2 for a, b in PAIRS]


def _oracle(q, z0):
    """fsolve per sample, each from the previous solution: (len(q), 6) as D, E, F."""
    out, z = [], np.asarray(z0, float)
    for qq in np.atleast_1d(q):
        z, _, ier, msg = fsolve(_eqs, z, args=(qq,), full_output=True, xtol=1e-15)
        assert np.max(np.abs(_eqs(z, qq))) < 1e-12, msg  # the oracle itself must have converged
        out.append(z)
    return np.array(out)


def _cross(u, v):
    return u[0] * v[1] - u[1] * v[0]


def _other_pose():
    """The triad's second assembly at Q0 (same ternary link, not mirrored), from seeded starts."""
    rng = np.random.default_rng(7)
    z1 = np.r_[POSE["D"], POSE["E"], POSE["F"]]
    side = np.sign(_cross(z1[2:4] - z1[0:2], z1[4:6] - z1[0:2]))
    for _ in range(200):
        z, _, ier, _ = fsolve(_eqs, rng.uniform(-3, 7, 6), args=(Q0,), full_output=True, xtol=1e-15)
        if (ier == 1 and np.max(np.abs(_eqs(z, Q0))) < 1e-12 and np.max(np.abs(z - z1)) > 0.5
                and np.sign(_cross(z[2:4] - z[0:2], z[4:6] - z[0:2])) == side):
            return z
    raise AssertionError("no second assembly found")


def _known(q):
    c, s = np.cos(q), np.sin(q)
    A = (R * c, R * s, -R * s * QD, R * c * QD, -R * s * QDD - R * c * QD ** 2, R * c * QDD - R * s * QD ** 2)
    return dict(A=A, O1=(O1[0], O1[1], 0, 0, 0, 0), O2=(O2[0], O2[1], 0, 0, 0, 0))


def _group(z):
    pose = dict(POSE, D=tuple(z[0:2]), E=tuple(z[2:4]), F=tuple(z[4:6]))
    return make_group(LINKS, ("A", "O1", "O2"), ("D", "E", "F"), pose, where="triad")


BRANCHES = {"pose": np.r_[POSE["D"], POSE["E"], POSE["F"]], "other": None}


@pytest.fixture(scope="module", params=["pose", "other"])
def branch_case(request):
    z = BRANCHES["pose"] if request.param == "pose" else _other_pose()
    g = _group(z)
    sol = solve_group(g, _known(Q))   # 40 < 161 samples: the batched path is exercised
    return z, g, sol


def _xyz(sol, k):
    return np.stack([sol.points[p][k] for p in "DEF"] + [sol.points[p][k + 1] for p in "DEF"], axis=1)[
        :, [0, 3, 1, 4, 2, 5]]


def test_positions_match_the_oracle_on_both_branches(branch_case):
    z, g, sol = branch_case
    assert sol.assembled.all()
    ref = _oracle(Q, z)
    # 1e-12 of size: the oracle and Newton both converge to rounding (about 1e-15 of size)
    assert np.max(np.abs(_xyz(sol, 0) - ref)) <= 1e-12 * g.size


def test_the_two_branches_differ_and_are_reported():
    g1, g2 = _group(BRANCHES["pose"]), _group(_other_pose())
    assert g1.branch == -g2.branch
    s2 = solve_group(g2, _known(Q))
    assert s2.branch == g2.branch
    assert np.min(np.abs(_xyz(s2, 0) - _oracle(Q, BRANCHES["pose"])).max(axis=1)) > 0.1


def test_rates_match_finite_differences_of_the_oracle(branch_case):
    z, g, sol = branch_case
    start = _oracle(Q[:1], z)[0]

    def stencils(step):
        """Five-point (4th-order) first and second derivatives of the oracle along the crank angle."""
        X = np.stack([_oracle(Q + kk * step, start) for kk in range(-2, 3)])
        d1 = (X[0] - 8 * X[1] + 8 * X[3] - X[4]) / (12 * step)
        d2 = (-X[0] + 16 * X[1] - 30 * X[2] + 16 * X[3] - X[4]) / (12 * step ** 2)
        return d1, d2

    h = 2e-3                                  # crank-angle step [rad]
    (a1, a2), (b1, b2), (c1, c2) = stencils(h), stencils(2 * h), stencils(4 * h)
    # Richardson: (16 D(h) - D(2h)) / 15 cancels the h^4 term, leaving O(h^6) truncation
    r1, r2 = (16 * a1 - b1) / 15, (16 * a2 - b2) / 15
    s1, s2 = (16 * b1 - c1) / 15, (16 * b2 - c2) / 15
    # the same at 2h has 64x the truncation: |r - s| / 63 bounds the truncation at h; under 1e-10 of
    # peak it leaves room for the rounding, eps * size / h^2 ~ 3e-10 of peak for the second derivative
    assert np.max(np.abs(r1 - s1)) / 63 <= 1e-10 * np.max(np.abs(r1))
    assert np.max(np.abs(r2 - s2)) / 63 <= 1e-10 * np.max(np.abs(r2))
    v_ref = r1 * QD
    a_ref = r2 * QD ** 2 + r1 * QDD
    v, a = _xyz(sol, 2), _xyz(sol, 4)
    # 1e-9 of peak: the stencils' truncation (bounded above) plus their rounding (~3e-10 of peak)
    assert np.max(np.abs(v - v_ref)) <= 1e-9 * np.max(np.abs(v_ref))
    assert np.max(np.abs(a - a_ref)) <= 1e-9 * np.max(np.abs(a_ref))


def test_link_rates_match_finite_differences_of_the_solved_angle(branch_case):
    z, g, sol = branch_case
    c, s, w, al = sol.links["T"]

    def phi(dq):
        so = solve_group(g, _known(Q + dq))
        D, E = so.points["D"], so.points["E"]
        return np.arctan2(E[1] - D[1], E[0] - D[0])

    dw, da = 1e-5, 1e-4    # crank-angle steps [rad] for the first and second differences
    d1 = (phi(dw) - phi(-dw)) / (2 * dw)
    # 1e-8 of peak: truncation dw^2 / 6 * |third derivative| ~ 1e-11 and rounding eps / dw ~ 1e-11
    assert np.max(np.abs(w - d1 * QD)) <= 1e-8 * np.max(np.abs(w))
    d1a = (phi(da) - phi(-da)) / (2 * da)
    d2 = (phi(da) - 2 * phi(0.0) + phi(-da)) / da ** 2
    # 1e-6 of peak: rounding 4 eps / da^2 ~ 1e-7 of the angle's second derivative dominates
    assert np.max(np.abs(al - (d2 * QD ** 2 + d1a * QDD))) <= 1e-6 * np.max(np.abs(al))
    np.testing.assert_allclose(np.arctan2(s, c), phi(0.0), rtol=0, atol=1e-14)  # the same angle, to rounding


@pytest.mark.parametrize("branch", [1, -1])
def test_a_dyad_as_a_general_group_equals_the_closed_form_rrr(branch):
    t = np.linspace(0.0, 2 * np.pi, 300)
    P = (np.cos(t), np.sin(t), -np.sin(t) * 3, np.cos(t) * 3, -np.cos(t) * 9, -np.sin(t) * 9)
    Q_ = (np.full_like(t, 3.0), np.zeros_like(t), 0 * t, 0 * t, 0 * t, 0 * t)
    a, b = 2.5, 2.0
    C, links, _ = _rrr(P, Q_, a, b, branch)
    pose = dict(P=(P[0][0], P[1][0]), Q=(3.0, 0.0), C=(C[0][0], C[1][0]))
    g = make_group({"2": ("P", "C"), "3": ("Q", "C")}, ("P", "Q"), ("C",), pose)
    sol = solve_group(g, dict(P=P, Q=Q_))
    assert sol.assembled.all()
    for k in range(6):
        scale = g.size if k < 2 else np.max(np.abs(C[k]))   # size, or the closed form's peak rate
        # 1e-13 of scale: both are exact up to rounding of O(10) operations
        assert np.max(np.abs(sol.points["C"][k] - C[k])) <= 1e-13 * scale, k
    for k in range(4):
        assert np.max(np.abs(sol.links["2"][k] - links[0][k])) <= 1e-12 * (1, 1, 10, 100)[k]


def test_samples_where_the_triad_cannot_assemble_are_flagged():
    q = Q0 + np.linspace(0.0, 2 * np.pi, 400)     # a full turn: the triad locks near Q0 + 0.96
    sol = solve_group(_group(BRANCHES["pose"]), _known(q))
    assert sol.assembled[:50].all() and not sol.assembled.all()
    bad = ~sol.assembled
    assert np.isnan(sol.points["D"][0][bad]).all() and np.isnan(sol.points["F"][5][bad]).all()
    # the oracle confirms the first flagged sample's neighbourhood is at or past the lock
    first = np.flatnonzero(bad)[0]
    assert q[first] > Q0 + 0.9


def test_bad_groups_are_refused_with_one_line():
    with pytest.raises(ParameterError, match="equations"):
        make_group({"2": ("A", "D"), "T": ("D", "E", "F"), "4": ("O1", "E")}, ("A", "O1"), ("D", "E", "F"),
                   POSE)
    with pytest.raises(ParameterError, match="pose has no position"):
        make_group(LINKS, ("A", "O1", "O2"), ("D", "E", "F"), {k: v for k, v in POSE.items() if k != "F"})
    with pytest.raises(ParameterError, match="singular"):  # a dyad pose with C on the line P -> Q
        make_group({"2": ("P", "C"), "3": ("Q", "C")}, ("P", "Q"), ("C",), dict(P=(0, 0), Q=(3, 0), C=(1, 0)))


def test_a_long_run_through_the_middle_level_matches_the_oracle():
    q = Q0 + np.linspace(0.0, 0.8, 20001)       # 20001 > 64 * 40 samples: the batched middle level runs
    g = _group(BRANCHES["pose"])
    sol = solve_group(g, _known(q))
    assert sol.assembled.all()
    pick = np.arange(0, len(q), 997)
    ref = _oracle(q[pick], BRANCHES["pose"])
    got = np.stack([sol.points[p][k][pick] for p in "DEF" for k in (0, 1)], axis=1)
    # 1e-12 of size: both converge to rounding (about 1e-15 of size)
    assert np.max(np.abs(got - ref)) <= 1e-12 * g.size


def test_a_motion_solved_in_two_blocks_continues_from_the_first_blocks_end():
    g = _group(BRANCHES["pose"])
    whole = solve_group(g, _known(Q))
    first = solve_group(g, _known(Q[:80]))
    end = {p: (first.points[p][0][-1], first.points[p][1][-1]) for p in "DEF"}
    second = solve_group(g, _known(Q[79:]), start=end)
    for p in "DEF":
        for k in range(6):
            # 1e-12 of size (and of peak rates): two Newton runs to rounding from different starts
            scale = g.size if k < 2 else np.max(np.abs(whole.points[p][k]))
            assert np.max(np.abs(second.points[p][k] - whole.points[p][k][79:])) <= 1e-12 * scale


@pytest.mark.parametrize("branch", [1, -1])
def test_a_coupler_point_on_a_dyad_link_equals_the_closed_form_point(branch):
    """A ternary link (P, C, X) pinned at a known point: its rigid-frame rows see the known point's rates."""
    t = np.linspace(0.0, 2 * np.pi, 300)
    P = (np.cos(t), np.sin(t), -np.sin(t) * 3, np.cos(t) * 3, -np.cos(t) * 9 - np.sin(t), -np.sin(t) * 9 + np.cos(t))
    Q_ = (np.full_like(t, 3.0), np.zeros_like(t), 0 * t, 0 * t, 0 * t, 0 * t)
    C, _, _ = _rrr(P, Q_, 2.5, 2.0, branch)
    u, v = 1.2, -0.7                                   # X in the frame of P -> C [m]
    X = _point(P, C, u, v)
    pose = dict(P=(P[0][0], P[1][0]), Q=(3.0, 0.0), C=(C[0][0], C[1][0]), X=(X[0][0], X[1][0]))
    g = make_group({"2": ("P", "C", "X"), "3": ("Q", "C")}, ("P", "Q"), ("C", "X"), pose)
    sol = solve_group(g, dict(P=P, Q=Q_))
    assert sol.assembled.all()
    for k in range(6):
        scale = g.size if k < 2 else np.max(np.abs(X[k]))   # size, or the closed form's peak rate
        # 1e-13 of scale: both are exact up to rounding of O(10) operations
        assert np.max(np.abs(sol.points["X"][k] - X[k])) <= 1e-13 * scale, k


def test_samples_off_the_continuous_path_are_flagged_not_solved_on_some_branch():
    # a dyad whose outer point Q teleports between two coarse nodes: Newton still converges there, but far
    # from the path interpolated between the nodes (where Q is the same), which the branch cannot vouch for
    qx = np.r_[3.0, np.full(9, 0.5), 3.0]
    qy = np.r_[0.0, np.full(9, 4.0), 0.0]
    z = np.zeros(11)
    g = make_group({"2": ("P", "C"), "3": ("Q", "C")}, ("P", "Q"), ("C",), dict(P=(0, 0), Q=(3, 0), C=(1.5, 2.0)))
    sol = solve_group(g, dict(P=(z, z, z, z, z, z), Q=(qx, qy, z, z, z, z)))
    assert sol.assembled[[0, -1]].all() and not sol.assembled[1:-1].any()
    assert np.isnan(sol.points["C"][0][1:-1]).all()


# ------------------------------------------------------------------------------------ the kind "group"
KINDS = Path(__file__).resolve().parent / "kinds"

# The triad above as a file: crank A about the origin from 0.5 rad; it locks near 0.5 + 0.96 rad.
TRIAD = """
format = "linkage/1"
[ground]
O = [0, 0]
O1 = [4.0, 3.5]
O2 = [3.5, -0.5]
[[inputs]]
kind = "crank"
pivot = "O"
point = "A"
length = 1.0
link = "1"
phi0 = 0.5
omega = 2.0
[[groups]]
kind = "group"
points = ["D", "E", "F"]
links = { 2 = ["A", "D"], T = ["D", "E", "F"], 4 = ["O1", "E"], 5 = ["O2", "F"] }
pose = { A = ["cos(0.5)", "sin(0.5)"], O1 = [4.0, 3.5], O2 = [3.5, -0.5], D = [1.5, 2.0], E = [3.0, 2.5], F = [2.6, 1.2] }
"""


def _oracle_at(m, q, guess_from):
    """The Newton oracle (tests/oracle_linkage.py) at inputs q (N,), started GUESS of the size off
    ``guess_from`` (a Solution at the same inputs); returns its points."""
    rng = np.random.default_rng(3)
    n = len(q)
    moving = [p for e in m.geometry.elements for p in e["places"]]
    guess = {p: (guess_from["x" + p] + rng.uniform(-1, 1, n) * GUESS * m.size,
                 guess_from["y" + p] + rng.uniform(-1, 1, n) * GUESS * m.size) for p in moving}
    zero = np.zeros((n, 1))
    pts, step = oracle_linkage.solve(m.geometry, np.asarray(q, float)[:, None], zero + 1.0, zero, guess)
    assert step <= 1e-14 * m.size          # the oracle converged (quadratically) to rounding
    assert sum(oracle_linkage.branch_violations(m.geometry, pts).values()) == 0
    return pts


def _worst_position(m, sol, pts):
    return max(np.max(np.hypot(sol["x" + p] - pts[p][0], sol["y" + p] - pts[p][1])) for p in m.points) / m.size


@pytest.mark.parametrize("name", ["stephenson_ii", "double_butterfly"])
def test_a_long_run_continues_across_the_solver_blocks(name, monkeypatch):
    """20000 samples over three turns: Mechanism.solve works in blocks of 8192 samples and the group carries its
    solution from one block to the next; every sample agrees with the oracle."""
    monkeypatch.setenv("LINKAGE_JIT", "0")
    m = analytic.load(name)
    q = m.inputs[0].motion.q0 + np.linspace(0.0, 6 * np.pi, 20000)
    sol = m.solve(q, 1.0)
    assert sol.valid.all(), sol.first_failure()
    pick = np.r_[np.arange(0, 20000, 997), 8191, 8192, 16383, 16384]
    sub = m.solve(q[pick], 1.0)                      # the same samples as a path of their own
    pts = _oracle_at(m, q[pick], sub)
    assert _worst_position(m, sub, pts) <= POS_TOL
    for p in m.points:                                # the long run's samples are those
        # 1e-12 of size: two Newton runs to rounding from different starts
        assert np.max(np.abs(sol["x" + p][pick] - sub["x" + p])) <= 1e-12 * m.size


@pytest.mark.parametrize("path", ["group.toml", "group__other.toml"])
def test_a_solve_away_from_the_pose_follows_the_inputs_there(path):
    """One sample 200 deg past the start (the lead-in: the inputs followed from their start values), and a
    path of 6 samples per turn (gaps filled in), land on the pose's assembly: the oracle started from them
    stays, and they equal a dense path's samples."""
    m = analytic.load(str(KINDS / path))
    q0 = m.inputs[0].motion.q0
    one = m.solve([q0 + math.radians(200)], 1.0)
    coarse = m.solve(q0 + np.linspace(0, 2 * np.pi, 7), 1.0)        # every 60 deg
    dense = m.solve(q0 + np.linspace(0, 2 * np.pi, 1441), 1.0)      # every 0.25 deg
    for sol, ref in ((one, {p: dense[p][[800]] for p in dense}),
                     (coarse, {p: dense[p][::240] for p in dense})):
        assert sol.valid.all()
        for p in m.points:
            # 1e-12 of size: Newton to rounding along two paths
            assert np.max(np.abs(sol["x" + p] - ref["x" + p])) <= 1e-12 * m.size
    pts = _oracle_at(m, [q0 + math.radians(200)], one)
    assert _worst_position(m, one, pts) <= POS_TOL


def test_the_two_assemblies_are_held_apart():
    """group.toml and group__other.toml share every dimension; their determinant signs (the branch reported)
    differ and their points stay apart over the turn."""
    a, b = (analytic.load(str(KINDS / f)) for f in ("group.toml", "group__other.toml"))
    ea, eb = a.geometry.elements[-1], b.geometry.elements[-1]
    ga, gb = (kinds.get("group").check_resolved(e) or e["_group"] for e in (ea, eb))
    np.testing.assert_allclose(ga.length, gb.length, rtol=1e-14)     # one mechanism: the pose's rounding
    assert ga.branch == -gb.branch
    q = np.linspace(0, 2 * np.pi, 181)
    sa, sb = a.solve(q, 1.0), b.solve(q, 1.0)
    assert sa.valid.all() and sb.valid.all()
    assert np.min(np.hypot(sa["xQ1"] - sb["xQ1"], sa["yQ1"] - sb["yQ1"])) > 0.1 * a.size


def test_where_the_group_cannot_assemble_it_is_not_assembled_and_named():
    m = analytic.from_text(TRIAD, "triad")
    q = 0.5 + np.linspace(0.0, 2 * np.pi, 400)
    sol = m.solve(q, 2.0)
    assert sol.valid[:50].all() and not sol.valid.all()
    k, label = sol.first_failure()
    assert "points D, E, F" in label and q[k] > 0.5 + 0.9        # near the lock the oracle test confirms
    assert np.isnan(sol["xD"][~sol.valid]).all()


def test_a_motion_past_the_lock_and_back_returns_to_the_same_assembly():
    """The crank rocks past the triad's lock (a fold: there its two assemblies of opposite determinant sign
    meet) and back: past it no sample is assembled, and on the way back the group is on the pose's assembly
    again (the branch held), sample for sample where it was on the way out."""
    m = analytic.from_text(TRIAD, "triad")
    t = np.linspace(0.0, 1.0, 801)
    q = 0.5 + 1.2 * np.sin(np.pi * t)                 # out and back: q(t) = q(1 - t)
    sol = m.solve(q, 1.0)
    ok = sol.valid
    assert ok[:230].all() and not ok[400] and ok[-230:].all()      # the lock: q = 1.466, t = 0.298
    back = ok & ok[::-1]
    for p in ("D", "E", "F"):
        # 1e-12 of size: the same assembly, Newton to rounding along the two ways
        assert np.max(np.abs(sol["x" + p][back] - sol["x" + p][::-1][back])) <= 1e-12 * m.size
    g = m.geometry.elements[-1]["_group"]
    pos = {p: (sol["x" + p], sol["y" + p]) for p in ("A", "O1", "O2", "D", "E", "F")}
    assert np.all(gg.singularity(g, pos)[ok] > 0)


def test_linkage_check_reports_the_class_and_the_branch():
    for target, points, expect in (("stephenson_ii", "Q1+Q2+Q3+C", "triad (class III), branch -1"),
                                   (str(KINDS / "group__other.toml"), "Q1+Q2+Q3", "triad (class III), branch +1"),
                                   ("double_butterfly", "H+C3+D3+C4+D4", "6-link group (class III), branch -1")):
        out = cli_runner.run("check", target)
        assert out.returncode == 0, out.stderr
        assert re.search(re.escape(points) + r" \(links [^)]*\): " + re.escape(expect), out.stdout), out.stdout


def test_the_assur_class_of_each_group_shape():
    triad = {"points": ["D", "E", "F"], "links": {"2": ("A", "D"), "T": ("D", "E", "F"), "4": ("O1", "E"),
                                                   "5": ("O2", "F")}}
    dyad = {"points": ["C"], "links": {"2": ("B", "C"), "3": ("D", "C")}}
    # Pyslvs' "Stephenson II" (driven by its binary crank): a quadrilateral L2-L4-L3-L5 pinned at two points
    tetrad = {"points": ["J2", "J3", "J4", "J6"], "links": {"L2": ("J1", "J2", "J3"), "L3": ("J5", "J4", "J6"),
                                                           "L4": ("J3", "J4"), "L5": ("J2", "J6")}}
    butterfly = linkfile.read(analytic.registry.LIBRARY / "double_butterfly.toml").groups[-1].fields
    assert assur_class(dyad) == ("dyad", 2)
    assert assur_class(triad) == ("triad", 3)
    assert assur_class(tetrad) == ("tetrad", 4)
    assert assur_class(butterfly) == ("6-link group", 3)


def _dyads_found(links: dict, known: set) -> list:
    """Peel dyads off a group as a user would: a point on two links, each of which carries a known point
    (written here from the links, not from the kind)."""
    found, known, left = [], set(known), dict(links)
    progress = True
    while progress:
        progress = False
        for p in {q for pts in left.values() for q in pts} - known:
            on = [ln for ln, pts in left.items() if p in pts and any(q in known for q in pts if q != p)]
            if len(on) >= 2:
                found.append(p)
                for ln in on[:2]:
                    known.update(left.pop(ln))
                progress = True
                break
    return found


@pytest.mark.parametrize("name", ["stephenson_ii", "double_butterfly"])
def test_the_library_groups_cannot_be_split_into_dyads(name):
    d = linkfile.read(analytic.registry.LIBRARY / f"{name}.toml")
    e = d.groups[-1]
    known = set(d.ground) | {p for x in d.order if x is not e for p in x.places}
    assert _dyads_found(e.fields["links"], known) == []
    assert _dyads_found({"2": ("B", "C"), "3": ("D", "C")}, {"B", "D"}) == ["C"]   # the check can find one


def test_a_dyad_written_as_a_group_equals_the_rrr_and_its_measure_is_the_transmission_sine():
    rrr = (KINDS / "rrr.toml").read_text()
    m = analytic.from_text(rrr, "rrr")
    sol0 = m.solve([0.0], 0.0)
    B, C = (float(sol0["xB"][0]), float(sol0["yB"][0])), (float(sol0["xC"][0]), float(sol0["yC"][0]))
    as_group = rrr.split("[[groups]]")[0] + f"""
[[groups]]
kind = "group"
points = ["C"]
links = {{ 2 = ["B", "C"], 3 = ["D", "C"] }}
pose = {{ B = [{B[0]!r}, {B[1]!r}], D = [0.3, 0], C = [{C[0]!r}, {C[1]!r}] }}
"""
    g = analytic.from_text(as_group, "as_group")
    q = np.linspace(0, 2 * np.pi, 91)
    a, b = m.solve(q, 2.0, 0.7), g.solve(q, 2.0, 0.7)
    for name in ("xC", "yC", "vxC", "vyC", "axC", "ayC", "omega2", "alpha3"):
        scale = max(np.max(np.abs(a[name])), m.size)
        assert np.max(np.abs(a[name] - b[name])) <= 1e-12 * scale, name     # rounding of two exact forms
    mu = figures.singularity(g, b)
    assert np.max(np.abs(next(iter(mu.values())) - np.sin(a["muC"]))) <= 1e-12


GOOD = (KINDS / "group.toml").read_text()


@pytest.mark.parametrize("change, words", [
    (('rod3 = ["G2", "Q3"]', 'rod3 = ["Q3"]'), r"field 'links': link rod3 has 1 point"),
    (('rod3 = ["G2", "Q3"]', 'rod3 = ["G2", "Q3"], extra = ["G1", "G2"]'), r"link extra carries only known points"),
    (('rod3 = ["G2", "Q3"] }', 'rod3 = ["G2", "Q3"], rod4 = ["G1", "Q3"] }'),
     r"not an Assur group: 7 equations for 6 unknowns"),
    ((", Q3 = [0.492, 0.109] }", " }"), r"field 'pose': no position for point Q3"),
    (("G2 = [0.427, -0.155], Q1", "G2 = [0.427, -0.1553], Q1"),
     r"field 'pose': point G2 is at \(0.427, -0.155\) m at the start but the pose puts it 0.0003 m away"),
    (("Q3 = [0.492, 0.109]", "Q3 = [0.492, 0.109], Z = [0, 0]"), r"field 'pose': point Z is on none"),
    (("Q2 = [0.19, 0.133]", "Q2 = [0.489, -0.076]"), r"field 'pose': .*(points 'Q1' and 'Q2' coincide|singular)"),
])
def test_bad_groups_are_refused_in_one_line_naming_the_field(change, words, tmp_path):
    text = GOOD.replace(*change)
    assert text != GOOD
    with pytest.raises(ParameterError) as err:
        analytic.from_text(text, "bad.toml")
    msg = str(err.value)
    assert "\n" not in msg and "groups[2] (points Q1, Q2, Q3)" in msg, msg
    assert re.search(words, msg), msg
    f = tmp_path / "bad.toml"
    f.write_text(text)
    out = cli_runner.run("check", str(f))
    assert out.returncode == 2 and "Traceback" not in out.stderr and len(out.stderr.strip().splitlines()) == 1


def test_a_singular_pose_is_refused():
    # a triad folds where the lines of its three rods meet in one point (the triangle can turn about it):
    # here X = (2.6, 1.9), with D, E, F on the lines A -> X, O1 -> X, O2 -> X
    text = TRIAD.replace("D = [1.5, 2.0], E = [3.0, 2.5], F = [2.6, 1.2]",
                         'D = ["cos(0.5) + 0.6 * (2.6 - cos(0.5))", "sin(0.5) + 0.6 * (1.9 - sin(0.5))"], '
                         'E = [3.3, 2.7], F = [3.05, 0.7]')
    assert text != TRIAD
    with pytest.raises(ParameterError, match=r"points D, E, F\): field 'pose': the pose is singular"):
        analytic.from_text(text, "folded")


def test_batch_solves_designs_one_by_one_each_from_its_pose():
    """Two designs whose poses are the two assemblies of one triad (a parameter picks the pose): solved as
    one concatenated path the second would continue from the first's assembly; design by design each keeps
    its own. A third design's pose disagrees with its crank at the start: invalid, with the message."""
    a, b = (linkfile.read(KINDS / f).groups[-1].fields["pose"] for f in ("group.toml", "group__other.toml"))
    pose = ", ".join(f'{p} = ["{a[p][0]} + (1 - s) / 2 * ({b[p][0]} - {a[p][0]})", '
                     f'"{a[p][1]} + (1 - s) / 2 * ({b[p][1]} - {a[p][1]})"]' for p in a)
    text = GOOD.replace("[ground]", "[parameters]\ns = 1\nr = 0.1\n\n[ground]").replace("length = 0.1", 'length = "r"')
    text = text.split("pose = ")[0] + "pose = { " + pose + " }\n"
    base = analytic.from_text(text, "two")
    designs = batch.resolve(base, {"s": np.array([1.0, -1.0, 1.0]), "r": np.array([0.1, 0.1, 0.1003])})
    assert list(designs.valid) == [True, True, False]
    assert "point P1" in designs.reasons[2] and "field 'pose'" in designs.reasons[2]
    t = np.linspace(0.0, 1.0, 91)
    sol = batch.solve(designs, *batch.drive(designs, np.tile(t, (3, 1))))
    for k, s in enumerate((1.0, -1.0)):
        one = base.with_values(s=s).solve(*base.drive(t))
        for name in ("xQ1", "yQ3", "vxQ2", "ayQ3", "omegacoupler"):
            scale = max(np.max(np.abs(one[name])), base.size)
            assert np.max(np.abs(sol[name][k] - one[name])) <= 1e-12 * scale, (k, name)
    assert np.min(np.hypot(sol["xQ1"][0] - sol["xQ1"][1], sol["yQ1"][0] - sol["yQ1"][1])) > 0.1 * base.size
    assert np.isnan(sol["xQ1"][2]).all()


def test_groups_run_on_numpy_and_the_compiled_path_gives_the_same(monkeypatch):
    from analytic.solver import jit
    m = analytic.load("stephenson_ii")
    assert not jit.supports(m.geometry)
    q = np.linspace(0, 2 * np.pi, 50)
    monkeypatch.setenv("LINKAGE_JIT", "1")
    a = m.solve(q, 1.0)
    monkeypatch.setenv("LINKAGE_JIT", "0")
    b = m.solve(q, 1.0)
    for name in a:
        assert np.array_equal(a[name], b[name], equal_nan=True), name


def test_batched_lu_solves_and_its_determinant():
    rng = np.random.default_rng(5)
    for n in (2, 4, 6):
        A = rng.normal(size=(n, n, 500))
        b = rng.normal(size=(n, 500))
        ref = np.linalg.solve(np.moveaxis(A, 2, 0), b.T[..., None])[..., 0].T
        det = np.linalg.det(np.moveaxis(A, 2, 0))
        for order in (None, np.argsort(-np.abs(A[:, 0]), axis=0), np.tile(np.arange(n)[::-1, None], 500)):
            LU, perm, d = gg.lu(A.copy(), order)
            x = gg.lu_solve(LU, perm, b)
            # partial pivoting (or its fallback for multipliers above GROWTH): rounding times the condition
            cond = np.linalg.cond(np.moveaxis(A, 2, 0))
            assert np.all(np.max(np.abs(x - ref), axis=0) <= 1e-13 * cond * np.max(np.abs(ref), axis=0))
            assert np.all(np.abs(d - det) <= 1e-12 * np.abs(det) * cond)


def _windows(starts, width, back=False):
    """Windows of 9 samples from each start [deg], each run back over itself after it when ``back`` (the turn is
    a repeated sample: a zero step between the two ways)."""
    w = np.asarray(starts, float)[:, None] + width * np.linspace(0, 1, 9)[None, :]
    if back:
        w = np.concatenate((w, w[:, ::-1]), axis=1)
    return np.radians(w.ravel())


@pytest.mark.parametrize("mech, q", [
    ("butterfly", _windows([107.8, 107.4, 107.6, 107.9, 150.0, 149.5, 300.0, 20.0, 20.1], 0.2)),  # stepping back
    ("butterfly", _windows([358.0 + 0.4 * k for k in range(12)], 0.125)),                         # dense clusters
    ("triad", _windows([81.4, 81.6, 81.8, 82.0], 0.2, back=True)),  # back over itself, 2 deg short of the lock
], ids=["back", "clusters", "repeated"])
def test_windows_that_step_back_are_solved_on_the_branch(mech, q):
    """Samples in short windows that each start a little behind where the last one ended, clusters of dense
    samples with wide steps between them, windows run back over themselves (as the time-step scan zooms into
    its peaks; near the triad's lock its points move fast): every sample equals the same samples solved in
    increasing order."""
    m = analytic.load(str(KINDS / "group__butterfly.toml")) if mech == "butterfly" else analytic.from_text(TRIAD, "t")
    sol = m.solve(q, 1.0)
    order = np.argsort(q, kind="stable")
    ref = m.solve(q[order], 1.0)
    assert sol.valid.all() and ref.valid.all()
    for p in [e["places"] for e in m.geometry.elements][-1]:
        for c in ("x", "vy"):
            scale = max(np.max(np.abs(ref[c + p])), m.size)
            # 1e-12 of scale: Newton to rounding along two paths; exact rates at the same points
            assert np.max(np.abs(sol[c + p][order] - ref[c + p])) <= 1e-12 * scale
