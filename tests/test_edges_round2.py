"""Issue 32, bad input seen since issue 20: each class ends in one line naming the option or file and the
fix, exit code 2, no traceback, nothing written, the user's files byte-identical (tests from outside: the
real command in a folder of files the user had)."""

import json
import re
import subprocess
import sys

import pytest

TARGETS = "x,y\n0,0\n1,0.2\n2,0.1\n3,-0.4\n"
TABLE = "omega,tau\n0,2\n100,0\n"


def _lib(name):
    from analytic.registry import LIBRARY
    return (LIBRARY / f"{name}.toml").read_text()


def _fast_fivebar():
    """A five-bar whose cranks turn 50 rad/s: a 0.05 s step cannot hold it (compare refuses in one line)."""
    text = _lib("fivebar")
    text = re.sub(r"(?m)^omega2 = .*$", "omega2 = 50", text)
    return re.sub(r"(?m)^omega4 = .*$", "omega4 = 50", text)


FILES = {
    "t.csv": TARGETS,
    "t.toml": TARGETS,
    "table.csv": TABLE,
    "semi.csv": "omega;tau\n0;2\n100;0\n",
    "semi_targets.csv": "x;y\n0;0\n1;0.2\n2;0.1\n3;-0.4\n",
    "wide.csv": "omega,tau\n0," + "1" * 200_000 + "\n100,0\n",
    "wide_targets.csv": "x,y\n0," + "1" * 200_000 + "\n1,0.2\n2,0.1\n3,-0.4\n",
    "latin1.csv": b"omega,tau\n0,2\xb0\n100,0\n",
    "deep.json": '{"2": ' + "[" * 100_000 + "]" * 100_000 + "}",
    "digits5001.json": '{"2": {"m": ' + "9" * 5001 + ', "cx": 0, "cy": 0, "I": 0.01}}',
    "digits400.json": '{"2": {"m": 1, "cx": 0, "cy": 0, "I": ' + "9" * 400 + '}}',
    "heavy.json": '{"2": {"m": 1e62, "cx": 0, "cy": 0, "I": 1}}',
    "m5001.json": lambda: json.dumps({"format": "linkage/1", "name": "m", "x": 0}).replace('"x": 0', '"x": ' + "9" * 5001),
    "m5001.toml": lambda: _lib("fourbar").replace("alpha1 = 0.0", "alpha1 = " + "9" * 5001, 1),
    "fast5.toml": _fast_fivebar,
}


def _setup(folder):
    for name, data in FILES.items():
        data = data() if callable(data) else data
        (folder / name).write_bytes(data if isinstance(data, bytes) else data.encode())
    return {p.name: p.read_bytes() for p in folder.iterdir()}


def run(folder, *args, timeout=120):
    return subprocess.run([sys.executable, "-m", "sim", *args], capture_output=True, text=True, cwd=folder,
                          timeout=timeout)


CASES = [
    ("--input-range -inf:inf", ["analyze", "fourbar", "--input-range", "-inf:inf"],
     r"--input-range='-inf' is not a number"),
    ("a 5001-digit integer in a JSON mechanism", ["check", "m5001.json"], r"m5001\.json: an integer of more than 4300"),
    ("a 5001-digit integer in a TOML mechanism", ["check", "m5001.toml"], r"m5001\.toml: an integer of more than 4300"),
    ("a 5001-digit integer in --inertia", ["forces", "fourbar", "--inertia", "digits5001.json"],
     r"--inertia 2: inertia m=inf must be a finite number of magnitude <= 1e\+12"),
    ("a 400-digit integer in --inertia (OverflowError)", ["dynamics", "fourbar", "--motor", "2,150rpm", "--inertia",
                                                          "digits400.json"], r"--inertia 2: inertia I=inf must be a finite"),
    ("a mass of 1e62 kg", ["forces", "fourbar", "--inertia", "heavy.json"], r"inertia m=1e\+62 must be a finite number"),
    ("deeply nested --inertia (RecursionError)", ["forces", "fourbar", "--inertia", "deep.json"],
     r"--inertia deep\.json: nested too deeply"),
    ("render --fps tiny", ["render", "fourbar", "--out", "v.mp4", "--fps", "0.001"],
     r"--fps 0\.001 must be a number in \[1, 240\]"),
    ("synthesize --out onto the target file", ["synthesize", "path", "t.toml", "--out", "t.toml"],
     r"--out t\.toml is an input of this command and would be overwritten \(the target file\)"),
    ("synthesize --out into the library", ["synthesize", "path", "t.csv", "--out", "LIBRARY/new.toml"],
     r"is in the shipped mechanism library"),
    ("synthesize --plot onto the target file", ["synthesize", "path", "t.csv", "--plot", "t.csv"],
     r"--plot t\.csv is an input of this command"),
    ("dynamics --csv onto the motor table", ["dynamics", "fourbar", "--motor-table", "table.csv", "--csv", "table.csv"],
     r"--csv table\.csv is an input of this command and would be overwritten \(--motor-table\)"),
    ("run --out-dir the library", ["run", "fourbar", "--no-video", "--out-dir", "LIBRARY"],
     r"--out-dir .*: that is the shipped mechanism library"),
    ("a motor table field over the csv limit", ["dynamics", "fourbar", "--motor-table", "wide.csv"],
     r"--motor-table wide\.csv: line 2: not a CSV row \(field larger than field limit"),
    ("a target field over the csv limit", ["synthesize", "path", "wide_targets.csv"],
     r"wide_targets\.csv: line 2: not a CSV row"),
    ("a motor table not UTF-8", ["dynamics", "fourbar", "--motor-table", "latin1.csv"],
     r"--motor-table latin1\.csv: not UTF-8 text \(byte 0xb0"),
    ("a motor table separated by ';'", ["dynamics", "fourbar", "--motor-table", "semi.csv"],
     r"semi\.csv: the columns are separated by semicolons; separate them by commas"),
    ("targets separated by ';'", ["synthesize", "path", "semi_targets.csv"],
     r"semi_targets\.csv: the columns are separated by semicolons"),
    ("a newline in an output name", ["analyze", "fourbar", "--csv", "a\nlinkage: error: forged/x.csv"],
     r"a\\nlinkage: error: forged does not exist"),
    ("a failing run writes no file", ["run", "fourbar", "fast5.toml", "--no-video", "--out-dir", ".",
                                      "--timestep", "0.05"], r"the time step 0\.05 s is too large"),
]


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_one_line_exit_2_nothing_written(tmp_path, case):
    from analytic.registry import LIBRARY
    _, args, pattern = case
    args = [a.replace("LIBRARY", str(LIBRARY)) for a in args]
    library = sorted(p.name for p in LIBRARY.iterdir())
    before = _setup(tmp_path)
    r = run(tmp_path, *args)
    assert r.returncode == 2, (r.returncode, r.stdout[-300:], r.stderr[-500:])
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("linkage: error: ") and "Traceback" not in r.stderr, r.stderr
    assert re.search(pattern, lines[0]), lines[0]
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before     # nothing new, nothing changed
    assert sorted(p.name for p in LIBRARY.iterdir()) == library


def test_a_failing_run_into_a_new_folder_leaves_no_folder(tmp_path):
    _setup(tmp_path)
    r = run(tmp_path, "run", "fourbar", "fast5.toml", "--no-video", "--out-dir", "o", "--timestep", "0.05")
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("args", [["analyze", "fourbar", "--input-range", "-1:1"],
                                  ["analyze", "fourbar", "--set", "l1=0.2", "--set", "l3=0.1", "--input-range",
                                   "-.9:-.8"]])
def test_values_starting_with_a_minus_reach_the_option(tmp_path, args):
    r = run(tmp_path, *args)
    assert "expected one argument" not in r.stderr and "Traceback" not in r.stderr
    assert r.returncode in (0, 2), r.stderr
    if r.returncode == 2:
        assert re.fullmatch(r"linkage: error: .*input range.*\n", r.stderr), r.stderr


def test_an_interrupted_video_is_killed_before_ffmpeg_reads_a_cut_frame(tmp_path):
    """A frame cut short by Ctrl-C: the writer is aborted; ffmpeg must be killed before its input closes,
    else it reads the partial frame and prints its complaint on the user's terminal (issue 32)."""
    code = (
        "import sys\n"
        "from sim.output.render import _Writer\n"
        f"w = _Writer({str(tmp_path / 'v.gif')!r}, 30.0, (640, 480))\n"
        "p = w._gen.gi_frame.f_locals['p']\n"
        "p.stdin.write(b'\\0' * 131072)\n"           # part of a 640x480x3 frame, as a write cut by a signal
        "p.stdin.flush()\n"
        "w.abort()\n"
        "print(p.returncode)\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert r.stderr == "", r.stderr                      # nothing from ffmpeg on the terminal
    assert int(r.stdout.strip()) != 0                    # ffmpeg was killed, not let finish


def test_an_integer_past_float_range_is_refused_by_the_inertia_itself():
    """OverflowError from float(10**400) inside the check: a ParameterError naming the value, cut short."""
    from analytic import ParameterError
    from analytic.mass import Inertia
    with pytest.raises(ParameterError, match=r"inertia I=1000000000.*\.\.\. must be a finite number"):
        Inertia(m=1.0, cx=0.0, cy=0.0, I=10 ** 400)


def test_ctrl_c_while_a_compiled_module_initialises_is_one_line(monkeypatch, capsys):
    """pybind11 turns a Ctrl-C during ``import mujoco`` into ImportError("initialization failed") caused by
    the KeyboardInterrupt: it is an interrupt (exit 130, one line); another ImportError is not hidden."""
    from sim.front import cli
    from sim.front.cli import listing

    def cut(args):
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as exc:
            raise ImportError("initialization failed") from exc
    monkeypatch.setattr(listing, "run", cut)
    assert cli.main(["list"]) == 130
    assert capsys.readouterr().err == "linkage: interrupted\n"

    def broken(args):
        raise ImportError("no module named nothing")
    monkeypatch.setattr(listing, "run", broken)
    with pytest.raises(ImportError):
        cli.main(["list"])


@pytest.mark.parametrize("option, pattern", [
    (["--popsize", "4"], r"--popsize 4 must be an integer in 5\.\.10,000"),
    (["--seed", "-1"], r"--seed -1 must be an integer in 0\.\."),
    (["--budget", "inf"], r"--budget inf must be a number of seconds in \(0, 604800\]"),
    (["--restarts", "100000000"], r"--restarts 100000000 must be an integer in 1\.\.10,000"),
    (["--designs", "1000"], r"--designs 1000 must be an integer in 1\.\.100"),
])
def test_synthesis_options_that_would_crash_or_never_end_are_refused(tmp_path, option, pattern):
    (tmp_path / "t.csv").write_text(TARGETS)
    r = run(tmp_path, "synthesize", "path", "t.csv", *option, timeout=60)
    assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr[-500:]
    assert re.fullmatch(r"linkage: error: " + pattern + r".*\n", r.stderr), r.stderr


@pytest.mark.parametrize("old, new, pattern", [("P[12.5, 21.6506]", "P[12.5, 1e999]", r"pose\.J1\[1\] = inf"),
                                               ("P[80.0, 0.0]", "P[-1e999, 0.0]", r"pose\.J3\[0\] = -inf")])
def test_an_import_refuses_a_coordinate_that_is_not_finite(tmp_path, old, new, pattern):
    from pathlib import Path
    src = (Path(__file__).parent / "peers_examples" / "fourbar.pyslvs").read_text()
    assert old in src
    (tmp_path / "m.pyslvs").write_text(src.replace(old, new, 1))
    r = run(tmp_path, "import", "m.pyslvs", "--out", "m.toml")
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert re.search(pattern, r.stderr), r.stderr
    assert not (tmp_path / "m.toml").exists()
