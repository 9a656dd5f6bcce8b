"""Peers' files that drive a linkage by a relative angle open with it (issue 37, item 8): a PMKS four-bar
A0-A-B-B0 whose driving joint is its coupler joint A (``crank coupler R``: PMKS turns the coupler relative to
the crank) imports as a ``motor`` and solves as a ``motor_dyad`` (the crank and coupler one bent link at the
driven angle, closed to B0 by the rocker). Checked against hand geometry (the law of cosines on the bent link),
finite differences, a power balance of the motor's torque and MuJoCo (``compare``); a driver on three links or
on the ground twice is refused in one line naming the joint."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import analytic
from tests.cli_runner import run
from tests.fourbar_text import joints_fourbar_text  # the mm four-bar in the links-and-joints form

A_, B_, C_, G_ = 100.0, 350.0, 300.0, 400.0       # |A0 A|, |A B|, |B B0|, |A0 B0| [mm]
Q0 = math.radians(60.0)                          # the crank's direction in the drawn pose


def _pose():
    """A0, A, B, B0 [mm] of the drawn pose: A at Q0 from A0, B on the circles about A and B0, above A -> B0."""
    a0, b0 = np.array([0.0, 0.0]), np.array([G_, 0.0])
    a = A_ * np.array([math.cos(Q0), math.sin(Q0)])
    d = float(np.linalg.norm(b0 - a))
    along = (B_ ** 2 - C_ ** 2 + d ** 2) / (2 * d)
    u = (b0 - a) / d
    b = a + along * u + math.sqrt(B_ ** 2 - along ** 2) * np.array([-u[1], u[0]])
    return a0, a, b, b0


def _pmks(first: str = "crank", second: str = "coupler") -> str:
    _, a, b, _ = _pose()
    return (f"ground crank R 0 0\n{first} {second} R {float(a[0])!r} {float(a[1])!r}\ncoupler rocker R {float(b[0])!r} {float(b[1])!r}\n"
            f"rocker ground R {G_!r} 0\nd=1\n")


def _imported(tmp_path, text: str, name: str = "fourbar"):
    src, out = tmp_path / f"{name}.txt", tmp_path / f"{name}.toml"
    src.write_text(text)
    r = run("import", src, "--out", out)
    assert r.returncode == 0, r.stderr
    return out, analytic.load(str(out))


def _hand(q, on_crank: bool = True, dims=(A_, B_, C_, G_)):
    """A and B [m] at the motor's angle q by hand: theta (coupler from crank) = q, or -q with the housing on
    the coupler; the side |A0 B| by the law of cosines on the bent link (interior angle pi - theta at A), B on
    the circles about A0 and B0 above A0 -> B0 (the pose's side), A at the angle alpha (law of cosines again)
    from A0 -> B, to its right where the coupler turns left of the crank (sin theta > 0)."""
    a_, b_, c_, g_ = dims
    th = np.asarray(q, dtype=float) * (1 if on_crank else -1)
    d = np.sqrt(a_ ** 2 + b_ ** 2 - 2 * a_ * b_ * np.cos(math.pi - th))
    x = (d ** 2 - c_ ** 2 + g_ ** 2) / (2 * g_)
    bx, by = x, np.sqrt(d ** 2 - x ** 2)
    alpha = np.arccos((a_ ** 2 + d ** 2 - b_ ** 2) / (2 * a_ * d))
    beta = np.arctan2(by, bx) - np.sign(np.sin(th)) * alpha
    return np.stack([a_ * np.cos(beta), a_ * np.sin(beta)]) / 1000, np.stack([bx, by]) / 1000


def test_a_pmks_relative_driver_imports_as_a_motor_and_solves_as_hand_geometry_says(tmp_path):
    out, mech = _imported(tmp_path, _pmks())
    assert "kind = \"motor\"" in out.read_text() and "link = \"coupler\"" in out.read_text()
    (e,) = mech.geometry.elements[:1]
    assert e["kind"] == "motor_dyad" and e["on"] == "crank" and tuple(e["links"]) == ("crank", "coupler")
    q = np.linspace(-math.pi, math.pi, 73)                # a full turn: |A0 B| in [250, 450] always closes
    sol = mech.solve(q)
    A, B = _hand(q)
    # two formulas for one intersection on a 0.4 m figure, double precision: rounding
    assert np.max(np.hypot(sol["xJ1"] - A[0], sol["yJ1"] - A[1])) <= 1e-12
    assert np.max(np.hypot(sol["xJ2"] - B[0], sol["yJ2"] - B[1])) <= 1e-12
    # the start angle is the pose's: the coupler's direction less the crank's
    a0, a, b, _ = _pose()
    (ux, uy), (vx, vy) = a - a0, b - a
    t = math.atan2(ux * vy - uy * vx, ux * vx + uy * vy)
    assert mech.inputs[0].motion.q0 == pytest.approx(t, abs=1e-12)    # one atan2 of pose numbers: rounding


def test_the_housing_on_the_coupler_drives_minus_the_angle(tmp_path):
    _, mech = _imported(tmp_path, _pmks("coupler", "crank"))
    (e,) = mech.geometry.elements[:1]
    assert e["kind"] == "motor_dyad" and e["on"] == "coupler"
    q = np.linspace(-3.0, 3.0, 31)
    sol = mech.solve(q)
    A, B = _hand(q, on_crank=False)
    # as above: rounding on a 0.4 m figure
    assert np.max(np.hypot(sol["xJ1"] - A[0], sol["yJ1"] - A[1])) <= 1e-12
    assert np.max(np.hypot(sol["xJ2"] - B[0], sol["yJ2"] - B[1])) <= 1e-12


@pytest.mark.parametrize("first, second", [("crank", "coupler"), ("coupler", "crank")])
def test_rates_match_finite_differences(tmp_path, first, second):
    _, mech = _imported(tmp_path, _pmks(first, second))
    q = np.linspace(-3.0, 3.0, 25)
    h = 1e-4
    names = ("J1", "J2")
    at = [mech.solve(q + k * h, 1.0, 0.0) for k in (-2, -1, 1, 2)]
    mid = mech.solve(q, 1.0, 0.0)
    acc_only = mech.solve(q, 0.0, 1.0)

    def fd(key):                                     # five-point derivative in q
        return (at[0][key] - 8 * at[1][key] + 8 * at[2][key] - at[3][key]) / (12 * h)

    for p in names:
        for ax in "xy":
            # five-point rule at h = 1e-4 on a 0.4 m figure: truncation ~h^4 x 0.4 and rounding ~1e-16 x 0.4 / h
            assert np.max(np.abs(fd(f"{ax}{p}") - mid[f"v{ax}{p}"])) <= 1e-9
            assert np.max(np.abs(fd(f"v{ax}{p}") - mid[f"a{ax}{p}"])) <= 1e-9      # qd = 1, qdd = 0
            assert np.max(np.abs(acc_only[f"a{ax}{p}"] - mid[f"v{ax}{p}"])) <= 1e-12  # qdd = 1: a = dx/dq
    for ln in ("crank", "coupler", "rocker"):
        assert np.max(np.abs(fd(f"omega{ln}") - mid[f"alpha{ln}"])) <= 1e-8     # as above, angles of order 1


def test_the_motor_torque_balances_the_load_and_kinetic_energy_power(tmp_path):
    out, mech = _imported(tmp_path, _pmks())
    inertia = {"crank": {"m": 0.3, "cx": 0, "cy": 0, "I": 300.0}, "coupler": {"m": 0.8, "cx": 0, "cy": 0, "I": 9000.0},
               "rocker": {"m": 0.5, "cx": 0, "cy": 0, "I": 4000.0}}          # I in kg mm^2 (the file's unit)
    path = tmp_path / "inertia.json"
    path.write_text(json.dumps(inertia))
    r = run("forces", out, "--torque", "3@rocker", "--inertia", path, "--samples", "37", "--json")
    assert r.returncode == 0, r.stderr
    f = json.loads(r.stdout)
    t = np.array(f["t"])
    tau = np.array(f["drives"]["q_J1"])
    m = mech.inputs[0].motion
    origins = mech.link_origins                      # each link's centre is at its frame's origin (cx = cy = 0)

    def kinetic(tt):
        s = mech.solve(m.q0 + m.rate * tt, m.rate, 0.0)
        ke = 0.0
        for ln, v in inertia.items():
            o = origins[ln]
            ke = ke + 0.5 * v["m"] * (s[f"vx{o}"] ** 2 + s[f"vy{o}"] ** 2) + 0.5 * v["I"] * 1e-6 * s[f"omega{ln}"] ** 2
        return ke, s
    h = 1e-5
    ke_rate = (kinetic(t - 2 * h)[0] - 8 * kinetic(t - h)[0] + 8 * kinetic(t + h)[0] - kinetic(t + 2 * h)[0]) / (12 * h)
    s = kinetic(t)[1]
    load = 3.0 * s["omegarocker"]                    # the load torque's power on the rocker [W]
    balance = tau * s["dq_J1"] + load - ke_rate
    scale = np.max(np.abs(tau * s["dq_J1"]))
    # five-point rule at h = 1e-5 s on energies of ~1e-2 J turning once a second: ~1e-9 of the drive's power
    assert np.max(np.abs(balance)) <= 1e-7 * scale
    assert scale > 1.0                               # the drive does work: the balance is not 0 = 0


def test_compare_passes_in_mujoco(tmp_path):
    out, _ = _imported(tmp_path, _pmks())
    r = run("compare", out)
    assert r.returncode == 0 and "PASSED" in r.stdout, r.stdout + r.stderr
    r = run("forces", out, "--torque", "3@rocker", "--gravity", "0,-9.81", "--simulate")
    assert r.returncode == 0 and "PASSED" in r.stdout, r.stdout + r.stderr


@pytest.mark.parametrize("text, what", [
    ("ground crank R 0 0\ncrank coupler extra R 50 86.6\ncoupler rocker R 333 292\nrocker ground R 400 0\n"
     "extra ground R 100 200\nd=1\n", "3 links"),
    ("ground crank R 0 0\ngnd ground R 50 86.6\ncrank rocker R 333 292\nrocker ground R 400 0\nd=1\n", "twice"),
])
def test_a_bad_relative_driver_is_refused_in_one_line_naming_the_joint(tmp_path, text, what):
    src = tmp_path / "bad.txt"
    src.write_text(text)
    out = tmp_path / "bad.toml"
    r = run("import", src, "--out", out)
    assert r.returncode == 2 and not out.exists()
    line = r.stderr.strip()
    assert "\n" not in line and "Traceback" not in line and "J1" in line and what in line, line


JOINTS_FORM = joints_fourbar_text('kind = "motor"\njoint = "B"')


def test_a_links_and_joints_motor_at_the_coupler_joint_drives_the_coupler_and_places_its_third_point():
    m = analytic.from_text(JOINTS_FORM, "motor_at_b.toml")
    e = m.geometry.elements[0]
    assert e["kind"] == "motor_dyad" and e["on"] == "crank" and tuple(e["links"]) == ("crank", "coupler")
    A0, B0, C0, D, E0 = (np.array(v) for v in ([0, 0], [12.5, 21.6506], [74.2099, 54.6944], [80, 0],
                                               [29.506, 53.4436]))
    dims = (np.linalg.norm(B0 - A0), np.linalg.norm(C0 - B0), np.linalg.norm(C0 - D), 80.0)
    q = np.linspace(-math.pi, math.pi, 37)
    sol = m.solve(q)
    valid = np.isfinite(sol["xC"])
    assert valid.all()          # |A C| in [|BC| - |AB|, |BC| + |AB|] = [36.7, 86.7] mm; D's circle reaches [25.3, 134.7]
    B, C = (x[:, valid] * 1000 for x in _hand(q, dims=dims))     # [mm]
    b = dims[1]
    u0 = (C0 - B0) / b
    eu, ev = (E0 - B0) @ u0, u0[0] * (E0 - B0)[1] - u0[1] * (E0 - B0)[0]
    u = (C - B) / b
    E = B + eu * u + ev * np.stack([-u[1], u[0]])
    for p, want in (("B", B), ("C", C), ("E", E)):
        got = np.stack([sol[f"x{p}"][valid], sol[f"y{p}"][valid]]) * 1000
        assert np.max(np.hypot(*(got - want))) <= 1e-9       # hand formulas on an 80 mm figure: rounding


def test_a_motor_dyad_housing_on_a_link_not_its_own_is_refused_naming_the_field(tmp_path):
    text = (Path(__file__).resolve().parent / "kinds" / "motor_dyad.toml").read_text()
    bad = tmp_path / "bad_on.toml"
    bad.write_text(text.replace('name = "elbow"', 'name = "elbow"\non = "rocker"'))
    r = run("check", bad)
    line = r.stderr.strip()
    assert r.returncode == 2 and "\n" not in line and "field 'on'" in line and "'rocker'" in line, line
