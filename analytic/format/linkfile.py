"""Mechanism files (``linkage/1``, SPEC.md): read, check and resolve them.

A file is data: TOML (or the same structure in JSON), read with :mod:`tomllib`/:mod:`json`, never
executed, with no includes. :func:`read` turns it into a :class:`Definition` (the elements as written,
values still symbolic) after checking every name, field and reference; :func:`resolve` evaluates the
values with a set of parameter values into a :class:`Geometry` in SI units, which the solver uses.

Every problem is one line naming the file, the element (by its point) and the field, and what to change.
"""

from __future__ import annotations

import json
import math
import re
import stat
import sys
import tomllib
from dataclasses import dataclass, field, replace
from pathlib import Path

from analytic import kinds, topology
from analytic._common import FileError, ParameterError
from analytic.format import expr, lawfield
from analytic.kinds.base import GROUND, REQUIRED, SIZE_PER_SECOND, Guide

FORMAT = "linkage/1"
UNITS = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "in": 0.0254}
MAX_FILE_BYTES = 1 << 20
MAX_ITEMS = 500          # parameters, ground points, elements: each at most this many (bounds memory and time)
MAX_MAGNITUDE = 1e12     # |number| in a file; beyond it a value is a typo, not a design
LINK_NAME = re.compile(r"^[A-Za-z0-9_]+$")
"""Link names may start with a digit (SPEC's example names the four-bar's links "1", "2", "3")."""


JOINTS_FORM = ("links", "joints", "pose")
"""The top-level fields that mark a file in the links-and-joints form (:data:`.joints.FIELDS`: that module, and
what it imports, loaded only for such a file)."""

TOP_LEVEL = {"format", "name", "units", "description", "output", "parameters", "ground", "inputs", "groups",
             "inertia", "mass", "force_units", "loads", "friction", "parts"} | set(JOINTS_FORM)
"""The links-and-joints form (:mod:`.joints`) adds ``links``, ``joints`` and ``pose``."""
TOP_LEVEL = TOP_LEVEL | {"input_range"}
"""``input_range = "LO:HI"``: the first input's working range (as ``--input-range`` takes it; a synthesised
motion or function generator's travel): every command rocks over it unless given ``--input-range``."""


@dataclass(frozen=True)
class Element:
    """One input or group as written: its ``kind`` (a name in :data:`analytic.kinds.KINDS`), its fields
    (values still symbolic: numbers, quantity strings, parameter names or expressions), where it stands
    (``groups[2]``) and the points it places."""

    kind: str
    fields: dict
    where: str
    places: tuple[str, ...]
    law: lawfield.Written | None = None
    """An input's motion law as written (``segments`` or ``table``, SPEC "Motion laws"), or None: its kind's
    constant-acceleration law."""

    @property
    def point(self) -> str:
        """The (first) point it places: names the element in messages."""
        return self.places[0]

    @property
    def label(self) -> str:
        if len(self.places) == 1:
            return f"{self.where} (point {self.places[0]})"
        return f"{self.where} (points {', '.join(self.places)})"

    def needs(self) -> tuple[str, ...]:
        """The points this element needs before it can be solved."""
        return kinds.get(self.kind).needs(self.fields)

    def links(self) -> tuple[str, ...]:
        """The links this element creates."""
        return tuple(part.name for part in kinds.get(self.kind).structure(self.fields).links)


@dataclass(frozen=True)
class Definition:
    """A mechanism as its file describes it; ``order`` lists the elements in solving order."""

    name: str
    source: str
    units: str
    description: str
    parameters: dict[str, object]
    parameter_order: tuple[str, ...]
    parameter_kind: dict[str, str]
    ground: dict[str, tuple[object, object]]
    inputs: tuple[Element, ...]
    groups: tuple[Element, ...]
    order: tuple[Element, ...]
    output: str
    inertia: dict = field(default_factory=dict)
    topology: topology.Topology | None = None
    mass: dict = field(default_factory=dict)
    """The ``[mass]`` section as written (numbers in file units; see :mod:`analytic.mass`)."""
    force_units: str = "N"
    loads: tuple = ()
    """The ``[[loads]]`` tables as written (checked; resolved by :func:`analytic.loads.resolve`)."""
    friction: dict | None = None
    loadset: object = field(default=None, compare=False, repr=False)
    """The loads parsed once when the file is read, at its parameter values (an
    :class:`analytic.loads.LoadSet` of typed records; None without loads), reused wherever those values hold."""
    input_range: str = ""
    """The file's ``input_range`` ("LO:HI", '' if none): the working range commands default to."""
    parts: dict = field(default_factory=dict)
    """The ``[parts]`` section as written (file units; see :mod:`analytic.parts`)."""

    @property
    def scale(self) -> float:
        return UNITS[self.units]

    @property
    def elements(self) -> tuple[Element, ...]:
        """The elements as written (inputs, then groups): the indices of ``topology.order``."""
        return self.inputs + self.groups


def _fail(source: str, where: str, what: str) -> FileError:
    return FileError(f"{source}: {where}: {what}")


# --------------------------------------------------------------------------------------------- read
def read(path: str | Path) -> Definition:
    """Read and check a ``linkage/1`` file (``.toml`` or ``.json``)."""
    p = Path(path)
    source = str(path)
    try:
        st = p.stat()
        if p.is_dir():
            raise FileError(f"{source} is a folder, not a mechanism file")
        if not stat.S_ISREG(st.st_mode):
            raise FileError(f"{source} is not a regular file (a device or a pipe); save the mechanism to a file")
        if st.st_size > MAX_FILE_BYTES:
            raise FileError(f"{source} is {st.st_size} bytes; a mechanism file is at most {MAX_FILE_BYTES} bytes")
        with open(p, "rb") as fh:                      # read at most the cap: the file may grow meanwhile
            raw = fh.read(MAX_FILE_BYTES + 1)
        if len(raw) > MAX_FILE_BYTES:
            raise FileError(f"{source} is over {MAX_FILE_BYTES} bytes; a mechanism file is at most that")
    except FileError:
        raise
    except OSError as exc:
        raise FileError(f"{source}: cannot read it ({exc.strerror or exc})") from None
    return parse(raw, source, json_format=p.suffix.lower() == ".json", default_name=p.stem)


def parse(raw: bytes | str, source: str = "<text>", json_format: bool | None = None,
          default_name: str = "mechanism") -> Definition:
    """Parse a file's text (TOML, or JSON when ``json_format``; None: JSON if it starts with '{')."""
    if isinstance(raw, bytes):
        try:
            text = raw.decode("utf-8-sig")
        except UnicodeDecodeError as exc:
            raise FileError(f"{source}: not UTF-8 text (byte 0x{raw[exc.start]:02x} at offset {exc.start}); "
                            f"save the file as UTF-8") from None
    else:
        text = raw
    if json_format is None:
        json_format = text.lstrip().startswith("{")
    if len(text) > MAX_FILE_BYTES:
        raise FileError(f"{source} is over {MAX_FILE_BYTES} characters; a mechanism file is at most that")
    try:
        data = json.loads(text, object_pairs_hook=_unique_keys(source)) if json_format else tomllib.loads(text)
    except RecursionError:
        raise FileError(f"{source}: nested too deeply; a mechanism file nests tables a few levels only") from None
    except tomllib.TOMLDecodeError as exc:
        raise FileError(f"{source}: not valid TOML: {exc}") from None
    except json.JSONDecodeError as exc:
        raise FileError(f"{source}: not valid JSON: {exc.msg} (line {exc.lineno}, column {exc.colno})") from None
    except FileError:                            # the hook's own (a key given twice)
        raise
    except ValueError:                           # Python's int-string limit: an integer of over 4300 digits
        raise FileError(f"{source}: an integer of more than {sys.get_int_max_str_digits()} digits; no value of a "
                        f"mechanism is that long: fix the number") from None
    if not isinstance(data, dict):
        raise FileError(f"{source}: expected a table of fields at the top level")
    return _check(data, source, default_name)


def from_data(data: dict, source: str, default_name: str = "mechanism") -> Definition:
    """A definition from a file's top-level table (either form), e.g. one converted from another tool's file."""
    return _check(data, source, default_name)


def _unique_keys(source: str):
    def hook(pairs):
        seen = {}
        for k, v in pairs:
            if k in seen:
                raise FileError(f"{source}: field {_short(k)} is given twice; keep one")
            seen[k] = v
        return seen
    return hook


def _short(value, limit: int = 60) -> str:
    """``repr(value)`` cut to ``limit`` characters (a message stays one readable line)."""
    text = repr(value)
    quote = "'" if isinstance(value, str) else ""
    return text if len(text) <= limit else text[:limit - 5] + "..." + quote + f" ({len(text)} characters)"


def _check(data: dict, source: str, default_name: str) -> Definition:
    fmt = data.get("format")
    if not isinstance(fmt, str) or fmt != FORMAT:
        fmt = _short(fmt)
        raise _fail(source, "format", f"{fmt} is not supported; the first line must be format = \"{FORMAT}\"")
    unknown = sorted(set(data) - TOP_LEVEL)
    if unknown:
        raise _fail(source, unknown[0], f"unknown field; the top level takes {', '.join(sorted(TOP_LEVEL))}")
    units = data.get("units", "m")
    if not isinstance(units, str) or units not in UNITS:
        raise _fail(source, "units", f"unknown unit {_short(units)}; use one of {', '.join(UNITS)}")
    name = data.get("name", default_name)
    if not (isinstance(name, str) and expr.NAME.match(name)):
        raise _fail(source, "name", f"{_short(name)} is not a name (letters, digits and _, starting with a letter)")
    description = data.get("description", "")
    if not isinstance(description, str):
        raise _fail(source, "description", "must be a string")
    input_range = data.get("input_range", "")
    if not (isinstance(input_range, str) and (not input_range or input_range.count(":") == 1)):
        raise _fail(source, "input_range", f"{_short(input_range)} is not \"LO:HI\" (e.g. \"10deg:80deg\")")

    params = data.get("parameters", {})
    if not isinstance(params, dict):
        raise _fail(source, "parameters", "must be a table NAME = value")
    for section, table in (("parameters", params), ("ground", data.get("ground", {})),
                           ("inputs", data.get("inputs", [])), ("groups", data.get("groups", []))):
        if isinstance(table, (dict, list)) and len(table) > MAX_ITEMS:
            raise _fail(source, section, f"{len(table)} entries; a mechanism file holds at most {MAX_ITEMS}")
    for pname, value in params.items():
        if not expr.NAME.match(pname):
            raise _fail(source, f"parameters.{_short(pname)}", "not a valid name (letters, digits and _)")
        if isinstance(value, bool) or not isinstance(value, (int, float, str)):
            raise _fail(source, f"parameters.{pname}", f"{_short(value)} must be a number or a string such as \"30deg\"")
        _scalar(value, f"parameters.{pname}", source)

    labels, measured = None, None
    if any(k in data for k in JOINTS_FORM):     # links and joints: converted into the elements below
        from analytic.format import joints
        from types import SimpleNamespace
        values = parameter_values(SimpleNamespace(parameters=params, parameter_order=tuple(params), source=source,
                                                  name=name))
        converted = joints.convert(data, source, values)
        data, labels, measured = converted.data, converted.labels, converted.kinds

    ground = data.get("ground", {})
    if not isinstance(ground, dict):
        raise _fail(source, "ground", "must be a table NAME = [x, y]")
    for gname, xy in ground.items():
        if not expr.NAME.match(gname):
            raise _fail(source, f"ground.{_short(gname)}", "not a valid name (letters, digits and _)")
        if not (isinstance(xy, list) and len(xy) == 2):
            raise _fail(source, f"ground.{gname}", f"{_short(xy)} must be [x, y]")
        for c in xy:
            _scalar(c, f"ground.{gname}", source)

    elements = []
    for section in ("inputs", "groups"):
        items = data.get(section, [])
        if not isinstance(items, list):
            raise _fail(source, section, f"must be an array of tables ([[{section}]])")
        for i, item in enumerate(items, 1):
            where = labels[len(elements)] if labels else f"{section}[{i}]"
            written = _table_start(item, where, section, source, UNITS[units])
            if written is not None:                  # a required start (an actuator's l0) from its table
                kind = kinds.get(item["kind"])
                item = {**item, kind.motion_fields[0]: written.table[1][0] / (1.0 if kind.angular else UNITS[units])}
            el = _element(item, where, section, source)
            if section == "inputs":
                if written is None:
                    written = lawfield.check(item, kinds.get(el.kind), kinds.get(el.kind).motion_fields, el.label,
                                             source, UNITS[units])
                el = replace(el, law=written) if written is not None else el
            elements.append(el)
    elements = _sized_rates(elements, ground, params, source, name)
    inputs = tuple(e for e in elements if kinds.get(e.kind).section == "inputs")
    groups = tuple(e for e in elements if kinds.get(e.kind).section == "groups")
    if not elements:
        raise _fail(source, "inputs", "none given; a mechanism needs at least one [[inputs]] (e.g. kind = \"crank\")")
    _check_names(source, params, ground, elements)
    try:
        topo = topology.build(tuple(ground), inputs + groups)
    except topology.StructureError as exc:
        raise _fail(source, exc.where, exc.what) from None
    order = tuple((inputs + groups)[i] for i in topo.order)
    if measured is None:
        param_kinds = _parameter_kinds(source, params, ground, elements)
    else:                                      # derived fields mix the pose's lengths into angles: the
        param_kinds = {**_parameter_kinds(source, params, {}, []), **measured}   # form says what each measures
    output = data.get("output", order[-1].places[-1])
    if not isinstance(output, str):
        raise _fail(source, "output", f"{_short(output)} must be one point name such as \"E\"")
    if output not in topo.points:
        raise _fail(source, "output", f"{output!r} is not a point of the mechanism")
    inertia = data.get("inertia", {})
    if not isinstance(inertia, dict):
        raise _fail(source, "inertia", "must be a table LINK = {m = ..., cx = ..., cy = ..., I = ...}")
    links = {ln for e in elements for ln in e.links()}
    for lname, entry in inertia.items():
        if lname not in links:
            raise _fail(source, f"inertia.{lname}", f"no link named {lname!r}; links: {', '.join(sorted(links))}")
        if not (isinstance(entry, dict) and set(entry) <= {"m", "cx", "cy", "I"} and {"m", "I"} <= set(entry)):
            raise _fail(source, f"inertia.{lname}", "give {m = kg, I = kg m^2 about the centre of mass, "
                                                   "cx, cy = centre of mass in the link frame}")
        for key, v in entry.items():
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not abs(v) <= MAX_MAGNITUDE:
                raise _fail(source, f"inertia.{lname}.{key}", f"{_short(v)} must be a finite number")
            if key in ("m", "I") and not v >= 0:
                raise _fail(source, f"inertia.{lname}.{key}", f"{v!r} must be >= 0 (m = 0 and I = 0: a massless link)")
        if entry["m"] == 0 and entry["I"] != 0:
            raise _fail(source, f"inertia.{lname}.I", "a massless link (m = 0) has no moment of inertia: give I = 0")
    mass = _check_mass(data.get("mass", {}), links, source)
    from analytic.format import parts_table
    parts = parts_table.check(data.get("parts", {}), links, source)
    definition = Definition(name, source, units, description, dict(params), tuple(params), param_kinds,
                            {k: tuple(v) for k, v in ground.items()}, inputs, groups, order, output, inertia, topo,
                            mass=mass, input_range=input_range, parts=parts)
    _check_mobility(definition)
    if any(k in data for k in ("force_units", "loads", "friction")):   # SPEC "Loads": checked here, used later
        from analytic import loads
        definition = replace(definition, force_units=loads.check_units(source, data.get("force_units")),
                             loads=tuple(data.get("loads", ())) if isinstance(data.get("loads", ()), list)
                             else data.get("loads", ()), friction=data.get("friction"))
        definition = replace(definition, loadset=loads.parse(definition, parameter_values(definition)))
    return definition


MASS_FIELDS = {"shape": "", "density": "kg/m^3", "width": "file units", "thickness": "file units"}
"""The material fields of ``[mass]`` (file-wide) and ``[mass.links.LINK]`` (one link), with their units."""


def _key(k) -> str:
    """A table key in a message: as written when it is a plain name, else quoted and cut."""
    return k if isinstance(k, str) and LINK_NAME.match(k) and len(k) <= 60 else _short(k)


def _check_mass(section, links: set, source: str) -> dict:
    """The ``[mass]`` section checked (see :mod:`analytic.mass`): a shape "bar" or "plate", a density,
    width and thickness > 0, per-link overrides of existing links, counterweights ``LINK = {m = kg,
    at = [u, v]}`` (or a list of them); a density needs a width and a thickness. One line naming the link and field otherwise."""
    if not isinstance(section, dict):
        raise _fail(source, "mass", "must be a table (density = kg/m^3, width, thickness, shape = \"bar\" or "
                                    "\"plate\", [mass.links.LINK], [mass.counterweights])")
    unknown = sorted(set(section) - set(MASS_FIELDS) - {"links", "counterweights"})
    if unknown:
        raise _fail(source, f"mass.{_key(unknown[0])}", f"unknown field; [mass] takes {', '.join(MASS_FIELDS)}, "
                                                         f"links and counterweights")

    def material(table, where):
        for key, v in table.items():
            if key not in MASS_FIELDS:
                raise _fail(source, f"{where}.{_key(key)}", f"unknown field; a link's material takes "
                                                               f"{', '.join(MASS_FIELDS)}")
            if key == "shape":
                if v not in ("bar", "plate"):
                    raise _fail(source, f"{where}.shape", f"{_short(v)} must be \"bar\" or \"plate\"")
                continue
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not abs(v) <= MAX_MAGNITUDE:
                raise _fail(source, f"{where}.{key}", f"{_short(v)} must be a finite number [{MASS_FIELDS[key]}]")
            if not v > 0:
                raise _fail(source, f"{where}.{key}", f"{v!r} must be > 0 [{MASS_FIELDS[key]}]")

    top = {k: v for k, v in section.items() if k in MASS_FIELDS}
    material(top, "mass")
    per = section.get("links", {})
    if not isinstance(per, dict):
        raise _fail(source, "mass.links", "must be a table of links: [mass.links.LINK] with density, width, ...")
    for ln, table in per.items():
        if ln not in links:
            raise _fail(source, f"mass.links.{_key(ln)}", f"no link named {ln!r}; links: {', '.join(sorted(links))}")
        if not isinstance(table, dict):
            raise _fail(source, f"mass.links.{ln}", "must be a table (density, width, thickness, shape)")
        material(table, f"mass.links.{ln}")
    for ln in sorted(links):
        merged = {**top, **per.get(ln, {})}
        where = f"mass.links.{ln}" if ln in per else "mass"
        if "density" in merged:
            for key in ("width", "thickness"):
                if key not in merged:
                    raise _fail(source, f"{where}", f"link {ln}: a density needs a {key} [file units]; give "
                                                    f"{key} = ...")
        elif merged:
            raise _fail(source, f"{where}", f"link {ln}: {', '.join(sorted(merged))} without a density; give "
                                            f"density = kg/m^3 (e.g. 7850 for steel)")
    weights = section.get("counterweights", {})
    if not isinstance(weights, dict):
        raise _fail(source, "mass.counterweights", "must be a table LINK = {m = kg, at = [u, v]}")
    for ln, entry in weights.items():
        where = f"mass.counterweights.{_key(ln)}"
        if ln not in links:
            raise _fail(source, where, f"no link named {ln!r}; links: {', '.join(sorted(links))}")
        for w in (entry if isinstance(entry, list) and entry else [entry]):
            if not (isinstance(w, dict) and set(w) == {"m", "at"}):
                raise _fail(source, where, "give {m = kg, at = [u, v]} (the point mass and where it sits in the "
                                           "link's frame, file units), or a list of them")
            m = w["m"]
            if isinstance(m, bool) or not isinstance(m, (int, float)) or not abs(m) <= MAX_MAGNITUDE:
                raise _fail(source, f"{where}.m", f"{_short(m)} must be a finite number [kg]")
            if not m > 0:
                raise _fail(source, f"{where}.m", f"{m!r} must be > 0 [kg]")
            at = w["at"]
            if not (isinstance(at, list) and len(at) == 2 and all(
                    not isinstance(c, bool) and isinstance(c, (int, float)) and abs(c) <= MAX_MAGNITUDE for c in at)):
                raise _fail(source, f"{where}.at", f"{_short(at)} must be [u, v]: two finite numbers [file units]")
    return section


def _table_start(item, where: str, section: str, source: str, scale: float):
    """An input's ``table`` law (:func:`lawfield.check`) where its kind requires the start value the table's
    first row gives (an actuator's ``l0``) and the file leaves it out, as SPEC's tables do; else None (the
    element is read as written, and a start given beside a table is refused there)."""
    if section != "inputs" or not isinstance(item, dict) or "table" not in item:
        return None
    if item.get("kind") not in kinds.of_section(section):
        return None
    kind = kinds.get(item["kind"])
    first = kind.motion_fields[0]
    if first in item or kind.fields[first].default is not REQUIRED:
        return None
    return lawfield.check(item, kind, kind.motion_fields, _placed(item, where), source, scale)


def _placed(item: dict, where: str) -> str:
    """``where`` with the point the element places, where it names one (as the element's label reads), for
    a message about an element whose kind is not known yet."""
    point, points = item.get("point"), item.get("points")
    if isinstance(point, str) and expr.NAME.match(point):
        return f"{where} (point {point})"
    if isinstance(points, list) and points and all(isinstance(p, str) and expr.NAME.match(p) for p in points):
        return f"{where} (points {', '.join(points[:8])}{', ...' if len(points) > 8 else ''})"
    return where


def _element(item, where: str, section: str, source: str) -> Element:
    if not isinstance(item, dict):
        raise _fail(source, where, "must be a table of fields")
    name = item.get("kind")
    allowed = kinds.of_section(section)
    if name not in allowed:
        raise _fail(source, _placed(item, where), f"unknown kind {_short(name)}; [[{section}]] takes kind = "
                                   f"{' or '.join(repr(k) for k in allowed)}")
    kind = kinds.get(name)
    spec = kind.fields
    placed = [f for f, fld in spec.items() if fld.type in ("new", "news")][0]
    first = item.get(placed)
    if spec[placed].type == "new":
        if not (isinstance(first, str) and expr.NAME.match(first)):
            raise _fail(source, where, f"field {placed!r}: {_short(first)} must be a point name (letters, digits "
                                       f"and _)")
        label = f"{where} (point {first})"
    else:
        if not (isinstance(first, list) and first and all(isinstance(p, str) and expr.NAME.match(p) for p in first)):
            raise _fail(source, where, f"field {placed!r}: {_short(first)} must be a list of point names")
        if len(set(first)) != len(first):
            raise _fail(source, where, f"field {placed!r}: a point is listed twice")
        label = f"{where} (points {', '.join(first)})"
    unknown = sorted(set(item) - set(spec) - {"kind"} - (set(lawfield.FIELDS) if section == "inputs" else set()))
    if unknown:
        raise _fail(source, label, f"unknown field {unknown[0]!r}; a {name} takes {', '.join(spec)}")
    fields = {}
    for fname, fld in spec.items():
        if fname not in item:
            if fld.default is REQUIRED:
                raise _fail(source, label, f"field {fname!r} is missing")
            if fld.default is SIZE_PER_SECOND:          # filled in by _sized_rates once every element is read
                fields[fname] = SIZE_PER_SECOND
                continue
            value = _default(fld.default, item)
        else:
            value = item[fname]
        fields[fname] = _field(value, fld.type, f"{label}: field {fname!r}", source)
    problem = kind.check(fields)
    if problem:
        raise _fail(source, label, problem)
    return Element(name, fields, where, tuple(kind.places(fields)))


def _sized_rates(elements: list[Element], ground: dict, params: dict, source: str, name: str) -> list[Element]:
    """The elements with each rate left to :data:`SIZE_PER_SECOND` given its value: the mechanism's size (as
    :func:`analytic.solver.kinematics.size_of` measures it, in file units, at the parameters' values) per second.
    A value that cannot be evaluated yet is left out of the size (resolving the file names it later)."""
    if not any(v is SIZE_PER_SECOND for e in elements for v in e.fields.values()):
        return elements
    from types import SimpleNamespace
    try:
        values = parameter_values(SimpleNamespace(parameters=params, parameter_order=tuple(params), source=source,
                                                  name=name))
    except (FileError, ParameterError, ValueError):
        values = {}

    def num(v, kind, where):
        q = expr.quantity(v) if isinstance(v, str) else None
        return float(v) if isinstance(v, (int, float)) else q[0] if q else expr.evaluate(v, values)

    sizes, xy = [], []
    for x, y in ground.values():
        try:
            xy.append((num(x, "length", ""), num(y, "length", "")))
        except (ValueError, TypeError):
            pass
    if len(xy) > 1:
        sizes += [max(p[k] for p in xy) - min(p[k] for p in xy) for k in (0, 1)]
    for e in elements:
        kind = kinds.get(e.kind)
        try:
            sizes.append(kind.extent({f: 0.0 if v is SIZE_PER_SECOND else
                                      resolve_field(v, kind.fields[f].type, num, "", source) for f, v in e.fields.items()}))
        except (ValueError, TypeError, KeyError, FileError, ParameterError):
            pass
    size = max([s for s in sizes if math.isfinite(s)] + [1e-12])
    return [replace(e, fields={f: kinds.get(e.kind).default_rate(size)[1] if v is SIZE_PER_SECOND else v
                               for f, v in e.fields.items()}) for e in elements]


def _default(default, item):
    if isinstance(default, str):
        return default.format(**_names(item))
    if isinstance(default, tuple):
        return [d.format(**_names(item)) for d in default]
    return default


def _names(item) -> dict:
    f = item.get("from")
    name = item.get("name", item.get("point", ""))
    return {"pivot": item.get("pivot", ""), "point": item.get("point", ""), "through": item.get("through", ""),
            "name": name if isinstance(name, str) else "",
            "from": f if isinstance(f, str) else "", "from0": f[0] if isinstance(f, list) and f else "",
            "from1": f[1] if isinstance(f, list) and len(f) > 1 else ""}


def _scalar(value, what: str, source: str):
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise FileError(f"{source}: {what}: {_short(value)} must be a number, a parameter name or an expression")
    if isinstance(value, float) and not math.isfinite(value):
        raise FileError(f"{source}: {what}: must be finite")
    if isinstance(value, (int, float)) and not abs(value) <= MAX_MAGNITUDE:
        raise FileError(f"{source}: {what}: {_short(value)} is out of range; give a magnitude <= {MAX_MAGNITUDE:g}")
    if isinstance(value, str):
        try:
            expr.names_in(value)
        except ValueError as exc:
            raise FileError(f"{source}: {what}: {exc}") from None
    return value


def _name(value, what: str, source: str) -> str:
    if not (isinstance(value, str) and expr.NAME.match(value)):
        raise FileError(f"{source}: {what}: {_short(value)} must be a name (letters, digits and _)")
    return value


def _link_name(value, what: str, source: str) -> str:
    if not (isinstance(value, str) and LINK_NAME.match(value)):
        raise FileError(f"{source}: {what}: {_short(value)} must be a link name (letters, digits and _)")
    return value


def _field(value, ftype: str, what: str, source: str):
    if ftype == "word":                                 # a choice or an optional name, checked by its kind
        if not isinstance(value, str):
            raise FileError(f"{source}: {what}: {_short(value)} must be a word in quotes")
        return value
    if ftype == "links1":
        if not (isinstance(value, list) and len(value) == 1):
            raise FileError(f"{source}: {what}: {_short(value)} must be a list of one link name")
        return (_link_name(value[0], what, source),)
    if ftype == "camlaw":
        return _camlaw(value, what, source)
    if ftype == "outline":
        return _outline(value, what, source)
    if ftype == "guide" and value is None:              # an optional guide left out
        return None
    if ftype in ("point", "new"):
        return _name(value, what, source)
    if ftype in ("link", "linkref"):
        return _link_name(value, what, source)
    if ftype in ("news", "points"):
        if not (isinstance(value, list) and value):
            raise FileError(f"{source}: {what}: {_short(value)} must be a list of point names")
        return tuple(_name(v, what, source) for v in value)
    if ftype == "links2":
        if not (isinstance(value, list) and len(value) == 2):
            raise FileError(f"{source}: {what}: {_short(value)} must be a list of two link names")
        names = tuple(_link_name(v, what, source) for v in value)
        if names[0] == names[1]:
            raise FileError(f"{source}: {what}: the two names must differ (both are {names[0]!r})")
        return names
    if ftype == "pair":
        if not (isinstance(value, list) and len(value) == 2):
            raise FileError(f"{source}: {what}: {_short(value)} must be a list of two names")
        names = tuple(_name(v, what, source) for v in value)
        if names[0] == names[1]:
            raise FileError(f"{source}: {what}: the two names must differ (both are {names[0]!r})")
        return names
    if ftype == "carrier":
        if isinstance(value, str):
            return _link_name(value, what, source)
        return _field(value, "pair", what + " (two points of the link, or the link's name)", source)
    if ftype in ("lengths2", "xy"):
        if not (isinstance(value, list) and len(value) == 2):
            raise FileError(f"{source}: {what}: {_short(value)} must be a list of two values")
        return tuple(_scalar(v, what, source) for v in value)
    if ftype == "linktable":
        if not (isinstance(value, dict) and value):
            raise FileError(f"{source}: {what}: give a table LINK = [\"P\", \"Q\", ...] of the group's links")
        return {_link_name(k, what, source): _field(v, "points", f"{what}: link {k}", source)
                for k, v in value.items()}
    if ftype == "pose":
        if not isinstance(value, dict):
            raise FileError(f"{source}: {what}: give a table POINT = [x, y] of assembled positions")
        out = {}
        for k, xy in value.items():
            _name(k, what, source)
            if not (isinstance(xy, list) and len(xy) == 2):
                raise FileError(f"{source}: {what}: {k} = {_short(xy)} must be [x, y]")
            out[k] = tuple(_scalar(v, f"{what}: {k}", source) for v in xy)
        return out
    if ftype == "slidetable":
        return _slidetable(value, what, source)
    if ftype == "guide":
        if isinstance(value, list):
            if len(value) != 2:
                raise FileError(f"{source}: {what}: a guide is [\"P\", \"Q\"] or {{through = ..., angle = ...}}")
            pts = tuple(_name(v, what, source) for v in value)
            if pts[0] == pts[1]:
                raise FileError(f"{source}: {what}: the guide's two points must differ")
            return Guide(points=pts)
        if isinstance(value, dict):
            extra = set(value) - {"through", "angle"}
            if extra or "through" not in value:
                raise FileError(f"{source}: {what}: a ground guide is {{through = \"P\" or [x, y], angle = \"0deg\"}}")
            through = value["through"]
            if isinstance(through, list):
                if len(through) != 2:
                    raise FileError(f"{source}: {what}: through = [x, y] takes two values")
                through = tuple(_scalar(v, what, source) for v in through)
            else:
                through = _name(through, what, source)
            return Guide(through=through, angle=_scalar(value.get("angle", 0.0), what, source))
        raise FileError(f"{source}: {what}: a guide is [\"P\", \"Q\"] or {{through = ..., angle = ...}}")
    return _scalar(value, what, source)


def _camlaw(value, what: str, source: str):
    """A cam's ``segments`` (SPEC "Cams and followers"): (shape, duration, rise) with values still symbolic,
    durations angles of the cam (summing to a turn, checked when resolved); None where not given."""
    if value is None:
        return None

    class _Rises:                                    # lawfield's segment checks; the rises' unit (a length for
        angular = True                               # a translating follower, an angle for an arm) is checked
                                                     # when the file is resolved
    def fail(field, text):
        return FileError(f"{source}: {what}: {text}")

    return lawfield._segments(value, _Rises, fail)


def _outline(value, what: str, source: str):
    """A cam's ``profile``: the path of a CSV of its outline (x, y in the cam's frame, file units), read here:
    a tuple of (x, y) in file units; "" where not given."""
    if value == "":
        return ""
    if not (isinstance(value, str) and value.strip()):
        raise FileError(f"{source}: {what}: {_short(value)} must be the path of a CSV file (columns x,y)")
    from analytic.cams import read_outline
    path = Path(value)
    if not path.is_absolute():
        base = Path(source).parent if Path(source).is_file() else Path.cwd()
        path = base / path
    try:
        with open(path, "rb") as fh:
            raw = fh.read(lawfield.MAX_TABLE_BYTES + 1)
    except OSError as exc:
        raise FileError(f"{source}: {what}: cannot read {value!r} ({exc.strerror or exc})") from None
    if len(raw) > lawfield.MAX_TABLE_BYTES:
        raise FileError(f"{source}: {what}: {value!r} is over {lawfield.MAX_TABLE_BYTES} bytes")
    try:
        q = read_outline(raw.decode("utf-8-sig"), 1.0)
    except (ValueError, UnicodeDecodeError) as exc:
        raise FileError(f"{source}: {what}: {value}: {exc}") from None
    return tuple((float(x), float(y)) for x, y in q)


def _slidetable(value, what: str, source: str) -> dict:
    """``{BLOCK = {guide = LINK or ["P", "Q"] or "ground", point = "P", angle = A}}``: a group's prismatic
    pairs, as {block: (guide, point, angle)} (guide: a link name, a pair of points, or None for the ground)."""
    form = (" a table BLOCK = {guide = \"LINK\" or [\"P\", \"Q\"] or \"ground\", point = \"P\", "
            "angle = \"30deg\"}")
    if not isinstance(value, dict):
        raise FileError(f"{source}: {what}: give" + form)
    out = {}
    for block, t in value.items():
        _link_name(block, what, source)
        if not isinstance(t, dict) or set(t) - {"guide", "point", "angle"} or not {"guide", "point"} <= set(t):
            raise FileError(f"{source}: {what}: slide of {block}: give" + form)
        guide = t["guide"]
        if isinstance(guide, list):
            guide = _field(guide, "pair", f"{what}: slide of {block}: guide", source)
        else:
            guide = _link_name(guide, f"{what}: slide of {block}: guide", source)
            guide = None if guide == GROUND else guide
        out[block] = (guide, _name(t["point"], f"{what}: slide of {block}: point", source),
                      _scalar(t.get("angle", 0.0), f"{what}: slide of {block}: angle", source))
    return out


def _check_names(source: str, params: dict, ground: dict, elements: list[Element]) -> None:
    seen: dict[str, str] = {}

    def claim(name: str, what: str, where: str):
        if name in seen:
            raise _fail(source, where, f"{what} name {name!r} is already used by {seen[name]}; choose another")
        seen[name] = f"{what} {name!r}" if what == "parameter" else where

    for p in params:
        claim(p, "parameter", f"parameters.{p}")
    for g in ground:
        claim(g, "point", f"ground.{g}")
    for e in elements:
        for p in e.places:
            claim(p, "point", e.label)
    links: dict[str, str] = {}
    for e in elements:
        for ln in e.links():
            if ln in links:
                raise _fail(source, e.label, f"link name {ln!r} is already used by {links[ln]}; every link is "
                                             f"named once (attach more points to it with kind = \"point\")")
            if ln in params or ln in ground or ln == GROUND or any(ln in x.places for x in elements):
                raise _fail(source, e.label, f"link name {ln!r} is also a parameter or point name; choose another")
            links[ln] = e.label
    named: dict[str, str] = {}
    for e in elements:                               # an input's columns and drive are named after its key
        kind = kinds.get(e.kind)
        if kind.section == "inputs":
            key = kind.input_key(e.fields)
            if key in named:
                raise _fail(source, e.label, f"field 'name': the input {key.lstrip('_')!r} is already named by "
                                             f"{named[key]}; give each input its own name")
            named[key] = e.label
    points = set(ground) | {p for e in elements for p in e.places}
    for e in elements:
        kind = kinds.get(e.kind)
        for p in e.needs():
            if p not in points:
                raise _fail(source, e.label, f"point {p!r} is never defined; define it in [ground] or by an element")
        problem = kind.check_context(e.fields, tuple(ground))
        if problem:
            raise _fail(source, e.label, problem)
        own = [p for p in e.needs() if p in e.places]
        if own:
            raise _fail(source, e.label, f"the element uses its own point {own[0]!r}")


_FIELD_KIND = {"length": "length", "size": "length", "lengths2": "length", "xy": "length", "angle": "angle",
               "branch": "branch", "number": "number"}


def _parameter_kinds(source: str, params: dict, ground: dict, elements: list[Element]) -> dict[str, str]:
    """What each parameter measures (length, angle, branch, number), from where it is used; a parameter
    used as a length and as an angle is an error."""
    measured: dict[str, str] = {}
    undefined = []

    def use(value, kind: str, where: str):
        if not isinstance(value, str):
            return
        for n in expr.names_in(value):
            if n not in params:
                undefined.append((where, n))
                continue
            if measured.get(n, kind) != kind:
                raise _fail(source, where, f"parameter {n!r} is used as a {measured[n]} elsewhere and as a {kind} "
                                           f"here; use two parameters")
            measured[n] = kind

    for g, xy in ground.items():
        for v in xy:
            if isinstance(v, bool) or not isinstance(v, (int, float, str)):
                raise _fail(source, f"ground.{g}", f"{_short(v)} must be a number, a parameter name or an expression")
            use(v, "length", f"ground.{g}")
    for e in elements:
        for fname, fld in kinds.get(e.kind).fields.items():
            ftype = fld.type
            value = e.fields[fname]
            where = f"{e.label}: field {fname!r}"
            if ftype == "pose":
                for xy in value.values():
                    for v in xy:
                        use(v, "length", where)
            elif ftype == "slidetable":
                for _, _, angle in value.values():
                    use(angle, "angle", where)
            elif ftype == "guide" and value is None:
                pass
            elif ftype == "camlaw" and value is not None:
                rise = kinds.get(e.kind).rise_measure(e.fields)
                for _, duration, r in value:
                    use(duration, "angle", where)
                    use(r, rise, where)
            elif ftype == "guide":
                if value.through is not None and not isinstance(value.through, str):
                    for v in value.through:
                        use(v, "length", where)
                use(value.angle, "angle", where)
            elif ftype in ("lengths2", "xy"):
                for v in value:
                    use(v, "length", where)
            elif ftype in _FIELD_KIND:
                use(value, _FIELD_KIND[ftype], where)
        if e.law is not None:
            for value, measure in lawfield.uses(e.law, kinds.get(e.kind)):
                use(value, measure, f"{e.label}: field 'segments'")
    if undefined:
        where, n = undefined[0]
        raise _fail(source, where, f"{n!r} is not a parameter; define it under [parameters]")
    # Parameters used only inside other parameters' expressions take the kind "number"; an expression
    # parameter gets the kind of its use.
    for p, value in params.items():
        if isinstance(value, str):
            q = expr.quantity(value)
            if q is None:
                try:
                    used = expr.names_in(value)
                except ValueError as exc:
                    raise _fail(source, f"parameters.{p}", str(exc)) from None
                missing = used - set(params)
                if missing:
                    raise _fail(source, f"parameters.{p}", f"{sorted(missing)[0]!r} is not a parameter")
            elif q[1] and measured.get(p) == "length":
                raise _fail(source, f"parameters.{p}", f"{_short(value)} is an angle but {p} is used as a length")
    return {p: measured.get(p, "number") for p in params}


def _check_mobility(d: Definition) -> None:
    """Gruebler's count must equal the number of inputs."""
    topo = d.topology
    mobility = topo.mobility
    if not d.inputs:
        raise _fail(d.source, "inputs", f"no input: the mechanism has mobility {mobility} (Gruebler: "
                                        f"{topo.gruebler()}); add an [[inputs]] crank or slider")
    if mobility != len(d.inputs):
        raise _fail(d.source, "inputs", f"the mechanism has mobility {mobility} (Gruebler: {topo.gruebler()}) but "
                                        f"{len(d.inputs)} input(s); give one input per degree of freedom")
    lost = topology.disconnected(topo)
    if lost:
        raise _fail(d.source, "groups", f"links {', '.join(sorted(lost))} are not connected to the ground")


# ------------------------------------------------------------------------------------------ resolve
@dataclass(frozen=True)
class Geometry:
    """Numeric data of a definition for one set of parameter values, SI units (m, rad, s).

    ``ground``: name -> (x, y); ``elements``: one dict of numeric fields per element, in solving order
    (lengths in m, angles in rad, branches +-1); ``values``: the parameter values (file units)."""

    ground: dict[str, tuple[float, float]]
    elements: tuple[dict, ...]
    values: dict[str, float]


def parameter_values(d: Definition, overrides: dict[str, float] | None = None) -> dict[str, float]:
    """Every parameter's value (file units; angles in rad), with ``overrides`` (already numbers)."""
    overrides = dict(overrides or {})
    for k in overrides:
        if k not in d.parameters:
            raise ParameterError(f"{k!r} is not a parameter of {d.name}; parameters: "
                                 f"{', '.join(d.parameter_order) or '(none)'}")
    values: dict[str, float] = {}

    def direct(p: str) -> float | None:
        if p in overrides:
            return float(overrides[p])
        raw = d.parameters[p]
        if isinstance(raw, (int, float)):
            return float(raw)
        q = expr.quantity(raw)
        return None if q is None else q[0]

    for first in d.parameter_order:                # depth-first with an explicit stack (no recursion limit)
        stack: list[str] = [first]
        while stack:
            p = stack[-1]
            if p in values:
                stack.pop()
                continue
            v = direct(p)
            if v is None:
                raw = d.parameters[p]
                missing = [n for n in sorted(expr.names_in(raw)) if n not in values and n in d.parameters]
                for n in missing:
                    if n in stack:
                        cycle = stack[stack.index(n):] + [n]
                        raise _fail(d.source, f"parameters.{n}", f"defined in terms of itself ({' -> '.join(cycle)})")
                if missing:
                    stack.extend(missing[:1])
                    continue
                try:
                    v = expr.evaluate(raw, {n: values[n] for n in expr.names_in(raw) if n in values})
                except ValueError as exc:
                    raise ParameterError(f"{d.source}: parameters.{p}: {exc}") from None
            if not abs(v) <= MAX_MAGNITUDE:
                raise ParameterError(f"{d.source}: parameters.{p}: {v:g} is out of range; give a magnitude "
                                     f"<= {MAX_MAGNITUDE:g}")
            values[p] = v
            stack.pop()
    return values


def resolve(d: Definition, values: dict[str, float], keep_problems: bool = False) -> Geometry:
    """Evaluate every field of ``d`` with parameter ``values`` (see :func:`parameter_values`). An element its
    kind finds unbuildable once resolved (``check_resolved``: a cam that undercuts) is refused in one line; with
    ``keep_problems`` it is kept, its one line in its ``"problem"`` field (the app's cam panel draws the
    undercut it refuses)."""
    k = d.scale

    def num(v, kind: str, where: str) -> float:
        if isinstance(v, (int, float)):
            x = float(v)
        else:
            q = expr.quantity(v)
            if q is not None:
                if q[1] and kind == "length":
                    raise ParameterError(f"{d.source}: {where}: {_short(v)} is an angle where a length is expected")
                x = q[0]
            else:
                try:
                    x = expr.evaluate(v, values)
                except ValueError as exc:
                    raise ParameterError(f"{d.source}: {where}: {exc}") from None
        if not math.isfinite(x):
            raise ParameterError(f"{d.source}: {where}: {_short(v)} is not finite")
        return x * k if kind == "length" else x

    ground = {g: (num(x, "length", f"ground.{g}"), num(y, "length", f"ground.{g}")) for g, (x, y) in d.ground.items()}
    elements = []
    n_inputs = 0
    for e in d.order:
        kind = kinds.get(e.kind)
        out = {"kind": e.kind, "point": e.point, "places": e.places, "label": e.label}
        if kind.section == "inputs":
            out["input"] = n_inputs
            n_inputs += 1
        for fname, fld in kind.fields.items():
            if fld.type == "camlaw":
                out[fname] = _resolve_camlaw(e.fields[fname], kind.rise_measure(e.fields), num,
                                             f"{e.label}: field {fname!r}", d.source)
                continue
            out[fname] = resolve_field(e.fields[fname], fld.type, num, f"{e.label}: field {fname!r}", d.source)
        if e.law is not None:
            out["law"] = lawfield.resolve(e.law, kind, num, e.label, d.source)
            if e.law.table is not None:                # a table's first q is the input's start value
                out[kind.motion_fields[0]] = e.law.table[1][0]
        kind.resolve_extra(out, d.topology)
        kind.resolve_at(out, ground)
        problem = kind.check_resolved(out, units=d.units)
        if problem and not keep_problems:
            raise ParameterError(f"{d.source}: {e.label}: {problem}")
        if problem:
            out["problem"] = problem
        elements.append(out)
    return Geometry(ground, tuple(elements), dict(values))


NAMES = ("point", "new", "news", "points", "link", "linkref", "pair", "links2", "carrier", "linktable", "word",
         "links1")
"""Field types whose values are names (resolved as they are)."""


def resolve_field(v, ftype: str, num, where: str, source: str):
    """One field's value resolved with ``num(value, kind, where)`` (kind "length", "angle" or "number")."""
    if ftype in NAMES:
        return v
    if ftype == "outline":                               # file units -> m
        k = num(1.0, "length", where)
        return tuple((x * k, y * k) for x, y in v) if v else ""
    if ftype == "guide" and v is None:
        return None
    if ftype == "guide":
        if v.points:
            return {"points": v.points}
        through = v.through if isinstance(v.through, str) else tuple(num(c, "length", where) for c in v.through)
        return {"through": through, "angle": num(v.angle, "angle", where)}
    if ftype == "slidetable":
        return {b: (g, p, num(a, "angle", where)) for b, (g, p, a) in v.items()}
    if ftype == "pose":
        return {p: (num(x, "length", where), num(y, "length", where)) for p, (x, y) in v.items()}
    if ftype in ("lengths2", "xy"):
        out = tuple(num(c, "length", where) for c in v)
        if ftype == "lengths2":
            for c in out:
                if c <= 0:
                    raise ParameterError(f"{source}: {where}: length {c:g} m must be > 0")
        return out
    if ftype == "branch":
        b = num(v, "number", where)
        if b not in (1.0, -1.0):
            raise ParameterError(f"{source}: {where}: branch {b:g} must be +1 or -1")
        return int(b)
    if ftype == "number":
        return num(v, "number", where)
    x = num(v, "length" if ftype in ("length", "size") else "angle", where)
    if ftype == "size" and x <= 0:
        raise ParameterError(f"{source}: {where}: length {x:g} m must be > 0")
    return x


def _resolve_camlaw(v, rise: str, num, where: str, source: str):
    """A cam's segments as an :class:`analytic.laws.Profile` over the cam angle (durations in rad summing to a
    turn, rises in m or rad as ``rise`` says), or None where not given."""
    if v is None:
        return None
    from analytic import laws
    segs = []
    for k, (shape, duration, r) in enumerate(v, 1):
        at = f"{where}: segment {k}"
        dur = num(duration, "angle", at + ": duration")
        if not dur > 0:
            raise ParameterError(f"{source}: {at}: duration {math.degrees(dur):.6g}deg must be > 0")
        segs.append(laws.Segment(shape, dur, num(r, rise, at + ": rise")))
    law = laws.Profile(tuple(segs))
    total = law.duration
    if abs(total - 2 * math.pi) > laws.CLOSE * 2 * math.pi:
        raise ParameterError(f"{source}: {where}: the durations sum to {math.degrees(total):.6g}deg; a cam's "
                             f"segments make one turn (360deg): {'add' if total < 2 * math.pi else 'take away'} "
                             f"{abs(360 - math.degrees(total)):.6g}deg")
    scale = max(max(abs(s.rise) for s in segs), 1e-300)
    if abs(law.rise) > laws.CLOSE * scale * len(segs):
        unit = "deg" if rise == "angle" else "m"
        net = math.degrees(law.rise) if rise == "angle" else law.rise
        raise ParameterError(f"{source}: {where}: the rises sum to {net:.6g} {unit}; the follower must end the turn "
                             f"where it starts: make them sum to 0")
    return law


def is_size(d: Definition, name: str) -> bool:
    """A length parameter used directly as a size (a link length, which must be > 0), not as a coordinate."""
    for e in d.order:
        for fname, fld in kinds.get(e.kind).fields.items():
            if fld.type in ("size", "lengths2"):
                v = e.fields[fname]
                if name in (v if isinstance(v, tuple) else (v,)):
                    return True
    return False
