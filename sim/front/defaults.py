"""Simulation defaults that the command line shows without importing MuJoCo."""

DEFAULT_INTEGRATOR = "rk4"
INTEGRATOR_NAMES = ("euler", "implicit", "implicitfast", "rk4")
