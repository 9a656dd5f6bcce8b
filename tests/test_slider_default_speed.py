"""A slider input's default speed in the plain ``linkage/1`` form (issue 32): the mechanism's size per second, as the
links-and-joints form already has it (and as a crank's default turns it once a second), in any unit. It was 0.1 file
units per second: 0.1 mm/s in a mm file, so that forces fell to MuJoCo's noise.

The mechanism is written here: a block on the x-axis pushes a rod (100) to a rocker (40) pivoted at (60, 70); its
size by hand is the longest of the rod, the rocker and the ground's spread (70 in y): 100.
"""

from __future__ import annotations

import pytest

from analytic.format import linkfile
from analytic.mechanism import Mechanism

FILE = """format = "linkage/1"
units = "{units}"
[parameters]
lrod = {rod}
[ground]
O = [0, 0]
D = [{dx}, {dy}]
[[inputs]]
kind = "slider"
point = "B"
guide = {{ through = "O", angle = "0deg" }}
s0 = {s0}
{v}
[[groups]]
kind = "RRR"
point = "C"
from = ["B", "D"]
lengths = ["lrod", {rocker}]
links = ["rod", "rocker"]
branch = -1
"""
TOL = 1e-12   # relative: the motion law's arithmetic in doubles; a wrong default is off by a factor of 10 or more


def mech(tmp_path, units="mm", k=1.0, rod=100.0, v="", name="m"):
    """The block-rod-rocker in ``units``, every length multiplied by ``k`` (the same drawing in another unit)."""
    path = tmp_path / f"{name}.toml"
    path.write_text(FILE.format(units=units, rod=rod * k, dx=60 * k, dy=70 * k, s0=60 * k, rocker=40 * k, v=v))
    return Mechanism.from_definition(linkfile.read(path), {})


def travel_in_one_second(m) -> float:
    """How far the block moves in the first second [m], from the drive (the motion law the solver gets)."""
    q, _, _ = m.drive([0.0, 1.0])
    return float(q[1, 0] - q[0, 0])


@pytest.mark.parametrize("units, k, speed", [("mm", 1.0, 0.100), ("m", 1e-3, 0.100),
                                             ("in", 1 / 25.4, 3.94 * 0.0254)])   # 3.937 in to 3 digits
def test_the_block_moves_the_mechanism_s_size_in_one_second_in_any_unit(tmp_path, units, k, speed):
    m = mech(tmp_path, units, k)
    assert travel_in_one_second(m) == pytest.approx(speed, rel=TOL)     # 100 mm, the rod, in every unit
    assert m.inputs[0].motion.rate == pytest.approx(speed, rel=TOL)


def test_the_default_grows_with_the_mechanism(tmp_path):
    # a 250 mm rod: the longest link, so 250 mm/s; a 50 mm rod leaves the ground's spread (70 mm) the size
    assert travel_in_one_second(mech(tmp_path, rod=250.0, name="long")) == pytest.approx(0.250, rel=TOL)
    assert travel_in_one_second(mech(tmp_path, rod=50.0, name="short")) == pytest.approx(0.070, rel=TOL)


def test_a_given_speed_is_kept(tmp_path):
    m = mech(tmp_path, v="v = 30.0")
    assert travel_in_one_second(m) == pytest.approx(0.030, rel=TOL)


def test_the_default_is_written_into_the_definition_as_a_number_in_file_units(tmp_path):
    """What ``check`` and the app show: a plain number (100 mm/s), not a marker."""
    path = tmp_path / "m.toml"
    path.write_text(FILE.format(units="mm", rod=100.0, dx=60, dy=70, s0=60, rocker=40, v=""))
    v = linkfile.read(path).inputs[0].fields["v"]
    assert isinstance(v, float) and v == pytest.approx(100.0, rel=TOL)
