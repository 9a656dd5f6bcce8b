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


# ------------------------------------------------------------------------------------------------ item 7
def _loads_text(magnitude_line):
    """tests/mechanisms/fourbar_loads.toml with its brake's magnitude replaced by ``magnitude_line``."""
    from pathlib import Path
    text = (Path(__file__).parent / "mechanisms" / "fourbar_loads.toml").read_text()
    old = 'magnitude = "-0.5*cos(phi1)"'
    assert old in text
    return text.replace(old, magnitude_line)


TABLE = "phi,tau\n0,1\n180,2\n360,1\n"


def test_an_output_onto_a_load_table_named_in_the_file_is_refused(tmp_path):
    """Fault: ``forces m.toml --csv tab.csv`` where m.toml's load reads tab.csv overwrote the table with the
    forces (guard_outputs knew only the command line's inputs)."""
    (tmp_path / "tab.csv").write_text(TABLE)
    (tmp_path / "m.toml").write_text(_loads_text('table = "tab.csv"'))
    before = _files(tmp_path)
    for args in (["forces", "m.toml", "--csv", "tab.csv"], ["analyze", "m.toml", "--csv", "./tab.csv"],
                 ["dynamics", "m.toml", "--motor", "5,150rpm", "--csv", "tab.csv"]):
        r = cli_runner.run(*args, cwd=tmp_path)
        _one_line(r, r"--csv \S*tab\.csv is an input of this command and would be overwritten \(a load table of "
                     r"m\.toml\)")
        assert _files(tmp_path) == before


def test_run_into_the_folder_of_a_load_table_of_its_name_is_refused(tmp_path):
    (tmp_path / "tab.csv").write_text(TABLE)
    (tmp_path / "m.toml").write_text(_loads_text('table = "tab.csv"').replace('name = "fourbar_loads"',
                                                                               'name = "tab"'))
    before = _files(tmp_path)
    r = cli_runner.run("run", "m.toml", "--no-video", "--out-dir", ".", cwd=tmp_path)
    _one_line(r, r"--out-dir \.: tab\.csv is a load table this run reads")
    assert _files(tmp_path) == before


def _fifo(folder):
    os.mkfifo(folder / "tab.csv")


TABLES = [
    ("a fifo", _fifo, r"tab\.csv is not a regular file \(a pipe or a device\)"),
    ("/dev/zero", None, r"/dev/zero is not a regular file"),
    ("not UTF-8", lambda f: (f / "tab.csv").write_bytes(b"phi,tau\n0,1\xb0\n180,2\n360,1\n"),
     r"tab\.csv is not UTF-8 text \(byte 0xb0 at offset 11\); save it as UTF-8"),
    ("a 200,000-character field", lambda f: (f / "tab.csv").write_text("phi,tau\n0," + "1" * 200_000 + "\n180,2\n"),
     r"tab\.csv line 2: not a CSV row \(field larger than field limit"),
]


@pytest.mark.parametrize("case", TABLES, ids=[c[0] for c in TABLES])
def test_a_load_table_that_cannot_be_read_is_one_line(tmp_path, case):
    """Faults: a fifo blocked forever and /dev/zero read forever (open() on anything); a byte not UTF-8
    (UnicodeDecodeError) and a field over the csv module's limit (_csv.Error) ended in tracebacks."""
    _, make, pattern = case
    name = "/dev/zero" if make is None else "tab.csv"
    if make is not None:
        make(tmp_path)
    (tmp_path / "m.toml").write_text(_loads_text(f'table = "{name}"'))
    r = subprocess.run([sys.executable, "-m", "sim", "forces", "m.toml"], capture_output=True, text=True,
                       cwd=tmp_path, timeout=60)      # a process: a guard against the hang the fifo was
    _one_line(r, r"m\.toml: loads\[3\] \(brake\)\.table: " + pattern)


BAD_SCHEDULERS = ["junk", "tcp://", "http://x:99", ":::", "tcp://h:99999", "tcp://h:0", "[::1]:x", "inproc://x"]


@pytest.mark.parametrize("address", BAD_SCHEDULERS)
def test_every_bad_scheduler_address_is_one_line(tmp_path, address):
    """Fault: Dask's parser raised ValueError (missing port number, unknown address scheme, ipv6 needs
    brackets) past the OSError the connection caught: a traceback."""
    r = cli_runner.run("tolerance", "fourbar", "--tol", "l1=±0.001", "--samples", "4", "--scheduler", address,
                       cwd=tmp_path)
    _one_line(r, r"--scheduler .* is not a Dask scheduler address; give tcp://HOST:PORT")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("command", [["dynamics", "--motor", "5,150rpm"], ["compare"], ["forces"]])
def test_a_load_expression_dividing_by_zero_is_one_line_in_every_command(tmp_path, command):
    """Fault: 1/sin(phi1) (infinite at phi1 = 0) raised a bare ValueError from the MuJoCo model's loads
    (sim.model.loads) and the reduced equation: a traceback in dynamics, compare, simulate; forces alone
    named the load."""
    (tmp_path / "m.toml").write_text(_loads_text('magnitude = "1/sin(phi1)"'))
    r = cli_runner.run(command[0], "m.toml", *command[1:], cwd=tmp_path)
    _one_line(r, r"load brake: '1/sin\(phi1\)' is not finite at every sample")


def _pyslvs(**edits):
    from pathlib import Path
    text = (Path(__file__).parent / "peers_examples" / "fourbar.pyslvs").read_text()
    for old, new in edits.items():
        assert old in text
        text = text.replace(old, new)
    return text


PYSLVS = [
    ("an input .inf", {"input:\n- - 0\n": "input:\n- - .inf\n"}, r"input \[inf, 1\] is not a pair of joint numbers"),
    ("an input 1.0e+300", {"input:\n- - 0\n": "input:\n- - 1.0e+300\n"},
     r"input \[1e\+300, 1\] is not a pair of joint numbers"),
    ("an input .nan", {"  - 1\nlinks": "  - .nan\nlinks"}, r"input \[0, nan\] is not a pair"),
    ("a slide angle 1e300", {"J[R, color[Green], P[80.0": "J[P, A[1e300], color[Green], P[80.0"},
     r"joint J3: A\[1e300\] is out of range; give the slide's angle in degrees"),
    ("a pose 1e300", {"P[0.0, 0.0]": "P[1e300, 0.0]"}, r"pose\.J0\[0\] = 1e\+300 is not a finite number of magnitude <= 1e\+12"),
]


@pytest.mark.parametrize("case", PYSLVS, ids=[c[0] for c in PYSLVS])
def test_inf_and_1e300_in_a_pyslvs_project_are_one_line(tmp_path, case):
    """Fault: an input pair holding .inf raised OverflowError (int(inf)) past the ValueError caught."""
    _, edits, pattern = case
    (tmp_path / "p.pyslvs").write_text(_pyslvs(**edits))
    r = cli_runner.run("import", "p.pyslvs", "--out", "p.toml", cwd=tmp_path)
    _one_line(r, r"p\.pyslvs: " + pattern)
    assert not (tmp_path / "p.toml").exists()


def test_a_yaml_alias_bomb_in_the_inputs_is_refused_at_once(tmp_path):
    """Fault: ``input: *a8`` (9^8 = 43 million strings by reference, 1 kB of YAML) was expanded by the
    message's repr: 48 s and 3 GB before its one line."""
    lines = ['a0: &a0 ["lol","lol","lol","lol","lol","lol","lol","lol","lol"]']
    lines += [f"a{i}: &a{i} [" + ",".join([f"*a{i - 1}"] * 9) + "]" for i in range(1, 9)]
    text = _pyslvs(**{"input:\n- - 0\n  - 1\n": ""}) + "\n".join(lines) + "\ninput: *a8\n"
    (tmp_path / "bomb.pyslvs").write_text(text)
    r = cli_runner.run("check", "bomb.pyslvs", cwd=tmp_path)
    _one_line(r, r"bomb\.pyslvs: input list of 9 is not a pair of joint numbers")
    assert len(r.stderr) < 300


EXPRESSION = ("M[J[R, P[0.0, 0.0], L[ground, L1]], J[R, P[12.5, 21.6506], L[L1, L2]], "
              "J[R, P[74.2099, 54.6944], L[L2, L3]], J[R, P[80.0, 0.0], L[ground, L3]]]")


def test_block_comments_match_as_the_greedy_pattern_did():
    """The linear-time block-comment blanking gives what Pyslvs' greedy pattern (re.sub) gives, on 20,000
    random texts of comment marks, brackets, letters and line breaks (the regex is the reference)."""
    import random
    from analytic.format import pyslvs as P

    def blank(m):
        return re.sub(r"[^\n]", " ", m.group(0))
    rng = random.Random(1)
    alphabet = ["#[", "#]", "#", "[", "]", "a", "\n", " "]
    for _ in range(20_000):
        text = "".join(rng.choice(alphabet) for _ in range(rng.randint(0, 14)))
        assert P._blank_block(text, blank) == P._BLOCK_COMMENT.sub(blank, text), text


@pytest.mark.slow
def test_a_comment_bomb_in_a_pyslvs_expression_is_read_at_once(tmp_path):
    """Fault: 300,000 unclosed '#[' (600 kB, under the 1 MB file limit) before an expression: the greedy
    block-comment regex retried from every one of them, quadratic (still running after 120 s). The import
    now answers in seconds; the expression after the marks is still read (4 joints)."""
    (tmp_path / "bomb.txt").write_text("#[" * 300_000 + "\n" + EXPRESSION + "\n")
    r = subprocess.run([sys.executable, "-m", "sim", "import", "bomb.txt", "--input", "0,1", "--out", "b.toml"],
                       capture_output=True, text=True, cwd=tmp_path, timeout=60)   # a guard against the hang
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "b.toml").read_text().count('point = "J') >= 4


def test_a_target_of_1e300_is_out_of_range(tmp_path):
    """Fault: a target y of 1e300 made the spread 1e300, and every other point 'the same point' (lines 2
    and 3 give the same point; remove one)."""
    (tmp_path / "t.csv").write_text("x,y\n0,0\n1,0.2\n2,0.1\n3,1e300\n")
    r = cli_runner.run("synthesize", "path", "t.csv", cwd=tmp_path)
    _one_line(r, r"t\.csv: line 5, column y: '1e300' is out of range; give a magnitude <= 1e\+12")


def test_forces_refuses_a_sample_count_past_its_memory_before_any_work(tmp_path):
    """Fault: ``forces --samples 10000000`` took 5.7 GB (peak RSS) and tens of seconds before answering.
    The bound: 2 GB at 16 bytes a solved value a sample, 42 values on the four-bar."""
    from sim.service.analysis import BYTES_PER_VALUE, RUN_MEMORY
    most = RUN_MEMORY // (BYTES_PER_VALUE * 42)
    r = cli_runner.run("forces", "fourbar", "--samples", "10000000", "--csv", "f.csv", cwd=tmp_path)
    _one_line(r, rf"samples=10,000,000: the fourbar's joint forces .* need about 6\.3 GB \(42 values a sample\); "
                 rf"at most {most:,} fit in the 2 GB")
    assert list(tmp_path.iterdir()) == []


def _frame_over_pivots():
    return _lib("fourbar") + "\n[parts]\nframe = [[-0.05, -0.05], [0.35, -0.05], [0.35, 0.05], [-0.05, 0.05]]\n"


def test_a_frame_covering_the_pivots_exports_its_drawing(tmp_path):
    """Fault: a frame polygon over both ground pivots lifts every link off layer 0; the exploded view's
    z levels took the minimum over layer 0's (no) links: ValueError, a traceback from export --svg."""
    (tmp_path / "fb.toml").write_text(_frame_over_pivots())
    r = cli_runner.run("export", "fb.toml", "--svg", "fb.svg", cwd=tmp_path)
    assert r.returncode == 0 and "Traceback" not in r.stderr, r.stderr
    assert (tmp_path / "fb.svg").read_text().lstrip().startswith("<?xml")


PARTS = [
    ("a pin wider than the bar", "pin_diameter = 0.5", r"pv\.toml: parts: link 1: the hole .* leaves no material"),
    ("an end radius of 1e12", "end_radius = 1e12",
     r"pv\.toml: parts\.end_radius: 1e\+12 is more than 10 times the mechanism's size \(0\.3 m\)"),
    ("a layer gap of 1e12", "layer_gap = 1e12", r"pv\.toml: parts\.layer_gap: 1e\+12 is more than 10 times"),
]


@pytest.mark.parametrize("case", PARTS, ids=[c[0] for c in PARTS])
@pytest.mark.parametrize("command", [["check"], ["check", "--interference"], ["export", "--svg", "pv.svg"]])
def test_check_refuses_the_parts_values_export_refuses(tmp_path, case, command):
    """Faults: check printed 'parts: none made' and exited 0 on [parts] values export refuses; an end
    radius of 1e12 divided by zero tessellating its arcs (ZeroDivisionError in every command); a layer gap
    of 1e12 made MuJoCo's mesh coplanar (check --interference)."""
    _, line, pattern = case
    (tmp_path / "pv.toml").write_text(_lib("fourbar") + f"\n[parts]\n{line}\n")
    r = cli_runner.run(command[0], "pv.toml", *command[1:], cwd=tmp_path)
    _one_line(r, pattern)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pv.toml"]


def test_a_frame_of_20000_corners_is_refused_before_any_work(tmp_path):
    """Fault: a 20,000-corner frame (880 kB, under the file limit) made ``check`` take 31 s and
    ``check --interference`` 46 s; refused now at the file's reading, with the limit."""
    import math
    n = 20_000
    corners = [[round(0.15 + 0.5 * math.cos(2 * math.pi * k / n), 6), round(-0.3 + 0.1 * math.sin(2 * math.pi * k / n), 6)]
               for k in range(n)]
    (tmp_path / "f.toml").write_text(_lib("fourbar") + f"\n[parts]\nframe = {corners}\n")
    r = cli_runner.run("check", "f.toml", "--interference", cwd=tmp_path)
    _one_line(r, r"f\.toml: parts\.frame: 20000 corners; a frame has at most 1000 \(simplify its outline\)")


def _many_joints_pyslvs(n):
    extra = "".join(f", J[R, P[{k % 97}.5, {k % 89}.25], L[L2]]" for k in range(n))
    return EXPRESSION[:-1] + extra + "]\n"


def _many_joints_pmks(n):
    rows = ["ground,input,R,0,0,t,f,f,t", "input,coupler,R,12.5,21.65,t,f,f,f", "coupler,output,R,74.2,54.7,t,f,f,f",
            "ground,output,R,80,0,t,f,f,f"]
    return "\n".join(rows + [f"coupler,R,{k % 97}.5,{k % 89}.25,t,f,f,f" for k in range(n)]) + "\n"


@pytest.mark.parametrize("name, make, extra", [("big.txt", _many_joints_pyslvs, ["--input", "0,1"]),
                                                ("big_pmks.txt", _many_joints_pmks, [])])
def test_a_foreign_file_of_30000_joints_is_refused_while_read(tmp_path, name, make, extra):
    """Fault: a Pyslvs expression (or PMKS text) of 30,000 joints, 860 kB, was converted in full (past 120 s)
    before the 500-entry limit of a mechanism refused the result."""
    (tmp_path / name).write_text(make(30_000))
    r = cli_runner.run("import", name, *extra, "--out", "b.toml", cwd=tmp_path)
    _one_line(r, re.escape(name) + r": more than 500 joints; a mechanism holds at most that many")
    assert not (tmp_path / "b.toml").exists()


def test_a_foreign_file_of_500_joints_is_not_refused_for_its_count():
    """The bound is the mechanism file's own (500 items): 4 joints plus 496 points on the coupler read."""
    from analytic.format import pyslvs
    assert len(pyslvs.parse_expression(_many_joints_pyslvs(496), "ok.txt")) == 500


def test_synthesize_motion_count_1000_is_refused_before_any_work(tmp_path):
    """Fault: ``synthesize motion --count 1000`` checked every design in MuJoCo: past 200 s (--count 100:
    55 s)."""
    (tmp_path / "poses.csv").write_text("x,y,theta\n0,0,0\n1,0.5,20\n2,0.8,45\n3,0.6,70\n")
    r = cli_runner.run("synthesize", "motion", "poses.csv", "--count", "1000", cwd=tmp_path)
    _one_line(r, r"--count 1000 must be in 1\.\.20: every design returned is checked by a MuJoCo run")


def test_a_motor_run_stalled_by_a_coarse_time_step_names_the_time_step(tmp_path):
    """Fault: ``dynamics --motor 5,1e9 --timestep 0.01`` said 'in MuJoCo the motor stalls the fourbar at
    phi=833.3deg', a stall that is the 10 ms step's (the reduced equation turns it, and at the step the run
    chooses MuJoCo agrees): the fix, the time step, went unnamed."""
    r = cli_runner.run("dynamics", "fourbar", "--motor", "5,1e9", "--timestep", "0.01", "--csv", "out.csv",
                       cwd=tmp_path)
    _one_line(r, r"in MuJoCo the motor stalls the fourbar .*where the reduced equation turns it: the time step "
                 r"0\.01 s given by --timestep is above the \S+ s this motor run needs; drop --timestep")
    assert list(tmp_path.iterdir()) == []


def _first_repeat(k, lines):
    """The first repeated row in file order by a double loop over the rows (the check as first written, 4-5 s
    on 1,000 targets): (earlier line, later line) or None."""
    import numpy as np
    scale = max(float(np.ptp(k, axis=0).max()), 1e-12)
    for i in range(len(k)):
        for j in range(i):
            if np.all(np.abs(k[i] - k[j]) <= 1e-9 * scale):     # the check's own tolerance: 1e-9 of the spread
                return lines[j], lines[i]
    return None


def test_repeated_targets_are_found_as_the_double_loop_finds_them():
    """The sorted scan that replaced the double loop (1,000 targets read in 5 s before the search began)
    names the same first pair on 3,000 random small tables with repeats, near-repeats and ties."""
    import numpy as np
    from analytic import ParameterError
    from sim.service.design import check_repeats
    rng = np.random.default_rng(0)
    for _ in range(3000):
        n, c = int(rng.integers(1, 12)), int(rng.integers(1, 4))
        data = rng.integers(0, 3, size=(n, c)) * rng.choice([1.0, 1e-10, 0.5])
        lines = list(range(2, n + 2))
        expected = _first_repeat(data, lines)
        if expected is None:
            check_repeats("t.csv", data, lines, lambda d: d, "point")
            continue
        with pytest.raises(ParameterError, match=rf"lines {expected[0]} and {expected[1]} give the same point"):
            check_repeats("t.csv", data, lines, lambda d: d, "point")


def test_a_target_file_of_more_than_10000_rows_is_refused(tmp_path):
    # its first two rows repeat: without the bound the repeat is refused at once instead (not a long search)
    (tmp_path / "t.csv").write_text("x,y\n0,0\n" + "".join(f"{k},{k % 7}\n" for k in range(10_000)))
    r = cli_runner.run("synthesize", "path", "t.csv", cwd=tmp_path)
    _one_line(r, r"t\.csv: 10,001 rows; a synthesis takes at most 10,000")


def test_a_failed_forces_simulation_writes_no_csv(tmp_path, monkeypatch):
    # forces --simulate --csv whose MuJoCo check fails (its verdict forced to FAILED here: a real failure
    # needs a broken model) writes neither the CSV nor its units file, and says so in one line
    from linkage import results
    monkeypatch.setattr(results.Forces, "passed", property(lambda self: False))
    from tests.cli_runner import run as run_in_process
    out = tmp_path / "f.csv"
    r = run_in_process("forces", "fourbar", "--simulate", "--samples", "13", "--csv", out)
    assert r.returncode == 1
    assert not out.exists() and not (tmp_path / "f.csv.units.json").exists()
    assert "not written" in r.stderr and "f.csv" in r.stderr and len(r.stderr.strip().splitlines()) == 1


@pytest.mark.parametrize("address", ["tcp://127.0.0.1:8786", "127.0.0.1:8786", "tls://h.example:8786", "[::1]:8786",
                                     "inproc://192.0.2.2/24398/1", "local"])
def test_a_well_formed_scheduler_address_is_accepted(address):
    """The check refuses what Dask's parser cannot read, not the schemes it can (an in-process cluster's address
    came back refused: the tolerance test's cluster in this process)."""
    from sim.run.parallel import check_scheduler
    assert check_scheduler(address) == address
