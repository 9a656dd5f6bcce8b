"""A ``linkage/1`` table written as TOML text by tomlkit (the one writer of the format's files: ``linkage
import``, ``export --toml``'s generated file, a drawing from the app; edits of a file keep its text and go
through tomlkit too, :mod:`sim.output.tomlout` and :mod:`sim.service.editing`).

:func:`dumps` takes the table in the format's order: the top-level values first, then each table
(``[parameters]``, ``[ground]``, ...), then each array of tables (``[[links]]``, ``[[inputs]]``, ...), each
after a blank line. Inside a table a value that is itself a table is written inline (``{ through = "A",
angle = 0.5 }``), except where every value of that table is a table (``[mass.links."crank"]``): then each is
a table of its own. Floats are written as Python's shortest text that reads back as the same number; a
value may carry a comment (:func:`commented`)."""

from __future__ import annotations

import numbers

import tomlkit


def dumps(data: dict) -> str:
    """``data`` (a ``linkage/1`` table) as TOML text."""
    doc = tomlkit.document()
    for key, value in data.items():
        if not (_is_table(value) or _is_tables(value)):
            doc.add(key, _value(value))
    for key, value in data.items():
        if _is_table(value):
            doc.add(tomlkit.nl())
            doc.add(key, _table(value))
    for key, value in data.items():
        if _is_tables(value):
            tables = tomlkit.aot()
            for item in value:
                tables.append(_table(item))
            doc.add(tomlkit.nl())
            doc.add(key, tables)
    return doc.as_string()


def commented(value, comment: str):
    """``value`` written with ``# comment`` after it on its line."""
    item = _value(value)
    item.comment(comment)
    return item


def _is_table(v) -> bool:
    return isinstance(v, dict)


def _is_tables(v) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)


def _table(data: dict):
    table = tomlkit.table()
    for key, value in data.items():
        if isinstance(value, dict) and value and all(isinstance(x, dict) for x in value.values()):
            table.add(key, _table(value))
        else:
            table.add(key, _value(value))
    return table


def _value(v):
    """A value as tomlkit writes it: tables inline, lists of them too (an item already made, as it is)."""
    if isinstance(v, tomlkit.items.Item):
        return v
    if isinstance(v, dict):
        inline = tomlkit.inline_table()
        for key, x in v.items():
            inline.append(key, _value(x))
        return inline
    if isinstance(v, (list, tuple)):
        array = tomlkit.array()
        for x in v:
            array.append(_value(x))
        return array
    if isinstance(v, (bool, str)):
        return tomlkit.item(v)
    if isinstance(v, numbers.Integral):
        return tomlkit.item(int(v))
    if isinstance(v, numbers.Real):
        return tomlkit.item(float(v))
    return tomlkit.item(str(v))
