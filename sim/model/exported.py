"""Load a model written by ``linkage export --mjcf`` as the simulation that ``compare`` validated.

MJCF cannot carry one setting of that simulation: after compiling, ``sim/model/__init__.py`` shrinks MuJoCo's
constraint regulariser by scaling ``body_invweight0`` (see ``model.REGULARIZATION_SCALE``). The
equalities' ``solimp`` is already at MuJoCo's cap (0.9999), so no XML attribute reaches the same
regulariser; the exported file stores the factor as the custom numeric ``linkage_invweight0_scale`` and
:func:`load_exported` applies it. Loaded in plain MuJoCo the loops open by 3e-6 to 8e-5 of the size over
a turn (whitworth 3.7e-5 m against 2.7e-9 m through this loader; see docs/CONVENTIONS.md).
"""

from __future__ import annotations

import os
import stat

import mujoco

from analytic import ParameterError

from sim.model import INVWEIGHT_NUMERIC

MAX_XML_BYTES = 16 << 20
"""[bytes] Largest exported file read (a generated model of the library's largest mechanism is ~40 kB)."""


def load_exported(path: str | os.PathLike) -> tuple[mujoco.MjModel, mujoco.MjData]:
    """(model, data) of an exported MJCF file, with the regulariser of the validated simulation and the
    data at the ``home`` keyframe (every loop closed, the drives' states set).

    Parameters
    ----------
    path : str or PathLike
        A file written by ``linkage export --mjcf``.

    Returns
    -------
    (mujoco.MjModel, mujoco.MjData)
        ``model.body_invweight0`` multiplied by the file's ``linkage_invweight0_scale``; ``data`` reset to
        the keyframe ``home`` and forwarded.
    """
    try:
        st = os.stat(path)
    except OSError as exc:
        raise ParameterError(f"{path}: cannot read it ({exc.strerror or exc})") from None
    if not stat.S_ISREG(st.st_mode) or st.st_size > MAX_XML_BYTES:
        raise ParameterError(f"{path}: not a regular file of at most {MAX_XML_BYTES} bytes")
    try:
        model = mujoco.MjModel.from_xml_path(str(path))
    except ValueError as exc:
        raise ParameterError(f"{path}: MuJoCo cannot load it: {str(exc).splitlines()[0]}") from None
    numeric = next((model.numeric(i) for i in range(model.nnumeric) if model.numeric(i).name == INVWEIGHT_NUMERIC),
                   None)
    if numeric is None or numeric.data.size != 1 or not 0 < float(numeric.data[0]) <= 1:
        raise ParameterError(f"{path}: no custom numeric {INVWEIGHT_NUMERIC!r} in (0, 1]: not a file written by "
                             f"linkage export --mjcf")
    model.body_invweight0[:] *= float(numeric.data[0])
    data = mujoco.MjData(model)
    if model.nkey == 0 or "home" not in {model.key(i).name for i in range(model.nkey)}:
        raise ParameterError(f"{path}: no keyframe 'home': not a file written by linkage export --mjcf")
    mujoco.mj_resetDataKeyframe(model, data, model.key("home").id)
    mujoco.mj_forward(model, data)
    return model, data
