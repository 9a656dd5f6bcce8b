"""The server's recently loaded mechanisms (sim.front.requests.Mechanisms): a drag's next step starts from
the mechanism its last step solved, and the answers are the same as without the cache."""

from __future__ import annotations

import json

import numpy as np

from sim.front import app
from sim.front.requests import Mechanisms, mechanism_of


def test_the_same_request_gets_the_same_mechanism_and_other_values_another():
    cache = Mechanisms(size=2)
    a = mechanism_of({"mechanism": "fourbar", "set": {"l1": 0.1}}, cache)
    assert mechanism_of({"mechanism": "fourbar", "set": {"l1": 0.1}}, cache) is a
    b = mechanism_of({"mechanism": "fourbar", "set": {"l1": 0.12}}, cache)
    assert b is not a and b.values["l1"] == 0.12 and a.values["l1"] == 0.1
    mechanism_of({"mechanism": "sixbar"}, cache)                       # a third: the oldest (a) is let go
    assert mechanism_of({"mechanism": "fourbar", "set": {"l1": 0.1}}, cache) is not a
    up = {"text": (app.STATIC.parents[2] / "analytic" / "library" / "fourbar.toml").read_text(), "set": {"l1": 0.1}}
    assert mechanism_of(up, cache) is mechanism_of(dict(up), cache)       # an uploaded file: by its text


def test_a_drag_through_the_cache_answers_as_without_it():
    first = app.solve({"mechanism": "fourbar", "samples": 361, "figures": False})
    i = 60
    C = np.array([first["points"]["C"]["x"][i], first["points"]["C"]["y"][i]])
    q = [first["inputs"]["phi1"][i]]
    cache = Mechanisms()
    body = {"mechanism": "fourbar", "set": {}, "samples": 361, "figures": False, "point": "C", "input": q}
    for k in range(1, 6):                      # five steps, each from the values the last one left
        step = {**body, "target": (C + 0.004 * k).tolist()}
        with_cache, without = app.drag(step, cache), app.drag(step)
        assert json.dumps(with_cache) == json.dumps(without)
        body["set"] = with_cache["drag"]["set"]
    # the next step's starting mechanism is the one the last step solved: its change points already scheduled
    assert "_scheduled" in mechanism_of(body, cache).__dict__
    assert "_scheduled" not in mechanism_of(body).__dict__


def test_the_unit_table_is_worked_out_once_per_file_and_reads_as_without_the_cache(monkeypatch):
    """Units follow from a mechanism's structure: a server works them out once per library name or file text,
    not at every drag step or slider move, and the answer is the one worked out afresh."""
    from sim import service
    calls = []
    real = service.units_of
    monkeypatch.setattr(service, "units_of", lambda *a, **k: calls.append(1) or real(*a, **k))
    cache = Mechanisms()
    bodies = [{"mechanism": "fourbar", "set": {"l1": v}, "samples": 37, "figures": False} for v in (0.1, 0.11, 0.12)]
    answers = [app.solve(b, cache)["units"] for b in bodies]
    assert len(calls) == 1                                   # three values of one mechanism: one table
    app.solve({"mechanism": "sixbar", "samples": 37, "figures": False}, cache)
    assert len(calls) == 2                                   # another mechanism: its own
    fresh = app.solve(bodies[-1])["units"]                   # no cache: worked out for this answer
    assert len(calls) == 3 and answers[-1] == fresh and answers[0] == fresh
