"""Files of other linkage tools, opened as ``linkage/1`` mechanisms: Pyslvs-UI projects (``.pyslvs``, YAML),
bare Pyslvs expressions (``M[J[...], ...]`` in a text file) and PMKS text files.

:func:`detect` tells them apart (by extension, then content); :func:`read` turns one into a
links-and-joints table (:mod:`analytic.format.joints`), which :func:`dumps` writes as a ``linkage/1`` TOML
file (``linkage import``) and :func:`definition` reads as a mechanism (every command that takes MECH).

Point names are the source's joints ``J0``, ``J1``, ... (neither tool names its joints), link names the
source's (``ground`` stays ``ground``; PMKS' spellings of the ground become ``ground``; characters a name
cannot hold become ``_``; a pin-in-slot joint ``Jn`` adds its block ``Jn_block``). Neither format has units:
the file's unit is ``mm`` unless told otherwise. The first input moves at the format's defaults: a crank one
turn per second (``omega = "360deg"``), a slider the mechanism's size per second
(:meth:`analytic.kinds.slider.Slider.default_rate`); the others are held at their drawn values (rate 0), as
Pyslvs drives its inputs, one dial at a time (PMKS has one driver). Which input kind a source's input is, the input kinds
say themselves (:meth:`analytic.kinds.base.Kind.from_pyslvs`, ``from_pmks``: the first registered kind that
claims it), so a new input kind is one module.
"""

from __future__ import annotations

import math
import re
import stat
from pathlib import Path

from analytic import kinds
from analytic._common import FileError
from analytic.format import pmks, pyslvs

MAX_FILE_BYTES = 1 << 20          # as linkfile.MAX_FILE_BYTES
PYSLVS_PROJECT, PYSLVS_EXPRESSION, PMKS_TEXT = "Pyslvs project", "Pyslvs expression", "PMKS text"
UNITS = ("m", "mm", "cm", "in")   # as linkfile.UNITS
DEFAULT_UNITS = "mm"


def _raw(path: Path) -> bytes:
    source = str(path)
    try:
        st = path.stat()
        if not stat.S_ISREG(st.st_mode):
            raise FileError(f"{source} is not a regular file; give a mechanism file")
        with open(path, "rb") as fh:
            raw = fh.read(MAX_FILE_BYTES + 1)
    except OSError as exc:
        raise FileError(f"{source}: cannot read it ({exc.strerror or exc})") from None
    if len(raw) > MAX_FILE_BYTES:
        raise FileError(f"{source} is over {MAX_FILE_BYTES} bytes; a mechanism file is at most that")
    return raw


def _text(raw: bytes, source: str) -> str:
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise FileError(f"{source}: not UTF-8 text (byte 0x{raw[exc.start]:02x} at offset {exc.start}); save it as "
                        f"UTF-8") from None


def detect(path: str | Path) -> str | None:
    """Which tool's file ``path`` is: :data:`PYSLVS_PROJECT`, :data:`PYSLVS_EXPRESSION`, :data:`PMKS_TEXT`,
    or None for a ``linkage/1`` file (``.toml``, ``.json``, or anything else that reads as none of them)."""
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix in (".toml", ".json"):
        return None
    if suffix == ".pyslvs":
        return PYSLVS_PROJECT
    if not p.is_file():
        return None
    try:
        with open(p, "rb") as fh:
            head = fh.read(MAX_FILE_BYTES)
    except OSError:
        return None
    try:
        text = head.decode("utf-8-sig")
    except UnicodeDecodeError:
        return None
    if pyslvs.is_expression(text):
        return PYSLVS_EXPRESSION
    if re.search(r"(?m)^\s*mechanism\s*:", text) and "M[" in text:
        return PYSLVS_PROJECT
    if suffix == ".pmks":
        raise FileError(f"{path}: a PMKS JSON file (.pmks) is not read; open it in PMKS and save the text form "
                        f"(one joint per line)")
    if pmks.looks_like(text):
        return PMKS_TEXT
    return None


def name_of(stem: str) -> str:
    """A mechanism name from a file's stem (characters a name cannot hold become ``_``)."""
    name = re.sub(r"[^A-Za-z0-9_]+", "_", stem).strip("_")
    return name if name and name[0].isalpha() else f"m_{name}" if name else "imported"


def pose_size(form: dict) -> float:
    """The largest distance between two of the pose's points (file units): the size the inputs' default
    rates are scaled by."""
    xy = list(form["pose"].values())
    return max((math.dist(a, b) for i, a in enumerate(xy) for b in xy[i + 1:]), default=0.0)


MAX_MAGNITUDE = 1e12
"""The largest coordinate or angle read from another tool's file (as every number of a mechanism file)."""


def _check_numbers(form, source: str, where: str = "") -> None:
    """Every number of the converted table finite and of magnitude <= MAX_MAGNITUDE (a coordinate written
    nan, inf or 1e999 in the source is refused, naming it, rather than imported)."""
    if isinstance(form, dict):
        for k, v in form.items():
            _check_numbers(v, source, f"{where}.{k}" if where else str(k))
    elif isinstance(form, (list, tuple)):
        for i, v in enumerate(form):
            _check_numbers(v, source, f"{where}[{i}]")
    elif isinstance(form, float) and not (math.isfinite(form) and abs(form) <= MAX_MAGNITUDE):
        raise FileError(f"{source}: {where} = {form!r} is not a finite number of magnitude <= {MAX_MAGNITUDE:g}; "
                        f"fix the value in the source")


def read(path: str | Path, inputs: list[tuple[int, int]] | None = None, units: str = DEFAULT_UNITS,
         kind: str | None = None) -> dict:
    """The links-and-joints table of another tool's file (see the module docstring); ``inputs`` (Pyslvs
    (base, driver) pairs) replace a project's and are needed for a bare expression."""
    p = Path(path)
    source = str(path)
    kind = kind or detect(p)
    if kind is None:
        raise FileError(f"{source}: neither a Pyslvs project or expression nor a PMKS text file")
    if units not in UNITS:
        raise FileError(f"unit {units!r} is not one of {', '.join(UNITS)}")
    raw = _raw(p)
    if kind == PYSLVS_PROJECT:
        expression, pairs = pyslvs.read_project(raw, source)
        if inputs is not None:
            pairs = inputs
        form = pyslvs.to_form(pyslvs.parse_expression(expression, source), pairs, source)
    elif kind == PYSLVS_EXPRESSION:
        if not inputs:
            raise FileError(f"{source}: a bare Pyslvs expression has no inputs; import it with 'linkage import "
                            f"{source} --input BASE,DRIVER --out FILE.toml'")
        form = pyslvs.to_form(pyslvs.parse_expression(_text(raw, source), source), inputs, source)
    else:
        if inputs:
            raise FileError(f"{source}: a PMKS file names its own driving joint; --input is for Pyslvs expressions")
        form = pmks.to_form(_text(raw, source), source)
    if not form["inputs"]:
        raise FileError(f"{source}: the project has no input; give one with --input BASE,DRIVER")
    _check_numbers(form, source)
    size = pose_size(form)
    for k, item in enumerate(form["inputs"]):          # the first at its kind's default rate (unless its kind
        rate, value = kinds.get(item["kind"]).default_rate(size)   # set one), the others held
        if k == 0:
            item.setdefault(rate, value)
        else:
            item[rate] = 0.0
    out = {"format": "linkage/1", "name": name_of(p.stem), "units": units,
           "description": f"imported from the {kind} {p.name}"}
    out.update(form)
    return out


def definition(path: str | Path, inputs=None, units: str = DEFAULT_UNITS):
    """Another tool's file as a :class:`~analytic.format.linkfile.Definition`."""
    from analytic.format import linkfile
    return linkfile.from_data(read(path, inputs, units), str(path), name_of(Path(path).stem))


# --------------------------------------------------------------------------------------------- writing
def dumps(data: dict) -> str:
    """A links-and-joints table as ``linkage/1`` TOML text (:func:`analytic.format.writing.dumps`)."""
    from analytic.format import writing
    top = {k: data[k] for k in ("format", "name", "units", "description", "output", "input_range") if k in data}
    rest = {k: data[k] for k in ("parameters", "ground", "pose", "links", "joints", "inputs", "groups") if data.get(k)}
    return writing.dumps({**top, **rest})
