"""``import linkage as lk`` (SPEC "Python API"): the door's names, its signatures (the subject positional,
every option keyword-only), its results (frozen, ``to_dict()`` equal to the command's ``--json``), its
errors, its cost at import, and the loads given as keywords checked against virtual power."""

from __future__ import annotations

import dataclasses
import doctest
import inspect
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import linkage as lk

ROOT = Path(__file__).resolve().parents[1]
FUNCTIONS = ("load", "analyze", "simulate", "compare", "forces", "dynamics", "export", "tolerance", "synthesize",
             "sweep")


def _cli_json(*args) -> dict:
    """What ``python -m sim ARGS --json`` prints, from a separate process (the command as a user runs it)."""
    r = subprocess.run([sys.executable, "-m", "sim", *map(str, args), "--json"], capture_output=True, text=True,
                       cwd=ROOT, timeout=300)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout)


def _same(a, b, where="") -> list[str]:
    """Where two JSON-like objects differ: keys, lengths, texts, or numbers beyond 1e-12 relative (the JSON
    text is Python's shortest repr, which reads back to the same float; the margin only allows for a
    different last bit between two processes' libm)."""
    if isinstance(a, dict) and isinstance(b, dict):
        if set(a) != set(b):
            return [f"{where}: keys {sorted(set(a) ^ set(b))}"]
        return [d for k in a for d in _same(a[k], b[k], f"{where}.{k}")]
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{where}: length {len(a)} != {len(b)}"]
        return [d for i, (x, y) in enumerate(zip(a, b)) for d in _same(x, y, f"{where}[{i}]")]
    if isinstance(a, bool) or isinstance(b, bool) or not isinstance(a, (int, float)) or not isinstance(b, (int, float)):
        return [] if a == b else [f"{where}: {a!r} != {b!r}"]
    return [] if math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-300) else [f"{where}: {a!r} != {b!r}"]


# ------------------------------------------------------------------------------------------ the door
def test_the_door_has_at_most_30_names_each_documented_with_an_example():
    assert len(lk.__all__) <= 30 and len(set(lk.__all__)) == len(lk.__all__)
    assert set(FUNCTIONS) <= set(lk.__all__) and "ParameterError" in lk.__all__
    assert "annotations" not in lk.__all__
    for name in lk.__all__:
        obj = getattr(lk, name)
        doc = inspect.getdoc(obj) or ""
        assert len(doc) > 40, name
        if name != "ParameterError":
            assert "Example:" in doc and ">>>" in doc, f"{name} has no example"


def test_every_option_is_keyword_only():
    """The subject (a mechanism, a name, a problem) is the one positional parameter; every other is a keyword."""
    for name in FUNCTIONS:
        params = list(inspect.signature(getattr(lk, name)).parameters.values())
        assert params[0].kind in (inspect.Parameter.POSITIONAL_ONLY, inspect.Parameter.POSITIONAL_OR_KEYWORD), name
        late = [p.name for p in params[1:] if p.kind not in (inspect.Parameter.KEYWORD_ONLY,
                                                              inspect.Parameter.VAR_KEYWORD)]
        assert late == [], f"{name}: {late} can be given by position"
    mech = lk.load("fourbar")
    with pytest.raises(TypeError):
        lk.analyze(mech, 361)                                   # a positional option is refused
    with pytest.raises(TypeError):
        lk.forces(mech, 73)


def test_the_docstrings_examples_run_as_written():
    """Every ``>>>`` example of the door (the functions and the results) prints what it shows."""
    import linkage.api
    import linkage.mechanism
    import linkage.results
    failures, tried = 0, 0
    for module in (linkage.api, linkage.mechanism, linkage.results):
        r = doctest.testmod(module, extraglobs={"lk": lk}, optionflags=doctest.ELLIPSIS, verbose=False)
        failures, tried = failures + r.failed, tried + r.attempted
    assert tried >= 20
    assert failures == 0


def test_importing_the_door_loads_nothing_heavy_and_the_command_still_starts():
    code = ("import sys, linkage\nprint(sorted(m for m in ('numpy', 'scipy', 'mujoco', 'matplotlib', "
            "'analytic.mechanism', 'sim.service') if m in sys.modules))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=60)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "[]"
    r = subprocess.run([sys.executable, "-m", "sim", "list"], capture_output=True, text=True, cwd=ROOT, timeout=60)
    assert r.returncode == 0 and r.stdout.startswith("fourbar"), r.stderr


def test_the_readmes_first_python_block_opens_the_door():
    import re
    first = re.search(r"```python\n(.*?)```", (ROOT / "README.md").read_text(), re.S).group(1)
    assert first.splitlines()[0] == "import linkage as lk"          # tests/test_readme.py runs it as written


# ------------------------------------------------------------------------------------------ results
def test_forces_to_dict_is_the_commands_json_number_for_number():
    mech = lk.load("fourbar", l1=0.12)
    f = lk.forces(mech, samples=73, gravity=(0, -9.81))
    cli = _cli_json("forces", "fourbar", "--set", "l1=0.12", "--samples", 73, "--gravity", "0,-9.81")
    assert _same(f.to_dict(), cli) == []
    assert f.drives["phi1"].shape == (73,) and set(f.joints) == {"A", "B", "C", "D"}
    assert f.peaks["drives"]["phi1"]["value"] == pytest.approx(float(np.abs(f.drives["phi1"]).max()), rel=1e-15)


def test_to_dict_in_other_units_is_the_commands_json_with_the_same_unit_options():
    mech = lk.load("whitworth")                                        # a mm file
    f = lk.forces(mech, samples=19)
    cli = _cli_json("forces", "whitworth", "--samples", 19, "--units", "mm", "--angles", "deg")
    assert _same(f.to_dict(units="mm", angles="deg"), cli) == []
    a = lk.analyze(mech, samples=19)
    cli = _cli_json("analyze", "whitworth", "--samples", 19, "--units", "mm", "--speeds", "rpm")
    assert _same(a.to_dict(units="mm", speeds="rpm"), cli) == []
    si = a.to_dict()["ranges"]["xR"]
    assert a.to_dict(units="mm")["ranges"]["xR"] == pytest.approx([1000 * v for v in si], rel=1e-12)  # m -> mm


def test_forces_with_named_loads_match_the_command_with_the_same_loads():
    """A force at a named point, a couple on a link and links' inertias: the keywords and the options."""
    inertia = {"2": {"m": 0.5, "cx": 0.1, "cy": 0.0, "I": 0.004}}
    mech = lk.load("fourbar")
    f = lk.forces(mech, samples=37, force=(-50, 10, "E"), torque={"3": 0.5}, inertia=inertia)
    path = ROOT / "tests" / "_api_inertia.json"
    path.write_text(json.dumps(inertia))
    try:
        cli = _cli_json("forces", "fourbar", "--samples", 37, "--force", "-50,10@E", "--torque", "0.5@3",
                        "--inertia", path)
    finally:
        path.unlink()
    assert _same(f.to_dict(), cli) == []


def test_analyze_and_compare_to_dict_are_the_commands_json():
    mech = lk.load("fourbar", l1=0.12)
    a = lk.analyze(mech, samples=181)
    assert _same(a.to_dict(), _cli_json("analyze", "fourbar", "--set", "l1=0.12", "--samples", 181)) == []
    c = lk.compare(mech)
    mine, cli = c.to_dict(), _cli_json("compare", "fourbar", "--set", "l1=0.12")
    for record in (mine, cli):
        record.pop("cpu_seconds")                            # the one timed field
    assert _same(mine, cli) == []
    assert c.passed is True and cli["passed"] is True


def test_simulate_to_dict_is_the_commands_json():
    mech = lk.load("sixbar")
    s = lk.simulate(mech, revolutions=0.25, gravity=(0, -9.81))
    mine, cli = s.to_dict(), _cli_json("simulate", "sixbar", "--revolutions", 0.25, "--gravity", "0,-9.81")
    for record in (mine, cli):
        record.pop("cpu_seconds")                            # the one timed field
    assert _same(mine, cli) == []
    assert s["xC"].shape == s.t.shape
    # a quarter turn at the sixbar's 2 pi rad/s is 0.25 s, run to the first whole step past it
    assert 0.25 - 1e-12 <= s.t[-1] < 0.25 + s.timestep


def test_tolerance_and_synthesis_to_dict_are_the_commands_json():
    t = lk.tolerance(lk.load("fourbar"), tol={"l1": "±0.001", "l3": "±0.5%"}, samples=40, seed=3)
    cli = _cli_json("tolerance", "fourbar", "--tol", "l1=±0.001", "--tol", "l3=±0.5%", "--samples", 40, "--seed", 3)
    assert _same(t.to_dict(), cli) == []
    s = lk.synthesize("two-position", E1=(30, 31), E2=(10, 35), crank_rotation="35deg")
    assert _same(s.to_dict(), _cli_json("synthesize", "two-position", "--E1", "30,31", "--crank-rotation",
                                        "35deg")) == []


def test_dynamics_to_dict_is_the_commands_json():
    d = lk.dynamics(lk.load("fourbar"), motor=(2.0, 15.0), revolutions=3, gravity=(0, -9.81))
    cli = _cli_json("dynamics", "fourbar", "--motor", "2,15", "--revolutions", 3, "--gravity", "0,-9.81")
    assert _same(d.to_dict(), cli) == []
    assert d.passed and cli["passed"] is True


def test_function_synthesis_through_the_door_recovers_the_four_bar_its_pairs_came_from():
    """Seven (crank, rocker) angle pairs read off the shipped four-bar (closed forms): Freudenstein's answer
    with the same ground is that four-bar's l1, l2, l3, and MuJoCo passes it."""
    mech = lk.load("fourbar")
    a = lk.analyze(mech, samples=7, input_range="20deg:140deg")
    s = lk.synthesize("function", pairs=np.column_stack([a["phi1"], a["phi3"]]), angles="rad",
                      ground=mech.values["l4"])
    assert s.best is not None
    for k in ("l1", "l2", "l3"):            # exact through 3+ consistent pairs: rounding of the least squares
        assert s.best["parameters"][k] == pytest.approx(mech.values[k], rel=1e-9), k
    assert [d["compare_passed"] for d in s.to_dict()["designs"]] == [True]
    assert all("text" not in d for d in s.to_dict()["designs"])          # as --json prints them


def test_the_analysis_columns_are_the_closed_forms_hand_geometry():
    """a["xE"] at the start against the four-bar drawn by hand: B on the crank circle, C where the circles
    about B (l2) and D (l3) meet (the file's branch), E on BC's frame."""
    mech = lk.load("fourbar")
    v = mech.values
    a = lk.analyze(mech, samples=9)
    phi = a["phi1"][0]
    bx, by = v["l1"] * math.cos(phi), v["l1"] * math.sin(phi)
    dx, dy = v["l4"], 0.0
    d = math.hypot(dx - bx, dy - by)
    along = (v["l2"] ** 2 - v["l3"] ** 2 + d * d) / (2 * d)
    h = math.sqrt(v["l2"] ** 2 - along ** 2)
    ux, uy = (dx - bx) / d, (dy - by) / d
    cands = [(bx + along * ux - s * h * uy, by + along * uy + s * h * ux) for s in (1, -1)]
    sol = a.analysis.solution
    cx, cy = min(cands, key=lambda c: math.hypot(c[0] - float(sol["xC"][0]), c[1] - float(sol["yC"][0])))
    assert math.hypot(cx - float(sol["xC"][0]), cy - float(sol["yC"][0])) < 1e-12   # rounding of a few lengths
    assert math.hypot(bx - float(sol["xB"][0]), by - float(sol["yB"][0])) < 1e-12


def test_a_force_and_a_couple_given_as_keywords_change_the_drive_by_their_virtual_power():
    """The drive torque with a force F at E and a couple T on link 3, less the drive without them, is
    -(F . vE + T omega3) / omega1 at every sample (virtual power: inertia and gravity cancel in the
    difference); vE and omega3 from the closed-form analysis, not from the forces."""
    mech = lk.load("fourbar")
    bare = lk.forces(mech, samples=25, gravity=(0, -9.81))
    loaded = lk.forces(mech, samples=25, gravity=(0, -9.81), force=(-40.0, 15.0, "E"), torque={"3": 0.7})
    a = lk.analyze(mech, samples=25)
    expected = -(-40.0 * a["vxE"] + 15.0 * a["vyE"] + 0.7 * a["omega3"]) / a["omega1"]
    diff = loaded.drives["phi1"] - bare.drives["phi1"]
    assert np.max(np.abs(diff - expected)) < 1e-9 * np.max(np.abs(expected))   # the solver's rounding


def test_results_are_frozen_and_errors_are_one_parameter_error_line():
    mech = lk.load("fourbar")
    a = lk.analyze(mech, samples=5)
    with pytest.raises(dataclasses.FrozenInstanceError):
        a.samples = 7
    with pytest.raises(lk.ParameterError) as err:
        lk.analyze(mech, samples=1)
    assert "samples=1" in str(err.value) and "\n" not in str(err.value)
    with pytest.raises(lk.ParameterError, match="not a valid length"):
        lk.load("fourbar", l1=-0.1)
    with pytest.raises(lk.ParameterError, match="no point named 'Z'"):
        lk.forces(mech, force=(1, 0, "Z"))
    with pytest.raises(lk.ParameterError, match="is not a mechanism"):
        lk.analyze("fourbar")


def test_load_takes_names_paths_and_mechanisms():
    m = lk.load("fourbar", l1=0.12)
    assert isinstance(m, lk.Mechanism) and m.values["l1"] == pytest.approx(0.12, rel=1e-15)
    m2 = lk.load(m, l2=0.3)
    assert m2.values["l1"] == pytest.approx(0.12, rel=1e-15) and m2.values["l2"] == pytest.approx(0.3, rel=1e-15)
    path = next((ROOT / "analytic" / "library").glob("*.toml"))
    assert lk.load(path).name == lk.load(str(path)).name


# ------------------------------------------------------------------------------------------ notebook
def _count(svg: str, *tags) -> int:
    return sum(svg.count(f"<{t} ") for t in tags)


def test_a_mechanism_and_a_result_show_themselves_as_html():
    mech = lk.load("fourbar")
    page = mech._repr_html_()
    assert page.count("<svg") == 1
    assert _count(page, "polyline", "polygon") == len(mech.topology.links) + 1      # each link, and E's path
    for name in mech.definition.parameter_order:
        assert f">{name}<" in page
    a = lk.analyze(mech, samples=91)
    view = a._repr_html_()
    assert "<animate" in view and "transmission" in view
    shown = float(view.split(">samples<")[1].split(">")[2].split("<")[0])       # the table's row
    assert shown == pytest.approx(91, abs=1e-12)                                # the count, as printed
