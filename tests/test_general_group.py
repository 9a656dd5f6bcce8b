"""A numerically solved Assur group (analytic/solver/general_group.py) against an oracle written here.

The group: a class III triad (a ternary link D E F with three binary links pinned at A, O1, O2), the
group a Stephenson six-bar leaves when its crank is the link that makes the rest indecomposable into dyads.
The oracle solves the six distance equations |D-A|, |D-E|, |E-F|, |D-F|, |E-O1|, |F-O2| (written from the
geometry, not from the solver's link-frame equations) with scipy's fsolve sample by sample, and its rates are
finite differences of it along the crank angle.
"""

import numpy as np
import pytest
from scipy.optimize import fsolve

from analytic import ParameterError
from analytic.solver.general_group import make_group, solve_group
from analytic.kinds.base import line, on_frame
from analytic.kinds.rrr import rrr as _rrr


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
