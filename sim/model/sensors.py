"""The model's sensors: every point's position, velocity and acceleration, every link's axis and rates, the
drives' joints and forces, the load, and the loop closures' second sites."""

from __future__ import annotations

import mujoco


def add_sensors(spec, mech, drives, loops):
    S = mujoco.mjtSensor
    site, body = mujoco.mjtObj.mjOBJ_SITE, mujoco.mjtObj.mjOBJ_BODY

    def add(name, kind, objtype=None, objname=None):
        s = spec.add_sensor(name=name, type=kind)
        if objtype is not None:
            s.objtype, s.objname = objtype, objname
        return s

    add("time", S.mjSENS_CLOCK)
    for p in mech.points:
        add(f"{p}_pos", S.mjSENS_FRAMEPOS, site, p)
        add(f"{p}_vel", S.mjSENS_FRAMELINVEL, site, p)
        add(f"{p}_acc", S.mjSENS_FRAMELINACC, site, p)
    for ln in mech.links:
        add(f"{ln}_xaxis", S.mjSENS_FRAMEXAXIS, body, ln)
        add(f"{ln}_angvel", S.mjSENS_FRAMEANGVEL, body, ln)
        add(f"{ln}_angacc", S.mjSENS_FRAMEANGACC, body, ln)
    for d in drives:
        s = add(f"{d.joint}_q", S.mjSENS_JOINTPOS)
        s.objtype, s.objname = mujoco.mjtObj.mjOBJ_JOINT, d.joint
        s = add(f"{d.joint}_qd", S.mjSENS_JOINTVEL)
        s.objtype, s.objname = mujoco.mjtObj.mjOBJ_JOINT, d.joint
        s = add(f"tau{d.input.link}", S.mjSENS_ACTUATORFRC)
        s.objtype, s.objname = mujoco.mjtObj.mjOBJ_ACTUATOR, d.actuator
    s = add("load", S.mjSENS_ACTUATORFRC)
    s.objtype, s.objname = mujoco.mjtObj.mjOBJ_ACTUATOR, "load"
    for lp in loops:
        for nm in (lp.site1, lp.site2):
            if nm not in mech.points:
                add(f"{nm}_pos", S.mjSENS_FRAMEPOS, site, nm)
