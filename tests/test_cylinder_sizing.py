"""The cylinder sizing table of ``linkage forces`` (issue 37, item 7): per actuator the peak push and pull force
and where they occur, with the file's bore and rod the peak pressure on each area, and with ``--pressure`` the
bore each needs. Push area pi D^2/4, pull area pi (D^2 - d^2)/4 (D bore, d rod).

Every expected number here is worked by hand from those two areas (the literals below, with the arithmetic in
their comments), not by the code under test.
"""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest

from analytic import ParameterError
from analytic.kinds.actuator import sizing
from analytic.quantities import parse_pressure
from tests.cli_runner import run

# a made-up force history [N, + pushing] of a cylinder of bore 100 mm and rod 50 mm
FORCE = np.array([1000.0, -500.0, 3000.0, -2000.0, 0.0])
CYL = {"bore": 0.100, "rod": 0.050}


def test_the_peaks_pressures_and_bores_by_hand():
    s = sizing(CYL, FORCE, 200e5)
    assert (s["push"]["at"], s["pull"]["at"]) == (2, 3)
    # the peaks are samples of the history: exact
    assert (s["push"]["F"], s["pull"]["F"]) == pytest.approx((3000.0, 2000.0), rel=1e-15)
    # 3000 N / (pi 0.1^2 / 4 = 7.853982e-3 m^2) = 381971.86 Pa; 2000 N / (pi (0.1^2 - 0.05^2) / 4 = 5.890486e-3 m^2)
    # = 339530.55 Pa: hand values rounded to 8 digits
    assert s["push"]["pressure"] == pytest.approx(381971.86, rel=1e-7)
    assert s["pull"]["pressure"] == pytest.approx(339530.55, rel=1e-7)
    z = s["sizing"]
    # at 200 bar = 2e7 Pa: D_push = sqrt(4 3000 / (pi 2e7)) = sqrt(1.909859e-4) = 13.8198 mm;
    # D_pull = sqrt(4 2000 / (pi 2e7) + 0.05^2) = sqrt(2.627324e-3) = 51.2574 mm: hand values to 6 digits
    assert z["bore_push"] == pytest.approx(0.0138198, rel=1e-5)
    assert z["bore_pull"] == pytest.approx(0.0512574, rel=1e-5)
    assert z["bore"] == pytest.approx(0.0512574, rel=1e-5)              # the pull governs here
    assert z["enough"] is True                                          # 100 mm >= 51.3 mm
    # at 2 bar: D_push = sqrt(4 3000 / (pi 2e5)) = 138.198 mm > D_pull = sqrt(1.27324e-2 + 2.5e-3) = 123.4 mm
    low = sizing(CYL, FORCE, 2e5)["sizing"]
    assert low["bore"] == pytest.approx(0.138198, rel=1e-5) and low["enough"] is False


def test_a_bore_enough_for_the_push_but_not_the_pull_round_a_thick_rod_is_not_enough():
    # bore 100 mm, rod 70 mm, pushing 1000 N and pulling 2500 N, at 5 bar = 5e5 Pa:
    # D_push = sqrt(4 1000 / (pi 5e5)) = sqrt(2.546479e-3) = 50.4627 mm (the bore is plenty for it), but
    # D_pull = sqrt(4 2500 / (pi 5e5) + 0.07^2) = sqrt(1.126620e-2) = 106.142 mm > 100 mm: hand values to 6 digits
    s = sizing({"bore": 0.100, "rod": 0.070}, np.array([1000.0, -2500.0]), 5e5)
    z = s["sizing"]
    assert z["bore_push"] == pytest.approx(0.0504627, rel=1e-5)
    assert z["bore_pull"] == pytest.approx(0.106142, rel=1e-5)
    assert z["bore"] == pytest.approx(0.106142, rel=1e-5)               # the pull governs
    assert z["enough"] is False                                         # 100 mm < 106.1 mm
    # the pull's pressure on the annulus: 2500 N / (pi (0.1^2 - 0.07^2) / 4 = 4.005531e-3 m^2) = 624137.03 Pa
    assert s["pull"]["pressure"] == pytest.approx(624137.03, rel=1e-7)


def test_a_cylinder_that_never_pulls_has_no_pull_peak():
    s = sizing({"bore": 0.0, "rod": 0.0}, np.array([10.0, 20.0, 5.0]), 1e5)
    assert s["pull"] == {"F": 0.0, "at": None}
    assert "pressure" not in s["push"]                  # no bore: no pressure
    assert "enough" not in s["sizing"]
    # 20 N at 1 bar: D = sqrt(4 20 / (pi 1e5)) = 15.9577 mm; no rod: the pull needs no bore
    assert s["sizing"]["bore_push"] == pytest.approx(0.0159577, rel=1e-5)
    assert s["sizing"]["bore_pull"] == 0.0


@pytest.mark.parametrize("text, pa", [("200bar", 2e7), ("20 MPa", 2e7), ("3000psi", 20684271.88),
                                      ("150000", 1.5e5), ("2.5e2kPa", 2.5e5)])
def test_pressure_units(text, pa):
    # psi: 4.4482216152605 N / 0.0254^2 m^2 = 6894.7573 Pa, times 3000; the rest powers of ten
    assert parse_pressure(text) == pytest.approx(pa, rel=1e-9)


@pytest.mark.parametrize("text", ["200bars", "bar", "-3bar", "0MPa", "20 atm"])
def test_a_bad_pressure_is_refused(text):
    with pytest.raises(ParameterError, match="--pressure"):
        parse_pressure(text)


def _one_line_exit_2(r, *needles):
    assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1, r.stderr
    for n in needles:
        assert n in lines[0], (n, lines[0])


def test_the_command_refuses_a_bad_unit_and_a_mechanism_without_actuators():
    _one_line_exit_2(run("forces", "dump_tipper", "--pressure", "200 atm"), "--pressure", "bar, psi")
    _one_line_exit_2(run("forces", "fourbar", "--pressure", "200bar"), "--pressure", "actuator")


def test_forces_json_and_text_carry_the_sizing_table():
    args = ("forces", "excavator", "--gravity", "0,-9.81", "--samples", "9", "--pressure", "250bar")
    out = json.loads(run(*args, "--json").stdout)
    for name, (bore, rod) in {"boom": (0.14, 0.10), "stick": (0.12, 0.085), "bucket": (0.11, 0.075)}.items():
        f = np.array(out["drives"]["s_" + name])
        rec = out["actuators"][name]
        push, pull, z = rec["push"], rec["pull"], rec["sizing"]
        # the peaks against the drive force the same JSON prints: one max each, exact
        assert push["F"] == pytest.approx(max(f.max(), 0.0), rel=1e-15)
        assert pull["F"] == pytest.approx(max(-f.min(), 0.0), rel=1e-15)
        for side in (push, pull):
            if side["F"] > 0:                           # where it occurs: the sample's time and length
                assert side["t"] == pytest.approx(out["t"][side["at"]], rel=1e-15)
                assert side["s_" + name] == pytest.approx(out["inputs"]["s_" + name][side["at"]], rel=1e-15)
        # the areas by hand from the file's diameters; one division or square root: rounding
        assert push["pressure"] == pytest.approx(push["F"] / (math.pi * bore ** 2 / 4), rel=1e-12)
        assert pull["pressure"] == pytest.approx(pull["F"] / (math.pi * (bore ** 2 - rod ** 2) / 4), rel=1e-12)
        need = max(math.sqrt(4 * push["F"] / (math.pi * 250e5)), math.sqrt(4 * pull["F"] / (math.pi * 250e5) + rod ** 2))
        assert z["bore"] == pytest.approx(need, rel=1e-12) and z["pressure"] == pytest.approx(250e5, rel=1e-15)
        assert z["enough"] == (bore >= need)
    text = run(*args).stdout
    line = next(ln for ln in text.splitlines() if ln.strip().startswith("at 250 bar"))      # the boom's
    assert "cylinder sizing (push area pi D^2/4, pull area pi (D^2 - d^2)/4" in text
    shown = float(re.search(r"bore >= ([0-9.e+-]+) m for the push", line).group(1))
    assert shown == pytest.approx(out["actuators"]["boom"]["sizing"]["bore_push"], rel=1e-3)   # printed to 4 digits
