"""The load kinds' conformance suite (as scikit-learn's ``check_estimator`` runs every estimator through the
same checks): every kind of the registry (analytic.loads.KINDS) has an example in tests/loads/ (a four-bar
with one load of that kind; ``KIND__variant.toml`` for more) and each example passes, with checks that
share nothing with the hook they check:

* power balance: the load's generalized force (virtual work with the solver's velocity coefficients) times
  the input rate, integrated over the cycle, equals minus the change of its energy function at every sample
  (a store); equals minus its dissipation pointwise (a damper); equals the power of its wrenches on the
  links' velocities (anything else);
* MuJoCo: at poses of the cycle, the generalized force MuJoCo computes from the load's MuJoCo form (its
  tendon's passive force) or from the body wrenches the simulation applies equals J^T f of the load's
  wrenches with MuJoCo's own point Jacobians;
* export: the file written back (sim.output.tomlout.generate) reads back to the same records;
* bad fields: a bad value of each field is refused in one line naming the load and the field;
* the drawing: every sample drawn (finite ends, points and values), with a shape and symbol app.js draws.

Besides: the gas spring's closed-form energy against quadrature (n = 1 the log case, ratio = 1 the
constant push), its refusal of a motion past its stroke, and the table spring against its table."""

from __future__ import annotations

import math
import re
from pathlib import Path

import mujoco
import numpy as np
import pytest
from scipy import integrate

import analytic
from analytic import loads as AL
from analytic.loads import kinetostatics as K

HERE = Path(__file__).parent
EXAMPLES = sorted((HERE / "loads").glob("*.toml"))
APP_JS = (HERE.parent / "sim" / "front" / "static" / "app.js").read_text()


def example_kind(path: Path) -> str:
    return path.stem.split("__")[0]


def load(path):
    """(mech, its one load as the definition holds it, the same resolved)."""
    mech = analytic.load(str(path))
    ls = AL.resolve(mech)
    assert len(ls.loads) == 1
    return mech, mech.definition.loadset.loads[0], ls.loads[0]


def state_over(mech, q, rate: float = 1.0):
    """The State (every output the loads and generalized forces read) at inputs ``q`` and input ``rate``."""
    q = np.asarray(q, dtype=float)
    qd = np.full_like(q, rate)
    sol = mech.solve(q, qd, 0.0, outputs=K.full_wanted(mech))
    sol = {k: np.asarray(sol[k]).reshape(len(q)) for k in K.full_wanted(mech)}
    return AL.State(mech, sol, q.reshape(-1, 1), qd.reshape(-1, 1), q.copy())


@pytest.mark.parametrize("kind", list(AL.KINDS))
def test_every_kind_has_an_example(kind):
    assert any(example_kind(p) == kind for p in EXAMPLES), f"add tests/loads/{kind}.toml"


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_power_balance(path):
    mech, _, ld = load(path)
    n = 4000
    q = np.linspace(0.0, 2 * math.pi, n + 1)             # one turn at unit rate: t = q
    st = state_over(mech, q)
    variables = st.variables(AL.scales(mech.definition, mech.parameters))
    apps = ld.applications(st, variables)
    Q = K.generalized(mech, st.q, st, apps)[mech.inputs[0].link]          # at unit rate: the power
    assert np.all(np.isfinite(Q)) and np.max(np.abs(Q)) > 1e-3             # the load does work
    E, D = ld.energy(st), ld.dissipation(st)
    assert E is None or D is None                                            # a store or a damper, not both
    if E is not None:
        work = np.concatenate([[0.0], np.cumsum(0.5 * (Q[1:] + Q[:-1]) * np.diff(q))])
        change = E - E[0]
        span = np.max(E) - np.min(E)
        assert span > 1e-3
        # the trapezoidal rule's error over a turn of 4000 steps: (2 pi / 4000)^2 / 12 of the power's curvature
        # integrated, ~1e-6 of the energy's range for these smooth (or once kinked) forces
        assert np.max(np.abs(work + change)) <= 1e-5 * span
        # and pointwise: the power is minus the energy's rate (central differences, error h^2 / 6 E''')
        dE = (E[2:] - E[:-2]) / (q[2] - q[0])
        assert np.max(np.abs(Q[1:-1] + dE)) <= 2e-3 * np.max(np.abs(Q))      # kinks of a table: a few samples
    elif D is not None:
        assert np.all(D >= 0)
        # its power is minus what it dissipates, sample by sample: rounding only (1e-12 of the peak)
        assert np.allclose(Q, -D, rtol=0, atol=1e-12 * np.max(np.abs(D)))
    else:
        from analytic.loads.common import power
        # the wrenches' power on the links' velocities (the State's) equals the generalized force's: rounding
        assert np.allclose(power(st, apps), Q, rtol=0, atol=1e-12 * np.max(np.abs(Q)))


def _revolute_pose(built, mech, sol0, sol, k, data):
    """Set MuJoCo's tree joints to the analytic pose and rates of sample ``k`` (each hinge: the change of its
    links' relative angle since the start pose, the model's zero)."""
    from analytic.kinds import GROUND
    from sim.model.build import spanning_tree
    order, _ = spanning_tree(mech)

    def phi(s, ln, i):
        return 0.0 if ln == GROUND else math.atan2(s["sin" + ln][i], s["cos" + ln][i])

    def w(ln):
        return 0.0 if ln == GROUND else float(sol["omega" + ln][k])

    data.qpos[:] = 0.0
    data.qvel[:] = 0.0
    for parent, child, j in order:
        assert j.kind == "revolute"                     # the examples are four-bars
        jid = built.model.joint(j.name).id
        d = (phi(sol, child, k) - phi(sol, parent, k)) - (phi(sol0, child, 0) - phi(sol0, parent, 0))
        data.qpos[built.model.jnt_qposadr[jid]] = math.remainder(d, 2 * math.pi)
        data.qvel[built.model.jnt_dofadr[jid]] = w(child) - w(parent)
    mujoco.mj_forward(built.model, data)


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_mujoco_force_equals_the_analytic_one(path):
    from sim.model import loads as ML
    from sim.model.build import build
    mech, _, ld = load(path)
    built = build(mech, native=True)                   # tendons where the kind has a MuJoCo form
    model, data = built.model, mujoco.MjData(built.model)
    q = np.linspace(0.0, 2 * math.pi, 9)[:-1] + 0.3
    st = state_over(mech, q, 2 * math.pi)              # the file's 360 deg/s: a damper's force too
    st0 = state_over(mech, np.array([0.0]))
    peak = 0.0
    apps = ld.applications(st, st.variables(AL.scales(mech.definition, mech.parameters)))
    native = ld.name in built.native
    form = ld.mujoco()
    assert native == (not isinstance(form, str))
    xfrc = None if native else ML.wrenches(built, st.t, st.q, st.qd).xfrc
    for k in range(len(q)):
        _revolute_pose(built, mech, st0.sol, st.sol, k, data)
        for ln, o in mech.link_origins.items():        # the pose is the analytic one (rounding)
            assert np.allclose(data.xpos[model.body(ln).id][:2], [st.sol["x" + o][k], st.sol["y" + o][k]],
                               atol=1e-12)
        want = np.zeros(model.nv)                      # J^T f with MuJoCo's Jacobians at the points
        for a in apps:
            if a.link == "ground":
                continue
            jacp, jacr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
            at = lambda v: float(np.broadcast_to(v, (len(q),))[k])  # noqa: E731
            mujoco.mj_jac(model, data, jacp, jacr, np.array([at(a.px), at(a.py), 0.0]), model.body(a.link).id)
            want += jacp.T @ np.array([at(a.fx), at(a.fy), 0.0]) + jacr.T @ np.array([0.0, 0.0, at(a.couple)])
        peak = max(peak, float(np.max(np.abs(want))))
        rest = 0.0                                     # the size of the terms the share is taken from
        if native:
            t = model.tendon(f"load_{ld.name}").id
            before = data.qfrc_passive.copy()
            kept = model.tendon_stiffness[t].copy(), model.tendon_damping[t].copy()
            model.tendon_stiffness[t], model.tendon_damping[t] = 0.0, 0.0
            mujoco.mj_forward(model, data)
            got = before - data.qfrc_passive
            rest = float(np.max(np.abs(data.qfrc_passive)))
            model.tendon_stiffness[t], model.tendon_damping[t] = kept
        else:
            data.xfrc_applied[:] = 0.0
            mujoco.mj_forward(model, data)
            without = data.qfrc_smooth.copy()
            data.xfrc_applied[:] = xfrc[k]
            mujoco.mj_forward(model, data)
            got = data.qfrc_smooth - without
            rest = float(np.max(np.abs(without)))
            data.xfrc_applied[:] = 0.0
        # rounding of the Jacobian products (1e-15 of the forces x lever arms) and of the other terms of the
        # sum the share is the difference of (the bias forces: 1e-15 of them)
        assert np.allclose(got, want, rtol=0, atol=1e-9 * max(np.max(np.abs(want)), rest)), (k, got, want)
    assert peak > 1e-3                                 # a real force, not a vanishing one


def same(a, b, path="") -> None:
    """Records equal: strings and flags exactly, numbers to rounding (1e-12 relative: a value divided by the
    file's unit and multiplied back)."""
    if hasattr(a, "__dataclass_fields__"):
        assert type(a) is type(b), path
        for f in a.__dataclass_fields__:
            same(getattr(a, f), getattr(b, f), f"{path}.{f}")
    elif isinstance(a, (tuple, list)) or isinstance(a, np.ndarray):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            same(x, y, f"{path}[{i}]")
    elif isinstance(a, (float, int, np.floating)) and not isinstance(a, bool):
        assert isinstance(b, (float, int, np.floating)), path
        if math.isnan(a):
            assert math.isnan(b), path
        else:
            assert b == pytest.approx(a, rel=1e-12, abs=1e-15), path
    else:
        assert a == b, path


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_export_round_trip(path, tmp_path):
    from sim.output import tomlout
    mech, held, _ = load(path)
    out = tmp_path / "back.toml"
    out.write_text(tomlout.generate(mech))
    back = analytic.load(str(out))
    assert len(back.definition.loadset.loads) == 1
    same(held, back.definition.loadset.loads[0])
    assert "[[loads]]" in out.read_text()


BAD = {"number": [1, 2], "text": 42, "pair": "x", "point": "NOPOINT", "table": [[1]], "links": ["nolink", "2"],
       "between": [["nolink", "S0"], ["3", [0.2, 0]]], "frame": "sideways"}
"""A bad value of each type of field (analytic.loads.base.Field.type)."""


def _with(path: Path, key: str, value) -> str:
    """The example's text with its load's ``key`` set to ``value`` (added where absent)."""
    import json
    head, table = path.read_text().split("[[loads]]\n")
    lines = [ln for ln in table.splitlines() if not re.match(rf"^{key}\s*=", ln)]
    return head + "[[loads]]\n" + "\n".join(lines + [f"{key} = {json.dumps(value)}"]) + "\n"


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_a_bad_value_of_each_field_is_refused_in_one_line_naming_it(path, tmp_path):
    _, held, _ = load(path)
    kind = AL.get(held.kind)
    given = set(held.file_table(AL.scales(analytic.load(str(path)).definition, {})))
    checked = 0
    for f in kind.fields:
        key = f.name
        if f.type == "point" and "at" in given:
            key, value = "at", "x"
        elif key not in given:
            continue
        else:
            value = BAD[f.type]
        p = tmp_path / f"{path.stem}.toml"
        p.write_text(_with(path, key, value))
        with pytest.raises(analytic.ParameterError) as err:
            analytic.load(str(p))
        msg = str(err.value)
        assert "\n" not in msg and f"({held.name}).{key}" in msg, (key, msg)
        checked += 1
    assert checked >= 2


def test_an_unknown_kind_is_refused_naming_the_load_and_every_kind(tmp_path):
    path = HERE / "loads" / "spring.toml"
    p = tmp_path / "bungee.toml"
    p.write_text(_with(path, "kind", "bungee"))
    with pytest.raises(analytic.ParameterError) as err:
        analytic.load(str(p))
    msg = str(err.value)
    assert "\n" not in msg and "(ret).kind" in msg and "'bungee'" in msg
    assert all(k in msg for k in AL.KINDS)


def test_an_unknown_kind_is_refused_by_the_cli_with_exit_2(tmp_path):
    from cli_runner import run
    p = tmp_path / "bungee.toml"
    p.write_text(_with(HERE / "loads" / "spring.toml", "kind", "bungee"))
    r = run("check", p)
    assert r.returncode == 2 and r.stdout == ""
    assert len(r.stderr.strip().splitlines()) == 1 and "(ret).kind" in r.stderr and "gas_spring" in r.stderr


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_the_drawing(path):
    from sim.service.load_editing import load_geometry
    mech, _, _ = load(path)
    n = 61
    q = np.linspace(0.0, 2 * math.pi, n).reshape(-1, 1)
    g = load_geometry(mech, q[:, 0], q, np.ones_like(q), AL.resolve(mech))
    (entry,) = g["loads"]
    arrays = {"arrow": ("x", "y", "fx", "fy"), "between": ("x1", "y1", "x2", "y2", "value"),
              "pin": ("x", "y", "value"), "moment": ("x", "y", "value")}[entry["shape"]]
    for k in arrays:
        assert entry[k].shape == (n,) and np.all(np.isfinite(entry[k])), k
    magnitude = np.hypot(entry["fx"], entry["fy"]) if entry["shape"] == "arrow" else np.abs(entry["value"])
    assert np.max(magnitude) > 0
    # the page draws its shape and its symbol (sim/front/static/app.js)
    assert f'ld.shape === "{entry["shape"]}"' in APP_JS
    assert entry["symbol"] in ("arrow", "arc") or f'ld.symbol === "{entry["symbol"]}"' in APP_JS
    fu = mech.definition.force_units                  # in the file's units, as written
    assert entry["unit"] == (fu if entry["shape"] in ("arrow", "between") else f"{fu} {mech.units}")


@pytest.mark.parametrize("kind", list(AL.KINDS))
def test_the_editor_offers_each_kind_and_its_fields(kind):
    from sim.front.loads_panel import form_html
    html = form_html()
    assert f'<option value="{kind}">' in html
    for f in AL.get(kind).fields:
        label = re.search(rf'<label data-kinds="([^"]*)"[^>]*>[^<]*<[a-z]+ [^>]*id="load-{f.name.replace("_", "-")}"', html)
        assert label and kind in label.group(1).split(), f.name
        assert f'data-type="{f.type}"' in html
    assert set(re.findall(r"^\s{4}(\w+): \(", APP_JS, re.M)) >= {f.type for f in AL.get(kind).fields}


# ----------------------------------------------------------------------------------------- gas spring
@pytest.mark.parametrize("n", [1.0, 1.0 + 1e-9, 1.2, 1.4, 0.5])
@pytest.mark.parametrize("ratio", [1.0, 1.0 + 1e-10, 1.3, 2.5])
def test_gas_spring_energy_is_the_integral_of_its_push(n, ratio):
    from analytic.loads.gas_spring import GasSpring
    g = GasSpring("g", (), 0.4, 0.1, 250.0, ratio, n)
    assert g.push(0.0) == pytest.approx(250.0, rel=1e-14)                  # F1 at full extension
    assert g.push(0.1) == pytest.approx(250.0 * ratio, rel=1e-12)          # ratio x F1 fully compressed
    for x in (0.0, 0.013, 0.05, 0.0999, 0.1):
        want, err = integrate.quad(lambda s: float(g.push(s)), 0.0, x, epsabs=0, epsrel=1e-13)
        assert float(g.stored(x)) == pytest.approx(want, rel=1e-11, abs=1e-13)   # quad's error ~1e-14


def test_gas_spring_pushes_its_ends_apart_by_the_polytropic_law():
    mech, ld, _ = load(HERE / "loads" / "gas_spring.toml")
    st = state_over(mech, np.linspace(0, 2 * math.pi, 13))
    (x1, y1), (x2, y2) = st.position(ld.ends[0]), st.position(ld.ends[1])
    L = np.hypot(x2 - x1, y2 - y1)
    x = 0.33 - L
    V = 1 - (1 - 1.4 ** (-1 / 1.2)) * x / 0.17                            # the gas volume over V0
    F = 200 * V ** -1.2                                                    # p0 V0^n / V^n times the area
    a = ld.applications(st)[1]                                             # on the rocker's end: away from G
    assert np.allclose(a.fx, F * (x2 - x1) / L, rtol=1e-12) and np.allclose(a.fy, F * (y2 - y1) / L, rtol=1e-12)


def test_gas_spring_past_its_stroke_is_refused_in_one_line(tmp_path):
    p = tmp_path / "short.toml"
    p.write_text(_with(HERE / "loads" / "gas_spring.toml", "stroke", 0.05))
    from cli_runner import run
    r = run("forces", p, "--samples", 37)
    assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert "load gas" in r.stderr and "stroke" in r.stderr and "Traceback" not in r.stderr


@pytest.mark.parametrize("field,value,says", [("stroke", 0.4, "shorter than extended_length"),
                                               ("ratio", 0.9, ">= 1"), ("n", 0, "(0, 3]"), ("force", -5, "> 0")])
def test_gas_spring_fields_out_of_range_are_refused(tmp_path, field, value, says):
    p = tmp_path / "g.toml"
    p.write_text(_with(HERE / "loads" / "gas_spring.toml", field, value))
    with pytest.raises(analytic.ParameterError) as err:
        analytic.load(str(p))
    assert f"(gas).{field}" in str(err.value) and says in str(err.value)


# ----------------------------------------------------------------------------------------- table spring
def test_table_spring_follows_its_table():
    mech, ld, _ = load(HERE / "loads" / "table_spring.toml")
    st = state_over(mech, np.linspace(0, 2 * math.pi, 25))
    (x1, y1), (x2, y2) = st.position(ld.ends[0]), st.position(ld.ends[1])
    L = np.hypot(x2 - x1, y2 - y1)
    d = L - 0.15
    rows = [(-0.1, -10), (0, 0), (0.05, 40), (0.1, 150), (0.2, 600)]
    assert d.min() > -0.1 and d.max() < 0.2                                # inside the table: no extrapolation
    T = np.array([next(y0 + (y1_ - y0) * (v - x0) / (x1_ - x0) for (x0, y0), (x1_, y1_) in zip(rows, rows[1:])
                       if x0 <= v <= x1_) for v in d])                     # by hand, row by row
    a = ld.applications(st)[0]                                             # on the frame's end: pulled along
    assert np.allclose(a.fx, T * (x2 - x1) / L, rtol=1e-12, atol=1e-12)
    assert np.allclose(a.fy, T * (y2 - y1) / L, rtol=1e-12, atol=1e-12)
    E = ld.energy(st)
    want = [integrate.quad(lambda s: np.interp(s, *zip(*rows)), 0.0, v, points=[0.05, 0.1], epsrel=1e-12)[0]
            for v in d]
    assert np.allclose(E, want, rtol=1e-9, atol=1e-12)                    # quad's error on the kinks


def test_table_spring_beyond_its_rows_goes_on_with_each_end_rows_slope(tmp_path):
    # the example's table cut short so that the rocker's motion (deflection -29.8 to +65.1 mm) leaves it at both
    # ends: below its first row the tension goes on with the first two rows' slope (2 N / 10 mm = 200 N/m), above
    # its last with the last two rows' (40 N / 20 mm = 2000 N/m), SPEC "table_spring"
    old = "table = [[-0.1, -10], [0, 0], [0.05, 40], [0.1, 150], [0.2, 600]]"
    text = (HERE / "loads" / "table_spring.toml").read_text()
    assert old in text
    path = tmp_path / "short_table.toml"
    path.write_text(text.replace(old, "table = [[-0.01, -2], [0, 0], [0.02, 10], [0.04, 50]]"))
    mech, ld, _ = load(path)
    st = state_over(mech, np.linspace(0, 2 * math.pi, 25))
    (x1, y1), (x2, y2) = st.position(ld.ends[0]), st.position(ld.ends[1])
    L = np.hypot(x2 - x1, y2 - y1)
    d = L - 0.15
    assert d.min() < -0.01 and d.max() > 0.04                              # past both ends of the table

    def tension(v):                                                        # by hand, piece by piece
        if v < -0.01:
            return -2.0 + 200.0 * (v + 0.01)
        if v > 0.04:
            return 50.0 + 2000.0 * (v - 0.04)
        return float(np.interp(v, [-0.01, 0.0, 0.02, 0.04], [-2.0, 0.0, 10.0, 50.0]))
    T = np.array([tension(v) for v in d])
    a = ld.applications(st)[0]                                             # on the frame's end: pulled along
    # one product of a tension of <= 100 N with a unit vector: rounding
    assert np.allclose(a.fx, T * (x2 - x1) / L, rtol=1e-12, atol=1e-12)
    assert np.allclose(a.fy, T * (y2 - y1) / L, rtol=1e-12, atol=1e-12)
    want = [integrate.quad(tension, 0.0, v, points=[-0.01, 0.02, 0.04], epsrel=1e-12)[0] for v in d]
    assert np.allclose(ld.energy(st), want, rtol=1e-9, atol=1e-12)        # quad's error on the kinks


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_the_panel_adds_each_kind_as_the_file_writes_it(path):
    """The app's panel (POST /api/loads/edit) adds the load, given as its table, to the file without loads:
    the new file reads back to the same record."""
    from sim.front import loads_panel
    mech, held, _ = load(path)
    table = held.file_table(AL.scales(mech.definition, mech.parameters))
    bare = path.read_text().split("[[loads]]")[0]
    out = loads_panel.edit({"text": bare, "action": "add", "load": table})
    from sim import service
    again = service.load("<upload>", {}, text=out["text"])
    same(held, again.definition.loadset.loads[0])


def test_a_file_with_force_units_and_no_loads_reads():
    """``force_units`` alone (the loads all removed in the panel) was refused as "loads: must be an array"."""
    text = (HERE / "loads" / "torque.toml").read_text().split("[[loads]]")[0]
    assert 'force_units = "N"' in text
    from sim import service
    m = service.load("<upload>", {}, text=text)
    assert m.definition.force_units == "N" and not AL.resolve(m)


def test_gas_spring_that_does_not_fit_at_the_start_pose_is_refused_by_the_panel():
    from sim.front import loads_panel
    path = HERE / "loads" / "gas_spring.toml"
    text = path.read_text()
    bare = text.split("[[loads]]")[0]
    mech, held, _ = load(path)
    table = {**held.file_table(AL.scales(mech.definition, mech.parameters)), "extended_length": 0.2}
    with pytest.raises(analytic.ParameterError) as err:       # its length at the start pose is 0.274 m > 0.2
        loads_panel.edit({"text": bare, "action": "add", "load": table})
    assert "load gas" in str(err.value) and "\n" not in str(err.value)


def test_the_page_holds_the_registrys_form():
    from sim.front import app
    html = app.page({"name": "fourbar"}).decode()
    assert "<!--LOAD_FORM-->" not in html and 'id="load-kind"' in html
    assert all(f'<option value="{k}">' in html for k in AL.KINDS)
