"""The results the door's functions return: frozen objects with attributes, and ``to_dict()``, the object
the matching command prints with ``--json`` (SI; the same numbers, as plain lists, floats and ``None``
where JSON has no NaN). Each keeps the service's own result (``.run``, ``.comparison``, ...) for what the
attributes do not show."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

__all__ = ["Analysis", "Simulation", "Comparison", "Forces", "Dynamics", "Export", "Tolerance", "Synthesis",
           "Sweep"]


def _plain(record: dict) -> dict:
    """A record as ``--json`` prints it: numpy arrays as lists, non-finite floats as None (a new object)."""
    from sim.output.jsonout import clean
    return clean(record)


class _Result:
    """What every result shares: ``to_dict()`` and a notebook view (``_repr_html_``)."""

    _file_forces = False
    """Whether ``units=`` also puts forces in the file's ``force_units`` (as ``forces`` and ``dynamics`` do)."""

    def to_dict(self, *, units: str | None = None, angles: str | None = None, speeds: str | None = None,
                display=None) -> dict:
        """The object the command prints with ``--json``: SI, or as ``--units``/``--angles``/``--speeds``
        ask (``units="mm"``, ``angles="deg"``, ``speeds="rpm"``; or a ready
        :class:`analytic.quantities.Display`)."""
        if display is None and (units or angles or speeds):
            from types import SimpleNamespace
            from sim.output.units import machine_units
            asked = SimpleNamespace(units=units, angles=angles, speeds=speeds)
            display = machine_units(asked, getattr(self, "mechanism", None) if self._file_forces else None)
        return _plain(self._record(display))

    def _repr_html_(self) -> str:
        from linkage.notebook import result_html
        return result_html(self)

    def _view(self) -> tuple:
        """What the notebook view draws and adds to its table: (the solution to animate, None for one cycle
        of the mechanism, or False for no drawing; extra (name, value) rows)."""
        return None, []


@dataclass(frozen=True, repr=False, eq=False)
class Analysis(_Result):
    """Closed-form kinematics over a run (:func:`linkage.analyze`, ``linkage analyze --json``).

    ``a["xE"]``: a column of ``linkage analyze --csv`` (SI array over the samples: ``t``, the inputs, every
    output); ``a.t`` [s]; ``a.figures``: the figures of merit (transmission angle range, time ratio, ...);
    ``a.columns``: every column by name.

    Example:
        >>> a = lk.analyze(lk.load("fourbar"), samples=5)
        >>> a["xE"].shape, round(float(a.t[-1]), 4)
        ((5,), 1.0)
    """

    mechanism: Any
    samples: int
    revolutions: float
    analysis: Any = field(repr=False)
    """The service's result (``sim.service.analysis.Analysis``): t, inputs, solution, figures."""

    @property
    def t(self):
        return self.analysis.t

    @property
    def figures(self) -> dict:
        return self.analysis.figures

    @property
    def columns(self) -> dict:
        from sim.service.analysis import analysis_columns
        return analysis_columns(self.mechanism, self.analysis)

    def __getitem__(self, name: str):
        cols = self.columns
        if name not in cols:
            raise KeyError(f"{name!r} is not a column of the analysis; columns: {', '.join(cols)}")
        return cols[name]

    def _record(self, display):
        from sim.service.analysis import analysis_record
        return analysis_record(self.mechanism, self.analysis, self.samples, self.revolutions, display)

    def __repr__(self) -> str:
        return f"<Analysis of the {self.mechanism.name}: {len(self.t)} samples, columns {', '.join(self.columns)}>"


    def _view(self) -> tuple:
        from linkage.notebook import figure_rows
        return self.analysis.solution, figure_rows(self.to_dict().get("figures", {}))


@dataclass(frozen=True, repr=False, eq=False)
class Simulation(_Result):
    """The MuJoCo model simulated (:func:`linkage.simulate`, ``linkage simulate --json``).

    ``s["xE"]``: a column of ``linkage simulate --csv`` (SI, over the steps); ``s.t``; ``s.steps``;
    ``s.timestep`` [s]; ``s.trajectory``: the whole trajectory (``sim.run.simulate.Trajectory``).

    Example:
        >>> s = lk.simulate(lk.load("fourbar"), revolutions=0.25)
        >>> s.steps > 0 and float(s.loop_violation.max()) < 1e-6
        True
    """

    mechanism: Any
    revolutions: float
    built: Any = field(repr=False)
    trajectory: Any = field(repr=False)

    @property
    def t(self):
        return self.trajectory.t

    @property
    def steps(self) -> int:
        return int(self.trajectory.steps)

    @property
    def timestep(self) -> float:
        return float(self.trajectory.timestep)

    @property
    def loop_violation(self):
        return self.trajectory.loop_violation

    @property
    def columns(self) -> dict:
        from sim.service.simulation import trajectory_columns
        return trajectory_columns(self.trajectory, self.mechanism)

    def __getitem__(self, name: str):
        cols = self.columns
        if name not in cols:
            raise KeyError(f"{name!r} is not a column of the simulation; columns: {', '.join(cols)}")
        return cols[name]

    def _record(self, display):
        from sim.service.simulation import simulation_record
        return simulation_record(self.built, self.trajectory, self.revolutions, display)

    def __repr__(self) -> str:
        tr = self.trajectory
        return f"<Simulation of the {self.mechanism.name}: {tr.steps} steps of {tr.timestep:.3g} s>"


    def _view(self) -> tuple:
        return self.trajectory.outputs, []


@dataclass(frozen=True, repr=False, eq=False)
class Comparison(_Result):
    """The simulation cross-validated against the closed forms (:func:`linkage.compare`, ``linkage compare
    --json``).

    ``c.passed``: every check within its tolerance (and no collision with ``interference=True``);
    ``c.errors``: per output its max and RMS error, peak and tolerance (SI); ``c.trajectory``: the simulated
    run; ``c.interference``: the parts' verdict over the run, or None.

    Example:
        >>> c = lk.compare(lk.load("fourbar"))
        >>> c.passed
        True
    """

    mechanism: Any
    built: Any = field(repr=False)
    comparison: Any = field(repr=False)
    interference: dict | None = None

    @property
    def passed(self) -> bool:
        clash = self.interference
        return bool(self.comparison.passed) and not (clash and clash["interference"])

    @property
    def errors(self) -> dict:
        return self.comparison.errors

    @property
    def trajectory(self):
        return self.comparison.trajectory

    def _record(self, display):
        from sim.service.simulation import comparison_record
        record = comparison_record(self.built, self.comparison, display)
        if self.interference is not None:
            record["interference"] = self.interference
        return record

    def __repr__(self) -> str:
        return f"<Comparison of the {self.mechanism.name}: {'PASSED' if self.passed else 'FAILED'}>"


    def _view(self) -> tuple:
        rows = [("verdict", "PASSED" if self.passed else "FAILED")]
        rows += [(f"{k} error (max / tol)", f"{e['max']:.3g} / {e['tol']:.3g} {e['unit']}")
                 for k, e in list(self.errors.items())[:8]]
        return self.trajectory.outputs, rows


@dataclass(frozen=True, repr=False, eq=False)
class Forces(_Result):
    """Joint forces, drives and shaking along the motion (:func:`linkage.forces`, ``linkage forces --json``).

    ``f.drives["phi1"]``: the drive torque [N m] (a slider: force [N]) over the samples; ``f.joints``: each
    joint's ``Fx``, ``Fy`` (and ``M`` of a prismatic pair) by name; ``f.shaking``: ``Fx, Fy, M``;
    ``f.peaks``: each one's peak and where; ``f.t``; ``f.run``: the service's ``ForceRun``.

    Example:
        >>> f = lk.forces(lk.load("fourbar", l1=0.12), samples=73, gravity=(0, -9.81))
        >>> round(f.peaks["drives"]["phi1"]["value"], 4)
        0.8178
    """

    _file_forces = True
    mechanism: Any
    run: Any = field(repr=False)
    simulated_run: Any = field(default=None, repr=False)
    """MuJoCo's answer (``sim.run.forces.Simulated``) with ``simulate=True``, else None."""
    simulation: tuple = field(default=(None, None), repr=False)
    """(settings, loads) MuJoCo ran with."""

    @property
    def t(self):
        return self.run.t

    @property
    def drives(self) -> dict:
        return {inp.q: self.run.forces.drives[inp.link] for inp in self.mechanism.inputs}

    @property
    def joints(self) -> dict:
        return {j["name"]: j for j in self._si["joints"]}

    @property
    def shaking(self) -> dict:
        return self._si["shaking"]

    @property
    def peaks(self) -> dict:
        return self._si["peaks"]

    @property
    def simulated(self) -> dict | None:
        """The ``simulated`` object of ``--simulate --json`` (its ``passed`` and ``agreement``), or None."""
        return self._si.get("simulated")

    @property
    def passed(self) -> bool:
        """False only where MuJoCo was asked (``simulate=True``) and disagrees."""
        return self.simulated is None or bool(self.simulated.get("passed", False))

    @property
    def _si(self) -> dict:
        return self._record(None)

    def _record(self, display):
        """The record in ``display`` units (None: SI), made once per display: ``passed`` reads the SI one and
        ``to_dict`` the one asked for, the same when that is SI (a cam's jump speed is not found twice)."""
        from analytic.quantities import SI
        records = self.__dict__.setdefault("_records", {})
        key = display or SI
        if key not in records:
            records[key] = self._made(display)
        return records[key]

    def _made(self, display):
        from sim.service.forces import forces_record, simulated_forces
        record = forces_record(self.run, display)
        if self.simulated_run is not None:
            settings, loads = self.simulation
            record["simulated"] = simulated_forces(self.run, settings, loads, display, simulated=self.simulated_run)
        return record

    def __repr__(self) -> str:
        return f"<Forces in the {self.mechanism.name}: {len(self.t)} samples, joints {', '.join(self.joints)}>"


    def _view(self) -> tuple:
        p = self.peaks
        rows = [(f"peak |F| at {j} [N]", e["F"]) for j, e in p["joints"].items()]
        rows += [(f"peak drive {q}", e["value"]) for q, e in p["drives"].items()]
        rows += [("peak shaking force [N]", p["shaking"]["F"]), ("peak shaking moment [N m]", p["shaking"]["M"])]
        return self.run.solution, rows


@dataclass(frozen=True, repr=False, eq=False)
class Dynamics(_Result):
    """A motor drives the linkage (:func:`linkage.dynamics`, ``linkage dynamics --json``).

    ``d.passed``: the reduced equation and MuJoCo agree; ``d.run``: the service's result (its ``run.t``,
    ``run.omega``, ``run.fluctuation``, ...).

    Example:
        >>> d = lk.dynamics(lk.load("fourbar"), motor=(2.0, 15.0), revolutions=3)
        >>> d.passed
        True
    """

    _file_forces = True
    mechanism: Any
    run: Any = field(repr=False)

    @property
    def passed(self) -> bool:
        return bool(self.run.passed)

    def _record(self, display):
        from sim.service import dynamics as D
        two = len(self.mechanism.inputs) == 2
        record = D.record_two(self.run) if two else D.record(self.run)
        return D.in_units(record, display) if display is not None else record

    def __repr__(self) -> str:
        return f"<Dynamics of the {self.mechanism.name}: {'PASS' if self.passed else 'FAIL'}>"


@dataclass(frozen=True, repr=False, eq=False)
class Export(_Result):
    """The generated MuJoCo model and the mechanism file (:func:`linkage.export`): ``e.mjcf`` (MJCF text),
    ``e.toml`` (the ``linkage/1`` file with the current values), ``e.loads_left_out`` (loads MJCF cannot
    hold). ``to_dict()``: these three and the mechanism's name (``linkage export`` prints no JSON).

    Example:
        >>> e = lk.export(lk.load("fourbar", l1=0.12))
        >>> "<mujoco" in e.mjcf and "l1 = 0.12" in e.toml
        True
    """

    mechanism: Any
    mjcf: str = field(repr=False)
    toml: str = field(repr=False)
    loads_left_out: tuple = ()

    def _record(self, display):
        return {"mechanism": self.mechanism.name, "mjcf": self.mjcf, "toml": self.toml,
                "loads_left_out": list(self.loads_left_out)}

    def __repr__(self) -> str:
        return f"<Export of the {self.mechanism.name}: MJCF {len(self.mjcf)} chars, file {len(self.toml)} chars>"


    def _view(self) -> tuple:
        rows = [("mechanism", self.mechanism.name), ("MJCF", f"{len(self.mjcf)} characters"),
                ("file", f"{len(self.toml)} characters"), ("loads left out", "; ".join(self.loads_left_out))]
        return False, rows


@dataclass(frozen=True, repr=False, eq=False)
class Tolerance(_Result):
    """The spread of results under the parameters' tolerances (:func:`linkage.tolerance`, ``linkage
    tolerance --json``): ``t.result`` (Monte Carlo, first-order and Sobol answers); ``t.outputs``: each
    output's record (mean, std, percentiles, what drives it).

    Example:
        >>> t = lk.tolerance(lk.load("fourbar"), tol={"l1": "±0.1"}, samples=50)
        >>> sorted(t.outputs)[:2]
        ['path_deviation', 'peak_joint_force']
    """

    mechanism: Any
    result: Any = field(repr=False)

    @property
    def outputs(self) -> dict:
        return self.to_dict()["outputs"]

    def _record(self, display):
        from sim.service.tolerance import tolerance_record
        return tolerance_record(self.result, self.mechanism, display)

    def __repr__(self) -> str:
        return f"<Tolerance of the {self.mechanism.name}>"


@dataclass(frozen=True, repr=False, eq=False)
class Synthesis(_Result):
    """A synthesis (:func:`linkage.synthesize`, ``linkage synthesize ... --json``). Two-position:
    ``s.optimum`` (the best design's record, or None), ``s.rows`` (the designs at the paper's coupler
    rotations), ``s.excluded``. Function and motion: ``s.designs`` (best first, each with its parameters,
    measures, ``text`` (its ``linkage/1`` file) and MuJoCo's verdict), ``s.best`` (the first that meets the
    limits and passes ``compare``, or None), ``s.rejected``.

    Example:
        >>> s = lk.synthesize("two-position", E1=(30, 31), E2=(5, 47), A=(0, 0), D=(60, 0),
        ...                   crank_rotation="60deg", rocker_rotation="30deg")
        >>> round(s.optimum["total"], 2) > 0
        True
    """

    problem: str
    record: dict = field(repr=False)

    @property
    def optimum(self):
        return self.record.get("optimum")

    @property
    def rows(self) -> list:
        return self.record.get("rows", [])

    @property
    def excluded(self) -> list:
        return self.record.get("excluded", [])

    @property
    def designs(self) -> list:
        return self.record.get("designs", [])

    @property
    def rejected(self) -> list:
        return self.record.get("rejected", [])

    @property
    def best(self):
        return next((d for d in self.designs if d["compare_passed"] and d["simulated"]["passed"]), None)

    def _record(self, display):
        if "designs" not in self.record:
            return self.record
        return {"designs": [{k: v for k, v in d.items() if k != "text"} for d in self.designs],
                "rejected": self.rejected}

    def __repr__(self) -> str:
        found = self.optimum if "designs" not in self.record else self.best
        return f"<Synthesis {self.problem}: {'a design' if found else 'no design'}>"

    def _view(self) -> tuple:
        return False, _scalars_of(self.optimum or self.best or {})


@dataclass(frozen=True, repr=False, eq=False)
class Sweep(_Result):
    """A parameter study (:func:`linkage.sweep`): ``s.rows`` (one per combination, its ``params``,
    ``values`` and ``valid``), ``s["area"]``: a column of ``linkage sweep --csv`` (SI). ``to_dict()``:
    ``{"mechanism", "vary", "columns", "units"}``, the CSV's columns and units (the command prints no JSON).

    Example:
        >>> s = lk.sweep(lk.load("fourbar"), vary={"l1": [0.1, 0.12]}, samples=36)
        >>> len(s.rows), bool(s["valid"].all())
        (2, True)
    """

    mechanism: Any
    vary: dict
    rows: list = field(repr=False)

    @property
    def columns(self) -> dict:
        from sim.service.design import sweep_columns
        return sweep_columns(self.mechanism, list(self.vary), self.rows, None)[0]

    def __getitem__(self, name: str):
        return self.columns[name]

    def _record(self, display):
        from sim.service.design import sweep_columns
        cols, units = sweep_columns(self.mechanism, list(self.vary), self.rows, display)
        return {"mechanism": self.mechanism.name, "vary": self.vary, "columns": cols, "units": units}

    def __repr__(self) -> str:
        return f"<Sweep of the {self.mechanism.name}: {len(self.rows)} combinations>"

    def _view(self) -> tuple:
        return False, [("combinations", len(self.rows)), ("valid", sum(bool(r.valid) for r in self.rows)),
                       ("varied", ", ".join(self.vary))]


def _scalars_of(d: dict) -> list[tuple]:
    return [(k, v) for k, v in d.items() if isinstance(v, (bool, int, float, str))]
