"""Issue 41, items 7 and 8: faults found from outside. Bad input ends in one line naming the file, element,
field or option and the fix, exit code 2, no traceback; a failed verdict (exit 1) and a refusal write
nothing; resource bombs are refused early with the limit named. Each case was reproduced before its fix
(the fault each test catches is in its docstring)."""

import os
import re
import subprocess
import sys

import pytest

import cli_runner  # the command in this process (tests/cli_runner.py)


def _lib(name):
    from analytic.registry import LIBRARY
    return (LIBRARY / f"{name}.toml").read_text()


def _files(folder):
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in folder.rglob("*") if p.is_file()}


def _one_line(r, pattern):
    """Exit 2, one line on stderr matching ``pattern``, no traceback."""
    assert r.returncode == 2, (r.returncode, r.stdout[-300:], r.stderr[-800:])
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("linkage: error: ") and "Traceback" not in r.stderr, r.stderr
    assert re.search(pattern, lines[0]), lines[0]


# ------------------------------------------------------------------------------------------------ item 8
def test_json_piped_into_head_n_0_is_quiet_with_python_buffering_stdout(tmp_path):
    """Fault: with stdout block-buffered (PYTHONUNBUFFERED unset, as a user's shell has it) the JSON sat in
    the buffer until exit, and the interpreter's final flush met the closed pipe: 'Exception ignored ...
    BrokenPipeError' and exit 120."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}
    r = subprocess.run(f"{sys.executable} -m sim analyze fourbar --json | head -n 0", shell=True,
                       capture_output=True, text=True, cwd=tmp_path, timeout=120, env=env)
    assert r.stderr == "", r.stderr
    assert list(tmp_path.iterdir()) == []


def test_a_failed_run_writes_no_file_and_leaves_no_folder(tmp_path):
    """Fault: ``run`` whose comparison FAILED (exit 1: a 20 ms step on the four-bar) wrote o/fourbar.csv,
    its units file and the sheet."""
    r = cli_runner.run("run", "fourbar", "--no-video", "--out-dir", "o", "--timestep", "0.02", cwd=tmp_path)
    assert r.returncode == 1 and "FAILED" in r.stdout, (r.returncode, r.stderr)
    assert list(tmp_path.iterdir()) == []                      # no o/ and nothing in it
    line, = r.stderr.strip().splitlines()
    assert re.search(r"not written: o/fourbar\.csv, o/fourbar\.png \(fourbar FAILED .*drop --timestep", line), line


def test_a_failed_run_into_an_existing_folder_changes_nothing_there(tmp_path):
    (tmp_path / "o").mkdir()
    (tmp_path / "o" / "fourbar.csv").write_text("mine\n")      # a file of the user's, of an output's name
    before = _files(tmp_path)
    r = cli_runner.run("run", "fourbar", "--no-video", "--out-dir", "o", "--timestep", "0.02", cwd=tmp_path)
    assert r.returncode == 1, r.stderr
    assert _files(tmp_path) == before


def test_a_failed_motor_run_writes_neither_its_csv_nor_its_units_file(tmp_path):
    """Fault: ``dynamics --motor 5,1e9 --csv out.csv`` that ended FAIL (exit 1; here a 2 ms step the motor
    cannot be followed at) left out.csv and out.csv.units.json."""
    r = cli_runner.run("dynamics", "fourbar", "--motor", "5,1e9", "--timestep", "0.002", "--csv", "out.csv",
                       "--plot", "p.png", cwd=tmp_path)
    assert r.returncode == 1 and "FAIL" in r.stdout, (r.returncode, r.stderr)
    assert list(tmp_path.iterdir()) == []
    line, = r.stderr.strip().splitlines()
    assert re.search(r"not written: out\.csv, out\.csv\.units\.json, p\.png \(MuJoCo disagrees", line), line


def test_a_failed_force_check_writes_no_csv(tmp_path, monkeypatch):
    """``forces --simulate --csv`` whose MuJoCo check fails (stood in for by a verdict of False) exits 1
    and writes neither the CSV nor its units file."""
    from sim import service
    monkeypatch.setattr(service, "simulated_forces", lambda *a, **k: {"passed": False})
    r = cli_runner.run("forces", "fourbar", "--simulate", "--samples", "37", "--json", "--csv", "f.csv", cwd=tmp_path)
    assert r.returncode == 1, r.stderr
    assert list(tmp_path.iterdir()) == []
    assert "not written: f.csv, f.csv.units.json" in r.stderr


def _never():
    return _lib("fourbar").replace('name = "fourbar"', 'name = "never"').replace("l4 = 0.30 ", "l4 = 3.0 ")


def _unknown_kind():
    return _lib("fourbar").replace('kind = "RRR"', 'kind = "RRX"')


MESSAGES = [
    ("a file that cannot assemble names the file", {"never.toml": _never}, ["analyze", "never.toml"],
     r"never\.toml: the never cannot be assembled at any value of phi1: change its lengths"),
    ("...in run too", {"never.toml": _never}, ["run", "never.toml", "--no-video", "--out-dir", "o"],
     r"never\.toml: the never cannot be assembled"),
    ("an input that does not move names its speed", {}, ["compare", "fourbar", "--set", "omega1=0"],
     r"the input phi1 of the fourbar does not move \(omega1 = 0\): give omega1 a non-zero value"),
    ("an input too fast names its speed", {}, ["compare", "fourbar", "--set", "omega1=1e6"],
     r"needing a time step of .* < 1e-06 s\): lower omega1 \(now 1e\+06 rad/s\)"),
    ("an empty input range names the option", {}, ["analyze", "fourbar", "--input-range", "1:1"],
     r"--input-range 1:1: the end must exceed the start"),
    ("an unknown kind names the element's point", {"k.toml": _unknown_kind}, ["check", "k.toml"],
     r"k\.toml: groups\[1\] \(point C\): unknown kind 'RRX'"),
]


@pytest.mark.parametrize("case", MESSAGES, ids=[c[0] for c in MESSAGES])
def test_the_message_names_what_to_change(tmp_path, case):
    """Faults: 'the never cannot be assembled' named no file; 'the input does not move' and 'moves too fast
    ... slow its drives' named no parameter; 'input range 57.30deg:57.30deg' no option; 'groups[1]: unknown
    kind' no point."""
    _, files, args, pattern = case
    for name, text in files.items():
        (tmp_path / name).write_text(text())
    before = _files(tmp_path)
    r = cli_runner.run(*args, cwd=tmp_path)
    _one_line(r, pattern)
    assert _files(tmp_path) == before
