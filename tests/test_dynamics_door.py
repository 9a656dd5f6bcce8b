"""Issue 39: the command line's ``linkage dynamics`` and the app's dynamics panel run the one door function
(:func:`linkage.dynamics`) with keywords, and the MuJoCo run's step bound is the door's (checked before MuJoCo
takes a step), so both see it: the app passes its own bound (MAX_DYNAMICS_STEPS), the command line the
simulation's cap. Before, the app called the service layer for the reduced run and did the step check itself."""

from __future__ import annotations

import functools
import json
import re

import pytest

import linkage
import linkage.api
from sim.front import app
from tests.app_client import post
from tests.cli_runner import run


def test_the_command_line_and_the_app_call_the_door_with_keywords(server, monkeypatch):
    calls = []
    real = linkage.api.dynamics

    @functools.wraps(real)                       # the app reads the door's keywords off its signature
    def spy(mech, *args, **kw):
        calls.append((args, kw))
        return real(mech, *args, **kw)
    monkeypatch.setattr(linkage, "dynamics", spy)
    r = run("dynamics", "fourbar", "--motor", "2,15.7", "--revolutions", "2", "--json")
    assert r.returncode == 0, r.stderr
    status, body = post(server, "/api/dynamics", {"mechanism": "fourbar", "motor": {"T0": 2, "W0": 15.7},
                                                  "revolutions": 2})
    assert status == 200, body
    assert len(calls) == 2 and calls[0][0] == () and calls[1][0] == ()          # keywords only, both
    (_, cli), (_, page) = calls
    assert page["max_steps"] == app.MAX_DYNAMICS_STEPS and cli.get("max_steps") is None
    assert page.get("simulate", True) is True and cli.get("simulate", True) is True
    # the same run asked for, and answered alike: MuJoCo's mean speed from both
    assert page["revolutions"] == cli["revolutions"] == 2
    cli_out = json.loads(r.stdout)
    assert body["simulated"]["mean_speed"] == pytest.approx(cli_out["simulated"]["mean_speed"], rel=1e-12)


def test_the_step_bound_is_the_doors_and_refuses_before_mujoco(monkeypatch):
    from sim.service import dynamics as D
    mech = linkage.load("fourbar")
    d = linkage.dynamics(mech, motor=(2.0, 15.7), revolutions=3)        # the run the bound is about
    taken = len(d.run.sim.t) - 1                                         # MuJoCo's steps

    def no_mujoco(*a, **k):
        raise AssertionError("MuJoCo was run past the bound")
    monkeypatch.setattr(D, "simulated", no_mujoco)
    with pytest.raises(linkage.ParameterError) as e:
        linkage.dynamics(mech, motor=(2.0, 15.7), revolutions=3, max_steps=100)
    text = str(e.value)
    assert re.search(r"^MuJoCo would take about [0-9,]+ steps of [0-9.e-]+ s for this run \(at most 100\): lower the "
                     r"revolutions", text), text
    predicted = int(re.search(r"about ([0-9,]+) steps", text).group(1).replace(",", ""))
    # the prediction (the reduced run's duration over the step) against the steps MuJoCo took: the run ends
    # at its last revolution's end, to within a step, and the two models' durations agree to their tolerance
    assert predicted == pytest.approx(taken, rel=0.01)
    linkage.dynamics(mech, motor=(2.0, 15.7), revolutions=3, simulate=False)   # the reduced equation alone runs
    with pytest.raises(linkage.ParameterError, match="max_steps"):
        linkage.dynamics(mech, motor=(2.0, 15.7), max_steps=0)
