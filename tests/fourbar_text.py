"""The four-bars several tests load as text: the hand four-bar of a ``linkage/1`` file (ground A (0, 0), D (0.3,
0); crank AB 0.1, coupler BC 0.3, rocker DC 0.25, open branch; output C), with the name and the crank's speed
each test needs, and a mm four-bar in the links-and-joints form (:func:`joints_fourbar_text`)."""


def fourbar_text(name: str, omega1: float) -> str:
    """The four-bar as a ``linkage/1`` file's text (its own sections to be appended after it)."""
    return f"""\
format = "linkage/1"
name = "{name}"
output = "C"
[parameters]
omega1 = {omega1!r}
[ground]
A = [0, 0]
D = [0.3, 0]
[[inputs]]
kind = "crank"
pivot = "A"
point = "B"
length = 0.1
link = "1"
phi0 = 0
omega = "omega1"
[[groups]]
kind = "RRR"
point = "C"
from = ["B", "D"]
lengths = [0.3, 0.25]
links = ["2", "3"]
branch = 1
"""


def joints_fourbar_text(inputs: str, name: str | None = None) -> str:
    """A mm four-bar in the links-and-joints form (ground pivots A (0, 0) and D (80, 0), crank AB, coupler BCE
    with its point E, rocker DC, all four joints R; output E), driven by the ``inputs`` table given (e.g.
    ``'kind = "crank"\npivot = "A"\npoint = "B"'``)."""
    title = f'name = "{name}"\n' if name else ""
    return f"""
format = "linkage/1"
{title}units = "mm"
output = "E"

[pose]
A = [0, 0]
D = [80, 0]
B = [12.5, 21.6506]
C = [74.2099, 54.6944]
E = [29.506, 53.4436]

[[links]]
name = "crank"
points = ["A", "B"]

[[links]]
name = "coupler"
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
{inputs}
"""
