"""One MuJoCo frame of cam_roller at 1.3x its jump speed, at the step of the largest gap between the roller and
the cam (the follower in flight), with the model's own camera: the picture of SPEC "Cams and followers".

    PYTHONPATH=. MUJOCO_GL=egl python renders/readme/cam_jump_frame.py [renders/readme/cam_roller_jump.png]
"""

from __future__ import annotations

import json
import sys

import mujoco
import numpy as np

from sim import service
from sim.model.cam_contact import SEPARATION_GAP, readings


def main(out: str = "renders/readme/cam_roller_jump.png") -> None:
    from sim.front.cli import main as cli
    import contextlib
    import io
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        cli(["forces", "cam_roller", "--json"])
    wj = json.loads(buf.getvalue())["cams"]["c1"]["jump_speed"]
    w = 1.3 * wj
    mech = service.load("cam_roller", {"omega1": repr(w)})
    built, tr = service.simulate(mech, 1.0)
    m = built.model
    d = mujoco.MjData(m)
    sens = []
    for k in range(len(tr.t)):
        d.qpos[:], d.qvel[:] = tr.qpos[k], tr.qvel[k]
        mujoco.mj_forward(m, d)
        sens.append(d.sensordata.copy())
    size = 0.048
    force, gap = readings(m, np.array(sens), "c1", 4 * SEPARATION_GAP * size)
    # the frame where the follower is farthest above the law (linkage's closed form at the simulated input)
    ref = mech.solve(np.asarray(tr.inputs["phi1"])[:, None])
    lifts = np.asarray(tr.outputs["sfollower"]) - np.asarray(ref["sfollower"])
    k = int(np.argmax(lifts))
    lift = float(lifts[k])
    d.qpos[:] = tr.qpos[k]
    mujoco.mj_forward(m, d)
    print(f"largest measured gap {gap.max() * 1e3:.3f} mm (the sensor's margin: {4 * SEPARATION_GAP * size * 1e3:.3f} mm)")
    print(f"jump speed {wj:.2f} rad/s, run at {w:.2f}; frame at step {k}, cam angle "
          f"{tr.inputs['phi1'][k] % (2 * np.pi):.3f} rad, follower {lift * 1e3:.2f} mm above the law; "
          f"cams {tr.cams}")
    m.vis.global_.offwidth, m.vis.global_.offheight = 800, 800
    with mujoco.Renderer(m, height=800, width=800) as r:
        cam = mujoco.MjvCamera()
        cam.type = mujoco.mjtCamera.mjCAMERA_FREE
        cam.lookat[:] = [0.0, 0.03, 0.0]
        cam.distance, cam.azimuth, cam.elevation = 0.22, 90.0, -90.0
        r.update_scene(d, camera=cam)
        img = r.render()
    from PIL import Image
    Image.fromarray(img).save(out)
    print("wrote", out)


if __name__ == "__main__":
    main(*sys.argv[1:])
