"""Check and analyze do bounded work (issue 32: mutated links-and-joints files ran past 20 s): the
assembly scan refines each dead point with few solves (a numerically solved group pays a fixed cost per
solve), to the same precision; a long value in a refused file is cut in the one-line message."""

import math

import numpy as np
import pytest

import analytic
from analytic.applications import figures


def _counting(mech):
    calls = []
    solve = mech.solve

    def counted(*args, **kwargs):
        calls.append(np.size(args[0]) if args else 0)
        return solve(*args, **kwargs)
    object.__setattr__(mech, "solve", counted) if hasattr(mech, "__dataclass_fields__") else setattr(
        mech, "solve", counted)
    return calls


def test_dead_points_by_hand_with_few_solves():
    """Non-Grashof four-bar l1 0.2, l2 0.3, l3 0.1, l4 0.3: coupler and rocker align where |BD| = 0.4 or
    0.2, i.e. cos(phi1) = (l1^2 + l4^2 - |BD|^2) / (2 l1 l4) = -0.25 and 0.75."""
    mech = analytic.load("fourbar").with_values(l1=0.2, l3=0.1)
    calls = _counting(mech)
    ranges = figures.assembly_ranges(mech)
    ends = sorted(abs(math.remainder(x, 2 * math.pi)) for r in ranges for x in r)
    want = sorted([math.acos(0.75)] * 2 + [math.acos(-0.25)] * 2)
    # refined to 1e-13 rad and rounded inward: 1e-12 bounds it
    assert np.allclose(ends, want, atol=1e-12), (ends, want)
    # one scan, then each refinement narrows the bracket 17 times: from 2 pi / 3600 to 1e-13 in <= 9 solves
    # (bisection took 34, each paying a numerically solved group's fixed cost)
    assert len(calls) <= 1 + 10, len(calls)


def test_a_long_value_in_a_refused_file_is_cut_in_its_message():
    from analytic import ParameterError
    from analytic.registry import LIBRARY
    text = (LIBRARY / "fivebar.toml").read_text().replace('pivot = "A"', 'pivot = "' + "+".join(["1"] * 300) + '"', 1)
    with pytest.raises(ParameterError) as info:
        analytic.from_text(text, "f.toml")
    msg = str(info.value)
    assert "field 'pivot'" in msg and "..." in msg and len(msg) < 200 and "\n" not in msg
