"""A motor drives the linkage (SPEC "Dynamics under a motor"; ``linkage dynamics``, the app's dynamics panel):
the speed over time from the reduced equation of motion and from MuJoCo, their agreement, the start-up, the speed
fluctuation and a flywheel sized for a target fluctuation; two motors on a two-input five-bar. Both models of a run
are built from one :class:`analytic.cycle.Cycle` of the prescribed motion (the mass model MuJoCo has, the time
step, the motor-driven model), made here and handed down (issue 30 item 2).

The motors are :mod:`analytic.applications.motor`'s; the runs are :mod:`sim.run.motor`'s. Values are SI
(rad/s, N m, kg m^2); errors are :class:`analytic.ParameterError` with one-line messages."""

from __future__ import annotations

import numpy as np

from analytic import ParameterError
from analytic.applications import motor as _motor

__all__ = ["sizing_tolerance", "linear_motor", "table_motor", "is_linear_motor", "cycle_of", "dynamics",
           "motor_timestep", "check_motor_steps", "simulated", "dynamics_two", "record", "record_two", "in_units", "CylinderDynamics",
           "cylinder_dynamics", "cylinder_record", "CYLINDER_S_TOL", "CYLINDER_V_TOL"]


def sizing_tolerance() -> float:
    """The relative error within which a flywheel sized for a target fluctuation must meet it in both runs
    (``sim.run.motor.SIZING_TOL``; that module imports MuJoCo, hence a function)."""
    from sim.run.motor import SIZING_TOL
    return SIZING_TOL


def linear_motor(T0: float, W0: float):
    """A DC-like motor, tau = T0 (1 - w / W0): stall torque ``T0`` [N m], no-load speed ``W0`` [rad/s]."""
    return _motor.LinearMotor(T0, W0)


def table_motor(omega, tau, source: str = "the table"):
    """A motor given by a torque-speed table: ``omega`` [rad/s] strictly increasing from 0, ``tau`` [N m]; linear
    between rows. ``source`` names the table in an error message (a file, an option)."""
    return _motor.TableMotor(tuple(omega), tuple(tau), source=source)


def is_linear_motor(motor) -> bool:
    """Whether ``motor`` is a :func:`linear_motor` (T0, W0) rather than a table."""
    return isinstance(motor, _motor.LinearMotor)


def cycle_of(mech):
    """The prescribed motion over one turn, solved once (:class:`analytic.cycle.Cycle`), which the models of a
    motor run are built from."""
    from analytic.cycle import Cycle
    return Cycle.of(mech, 1.0)


def dynamics(mech, loads, motor, flywheel: float | None = 0.0, target: float | None = None,
             start_speed: float = 0.0, revolutions: float = 10.0, settings=None, simulate_too: bool = True,
             cycle=None):
    """:func:`sim.run.motor.dynamics` (one motor on the first input) with the service's cycle: the reduced
    equation's run, the flywheel given or sized for ``target`` (Cs), and with ``simulate_too`` MuJoCo's run and
    their agreement (:class:`sim.run.motor.Dynamics`)."""
    from sim.model import Settings
    from sim.run import motor as smotor
    cycle = cycle if cycle is not None else cycle_of(mech)
    return smotor.dynamics(mech, loads, motor, flywheel, target, start_speed, revolutions, settings or Settings(),
                           simulate_too, cycle)


def motor_timestep(d, cycle=None) -> float:
    """The MuJoCo step a motor run ``d`` (the reduced equation's answer) will take [s]: a front end bounds the
    run's steps before paying for it."""
    import numpy as np
    from sim.run import motor as smotor
    return smotor.timestep_for(d.mech, d.run.reduced, d.motor, float(np.max(np.abs(d.run.omega))),
                               cycle if cycle is not None else cycle_of(d.mech))


def check_motor_steps(d, cycle=None, settings=None, most: int | None = None) -> None:
    """Refuse, before MuJoCo, the simulation of a motor run ``d`` (the reduced equation's answer) that would take
    more than ``most`` steps (None: sim.run.simulate.MAX_STEPS, the simulation's own cap) of its step
    (``settings.timestep`` where given, else :func:`motor_timestep`): one line with the steps, the step and the
    bound. The command line and the app both reach it through :func:`linkage.dynamics`."""
    from sim.run.simulate import MAX_STEPS
    most = MAX_STEPS if most is None else int(most)
    h = settings.timestep if settings is not None and settings.timestep is not None else motor_timestep(d, cycle)
    steps = float(d.run.t[-1]) / h
    if steps > most:
        raise ParameterError(f"MuJoCo would take about {steps:,.0f} steps of {h:.3g} s for this run (at most "
                             f"{most:,}): lower the revolutions or the motor's speed")


def simulated(d, loads, start_speed: float = 0.0, settings=None, cycle=None):
    """``d`` (from :func:`dynamics` with ``simulate_too=False``) with MuJoCo's run and the agreement
    (:func:`sim.run.motor.simulated`), its model built from ``cycle`` (made here when None)."""
    from sim.model import Settings
    from sim.run import motor as smotor
    return smotor.simulated(d, loads, start_speed, settings or Settings(),
                            cycle if cycle is not None else cycle_of(d.mech))


def dynamics_two(mech, loads, motors, flywheel=(0.0, 0.0), start_speed=(0.0, 0.0), revolutions: float = 10.0,
                 settings=None):
    """Two ``motors`` on the two cranks of a two-input ``mech`` (a five-bar), each crank's ``flywheel``
    [kg m^2] and ``start_speed`` [rad/s]: the 2x2 reduced equation's run and MuJoCo's."""
    from sim.run import motor as run
    extra = {} if settings is None else {"settings": settings}
    return run.dynamics_two(mech, loads, motors, flywheel, start_speed, revolutions, **extra)


def record(d) -> dict:
    """The JSON record of a :func:`dynamics` run (SI; ``linkage dynamics --json``)."""
    from sim.run import motor as run
    return run.record(d)


def record_two(d) -> dict:
    """The JSON record of a :func:`dynamics_two` run (SI)."""
    from sim.run import motor as run
    return run.record_two(d)


def in_units(record: dict, display) -> dict:
    """A :func:`sim.run.motor.record` (SI) with its angles and speeds in ``display`` units (``--angles``,
    ``--speeds``), the motor's torques in its force x length unit (``--units`` on a file with ``force_units``;
    N m otherwise), times stay SI; its ``units`` table saying which."""
    from analytic import quantities as _Q
    if display is None or display.is_si:
        return record
    names = {"phi": _Q.ANGLE, "omega": _Q.ANGULAR_VELOCITY, "mean_speed": _Q.ANGULAR_VELOCITY, "torque": _Q.TORQUE,
             "peak_torque": _Q.TORQUE}
    out = {k: (display.convert(names[k], v) if k in names else v) for k, v in record.items()}
    if isinstance(record.get("simulated"), dict):
        out["simulated"] = {k: (display.convert(names[k], v) if k in names else v)
                            for k, v in record["simulated"].items()}
    if isinstance(record.get("units"), dict):
        out["units"] = {**record["units"], **{k: display.unit(q) for k, q in names.items()}}
    else:
        out["units"] = {k: display.unit(q) for k, q in names.items()}
    return out


# ------------------------------------------------------------------------------------ a cylinder's supply
CYLINDER_S_TOL = 1e-5
"""[of the stroke] the cylinder's length, MuJoCo against the reduced equation at MuJoCo's steps: RK4's error at a
quarter of the supply's time constant per step and the loops' regulariser (the tipper at 200 bar, 2 L/s under
gravity: 1.1e-9 of the stroke)."""
CYLINDER_V_TOL = 1e-3
"""[of the free speed v0] the rod's speed, likewise (the start, where the speed rises within a few time
constants, is the worst: the tipper 6e-6 of v0)."""


class CylinderDynamics:
    """A cylinder's supply drives the linkage (:func:`cylinder_dynamics`): the supply, the reduced equation's run
    (:class:`analytic.applications.cylinder.CylinderRun`), MuJoCo's (:class:`sim.run.cylinder.CylinderSim`) and
    their largest differences."""

    def __init__(self, mech, pressure, flow, drive, run, sim, stroke):
        self.mech, self.pressure, self.flow, self.drive, self.run, self.sim = mech, pressure, flow, drive, run, sim
        self.stroke = stroke
        self.s_error = self.v_error = None
        if sim is not None:
            s, v = run.dense(sim.t)
            self.s_error = float(np.max(np.abs(sim.s - s)))
            self.v_error = float(np.max(np.abs(sim.v - v)))

    @property
    def passed(self) -> bool:
        if self.sim is None:
            return True
        lo, hi = self.stroke
        return self.s_error <= CYLINDER_S_TOL * (hi - lo) and self.v_error <= CYLINDER_V_TOL * self.drive.v0


def cylinder_dynamics(mech, pressure: float, flow: float, gravity=None, force=(0.0, 0.0), settings=None,
                      simulate_too: bool = True):
    """The linkage driven out by its cylinder (its one input, an actuator with a bore) from rest at the start
    length to the end of its stroke, the supply at ``pressure`` [Pa] and ``flow`` [m^3/s]: the stall force
    p A and the free speed Q / A on the push area (:mod:`analytic.applications.cylinder`), the mass model and
    loads as MuJoCo's model has them (``gravity`` (gx, gy) [m/s^2] or None, ``force`` (Fx, Fy) [N] on the output
    point); with ``simulate_too`` MuJoCo's run of the same supply and the agreement."""
    from analytic.applications import cylinder as acyl
    from sim import model as M
    from sim.model.settings import Loads
    from sim.run import cylinder as scyl
    if mech.definition.loads:
        raise ParameterError("a cylinder's supply runs with gravity and a constant force on the output point; "
                             "the file's [[loads]] are not applied to it yet: leave them out")
    loads = Loads(gravity=None if gravity is None else tuple(gravity), force=tuple(force))
    if len(mech.inputs) != 1 or mech.inputs[0].kind != "actuator":
        raise ParameterError(f"--pressure drives a cylinder: the {mech.name}'s one input must be an actuator "
                             f"(its inputs: {', '.join(i.q for i in mech.inputs)})")
    e = next(x for x in mech.geometry.elements if x["kind"] == "actuator")
    drive = acyl.supply(e, pressure, flow)
    settings = settings or M.Settings()
    b0 = M.build(mech, settings, loads)
    inertias = M.body_inertias(b0.model, mech.links)
    gravity = tuple(float(x) for x in b0.model.opt.gravity[:2]) if loads.gravity is not None else (0.0, 0.0)
    force = tuple(float(x) for x in b0.model.actuator("load").gear[:2])
    run = acyl.run(mech, inertias, drive, gravity, force)
    sim = None
    if simulate_too:
        sim = scyl.simulate(mech, loads, drive, float(run.t[-1]), e["stroke"][1], run.J_min, settings)
    return CylinderDynamics(mech, pressure, flow, drive, run, sim, tuple(e["stroke"]))


def cylinder_record(d: CylinderDynamics) -> dict:
    """The JSON of ``linkage dynamics --pressure --json`` (SI)."""
    r = d.run
    out = {"mechanism": d.mech.name, "input": d.mech.inputs[0].q,
           "supply": {"pressure": d.pressure, "flow": d.flow, "F0": d.drive.F0, "v0": d.drive.v0},
           "analytic": {"t": r.t, "s": r.s, "v": r.v, "force": r.force, "end": r.end, "duration": float(r.t[-1]),
                        "v_max": float(np.max(r.v))},
           "units": {"t": "s", "s": "m", "v": "m/s", "force": "N", "pressure": "Pa", "flow": "m^3/s", "F0": "N",
                     "v0": "m/s"}}
    if d.sim is not None:
        lo, hi = d.stroke
        out["simulated"] = {"steps": len(d.sim.t) - 1, "timestep": d.sim.timestep,
                            "loop_violation": d.sim.loop_violation, "duration": float(d.sim.t[-1]),
                            "agreement": {"s": d.s_error, "v": d.v_error, "tol_s": CYLINDER_S_TOL * (hi - lo),
                                          "tol_v": CYLINDER_V_TOL * d.drive.v0}}
        out["passed"] = d.passed
    return out
