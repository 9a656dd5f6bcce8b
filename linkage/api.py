"""The door's functions: each takes its subject first (a mechanism, or a synthesis problem) and every option
as a keyword, runs the service's use case (:mod:`sim.service`) and returns a frozen result
(:mod:`linkage.results`) whose ``to_dict()`` is the object the matching command prints with ``--json``.
The command line (:mod:`sim.front.cli`) calls these same functions with keywords once it has read its
options' text."""

from __future__ import annotations

import os

from analytic.errors import ParameterError
from linkage._inputs import at_value as _at, input_range_of
from linkage.results import (Analysis, Comparison, Dynamics, Export, Forces, Simulation, Sweep, Synthesis,
                             Tolerance)

__all__ = ["load", "analyze", "simulate", "compare", "forces", "dynamics", "export", "tolerance", "synthesize",
           "sweep", "list_mechanisms"]


# ------------------------------------------------------------------------------------------ helpers
def _mechanism(mech):
    from analytic.mechanism import Mechanism
    if not isinstance(mech, Mechanism):
        raise ParameterError(f"{mech!r} is not a mechanism: give one lk.load(...) returns (e.g. "
                             f"lk.load('fourbar'))")
    return mech


def _settings(timestep, integrator):
    from sim.service.simulation import settings
    return settings(timestep, integrator)


def _loads(mech, gravity, force, cutting_force, torque, inertia):
    from linkage._loads import run_loads
    return run_loads(mech, gravity=gravity, force=force, cutting_force=cutting_force, torque=torque,
                     inertia=inertia)


# ------------------------------------------------------------------------------------------ the door
def list_mechanisms() -> list:
    """The built-in mechanisms and the shipped library, as ``linkage list`` prints them: each a dict of its
    ``name``, ``description``, number of ``inputs`` and whether it is a ``builtin``.

    Example:
        >>> [m["name"] for m in lk.list_mechanisms()][:3]
        ['fourbar', 'sixbar', 'fivebar']
    """
    from sim.service.catalog import list_mechanisms as names
    return names()


def load(mechanism, /, *, text: str | None = None, **values):
    """A mechanism by name (``linkage list``), by the path of a ``linkage/1`` file (``.toml``/``.json``, or a
    Pyslvs or PMKS file), or from a file's ``text``; parameter values as keywords, in the file's units
    (numbers, or text such as ``"30deg"`` for an angle). A mechanism given instead of a name is returned with
    the values changed.

    Args:
        mechanism: a name, a path, or a mechanism.
        text: the file's contents instead of reading ``mechanism`` (which then only names it).
        **values: parameter values, e.g. ``l1=0.12`` or ``phi0="30deg"``.

    Returns:
        :class:`linkage.Mechanism`: its ``parameters``, ``inputs``, ``points``, ``solve``; shown as a drawing
        and a table in a notebook.

    Example:
        >>> mech = lk.load("fourbar", l1=0.12)
        >>> mech.name, mech.values["l1"]
        ('fourbar', 0.12)
    """
    from analytic.mechanism import Mechanism as Base
    from linkage.mechanism import Mechanism, of
    from sim.service.mechanisms import load as service_load
    if isinstance(mechanism, Base):
        given = {**mechanism.overrides}
        from sim.service.mechanisms import parameter_value
        given.update({k: parameter_value(mechanism, k, v) for k, v in values.items()})
        m = Mechanism.from_definition(mechanism.definition, given, mechanism.builtin)
        return of(m) if mechanism.rock is None else of(m.rocking(*mechanism.rock))
    if isinstance(mechanism, os.PathLike):
        mechanism = os.fspath(mechanism)
    if not isinstance(mechanism, str):
        raise ParameterError(f"load({mechanism!r}): give a mechanism's name (linkage list) or a file's path")
    return of(service_load(mechanism, values, text))


def analyze(mech, /, *, samples: int = 361, revolutions: float = 1.0, input_range=None,
            figures: bool = True) -> Analysis:
    """Closed-form kinematics over a run (``linkage analyze``): ``samples`` instants over ``revolutions`` of
    the first input, or its values evenly spaced over ``input_range`` (``(lo, hi)`` in rad or m, or
    ``"LO:HI"`` as the command line takes it; default: the file's own, if any). ``figures=False`` skips the
    figures of merit (their scans take 50 ms to 2 s, the curves ~1 ms), as the app does while a value is
    dragged.

    Returns:
        :class:`linkage.Analysis`: ``a["xE"]`` (SI arrays, the CSV's columns), ``a.t``, ``a.figures``;
        ``a.to_dict()`` is ``linkage analyze --json``.

    Example:
        >>> a = lk.analyze(lk.load("fourbar", l1=0.12), samples=361)
        >>> round(float(a["xE"].max()), 5)
        0.15972
    """
    from sim.service.analysis import analyze as run
    mech = _mechanism(mech)
    a = run(mech, samples, revolutions, input_range_of(mech, input_range), figures=figures)
    return Analysis(mech, samples, revolutions, a)


def simulate(mech, /, *, revolutions: float = 1.0, input_range=None, timestep: float | None = None,
             integrator: str | None = None, gravity=None, force=None, cutting_force=None, torque=None,
             inertia=None) -> Simulation:
    """The MuJoCo model built and simulated over ``revolutions`` of the first input (``linkage simulate``).

    Args:
        timestep: physics step [s] (None: chosen from the design's fastest rate).
        integrator: MuJoCo's integrator by name (None: the default).
        gravity: (gx, gy) [m/s^2].
        force: (fx, fy) [N] on the output point, or (fx, fy, POINT) / (fx, fy, POINT, LINK).
        cutting_force: F [N] resisting the output point's slow stroke along x.
        torque: {LINK: T} [N m], + counter-clockwise.
        inertia: {LINK: {"m", "cx", "cy", "I"}} in the file's units, or a JSON file's path.

    Returns:
        :class:`linkage.Simulation`: ``s["xE"]``, ``s.t``, ``s.trajectory``; ``to_dict()`` is
        ``linkage simulate --json``.

    Example:
        >>> s = lk.simulate(lk.load("fourbar"), revolutions=0.5)
        >>> s.timestep > 0
        True
    """
    from sim.service.simulation import simulate as run
    mech = _mechanism(mech)
    loads = _loads(mech, gravity, force, cutting_force, torque, inertia)
    built, tr = run(mech, revolutions, _settings(timestep, integrator), loads, input_range_of(mech, input_range))
    return Simulation(mech, revolutions, built, tr)


def compare(mech, /, *, revolutions: float = 1.0, input_range=None, timestep: float | None = None,
            integrator: str | None = None, gravity=None, force=None, cutting_force=None, torque=None,
            inertia=None, interference: bool = False) -> Comparison:
    """The simulation cross-validated against the closed forms (``linkage compare``): each output's error
    against its tolerance, the drives, the loops, the work balance. The loads as in :func:`simulate`;
    ``interference=True`` also sweeps the link solids over the run (a collision fails the comparison).

    Returns:
        :class:`linkage.Comparison`: ``c.passed``, ``c.errors``, ``c.trajectory``; ``to_dict()`` is
        ``linkage compare --json``.

    Example:
        >>> c = lk.compare(lk.load("fourbar"))
        >>> c.passed, c.errors["xE"]["max"] < c.errors["xE"]["tol"]
        (True, True)
    """
    from sim.service.simulation import compare as run
    mech = _mechanism(mech)
    loads = _loads(mech, gravity, force, cutting_force, torque, inertia)
    span = input_range_of(mech, input_range)
    built, c = run(mech, revolutions, _settings(timestep, integrator), loads, span)
    clash = None
    if interference:
        from sim.service import parts
        clash = parts.interference(parts.prepare(mech, span))
    return Comparison(mech, built, c, clash)


def forces(mech, /, *, samples: int = 361, revolutions: float = 1.0, input_range=None, gravity=None,
           force=None, cutting_force=None, torque=None, inertia=None, balance=None, at=None,
           simulate: bool = False, timestep: float | None = None, integrator: str | None = None,
           pressure=None) -> Forces:
    """Every joint's force, the drives and the shaking force and moment along the motion (``linkage
    forces``): Newton-Euler per Assur group with the file's ``[[loads]]`` and ``[friction]`` and the loads
    given here (as :func:`simulate` takes them).

    Args:
        samples: instants over the run.
        balance: counterweights minimising the RMS shaking force: True (the links pivoted at the ground) or
            the links' names; the forces with them in ``to_dict()["balance"]``.
        at: one pose instead of a run: the first input's value (rad, or m; or text such as ``"30deg"``).
        simulate: also run the MuJoCo model and compare its joint forces (``f.simulated``, ``f.passed``).
        pressure: a supply pressure (Pa, or text such as ``"200bar"``, ``"20MPa"``, ``"3000psi"``) to size each
            actuator for: the bores its peak push and pull need, in ``to_dict()["actuators"][name]["sizing"]``.

    Returns:
        :class:`linkage.Forces`: ``f.drives["phi1"]``, ``f.joints``, ``f.shaking``, ``f.peaks``;
        ``to_dict()`` is ``linkage forces --json``.

    Example:
        >>> f = lk.forces(lk.load("fourbar", l1=0.12), samples=73, gravity=(0, -9.81))
        >>> round(f.peaks["joints"]["A"]["F"], 4)
        9.561
    """
    from sim.service.forces import forces_run, simulated_forces_run
    mech = _mechanism(mech)
    at = _at(mech, at)
    if at is not None and (simulate or balance is not None):
        raise ParameterError("at= evaluates one pose: it does not combine with simulate= or balance=")
    links = None if balance is None or balance is False else () if balance is True else tuple(balance)
    loads = _loads(mech, gravity, force, cutting_force, torque, inertia)
    run = forces_run(mech, samples, revolutions, input_range_of(mech, input_range), loads.gravity, loads.force,
                     loads.slow_stroke_only, loads.inertias, links, loads.extra, at, _pressure(mech, pressure))
    if not simulate:
        return Forces(mech, run)
    settings = _settings(timestep, integrator)
    return Forces(mech, run, simulated_forces_run(run, settings, loads), (settings, loads))


def _pressure(mech, value):
    """A supply pressure [Pa] from a number (Pa) or text with its unit (sim.service.forces.supply_pressure)."""
    from sim.service.forces import supply_pressure
    if value is None:
        return None
    return supply_pressure(value if isinstance(value, str) else repr(float(value)), mech, "pressure=")


def _motor(value, what: str):
    from sim.service.dynamics import is_linear_motor, linear_motor, table_motor
    if is_linear_motor(value) or hasattr(value, "omega") and hasattr(value, "stall"):
        return value                                   # a motor already made (the service's)
    if isinstance(value, dict) and set(value) == {"omega", "tau"}:
        return table_motor(list(value["omega"]), list(value["tau"]), source=what)
    if isinstance(value, (tuple, list)) and len(value) == 2:
        return linear_motor(float(value[0]), float(value[1]))
    raise ParameterError(f"{what}={value!r}: give (T0, W0) (stall torque N m, no-load speed rad/s) or "
                         f"{{'omega': [...], 'tau': [...]}} (a torque-speed table)")


def dynamics(mech, /, *, motor, flywheel=None, target_fluctuation: float | None = None,
             start_speed: float = 0.0, revolutions: float = 10.0, timestep: float | None = None,
             integrator: str | None = None, gravity=None, force=None, cutting_force=None, torque=None,
             inertia=None, simulate: bool = True, max_steps: int | None = None) -> Dynamics:
    """A motor drives the linkage (``linkage dynamics``): the reduced equation of motion and MuJoCo's run,
    the speed fluctuation, start-up and flywheel; the loads as in :func:`simulate`.

    Args:
        motor: (T0, W0) a linear motor (stall torque [N m], no-load speed [rad/s]) or ``{"omega": [...],
            "tau": [...]}`` a torque-speed table (or a motor :mod:`sim.service.dynamics` made); a two-input
            five-bar takes ``{input: motor}`` for each.
        flywheel: on the input link [kg m^2] (``{input: J}`` for two motors).
        target_fluctuation: size the flywheel for this coefficient Cs, in (0, 1), instead.
        start_speed: the input's speed at t = 0 [rad/s].
        simulate: MuJoCo's run too (one motor; False: the reduced equation's answer alone).
        max_steps: refuse, before MuJoCo, a run that would take more steps than this (the reduced equation's
            duration over MuJoCo's step; None: the simulation's own cap, sim.run.simulate.MAX_STEPS).

    Returns:
        :class:`linkage.Dynamics`: ``d.passed``, ``d.run``; ``to_dict()`` is ``linkage dynamics --json``.

    Example:
        >>> d = lk.dynamics(lk.load("fourbar"), motor=(2.0, 15.0), revolutions=3)
        >>> 0 < d.to_dict()["mean_speed"] < 15.0
        True
    """
    from sim.service import dynamics as D
    mech = _mechanism(mech)
    loads = _loads(mech, gravity, force, cutting_force, torque, inertia)
    settings = _settings(timestep, integrator)
    names = [i.q for i in mech.inputs]
    if not isinstance(simulate, bool):
        raise ParameterError(f"simulate={simulate!r} must be True or False")
    if max_steps is not None and (isinstance(max_steps, bool) or not isinstance(max_steps, int) or max_steps < 1):
        raise ParameterError(f"max_steps={max_steps!r} must be an integer >= 1 (or None: the simulation's own cap)")
    if len(names) == 2:
        if not simulate or max_steps is not None:
            raise ParameterError(f"{'simulate=False' if not simulate else 'max_steps='}: the {mech.name}'s two-motor "
                                 f"run always runs MuJoCo, up to its own cap")
        if not isinstance(motor, dict) or set(motor) != set(names):
            raise ParameterError(f"motor=: the {mech.name} has two inputs; give {{{names[0]!r}: (T0, W0), "
                                 f"{names[1]!r}: (T0, W0)}}")
        if target_fluctuation is not None:
            raise ParameterError(f"target_fluctuation=: the {mech.name}'s two-motor run sizes no flywheel")
        fly = flywheel if isinstance(flywheel, dict) else dict.fromkeys(names, float(flywheel or 0.0))
        d = D.dynamics_two(mech, loads, tuple(_motor(motor[n], f"motor[{n!r}]") for n in names),
                           tuple(float(fly.get(n, 0.0)) for n in names), (float(start_speed),) * 2, revolutions,
                           settings)
        return Dynamics(mech, d)
    if len(names) != 1:
        raise ParameterError(f"the {mech.name} has {len(names)} inputs; dynamics drives one or two")
    if flywheel is not None and not float(flywheel) >= 0:
        raise ParameterError(f"flywheel={flywheel!r} must be >= 0 [kg m^2] (the flywheel's moment of inertia)")
    cycle = D.cycle_of(mech)                        # one prescribed-motion cycle for both models of the run
    d = D.dynamics(mech, loads, _motor(motor, "motor"), None if flywheel is None else float(flywheel),
                   target_fluctuation, float(start_speed), revolutions, settings, simulate_too=False, cycle=cycle)
    if simulate:                                    # its steps bounded before MuJoCo takes any
        D.check_motor_steps(d, cycle, settings, max_steps)
        d = D.simulated(d, loads, float(start_speed), settings, cycle)
    return Dynamics(mech, d)


def export(mech, /, *, timestep: float | None = None, integrator: str | None = "rk4", revolutions: float = 1.0,
           balance=None, mjcf=None, toml=None) -> Export:
    """The generated MuJoCo model (MJCF, its home keyframe closing every loop) and the mechanism file with
    the current values (``linkage export``); written to ``mjcf=`` and ``toml=`` paths when given.
    ``balance``: True or the links' names: counterweights written into both (see :func:`forces`).

    Returns:
        :class:`linkage.Export`: ``e.mjcf``, ``e.toml``, ``e.loads_left_out``.

    Example:
        >>> e = lk.export(lk.load("fourbar"))
        >>> "<keyframe>" in e.mjcf
        True
    """
    from sim import service
    from sim.output.io import check_writable, write_text
    from sim.service.export import loads_left_out
    mech = _mechanism(mech)
    for path, sfx in ((mjcf, (".xml",)), (toml, (".toml",))):
        if path is not None:
            check_writable(os.fspath(path), sfx)
    if balance is not None and balance is not False:
        mech, _ = service.balanced_mechanism(mech, None if balance is True else tuple(balance))
    model = service.export_mjcf(mech, _settings(timestep, integrator), revolutions)
    text = service.mechanism_text(mech)
    if mjcf is not None:
        write_text(os.fspath(mjcf), model)
    if toml is not None:
        write_text(os.fspath(toml), text)
    return Export(mech, model, text, tuple(loads_left_out(mech)))


def _tolerance_items(tol) -> list[str]:
    if isinstance(tol, dict):
        return [f"{k}={v}" if isinstance(v, str) else f"{k}=±{float(v)!r}" for k, v in tol.items()]
    if isinstance(tol, str):
        return [tol]
    if isinstance(tol, (list, tuple)) and all(isinstance(x, str) for x in tol):
        return list(tol)
    raise ParameterError(f"tol={tol!r}: give {{NAME: '±V'}} (or ±V%, normal:SIGMA; a number V means ±V)")


def tolerance(mech, /, *, tol, samples: int = 1000, seed: int = 1, outputs=None, sobol: bool = False,
              workers: int = 1, scheduler: str | None = None, input_range=None, gravity=None, force=None,
              cutting_force=None, inertia=None, progress=None) -> Tolerance:
    """Monte Carlo, first-order and (``sobol=True``) Sobol tolerance analysis (``linkage tolerance``): the
    spread of the path deviation, transmission angle, drive torque and joint forces under the parameters'
    tolerances, and which tolerance drives each.

    Args:
        tol: ``{NAME: "±V"}`` uniform on [-V, V] in the file's units (``"±V%"`` relative, ``"normal:SIGMA"``;
            a number V means ±V).
        samples: Monte Carlo designs; seed: the random seed.
        outputs: names (list or comma-separated): path_deviation, transmission_min, transmission_max,
            peak_torque, peak_joint_force, speed_fluctuation (default: the first five it has).
        workers, scheduler: processes here, or a Dask scheduler's address (``"local"`` starts one).
        progress: called as ``progress(done, total)``.

    Returns:
        :class:`linkage.Tolerance`; ``to_dict()`` is ``linkage tolerance --json``.

    Example:
        >>> t = lk.tolerance(lk.load("fourbar"), tol={"l1": "±0.1"}, samples=50)
        >>> t.to_dict()["samples"]
        50
    """
    from sim.service import tolerance as ts
    mech = _mechanism(mech)
    if isinstance(outputs, (list, tuple)):
        outputs = ",".join(outputs)
    loads = _loads(mech, gravity, force, cutting_force, None, inertia)
    result = ts.tolerance(mech, _tolerance_items(tol), samples, seed, outputs, sobol, scheduler, loads,
                          input_range_of(mech, input_range), workers, progress)
    return Tolerance(mech, result)


def _point(name: str, v) -> tuple[float, float]:
    from sim.service.values import parse_value
    if isinstance(v, str):
        v = v.split(",")
    if not isinstance(v, (tuple, list)) or len(v) != 2:
        raise ParameterError(f"{name}={v!r} is not (x, y), e.g. {name}=(30, 31)")
    return tuple(parse_value(name, str(x), angle=False) for x in v)


def _angle(name: str, v) -> float:
    from sim.service.values import parse_value
    return parse_value(name, v) if isinstance(v, str) else float(v)


def _rows(name: str, value, columns: tuple, degrees: bool, angle_columns: tuple):
    """``pairs=``/``poses=``: a CSV file's path (read and checked as the command reads it) or rows of
    numbers (angles in ``angles`` units): an array, angles in rad."""
    import numpy as np
    from sim.service import design
    if isinstance(value, (str, os.PathLike)):
        read = design.read_pairs if name == "pairs" else design.read_poses
        return read(os.fspath(value), degrees)
    try:
        data = np.array(value, dtype=float)
    except (TypeError, ValueError):
        data = np.empty((0, 0))
    if data.ndim != 2 or data.shape[1] != len(columns) or len(data) < design.MIN_ROWS[
            "function" if name == "pairs" else "motion"] or not np.isfinite(data).all():
        raise ParameterError(f"{name}=: give a CSV file's path or 3 or more rows of {', '.join(columns)} (finite "
                             f"numbers)")
    if degrees:
        for k in angle_columns:
            data[:, k] = np.radians(data[:, k])
    return data


def synthesize(problem: str, /, *, E1=(30, 31), E2=(10, 35), A=(0, 0), D=(36, 0), crank_rotation="35deg",
               rocker_rotation="50deg", theta_range=("-90deg", "90deg"), pairs=None, poses=None,
               ground: float = 1.0, angles: str = "deg", count: int | None = None, circle_points=None,
               evaluations: int | None = None, unit: str | None = None, min_transmission=None, max_size=None,
               pivot_region=None, grashof: str = "any", start_angles: str = "given", min_link=None,
               max_ratio=None) -> Synthesis:
    """Exact synthesis of a four-bar (``linkage synthesize PROBLEM``):

    - ``"two-position"`` (seed 001): the crank-rocker of least total length whose coupler point moves from
      ``E1`` to ``E2`` while the crank about ``A`` turns by ``crank_rotation`` and the rocker about ``D`` by
      ``rocker_rotation``, the coupler rotations searched over ``theta_range`` (points in ``unit``, default
      mm; angles in rad or text such as ``"35deg"``);
    - ``"function"`` (Freudenstein): through ``pairs`` of (input, output) angles from the line A->D (a CSV
      file's path with columns input,output, or rows), the ground link ``ground`` long; with
      ``start_angles="search"`` the angles are increments and the start angles are searched (at most
      ``evaluations`` candidates, ``count`` designs, default 1), under ``min_link`` and ``max_ratio`` (the
      longest over the shortest link) too; every design reports its ``structural_error`` over the range;
    - ``"motion"`` (Burmester): a coupler body through ``poses`` (x, y, theta: a CSV or rows), up to ``count``
      designs (``circle_points``: X1, Y1, X2, Y2 at pose 1, for 3 poses; ``evaluations``: candidates ranked).

    Angles of ``pairs`` and ``poses`` in ``angles`` (``"deg"`` or ``"rad"``); lengths in ``unit`` (default m
    for these two). Limits every design meets: ``min_transmission`` [deg] (None: the command's default, 30
    for function and motion, none for two-position; 0 for none), ``max_size``, ``pivot_region`` (a list of
    ``"NAME=x0:x1,y0:y1"``), ``grashof``. Every function and motion design is simulated (``compare``). Path
    synthesis is the command's ``linkage synthesize path`` for now.

    Returns:
        :class:`linkage.Synthesis`: ``s.optimum`` (two-position) or ``s.designs``, ``s.best``,
        ``s.rejected``; ``to_dict()`` is the command's ``--json``.

    Example:
        >>> s = lk.synthesize("two-position")
        >>> s.to_dict()["unit"], s.optimum["total"] > 0
        ('mm', True)
    """
    from sim.service import design
    if problem not in ("two-position", "function", "motion"):
        raise ParameterError(f"synthesize({problem!r}): the door solves two-position, function and motion; path "
                             f"synthesis is `linkage synthesize path` for now")
    unit = unit or ("mm" if problem == "two-position" else "m")
    if unit not in design.UNITS:
        raise ParameterError(f"unit={unit!r}: give one of {', '.join(sorted(design.UNITS))}")
    if angles not in ("deg", "rad"):
        raise ParameterError(f"angles={angles!r}: give deg or rad")
    if problem != "two-position" and min_transmission is None:
        min_transmission = 30.0
    limits = None
    if min_transmission is not None or max_size is not None or pivot_region or grashof != "any":
        limits = design.limits(min_transmission, max_size, tuple(pivot_region or ()), grashof, "min_transmission")
    if count is not None and (isinstance(count, bool) or not isinstance(count, int) or count < 1):
        raise ParameterError(f"count={count!r} must be an integer >= 1")
    if problem == "function":
        if pairs is None:
            raise ParameterError("synthesize('function'): give pairs= (a CSV of input,output or rows)")
        if min_link is not None or max_ratio is not None:
            from dataclasses import replace
            limits = replace(limits or design.limits(None), min_link=min_link, max_ratio=max_ratio).check()
        found, rejected = design.synthesize_function(
            _rows("pairs", pairs, ("input", "output"), angles == "deg", (0, 1)), float(ground), unit, limits,
            start_angles, design.FUNCTION_EVALUATIONS if evaluations is None else evaluations,
            1 if count is None else count)
        return Synthesis(problem, {"designs": found, "rejected": rejected})
    if problem == "motion":
        if poses is None:
            raise ParameterError("synthesize('motion'): give poses= (a CSV of x,y,theta or rows)")
        count = 3 if count is None else count
        rows = _rows("poses", poses, ("x", "y", "theta"), angles == "deg", (2,))
        if circle_points is not None and (len(rows) != 3 or len(circle_points) != 4):
            raise ParameterError("circle_points=(X1, Y1, X2, Y2) applies to 3 poses")
        found, rejected = design.synthesize_motion(rows, unit, count, None if circle_points is None else
                                                   [float(v) for v in circle_points], limits,
                                                   design.MOTION_POOL if evaluations is None else evaluations)
        return Synthesis(problem, {"designs": found, "rejected": rejected})
    task = design.two_position_task(E1=_point("E1", E1), E2=_point("E2", E2), A=_point("A", A), D=_point("D", D),
                                    phi12=_angle("crank_rotation", crank_rotation),
                                    psi12=_angle("rocker_rotation", rocker_rotation))
    if isinstance(theta_range, str):
        theta_range = theta_range.split(":", 1) if ":" in theta_range else (theta_range,)
    if len(theta_range) != 2:
        raise ParameterError(f"theta_range={theta_range!r} is not (lo, hi), e.g. ('-90deg', '90deg')")
    lo, hi = (_angle("theta_range", v) for v in theta_range)
    res = design.two_position(task, lo, hi, unit, limits)
    record = {"rows": res["rows"], "optimum": res["optimum"], "excluded": res["excluded"], "unit": unit}
    if limits is not None:
        record["limited"] = res["limited"]
    return Synthesis(problem, record)


def sweep(mech, /, *, vary: dict, samples: int = 360, forces: bool = False, workers: int = 1,
          scheduler: str | None = None, allow_large: bool = False, gravity=None, force=None, cutting_force=None,
          torque=None, inertia=None, progress=None) -> Sweep:
    """Every combination of the varied parameters (``linkage sweep``): each design's output path (box, area)
    and speed, with ``forces=True`` (or any load given) its peak joint force, peak drive and energy per
    cycle.

    Args:
        vary: ``{NAME: [V1, V2, ...]}`` (file units) or ``{NAME: "start:stop:count"}``.
        samples: samples per period.
        allow_large: allow grids over the command's limit of combinations.

    Returns:
        :class:`linkage.Sweep`: ``s.rows``, ``s["area"]`` (the CSV's columns).

    Example:
        >>> s = lk.sweep(lk.load("fourbar"), vary={"l1": "0.1:0.12:3"}, samples=36)
        >>> [round(float(v), 3) for v in s["l1"]]
        [0.1, 0.11, 0.12]
    """
    from sim.service import design
    mech = _mechanism(mech)
    if not isinstance(vary, dict) or not vary:
        raise ParameterError(f"vary={vary!r}: give {{NAME: [V1, V2, ...]}} or {{NAME: 'start:stop:count'}}")
    items = [f"{k}={v}" if isinstance(v, str) else f"{k}={','.join(repr(float(x)) for x in v)}"
             for k, v in vary.items()]
    grid = design.parse_vary(items, mech)
    rows, _ = design.sweep(mech, grid, samples, progress=progress, workers=workers, scheduler=scheduler,
                           allow_large=allow_large)
    if forces or any(x is not None for x in (gravity, force, cutting_force, torque, inertia)):
        from sim.service.sweep_forces import sweep_forces
        rows = sweep_forces(mech, rows, _loads(mech, gravity, force, cutting_force, torque, inertia), samples)
    return Sweep(mech, grid, list(rows))
