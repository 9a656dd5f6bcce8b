"""A seeded slice of benchmarks/fuzz.py's "surfaces" section (issue 32): forces, dynamics, synthesize path
and import with hostile options and input files. Every case exits 0/1, or 2 with one line; no input is
changed, nothing is written into the shipped library, no temporary is left, none runs past the case limit."""

import importlib.util
import os
import random
import signal
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def _fuzz():
    spec = importlib.util.spec_from_file_location("fuzz_campaign", ROOT / "benchmarks" / "fuzz.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.slow
def test_the_newer_surfaces_handle_hostile_input(tmp_path):
    fuzz = _fuzz()
    rng = random.Random(32)
    old = signal.signal(signal.SIGALRM, fuzz._alarm)
    cwd = os.getcwd()
    os.chdir(tmp_path)
    bad = []
    try:
        for argv, files in fuzz.surface_cases(rng, 80):
            cls, seconds = fuzz._timed(lambda: fuzz.surface_case(argv, files, tmp_path))
            if cls not in ("exit 0", "exit 2", "exit 1 (verdict)") or seconds > fuzz.CASE_SECONDS:
                bad.append((cls, round(seconds, 1), " ".join(argv)[:200]))
    finally:
        os.chdir(cwd)
        signal.signal(signal.SIGALRM, old)
    assert not bad, bad
