"""The quick refusal a drag's search for its limit uses (sim.service.editing.cannot_turn_fully): it may only
refuse values whose crank truly cannot turn fully, checked against Grashof's condition for the seed four-bar
(l2 = 0.3, l3 = 0.25, l4 = 0.3: the crank l1 turns fully while l1 + l4 <= l2 + l3, i.e. l1 <= 0.25, the
shortest link), and a drag's limit is the same with it as without it."""

from __future__ import annotations

import pytest

from sim import service
from sim.front import app
from sim.service import editing


@pytest.mark.parametrize("l1", [0.05, 0.1, 0.2, 0.24, 0.2499, 0.2501, 0.26, 0.29])
def test_it_refuses_only_a_crank_that_cannot_turn_fully(l1):
    mech = service.load("fourbar", {"l1": l1})
    grashof = l1 + 0.3 <= 0.3 + 0.25
    refused = editing.cannot_turn_fully(mech)
    if grashof:
        assert not refused
    elif l1 >= 0.26:            # far past the limit: a stretch of the turn ~ degrees wide does not assemble
        assert refused
    if refused:                 # the full check agrees wherever it refuses
        with pytest.raises(Exception, match="cannot turn fully|cannot be assembled"):
            service.check_turns_fully(mech)


BODY = {"mechanism": "fourbar", "point": "B", "target": [0.0, 0.4], "input": [1.0], "samples": 361, "figures": False}
"""The crank's tip dragged from l1 = 0.1 towards 0.4: past Grashof's limit at 0.25."""


def full_bisection(monkeypatch) -> dict:
    """The drag with the limit found by the full check alone (no cheap look, no quick refusal)."""
    with monkeypatch.context() as m:
        m.setattr(editing, "plain_turn_applies", lambda mech: False)
        m.setattr(editing, "cannot_turn_fully", lambda mech: False)
        return app.drag(BODY)["drag"]


@pytest.mark.parametrize("l1, turns", [(0.1, True), (0.2499, True), (0.2501, False), (0.3, False)])
def test_the_cheap_look_sees_grashofs_limit(l1, turns):
    assert editing.turns_on_its_geometry(service.load("fourbar", {"l1": l1})) is turns


def test_the_limit_a_drag_stops_at_is_the_same_with_the_quick_looks(monkeypatch):
    fast = app.drag(BODY)["drag"]
    slow = full_bisection(monkeypatch)
    assert "stops at the limit" in fast["message"]
    assert fast["set"] == slow["set"] and fast["message"] == slow["message"]
    assert 0.25 - 0.3 / 256 <= fast["set"]["l1"] <= 0.25     # Grashof's limit, within a halving of the way


@pytest.mark.parametrize("lie", ["always", "never", "early"])
def test_a_cheap_look_the_full_check_does_not_confirm_is_not_taken(monkeypatch, lie):
    """A look that says it always turns, never turns, or stops turning early (at l1 = 0.2, where the full
    check still turns a step further): the full check's own limit every time."""
    slow = full_bisection(monkeypatch)
    looks = {"always": lambda mech: True, "never": lambda mech: False, "early": lambda mech: mech.values["l1"] < 0.2}
    monkeypatch.setattr(editing, "turns_on_its_geometry", looks[lie])
    got = app.drag(BODY)["drag"]
    assert got["set"] == slow["set"] and got["message"] == slow["message"]
