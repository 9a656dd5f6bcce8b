"""A linkage drawn on the app's empty page (sim/front/draw.py, /api/draw): the links-and-joints file it
writes carries the drawn geometry (checked against the drawn distances), the mobility is counted before the
tool is asked (a rigid structure, loose freedoms, a missing input are named), and the tool's own Assur
groups come back."""

import math

import numpy as np
import pytest

from analytic import ParameterError
from sim import service
from sim.front import app, draw

P = {"O1": (0.0, 0.0, True), "O2": (0.08, 0.0, True), "A": (0.02, 0.035, False), "B": (0.09, 0.06, False),
     "E": (0.05, 0.09, False)}


def drawing(points, links, driven="L1"):
    return {"points": {n: {"x": x, "y": y, "ground": g} for n, (x, y, g) in points.items()},
            "links": [{"name": f"L{k + 1}", "points": list(pts)} for k, pts in enumerate(links)], "input": driven}


FOURBAR = drawing(P, [("O1", "A"), ("A", "B", "E"), ("B", "O2")])


def test_a_drawn_four_bar_keeps_the_drawn_lengths_and_its_dyad_is_found():
    r = draw.check(FOURBAR)
    assert r["error"] is None and r["mobility"] == 1 and r["output"] == "E"
    assert r["groups"] == [{"places": ["B"], "links": ["L2", "L3"], "class": "dyad RRR (class II)"}]
    m = service.load("<drawn>", text=r["text"])
    assert m.units == "mm"
    pos = {n: np.array(v[:2]) for n, v in P.items()}
    q0 = math.atan2(*(pos["A"] - pos["O1"])[::-1])
    assert m.inputs[0].motion.q0 == pytest.approx(q0, abs=1e-12)
    q = np.linspace(q0, q0 + 2 * math.pi, 73)
    s = m.solve(q)
    at = {n: np.column_stack([s["x" + n], s["y" + n]]) for n in ("O1", "O2", "A", "B", "E")}
    # every sample keeps the drawn distances (rigid links) [m]: 1e-9 bounds the solver's closure
    for a, b in (("O1", "A"), ("A", "B"), ("B", "O2"), ("A", "E"), ("B", "E")):
        drawn = np.hypot(*(pos[a] - pos[b]))
        assert np.allclose(np.hypot(*(at[a] - at[b]).T), drawn, atol=1e-9), (a, b)
    assert np.allclose(at["B"][0], pos["B"], atol=1e-12) and np.allclose(at["E"][0], pos["E"], atol=1e-12)


def test_mobility_is_counted_and_named_before_the_tool_is_asked():
    tri = draw.check(drawing({k: P[k] for k in ("O1", "O2", "A")}, [("O1", "A"), ("A", "O2")]))
    assert tri["mobility"] == 0 and "rigid structure" in tri["error"] and set(tri["names"]) == {"L1", "L2"}
    five = {**P, "C": (0.11, 0.02, False)}
    loose = draw.check(drawing({k: five[k] for k in ("O1", "A", "B", "C")}, [("O1", "A"), ("A", "B"), ("B", "C")]))
    assert loose["mobility"] == 3 and "mobility 3 with one input" in loose["error"]
    no_input = draw.check(drawing({k: P[k] for k in ("O1", "O2", "A", "B")}, [("O1", "A"), ("A", "B"), ("B", "O2")],
                                  None))
    assert no_input["mobility"] == 1 and "mark the driven link" in no_input["error"]
    alone = draw.check(drawing(P, [("O1", "A"), ("A", "B"), ("B", "O2")]))       # E on no link
    assert "E is on no link" in alone["error"] and alone["names"] == ["E"]


def test_the_driven_link_needs_one_ground_pivot():
    r = draw.check(drawing(P, [("O1", "A"), ("A", "B", "E"), ("B", "O2")], "L2"))
    assert "exactly one ground pivot" in r["error"] and r["names"] == ["L2"]


def test_a_drawing_at_a_dead_centre_is_refused_in_the_tools_words_naming_its_parts():
    # A, B and O2 in line: the pose gives the dyad no branch; the loader's line names the links and points
    pts = {"O1": (0.0, 0.0, True), "O2": (0.1, 0.0, True), "A": (0.05, 0.0, False), "B": (0.1, 0.0, False)}
    pts["B"] = (0.07, 0.0, False)
    r = draw.check(drawing(pts, [("O1", "A"), ("A", "B"), ("B", "O2")]))
    assert r["mobility"] == 1 and "singular" in r["error"] and not r["error"].startswith("<")
    assert {"L2", "L3", "B"} <= set(r["names"])


def test_bad_drawings_are_refused_naming_the_part():
    with pytest.raises(ParameterError, match="drawing must be an object"):
        draw.check([1, 2])
    with pytest.raises(ParameterError, match="link L1: it must join two or more different placed points"):
        draw.check(drawing(P, [("O1", "Z")]))
    with pytest.raises(ParameterError, match="point O1: give x and y"):
        draw.check({"points": {"O1": {"x": float("nan"), "y": 0}}, "links": []})
    with pytest.raises(ParameterError, match="input 'L9' is not a link"):
        draw.check(drawing(P, [("O1", "A")], "L9"))
    with pytest.raises(app.RequestError, match="unknown field 'points'"):
        app.draw({"points": {}})
