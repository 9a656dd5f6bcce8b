"""Path synthesis beyond the four-bar, open and closed targets, the plot, and the same answer on any
number of workers.

The families' vectorised closed forms (analytic/synthesis/curves.py) are checked against the general
solver reading the files they write (analytic/kinds, independent code); their transmission angles against
the solver's own transmission outputs (six-bar) or the angle measured from solved positions (slider-crank);
their full-turn constraint against the solver's assembly over the turn."""

import json
import math

import numpy as np
import pytest

from analytic.registry import from_text
from analytic.synthesis import path as sp
from analytic.synthesis.curves import FAMILIES
from sim.service import design as design_service
from sim.run.parallel import mapper

import cli_runner  # the command in this process (tests/cli_runner.py)


def run(*args, timeout=600):
    return cli_runner.run(*map(str, args))


def feasible(name, seed, mu_deg=35.0):
    """A random design of family ``name`` meeting the constraints (transmission >= mu_deg), its branch."""
    fam = FAMILIES[name]
    rng = np.random.default_rng(seed)
    cons = sp.Constraints(mu_min=math.radians(mu_deg))
    for _ in range(50):
        b = fam.branches[rng.integers(len(fam.branches))]
        X = fam.shape(rng.random((4000, fam.shape_dim)))
        for i in np.flatnonzero(sp.shape_violation(X, cons, b, fam) == 0):
            x = fam.move(X[i:i + 1], 0.7 * np.exp(1j * rng.uniform(-3, 3)), complex(*rng.uniform(-1, 1, 2)))[0]
            if sp.shape_violation(x[None], cons, b, fam, 4096)[0] == 0:
                return x, b
    raise AssertionError("no feasible design drawn")


def solver_of(name, x, b, phi1_0=0.0):
    return from_text(FAMILIES[name].text(x, b, "m", f"t_{name}", "test", phi1_0), "<test>")


@pytest.mark.parametrize("name,seed", [("slider_crank", 1), ("slider_crank", 2), ("watt", 3), ("watt", 4),
                                       ("stephenson", 5), ("stephenson", 6), ("fourbar", 7)])
def test_family_curve_matches_general_solver(name, seed):
    x, b = feasible(name, seed)
    q = np.linspace(0.0, 2 * math.pi, 721)
    sol = solver_of(name, x, b).solve(q)
    assert sol.first_failure() is None                      # the crank turns fully in the solver too
    E, ok = FAMILIES[name].points(x[None], q, b)
    p = "Q" if name in ("watt", "stephenson") else "E"
    assert ok.all()
    size = np.ptp(E[0], axis=0).max()
    # two double-precision evaluations of one geometry (closed forms vs the kinds' solver): rounding only
    assert np.abs(E[0, :, 0] - sol["x" + p]).max() < 1e-10 * size
    assert np.abs(E[0, :, 1] - sol["y" + p]).max() < 1e-10 * size


@pytest.mark.parametrize("name,seed", [("slider_crank", 11), ("watt", 12), ("stephenson", 13)])
def test_transmission_angle_matches_the_solver(name, seed):
    x, b = feasible(name, seed)
    fam = FAMILIES[name]
    q = np.linspace(0.0, 2 * math.pi, 20001)
    mech = solver_of(name, x, b)
    sol = mech.solve(q)
    if name == "slider_crank":
        # measured from the solved positions: the rod's angle to the slider line's normal
        rod = np.column_stack([sol["xC"] - sol["xB"], sol["yC"] - sol["yB"]])
        u = np.array([math.cos(x[2]), math.sin(x[2])])
        mu = np.arcsin(np.clip(np.abs(rod @ u) / np.hypot(*rod.T), 0, 1))   # 90 deg - angle to the line
        measured = mu.min()
    else:
        measured = min(sol[m].min() for m in mech.transmission_angles.values())
    # 20001 samples of a smooth angle: the sampled minimum is within 1e-6 rad of the true one
    assert abs(fam.mu_min(x[None], b)[0] - measured) < 1e-6


def transmission_sampled(name, x, b, n=20001) -> float:
    """The least transmission angle [rad] from solved poses (closed forms of ``points`` only, not the
    constraint's): the four-bar's between C->B and C->D, the slider-crank's rod against the line's normal;
    NaN where a pose does not close."""
    fam = FAMILIES[name]
    phi = np.linspace(0, 2 * math.pi, n, endpoint=False)
    ax, ay, th = x[:3]
    a = x[4] if name == "fourbar" else x[3]
    B = np.column_stack([ax + a * np.cos(phi), ay + a * np.sin(phi)])
    if name == "fourbar":
        C = fam.points(np.r_[x[:7], x[5], 0.0][None], phi, b)[0][0]
        D = np.array([ax + x[3] * math.cos(th), ay + x[3] * math.sin(th)])
        u, v = B - C, D - C
        mu = np.arccos(np.clip((u * v).sum(1) / np.hypot(*u.T) / np.hypot(*v.T), -1, 1))
        return float(min(mu.min(), math.pi - mu.max()))
    C = fam.points(np.r_[x[:5], x[5], x[4], 0.0][None], phi, b)[0][0]
    rod = C - B
    return float(np.arcsin(np.clip(np.abs(rod @ [math.cos(th), math.sin(th)]) / np.hypot(*rod.T), 0, 1)).min())


@pytest.mark.slow
@pytest.mark.parametrize("name", ["fourbar", "slider_crank"])
def test_constraint_margins_hold_where_the_sampled_transmission_angle_does(name):
    fam = FAMILIES[name]
    rng = np.random.default_rng(5)
    bound = math.radians(20.0)
    cons = sp.Constraints(mu_min=bound)
    t = sp.Target(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]))
    seen = {True: 0, False: 0}
    for _ in range(600 if name == "fourbar" else 200):
        b = fam.branches[rng.integers(2)]
        x = fam.shape(rng.random((1, fam.shape_dim)))[0]
        mu = transmission_sampled(name, x, b)
        if not math.isnan(mu) and abs(mu - bound) < 1e-4:
            continue                                  # 20001 samples: within 1e-4 rad of the bound, either
        m = sp.margins(x[None], cons, t, b, fam)[0]
        holds = not math.isnan(mu) and mu >= bound
        # the transmission margins are the first columns; all of them hold exactly where nothing is violated
        assert bool(np.all(m[:2 if name == "fourbar" else 1] >= 0)) == holds
        assert (sp.violation(x[None], cons, t, b, fam)[0] == 0) == bool(np.all(m >= 0))
        seen[holds] += 1
    assert min(seen.values()) > 20                   # both sides of the bound were drawn


@pytest.mark.parametrize("branch,side", [(1, 1), (1, -1), (-1, 1), (-1, -1)])
def test_fourbar_from_slider_crank_tends_to_its_curve(branch, side):
    from analytic.synthesis.curves import fourbar_from_slider_crank
    sc, fb = FAMILIES["slider_crank"], FAMILIES["fourbar"]
    rng = np.random.default_rng(8)
    xs = sc.shape(rng.random((1000, 4)))
    xs[:, :3] = rng.normal(size=(1000, 3))
    xs = xs[sc.excess(xs, (branch,), math.radians(30.0)) == 0]      # slider-cranks that turn, mu >= 30 deg
    assert len(xs) > 100
    phi = np.linspace(0, 2 * math.pi, 360, endpoint=False)
    E0, ok = sc.points(xs, phi, (branch,))
    assert ok.all()
    dev = {}
    for length in (100.0, 1000.0):
        x, br = fourbar_from_slider_crank(xs, branch, length, side)
        assert np.all(br == -side * branch)
        E1, _ = fb.points(x, phi, br[:, None])
        dev[length] = np.hypot(*(E1 - E0).transpose(2, 0, 1)).max(axis=1)
    # the rocker's arc leaves the slider line by ~travel^2 / (8 length): the curves' gap shrinks as 1/length
    # (ratio 10 up to the next order, 1/length^2: measured 9.83-10.18)
    ratio = dev[100.0] / dev[1000.0]
    assert np.all(np.isfinite(ratio)) and np.all((9 < ratio) & (ratio < 11))
    assert dev[1000.0].max() < 0.01                  # crank 1, traced points <= 16 away: measured 0.005


def test_sixbar_that_cannot_close_is_refused_like_the_solver_refuses_it():
    x, b = feasible("stephenson", 21)
    fam = FAMILIES["stephenson"]
    q = np.linspace(0.0, 2 * math.pi, 4096, endpoint=False)
    for k in np.linspace(0.98, 0.05, 94):                   # shorten the output rocker until the dyad tears
        bad = x.copy()
        bad[10] *= k
        _, ok = fam.points(bad[None], q, b)
        if 0 < ok.mean() < 1:
            break
    assert 0 < ok.mean() < 1
    assert fam.excess(bad[None], b, 0.0, 4096)[0] > 0
    assert math.isnan(fam.mu_min(bad[None], b)[0])
    assert "does not turn fully" in sp.failed_constraint(bad, sp.Constraints(), sp.Target(np.eye(2)), b, fam)
    start = float(q[np.argmax(ok[0])])                      # where it assembles
    sol = solver_of("stephenson", bad, b, start).solve(start + np.linspace(0, 2 * math.pi, 3601))
    assert sol.first_failure() is not None                  # the general solver cannot turn it either


def write_targets(path, xy, phi=None):
    head = "x,y" + (",phi" if phi is not None else "")
    rows = [f"{a:.17g},{c:.17g}" + (f",{math.degrees(p):.17g}" if phi is not None else "")
            for (a, c), p in zip(xy, phi if phi is not None else [None] * len(xy))]
    path.write_text(head + "\n" + "\n".join(rows) + "\n")


@pytest.mark.slow
def test_slider_crank_recovered_and_each_candidate_compared(tmp_path):
    x, b = feasible("slider_crank", 31)
    phi = np.sort(np.random.default_rng(31).uniform(0, 2 * math.pi, 12))
    E, _ = FAMILIES["slider_crank"].points(x[None], phi, b)
    f = tmp_path / "t.csv"
    write_targets(f, E[0])
    out = tmp_path / "sc.toml"
    r = run("synthesize", "path", f, "--type", "slider_crank", "--closed", "--generations", 80, "--designs", 2,
            "--workers", 2, "--budget", 10000, "--json", "--out", out)
    assert r.returncode == 0, r.stderr
    designs = json.loads(r.stdout)["designs"]
    size = np.ptp(E[0], axis=0).max()
    assert designs[0]["type"] == "slider_crank" and designs[0]["error"]["max"] < 1e-3 * size   # the bar
    for d in designs:                       # every candidate: compared (in a worker), through the solver
        assert d["compare_passed"] and not d["failed"] and d["parameters"]["mu_min_deg"] >= 30.0
        assert d["solver_deviation"] < 1e-9
    mech = from_text(out.read_text(), str(out))
    sol = mech.solve(np.linspace(0, 2 * math.pi, 20000))
    near = np.sqrt(((E[0][:, None, :] - np.column_stack([sol["xE"], sol["yE"]])[None]) ** 2).sum(-1)).min(1)
    assert near.max() < 1e-3 * size                      # 20000 samples: spacing far below 1e-3 of size


@pytest.mark.slow
def test_sixbar_path_synthesis_returns_a_checked_sixbar(tmp_path):
    x, b = feasible("stephenson", 41)
    phi = np.linspace(0, 2 * math.pi, 14, endpoint=False)
    E, _ = FAMILIES["stephenson"].points(x[None], phi, b)
    f = tmp_path / "t.csv"
    write_targets(f, E[0])
    out = tmp_path / "six.toml"
    r = run("synthesize", "path", f, "--type", "sixbar", "--closed", "--generations", 40, "--workers", 2,
            "--budget", 10000, "--json", "--out", out)
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)["designs"][0]
    assert d["type"] in ("watt", "stephenson") and d["compare_passed"] and not d["failed"]
    assert d["parameters"]["mu_min_deg"] >= 30.0 - 1e-9            # the solver's own transmission outputs
    mech = from_text(out.read_text(), str(out))
    assert mech.output_point == "Q" and len(mech.transmission_angles) == 2
    # the written design's errors are the ones reported (general solver, 40000 samples of the turn)
    sol = mech.solve(np.linspace(0, 2 * math.pi, 40000))
    near = np.sqrt(((E[0][:, None, :] - np.column_stack([sol["xQ"], sol["yQ"]])[None]) ** 2).sum(-1)).min(1)
    assert abs(near.max() - d["error"]["max"]) < 1e-3 * np.ptp(E[0], axis=0).max()   # sample spacing


def steps_in_sense(phis):
    """The crank-angle steps from each target to the next in the turning sense, and the return from the
    last to the first (what is left of the turn) [rad]."""
    d = np.angle(np.exp(1j * np.diff(phis)))
    d = d * (1 if d.sum() >= 0 else -1)
    return d, 2 * math.pi - d.sum()


@pytest.mark.slow
def test_closed_targets_are_a_loop_open_ones_a_stretch(tmp_path):
    """Targets on 150 deg of crank of a four-bar's curve: as an open path a design through them is found
    whose return from the last target to the first takes the other ~210 deg; as a closed path that return
    is a step like the others and must be under half a turn, so that design is not an answer."""
    x, b = feasible("fourbar", 51, mu_deg=40)
    phi = np.linspace(0.0, math.radians(150), 12) + 0.4
    E, _ = FAMILIES["fourbar"].points(x[None], phi, b)
    t_open, t_closed = sp.Target(E[0]), sp.Target(E[0], closed=True)
    kw = dict(seed=3, restarts=2, generations=60, popsize=40, n_polish=3)
    a = sp.synthesize(t_open, **kw)[0]
    c = sp.synthesize(t_closed, **kw)[0]
    assert a.violation == 0 and c.violation == 0
    assert a.err.max() < 1e-3 * t_open.size                 # recovered
    (da, ra), (dc, rc) = steps_in_sense(a.phis), steps_in_sense(c.phis)
    assert np.all(da >= 0) and ra > math.pi                 # the return is the long way round (~210 deg)
    assert np.all(dc >= 0) and np.all(dc < math.pi) and 0 <= rc < math.pi   # a loop: the return is a step
    assert c.err.max() < 1e-2 * t_closed.size               # a loop through the same points exists nearby
    # the CLI passes the flag through: same answers
    f = tmp_path / "t.csv"
    write_targets(f, E[0])
    assert design_service.read_target(str(f), closed=True).closed
    assert not design_service.read_target(str(f)).closed


def test_order_violation_by_hand():
    deg = np.radians
    assert sp.order_violation(deg([[0, 40, 80, 120]]), False)[0] == 0
    assert sp.order_violation(deg([[0, 40, 80, 120]]), True)[0] > 0       # closing step 240 deg: backward
    assert sp.order_violation(deg([[0, 90, 180, 270]]), True)[0] < 1e-12   # four quarter turns: one loop
    # one step back by 10 deg of 40: 10/180 half turns
    assert abs(sp.order_violation(deg([[0, 40, 30, 70]]), False)[0] - 10 / 180) < 1e-12


@pytest.mark.slow
def test_plot_of_targets_and_candidates(tmp_path):
    import matplotlib.image as mpimg
    x, b = feasible("fourbar", 61)
    phi = np.linspace(0, 2 * math.pi, 10, endpoint=False)
    E, _ = FAMILIES["fourbar"].points(x[None], phi, b)
    f = tmp_path / "t.csv"
    write_targets(f, E[0])
    png = tmp_path / "cands.png"
    r = run("synthesize", "path", f, "--closed", "--generations", 15, "--restarts", 2, "--designs", 2,
            "--budget", 10000, "--plot", png)
    assert r.returncode in (0, 1), r.stderr
    img = mpimg.imread(png)[..., :3]
    assert img.std() > 0.05                                    # not blank
    h, w, _ = img.shape
    blue = (np.abs(img - np.array([31, 119, 180]) / 255).sum(-1) < 0.1)      # tab:blue, the coupler curves
    red = (np.abs(img - np.array([214, 39, 40]) / 255).sum(-1) < 0.1)        # tab:red, the targets
    for half in (slice(0, w // 2), slice(w // 2, w)):          # one panel per candidate, both drawn
        assert blue[:, half].sum() > 200 and red[:, half].sum() > 50


def test_benchmark_targets_read_as_the_command_reads_them(tmp_path):
    t = design_service.read_target("benchmarks/data/path_mkh1.csv")
    assert t.xy.shape == (18, 2) and abs(t.xy[0, 0] - 0.5) < 1e-15 and abs(t.xy[0, 1] - 1.1) < 1e-15
    f = tmp_path / "three.csv"
    f.write_text("# a comment\n1,2,3\n4,5,6\n7,8,9\n1,1,1\n")
    from analytic import ParameterError
    with pytest.raises(ParameterError, match="line 2: no header and 3 column"):
        design_service.read_target(str(f))


@pytest.mark.slow
def test_same_answer_for_one_two_workers_and_a_dask_cluster():
    x, b = feasible("fourbar", 71)
    phi = np.linspace(0, 2 * math.pi, 8, endpoint=False)
    E, _ = FAMILIES["fourbar"].points(x[None], phi, b)
    t = sp.Target(E[0])
    # no budget: a deadline would make the answer depend on the speed
    kw = dict(seed=7, restarts=3, generations=10, popsize=20, n_polish=1, types=("fourbar", "slider_crank"))
    a = sp.synthesize(t, **kw)
    with mapper(2) as m:
        c = sp.synthesize(t, mapper=m, **kw)
    # determinism, not accuracy: the same seeded jobs must give bit-identical designs in any process
    assert [(d.seed, d.family.name, d.branch) for d in a] == [(d.seed, d.family.name, d.branch) for d in c]
    assert all(np.array_equal(p.x, q.x) for p, q in zip(a, c))
    pytest.importorskip("dask.distributed")
    import concurrent.futures as cf
    import time
    t0 = time.perf_counter()
    try:
        with mapper(2, "local") as m:
            if time.perf_counter() - t0 > 60:
                pytest.skip("the local Dask cluster took over 60 s to start on this machine")
            d = sp.synthesize(t, mapper=m, **kw)
    except (OSError, cf.TimeoutError) as exc:
        pytest.skip(f"no local Dask cluster here: {exc}")
    assert all(np.array_equal(p.x, q.x) and p.family == q.family for p, q in zip(a, d))


def test_sweep_on_two_workers_gives_the_same_rows():
    import analytic
    from analytic.applications import studies
    base = analytic.load("fivebar")
    vary = {"l1": list(np.linspace(0.1, 0.3, 70)), "l2": list(np.linspace(0.03, 0.09, 70))}   # 4900: 3 chunks
    one, paths1 = studies.sweep_mechanism(base, vary, 90, keep_paths=3)
    with mapper(2) as m:
        two, paths2 = studies.sweep_mechanism(base, vary, 90, keep_paths=3, mapper=m)
    assert len(one) == len(two) == 4900 and any(not r.valid for r in one)
    assert [r.params for r in one] == [r.params for r in two]
    assert [r.reason for r in one] == [r.reason for r in two]
    for r, s in zip(one, two):
        # the same arithmetic in another process: bit-identical (NaN where invalid)
        assert np.array_equal(np.array(list(r.values.values())), np.array(list(s.values.values())), equal_nan=True)
    assert [p[0] for p in paths1] == [p[0] for p in paths2]
