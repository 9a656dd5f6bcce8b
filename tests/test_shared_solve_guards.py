"""Guards of the shared solves (a cycle read as the turn's scan, the forces record kept per display), found
unchecked by benchmarks/mutation.py (round 4): a motion law that swings the crank back is not a turn's scan,
and a forces result asked in degrees after SI gives degrees."""

import math
from pathlib import Path

import pytest

LIBRARY = Path(__file__).resolve().parent.parent / "analytic" / "library"

SWING = """segments = [       # 90deg down and back: the crank never turns fully
  { shape = "cycloidal", duration = 0.40, rise = "90deg" },
  { shape = "dwell", duration = 0.10 },
  { shape = "poly345", duration = 0.40, rise = "-90deg" },
  { shape = "dwell", duration = 0.10 },
]
"""


def test_a_law_that_swings_the_crank_back_is_not_the_turns_scan(tmp_path):
    """servo_press with a law that turns its crank 90deg and back: its cycle's samples visit a quarter of the
    turn (their span, read here), so they are not the turn's check (Cycle.covers_turn) and give no turn scan
    (sim.service.simulation.turn_scan); the constant-speed and whole-turn laws still are."""
    from analytic import registry
    from analytic.cycle import Cycle
    from sim.service.simulation import turn_scan
    text = (LIBRARY / "servo_press.toml").read_text()
    start = text.index("segments = [")
    end = text.index("]\n", start) + 2
    p = tmp_path / "swinging_press.toml"
    p.write_text(text[:start] + SWING + text[end:])
    mech = registry.load(str(p))
    assert mech.inputs[0].motion.law.rise == pytest.approx(0.0, abs=1e-15)   # 90deg - 90deg: rounding
    cycle = Cycle.of(mech)
    q = cycle.q[:, 0]
    # a quarter turn, not 2 pi: the dwell holds the law's end exactly, so rounding only
    assert q.max() - q.min() == pytest.approx(math.pi / 2, rel=1e-9)
    assert not cycle.covers_turn
    assert turn_scan(mech, cycle) is None
    assert Cycle.of(registry.load("servo_press"), 0.25).covers_turn           # one whole turn a cycle


def test_a_forces_result_asked_in_degrees_after_si_is_in_degrees():
    """lk.forces on the four-bar: ``passed`` (the SI record), then ``to_dict(angles="deg")``: each peak's crank
    angle is the SI one times 180 / pi (the degree's definition) and the units say deg; SI asked again is SI."""
    import linkage as lk
    f = lk.forces(lk.load("fourbar"))
    f.passed                                          # reads (and keeps) the SI record first  # noqa: B018
    si = f.to_dict()
    deg = f.to_dict(angles="deg")
    assert si["units"]["angle"] == "rad" and deg["units"]["angle"] == "deg"
    for j, e in si["peaks"]["joints"].items():
        # one product by 180 / pi: rounding
        assert deg["peaks"]["joints"][j]["phi1"] == pytest.approx(math.degrees(e["phi1"]), rel=1e-12), j
        assert deg["peaks"]["joints"][j]["F"] == pytest.approx(e["F"], rel=1e-12)   # N either way: rounding
    assert f.to_dict()["units"]["angle"] == "rad"                            # SI asked again: SI
