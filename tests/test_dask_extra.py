"""Dask is an optional extra: the package's own dependencies leave it out, and every ``--scheduler`` path
says in one line how to install it where it is missing (exit code 2, no traceback)."""

import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from analytic import ParameterError
from sim.run.parallel import mapper

ROOT = Path(__file__).resolve().parents[1]
INSTALL = "pip install 'linkage[dask]'"


def test_dask_is_an_extra_that_the_test_extra_brings():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    names = [d.split("[")[0].split(">")[0].strip().lower() for d in project["dependencies"]]
    assert "dask" not in names and "distributed" not in names, names
    extras = project["optional-dependencies"]
    assert any(d.startswith("dask[distributed]") for d in extras["dask"])
    assert any(d.startswith("linkage[") and "dask" in d for d in extras["test"]), extras["test"]


@pytest.mark.parametrize("scheduler", ["local", "tcp://127.0.0.1:9"])
def test_the_scheduler_without_dask_names_the_extra(monkeypatch, scheduler):
    # None in sys.modules makes the import fail as if Dask were not installed
    monkeypatch.setitem(sys.modules, "dask", None)
    monkeypatch.setitem(sys.modules, "dask.distributed", None)
    with pytest.raises(ParameterError) as info:
        with mapper(2, scheduler):
            pass
    assert INSTALL in str(info.value) and "\n" not in str(info.value)


BLOCK_DASK = ("import sys; sys.modules['dask'] = None; sys.modules['dask.distributed'] = None\n"
              "from sim.front.cli import main\nsys.exit(main(sys.argv[1:]))")


@pytest.mark.parametrize("args", [
    ["sweep", "fivebar", "--vary", "l1=0.2,0.25", "--scheduler", "local"],
    ["tolerance", "fourbar", "--tol", "l1=+-0.0005", "--samples", "8", "--scheduler", "local"],
    ["synthesize", "path", "TARGETS", "--restarts", "1", "--generations", "2", "--scheduler", "local"],
])
def test_each_scheduler_command_without_dask_says_how_to_install_it(tmp_path, args):
    targets = tmp_path / "t.csv"
    targets.write_text("x,y\n1,0\n0,1\n-1,0\n0,-1\n0.7,0.7\n")
    args = [str(targets) if a == "TARGETS" else a for a in args]
    r = subprocess.run([sys.executable, "-c", BLOCK_DASK, *args], capture_output=True, text=True, cwd=ROOT,
                       timeout=120)
    assert r.returncode == 2, (r.returncode, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and INSTALL in lines[0], r.stderr
