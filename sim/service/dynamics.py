"""The motor-driven run (``linkage dynamics``, the app's dynamics panel): the reduced equation's answer and
MuJoCo's, both models built from one :class:`analytic.cycle.Cycle` of the prescribed motion (the mass model
MuJoCo has, the time step, the motor-driven model), made here and handed down (issue 30 item 2)."""

from __future__ import annotations

from analytic.mechanism import Mechanism


def cycle_of(mech: Mechanism):
    """The prescribed motion over one turn, solved once (:class:`analytic.cycle.Cycle`), which the models of a
    motor run are built from."""
    from analytic.cycle import Cycle
    return Cycle.of(mech, 1.0)


def dynamics(mech: Mechanism, loads, motor, flywheel: float | None = 0.0, target: float | None = None,
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


def simulated(d, loads, start_speed: float = 0.0, settings=None, cycle=None):
    """``d`` (from :func:`dynamics` with ``simulate_too=False``) with MuJoCo's run and the agreement
    (:func:`sim.run.motor.simulated`), its model built from ``cycle`` (made here when None)."""
    from sim.model import Settings
    from sim.run import motor as smotor
    return smotor.simulated(d, loads, start_speed, settings or Settings(),
                            cycle if cycle is not None else cycle_of(d.mech))
