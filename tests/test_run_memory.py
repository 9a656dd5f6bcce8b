"""The runs' one memory bound (issue 37): ``analyze``, ``forces``, ``simulate`` and ``compare`` refuse a run whose
samples or steps would need more than sim.service.analysis.RUN_MEMORY, before any work, in one line naming the
option and the most that fit. ``analyze fourbar --samples 10000000`` needed ~5 GB and ran; ``simulate`` was
capped at 2e7 steps whatever the mechanism (37 GB of a four-bar's compare). Peak memory at the bound:
benchmarks/run_memory.py."""

from __future__ import annotations

import re

import pytest

import linkage as lk
from tests.cli_runner import run


def _one_line(r, pattern):
    """Exit 2, one line on stderr matching ``pattern``, no traceback."""
    assert r.returncode == 2, (r.returncode, r.stdout[-300:], r.stderr[-800:])
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("linkage: error: ") and "Traceback" not in r.stderr, r.stderr
    assert re.search(pattern, lines[0]), lines[0]
    return lines[0]


def test_analyze_refuses_ten_million_samples_of_the_fourbar_naming_the_most_that_fit(tmp_path):
    from sim.service.analysis import BYTES_PER_VALUE, RUN_MEMORY
    r = run("analyze", "fourbar", "--samples", "10000000", "--csv", "a.csv", cwd=tmp_path)
    line = _one_line(r, r"^linkage: error: samples=10,000,000: the fourbar's outputs at that many samples need "
                        r"about [0-9.]+ GB \(\d+ values a sample\); at most [0-9,]+ fit in the 2 GB a run may use")
    values = int(re.search(r"\((\d+) values", line).group(1))
    most = int(re.search(r"at most ([0-9,]+) fit", line).group(1).replace(",", ""))
    assert most == RUN_MEMORY // (BYTES_PER_VALUE * values)
    need = float(re.search(r"about ([0-9.]+) GB", line).group(1))
    assert need == pytest.approx(10_000_000 * BYTES_PER_VALUE * values / 1024 ** 3, abs=0.05)   # printed to 0.1
    r = run("analyze", "fourbar", "--samples", "9", "--csv", "b.csv", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    columns = (tmp_path / "b.csv").read_text().splitlines()[0].split(",")
    assert values >= len(columns)             # every CSV column is an array the run keeps (a lower bound)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b.csv", "b.csv.units.json"]       # nothing of a.csv


def test_one_rule_bounds_analyze_forces_and_the_simulation(monkeypatch):
    """The bound is one rule read by every run: shrunk, it refuses each of them at its own count (the most
    samples or steps that fit), and lets that count through."""
    from sim.service import analysis
    monkeypatch.setattr(analysis, "RUN_MEMORY", 2 * 1024 ** 2)         # 2 MiB: a few thousand samples
    mech = lk.load("fourbar")
    for call, kind in ((lambda n: lk.analyze(mech, samples=n), "outputs"),
                       (lambda n: lk.forces(mech, samples=n), "joint forces")):
        with pytest.raises(lk.ParameterError) as e:
            call(1_000_000)
        text = str(e.value)
        assert f"the fourbar's {kind} at that many samples" in text and "fit in the 0.00195 GB a run may use" in text
        most = int(re.search(r"at most ([0-9,]+) fit", text).group(1).replace(",", ""))
        call(most)                                                       # the most that fit runs
        with pytest.raises(lk.ParameterError, match=rf"samples={most + 1:,}: "):
            call(most + 1)
    with pytest.raises(lk.ParameterError) as e:
        lk.simulate(mech, revolutions=20)
    text = str(e.value)
    assert re.search(r"^revolutions=20: the fourbar's [0-9,]+ steps of [0-9.]+ s need about .* values a step\); "
                     r"at most [0-9.]+ revolutions \([0-9,]+ steps\) fit in the 0\.00195 GB", text), text
    turns = float(re.search(r"at most ([0-9.]+) revolutions", text).group(1))
    assert 0 < turns < 20
    lk.compare(mech, revolutions=turns)                                  # the revolutions it names fit
    with pytest.raises(lk.ParameterError, match="a run may use"):
        lk.compare(mech, revolutions=20)


@pytest.mark.parametrize("name", ["fourbar", "fivebar", "jansen", "excavator", "scissor_lift", "arm_2r", "cam_roller"])
def test_the_analysis_count_covers_every_array_a_solve_makes(name):
    """The bound counts an analysis's arrays from the structure (no solve: a command solves at most three times,
    tests/test_solve_counts.py); a solve at one sample, counted here, must not keep more."""
    import numpy as np
    from sim.service.analysis import analysis_values
    mech = lk.load(name)
    solved = len(list(mech.solve(*mech.drive(np.zeros(1))).keys()))
    kept = solved + 4 * len(mech.inputs) + 1                 # with the inputs' columns, their jerk, the time
    assert kept <= analysis_values(mech) <= kept + 3 * len(mech.inputs)   # a crank's own 3 counted again at most
