"""What a simulation is run with: the integrator and the loops' correction (:class:`Settings`) and the loads
besides the drives (:class:`Loads`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco

from analytic import ParameterError
from sim.loading import Loads  # noqa: F401 (a run's loads, read without MuJoCo by the kinetostatics too)

INTEGRATORS = {"euler": mujoco.mjtIntegrator.mjINT_EULER, "rk4": mujoco.mjtIntegrator.mjINT_RK4,
               "implicit": mujoco.mjtIntegrator.mjINT_IMPLICIT,
               "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST}

DEFAULT_INTEGRATOR = "rk4"

LOOP_TIMECONST = 32.0
"""Time constant of the loops' drift correction, in time steps (solref[0] = LOOP_TIMECONST * h).
With the regulariser below made negligible the loops are held by the constraint force itself and this
Baumgarte-style correction only removes integration drift: too fast a correction disturbs RK4 (8 steps:
3x the loop error of 32 at 0.03 rad per step), too slow lets the drift build up (128 and 512 steps:
2x and 6x); 32 and 64 did equally well over 200 designs."""


@dataclass(frozen=True)
class Settings:
    """Simulation settings: ``timestep`` [s] (None: chosen from the design, see STEP_ANGLE), the
    integrator, and the loops' drift-correction time constant in steps."""

    timestep: float | None = None
    integrator: str = DEFAULT_INTEGRATOR
    timeconst: float = LOOP_TIMECONST

    def __post_init__(self):
        if self.timestep is not None and not (isinstance(self.timestep, (float, int))
                                              and math.isfinite(self.timestep) and 0 < self.timestep <= 0.05):
            raise ParameterError(f"timestep={self.timestep!r} must be a number in (0, 0.05] s (e.g. 0.001)")
        if self.integrator not in INTEGRATORS:
            raise ParameterError(f"integrator={self.integrator!r} is not known: use one of {', '.join(INTEGRATORS)}")
