"""Units of outputs and CSV columns, and the display units of the command line (no MuJoCo needed).

The table of what each output is lives in :mod:`analytic.quantities`; this module names CSV columns'
quantities, converts columns and figures for a front end, and reads ``--units/--angles/--speeds``.
"""

from __future__ import annotations

import numpy as np

from analytic import quantities as Q
from analytic.quantities import SI, Display, display_for, machine_display

__all__ = ["SI", "Display", "display_for", "machine_display", "output_kind", "column_quantity", "column_unit",
           "force_units",
           "convert_columns", "add_unit_options", "shown_units", "machine_units"]

_KIND = {Q.ANGLE: "angle", Q.LENGTH: "position", Q.ANGULAR_VELOCITY: "ang_velocity", Q.VELOCITY: "velocity",
         Q.ANGULAR_ACCELERATION: "ang_acceleration", Q.ACCELERATION: "acceleration", Q.FORCE: "force",
         Q.TORQUE: "force", Q.JERK: "jerk", Q.ANGULAR_JERK: "ang_jerk"}


def output_kind(mech, name: str) -> tuple[str, str]:
    """(SI unit, kind) of an output: kind is angle, position, ang_velocity, velocity, ang_acceleration,
    acceleration or force (a drive's torque or force). Raises KeyError for a name that is not an output
    of ``mech``."""
    o = Q.output(mech, name)
    return o.si_unit, _KIND[o.quantity]


def column_quantity(mech, column: str) -> str:
    """The quantity of a CSV column of analyze/simulate (``cmd_phi1`` is an angle like ``phi1``); a joint's
    coordinate ``q_NAME`` and rate ``v_NAME`` by the joint's kind (a hinge's angle, a slide's length); ``""``
    for a column of no known quantity (kept SI)."""
    if column.startswith("cmd_"):
        column = column[4:]
    if column.startswith(("q_", "v_")):
        kind = {j.name: j.kind for j in getattr(mech, "joints", ())}.get(column[2:])
        if kind == "revolute":
            return Q.ANGLE if column[0] == "q" else Q.ANGULAR_VELOCITY
        if kind == "prismatic":
            return Q.LENGTH if column[0] == "q" else Q.VELOCITY
        return ""
    return Q.quantity(mech, column)


def column_unit(mech, column: str, display: Display = SI) -> str:
    """The unit of a CSV column of analyze/simulate in ``display`` units."""
    q = column_quantity(mech, column)
    if q:
        return display.unit(q)
    if column.startswith("q_"):
        return "rad or m"
    if column.startswith("v_"):
        return "rad/s or m/s"
    return ""


def convert_columns(mech, columns: dict, display: Display) -> dict[str, np.ndarray]:
    """Columns (SI) converted to ``display`` units by their quantity (joint coordinates stay SI)."""
    return {c: display.convert(column_quantity(mech, c), np.asarray(v)) if column_quantity(mech, c) else v
            for c, v in columns.items()}


# ---------------------------------------------------------------------------------- command line
def add_unit_options(p) -> None:
    """``--units``, ``--angles``, ``--speeds`` on a command (SPEC "Units of results")."""
    p.add_argument("--units", choices=tuple(Q.LENGTH_UNITS) + (SI_CHOICE,), default=None,
                   help="length unit of results (default: the file's for what you read, m for CSV/JSON); SI: "
                        "metres and forces in N, moments in N m (whatever the file's force_units)")
    p.add_argument("--angles", choices=("rad", "deg"), default=None, help="angles in rad (default) or deg")
    p.add_argument("--speeds", choices=("rpm",), default=None,
                   help="angular speeds in rpm (default: rad/s, or deg/s with --angles deg)")


SI_CHOICE = "SI"
"""``--units SI``: metres, newtons and newton metres in everything shown and written."""


def shown_units(args, mech) -> Display:
    """What people read: the file's length unit unless ``--units``; angles and speeds as asked; forces in the
    file's ``force_units`` (moments in force unit x length unit unless N: SPEC "Loads"); ``--units SI``: m, N,
    N m."""
    if getattr(args, "units", None) == SI_CHOICE:
        return Display("m", getattr(args, "angles", None) or "rad", getattr(args, "speeds", None) or "", "N")
    return display_for(mech.units, getattr(args, "units", None), getattr(args, "angles", None),
                       getattr(args, "speeds", None), force_units(mech))


def machine_units(args, mech=None) -> Display:
    """What CSV and JSON hold: SI unless ``--units``/``--angles``/``--speeds`` was given; with ``--units`` and
    ``mech`` forces in its file's ``force_units``; ``--units SI``: m, N, N m."""
    if getattr(args, "units", None) == SI_CHOICE:
        return Display("m", getattr(args, "angles", None) or "rad", getattr(args, "speeds", None) or "", "N")
    return machine_display(getattr(args, "units", None), getattr(args, "angles", None), getattr(args, "speeds", None),
                           force_units(mech) if mech is not None else "N")


def force_units(mech) -> str:
    """The file's ``force_units`` (N for a built-in or a file without one)."""
    return getattr(getattr(mech, "definition", None), "force_units", None) or "N"
