"""The hand four-bar several tests load as text (ground A (0, 0), D (0.3, 0); crank AB 0.1, coupler BC 0.3,
rocker DC 0.25, open branch; output C), with the name and the crank's speed each test needs."""


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
