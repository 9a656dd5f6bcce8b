"""The app's loads on the canvas (issue 31, item 3): the file's ``[[loads]]`` and ``[friction]`` as the
animation draws them (``POST /api/loads/draw``), and the panel that adds, edits and removes loads by
rewriting the file's ``[[loads]]`` text (``POST /api/loads/edit``).

``draw`` answers, for the same samples as ``/api/solve`` (same ``samples``, ``revolutions``,
``input_range``), where every load acts and how much: a force's point and force vector, a torque's link
centre and moment, a spring's or damper's two ends and its tension, a pin's (torsion spring, pin damper)
position and moment, and the joints with friction. Positions are SI (m), as the solve's point paths; forces
and moments are in the file's ``force_units`` (moments in force unit x the file's length unit), as written.

``edit`` takes the file's text and one action (``add``, ``replace`` or ``remove``), and gives the new text:
the file edited in place by tomlkit (every comment and the layout kept; only the load added, replaced or
removed changes), checked by reading it back as ``linkage check`` does (a load the solver would refuse is
refused here, with the solver's one line, and nothing is written).
"""

from __future__ import annotations

import json
import math
import re
import tomllib

import numpy as np

from analytic import ParameterError
from sim.service import load_editing

DRAW_FIELDS = {"mechanism", "text", "set", "samples", "revolutions", "input_range", "digits"}
EDIT_FIELDS = {"mechanism", "text", "set", "action", "name", "load"}
ACTIONS = ("add", "replace", "remove")
MAX_DEPTH = 4
"""Nesting of a load's values: a spring's ``between`` is [[link, [u, v]], ...] (three levels)."""



class LoadsRequestError(ParameterError):
    """A refused panel request: one line naming the field and the fix."""


def check_fields(body: dict, fields: set, action: str) -> None:
    unknown = sorted(set(body) - fields)
    if unknown:
        raise LoadsRequestError(f"unknown field {unknown[0]!r}; {action} takes {', '.join(sorted(fields))}")


# ------------------------------------------------------------------------------------------ drawing
def geometry(mech, t, q, qd, loadset, digits: int | None = None) -> dict:
    """Where and how much each load of ``loadset`` acts over the samples ``t`` (inputs ``q``, ``qd``):
    :func:`sim.service.load_editing.load_geometry` with its arrays as JSON lists (``digits`` significant)."""
    from sim.front.requests import series
    g = load_editing.load_geometry(mech, t, q, qd, loadset)
    g["loads"] = [{k: series(v, digits=digits) if isinstance(v, np.ndarray) else v for k, v in e.items()}
                  for e in g["loads"]]
    return g


def draw(body: dict) -> dict:
    """``POST /api/loads/draw``: the loads of the request's mechanism over the solve's samples."""
    from sim import service
    from sim.front import requests as app
    check_fields(body, DRAW_FIELDS, "loads/draw")
    digits = int(app.number(body, "digits", 15, 3, 15, integer=True)) if "digits" in body else None
    mech = app.mechanism_of(body)
    samples, revolutions, rng = app.run_options(body, mech)
    a = service.analyze(mech, samples, revolutions, rng, figures=False)
    q = np.column_stack([np.broadcast_to(a.inputs[i.q], a.t.shape) for i in mech.inputs])
    qd = np.column_stack([np.broadcast_to(a.inputs[i.qd], a.t.shape) for i in mech.inputs])
    loadset = load_editing.resolve(mech)
    from sim.output.jsonout import clean
    items = clean([dict(x) for x in mech.definition.loads or () if isinstance(x, dict)])
    return {"mechanism": mech.name, "samples": samples, "items": items,
            **geometry(mech, a.t, q, qd, loadset, digits)}


# ------------------------------------------------------------------------------------------ the form
def form_html() -> str:
    """The load form's kind menu and fields, from the registry (analytic.loads.KINDS): one ``<option>`` per
    kind, one labelled input per field name (``id="load-NAME"``, ``data-field``, ``data-type``: how app.js
    reads it) shown for the kinds that take it (``data-kinds``); where kinds describe a field differently
    (``stroke``: a law's direction, a gas spring's length) the title gives each."""
    from html import escape
    kinds = load_editing.editor_fields()
    options = "".join(f'<option value="{escape(k)}">{escape(k.replace("_", " "))}</option>' for k in kinds)
    fields: dict[str, dict] = {}
    for kind, fs in kinds.items():
        for f in fs:
            entry = fields.setdefault(f.name, {"field": f, "kinds": [], "hints": [], "types": set()})
            entry["kinds"].append(kind)
            entry["types"].add(f.type)
            if f.hint and f.hint not in entry["hints"]:
                entry["hints"].append(f.hint)
    rows = [f'<label>kind <select id="load-kind">{options}</select></label>']
    for name, e in fields.items():
        f = e["field"]
        ident = "load-" + name.replace("_", "-")
        # a field text for one kind and a number for another (``stroke``) is read as a number where it is one
        kind_of = "number" if e["types"] == {"text", "number"} else f.type
        attrs = f'id="{ident}" data-field="{escape(name)}" data-type="{escape(kind_of)}"'
        if f.type == "frame":
            control = (f'<select {attrs}><option value="world">world</option>'
                       '<option value="link">link (turns with it)</option></select>')
        else:
            control = f'<input type="text" {attrs} autocomplete="off" spellcheck="false">'
        title = escape(" / ".join(e["hints"]))
        rows.append(f'<label data-kinds="{escape(" ".join(e["kinds"]))}" title="{title}">{escape(f.label or name)} '
                    f'{control}</label>')
    return "\n      ".join(rows)


# ------------------------------------------------------------------------------------------ editing
def toml_value(v, where: str, depth: int = 0) -> str:
    """One value as TOML (strings, finite numbers, booleans, arrays, inline tables)."""
    if depth > MAX_DEPTH:
        raise LoadsRequestError(f"{where}: nested too deeply")
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            raise LoadsRequestError(f"{where}: {v!r} must be a finite number")
        return repr(v)
    if isinstance(v, str):
        if any(ord(c) < 32 for c in v):
            raise LoadsRequestError(f"{where}: {v[:40]!r} holds a control character; give plain text")
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x, f"{where}[{i}]", depth + 1) for i, x in enumerate(v)) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_key(k, where)} = {toml_value(x, f'{where}.{k}', depth + 1)}"
                               for k, x in v.items()) + " }"
    raise LoadsRequestError(f"{where}: {json.dumps(v)[:40]} must be a number, text, true/false or a list")


def _key(k, where: str) -> str:
    if not isinstance(k, str) or not k:
        raise LoadsRequestError(f"{where}: field names must be text")
    return k if re.fullmatch(r"[A-Za-z0-9_-]+", k) else json.dumps(k)


def check_load(load, action: str) -> dict:
    if not isinstance(load, dict) or not load:
        raise LoadsRequestError(f"load must be an object such as {{\"name\": \"F1\", \"kind\": \"force\", \"link\": "
                                f"\"3\", \"point\": \"C\", \"direction\": [0, -1], \"magnitude\": 10}} to {action}")
    name = load.get("name")
    if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
        raise LoadsRequestError(f"load.name {json.dumps(name)[:40]}: give the load a name of letters, digits and _ "
                                f"(not starting with a digit)")
    kind = load.get("kind")
    fields = load_editing.load_fields()
    if kind not in fields:
        raise LoadsRequestError(f"load.kind {json.dumps(kind)[:40]}: use one of {', '.join(fields)}")
    unknown = sorted(set(load) - fields[kind])
    if unknown:
        raise LoadsRequestError(f"load.{unknown[0]}: not a field of a {kind}; it takes "
                                f"{', '.join(sorted(fields[kind]))}")
    toml_value(load, "load")                      # every value writable
    return dict(load)


def edited(text: str, action: str, name, load) -> tuple[str, list]:
    """(the new file text, its loads) after ``action`` on the file ``text``."""
    is_json = text.lstrip().startswith("{")
    try:
        data = json.loads(text) if is_json else tomllib.loads(text)
    except (ValueError, tomllib.TOMLDecodeError) as exc:
        raise LoadsRequestError(f"text: the file does not read ({str(exc).splitlines()[0]}); fix it first") from None
    loads = data.get("loads", [])
    if not isinstance(loads, list) or not all(isinstance(x, dict) for x in loads):
        raise LoadsRequestError("text: the file's loads must be [[loads]] tables; fix it first")
    names = [x.get("name") for x in loads]
    if action == "add":
        new = check_load(load, action)
        if new["name"] in names:
            raise LoadsRequestError(f"load.name {new['name']!r} is used by another load; give a new name "
                                    f"(or replace that one)")
        loads = loads + [new]
    else:
        if not isinstance(name, str) or name not in names:
            raise LoadsRequestError(f"name {json.dumps(name)[:40]}: no load of that name; the file's loads: "
                                    f"{', '.join(map(str, names)) or 'none'}")
        k = names.index(name)
        if action == "remove":
            loads = loads[:k] + loads[k + 1:]
        else:
            new = check_load(load, action)
            if new["name"] != name and new["name"] in names:
                raise LoadsRequestError(f"load.name {new['name']!r} is used by another load; give a new name")
            loads = loads[:k] + [new] + loads[k + 1:]
    if is_json:
        data = dict(data)
        if loads:
            data["loads"] = loads
        else:
            data.pop("loads", None)
        return json.dumps(data, indent=2) + "\n", loads
    return _edit_toml(text, action, names.index(name) if action != "add" else None, load), loads


def _edit_toml(text: str, action: str, k: int | None, load: dict | None) -> str:
    """The TOML ``text`` with its ``[[loads]]`` edited in place (tomlkit): the new table appended (add), the
    k-th replaced (replace) or taken out (remove); every comment and line the action does not touch kept."""
    import tomlkit
    doc = tomlkit.parse(text)
    if action == "add":
        if "loads" not in doc:
            doc.add(tomlkit.nl())
            doc.append("loads", tomlkit.aot())
        doc["loads"].append(_table(load))
    elif action == "replace":
        doc["loads"][k] = _table(load)
    else:
        del doc["loads"][k]
        if len(doc["loads"]) == 0:
            del doc["loads"]
    return tomlkit.dumps(doc)


def _table(load: dict):
    import tomlkit
    t = tomlkit.table()
    for key, v in load.items():
        t.add(key, _inline(v))
    return t


def _inline(v):
    """A value as tomlkit writes it inline (a spring's ``between`` is a list of lists; a table inline)."""
    import tomlkit
    if isinstance(v, dict):
        t = tomlkit.inline_table()
        t.update({k: _inline(x) for k, x in v.items()})
        return t
    if isinstance(v, list):
        return [_inline(x) for x in v]
    return v


def edit(body: dict) -> dict:
    """``POST /api/loads/edit``: {"text", "action": add|replace|remove, "name" (replace, remove), "load"
    (add, replace)} -> {"text": the new file, "loads": its loads as written, "mechanism"}. A library
    mechanism (``mechanism`` by name) is first written out as a file with its current values."""
    from sim import service
    from sim.front import requests as app
    check_fields(body, EDIT_FIELDS, "loads/edit")
    action = body.get("action")
    if action not in ACTIONS:
        raise LoadsRequestError(f"action {json.dumps(action)[:40]}: use one of {', '.join(ACTIONS)}")
    text = body.get("text")
    if text is None:
        text = service.mechanism_text(app.mechanism_of(body))
    elif not isinstance(text, str):
        raise LoadsRequestError("text must be the mechanism file's contents as a string")
    else:
        app.mechanism_of(body)                    # the file as it is must read (its own error first)
    new, loads = edited(text, action, body.get("name"), body.get("load"))
    mech = service.load("<upload>", body.get("set") or {}, text=new)
    load_editing.resolve(mech)                    # every load resolves, as forces and dynamics will resolve it
    return {"mechanism": mech.name, "text": new, "loads": loads}


__all__ = ["draw", "edit", "geometry", "form_html", "edited", "toml_value", "LoadsRequestError",
           "DRAW_FIELDS", "EDIT_FIELDS"]
