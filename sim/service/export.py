"""The generated MuJoCo model and the mechanism file as text (``linkage export --mjcf/--toml``)."""

from __future__ import annotations



from analytic.mechanism import Mechanism


def export_mjcf(mech: Mechanism, settings=None, revolutions: float = 1.0) -> str:
    """The generated MJCF of ``mech`` as a standalone document (its time step chosen for ``revolutions``)."""
    from sim.model import Settings, build, export_xml
    return export_xml(build(mech, settings or Settings(), revolutions=revolutions))


def mechanism_text(mech: Mechanism) -> str:
    """The mechanism's file (TOML) with its current parameter values written in."""
    from sim.output.tomlout import dump
    return dump(mech)
