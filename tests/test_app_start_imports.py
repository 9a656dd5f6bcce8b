"""What ``linkage app`` loads before its first request (benchmarks/RESULTS-2026-11-27.md: the app's import of
the motor types pulled in scipy.integrate, ~0.6 s of CPU and ~40 MB of memory at every start, where the
version before loaded only numpy): the server module loads none of the heavy libraries; a request that needs
one loads it then."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
HEAVY = ("scipy", "matplotlib", "mujoco", "dask", "SALib", "pymoo", "shapely", "ezdxf", "trimesh", "build123d")


def test_the_app_server_module_loads_no_heavy_library():
    code = ("import sys\nimport sim.front.app\n"
            f"print(sorted(m for m in {HEAVY!r} if m in sys.modules))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "[]", r.stdout


def test_the_motor_module_loads_scipy_only_when_a_run_integrates():
    """The motor types load and work without scipy (the runs, which integrate with solve_ivp and import it
    then, are tests/test_dynamics_motor.py's)."""
    code = ("import sys\nimport analytic\nfrom analytic.applications import motor\n"
            "before = 'scipy' in sys.modules\n"
            "m = motor.LinearMotor(2.0, 20.0)\n"
            "print(before, m.torque(10.0))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert r.returncode == 0, r.stderr
    before, torque = r.stdout.split()
    assert before == "False"
    assert abs(float(torque) - 1.0) < 1e-12    # T0 (1 - w / W0) = 2 (1 - 10/20) = 1 N m; rounding only
