"""Pyslvs mechanisms: a bare expression (``M[J[R, P[0, 0], L[ground, L1]], ...]``) or a Pyslvs-UI project
(``.pyslvs``, YAML), read into the links-and-joints form (:mod:`analytic.format.joints`).

The expression grammar, as Pyslvs documents it (read from its parser's grammar; no code taken)::

    mechanism : "M[" [joint ("," joint)* [","]] "]"
    joint     : "J[" type ["," "A[" number "]"] ["," "color[" colour "]"] "," "P[" x "," y "]"
                "," "L[" [name ("," name)* [","]] "]" "]"
    type      : "RP" | "R" | "P"

with ``#`` line comments and ``#[ ... #]`` block comments. Joints have no names: the n-th joint is point
``Jn`` (``J0``, ``J1``, ...); links are the names in ``L[...]``, ``ground`` the frame. Meaning:

* ``R`` with links a, b, c...: the links are pinned together at the point; with one link, a point on it;
* ``P`` with links [guide, block]: the block slides on the guide without turning, along ``A[deg]`` (the
  slide's direction in the drawn pose); the point is on the block;
* ``RP`` with links [slot, pin, ...]: a pin in a slot: an implicit block ``Jn_block`` slides in the slot
  link and the pin links are pinned to it at the point.

A project's inputs are pairs ``(base, driver)`` of joint indices: ``base != driver`` turns the link both
joints share about ``Jbase`` (the input is the angle of ``Jbase -> Jdriver``); ``base == driver`` drives the
slider at ``Jbase`` along its guide.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from analytic._common import FileError
from analytic.kinds.base import GROUND

MAX_JOINTS = 500
"""The most joints a foreign file may hold, as a linkage/1 file's items (analytic.format.linkfile.MAX_ITEMS):
converting 30,000 (a 860 kB expression) ran for minutes before that limit refused the result."""
_NUMBER = re.compile(r"[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?")
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_COLOUR = re.compile(r"\(\s*\d+\s*,\s*\d+\s*,\s*\d+\s*\)|[A-Za-z][A-Za-z-]*")
_BLOCK_COMMENT = re.compile(r"#\[[\s\S]*#\][^\n]*")   # greedy, as Pyslvs' grammar
_LINE_COMMENT = re.compile(r"#[^\n]*")


def strip_comments(text: str) -> str:
    """The text with its comments blanked out (line breaks kept, so positions stay where they were)."""
    def blank(m):
        return re.sub(r"[^\n]", " ", m.group(0))
    return _LINE_COMMENT.sub(blank, _blank_block(text, blank))


def _blank_block(text: str, blank) -> str:
    """``_BLOCK_COMMENT.sub(blank, text)`` in linear time: the greedy pattern matches from the first ``#[`` to
    the last ``#]`` after it and the rest of that line, once (after it no ``#]`` is left); the regex engine
    itself retries every later ``#[`` when none follows, quadratic in their count (300,000 of them, 600 kB,
    ran for minutes)."""
    start = text.find("#[")
    end = text.rfind("#]")
    if start < 0 or end < start + 2:
        return text
    match = _BLOCK_COMMENT.match(text, start)      # anchored at the first "#[": one pass to its end
    return text[:start] + blank(match) + text[match.end():]


def is_expression(text: str) -> bool:
    """Whether a text is a bare Pyslvs expression (``M[`` first, after comments)."""
    return strip_comments(text).lstrip().startswith("M[")


class _Parser:
    def __init__(self, text: str, source: str):
        self.s = strip_comments(text)
        self.i = 0
        self.source = source
        self.joint_count = 0

    def skip(self):
        while self.i < len(self.s) and self.s[self.i].isspace():
            self.i += 1

    def fail(self, expected: str) -> FileError:
        self.skip()
        line = self.s.count("\n", 0, self.i) + 1
        column = self.i - (self.s.rfind("\n", 0, self.i) + 1) + 1
        near = self.s[self.i:self.i + 20].split("\n")[0] or "the end"
        return FileError(f"{self.source}: not a Pyslvs expression: expected {expected} at line {line}, column "
                         f"{column} (near {near!r}); the expression is M[J[type, P[x, y], L[links]], ...]")

    def take(self, literal: str) -> bool:
        self.skip()
        if self.s.startswith(literal, self.i):
            self.i += len(literal)
            return True
        return False

    def need(self, literal: str):
        if not self.take(literal):
            raise self.fail(repr(literal))

    def match(self, pattern: re.Pattern, expected: str) -> str:
        self.skip()
        m = pattern.match(self.s, self.i)
        if not m:
            raise self.fail(expected)
        self.i = m.end()
        return m.group(0)

    def number(self) -> float:
        return float(self.match(_NUMBER, "a number"))

    def mechanism(self) -> list[tuple[str, float | None, tuple[float, float], list[str]]]:
        self.need("M[")
        joints = []
        while not self.take("]"):
            self.joint_count = len(joints)
            if len(joints) == MAX_JOINTS:          # refused while reading: the conversion grows faster than this
                raise FileError(f"{self.source}: more than {MAX_JOINTS} joints; a mechanism holds at most that many")
            joints.append(self.joint())
            if not self.take(","):
                self.need("]")
                break
        self.skip()
        if self.i != len(self.s):
            raise self.fail("the end after M[...]")
        return joints

    def joint(self):
        self.need("J[")
        kind = "RP" if self.take("RP") else "R" if self.take("R") else "P" if self.take("P") else None
        if kind is None:
            raise self.fail("a joint type R, P or RP")
        self.need(",")
        angle = None
        if self.take("A["):
            at = self.i
            angle = self.number()
            if not abs(angle) <= 360.0 * 1e6:          # 1e300 (or 1e999, read as inf) is no slide direction
                raise FileError(f"{self.source}: joint J{self.joint_count}: A[{self.s[at:self.i].strip()[:40]}] is "
                                f"out of range; give the slide's angle in degrees (e.g. A[30])")
            self.need("]")
            self.need(",")
        if self.take("color["):
            self.match(_COLOUR, "a colour")
            self.need("]")
            self.need(",")
        self.need("P[")
        x = self.number()
        self.need(",")
        y = self.number()
        self.need("]")
        self.need(",")
        self.need("L[")
        links = []
        while not self.take("]"):
            links.append(self.match(_NAME, "a link name"))
            if not self.take(","):
                self.need("]")
                break
        self.need("]")
        return kind, angle, (x, y), links


def parse_expression(text: str, source: str) -> list[tuple[str, float | None, tuple[float, float], list[str]]]:
    """The joints of an expression: (type, angle in degrees or None, (x, y), links) each."""
    return _Parser(text, source).mechanism()


def to_form(joints, inputs, source: str) -> dict:
    """The links-and-joints tables (``pose``, ``links``, ``joints``, ``inputs``) of a Pyslvs mechanism with
    its input pairs (base, driver)."""
    form, on, pjoints = form_of_joints(joints, source)
    form["inputs"] = [_input(pair, joints, on, pjoints, source) for pair in inputs]
    return form


def form_of_joints(joints, source: str) -> tuple[dict, dict, list]:
    """The ``pose``, ``links`` and ``joints`` tables of joints drawn at points, Pyslvs' and PMKS' way: each
    (type R, P, RP or G (PMKS' gear mesh at its pitch point); angle [deg] or None; (x, y); links, the guide
    first for P and RP) is point ``Jn``.
    Also returns each point's links and the P joints."""
    if not joints:
        raise FileError(f"{source}: the expression has no joint")
    pose, links, rjoints, pjoints, gjoints = {}, {}, [], [], []
    on: dict[str, list[str]] = {}                          # point -> links it is on (as the joints say)

    def link(name):
        if name != GROUND:
            links.setdefault(name, [])
        return name

    for k, (kind, angle, xy, ls) in enumerate(joints):
        p = f"J{k}"
        pose[p] = list(xy)
        if len(set(ls)) != len(ls):
            raise FileError(f"{source}: joint {p} names a link twice ({', '.join(ls)}); name each once")
        ls = [link(x) for x in ls]
        if kind == "G":                                       # PMKS: two gears meshing at their pitch point
            gjoints.append({"kind": "G", "point": p, "links": ls})
            continue
        if kind == "R":
            if not ls:
                raise FileError(f"{source}: joint {p} is a free point (L[] names no link), which a linkage cannot "
                                f"move; put it on a link")
            if len(ls) == 1:                                  # a point on one link (a tracer)
                if ls[0] != GROUND:
                    links[ls[0]].append(p)
                on.setdefault(p, []).append(ls[0])
            else:
                rjoints.append({"kind": "R", "point": p, "links": ls})
                on.setdefault(p, []).extend(ls)
            continue
        if angle is None:
            raise FileError(f"{source}: joint {p} is a {kind} joint without its slide angle A[degrees]; add it")
        if len(ls) < 2:
            raise FileError(f"{source}: joint {p} is a {kind} joint on {len(ls)} link(s); a slider joins a guide link "
                            f"and a block")
        slot, pins = ls[0], ls[1:]
        direction = {"angle": f"{angle:g}deg"}
        if kind == "P":
            if len(pins) > 1:
                raise FileError(f"{source}: joint {p} is a P joint on {len(ls)} links ({', '.join(ls)}); a prismatic "
                                f"pair joins two links: split it")
            block = pins[0]
            if block == GROUND:
                slot, block = block, slot                     # a P joint is the same either way round
            pjoints.append({"kind": "P", "point": p, "guide": slot, "block": block, **direction})
            on.setdefault(p, []).append(block)
            continue
        block = f"{p}_block"
        links[block] = [p]
        pjoints.append({"kind": "P", "point": p, "guide": slot, "block": block, **direction})
        rjoints.append({"kind": "R", "point": p, "links": [block] + pins})
        on.setdefault(p, []).extend([block] + pins)
    ground = [p for p, ls in on.items() if GROUND in ls and not any(j["point"] == p for j in rjoints)]
    out_links = []
    if ground:
        out_links.append({"name": GROUND, "points": ground})
    out_links += [{"name": n, **({"points": pts} if pts else {})} for n, pts in links.items()]
    return {"pose": pose, "links": out_links, "joints": rjoints + pjoints + gjoints}, on, pjoints


@dataclass(frozen=True)
class Pair:
    """A Pyslvs input pair as the input kinds read it (:meth:`analytic.kinds.base.Kind.from_pyslvs`): joint
    numbers ``base`` and ``driver`` (points ``J<base>``, ``J<driver>``), the parsed ``joints`` ((type, angle,
    (x, y), links), as :func:`parse_expression` gives them), ``on`` (each point's links) and ``pjoints`` (the
    form's P joints: point, guide, block)."""

    base: int
    driver: int
    joints: list
    on: dict
    pjoints: list
    source: str

    def fail(self, text: str) -> FileError:
        """The error naming the file, for ``raise``."""
        return FileError(f"{self.source}: {text}")


def _joint_number(x) -> int | None:
    """A joint number as an input pair holds it (0, 1.0 or '1'), else None (inf, 1e300, 1.5, a list)."""
    if isinstance(x, bool):
        return None
    if isinstance(x, int):
        return x
    if isinstance(x, float) and math.isfinite(x) and x.is_integer() and abs(x) < 2 ** 31:
        return int(x)
    if isinstance(x, str) and x.strip().isdigit() and len(x) < 10:
        return int(x)
    return None


def _input(pair, joints, on, pjoints, source: str) -> dict:
    """The ``[[inputs]]`` entry of a pair (base, driver): the first input kind that drives it says which."""
    from analytic import kinds
    numbers = [_joint_number(x) for x in pair] if isinstance(pair, (list, tuple)) and len(pair) == 2 else [None]
    if None in numbers:
        shown = f"{type(pair).__name__} of {len(pair)}" if isinstance(pair, (list, tuple, dict)) else \
            type(pair).__name__                    # a nested value (a YAML alias bomb) is never expanded
        if isinstance(pair, (list, tuple)) and len(pair) <= 3 and all(isinstance(x, (int, float, str)) for x in pair):
            shown = repr(list(pair))
        elif isinstance(pair, (int, float, str)) or pair is None:
            shown = repr(pair)
        raise FileError(f"{source}: input {shown[:80]} is not a pair of joint numbers (base, driver); give two "
                        f"whole numbers, e.g. [0, 1]")
    base, driver = numbers
    n = len(joints)
    for x in (base, driver):
        if not 0 <= x < n:
            raise FileError(f"{source}: input ({base}, {driver}): there is no joint {x} (joints J0 to J{n - 1})")
    found = Pair(base, driver, joints, on, pjoints, source)
    for name in kinds.of_section("inputs"):
        entry = kinds.get(name).from_pyslvs(found)
        if entry is not None:
            return entry
    raise FileError(f"{source}: input ({base}, {driver}): no input kind drives it; a pair (base, driver) turns the "
                    f"link two joints share, (base, base) drives a slider")


def read_project(raw: bytes, source: str) -> tuple[str, list]:
    """The expression and the input pairs of a Pyslvs-UI project file (YAML; a pickled one is refused)."""
    import yaml
    if raw[:1] == b"\x80":
        raise FileError(f"{source} is a pickled Pyslvs project (binary), which is never loaded (it could run code); "
                        f"save it from Pyslvs-UI as a YAML project")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise FileError(f"{source}: not UTF-8 text (byte 0x{raw[exc.start]:02x} at offset {exc.start}); a Pyslvs "
                        f"project is YAML") from None
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" (line {mark.line + 1})" if mark is not None else ""
        raise FileError(f"{source}: not valid YAML{where}; a Pyslvs project is YAML") from None
    except RecursionError:
        raise FileError(f"{source}: nested too deeply; a Pyslvs project nests a few levels only") from None
    except FileError:
        raise
    except ValueError:                           # Python's int-string limit: an integer of over 4300 digits
        raise FileError(f"{source}: an integer of more than 4300 digits; fix the number") from None
    if not isinstance(data, dict) or not isinstance(data.get("mechanism"), str):
        raise FileError(f"{source}: a Pyslvs project needs 'mechanism: M[...]' (its expression)")
    pairs = data.get("input") or []
    if not isinstance(pairs, list) or len(pairs) > 100:
        raise FileError(f"{source}: 'input' must be a list of [base, driver] pairs")
    return data["mechanism"], pairs
