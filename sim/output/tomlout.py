"""Write a mechanism back as a ``linkage/1`` TOML file, with its current parameter values."""

from __future__ import annotations

import math

from analytic import kinds
from analytic.kinds.base import Guide


def _field(v):
    """A field's value as written (a guide, a table of links or of positions, or a plain value)."""
    if isinstance(v, Guide):
        if v.points:
            return [list(p) for p in v.points]
        return {"through": v.through if isinstance(v.through, str) else list(v.through), "angle": v.angle}
    if isinstance(v, dict):
        return {k: list(x) for k, x in v.items()}
    return list(v) if isinstance(v, tuple) else v


def dump(mech, text: str | None = None) -> str:
    """The mechanism's file with its current parameter values: ``text`` (the file as uploaded; default the
    source file on disk) with only the changed values rewritten (comments, layout and values as written
    kept, ``"144deg"`` stays unless changed) where it is TOML and that reproduces this exact design; else
    the generated file."""
    edited = edit_parameters(mech, text)
    return edited if edited is not None else generate(mech)


def _source_text(mech) -> str | None:
    from pathlib import Path
    src = Path(mech.definition.source)
    if src.suffix.lower() != ".toml" or not src.is_file():
        return None
    try:
        return src.read_text()
    except (OSError, UnicodeDecodeError):
        return None


def _written(mech, name: str, old):
    """The new value of parameter ``name``, in the style of the ``old`` value as written: a value written in
    degrees (an angle, a speed, or a number used in other parameters' expressions) stays in degrees, a
    branch an integer; the value reads back as exactly the same float."""
    v = mech.values[name]
    kind = mech.definition.parameter_kind[name]
    if kind == "branch":
        return int(v)
    if isinstance(old, str) and old.strip().endswith("deg"):
        deg = degrees_text(v)
        if deg is not None:
            return f"{deg}deg"
    return float(v)


def degrees_text(v: float) -> str | None:
    """The shortest decimal text of ``v`` [rad] in degrees that reads back (``math.radians``, as the file's
    ``"...deg"`` is read) as exactly ``v``; None if none within a few units in the last place does."""
    if not math.isfinite(v):
        return None
    d = math.degrees(v)
    candidates = [d]
    up = down = d
    for _ in range(4):                               # radians(degrees(v)) may miss v by an ulp or two
        up, down = math.nextafter(up, math.inf), math.nextafter(down, -math.inf)
        candidates += [up, down]
    best = None
    for c in candidates:
        for digits in range(1, 18):
            text = f"{c:.{digits}g}"
            if math.radians(float(text)) == v:
                if best is None or len(text) < len(best):
                    best = text
                break
    if best is not None and "e" in best:              # the file's number pattern: plain decimals read best
        plain = f"{float(best):.17f}".rstrip("0").rstrip(".")
        best = plain if math.radians(float(plain)) == v else best
    return best


def edit_parameters(mech, text: str | None = None) -> str | None:
    """``text`` (default: the source file's text) with the values of the parameters set on ``mech``
    (``mech.overrides``) rewritten in its ``[parameters]`` table by tomlkit, every comment and the layout
    kept; None when there is no TOML text, a changed parameter is not in that table, or the result would
    not read back as this design (values within 1e-12, the rest of the definition equal)."""
    import tomlkit
    from analytic.format import linkfile
    text = _source_text(mech) if text is None else text
    if text is None or text.lstrip().startswith("{"):
        return None
    d = mech.definition
    original = linkfile.parameter_values(d, {})
    changed = [p for p in d.parameter_order if p in mech.overrides and mech.values[p] != original[p]]
    try:
        doc = tomlkit.parse(text)
    except tomlkit.exceptions.TOMLKitError:
        return None
    table = doc.get("parameters")
    if changed and (not isinstance(table, dict) or any(p not in table for p in changed)):
        return None
    for p in changed:
        table[p] = _written(mech, p, table[p].unwrap() if hasattr(table[p], "unwrap") else table[p])
    out = doc.as_string()
    try:
        back = linkfile.parse(out, d.source)
        values = linkfile.parameter_values(back, {})
    except Exception:                              # anything unexpected: the generated file instead
        return None
    same = all(math.isclose(values[k], mech.values[k], rel_tol=1e-12, abs_tol=1e-300) for k in mech.values)
    rest = all(getattr(back, f) == getattr(d, f) for f in ("name", "units", "parameter_order", "ground", "order",
                                                         "output", "inertia", "mass"))
    return out if same and rest and set(values) == set(mech.values) else None


def _segments(segments) -> list | str:
    """A law's ``segments`` as written: tables {shape, duration, rise} (a dwell without its rise); an empty
    law stays empty."""
    if not segments:
        return ""
    return [{"shape": shape, "duration": duration, **({} if shape == "dwell" else {"rise": rise})}
            for shape, duration, rise in segments]


def _element(e) -> dict:
    """An element's table as written: its kind's fields, and an input's motion law (``segments`` or ``table``)
    in place of the fields it replaces (the rates; a table's start too)."""
    kind = kinds.get(e.kind)
    law = getattr(e, "law", None)
    drop = () if law is None else kind.motion_fields[1:] if law.segments else kind.motion_fields
    out = {"kind": e.kind}
    for f, spec in kind.fields.items():
        v = e.fields[f]
        if f in drop or (v is None or (isinstance(v, str) and v == "")) and spec.default in (None, ""):
            continue                                   # unset and optional (a cam's profile, an arm's guide)
        out[f] = _segments(v) if spec.type == "camlaw" else _field(v)
    if law is not None and law.segments:
        out["segments"] = _segments(law.segments)
    elif law is not None:
        out["table"] = law.path
    return out


def generate(mech) -> str:
    """The mechanism's definition generated as TOML (:func:`analytic.format.writing.dumps`); parameters hold
    their current values (file units; angles in radians, or in degrees where the file wrote them so and the
    value reads back exactly) so the file reproduces this exact design."""
    from analytic.format import writing
    d = mech.definition
    data = {"format": "linkage/1", "name": d.name, "units": d.units}
    if d.description:
        data["description"] = d.description
    data["output"] = d.output
    if getattr(d, "input_range", ""):
        data["input_range"] = d.input_range
    if d.loads or d.friction:
        data["force_units"] = d.force_units
    if d.parameters:
        data["parameters"] = {}
        for p in d.parameter_order:
            v = mech.values[p]
            raw = d.parameters[p]
            deg = degrees_text(v) if isinstance(raw, str) and raw.strip().endswith("deg") else None
            data["parameters"][p] = f"{deg}deg" if deg is not None else int(v) if d.parameter_kind[p] == "branch" \
                else float(v)
    data["ground"] = {g: [x, y] for g, (x, y) in d.ground.items()}
    for section, elements in (("inputs", d.inputs), ("groups", d.groups)):
        if elements:
            data[section] = [_element(e) for e in elements]
    if d.inertia:
        data["inertia"] = {link: {k: float(x) for k, x in entry.items()} for link, entry in d.inertia.items()}
    if d.mass:
        data["mass"] = _mass_table(d.mass)
    parts = getattr(d, "parts", None)
    if parts:
        data["parts"] = {**{k: v for k, v in parts.items() if k != "layers"},
                         **({"layers": {k: int(v) for k, v in parts["layers"].items()}} if parts.get("layers") else {})}
    data.update(_loads_tables(mech))
    return writing.dumps(data)


def _loads_tables(mech) -> dict:
    """The ``[[loads]]`` tables (each record as its kind writes it: analytic.loads.tables) and ``[friction]``
    as written."""
    d = mech.definition
    out = {}
    if d.loads:
        from analytic import loads as AL
        tables = list(AL.tables(AL.parsed(mech), AL.scales(d, mech.parameters)))
        if tables:
            out["loads"] = tables
    if d.friction:
        out["friction"] = dict(d.friction)
    return out


def _mass_table(mass: dict) -> dict:
    """The ``[mass]`` table (analytic.mass) as written: its fields, the links' tables and the counterweights."""
    out = {k: v for k, v in mass.items() if k not in ("links", "counterweights")}
    if mass.get("links"):
        out["links"] = {link: dict(table) for link, table in mass["links"].items()}
    if mass.get("counterweights"):
        out["counterweights"] = {}
        for link, entry in mass["counterweights"].items():
            items = [{"m": float(w["m"]), "at": [float(x) for x in w["at"]]}
                     for w in (entry if isinstance(entry, list) else [entry])]
            out["counterweights"][link] = items[0] if len(items) == 1 else items
    return out
