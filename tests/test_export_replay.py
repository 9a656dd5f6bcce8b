"""The exported MJCF is the validated model: every library mechanism (and tests/mechanisms/*.toml),
written by ``linkage export --mjcf``, loaded through ``sim.load_exported`` and stepped with the controls
the simulation computes, keeps its loops within compare's loop tolerance and its points on the analytic
solution; the file is well-formed XML and tells a plain-MuJoCo reader what it cannot hold."""

import xml.etree.ElementTree as ET
from xml.dom import minidom
from pathlib import Path

import mujoco
import numpy as np
import pytest
from mujoco import rollout

import sim
from analytic import ParameterError
from analytic.registry import LIBRARY, load
from sim.run.compare import LOOP_TOL, tolerance
from sim.model import Settings, build, motion_scale
from sim.service import export_mjcf
from sim.run.simulate import controls, measure, steps_for

from agreement import skip_without_cam_contact
import cli_runner  # the command in this process (tests/cli_runner.py)

HERE = Path(__file__).parent
REVOLUTIONS = {"moving_guide": 0.8}     # it assembles from 0 to 311.8 deg only (linkage check), not a full turn
FILES = sorted(str(p) for p in LIBRARY.glob("*.toml")) + sorted(str(p) for p in (HERE / "mechanisms").glob("*.toml"))


def _replay(model, data, built, revolutions=1.0):
    """Step ``model`` from ``data``'s state with the simulation's controls; (inputs, solution, loop violation)."""
    kind = mujoco.mjtState.mjSTATE_FULLPHYSICS
    s0 = np.empty(mujoco.mj_stateSize(model, kind))
    mujoco.mj_getState(model, data, s0, kind)
    n = steps_for(built, revolutions)
    ctrl = controls(built, np.arange(n) * built.timestep)
    # an exported model's constant loads are actuators after the drives and the load (their ctrl unused)
    ctrl = np.pad(ctrl, ((0, 0), (0, model.nu - ctrl.shape[1])))
    _, sens = rollout.rollout(model, data, s0[None], ctrl[None], nstep=n)
    inputs, sol, viol, _ = measure(built, sens[0])
    return inputs, sol, viol


SLOW_REPLAYS = ("double_butterfly", "stephenson_ii")
"""Numerically solved groups: their replays cost 10-25 s each, so they run in the slow tier."""


@pytest.mark.parametrize("path", [pytest.param(f, marks=pytest.mark.slow) if Path(f).stem in SLOW_REPLAYS else f
                                  for f in FILES], ids=[Path(f).stem for f in FILES])
def test_exported_model_replays_within_compare_tolerances(tmp_path, path):
    mech = load(path)
    skip_without_cam_contact(mech)
    revolutions = REVOLUTIONS.get(Path(path).stem, 1.0)
    built = build(mech, Settings(), revolutions=revolutions, export=True)     # the drives as exported
    out = tmp_path / "m.xml"
    r = cli_runner.run("export", path, "--mjcf", str(out), "--revolutions",
                        str(revolutions), cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    text = out.read_text()
    ET.fromstring(text.split("-->", 1)[1])                  # the document after the header comment
    minidom.parseString(text)                       # the whole file, comment included, is well-formed
    model, data = sim.load_exported(out)
    inputs, sol, viol = _replay(model, data, built, revolutions)
    assert np.all(np.isfinite(viol))
    # compare's own loop tolerance (the loops' drift under the stiff drift correction, 1e-6 of the size)
    assert viol.max() <= LOOP_TOL * mech.size, (viol.max(), LOOP_TOL * mech.size)
    # the points against the analytic solution at the measured inputs (an independent closed-form solve)
    q = np.column_stack([inputs[i.q] for i in mech.inputs])
    ref = mech.solve(q)
    omega = motion_scale(mech)
    from sim.run.cams import tolerances
    floors = tolerances(built)
    for p in mech.points:
        for c in ("x", "y"):
            name = c + p
            if name not in mech.outputs:
                continue
            a, s = np.asarray(ref[name]), np.asarray(sol[name])
            tol = tolerance(mech, name, float(np.nanmax(np.abs(a))), omega)   # compare's position tolerance
            if floors is not None:                  # and compare's floor for a cam's compliant contact
                tol = max(tol, floors["position"])
            assert np.max(np.abs(s - a)) <= tol, (name, np.max(np.abs(s - a)), tol)


def test_plain_mujoco_misses_what_the_loader_holds(tmp_path):
    """The reason for the loader, measured: plain MuJoCo opens whitworth's loops beyond the tolerance."""
    mech = load("whitworth")
    built = build(mech, Settings())
    out = tmp_path / "w.xml"
    out.write_text(export_mjcf(mech))
    plain = mujoco.MjModel.from_xml_path(str(out))
    data = mujoco.MjData(plain)
    mujoco.mj_resetDataKeyframe(plain, data, plain.key("home").id)
    mujoco.mj_forward(plain, data)
    _, _, viol_plain = _replay(plain, data, built)
    model, data = sim.load_exported(out)
    _, _, viol = _replay(model, data, built)
    assert viol_plain.max() > LOOP_TOL * mech.size > viol.max()
    assert "sim.load_exported" in out.read_text().split("-->")[0]   # the file says so to its reader


def test_a_comment_breaker_in_the_source_stays_well_formed(tmp_path):
    src = tmp_path / "a--b---.toml"
    src.write_bytes((LIBRARY / "fourbar.toml").read_bytes())
    r = cli_runner.run("export", src.name, "--mjcf", "m.xml", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    minidom.parseString((tmp_path / "m.xml").read_text())


@pytest.mark.parametrize("target", ["library", "input"])
def test_export_toml_never_overwrites_an_input_or_the_library(tmp_path, target):
    lib = LIBRARY / "fourbar.toml"
    before = lib.read_bytes()
    if target == "library":
        args = ["fourbar", "--toml", str(lib)]
    else:
        (tmp_path / "mine.toml").write_bytes(before)
        (tmp_path / "alias.toml").symlink_to("mine.toml")
        args = ["mine.toml", "--toml", "alias.toml"]
    r = cli_runner.run("export", *args, cwd=tmp_path)
    assert r.returncode == 2 and r.stderr.startswith("linkage: error: ") and len(r.stderr.splitlines()) == 1
    assert lib.read_bytes() == before
    if target == "input":
        assert (tmp_path / "mine.toml").read_bytes() == before


def test_the_loader_refuses_a_foreign_file(tmp_path):
    f = tmp_path / "x.xml"
    f.write_text("<mujoco><worldbody/></mujoco>")
    with pytest.raises(ParameterError, match="linkage_invweight0_scale"):
        sim.load_exported(f)
