"""Mechanism files: the format's features (units, parameters, expressions, JSON, defaults) and one
clear line for every kind of mistake, naming the file, the element and the field."""

import json

import numpy as np
import pytest

import analytic
from analytic import FileError, ParameterError

import cli_runner  # the command in this process (tests/cli_runner.py)

FOURBAR = (analytic.registry.LIBRARY / "fourbar.toml").read_text()


def parse(text, source="m.toml"):
    return analytic.from_text(text, source)


def test_units_are_converted_to_si_and_set_acts_in_file_units():
    mm = FOURBAR.replace('format = "linkage/1"', 'format = "linkage/1"\nunits = "mm"')
    for k, v in (("l1 = 0.10", "l1 = 100.0"), ("l2 = 0.30", "l2 = 300.0"), ("l3 = 0.25", "l3 = 250.0"),
                 ("l4 = 0.30", "l4 = 300.0"), ("ex = 0.15", "ex = 150.0"), ("ey = 0.10", "ey = 100.0")):
        mm = mm.replace(k, v)
    a, b = parse(mm), analytic.load("fourbar")
    q = np.linspace(0, 6, 37)
    assert np.abs(a.solve(q)["xE"] - b.solve(q)["xE"]).max() < 1e-15          # 1 mm = 1e-3 m exactly
    assert a.with_values(l1=120.0).solve(q)["xB"][0] == pytest.approx(0.12, abs=1e-15)


def test_json_is_the_same_structure():
    import tomllib
    data = tomllib.loads(FOURBAR)
    a = analytic.from_text(json.dumps(data), "m.json")
    q = np.linspace(0, 6, 7)
    assert np.array_equal(a.solve(q)["xE"], analytic.load("fourbar").solve(q)["xE"])


def test_expressions_follow_their_parameters_unless_set():
    m = analytic.load("sixbar")
    assert m.values["h"] == pytest.approx(0.54 * (1 + (1 - (0.11 / 0.38) ** 2) ** 0.5) / 2, abs=1e-15)
    m2 = m.with_values(l1=0.12)
    assert m2.values["h"] == pytest.approx(0.54 * (1 + (1 - (0.12 / 0.38) ** 2) ** 0.5) / 2, abs=1e-15)
    assert m.with_values(h=0.5).with_values(l1=0.12).values["h"] == 0.5     # an explicit value stays


def _error(text, pattern):
    with pytest.raises(ParameterError) as exc:
        parse(text)
    msg = str(exc.value)
    assert "\n" not in msg and "m.toml" in msg, msg
    assert __import__("re").search(pattern, msg), msg


@pytest.mark.parametrize("edit,pattern", [
    (("[ground]", "[ground\n"), r"not valid TOML: .*line \d+"),
    (('format = "linkage/1"', 'format = "linkage/2"'), r"format: 'linkage/2' is not supported"),
    (('kind = "RRR"', 'kind = "RRRR"'), r"groups\[1\] \(point C\): unknown kind 'RRRR'; \[\[groups\]\] takes kind = 'RRR' or"),
    (('branch = "branch"', 'branch = "branch"\nbranchh = 1'), r"groups\[1\] \(point C\): unknown field 'branchh'; a RRR takes"),
    (('from = ["B", "D"]', 'from = ["B", "Q"]'), r"groups\[1\] \(point C\): point 'Q' is never defined"),
    (('point = "E"', 'point = "C"'), r"point name 'C' is already used by groups\[1\] \(point C\)"),
    (('links = ["2", "3"]', 'links = ["2", "1"]'), r"link name '1' is already used by inputs\[1\] \(point B\)"),
    (('from = ["B", "D"]', 'from = ["E", "D"]'), r"a cycle: C -> E depend on each other"),
    (('l2 = 0.30', 'l2 = -0.30'), r"l2=-0\.3 is not a valid length: it must be > 0"),
    (('format = "linkage/1"', 'format = "linkage/1"\nunits = "furlong"'), r"units: unknown unit 'furlong'; use one of m, mm"),
    (('length = "l1"', 'length = "l1 + lx"'), r"inputs\[1\] \(point B\): field 'length': 'lx' is not a parameter"),
    (('length = "l1"', 'length = "__import__(1)"'), r"unknown function|only numbers"),
    (('at = ["ex", "ey"]', 'at = ["ex", "30deg"]'), r"'30deg' is an angle where a length is expected"),
    (('on = ["B", "C"]', 'on = ["A", "C"]'), r"groups\[2\] \(point E\): field 'on': no link carries both 'A' and 'C'"),
])
def test_a_mistake_is_one_line_naming_the_file_element_and_field(edit, pattern):
    old, new = edit
    assert old in FOURBAR
    _error(FOURBAR.replace(old, new, 1), pattern)


def test_a_file_without_inputs_gives_the_gruebler_count():
    # The groups alone (links 2 and 3 pinned to ground at D and to B... with B on no crank) cannot move.
    text = FOURBAR.replace('[[inputs]]\nkind = "crank"\npivot = "A"\npoint = "B"', '[[groups]]\nkind = "RRR"\n'
                           'point = "B"\nfrom = ["A", "D"]\nlengths = [0.1, 0.25]\nlinks = ["1", "1b"]\n#')
    text = "\n".join(line for line in text.splitlines()
                      if not line.startswith(("length = \"l1\"", "link = \"1\"", "phi0", "omega", "alpha =")))
    with pytest.raises(FileError, match=r"inputs: no input: the mechanism has mobility 0 \(Gruebler: 3 x \(5 - 1\) "
                                        r"- 2 x 6 = 0\); add an \[\[inputs\]\] crank or slider"):
        parse(text)


def test_two_cranks_make_two_inputs_and_mobility_two():
    text = FOURBAR.replace('[[groups]]\nkind = "RRR"', '[[inputs]]\nkind = "crank"\npivot = "D"\npoint = "K"\n'
                           'length = 0.05\nlink = "9"\n\n[[groups]]\nkind = "RRR"', 1)
    text = text.replace('from = ["B", "D"]', 'from = ["B", "K"]')
    m = parse(text)
    assert [i.q for i in m.inputs] == ["phi1", "phi9"]
    assert m.topology.counts == (5, 5, 0) and m.topology.mobility == 2     # 3 x 4 - 2 x 5 = 2


def test_a_group_that_cannot_assemble_at_the_start_says_where_it_can():
    r = cli_runner.run("analyze", "fourbar", "--set", "l1=0.2", "--set", "l3=0.1",
                        "--set", "phi1_0=0")
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert "cannot turn fully" in r.stderr and "41.41deg..104.47deg" in r.stderr


def test_a_file_is_checked_from_the_command_line(tmp_path):
    f = tmp_path / "mine.toml"
    f.write_text(FOURBAR.replace("l2 = 0.30", "l2 = 0.32"))
    r = cli_runner.run("check", str(f))
    assert r.returncode == 0, r.stderr
    assert "mobility (Gruebler): 3 x (4 - 1) - 2 x 4 = 1" in r.stdout
    assert "solve order: B (crank) -> C (RRR) -> E (point)" in r.stdout
    assert "phi1 assembles over a full turn" in r.stdout
    bad = tmp_path / "bad.toml"
    bad.write_text(FOURBAR.replace('kind = "RRR"', 'kind = "RRX"'))
    r = cli_runner.run("analyze", str(bad))
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1
    assert f"{bad}: groups[1] (point C): unknown kind 'RRX'" in r.stderr
