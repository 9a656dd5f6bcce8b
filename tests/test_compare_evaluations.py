"""The compare's cheaper paths (issue 38) give what the plain ones give: the step's peak rate with each interval
evaluated once (a dwell's plateau of maxima, a steady rate), the energies read from the end-of-step evaluations
of a run with loads (also when the forces check's replay carries them), a cam's contact force (MuJoCo's own
mj_contactForce), and the model's MJCF written only for an export."""

from __future__ import annotations

import math

import numpy as np
import pytest

import analytic
from analytic.cycle import Cycle
from sim import service
from sim.model.timestep import peak_rates


def _plain_peak(cycle) -> float:
    """The peak rate as first written: every sampled maximum's two intervals, each by the cubic Hermite
    interpolant (a link's omega, a slide's ds) or the parabola through three samples, no interval shared."""
    mech, t, r = cycle.mech, cycle.t, cycle.rates()
    best = float(r.max())
    sol, size = cycle.solution, mech.size
    pad = np.pad(r, ((1, 1), (0, 0)), constant_values=-np.inf)
    top = (pad[1:-1] >= pad[:-2]) & (pad[1:-1] >= pad[2:])
    top[0] = top[-1] = False
    hermite, c = {}, 2 * len(mech.inputs)
    for ln in mech.links:
        hermite[c] = (np.asarray(sol["omega" + ln]), np.asarray(sol["alpha" + ln]))
        c += 2
    for j in mech.slides:
        hermite[c] = (np.asarray(sol["ds" + j]) / size, np.asarray(sol["dds" + j]) / size)
        c += 2
    u = np.linspace(0.0, 1.0, 65)
    for col in range(r.shape[1]):
        for i in np.flatnonzero(top[:, col]):
            if col in hermite:
                y, dy = hermite[col]
                for a, b in ((i - 1, i), (i, i + 1)):
                    h = t[b] - t[a]
                    v = (y[a] * (2 * u ** 3 - 3 * u ** 2 + 1) + h * dy[a] * (u ** 3 - 2 * u ** 2 + u)
                         + y[b] * (-2 * u ** 3 + 3 * u ** 2) + h * dy[b] * (u ** 3 - u ** 2))
                    best = max(best, float(np.max(np.abs(v))))
                continue
            (t0, t1, t2), (y0, y1, y2) = t[i - 1:i + 2], r[i - 1:i + 2, col]
            d1, d2 = (y1 - y0) / (t1 - t0), (y2 - y1) / (t2 - t1)
            curv = (d2 - d1) / (t2 - t0)
            if curv < 0:
                tv = 0.5 * (t0 + t1) - d1 / (2 * curv)
                if t0 <= tv <= t2:
                    best = max(best, y1 + d1 * (tv - t1) + curv * (tv - t0) * (tv - t1))
    return best


@pytest.mark.parametrize("name", ["fourbar", "cam_roller", "servo_press", "jansen", "watt_six_bar"])
def test_the_peak_rate_is_the_plain_scans(name):
    """cam_roller and servo_press dwell (plateaus of maxima), the cam and the cranks turn steadily (every sample
    a maximum); jansen's peak is a parabola's between samples, watt_six_bar's a Hermite interpolant's past the
    first interval of a link's maxima."""
    cycle = Cycle.of(analytic.load(name), 1.0)
    fast, plain = peak_rates(cycle), _plain_peak(cycle)
    # the same interpolants at the same points, the loop's arithmetic in scalars: rounding only
    assert math.isclose(fast, plain, rel_tol=1e-12), (fast, plain)


def test_a_loaded_runs_energies_come_from_its_end_of_step_evaluations():
    """cam_roller carries its spring as a load: the end-of-step accelerations are evaluated at every step, and
    the energies read there are sim.run.simulate.energies' (a fresh evaluation of each state)."""
    from sim.model.loads import wrenches
    from sim.run.compare import _end_accelerations
    from sim.run.simulate import controls, energies
    built, tr = service.simulation.simulate(analytic.load("cam_roller"), 1.0, None, None, None)
    assert built.loadset is not None
    t = np.arange(len(tr.t)) * tr.timestep
    steps = np.arange(len(tr.t) - 1)
    ends, (kinetic, potential) = _end_accelerations(built, tr, steps, controls(built, t), wrenches(built, t).xfrc,
                                                    energy=True)
    ref_kinetic, ref_potential = energies(built, tr)
    scale = np.max(np.abs(ref_kinetic)) + np.max(np.abs(ref_potential))
    # one state, one evaluation: the same MuJoCo arithmetic (the controls and wrenches do not enter it)
    np.testing.assert_allclose(kinetic, ref_kinetic, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(potential, ref_potential, rtol=0, atol=1e-12 * scale)
    assert sorted(ends) == steps.tolist()


def test_only_an_export_writes_the_models_mjcf():
    from sim.model import Settings, build, export_xml
    mech = analytic.load("fourbar")
    plain = build(mech, Settings())
    assert plain.spec_xml == ""
    with pytest.raises(ValueError, match="export=True"):
        export_xml(plain)
    assert "<mujoco" in export_xml(build(mech, Settings(), export=True))


def test_the_forces_replay_carries_the_end_of_step_evaluations(monkeypatch):
    """compare has the forces check's replay carry the work balance's end-of-step evaluations (each step's end
    state under that step's controls and the file's wrenches: only the acceleration stage redone,
    mj_forwardSkip): they are a fresh mj_forward of each end state, and its energies simulate.energies'."""
    import mujoco

    from sim.model.loads import wrenches
    from sim.run import compare as C
    from sim.run import forces as SF
    from sim.run import simulate as S
    built, tr = service.simulation.simulate(analytic.load("cam_roller"), 1.0, None, None, None)
    ends = C.end_evaluations(tr, built)
    SF.record(built, tr, np.arange(len(tr.t)), ends.request)        # the cam's forces check replays every step

    def nothing_left(built, tr, ends, pending):
        raise AssertionError(f"{len(pending)} end states left for a separate evaluation")
    monkeypatch.setattr(S, "_evaluate_ends", nothing_left)
    carried, (kinetic, potential) = ends.answer()
    model = built.model
    data = mujoco.MjData(model)
    t = np.arange(len(tr.t)) * tr.timestep
    ctrl, xfrc = S.controls(built, t), wrenches(built, t).xfrc
    dofs = [model.jnt_dofadr[model.joint(d.joint).id] for d in built.drives]
    fresh = np.empty((len(tr.t) - 1, len(dofs)))
    for k in range(len(tr.t) - 1):
        data.qpos[:], data.qvel[:], data.act[:] = tr.qpos[k + 1], tr.qvel[k + 1], tr.act[k + 1]
        data.ctrl[:], data.xfrc_applied[:] = ctrl[k], xfrc[k]
        mujoco.mj_forward(model, data)
        fresh[k] = data.qacc[dofs]
    assert sorted(carried) == list(range(len(tr.t) - 1))
    got = np.array([carried[k] for k in range(len(tr.t) - 1)])
    # the same evaluation of the same state and inputs (the skipped stages read neither ctrl nor xfrc_applied,
    # the solver starts from qacc_warmstart, which only mj_step writes): rounding at most
    np.testing.assert_allclose(got, fresh, rtol=0, atol=1e-12 * np.max(np.abs(fresh)))
    ref_kinetic, ref_potential = S.energies(built, tr)
    scale = np.max(np.abs(ref_kinetic)) + np.max(np.abs(ref_potential))
    # one state, one evaluation (energy depends on the state alone): rounding at most
    np.testing.assert_allclose(kinetic, ref_kinetic, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(potential, ref_potential, rtol=0, atol=1e-12 * scale)


@pytest.mark.parametrize("name", ["cam_fourbar", "cam_flat"])
def test_a_cams_contact_force_is_mujocos_contact_force(name):
    """The replay's cam contact force (its efc rows after the loops' equality rows, mapped to the bodies of
    their contacts) is the sum of MuJoCo's own mj_contactForce normal components over the contacts between the
    cam and its follower: cam_fourbar has loop rows before its contacts, cam_flat's face touches up to 12."""
    import mujoco

    from sim.run import forces as SF
    built, tr = service.simulation.simulate(analytic.load(name), 1.0, None, None, None)
    model = built.model
    data = mujoco.MjData(model)
    pairs = SF.cam_pairs(model, built.mech)
    got, ref, contacts = [], [], 0
    for k in range(0, len(tr.t), 10):
        data.qpos[:], data.qvel[:], data.act[:] = tr.qpos[k], tr.qvel[k], tr.act[k]
        mujoco.mj_forward(model, data)
        got.append(SF.contact_forces(model, data, pairs))
        row = np.zeros(len(pairs))
        f = np.zeros(6)
        for i in range(data.ncon):
            c = data.contact[i]
            if c.efc_address < 0:                   # a contact beyond its margin: no constraint row
                continue
            bodies = {int(model.geom_bodyid[c.geom[0]]), int(model.geom_bodyid[c.geom[1]])}
            for j, pair in enumerate(pairs):
                if bodies == set(pair):
                    mujoco.mj_contactForce(model, data, i, f)
                    row[j] += f[0]
                    contacts += 1
        ref.append(row)
    got, ref = np.array(got), np.array(ref)
    assert contacts > len(got)                      # the samples hold contacts, several at a time
    # the same constraint forces read by another route (one row per frictionless contact): rounding at most
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12 * np.max(np.abs(ref)))
