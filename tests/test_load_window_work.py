"""The work per cycle of a load active over part of the cycle (``active = "LO:HI"``) is exact for a constant
load (issue 41): the integral is cut at the window's edges (analytic.loads.kinetostatics.switched_work), where
the trapezoid of the power counted half a sample interval of the load at each edge (a -1.5 N m brake over
half a turn read -1.16956 J against T x delta phi = -1.18437 J). The expected works are written here from
the geometry: T times the link's turn, F times its point's displacement."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

import analytic
import cli_runner

LIB = Path(analytic.__file__).parent / "library"
PRESS = Path(__file__).parent / "mechanisms" / "press_5kn.toml"
BRAKE = -1.5                                                    # [N m]


def rocker_angle(phi: float) -> float:
    """The library four-bar's rocker DC angle [rad] at crank angle ``phi``, by hand: A = (0, 0), D = (0.3, 0),
    AB = 0.1, BC = 0.3, DC = 0.25; C where the circles about B and D meet, left of B -> D (branch +1)."""
    bx, by = 0.1 * math.cos(phi), 0.1 * math.sin(phi)
    dx, dy = 0.3 - bx, 0.0 - by
    d = math.hypot(dx, dy)
    a = (0.3 ** 2 - 0.25 ** 2 + d * d) / (2 * d)               # from B along B -> D to the chord
    h = math.sqrt(0.3 ** 2 - a * a)
    cx, cy = bx + (a * dx - h * dy) / d, by + (a * dy + h * dx) / d     # the left one
    return math.atan2(cy - 0.0, cx - 0.3)


def forces_json(path, samples: int) -> dict:
    r = cli_runner.run("forces", path, "--samples", samples, "--json")
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


@pytest.mark.parametrize("samples", [361, 50])         # edges on the samples (1 deg), and between them
@pytest.mark.parametrize("link,window", [("1", (0.0, 180.0)), ("1", (300.0, 420.0)), ("3", (33.3, 77.7)),
                                         ("3", (90.0, 270.0))])
def test_a_brake_over_part_of_a_turn_does_T_times_its_links_turn(tmp_path, samples, link, window):
    lo, hi = window
    path = tmp_path / "brake.toml"
    path.write_text((LIB / "fourbar.toml").read_text() + f'\n[[loads]]\nname = "brake"\nkind = "torque"\n'
                    f'link = "{link}"\nmagnitude = {BRAKE}\nactive = "{lo}deg:{hi}deg"\n')
    d = forces_json(path, samples)
    if link == "1":
        turn = math.radians(hi - lo)
    else:
        turn = rocker_angle(math.radians(hi)) - rocker_angle(math.radians(lo))
        turn = math.remainder(turn, 2 * math.pi)
    (load,) = d["loads"]
    # rounding: the sums of 360 intervals' displacements, ~1e-15 J each
    assert load["work_per_cycle"] == pytest.approx(BRAKE * turn, rel=0, abs=1e-12)
    e = d["energy"]
    # over a closed turn at constant speed the drive supplies what the brake takes: the balance's residual is the
    # trapezoid of the smooth power dT/dt over a period, ~1e-14 J here
    assert abs(e["residual"]) <= 1e-9
    assert e["drive_work"] == pytest.approx(-BRAKE * turn, rel=0, abs=1e-9)


@pytest.mark.parametrize("samples", [37, 50])          # the window's edges (200, 300 deg) on samples, and not
def test_a_punch_over_part_of_the_stroke_does_F_times_the_pistons_travel(samples):
    d = forces_json(PRESS, samples)
    r, l = 0.040, 0.160

    def x(deg):
        p = math.radians(deg)
        return r * math.cos(p) + math.sqrt(l * l - (r * math.sin(p)) ** 2)

    works = {ld["name"]: ld["work_per_cycle"] for ld in d["loads"]}
    # F_x = -5 kN while the piston travels from x(200 deg) to x(300 deg); rounding of the J-sized sums
    assert works["punch"] == pytest.approx(-5000.0 * (x(300.0) - x(200.0)), rel=0, abs=1e-9)
    # the spring's work is its energy's change, zero over a closed turn
    assert works["ret"] == pytest.approx(0.0, abs=1e-9)
