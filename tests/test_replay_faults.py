"""Faults the forces replay and the work balance's end-of-step evaluations it carries could hide
(benchmarks/mutation.py, the ``ends-``, ``evaluate-ends-``, ``contacts-``, ``settle-`` and ``judged`` rows): each
end evaluation is a fresh ``mj_forward`` of the step's end state under that step's controls and wrenches,
whichever path made it (carried by a replay, evaluated alone after it, or without one); compare's replay
carries every one of a cam's; each cam's contact force is its own pair's; the reader's contact forces are
MuJoCo's; a cam's work balance is reported, not judged, in the text too."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

import analytic
from sim import model as M
from sim import service
from sim.run import compare as C
from sim.run import forces as SF
from sim.run import simulate as S

from cli_runner import run

HERE = Path(__file__).parent

ROUNDING = 1e-12
"""[of the largest value] the same MuJoCo evaluation of the same state and inputs, by another route: rounding
only (the skipped stages read neither ctrl nor xfrc_applied; the solver starts from qacc_warmstart, which only
mj_step writes)."""


def _run(name):
    if name == "fivebar cutting":   # a force on its output's slow stroke only: the load switches twice a turn
        return service.simulation.simulate(service.load("fivebar"), 1.0, None,
                                           M.Loads(force=(-5.0, 0.0), slow_stroke_only=True), None)
    return service.simulation.simulate(analytic.load(name), 1.0, None, None, None)


def _inputs(built, tr):
    """The controls and the file's wrenches (None without loads) at every recorded step's start."""
    t = np.arange(len(tr.t)) * tr.timestep
    if built.loadset is None:
        return S.controls(built, t), None
    from sim.model.loads import wrenches
    return S.controls(built, t), wrenches(built, t).xfrc


def _forward(built, tr, data, state: int, step: int, inputs) -> None:
    """A plain mj_forward of the state recorded at ``state`` under step ``step``'s controls and wrenches, each
    field set apart on ``data``."""
    ctrl, xfrc = inputs
    data.qpos[:], data.qvel[:], data.act[:] = tr.qpos[state], tr.qvel[state], tr.act[state]
    data.ctrl[:] = ctrl[step]
    if xfrc is not None:
        data.xfrc_applied[:] = xfrc[step]
    mujoco.mj_forward(built.model, data)


def _fresh(built, tr, steps) -> np.ndarray:
    """Each drive's qacc at the end of each step k of ``steps``: the state recorded at k + 1 under step k's
    controls and wrenches, by a plain mj_forward on a new MjData."""
    model = built.model
    data, inputs = mujoco.MjData(model), _inputs(built, tr)
    dofs = [model.jnt_dofadr[model.joint(d.joint).id] for d in built.drives]
    out = np.empty((len(steps), len(dofs)))
    for n, k in enumerate(steps):
        _forward(built, tr, data, k + 1, k, inputs)
        out[n] = data.qacc[dofs]
    return out


@pytest.mark.parametrize("how", ["alone", "every step", "the forces check"])
@pytest.mark.parametrize("name", ["cam_roller", "fivebar cutting"])
def test_every_end_evaluation_is_a_fresh_mj_forward_whichever_path_made_it(name, how):
    """cam_roller's spring (the file's loads) changes its wrench at every step; the five-bar's cutting force
    switches at two steps (the load's control), and its second drive is not the model's second dof: each
    end-of-step evaluation, evaluated alone (no replay), carried by a replay of every step, or by the forces
    check's replay of its own steps (some carried, the rest evaluated after it), is the end state's under the
    step's inputs, each drive's own acceleration."""
    built, tr = _run(name)
    ends = C.end_evaluations(tr, built)
    steps = np.asarray(ends.request.steps)
    assert len(steps) >= 2                        # (the five-bar: its two switches; cam_roller: every step)
    if how == "every step":
        SF.record(built, tr, np.arange(len(tr.t)), ends.request)
    elif how == "the forces check":
        SF.check(built, tr, ends=ends.request)
    carried, _ = ends.answer()
    assert sorted(carried) == steps.tolist()
    got = np.array([carried[k] for k in steps.tolist()])
    fresh = _fresh(built, tr, steps)
    np.testing.assert_allclose(got, fresh, rtol=0, atol=ROUNDING * np.max(np.abs(fresh)))


def test_compare_carries_every_end_evaluation_of_a_cam_on_its_forces_replay(monkeypatch):
    """A cam's forces check replays every step, so compare has each end-of-step evaluation carried by it:
    none is left for a separate evaluation (the point of simulate.Ends; the values are the same either way)."""
    built, tr = _run("cam_roller")
    left = []
    monkeypatch.setattr(S, "_evaluate_ends", lambda built, tr, ends, pending: left.append(len(pending)))
    c = C.compare(tr, built)
    assert c.forces is not None and left == [], left


def _by_follower(model, data, followers) -> np.ndarray:
    """The normal force [N] on each follower body of ``followers`` (names) from every contact touching it:
    MuJoCo's mj_contactForce, the contacts attributed by their geoms' bodies (not by the cam pairs)."""
    ids = [model.body(f).id for f in followers]
    row, f = np.zeros(len(ids)), np.zeros(6)
    for i in range(data.ncon):
        c = data.contact[i]
        if c.efc_address < 0:                     # beyond its margin: no constraint row, no force
            continue
        bodies = {int(model.geom_bodyid[c.geom[0]]), int(model.geom_bodyid[c.geom[1]])}
        for j, b in enumerate(ids):
            if b in bodies:
                mujoco.mj_contactForce(model, data, i, f)
                row[j] += f[0]
    return row


def test_two_cams_on_one_shaft_each_report_their_own_followers_contact_force():
    """tests/mechanisms/cam_twin.toml: two cams on one shaft (one body), different laws, springs and followers:
    the replay's contact force of cam k is the force on follower k (its pair matched to its own cam)."""
    built, tr = service.simulation.simulate(analytic.load(HERE / "mechanisms" / "cam_twin.toml"), 1.0, None, None,
                                            None)
    model = built.model
    names = [c.link for c in built.mech.topology.couplings if c.kind == "cam"]
    assert names == ["up", "side"]
    steps = np.arange(0, len(tr.t), 10)
    got = SF.record(built, tr, steps).contact
    data, inputs = mujoco.MjData(model), _inputs(built, tr)
    ref = np.empty_like(got)
    for n, k in enumerate(steps):
        _forward(built, tr, data, k, k, inputs)
        ref[n] = _by_follower(model, data, names)
    peak = np.max(np.abs(ref))
    # the two followers' forces differ (a swap would show): measured apart by 0.67 of the peak (102 N) at most
    assert np.max(np.abs(ref[:, 0] - ref[:, 1])) > 0.2 * peak
    # the same constraint forces read by another route: rounding at most
    np.testing.assert_allclose(got, ref, rtol=0, atol=ROUNDING * peak)


def test_the_replays_contact_force_is_mujocos_with_loop_rows_before_it():
    """cam_fourbar: the loops' equality rows and the cam's contact rows together. The reader's settle (the dual
    solve of equality rows) is for equalities alone; the replay's contact force is mj_contactForce's of a plain
    mj_forward of the same state."""
    built, tr = _run("cam_fourbar")
    model = built.model
    steps = np.arange(0, len(tr.t), 10)
    got = SF.record(built, tr, steps).contact[:, 0]
    follower = next(c.link for c in built.mech.topology.couplings if c.kind == "cam")
    data, inputs = mujoco.MjData(model), _inputs(built, tr)
    ref = np.empty(len(steps))
    for n, k in enumerate(steps):
        _forward(built, tr, data, k, k, inputs)
        ref[n] = _by_follower(model, data, [follower])[0]
    assert np.count_nonzero(ref) > len(ref) // 2             # the samples hold contacts
    # the same evaluation's forces: rounding at most
    np.testing.assert_allclose(got, ref, rtol=0, atol=ROUNDING * np.max(np.abs(ref)))


def test_compares_text_says_a_cams_work_balance_is_reported_not_judged():
    """The text's work balance line gives WORK_TOL where the balance is judged (a four-bar) and says it is not
    judged with a cam (cam_roller), as the JSON's work_tol (null with a cam) does."""
    lines = {}
    for name in ("fourbar", "cam_roller"):
        r = run("compare", name)
        assert r.returncode == 0, r.stdout + r.stderr
        lines[name] = next(ln for ln in r.stdout.splitlines() if ln.strip().startswith("work balance"))
    assert "(tol 1e-03)" in lines["fourbar"] and "not judged" not in lines["fourbar"], lines["fourbar"]
    assert "reported, not judged" in lines["cam_roller"] and "tol 1e-03" not in lines["cam_roller"], lines["cam_roller"]


def test_a_replay_that_reads_the_energies_leaves_the_models_flags_as_it_found_them():
    """The replay enables MuJoCo's energy for a request that reads it, and only for its own evaluations: the
    built model (kept by the app and the sweeps for further runs) has its enable and disable flags back."""
    built, tr = _run("cam_roller")
    model = built.model
    before = (int(model.opt.enableflags), int(model.opt.disableflags))
    ends = C.end_evaluations(tr, built)
    assert ends.request.energy                    # cam_roller's spring: the energies come from these evaluations
    SF.record(built, tr, np.arange(0, len(tr.t), 3), ends.request)     # some carried, the rest evaluated after
    ends.answer()
    assert (int(model.opt.enableflags), int(model.opt.disableflags)) == before
    assert not before[0] & mujoco.mjtEnableBit.mjENBL_ENERGY
