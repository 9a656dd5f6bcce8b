"""MuJoCo models generated for any mechanism through :class:`mujoco.MjSpec`.

The model is a spanning tree of link bodies (:mod:`.build`): every driven pair and every prismatic pair is a
tree joint (MuJoCo cannot close a loop at a slide), the remaining revolutes close the loops, one site-based
``connect`` each, and each element kind adds the constraints it needs (a gear's coupling). Bodies carry the
file's link names, joints the point (revolute) or block-link (prismatic) names, sites the point names. Every
body is placed at its assembled pose at t = 0 (joint values 0 there), so the model as written, before any
keyframe, already closes every loop; the ``home`` keyframe adds the analytic initial velocities and drive
states. Everything in sim/ reads the model by name.

By concern: :mod:`.settings` (integrator, loads), :mod:`.timestep` (the step a design needs),
:mod:`.frames` (bodies' poses), :mod:`.inertia` (masses), :mod:`.drives` (position servos, the load),
:mod:`.sensors`, :mod:`.appearance` (geoms, camera), :mod:`.build` (the whole model), :mod:`.export` (MJCF
files and loading them back).
"""

import mujoco

from sim.model.build import (MIN_SIZE, REGULARIZATION_SCALE, Built, Context, Loop, build, model_loads,
                             regularization, spanning_tree)
from sim.model.drives import DRIVE_ERROR_BUDGET, SERVO_RATE, Drive, drive_command, input_jerk, slow_stroke
from sim.model.export import INVWEIGHT_NUMERIC, export_xml, load_exported
from sim.model.inertia import LINEAR_DENSITY, MIN_INERTIA, MIN_MASS, body_inertias, default_inertia
from sim.model.settings import DEFAULT_INTEGRATOR, INTEGRATORS, LOOP_TIMECONST, Loads, Settings
from sim.model.timestep import MAX_TIMESTEP, MIN_TIMESTEP, STEP_ANGLE, choose_timestep, motion_scale, rate_scale
from sim.model.appearance import framing, frame_extent, path_points

mujoco.set_mju_user_warning(lambda message: None)
"""MuJoCo's warnings are kept off the terminal and out of the user's folder (MuJoCo would print them and write
MUJOCO_LOG.TXT): a run that goes wrong is detected from its data and reported by SimulationError in one line."""

__all__ = ["Built", "Context", "Drive", "Loads", "Loop", "Settings", "build", "body_inertias", "choose_timestep",
           "default_inertia", "drive_command", "export_xml", "frame_extent", "framing", "input_jerk", "load_exported",
           "model_loads",
           "motion_scale", "path_points", "rate_scale", "regularization", "slow_stroke", "spanning_tree",
           "DEFAULT_INTEGRATOR", "DRIVE_ERROR_BUDGET", "INTEGRATORS", "INVWEIGHT_NUMERIC", "LINEAR_DENSITY",
           "LOOP_TIMECONST", "MAX_TIMESTEP", "MIN_INERTIA", "MIN_MASS", "MIN_SIZE", "MIN_TIMESTEP",
           "REGULARIZATION_SCALE", "SERVO_RATE", "STEP_ANGLE"]
