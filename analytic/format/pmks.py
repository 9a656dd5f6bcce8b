"""PMKS mechanisms (the Planar Mechanism Kinematic Simulator's text form, as its example files and its
``mech=`` URLs hold them), read into the links-and-joints form (:mod:`analytic.format.joints`).

The text, as PMKS documents and reads it (read from its reader; no code taken): pieces separated by line
breaks or ``|``; a piece with ``=`` holds settings (a URL's query: ``?set=s5&mech=...``, joined by ``&``;
``mech=`` starts the joints and may hold the first one, ``d=`` names the driving joint by its index; others are
ignored); every other piece is one joint::

    link link ... TYPE x y [angle] [flags]

words separated by commas or spaces. ``TYPE`` is the last word equal to ``R``, ``P``, ``RP`` or ``G``
(any case; a link may be called ``P``), the words before it are the joint's links, ``angle`` is the
slide's direction in degrees in the drawn pose (``P`` and ``RP``), and ``flags`` a word of ``t``/``f``
(or ``+``/``-``) whose fourth letter marks the driving joint. A link called ``ground`` (or ``0``,
``gnd``, ``grnd``, ``grond``, ``gound``, ``groud``, or a name starting with ``ground``) is the frame.

* ``R`` with links a, b, c...: pinned together at the point; with one link, a point on it;
* ``P a b``: b slides on a without turning (a guide, b block); ``RP a b c...``: b (and c...) pinned to a
  block that slides in a's slot (as in Pyslvs, :mod:`analytic.format.pyslvs`);
* ``G a b``: the gears of links a and b mesh at the point (where their pitch circles touch): a ``G`` joint
  of the links-and-joints form, which finds the carrier, the pitch radii and the ratio from the pose.

Joints have no names: the n-th joint line is point ``Jn``. The driver is ``d=``, else the first joint
whose fourth flag is set, else the first ``R`` or ``P`` joint of two or more links; it drives its first
two links relative to each other: an ``R`` or ``P`` joint on the ground (a crank, a slider), an ``R`` joint of
exactly two moving links (a motor turning the second relative to the first, :meth:`analytic.kinds.motor.Motor.
from_pmks`: placed from its carrier where other joints place that, else, where the two links close a loop with
one more link between placed points (a four-bar driven at its coupler joint), as a ``motor_dyad``), or an
``RP`` joint between two moving links: a cylinder (:meth:`analytic.kinds.actuator.Actuator.from_pmks`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from urllib.parse import unquote

from analytic._common import FileError
from analytic.format import pyslvs
from analytic.kinds.base import GROUND

TYPES = ("R", "P", "RP", "G")
_GROUND_NAMES = {"0", "gnd", "grnd", "grond", "gound", "groud", "ground"}
_NUMBER = re.compile(r"^[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?$")
_BAD = re.compile(r"[^A-Za-z0-9_]")


def _is_ground(name: str) -> bool:
    low = name.lower()
    return low in _GROUND_NAMES or low.startswith("ground")


def looks_like(text: str) -> bool:
    """Whether a text reads as PMKS joints: a ``mech=`` setting, or a first joint line with a type word
    followed by two numbers."""
    if "mech=" in text:
        return True
    for piece in re.split(r"[\n|]", text):
        words = [w for w in re.split(r"[,\s]+", piece.strip()) if w]
        if not words or "=" in piece:
            continue
        t = _type_index(words)
        return t is not None and t > 0 and len(words) >= t + 3 and all(
            _NUMBER.match(w) for w in words[t + 1:t + 3])
    return False


def _type_index(words: list[str]) -> int | None:
    idx = [i for i, w in enumerate(words) if w.upper() in TYPES]
    return idx[-1] if idx else None


def parse(text: str, source: str) -> tuple[list, int | None, list[bool]]:
    """The joints (type, angle [deg] or None, (x, y), links), the ``d=`` driver index or None, and each
    joint's driving flag."""
    if "%" in text:
        text = unquote(text)
    joints, flags, driver = [], [], None
    line = 0
    for piece in re.split(r"[\n|]", text):
        line += 1
        piece = piece.strip()
        if not piece:
            continue
        if "=" in piece:                   # settings: a URL's query holds several, joined by '&' after its '?'
            first = None
            for setting in re.split(r"[?&]", piece):
                if "=" not in setting:
                    continue
                key, value = (x.strip() for x in setting.split("=", 1))
                key = key.lower()
                if key.endswith("mech"):
                    first = value
                elif key == "d":
                    try:
                        driver = int(value)
                    except ValueError:
                        raise FileError(f"{source}: d={value!r} must be the driving joint's index") from None
            if not first:
                continue
            piece = first
        words = [w for w in re.split(r"[,\s]+", piece) if w]
        t = _type_index(words)
        if t is None or t == 0:
            raise FileError(f"{source}: piece {line} ({piece[:40]!r}) is not a PMKS joint (links, then R, P, RP or G, "
                            f"then x, y)")
        kind = words[t].upper()
        rest = words[t + 1:]
        if len(rest) < 2 or not all(_NUMBER.match(w) for w in rest[:2]):
            raise FileError(f"{source}: joint J{len(joints)} ({piece[:40]!r}) needs x and y after its type {kind}")
        x, y = float(rest[0]), float(rest[1])
        rest = rest[2:]
        angle = None
        if rest and _NUMBER.match(rest[0]):
            angle = None if kind == "R" else float(rest[0])      # an angle on an R line is ignored
            rest = rest[1:]
        flags.append(_driving(rest))
        links = []
        for w in words[:t]:
            name = GROUND if _is_ground(w) else _BAD.sub("_", w)
            links.append(name)
        joints.append((kind, angle, (x, y), links))
        if len(joints) > pyslvs.MAX_JOINTS:
            raise FileError(f"{source}: more than {pyslvs.MAX_JOINTS} joints; a mechanism holds at most that many")
    if not joints:
        raise FileError(f"{source}: no PMKS joint found (lines such as 'ground,input,R,0,0')")
    return joints, driver, flags


def _driving(rest: list[str]) -> bool:
    """The fourth flag (driving input), read as PMKS reads it."""
    if not rest:
        return False
    word = rest[0].lower()
    if "t" in word or "f" in word:
        return len(word) >= 4 and word[3] in "t+"
    return len(rest) >= 4 and word == "true"


def to_form(text: str, source: str) -> dict:
    """The links-and-joints tables (``pose``, ``links``, ``joints``, ``inputs``) of a PMKS text."""
    joints, driver, flags = parse(text, source)
    for k, (kind, _, _, links) in enumerate(joints):
        if kind == "G" and len(links) != 2:
            raise FileError(f"{source}: joint J{k} is a gear mesh (G) on {len(links)} link(s) ({', '.join(links)}); a "
                            f"mesh joins the gears of two links")
        if kind == "P" and len(links) != 2:
            raise FileError(f"{source}: joint J{k} is a P joint on {len(links)} link(s) ({', '.join(links)}); a "
                            f"prismatic pair joins a guide and a block")
        if len(set(links)) != len(links):
            raise FileError(f"{source}: joint J{k} names a link twice ({', '.join(links)}); name each once")
    points = {f"J{k}" for k in range(len(joints))}
    joints = [(kind, 0.0 if angle is None and kind != "R" else angle, xy,
               [x + "_link" if x in points else x for x in links]) for kind, angle, xy, links in joints]
    form, on, _ = pyslvs.form_of_joints(joints, source)
    if driver is None:
        driver = next((k for k, f in enumerate(flags) if f), None)
    if driver is None:
        driver = next((k for k, j in enumerate(joints) if j[0] in ("R", "P") and len(j[3]) >= 2), None)
    if driver is None or not 0 <= driver < len(joints):
        raise FileError(f"{source}: no driving joint (d={driver}); give d=INDEX or set the fourth flag of a joint")
    form["inputs"] = [_input(driver, joints, form, source)]
    return form


@dataclass(frozen=True)
class Driver:
    """A PMKS driving joint as the input kinds read it (:meth:`analytic.kinds.base.Kind.from_pmks`): its
    ``index`` (point ``J<index>``), ``type`` (``R``, ``P``, ``RP``, ``G``), ``links`` (as written, the
    ground's spellings made ``ground``) and the links-and-joints ``form`` read so far (links, joints)."""

    index: int
    type: str
    links: list
    form: dict

    @property
    def point(self) -> str:
        return f"J{self.index}"


def _input(k: int, joints, form: dict, source: str) -> dict:
    """The ``[[inputs]]`` entry of the driving joint ``k``: the first input kind that drives it says which."""
    from analytic import kinds
    kind, _, _, links = joints[k]
    found = Driver(k, kind, list(links), form)
    for name in kinds.of_section("inputs"):
        entry = kinds.get(name).from_pmks(found)
        if entry is not None:
            return entry
    p = f"J{k}"
    if kind not in ("R", "P") or len(links) < 2:
        raise FileError(f"{source}: the driving joint {p} is a {kind} joint of {len(links)} link(s); PMKS drives an "
                        f"R or P joint between two links")
    a, b = links[:2]
    if GROUND not in (a, b) and kind == "P":
        raise FileError(f"{source}: the driving joint {p} slides {b} on {a}, two moving links; write a cylinder as "
                        f"an RP joint '{a} LINK RP x y angle' (LINK: the link its rod is pinned to) at the rod's pin")
    if GROUND not in (a, b):
        raise FileError(f"{source}: the driving joint {p} pins {len(links)} links ({', '.join(links)}); a relative "
                        f"drive turns one moving link about another: drive an R joint of two links (or the "
                        f"ground)")
    raise FileError(f"{source}: the driving joint {p} ({kind}) is driven by no input kind")
