"""The loads of a run as the commands report them (SPEC "Loads"): which loads act (the file's ``[[loads]]``
and ``[friction]``, the command line's ``--force FX,FY@POINT[:LINK]`` and ``--torque T@LINK``, the shorthands
``--gravity``/``--force``/``--cutting-force``), each one's work per cycle, friction's dissipation and the
energy balance; and one pose (``--at``)."""

from __future__ import annotations

import math

import numpy as np

from analytic import ParameterError
from analytic import loads as AL
from analytic.kinds.base import GROUND as _GROUND
from analytic.loads import kinetostatics as K

__all__ = ["K", "table_files", "run_times", "at_time", "loadset", "energy_of", "table", "add_to_record", "summary", "GROUND",
           "force_load", "torque_load", "inertia", "cutting_direction"]


def table_files(mech) -> tuple:
    """The table files ``mech``'s ``[[loads]]`` read (``table = "file.csv"``): inputs no output may replace."""
    from analytic.loads.law import table_files as files
    return files(mech.definition)


def at_time(mech, value: float) -> float:
    """The time [s] at which the first input passes ``value`` [rad or m]: its first pass at or after t = 0 (for
    a crank, ``value`` plus any whole turns) -- at a constant speed, under an acceleration, rocking over an
    input range, or along a motion law (analytic.motion.Motion.time_at) within its first cycle."""
    first = mech.inputs[0]
    m = first.motion
    if m.constant and m.rate != 0.0:                   # a constant speed: any pass, by hand
        t = (value - m.q0) / m.rate
        if first.angular:
            t = math.fmod(t, 2 * math.pi / abs(m.rate))
            t = t + 2 * math.pi / abs(m.rate) if t < 0 else t
        return float(t)
    if m.rate == 0.0 and m.accel == 0.0 and m.law is None:
        raise ParameterError(f"--at needs the first input {first.q} to move; give its speed with --set")
    until = mech.duration(1.0)
    t = m.time_at(value, first.turn if first.angular else 0.0, until)
    if t is None:
        q = m.at(np.linspace(0.0, until, 721))[0]
        unit, k = ("deg", 180 / math.pi) if first.angular else (mech.definition.units, 1.0 / mech.scale)
        raise ParameterError(f"--at {value * k:g}{unit}: the input {first.q} does not pass it over its cycle "
                             f"(it runs {float(q.min()) * k:.6g}..{float(q.max()) * k:.6g} {unit}); give a value "
                             "in that range")
    return float(t)


def run_times(mech, samples: int, revolutions: float, at=None) -> tuple[np.ndarray, float]:
    """The run's instants and how many cycles they span (0 for one pose)."""
    if at is not None:
        return np.array([at_time(mech, at)]), 0.0
    return np.linspace(0.0, mech.duration(revolutions), samples), float(revolutions)


def loadset(mech, extra=()):
    """The file's loads with the command line's ``extra``, resolved for ``mech`` (SI)."""
    return AL.resolve(mech, tuple(extra))


def energy_of(mech, loaded, ls, inertias, gravity, force, on, cycles: float) -> dict | None:
    """Work per cycle of every load, friction's dissipation and the energy balance (None for one pose)."""
    if not cycles:
        return None
    st = loaded.state
    p = mech.output_point
    fx, fy = force
    force_power = None
    if fx or fy:
        force_power = np.asarray(on) * (fx * np.asarray(st.sol["vx" + p]) + fy * np.asarray(st.sol["vy" + p]))
        force_power = np.broadcast_to(force_power, (st.n,))
    return K.balance(mech, loaded, ls, inertias, gravity, cycles, force_power)


def table(run, display=None) -> list:
    """The JSON ``loads`` table: every load applied, each ``{"name", "kind", "link", "point" or "at",
    "work_per_cycle"}`` (J; positions in the display's length unit, SI by default) and its law's fields; the
    shorthands as ``gravity`` and ``force`` (the latter with ``Fx, Fy``, ``cutting`` and a cutting window)."""
    from analytic import quantities as Q
    display = display or Q.SI
    per = (run.energy or {}).get("work_per_cycle", {})
    scale = 1.0 / display.convert(Q.LENGTH, 1.0)
    out = []
    old = run.loads or {}
    if old.get("gravity"):
        out.append({"name": "gravity", "kind": "gravity", "link": None, "point": None, "g": list(old["gravity"]),
                    "work_per_cycle": (run.energy or {}).get("gravity_work_per_cycle")})
    if old.get("force"):
        f = old["force"]
        out.append({"name": "force", "kind": "force", "link": f["link"], "point": f["point"], "Fx": f["Fx"],
                    "Fy": f["Fy"], "cutting": f["cutting"], **({"window": f["window"]} if "window" in f else {}),
                    "work_per_cycle": (run.energy or {}).get("force_work_per_cycle")})
    for ld in run.loadset.loads if run.loadset else ():
        out.append({**ld.record(scale), "work_per_cycle": per.get(ld.name)})
    return out


def add_to_record(record: dict, run, display=None) -> None:
    """Friction (each pin's ``Mf`` in its joint entry, ``friction.dissipated_per_cycle``) and the energy
    balance into a forces JSON record."""
    loaded = run.loaded
    if loaded is not None and run.loadset is not None and run.loadset.friction:
        for k, m in loaded.Mf.items():
            record["joints"][k]["Mf"] = m
        for k, f in loaded.Ft.items():
            record["joints"][k]["Ff"] = f
        record["friction"] = {"dissipated_per_cycle": run.energy["friction_dissipated_per_cycle"]
                              if run.energy else None, "iterations": loaded.iterations,
                              **run.loadset.friction.record(loaded.forces.joints)}
    elif run.energy is not None:
        record["friction"] = {"dissipated_per_cycle": 0.0}
    if run.energy is not None:
        record["energy"] = {**run.energy["energy"], "power_residual": run.energy["power_residual"]}


def summary(run) -> list[str]:
    """Lines for the forces table: the loads and their work per cycle, friction, the energy balance."""
    lines = []
    e = run.energy
    for ld in run.loadset.loads if run.loadset else ():
        w = e["work_per_cycle"].get(ld.name) if e else None
        where = getattr(getattr(ld, "end", None), "point", None) or ""
        lines.append(f"  load {ld.name} ({ld.kind} on {ld.link}{' at ' + where if where else ''})"
                     + (f": work per cycle {w:.5g} J" if w is not None else ""))
    if e is not None and run.loadset is not None and run.loadset.friction:
        lines.append(f"  friction: dissipates {e['friction_dissipated_per_cycle']:.5g} J per cycle "
                     f"({run.loaded.iterations} solves)")
    if e is not None and (run.loadset or e["friction_dissipated_per_cycle"]):
        b = e["energy"]
        lines.append(f"  energy per cycle: drive {b['drive_work']:.5g} J + loads {b['loads_work']:.5g} J = "
                     f"friction {b['friction_dissipated']:.5g} + dampers {b['damper_dissipated']:.5g} + kinetic "
                     f"{b['kinetic_change']:.3g} + springs {b['spring_change']:.3g} (residual {b['residual']:.2g} J; "
                     f"power balance {e['power_residual']:.1e} of its scale)")
    return lines


def dynamics_loads(d) -> tuple[list, dict] | None:
    """The ``loads`` table and the energy balance of a motor run (sim.run.motor.Dynamics) over its last
    revolution: a load of the pose does the work of its generalized force over a turn (the periodic grid's
    rectangle rule, spectral for a smooth load), a damper -integral of C(u) w(u) du with the run's speed;
    motor + loads (+ gravity and the shorthand force) = the change of kinetic energy + residual."""
    import math
    r = d.run
    red = r.reduced
    terms = red.loads
    if terms is None:
        return None
    u = terms.u
    du = 2 * math.pi / len(u)
    last0 = 2 * math.pi * (r.revolutions - 1)
    w = r.speed_at(last0 + u)
    ls = d.built.loadset if d.built is not None else AL.resolve(d.mech)
    kinds = {ld.name: ld for ld in (ls.loads if ls else ())}
    table, total = [], 0.0
    for name, Q in terms.per_load.items():
        ld = kinds.get(name)
        W = float(np.sum(Q * w) * du) if ld is not None and ld.speed_linear else float(np.sum(Q) * du)
        total += W
        entry = ld.record(d.mech.scale / d.mech.scale) if ld is not None else {"name": name}
        table.append({**entry, "work_per_cycle": W})
    Qrest = red._Qg(u) + red.on(u) * red._QF(u)
    W_rest = float(np.sum(Qrest) * du)
    ta, tb = r.last_revolution
    wa, wb = float(r.dense(ta)[1]), float(r.dense(tb)[1])
    J0 = float(red.J(np.array([0.0]))[0])
    dT = 0.5 * J0 * (wb * wb - wa * wa)
    residual = r.energy_per_cycle + total + W_rest - dT
    return table, {"motor_work": r.energy_per_cycle, "loads_work": total + W_rest, "kinetic_change": dT,
                   "residual": residual, "per": "last revolution"}




GROUND = _GROUND
"""The name of the fixed link: no load acts on it."""


def force_load(name: str, link: str, point: str, fx: float, fy: float):
    """A constant world-frame force (fx, fy) [N] at the named ``point`` of ``link`` (the command line's
    ``--force FX,FY@POINT[:LINK]``), as the ``extra`` loads of :func:`sim.service.simulation.run_loads` and
    :func:`loadset` take."""
    from analytic.loads import force
    return force.constant(name, link, point, fx, fy)


def torque_load(name: str, link: str, torque: float):
    """A constant couple ``torque`` [N m] (+ counter-clockwise) on ``link`` (the command line's ``--torque``)."""
    from analytic.loads import torque as couple
    return couple.constant(name, link, torque)


def inertia(values: dict, scale: float = 1.0):
    """One link's inertial data (``analytic.mass.Inertia``, SI) from ``values`` {m, cx, cy, I} in a file's units:
    mass ``m`` [kg], centre of mass ``(cx, cy)`` [unit] in the link's frame, moment of inertia ``I`` [kg unit^2]
    about it; ``scale``: metres per unit. A bad value raises :class:`analytic.ParameterError`, a missing or
    unknown key TypeError."""
    from analytic.mass import Inertia
    given = Inertia(**values)
    return Inertia(m=given.m, cx=given.cx * scale, cy=given.cy * scale, I=given.I * scale * scale)


def cutting_direction(mech) -> float:
    """-1 or +1: the x direction that resists the output point during its slow (cutting) stroke (where a
    ``--cutting-force`` acts)."""
    from analytic.checks import slow_stroke
    lo, hi = slow_stroke(mech)
    first = mech.inputs[0]
    q = first.motion.q0 + np.linspace(lo, hi, 50)[1:-1]
    sol = mech.solve(q, math.copysign(1.0, first.motion.rate or 1.0))
    vx = float(np.nanmean(sol["vx" + mech.output_point]))
    return -math.copysign(1.0, vx)
