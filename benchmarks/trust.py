"""Is the simulation trustworthy for any design? Random valid designs of every mechanism, cross-validated.

Run:  python benchmarks/trust.py [--count N] [--seed S] [--long] [--verbose]

Draws random designs (seeded) across every mechanism of ``analytic.names()``: every length scaled so the
mechanism's size spans 5 mm .. 5 m (log-uniform), lengths perturbed by +-20 %, crank speed 0.2 .. 20 rev/s
(log-uniform, random sign), random phases and branches, sometimes an accelerating crank (speed changing
by up to +-50 % over the run), the five-bars' second crank at a speed ratio in -2 .. 3; 30 % of the
designs carry loads (from their own random stream, so the designs are those of earlier versions): an
external force on the output point of 0.1 .. 1000 x L^2 Omega^2 [N] (log-uniform, any direction; the
inertial force of a 1 kg/m bar of the size L), with gravity in a random in-plane direction in half of
them. A design is
valid when ``service.prepare`` (full turn, singular pose, assembly) and the time-step choice accept it;
refusals are counted by reason. Each valid design is simulated for one revolution with
``service.compare`` and judged here against the issue's targets, written independently of
sim/run/compare.py (its own verdict ``passed`` is reported alongside):

    angles          <= 1e-6 rad
    positions       <= 1e-6 of the size L
    velocities      <= 1e-5 of max(peak, L Omega)      (angular: max(peak, Omega))
    accelerations   <= 1e-3 of max(peak, L Omega^2)    (angular: max(peak, Omega^2))
    loops           <= 1e-6 of L
    drive error     <= 1e-4 rad (of L for a slider)

    joint forces    <= 1e-4 of the run's peak joint force     (MuJoCo's, sim.run.forces.measure, against
                       the analytic kinetostatics at the simulated inputs; couples and drive torques
                       against the peak force times L, a drive against max(its peak, that); each drive
                       against the power balance; the shaking force against momentum balance)

with Omega = sim.run.compare.motion_scale(mech). Prints the pass rate (overall and per mechanism, target
>= 99 %), the worst error/target per output kind, the failing designs with a reproduction command, the
CPU cost per simulated revolution (target median <= 15 ms) and the chosen time steps.

``--long``: a handful of designs run for 50 revolutions: the worst error/target in the last revolution
against the first (errors must stay flat) and the work balance per revolution (<= 1e-3).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
import traceback
from collections import Counter, defaultdict
from pathlib import Path

import numpy as np

# benchmarks/analytic.py would shadow the package of that name: keep this folder off the import path.
sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]
import analytic  # noqa: E402
from analytic import ParameterError, cams, kinds  # noqa: E402
from analytic.format import expr  # noqa: E402
from sim.run import compare as sim_compare  # noqa: E402
from sim import model as sim_model  # noqa: E402
from sim import service  # noqa: E402

# ------------------------------------------------------------------------------------ the targets
ANGLE = 1e-6          # rad
POSITION = 1e-6       # of the size
VELOCITY = 1e-5       # of max(peak, motion scale)
ACCELERATION = 1e-3   # of max(peak, motion scale squared)
LOOP = 1e-6           # of the size
DRIVE = 1e-4          # rad, or of the size for a slider
FORCE = 1e-4          # of the peak joint force (a moment: of the peak force times the size)
WORK = 1e-3           # of the kinetic-energy swing per revolution (--long)
PASS_RATE = 0.99
CPU_MS_PER_REV = 15.0

SIZE_RANGE = (0.005, 5.0)        # m
SPEED_RANGE = (0.2, 20.0)        # rev/s
RATIO_RANGE = (-2.0, 3.0)        # five-bars: omega of the second crank / the first
PERTURB = 0.20                   # relative, on every (non-derived) length
ACCEL_PROB = 0.3                 # share of designs with an accelerating crank
ACCEL_CHANGE = 0.5               # the speed changes by up to this fraction over the run
TWO_CRANK_RATIO_PARAM = "ratio"  # two_crank_five_bar's speed-ratio parameter
LOAD_PROB = 0.3                  # share of designs with an external force (and gravity in half of them)
FORCE_RANGE = (0.1, 1000.0)      # x L^2 Omega^2 [N]
GRAVITY = 9.81                   # m/s^2


# ------------------------------------------------------------------------------------------ output kinds
def kind_of(mech, name: str) -> str:
    """angle, position, ang_velocity, velocity, ang_acceleration, acceleration (own classifier)."""
    g = mech.aliases.get(name, name)
    points, links, slides = set(mech.points), set(mech.links), set(mech.slides)
    table = [("phi", links, "angle"), ("mu", points, "angle"), ("omega", links, "ang_velocity"),
             ("alpha", links, "ang_acceleration"), ("vx", points, "velocity"), ("vy", points, "velocity"),
             ("ax", points, "acceleration"), ("ay", points, "acceleration"), ("x", points, "position"),
             ("y", points, "position"), ("dds", slides, "acceleration"), ("ds", slides, "velocity"),
             ("s", slides, "position")]
    for prefix, pool, kind in table:
        if g.startswith(prefix) and g[len(prefix):] in pool:
            return kind
    raise KeyError(f"{mech.name}: cannot classify output {name!r}")


def target(kind: str, L: float, omega: float, peak: float) -> float:
    if kind == "angle":
        return ANGLE
    if kind == "position":
        return POSITION * L
    if kind == "ang_velocity":
        return VELOCITY * max(peak, omega)
    if kind == "velocity":
        return VELOCITY * max(peak, L * omega)
    if kind == "ang_acceleration":
        return ACCELERATION * max(peak, omega ** 2)
    if kind == "acceleration":
        return ACCELERATION * max(peak, L * omega ** 2)
    raise KeyError(kind)


def error_series(mech, tr) -> tuple[dict, dict]:
    """Per-sample error/target of every output, the loops and the drives (from the trajectory itself: the
    analytic solution at the simulated inputs), and each one's (kind, target)."""
    L = mech.size
    omega = sim_compare.motion_scale(mech)
    cols = [np.column_stack([tr.inputs[getattr(i, a)] for i in mech.inputs]) for a in ("q", "qd", "qdd")]
    ref = mech.solve(*cols)
    series, meta = {}, {}
    for name in mech.outputs:
        kind = kind_of(mech, name)
        a = np.asarray(ref[name])
        diff = np.asarray(tr.outputs[name]) - a
        if kind == "angle":
            diff = np.pi - np.mod(np.pi - diff, 2 * np.pi)
        peak = float(np.nanmax(np.abs(a)))                      # over the whole run
        tol = target(kind, L, omega, peak)
        err = np.abs(diff)
        err[~np.isfinite(err)] = np.inf
        series[name], meta[name] = err / tol, (kind, tol)
    series["loop"], meta["loop"] = np.asarray(tr.loop_violation) / (LOOP * L), ("loop", LOOP * L)
    drive = np.zeros(len(tr.t))
    for i in mech.inputs:
        angular = kinds.get(i.kind).angular              # a crank's or a motor's angle [rad], else [m]
        drive = np.maximum(drive, np.abs(tr.inputs[i.q] - tr.commanded[i.q]) / (1.0 if angular else L))
    series["drive"], meta["drive"] = drive / DRIVE, ("drive", DRIVE)
    return series, meta


def force_ratios(built, tr) -> dict:
    """Error/target of MuJoCo's joint forces (sim.run.forces.measure) at every step against answers computed
    here: each joint against the analytic kinetostatics at the simulated inputs, each drive against the
    power balance (virtual work, analytic/applications/torque.py), the shaking force against momentum
    balance (sum m (g - a_G) + the load). Empty where statics cannot give the joint forces."""
    from analytic.applications import forces as F
    from analytic.applications import torque
    from sim.run import forces as simforces
    mech, model = built.mech, built.model
    try:
        F.check_determinate(mech)
    except F.StaticsError:
        return {}
    mj = simforces.measure(built, tr)
    q, qd, qdd = (np.column_stack([tr.inputs[getattr(i, a)] for i in mech.inputs]) for a in ("q", "qd", "qdd"))
    inertias = sim_model.body_inertias(model, mech.links)
    g = tuple(float(x) for x in model.opt.gravity[:2])
    load = tuple(float(x) for x in model.actuator("load").gear[:2])
    an = F.solve(mech, q, qd, qdd, inertias, g, load, tr.load)
    L = mech.size
    peak = float(np.max(np.hypot(an.F[:, 0], an.F[:, 1])))
    out = {"joint_forces": max(float(np.max(np.hypot(*(mj.F[k] - an.F[k])))) for k in range(len(an.joints)))
           / peak / FORCE}
    couples = [float(np.max(np.abs(mj.couples[k] - an.couples[k]))) for k in an.couples]
    if couples:
        out["joint_couples"] = max(couples) / (peak * L) / FORCE
    power = torque.drive_forces(mech, q, qd, qdd, inertias, None, g, load, tr.load)
    out["drive_forces"] = max(
        float(np.max(np.abs(mj.drives[i.link] - power[i.link])))
        / max(float(np.max(np.abs(power[i.link]))), peak * (L if i.kind == "crank" else 1.0)) / FORCE
        for i in mech.inputs)
    sol = mech.solve(q, qd, qdd)
    sx = np.full(len(q), sum(b.m for b in inertias.values()) * g[0]) + load[0] * tr.load
    sy = np.full(len(q), sum(b.m for b in inertias.values()) * g[1]) + load[1] * tr.load
    for ln, b in inertias.items():
        o = mech.link_origins[ln]
        c, s_ = sol["cos" + ln], sol["sin" + ln]
        rx, ry = b.cx * c - b.cy * s_, b.cx * s_ + b.cy * c
        w, a = sol["omega" + ln], sol["alpha" + ln]
        sx = sx - b.m * (sol["ax" + o] - a * ry - w * w * rx)
        sy = sy - b.m * (sol["ay" + o] + a * rx - w * w * ry)
    out["shaking_force"] = float(np.max(np.hypot(mj.shaking[0] - sx, mj.shaking[1] - sy))) / peak / FORCE
    return out


def judge(mech, tr, window: slice | None = None, series=None) -> dict:
    """Error/target ratios of one trajectory (optionally over the samples in ``window``): per output,
    'loop' and 'drive', with (kind, error, target) of each."""
    series, meta = series or error_series(mech, tr)
    sl = window or slice(None)
    ratios = {k: float(np.max(v[sl])) for k, v in series.items()}
    detail = {k: (meta[k][0], ratios[k] * meta[k][1], meta[k][1]) for k in series}
    return {"ratios": ratios, "detail": detail}


# ------------------------------------------------------------------------------------------ random designs
def base_lengths(d) -> list[str]:
    """Length parameters given as numbers (derived ones follow the others)."""
    out = []
    for name in d.parameter_order:
        if d.parameter_kind[name] != "length":
            continue
        v = d.parameters[name]
        if isinstance(v, (int, float)) or (isinstance(v, str) and expr.quantity(v) is not None):
            out.append(name)
    return out


def draw(rng: np.random.Generator, name: str, perturb: float = PERTURB, ratio: float | None = None,
         accelerate: bool | None = None) -> tuple[dict, dict]:
    """Random parameter overrides for mechanism ``name`` (file units, angles in rad) and a description
    of the draw (scale, speed, ratio, acceleration)."""
    d = analytic.definition(name)
    mech0 = service.load(name)
    vals = mech0.parameters
    size_file = mech0.size / mech0.scale
    over: dict[str, float] = {}
    for p in base_lengths(d):
        v = vals[p]
        if v != 0.0:
            over[p] = v * (1.0 + rng.uniform(-perturb, perturb))
        elif rng.random() < 0.5:                                  # an offset that is zero by default
            over[p] = rng.uniform(-0.1, 0.1) * size_file
    # scale to a size drawn log-uniformly in SIZE_RANGE
    try:
        size1 = service.load(name, over).size
    except ParameterError:
        size1 = mech0.size
    s = 10 ** rng.uniform(math.log10(SIZE_RANGE[0] / size1), math.log10(SIZE_RANGE[1] / size1))
    over = {k: v * s for k, v in over.items()}
    for p in base_lengths(d):                                      # unperturbed lengths scale too
        if p not in over and vals[p] != 0.0:
            over[p] = vals[p] * s
    for p in d.parameter_order:
        if d.parameter_kind[p] == "branch":
            over[p] = float(rng.choice([-1.0, 1.0]))
    inputs = mech0.inputs
    rev_s = 10 ** rng.uniform(math.log10(SPEED_RANGE[0]), math.log10(SPEED_RANGE[1]))
    w1 = float(rng.choice([-1.0, 1.0])) * 2 * math.pi * rev_s
    accel = rng.random() < ACCEL_PROB
    accel = accel if accelerate is None else accelerate
    f = rng.uniform(-ACCEL_CHANGE, ACCEL_CHANGE) if accel else 0.0
    a1 = math.copysign(1.0, w1) * w1 * w1 * ((1 + f) ** 2 - 1) / (4 * math.pi)
    info = {"perturb": perturb, "scale": s, "rev_s": rev_s * math.copysign(1.0, w1), "speed_change": f}
    for k, inp in enumerate(inputs):
        phi0, om, al = inp.parameters
        if phi0:
            over[phi0] = rng.uniform(0.0, 2 * math.pi)
        if k == 0:
            if om:
                over[om] = w1
            if al:
                over[al] = a1
    if len(inputs) > 1:
        drawn = rng.uniform(*RATIO_RANGE)
        ratio = drawn if ratio is None else ratio
        info["ratio"] = ratio
        for inp in inputs[1:]:
            _, om, al = inp.parameters
            if TWO_CRANK_RATIO_PARAM in d.parameters and d.parameter_kind.get(TWO_CRANK_RATIO_PARAM) == "number" \
                    and isinstance(d.parameters.get(om), str) and expr.quantity(d.parameters[om]) is None:
                over[TWO_CRANK_RATIO_PARAM] = ratio          # omega4 = ratio*omega1 in the file
            elif om:
                over[om] = ratio * w1
            if al:
                over[al] = ratio * a1
    return over, info


def draw_loads(rng: np.random.Generator, mech) -> sim_model.Loads | None:
    """None, or an external force on the output point (and, half the time, gravity) in random directions."""
    if rng.random() >= LOAD_PROB:
        return None
    L, omega = mech.size, sim_compare.motion_scale(mech)
    f = L * L * omega * omega * 10 ** rng.uniform(*np.log10(FORCE_RANGE))
    a = rng.uniform(0.0, 2 * math.pi)
    g = rng.uniform(0.0, 2 * math.pi)
    gravity = (GRAVITY * math.cos(g), GRAVITY * math.sin(g)) if rng.random() < 0.5 else None
    return sim_model.Loads(gravity=gravity, force=(f * math.cos(a), f * math.sin(a)))


REASONS = [("cannot turn fully", "cannot turn fully"), ("singular pose", "singular pose"),
           ("cannot be assembled", "cannot be assembled"), ("moves too fast", "moves too fast"),
           ("not a valid length", "invalid length"), ("stops it before", "crank stops"),
           ("does not move", "input does not move"), ("run off", "block runs off its link"),
           ("field 'at'", "file expression undefined (a triangle cannot close)"),
           ("cannot compile", "MuJoCo cannot compile")]


def reason_of(msg: str) -> str:
    for key, label in REASONS:
        if key in msg:
            return label
    return "other: " + msg[:70]


def validate(mech) -> float:
    """Refuse up front (ParameterError) as the service does; returns the time step it will use."""
    service.prepare(mech, 1.0)
    return sim_model.choose_timestep(mech, 1.0)


def repro(name: str, over: dict, revolutions: float = 1.0, loads=None) -> str:
    sets = " ".join(f"--set {k}={v!r}" for k, v in over.items())
    rev = "" if revolutions == 1.0 else f" --revolutions {revolutions:g}"
    if loads is not None:
        if loads.gravity is not None:
            rev += f" --gravity {loads.gravity[0]!r},{loads.gravity[1]!r}"
        rev += f" --force {loads.force[0]!r},{loads.force[1]!r}"
    return f"linkage compare {name} {sets}{rev}"


def pct(x, q):
    return float(np.percentile(np.asarray(x), q))


# ---------------------------------------------------------------------------------------------- the run
def run(args) -> int:
    rng = np.random.default_rng(args.seed)
    rng_loads = np.random.default_rng([args.seed, 1])
    names = [n for n in analytic.names() if not cams.elements(service.load(n))]
    print(f"left out (cams: a contact, not a joint; judged by compare against its compliance, sim/run/cams.py and docs/CONVENTIONS.md): "
          f"{', '.join(n for n in analytic.names() if n not in names)}")
    t_wall0, t_cpu0 = time.time(), time.process_time()
    refusals: Counter = Counter()
    refusals_by_mech: dict[str, Counter] = defaultdict(Counter)
    results, crashes = [], []
    attempts, slot = 0, 0
    cap = args.count * args.max_attempts_factor
    gave_up: Counter = Counter()
    while len(results) < args.count and attempts < cap:
        name = str(rng.choice(names)) if args.random_mechanism else names[slot % len(names)]
        slot += 1
        for j in range(args.tries_per_design):
            attempts += 1
            # +-PERTURB at first; halved every 10 refusals (tightly constrained files, e.g. Klann's triangles)
            over, info = draw(rng, name, PERTURB * 0.5 ** (j // 10))
            try:
                mech = service.load(name, over)
                validate(mech)
                break
            except ParameterError as exc:
                r = reason_of(str(exc))
                refusals[r] += 1
                refusals_by_mech[name][r] += 1
            except Exception as exc:                                      # noqa: BLE001 - a bug, reported
                r = f"CRASH {type(exc).__name__}: {str(exc)[:60]}"
                refusals[r] += 1
                refusals_by_mech[name][r] += 1
                frames = traceback.extract_tb(exc.__traceback__)
                where = next((f for f in reversed(frames) if ".venv" not in f.filename
                              and "site-packages" not in f.filename), frames[-1])
                crashes.append((name, over, f"{type(exc).__name__}: {exc} "
                                            f"({Path(where.filename).name}:{where.lineno} in {where.name})"))
        else:
            gave_up[name] += 1
            continue
        loads = draw_loads(rng_loads, mech)
        rec = {"name": name, "over": over, "info": info, "size": mech.size, "loads": loads}
        c0 = time.process_time()
        try:
            built, c = service.compare(mech, 1.0, loads=loads)
        except Exception as exc:                                      # noqa: BLE001 - a failure, reported
            rec.update(ok=False, error=f"{type(exc).__name__}: {exc}", cpu_total=time.process_time() - c0)
            if args.verbose:
                traceback.print_exc()
            results.append(rec)
            print(f"[{len(results):4d}] {name:<22s} ERROR {rec['error'][:100]}", flush=True)
            continue
        tr = c.trajectory
        j = judge(mech, tr)
        forces = force_ratios(built, tr)
        j["ratios"].update(forces)
        for k, v in forces.items():
            j["detail"][k] = (k, v * FORCE, FORCE)
        worst = max(j["ratios"], key=j["ratios"].get)
        rec.update(ok=max(j["ratios"].values()) <= 1.0, ratios=j["ratios"], detail=j["detail"],
                   kinds={n: kind_of(mech, n) for n in mech.outputs}, own_verdict=c.passed,
                   forces=forces, own_forces=c.forces.worst / c.forces.tol if c.forces is not None else None,
                   torque={n: e["max"] / e["tol"] for n, e in c.errors.items() if n.startswith("tau")},
                   work=c.work_balance, h=tr.timestep, steps=tr.steps, cpu=tr.cpu_seconds,
                   cpu_total=time.process_time() - c0, worst=(worst, j["ratios"][worst]),
                   # own error computation against sim.run.compare's (same data: should agree to rounding)
                   agree=max((abs(j["detail"][n][1] - e["max"]) / max(e["max"], 1e-300)
                              for n, e in c.errors.items() if n in j["detail"]), default=0.0),
                   duration=mech.duration(1.0))
        results.append(rec)
        if args.verbose or not rec["ok"]:
            print(f"[{len(results):4d}] {name:<22s} size {mech.size:9.4g} m  {info['rev_s']:+7.2f} rev/s  "
                  f"h {tr.timestep:.3g}  worst {worst} {j['ratios'][worst]:.3g}  "
                  f"{'ok' if rec['ok'] else 'FAIL'}  (compare.passed={c.passed})", flush=True)
    report(args, names, results, refusals, refusals_by_mech, attempts, cap,
           time.time() - t_wall0, time.process_time() - t_cpu0)
    if gave_up:
        print("no valid design within --tries-per-design draws: " + ", ".join(f"{k} {v}x" for k, v in gave_up.items()))
    if crashes:
        print(f"\ncrashes while validating (not a ParameterError): {len(crashes)}; the first of each mechanism:")
        seen = set()
        for name, over, msg in crashes:
            if name in seen:
                continue
            seen.add(name)
            print(f"  {name}: {msg}")
            print(f"    {repro(name, over)}")
    if args.long:
        long_runs(args, rng, names)
    return 0


def report(args, names, results, refusals, refusals_by_mech, attempts, cap, wall, cpu) -> None:
    n = len(results)
    print()
    print(f"== trust: {n} valid designs (seed {args.seed}) from {attempts} attempts"
          f"{' (attempt cap reached)' if attempts >= cap and n < args.count else ''}")
    print(f"refused up front: {sum(refusals.values())}")
    for r, k in refusals.most_common():
        print(f"  {k:5d}  {r}")
    if not n:
        return
    ok = [r for r in results if r["ok"]]
    rate = len(ok) / n
    print(f"\npass rate (issue targets): {len(ok)}/{n} = {100 * rate:.1f} %  "
          f"(target >= {100 * PASS_RATE:.0f} %: {'MET' if rate >= PASS_RATE else 'NOT MET'})")
    loaded = [r for r in results if r.get("loads") is not None]
    if loaded:
        g = sum(r["loads"].gravity is not None for r in loaded)
        print(f"  with loads (force on the output point, {g} also with gravity): "
              f"{sum(r['ok'] for r in loaded)}/{len(loaded)} pass")
    own = [r for r in results if r.get("own_verdict")]
    print(f"sim.run.compare's own verdict passed: {len(own)}/{n}; disagreements with the issue targets: "
          f"{sum(1 for r in results if 'own_verdict' in r and r['own_verdict'] != r['ok'])}")
    print(f"\n{'mechanism':<22s} {'valid':>5s} {'pass':>5s} {'rate':>7s} {'refused':>7s}  worst error/target (output)")
    for name in names:
        rs = [r for r in results if r["name"] == name]
        refused = sum(refusals_by_mech[name].values())
        if not rs:
            print(f"{name:<22s} {0:5d} {0:5d} {'-':>7s} {refused:7d}")
            continue
        p = sum(r["ok"] for r in rs)
        w = max((r for r in rs if "worst" in r), key=lambda r: r["worst"][1], default=None)
        ws = f"{w['worst'][1]:.3g} ({w['worst'][0]})" if w else "-"
        print(f"{name:<22s} {len(rs):5d} {p:5d} {100 * p / len(rs):6.1f}% {refused:7d}  {ws}")
    reduced = Counter(r["name"] for r in results if r["info"]["perturb"] < PERTURB)
    if reduced:
        print("\ndesigns drawn with a reduced length perturbation (after 10+ refusals): "
              + ", ".join(f"{k} {v}" for k, v in reduced.most_common()))
    print("\nrefusals by mechanism:")
    for name in names:
        if refusals_by_mech[name]:
            print(f"  {name:<22s} " + ", ".join(f"{r} {k}" for r, k in refusals_by_mech[name].most_common()))

    # worst ratio per output kind
    per_kind: dict[str, tuple[float, dict, str]] = {}
    for r in results:
        if "ratios" not in r:
            continue
        for out, ratio in r["ratios"].items():
            kind = r["kinds"].get(out, out)
            if kind not in per_kind or ratio > per_kind[kind][0]:
                per_kind[kind] = (ratio, r, out)
    print("\nworst error/target per output kind (<= 1 passes):")
    print(f"  {'kind':<18s} {'ratio':>10s} {'median':>10s}  where")
    for kind in ("angle", "position", "ang_velocity", "velocity", "ang_acceleration", "acceleration", "loop",
                 "drive", "joint_forces", "joint_couples", "drive_forces", "shaking_force"):
        if kind not in per_kind:
            continue
        ratio, r, out = per_kind[kind]
        allk = [max(v for o, v in x["ratios"].items() if x["kinds"].get(o, o) == kind)
                for x in results if "ratios" in x and any(x["kinds"].get(o, o) == kind for o in x["ratios"])]
        print(f"  {kind:<18s} {ratio:10.3g} {np.median(allk):10.3g}  {r['name']} {out} "
              f"(size {r['size']:.3g} m, {r['info']['rev_s']:+.2f} rev/s)")
    agree = [r["agree"] for r in results if "agree" in r]
    if agree:
        print(f"  (check) own max errors vs sim.run.compare's errors[...]['max']: largest relative difference "
              f"{max(agree):.2g}")
    tq = [max(r["torque"].values()) for r in results if r.get("torque")]
    wk = [r["work"] for r in results if "work" in r]
    if tq:
        print(f"  (info) torque vs inverse dynamics, error/TORQUE_TOL: median {np.median(tq):.3g}, max {max(tq):.3g}")
    if wk:
        print(f"  (info) work balance per revolution / {WORK:g}: median {np.median(wk) / WORK:.3g}, "
              f"max {max(wk) / WORK:.3g}")

    forced = [r for r in results if r.get("forces")]
    if forced:
        print(f"\njoint forces against MuJoCo's (target {FORCE:g} of the peak joint force): "
              f"{sum(max(r['forces'].values()) <= 1.0 for r in forced)}/{len(forced)} designs within it "
              f"({len(results) - len(forced)} without: statically indeterminate or failed)")
        for label, group in (("unloaded", [r for r in forced if r["loads"] is None]),
                             ("loaded", [r for r in forced if r["loads"] is not None])):
            if not group:
                continue
            parts = []
            for key in ("joint_forces", "joint_couples", "drive_forces", "shaking_force"):
                v = [FORCE * r["forces"][key] for r in group if key in r["forces"]]
                if v:
                    parts.append(f"{key} median {np.median(v):.2g} max {max(v):.2g}")
            print(f"  {label} ({len(group)}): " + "; ".join(parts) + " (of the peak)")
        own = [(r["own_forces"], FORCE * max(r["forces"].values())) for r in forced if r.get("own_forces") is not None]
        if own:
            print(f"  (check) sim.run.compare's forces verdict: worst {max(o for o, _ in own) * FORCE:.2g} of the peak")

    fails = [r for r in results if not r["ok"]]
    print(f"\nfailing designs: {len(fails)}")
    for r in fails:
        info = r["info"]
        head = (f"  {r['name']}: size {r['size']:.4g} m, {info['rev_s']:+.3f} rev/s, speed change "
                f"{100 * info['speed_change']:+.0f} %, lengths +-{100 * info['perturb']:.0f} %" + (f", ratio {info['ratio']:.3f}" if "ratio" in info else ""))
        print(head)
        if "error" in r:
            print(f"    {r['error']}")
        else:
            bad = sorted(((v, o) for o, v in r["ratios"].items() if v > 1.0), reverse=True)
            for v, o in bad[:8]:
                kind, err, tol = r["detail"][o]
                print(f"    {o:<10s} {kind:<16s} error {err:.3e} target {tol:.3e}  ratio {v:.3g}")
            print(f"    h {r['h']:.4g} s, {r['steps']} steps; sim.run.compare passed={r['own_verdict']}")
        print(f"    {repro(r['name'], r['over'], loads=r['loads'])}")

    sims = [r for r in results if "cpu" in r]
    if sims:
        ms = [1e3 * r["cpu"] for r in sims]                 # rollout CPU per 1 simulated revolution
        tot = [1e3 * r["cpu_total"] for r in sims]
        hs = [r["h"] for r in sims]
        steps = [r["steps"] for r in sims]
        print(f"\nCPU ms per simulated revolution (rollout, time.process_time): min {min(ms):.1f}, median "
              f"{np.median(ms):.1f}, p90 {pct(ms, 90):.1f}, max {max(ms):.1f}  (target median <= "
              f"{CPU_MS_PER_REV:g}: {'MET' if np.median(ms) <= CPU_MS_PER_REV else 'NOT MET'})")
        print(f"CPU ms per design, build + simulate + compare:     min {min(tot):.1f}, median {np.median(tot):.1f}, "
              f"p90 {pct(tot, 90):.1f}, max {max(tot):.1f}")
        print(f"time step [s]: min {min(hs):.3g}, median {np.median(hs):.3g}, p90 {pct(hs, 90):.3g}, "
              f"max {max(hs):.3g}; at MAX_TIMESTEP {sum(h >= sim_model.MAX_TIMESTEP * (1 - 1e-12) for h in hs)}")
        print(f"steps per revolution: min {min(steps)}, median {np.median(steps):.0f}, p90 {pct(steps, 90):.0f}, "
              f"max {max(steps)}")
        print("costliest designs:")
        for r in sorted(sims, key=lambda r: -r["cpu"])[:3]:
            print(f"  {1e3 * r['cpu']:.0f} ms: {r['name']} size {r['size']:.3g} m, {r['info']['rev_s']:+.2f} rev/s, "
                  f"{r['steps']} steps of {r['h']:.3g} s (crank turns {2 * math.pi / r['steps']:.2g} rad/step on "
                  f"average)")
            print(f"    {repro(r['name'], r['over'], loads=r['loads'])}")
        us = [1e6 * r["cpu"] / r["steps"] for r in sims]
        print(f"CPU us per step: min {min(us):.1f}, median {np.median(us):.1f}, max {max(us):.1f}")
        print("median CPU ms per revolution by mechanism: " + ", ".join(
            f"{nm} {np.median([1e3 * r['cpu'] for r in sims if r['name'] == nm]):.1f}"
            for nm in names if any(r["name"] == nm for r in sims)))
    print(f"\ntotal: {wall:.1f} s wall, {cpu:.1f} s CPU")


# ---------------------------------------------------------------------------------------------- --long
def long_runs(args, rng, names) -> None:
    """A few steady designs for many revolutions: every error/target per revolution must stay flat (the
    last revolution's worst against the first's) and the work balance per revolution within WORK. Two-crank
    designs get an integer speed ratio, so that every revolution of the first crank repeats the same poses."""
    revs = args.long_revolutions
    print(f"\n== long runs: {args.long_count} designs x {revs:g} revolutions (flat: last/first <= "
          f"{args.max_growth:g}; work balance <= {WORK:g} per revolution)")
    print(f"  {'mechanism':<22s} {'size':>7s} {'rev/s':>7s} {'ratio':>5s} {'first':>8s} {'last':>8s} {'max':>8s} "
          f"{'last/first':>10s} {'drive 1st':>9s} {'drive last':>10s} {'work/rev':>9s} {'cpu s':>6s}  worst output")
    done, tries = 0, 0
    picks = [names[k] for k in rng.permutation(len(names))]
    while done < args.long_count and tries < 50 * args.long_count:
        name = picks[done % len(picks)]
        tries += 1
        ratio = float(rng.choice([-2.0, -1.0, 1.0, 2.0, 3.0]))
        over, info = draw(rng, name, ratio=ratio, accelerate=False)
        try:
            mech = service.load(name, over)
            service.prepare(mech, revs)
            sim_model.choose_timestep(mech, revs)
        except ParameterError:
            continue
        except Exception:                                      # noqa: BLE001 - reported by the main run
            continue
        c0 = time.process_time()
        try:
            built, c = service.compare(mech, revs)
        except Exception as exc:                               # noqa: BLE001
            print(f"  {name:<22s} ERROR {type(exc).__name__}: {exc}")
            print(f"    {repro(name, over, revs)}")
            done += 1
            continue
        tr = c.trajectory
        series = error_series(mech, tr)
        cuts = np.searchsorted(tr.t, [mech.duration(k) if k else 0.0 for k in range(int(revs))] + [np.inf])
        per_rev = [judge(mech, tr, slice(cuts[k], cuts[k + 1]), series)["ratios"] for k in range(int(revs))]
        keys = [k for k in per_rev[0] if k != "drive"]
        worst = max(keys, key=lambda k: max(r[k] for r in per_rev))
        f, lst = per_rev[0][worst], per_rev[-1][worst]
        top = max(r[worst] for r in per_rev)
        growth = lst / f if f > 0 else math.inf
        d1, dl = per_rev[0]["drive"] * DRIVE, per_rev[-1]["drive"] * DRIVE
        ok = top <= 1.0 and c.work_balance <= WORK and growth <= args.max_growth and dl <= DRIVE
        rstr = f"{info['ratio']:5.0f}" if "ratio" in info else f"{'-':>5s}"
        print(f"  {name:<22s} {mech.size:7.3g} {info['rev_s']:+7.2f} {rstr} {f:8.3g} {lst:8.3g} {top:8.3g} "
              f"{growth:10.3g} {d1:9.2e} {dl:10.2e} {c.work_balance:9.2e} {time.process_time() - c0:6.1f}  "
              f"{worst}  {'ok' if ok else 'FAIL'}", flush=True)
        if not ok:
            print(f"    {repro(name, over, revs)}")
        done += 1


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, default=200, help="valid designs to simulate (default 200)")
    ap.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    ap.add_argument("--max-attempts-factor", type=int, default=20, help="draw at most FACTOR * count designs")
    ap.add_argument("--random-mechanism", action="store_true",
                    help="draw the mechanism at random (default: cycle through them, equal shares)")
    ap.add_argument("--tries-per-design", type=int, default=40,
                    help="draws of one mechanism before giving up on that slot (default 40)")
    ap.add_argument("--long", action="store_true", help="also run a few designs for many revolutions")
    ap.add_argument("--long-count", type=int, default=5)
    ap.add_argument("--long-revolutions", type=float, default=50.0)
    ap.add_argument("--max-growth", type=float, default=2.0,
                    help="--long: largest accepted last/first revolution error ratio (default 2)")
    ap.add_argument("--verbose", action="store_true")
    args = ap.parse_args(argv)
    return run(args)


if __name__ == "__main__":
    sys.exit(main())
