"""The app's requests through the door (issue 39 item 1, issue 40 item 2): each action that runs a door function
(:mod:`linkage.api`) accepts exactly that function's keyword-only arguments, less the ones the server withholds,
plus the app's own fields; a field the door does not take is refused naming it; a keyword newly taken reaches
the door (a couple on the crank moves the drive torque by the couple, the crank's own moment balance); and an
absent ``input_range`` is the file's own, as in the command line and ``linkage``."""

import inspect
import math
from pathlib import Path

import pytest

import linkage.api as door
from sim.front import fields
from tests.app_client import post

LIBRARY = Path(__file__).resolve().parents[1] / "analytic" / "library"

ROUTES = {"solve": "/api/solve", "drag": "/api/drag", "simulate": "/api/simulate", "render": "/api/render",
          "forces": "/api/forces", "dynamics": "/api/dynamics", "export": "/api/export/csv"}
DOOR_FUNCTIONS = {"solve": ("analyze",), "drag": ("analyze",), "simulate": ("compare",), "render": ("simulate",),
                  "forces": ("forces",), "dynamics": ("dynamics",), "export": ("analyze", "export")}
"""Which door function each action runs, written out here (the module's table is what is checked)."""


def refusal(srv, path, body) -> str:
    status, data = post(srv, path, body)
    assert status == 400, (status, data)
    assert isinstance(data["error"], str) and "\n" not in data["error"] and "Traceback" not in data["error"]
    return data["error"]


def door_keywords(*names) -> set:
    """The keyword-only arguments of the named door functions, read from their signatures here."""
    return {p.name for n in names for p in inspect.signature(getattr(door, n)).parameters.values()
            if p.kind is inspect.Parameter.KEYWORD_ONLY}


def accepted_by_server(srv, action: str) -> set:
    """The fields the server names when it refuses an unknown one for ``action``."""
    msg = refusal(srv, ROUTES[action], {"mechanism": "fourbar", "zz_unknown": 1})
    head = f"unknown field 'zz_unknown'; {action} takes "
    assert msg.startswith(head), msg
    return set(msg[len(head):].split(", "))


@pytest.mark.parametrize("action", list(ROUTES))
def test_each_actions_fields_are_its_door_functions_keywords_and_the_apps_own(server, action):
    assert {f.__name__ for f in fields.DOORS[action]} == set(DOOR_FUNCTIONS[action])
    expected = (door_keywords(*DOOR_FUNCTIONS[action]) - set(fields.WITHHELD)) | fields.APP_FIELDS[action]
    assert accepted_by_server(server, action) == expected


def test_the_solve_and_forces_fields_written_out(server):
    """The two most used actions' fields by hand, so that the derivation cannot drift with the tables."""
    assert accepted_by_server(server, "solve") == {
        "mechanism", "text", "set", "outputs", "digits", "arrays",             # the app's own
        "samples", "revolutions", "input_range", "figures"}                     # lk.analyze's keywords
    assert accepted_by_server(server, "forces") == {
        "mechanism", "text", "set", "digits",
        "samples", "revolutions", "input_range", "gravity", "force", "cutting_force", "torque", "inertia",
        "simulate", "pressure"}                                                 # pressure: the cylinders' sizing


def test_every_withheld_keyword_is_one_of_the_doors():
    """A withheld name that no door function takes would be a stale entry hiding nothing."""
    every = door_keywords(*{n for names in DOOR_FUNCTIONS.values() for n in names})
    assert set(fields.WITHHELD) <= every, set(fields.WITHHELD) - every


@pytest.mark.parametrize("path, name", [
    ("/api/simulate", "samples"),       # lk.compare takes no samples
    ("/api/forces", "cutting"),         # the field's old name: the door's is cutting_force
    ("/api/dynamics", "input_range"),   # a motor turns the input through whole revolutions
    ("/api/export/mjcf", "mjcf"),       # a path the door would write on the server
    ("/api/simulate", "timestep"),      # withheld: bounded work
    ("/api/solve", "gravity"),          # kinematics takes no loads
])
def test_a_field_the_door_does_not_take_is_refused_naming_it(server, path, name):
    msg = refusal(server, path, {"mechanism": "fourbar", name: 1})
    assert msg.startswith(f"unknown field {name!r}; "), msg


def test_a_door_keyword_without_a_check_is_found_at_once(monkeypatch):
    """A door function growing a keyword whose annotation says no check is refused loudly (TypeError naming
    it), never accepted unchecked."""
    def fake(mech, /, *, samples: int = 361, shape: "list[int] | None" = None):
        return None
    monkeypatch.setitem(fields.DOORS, "solve", (fake,))
    fields.keywords.cache_clear()
    fields.accepted.cache_clear()
    try:
        assert "shape" in fields.accepted("solve")
        with pytest.raises(TypeError, match="shape"):
            fields.arguments({"shape": [1]}, "solve")
    finally:
        monkeypatch.undo()
        fields.keywords.cache_clear()
        fields.accepted.cache_clear()


@pytest.mark.parametrize("body, words", [
    ({"samples": "361"}, "samples must be an integer"),
    ({"samples": 1}, "samples=1 is out of range"),
    ({"simulate": "yes"}, "simulate must be true or false"),
    ({"torque": 3}, "torque 3 must be an object"),
    ({"inertia": "/etc/passwd"}, "inertia '/etc/passwd' must be an object"),   # never a server path
    ({"cutting_force": -1}, "cutting_force=-1 is out of range"),
    ({"torque": {"9": 1.0}}, "no moving link named '9'"),                    # the door's own check
])
def test_forces_fields_are_checked_by_the_door_signature_and_the_door(server, body, words):
    msg = refusal(server, "/api/forces", {"mechanism": "fourbar", **body})
    assert words in msg, msg


def test_a_couple_on_the_crank_reaches_the_door(server):
    """``torque`` is a field because lk.forces takes it: a constant couple T on the crank (link 1) lowers the
    drive torque by T at every instant (the crank's moment balance about its pivot A: the drive, the couple
    and the coupler's force at B; the couple changes nothing else of a quasi-static run)."""
    base = {"mechanism": "fourbar", "samples": 13}
    s0, plain = post(server, "/api/forces", base)
    s1, loaded = post(server, "/api/forces", {**base, "torque": {"1": 1.5}})
    assert s0 == s1 == 200
    assert plain["units"]["drives"]["phi1"] == "N m"
    for a, b in zip(plain["drives"]["phi1"], loaded["drives"]["phi1"]):
        assert abs((a - b) - 1.5) < 1e-9       # float rounding of the same solve plus 1.5 N m


def rocking_fourbar(span: str) -> str:
    text = (LIBRARY / "fourbar.toml").read_text()
    return text.replace('output = "E"\n', f'output = "E"\ninput_range = "{span}"\n', 1)


def test_an_absent_input_range_is_the_files_own_and_the_pages_wins(server):
    """A file that says it rocks rocks in the app too (as ``linkage analyze`` and ``lk.analyze`` run it);
    a range the page sends is used instead."""
    text = rocking_fourbar("-30deg:30deg")
    status, a = post(server, "/api/solve", {"text": text, "samples": 31, "figures": False})
    assert status == 200, a
    lo, hi = a["input_range"]
    assert abs(lo + math.pi / 6) < 1e-12 and abs(hi - math.pi / 6) < 1e-12    # 30 deg, parse rounding only
    phi = a["inputs"]["phi1"]
    assert abs(min(phi) + math.pi / 6) < 1e-9 and abs(max(phi) - math.pi / 6) < 1e-9   # the samples span it
    status, b = post(server, "/api/solve", {"text": text, "samples": 31, "figures": False, "input_range": "0:1"})
    assert status == 200, b
    assert abs(b["input_range"][0]) < 1e-12 and abs(b["input_range"][1] - 1.0) < 1e-12
    assert abs(min(b["inputs"]["phi1"])) < 1e-9 and abs(max(b["inputs"]["phi1"]) - 1.0) < 1e-9
    # the forces panel reads the same range
    status, f = post(server, "/api/forces", {"text": text, "samples": 31})
    assert status == 200, f
    assert abs(min(f["inputs"]["phi1"]) + math.pi / 6) < 1e-9 and abs(max(f["inputs"]["phi1"]) - math.pi / 6) < 1e-9
