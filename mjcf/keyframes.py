"""The hand-written MJCF files' ``home`` keyframes, from the analytic solver at SPEC defaults.

The hand-written files (fourbar.xml, sixbar.xml, fivebar.xml) are kept as independent, readable models
of the three built-ins; the simulation itself uses the models generated from the mechanism files
(sim/model.py), and tests/test_models.py checks that both agree. Run ``python -m mjcf.keyframes`` after
changing a file's joint layout or SPEC's default data.
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


def main() -> int:
    for name in FILES:
        path = HERE / f"{name}.xml"
        text = path.read_text()
        new = _KEY.sub(key_element(name), text)
        print(("updated " if new != text else "unchanged ") + str(path))
        if new != text:
            path.write_text(new)
    return 0


if __name__ == "__main__":
    sys.exit(main())
