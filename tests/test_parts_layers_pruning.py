"""The layers' conflict search measures only what can decide it (issue 30, item 5: ``linkage check`` at once):
the circles it bounds the outlines by never come closer than the outlines, and the pruned search reaches the
same verdicts as the full measurement of every sample (the plane distances of shapely, unpruned)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from analytic.parts import layers, model
from sim import service
from sim.service import parts as parts_service

NAMES = ("fourbar", "sixbar", "whitworth", "klann", "slider_crank")


def _swept(name):
    mech = parts_service.cycle_mechanism(service.load(name), None)
    sweep = model.cycle(mech, parts_service.SAMPLES)
    parts = model.build(mech, sweep)
    return mech, sweep, layers.outlines(mech, parts), model.settings(mech), list(parts)


@pytest.mark.parametrize("name", NAMES)
def test_the_bounding_circles_never_come_closer_than_the_outlines(name):
    mech, sweep, out, _, links = _swept(name)
    for a, b in itertools.combinations(links, 2):
        true = layers.signed_distance(layers.world(out, sweep, a), layers.world(out, sweep, b), depth=False)
        bound = layers.Swept(out, sweep).gap(a, b)
        assert np.all(bound <= true), (a, b, float(np.max(bound - true)))


def test_the_fourbars_crank_and_rocker_are_told_apart_by_their_circles_alone():
    """What the bound is for: the four-bar's crank and rocker (not pinned together) stay farther apart than
    the clearance at every sample by their circles, so none of their 721 poses is measured as polygons."""
    mech, sweep, out, cfg, _ = _swept("fourbar")
    assert np.all(layers.Swept(out, sweep).gap("1", "3") > cfg.clearance)


@pytest.mark.parametrize("name", NAMES)
def test_the_pruned_conflict_search_agrees_with_measuring_every_sample(name):
    """Conflict or not as the full search (penetration depths measured at every sample, refined) says; where
    the uniform samples already come closer than the clearance, the first of them, by brute force."""
    mech, sweep, out, cfg, links = _swept(name)
    thr = cfg.clearance
    for a, b in itertools.combinations(links, 2):
        pruned = layers.pair_distance(mech, out, sweep, a, b, thr, penetration_depth=False,
                                       swept=layers.Swept(out, sweep))
        full = layers.pair_distance(mech, out, sweep, a, b, thr, penetration_depth=True)
        assert (pruned.first is None) == (full.first is None), (a, b)
        d = layers.signed_distance(layers.world(out, sweep, a), layers.world(out, sweep, b), depth=False)
        if np.any(d < thr):
            assert pruned.first == sweep.t[np.argmax(d < thr)], (a, b)


def test_the_layout_is_the_same_with_every_sample_measured(monkeypatch):
    """The whole layout (layers, z, pins, clashes) with the bounds switched off: circles that never prune."""
    for name in ("fourbar", "sixbar", "klann"):
        mech, sweep, out, _, _ = _swept(name)
        parts = model.build(mech, sweep)
        fast = layers.layout(mech, parts, sweep)
        with monkeypatch.context() as m:
            m.setattr(layers.Swept, "gap", lambda self, a, b: np.full(len(self.sweep.t), -np.inf))
            slow = layers.layout(mech, parts, sweep)
        assert (fast.layers, fast.z, fast.pins, fast.clashes, fast.conflicts) == (
            slow.layers, slow.z, slow.pins, slow.clashes, slow.conflicts), name
