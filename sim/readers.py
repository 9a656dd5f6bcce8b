"""The small input files of the command line (an --inertia JSON, a motor table, a target CSV), read with
one-line errors that name the option and the file: not a regular file, too large, not UTF-8, nested too
deeply, numbers past any range, a field past the csv module's limit, another separator than the comma.
"""

from __future__ import annotations

import csv
import io
import json
import os
import stat

from analytic import ParameterError

MAX_BYTES = 16 * 1024 * 1024
"""The largest input file read [bytes]: a motor table or a target list of a million rows fits."""


def read_text(option: str, path: str, what: str = "file") -> str:
    """The UTF-8 text of a regular file of at most MAX_BYTES (a device, a pipe or a folder refused first)."""
    where = f"{option} {path}" if option else str(path)
    as_what = " as JSON" if what == "JSON file" else ""        # the words --inertia's message always had
    try:
        st = os.stat(path)
    except OSError as exc:
        raise ParameterError(f"{where}: cannot read it{as_what} ({exc.strerror or exc})") from None
    if not stat.S_ISREG(st.st_mode):
        raise ParameterError(f"{where} is not a regular file; give a {what}")
    if st.st_size > MAX_BYTES:
        raise ParameterError(f"{where} is over {MAX_BYTES // (1024 * 1024)} MB; a {what} is at most that")
    try:
        with open(path, "rb") as f:
            raw = f.read(MAX_BYTES + 1)
    except OSError as exc:
        raise ParameterError(f"{where}: cannot read it{as_what} ({exc.strerror or exc})") from None
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ParameterError(f"{where}: not UTF-8 text (byte 0x{raw[exc.start]:02x} at offset {exc.start}); "
                             f"save it as UTF-8") from None


def _number(text: str) -> float:
    """A JSON integer as a float (a 5000-digit one becomes inf, refused by the value's own check, where
    int() would stop at Python's 4300-digit limit)."""
    return float(text)


def read_json(option: str, path: str):
    """A JSON file's value; NaN and Infinity refused, integers read as floats."""
    text = read_text(option, path, "JSON file")

    def constant(name):
        raise ParameterError(f"{option} {path}: {name} is not a number; give finite numbers")
    try:
        return json.loads(text, parse_int=_number, parse_constant=constant)
    except RecursionError:
        raise ParameterError(f"{option} {path}: nested too deeply; give an object of links, each an object "
                             f"of numbers") from None
    except json.JSONDecodeError as exc:
        raise ParameterError(f"{option} {path}: cannot read it as JSON: {exc.msg} (line {exc.lineno}, column "
                             f"{exc.colno})") from None


def csv_rows(option: str, path: str, text: str | None = None) -> list[tuple[int, list[str]]]:
    """(line number, cells) of every row of a comma-separated file; a field past the csv module's limit, a
    NUL byte, or a file separated by ';' or tabs instead of commas gets one line."""
    where = f"{option} {path}" if option else str(path)
    text = read_text(option, path, "CSV file") if text is None else text
    first = next((ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")), "")
    if "," not in first:
        for sep, name in ((";", "semicolons"), ("\t", "tabs")):
            if sep in first:
                raise ParameterError(f"{where}: the columns are separated by {name}; separate them by commas "
                                     f"(and write decimals with a point: 0.5,2)")
    rows = []
    reader = csv.reader(io.StringIO(text, newline=""))
    try:
        for cells in reader:
            rows.append((reader.line_num, cells))
    except csv.Error as exc:
        raise ParameterError(f"{where}: line {reader.line_num}: not a CSV row ({exc}); give numbers separated "
                             f"by commas") from None
    return rows
