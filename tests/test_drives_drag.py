"""Dragging an actuator's pin in the app moves that actuator (issue 37, item 7): on the excavator (three
cylinders, three inputs) the pin D1, D2 or D3 dragged changes its own cylinder's length, the others kept, and
/api/drag names the input it moved (the page shows the frame nearest that input's value). The length is checked
against the geometry written here: the pin stays on its circle about the link's pivot, nearest the target, so
the length is the distance from the barrel's pin to the target's radial projection on that circle."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sim import service
from sim.front import app
from sim.service import editing as D

TOL = 1e-7
"""[m] the drag's closure (1e-9 of the 7 m machine) plus the oracle's rounding."""

# (pin, its input, the link's pivot, the barrel's pin, |pivot - pin|) of library/excavator.toml
PINS = [("D1", "s_boom", "A", "C1", 2.1708), ("D2", "s_stick", "B", "C2", 0.728), ("D3", "s_bucket", "T", "C3", 0.4301)]
Q = [2.3436, 2.0248, 1.93]


@pytest.fixture(scope="module")
def excavator():
    return service.load("excavator")


@pytest.mark.parametrize("pin, column, pivot, base, radius", PINS)
def test_dragging_a_cylinders_pin_moves_its_own_length(excavator, pin, column, pivot, base, radius):
    s = excavator.solve(np.array([Q]))
    xy = {p: np.array([float(s["x" + p][0]), float(s["y" + p][0])]) for p in (pin, pivot, base)}
    target = xy[pin] + [0.03, 0.05]
    d = D.drag(excavator, None, pin, target, Q)
    assert d.input_name == column and d.values == {} and d.scrub
    # the pin on its circle about the pivot nearest the target, then the cylinder's length to it (hand)
    u = (target - xy[pivot]) / np.linalg.norm(target - xy[pivot])
    nearest = xy[pivot] + radius * u
    assert d.input == pytest.approx(float(np.linalg.norm(nearest - xy[base])), abs=TOL)
    assert np.linalg.norm(np.array(d.position) - nearest) <= TOL
    # the other cylinders are kept: the pose at the new length with the others' values places the pin there
    q = list(Q)
    q[[c for _, c, *_ in PINS].index(column)] = d.input
    s2 = excavator.solve(np.array([q]))
    assert math.hypot(s2["x" + pin][0] - d.position[0], s2["y" + pin][0] - d.position[1]) <= TOL


def test_the_drag_answer_names_the_input_it_moved():
    s = service.load("excavator").solve(np.array([Q]))
    target = [float(s["xD2"][0]) - 0.02, float(s["yD2"][0]) + 0.04]
    out = app.drag({"mechanism": "excavator", "point": "D2", "target": target, "input": Q})
    assert out["drag"]["input_name"] == "s_stick" and out["drag"]["input"] is not None
