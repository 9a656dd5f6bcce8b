"""The MuJoCo models: every generated model (built-ins and library) compiles with every element named,
closes every loop in its default pose, carries a home keyframe, steps without warnings and
deterministically; the hand-written files of the three built-ins stay in sync with the analytic solver
and agree with the generated models."""

import math

import mujoco
import numpy as np
import pytest

from agreement import skip_without_cam_contact
import analytic
from mjcf import keyframes
from sim import model
from sim import service

NAMES = list(analytic.names())
OBJECTS = [(mujoco.mjtObj.mjOBJ_BODY, "nbody"), (mujoco.mjtObj.mjOBJ_JOINT, "njnt"),
           (mujoco.mjtObj.mjOBJ_GEOM, "ngeom"), (mujoco.mjtObj.mjOBJ_SITE, "nsite"),
           (mujoco.mjtObj.mjOBJ_EQUALITY, "neq"), (mujoco.mjtObj.mjOBJ_ACTUATOR, "nu"),
           (mujoco.mjtObj.mjOBJ_CAMERA, "ncam"), (mujoco.mjtObj.mjOBJ_SENSOR, "nsensor"),
           (mujoco.mjtObj.mjOBJ_KEY, "nkey")]


def _unnamed(m):
    out = []
    for obj, count in OBJECTS:
        for i in range(getattr(m, count)):
            if obj == mujoco.mjtObj.mjOBJ_BODY and i == 0:
                continue                                   # the world body
            if not mujoco.mj_id2name(m, obj, i):
                out.append(f"{obj.name} #{i}")
    return out


@pytest.fixture(scope="module", params=NAMES)
def exported(request):
    mech = analytic.load(request.param)
    skip_without_cam_contact(mech)
    xml = service.export_mjcf(mech)
    return mech, mujoco.MjModel.from_xml_string(xml)


def test_every_element_of_a_generated_model_is_named(exported):
    mech, m = exported
    assert not _unnamed(m)
    # the file's names: a body per link, a site per point
    assert {m.body(i).name for i in range(1, m.nbody)} == set(mech.links)
    assert set(mech.points) <= {m.site(i).name for i in range(m.nsite)}


def test_a_generated_model_closes_every_loop_as_written_and_at_home(exported):
    mech, m = exported
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)                      # the default pose, qpos = 0: no keyframe applied
    tol = 1e-12 * max(mech.size, 1.0)            # rounding of body and site poses
    rows = {mujoco.mjtEq.mjEQ_CONNECT: 3, mujoco.mjtEq.mjEQ_TENDON: 1}   # a loop closure; a gear coupling
    assert d.ne == sum(rows[mujoco.mjtEq(t)] for t in m.eq_type)
    assert np.abs(d.efc_pos[:d.ne]).max(initial=0.0) < tol
    mujoco.mj_resetDataKeyframe(m, d, m.key("home").id)
    mujoco.mj_forward(m, d)
    assert np.abs(d.efc_pos[:d.ne]).max(initial=0.0) < tol
    # ... and the home keyframe's velocities keep them closed: constraint velocity ~ 0
    assert np.abs(d.efc_vel[:d.ne]).max(initial=0.0) < 1e-9 * max(mech.size, 1.0) * 2 * math.pi


def test_a_generated_model_steps_without_warnings_and_deterministically(exported):
    mech, m = exported
    runs = []
    for _ in range(2):
        d = mujoco.MjData(m)
        mujoco.mj_resetDataKeyframe(m, d, m.key("home").id)
        q0 = d.qpos.copy()
        for _ in range(100):
            mujoco.mj_step(m, d)
        assert all(w.number == 0 for w in d.warning), [w.number for w in d.warning]
        assert np.abs(d.qpos - q0).max() > 1e-3            # it moves
        runs.append(np.concatenate([d.qpos, d.qvel, d.qacc]))
    assert np.array_equal(runs[0], runs[1])


def test_generated_lengths_read_back():
    mech = analytic.load("fourbar", l1=0.07, l2=0.23, l3=0.19, l4=0.21, ex=-0.04, ey=0.06, phi1_0=1.0)
    b = model.build(mech)
    d = mujoco.MjData(b.model)
    d.qpos[:] = b.qpos0
    mujoco.mj_forward(b.model, d)
    w = lambda s: d.site(s).xpos[:2].copy()                 # noqa: E731
    tol = 1e-12                                              # rounding of body/site poses
    assert abs(np.linalg.norm(w("B") - w("A")) - 0.07) < tol
    assert abs(np.linalg.norm(w("C") - w("B")) - 0.23) < tol
    assert abs(np.linalg.norm(w("C") - w("D")) - 0.19) < tol
    assert abs(np.linalg.norm(w("D") - w("A")) - 0.21) < tol
    e = b.model.site("E").pos                                 # E in the coupler frame (origin B, x to C)
    assert abs(e[0] - (-0.04)) < tol and abs(e[1] - 0.06) < tol


# ------------------------------------------------------------------------------ hand-written files
HAND = keyframes.FILES


@pytest.mark.parametrize("name", HAND)
def test_hand_written_files_are_named_and_their_keyframe_is_the_analytic_solution(name):
    m = mujoco.MjModel.from_xml_path(str(keyframes.HERE / f"{name}.xml"))
    assert not _unnamed(m)
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key("home").id)
    mujoco.mj_forward(m, d)
    assert np.abs(d.efc_pos[:d.ne]).max() < 1e-12           # rounding level; positions ~0.5 m
    # The keyframe's numbers against the analytic solution at SPEC defaults, joint by joint (read from the
    # compiled model, never as text: the last printed digit may differ between numpy/libm builds).
    # 1e-12: rounding of a solve whose values are O(1) rad, m and rad/s.
    state, ctrl = keyframes.joint_state(name)
    key = m.key("home")
    for joint, (q, v) in state.items():
        assert abs(key.qpos[m.joint(joint).qposadr[0]] - q) < 1e-12, (joint, "qpos")
        assert abs(key.qvel[m.joint(joint).dofadr[0]] - v) < 1e-12, (joint, "qvel")
    assert np.abs(key.ctrl - np.asarray(ctrl)).max() < 1e-12


POINT_SITES = {"fourbar": ("E", "E"), "sixbar": ("C", "C"), "fivebar": ("P", "P")}


@pytest.mark.parametrize("name", HAND)
def test_hand_written_and_generated_models_trace_the_same_output_path(name):
    # Both models simulate 1/4 turn from the same state; the output point's world path must agree within
    # the comparison's position tolerance (1e-6 of the size): the hand-written model's velocity servo
    # lags its crank by up to ~1e-3 rad, so it is compared at its own simulated crank angle through the
    # analytic solution, and the generated model likewise.
    mech = analytic.load(name)
    hand = mujoco.MjModel.from_xml_path(str(keyframes.HERE / f"{name}.xml"))
    hand.body_invweight0[:] *= model.REGULARIZATION_SCALE      # as the generated models (XML cannot say it)
    d = mujoco.MjData(hand)
    mujoco.mj_resetDataKeyframe(hand, d, hand.key("home").id)
    site = POINT_SITES[name][0]
    inputs = [i for i in mech.inputs]
    joints = {"fourbar": ["A"], "sixbar": ["O2"], "fivebar": ["A", "D"]}[name]
    worst = 0.0
    for _ in range(125):
        mujoco.mj_step(hand, d)
        q = np.array([[d.joint(j).qpos[0] for j in joints]])
        ref = mech.solve(q)
        p = mech.output_point
        worst = max(worst, float(np.hypot(d.site(site).xpos[0] - ref["x" + p][0], d.site(site).xpos[1] - ref["y" + p][0])))
    assert worst < 1e-6 * mech.size, worst
    built, tr = service.simulate(mech, 0.25)
    assert len(inputs) == len(joints)
    sim_ref = mech.solve(np.column_stack([tr.inputs[i.q] for i in inputs]))
    p = mech.output_point
    gen = np.hypot(tr.outputs["x" + p] - sim_ref["x" + p], tr.outputs["y" + p] - sim_ref["y" + p]).max()
    assert gen < 1e-6 * mech.size
