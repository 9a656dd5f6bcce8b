"""Regenerate the ``home`` keyframes of the MJCF files from the analytic solver at SPEC defaults.

Run ``python -m sim.keyframes`` after changing a model's joint layout or SPEC's default data; the test
suite checks that every file's keyframe equals what this produces and closes every loop.
"""

from __future__ import annotations

import re
import sys

from .model import build, mjcf_path
from .params import CLASSES

_KEY = re.compile(r'<key name="home"[^>]*/>')


def key_element(name: str) -> str:
    """The ``<key name="home" .../>`` element for mechanism ``name`` at SPEC defaults."""
    b = build(CLASSES[name]())
    fmt = lambda xs: " ".join(repr(float(x)) for x in xs)  # noqa: E731 - shortest round-trip digits
    return f'<key name="home" qpos="{fmt(b.qpos0)}" qvel="{fmt(b.qvel0)}" ctrl="{fmt(b.ctrl0)}"/>'


def main() -> int:
    for name in CLASSES:
        path = mjcf_path(name)
        text = path.read_text()
        new = _KEY.sub(key_element(name), text)
        if new != text:
            path.write_text(new)
            print(f"updated {path}")
        else:
            print(f"unchanged {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
