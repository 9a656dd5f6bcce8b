"""The app's cam panel (issue 38, item 7): ``POST /api/cam`` answers a mechanism's cams for the panel (the law
as written, its SVAJ diagram over the cam angle, the profile with its pressure angle and radius of curvature,
:mod:`sim.service.cam_editing`), and with an ``edit`` (the follower's segments, the roller, the base radius of
one cam) writes it into the file as the loads panel writes loads: the text edited in place by tomlkit (every
comment kept), read back as ``linkage check`` reads it. An edit the file cannot take is refused with the
analytic side's one line and nothing is written; one that makes the cam undercut answers its drawing (the
undercut marked) with ``problem``, the line that refuses it, and no text.
"""

from __future__ import annotations

import re

from analytic import ParameterError
from sim.service import cam_editing

FIELDS = {"mechanism", "text", "set", "cam", "edit"}


class CamRequestError(ParameterError):
    """A refused cam panel request: one line naming the field and the fix."""


def _line(exc: BaseException) -> str:
    """The analytic side's message without the uploaded text's placeholder name."""
    text = (str(exc).strip().splitlines() or [""])[0]
    return re.sub(r"^<(upload|text)>:\s*", "", text)


def cam(body: dict, cache=None) -> dict:
    """``POST /api/cam``: {"mechanism" or "text", "set", "cam" (a cam's name; default every cam), "edit"
    (optional: {"segments", "roller", "base_radius"} of that cam)} -> {"mechanism", "cams": {name: panel
    data}, "text": the edited file or None, "problem": None, or the one line refusing an undercutting edit}."""
    from sim import service
    from sim.front import requests as app
    unknown = sorted(set(body) - FIELDS)
    if unknown:
        raise CamRequestError(f"unknown field {unknown[0]!r}; cam takes {', '.join(sorted(FIELDS))}")
    name = body.get("cam")
    if name is not None and not isinstance(name, str):
        raise CamRequestError("cam must be a cam's name (its [[groups]] name)")
    mech = app.mechanism_of(body, cache)
    if "edit" not in body:
        return {"mechanism": mech.name, "cams": cam_editing.panel(mech, name), "text": None, "problem": None}
    if name is None:
        raise CamRequestError("cam: name the cam the edit is for")
    text = body.get("text")
    if text is None:
        text = service.mechanism_text(mech)        # a library mechanism: written out with its current values
    try:
        new = cam_editing.edited_text(text, name, body["edit"])
    except ParameterError as exc:
        raise CamRequestError(_line(exc)) from None
    values = body.get("set") or {}
    try:
        edited = service.load("<upload>", values, text=new)
    except ParameterError as exc:
        shown = cam_editing.preview(new, values, name)
        if shown is None:
            raise CamRequestError(_line(exc)) from None
        return {"mechanism": mech.name, "cams": shown, "text": None, "problem": _line(exc)}
    return {"mechanism": edited.name, "cams": cam_editing.panel(edited, name), "text": new, "problem": None}


__all__ = ["cam", "FIELDS", "CamRequestError"]
