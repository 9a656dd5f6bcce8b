"""Opening a mechanism file as text (the app's Open button and its first mechanism; public API): a
``linkage/1`` file read as it is, a Pyslvs project or expression or a PMKS text file (told apart as
``linkage import`` tells them, by extension and content) converted to ``linkage/1`` text in the
links-and-joints form. Errors are one line naming the file."""

from __future__ import annotations

from pathlib import Path


def foreign_text(path) -> tuple[str, str] | None:
    """(the foreign kind, its ``linkage/1`` text) of a Pyslvs or PMKS file at ``path``; None for any other
    file (a ``linkage/1`` file is read as it is)."""
    from analytic.format import foreign
    kind = foreign.detect(path)
    if kind is None:
        return None
    from sim.service.importing import driven
    return kind, foreign.dumps(driven(foreign.read(path, kind=kind), str(path))[0])


def file_text(path) -> str:
    """The ``linkage/1`` text of the file at ``path``: a foreign file converted (and checked to load), a
    ``linkage/1`` file checked to read (a regular UTF-8 file within the size cap) and given as written."""
    from analytic.format import foreign, linkfile
    if foreign.detect(path):
        from sim.service.importing import driven
        foreign.definition(path)            # a mechanism, or one line naming the file
        return foreign.dumps(driven(foreign.read(path), str(path))[0])    # driven as linkage import writes it
    linkfile.read(path)
    return Path(path).read_bytes()[:linkfile.MAX_FILE_BYTES].decode("utf-8-sig")
