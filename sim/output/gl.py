"""The offscreen OpenGL backend for MuJoCo, chosen before mujoco is imported (it is fixed then)."""

import os


def ensure_gl_backend() -> str:
    """The user's ``MUJOCO_GL`` if set, else EGL, else OSMesa where no EGL library is installed."""
    if "MUJOCO_GL" not in os.environ:
        import ctypes.util
        # OSMesa looked for only without EGL: a library not found costs ldconfig, gcc and ld runs (~9 ms CPU)
        have_egl = ctypes.util.find_library("EGL") is not None
        os.environ["MUJOCO_GL"] = "egl" if have_egl or ctypes.util.find_library("OSMesa") is None else "osmesa"
        if "PYOPENGL_PLATFORM" not in os.environ:
            os.environ["PYOPENGL_PLATFORM"] = os.environ["MUJOCO_GL"]
    return os.environ["MUJOCO_GL"]
