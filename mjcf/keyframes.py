"""The hand-written MJCF files' assembled poses and ``home`` keyframes, from the analytic solver at SPEC
defaults.

The hand-written files (fourbar.xml, sixbar.xml, fivebar.xml) are kept as independent, readable models
of the three built-ins; the simulation itself uses the models generated from the mechanism files
(sim/model/build.py), and tests/test_models.py checks that both agree.

Each file draws its bodies in the assembled pose at SPEC defaults, so that the model as written
(qpos = qpos0, before any keyframe) already closes every loop: a hinged body is turned by
``euler="0 0 q"`` and a sliding body is placed at ``pos`` along its slide, and each joint's ``ref`` is
that value q, so qpos0 = q and every joint keeps its meaning (an angle relative to the parent body, a
distance along the slide). The ``home`` keyframe holds the same qpos, plus the velocities and controls.
Run ``python -m mjcf.keyframes`` after changing a file's joint layout or SPEC's default data: it
rewrites those attributes and the keyframe, at full double precision (repr) so that the loops close to
rounding (~1e-16 m).
"""

from __future__ import annotations

import math
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
_KEY = re.compile(r'<key name="home"[^>]*/>')


def _wrap(a) -> float:
    return float(math.remainder(float(a), 2 * math.pi))


def joint_state(name: str) -> tuple[dict[str, tuple[float, float]], list[float]]:
    """{joint: (qpos, qvel)} and the controls of a hand-written file at SPEC defaults."""
    import analytic
    m = analytic.load(name)
    (q, qd, qdd), s = m.solve_at([0.0])
    g = lambda k: float(s[k][0])                                     # noqa: E731
    if name == "fourbar":
        w = float(qd[0, 0])
        return ({"A": (float(q[0, 0]), w), "B": (_wrap(g("phi2") - q[0, 0]), g("omega2") - w),
                 "D": (g("phi3"), g("omega3"))}, [w, 0.0])
    if name == "sixbar":
        w = float(qd[0, 0])
        return ({"O2": (float(q[0, 0]), w), "O4": (g("phi3"), g("omega3")), "s": (g("s"), g("ds")),
                 "B": (_wrap(g("phi4") - g("phi3")), g("omega4") - g("omega3")), "xC": (g("xC"), g("vxC"))},
                [w, 0.0])
    w2, w4 = float(qd[0, 0]), float(qd[0, 1])
    return ({"A": (float(q[0, 0]), w2), "B": (_wrap(g("theta3") - q[0, 0]), g("omega3") - w2),
             "S": (g("S"), g("dS")), "D": (float(q[0, 1]), w4)}, [w2, w4, 0.0])


# The bodies each file draws in its assembled pose, by the joint that moves them.
# Hinged: body -> joint; the body is written turned by euler="0 0 q" about its frame's origin, which is
# where its hinge sits (every hinge of these files has pos = 0).
HINGED = {
    "fourbar": {"crank": "A", "coupler": "B", "rocker": "D"},
    "sixbar": {"crank": "O2", "guide": "O4", "rod": "B"},
    "fivebar": {"crank2": "A", "link3": "B", "crank4": "D"},
}
# Sliding: body -> (joint, y); the body slides along its parent's x axis (class "slider", axis 1 0 0,
# no euler) and is written at pos = (q, y, 0), y a parameter's name or a number. The six-bar's block sits
# at s along the guide bar (frame origin O4, x toward B), its ram at xC on the ram line y = h (world
# frame); the five-bar's block at S along link 3 (frame origin B, x toward C).
SLID = {
    "fourbar": {},
    "sixbar": {"block": ("s", 0.0), "ram": ("xC", "h")},
    "fivebar": {"block": ("S", 0.0)},
}


def pose_attributes(name: str) -> dict[tuple[str, str], dict[str, str]]:
    """{(tag, element name): {attribute: value}}: the assembled pose of ``name``.xml at SPEC defaults.

    Every joint gets ``ref`` = its value q in that pose (so qpos0 = the home keyframe's qpos); every
    hinged body ``euler="0 0 q"``, every sliding body ``pos="q y 0"``."""
    import analytic
    values = analytic.load(name).values
    state, _ = joint_state(name)
    r = lambda x: repr(float(x))                                       # noqa: E731 - round-trip digits
    out: dict[tuple[str, str], dict[str, str]] = {("joint", j): {"ref": r(q)} for j, (q, _) in state.items()}
    for body, j in HINGED[name].items():
        out[("body", body)] = {"euler": f"0 0 {r(state[j][0])}"}
    for body, (j, y) in SLID[name].items():
        y = values[y] if isinstance(y, str) else y
        out[("body", body)] = {"pos": f"{r(state[j][0])} {r(y) if y else 0} 0"}
    missing = set(state) - {j for j, _ in SLID[name].values()} - set(HINGED[name].values())
    if missing:
        raise ValueError(f"{name}: joints {sorted(missing)} move no body listed in HINGED or SLID")
    return out


def _set_attributes(text: str, tag: str, name: str, attrs: dict[str, str]) -> str:
    """``text`` with the attributes of its one ``<tag name="name" ...>`` element set to ``attrs``: an
    existing attribute is replaced in place, a missing one goes after ``pos`` (bodies) or ``class``
    (joints), else after ``name``."""
    elem = re.compile(rf'<{tag}\s+name="{re.escape(name)}"[^>]*>')
    found = elem.findall(text)
    if len(found) != 1:
        raise ValueError(f'{len(found)} elements <{tag} name="{name}"> (need exactly one)')
    head = found[0]
    for attr, value in attrs.items():
        old = re.search(rf'\s{attr}="[^"]*"', head)
        if old:
            head = head[:old.start()] + f' {attr}="{value}"' + head[old.end():]
            continue
        after = None
        for anchor in ("name", "pos" if tag == "body" else "class"):
            a = re.search(rf'\s{anchor}="[^"]*"', head)
            after = a.end() if a else after
        head = head[:after] + f' {attr}="{value}"' + head[after:]
    return text.replace(found[0], head)


def rewrite(name: str, text: str) -> str:
    """``text`` (``name``.xml) with its bodies' assembled poses, joints' refs and home keyframe regenerated."""
    for (tag, element), attrs in pose_attributes(name).items():
        text = _set_attributes(text, tag, element, attrs)
    return _KEY.sub(key_element(name), text)


def key_element(name: str) -> str:
    """The ``<key name="home" .../>`` element of ``name``.xml, joints in the file's order."""
    import mujoco
    model = mujoco.MjModel.from_xml_path(str(HERE / f"{name}.xml"))
    state, ctrl = joint_state(name)
    qpos, qvel = [0.0] * model.nq, [0.0] * model.nv
    for j, (q, v) in state.items():
        qpos[model.joint(j).qposadr[0]] = q
        qvel[model.joint(j).dofadr[0]] = v
    fmt = lambda xs: " ".join(repr(float(x)) for x in xs)  # noqa: E731 - shortest round-trip digits
    return f'<key name="home" qpos="{fmt(qpos)}" qvel="{fmt(qvel)}" ctrl="{fmt(ctrl)}"/>'


FILES = ("fourbar", "sixbar", "fivebar")


def closure(name: str) -> tuple[float, float]:
    """The largest loop-closure error [m] of ``name``.xml as written (qpos0) and at its home keyframe."""
    import mujoco
    import numpy as np
    model = mujoco.MjModel.from_xml_path(str(HERE / f"{name}.xml"))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    as_written = float(np.abs(data.efc_pos[:data.ne]).max(initial=0.0))
    mujoco.mj_resetDataKeyframe(model, data, model.key("home").id)
    mujoco.mj_forward(model, data)
    return as_written, float(np.abs(data.efc_pos[:data.ne]).max(initial=0.0))


def main() -> int:
    worst = 0.0
    for name in FILES:
        path = HERE / f"{name}.xml"
        text = path.read_text()
        new = rewrite(name, text)
        if new != text:
            path.write_text(new)
        as_written, home = closure(name)
        worst = max(worst, as_written, home)
        print(f"{'updated' if new != text else 'unchanged'} {path}: loops closed to {as_written:.1e} m as "
              f"written, {home:.1e} m at home")
    return 0 if worst < 1e-12 else 1          # rounding level at these sizes (~0.5 m); more: a layout error


if __name__ == "__main__":
    sys.exit(main())
