"""Dragging a point (sim/service/editing.py, /api/drag): the file's values that place it change so that it lands
where it was dragged, checked against the geometry written out here (circle distances, a crank's angle, a
coupler point's local frame), never against the solver's own answer alone."""

import math
from pathlib import Path

import numpy as np
import pytest

from analytic import ParameterError
from sim import service
from sim.front import app
from sim.service import editing as D

PEERS = Path(__file__).parent / "peers_examples"
TOL = 1e-7
"""[m] the drag's closure (1e-9 of a ~0.4 m size) plus the oracle's rounding: far below any visible shift."""


def fourbar_pose(m, q):
    """A, B, D of the seed four-bar at crank angle q, from its parameters (the oracle)."""
    v = m.values
    return np.zeros(2), v["l1"] * np.array([math.cos(q), math.sin(q)]), np.array([v["l4"], 0.0])


def solved(m, q, p):
    s = m.solve(np.array([[q]]))
    return np.array([float(s["x" + p][0]), float(s["y" + p][0])])


@pytest.fixture(scope="module")
def fourbar():
    return service.load("fourbar")


def test_dragging_the_coupler_joint_sets_both_link_lengths_to_the_new_distances(fourbar):
    q = 0.7
    target = solved(fourbar, q, "C") + [0.03, -0.02]
    d = D.drag(fourbar, None, "C", target, [q])
    assert d.reached and set(d.values) == {"l2", "l3"}
    A, B, Dp = fourbar_pose(fourbar, q)
    assert d.values["l2"] == pytest.approx(np.hypot(*(target - B)), abs=TOL)
    assert d.values["l3"] == pytest.approx(np.hypot(*(target - Dp)), abs=TOL)
    assert np.allclose(solved(fourbar.with_values(**d.values), q, "C"), target, atol=TOL)


def test_dragging_across_the_line_BD_flips_the_branch(fourbar):
    q = 0.7
    A, B, Dp = fourbar_pose(fourbar, q)
    target = np.array([0.15, -0.25])            # right of B->D: the branch +1 puts C to its left
    assert (Dp - B)[0] * (target - B)[1] - (Dp - B)[1] * (target - B)[0] < 0
    d = D.drag(fourbar, None, "C", target, [q])
    assert d.reached and d.values["branch"] == -1
    assert d.values["l2"] == pytest.approx(np.hypot(*(target - B)), abs=TOL)
    assert d.values["l3"] == pytest.approx(np.hypot(*(target - Dp)), abs=TOL)


def test_a_locked_length_keeps_the_joint_on_its_circle_nearest_the_target(fourbar):
    q = 0.7
    A, B, Dp = fourbar_pose(fourbar, q)
    target = solved(fourbar, q, "C") + [0.04, 0.03]
    d = D.drag(fourbar, None, "C", target, [q], locked=["l3"])
    assert not d.reached and set(d.values) == {"l2"} and "l3" in d.message
    nearest = Dp + fourbar.values["l3"] * (target - Dp) / np.hypot(*(target - Dp))
    assert np.allclose(d.position, nearest, atol=1e-6)      # [m] the least-squares stop: 1e-6 of the size
    assert d.values["l2"] == pytest.approx(np.hypot(*(nearest - B)), abs=1e-6)


def test_a_drag_that_would_break_assembly_stops_at_the_limit_and_says_why(fourbar):
    q = 0.7
    A, B, Dp = fourbar_pose(fourbar, q)
    d = D.drag(fourbar, None, "C", [1.5, 1.5], [q], locked=["l3"])   # l2 stretches until C lines up with D
    assert not d.reached and "stops at the limit" in d.message
    C = np.array(d.position)
    assert np.hypot(*(C - Dp)) == pytest.approx(fourbar.values["l3"], abs=TOL)
    assert np.hypot(*(C - B)) == pytest.approx(d.values["l2"], abs=TOL)


def test_a_ground_pivot_follows_the_coordinate_its_parameter_gives(fourbar):
    d = D.drag(fourbar, None, "D", [0.36, 0.05], [0.7])
    assert d.values == pytest.approx({"l4": 0.36}, abs=TOL) and not d.reached
    assert d.position == pytest.approx((0.36, 0.0), abs=TOL)
    assert "numbers" in d.message                       # its y is the number 0 in the file
    fixed = D.drag(fourbar, None, "A", [0.1, 0.1], [0.7])
    assert fixed.values == {} and not fixed.reached and "no value of the file places it" in fixed.message


def test_the_crank_tip_turns_the_input_and_sets_the_crank_length(fourbar):
    target = np.array([0.03, 0.11])
    d = D.drag(fourbar, None, "B", target, [0.7])
    assert d.reached
    assert d.input == pytest.approx(math.atan2(0.11, 0.03), abs=1e-9)
    assert d.values["l1"] == pytest.approx(np.hypot(*target), abs=TOL)
    scrub = D.drag(fourbar, None, "B", 0.5 * target, [0.7], locked=["l1"])     # l1 locked: a pure scrub
    assert scrub.values == {} and scrub.input == pytest.approx(math.atan2(0.11, 0.03), abs=1e-6)


def test_the_coupler_point_moves_in_its_links_frame(fourbar):
    q = 2.0
    B = fourbar_pose(fourbar, q)[1]
    C = solved(fourbar, q, "C")
    target = solved(fourbar, q, "E") + [-0.02, 0.05]
    d = D.drag(fourbar, None, "E", target, [q])
    assert d.reached and set(d.values) == {"ex", "ey"}
    u = (C - B) / np.hypot(*(C - B))
    local = target - B
    assert d.values["ex"] == pytest.approx(local @ u, abs=TOL)
    assert d.values["ey"] == pytest.approx(local @ np.array([-u[1], u[0]]), abs=TOL)


def test_round_values_lands_on_multiples_of_the_step(fourbar):
    q = 0.7
    target = solved(fourbar, q, "C") + [0.0312, -0.0123]
    d = D.drag(fourbar, None, "C", target, [q], round_to=0.005)
    for name in ("l2", "l3"):
        assert d.values[name] / 0.005 == pytest.approx(round(d.values[name] / 0.005), abs=1e-9)
    assert np.hypot(*(np.array(d.position) - target)) < 0.005      # within a step of the pointer


def test_a_pyslvs_import_drags_its_pose_and_keeps_the_rest_of_the_file():
    from analytic.format import foreign
    text = foreign.dumps(foreign.read(str(PEERS / "fourbar.pyslvs")))
    m = service.load("<upload>", text=text)
    q0 = m.inputs[0].motion.q0
    q = q0 + 0.8
    s = 1e-3                                             # mm file
    J0, J1p, J3 = (np.array(foreign.read(str(PEERS / "fourbar.pyslvs"))["pose"][p]) for p in ("J0", "J1", "J3"))
    r = np.hypot(*(J1p - J0))
    J1 = J0 + r * np.array([math.cos(q), math.sin(q)])  # the crank tip at q [mm]
    target = solved(m, q, "J2") + [0.004, -0.003]
    d = D.drag(m, text, "J2", target, [q])
    assert d.reached and d.values == {} and d.text is not None
    new = service.load("<upload>", text=d.text)
    assert np.allclose(solved(new, q, "J2"), target, atol=TOL)
    pose = D.file_data(d.text)["pose"]
    J2 = np.array(pose["J2"])
    # the new pose's link lengths are the distances from the target to J1 (at q) and to J3 [mm]
    assert np.hypot(*(J2 - J1p)) == pytest.approx(np.hypot(*(target / s - J1)), abs=1e-5)  # 9 digits written
    assert np.hypot(*(J2 - J3)) == pytest.approx(np.hypot(*(target / s - J3)), abs=1e-5)
    old_lines = [ln for ln in text.splitlines() if not ln.startswith("J2 =")]
    assert [ln for ln in d.text.splitlines() if not ln.startswith("J2 =")] == old_lines


def test_the_input_tip_of_a_pyslvs_import_turns_the_input_and_leaves_the_pose():
    from analytic.format import foreign
    text = foreign.dumps(foreign.read(str(PEERS / "fourbar.pyslvs")))
    m = service.load("<upload>", text=text)
    J0 = np.array(D.file_data(text)["pose"]["J0"]) * 1e-3
    target = J0 + 0.01 * np.array([math.cos(2.0), math.sin(2.0)])      # inside the crank's circle: unreachable
    d = D.drag(m, text, "J1", target, [m.inputs[0].motion.q0])
    assert d.text is None and d.values == {} and d.scrub and "turned to 114.6 deg" in d.message
    assert d.input == pytest.approx(2.0, abs=1e-6)                      # the crank points at the pointer
    r = np.hypot(*(np.array(d.position) - J0))
    assert r == pytest.approx(0.025, rel=1e-5)                          # on the crank's own circle (25 mm)


def test_rewrite_pose_touches_only_the_entry_and_keeps_comments():
    text = '[pose]\nA = [0, 0]   # the pivot\nB = [1, 2]\n\n[ground]\nB = [5, 5]\n'
    old = D.file_data(text)
    new = {**old, "pose": {**old["pose"], "A": [0.5, -1.0]}}
    out = D.rewrite_pose(text, old, new)
    assert out == '[pose]\nA = [0.5, -1.0]   # the pivot\nB = [1, 2]\n\n[ground]\nB = [5, 5]\n'


def test_bad_drags_are_one_line_naming_the_field(fourbar):
    with pytest.raises(ParameterError, match="point 'Z' is not a point"):
        D.drag(fourbar, None, "Z", [0, 0], [0.0])
    with pytest.raises(ParameterError, match="input must give 1"):
        D.drag(fourbar, None, "C", [0, 0], [0.0, 1.0])
    with pytest.raises(app.RequestError, match=r"target \[0\] must be two numbers"):
        app.drag({"mechanism": "fourbar", "point": "C", "target": [0], "input": [0.0]})
    with pytest.raises(app.RequestError, match="input must be the pose's 1 input"):
        app.drag({"mechanism": "fourbar", "point": "C", "target": [0.3, 0.2], "input": 0.0})


def test_a_crank_dragged_past_turning_fully_stops_at_the_grashof_limit():
    # l1 + l4 <= l2 + l3 keeps the seed four-bar's crank turning (l1 <= 0.25 with l2 0.3, l3 0.25, l4 0.3)
    answer = app.drag({"mechanism": "fourbar", "point": "B", "target": [0.0, 0.4], "input": [1.0],
                       "samples": 361, "figures": False})
    g = answer["drag"]
    assert "stops at the limit" in g["message"] and "cannot turn fully" in g["message"] and not g["reached"]
    l1 = g["set"]["l1"]
    assert 0.25 - 0.3 / 256 <= l1 <= 0.25                 # within a halving step (of the 0.1 -> 0.4 way) of it
    assert answer["solve"]["parameters"]["l1"] == l1


def test_the_api_answers_the_drag_with_the_solve_of_the_new_values():
    q_index = 60
    first = app.solve({"mechanism": "fourbar", "samples": 361, "figures": False})
    q = first["inputs"]["phi1"][q_index]
    C = np.array([first["points"]["C"]["x"][q_index], first["points"]["C"]["y"][q_index]])
    target = C + [0.02, 0.02]
    answer = app.drag({"mechanism": "fourbar", "point": "C", "target": target.tolist(), "input": [q],
                       "samples": 361, "figures": False})
    g, s = answer["drag"], answer["solve"]
    assert g["reached"] and set(g["set"]) == {"l2", "l3"}
    assert s["parameters"]["l2"] == pytest.approx(g["set"]["l2"], rel=1e-12)
    assert s["inputs"]["phi1"][q_index] == pytest.approx(q, abs=1e-12)
    got = np.array([s["points"]["C"]["x"][q_index], s["points"]["C"]["y"][q_index]])
    assert np.allclose(got, target, atol=TOL)


# ------------------------------------------------------------------------ placing by the elements up to P
SAME_DRAG = 1e-12
"""Relative: the two ways of placing the point run the same closed forms on the same values (the elements after
the point only add work), so they agree to rounding; the position to SAME_DRAG of the mechanism's size."""


def assert_same_drag(d, whole, size):
    assert (d.point, d.text, d.reached, d.message, d.scrub) == (whole.point, whole.text, whole.reached,
                                                                 whole.message, whole.scrub)
    assert d.values.keys() == whole.values.keys()
    for k, v in whole.values.items():
        assert d.values[k] == pytest.approx(v, rel=SAME_DRAG, abs=SAME_DRAG)
    assert (d.input is None) == (whole.input is None)
    if whole.input is not None:
        assert d.input == pytest.approx(whole.input, rel=SAME_DRAG, abs=SAME_DRAG)
    assert np.allclose(d.position, whole.position, rtol=0, atol=SAME_DRAG * size)
def _every_group_closes(m, q) -> bool:
    return m.solve(np.array([[q]])).first_failure() is None


@pytest.mark.parametrize("name, point, angle, reach", [
    ("jansen", "C", 0.0, 0.2), ("jansen", "D", 0.0, 0.1), ("stephenson_six_bar", "C", 0.0, 0.4),
    ("peaucellier", "C", 1.9634954084936207, 0.8)])
def test_a_drag_that_leaves_a_later_group_open_is_solved_with_the_whole_mechanism(name, point, angle, reach):
    """The drag places the point by the elements up to it; where the values it finds leave a group after the
    point unable to close in this pose, the drag is solved again on the whole mechanism (the answer the
    drag gave before it placed by the elements up to the point), which stops where that group opens."""
    m = service.load(name)
    q = 0.5
    target = solved(m, q, point) + reach * m.size * np.array([math.cos(angle), math.sin(angle)])
    with pytest.raises(D._Downstream):                       # the pruned solve ends with a later group open
        D._drag(m, None, point, target, [q], (), None, prune=True)
    d = D.drag(m, None, point, target, [q])
    whole = D._drag(m, None, point, target, [q], (), None, prune=False)
    assert_same_drag(d, whole, m.size)
    assert _every_group_closes(m.with_values(**d.values), q)     # every group of the answer closes in the pose
    assert not d.reached and "stops at the limit" in d.message


@pytest.mark.parametrize("name", ["fourbar", "jansen", "klann", "watt_six_bar", "stephenson_six_bar", "hoekens"])
def test_placing_by_the_elements_up_to_the_point_gives_the_whole_mechanisms_answer(name):
    """Later elements cannot move the point: the drag placed by the elements up to it lands on the same values,
    to the last bit, as placing the whole mechanism each time."""
    m = service.load(name)
    q = 0.9
    tips = {i.point for i in m.inputs}
    point = next(p for p in m.points if p not in m.definition.ground and p not in tips)
    target = solved(m, q, point) + 0.01 * m.size * np.array([0.6, -0.8])
    d = D.drag(m, None, point, target, [q])
    whole = D._drag(m, None, point, target, [q], (), None, prune=False)
    assert d.reached and d.values
    assert_same_drag(d, whole, m.size)
    assert np.allclose(solved(m.with_values(**d.values), q, point), target, atol=TOL)


def test_a_pose_where_a_later_group_is_open_is_refused_before_any_drag():
    """Jansen's leg with k = 40 mm: at phiOA = 0 the group placing F cannot close (its links are too short to
    meet), though C's group, before it, does. Dragging C there is refused with the pose named, as when every
    placement solved the whole mechanism: the drag's start is placed whole."""
    m = service.load("jansen").with_values(k=40.0)
    failure = m.solve(np.array([[0.0]])).first_failure()
    assert failure is not None and "point F" in failure[1]                  # F open at this pose ...
    c = solved(m, 0.0, "C")                                                   # ... C placed
    with pytest.raises(ParameterError, match="C is not assembled in this pose"):
        D.drag(m, None, "C", c + [0.002, 0.001], [0.0])
    with pytest.raises(ParameterError, match="C is not assembled in this pose"):     # nothing free to change
        D.drag(m, None, "C", c + [0.002, 0.001], [0.0], locked=("b", "j"))
