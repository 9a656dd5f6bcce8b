"""Can the tests fail? A small mutation check: each mutation is applied to a temporary COPY of the
project, the relevant test files run there, and the mutation is KILLED (good: a test failed) or SURVIVES
(bad: nothing noticed it).

Run:  PYTHONPATH=$PWD python benchmarks/mutation.py [--only ID ...] [--list] [--keep] [--timeout S]
      [--without TEST_FILE ...]   (the kill count without some test files: what the suite caught before them)

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
from dataclasses import dataclass, field, replace
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
KINDS = "tests/test_kinds.py"
KIN_TESTS = [GS, LIB, NEWTON, FD, GEOM, CV, KINDS]
UNITS = "tests/test_units.py"
INDEP = "tests/test_independent.py"
EDGES = "tests/test_edges.py"
NEAR = "tests/test_near_singular.py"
TOML = "tests/test_export_toml_units.py"
SWEEP = "tests/test_sweep.py"
BAD = "tests/test_bad_inputs.py"
FV = "tests/test_forces_verdict.py"
MEAS = "tests/test_measures_on_known_poses.py"
SV = "tests/test_singularity_values.py"
CMD = "tests/test_commanded_columns.py"
GEARS = "tests/test_gears_accelerating.py"
FLY = "tests/test_flywheel_energy.py"
LAWS = "tests/test_motion_laws.py"
LAW_EVAL = "tests/test_law_evaluation.py"
CYL_SIZE = "tests/test_cylinder_sizing.py"
CYL_DYN = "tests/test_cylinder_dynamics.py"
DRIVES = "tests/test_drives.py"
DRIVES_CF = "tests/test_drives_closed_form.py"
CAMS = "tests/test_cams.py"
CAM_MECH = "tests/test_cam_mechanism.py"
LOAD_KINDS = "tests/test_load_kinds.py"
LOADS_EL = "tests/test_loads_elements.py"
WINDOW = "tests/test_load_window_work.py"
DRIVE_TORQUE = "tests/test_drive_torque.py"
SYN_BUILD = "tests/test_synthesis_buildable.py"
LAWS_SETUPS = "tests/test_load_laws_setups.py"
CAM_CONTACT = "tests/test_cam_contact.py"
TOLERANCE = "tests/test_tolerance.py"
TWO = "tests/test_parts_two_plates.py"
MASS1 = "tests/test_one_mass_truth.py"
MRI = "tests/test_motor_relative_import.py"
SOLVES = "tests/test_solve_counts.py"
STARTUP = "tests/test_startup_imports.py"
APP_CAM = "tests/test_app_cam.py"
TWO_RULES = "tests/test_two_plate_rules.py"
CAM_FACE = "tests/test_cam_face_and_windows.py"
PANEL = "tests/test_cam_panel_units.py"
GUARDS = "tests/test_shared_solve_guards.py"
EVALS = "tests/test_compare_evaluations.py"
FMJ = "tests/test_forces_mujoco.py"
RFAULTS = "tests/test_replay_faults.py"
REPLAY = [RFAULTS, EVALS, FMJ, CAM_MECH, CV, CLI_S, INDEP, FV, DYN, EDGES, "tests/test_drives_cycle.py",
          "tests/test_forces.py", "tests/test_loads_mujoco.py", "tests/test_cam_contact.py"]
"""The forces replay and the work balance's end-of-step evaluations it carries (sim/run/simulate.py replay,
sim/run/forces.py reader, sim/run/compare.py end_evaluations): the test files that run them."""


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
             "        out += self.extra_outputs\n", "", [CLI_A, GS, LIB, CV],
             "tests/test_library.py's transmission-angle test iterates over general_outputs (empty after the "
             "mutation); a test should require muP among a library mechanism's outputs / analyze CSV columns"),
    Mutation("out-csv-columns", "mu columns left out of the analyze CSV (service.analysis_columns)",
             "sim/service/analysis.py", "**{k: np.asarray(a.solution[k]) for k in mech.outputs}}",
             "**{k: np.asarray(a.solution[k]) for k in mech.outputs if not k.startswith(\"mu\")}}",
             [CLI_A], "tests/test_cli_analyze.py (CSV header of the four-bar)"),
    # --- a formula perturbed by 1e-6 relative (the numpy solver)
    Mutation("kin-rrr-alpha", "RRR group: alpha of the first link x (1 + 1e-6) (kinds/rrr.py rrr)",
             "analytic/kinds/rrr.py", "    al1 *= idet\n", "    al1 *= idet * (1.0 + 1e-6)\n", KIN_TESTS,
             "tests/test_library.py / test_analytic_vs_newton.py (accelerations to RATE_TOL 1e-9 of the peak)",
             mirror=[PATHS]),
    Mutation("kin-rrr-omega", "RRR group: omega of the second link x (1 + 1e-6) (kinds/rrr.py rrr)",
             "analytic/kinds/rrr.py", "    w2 *= idet\n", "    w2 *= idet * (1.0 + 1e-6)\n", KIN_TESTS,
             "tests/test_library.py / test_analytic_vs_newton.py (link rates to RATE_TOL 1e-9)", mirror=[PATHS]),
    Mutation("kin-rpr-coriolis", "RPR group: Coriolis term 2 ds w x (1 + 1e-6) (kinds/rpr.py, numpy)",
             "analytic/kinds/rpr.py", "\n    a = (-adx * sn + ady * c - 2.0 * ds * w + offset * w * w) / s",
             "\n    a = (-adx * sn + ady * c - 2.0 * (1.0 + 1e-6) * ds * w + offset * w * w) / s", KIN_TESTS,
             "tests/test_library.py (inverted_slider_crank, whitworth) or the five-bar's closed-form check",
             mirror=[PATHS]),
    Mutation("kin-rrp-coriolis", "RRP group: Coriolis term 2 ds w x (1 + 1e-6) (kinds/rrp.py, numpy)",
             "analytic/kinds/rrp.py", "ax0, ay0 = C0[4] - 2.0 * ds * w * s, C0[5] + 2.0 * ds * w * c",
             "ax0, ay0 = C0[4] - 2.0 * (1.0 + 1e-6) * ds * w * s, C0[5] + 2.0 * (1.0 + 1e-6) * ds * w * c",
             KIN_TESTS, "a block on a turning guide (RRP on a moving line): tests/kinds/rrp*.toml in test_kinds",
             mirror=[PATHS]),
    Mutation("kin-crank-velocity", "crank tip velocity x (1 + 1e-6) (kinds/crank.py)",
             "analytic/kinds/crank.py", "P[2] - qd * ry, P[3] + qd * rx, ax, ay)",
             "P[2] - qd * (1.0 + 1e-6) * ry, P[3] + qd * (1.0 + 1e-6) * rx, ax, ay)", KIN_TESTS,
             "tests/test_library.py / test_analytic_vs_newton.py / test_general_solver.py (velocities to 1e-9)",
             mirror=[PATHS]),
    # --- inverse dynamics
    Mutation("torque-mass-1e-6", "inverse dynamics: every link's m (a - g).dv term x (1 + 1e-6) "
             "(torque.drive_forces)", "analytic/applications/torque.py", "tau = tau + b.m * ((agx - gx) * cvx",
             "tau = tau + b.m * (1.0 + 1e-6) * ((agx - gx) * cvx", [DYN, CV],
             "tests/test_dynamics.py (the general inverse dynamics against tests/builtin_dynamics.py's torques or the "
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
    Mutation("step-angle-10x", "sim/model/timestep.py STEP_ANGLE 10x larger (0.025 -> 0.25 rad per step)", "sim/model/timestep.py",
             "STEP_ANGLE = 0.025\n", "STEP_ANGLE = 0.25\n", [CV, MOD],
             "tests/test_cross_validation.py::test_the_simulation_records_what_happened (h <= 0.03 / Omega)"),
    Mutation("rate-no-zoom", "analytic/cycle.py: the fastest rate from the dense scan only (REFINE 0: no samples added "
             "at the peaks)", "analytic/cycle.py", "REFINE = 256\n", "REFINE = 0\n", [CV],
             "tests/test_cross_validation.py::test_the_step_follows_a_peak_that_falls_between_samples"),
    Mutation("rate-first-turn", "analytic/cycle.py: the cycle (and the step chosen from it) over the first revolution of "
             "the run only", "analytic/cycle.py", "span = 1.0 if periodic(mech) else float(revolutions)\n",
             "span = 1.0\n",
             [CV], "tests/test_cross_validation.py::test_the_step_follows_the_fastest_revolution_of_an_accelerating_run"),
    Mutation("regulariser-ignores-loads", "sim/model/build.py: the constraint regulariser not reduced for loads",
             "sim/model/build.py", "scale = REGULARIZATION_SCALE / (1.0 + load / inertial) if inertial > 0",
             "scale = REGULARIZATION_SCALE / (1.0 + 0 * load / inertial) if inertial > 0", [CV],
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
    Mutation("inertia-option-in-si", "sim/front/cli/options.py: --inertia read in SI, not in the file's unit", "sim/front/cli/options.py",
             "inertias[link] = Inertia(m=given.m, cx=given.cx * s, cy=given.cy * s, I=given.I * s * s)",
             "inertias[link] = given", ["tests/test_units.py"],
             "tests/test_units.py::test_inertia_file_is_read_in_the_file_unit_like_the_inertia_table"),
    Mutation("sheet-figures-from-samples", "sim/output/plot.py: the sheet's figures from the simulated samples",
             "sim/output/plot.py", "figs = service.figures(mech)", "figs = figures.of(mech, c.analytic)", ["tests/test_units.py"],
             "tests/test_units.py::test_plot_sheet_figures_are_analyze_figures_and_the_hand_value"),
    # --- issue 20's survivors (an audit's six faults): loads, verdicts, mm guides, sweep metrics
    Mutation("force-opposite", "sim/front/cli/options.py loads_from: the --force applied in the opposite direction (both sides "
             "of compare read the same model)", "sim/front/cli/options.py", 'force = pair("--force", force_text) or (0.0, 0.0)',
             'force = tuple(-v for v in pair("--force", force_text) or (0.0, 0.0))', [INDEP, CLI_S],
             "tests/test_independent.py::test_a_force_on_the_output_point_is_applied_as_given (power balance)"),
    Mutation("gravity-opposite", "sim/front/cli/options.py loads_from: --gravity applied upwards", "sim/front/cli/options.py",
             'gravity = pair("--gravity", args.gravity)',
             'gravity = tuple(-v for v in pair("--gravity", args.gravity)) if args.gravity else None', [INDEP, CLI_S],
             "tests/test_independent.py::test_gravity_is_applied_downwards_as_given (tau = m g cx cos phi)"),
    Mutation("cutting-assists", "sim/service/loads.py cutting_direction: the cutting force pushes the ram along its slow "
             "stroke instead of resisting it", "sim/service/loads.py", "return -math.copysign(1.0, vx)",
             "return math.copysign(1.0, vx)", [INDEP, CLI_S],
             "tests/test_independent.py::test_a_cutting_force_resists_the_slow_stroke (work = F H)"),
    Mutation("verdict-ignores-torque", "sim/run/compare.py: the verdict ignores the drive torque", "sim/run/compare.py",
             "        ok &= passed\n", '        ok &= passed or kind == "force"\n', [CV, INDEP],
             "tests/test_independent.py::test_the_verdict_fails_when_the_drive_torque_is_off"),
    Mutation("verdict-ignores-loop", "sim/run/compare.py: the verdict ignores the loop violation", "sim/run/compare.py",
             "    ok &= drive <= DRIVE_TOL and viol <= LOOP_TOL * mech.size and balance <= WORK_TOL",
             "    ok &= drive <= DRIVE_TOL and balance <= WORK_TOL", [CV, INDEP],
             "tests/test_independent.py::test_the_verdict_fails_when_a_loop_opens"),
    Mutation("verdict-ignores-drive", "sim/run/compare.py: the verdict ignores the drive error", "sim/run/compare.py",
             "    ok &= drive <= DRIVE_TOL and viol <= LOOP_TOL * mech.size and balance <= WORK_TOL",
             "    ok &= viol <= LOOP_TOL * mech.size and balance <= WORK_TOL", [CV, INDEP],
             "tests/test_independent.py::test_the_verdict_fails_when_the_drive_lags"),
    Mutation("guide-through-unscaled", "analytic/format/linkfile.py resolve: a ground guide's through = [x, y] not "
             "converted from the file's unit", "analytic/format/linkfile.py",
             'tuple(num(c, "length", where) for c in v.through)', 'tuple(num(c, "number", where) for c in v.through)',
             [INDEP, UNITS, LIB], "tests/test_independent.py::test_a_guide_through_coordinates_in_a_mm_file_is_in_mm"),
    Mutation("sweep-fluct-over-max", "analytic/applications/studies.py: the fluctuation divided by the max speed, not "
             "the mean", "analytic/applications/studies.py",
             "fluct = (speed.max(axis=-1) - speed.min(axis=-1)) / mean",
             "fluct = (speed.max(axis=-1) - speed.min(axis=-1)) / speed.max(axis=-1)", [INDEP, SWEEP],
             "tests/test_independent.py::test_sweep_metrics_by_hand_from_analyze"),
    Mutation("sweep-mu-max", "analytic/applications/studies.py: mu_min taken as the largest transmission angle",
             "analytic/applications/studies.py", 'stats["mu_min"] = np.min([sol[n] for n in want[4:]], axis=(0, 2))',
             'stats["mu_min"] = np.max([sol[n] for n in want[4:]], axis=(0, 2))', [INDEP, SWEEP],
             "tests/test_independent.py::test_sweep_metrics_by_hand_from_analyze (the textbook extremes)"),
    Mutation("set-overrides-vary", "sim/service/design.py: --set and --vary of one parameter accepted silently",
             "sim/service/design.py", "            if name in mech.overrides:\n", "            if False:\n",
             [INDEP, SWEEP], "tests/test_independent.py::test_set_and_vary_of_one_parameter_is_refused"),
    Mutation("range-input-at-rest", "sim/service/analysis.py analyze: an input range samples the input at rest (zero rates "
             "everywhere)", "sim/service/analysis.py", "q[:, 0], qd[:, 0], qdd[:, 0] = q1, first.motion.rate, 0.0",
             "q[:, 0], qd[:, 0], qdd[:, 0] = q1, 0.0, 0.0", [INDEP, CLI_A],
             "tests/test_independent.py::test_an_input_range_moves_the_input_at_its_speed"),
    Mutation("compiled-never-taken", "analytic/mechanism.py: the compiled path never taken", "analytic/mechanism.py",
             "if jit.enabled(n) and jit.supports(geometry):", "if False and jit.enabled(n) and jit.supports(geometry):",
             [INDEP, PATHS], "tests/test_independent.py::test_the_compiled_path_is_taken_when_asked"),
    Mutation("with-values-merge-order", "analytic/mechanism.py with_values: the old overrides win over the new",
             "analytic/mechanism.py", "merged = {**self.overrides, **overrides}", "merged = {**overrides, **self.overrides}",
             [INDEP], "tests/test_independent.py::test_with_values_keeps_the_new_values_over_the_old"),
    # --- tolerances' scales and what a verdict measures
    Mutation("velocity-scale-no-size", "sim/run/compare.py: a velocity's scale max(peak, Omega) (the size dropped)",
             "sim/run/compare.py", "return VELOCITY_TOL * max(peak, L * omega)", "return VELOCITY_TOL * max(peak, omega)",
             [CV, INDEP], "tests/test_independent.py::test_tolerances_follow_the_spec_scales"),
    Mutation("slider-drive-error-unscaled", "sim/run/compare.py drive_error: a slider's error not over the size",
             "sim/run/compare.py", "float(e) / i.spec.rate_scale(mech.size)", "float(e)", [CV, INDEP],
             "tests/test_independent.py::test_a_sliders_drive_error_is_measured_against_the_size"),
    Mutation("load-work-dropped", "sim/run/compare.py work_balance: the load's work left out", "sim/run/compare.py",
             "        work += tr.load[:-1] * (", "        work += 0.0 * tr.load[:-1] * (", [CV, CLI_S, INDEP],
             "tests/test_cli_simulate.py (compare with a cutting force: the balance needs the load's work)"),
    Mutation("angle-diff-unwrapped", "sim/run/compare.py: angle errors not wrapped into (-pi, pi]", "sim/run/compare.py",
             "            diff = np.pi - np.mod(np.pi - diff, 2 * np.pi)", "            diff = diff", [CV, INDEP],
             "a run whose angles cross +-pi at slightly different instants"),
    Mutation("torque-floor-dropped", "sim/run/compare.py: a drive force's tolerance without its inertial floor",
             "sim/run/compare.py", "return TORQUE_TOL * max(peak, TORQUE_FLOOR * force_scale)", "return TORQUE_TOL * peak",
             [EDGES, INDEP], "tests/test_edges.py::test_a_parallelogram_is_simulated_through_its_change_points"),
    Mutation("work-floor-dropped", "sim/run/compare.py: the work balance against the KE swing only (zero for a lone "
             "crank)", "sim/run/compare.py", "WORK_FLOOR * float(np.max(np.abs(kinetic)))", "0.0 * float(np.max(np.abs(kinetic)))",
             [EDGES], "tests/test_edges.py::test_a_lone_crank_at_constant_speed_passes_compare"),
    # --- units of results
    Mutation("param-si-unscaled", "analytic/quantities.py parameter_si: lengths not converted from the file's unit",
             "analytic/quantities.py", "return v * mech.scale if parameter_quantity(mech, name)",
             "return v if parameter_quantity(mech, name)", [UNITS],
             "tests/test_units.py::test_analyze_header_shows_parameters_in_the_display_units"),
    Mutation("json-parameters-raw", "sim/service/analysis.py analysis_record: parameters in file units whatever the units table "
             "says", "sim/service/analysis.py", '"parameters": Q.parameters_in(mech, display), "samples"',
             '"parameters": mech.parameters, "samples"', [UNITS],
             "tests/test_units.py::test_json_parameters_are_in_the_units_the_table_names"),
    Mutation("slider-range-in-metres", "sim/front/cli/options.py parse_range: a slider's --input-range read in m, not the "
             "file's unit", "sim/front/cli/options.py", "scale = 1.0 if angle else mech.scale", "scale = 1.0", [UNITS],
             "tests/test_units.py::test_check_prints_a_slider_range_in_the_file_unit_that_can_be_pasted"),
    Mutation("summary-unconverted", "analytic/applications/figures.py _shown: summaries print SI numbers beside the "
             "display unit", "analytic/applications/figures.py", 'lambda v, with_unit=1: f"{v * f:.6g}"',
             'lambda v, with_unit=1: f"{v:.6g}"', [UNITS],
             "tests/test_units.py::test_mm_file_summary_is_the_metre_design_times_1000"),
    Mutation("deg-angular-acceleration", "analytic/quantities.py: angular accelerations not converted to deg/s^2",
             "analytic/quantities.py", "if quantity == ANGLE or quantity == ANGULAR_ACCELERATION:",
             "if quantity == ANGLE:", [UNITS], "tests/test_units.py (CSV alpha3 in deg/s^2 against the metre design)"),
    Mutation("time-ratio-off-by-one", "analytic/applications/figures.py time_ratio: the samples counted one too many",
             "analytic/applications/figures.py", "    n = len(vx) - 1\n", "    n = len(vx)\n", [UNITS],
             "tests/test_units.py::test_plot_sheet_figures_are_analyze_figures_and_the_hand_value (K by hand)"),
    Mutation("toml-deg-lost", "sim/output/tomlout.py: a changed angle written in radians though the file wrote degrees",
             "sim/output/tomlout.py", '.rstrip().endswith("deg"):', '.rstrip().endswith("deg") and False:', [TOML],
             "tests/test_export_toml_units.py"),
    # --- edges
    Mutation("inward-rounding-outward", "analytic/applications/figures.py round_inward: ends rounded outward",
             "analytic/applications/figures.py",
             "(math.ceil(x / quantum + INWARD) if up else math.floor(x / quantum - INWARD))",
             "(math.floor(x / quantum) if up else math.ceil(x / quantum))", [EDGES, CV],
             "tests/test_edges.py::test_check_prints_the_limits_rounded_inward (the cosine rule)"),
    Mutation("fold-step-ignored", "sim/model/timestep.py: the step not shortened near a dead point's fold",
             "sim/model/timestep.py", "    h *= fold_factor(mech, revolutions, cycle)\n", "", [EDGES],
             "tests/test_edges.py::test_a_range_a_hundredth_of_a_degree_inside_passes"),
    Mutation("fold-refusal-dropped", "sim/service/simulation.py check_fold: a range at the dead point simulated anyway",
             "sim/service/simulation.py", "    if m >= FOLD_FLOOR and not close:\n", "    if True:\n", [EDGES],
             "tests/test_edges.py::test_a_range_at_the_printed_limits_is_refused_with_how_far_to_stay_..."),
    Mutation("change-point-never-flips", "analytic/kinds/rrr.py signs: the branch sign never flips at a change point",
             "analytic/kinds/rrr.py", "return np.where(count % 2 == 0, 1.0, -1.0)", "return np.where(count % 2 == 0, 1.0, 1.0)",
             [EDGES], "tests/test_edges.py::test_a_parallelogram_keeps_its_form_through_its_change_points (by hand)"),
    Mutation("change-point-limit-crude", "analytic/kinds/rrr.py limit_rates: the mean of the two sides, not extrapolated",
             "analytic/kinds/rrr.py", "lim = [(4.0 * x - y) / 3.0 for x, y in zip(*means)]", "lim = [x for x, y in zip(*means)]",
             [EDGES], "tests/test_edges.py::test_the_crossed_form_is_smooth_too_... (finite differences)"),
    Mutation("change-point-regulariser", "sim/model/build.py: the regulariser not shrunk for change points",
             "sim/model/build.py", "        scale *= CHANGE_POINT_SCALE\n", "        scale *= 1.0\n", [EDGES],
             "tests/test_edges.py::test_a_parallelogram_is_simulated_through_its_change_points"),
    # --- issue 32's leftovers: a verdict's bound loosened, a reported angle out of range, a measure's function,
    # commanded columns left SI, a gear's acceleration term, the flywheel and fluctuation
    Mutation("fv-tol-10x", "sim/run/forces.py FORCE_TOL loosened 10x (1e-4 -> 1e-3)", "sim/run/forces.py",
             "FORCE_TOL = 1e-4\n", "FORCE_TOL = 1e-3\n", [FV], "tests/test_forces_verdict.py (just outside: FAIL)"),
    Mutation("fv-identity-10x", "sim/run/forces.py IDENTITY_TOL loosened 10x (1e-8 -> 1e-7)", "sim/run/forces.py",
             "IDENTITY_TOL = 1e-8\n", "IDENTITY_TOL = 1e-7\n", [FV], "tests/test_forces_verdict.py (power balance)"),
    Mutation("fv-floor-10x", "sim/run/forces.py JOINT_FLOOR 10x higher (1e-3 -> 1e-2)", "sim/run/forces.py",
             "JOINT_FLOOR = 1e-3\n", "JOINT_FLOOR = 1e-2\n", [FV], "tests/test_forces_verdict.py (the slow run)"),
    Mutation("fv-identity-ignored", "sim/run/forces.py: the verdict ignores the Newton-Euler vs power balance",
             "sim/run/forces.py", "passed = bool(worst <= FORCE_TOL and identity <= IDENTITY_TOL)",
             "passed = bool(worst <= FORCE_TOL)", [FV], "tests/test_forces_verdict.py"),
    Mutation("fv-couple-no-size", "sim/run/forces.py: a guide's couple judged against the peak force (the size L "
             "dropped)", "sim/run/forces.py", "shares[f\"M_{j.name}\"] = m / (scale * L)",
             "shares[f\"M_{j.name}\"] = m / scale", [FV], "tests/test_forces_verdict.py (slider_crank's couple)"),
    Mutation("fv-drive-no-size", "sim/run/forces.py: a crank's drive judged against the peak force (the size L dropped)",
             "sim/run/forces.py", "dscale = max(own, scale * (L if inp.angular else 1.0))", "dscale = max(own, scale)",
             [FV], "tests/test_forces_verdict.py"),
    Mutation("fv-shaking-moment-dropped", "sim/run/forces.py: the shaking moment left out of the verdict",
             "sim/run/forces.py", "    shares[\"shaking moment\"] = ms / (scale * L)\n", "", [FV],
             "tests/test_forces_verdict.py"),
    Mutation("fv-gear-dropped", "sim/run/forces.py: the gear pairs' moments left out of the verdict",
             "sim/run/forces.py", "        shares[f\"gear pair {k}\"] = m / (scale * L)\n", "", [FV],
             "tests/test_forces_verdict.py (gear.toml)"),
    Mutation("fv-cli-exit-0", "sim/front/cli/forces.py: `forces --simulate` exits 0 whatever the verdict",
             "sim/front/cli/forces.py", "return 0 if simulated is None or simulated.get(\"passed\", False) else 1",
             "return 0", [FV], "tests/test_forces_verdict.py::test_linkage_forces_simulate_exits_1_just_outside_the_bound"),
    Mutation("mu-obtuse", "analytic/kinds/rrr.py: the transmission angle not folded to the acute one (0..180 deg)",
             "analytic/kinds/rrr.py", "np.arctan2(np.abs(det, out=det), np.abs(dot, out=dot))",
             "np.arctan2(np.abs(det, out=det), dot)", [MEAS], "tests/test_measures_on_known_poses.py"),
    Mutation("sv-prp-cos", "analytic/kinds/prp.py: the measure the cos of the angle between the guides, not its sin",
             "analytic/kinds/prp.py", "return np.abs(c1 * s2 - s1 * c2)", "return np.abs(c1 * c2 + s1 * s2)", [SV],
             "tests/test_singularity_values.py"),
    Mutation("sv-rpp-cos", "analytic/kinds/rpp.py: the measure the cos of the slot's angle", "analytic/kinds/rpp.py",
             "return abs(math.sin(e[\"angle\"]))", "return abs(math.cos(e[\"angle\"]))", [SV],
             "tests/test_singularity_values.py"),
    Mutation("sv-ppr-cos", "analytic/kinds/ppr.py: the measure the cos of the slot's angle", "analytic/kinds/ppr.py",
             "return abs(math.sin(e[\"angle\"]))", "return abs(math.cos(e[\"angle\"]))", [SV],
             "tests/test_singularity_values.py"),
    Mutation("sv-rpr-offset", "analytic/kinds/rpr.py: the block's distance over the slotted link's length, not the "
             "size", "analytic/kinds/rpr.py", "return np.abs(st.slides[e[\"links\"][1]][0]) / size",
             "return np.abs(st.slides[e[\"links\"][1]][0]) / (size + 0.1 * e[\"length\"])", [SV],
             "tests/test_singularity_values.py"),
    Mutation("sv-group-unnormalised", "analytic/solver/general_group.py singularity: the Jacobian's rows not scaled to "
             "unit length", "analytic/solver/general_group.py",
             "        J /= np.sqrt(np.sum(J * J, axis=1, keepdims=True))\n", "", [SV], "tests/test_singularity_values.py"),
    Mutation("cmd-columns-si", "sim/output/units.py: commanded columns (cmd_) left SI", "sim/output/units.py",
             "    if column.startswith(\"cmd_\"):\n        column = column[4:]\n",
             "    if column.startswith(\"cmd_\"):\n        return \"\"\n", [CMD], "tests/test_commanded_columns.py"),
    Mutation("forces-inputs-si", "sim/service/forces.py: the JSON's inputs left SI", "sim/service/forces.py",
             "\"inputs\": {inp.q: display.convert(inp_q(inp), run.inputs[inp.q]) for inp in mech.inputs},",
             "\"inputs\": {inp.q: run.inputs[inp.q] for inp in mech.inputs},", [CMD], "tests/test_commanded_columns.py"),
    Mutation("dynamics-simulated-si", "sim/front/cli/dynamics.py: the simulated run's angles and speeds left SI",
             "sim/front/cli/dynamics.py", "        out[\"simulated\"] = {k: (display.convert(names[k], v) if k in names else v)\n"
             "                            for k, v in record[\"simulated\"].items()}\n",
             "        out[\"simulated\"] = dict(record[\"simulated\"])\n", [CMD], "tests/test_commanded_columns.py"),
    Mutation("gear-alpha-carrier", "analytic/kinds/gear.py: a gear's acceleration without the carrier's",
             "analytic/kinds/gear.py", "        a = a_c + k * (a_a - a_c) + zero\n", "        a = k * a_a + zero\n",
             [GEARS], "tests/test_gears_accelerating.py (finite differences at non-zero acceleration)"),
    Mutation("gear-alpha-ratio", "analytic/kinds/gear.py: a gear's acceleration not scaled by the ratio",
             "analytic/kinds/gear.py", "        a = a_c + k * (a_a - a_c) + zero\n", "        a = a_c + (a_a - a_c) + zero\n",
             [GEARS], "tests/test_gears_accelerating.py"),
    Mutation("fly-cs-over-max", "analytic/applications/motor.py: Cs over the largest speed, not the mean",
             "analytic/applications/motor.py", "fluctuation=(w_max - w_min) / mean,", "fluctuation=(w_max - w_min) / w_max,",
             [FLY], "tests/test_flywheel_energy.py"),
    Mutation("fly-flywheel-halved", "analytic/applications/motor.py: the flywheel's inertia counted half",
             "analytic/applications/motor.py", "    J = np.full(len(u), float(flywheel))\n",
             "    J = np.full(len(u), 0.5 * float(flywheel))\n", [FLY], "tests/test_flywheel_energy.py"),
    Mutation("fly-gravity-opposite", "analytic/applications/motor.py: gravity's generalized force of the wrong sign",
             "analytic/applications/motor.py", "        Qg = Qg + b.m * (gx * vx + gy * vy)\n",
             "        Qg = Qg - b.m * (gx * vx + gy * vy)\n", [FLY], "tests/test_flywheel_energy.py (energy: m g R sin phi)"),
    Mutation("two-cs-over-max", "analytic/applications/motor.py run_two: Cs over the largest speed",
             "analytic/applications/motor.py", "cs = (Yl[2:4].max(axis=1) - Yl[2:4].min(axis=1)) / mean",
             "cs = (Yl[2:4].max(axis=1) - Yl[2:4].min(axis=1)) / Yl[2:4].max(axis=1)", [FLY],
             "tests/test_flywheel_energy.py"),
    Mutation("two-armature-dropped", "analytic/applications/motor.py mass_matrix: the flywheels (armature) left out",
             "analytic/applications/motor.py", "    M = np.diag(np.asarray(armature, float))\n", "    M = np.zeros((2, 2))\n",
             [FLY], "tests/test_flywheel_energy.py"),
    Mutation("two-gravity-dropped", "analytic/applications/motor.py mass_matrix: gravity left out of Q",
             "analytic/applications/motor.py", "        Q = Q + b.m * V @ np.array([gx, gy])\n", "", [FLY],
             "tests/test_flywheel_energy.py"),
    Mutation("two-first-order-lag", "analytic/applications/motor.py run_two: the second motor's torque from the first's "
             "speed", "analytic/applications/motor.py",
             "tau = np.array([float(motors[0].torque(w[0])), float(motors[1].torque(w[1]))])",
             "tau = np.array([float(motors[0].torque(w[0])), float(motors[1].torque(w[0]))])", [FLY],
             "tests/test_flywheel_energy.py"),
    Mutation("titles-unfitted", "sim/front/cli/synth_path.py: the panels' titles laid out as written (cut at the edge)",
             "sim/front/cli/synth_path.py", "    fig.tight_layout()\n    fit(fig)\n", "    fig.tight_layout()\n",
             ["tests/test_plot_titles.py"], "tests/test_plot_titles.py"),
    Mutation("ticks-unthinned", "sim/output/fit.py: overlapping tick labels left as they are", "sim/output/fit.py",
             "        if not (fit_titles(fig) | thin_ticks(fig)):", "        if not fit_titles(fig):",
             ["tests/test_plot_titles.py"], "tests/test_plot_titles.py"),
    Mutation("layers-no-clique-bound", "analytic/parts/layers.py colour: the search counts up from one layer (no clique "
             "bound)", "analytic/parts/layers.py", "low = max([0, _clique(nodes, adj)]", "low = max([0, 0]",
             ["tests/test_parts_bounded.py"], "tests/test_parts_bounded.py::test_a_complete_conflict_graph_..."),
    Mutation("layers-disc-too-small", "analytic/parts/layers.py Swept.disc: the bounding disc half as wide (not a bound)",
             "analytic/parts/layers.py", "return self.sweep.frames[link][:, :2], float(np.max(np.hypot(*self.out.local[link].T)))",
             "return self.sweep.frames[link][:, :2], 0.5 * float(np.max(np.hypot(*self.out.local[link].T)))",
             ["tests/test_parts_bounded.py"], "tests/test_parts_bounded.py (brute force)"),
    Mutation("layers-pin-disc-too-small", "analytic/parts/layers.py pin_rules: the link's disc half as wide",
             "analytic/parts/layers.py", "radius = {ln: float(np.max(np.hypot(*out.local[ln].T))) for ln in parts}",
             "radius = {ln: 0.5 * float(np.max(np.hypot(*out.local[ln].T))) for ln in parts}",
             ["tests/test_parts_bounded.py"], "tests/test_parts_bounded.py (brute force)"),
    Mutation("layers-no-size-limit", "analytic/parts/layers.py: no limit on the links laid out", "analytic/parts/layers.py",
             "    if len(parts) > MAX_LINKS:\n", "    if False:\n", ["tests/test_parts_bounded.py"],
             "tests/test_parts_bounded.py::test_past_max_links_..."),
    Mutation("titles-no-relayout", "sim/output/fit.py: the figure not laid out again after wrapping a title",
             "sim/output/fit.py", "        fig.tight_layout()                        # laid out once by tight_layout",
             "        pass                                      # laid out once by tight_layout",
             ["tests/test_plot_titles.py"], "tests/test_plot_titles.py"),
    Mutation("titles-no-shrink", "sim/output/fit.py: a word wider than its room left as it is",
             "sim/output/fit.py", "        text_artist.set_fontsize(max(MIN_FONTSIZE, 0.9 * text_artist.get_fontsize()))",
             "        break", ["tests/test_plot_titles.py"], "tests/test_plot_titles.py"),
    # --- the phase's newer code: motion laws, actuators and relative motors, cams, load kinds, the drive
    # torque, synthesis limits, the tolerance's speed fluctuation (a fresh batch of realistic faults)
    Mutation("law-parabolic-decel-sign", "analytic/laws.py shape: the parabolic law's second half accelerating (+4, "
             "not -4)", "analytic/laws.py", "np.where(first, 4.0, -4.0), zero.copy())",
             "np.where(first, 4.0, 4.0), zero.copy())", [LAWS, LAW_EVAL],
             "tests/test_motion_laws.py (finite differences of y' give y'')"),
    Mutation("law-compiled-sine-rate-T", "analytic/laws.py Compiled.of: a sine term's derivatives w^d not (w / T)^d "
             "(the segment's duration dropped)", "analytic/laws.py",
             "amps.append([A * h * (w / T) ** d for d in range(4)])", "amps.append([A * h * w ** d for d in range(4)])",
             [LAWS, LAW_EVAL], "tests/test_law_evaluation.py (one pass equals segment by segment)"),
    Mutation("law-modtrap-middle-period", "analytic/laws.py: the modified trapezoid's middle cosine at half its "
             "frequency (2 pi, not 4 pi)", "analytic/laws.py",
             "(3 / 8, 5 / 8, 1.0, 4 * math.pi, _HALF)", "(3 / 8, 5 / 8, 1.0, 2 * math.pi, _HALF)", [LAWS, LAW_EVAL],
             "tests/test_motion_laws.py::test_peak_velocity_and_acceleration_are_norton_s (C_a 4.888)"),
    Mutation("law-table-not-periodic", "analytic/laws.py Table: a closing table splined with not-a-knot ends (the "
             "acceleration jumps where the cycle repeats)", "analytic/laws.py",
             'return CubicSpline(t, resid, bc_type="periodic")', 'return CubicSpline(t, resid, bc_type="not-a-knot")',
             [LAWS], "tests/test_motion_laws.py::test_a_table_that_closes_a_turn_is_periodic"),
    Mutation("law-boundary-left", "analytic/laws.py Compiled.at: a sample exactly at a segment boundary given the "
             "piece that ends there (searchsorted side left)", "analytic/laws.py",
             'k = np.searchsorted(self.breaks, tau, side="right")       # the piece: 0 .. P - 1',
             'k = np.searchsorted(self.breaks, tau, side="left")       # the piece: 0 .. P - 1', [LAWS, LAW_EVAL],
             "a profile with a velocity jump sampled exactly at the boundary (constant then dwell)"),
    Mutation("lawfield-slider-rise-unscaled", "analytic/format/lawfield.py resolve: a slider's rise not converted from "
             "the file's unit", "analytic/format/lawfield.py",
             'num(rise, "angle" if kind.angular else "length", where + ": rise")',
             'num(rise, "angle" if kind.angular else "number", where + ": rise")', [LAWS],
             "tests/test_motion_laws.py::test_a_slider_takes_a_law_in_file_units"),
    Mutation("act-pull-area-full", "analytic/kinds/actuator.py areas: the pull area the full bore (the rod not "
             "taken off)", "analytic/kinds/actuator.py", "math.pi * (bore * bore - rod * rod) / 4",
             "math.pi * (bore * bore) / 4", [CYL_SIZE, DRIVES], "tests/test_cylinder_sizing.py (pressures by hand)"),
    Mutation("act-areas-swapped", "analytic/kinds/actuator.py pressure: the push force over the pull area and the pull "
             "over the push area", "analytic/kinds/actuator.py", "np.where(push, force / a_push, -force / a_pull)",
             "np.where(push, force / a_pull, -force / a_push)", [CYL_SIZE, DRIVES],
             "tests/test_drives.py::test_the_pressure_is_the_force_over_the_push_or_pull_area"),
    Mutation("act-drive-sign", "analytic/kinds/actuator.py forces: the cylinder's force positive when it pulls",
             "analytic/kinds/actuator.py", "drive = -(ux * tx + uy * ty)", "drive = ux * tx + uy * ty",
             [CYL_SIZE, DRIVES], "tests/test_drives.py::test_the_tipper_cylinder_force_equals_virtual_work"),
    Mutation("act-stroke-extended-unchecked", "analytic/kinds/actuator.py motion_problem: a motion past the extended "
             "end of the stroke not refused", "analytic/kinds/actuator.py",
             "out = (q < lo - tol) | (q > hi + tol)", "out = (q < lo - tol)", [DRIVES],
             "tests/test_drives.py::test_a_motion_past_the_stroke_is_refused_saying_when_and_by_how_much"),
    Mutation("act-sizing-pull-no-rod", "analytic/kinds/actuator.py sizing: the bore the pull needs without the rod's "
             "area", "analytic/kinds/actuator.py",
             'need_pull = math.sqrt(4 * out["pull"]["F"] / (math.pi * p) + rod * rod)',
             'need_pull = math.sqrt(4 * out["pull"]["F"] / (math.pi * p))', [CYL_SIZE],
             "tests/test_cylinder_sizing.py::test_the_peaks_pressures_and_bores_by_hand"),
    Mutation("cyl-supply-radius", "analytic/applications/cylinder.py supply: the push area pi bore^2 (the bore taken "
             "as a radius)", "analytic/applications/cylinder.py", "area = math.pi * bore * bore / 4",
             "area = math.pi * bore * bore", [CYL_DYN],
             "tests/test_cylinder_dynamics.py::test_the_supply_is_the_pressure_and_flow_on_the_push_area"),
    Mutation("motor-reaction-on-ground", "analytic/applications/forces.py Context.drive: a motor's reaction put on "
             "the ground, not on its carrier `on`", "analytic/applications/forces.py",
             '        if j.kind == "revolute":\n            self._couple(j.a, -value)',
             '        if j.kind == "revolute":\n            self._couple(GROUND, -value)', [DRIVES],
             "tests/test_drives.py::test_the_2r_arm_holds_its_weights_with_the_moments_about_its_joints"),
    Mutation("motor-carrier-rate-dropped", "analytic/kinds/motor.py solve: the driven link's rate without the "
             "carrier's", "analytic/kinds/motor.py", "w, a = w0 + qd, a0 + qdd", "w, a = qd, a0 + qdd",
             [DRIVES, DRIVES_CF], "tests/test_drives.py (power balance of the 2R arm)"),
    Mutation("cam-pa-sign", "analytic/cams.py at: the pressure angle's sign flipped (normal to motion, not motion to "
             "normal)", "analytic/cams.py", "pa = np.arctan2(tx * nwy - ty * nwx, tx * nwx + ty * nwy)",
             "pa = np.arctan2(ty * nwx - tx * nwy, tx * nwx + ty * nwy)", [CAMS],
             "tests/test_cams.py::test_pressure_angle_by_the_textbook_formula (signed, with an offset)"),
    Mutation("cam-rho-pitch-sign", "analytic/cams.py at: the pitch curve's radius of curvature of the wrong sign "
             "(convex negative)", "analytic/cams.py", "rho_p = -speed ** 3 / cross", "rho_p = speed ** 3 / cross",
             [CAMS], "tests/test_cams.py::test_pressure_angle_and_curvature_match_finite_differences"),
    Mutation("cam-offset-sign", "analytic/kinds/cam.py resolve_at: the guide's offset measured to its right",
             "analytic/kinds/cam.py", "offset = (O[0] - A[0]) * -math.sin(gam) + (O[1] - A[1]) * math.cos(gam)",
             "offset = (O[0] - A[0]) * math.sin(gam) - (O[1] - A[1]) * math.cos(gam)", [CAMS, CAM_MECH],
             "tests/test_cams.py (an offset follower's place)"),
    Mutation("cam-flat-rho-sign", "analytic/cams.py at: a flat face's radius of curvature d - h'' (Norton 8.31: "
             "d + h'')", "analytic/cams.py", "        rho = d + h2\n", "        rho = d - h2\n", [CAMS],
             "tests/test_cams.py::test_pressure_angle_and_curvature_match_finite_differences[flat]"),
    Mutation("cam-face-travel-one-side", "analytic/cams.py face_travel: the contact's largest distance from the foot, "
             "not its travel (max - min)", "analytic/cams.py", "return float(np.ptp(self.face_offset))",
             "return float(np.max(np.abs(self.face_offset)))", [CAMS],
             "tests/test_cams.py::test_a_flat_face_cusp_and_a_narrow_face_are_refused"),
    Mutation("cam-roller-undercut-ignored", "analytic/cams.py problems: a roller larger than the pitch curve's radius "
             "of curvature not refused", "analytic/cams.py",
             "bad = np.flatnonzero((geo.rho_pitch > 0) & (geo.rho_pitch <= rr))",
             "bad = np.flatnonzero((geo.rho_pitch > 0) & (geo.rho_pitch <= 0.0))", [CAMS],
             "tests/test_cams.py::test_an_undercut_is_refused_saying_where"),
    Mutation("cam-force-no-cos", "analytic/kinds/cam.py forces: a translating follower's contact force without "
             "1/cos(pressure angle)", "analytic/kinds/cam.py",
             "N = -(W[0] * c + W[1] * s) / (nx * c + ny * s)", "N = -(W[0] * c + W[1] * s)", [CAMS],
             "tests/test_cams.py::test_contact_force_by_the_followers_newton_equation"),
    Mutation("cam-jump-speed-no-sqrt", "sim/service/forces.py jump_speed: k* = min(-Ns/N1), not its square root "
             "(forces scale with k^2)", "sim/service/forces.py", "return float(np.sqrt(np.min(-Ns[falls] / N1[falls])) * speed)",
             "return float(np.min(-Ns[falls] / N1[falls]) * speed)", [CAMS],
             "tests/test_cams.py::test_jump_speed_matches_a_scan_of_the_contact_force"),
    Mutation("gas-a-exponent", "analytic/loads/gas_spring.py a: 1 - ratio^(-n), not ratio^(-1/n) (equal at n = 1)",
             "analytic/loads/gas_spring.py", "return -float(np.expm1(-np.log(self.ratio) / self.n))",
             "return -float(np.expm1(-np.log(self.ratio) * self.n))", [LOAD_KINDS],
             "tests/test_load_kinds.py::test_gas_spring_pushes_its_ends_apart_by_the_polytropic_law (n != 1)"),
    Mutation("gas-energy-exponent-sign", "analytic/loads/gas_spring.py stored: the energy's exponent (n - 1), not "
             "(1 - n)", "analytic/loads/gas_spring.py", "_phi((1.0 - self.n) * np.log1p(-u))",
             "_phi((self.n - 1.0) * np.log1p(-u))", [LOAD_KINDS],
             "tests/test_load_kinds.py::test_gas_spring_energy_is_the_integral_of_its_push"),
    Mutation("table-spring-hi-slope", "analytic/loads/spring.py table_value: beyond the last row continued with the "
             "first rows' slope", "analytic/loads/spring.py",
             "slope_hi = (y[-1] - y[-2]) / (x[-1] - x[-2])", "slope_hi = (y[1] - y[0]) / (x[1] - x[0])",
             [LOAD_KINDS, LOADS_EL], "tests/test_load_kinds.py::test_table_spring_follows_its_table (beyond its rows)"),
    Mutation("table-spring-energy-rectangle", "analytic/loads/spring.py table_integral: the last part's area as a "
             "rectangle (the slope term dropped)", "analytic/loads/spring.py",
             "return cum[k] + y[k] * d + 0.5 * slope * d * d", "return cum[k] + y[k] * d", [LOAD_KINDS, LOADS_EL],
             "tests/test_load_kinds.py::test_power_balance (table_spring)"),
    Mutation("window-edge-wrong-side", "analytic/loads/kinetostatics.py switched_work: the load's value at the edge "
             "taken from the sample outside the window", "analytic/loads/kinetostatics.py",
             "k = np.where(on[cut], cut, cut + 1)", "k = np.where(on[cut], cut + 1, cut)", [WINDOW],
             "tests/test_load_window_work.py"),
    Mutation("window-crank-not-wrapped", "analytic/loads/law.py on: a crank's window not repeated every turn",
             "analytic/loads/law.py", "return np.mod(q1 - lo, 2 * math.pi) <= (hi - lo) + 1e-12",
             "return (q1 >= lo) & (q1 <= hi)", [WINDOW], "tests/test_load_window_work.py (a window across 0 deg)"),
    Mutation("delivered-armature-sign", "sim/run/simulate.py delivered: the rotor's inertia term added, not taken off",
             "sim/run/simulate.py", "return np.asarray(actuator_force) - drive.armature * np.asarray(qdd)",
             "return np.asarray(actuator_force) + drive.armature * np.asarray(qdd)", [DRIVE_TORQUE],
             "tests/test_drive_torque.py::test_an_accelerating_crank_reports_its_links_torque_not_its_rotors"),
    Mutation("synth-ratio-without-ground", "analytic/synthesis/function.py _closed_form: --max-ratio over the moving "
             "links only (the ground left out)", "analytic/synthesis/function.py",
             "elif limits.max_ratio is not None and max(links) > limits.max_ratio * min(links) * (1 + sc.SLACK_REL):",
             "elif limits.max_ratio is not None and max(links[:3]) > limits.max_ratio * min(links[:3]) * (1 + sc.SLACK_REL):",
             [SYN_BUILD], "tests/test_synthesis_buildable.py::test_function_search_of_start_angles_..."),
    Mutation("synth-min-link-without-ground", "analytic/synthesis/constraints.py broken: --min-link over the moving "
             "links only", "analytic/synthesis/constraints.py",
             "if m.links and limits.min_link is not None and min(m.links) < limits.min_link * (1 - SLACK_REL):",
             "if m.links and limits.min_link is not None and min(m.links[:3]) < limits.min_link * (1 - SLACK_REL):",
             [SYN_BUILD], "tests/test_synthesis_buildable.py::test_function_min_link_and_max_ratio_refuse_the_given_design"),
    Mutation("synth-structural-error-ends", "sim/service/design.py structural_error: the error's max over the range's "
             "ends only (where the first and last pairs are)", "sim/service/design.py",
             "    k = int(np.argmax(e))\n    return {\"max\": float(e[k]),",
             "    k = int(np.argmax(e[[0, -1]])) * (len(e) - 1)\n    return {\"max\": float(e[k]),", [SYN_BUILD],
             "tests/test_synthesis_buildable.py::test_function_structural_error_over_the_range_not_only_at_the_pairs"),
    Mutation("tol-fluct-plain-mean", "analytic/applications/tolerance.py: the speed fluctuation over the plain mean "
             "(the closed run's repeated sample counted twice)", "analytic/applications/tolerance.py",
             'out["speed_fluctuation"] = (speed_max - speed_min) / closed_mean(speed, axis=1)',
             'out["speed_fluctuation"] = (speed_max - speed_min) / np.nanmean(speed, axis=1)', [LAWS_SETUPS],
             "tests/test_load_laws_setups.py::test_tolerance_speed_fluctuation_and_its_percentiles_by_hand"),
    Mutation("tol-fluct-unrefined", "analytic/applications/tolerance.py: the speed's extremes at the samples (not "
             "refined between them)", "analytic/applications/tolerance.py",
             "speed_max, speed_min = _extreme(speed, 1.0), _extreme(speed, -1.0)",
             "speed_max, speed_min = np.nanmax(speed, axis=1), np.nanmin(speed, axis=1)", [LAWS_SETUPS],
             "tests/test_load_laws_setups.py::test_tolerance_speed_fluctuation_and_its_percentiles_by_hand"),
    # (second round: subtler faults of the same code, after the first round was all killed but three)
    Mutation("law-harmonic-jerk-sign", "analytic/laws.py shape: the harmonic law's jerk of the wrong sign",
             "analytic/laws.py", "-math.pi ** 3 / 2 * np.sin(a))", "math.pi ** 3 / 2 * np.sin(a))", [LAWS, LAW_EVAL],
             "tests/test_motion_laws.py::test_each_derivative_is_the_finite_difference_of_the_one_before[harmonic]"),
    Mutation("act-enough-push-only", "analytic/kinds/actuator.py sizing: a bore judged enough against the push's "
             "need only (the pull round the rod ignored)", "analytic/kinds/actuator.py",
             'out["sizing"]["enough"] = bool(bore >= need)', 'out["sizing"]["enough"] = bool(bore >= need_push)',
             [CYL_SIZE], "a bore between the push's need and the pull's (a thick rod)"),
    Mutation("act-singularity-cos", "analytic/kinds/actuator.py singularity: the cos of the angle between the link "
             "and the cylinder, not its sin", "analytic/kinds/actuator.py", "return np.abs(c1 * s2 - s1 * c2)",
             "return np.abs(c1 * c2 + s1 * s2)", ["tests/test_singularity_values.py", DRIVES],
             "tests/test_singularity_values.py (an actuator's measure at a known pose)"),
    Mutation("cyl-stall-sign", "analytic/applications/cylinder.py run: the stall check with the load's sign flipped",
             "analytic/applications/cylinder.py", "if drive.F0 + Q0[0] <= 0:", "if drive.F0 - Q0[0] <= 0:",
             [CYL_DYN], "tests/test_cylinder_dynamics.py::test_bad_supplies_are_refused_in_one_line"),
    Mutation("cam-arm-direction-radial", "analytic/cams.py follow: an arm's direction of motion taken along the arm "
             "(B -> F), not square to it", "analytic/cams.py", "return Follow(theta, r, r1, r2, (-sw, cw), (h, h1, h2, h3), psi)",
             "return Follow(theta, r, r1, r2, (cw, sw), (h, h1, h2, h3), psi)", [CAMS],
             "an oscillating follower's pressure angle against finite differences or a hand value"),
    Mutation("cam-jump-speed-peak-speed", "sim/service/forces.py jump_speed: k* times the cam's peak speed, not its "
             "mean", "sim/service/forces.py", 'speed = float(np.mean(np.abs(run.solution["omega" + e["cam"]])))',
             'speed = float(np.max(np.abs(run.solution["omega" + e["cam"]])))', [CAMS],
             "tests/test_cams.py::test_jump_speed_matches_a_scan_of_the_contact_force (an accelerating cam)"),
    Mutation("cam-add-knife-sphere-sunk", "sim/model/cam_contact.py add: a knife's sphere centred below the trace point "
             "(sunk 2 r into the plate)", "sim/model/cam_contact.py", "px, py = px + r * ux, py + r * uy",
             "px, py = px - r * ux, py - r * uy", [CAM_CONTACT],
             "tests/test_cam_contact.py (the knife added to a mechanism's bodies rests on the plate)"),
    Mutation("cam-add-flat-face-sunk", "sim/model/cam_contact.py add: a flat face's box centred below the trace point "
             "(its face 2 ht into the plate)", "sim/model/cam_contact.py", "pos=loc(px + ht * ux, py + ht * uy)",
             "pos=loc(px - ht * ux, py - ht * uy)", [CAM_CONTACT],
             "tests/test_cam_contact.py (the flat face added to a mechanism's bodies rests on the plate)"),
    Mutation("load-stroke-sign-dropped", "analytic/loads/law.py gate: a load's stroke condition ignores its sign (\"-x\" "
             "acts as \"+x\")", "analytic/loads/law.py", "return np.where(sign * rate > 0, v, 0.0)",
             "return np.where(rate > 0, v, 0.0)", ["tests/test_loads.py", "tests/test_sweep_forces.py"],
             "tests/test_sweep_forces.py (an up and a down torque, stroke + and -)"),
    Mutation("tol-extreme-vertex-2x", "analytic/applications/tolerance.py _extreme: the parabola's vertex twice as far "
             "from the sample (8 -> 4)", "analytic/applications/tolerance.py",
             "vertex = best - (b - a) ** 2 / (8 * bend)", "vertex = best - (b - a) ** 2 / (4 * bend)", [LAWS_SETUPS, TOLERANCE],
             "tests/test_load_laws_setups.py::test_tolerance_speed_fluctuation_and_its_percentiles_by_hand"),
    Mutation("tol-fluct-x-speed", "analytic/applications/tolerance.py: the output point's speed as |vx| (a piston's), "
             "not |v|", "analytic/applications/tolerance.py", 'speed = np.hypot(sol["vx" + p], sol["vy" + p])',
             'speed = np.abs(sol["vx" + p])', [LAWS_SETUPS, TOLERANCE],
             "a four-bar coupler point's speed fluctuation by hand (the slider-crank's piston moves along x only)"),
    # (third round)
    Mutation("law-compiled-jerk-phase", "analytic/laws.py Compiled: the jerk's sine term a quarter turn of phase, "
             "not three (the jerk of a sine piece of the wrong sign)", "analytic/laws.py",
             "SHIFT = np.array([[0.0], [_HALF], [math.pi], [3 * _HALF]])",
             "SHIFT = np.array([[0.0], [_HALF], [math.pi], [_HALF]])", [LAWS, LAW_EVAL],
             "tests/test_motion_laws.py::test_the_servo_press_cycle_is_its_profile_and_analyze_gives_the_exact_jerk"),
    Mutation("cam-separation-start-early", "sim/model/cam_contact.py separation: the separation said to start at the "
             "last sample in contact, not the first after it", "sim/model/cam_contact.py",
             "start = int(touching[-1]) + 1 if len(touching) else 0",
             "start = int(touching[-1]) if len(touching) else 0", [CAM_CONTACT],
             "tests/test_cam_contact.py::test_separation_at_1_3_the_jump_speed_where_the_force_vanishes"),
    Mutation("motor-measured-rate-absolute", "analytic/kinds/motor.py measured_extras: the simulated dq, ddq of a motor "
             "its link's absolute rates, not relative to the carrier", "analytic/kinds/motor.py",
             "return {self.columns[1] + key: w - w0, self.columns[2] + key: a - a0}",
             "return {self.columns[1] + key: w, self.columns[2] + key: a}", [KINDS],
             "tests/test_kinds.py (MuJoCo against the closed forms, motor.toml)"),
    Mutation("path-ratio-check-10x", "analytic/synthesis/path.py: the final --max-ratio check 10x looser",
             "analytic/synthesis/path.py", "if L.max() / L.min() > cons.max_ratio:",
             "if L.max() / L.min() > 10 * cons.max_ratio:", ["tests/test_synthesis_path_limits.py",
                                                             "tests/test_synthesis_constraints.py"],
             "a path design just over --max-ratio refused by the final check"),
    Mutation("path-ratio-violation-dropped", "analytic/synthesis/path.py shape_violation: the link ratio left out of "
             "the search's penalty", "analytic/synthesis/path.py", "np.maximum(ratio / cons.max_ratio - 1, 0)",
             "0.0 * np.maximum(ratio / cons.max_ratio - 1, 0)", ["tests/test_synthesis_path_limits.py",
                                                                 "tests/test_synthesis_constraints.py"],
             "tests/test_synthesis_path_limits.py::test_margins_hold_exactly_where_nothing_is_violated_..."),
    Mutation("synth-broken-ratio-without-ground", "analytic/synthesis/constraints.py broken: --max-ratio over the "
             "moving links only", "analytic/synthesis/constraints.py",
             "if m.links and limits.max_ratio is not None and max(m.links) > limits.max_ratio * min(m.links) * (1 + SLACK_REL):",
             "if m.links and limits.max_ratio is not None and max(m.links[:3]) > limits.max_ratio * min(m.links[:3]) * (1 + SLACK_REL):",
             [SYN_BUILD], "tests/test_synthesis_buildable.py::test_function_min_link_and_max_ratio_count_the_ground_link"),
    # (fourth round: the code of the last hours: two-plate links, the trammel's offsets, the cam panel, a flat
    # face's placement, the cams' compliance, the drives' spread, relative motors, the shared solves, lazy kinds)
    Mutation("two-plates-swapped", "analytic/parts/layers.py Layout.plates: a two-plate link's upper plate listed "
             "first (the BOM's layer and the scene's plate names swapped)", "analytic/parts/layers.py",
             "return (first, self.second[link]) if", "return (self.second[link], first) if", [TWO_RULES, TWO],
             "the BOM's layer is the lower plate's, upper_layer the upper's (layer < upper_layer)"),
    Mutation("two-plates-adjacent", "analytic/parts/layers.py two_plates: a two-plate link's plates on adjacent "
             "layers (nothing can pass between them)", "analytic/parts/layers.py",
             "[(a, b) for a in range(k) for b in range(a + 2, k)]", "[(a, b) for a in range(k) for b in range(a + 1, k)]",
             [TWO_RULES, TWO], "every two-plate link has a layer between its plates that a link passing its pin uses"),
    Mutation("two-plates-stub-short", "analytic/parts/layers.py _two_plate_layout: a pin from a top plate ('above') "
             "ends at its links' top, not the stack's top", "analytic/parts/layers.py",
             'hi = top if sp.side == "above" else max(e[1] for e in ends)', "hi = max(e[1] for e in ends)", [TWO_RULES, TWO],
             "a stub pin from the top plate spans up to the top of the stack"),
    Mutation("two-plates-ground-pin-floating", "analytic/parts/layers.py _two_plate_layout: a ground pin ('below') "
             "starts at its links' bottom, not the frame's z = 0", "analytic/parts/layers.py",
             'lo = 0.0 if sp.side == "below" else min(e[0] for e in ends)', "lo = min(e[0] for e in ends)", [TWO_RULES, TWO],
             "a ground pin of a two-plate layout reaches the frame (z = 0)"),
    Mutation("two-plates-span-touching", "analytic/parts/layers.py spans: a ground pin from below allowed where a "
             "crossing plate shares its top layer", "analytic/parts/layers.py",
             "            if all(c > hi for c in cross):", "            if all(c >= hi for c in cross):", [TWO_RULES, TWO],
             "tests/test_parts_two_plates.py (the exported solids never reach into a pin)"),
    Mutation("mass-two-plate-I-once", "analytic/mass.py parts_inertias: a two-plate link's I of one plate (its mass "
             "doubled)", "analytic/mass.py", "I=n * mp.I)", "I=mp.I)", [MASS1, TWO],
             "a two-plate lever's I about its centre by hand (twice the plate's)"),
    Mutation("mass-two-plate-m-once", "analytic/mass.py parts_inertias: a two-plate link weighed as one plate",
             "analytic/mass.py", "Inertia(m=n * mp.m,", "Inertia(m=mp.m,", [MASS1, TWO],
             "tests/test_one_mass_truth.py::test_a_two_plate_link_weighs_both_plates_in_the_bom_and_the_forces"),
    Mutation("bom-holes-one-plate", "sim/output/parts_files.py bom_rows: a two-plate link's holes of one plate",
             "sim/output/parts_files.py", '"holes": n * len(part.holes)', '"holes": len(part.holes)', [TWO],
             "the BOM's holes of a two-plate link: both plates'"),
    Mutation("bom-volume-one-plate", "sim/output/parts_files.py bom_rows: a two-plate link's volume of one plate",
             "sim/output/parts_files.py", '"volume": n * mp.volume', '"volume": mp.volume', [TWO_RULES, TWO, MASS1],
             "the BOM's volume of a two-plate link against its mass / density"),
    Mutation("bom-upper-layer-lower", "sim/output/parts_files.py bom_rows: upper_layer the lower plate's layer",
             "sim/output/parts_files.py", '"upper_layer": plates[1][0] if n == 2', '"upper_layer": plates[0][0] if n == 2',
             [TWO], "tests/test_parts_two_plates.py::test_bom_lists_a_two_plate_link_as_two_plates"),
    Mutation("stl-one-plate", "sim/output/parts_files.py: a two-plate link's STL holds its lower plate only",
             "sim/output/parts_files.py", "for _, (z0, z1) in pm.layout.plates(link)]",
             "for _, (z0, z1) in pm.layout.plates(link)[:1]]", [TWO],
             "tests/test_parts_two_plates.py (the exported STL over a dense sweep)"),
    Mutation("scene-pin-bits-lower-plate", "sim/model/parts_scene.py: a pin collides with the lower plates only (the "
             "upper plates' layer bits left out)", "sim/model/parts_scene.py",
             "            for layer, (z0, z1) in layout.plates(ln):\n                if z0 < hi",
             "            for layer, (z0, z1) in layout.plates(ln)[:1]:\n                if z0 < hi", [TWO_RULES, TWO],
             "tests/test_parts_two_plates.py::test_interference_checks_every_passed_pin_in_mujoco"),
    Mutation("scene-pairs-lower-layer", "sim/model/parts_scene.py: the link pairs checked from their lower plates' "
             "layers only", "sim/model/parts_scene.py", "on = {ln: {k for k, _ in layout.plates(ln)} for ln in links}",
             "on = {ln: {layout.layers[ln]} for ln in links}", [TWO_RULES, TWO],
             "a two-plate link's upper plate paired with the links on its layer"),
    Mutation("trammel-offset-small", "analytic/library/elliptic_trammel.toml: the rod pins' offset c = 60 (under "
             "(L/2 + 11)/sqrt(2) = 78.4: the rod passes over the crank pin)", "analytic/library/elliptic_trammel.toml",
             "\nc = 100 ", "\nc = 60 ", [TWO, LIB],
             "tests/test_parts_two_plates.py::test_elliptic_trammel_builds_without_a_pin_clash"),
    Mutation("trammel-pin-B-flipped", "analytic/library/elliptic_trammel.toml: the rod's pin B c on the other side of "
             "its slot", "analytic/library/elliptic_trammel.toml", 'on = "blockB"\nat = ["c", 0]',
             'on = "blockB"\nat = ["-c", 0]', [LIB, TWO], "the trammel's E on the ellipse (L - b) cos, b sin"),
    Mutation("cam-face-centre-half-travel", "analytic/cams.py face_centre: half the contact's travel (max - min), not "
             "its middle", "analytic/cams.py",
             "return 0.5 * float(np.max(self.face_offset) + np.min(self.face_offset))",
             "return 0.5 * float(np.max(self.face_offset) - np.min(self.face_offset))", [CAM_CONTACT, CAM_MECH],
             "tests/test_cam_mechanism.py (the face of face_width covers the contact's travel)"),
    Mutation("cam-add-flat-mid-sign", "sim/model/cam_contact.py add: a flat face shifted to the guide's right by its "
             "centre, not its left", "sim/model/cam_contact.py",
             "pos=loc(px + ht * ux - mid * uy, py + ht * uy + mid * ux)",
             "pos=loc(px + ht * ux + mid * uy, py + ht * uy - mid * ux)", [CAM_CONTACT, CAM_MECH],
             "a flat face in a mechanism's model covers the contact's travel"),
    Mutation("drawing-face-on-foot", "sim/output/drawing.py face_of: a given face_width centred on the foot (the old "
             "placement), not the contact's travel", "sim/output/drawing.py",
             "return (ux, uy, mid - 0.5 * w, mid + 0.5 * w)", "return (ux, uy, -0.5 * w, 0.5 * w)",
             [CAM_FACE, CAMS, "tests/test_cam_drawing.py"], "the drawn face holds the touching corner at every pose"),
    Mutation("cams-window-not-centred", "sim/run/cams.py window_means: each window starting at its step, not "
             "centred on it", "sim/run/cams.py", "start = np.clip(at - (w - 1) // 2, 0, n - w)",
             "start = np.clip(at, 0, n - w)", [CAM_FACE, CAM_MECH, CAM_CONTACT, "tests/test_forces_mujoco.py"],
             "window_means on a hand ramp: the mean of a centred window is the value at its step"),
    Mutation("cams-mean-force-2x", "sim/run/cams.py Compliance.mean_force: twice the bound (the 2 of the speed "
             "error kept after W = 2 pi tau)", "sim/run/cams.py",
             "return self.m_eff * self.position / (math.pi * self.tau ** 2)",
             "return 2 * self.m_eff * self.position / (math.pi * self.tau ** 2)", [CAM_MECH, CAM_CONTACT],
             "Compliance.mean_force by hand: m_eff T / (pi tau^2)"),
    Mutation("cam-refusal-in-metres", "analytic/kinds/cam.py check_resolved: a mm file's refusal gives metres "
             "labelled mm", "analytic/kinds/cam.py", 'return problem[0].format(*(f"{x / per:.4g} {units}"',
             'return problem[0].format(*(f"{x:.4g} {units}"', [CAMS],
             "tests/test_cams.py (a mm file's cam refusals in mm)"),
    Mutation("spread-ignored", "sim/model/build.py regularization: the loops' spread ignored (min(1, SPREAD_REF / "
             "spread) dropped)", "sim/model/build.py", "return scale * min(1.0, SPREAD_REF / spread)", "return scale",
             [DRIVES, "tests/test_drives_cycle.py"], "tests/test_drives_cycle.py (excavator_cycle compare)"),
    Mutation("spread-one-body", "sim/model/build.py loop_spread: one body's invweight0 only (the second site's "
             "body left out)", "sim/model/build.py",
             "diag = float(model.body_invweight0[a.bodyid[0], 0] + model.body_invweight0[b.bodyid[0], 0])",
             "diag = float(model.body_invweight0[a.bodyid[0], 0])", [DRIVES, "tests/test_drives_cycle.py"],
             "loop_spread by hand on a loop of two known bodies"),
    Mutation("driven-slides-inverted", "analytic/mechanism.py driven_slides: the slides no input drives",
             "analytic/mechanism.py", 'if j.kind == "prismatic" and j.input is not None)',
             'if j.kind == "prismatic" and j.input is None)', [DRIVES, CLI_A],
             "tests/test_drives.py (s_lift reported once)"),
    Mutation("memory-most-refused", "sim/service/analysis.py check_memory: the most that fit refused too (< for <=; "
             "the fault that drops the values a sample lets a 10-million-sample run through: 76 s and 5 GB before "
             "the test fails, so it is not tried here)", "sim/service/analysis.py",
             "    if count <= limit:\n        return\n", "    if count < limit:\n        return\n",
             ["tests/test_run_memory.py"], "tests/test_run_memory.py::test_one_rule_bounds_analyze_forces_and_the_simulation"),
    Mutation("memory-links-undercounted", "sim/service/analysis.py analysis_values: a link's 4 arrays, not 5",
             "sim/service/analysis.py", "5 * len(mech.links)", "4 * len(mech.links)", ["tests/test_run_memory.py"],
             "tests/test_run_memory.py::test_the_analysis_count_covers_every_array_a_solve_makes"),
    Mutation("door-steps-per-revolution", "sim/service/dynamics.py check_motor_steps: the steps counted over one "
             "second, not the run", "sim/service/dynamics.py", "steps = float(d.run.t[-1]) / h", "steps = 1.0 / h",
             ["tests/test_dynamics_door.py"], "tests/test_dynamics_door.py::test_the_step_bound_is_the_doors_..."),
    Mutation("motor-dyad-dd-sign", "analytic/kinds/motor_dyad.py bent: d' of the wrong sign", "analytic/kinds/motor_dyad.py",
             "    dd = -a * b * s * thd / d\n", "    dd = a * b * s * thd / d\n", [KINDS, MRI],
             "the bent link's side against finite differences (tests/kinds/motor_dyad*.toml)"),
    Mutation("motor-dyad-gdd-swapped", "analytic/kinds/motor_dyad.py bent: gamma'' with (a^2 - b^2), not (b^2 - a^2)",
             "analytic/kinds/motor_dyad.py", "gdd = g * thdd + a * b * s * (b * b - a * a) * thd * thd / (d2 * d2)",
             "gdd = g * thdd + a * b * s * (a * a - b * b) * thd * thd / (d2 * d2)", [KINDS, MRI],
             "a motor_dyad's accelerations against finite differences"),
    Mutation("motor-dyad-gd-dropped-cos", "analytic/kinds/motor_dyad.py bent: gamma' = b^2 / d^2 theta' (the a b "
             "cos term dropped)", "analytic/kinds/motor_dyad.py", "g = b * (b + a * c) / d2", "g = b * b / d2",
             [KINDS, MRI], "a motor_dyad's rates against finite differences"),
    Mutation("motor-dyad-on-sign", "analytic/kinds/motor_dyad.py roles: the housing on the second link keeps "
             "theta = +q", "analytic/kinds/motor_dyad.py", "else (second, first, -1)", "else (second, first, 1)",
             [KINDS, MRI], "tests/kinds/motor_dyad__on_second.toml"),
    Mutation("motor-from-pmks-reversed", "analytic/kinds/motor.py from_pmks: PMKS's first link driven, relative to "
             "the second", "analytic/kinds/motor.py", '"link": links[1]}', '"link": links[0]}',
             [MRI, "tests/test_input_plugin.py"], "a PMKS driver between two moving links: the second link turns"),
    Mutation("covers-turn-any-law", "analytic/cycle.py covers_turn: any motion law's cycle taken as the turn's "
             "check (a law that swings back included)", "analytic/cycle.py",
             "return law is not None and law.rise != 0.0 and self.revolutions == 1.0",
             "return law is not None and self.revolutions == 1.0", [GUARDS, SOLVES, LAWS],
             "tests/test_solve_counts.py::test_a_motion_law_that_cannot_turn_fully_is_refused_with_its_limits"),
    Mutation("jump-rest-poses-always-shared", "sim/service/forces.py jump_speed: the run's rest poses read whatever "
             "the samples", "sim/service/forces.py",
             "sol=run.rest if _at_poses(run.rest, run.solution, mech) else None", "sol=run.rest", [SOLVES, CAMS],
             "tests/test_solve_counts.py::test_jump_speed_of_other_poses_does_not_read_the_runs_rest_poses"),
    Mutation("jump-rest-rows-shifted", "sim/service/forces.py _solved: the rest poses taken from the moving rows "
             "(the interleave's even rows)", "sim/service/forces.py",
             "return take(sol, slice(0, None, 2)), take(sol, slice(1, None, 2))",
             "return take(sol, slice(0, None, 2)), take(sol, slice(0, None, 2))", [SOLVES, CAMS],
             "tests/test_solve_counts.py::test_jump_speed_from_the_shared_rest_poses_is_the_one_solved_apart"),
    Mutation("cam-contact-cycle-first-rows", "sim/run/cams.py _one_cycle: the first 721 dense samples, not every "
             "5th over the period", "sim/run/cams.py", "rows = cycle.dense[::SAMPLES // CONTACT_SAMPLES]",
             "rows = cycle.dense[:CONTACT_SAMPLES + 1]", [SOLVES],
             "tests/test_solve_counts.py::test_cam_contact_from_the_cycle_is_the_one_solved_apart"),
    Mutation("forces-memo-not-keyed", "linkage/results.py Forces._record: one record whatever the display (the "
             "first asked for kept)", "linkage/results.py", "        key = display or SI\n", "        key = SI\n",
             [GUARDS, SOLVES, "tests/test_force_units_display.py", UNITS],
             "to_dict in mm after passed (SI): the record in mm"),
    Mutation("lazy-loaded-imports", "analytic/_common.py LazyKinds.loaded: imports the kind's module (as []) ",
             "analytic/_common.py", "        return self._entries.get(name)\n",
             "        return self[name] if name in self else None\n", [STARTUP],
             "tests/test_startup_imports.py (a command loads only the kinds it uses)"),
    Mutation("lazy-loads-no-getattr", "analytic/loads/__init__.py: the package's PEP 562 __getattr__ gone (a load "
             "kind's module no attribute of the package until imported: the bug 4f7911f fixed)", "analytic/loads/__init__.py",
             "def __getattr__(name: str):", "def _getattr(name: str):", [STARTUP, "tests/test_loads.py"],
             "tests/test_startup_imports.py::test_every_kinds_module_is_an_attribute_of_its_package_though_imported_lazily"),
    Mutation("lazy-kinds-modules-case", "analytic/kinds/__init__.py: MODULES as the sections' names unlowered "
             "(analytic.kinds.crank no attribute)", "analytic/kinds/__init__.py",
             "MODULES = tuple(name.lower() for name in SECTIONS)", "MODULES = tuple(name for name in SECTIONS)",
             [STARTUP, KINDS], "tests/test_startup_imports.py (each kind's module an attribute of its package)"),
    Mutation("blas-threads-forced", "sim/front/launch.py: one OpenBLAS thread even where the user set "
             "OPENBLAS_NUM_THREADS", "sim/front/launch.py", 'os.environ.setdefault("OPENBLAS_NUM_THREADS", BLAS_THREADS)',
             'os.environ["OPENBLAS_NUM_THREADS"] = BLAS_THREADS', [STARTUP],
             "tests/test_startup_imports.py::test_a_command_asks_openblas_for_one_thread_unless_told"),
    Mutation("panel-arm-in-radians", "sim/service/cam_editing.py view: an arm's lift sent in rad labelled deg",
             "sim/service/cam_editing.py", "f = math.degrees(1.0) if arm else 1.0 / k", "f = 1.0 if arm else 1.0 / k",
             [PANEL, APP_CAM], "tests/test_app_cam.py (an oscillating cam's SVAJ by hand)"),
    Mutation("panel-rho-in-metres", "sim/service/cam_editing.py view: the profile's rho in metres labelled in the "
             "file's unit", "sim/service/cam_editing.py", '"rho": _list(rho[pick] / k)', '"rho": _list(rho[pick])',
             [PANEL, APP_CAM], "the profile's rho in a mm file by hand (a circle's)"),
    Mutation("panel-pa-max-signed", "sim/service/cam_editing.py view: the largest pressure angle's mark at the most "
             "positive angle, not the largest |angle|", "sim/service/cam_editing.py",
             "i_pa = int(np.nanargmax(np.abs(pa)))", "i_pa = int(np.nanargmax(pa))", [PANEL, APP_CAM],
             "tests/test_app_cam.py::test_the_largest_pressure_angle_is_the_pitch_curve_normal_against_the_guide"),
    Mutation("panel-base-radius-not-written", "sim/service/cam_editing.py edited_text: a base radius edit not "
             "written into a TOML file", "sim/service/cam_editing.py",
             'for key in ("roller", "base_radius"):\n        if key in edit:\n            table[key] = edit[key]',
             'for key in ("roller",):\n        if key in edit:\n            table[key] = edit[key]', [PANEL, APP_CAM], "an edit of base_radius written and read back"),
    # --- the forces replay carrying the work balance's end-of-step evaluations (simulate.Ends, issue 38)
    # (measured: without tests/test_replay_faults.py 30 of 42 killed, with it 39 of 42; the 3 left are equivalent,
    # each says why: --only ends-pending-start-state ... valve-test-masks-swapped [--without tests/test_replay_faults.py])
    Mutation("ends-pending-start-state", "sim/run/simulate.py replay: step k's end evaluated on its START state "
             "(the pending map keyed k, not k + 1)", "sim/run/simulate.py",
             "{k + 1: n for n, k in enumerate(np.asarray(ends.steps).tolist())}",
             "{k: n for n, k in enumerate(np.asarray(ends.steps).tolist())}", REPLAY,
             "test_compare_evaluations: the carried accelerations against a fresh mj_forward of state k + 1"),
    Mutation("ends-inputs-not-swapped", "sim/run/simulate.py replay: the end state evaluated under the replayed "
             "step's own controls and wrenches (step k's inputs not set before mj_forwardSkip)", "sim/run/simulate.py",
             "                    mujoco.mj_setState(model, data, ends.inputs[n], ends.sig)\n", "", REPLAY,
             "the carried accelerations under step k's controls and wrenches (cam_roller's spring changes each step)"),
    Mutation("ends-skip-from-pos", "sim/run/simulate.py replay: the carried evaluation skips the position stage "
             "only (mjSTAGE_POS, velocity stage redone)", "sim/run/simulate.py",
             "mujoco.mjtStage.mjSTAGE_VEL, 1)", "mujoco.mjtStage.mjSTAGE_POS, 1)", REPLAY,
             "EQUIVALENT: the velocity stage reads neither ctrl nor xfrc_applied (mj_fwdVelocity), so it recomputes "
             "the same values; a cost only"),
    Mutation("replay-skip-from-pos", "sim/run/simulate.py replay: each replayed state evaluated from mjSTAGE_POS "
             "(the positions' stage of the previous state kept; the reverse of the carried evaluation's skip)",
             "sim/run/simulate.py", "mujoco.mjtStage.mjSTAGE_NONE, 0 if sensors else 1)",
             "mujoco.mjtStage.mjSTAGE_POS, 0 if sensors else 1)", REPLAY,
             "the replayed forces against the analytic ones (test_forces_mujoco)"),
    Mutation("ends-read-before-eval", "sim/run/simulate.py replay: the end evaluation read before its "
             "mj_forwardSkip (the replayed step's own qacc)", "sim/run/simulate.py",
             "                    mujoco.mj_forwardSkip(model, data, mujoco.mjtStage.mjSTAGE_VEL, 1)\n"
             "                    ends.read(n, data)\n",
             "                    ends.read(n, data)\n"
             "                    mujoco.mj_forwardSkip(model, data, mujoco.mjtStage.mjSTAGE_VEL, 1)\n", REPLAY,
             "the carried accelerations against fresh evaluations under step k's inputs"),
    Mutation("ends-energy-not-enabled", "sim/run/simulate.py replay: mjENBL_ENERGY not set for a request that "
             "reads the energies", "sim/run/simulate.py", "    if ends is not None and ends.energy:\n",
             "    if False:\n", REPLAY, "the carried energies against simulate.energies"),
    Mutation("ends-energy-flag-kept", "sim/run/simulate.py replay: the model's enable flags not restored (energy "
             "left on)", "sim/run/simulate.py", "    finally:\n        model.opt.enableflags = flags\n    return (out",
             "    finally:\n        pass\n    return (out", REPLAY,
             "the values equal (the energy flag adds mj_energyPos/Vel to later evaluations, no other output), the "
             "built model changed: test_replay_faults (the model's flags as the replay found them)"),
    Mutation("replay-sensors-always-skipped", "sim/run/simulate.py replay: the sensors never evaluated (the "
             "sensors flag ignored)", "sim/run/simulate.py", "0 if sensors else 1)", "1)", REPLAY,
             "test_forces_mujoco::test_the_replay_reproduces_the_rollout (reads sensordata)"),
    Mutation("evaluate-ends-skip-vel", "sim/run/simulate.py _evaluate_ends: a fresh state evaluated from "
             "mjSTAGE_VEL (the positions' and velocities' stages of the previous state kept)", "sim/run/simulate.py",
             "mujoco.mj_forwardSkip(model, data, mujoco.mjtStage.mjSTAGE_NONE, 1)",
             "mujoco.mj_forwardSkip(model, data, mujoco.mjtStage.mjSTAGE_VEL, 1)", REPLAY,
             "the end evaluations run alone (no replay) against fresh mj_forward"),
    Mutation("evaluate-ends-inputs-not-set", "sim/run/simulate.py _evaluate_ends: the end states evaluated without "
             "their step's controls and wrenches", "sim/run/simulate.py",
             "        mujoco.mj_setState(model, data, state, sig)\n        mujoco.mj_setState(model, data, ends.inputs[n], "
             "ends.sig)\n", "        mujoco.mj_setState(model, data, state, sig)\n", REPLAY,
             "tests/test_replay_faults.py::test_every_end_evaluation_is_a_fresh_mj_forward_whichever_path_made_it[cam_roller-alone]"),
    Mutation("evaluate-ends-start-state", "sim/run/simulate.py _evaluate_ends: the state before the one pending "
             "(k, not k + 1)", "sim/run/simulate.py", "_states(built, tr, np.asarray(at, dtype=int))",
             "_states(built, tr, np.asarray(at, dtype=int) - 1)", REPLAY,
             "the end evaluations run alone against fresh mj_forward of state k + 1"),
    Mutation("replay-controls-next-step", "sim/run/simulate.py replay: each replayed state under the next step's "
             "controls", "sim/run/simulate.py", "controls(built, steps * built.timestep)",
             "controls(built, (steps + 1) * built.timestep)", REPLAY,
             "the replayed drive force against the rollout's sensor (a drive whose control changes)"),
    Mutation("states-wrenches-next-step", "sim/run/simulate.py _states: the file's loads' wrenches of the next "
             "step", "sim/run/simulate.py", "parts.append(wrenches(built, t).xfrc",
             "parts.append(wrenches(built, t + built.timestep).xfrc", REPLAY,
             "the replayed forces of a run with loads against the analytic ones"),
    Mutation("ends-pending-not-popped", "sim/run/simulate.py replay: the carried ends left pending (evaluated "
             "again, whole, after the replay)", "sim/run/simulate.py", "n = pending.pop(k, None)",
             "n = pending.get(k)", REPLAY,
             "values equal (a fresh evaluation gives the same): tests/test_replay_faults.py::"
             "test_compare_carries_every_end_evaluation_of_a_cam_on_its_forces_replay"),
    Mutation("contacts-rows-from-0", "sim/run/forces.py contacts_reader: the contact rows counted from 0, not "
             "from data.ne (equality rows read as contacts)", "sim/run/forces.py",
             "zip(data.efc_id[ne:n].tolist(), data.efc_force[ne:n].tolist())",
             "zip(data.efc_id[:n].tolist(), data.efc_force[:n].tolist())", REPLAY,
             "test_compare_evaluations::test_a_cams_contact_force_is_mujocos_contact_force[cam_fourbar]"),
    Mutation("contacts-last-row-only", "sim/run/forces.py contacts_reader: a cam's force the last of its contact "
             "rows, not their sum", "sim/run/forces.py", "                    out[k] += f\n",
             "                    out[k] = f\n", REPLAY, "cam_flat's face touching at several points"),
    Mutation("contacts-sign", "sim/run/forces.py contacts_reader: a contact row's force with the wrong sign",
             "sim/run/forces.py", "                    out[k] += f\n", "                    out[k] -= f\n", REPLAY,
             "the cam's contact force against mj_contactForce"),
    Mutation("contacts-one-order", "sim/run/forces.py contacts_reader: a pair matched in the order (cam, follower) "
             "only", "sim/run/forces.py", "which[a, b] = which[b, a] = k", "which[a, b] = k", REPLAY,
             "a contact whose geoms come (follower, cam)"),
    Mutation("contacts-wrong-cam", "sim/run/forces.py contacts_reader: the pairs matched to the cams in reverse "
             "order", "sim/run/forces.py", "which[a, b] = which[b, a] = k",
             "which[a, b] = which[b, a] = len(pairs) - 1 - k", REPLAY,
             "tests/test_replay_faults.py::test_two_cams_on_one_shaft_each_report_their_own_followers_contact_force (tests/"
             "mechanisms/cam_twin.toml; no shipped mechanism has two cams)"),
    Mutation("reader-eq-all-rows", "sim/run/forces.py reader: every constraint row read as an equality's (the "
             "contact rows counted again)", "sim/run/forces.py", "        eq = data.ne  ", "        eq = data.nefc  ",
             REPLAY, "a cam's replay (rows that come and go)"),
    Mutation("settle-contacts-too", "sim/run/forces.py settle: the dual solve applied whatever the rows (contact "
             "rows treated as equalities)", "sim/run/forces.py", "    if n and data.ne == n:", "    if n:", REPLAY,
             "a cam's contact force against mj_contactForce after the replay's reader"),
    Mutation("settle-mixed-rows", "sim/run/forces.py settle: the dual solve applied where any equality row is "
             "(cam_fourbar's loops and contacts together)", "sim/run/forces.py", "    if n and data.ne == n:",
             "    if n and data.ne:", REPLAY, "tests/test_replay_faults.py::test_the_replays_contact_force_is_mujocos_with_loop_rows_before_it"),
    Mutation("reader-no-settle", "sim/run/forces.py reader: the primal solver's forces kept (settle dropped)",
             "sim/run/forces.py", "        settle(model, data)\n        eq = data.ne", "        eq = data.ne", REPLAY,
             "test_forces_mujoco (a rocking four-bar's loop forces)"),
    Mutation("record-sensors-on", "sim/run/forces.py record: the replay evaluates the sensors (sensors=False "
             "dropped)", "sim/run/forces.py", "ends, sensors=False)", "ends, sensors=True)", REPLAY,
             "EQUIVALENT: the reader reads no sensor; a cost only"),
    Mutation("end-request-ctrl-next", "sim/run/compare.py _end_request: step k's end under step k + 1's controls",
             "sim/run/compare.py", "sig, parts = S.mjSTATE_CTRL, [ctrl[steps]]",
             "sig, parts = S.mjSTATE_CTRL, [ctrl[steps + 1]]", REPLAY,
             "tests/test_replay_faults.py::test_every_end_evaluation_is_a_fresh_mj_forward_whichever_path_made_it[fivebar "
             "cutting-*] (the load's control switches; the shaper's work balance alone does not notice)"),
    Mutation("end-request-xfrc-next", "sim/run/compare.py _end_request: step k's end under step k + 1's wrenches",
             "sim/run/compare.py", "parts.append(xfrc[steps].reshape(", "parts.append(xfrc[steps + 1].reshape(",
             REPLAY, "the carried accelerations under step k's wrenches (cam_roller's spring)"),
    Mutation("end-request-no-xfrc-bit", "sim/run/compare.py _end_request: the wrenches in the inputs but not in "
             "their signature (not set)", "sim/run/compare.py", "        sig |= S.mjSTATE_XFRC_APPLIED\n"
             "        parts.append(xfrc[steps]", "        parts.append(xfrc[steps]", REPLAY,
             "the carried accelerations under step k's wrenches"),
    Mutation("end-request-energy-dropped", "sim/run/compare.py _end_request: the request does not ask for the "
             "energies (Ends.energy False)", "sim/run/compare.py", "int(sig), read, energy)", "int(sig), read)",
             REPLAY, "the carried energies against simulate.energies"),
    Mutation("answer-energy-rows-start", "sim/run/compare.py answer: the end energies stored at the steps' "
             "start rows", "sim/run/compare.py", "energies[steps + 1] = energy_at", "energies[steps] = energy_at",
             REPLAY, "the energies against simulate.energies"),
    Mutation("answer-energies-swapped", "sim/run/compare.py answer: kinetic and potential swapped",
             "sim/run/compare.py", "return out, (energies[:, 1], energies[:, 0])",
             "return out, (energies[:, 0], energies[:, 1])", REPLAY, "the energies against simulate.energies"),
    Mutation("energy0-next-state", "sim/run/compare.py answer: the first energy from the second state",
             "sim/run/compare.py", "_energy(model, tr.qpos[0], tr.qvel[0])", "_energy(model, tr.qpos[1], tr.qvel[1])",
             REPLAY, "the energies against simulate.energies"),
    Mutation("answer-first-dofs", "sim/run/compare.py answer: the first len(drives) accelerations, not the "
             "drives' dofs", "sim/run/compare.py", "qacc[:, dofs].tolist()", "qacc[:, :len(dofs)].tolist()", REPLAY,
             "tests/test_replay_faults.py::test_every_end_evaluation_is_a_fresh_mj_forward_whichever_path_made_it[fivebar "
             "cutting-*] (its second drive is dof 3)"),
    Mutation("answer-seen-any", "sim/run/compare.py answer: the request evaluated alone only where no end at all "
             "was carried", "sim/run/compare.py", "if not seen.all():", "if not seen.any():", REPLAY,
             "EQUIVALENT: a replay evaluates every pending end state before it returns (_evaluate_ends)"),
    Mutation("compare-ends-not-carried", "sim/run/compare.py compare: the forces check not given the request "
             "(the end states evaluated again, alone)", "sim/run/compare.py",
             "joint_forces.check(built, tr, solved=solved, ends=ends.request)",
             "joint_forces.check(built, tr, solved=solved)", REPLAY,
             "values equal: tests/test_replay_faults.py::test_compare_carries_every_end_evaluation_of_a_cam_on_its_forces_replay"),
    Mutation("judged-inverted", "sim/run/compare.py compare: work_judged inverted (judged with a cam, not without)",
             "sim/run/compare.py", "judged = floors is None", "judged = floors is not None", REPLAY,
             "test_independent (work_tol 1e-3), test_cam_mechanism (work_tol None)"),
    Mutation("work-tol-always", "sim/run/compare.py as_dict: work_tol given with a cam too", "sim/run/compare.py",
             '"work_tol": WORK_TOL if self.work_judged else None', '"work_tol": WORK_TOL', REPLAY,
             "test_cam_mechanism (a cam's JSON work_tol null)"),
    Mutation("cam-balance-judged", "sim/run/compare.py compare: a cam's work balance judged after all",
             "sim/run/compare.py", "(balance <= WORK_TOL or not judged)", "(balance <= WORK_TOL)", REPLAY,
             "test_cam_mechanism (cam_roller passes; its balance 2.6 % of the swing)"),
    Mutation("judged-not-passed", "sim/run/compare.py compare: work_judged not passed to the Comparison (default "
             "True)", "sim/run/compare.py", "forces=forces,\n                      work_judged=judged)",
             "forces=forces)", REPLAY, "test_cam_mechanism (a cam's JSON work_tol null)"),
    Mutation("text-verdict-inverted", "sim/run/compare.py text: the 'reported, not judged' line shown where it is "
             "judged and the tolerance where it is not", "sim/run/compare.py", "if c.work_judged else",
             "if not c.work_judged else", REPLAY, "tests/test_replay_faults.py::test_compares_text_says_a_cams_work_balance_is_reported_not_judged"),
    Mutation("valve-roller-diameter", "tests/mechanisms/cam_valve_textbook.toml: the roller's 20 mm diameter given "
             "as its radius", "tests/mechanisms/cam_valve_textbook.toml", "roller = 10\n", "roller = 20\n", [CAMS],
             "test_cams::test_a_textbook_valve_cam_to_its_printed_answers (the closed valve's 35 mm)"),
    Mutation("valve-fall-quarter-turn", "tests/mechanisms/cam_valve_textbook.toml: the fall in 1/4 turn, not 1/6",
             "tests/mechanisms/cam_valve_textbook.toml",
             '{ shape = "harmonic", duration = "60deg", rise = -50 },\n  { shape = "dwell", duration = "150deg" }',
             '{ shape = "harmonic", duration = "90deg", rise = -50 },\n  { shape = "dwell", duration = "120deg" }',
             [CAMS], "the printed 0.78 m/s and 24.67 m/s2 of the lowering"),
    Mutation("valve-test-masks-swapped", "tests/test_cams.py textbook valve: the raising and lowering masks "
             "swapped (the test itself wrong: it must then fail)", "tests/test_cams.py",
             "raising, lowering = (turn > 0) & (turn < 120), (turn > 150) & (turn < 210)",
             "lowering, raising = (turn > 0) & (turn < 120), (turn > 150) & (turn < 210)", [CAMS],
             "the test's own printed answers (0.39 against 0.78 m/s)"),
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
    ap.add_argument("--without", nargs="*", default=[], metavar="TEST_FILE",
                    help="leave these test files out of every mutation's tests (what the suite caught before them)")
    args = ap.parse_args(argv)
    muts = [m for m in MUTATIONS if not args.only or m.id in args.only]
    if args.without:
        gone = {str(Path(t)) for t in args.without}
        muts = [replace(m, tests=[t for t in m.tests if t not in gone]) for m in muts]
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
            if not m.tests:
                rows.append((m, None, None, "SURVIVED (no tests)"))
                print(f"{m.id:<22s} SURVIVED: no test file left", flush=True)
                shutil.rmtree(work, ignore_errors=True)
                continue
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
    survivors = [(m, v) for m, res, mir, v in rows if v.startswith("SURVIVED")]
    killed = sum(1 for _, _, _, v in rows if v.startswith("killed"))
    print(f"\nkilled {killed} of {len(rows)}; survived {len(survivors)}")
    if survivors:
        print("\nsurvivors and the test that should have caught them:")
        for m, _ in survivors:
            print(f"  {m.id}: {m.what}\n    -> {m.should_catch}")


if __name__ == "__main__":
    sys.exit(main())
