"""The generated MuJoCo model and the mechanism file as text (``linkage export --mjcf/--toml``)."""

from __future__ import annotations

import json
from dataclasses import replace



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


def balanced_text(mech: Mechanism, balanced: Mechanism) -> str:
    """The file of ``balanced`` (``mech`` with :func:`sim.service.forces.balanced_mechanism`'s counterweights)
    for ``linkage export --balance --toml``: the user's own text (``mech``'s parameter values written in as
    :func:`mechanism_text` does) with only the new counterweights added, so its comments, layout and every
    table it does not change (``[[loads]]``, ``[friction]``, ``[parts]``) stay as written: a new
    ``[mass.counterweights]`` table appended at its end, or the file's own one edited; the generated file
    where there is no TOML text to edit or the edit would not read back as ``balanced``."""
    from sim.output.tomlout import edit_parameters, generate
    text = edit_parameters(mech)
    if text is None:
        return generate(balanced)
    old = (mech.definition.mass or {}).get("counterweights", {})
    new = (balanced.definition.mass or {}).get("counterweights", {})
    try:
        out = _with_counterweights(text, {k: v for k, v in new.items() if old.get(k) != v}, bool(old))
        from analytic.format import linkfile
        back = linkfile.parse(out, mech.definition.source)
        same = (replace(back, parameters=balanced.definition.parameters) == balanced.definition
                and linkfile.parameter_values(back, {}) == balanced.values)
    except Exception:                              # anything unexpected: the generated file instead
        return generate(balanced)
    return out if same else generate(balanced)


def _inline(w: dict) -> str:
    return f"{{ m = {float(w['m'])!r}, at = [{', '.join(repr(float(x)) for x in w['at'])}] }}"


def _with_counterweights(text: str, weights: dict, edit: bool) -> str:
    """``text`` (TOML) with the ``[mass.counterweights]`` entries ``weights`` (link -> {m, at} or a list of
    them, file units): appended as a new table after the last line, or (``edit``: the file has the table)
    set in it by tomlkit, which keeps the comments and layout around them."""
    if not edit:
        entries = [f"{json.dumps(link)} = " + ("[" + ", ".join(_inline(w) for w in e) + "]" if isinstance(e, list)
                                               else _inline(e)) for link, e in weights.items()]
        return text.rstrip("\n") + "\n\n[mass.counterweights]\n" + "\n".join(entries) + "\n"
    import tomlkit
    doc = tomlkit.parse(text)
    table = doc["mass"]["counterweights"]
    for link, entry in weights.items():
        table[link] = tomlkit.parse(f"x = {'[' + ', '.join(_inline(w) for w in entry) + ']' if isinstance(entry, list) else _inline(entry)}")["x"]
    return tomlkit.dumps(doc)
