"""MuJoCo models of the mechanisms: the MJCF files in ``mjcf/`` with the user's parameters applied
through :class:`mujoco.MjSpec`, and the initial state assembled from the analytic solver.

Everything is looked up by name (bodies, geoms, sites, joints, keys), never by index.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

import mjcf
from analytic import ParameterError, fivebar, fourbar, sixbar
from .params import mechanism_name

MJCF_DIR = Path(mjcf.__file__).resolve().parent

INTEGRATORS = {"euler": mujoco.mjtIntegrator.mjINT_EULER, "rk4": mujoco.mjtIntegrator.mjINT_RK4,
               "implicit": mujoco.mjtIntegrator.mjINT_IMPLICIT,
               "implicitfast": mujoco.mjtIntegrator.mjINT_IMPLICITFAST}
if hasattr(mujoco.mjtIntegrator, "mjINT_DISCRETE"):
    INTEGRATORS["discrete"] = mujoco.mjtIntegrator.mjINT_DISCRETE

DEFAULT_TIMESTEP = 0.002
DEFAULT_INTEGRATOR = "rk4"
SERVO_RATIO = 0.25
"""kv * timestep / armature of the crank velocity servos, i.e. the servo's time constant is 4 steps. RK4 is
stable up to 2.78, but a servo mode resolved by only 1 step lets the integrator pump energy: the work
balance of linkage compare was 1e-4 (four-bar) to 4e-3 (loaded shaper) of the kinetic-energy swing at 1,
1e-5 at 0.25 (benchmarks/simulate.py). kv follows the timestep."""
LOOP_TIMECONST = 16.0
"""Time constant of the loops' drift correction, in timesteps (solref[0] = LOOP_TIMECONST * timestep).
With the regularisation below made negligible, the loops are held by the constraint force itself and
this Baumgarte-style correction only removes integration drift; a slow one (16 steps) disturbs RK4 least:
errors fell 10-50x from 3 to 16 steps in the study of benchmarks/simulate.py."""
REGULARIZATION_SCALE = 1e-4
"""Scale applied to the compiled ``body_invweight0``. MuJoCo sizes each constraint's regulariser as
R = (1 - d) / d * invweight with the impedance d capped at 0.9999, and that leak of 1e-4 of the constraint
force shows up as loop violation (up to 3e-7 m) and velocity error (up to 1e-3 rad/s) in these fast
linkages. invweight0 serves only that purpose in a model without contacts, so scaling it by 1e-4 acts as
an impedance of 1 - 1e-8 (measured: violation 2e-7 -> 2e-8 m for the five-bar at omega4 = 2 omega2)."""
CRANK_ARMATURE = 0.01
"""Rotor inertia [kg m^2] added to each driven crank joint: a motor's rotor, which also lets the servo
be stiff (kv = armature / timestep) so that the crank speed ripples by ~1 % (reported by compare)."""
RIPPLE_TARGET = 0.01
"""Drives are sized so that the peak analytic torque would slow the crank by at most 1 % of its speed
through the servo (kv >= peak torque / (0.01 omega)); the armature grows with kv (kv h / armature = 1),
like the reflected inertia of a bigger geared motor. Unloaded defaults keep CRANK_ARMATURE."""


def mjcf_path(name: str) -> Path:
    """Path of the MJCF file of mechanism ``name``."""
    return MJCF_DIR / f"{name}.xml"


@dataclass(frozen=True)
class Loads:
    """What acts on the mechanism besides its drives.

    ``gravity`` (gx, gy) [m/s^2] in the plane (None: MuJoCo's -z gravity, normal to the plane, no effect);
    ``force`` (Fx, Fy) [N] on the output point (four-bar E, shaper ram C, five-bar P), fixed in the world
    frame; ``cutting_only`` (shaper) applies it only during the slow (cutting) stroke; ``inertias``
    replaces bodies' inertial data (keyed by MJCF body name) on the MuJoCo side too.
    """

    gravity: tuple[float, float] | None = None
    force: tuple[float, float] = (0.0, 0.0)
    cutting_only: bool = False
    inertias: dict | None = None


@dataclass(frozen=True)
class Built:
    """A compiled model with the parameters it was built from and its initial state."""

    name: str
    mech: object
    model: mujoco.MjModel
    qpos0: np.ndarray
    qvel0: np.ndarray
    ctrl0: np.ndarray
    loads: Loads = Loads()
    rock: tuple[float, float] | None = None
    """Four-bar only: the crank rocks between these angles [rad] instead of turning (see check_rock)."""

    @property
    def cranks(self) -> tuple[str, ...]:
        """Names of the crank velocity actuators (every actuator but the load)."""
        return tuple(self.model.actuator(i).name for i in range(self.model.nu)
                     if self.model.actuator(i).name != "load")


def check_settings(timestep: float, integrator: str) -> None:
    if not (isinstance(timestep, float | int) and math.isfinite(timestep) and 0 < timestep <= 0.05):
        raise ParameterError(f"--timestep {timestep!r} must be a number in (0, 0.05] s (e.g. 0.001)")
    if integrator not in INTEGRATORS:
        raise ParameterError(f"--integrator {integrator!r} is not known: use one of {', '.join(INTEGRATORS)}")


def build(mech, timestep: float = DEFAULT_TIMESTEP, integrator: str = DEFAULT_INTEGRATOR,
          timeconst: float = LOOP_TIMECONST, loads: Loads = Loads(),
          rock: tuple[float, float] | None = None) -> Built:
    """Compile the mechanism's MJCF with ``mech``'s parameters, simulation settings, loads and initial
    state. ``rock`` (four-bar): drive the crank back and forth between two angles [rad], starting at rest
    at the first, phi(t) = mid - amp cos(|omega1| t)."""
    check_settings(timestep, integrator)
    name = mechanism_name(mech)
    if rock is not None:
        check_rock(mech, rock)
        from dataclasses import replace
        mech = replace(mech, phi1_0=rock[0])
    spec = mujoco.MjSpec.from_file(str(mjcf_path(name)))
    _GEOMETRY[name](spec, mech)
    _scale_visuals(spec, _scale(name, mech))
    _apply_loads(spec, name, loads)
    joints, ctrl = _INITIAL[name](mech)
    if rock is not None:                            # at rest at the first angle
        joints = {j: (q, 0.0) for j, (q, _) in joints.items()}
        ctrl = [0.0]
    ctrl = list(ctrl) + [0.0]                      # the load actuator, switched by the controls
    spec.option.timestep = float(timestep)
    spec.option.integrator = INTEGRATORS[integrator]
    for act in spec.actuators:
        if act.name == "load":
            continue
        joint = spec.joint(act.target)
        joint.armature = CRANK_ARMATURE
        kv = SERVO_RATIO * CRANK_ARMATURE / timestep
        act.gainprm[0] = kv          # velocity servo: force = kv * (ctrl - qvel)
        act.biasprm[2] = -kv
    for eq in spec.equalities:
        eq.solref[0] = timeconst * timestep
    _frame_camera(spec, name, mech)
    model = spec.compile()
    model.body_invweight0[:] *= REGULARIZATION_SCALE
    _size_drives(model, name, mech, loads, timestep, rock)
    qpos = np.zeros(model.nq)
    qvel = np.zeros(model.nv)
    for jname, (q, v) in joints.items():
        j = model.joint(jname)
        qpos[j.qposadr[0]] = q
        qvel[j.dofadr[0]] = v
    # The MJCF's home keyframe is the SPEC default; the built model's keyframe is this mechanism's.
    key = model.key("home")
    key.qpos[:] = qpos
    key.qvel[:] = qvel
    key.ctrl[:] = ctrl
    return Built(name, mech, model, qpos, qvel, np.asarray(ctrl, float), loads, rock)


ROCK_MARGIN = math.radians(1.0)
"""A rocking crank must stay this far inside its reachable interval: at a limit angle the loop is at a
dead centre, where the servo could push it through to the other branch."""


def check_rock(mech, rock: tuple[float, float]) -> None:
    """The rocking range must be a four-bar's, ordered, and inside one reachable crank interval with a
    margin of ROCK_MARGIN; the error names the limits."""
    if mechanism_name(mech) != "fourbar":
        raise ParameterError("--input-range applies to the four-bar only (its crank may not turn fully)")
    lo, hi = rock
    if not hi > lo:
        raise ParameterError(f"--input-range {math.degrees(lo):.2f}deg:{math.degrees(hi):.2f}deg: the end must "
                             f"exceed the start")
    lim = fourbar.crank_limits(mech)
    if lim.full_turn:
        return
    for a, b in lim.intervals:
        for shift in (0.0, 2 * math.pi, -2 * math.pi):
            if a + ROCK_MARGIN <= lo + shift and hi + shift <= b - ROCK_MARGIN:
                return
    raise ParameterError(
        f"--input-range {math.degrees(lo):.2f}deg:{math.degrees(hi):.2f}deg leaves the crank's reachable range "
        f"{fourbar.describe_range(lim)} (keep {math.degrees(ROCK_MARGIN):g}deg clear of the limit angles)")


def _size_drives(model: mujoco.MjModel, name: str, mech, loads: Loads, timestep: float, rock=None) -> None:
    """Stiffen each crank servo (and its rotor) where the load needs it; see RIPPLE_TARGET."""
    from analytic.dynamics import INPUTS, torques
    inputs = INPUTS[name]
    t = np.linspace(0.0, 1.0, 721)
    if name == "fivebar":                          # both cranks back where they started
        from analytic.studies import common_period
        period = common_period(mech.omega2, mech.omega4)[0]
    else:
        period = 2 * math.pi / (abs(mech.omega1) or 1.0)
    if rock is not None:                          # the rocking motion of the four-bar crank
        rate, amp = abs(mech.omega1), 0.5 * (rock[1] - rock[0])
        u = rate * t * period
        phi, omega, alpha = ({"1": 0.5 * (rock[0] + rock[1]) - amp * np.cos(u)}, {"1": amp * rate * np.sin(u)},
                             {"1": amp * rate ** 2 * np.cos(u)})
        speeds = {"1": amp * rate}
    else:
        phi = {j: getattr(mech, f"phi{j}_0") + getattr(mech, f"omega{j}") * t * period for j in inputs}
        omega = {j: np.full_like(t, getattr(mech, f"omega{j}")) for j in inputs}
        alpha = {j: np.zeros_like(t) for j in inputs}
        speeds = {j: abs(getattr(mech, f"omega{j}")) for j in inputs}
    names = [model.body(i).name for i in range(1, model.nbody)]
    gravity = tuple(model.opt.gravity[:2])
    tau = torques(name, mech, phi, omega, alpha, body_inertias(model, names), None, gravity,
                  tuple(model.actuator("load").gear[:2]), 1.0)
    for j, act in zip(inputs, [a for a in (model.actuator(i) for i in range(model.nu)) if a.name != "load"]):
        speed = speeds[j]
        if speed == 0:
            continue
        kv = float(np.max(np.abs(tau[f"tau{j}"]))) / (RIPPLE_TARGET * speed)
        if kv > act.gainprm[0]:
            act.gainprm[0], act.biasprm[2] = kv, -kv
            model.dof_armature[model.jnt_dofadr[act.trnid[0]]] = kv * timestep / SERVO_RATIO


def _apply_loads(spec, name: str, loads: Loads) -> None:
    if loads.gravity is not None:
        gx, gy = loads.gravity
        if not (math.isfinite(gx) and math.isfinite(gy)):
            raise ParameterError(f"--gravity {loads.gravity} must be two finite numbers gx,gy [m/s^2]")
        spec.option.gravity = [gx, gy, 0.0]
    fx, fy = loads.force
    if not (math.isfinite(fx) and math.isfinite(fy)):
        raise ParameterError(f"--force {loads.force} must be two finite numbers Fx,Fy [N]")
    spec.actuator("load").gear = [fx, fy, 0.0, 0.0, 0.0, 0.0]
    for body, inertia in (loads.inertias or {}).items():
        b = spec.body(body)
        if b is None:
            raise ParameterError(f"--inertia: the {name} has no body {body!r}")
        b.explicitinertial = True
        b.mass = inertia.m
        b.ipos = [inertia.cx, inertia.cy, 0.0]
        b.iquat = [1.0, 0.0, 0.0, 0.0]
        # A thin plate in the plane: Ixx + Iyy = Izz satisfies the triangle inequality.
        b.inertia = [inertia.I / 2, inertia.I / 2, inertia.I]


def body_inertias(model: mujoco.MjModel, names) -> dict:
    """The compiled bodies' inertial data as analytic.dynamics.Inertia (mass, COM in the body frame, Izz
    about the COM in the body frame)."""
    from analytic.dynamics import Inertia
    out = {}
    for n in names:
        b = model.body(n)
        rot = np.empty(9)
        mujoco.mju_quat2Mat(rot, b.iquat)
        rot = rot.reshape(3, 3)
        izz = float((rot @ np.diag(b.inertia) @ rot.T)[2, 2])
        out[n] = Inertia(m=float(b.mass[0]), cx=float(b.ipos[0]), cy=float(b.ipos[1]), I=izz)
    return out


# ------------------------------------------------------------------------------------ geometry
def _set(spec, kind: str, name: str, **attrs) -> None:
    element = getattr(spec, kind)(name)
    if element is None:
        raise KeyError(f"MJCF has no {kind} named {name!r}")
    for key, value in attrs.items():
        setattr(element, key, value)


def _fourbar_geometry(spec, m: fourbar.FourBar) -> None:
    _set(spec, "site", "D", pos=[m.l4, 0, 0])
    _set(spec, "geom", "ground_D", pos=[m.l4, -0.012, -0.012])
    _set(spec, "geom", "crank", fromto=[0, 0, 0, m.l1, 0, 0])
    _set(spec, "site", "B_crank", pos=[m.l1, 0, 0])
    _set(spec, "body", "coupler", pos=[m.l1, 0, 0])
    _set(spec, "geom", "coupler", fromto=[0, 0, 0.012, m.l2, 0, 0.012])
    _set(spec, "geom", "coupler_E", fromto=[0, 0, 0.012, m.ex, m.ey, 0.012])
    _set(spec, "site", "C_coupler", pos=[m.l2, 0, 0])
    _set(spec, "site", "E", pos=[m.ex, m.ey, 0])
    _set(spec, "body", "rocker", pos=[m.l4, 0, 0])
    _set(spec, "geom", "rocker", fromto=[0, 0, 0.006, m.l3, 0, 0.006])
    _set(spec, "geom", "pin_C", pos=[m.l3, 0, 0.012])
    _set(spec, "site", "C", pos=[m.l3, 0, 0])


def _sixbar_geometry(spec, m: sixbar.SixBar) -> None:
    _set(spec, "site", "O2", pos=[0, m.l6, 0])
    _set(spec, "geom", "ground_O2", pos=[-0.02, m.l6, -0.012])
    _set(spec, "body", "crank", pos=[0, m.l6, 0])
    _set(spec, "geom", "crank", fromto=[0, 0, 0.012, m.l1, 0, 0.012])
    _set(spec, "geom", "pin_A", pos=[m.l1, 0, 0.018])
    _set(spec, "site", "A", pos=[m.l1, 0, 0])
    _set(spec, "geom", "guide", fromto=[0, 0, 0, m.l3, 0, 0])
    _set(spec, "site", "B_guide", pos=[m.l3, 0, 0])
    _set(spec, "body", "rod", pos=[m.l3, 0, 0])
    _set(spec, "geom", "rod", fromto=[0, 0, 0.012, m.l4, 0, 0.012])
    _set(spec, "site", "C_rod", pos=[m.l4, 0, 0])
    _set(spec, "body", "ram", pos=[0, m.h, 0])
    f = sixbar.figures(m)
    lo, hi = sorted(f.xC_limits)
    _set(spec, "geom", "ram_guide", pos=[0.5 * (lo + hi), m.h, -0.02], size=[0.5 * (hi - lo) + 0.06, 0.004, 0.002])


def _fivebar_geometry(spec, m: fivebar.FiveBar) -> None:
    _set(spec, "site", "D", pos=[m.l1, 0, 0])
    _set(spec, "geom", "ground_D", pos=[m.l1, -0.012, -0.02])
    _set(spec, "geom", "crank2", fromto=[0, 0, 0, m.l2, 0, 0])
    _set(spec, "site", "B_crank2", pos=[m.l2, 0, 0])
    _set(spec, "body", "link3", pos=[m.l2, 0, 0])
    # Link 3 reaches past both P and the farthest block position S_max = l1 + l2 + l4.
    _set(spec, "geom", "link3", fromto=[0, 0, 0.012, max(m.lp, m.l1 + m.l2 + m.l4) + 0.01, 0, 0.012])
    _set(spec, "site", "P", pos=[m.lp, 0, 0])
    _set(spec, "body", "crank4", pos=[m.l1, 0, 0])
    _set(spec, "geom", "crank4", fromto=[0, 0, 0, m.l4, 0, 0])
    _set(spec, "geom", "pin_C", pos=[m.l4, 0, 0.02])
    _set(spec, "site", "C", pos=[m.l4, 0, 0])


_GEOMETRY = {"fourbar": _fourbar_geometry, "sixbar": _sixbar_geometry, "fivebar": _fivebar_geometry}


def _lengths(mech) -> list[float]:
    return [v for k, v in vars(mech).items() if k[0] == "l" and isinstance(v, float)]


def _scale(name: str, mech) -> float:
    """Size of ``mech`` relative to its SPEC default (longest length against longest length)."""
    from .params import CLASSES
    return max(_lengths(mech)) / max(_lengths(CLASSES[name]()))


def _scale_visuals(spec, k: float) -> None:
    """Scale link thickness, pins, blocks, anchors and markers with the mechanism's size, so that a
    36 mm linkage is drawn like a 300 mm one (masses follow: capsules of steel, ~k^3)."""
    if abs(k - 1.0) < 1e-12:
        return
    for g in spec.geoms:
        if g.name == "paper":
            continue
        g.size = [x * k for x in g.size]
        if g.name.startswith("ground_"):
            pivot = spec.site(g.name[len("ground_"):]).pos
            g.pos = [pivot[0], pivot[1] - 0.012 * k, -0.012 * k]
        else:
            g.pos = [g.pos[0], g.pos[1], g.pos[2] * k]
            if g.type == mujoco.mjtGeom.mjGEOM_CAPSULE:
                f = list(g.fromto)
                g.fromto = [f[0], f[1], f[2] * k, f[3], f[4], f[5] * k]
    for site in spec.sites:
        site.size = [x * k for x in site.size]


# ------------------------------------------------------------------------------- initial state
def _wrap(a):
    return float(math.remainder(float(a), 2 * math.pi))


def _fourbar_initial(m: fourbar.FourBar):
    fourbar.check_reachable(m, [m.phi1_0])
    s = fourbar.solve(m, m.phi1_0, m.omega1, m.alpha1)
    joints = {"A": (m.phi1_0, m.omega1), "B": (_wrap(s.phi2 - m.phi1_0), float(s.omega2 - m.omega1)),
              "D": (float(s.phi3), float(s.omega3))}
    return joints, [m.omega1]


def _sixbar_initial(m: sixbar.SixBar):
    s = sixbar.solve(m, m.phi1_0, m.omega1, m.alpha1)
    joints = {"O2": (m.phi1_0, m.omega1), "O4": (float(s.phi3), float(s.omega3)), "s": (float(s.s), float(s.ds)),
              "B": (_wrap(s.phi4 - s.phi3), float(s.omega4 - s.omega3)), "xC": (float(s.xC), float(s.vxC))}
    return joints, [m.omega1]


def _fivebar_initial(m: fivebar.FiveBar):
    s = fivebar.solve(m, m.phi2_0, m.phi4_0, m.omega2, m.omega4, m.alpha2, m.alpha4)
    joints = {"A": (m.phi2_0, m.omega2), "B": (_wrap(s.theta3 - m.phi2_0), float(s.omega3 - m.omega2)),
              "S": (float(s.S), float(s.dS)), "D": (m.phi4_0, m.omega4)}
    return joints, [m.omega2, m.omega4]


_INITIAL = {"fourbar": _fourbar_initial, "sixbar": _sixbar_initial, "fivebar": _fivebar_initial}


# -------------------------------------------------------------------------------------- camera
def path_points(mech, samples: int = 361) -> np.ndarray:
    """Every drawn point over one period of the first crank, shape (k, 2) [m]: frames the camera."""
    name = mechanism_name(mech)
    t = np.linspace(0.0, 1.0, samples)
    if name == "fourbar":
        lim = fourbar.crank_limits(mech)
        phi0 = mech.phi1_0 % (2 * math.pi)                 # the interval the linkage starts in
        lo, hi = next(((a, b) for a, b in lim.intervals
                       if a <= phi0 <= b or a <= phi0 - 2 * math.pi <= b), lim.intervals[0])
        st = fourbar.solve(mech, lo + (hi - lo) * t, 1.0)
        pts = fourbar.joints(mech, st)
        return np.concatenate([np.column_stack(p) for p in pts.values()])
    if name == "sixbar":
        st = sixbar.solve(mech, 2 * math.pi * t, 1.0)
        xs = [st.xA, st.xB, st.xC, 0 * t, 0 * t]
        ys = [st.yA, st.yB, mech.h + 0 * t, 0 * t, mech.l6 + 0 * t]
        return np.column_stack([np.concatenate(xs), np.concatenate(ys)])
    period = 2 * math.pi / min(abs(mech.omega2), abs(mech.omega4)) if mech.omega2 and mech.omega4 else 1.0
    st = fivebar.solve(mech, *fivebar.drive(mech, t * period))
    xs = [st.xB, st.xC, st.xP, 0 * t, mech.l1 + 0 * t]
    ys = [st.yB, st.yC, st.yP, 0 * t, 0 * t]
    return np.column_stack([np.concatenate(xs), np.concatenate(ys)])


def _framing(mech, aspect: float) -> tuple[np.ndarray, float]:
    """Centre (x, y) [m] and vertical extent [m] of an orthographic view showing every drawn point of
    ``mech`` in an image of width/height ``aspect``, with a 30 % margin."""
    pts = path_points(mech)
    lo, hi = pts.min(0), pts.max(0)
    return 0.5 * (lo + hi), float(max(hi[1] - lo[1], (hi[0] - lo[0]) / aspect) * 1.3)


def _frame_camera(spec, name: str, mech, aspect: float = 4 / 3) -> None:
    center, extent = _framing(mech, aspect)
    _set(spec, "camera", "top", pos=[center[0], center[1], 1.0], fovy=extent)
    _set(spec, "geom", "paper", pos=[center[0], center[1], -0.03])


def frame_extent(mech, aspect: float) -> float:
    """The orthographic camera's vertical extent [m] that shows every point for an image ``aspect``."""
    return _framing(mech, aspect)[1]
