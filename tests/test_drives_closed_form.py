"""An actuator (or a motor) adds no Newton iterations where a dyad solves it in closed form (issue 37): solving
the excavator (three cylinders), the scissor lift (a cylinder under an RRP and two RRRs), the tipper and the 2R
arm over their motion calls none of the iterative solvers' Newton steps.

The count is taken at every Newton entry of the two iterative group solvers: ``general_group._newton`` (the
batch Newton of a general Assur group), its per-sample ``_newton1`` (path tracing) and ``lu_solve`` (one call per
Newton step and per rate solve), ``prismatic_group._newton1`` and ``_solve`` (its Newton steps and rates). The
positive controls (a general group, a group with prismatic pairs) show the counter does count.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import analytic
from analytic.solver import general_group as gg
from analytic.solver import prismatic_group as pg

KINDS = Path(__file__).resolve().parent / "kinds"
NEWTON_ENTRIES = ((gg, "_newton"), (gg, "_newton1"), (gg, "lu_solve"), (pg, "_newton1"), (pg, "_solve"))


@pytest.fixture
def newton_calls(monkeypatch):
    """A counter of calls to every Newton entry (the modules look these names up at call time)."""
    calls = {"n": 0}
    for mod, name in NEWTON_ENTRIES:
        f = getattr(mod, name)

        def counted(*args, _f=f, **kw):
            calls["n"] += 1
            return _f(*args, **kw)
        monkeypatch.setattr(mod, name, counted)
    return calls


def _solve_everything(mech):
    """The motion over its cycle (dense), and one far sample alone (no path from the start)."""
    t = np.linspace(0.0, 1.0, 201)
    (q, _, _), sol = mech.solve_at(t)
    assert np.isfinite(sol[f"x{mech.output_point}"]).all()    # it did solve: a refused pose would be NaN
    mech.solve(q[-1:])
    return q


@pytest.mark.parametrize("source", ["excavator", "scissor_lift", "dump_tipper", "arm_2r",
                                    str(KINDS / "actuator__on_links.toml")])
def test_an_actuator_or_motor_adds_no_newton_iteration(source, newton_calls):
    mech = analytic.load(source)
    assert any(e["kind"] in ("actuator", "motor") for e in mech.geometry.elements)
    _solve_everything(mech)
    assert newton_calls["n"] == 0


@pytest.mark.parametrize("source", ["double_butterfly", str(KINDS / "group__slides.toml")])
def test_the_counter_counts_the_iterative_groups(source, newton_calls):
    _solve_everything(analytic.load(source))
    assert newton_calls["n"] > 0
