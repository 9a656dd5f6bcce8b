"""MuJoCo models of the linkages: build, simulate, cross-validate, render; and the ``linkage`` command.

MuJoCo fixes its OpenGL backend when it is imported, so the offscreen backend is chosen here, before
any submodule imports mujoco: the user's ``MUJOCO_GL`` if set, else EGL (OSMesa where EGL is missing).
"""

from sim.output.gl import ensure_gl_backend

ensure_gl_backend()


def load_exported(path):
    """(MjModel, MjData) of a ``linkage export --mjcf`` file as validated: see :mod:`sim.model.export`."""
    from sim.model.export import load_exported as load
    return load(path)
