"""The app's loads panel edits a file in place (issue 40, item 3): adding, replacing and removing a load keep
every comment and line the action does not touch (the other loads' comments, a table after the loads), and
the edited text reads back with the load as given."""

from __future__ import annotations

import tomllib

from sim.front import loads_panel

TEXT = """\
# a press: the crank drives a piston
format = "linkage/1"
name = "press"
output = "C"
force_units = "N"   # newtons

[parameters]
r = 0.05            # crank [m]
l = 0.2             # rod

[ground]
A = [0, 0]

[[inputs]]
kind = "crank"
pivot = "A"
point = "B"
length = "r"
link = "1"

[[groups]]
kind = "RRP"
point = "C"
from = "B"
length = "l"
guide = { through = "A", angle = "0deg" }
links = ["2", "piston"]

# the punch, over the working stroke
[[loads]]
name = "punch"      # keep me
kind = "force"
link = "piston"
point = "C"
direction = [-1, 0]
magnitude = 100     # N

[[loads]]
name = "brake"
kind = "torque"     # on the crank
link = "1"
magnitude = -0.5

[friction]          # after the loads
mu = 0.1            # steel on bronze
pin_radius = 0.005
"""

COMMENTS = ["# a press: the crank drives a piston", "# newtons", "# crank [m]", "# the punch, over the working stroke",
            "# keep me", "# N", "# after the loads", "# steel on bronze"]


def _comments_kept(text, but=()):
    for c in COMMENTS:
        if c not in but:
            assert c in text, c


def test_adding_a_load_keeps_every_comment_and_the_friction_table():
    new, loads = loads_panel.edited(TEXT, "add", None, {"name": "g", "kind": "torque", "link": "2",
                                                          "magnitude": 0.25})
    _comments_kept(new)
    data = tomllib.loads(new)
    assert [ld["name"] for ld in data["loads"]] == ["punch", "brake", "g"]
    assert data["loads"][2]["magnitude"] == 0.25 and data["friction"]["mu"] == 0.1
    assert [ld["name"] for ld in loads] == ["punch", "brake", "g"]


def test_replacing_a_load_keeps_the_other_loads_comments():
    new, _ = loads_panel.edited(TEXT, "replace", "brake", {"name": "brake", "kind": "torque", "link": "1",
                                                            "magnitude": -0.75})
    _comments_kept(new)
    data = tomllib.loads(new)
    assert data["loads"][1] == {"name": "brake", "kind": "torque", "link": "1", "magnitude": -0.75}
    assert data["loads"][0]["magnitude"] == 100
    # nothing outside the replaced table changed: the text up to it is the file's own
    head = TEXT.split('[[loads]]\nname = "brake"')[0]
    assert new.startswith(head)


def test_removing_every_load_leaves_the_rest_of_the_file_as_it_was():
    one, _ = loads_panel.edited(TEXT, "remove", "punch", None)
    _comments_kept(one, but=("# keep me", "# N"))
    none, loads = loads_panel.edited(one, "remove", "brake", None)
    assert loads == [] and "loads" not in tomllib.loads(none)
    assert "# steel on bronze" in none and "# crank [m]" in none
    assert tomllib.loads(none)["friction"] == {"mu": 0.1, "pin_radius": 0.005}


def test_a_spring_written_through_the_panel_reads_back_as_given():
    spring = {"name": "s", "kind": "spring", "between": [["ground", "A"], ["2", [0.1, 0.0]]], "stiffness": 200.0,
              "free_length": 0.05}
    new, _ = loads_panel.edited(TEXT, "add", None, spring)
    assert tomllib.loads(new)["loads"][2] == spring
