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


def test_the_limit_a_drag_stops_at_is_the_same_with_the_quick_refusal(monkeypatch):
    body = {"mechanism": "fourbar", "point": "B", "target": [0.0, 0.4], "input": [1.0], "samples": 361,
            "figures": False}
    fast = app.drag(body)["drag"]
    monkeypatch.setattr(editing, "cannot_turn_fully", lambda mech: False)
    slow = app.drag(body)["drag"]
    assert "stops at the limit" in fast["message"]
    assert fast["set"] == slow["set"] and fast["message"] == slow["message"]
    assert 0.25 - 0.3 / 256 <= fast["set"]["l1"] <= 0.25     # Grashof's limit, within a halving of the way
