"""The service layer: the documented Python API that every front end (the ``linkage`` command, the web app)
and every script goes through. Plain functions on :class:`analytic.Mechanism`, no argparse; errors are
:class:`analytic.ParameterError` with one-line messages that speak of parameters, not of command-line flags.

One module per use case:

- :mod:`.mechanisms`: load a mechanism by name or file, its parameters, its drawing;
- :mod:`.analysis`: closed-form kinematics over a run (``analyze``) and its figures of merit;
- :mod:`.simulation`: the MuJoCo model simulated and cross-checked (``simulate``, ``compare``);
- :mod:`.forces`: joint forces, drives, shaking, balancing (``forces_run``), and MuJoCo's answer;
- :mod:`.export`: the MJCF model and the mechanism file as text;
- :mod:`.loads`: the loads a run applies and their work (``[[loads]]``, ``--force``, ``--torque``, ``--at``);
- :mod:`.dynamics`: the motor-driven run (``dynamics``, the app's Dynamics tab), its models built from one cycle;
- :mod:`.importing`: Pyslvs and PMKS files as ``linkage/1`` (``import``); :mod:`.structure`: ``check``'s report;
  :mod:`.values`: typed numbers and angles; :mod:`.catalog`: the library's names and headers (no numpy);
- :mod:`.design`: synthesis (path, motion, function, two-position) and sweeps; :mod:`.pareto` the
  multi-objective search; :mod:`.synth_checks` the simulation of every returned design;
- :mod:`.tolerance`: Monte Carlo, first-order and Sobol tolerance analysis;
- :mod:`.parts`: link solids, layers, interference, DXF/SVG/PDF/STEP/STL exports and the bill of materials.
- the app's use cases: :mod:`.editing` (a point dragged: the file's values that place it; a drawn linkage's
  groups), :mod:`.opening` (a file as ``linkage/1`` text),
  :mod:`.load_editing` (the file's loads drawn and checked), :mod:`.cam_editing` (a cam's law, SVAJ and profile
  for the cam panel, its segments edited), :mod:`.path_targets` (path synthesis from placed
  points), :mod:`.inputs` (input values from text), :mod:`.viewing` (the figures' summary).

The first five's names are given here (imported on first use, so that ``from sim import service`` stays light),
so ``from sim import service; service.load("my_linkage.toml")`` reaches them; the others load scipy, pymoo, SALib,
shapely or a CAD kernel and are imported by name when used (``from sim.service import design``). MuJoCo and matplotlib are imported only by the functions that need
them, so analysis stays fast.
"""

from __future__ import annotations

import lazy_loader

from sim.service.catalog import list_mechanisms

_LAZY = {
    "mechanisms": ("parameter_value", "load", "parameter_table", "describe", "link_drawing"),
    "analysis": ("MAX_SAMPLES", "MAX_REVOLUTIONS", "Analysis", "check_samples", "check_revolutions", "check_range",
                 "analyze", "figures", "check_turns_fully", "analysis_record", "units_table", "parameters_record",
                 "analysis_columns", "units_of"),
    "simulation": ("check_singular", "CHANGE_SWING", "check_change_swing", "CHANGE_START", "CHANGE_SHIFT",
                   "clear_of_change_point", "start_note", "change_points", "passes_smoothly", "prepare",
                   "check_folded_change_points", "check_fold", "simulate", "compare", "comparison_record",
                   "trajectory_columns"),
    "export": ("export_mjcf", "mechanism_text", "table_text"),
    "forces": ("ForceRun", "check_forces_singular", "mass_sources", "forces_run", "force_peaks", "forces_record",
               "loads_table", "balance_record", "forces_columns", "forces_table", "balanced_mechanism",
               "simulated_forces_run", "simulated_forces"),
}
"""The use-case modules whose names this package gives, each imported on the first access to one of them
(they load numpy): ``from sim import service`` costs nothing until a function is used."""


SUBMODULES = ("analysis", "cam_editing", "catalog", "design", "dynamics", "editing", "export", "forces", "importing", "inputs",
              "load_editing", "loads", "mechanisms", "opening", "pareto", "parts", "path_targets", "simulation",
              "structure", "sweep_forces", "synth_checks", "tolerance", "values", "viewing")
"""Every use-case module, imported on its first access (``service.design``)."""

# PEP 562 by lazy_loader: ``service.analyze`` imports :mod:`.analysis` on first use; a submodule by its name
__getattr__, __dir__, _ = lazy_loader.attach(__name__, submodules=SUBMODULES, submod_attrs=_LAZY)

__all__ = ["list_mechanisms", "parameter_value", "load", "parameter_table", "describe",
           "link_drawing", "MAX_SAMPLES", "MAX_REVOLUTIONS", "Analysis", "check_samples", "check_revolutions",
           "check_range", "analyze", "figures", "check_turns_fully", "analysis_record", "units_table",
           "parameters_record", "analysis_columns", "units_of", "check_singular", "CHANGE_SWING",
           "check_change_swing", "CHANGE_START", "CHANGE_SHIFT", "clear_of_change_point", "start_note",
           "change_points", "passes_smoothly", "prepare", "check_folded_change_points", "check_fold", "simulate",
           "compare", "comparison_record", "trajectory_columns", "export_mjcf", "mechanism_text", "table_text", "ForceRun",
           "check_forces_singular", "mass_sources", "forces_run", "force_peaks", "forces_record", "loads_table",
           "balance_record", "forces_columns", "forces_table", "balanced_mechanism", "simulated_forces_run",
           "simulated_forces"]
