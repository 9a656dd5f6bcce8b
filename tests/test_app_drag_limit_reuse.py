"""A drag step stopped at an assembly limit (sim/front/app.py drag_limit): the answer solved from the limit
search's own trial mechanism (requests.Seeded) is the solve of a fresh load of the values it gives."""

from __future__ import annotations

import numpy as np

from sim.front import app


def _start():
    sol = app.solve({"mechanism": "jansen", "samples": 73, "figures": False})
    i = 6
    x, y = sol["points"]["C"]["x"][i], sol["points"]["C"]["y"][i]
    return x, y, [sol["inputs"][sol["input"]][i]]


def test_limit_answer_is_fresh_solve_of_its_values():
    x, y, q = _start()
    cache = app.Mechanisms()
    body = {"mechanism": "jansen", "set": {}, "samples": 73, "figures": False, "point": "C",
            "target": [x + 0.1, y], "input": q}                      # 0.1 m: far past where the crank turns
    a = app.drag(body, cache)
    assert not a["drag"]["reached"] and "limit" in a["drag"]["message"] and a["drag"]["changed"]
    fresh = app.solve({"mechanism": "jansen", "set": a["drag"]["set"], "samples": 73, "figures": False})
    for p, xy in fresh["points"].items():
        for c in "xy":
            # the same values solved by the same closed forms: only the mechanism object differs
            np.testing.assert_allclose(np.array(a["solve"]["points"][p][c], float), np.array(xy[c], float),
                                       rtol=1e-12, atol=1e-15)


def test_pressing_on_the_limit_keeps_the_values():
    # a step of the benchmark's Klann drag (benchmarks/app_drag.py) whose start is already at the limit: the
    # crank stops turning fully at every fraction of the way toward the target
    body = {"set": {"rod_elbow": 59.70309646583667, "lower_rocker": 29.818355074772853}, "mechanism": "klann",
            "samples": 361, "figures": False, "point": "E", "target": [-0.03915216145467217, -0.003508293927398277],
            "input": [0.5235987755982989], "locked": []}
    a = app.drag(body, app.Mechanisms())
    assert not a["drag"]["reached"] and a["solve"] is None and a["drag"]["changed"] == {}
    assert a["drag"]["set"] == body["set"] and "cannot turn fully" in a["drag"]["message"]
