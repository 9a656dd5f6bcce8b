"""The protocol every load kind implements (beside :class:`analytic.kinds.base.Kind` for the elements).

A load kind is one module of :mod:`analytic.loads` holding its record (a frozen dataclass in SI that
subclasses :class:`Load`) and ``KIND``, a :class:`LoadKind`: its name, the fields its ``[[loads]]`` table
takes (:class:`Field`: what the editor shows and how the value is written) and its parser. The record owns
everything about the load, each a hook with a default here:

* **format**: ``KIND.parse`` (the table -> the record, a :class:`~analytic.loads.common.LoadError` naming the
  field for anything wrong) and :meth:`Load.file_table` (the record -> the table in file units: an exported file
  reads back to the same record);
* **mechanics**: :meth:`Load.applications` (the wrenches it puts on links; its generalized force and its rate
  follow by virtual work, :func:`analytic.loads.kinetostatics.generalized`), :meth:`Load.energy` (stored, or
  None), :meth:`Load.dissipation` (or None), :meth:`Load.at_start` (fixing what the start pose sets: a
  spring's free length from its preload);
* **reduced equation** (:mod:`analytic.loads.reduced`): :attr:`Load.speed_linear` (a force linear in the speed,
  carried as a damping coefficient) and :meth:`Load.rates_read` (what the reduced equation cannot carry);
* **MuJoCo**: :meth:`Load.mujoco` (a :class:`LineTendon`, :class:`PinTendon` or :class:`ConstantActuator`
  the model builder turns into its element, or a sentence saying why MJCF cannot hold it);
* **drawing**: :meth:`Load.drawing` (its shape and symbol over the samples, for the app and the pictures);
* **outputs**: :meth:`Load.record` (its entry of the ``loads`` table of ``forces``/``dynamics`` JSON).

Nothing outside a load kind's module switches on its class or name: registering a kind is one line in
:mod:`analytic.loads`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np


@dataclass(frozen=True)
class Field:
    """One field of a load kind's table (besides ``name`` and ``kind``), as the editor shows it.

    ``type`` says how the editor reads the text typed into it: ``text`` as is; ``number`` a number or an
    expression; ``pair`` "x,y"; ``point`` a point's name or "u,v" (``at``); ``table`` rows "x,y; x,y"; ``between``
    two ends "LINK:POINT LINK:u,v"; ``links`` "A,B"; ``frame`` world or link."""

    name: str
    type: str = "number"
    label: str = ""
    hint: str = ""


@dataclass(frozen=True)
class LoadKind:
    """A load kind: ``name`` (the file's ``kind``), its ``fields`` and ``parse(item, where, scales) -> record``."""

    name: str
    fields: tuple
    parse: Callable
    doc: str = ""

    @property
    def field_names(self) -> frozenset:
        """Every key its table may have (``name`` and ``kind`` included; ``point`` also as ``at``)."""
        names = {"name", "kind"} | {f.name for f in self.fields}
        if "point" in names:
            names.add("at")
        return frozenset(names)


# ------------------------------------------------------------------------------------------ MuJoCo forms
@dataclass(frozen=True)
class LineTendon:
    """A spatial tendon between the two ends (:class:`~analytic.loads.common.End`): Hooke's ``stiffness``
    [N/m] about ``length`` [m] and viscous ``damping`` [N s/m] along it."""

    ends: tuple
    stiffness: float = 0.0
    length: float = 0.0
    damping: float = 0.0


@dataclass(frozen=True)
class PinTendon:
    """A fixed tendon over the hinges that turn ``links[1]`` relative to ``links[0]``: ``stiffness`` [N m/rad]
    about the relative angle ``free_angle`` (taken in (-pi, pi] from the start pose) and ``damping``
    [N m s/rad]."""

    links: tuple
    stiffness: float = 0.0
    free_angle: float = 0.0
    damping: float = 0.0


@dataclass(frozen=True)
class ConstantActuator:
    """A constant force ``value`` [N] along ``direction`` at ``end`` (world-fixed, or turning with the link
    when not ``world``), or with ``end`` None a constant couple ``value`` [N m] on ``link``."""

    link: str
    end: object
    direction: tuple
    world: bool
    value: float


# ------------------------------------------------------------------------------------------ the record
class Load:
    """What every load record (a frozen dataclass with ``name``, ``kind`` and ``link``: the link it is reported
    on) answers; the defaults are those of a load that stores no energy, dissipates none and reads the pose
    only."""

    speed_linear = False
    """Its force is linear in the speed (a damper): the reduced equation carries it as C(u) w."""

    needs_start = False
    """It is completed from the start pose by :meth:`at_start` (a spring given by its preload)."""

    def applications(self, state, variables=None) -> list:
        """The wrenches (:class:`~analytic.loads.common.Application`) it puts on links over the samples."""
        raise NotImplementedError

    def energy(self, state):
        """The energy it stores [J] over the samples (its change is minus its work), or None."""
        return None

    def dissipation(self, state):
        """The power it dissipates [W] (>= 0) over the samples, or None."""
        return None

    def at_start(self, state) -> "Load":
        """The load with what the start pose fixes (``state``: one sample at t = 0)."""
        return self

    def rates_read(self) -> frozenset:
        """The names its value reads (an expression's), for the reduced equation's check."""
        return frozenset()

    def mujoco(self):
        """Its MuJoCo form (:class:`LineTendon`, :class:`PinTendon`, :class:`ConstantActuator`), or a str:
        why MJCF cannot hold it (it is then applied as body wrenches from the motion)."""
        return "its kind has no MJCF element"

    def drawing(self, state, apps) -> dict:
        """How it is drawn over the samples (SI): ``shape`` ("arrow": x y fx fy at its point; "between": x1 y1
        x2 y2 and ``value`` its tension; "pin": x y at ``joint`` and ``value`` the moment on links[1];
        "moment": x y at the link's centre and ``value``), ``quantity`` ("force" or "moment": the unit of
        ``value``) and ``symbol`` (the picture: arrow, zigzag, dashpot, strut, arc)."""
        a = apps[0]
        return {"shape": "arrow", "symbol": "arrow", "quantity": "force", "x": a.px, "y": a.py,
                "fx": a.fx, "fy": a.fy}

    def file_table(self, sc) -> dict:
        """The ``[[loads]]`` table that reads back to this record (file units of ``sc``)."""
        raise NotImplementedError

    def record(self, scale: float) -> dict:
        """Its entry of the ``loads`` table of the JSON outputs (lengths divided by ``scale``)."""
        raise NotImplementedError


def between_drawing(ld, state, apps, symbol: str) -> dict:
    """A load between two ends drawn as ``symbol``: its ends and its tension (on the first end, + pulling it
    towards the second)."""
    (x1, y1), (x2, y2) = state.position(ld.ends[0]), state.position(ld.ends[1])
    a = apps[0]
    ex, ey = np.asarray(x2 - x1), np.asarray(y2 - y1)
    tension = (np.asarray(a.fx) * ex + np.asarray(a.fy) * ey) / np.maximum(np.hypot(ex, ey), 1e-300)
    return {"shape": "between", "symbol": symbol, "quantity": "force", "x1": x1, "y1": y1, "x2": x2, "y2": y2,
            "value": tension}


def pin_drawing(ld, state, apps, symbol: str) -> dict:
    """A load at a pin drawn as ``symbol``: the pin and the moment on links[1]."""
    x, y = state.xy(ld.joint)
    return {"shape": "pin", "symbol": symbol, "quantity": "moment", "joint": ld.joint, "x": x, "y": y,
            "value": apps[0].couple}


def ends_table(ld, sc) -> list:
    """``between`` as written: [[LINK, POINT or [u, v]], ...] (file units)."""
    return [[e.link, e.point if e.point else [e.u / sc.length, e.v / sc.length]] for e in ld.ends]


__all__ = ["Field", "LoadKind", "Load", "LineTendon", "PinTendon", "ConstantActuator", "between_drawing",
           "pin_drawing", "ends_table"]
