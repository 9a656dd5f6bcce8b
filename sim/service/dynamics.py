"""A motor drives the linkage (SPEC "Dynamics under a motor"; ``linkage dynamics``): the speed over time from
the reduced equation of motion and from MuJoCo, their agreement, the start-up, the speed fluctuation and a
flywheel sized for a target fluctuation; two motors on a two-input five-bar.

The motors are :mod:`analytic.applications.motor`'s; the runs are :mod:`sim.run.motor`'s. Values are SI
(rad/s, N m, kg m^2); errors are :class:`analytic.ParameterError` with one-line messages."""

from __future__ import annotations

from analytic.applications import motor as _motor

__all__ = ["sizing_tolerance", "linear_motor", "table_motor", "is_linear_motor", "dynamics", "dynamics_two", "record",
           "record_two"]


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


def dynamics(mech, loads, motor, flywheel: float | None = 0.0, target: float | None = None, start_speed: float = 0.0,
             revolutions: float = 10.0, settings=None):
    """Drive the one-input ``mech`` by ``motor`` under ``loads`` (:func:`sim.service.simulation.run_loads`) from
    ``start_speed`` [rad/s] for ``revolutions``: the reduced equation's run and MuJoCo's, with the ``flywheel``
    [kg m^2] given, or sized for the fluctuation ``target`` (Cs in (0, 1)) and checked by both runs.
    ``settings``: MuJoCo's (:func:`sim.service.simulation.settings`; None: the defaults)."""
    from sim.run import motor as run
    extra = {} if settings is None else {"settings": settings}
    return run.dynamics(mech, loads, motor, flywheel, target, start_speed, revolutions, **extra)


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
