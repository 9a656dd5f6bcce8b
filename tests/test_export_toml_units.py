"""``export --toml`` writes a changed value in the unit style the file used: a value written in degrees
stays in degrees (``--set swing=20deg`` gives ``swing = "20deg"``, not 0.3490658503988659), and reads back
as exactly the same number."""

import math
import random
import re
from pathlib import Path

import analytic
from sim.output.tomlout import degrees_text

import cli_runner  # the command in this process (tests/cli_runner.py)

LIB = Path(analytic.__file__).parent / "library"


def export(tmp_path, name, *sets):
    out = tmp_path / f"{name}_out.toml"
    args = [a for s in sets for a in ("--set", s)]
    r = cli_runner.run("export", name, *args, "--toml", str(out))
    assert r.returncode == 0, r.stderr
    return out


def test_a_changed_angle_written_in_degrees_stays_in_degrees(tmp_path):
    out = export(tmp_path, "peaucellier", "swing=20deg")
    text = out.read_text()
    line = next(ln for ln in text.splitlines() if ln.startswith("swing"))
    # the value in degrees, the comment kept
    assert re.match(r'swing = "20deg"\s+# half swing of the guide link', line), line
    # exactly the value given: "20deg" means math.radians(20.0) by the format's definition
    assert analytic.load(str(out)).values["swing"] == math.radians(20.0)
    # and nothing else changed: every other line as shipped
    shipped = (LIB / "peaucellier.toml").read_text().splitlines()
    assert [a for a, b in zip(text.splitlines(), shipped) if a != b] == [line]


def test_a_speed_in_degrees_per_second_and_a_length_keep_their_style(tmp_path):
    out = export(tmp_path, "whitworth", "omega1=720deg", "r=140", "phi1_0=0.5")
    text = out.read_text()
    assert re.search(r'^omega1 = "720deg"$', text, re.M)
    assert re.search(r"^r = 140\.0\s+#", text, re.M)
    mech = analytic.load(str(out))
    assert mech.values["omega1"] == math.radians(720.0) and mech.values["r"] == 140.0
    assert mech.values["phi1_0"] == 0.5               # written in radians in the file (0.0): stays radians


def test_degrees_text_reads_back_exactly():
    rng = random.Random(20)
    for _ in range(2000):
        typed = round(rng.uniform(-720, 720), rng.randint(0, 6))      # what a user types with deg
        v = math.radians(typed)
        t = degrees_text(v)
        assert math.radians(float(t)) == v and len(t) <= len(repr(typed)), (typed, t)
    for _ in range(2000):                                            # any angle: exact, or None (then radians)
        v = rng.uniform(-10, 10)
        t = degrees_text(v)
        assert t is None or math.radians(float(t)) == v
