"""A ``linkage/1`` file edited in the app keeps every comment and its layout (issue 40): a dragged point's
``[pose]`` numbers, even a point written over several lines, and the parameter values a download writes in,
edited in place (tomlkit) while the rest of the file stays byte for byte."""

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

import analytic
from sim import service
from sim.front import app

LIB = Path(analytic.__file__).parent / "library"
TOL = 1e-6      # / size: the drag places the point within 1e-9 of the size, the file keeps 9 decimals of mm

FOURBAR = """\
# a four-bar in the links-and-joints form, with comments everywhere
format = "linkage/1"
name = "fourbar_lj"   # its name
units = "mm"
output = "E"

[pose]   # the points at the start
A = [0, 0]           # the crank's pivot
D = [80, 0]
B = [12.5, 21.6506]
C = [
  74.2099,   # x of C
  54.6944,   # y of C
]                    # C written over two lines
E = [29.506, 53.4436]

# the links
[[links]]
name = "crank"
points = ["A", "B"]

[[links]]
name = "coupler"   # B, C and the coupler point E
points = ["B", "C", "E"]

[[links]]
name = "rocker"
points = ["D", "C"]

[[joints]]
kind = "R"
point = "A"
links = ["ground", "crank"]

[[joints]]
kind = "R"
point = "B"
links = ["crank", "coupler"]

[[joints]]
kind = "R"
point = "C"
links = ["coupler", "rocker"]

[[joints]]
kind = "R"
point = "D"
links = ["rocker", "ground"]

[[inputs]]
kind = "crank"   # driven at A
pivot = "A"
point = "B"
"""


def comments(text: str) -> list[str]:
    """Every comment of a file, in order (these files hold no '#' inside a string)."""
    return ["#" + line.split("#", 1)[1] for line in text.splitlines() if "#" in line]


def solved(mech, q: float, p: str) -> np.ndarray:
    s = mech.solve(np.array([[q]]), outputs=("x" + p, "y" + p))
    return np.array([float(np.ravel(s["x" + p])[0]), float(np.ravel(s["y" + p])[0])])


def test_dragging_a_point_written_over_two_lines_keeps_every_comment():
    mech = service.load("<upload>", text=FOURBAR)
    q = mech.inputs[0].motion.q0
    target = solved(mech, q, "C") + [0.003, -0.002]                 # [m]
    out = app.drag({"text": FOURBAR, "point": "C", "target": list(target), "input": [q]})["drag"]
    assert out["reached"] and out["text"] is not None, out["message"]
    text = out["text"]
    assert comments(text) == comments(FOURBAR)
    # only C's two numbers changed: every other line byte for byte
    old, new = FOURBAR.splitlines(), text.splitlines()
    assert len(old) == len(new)
    changed = [i for i, (a, b) in enumerate(zip(old, new)) if a != b]
    assert changed == [old.index("  74.2099,   # x of C"), old.index("  54.6944,   # y of C")], changed
    # the file read as TOML (not by the editor) places C where it was dragged
    assert tomllib.loads(text)["pose"]["C"] == pytest.approx(list(target * 1000), abs=TOL * 100)
    again = service.load("<upload>", text=text)
    assert np.hypot(*(solved(again, q, "C") - target)) < TOL * mech.size


def test_a_download_of_an_uploaded_file_keeps_its_comments_and_writes_the_values_set():
    shipped = (LIB / "fourbar.toml").read_text()
    assert len(comments(shipped)) >= 5                              # the test means something
    data, ctype, _ = app.export("toml", {"text": shipped, "set": {"l2": 0.31, "omega1": "720deg"}})
    text = data.decode()
    assert ctype == "application/toml" and comments(text) == comments(shipped)
    old, new = shipped.splitlines(), text.splitlines()
    changed = [a.split("=")[0].strip() for a, b in zip(old, new) if a != b]
    assert len(old) == len(new) and changed == ["l2", "omega1"], changed
    values = analytic.from_text(text, "back.toml").values
    assert values["l2"] == 0.31 and values["omega1"] == math.radians(720.0)   # exact: the text reads back so
    assert 'omega1 = "720deg"' in text                             # written in degrees as the file did


@pytest.mark.parametrize("name", analytic.names())
def test_a_generated_file_reads_back_as_the_same_design(name):
    """The writer (tomlkit) of a file without a text to edit: every library mechanism, its values changed,
    read back by the format's reader as the same definition and the same values."""
    from analytic.format import linkfile
    from sim.output.tomlout import generate
    mech = service.load(name)
    # every length-like parameter 1% longer: values the shipped file does not hold
    changed = {k: v * 1.01 for k, v in mech.values.items() if mech.definition.parameter_kind[k] == "length"}
    mech = service.load(name, changed)
    back = linkfile.parse(generate(mech), "back.toml")
    d = mech.definition
    for field in ("name", "units", "parameter_order", "ground", "order", "output", "inertia", "mass"):
        assert getattr(back, field) == getattr(d, field), field
    values = linkfile.parameter_values(back, {})
    for k, v in mech.values.items():
        assert values[k] == pytest.approx(v, rel=1e-15, abs=1e-300), k     # written with repr: exact but for "deg"


@pytest.mark.parametrize("family", ["fourbar", "slider_crank", "watt", "stephenson"])
def test_a_synthesised_design_file_reads_back_with_any_description(family):
    """The synthesis families' files go through the one writer: a description holding quotes and a backslash
    (which the old text templates wrote unescaped, breaking the file) reads back as given, the design's
    values exactly, and the comments that name the links are kept."""
    from analytic.synthesis import curves
    fam = curves.FAMILIES[family]
    x = np.linspace(0.3, 1.7, len(fam.names))
    description = 'a "quoted" \\ description'
    text = fam.text(x, [1, -1], "mm", f"path_{family}", description, 0.3, -6.2)
    data = tomllib.loads(text)
    assert data["description"] == description
    assert "# crank AB" in text
    mech = analytic.from_text(text, "back.toml")
    # exact: written as repr, the shortest text that reads back as the same float
    assert mech.values["phi1_0"] == pytest.approx(0.3, abs=0) and mech.values["omega1"] == pytest.approx(-6.2, abs=0)
