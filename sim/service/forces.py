"""Joint forces along the motion (``linkage forces``): Newton-Euler per group with the loads, the peaks,
the records and tables, balancing, and MuJoCo's answer."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from analytic import ParameterError, kinds
from analytic.checks import check_forces_singular, measured_outputs  # noqa: F401 (the service's names)
from analytic.checks import singular_text as _singular_text
from analytic.mechanism import Mechanism
from sim.service.analysis import (BYTES_PER_VALUE, check_memory, check_range, check_revolutions, check_samples,
                                  check_turns_fully)


@dataclass(frozen=True)
class ForceRun:
    """One run of ``linkage forces``: the motion (``t`` [s], the inputs ``q, qd, qdd`` of shape (N, k) and
    their columns ``inputs``), the mass model, the loads applied (``loads``: a JSON-ready description), the
    joint forces, and with balancing the counterweights (``balance``) and the forces with them (``balanced``)."""

    mech: Mechanism
    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    inputs: dict
    solution: object
    inertias: dict
    sources: dict
    loads: dict
    forces: object
    balance: object = None
    balanced: object = None
    loaded: object = None
    """The kinetostatics with the file's and the command line's loads (:class:`analytic.loads.kinetostatics.Loaded`)."""
    loadset: object = None
    energy: dict | None = None
    """Each load's work per cycle, friction's dissipation and the energy balance (sim.service.loads.energy_of)."""
    pressure: float | None = None
    """The supply pressure [Pa] to size the actuators for (``--pressure``), or None."""
    rest: object = None
    """Where the mechanism has a cam: the solution at the run's poses at rest (no rates), for :func:`jump_speed`."""


def _local_at_start(mech: Mechanism, t: np.ndarray, sol):
    """Every link's points in its frame (analytic.mass.local_points) from the run's first sample where the run
    starts at t = 0 (the pose the mass model is built at), else None (solved there)."""
    from analytic import mass
    if len(t) == 0 or t[0] != 0.0 or not bool(np.asarray(sol.valid)[0]):
        return None
    points = {p: (float(sol["x" + p][0]), float(sol["y" + p][0])) for p in mech.points}
    frames = {ln: (points[mech.link_origins[ln]][0], points[mech.link_origins[ln]][1],
                   math.atan2(float(sol["sin" + ln][0]), float(sol["cos" + ln][0]))) for ln in mech.links}
    return mass.local_points(mech, points, frames)


def _load_window(mech: Mechanism, q1: np.ndarray):
    """1 where a cutting force acts (the output point's slow stroke along x), else 0: the simulation's switch
    (sim.model.drives.load_switch) on the first input's phase; and the window (lo, hi) [rad of phase]."""
    from analytic.checks import slow_stroke
    lo, hi = slow_stroke(mech)
    phase = np.mod(q1 - mech.inputs[0].motion.q0, 2 * math.pi)
    on = ((phase >= lo) & (phase <= hi)) | ((phase + 2 * math.pi >= lo) & (phase + 2 * math.pi <= hi))
    return on.astype(float), (lo, hi)


def mass_sources(mech: Mechanism, given: dict | None) -> dict[str, str]:
    """Where each link's mass comes from: --inertia, [inertia], [mass] or the default; "+ counterweight"."""
    from analytic import mass
    mats = mass.materials(mech)
    weighted = {w.link for w in mass.counterweights(mech)}
    out = {}
    for ln in mech.links:
        src = ("--inertia" if ln in (given or {}) else "[inertia]" if ln in mech.definition.inertia
               else f"[mass] {mats[ln].shape}" if ln in mats else "default (1 kg/m bars)")
        out[ln] = src + (" + counterweight" if ln in weighted else "")
    return out


def check_forces_memory(mech: Mechanism, samples: int) -> None:
    """Refuse a sample count whose force run would need more than RUN_MEMORY (the runs' one rule,
    :func:`sim.service.analysis.check_memory`): one line with the count that fits."""
    from analytic.loads.kinetostatics import full_wanted
    check_memory("samples", f"{samples:,}", samples, len(full_wanted(mech)), BYTES_PER_VALUE,
                 f"the {mech.name}'s joint forces at that many samples")


def forces_run(mech: Mechanism, samples: int = 361, revolutions: float = 1.0, input_range=None,
               gravity=None, force=(0.0, 0.0), slow_stroke_only: bool = False, inertias: dict | None = None,
               balance=None, extra_loads=(), at=None, pressure=None) -> ForceRun:
    """Every joint force of ``mech`` along its motion law: ``samples`` instants over ``revolutions`` of the
    first input (or rocking over ``input_range``), with ``gravity`` (gx, gy) [m/s^2], ``force`` (Fx, Fy) [N]
    on the output point (only on the slow stroke when ``slow_stroke_only``: a cutting force) and the mass
    model with ``inertias`` ({link: Inertia}, SI) replacing links' own. ``balance``: None, or the links to
    carry counterweights (an empty tuple: the default choice, see analytic.applications.balance).
    ``extra_loads``: the command line's loads (analytic.loads dataclasses) besides the file's ``[[loads]]``
    and ``[friction]`` (SPEC "Loads"); ``at``: one value of the first input [rad or m] instead of a run;
    ``pressure``: the supply pressure [Pa] to size the actuators for (their bores, :func:`actuator_sizing`)."""
    from analytic import mass
    from analytic.applications import balance as bal
    from analytic.applications import forces as F
    check_samples(samples)
    check_revolutions(revolutions)
    F.check_determinate(mech)
    if at is None:
        check_forces_memory(mech, samples)
    if input_range is not None:
        lo, hi = check_range(mech, *input_range)
        mech = mech.rocking(lo, hi)
    elif at is None:                               # one pose needs only to assemble (check_assembles)
        check_turns_fully(mech)
    from sim.service import loads as L
    t, cycles = L.run_times(mech, samples, revolutions, at)
    q, qd, qdd = mech.drive(t)
    mech.check_motion(q, t)
    sol, rest = _solved(mech, q, qd, qdd, sorted(set(L.K.full_wanted(mech)) | set(measured_outputs(mech))))
    if sol.first_failure() is not None:      # which samples assemble is the positions' alone: refused as the
        mech.check_assembles(q)              # positions' own check words it
    check_forces_singular(mech, q, sol)
    model = mass.model(mech, inertias, local=_local_at_start(mech, t, sol))
    gx, gy = gravity if gravity is not None else (0.0, 0.0)
    fx, fy = force
    on, window = (_load_window(mech, q[:, 0]) if slow_stroke_only and (fx or fy) else (1.0, None))
    loadset = L.loadset(mech, extra_loads)
    loaded = L.K.solve(mech, q, qd, qdd, t, model, loadset, (gx, gy), (fx, fy), on, sol=sol)
    result = loaded.forces
    bad = F.singular_samples(result)
    if bad.any():
        k = int(np.argmax(bad))
        raise ParameterError(_singular_text(mech, float(q[k, 0]), "a group"))
    point = mech.output_point
    loads = {"gravity": list(gravity) if gravity is not None else None,
             "force": ({"Fx": fx, "Fy": fy, "point": point, "link": mech.topology.loaded_link(point),
                        "cutting": bool(slow_stroke_only),
                        **({"window": list(window)} if window is not None else {})} if (fx or fy) else None)}
    cols = {}
    for k, inp in enumerate(mech.inputs):
        cols[inp.q] = q[:, k]
    balance_result = balanced = None
    if balance is not None:
        balance_result = bal.balance(mech, sol, model, tuple(balance) or None)    # the closed run: its ends weigh half
        balanced = L.K.solve(mech, q, qd, qdd, t, bal.with_counterweights(model, balance_result.counterweights),
                             loadset, (gx, gy), (fx, fy), on, sol=sol).forces
    energy = L.energy_of(mech, loaded, loadset, model, (gx, gy), (fx, fy), on, cycles)
    return ForceRun(mech, t, q, qd, qdd, cols, sol, model, mass_sources(mech, inertias), loads, result,
                    balance_result, balanced, loaded, loadset, energy, pressure, rest)


def _solved(mech: Mechanism, q, qd, qdd, outputs):
    """The solution at (q, qd, qdd) with ``outputs``; where the mechanism has a cam, also the poses at rest (the
    same q, no rates: what :func:`jump_speed` weighs the contact at), in the same solve, the rows interleaved
    sample by sample (a numerically solved group meets each pose next to itself); else None for those."""
    if not any(c.kind == "cam" for c in mech.topology.couplings):
        return mech.solve(q, qd, qdd, outputs=outputs), None
    from analytic.cycle import take
    both = [np.repeat(x, 2, axis=0) for x in (q, qd, qdd)]
    both[1][1::2] = 0.0
    both[2][1::2] = 0.0
    sol = mech.solve(*both, outputs=outputs)
    return take(sol, slice(0, None, 2)), take(sol, slice(1, None, 2))


def force_peaks(run: ForceRun, forces=None) -> dict:
    """Each joint's peak |F| [N] (a prismatic pair's also its peak |M| [N m]), each drive's peak and the
    shaking force's and moment's, with the sample index where each occurs; the RMS over the closed run
    (its end sample counted once)."""
    from analytic.applications.averages import closed_rms
    f = forces or run.forces
    out = {"joints": {}, "drives": {}, "shaking": {}}
    mag = f.magnitude()
    for k, j in enumerate(f.joints):
        i = int(np.argmax(mag[k]))
        entry = {"F": float(mag[k, i]), "at": i}
        if j.kind == "prismatic":
            m = np.abs(f.M(k))
            entry.update({"M": float(m.max()), "at_M": int(np.argmax(m))})
        out["joints"][j.name] = entry
    for inp in run.mech.inputs:
        d = np.abs(f.drives[inp.link])
        out["drives"][inp.q] = {"value": float(d.max()), "at": int(np.argmax(d))}
    sf = np.hypot(f.shaking[0], f.shaking[1])
    sm = np.abs(f.shaking[2])
    out["shaking"] = {"F": float(sf.max()), "at": int(np.argmax(sf)), "M": float(sm.max()), "at_M": int(np.argmax(sm)),
                      "F_rms": float(closed_rms(sf))}
    return out


def force_factors(mech: Mechanism) -> tuple[float, float, str, str]:
    """What people read forces in (SPEC "Units of results", as ``linkage forces`` prints them): the factors from
    N and N m to the file's ``force_units`` and to that unit x the file's length unit (N m for a file in N),
    and the two units' names."""
    from analytic import quantities as Q
    from sim.output.units import force_units
    display = Q.Display(mech.units, "rad", "", force_units(mech))
    return (display.convert(Q.FORCE, 1.0), display.convert(Q.TORQUE, 1.0), display.unit(Q.FORCE),
            display.unit(Q.TORQUE))


def forces_record(run: ForceRun, display=None) -> dict:
    """The JSON of ``linkage forces --json`` (SPEC "Forces"): SI, world frame, arrays over the samples,
    unless ``display`` converts lengths and angles (forces stay N, torques N m)."""
    from analytic import quantities as Q
    from analytic.applications.forces import centres
    display = display or Q.SI
    mech, f = run.mech, run.forces

    def L(v):
        return display.convert(Q.LENGTH, v)

    def inp_q(inp):
        return Q.ANGLE if inp.angular else Q.LENGTH

    com = centres(mech, run.solution, run.inertias)
    links = {ln: {"m": b.m, "I": b.I, "cx": L(b.cx), "cy": L(b.cy), "xG": L(com[ln][0]), "yG": L(com[ln][1]),
                  "source": run.sources[ln]} for ln, b in run.inertias.items()}
    joints = []
    for k, j in enumerate(f.joints):
        entry = {"name": j.name, "point": j.point, "kind": "R" if j.kind == "revolute" else "P",
                 "links": [j.a, j.b], "Fx": f.F[k, 0], "Fy": f.F[k, 1]}
        if j.kind == "prismatic":
            entry["M"] = f.M(k)
        if j.input is not None:
            entry["input"] = mech.inputs[j.input].q
        joints.append(entry)
    joints += cam_joints(run, display)
    drives = {inp.q: f.drives[inp.link] for inp in mech.inputs}
    record = {"mechanism": mech.name, "samples": len(run.t), "t": run.t,
              "inputs": {inp.q: display.convert(inp_q(inp), run.inputs[inp.q]) for inp in mech.inputs},
              "links": links, "joints": joints, "drives": drives,
              "shaking": {"Fx": f.shaking[0], "Fy": f.shaking[1], "M": f.shaking[2]},
              "loads": loads_table(run, display), "peaks": _peaks_at(run, force_peaks(run), display),
              "units": {"file": mech.units, "length": display.unit(Q.LENGTH), "angle": display.unit(Q.ANGLE),
                        "time": "s", "force": "N", "torque": "N m", "mass": "kg", "I": "kg m^2",
                        "inputs": {inp.q: display.unit(inp_q(inp)) for inp in mech.inputs},
                        "drives": {inp.q: inp.spec.drive_unit for inp in mech.inputs}}}
    for e in mech.geometry.elements:               # what an input's kind reports of its drive (a pressure)
        kind = kinds.get(e["kind"])
        if kind.section == "inputs":
            for section, entries in kind.drive_report(e, f.drives[kind.input_key(e)], run.pressure).items():
                record.setdefault(section, {}).update(entries)
                record["units"].setdefault(section, dict(kind.report_units.get(section, {})))
    cams = cams_record(run)
    if cams:
        record["cams"] = cams
    if "actuators" in record:
        _actuator_units(record, run, display)
    if run.balance is not None:
        record["balance"] = balance_record(run, display)
    from sim.service import loads as L
    L.add_to_record(record, run, display)          # friction's Mf at one pose (--at) too; energy per cycle
    if display.unit(Q.FORCE) != "N":
        _force_units(record, mech, display)
    return record


def cam_joints(run: ForceRun, display=None) -> list:
    """The ``joints`` entries of kind ``cam`` (SPEC "Cams and followers"): per cam contact, its point (the
    follower's trace point; ``x``, ``y``: the contact point itself), the cam's and the follower's links, the
    contact force ``N`` [N] along the common normal (> 0 pressing) and its components on the follower."""
    if not any(c.kind == "cam" for c in run.mech.topology.couplings):
        return []                                  # no cam: its module not loaded
    from analytic import cams
    from analytic import quantities as Q
    display = display or Q.SI
    mech, f = run.mech, run.forces
    out = []
    elements = cams.elements(mech)
    for k, c in enumerate(mech.topology.couplings):
        if c.kind != "cam":
            continue
        e = next(x for x in elements.values() if x["links"][0] == c.link)
        g = cams.at(e["setup"], np.arctan2(run.solution["sin" + c.mesh], run.solution["cos" + c.mesh]))
        N = f.couplings[k]
        ax, ay = e["setup"].pivot
        out.append({"name": e["name"], "point": e["point"], "kind": "cam", "links": [c.mesh, c.link], "N": N,
                    "Fx": N * g["normal"][0], "Fy": N * g["normal"][1],
                    "x": display.convert(Q.LENGTH, ax + g["contact"][0]),
                    "y": display.convert(Q.LENGTH, ay + g["contact"][1])})
    return out


def cams_record(run: ForceRun) -> dict:
    """Per cam: the least contact force over the run [N] and the jump speed [rad/s] (:func:`jump_speed`)."""
    out = {}
    for j in cam_joints(run):
        out[j["name"]] = {"contact_min": float(np.min(j["N"])), "jump_speed": jump_speed(run, j["name"])}
    return out


def jump_speed(run: ForceRun, name: str) -> float:
    """The cam speed [rad/s] at which cam ``name``'s contact force first falls to zero, for the file's law
    scaled in time: run k times faster, every velocity scales by k and every acceleration by k^2 (the follower's
    h'' omega^2 + h' alpha too), so at each cam angle N(k) = N_s + k^2 N_1, N_s the force at rest (the loads
    that depend on the pose only: springs, gravity, the file's forces) and N_1 = N(1) - N_s from the file's
    run. The contact is first lost at k* = the least sqrt(-N_s / N_1) over the samples where N_1 < 0; the
    jump speed is k* times the cam's mean speed over the run (a steady cam: its speed). inf where inertia never
    unloads the contact, 0 where it is lost at rest. Velocity-dependent loads (dampers, friction) are not of
    this form and are left out of N_s."""
    from analytic import cams
    from sim.service import loads as L
    mech = run.mech
    e = cams.elements(mech)[name]
    k = next(i for i, c in enumerate(mech.topology.couplings) if c.kind == "cam" and c.link == e["links"][0])
    speed = float(np.mean(np.abs(run.solution["omega" + e["cam"]])))
    zero = np.zeros_like(run.qd)
    loadset = run.loadset if run.loadset is not None else L.loadset(mech, ())
    gravity = run.loads["gravity"] or (0.0, 0.0)
    force = run.loads["force"]
    fx, fy = (force["Fx"], force["Fy"]) if force else (0.0, 0.0)
    rest = L.K.solve(mech, run.q, zero, zero, run.t, run.inertias, loadset, tuple(gravity), (fx, fy), 1.0,
                     sol=run.rest if _at_poses(run.rest, run.solution, mech) else None).forces
    Ns, N = rest.couplings[k], run.forces.couplings[k]
    if np.any(Ns <= 0):
        return 0.0
    N1 = N - Ns
    falls = N1 < 0
    return float(np.sqrt(np.min(-Ns[falls] / N1[falls])) * speed) if falls.any() else float("inf")
def _at_poses(rest, sol, mech) -> bool:
    """Whether ``rest`` (ForceRun.rest) holds the poses of ``sol``: every point where the run's solution has it (a
    run whose samples were replaced, MuJoCo's, solves its own rest poses)."""
    if rest is None:
        return False
    return all(np.array_equal(np.asarray(rest[c + p]), np.asarray(sol[c + p])) for p in mech.points for c in "xy")


def supply_pressure(text, mech: Mechanism, what: str = "--pressure") -> float:
    """The supply pressure [Pa] to size ``mech``'s actuators for, from ``text`` with its unit (``200bar``,
    ``20MPa``, ``3000psi``; analytic.quantities.parse_pressure); a ParameterError naming ``what`` for a bad
    one or where ``mech`` has no actuator."""
    from analytic.quantities import parse_pressure
    value = parse_pressure(text, what)
    if not any(e["kind"] == "actuator" for e in mech.geometry.elements):
        raise ParameterError(f"{what} sizes actuators: the {mech.name} has none (an [[inputs]] kind = \"actuator\")")
    return value


def actuator_sizing(run: ForceRun) -> dict:
    """{actuator's name: its sizing table} (analytic.kinds.actuator.sizing: the peak push and pull [N] with
    their samples, the peak pressures with a bore, the bores ``run.pressure`` needs), SI."""
    from analytic.kinds.actuator import sizing
    return {e["name"]: sizing(e, run.forces.drives["_" + e["name"]], run.pressure)
            for e in run.mech.geometry.elements if e["kind"] == "actuator"}


def _actuator_units(record: dict, run: ForceRun, display) -> None:
    """The sizing entries of ``record["actuators"]`` where people read them: beside each peak's sample ``at``
    its time ``t`` and the actuator's length there, forces in the force unit, diameters in the length unit."""
    from analytic import quantities as Q
    columns = {inp.link: inp.q for inp in run.mech.inputs}          # an actuator's input link is _NAME
    for name, entry in record["actuators"].items():
        for side in ("push", "pull"):
            if side in entry:
                pk, q = entry[side], columns["_" + name]
                if pk["at"] is not None:
                    pk["t"] = float(run.t[pk["at"]])
                    pk[q] = display.convert(Q.LENGTH, float(run.inputs[q][pk["at"]]))
                pk["F"] = float(display.convert(Q.FORCE, pk["F"]))
        for k in ("bore_push", "bore_pull", "bore", "rod"):
            if k in entry.get("sizing", {}):
                entry["sizing"][k] = float(display.convert(Q.LENGTH, entry["sizing"][k]))
    record["units"]["actuators"].update({"F": display.unit(Q.FORCE), "bore": display.unit(Q.LENGTH)})


def _force_units(record: dict, mech: Mechanism, display) -> None:
    """The forces [N] and moments [N m] of a :func:`forces_record` in ``display``'s force unit and force x
    length (``--units`` on a file with ``force_units``), its ``units`` table saying so; energies stay J."""
    from analytic import quantities as Q

    def F(v):
        return display.convert(Q.FORCE, np.asarray(v)) if v is not None else v

    def M(v):
        return display.convert(Q.TORQUE, np.asarray(v)) if v is not None else v

    angular = {inp.q: inp.angular for inp in mech.inputs}       # a torque (a turning input) or a force
    for j in record["joints"]:
        for k in ("Fx", "Fy", "Ff"):
            if k in j:
                j[k] = F(j[k])
        for k in ("M", "Mf"):
            if k in j:
                j[k] = M(j[k])
    record["drives"] = {q: (M(v) if angular[q] else F(v)) for q, v in record["drives"].items()}
    sh = record["shaking"]
    record["shaking"] = {"Fx": F(sh["Fx"]), "Fy": F(sh["Fy"]), "M": M(sh["M"])}
    peaks = record["peaks"]
    for entry in peaks["joints"].values():
        entry["F"] = float(F(entry["F"]))
        if "M" in entry:
            entry["M"] = float(M(entry["M"]))
    for q, entry in peaks["drives"].items():
        entry["value"] = float(M(entry["value"]) if angular[q] else F(entry["value"]))
    for k, conv in (("F", F), ("F_rms", F), ("M", M)):
        peaks["shaking"][k] = float(conv(peaks["shaking"][k]))
    for ld in record.get("loads", ()):
        if ld.get("kind") == "force" and "Fx" in ld and ld.get("name") == "force":
            ld["Fx"], ld["Fy"] = float(F(ld["Fx"])), float(F(ld["Fy"]))
    if "balance" in record:
        b = record["balance"]
        for when in ("before", "after"):
            b["shaking"][when] = {k: float(F(v)) for k, v in b["shaking"][when].items()}
            b["inertial_shaking"][when] = {k: (float(F(v)) if k in ("rms", "peak") else v)
                                           for k, v in b["inertial_shaking"][when].items()}
        b["shaking_force_after"] = {k: F(v) for k, v in b["shaking_force_after"].items()}
        b["drives_after"] = {q: (M(v) if angular[q] else F(v)) for q, v in b["drives_after"].items()}
    u = record["units"]
    u["force"], u["torque"] = display.unit(Q.FORCE), display.unit(Q.TORQUE)
    u["drives"] = {q: display.unit(Q.TORQUE if angular[q] else Q.FORCE) for q in angular}


def loads_table(run: ForceRun, display=None) -> list:
    """The JSON ``loads`` table (SPEC "Loads"): every load applied with its link, point and work per cycle."""
    from sim.service import loads as L
    return L.table(run, display)


def _peaks_at(run: ForceRun, peaks: dict, display) -> dict:
    """The peaks with the first input's value (display units) beside each sample index ``at``/``at_M``."""
    from analytic import quantities as Q
    first = run.mech.inputs[0]
    quantity = Q.ANGLE if first.angular else Q.LENGTH

    def value(i):
        return display.convert(quantity, float(run.q[i, 0]))

    def walk(d):
        out = {}
        for k, v in d.items():
            out[k] = walk(v) if isinstance(v, dict) else v
            if k in ("at", "at_M") and not isinstance(v, dict):
                out[f"{first.q}{'' if k == 'at' else '_M'}"] = value(v)
        return out
    return walk(peaks)


def balance_record(run: ForceRun, display=None) -> dict:
    """The counterweights (mass [kg], position in the link's frame) and the shaking force before/after."""
    from analytic import quantities as Q
    display = display or Q.SI
    b = run.balance
    after = force_peaks(run, run.balanced)["shaking"]
    before = force_peaks(run)["shaking"]
    return {"method": b.method,
            "counterweights": [{"link": w.link, "m": w.m, "at": [display.convert(Q.LENGTH, w.u),
                                                                display.convert(Q.LENGTH, w.v)]}
                               for w in b.counterweights],
            "inertial_shaking": {"before": b.before, "after": b.after},
            "shaking": {"before": {"rms": before["F_rms"], "peak": before["F"]},
                        "after": {"rms": after["F_rms"], "peak": after["F"]}},
            "shaking_force_after": {"Fx": run.balanced.shaking[0], "Fy": run.balanced.shaking[1]},
            "drives_after": {inp.q: run.balanced.drives[inp.link] for inp in run.mech.inputs}}


def forces_columns(run: ForceRun) -> tuple[dict, dict]:
    """CSV columns of a forces run and their quantities: t, the inputs, each joint's ``Fx_J Fy_J F_J``
    (``M_J`` for a prismatic pair), each drive ``tauL`` (L the input's link, as in simulate's CSV), the shaking
    force and moment."""
    from analytic import quantities as Q
    mech, f = run.mech, run.forces
    cols = {"t": run.t}
    qty = {"t": Q.TIME}
    for inp in mech.inputs:
        cols[inp.q] = run.inputs[inp.q]
        qty[inp.q] = Q.ANGLE if inp.angular else Q.LENGTH
    mag = f.magnitude()
    for k, j in enumerate(f.joints):
        for name, v in ((f"Fx_{j.name}", f.F[k, 0]), (f"Fy_{j.name}", f.F[k, 1]), (f"F_{j.name}", mag[k])):
            cols[name], qty[name] = v, Q.FORCE
        if j.kind == "prismatic":
            cols[f"M_{j.name}"], qty[f"M_{j.name}"] = f.M(k), Q.TORQUE
    for inp in mech.inputs:
        cols[f"tau{inp.link}"] = f.drives[inp.link]                 # as simulate's CSV names a drive
        qty[f"tau{inp.link}"] = inp.spec.drive_quantity
    for name, k, quantity in (("Fx_shaking", 0, Q.FORCE), ("Fy_shaking", 1, Q.FORCE), ("M_shaking", 2, Q.TORQUE)):
        cols[name], qty[name] = f.shaking[k], quantity
    return cols, qty


def forces_table(run: ForceRun, display=None) -> str:
    """What ``linkage forces`` prints: each joint's peak force and the first input's value where it occurs,
    the drives' peaks, the shaking force's and moment's (lengths, forces and moments in ``display`` units: the
    file's ``force_units``, moments in force x length unless N, then N m)."""
    from analytic import quantities as Q
    from analytic.applications.forces import angle_text
    display = display or Q.SI
    mech, f = run.mech, run.forces
    first = mech.inputs[0]
    q1 = run.q[:, 0]

    def at(i):
        if first.angular:
            return angle_text(first, float(q1[i]))
        return f"{display.convert(Q.LENGTH, float(q1[i])):.6g} {display.unit(Q.LENGTH)}"

    peaks = force_peaks(run)
    loads = run.loads
    FU, MU = display.unit(Q.FORCE), display.unit(Q.TORQUE)

    def F(v):
        return display.convert(Q.FORCE, v)

    def M(v):
        return display.convert(Q.TORQUE, v)
    parts = []
    if loads["gravity"]:
        parts.append(f"gravity {loads['gravity'][0]:g},{loads['gravity'][1]:g} m/s^2")
    if loads["force"]:
        fl = loads["force"]
        parts.append(f"{'cutting force' if fl['cutting'] else 'force'} {fl['Fx']:g},{fl['Fy']:g} N on {fl['point']} "
                     f"(link {fl['link']})")
    if run.loadset:
        parts.append(f"{len(run.loadset.loads)} load{'s' * (len(run.loadset.loads) != 1)}"
                     + (" and friction" if run.loadset.friction else ""))
    lines = [f"{mech.name}: joint forces over {len(run.t)} samples ({', '.join(parts) or 'inertia only'}); "
             f"masses: {sum(b.m for b in run.inertias.values()):.4g} kg in {len(run.inertias)} links",
             f"  {'joint':<12s} {'kind':<5s} {'links':<22s} {f'peak |F| [{FU}]':>13s}  at {first.q}"]
    for k, j in enumerate(f.joints):
        pk = peaks["joints"][j.name]
        kind = "R" if j.kind == "revolute" else "P"
        extra = ""
        if j.kind == "prismatic":
            extra = f"; couple peak {M(pk['M']):.4g} {MU} at {at(pk['at_M'])}"
        if j.input is not None:
            extra += " (driven)"
        lines.append(f"  {j.name:<12s} {kind:<5s} {j.a + '-' + j.b:<22s} {F(pk['F']):13.5g}  {at(pk['at'])}{extra}")
    for inp in mech.inputs:
        d = peaks["drives"][inp.q]
        unit, conv = (MU, M) if inp.angular else (FU, F)
        lines.append(f"  drive of {inp.q}: peak {inp.spec.drive_quantity} {conv(d['value']):.5g} "
                     f"{unit} at {at(d['at'])}")
    for e in mech.geometry.elements:               # what a kind reports of its drive: an actuator's pressure
        kind = kinds.get(e["kind"])
        if kind.section != "inputs":
            continue
        for entries in kind.drive_report(e, f.drives[kind.input_key(e)]).values():
            for name, rec in entries.items():
                p = np.asarray(rec.get("pressure", []), dtype=float)
                if p.size and np.isfinite(p).any():
                    i = int(np.nanargmax(p))
                    lines.append(f"  pressure of {name}: peak {p[i] / 1e5:.5g} bar on its {rec['area'][i]} area "
                                 f"at {at(i)}")
    cams = cams_record(run)
    for j in cam_joints(run):
        N = j["N"]
        lo, hi = int(np.argmin(N)), int(np.argmax(N))
        w = cams[j["name"]]["jump_speed"]
        jump = ("the contact is lost at rest" if w == 0 else "never (inertia does not unload the contact)"
                if w == float("inf") else f"{w:.5g} rad/s ({w * 30 / np.pi:.5g} rpm, the cam's mean speed)")
        lines.append(f"  cam {j['name']} ({j['links'][0]}-{j['links'][1]}): contact force {F(N[lo]):.5g} {FU} at "
                     f"{at(lo)} .. {F(N[hi]):.5g} {FU} at {at(hi)}{' (the follower leaves the cam)' if N[lo] < 0 else ''};"
                     f" jump speed {jump}")
    lines += sizing_lines(run, display)
    s = peaks["shaking"]
    lines.append(f"  shaking force: peak {F(s['F']):.5g} {FU} at {at(s['at'])} (RMS {F(s['F_rms']):.5g} {FU}); "
                 f"shaking moment about the origin: peak {M(s['M']):.5g} {MU} at {at(s['at_M'])}")
    if run.balance is not None:
        b = run.balance
        lines.append(f"  balance ({b.method}): " + ("; ".join(
            f"{w.m:.4g} kg on link {w.link} at ({display.convert(Q.LENGTH, w.u):.4g}, "
            f"{display.convert(Q.LENGTH, w.v):.4g}) {display.unit(Q.LENGTH)}" for w in b.counterweights)
            or "no counterweight helps"))
        after = force_peaks(run, run.balanced)["shaking"]
        lines.append(f"    shaking force of the inertia: RMS {F(b.before['rms']):.5g} -> {F(b.after['rms']):.5g} {FU}, "
                     f"peak {F(b.before['peak']):.5g} -> {F(b.after['peak']):.5g} {FU}; with the loads: RMS "
                     f"{F(s['F_rms']):.5g} -> {F(after['F_rms']):.5g} {FU}")
    from sim.service import loads as L
    lines += L.summary(run)
    return "\n".join(lines)


def sizing_lines(run: ForceRun, display=None) -> list[str]:
    """The cylinder sizing table of ``linkage forces``: per actuator the peak push and pull force and where
    (time and the actuator's length), with a bore the peak pressure on the push area pi D^2/4 and the pull area
    pi (D^2 - d^2)/4, and with ``--pressure p`` the bore each needs: sqrt(4 F / (pi p)) for the push,
    sqrt(4 F / (pi p) + d^2) for the pull round the rod d."""
    from analytic import quantities as Q
    display = display or Q.SI
    table = actuator_sizing(run)
    if not table:
        return []
    FU, LU = display.unit(Q.FORCE), display.unit(Q.LENGTH)

    def F(v):
        return display.convert(Q.FORCE, v)

    def L(v):
        return display.convert(Q.LENGTH, v)
    columns = {inp.link: inp.q for inp in run.mech.inputs}          # an actuator's input link is _NAME
    lines = ["  cylinder sizing (push area pi D^2/4, pull area pi (D^2 - d^2)/4; D bore, d rod):",
             f"  {'actuator':<12s} {f'peak push [{FU}]':>16s}  {'at':<30s} {f'peak pull [{FU}]':>16s}  at"]
    elements = {e["name"]: e for e in run.mech.geometry.elements if e["kind"] == "actuator"}

    def where(q, i):
        return "never" if i is None else f"t={run.t[i]:.4g} s, {q}={L(float(run.inputs[q][i])):.5g} {LU}"
    for name, s in table.items():
        q = columns["_" + name]
        push, pull = s["push"], s["pull"]
        lines.append(f"  {name:<12s} {F(push['F']):16.5g}  {where(q, push['at']):<30s} {F(pull['F']):16.5g}  "
                     f"{where(q, pull['at'])}")
        e = elements[name]
        if e["bore"] > 0:
            lines.append(f"    bore {L(e['bore']):.4g} {LU}, rod {L(e['rod']):.4g} {LU}: peak "
                         f"{push['pressure'] / 1e5:.4g} bar pushing, {pull['pressure'] / 1e5:.4g} bar pulling")
        if "sizing" in s:
            z = s["sizing"]
            rod = f"round the rod {L(z['rod']):.4g} {LU}" if z["rod"] > 0 else "(no rod given: taken as 0)"
            verdict = ""
            if "enough" in z:
                verdict = (f"; the file's bore {L(e['bore']):.4g} {LU} "
                           + ("suffices" if z["enough"] else "is too small"))
            lines.append(f"    at {z['pressure'] / 1e5:.4g} bar: bore >= {L(z['bore_push']):.4g} {LU} for the push, "
                         f">= {L(z['bore_pull']):.4g} {LU} for the pull {rod}: "
                         f"bore >= {L(z['bore']):.4g} {LU}{verdict}")
    return lines


def balanced_mechanism(mech: Mechanism, links=None) -> tuple[Mechanism, object]:
    """``mech`` with the counterweights of :func:`analytic.applications.balance.balance` written into its
    file's ``[mass.counterweights]`` (file units), so every model built from it (MuJoCo's included) carries
    them; and the Balance. The balance is fitted over the dense samples of one turn's cycle
    (analytic.cycle.Cycle: evenly spaced over the closed turn, whose ends the balance weighs half; 360 samples
    of the open turn, weighed so, had biased a least-squares counterweight by ~1/360, 0.1 %)."""
    from analytic import mass
    from analytic.applications import balance as bal
    from analytic.cycle import Cycle, take
    cycle = Cycle.of(mech, 1.0)
    turn = cycle.dense                                                  # the closed turn, evenly spaced
    if not cycle.solution.valid[turn].all():
        mech.check_assembles(cycle.q[turn])
    result = bal.balance(mech, take(cycle.solution, turn), mass.model(mech), tuple(links or ()) or None)
    d = mech.definition
    section = {k: v for k, v in (d.mass or {}).items()}
    weights = {k: (list(v) if isinstance(v, list) else [v]) for k, v in section.get("counterweights", {}).items()}
    s = mech.scale
    for w in result.counterweights:
        weights.setdefault(w.link, []).append({"m": w.m, "at": [w.u / s, w.v / s]})
    section["counterweights"] = {k: (v[0] if len(v) == 1 else v) for k, v in weights.items()}
    new = replace(d, mass=section)
    return Mechanism.from_definition(new, mech.overrides, mech.builtin), result


def simulated_forces_run(run: ForceRun, settings=None, loads=None):
    """``run`` simulated in MuJoCo, its joint forces read at the run's samples and compared with the analytic
    ones at the simulated inputs (:class:`sim.run.forces.Simulated`)."""
    from analytic.cycle import Cycle
    from sim.run import forces as simforces
    t = np.asarray(run.t)
    return simforces.simulate_run(run, settings, loads, Cycle.of(run.mech, float(t[-1] / run.mech.duration(1.0))))


def simulated_forces(run: ForceRun, settings=None, loads=None, display=None, simulated=None) -> dict:
    """The ``simulated`` object of ``linkage forces --simulate --json``: MuJoCo's answer in the fields of
    :func:`forces_record` (at the run's samples, the inputs as simulated, the model's masses), the time step
    and steps, the agreement with the analytic forces (``agreement``: each joint's largest difference [N] and
    its share of the peak joint force, the drives' three answers, the shaking force) and ``passed``.
    ``simulated``: MuJoCo's run (:func:`simulated_forces_run`) when already made (the record in other units)."""
    from sim.model import body_inertias
    s = simulated if simulated is not None else simulated_forces_run(run, settings, loads)
    mech, tr = run.mech, s.trajectory
    q, qd, qdd = s.inputs
    sol = {k: np.asarray(v)[s.steps] for k, v in tr.outputs.items() if k[:1] in ("x", "y", "c", "s", "o")}
    sim_run = replace(run, t=run.t[:len(s.steps)], q=q, qd=qd, qdd=qdd, inputs={inp.q: q[:, k] for k, inp in enumerate(mech.inputs)},
                      solution=sol, inertias=body_inertias(s.built.model, mech.links), forces=s.forces,
                      balance=None, balanced=None, rest=None)          # the rest poses: solved at these inputs
    record = forces_record(sim_run, display)
    for key in ("mechanism", "loads", "units"):
        record.pop(key, None)
    record.update({"timestep": s.built.timestep, "steps": int(tr.steps), "agreement": s.agreement.as_dict(),
                   "passed": s.agreement.passed})
    return record
