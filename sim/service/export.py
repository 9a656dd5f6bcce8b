"""The generated MuJoCo model and the mechanism file as text (``linkage export --mjcf/--toml``)."""

from __future__ import annotations



from analytic.mechanism import Mechanism


def export_mjcf(mech: Mechanism, settings=None, revolutions: float = 1.0) -> str:
    """The generated MJCF of ``mech`` as a standalone document (its time step chosen for ``revolutions``)."""
    from analytic.cycle import Cycle
    from sim.model import Settings, build, export_xml
    cycle = Cycle.of(mech, revolutions)              # the motion solved once, handed to the model builder
    return export_xml(build(mech, settings or Settings(), revolutions=revolutions, cycle=cycle, export=True))


def loads_left_out(mech: Mechanism) -> list[str]:
    """The file's loads that an exported MJCF model cannot hold (``NAME (KIND): why``; friction too): what
    ``linkage export --mjcf`` notes on stderr and writes into the file (sim.model.export.left_out)."""
    from sim.model.loads import loadset_of, not_in_xml
    from sim.model import Loads
    ls = loadset_of(mech, Loads())
    if ls is None:
        return []
    out = [f"{ld.name} ({ld.kind}): {not_in_xml(ld)}" for ld in ls.loads if not_in_xml(ld) is not None]
    return out + (["[friction] (Coulomb): its torque follows the joint forces it changes"] if ls.friction else [])


def mechanism_text(mech: Mechanism, text: str | None = None) -> str:
    """The mechanism's file (TOML) with its current parameter values written in: ``text`` (the file as the
    app uploaded it; default the source file) edited with its comments and layout kept where it is TOML."""
    from sim.output.tomlout import dump
    return dump(mech, text)


def table_text(data: dict) -> str:
    """A ``linkage/1`` table (a drawing's, an import's) as the file's TOML text (one writer for the format's
    files: :func:`analytic.format.writing.dumps`)."""
    from analytic.format import writing
    return writing.dumps(data)
