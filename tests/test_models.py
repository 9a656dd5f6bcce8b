"""Every MJCF file: compiles, all elements named, keyframe closes every loop and matches the analytic
solver, steps with zero MuJoCo warnings, is deterministic, and the built lengths equal the parameters."""


import mujoco
import numpy as np
import pytest

from analytic import FiveBar, FourBar, SixBar
from sim import keyframes, model
from sim.params import CLASSES

NAMES = list(CLASSES)
OBJECTS = [(mujoco.mjtObj.mjOBJ_BODY, "nbody"), (mujoco.mjtObj.mjOBJ_JOINT, "njnt"),
           (mujoco.mjtObj.mjOBJ_GEOM, "ngeom"), (mujoco.mjtObj.mjOBJ_SITE, "nsite"),
           (mujoco.mjtObj.mjOBJ_EQUALITY, "neq"), (mujoco.mjtObj.mjOBJ_ACTUATOR, "nu"),
           (mujoco.mjtObj.mjOBJ_CAMERA, "ncam"), (mujoco.mjtObj.mjOBJ_SENSOR, "nsensor"),
           (mujoco.mjtObj.mjOBJ_KEY, "nkey")]


def raw(name):
    return mujoco.MjModel.from_xml_path(str(model.mjcf_path(name)))


@pytest.mark.parametrize("name", NAMES)
def test_every_element_is_named(name):
    m = raw(name)
    for obj, count in OBJECTS:
        for i in range(getattr(m, count)):
            if obj == mujoco.mjtObj.mjOBJ_BODY and i == 0:
                continue                                   # the world body
            assert mujoco.mj_id2name(m, obj, i), f"unnamed {obj.name} #{i}"


@pytest.mark.parametrize("name", NAMES)
def test_keyframe_is_the_analytic_solution_and_closes_every_loop(name):
    m = raw(name)
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key("home").id)
    mujoco.mj_forward(m, d)
    # Loop closure at rounding level: positions of order 0.5 m.
    assert np.abs(d.efc_pos[:d.ne]).max() < 1e-12
    # ...and the file is in sync with the generator (python -m sim.keyframes).
    assert f'{keyframes.key_element(name)}' in model.mjcf_path(name).read_text()


@pytest.mark.parametrize("name", NAMES)
def test_steps_without_warnings_deterministically_and_moves(name):
    m = raw(name)
    runs = []
    for _ in range(2):
        d = mujoco.MjData(m)
        mujoco.mj_resetDataKeyframe(m, d, m.key("home").id)
        q0 = d.qpos.copy()
        for _ in range(250):
            mujoco.mj_step(m, d)
        assert all(w.number == 0 for w in d.warning), [w.number for w in d.warning]
        assert np.abs(d.qpos - q0).max() > 0.5              # half a turn at 1 rev/s: it moves
        runs.append(np.concatenate([d.qpos, d.qvel, d.qacc]))
    assert np.array_equal(runs[0], runs[1])


def _sites_at_home(mech):
    """Built model and a function giving a site's world (x, y) at its home keyframe."""
    b = model.build(mech)
    d = mujoco.MjData(b.model)
    mujoco.mj_resetDataKeyframe(b.model, d, 0)
    mujoco.mj_forward(b.model, d)
    return b, lambda site: d.site(site).xpos[:2].copy()


def test_fourbar_lengths_read_back():
    mech = FourBar(l1=0.07, l2=0.23, l3=0.19, l4=0.21, ex=-0.04, ey=0.06, phi1_0=1.0)
    b, w = _sites_at_home(mech)
    tol = 1e-12                                   # rounding of body/site poses
    assert abs(np.linalg.norm(w("B") - w("A")) - mech.l1) < tol
    assert abs(np.linalg.norm(w("C_coupler") - w("B")) - mech.l2) < tol
    assert abs(np.linalg.norm(w("C") - w("D")) - mech.l3) < tol
    assert abs(np.linalg.norm(w("D") - w("A")) - mech.l4) < tol
    assert np.linalg.norm(w("C") - w("C_coupler")) < tol
    e = b.model.site("E").pos
    assert abs(e[0] - mech.ex) < tol and abs(e[1] - mech.ey) < tol


def test_sixbar_lengths_read_back():
    mech = SixBar(l6=0.35, l1=0.09, l3=0.5, l4=0.2, phi1_0=2.0)
    b, w = _sites_at_home(mech)
    tol = 1e-12
    assert abs(np.linalg.norm(w("O2") - w("O4")) - mech.l6) < tol
    assert abs(np.linalg.norm(w("A") - w("O2")) - mech.l1) < tol
    assert abs(np.linalg.norm(w("B") - w("O4")) - mech.l3) < tol
    assert abs(np.linalg.norm(w("C_rod") - w("B")) - mech.l4) < tol
    assert abs(w("C")[1] - mech.h) < tol
    assert np.linalg.norm(w("A") - w("A_block")) < tol and np.linalg.norm(w("C") - w("C_rod")) < tol


def test_fivebar_lengths_read_back():
    mech = FiveBar(l1=0.25, l2=0.05, l4=0.07, lp=0.2, phi2_0=0.3, phi4_0=2.0)
    b, w = _sites_at_home(mech)
    tol = 1e-12
    assert abs(np.linalg.norm(w("D") - w("A")) - mech.l1) < tol
    assert abs(np.linalg.norm(w("B") - w("A")) - mech.l2) < tol
    assert abs(np.linalg.norm(w("C") - w("D")) - mech.l4) < tol
    assert abs(np.linalg.norm(w("P") - w("B")) - mech.lp) < tol
    assert np.linalg.norm(w("C_block") - w("C")) < tol
    # P lies on the line B->C.
    u, p = w("C") - w("B"), w("P") - w("B")
    assert abs(u[0] * p[1] - u[1] * p[0]) < tol
