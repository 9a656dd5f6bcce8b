"""`linkage tolerance`: the Monte Carlo spread agrees with first-order propagation for small tolerances, the
rates agree with closed forms (slider-crank piston position, four-bar transmission angle by the cosine law),
Sobol indices of additive cases match their variance shares, failed designs are counted, bad input is one
line with exit code 2."""

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from analytic.applications import tolerance as T
from sim import service
from sim.service import tolerance as ts


def run(*args):
    return subprocess.run([sys.executable, "-m", "sim", *args], capture_output=True, text=True)


# four-bar defaults (SPEC): l1 = 0.10, l2 = 0.30, l3 = 0.25, l4 = 0.30 [m]
L1, L2, L3, L4 = 0.10, 0.30, 0.25, 0.30


def mu_rates():
    """The smallest transmission angle of the default crank-rocker and its rates, by hand: it occurs with the
    crank along the ground towards D (phi1 = 0), where the diagonal BD = l4 - l1 and the cosine law gives
    cos mu = (l2^2 + l3^2 - BD^2) / (2 l2 l3); implicit differentiation, d mu = -d(cos mu) / sin mu."""
    bd = L4 - L1
    c = (L2 ** 2 + L3 ** 2 - bd ** 2) / (2 * L2 * L3)
    mu = math.acos(c)
    s = math.sin(mu)
    dc_dbd = -bd / (L2 * L3)
    dc_dl2 = (L2 ** 2 - L3 ** 2 + bd ** 2) / (2 * L2 ** 2 * L3)
    return mu, {"l1": -(dc_dbd * -1) / s, "l4": -(dc_dbd * 1) / s, "l2": -dc_dl2 / s}


# ------------------------------------------------------------------------------ Monte Carlo vs first order
def test_monte_carlo_spread_agrees_with_first_order_for_small_tolerances():
    mech = service.load("fourbar")
    n = 1500
    r = ts.tolerance(mech, ["l1=±0.0002", "l2=normal:0.0001", "l3=±0.05%"], samples=n, seed=3)
    assert r.failed == 0 and r.samples == n
    for name in ("transmission_min", "peak_torque", "peak_joint_force"):
        s = r.summaries[name]
        # the estimated std's relative sampling error is ~ sqrt((kurtosis - 1) / 4N) <= 1/sqrt(2N) = 1.8 %;
        # second-order terms are ~ tolerance/length ~ 1e-3 of it: 7 % is 3.8 sampling sigmas
        assert s.std == pytest.approx(s.first_order_std, rel=0.07), name
        # the mean moves from the nominal only by second-order terms and sampling: within 4 std/sqrt(N)
        assert abs(s.mean - s.nominal) < 4 * s.std / math.sqrt(n), name
    # path_deviation is a norm: its linearised value over the same draws, max_u |J(u) d|, differs from the
    # solver's only by the second-order terms (~ 1e-3 relative here): 1 %
    s = r.summaries["path_deviation"]
    assert s.std == pytest.approx(s.first_order_std, rel=0.01)
    assert s.nominal == 0.0 and s.p05 > 0


def test_first_order_std_of_the_transmission_angle_is_the_hand_computed_one():
    mech = service.load("fourbar")
    v1, v4 = 0.0005, 0.001
    r = ts.tolerance(mech, [f"l1=±{v1}", f"l4=±{v4}", "l2=normal:0.0003"], samples=400, seed=1,
                     outputs="transmission_min")
    mu, rate = mu_rates()
    s = r.summaries["transmission_min"]
    assert s.nominal == pytest.approx(mu, abs=1e-12)   # phi1 = 0 is a sample of the cycle: the same pose
    for p in ("l1", "l2", "l4"):
        # central differences with a step of 1e-3 std: truncation ~ (step)^2 relative, far below 1e-6
        assert s.rates[p] == pytest.approx(rate[p], rel=1e-6), p
    expected = math.sqrt((rate["l1"] * v1 / math.sqrt(3)) ** 2 + (rate["l4"] * v4 / math.sqrt(3)) ** 2
                         + (rate["l2"] * 0.0003) ** 2)
    assert s.first_order_std == pytest.approx(expected, rel=1e-6)   # uniform: V/sqrt(3); normal: sigma
    # and the solver's spread: sampling error of a std at N = 400 is ~ 1/sqrt(2N) = 3.5 %: 4 sigmas
    assert s.std == pytest.approx(expected, rel=0.14)


def test_transmission_angle_that_passes_a_right_angle_has_its_maximum_exactly_there():
    # the default crank-rocker's coupler-rocker angle is 41.4 deg at phi1 = 0 and 92.9 deg at phi1 = 180 deg
    # (cosine law, diagonals l4 -/+ l1): it passes 90 deg, where the folded transmission angle peaks; small
    # tolerances keep both ends on their sides, so the maximum stays pi/2 exactly and has no spread
    mech = service.load("fourbar")
    r = ts.tolerance(mech, ["l1=±0.001", "l3=±0.001"], samples=100, seed=1, outputs="transmission_max")
    s = r.summaries["transmission_max"]
    assert s.nominal == math.pi / 2 and s.first_order_std == 0.0
    assert s.p05 == s.p95 == math.pi / 2 and s.std < 1e-15        # np.std of a constant: rounding of its mean


# ------------------------------------------------------------------------------ hand-computed rates
def slider_crank_rates(phi, r=0.05, l=0.20):
    """Piston position x = r cos(phi) + sqrt(l^2 - r^2 sin^2(phi)) (no offset) and its rates d x/d r, d x/d l."""
    root = np.sqrt(l * l - (r * np.sin(phi)) ** 2)
    return np.cos(phi) - r * np.sin(phi) ** 2 / root, l / root


def test_piston_position_rates_are_the_closed_form_at_every_crank_angle():
    mech = service.load("slider_crank")
    tols = ts.tolerances_of(mech, ["r=±0.001", "l=±0.001"])
    nominal, cycle = ts.cycle_of(mech)
    _, _, jac = T.rates(nominal, tols, cycle, ("path_deviation",))
    phi = cycle.q[:, 0]
    dxdr, dxdl = slider_crank_rates(phi)
    # central differences on the solver (step 1e-3 of the std ~ 6e-7 m): truncation ~ step^2 x''' ~ 1e-12,
    # rounding ~ 1e-16 * 0.25 m / 6e-7 m ~ 4e-11
    np.testing.assert_allclose(jac[0, :, 0], dxdr, atol=1e-8)
    np.testing.assert_allclose(jac[1, :, 0], dxdl, atol=1e-8)
    np.testing.assert_allclose(jac[:, :, 1], 0.0, atol=1e-8)    # the piston stays on its line


def test_path_deviation_of_a_slider_crank_rod_tolerance_is_the_hand_computed_distribution():
    # with the rod alone, the piston moves by dl * l / sqrt(l^2 - r^2 sin^2 phi), largest at phi = 90 deg:
    # path_deviation = |dl| * l / sqrt(l^2 - r^2) (to first order), |dl| uniform on [0, V]
    mech = service.load("slider_crank")
    v, n = 0.002, 4000
    r = ts.tolerance(mech, [f"l=±{v}"], samples=n, seed=5, outputs="path_deviation")
    k = 0.20 / math.sqrt(0.20 ** 2 - 0.05 ** 2)
    s = r.summaries["path_deviation"]
    assert s.rates["l"] == pytest.approx(k, rel=1e-6)           # the largest rate over the cycle's samples
    assert s.first_order_std == pytest.approx(k * v / math.sqrt(12), rel=0.04)   # std of |d| ~ U(0, V): V/sqrt(12)
    # Monte Carlo mean of k|d|: k V / 2, sampling error k V / sqrt(12 N) = 0.5 % of it; 2nd-order terms ~ V/l = 1 %
    assert s.mean == pytest.approx(k * v / 2, rel=0.03)
    assert s.p95 == pytest.approx(k * v * 0.95, rel=0.03)       # percentiles of U(0, kV)


def test_speed_tolerance_scales_inertia_forces_as_its_square_and_leaves_the_poses():
    # with inertia loads only and a constant input speed, every acceleration is omega^2 times a function of
    # the pose, so every force and drive torque is too: d(peak)/d(omega) = 2 peak / omega; the poses (at the
    # same input values) do not move at all
    mech = service.load("fourbar")
    w = float(mech.values["omega1"])
    r = ts.tolerance(mech, ["omega1=±1%", "l1=±0.0001"], samples=50, seed=1)
    for name in ("peak_torque", "peak_joint_force"):
        s = r.summaries[name]
        # central differences of a quadratic are exact; rounding ~ 1e-16 / (1e-3 x 0.6 % of omega): 1e-6
        assert s.rates["omega1"] == pytest.approx(2 * s.nominal / w, rel=1e-6), name
    for name in ("path_deviation", "transmission_min"):
        assert abs(r.summaries[name].rates["omega1"]) < 1e-9, name


def test_nominal_forces_are_those_of_linkage_forces_with_its_loads():
    # the nominal design through the tolerance path (batch kinematics, each design's own mass model, the
    # cutting force's window and gravity from the command's loads) against `linkage forces` (one mechanism,
    # its own kinematics): the same numbers to rounding
    from sim.model import Loads
    from sim.front.cli.options import cutting_direction
    mech = service.load("sixbar")
    force = (cutting_direction(mech) * 500.0, 0.0)
    loads = Loads(gravity=(0.0, -9.81), force=force, slow_stroke_only=True)
    r = ts.tolerance(mech, ["l1=±0.0001"], samples=10, seed=1, outputs="peak_torque,peak_joint_force",
                     loads=loads)
    run_ = service.forces_run(mech, 361, 1.0, None, (0.0, -9.81), force, True)
    peaks = service.force_peaks(run_)
    assert r.summaries["peak_torque"].nominal == pytest.approx(peaks["drives"]["phi1"]["value"], rel=1e-9)
    assert r.summaries["peak_joint_force"].nominal == pytest.approx(
        max(j["F"] for j in peaks["joints"].values()), rel=1e-9)


# ------------------------------------------------------------------------------ Sobol indices
def test_sobol_indices_of_an_additive_function_are_its_variance_shares():
    # y = 2 a + b, a uniform on [-1, 1] (variance 1/3), b normal with sigma 0.5: variances 4/3 and 1/4;
    # additive, so S1 = ST = each term's share
    tols = (T.Tolerance("a", "uniform", 1.0), T.Tolerance("b", "normal", 0.5))
    x = T.saltelli(tols, 4096, seed=2)
    assert abs(x[:, 0]).max() <= 1.0 and x[:, 1].std() == pytest.approx(0.5, rel=0.03)
    y = 2 * x[:, 0] + x[:, 1]
    share = {"a": (4 / 3) / (4 / 3 + 0.25), "b": 0.25 / (4 / 3 + 0.25)}
    s, dropped = T.sobol_indices(tols, y, seed=2)
    assert dropped == 0
    for p in ("a", "b"):
        # Saltelli/Jansen estimators at N = 4096: bootstrap 95 % half-widths ~ 0.03 (SALib's S1_conf)
        assert s[p]["S1"] == pytest.approx(share[p], abs=0.05), p
        assert s[p]["ST"] == pytest.approx(share[p], abs=0.05), p
    # failed designs (NaN) drop their whole block: the estimates keep their structure and their values
    y2 = y.copy()
    y2[5 * 4: 5 * 4 + 1] = np.nan                       # one row of block 5
    y2[100 * 4 + 3] = np.nan                            # and of block 100
    s2, dropped = T.sobol_indices(tols, y2, seed=2)
    assert dropped == 2
    assert s2["a"]["S1"] == pytest.approx(share["a"], abs=0.05)


def test_sobol_indices_of_the_transmission_angle_follow_the_hand_computed_rates():
    # small tolerances on l1 and l4: mu_min is linear in them to first order, with rates -k and +k (the
    # diagonal BD = l4 - l1), so its variance shares are V1^2 : V4^2 = 1 : 4
    mech = service.load("fourbar")
    r = ts.tolerance(mech, ["l1=±0.0005", "l4=±0.001"], samples=1000, seed=4, outputs="transmission_min",
                     sobol=True)
    s = r.summaries["transmission_min"]
    assert r.sobol_evaluations == 1024 * 4 and r.sobol_dropped == 0
    assert s.shares["l1"] == pytest.approx(0.2, rel=1e-6) and s.shares["l4"] == pytest.approx(0.8, rel=1e-6)
    for p, share in (("l1", 0.2), ("l4", 0.8)):
        # estimator error at N = 1024: ~ 0.03 (SALib's bootstrap half-width); nonlinearity ~ 1e-3
        assert s.sobol[p]["S1"] == pytest.approx(share, abs=0.06), p
        assert s.sobol[p]["ST"] == pytest.approx(share, abs=0.06), p


# ------------------------------------------------------------------------------ failures
def test_designs_that_cannot_assemble_are_counted_and_each_is_a_real_failure():
    # l1 uniform on [-0.1, 0.3]: l1 <= 0 is no crank; l1 > 0.25 makes l3 the shortest link, so the crank l1
    # cannot turn fully (Grashof): 0.1/0.4 + 0.05/0.4 = 37.5 % fail
    mech = service.load("fourbar")
    n = 1000
    r = ts.tolerance(mech, ["l1=±0.2"], samples=n, seed=7, outputs="path_deviation,transmission_min")
    l1 = L1 + r.deltas[:, 0]
    should_fail = (l1 <= 0) | (l1 > L3)
    failed = np.array([bool(x) for x in r.reasons])
    np.testing.assert_array_equal(failed, should_fail)          # every failure, and only those, by geometry
    assert r.failed == int(should_fail.sum())
    assert abs(r.failed - 0.375 * n) < 4 * math.sqrt(n * 0.375 * 0.625)   # binomial: 4 sigmas
    v = r.values["path_deviation"]
    assert np.all(np.isnan(v[failed])) and np.all(np.isfinite(v[~failed]))
    # the statistics are over the designs that assembled, never over NaN
    assert r.summaries["path_deviation"].mean == pytest.approx(float(np.mean(v[~failed])), rel=1e-12)
    assert any("cannot assemble" in x for x in r.reasons if x)


def test_cli_json_follows_spec_and_counts_failures(tmp_path):
    png = tmp_path / "tol.png"
    p = run("tolerance", "fourbar", "--tol", "l1=±0.2", "--tol", "l2=+-0.001", "--samples", "100", "--seed", "2",
            "--outputs", "path_deviation,transmission_min,peak_torque", "--sobol", "--json", "--plot", str(png))
    assert p.returncode == 0, p.stderr
    d = json.loads(p.stdout)
    assert d["samples"] == 100 and 0 < d["failed"] < 100
    assert set(d["outputs"]) == {"path_deviation", "transmission_min", "peak_torque"}
    for name, o in d["outputs"].items():
        for key in ("nominal", "mean", "std", "p05", "p95", "first_order_std"):
            assert isinstance(o[key], float), (name, key)
        assert set(o["sobol"]) == {"l1", "l2"} and set(o["sobol"]["l1"]) >= {"S1", "ST"}
    assert d["tolerances"]["l1"]["half_width"] == pytest.approx(0.2)
    assert d["failures"] and "reason" in d["failures"][0]
    assert png.stat().st_size > 20_000


def test_mm_file_tolerances_are_in_file_units_and_the_json_si(tmp_path):
    # the same four-bar in mm: a tolerance of 0.5 mm is the m file's 0.0005
    mm = tmp_path / "fb_mm.toml"
    mm.write_text(MM_FOURBAR)
    a = run("tolerance", str(mm), "--tol", "l1=±0.5", "--samples", "50", "--outputs", "transmission_min,"
            "path_deviation", "--json")
    b = run("tolerance", "fourbar", "--tol", "l1=±0.0005", "--samples", "50", "--outputs", "transmission_min,"
            "path_deviation", "--json")
    assert a.returncode == 0 and b.returncode == 0, a.stderr + b.stderr
    da, db = json.loads(a.stdout), json.loads(b.stdout)
    for name in ("transmission_min", "path_deviation"):
        for key in ("std", "first_order_std", "p95"):
            # same draws (same seed, same widths in file units), same geometry: rounding only
            assert da["outputs"][name][key] == pytest.approx(db["outputs"][name][key], rel=1e-9), (name, key)
        # rates per SI unit of the parameter (the same physical step; its rounding ~ 1e-16 / 1e-3 std ~ 1e-10)
        assert da["outputs"][name]["rates"]["l1"] == pytest.approx(db["outputs"][name]["rates"]["l1"], rel=1e-6)
    assert da["tolerances"]["l1"]["half_width"] == pytest.approx(0.0005, rel=1e-12)    # SI in the JSON


MM_FOURBAR = """
format = "linkage/1"
name = "fourbar_mm"
units = "mm"
output = "E"
[parameters]
l1 = 100.0
l2 = 300.0
l3 = 250.0
l4 = 300.0
[ground]
A = [0, 0]
D = ["l4", 0]
[[inputs]]
kind = "crank"
pivot = "A"
point = "B"
length = "l1"
link = "1"
phi0 = 0
omega = "360deg"
[[groups]]
kind = "RRR"
point = "C"
from = ["B", "D"]
lengths = ["l2", "l3"]
links = ["2", "3"]
branch = 1
[[groups]]
kind = "point"
point = "E"
on = ["B", "C"]
at = [150, 100]
"""


# ------------------------------------------------------------------------------ bad input
def test_tolerance_forms():
    nominal = {"l1": 0.1, "phi1_0": 0.5, "n": 3.0}
    kinds = {"l1": "length", "phi1_0": "angle", "n": "number"}
    cases = {"l1=±0.002": ("uniform", 0.002), "l1=+-0.002": ("uniform", 0.002), "l1=+/-2e-3": ("uniform", 0.002),
             "l1=±5%": ("uniform", 0.005), "l1=normal:0.001": ("normal", 0.001), "l1=normal:2%": ("normal", 0.002),
             "phi1_0=±1deg": ("uniform", math.radians(1)), "phi1_0=±10%": ("uniform", 0.05),
             "n = normal: 0.5": ("normal", 0.5)}
    for text, (dist, width) in cases.items():
        t = T.parse(text, nominal, kinds)
        assert (t.dist, t.name) == (dist, text.split("=")[0].strip()), text
        assert t.width == pytest.approx(width, rel=1e-12), text
    # standard deviations: uniform on [-V, V] has V/sqrt(3); normal has sigma
    assert T.parse("l1=±0.003", nominal, kinds).std == pytest.approx(0.003 / math.sqrt(3), rel=1e-15)
    assert T.parse("l1=normal:0.003", nominal, kinds).std == 0.003


@pytest.mark.parametrize("tol, words", [
    ("l9=±0.1", ["l9", "not a parameter"]),
    ("l1=0.1", ["l1", "±V"]),
    ("l1=±abc", ["l1", "not a number"]),
    ("l1=normal:-0.01", ["l1", "> 0"]),
    ("l1=±0", ["l1", "> 0"]),
    ("branch=±1", ["branch", "assembly branch"]),
    ("phi1_0=±1%", ["phi1_0", "absolute"]),
    ("l1=±1deg", ["l1", "length"]),
])
def test_bad_tolerance_is_one_line_and_exit_2(tol, words):
    p = run("tolerance", "fourbar", "--tol", tol, "--samples", "10")
    assert p.returncode == 2, p.stderr
    assert p.stdout == "" and len(p.stderr.strip().splitlines()) == 1 and "Traceback" not in p.stderr
    for w in words:
        assert w in p.stderr, (w, p.stderr)


@pytest.mark.parametrize("args, words", [
    (["--tol", "l1=±0.001", "--outputs", "path_deviation,bogus"], ["bogus", "path_deviation"]),
    (["--tol", "l1=±0.001", "--tol", "l1=±0.002"], ["l1", "twice"]),
    ([], ["--tol"]),
    (["--tol", "l1=±0.001", "--samples", "1"], ["--samples"]),
])
def test_bad_options_are_one_line_and_exit_2(args, words):
    p = run("tolerance", "fourbar", *args)
    assert p.returncode == 2, p.stderr
    assert len(p.stderr.strip().splitlines()) == 1 and "Traceback" not in p.stderr
    for w in words:
        assert w in p.stderr, (w, p.stderr)


def test_transmission_of_a_mechanism_without_one_is_refused():
    p = run("tolerance", "scotch_yoke", "--tol", "r=±0.001", "--outputs", "transmission_min")
    assert p.returncode == 2 and "transmission" in p.stderr and len(p.stderr.strip().splitlines()) == 1


# ------------------------------------------------------------------------------ Dask
@pytest.mark.slow
def test_a_dask_scheduler_gives_the_same_answer():
    distributed = pytest.importorskip("dask.distributed")
    mech = service.load("fourbar")
    args = (["l1=±0.0005", "l3=normal:0.0002"], 200, 11, "path_deviation,transmission_min,peak_torque")
    here = ts.tolerance(mech, *args, sobol=True)
    # a cluster in this process, reached by its scheduler's address as --scheduler ADDRESS would be
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:
        there = ts.tolerance(mech, *args, sobol=True, scheduler=cluster.scheduler_address)
        # the chunks ran on the cluster: 1 for the rates (5 designs), 1 for the 200 draws, 4 for the 256 x 4
        # Saltelli designs (chunks of 256)
        prefix = cluster.scheduler.task_prefixes["evaluate_chunk"]
        assert prefix.state_counts["memory"] == 6
    assert there.failed == here.failed == 0
    for name in here.outputs:
        # the same designs solved the same way on another worker: identical to rounding
        np.testing.assert_allclose(there.values[name], here.values[name], rtol=1e-12, atol=0)
        a, b = there.summaries[name], here.summaries[name]
        assert a.first_order_std == pytest.approx(b.first_order_std, rel=1e-12)
        for p in ("l1", "l3"):
            assert a.sobol[p]["S1"] == pytest.approx(b.sobol[p]["S1"], rel=1e-9, abs=1e-12)


def test_force_outputs_carry_the_files_loads_and_friction(tmp_path):
    # issue 41: tolerance refused peak_torque / peak_joint_force for a file with [[loads]] or [friction]; now its
    # nominal design's peaks are those `linkage forces` reports with the same spring and friction
    from pathlib import Path
    import cli_runner
    text = (Path(__file__).parent / "loads" / "spring.toml").read_text() + "[friction]\nmu = 0.2\npin_radius = 0.01\n"
    (tmp_path / "f.toml").write_text(text)
    r = cli_runner.run("tolerance", "f.toml", "--tol", "omega1=±1%", "--samples", "20", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)["outputs"]
    r = cli_runner.run("forces", "f.toml", "--json", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    torque = max(float(np.max(np.abs(v))) for v in d["drives"].values())
    joint = max(float(np.max(np.hypot(j["Fx"], j["Fy"]))) for j in d["joints"])
    bare = json.loads(cli_runner.run("forces", "fourbar", "--json").stdout)          # no spring, no friction
    assert torque > 2 * max(float(np.max(np.abs(v))) for v in bare["drives"].values())   # the loads matter
    # 1e-9: the same 361 samples of the same motion, the friction's fixed point stopped at 1e-12 of the peak
    assert out["peak_torque"]["nominal"] == pytest.approx(torque, rel=1e-9)
    assert out["peak_joint_force"]["nominal"] == pytest.approx(joint, rel=1e-9)
