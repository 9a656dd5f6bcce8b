"""Every class of bad input a new user produces ends in one clear line and exit code 2 (or a correct
result), never a traceback, a hang, exit 0 with nonsense, or a lost file.

Each case runs the real command in a folder holding files the user already had; afterwards those files
must be byte-identical and no MUJOCO_LOG.TXT may appear.
"""

import json
import os
import re
import signal
import subprocess
import sys
import time

import pytest

PREEXISTING = {"in.csv": b"t,x\n0,1\n", "inertia.json": json.dumps({"2": {"m": 1, "cx": 0, "cy": 0, "I": 0.01}}).encode(),
               "notes.txt": b"my notes\n", "mech.toml": None}


def _setup(folder):
    from analytic.registry import LIBRARY
    for name, data in PREEXISTING.items():
        (folder / name).write_bytes(data if data is not None else (LIBRARY / "fourbar.toml").read_bytes())
    (folder / "afile").write_bytes(b"not a folder")
    return {p.name: p.read_bytes() for p in folder.iterdir()}


def run(folder, *args, timeout=120):
    return subprocess.run([sys.executable, "-m", "sim", *args], capture_output=True, text=True, cwd=folder,
                          timeout=timeout)


CASES = [
    # (class, args, pattern in the one line)
    ("deg on a length", ["analyze", "fourbar", "--set", "l1=5deg"], r"l1=.*is a length, not an angle"),
    ("huge speed", ["analyze", "fourbar", "--set", "omega1=1e308"], r"omega1=.*out of range"),
    ("huge offset", ["analyze", "fourbar", "--set", "ex=1e308"], r"ex=.*out of range"),
    ("huge acceleration", ["analyze", "fourbar", "--set", "alpha1=1e308"], r"alpha1=.*out of range"),
    ("huge phase", ["analyze", "fourbar", "--set", "phi1_0=1e308"], r"phi1_0=.*out of range"),
    ("huge revolutions", ["analyze", "fourbar", "--revolutions", "1e308"], r"revolutions=.*must be a number in"),
    ("huge input range", ["analyze", "fourbar", "--input-range", "0:1e308"], r"input-range.*out of range"),
    ("inverted range", ["analyze", "fourbar", "--set", "l1=0.2", "--set", "l3=0.1", "--input-range", "100deg:45deg"],
     r"--input-range 100deg:45deg: the end must exceed the start"),
    ("inverted range, simulate", ["compare", "fourbar", "--set", "l1=0.2", "--set", "l3=0.1", "--input-range",
                                  "100deg:45deg"], r"--input-range 100deg:45deg: the end must exceed the start"),
    ("too many samples", ["analyze", "fourbar", "--samples", "1000000000"], r"samples=1000000000 must be an integer in"),
    ("too many revolutions to simulate", ["simulate", "fourbar", "--revolutions", "1e9"], r"revolutions=.*must be a number in"),
    ("sweep samples", ["sweep", "fivebar", "--vary", "l2=0.05,0.06", "--samples", "100000000"], r"samples=100000000 must be"),
    ("a huge sweep without --yes", ["sweep", "fivebar", "--vary", "l2=0.04:0.06:5000", "--vary", "l4=0.06:0.08:2000"],
     r"10,000,000 combinations .*add --yes"),
    ("render fps", ["render", "fourbar", "--out", "v.mp4", "--fps", "1e6"], r"--fps .* must be a number in"),
    ("repeated --set", ["analyze", "fourbar", "--set", "l1=0.1", "--set", "l1=0.12"], r"--set l1 is given twice"),
    ("repeated --vary", ["sweep", "fourbar", "--vary", "l1=0.1,0.12", "--vary", "l1=0.13"], r"--vary l1 is given twice"),
    ("--show -1", ["sweep", "fourbar", "--vary", "l1=0.1,0.12", "--show", "-1"], r"--show -1 must be >= 0"),
    ("output is a folder", ["analyze", "fourbar", "--csv", "."], r"is a folder; give a file name"),
    ("output folder missing", ["analyze", "fourbar", "--csv", "nowhere/x.csv"], r"folder nowhere does not exist"),
    ("output not writable", ["render", "fourbar", "--out", "/proc/v.mp4"], r"cannot write in folder /proc"),
    ("out-dir is a file", ["run", "fourbar", "--out-dir", "afile", "--no-video"], r"--out-dir afile is a file"),
    ("out-dir cannot be made", ["run", "fourbar", "--out-dir", "/proc/x", "--no-video"], r"--out-dir /proc/x"),
    ("an input overwritten", ["simulate", "fourbar", "--inertia", "in.csv", "--csv", "in.csv"],
     r"in\.csv is an input of this command and would be overwritten"),
    ("a mechanism file overwritten", ["export", "mech.toml", "--toml", "mech.toml"],
     r"mech\.toml is an input of this command and would be overwritten"),
    ("unknown mechanism", ["analyze", "fourbaar"], r"'fourbaar' is not a mechanism: use one of fourbar"),
    ("missing file", ["analyze", "mine.toml"], r"mine\.toml: no such file"),
    ("unknown parameter", ["analyze", "slider_crank", "--set", "l1=0.1"], r"'l1' is not a parameter of slider_crank"),
    ("unsupported output type", ["plot", "fourbar", "--out", "x.bmp"], r"unsupported output type '\.bmp'"),
    ("no extension", ["analyze", "fourbar", "--csv", "x"], r"unsupported output type '\(no extension\)'"),
    ("a start at rest on a change point", ["simulate", "fourbar", "--set", "l1=0.25", "--set", "omega1=0"],
     r"starts at a change point \(phi1=0\.00deg"),
    ("a rocking range past a dead point", ["compare", "fourbar", "--set", "l1=0.2", "--set", "l3=0.1",
                                           "--input-range", "40deg:100deg"], r"cannot be assembled at phi1=40\.00deg"),
    ("a timestep far too large", ["compare", "fivebar", "--timestep", "0.05", "--set", "omega2=50", "--set", "omega4=50"],
     r"the time step 0\.05 s is too large for this design"),
    ("a first-order integrator at the chosen step", ["compare", "fivebar", "--integrator", "implicitfast"],
     r"the implicitfast integrator cannot hold the loops .* use --integrator rk4"),
    ("a negative cutting force", ["compare", "sixbar", "--cutting-force", "-5"], r"--cutting-force -5 must be >= 0"),
    ("a bad gravity", ["compare", "fourbar", "--gravity", "1"], r"--gravity '1' is not two numbers"),
    ("a bad inertia entry", ["compare", "fourbar", "--inertia", "notes.txt"], r"--inertia notes\.txt: cannot read it as JSON"),
]


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_bad_input_is_one_line_exit_2_and_loses_nothing(tmp_path, case):
    _, args, pattern = case
    before = _setup(tmp_path)
    r = run(tmp_path, *args)
    assert r.returncode == 2, (r.returncode, r.stdout[-500:], r.stderr[-500:])
    assert "Traceback" not in r.stderr and "WARNING" not in r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("linkage: error: "), r.stderr
    assert re.search(pattern, lines[0]), lines[0]
    after = {p.name: p.read_bytes() for p in tmp_path.iterdir() if p.name in before}
    assert after == before                                   # the user's files are untouched
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()
    assert not any(p.name.startswith(".") for p in tmp_path.iterdir())   # no temporary file left behind


@pytest.mark.parametrize("args", [
    ["analyze", "fourbar", "--set", "l1=0.2", "--set", "l3=0.1", "--input-range", "-104deg:-42deg"],
    ["compare", "fourbar", "--force", "-10,0", "--revolutions", "0.25"],
    ["compare", "fourbar", "--gravity", "-9.81,0", "--revolutions", "0.25"],
    ["synthesize", "two-position", "--E1", "-5,3", "--E2", "10,35"],
])
def test_negative_values_work_as_written(tmp_path, args):
    r = run(tmp_path, *args)
    assert "expected one argument" not in r.stderr and "Traceback" not in r.stderr
    assert r.returncode in (0, 2), r.stderr
    if r.returncode == 2:                                        # a real error about the values, not the parser
        assert "linkage: error:" in r.stderr


def test_a_failing_run_creates_no_output_folder(tmp_path):
    r = run(tmp_path, "run", "fourbar", "--set", "l1=0.25", "--set", "omega1=0", "--out-dir", "out", "--no-video")
    assert r.returncode == 2 and not (tmp_path / "out").exists()


def test_the_readme_rocking_example_is_accepted_by_analyze_and_compare(tmp_path):
    for cmd in ("analyze", "compare"):
        r = run(tmp_path, cmd, "fourbar", "--set", "l1=0.2", "--set", "l3=0.1", "--input-range", "42deg:104deg")
        assert r.returncode == 0, (cmd, r.stderr)


def test_a_gif_says_the_rate_it_stores(tmp_path):
    r = run(tmp_path, "render", "fourbar", "--out", "v.gif", "--fps", "200", "--size", "64x48", "--revolutions", "0.1")
    assert r.returncode == 0, r.stderr
    assert "at 50 fps" in r.stdout                               # GIF delays are whole centiseconds


def test_output_piped_into_head_ends_quietly(tmp_path):
    r = subprocess.run(f"{sys.executable} -m sim analyze fivebar --json | head -1", shell=True, capture_output=True,
                       text=True, cwd=tmp_path)
    assert r.stdout.strip() == "{" and "Traceback" not in r.stderr and "BrokenPipe" not in r.stderr


def _wait_until_simulating(p) -> None:
    """Block until the process is loading MuJoCo (it is inside the command, about to simulate): the event a
    signal test waits on, however busy the machine (a fixed delay could land in Python's start-up). The
    signal may then come while MuJoCo's compiled module initialises (ImportError caused by the interrupt)
    or later, while it simulates: one line either way."""
    maps = f"/proc/{p.pid}/maps"
    if not os.path.exists(maps):
        pytest.skip("needs /proc to see the process load MuJoCo")
    while p.poll() is None:
        with open(maps) as f:
            if "mujoco" in f.read():
                return
        time.sleep(0.02)                                   # polling the event, not a delay it depends on
    pytest.fail(f"the process ended before simulating: {p.stderr.read()}")


def test_ctrl_c_ends_in_one_line(tmp_path):
    p = subprocess.Popen([sys.executable, "-m", "sim", "compare", "fivebar", "--revolutions", "200"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path)
    _wait_until_simulating(p)
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=300)                  # a guard against a hang, not a measure of speed
    assert p.returncode == 130 and err.strip().splitlines() == ["linkage: interrupted"], err


def test_csv_carries_its_units_and_compare_json_its_context(tmp_path):
    r = run(tmp_path, "analyze", "fivebar", "--csv", "a.csv")
    assert r.returncode == 0
    units = json.loads((tmp_path / "a.csv.units.json").read_text())["units"]
    assert units["S"] == "m" and units["theta3"] == "rad" and units["ddS"] == "m/s^2" and units["t"] == "s"
    r = run(tmp_path, "compare", "sixbar", "--cutting-force", "100", "--gravity", "0,-9.81", "--json")
    out = json.loads(r.stdout)
    assert out["parameters"]["l6"] == 0.38 and out["loads"]["gravity"] == [0.0, -9.81]
    # the ram's cutting (slow) stroke runs towards -x with the crank turning counter-clockwise: it is resisted
    assert out["loads"]["slow_stroke_only"] is True and out["loads"]["force"][0] == pytest.approx(100.0)


def test_help_starts_without_mujoco_or_matplotlib():
    code = ("import sys, runpy; sys.argv = ['linkage', 'analyze', 'fourbar'];\n"
            "from sim.front.cli import main; main();\n"
            "assert 'mujoco' not in sys.modules and 'matplotlib' not in sys.modules, "
            "[m for m in ('mujoco', 'matplotlib') if m in sys.modules]")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       env={**os.environ, "LINKAGE_JIT": "0"})
    assert r.returncode == 0, r.stderr


# ------------------------------------------------------------------ issue 20: one case per input class
def _lib(name):
    from analytic.registry import LIBRARY
    return (LIBRARY / f"{name}.toml").read_text()


def _fourbar(old, new):
    text = _lib("fourbar")
    assert old in text
    return text.replace(old, new, 1)


_REVERSED = "\n".join(f'p{i} = "p{i + 1}"' for i in range(1500)) + "\np1500 = 1\n"
_TINY = {"l1 = 0.10": "l1 = 1e-7", "l2 = 0.30": "l2 = 3e-7", "l3 = 0.25": "l3 = 2.5e-7", "l4 = 0.30": "l4 = 3e-7",
         "ex = 0.15": "ex = 1.5e-7", "ey = 0.10": "ey = 1e-7"}


def _tiny():
    text = _lib("fourbar")
    for a, b in _TINY.items():
        text = text.replace(a, b, 1)
    return text


FILE_CASES = [
    # (class, file name, contents (str or bytes), command and options after the file, pattern in the one line)
    ("only format", "m.toml", 'format = "linkage/1"\n', ["check"], r"inputs: none given"),
    ("output a list", "m.toml", lambda: _fourbar('output = "E"', 'output = ["C"]'), ["check"],
     r"output: \['C'\] must be one point name"),
    ("units a table", "m.toml", lambda: _fourbar('output = "E"', 'output = "E"\nunits = {a = 1}'), ["check"],
     r"units: unknown unit \{'a': 1\}"),
    ("an unknown name in a ground coordinate", "m.toml", lambda: _fourbar('D = ["l4", 0]', 'D = ["l4", "zz + 1"]'),
     ["check"], r"ground\.D: 'zz \+ 1' uses 'zz'|ground\.D: .*zz"),
    ("an angle in a ground coordinate", "m.toml", lambda: _fourbar('D = ["l4", 0]', 'D = ["l4", "30deg"]'),
     ["check"], r"ground\.D: '30deg' is an angle where a length is expected"),
    ("an integer beyond float range", "m.toml", lambda: _fourbar("alpha1 = 0.0", "alpha1 = " + "9" * 400), ["check"],
     r"parameters\.alpha1: 9{20,}.* is out of range"),
    ("deep nesting in TOML", "m.toml", 'format = "linkage/1"\nx = ' + "[" * 5000 + "]" * 5000 + "\n", ["check"],
     r"nested too deeply"),
    ("deep nesting in JSON", "m.json", '{"format": "linkage/1", "x": ' + "[" * 100000 + "]" * 100000 + "}", ["check"],
     r"nested too deeply"),
    ("deep nesting in an expression", "m.toml", lambda: _fourbar("alpha1 = 0.0", 'alpha1 = "' + "-" * 300 + '1"'),
     ["check"], r"parameters\.alpha1: .* nested too deeply"),
    ("a long run of digits (was cubic backtracking)", "m.toml",
     lambda: _fourbar("alpha1 = 0.0", 'alpha1 = "' + "1" * 380 + 'x"'), ["check"],
     r"parameters\.alpha1: .* is not a number, a parameter name or an arithmetic expression"),
    ("1,500 parameters in reverse order", "m.toml", lambda: _fourbar("[parameters]", "[parameters]\n" + _REVERSED),
     ["check"], r"parameters: 1511 entries; a mechanism file holds at most 500"),
    ("strings in [inertia]", "m.toml", lambda: _lib("fourbar") + '\n[inertia]\n2 = {m = "a", I = "b"}\n', ["check"],
     r"inertia\.2\.m: 'a' must be a finite number"),
    ("phi1_0 = 1.8e308", "m.toml", lambda: _fourbar("phi1_0 = 0.0", "phi1_0 = 1.8e308"), ["check"],
     r"parameters\.phi1_0: must be finite"),
    ("phi1_0 = 1e300 as text", "m.toml", lambda: _fourbar("phi1_0 = 0.0", 'phi1_0 = "1e300"'), ["check"],
     r"parameters\.phi1_0: 1e\+300 is out of range"),
    ("JSON duplicate keys", "m.json", '{"format": "linkage/1", "format": "linkage/1"}', ["check"],
     r"field 'format' is given twice"),
    ("a newline in a name", "m.json", '{"format": "linkage/1", "name": "a\\nlinkage: error: forged"}', ["check"],
     r"name: 'a\\nlinkage: error: forged' is not a name"),
    ("a design that assembles nowhere", "m.toml", lambda: _fourbar("l4 = 0.30", "l4 = 3.0"), ["check"],
     r"assembles at no value of phi1; change the lengths"),
    ("1/30deg", "m.toml", lambda: _fourbar("phi1_0 = 0.0", 'phi1_0 = "1/30deg"'), ["check"],
     r"parameters\.phi1_0: '1/30deg': a 'deg' value divides"),
    ("not UTF-8", "m.toml", lambda: _lib("fourbar").encode() + b"# caf\xe9\n", ["check"], r"not UTF-8 text \(byte 0xe9"),
    ("not UTF-8, opened in the app", "m.toml", lambda: _lib("fourbar").encode() + b"# caf\xe9\n",
     ["app", "--port", "0", "--no-browser"], r"not UTF-8 text \(byte 0xe9"),
    ("tiny lengths", "m.toml", _tiny, ["compare"], r"spans 3e-07 m .* needs at least 0\.001 m"),
    ("metres typed into a mm file", "m.toml", lambda: _fourbar('output = "E"', 'output = "E"\nunits = "mm"'),
     ["compare"], r"spans 0\.0003 m \(0\.3 mm\).*were metres typed into a mm file"),
    ("slider_crank with units = mm", "m.toml", lambda: _lib("slider_crank").replace(
        'format = "linkage/1"', 'format = "linkage/1"\nunits = "mm"', 1), ["render", "--out", "v.mp4"],
     r"were metres typed into a mm file"),
]


@pytest.mark.parametrize("case", FILE_CASES, ids=[c[0] for c in FILE_CASES])
def test_a_bad_file_is_one_line_exit_2(tmp_path, case):
    _, fname, contents, args, pattern = case
    contents = contents() if callable(contents) else contents
    path = tmp_path / fname
    path.write_bytes(contents if isinstance(contents, bytes) else contents.encode())
    before = path.read_bytes()
    r = run(tmp_path, args[0], fname, *args[1:], timeout=60)
    assert r.returncode == 2, (r.returncode, r.stdout[-300:], r.stderr[-500:])
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("linkage: error: ") and "Traceback" not in r.stderr, r.stderr
    assert re.search(pattern, lines[0]), lines[0]
    assert len(lines[0]) < 400                                     # a long value is cut, not echoed whole
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == [fname]   # nothing written, no temporary left


@pytest.mark.parametrize("special", ["/dev/zero", "/dev/urandom", "fifo"])
def test_a_device_or_pipe_is_refused_before_reading(tmp_path, special):
    if special == "fifo":
        os.mkfifo(tmp_path / "fifo")
    r = run(tmp_path, "check", special, timeout=30)                # a read would block or fill memory
    assert r.returncode == 2 and re.fullmatch(r"linkage: error: \S+ is not a regular file .*\n", r.stderr), r.stderr


@pytest.mark.parametrize("args, pattern", [
    (["compare", "fourbar", "--set", "ex=0", "--set", "ey=0", "--revolutions", "0.25"], None),
    (["synthesize", "two-position", "--E1", "30deg,31"], r"--E1='30deg': --E1 is a length, not an angle"),
    (["synthesize", "two-position", "--E1", "0.030,0.031", "--E2", "0.010,0.035"],
     r"--E1 and --E2 are 0\.0204 mm apart but --A and --D 36 mm: give every coordinate in mm"),
    (["export", "fourbar", "--toml", "LIBRARY/fourbar.toml"], r"is in the shipped mechanism library"),
])
def test_cli_classes_of_issue_20(tmp_path, args, pattern):
    from analytic.registry import LIBRARY
    args = [a.replace("LIBRARY", str(LIBRARY)) for a in args]
    r = run(tmp_path, *args, timeout=120)
    assert "Traceback" not in r.stderr and "Warning" not in r.stderr, r.stderr
    if pattern is None:                                            # a coupler point on its pin simulates
        assert r.returncode == 0 and "PASSED" in r.stdout, r.stdout[-500:]
    else:
        assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1, r.stderr
        assert re.search(pattern, r.stderr), r.stderr


def test_a_slider_scan_in_a_mm_file_covers_four_sizes_in_metres():
    import analytic
    from analytic.applications import figures
    mech = analytic.load(str(__import__("pathlib").Path(__file__).parent / "mechanisms" / "slider_driven.toml"))
    lo, hi = figures._first_range(mech)
    # s0 = 60 mm, size 100 mm (the rod): the scan is s0 +- 4 x 0.1 m, in metres like the slider's q
    assert lo == pytest.approx(0.06 - 0.4, abs=1e-12) and hi == pytest.approx(0.06 + 0.4, abs=1e-12)


@pytest.mark.parametrize("sig, code, word", [(signal.SIGINT, 130, "interrupted"), (signal.SIGTERM, 143, "terminated")])
def test_a_signal_during_render_ends_in_one_line_and_leaves_no_file(tmp_path, sig, code, word):
    p = subprocess.Popen([sys.executable, "-m", "sim", "render", "fourbar", "--out", "v.mp4", "--revolutions", "60"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tmp_path)
    while p.poll() is None and not any(tmp_path.iterdir()):   # the event: the video's temporary exists
        time.sleep(0.02)
    assert p.poll() is None, p.stderr.read()                   # still rendering when the signal comes
    p.send_signal(sig)
    _, err = p.communicate(timeout=300)                         # a guard against a hang, not a measure
    assert p.returncode == code and err.strip().splitlines() == [f"linkage: {word}"], err
    assert list(tmp_path.iterdir()) == []


def test_output_piped_into_head_n_0_ends_quietly(tmp_path):
    r = subprocess.run(f"{sys.executable} -m sim analyze fivebar --json | head -n 0", shell=True, capture_output=True,
                       text=True, cwd=tmp_path, timeout=120)
    assert r.stderr == "", r.stderr


def test_a_failed_compare_at_a_given_time_step_says_why(tmp_path):
    r = run(tmp_path, "compare", "fourbar", "--timestep", "0.05")
    assert r.returncode == 1 and "FAILED" in r.stdout and "Traceback" not in r.stderr
    assert re.fullmatch(r"linkage: the time step 0\.05 s given by --timestep is above the \S+ s this design needs; "
                        r"drop --timestep\n", r.stderr), r.stderr
