"""What the app's request handlers share: a refused request (:class:`RequestError`), bounded numbers, the
mechanism a request names or uploads, its run options, and arrays as JSON-ready lists. Kept apart from
:mod:`sim.front.app` so that the handlers in other modules (:mod:`sim.front.loads_panel`) need not import the
server that imports them."""

from __future__ import annotations

import base64
import collections
import math
import threading

import numpy as np

import analytic
from analytic import Mechanism
from sim import service
from sim.service import inputs


MAX_SAMPLES = 20_001


MAX_REVOLUTIONS = 20.0


class RequestError(Exception):
    """A refused request: its HTTP status and a one-line message for the page."""

    def __init__(self, status: int, message: str):
        super().__init__(message)
        self.status = status


def number(body: dict, key: str, default: float, lo: float, hi: float, integer: bool = False) -> float:
    """A bounded numeric field: an integer where ``integer``; booleans are not numbers."""
    v = body.get(key, default)
    kinds = (int,) if integer else (int, float)
    if isinstance(v, bool) or not isinstance(v, kinds):
        raise RequestError(400, f"{key} must be {'an integer' if integer else 'a number'} (got {_short(v)})")
    if not (math.isfinite(v) and lo <= v <= hi):
        raise RequestError(400, f"{key}={_short(v)} is out of range: give {'an integer' if integer else 'a number'} "
                                f"in {lo:g}..{hi:g}")
    return v


class Mechanisms:
    """The mechanisms a server's last requests loaded, by what names them (the name or the file's text, and the
    values set): a drag's next step starts from the values its last step solved, and a Mechanism keeps what
    it worked out once (the change points' schedule and its scan of the turn, 1-3 ms), so the step finds
    them done. A mechanism is immutable; the cache holds the last ``size`` and belongs to one server."""

    UNITS = 64
    """Unit tables kept (one per file text or library name)."""

    def __init__(self, size: int = 8):
        self.size = size
        self._items: collections.OrderedDict = collections.OrderedDict()
        self._units: collections.OrderedDict = collections.OrderedDict()
        self._lock = threading.Lock()

    def holds(self, key) -> bool:
        """Whether ``key``, or a key of the same library name (the name is then known), is held."""
        with self._lock:
            return key in self._items or (key[1] is None and any(k[0] == key[0] and k[1] is None
                                                                   for k in self._items))

    def get(self, key, make):
        """The mechanism ``key`` names, loaded by ``make()`` unless held."""
        return self._kept(self._items, self.size, key, make)

    def units(self, key: str, make) -> dict[str, str]:
        """The unit of every column of the mechanism that ``key`` (its file's text or library name) names:
        units follow from a mechanism's structure, not its values, so they are worked out once per text rather
        than at every drag step or slider move (``make()``, ~5 ms for a 70-output walking leg)."""
        return self._kept(self._units, self.UNITS, key, make)

    def _kept(self, store: collections.OrderedDict, size: int, key, make):
        """``store[key]``, made by ``make()`` where absent; the ``size`` last used are kept."""
        with self._lock:
            if key in store:
                store.move_to_end(key)
                return store[key]
        value = make()                                  # outside the lock: two threads may both make it
        with self._lock:
            store[key] = value
            while len(store) > size:
                store.popitem(last=False)
        return value


class Seeded:
    """A server's :class:`Mechanisms` that takes what ``spare`` already built (a drag limit's trials, whose change
    points are scheduled) instead of building it again."""

    def __init__(self, cache: Mechanisms, spare: Mechanisms):
        self.cache, self.spare = cache, spare

    def holds(self, key) -> bool:
        return self.cache.holds(key) or self.spare.holds(key)

    def get(self, key, make):
        return self.cache.get(key, lambda: self.spare.get(key, make))

    def units(self, key: str, make) -> dict[str, str]:
        return self.cache.units(key, make)


def mechanism_of(body: dict, cache: Mechanisms | None = None) -> Mechanism:
    """The mechanism of a request: a known name, or an uploaded file's text; never a path. ``cache``: a
    server's :class:`Mechanisms`, to reuse one loaded with the same values."""
    values = body.get("set", {})
    if not isinstance(values, dict):
        raise RequestError(400, "set must be an object of parameter values, e.g. {\"l1\": 0.12}")
    for k, v in values.items():
        if isinstance(v, bool) or not isinstance(v, (int, float, str)):
            raise RequestError(400, f"set.{k} must be a number or text such as \"30deg\" (got {_short(v)})")
    text = body.get("text")
    if text is not None:
        if not isinstance(text, str):
            raise RequestError(400, "text must be the mechanism file's contents as a string")
        key = ("<upload>", text, tuple(sorted(values.items())))
        return cache.get(key, lambda: service.load("<upload>", values, text=text)) if cache else \
            service.load("<upload>", values, text=text)
    name = body.get("mechanism")
    if not isinstance(name, str):
        raise RequestError(400, "mechanism must be a name (GET /api/mechanisms lists them) or give text")
    key = (name, None, tuple(sorted(values.items())))
    if not (cache and cache.holds(key)) and name not in analytic.names():   # names() lists a folder: ~0.4 ms
        raise RequestError(404, f"unknown mechanism {_short(name)}; known: {', '.join(analytic.names())}")
    return cache.get(key, lambda: service.load(name, values)) if cache else service.load(name, values)


def input_range_of(body: dict, mech: Mechanism) -> tuple[float, float] | None:
    """The first input's range: ``"LO:HI"`` (angles in rad or with a deg suffix) or [LO, HI]; absent: the
    file's own ``input_range`` as the door reads it (:func:`linkage._inputs.input_range_of`), None where the
    file has none (the input turns)."""
    from linkage._inputs import input_range_of as door_range
    v = body.get("input_range")
    if v is None or v == "":
        return door_range(mech, None)
    if isinstance(v, str) and ":" in v:
        return inputs.input_range(mech, v)
    if isinstance(v, list) and len(v) == 2 and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v):
        return float(v[0]), float(v[1])
    raise RequestError(400, f"input_range {_short(v)} is not LO:HI (e.g. \"-100deg:-45deg\") or [LO, HI]")


def run_options(body: dict, mech: Mechanism) -> tuple[int, float, tuple[float, float] | None]:
    """(samples, revolutions, input range) of a request, bounded."""
    samples = int(number(body, "samples", 361, 2, MAX_SAMPLES, integer=True))
    revolutions = float(number(body, "revolutions", 1.0, 1e-6, MAX_REVOLUTIONS))
    return samples, revolutions, input_range_of(body, mech)


def series(a, n: int | None = None, digits: int | None = None) -> list:
    """An array as a JSON-ready list with NaN as None (plain ``tolist`` when all finite: the common case,
    and ~50 times faster than cleaning each number). ``digits``: significant digits relative to the array's
    peak; the page asks for 7 while dragging, which halves the bytes and the time to encode them."""
    a = np.asarray(a, dtype=float)
    a = np.broadcast_to(a, (n,)) if n is not None and a.ndim == 0 else a.ravel()
    finite = np.isfinite(a)
    if digits is not None and finite.any():
        peak = float(np.max(np.abs(a[finite])))
        if peak > 0:
            a = np.round(a, digits - 1 - math.floor(math.log10(peak)))
    if finite.all():
        return a.tolist()
    return [v if ok else None for v, ok in zip(a.tolist(), finite.tolist())]


def packed(a, n: int | None = None) -> dict:
    """An array as ``{"f64": base64}``: its float64 values, little-endian, exact (NaN where a value is not
    finite, which the page reads as a gap). ~100 times cheaper to encode than the numbers' text, and ~10.7
    characters a value where the text takes up to 24: what a drag step asks for (``"arrays": "f64"``)."""
    a = np.asarray(a, dtype="<f8")
    a = np.broadcast_to(a, (n,)) if n is not None and a.ndim == 0 else a.ravel()
    return {"f64": base64.b64encode(np.ascontiguousarray(a).tobytes()).decode("ascii")}


def _short(v) -> str:
    r = repr(v)
    return r if len(r) <= 60 else r[:57] + "..."
