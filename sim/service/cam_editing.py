"""The app's cam panel (issue 38, item 7): a cam's law as the file writes it (its segments, roller and base
radius), its SVAJ diagram over the cam angle, its profile with the pressure angle and the radius of
curvature along it, and the same for an edit of the law that the file cannot take (an undercut: drawn, with
where it undercuts, and refused).

Everything is computed by the analytic side: the law is the file's own :class:`analytic.laws.Profile`
(exact derivatives), the profile, the pressure angle, the radius of curvature and the undercut are
:mod:`analytic.cams`'s (:func:`analytic.cams.build`, :func:`analytic.cams.problems`). The page only draws.

Units: the cam angle in deg; a translating follower's lift in the file's length unit and its derivatives per
radian of cam angle (unit/rad, unit/rad^2, unit/rad^3); an arm's in deg (deg/rad, ...); the profile [m] in
the cam's frame (as the mechanism view's points); radii of curvature in the file's unit: ``rho_min`` is the
analytic side's (the smallest, the most negative where the profile is concave), ``rho_convex_min`` the
sharpest convex bend (the smallest positive radius), the one the drawing marks.
"""

from __future__ import annotations

import math

import numpy as np

from analytic import ParameterError

SVAJ_SAMPLES = 721
"""Cam angles of the SVAJ diagram over a turn, both ends included (one per 0.5 deg)."""
PROFILE_SAMPLES = 720
"""Points of the drawn profile (one per 0.5 deg of cam angle)."""
SEGMENT_KEYS = ("shape", "duration", "rise")


def elements(mech) -> dict:
    """The mechanism's cams {name: resolved element} (empty where it has none)."""
    from analytic import cams
    return cams.elements(mech)


def written(definition, name: str) -> dict:
    """The cam ``name``'s law as its file writes it: ``segments`` [{shape, duration, rise}] (values as written:
    numbers, quantities such as "120deg", parameter names), ``roller``, ``base_radius``; None for a cam whose
    outline is given (``profile``) instead of segments."""
    from analytic import kinds
    for e in definition.order:
        if e.kind != "cam" or _name(e.fields) != name:
            continue
        segs = e.fields.get("segments")
        if segs is None:
            return None
        rows = [{"shape": s, "duration": d, **({} if s == "dwell" else {"rise": r})} for s, d, r in segs]
        return {"segments": rows, "roller": e.fields.get("roller", 0.0), "base_radius": e.fields["base_radius"],
                "rise_measure": kinds.get("cam").rise_measure(e.fields)}
    raise ParameterError(f"cam {name!r}: no cam of that name; the file's cams: "
                         f"{', '.join(_name(e.fields) for e in definition.order if e.kind == 'cam') or 'none'}")


def _name(fields: dict) -> str:
    name = fields.get("name") or "{point}"
    return name.replace("{point}", str(fields.get("point")))


def view(setup, unit: tuple[float, str]) -> dict:
    """The panel's data for a cam of ``setup`` (:class:`analytic.cams.Setup`); ``unit``: (metres per file unit,
    its name). See the module docstring for the units."""
    from analytic import cams
    k, uname = unit
    arm = setup.motion == "oscillating"
    f = math.degrees(1.0) if arm else 1.0 / k          # the lift's display unit per SI unit (rad or m)
    su = "deg" if arm else uname
    theta = np.linspace(0.0, 2 * math.pi, SVAJ_SAMPLES)
    h, h1, h2, h3 = setup.law.at(np.mod(theta, 2 * math.pi))
    h = np.asarray(h, dtype=float)
    h = np.where(np.arange(len(theta)) == len(theta) - 1, h[0], h)     # 360deg: the turn's start again
    h1, h2, h3 = (np.asarray(x, dtype=float) for x in (h1, h2, h3))
    dense = cams.build(setup)                          # the checks' samples: the marks where the check finds them
    step = max(1, len(dense.theta) // PROFILE_SAMPLES)
    pick = np.arange(0, len(dense.theta), step)
    pa = dense.pressure_angle
    i_pa = int(np.nanargmax(np.abs(pa)))
    rho = dense.rho
    i_rho = int(np.nanargmin(rho)) if np.isfinite(rho).any() else 0
    convex = np.where(rho > 0, rho, np.inf)
    i_sharp = int(np.argmin(convex)) if np.isfinite(convex).any() else None
    bad, worst, _ = cams.defects(dense)
    problem = cams.problems(dense, unit)
    kc = dense.contact_cam

    def mark(i, value, vunit):
        return {"theta": math.degrees(float(dense.theta[i])), "value": _finite(value), "unit": vunit,
                "x": float(kc[i, 0]), "y": float(kc[i, 1])}

    starts = getattr(setup.law, "starts", None)
    out = {
        "follower": setup.motion, "contact": setup.contact, "roller": setup.roller, "base_radius": setup.base_radius,
        "svaj": {"theta": _list(np.degrees(theta)), "s": _list(h * f), "v": _list(h1 * f), "a": _list(h2 * f),
                 "j": _list(h3 * f),
                 "units": {"theta": "deg", "s": su, "v": f"{su}/rad", "a": f"{su}/rad^2", "j": f"{su}/rad^3"}},
        "boundaries": _list(np.degrees(starts)) if starts is not None else [],
        "profile": {"theta": _list(np.degrees(dense.theta[pick])), "x": _list(kc[pick, 0]), "y": _list(kc[pick, 1]),
                    "pressure_angle": _list(np.degrees(pa[pick])), "rho": _list(rho[pick] / k),
                    "undercut": [bool(b) for b in bad[pick]]},
        "pitch": {"x": _list(dense.pitch[pick, 0]), "y": _list(dense.pitch[pick, 1])},
        "pressure_angle_max": mark(i_pa, math.degrees(abs(float(pa[i_pa]))), "deg"),
        "rho_min": mark(i_rho, float(rho[i_rho]) / k, uname),
        "rho_convex_min": None if i_sharp is None else mark(i_sharp, float(rho[i_sharp]) / k, uname),
        "undercut": None if worst is None else {**mark(worst, None, ""), "message": problem},
        "problem": problem,
        "length_unit": uname,
    }
    return out


def _finite(v):
    return float(v) if v is not None and math.isfinite(v) else None


def _list(a) -> list:
    a = np.asarray(a, dtype=float)
    ok = np.isfinite(a)
    return a.tolist() if ok.all() else [float(v) if o else None for v, o in zip(a.tolist(), ok.tolist())]


def panel(mech, name: str | None = None) -> dict:
    """Every cam of ``mech`` (or the one ``name``d) for the panel: {name: :func:`view` plus its law as written
    (:func:`written`) and its link and follower}."""
    from analytic import laws
    cams_ = elements(mech)
    if name is not None and name not in cams_:
        raise ParameterError(f"cam {name!r}: no cam of that name; the mechanism's cams: {', '.join(cams_) or 'none'}")
    unit = (mech.scale, mech.units)
    out = {}
    for n, e in cams_.items():
        if name is not None and n != name:
            continue
        out[n] = {**view(e["setup"], unit), "written": written(mech.definition, n), "link": e["cam"],
                  "follower_link": e["links"][0], "shapes": list(laws.SHAPES)}
    return out


def preview(text: str, values: dict, name: str) -> dict:
    """The panel's data of the cam ``name`` of a file ``text`` that does not load because that cam cannot be
    made (an undercut, a cusp: :func:`analytic.cams.problems`), with its ``problem``; None where the file fails
    for another reason (the caller then gives that reason) or the cam is not built."""
    from analytic import laws
    from analytic.format import linkfile
    from sim.service.mechanisms import parameter_value
    try:
        d = linkfile.parse(text, "<upload>")
        overrides = {k: parameter_value(d, k, v) for k, v in (values or {}).items()}
        g = linkfile.resolve(d, linkfile.parameter_values(d, overrides), keep_problems=True)
    except ParameterError:
        return None
    for e in g.elements:
        if e["kind"] == "cam" and e["name"] == name and e.get("problem") and "setup" in e:
            out = view(e["setup"], (d.scale, d.units))
            if not out["problem"]:
                return None
            return {name: {**out, "written": written(d, name), "link": e["cam"], "follower_link": e["links"][0],
                           "shapes": list(laws.SHAPES)}}
    return None


# ------------------------------------------------------------------------------------------ editing
def check_edit(edit) -> dict:
    """An edit from the page, checked for shape only (the file's reader checks the values): {"segments": [{shape,
    duration, rise}], "roller", "base_radius"} (each optional)."""
    if not isinstance(edit, dict):
        raise ParameterError("edit must be an object {\"segments\": [...], \"roller\": ..., \"base_radius\": ...}")
    unknown = sorted(set(edit) - {"segments", "roller", "base_radius"})
    if unknown:
        raise ParameterError(f"edit.{unknown[0]}: not a field of the cam editor; it takes segments, roller, base_radius")
    for key in ("roller", "base_radius"):
        if key in edit:
            _scalar(edit[key], f"edit.{key}")
    if "segments" in edit:
        segs = edit["segments"]
        if not isinstance(segs, list) or not segs:
            raise ParameterError("edit.segments: give a list of {shape, duration, rise} rows (one at least)")
        for i, row in enumerate(segs, 1):
            if not isinstance(row, dict):
                raise ParameterError(f"edit.segments: row {i} must be {{shape, duration, rise}}")
            extra = sorted(set(row) - set(SEGMENT_KEYS))
            if extra:
                raise ParameterError(f"edit.segments: row {i}: unknown key {extra[0]!r}; a row takes shape, duration, rise")
            for key, v in row.items():
                _scalar(v, f"edit.segments: row {i}: {key}")
    return edit


def _scalar(v, where: str) -> None:
    if isinstance(v, bool) or not isinstance(v, (int, float, str)):
        raise ParameterError(f"{where}: give a number or text such as \"120deg\"")
    if isinstance(v, float) and not math.isfinite(v):
        raise ParameterError(f"{where}: must be finite")
    if isinstance(v, str) and (len(v) > 200 or any(ord(c) < 32 for c in v)):
        raise ParameterError(f"{where}: {v[:40]!r} is not a value; give a number or text such as \"120deg\"")


def edited_text(text: str, name: str, edit: dict) -> str:
    """The file ``text`` with the cam ``name``'s segments, roller and base radius replaced by ``edit``'s (those it
    gives): a TOML file edited in place (tomlkit: every comment and line the edit does not touch kept), a JSON
    file rewritten."""
    import json
    edit = check_edit(edit)
    if text.lstrip().startswith("{"):
        data = json.loads(text)
        table = _cam_table(data.get("groups", []), name)
        table.update(_plain(edit))
        return json.dumps(data, indent=2) + "\n"
    import tomlkit
    doc = tomlkit.parse(text)
    table = _cam_table(doc.get("groups", []), name)
    for key in ("roller", "base_radius"):
        if key in edit:
            table[key] = edit[key]
    if "segments" in edit:                          # one row a line, as the library's files write them
        rows = "".join(f"  {{ {', '.join(f'{k} = {_toml(row[k])}' for k in SEGMENT_KEYS if k in row)} }},\n"
                       for row in edit["segments"])
        table["segments"] = tomlkit.parse(f"segments = [\n{rows}]\n")["segments"]
    return tomlkit.dumps(doc)


def _toml(v) -> str:
    """A checked scalar (:func:`_scalar`) as TOML: a number as Python writes it, text in quotes."""
    import json
    return json.dumps(v, ensure_ascii=False) if isinstance(v, str) else repr(v)


def _plain(edit: dict) -> dict:
    out = {k: edit[k] for k in ("roller", "base_radius") if k in edit}
    if "segments" in edit:
        out["segments"] = [{k: r[k] for k in SEGMENT_KEYS if k in r} for r in edit["segments"]]
    return out


def _cam_table(groups, name: str):
    for t in groups:
        if isinstance(t, dict) and t.get("kind") == "cam" and _name(t) == name:
            return t
    raise ParameterError(f"cam {name!r}: the file has no [[groups]] cam of that name")


__all__ = ["panel", "preview", "written", "view", "edited_text", "check_edit", "elements", "SVAJ_SAMPLES"]
