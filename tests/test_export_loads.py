"""``linkage export --mjcf`` writes the file's loads that MJCF can hold statically (sim.model.loads.not_in_xml):
springs, dampers and torsion springs as tendons, constant forces and torques as constant-force actuators; the
others (expressions, tables, part-cycle loads, friction) are listed in the file (custom text, header) and in
a one-line note. Checked by loading the exported file with MuJoCo alone and simulating it: the spring's
generalized force is Hooke's law on the geometry, the punch is 500 N along -x at the piston pin."""

from __future__ import annotations

import math
from pathlib import Path

import mujoco
import numpy as np
import pytest

import analytic
from cli_runner import run

PRESS = Path(__file__).parent / "mechanisms" / "press_loads.toml"


def texts(model) -> dict:
    """The model's custom texts by name."""
    raw = bytes(model.text_data)
    out = {}
    for i in range(model.ntext):
        a = int(model.text_adr[i])
        out[mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_TEXT, i)] = raw[a:a + int(model.text_size[i]) - 1].decode()
    return out


def generalized(model, data, site, f):
    """J_p(site)^T f: the generalized force of a world force f (3,) at a site (MuJoCo's kinematic Jacobian)."""
    jacp = np.zeros((3, model.nv))
    mujoco.mj_jacSite(model, data, jacp, None, model.site(site).id)
    return jacp.T @ f


def exported_press(tmp_path, loads: str):
    """The press with ``loads`` (TOML) in place of its own, written by ``export --mjcf`` and loaded in plain
    MuJoCo at its home keyframe: (model, data)."""
    p = tmp_path / "press.toml"
    p.write_text(PRESS.read_text().split("[[loads]]")[0] + loads)
    out = tmp_path / "press.xml"
    r = run("export", p, "--mjcf", out)
    assert r.returncode == 0 and r.stderr == "", r.stderr
    model = mujoco.MjModel.from_xml_path(str(out))
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("home").id)
    return model, data


def actuator_share(model, data, name: str) -> np.ndarray:
    """The generalized force actuator ``name`` adds: qfrc_actuator with its constant (biasprm[0]) less without."""
    i = model.actuator(name).id
    mujoco.mj_forward(model, data)
    with_it = data.qfrc_actuator.copy()
    constant, model.actuator_biasprm[i, 0] = model.actuator_biasprm[i, 0], 0.0
    mujoco.mj_forward(model, data)
    share = with_it - data.qfrc_actuator
    model.actuator_biasprm[i, 0] = constant
    mujoco.mj_forward(model, data)
    return share


def test_the_exported_press_carries_its_spring_and_punch(tmp_path):
    out = tmp_path / "press.xml"
    r = run("export", PRESS, "--mjcf", out)
    assert r.returncode == 0, r.stderr
    assert "[friction]" in r.stderr and "leaves out" in r.stderr          # one note naming what is left out
    model = mujoco.MjModel.from_xml_path(str(out))
    assert texts(model)["linkage_loads_not_in_model"].startswith("[friction]")
    # the regulariser the file documents (its header): without it a 500 N punch opens the loops by ~4 mm
    scale = float(model.numeric("linkage_invweight0_scale").data[0])
    model.body_invweight0[:] *= scale
    model.tendon_invweight0[:] *= scale
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key("home").id)
    mech = analytic.load(str(PRESS))
    k, free = 2.0 * 1000, 50.0 / 1000              # the file's 2 N/mm and 50 mm, in N/m and m
    anchor = np.array([0.2, 0.06, 0.0])            # ground end [200, 60] mm
    checked = 0
    for step in range(1, 241):
        mujoco.mj_step(model, data)
        if step % 40:
            continue
        mujoco.mj_forward(model, data)
        # the geometry: MuJoCo's piston pin where the solver puts it at the simulated crank angle
        xB, yB = data.site("B").xpos[:2]
        sol = mech.solve(np.array([math.atan2(yB, xB)]))
        c = data.site("C").xpos
        # the loops of a file loaded as it is open by up to 8e-5 of the size (the header's note): 1e-4
        assert math.hypot(c[0] - sol["xC"][0], c[1] - sol["yC"][0]) <= 1e-4 * mech.size
        # Hooke's law from the geometry: tension k (L - L0) pulling the piston end towards the anchor
        end = data.site("load_ret_2").xpos
        assert np.allclose(end, c, atol=1e-12)      # the spring's end is the piston pin, [0, 0] on the piston
        d = end - anchor
        L = float(np.linalg.norm(d))
        f = -k * (L - free) * d / L
        passive = data.qfrc_passive.copy()
        model.tendon_stiffness[model.tendon("load_ret").id] = 0.0
        mujoco.mj_forward(model, data)
        spring = passive - data.qfrc_passive            # the spring's share alone
        model.tendon_stiffness[model.tendon("load_ret").id] = k
        mujoco.mj_forward(model, data)
        want = generalized(model, data, "load_ret_2", f)
        assert abs(k * (L - free)) > 1.0                 # a real tension (tens of N), not a vanishing one
        # rounding of the Jacobian products (1e-15 of the force x lever arms)
        assert np.allclose(spring, want, rtol=0, atol=1e-9 * np.max(np.abs(want)))
        # the punch: 500 N along -x at the piston pin, whatever the pose
        act = data.qfrc_actuator.copy()
        pid = model.actuator("load_punch").id
        model.actuator_biasprm[pid, 0] = 0.0
        mujoco.mj_forward(model, data)
        punch = act - data.qfrc_actuator
        model.actuator_biasprm[pid, 0] = 500.0
        mujoco.mj_forward(model, data)
        assert np.allclose(data.site("load_punch").xpos, c, atol=1e-12)     # at the pin, on the piston
        want = generalized(model, data, "load_punch", np.array([-500.0, 0.0, 0.0]))
        assert np.allclose(punch, want, rtol=0, atol=1e-9 * np.max(np.abs(want)))   # rounding
        checked += 1
    assert checked == 6
    assert np.all(np.isfinite(data.qpos))


def test_loads_mjcf_cannot_hold_are_named(tmp_path):
    text = PRESS.read_text().split("[friction]")[0] + (
        '\n[[loads]]\nname = "gas"\nkind = "force"\nlink = "piston"\npoint = "C"\ndirection = [-1, 0]\n'
        'magnitude = "100 * (1 + cos(phi1))"\n\n[[loads]]\nname = "cut"\nkind = "torque"\nlink = "1"\n'
        'magnitude = -2\nactive = "0deg:90deg"\n')
    p = tmp_path / "press.toml"
    p.write_text(text)
    out = tmp_path / "press.xml"
    r = run("export", p, "--mjcf", out)
    assert r.returncode == 0, r.stderr
    assert "gas (force)" in r.stderr and "cut (torque)" in r.stderr and "[friction]" not in r.stderr
    model = mujoco.MjModel.from_xml_path(str(out))
    names = {model.actuator(i).name for i in range(model.nu)}
    assert "load_punch" in names and "load_gas" not in names and "load_cut" not in names
    left = texts(model)["linkage_loads_not_in_model"]
    assert "gas (force)" in left and "cut (torque)" in left
    head = out.read_text().split("-->")[0]
    assert "NOT in this model" in head and "gas (force)" in head


@pytest.mark.parametrize("frame", ["world", "link"])
def test_a_constant_torque_and_a_link_force_are_actuators(tmp_path, frame):
    # a torque of 3 N mm = 3e-3 N m on the rod: its generalized force is 3e-3 times the rod's angular
    # Jacobian (z); a link-fixed force turns with the rod (its direction in the rod's frame)
    model, data = exported_press(tmp_path, (
        '[[loads]]\nname = "T"\nkind = "torque"\nlink = "2"\nmagnitude = 3\n\n'
        f'[[loads]]\nname = "F"\nkind = "force"\nlink = "2"\nat = [75, 0]\ndirection = [0, 1]\nframe = "{frame}"\n'
        'magnitude = 10\n'))
    for _ in range(50):
        mujoco.mj_step(model, data)
    mujoco.mj_forward(model, data)
    body = model.body("2").id
    jacr = np.zeros((3, model.nv))
    mujoco.mj_jacBody(model, data, None, jacr, body)
    torque = actuator_share(model, data, "load_T")
    assert np.allclose(torque, 3e-3 * jacr[2], rtol=0, atol=1e-12)          # rounding
    force = actuator_share(model, data, "load_F")
    angle = math.atan2(data.xmat[body][3], data.xmat[body][0])            # the rod's angle in the world
    u = np.array([0.0, 1.0, 0.0]) if frame == "world" else np.array([-math.sin(angle), math.cos(angle), 0.0])
    assert abs(angle) > 0.05                        # the rod is turned: world and link directions differ
    want = generalized(model, data, "load_F", 10.0 * u)
    assert np.allclose(force, want, rtol=0, atol=1e-9 * np.max(np.abs(want)))                  # rounding


def test_a_constant_pressure_is_its_force(tmp_path):
    # 0.5 N/mm^2 on 100 mm^2 is 50 N (0.5e6 Pa x 1e-4 m^2) along -x at the piston pin
    model, data = exported_press(tmp_path, (
        '[[loads]]\nname = "gas"\nkind = "pressure"\nlink = "piston"\narea = 100\ndirection = [-1, 0]\n'
        'magnitude = 0.5\n'))
    mujoco.mj_forward(model, data)
    gid = model.actuator("load_gas").id
    assert model.actuator_biasprm[gid, 0] == pytest.approx(50.0, rel=1e-12)          # rounding
    share = actuator_share(model, data, "load_gas")
    want = generalized(model, data, "load_gas", np.array([-50.0, 0.0, 0.0]))
    assert np.allclose(share, want, rtol=0, atol=1e-9 * np.max(np.abs(want)))   # rounding
