"""Can the tests fail? A small mutation check: each mutation is applied to a temporary COPY of the
project, the relevant test files run there, and the mutation is KILLED (good: a test failed) or SURVIVES
(bad: nothing noticed it).

Run:  python benchmarks/mutation.py [--only ID ...] [--list] [--keep] [--timeout S]

The copy holds the repository's tracked and untracked (not ignored) files, as ``git ls-files -co
--exclude-standard`` lists them, in /tmp/mut-XXXX; the real files are never written. Each mutation is an
exact string replacement in one file of a fresh copy of it (refused, and reported as NOT APPLIED, if the
text is not found the expected number of times: the code moved on). Tests run as
``python -m pytest -x -q -p no:cacheprovider FILES`` from the copy's root with ``PYTHONPATH=<copy>``
first on the path (the package is installed editable from the real tree: the copy must shadow it; this
is checked once by printing ``analytic.__file__``), ``LINKAGE_JIT=0`` (the numpy solver, the one the
mutations edit) and ``MUJOCO_GL=egl``. Tests that fail on the unmutated copy are deselected everywhere.

For the solver's formulas (analytic/solver/kinematics.py) the compiled path (analytic/solver/jit.py) mirrors every
formula, so tests/test_solver_paths.py kills any such mutation by comparing the two paths; that says
nothing about whether the formula is right, so it is run apart and shown in its own column, and the
verdict comes from the tests that check the physics.
"""

from __future__ import annotations

import argparse
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

CV = "tests/test_cross_validation.py"
GS = "tests/test_general_solver.py"
LIB = "tests/test_library.py"
CLI_A = "tests/test_cli_analyze.py"
CLI_S = "tests/test_cli_simulate.py"
DYN = "tests/test_dynamics.py"
MOD = "tests/test_models.py"
NEWTON = "tests/test_analytic_vs_newton.py"
FD = "tests/test_rates_vs_finite_differences.py"
GEOM = "tests/test_fourbar_geometry.py"
PATHS = "tests/test_solver_paths.py"
KIN_TESTS = [GS, LIB, NEWTON, FD, GEOM, CV]


@dataclass(frozen=True)
class Mutation:
    id: str
    what: str
    file: str
    old: str
    new: str
    tests: list
    should_catch: str
    count: int = 1
    mirror: list = field(default_factory=list)
    """Tests that compare two copies of the same formulas (shown apart, not part of the verdict)."""


def _tol(name: str, value: str, loose: str, extra_tests=(), should=""):
    return Mutation(f"tol-{name}", f"sim/run/compare.py {name} loosened 10x ({value} -> {loose})", "sim/run/compare.py",
                    f"{name} = {value}\n", f"{name} = {loose}\n", [CV, *extra_tests],
                    should or f"tests/test_cross_validation.py should pin {name} (e.g. compare the comparison's "
                                f"own tolerance with the pinned value, or run a case whose error lies between "
                                f"the two)")


MUTATIONS = [
    _tol("ANGLE_TOL", "1e-6", "1e-5"),
    _tol("POSITION_TOL", "1e-6", "1e-5"),
    _tol("VELOCITY_TOL", "1e-5", "1e-4"),
    _tol("ACCELERATION_TOL", "1e-3", "1e-2"),
    _tol("LOOP_TOL", "1e-6", "1e-5", [CLI_S],
         "test_cross_validation.test_simulation_matches_analytic checks max_loop_violation against its pinned "
         "LOOP directly, never the code's LOOP_TOL: it should also assert c.as_dict(built)['loop_tol'] <= "
         "LOOP * size (or that a run with a violation between the two fails)"),
    _tol("DRIVE_TOL", "1e-4", "1e-3", [CLI_S],
         "test_cross_validation.test_simulation_matches_analytic checks drive_error against its pinned DRIVE "
         "directly, never the code's DRIVE_TOL: it should also assert c.as_dict(built)['drive_tol'] <= DRIVE"),
    _tol("TORQUE_TOL", "5e-3", "5e-2", [DYN]),
    _tol("WORK_TOL", "1e-3", "1e-2", [DYN, CLI_S],
         "test_cross_validation.test_fifty_revolutions_keep_every_error_flat checks work_balance <= 1e-3 "
         "itself; nothing pins the code's WORK_TOL: a test should assert c.as_dict(built)['work_tol'] <= 1e-3"),
    # --- an output dropped
    Mutation("out-mu-fourbar", "'mu' dropped from the four-bar's SPEC outputs (analytic/closed_forms/fourbar.py OUTPUTS)",
             "analytic/closed_forms/fourbar.py", '"axE", "ayE", "mu")', '"axE", "ayE")', [CLI_A, GS, CV],
             "tests/test_cli_analyze.py::test_csv_has_time_inputs_and_every_spec_output compares the header "
             "with module.OUTPUTS, the very tuple mutated: it should pin SPEC's literal column list"),
    Mutation("out-mu-general", "transmission angles muP dropped from every library mechanism's outputs "
             "(Mechanism.general_outputs)", "analytic/mechanism.py",
             "        out += [f\"mu{e['point']}\" for e in self.geometry.elements if e[\"kind\"] == \"RRR\"]\n",
             "", [CLI_A, GS, LIB, CV],
             "tests/test_library.py's transmission-angle test iterates over general_outputs (empty after the "
             "mutation); a test should require muP among a library mechanism's outputs / analyze CSV columns"),
    Mutation("out-csv-columns", "mu columns left out of the analyze CSV (service.analysis_columns)",
             "sim/service.py", "**{k: np.asarray(a.solution[k]) for k in mech.outputs}}",
             "**{k: np.asarray(a.solution[k]) for k in mech.outputs if not k.startswith(\"mu\")}}",
             [CLI_A], "tests/test_cli_analyze.py (CSV header of the four-bar)"),
    # --- a formula perturbed by 1e-6 relative (the numpy solver)
    Mutation("kin-rrr-alpha", "RRR group: alpha of the first link x (1 + 1e-6) (kinematics._rrr)",
             "analytic/solver/kinematics.py", "    al1 *= idet\n", "    al1 *= idet * (1.0 + 1e-6)\n", KIN_TESTS,
             "tests/test_library.py / test_analytic_vs_newton.py (accelerations to RATE_TOL 1e-9 of the peak)",
             mirror=[PATHS]),
    Mutation("kin-rrr-omega", "RRR group: omega of the second link x (1 + 1e-6) (kinematics._rrr)",
             "analytic/solver/kinematics.py", "    w2 *= idet\n", "    w2 *= idet * (1.0 + 1e-6)\n", KIN_TESTS,
             "tests/test_library.py / test_analytic_vs_newton.py (link rates to RATE_TOL 1e-9)", mirror=[PATHS]),
    Mutation("kin-rpr-coriolis", "RPR group: Coriolis term 2 ds w x (1 + 1e-6) (kinematics._rpr)",
             "analytic/solver/kinematics.py", "- 2.0 * ds * w + offset * w * w) / s",
             "- 2.0 * (1.0 + 1e-6) * ds * w + offset * w * w) / s", KIN_TESTS,
             "tests/test_library.py (inverted_slider_crank, whitworth) or the five-bar's closed-form check",
             mirror=[PATHS]),
    Mutation("kin-rrp-coriolis", "RRP group: Coriolis term 2 ds w x (1 + 1e-6) (kinematics._rrp)",
             "analytic/solver/kinematics.py", "ax0, ay0 = C0[4] - 2.0 * ds * w * s, C0[5] + 2.0 * ds * w * c",
             "ax0, ay0 = C0[4] - 2.0 * (1.0 + 1e-6) * ds * w * s, C0[5] + 2.0 * (1.0 + 1e-6) * ds * w * c",
             KIN_TESTS, "a test with a block on a turning guide (RRP on a moving line): test_library if a library "
                        "file has one, else nothing", mirror=[PATHS]),
    Mutation("kin-crank-velocity", "crank tip velocity x (1 + 1e-6) (kinematics._crank)",
             "analytic/solver/kinematics.py", "P[2] - qd * ry, P[3] + qd * rx, ax, ay)",
             "P[2] - qd * (1.0 + 1e-6) * ry, P[3] + qd * (1.0 + 1e-6) * rx, ax, ay)", KIN_TESTS,
             "tests/test_library.py / test_analytic_vs_newton.py / test_general_solver.py (velocities to 1e-9)",
             mirror=[PATHS]),
    # --- inverse dynamics
    Mutation("torque-mass-1e-6", "inverse dynamics: every link's m (a - g).dv term x (1 + 1e-6) "
             "(torque.drive_forces)", "analytic/applications/torque.py", "tau = tau + b.m * ((agx - gx) * cvx",
             "tau = tau + b.m * (1.0 + 1e-6) * ((agx - gx) * cvx", [DYN, CV],
             "tests/test_dynamics.py (the general inverse dynamics against analytic.closed_forms.dynamics.torques or the "
             "power balance, at rounding level)"),
    Mutation("torque-com-1pct", "inverse dynamics: centre-of-mass offset 1 % too far (torque._com)",
             "analytic/applications/torque.py", "rx, ry = b.cx * c - b.cy * s, b.cx * s + b.cy * c",
             "rx, ry = 1.01 * (b.cx * c - b.cy * s), 1.01 * (b.cx * s + b.cy * c)", [DYN, CV],
             "tests/test_dynamics.py (MuJoCo's actuator torque against torque.drive_forces, or the dedicated "
             "torques)"),
    Mutation("torque-inertia-1pct", "inverse dynamics: moment of inertia term x 1.01 (torque.drive_forces)",
             "analytic/applications/torque.py", "b.I * sol[\"alpha\" + link] * coeff[\"omega\" + link]",
             "1.01 * b.I * sol[\"alpha\" + link] * coeff[\"omega\" + link]", [DYN, CV],
             "tests/test_dynamics.py"),
    # --- the drives
    Mutation("servo-budget-1000x", "sim/model/drives.py DRIVE_ERROR_BUDGET 1000x larger (a soft servo)", "sim/model/drives.py",
             "DRIVE_ERROR_BUDGET = 1e-6\n", "DRIVE_ERROR_BUDGET = 1e-3\n", [CV, MOD, DYN],
             "tests/test_cross_validation.py (drive error against DRIVE)"),
    Mutation("step-angle-10x", "sim/model/timestep.py STEP_ANGLE 10x larger (0.03 -> 0.3 rad per step)", "sim/model/timestep.py",
             "STEP_ANGLE = 0.03\n", "STEP_ANGLE = 0.3\n", [CV, MOD],
             "tests/test_cross_validation.py::test_the_simulation_records_what_happened (h <= 0.03 / Omega)"),
    Mutation("rate-no-zoom", "sim/model/timestep.py: the fastest rate from the 720-sample scan only (RATE_ZOOMS 0)",
             "sim/model/timestep.py", "RATE_ZOOMS = 8\n", "RATE_ZOOMS = 0\n", [CV],
             "tests/test_cross_validation.py::test_the_step_follows_a_peak_that_falls_between_samples"),
    Mutation("rate-first-turn", "sim/model/timestep.py: the step chosen from the first revolution of the run only",
             "sim/model/timestep.py", "omega = rate_scale(mech, revolutions)\n", "omega = rate_scale(mech, min(revolutions, 1.0))\n",
             [CV], "tests/test_cross_validation.py::test_the_step_follows_the_fastest_revolution_of_an_accelerating_run"),
    Mutation("regulariser-ignores-loads", "sim/model/build.py: the constraint regulariser not reduced for loads",
             "sim/model/build.py", "return REGULARIZATION_SCALE / (1.0 + load / inertial) if inertial > 0",
             "return REGULARIZATION_SCALE / (1.0 + 0 * load / inertial) if inertial > 0", [CV],
             "tests/test_cross_validation.py::test_loads_far_above_the_inertial_forces_keep_the_accuracy"),
    Mutation("regulariser-100x", "sim/model/build.py REGULARIZATION_SCALE 100x larger (1e-6 -> 1e-4, the old value)",
             "sim/model/build.py", "REGULARIZATION_SCALE = 1e-6\n", "REGULARIZATION_SCALE = 1e-4\n", [CV],
             "tests/test_cross_validation.py (the near-singular Whitworth case)"),
    Mutation("loop-timeconst-16x", "sim/model/settings.py LOOP_TIMECONST 16x shorter (32 -> 2 steps: a drift correction "
             "RK4 cannot follow; 8 steps only triples the errors, all within tolerance)", "sim/model/settings.py",
             "LOOP_TIMECONST = 32.0\n", "LOOP_TIMECONST = 2.0\n", [CV, MOD],
             "tests/test_cross_validation.py"),
    # --- units of results (SPEC "Units of results")
    Mutation("display-inch", "analytic/quantities.py: the inch as 25 mm", "analytic/quantities.py",
             '"in": 0.0254}', '"in": 0.025}', ["tests/test_units.py"], "tests/test_units.py (JSON --units in, by hand)"),
    Mutation("display-rpm-inverted", "analytic/quantities.py: rpm per rad/s inverted", "analytic/quantities.py",
             "RPM = 60.0 / (2.0 * math.pi)", "RPM = 2.0 * math.pi / 60.0", ["tests/test_units.py"],
             "tests/test_units.py (CSV --speeds rpm: 360 deg/s is 60 rpm)"),
    Mutation("inertia-option-in-si", "sim/front/cli.py: --inertia read in SI, not in the file's unit", "sim/front/cli.py",
             "inertias[link] = Inertia(m=given.m, cx=given.cx * s, cy=given.cy * s, I=given.I * s * s)",
             "inertias[link] = given", ["tests/test_units.py"],
             "tests/test_units.py::test_inertia_file_is_read_in_the_file_unit_like_the_inertia_table"),
    Mutation("sheet-figures-from-samples", "sim/output/plot.py: the sheet's figures from the simulated samples",
             "sim/output/plot.py", "figs = service.figures(mech)", "figs = figures.of(mech, c.analytic)", ["tests/test_units.py"],
             "tests/test_units.py::test_plot_sheet_figures_are_analyze_figures_and_the_hand_value"),
]


# ------------------------------------------------------------------------------------------- the copy
def repo_files(root: Path) -> list[str]:
    out = subprocess.run(["git", "-C", str(root), "ls-files", "-co", "--exclude-standard", "-z"],
                         capture_output=True, check=True).stdout.decode()
    return [f for f in out.split("\0") if f and (root / f).is_file()]


def make_copy(root: Path, dest: Path, files: list[str]) -> None:
    for f in files:
        target = dest / f
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(root / f, target)


def env_for(copy: Path) -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(copy) + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    env["LINKAGE_JIT"] = "0"
    env["MUJOCO_GL"] = env.get("MUJOCO_GL", "egl")
    env["PYTHONDONTWRITEBYTECODE"] = "1"
    return env


def check_imports(copy: Path) -> str:
    r = subprocess.run([sys.executable, "-c", "import analytic, sim; print(analytic.__file__); print(sim.__file__)"],
                       cwd=copy, env=env_for(copy), capture_output=True, text=True)
    where = r.stdout.split()
    if r.returncode != 0 or len(where) != 2 or not all(Path(w).resolve().is_relative_to(copy.resolve()) for w in where):
        raise SystemExit(f"the copy does not shadow the installed package: {r.stdout} {r.stderr}")
    return where[0]


def child_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def pytest(copy: Path, tests: list, timeout: float, deselect=(), stop_first=True) -> dict:
    cmd = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-W", "ignore::DeprecationWarning"]
    if stop_first:
        cmd.append("-x")
    cmd += [t for t in tests if (copy / t).exists()]
    for d in deselect:
        cmd += ["--deselect", d]
    w0, c0 = time.time(), child_cpu()
    try:
        r = subprocess.run(cmd, cwd=copy, env=env_for(copy), capture_output=True, text=True, timeout=timeout)
        rc, out = r.returncode, r.stdout + r.stderr
    except subprocess.TimeoutExpired as exc:
        rc, out = None, (exc.stdout or b"").decode(errors="replace") if isinstance(exc.stdout, bytes) else (exc.stdout or "")
    failed = [f.strip() for f in re.findall(r"^(?:FAILED|ERROR) (.+?)(?: - .*)?$", out, flags=re.M)]
    summary = next((ln for ln in reversed(out.splitlines()) if re.search(r"passed|failed|error|no tests", ln)), "")
    return {"rc": rc, "failed": failed, "summary": summary.strip("= "), "wall": time.time() - w0,
            "cpu": child_cpu() - c0, "out": out}


def verdict(res: dict) -> str:
    rc = res["rc"]
    if rc is None:
        return "TIMEOUT"
    if rc == 0:
        return "SURVIVED"
    if rc == 1:
        return "killed"
    if rc == 2:
        return "killed (errors)"
    return f"rc {rc}"


# ------------------------------------------------------------------------------------------- the run
def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="*", help="mutation ids to run (default: all)")
    ap.add_argument("--list", action="store_true", help="list the mutations and exit")
    ap.add_argument("--timeout", type=float, default=480.0, help="per pytest run [s] (default 480)")
    ap.add_argument("--no-baseline", action="store_true", help="skip the run of the unmutated copy")
    ap.add_argument("--no-mirror", action="store_true", help="skip tests/test_solver_paths.py runs")
    ap.add_argument("--keep", action="store_true", help="keep the temporary copy")
    args = ap.parse_args(argv)
    muts = [m for m in MUTATIONS if not args.only or m.id in args.only]
    if args.list:
        for m in MUTATIONS:
            print(f"{m.id:<22s} {m.what}\n{'':<22s} tests: {' '.join(Path(t).name for t in m.tests)}")
        return 0
    t_all, c_all = time.time(), child_cpu() + time.process_time()
    tmp = Path(tempfile.mkdtemp(prefix="mut-", dir="/tmp"))
    try:
        files = repo_files(ROOT)
        base = tmp / "base"
        make_copy(ROOT, base, files)
        print(f"copy of {len(files)} files in {base}; imports from {check_imports(base)}", flush=True)
        deselect = []
        if not args.no_baseline:
            union = sorted({t for m in muts for t in m.tests})
            base_res = pytest(base, union, args.timeout, stop_first=False)
            deselect = base_res["failed"]
            print(f"baseline (unmutated copy), {len(union)} files: {base_res['summary']} in {base_res['wall']:.0f} s"
                  + (f"; deselected as failing already: {', '.join(deselect)}" if deselect else ""), flush=True)
            if base_res["rc"] not in (0, 1):
                print(base_res["out"][-3000:])
                raise SystemExit("the baseline run did not complete: fix the tests before mutating")
        rows = []
        for m in muts:
            work = tmp / m.id
            shutil.copytree(base, work)
            path = work / m.file
            text = path.read_text()
            n = text.count(m.old)
            if n != m.count:
                rows.append((m, None, None, f"NOT APPLIED ({n} matches)"))
                print(f"{m.id:<22s} NOT APPLIED: the text occurs {n} times in {m.file}", flush=True)
                shutil.rmtree(work, ignore_errors=True)
                continue
            path.write_text(text.replace(m.old, m.new))
            res = pytest(work, m.tests, args.timeout, deselect)
            mir = pytest(work, m.mirror, args.timeout) if m.mirror and not args.no_mirror else None
            v = verdict(res)
            rows.append((m, res, mir, v))
            by = f" by {res['failed'][0]}" if res["failed"] else ""
            print(f"{m.id:<22s} {v}{by}  [{res['summary']}; {res['wall']:.0f} s]"
                  + (f"  mirror: {verdict(mir)}" if mir else ""), flush=True)
            if not args.keep:
                shutil.rmtree(work, ignore_errors=True)
        table(rows)
    finally:
        if not args.keep:
            shutil.rmtree(tmp, ignore_errors=True)
        else:
            print(f"kept {tmp}")
    print(f"\ntotal: {time.time() - t_all:.0f} s wall, {child_cpu() + time.process_time() - c_all:.0f} s CPU")
    return 0


SHORT = {CV: "cv", GS: "gs", LIB: "lib", CLI_A: "cli_a", CLI_S: "cli_s", DYN: "dyn", MOD: "mod", NEWTON: "newton",
         FD: "fd", GEOM: "geom", PATHS: "paths"}


def table(rows) -> None:
    print("\ntest files: " + ", ".join(f"{v}={Path(k).name}" for k, v in SHORT.items()))
    print(f"{'mutation':<22s} {'tests run':<30s} {'result':<16s} {'wall s':>6s} {'cpu s':>6s}  {'mirror':<9s} "
          f"first failing test")
    for m, res, mir, v in rows:
        tests = ",".join(SHORT.get(t, Path(t).stem) for t in m.tests)
        if res is None:
            print(f"{m.id:<22s} {tests:<30s} {v:<16s}")
            continue
        first = res["failed"][0].replace("tests/", "") if res["failed"] else ""
        print(f"{m.id:<22s} {tests:<30s} {v:<16s} {res['wall']:6.0f} {res['cpu']:6.0f}  "
              f"{verdict(mir) if mir else '-':<9s} {first}")
    survivors = [(m, v) for m, res, mir, v in rows if v == "SURVIVED"]
    killed = sum(1 for _, _, _, v in rows if v.startswith("killed"))
    print(f"\nkilled {killed} of {len(rows)}; survived {len(survivors)}")
    if survivors:
        print("\nsurvivors and the test that should have caught them:")
        for m, _ in survivors:
            print(f"  {m.id}: {m.what}\n    -> {m.should_catch}")


if __name__ == "__main__":
    sys.exit(main())
