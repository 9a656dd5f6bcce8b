"""An input kind is a plug-in: a third kind, registered here only, runs through ``linkage analyze``.

The toy kind is a crank behind a gear pair: a motor coordinate ``theta`` (its own column names ``thetaK``,
``dthetaK``, ``ddthetaK``) turns the driven link at ``ratio`` times its angle. Nothing in the project knows
it: the test registers it in :data:`analytic.kinds.KINDS` for its own duration. The oracle is the project's
own ``crank``, a different code path: a four-bar whose link turns at ``ratio * theta`` must pass through the
same poses, at the same times, as the crank four-bar whose angle is ``phi = ratio * theta``.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import analytic
from analytic import kinds
from analytic.kinds.base import Field, Kind, LinkPart, State, Structure
from tests.cli_runner import run

RATIO = 2.0
THETA0 = 15.0            # [deg] the motor's start; the link starts at RATIO * THETA0
OMEGA = 180.0            # [deg/s] the motor's speed; the link turns at RATIO * OMEGA = one turn per second
ALPHA = 20.0             # [deg/s^2]


class GearedCrank(Kind):
    """A link turned about a ground pivot through a gear pair: phi = ratio * theta (a toy input kind)."""

    name = "geared_crank"
    section = "inputs"
    summary = "a link turned about a ground pivot by a motor through a gear pair: phi = ratio * theta"
    motion_fields = ("theta0", "omega", "alpha")
    angular = True
    columns = ("theta", "dtheta", "ddtheta")
    fields = {"pivot": Field("point"), "point": Field("new"), "length": Field("size"),
              "link": Field("link", "{pivot}{point}"), "ratio": Field("number", 1.0),
              "theta0": Field("angle", 0.0), "omega": Field("angle", 2 * math.pi), "alpha": Field("angle", 0.0)}

    def needs(self, f):
        return (f["pivot"],)

    def structure(self, f):
        return Structure(links=(LinkPart(f["link"], f["pivot"], (f["pivot"], f["point"])),),
                         driven_pin=(f["pivot"], f["link"]))

    def input_joint(self, e):
        return e["pivot"]

    def solve(self, e, st: State):
        j, k, r = e["input"], e["ratio"], e["length"]
        P = st.points[e["pivot"]]
        a, w, al = k * st.q[j], k * st.qd[j], k * st.qdd[j]
        c, s = np.cos(a), np.sin(a)
        rx, ry = r * c, r * s
        st.points[e["point"]] = (P[0] + rx, P[1] + ry, P[2] - w * ry, P[3] + w * rx,
                                 P[4] - al * ry - w * w * rx, P[5] + al * rx - w * w * ry)
        st.links[e["link"]] = (c, s, w, al)


FOURBAR = Path(analytic.__file__).resolve().parent / "library" / "fourbar.toml"


def _geared_file(tmp_path) -> Path:
    """The library's four-bar with its crank replaced by the geared crank (same link, same point, its motion
    law the same parameters: set them with :func:`_geared_args`)."""
    text = FOURBAR.read_text()
    crank = text[text.index("[[inputs]]"):text.index("[[groups]]")]
    geared = ('[[inputs]]\nkind = "geared_crank"\npivot = "A"\npoint = "B"\nlength = "l1"\nlink = "1"\n'
              f'ratio = {RATIO}\ntheta0 = "phi1_0"\nomega = "omega1"\nalpha = "alpha1"\n\n')
    path = tmp_path / "geared.toml"
    path.write_text(text.replace(crank, geared))
    return path


@pytest.fixture
def geared(tmp_path, monkeypatch):
    monkeypatch.setitem(kinds.KINDS, GearedCrank.name, GearedCrank())
    return _geared_file(tmp_path)


def _geared_args(alpha=ALPHA):
    return ["--set", f"phi1_0={THETA0}deg", "--set", f"omega1={OMEGA}deg", "--set", f"alpha1={alpha}deg"]


def _crank_args(alpha=ALPHA):
    """The crank four-bar moving as the geared one's link does: phi = RATIO * theta at every time."""
    return ["--set", f"phi1_0={RATIO * THETA0}deg", "--set", f"omega1={RATIO * OMEGA}deg",
            "--set", f"alpha1={RATIO * alpha}deg"]


def test_a_kind_registered_here_only_is_read_and_solved_as_its_declarations_say(geared):
    mech = analytic.load(str(geared)).with_values(phi1_0=math.radians(THETA0), omega1=math.radians(OMEGA),
                                                  alpha1=math.radians(ALPHA))
    (inp,) = mech.inputs
    assert (inp.kind, inp.q, inp.qd, inp.qdd, inp.unit) == ("geared_crank", "theta1", "dtheta1", "ddtheta1", "rad")
    # the link's own angle is an output of its own now (the input's column is the motor's theta)
    assert "phi1" in mech.general_outputs and "theta1" not in mech.general_outputs
    crank = analytic.load(str(FOURBAR))
    t = np.linspace(0.0, 1.7, 41)
    _, sol_g = mech.solve_at(t)
    _, sol_c = crank.with_values(phi1_0=math.radians(RATIO * THETA0), omega1=math.radians(RATIO * OMEGA),
                                 alpha1=math.radians(RATIO * ALPHA)).solve_at(t)
    for k in ("xE", "yE", "vxE", "vyE", "axE", "ayE", "omega3", "alpha3", "omega1", "alpha1"):
        # the same closed-form expressions on angles equal to round-off (ratio * theta vs phi: 1 ulp each)
        np.testing.assert_allclose(sol_g[k], sol_c[k], rtol=0, atol=1e-9, err_msg=k)
    for f in (np.cos, np.sin):      # the link's angle, wrapped or not
        np.testing.assert_allclose(f(sol_g["phi1"]), f(sol_c["phi1"]), rtol=0, atol=1e-9)  # round-off
    # the motor's own column is its law theta0 + omega t + alpha t^2 / 2, written by hand
    theta = np.radians(THETA0 + OMEGA * t + 0.5 * ALPHA * t * t)
    np.testing.assert_allclose(sol_g["theta1"], theta, rtol=0, atol=1e-12)  # round-off of the law's sum


def test_analyze_runs_the_new_kind_and_agrees_with_the_crank(geared, tmp_path):
    # half a motor turn: the link turns once, over the same second as the crank's one revolution
    g = run("analyze", geared, "--json", "--revolutions", "0.5", *_geared_args())
    assert g.returncode == 0, g.stderr
    c = run("analyze", FOURBAR, "--json", *_crank_args())
    assert c.returncode == 0, c.stderr
    fg, fc = json.loads(g.stdout)["figures"], json.loads(c.stdout)["figures"]
    assert fg["input"] == "theta1" and fc["input"] == "phi1"
    for key in ("xE_range", "yE_range", "vE_min", "vE_mean", "vE_max", "time_ratio"):
        # the same poses at the same 361 times: equal to round-off
        np.testing.assert_allclose(fg[key], fc[key], rtol=1e-9, atol=1e-12, err_msg=key)
    np.testing.assert_allclose(fg["transmission"]["C"], fc["transmission"]["C"], rtol=1e-9, atol=1e-12)
    # the geared input's range is its own coordinate's: a full motor turn from theta0, where the link turns twice
    assert fg["turns_fully"] and fc["turns_fully"]
    np.testing.assert_allclose(fg["input_ranges"], [[math.radians(THETA0), math.radians(THETA0) + 2 * math.pi]],
                               rtol=0, atol=1e-12)  # q0 + 2 pi, as written
    units = json.loads(g.stdout)["units"]
    assert units["parameters"] == json.loads(c.stdout)["units"]["parameters"]
    assert units["figures"]["input_ranges"] == "rad"       # an angle: the kind says so


def test_an_angle_typed_for_the_new_kind_is_read_in_degrees(geared):
    # --at takes the first input's angle in degrees where its kind is angular: theta = 40deg puts the link at
    # 80deg, where the crank four-bar is at --at 80deg
    g = run("analyze", geared, "--json", "--at", "40deg", *_geared_args(alpha=0.0))
    c = run("analyze", FOURBAR, "--json", "--at", f"{RATIO * 40}deg", *_crank_args(alpha=0.0))
    assert g.returncode == 0 and c.returncode == 0, g.stderr + c.stderr
    og, oc = json.loads(g.stdout)["outputs"], json.loads(c.stdout)["outputs"]
    # the motor's coordinate as typed, in its own column; the link at RATIO times it
    assert math.isclose(og["theta1"], math.radians(40), abs_tol=1e-15)   # one deg -> rad conversion
    assert math.isclose(oc["phi1"], math.radians(RATIO * 40), abs_tol=1e-15)
    for k in ("xE", "yE", "xC", "yC", "vxE", "vyE", "omega3"):
        # one pose each: the same expressions on equal angles and speeds, to round-off
        assert math.isclose(og[k], oc[k], rel_tol=1e-12, abs_tol=1e-12), k


def test_an_input_range_typed_for_the_new_kind_is_read_in_degrees(geared):
    # --input-range takes the first input's range in degrees where its kind is angular: the motor's 20..60deg
    # sweeps the link over 40..120deg, where the crank four-bar's range is 40deg:120deg
    g = run("analyze", geared, "--json", "--input-range", "20deg:60deg", *_geared_args(alpha=0.0))
    c = run("analyze", FOURBAR, "--json", "--input-range", f"{RATIO * 20}deg:{RATIO * 60}deg",
            *_crank_args(alpha=0.0))
    assert g.returncode == 0 and c.returncode == 0, g.stderr + c.stderr
    fg, fc = json.loads(g.stdout)["figures"], json.loads(c.stdout)["figures"]
    for key in ("xE_range", "yE_range"):
        # the same poses at the same samples of the two ranges: equal to round-off
        np.testing.assert_allclose(fg[key], fc[key], rtol=1e-9, atol=1e-12, err_msg=key)
    full = run("analyze", FOURBAR, "--json", *_crank_args(alpha=0.0))
    # and the range was honoured: a part of the full turn's path, not all of it
    assert np.ptp(fg["xE_range"]) < np.ptp(json.loads(full.stdout)["figures"]["xE_range"]) - 1e-3


class GearedInJoints(GearedCrank):
    """The toy kind as the links-and-joints form would take it: its own fields, its own recognition."""

    joints_form = {"pivot": "point", "point": "point", "ratio": "number", "omega": "angle"}
    joints_summary = "a link turned by a motor through a gear pair"

    def from_joints(self, item, where, dec):
        raise dec.fail(where, f"reached the geared crank's own recognition (ratio {item['ratio']})")


STEPHENSON = Path(__file__).resolve().parent / "peers_examples" / "stephenson.toml"


@pytest.mark.parametrize("entry, expected", [
    ('kind = "geared_crank"\nratio = 2', "inputs[1]: reached the geared crank's own recognition (ratio 2)"),
    ('kind = "geared_crank"\nspeed = 2', "inputs[1]: unknown field 'speed'; a geared_crank takes kind, omega, pivot, "
                                         "point, ratio"),
    ('kind = "cam"', 'inputs[1]: unknown kind \'cam\'; an input is kind = "crank" (a link turned about a ground '
                     'pivot) or "slider" (a block driven along a ground guide) or "actuator" (a cylinder: the P joint '
                     'between its barrel and its rod, pinned at C and D) or "motor" (a link turned by a motor at an R '
                     'joint with another moving link) or "geared_crank" (a link turned by a motor through a gear pair)'),
])
def test_the_links_and_joints_form_asks_the_registered_kinds(tmp_path, monkeypatch, entry, expected):
    monkeypatch.setitem(kinds.KINDS, GearedInJoints.name, GearedInJoints())
    text = STEPHENSON.read_text()
    assert text.count('kind = "crank"') == 1
    path = tmp_path / "geared_joints.toml"
    path.write_text(text.replace('kind = "crank"', entry))
    r = run("check", path)
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert expected in r.stderr, r.stderr


# ------------------------------------------------------------------ other tools' files: the kinds recognise
PEERS = Path(__file__).resolve().parent / "peers_examples"


class GearedImported(GearedInJoints):
    """The toy kind as the importers would take it: it claims a Pyslvs pair of two joints and a PMKS R
    driver, writing its own entry (ratio 2), as a new input kind's module would."""

    def default_rate(self, size):
        return "omega", "180deg"

    def from_pyslvs(self, pair):
        if pair.base == pair.driver:
            return None
        return {"kind": self.name, "pivot": f"J{pair.base}", "point": f"J{pair.driver}", "ratio": 2}

    def from_pmks(self, driver):
        if driver.type != "R":
            return None
        return {"kind": self.name, "pivot": driver.point, "ratio": 2}


def _registered_first(monkeypatch, kind):
    """``kind`` registered before every other (the importers take the first kind that claims an input)."""
    monkeypatch.setattr(kinds, "KINDS", {kind.name: kind, **kinds.KINDS})


def test_the_importers_ask_the_registered_input_kinds(tmp_path, monkeypatch):
    from analytic.format import foreign
    _registered_first(monkeypatch, GearedImported())
    # a Pyslvs project's pair (0, 1) and a PMKS file's driving R joint J0, each now the toy's, at its rate
    assert foreign.read(PEERS / "fourbar.pyslvs")["inputs"] == [
        {"kind": "geared_crank", "pivot": "J0", "point": "J1", "ratio": 2, "omega": "180deg"}]
    assert foreign.read(PEERS / "rpp.txt")["inputs"] == [
        {"kind": "geared_crank", "pivot": "J0", "ratio": 2, "omega": "180deg"}]
    # and end to end: the import writes the toy's entry, which the links-and-joints form hands to its kind
    out = tmp_path / "x.toml"
    r = run("import", PEERS / "fourbar.pyslvs", "--out", out)
    assert r.returncode == 2 and "Traceback" not in r.stderr and not out.exists()
    assert "reached the geared crank's own recognition (ratio 2)" in r.stderr, r.stderr


@pytest.mark.parametrize("name, inputs", [("fourbar.pyslvs", None), ("slider_crank_rp.txt", [(0, 1)]),
                                          ("quick_return.txt", [(0, 1)]), ("rpp.txt", None),
                                          ("peas_6link.txt", None)])
def test_a_kind_that_claims_no_input_leaves_the_imports_as_they_were(monkeypatch, name, inputs):
    # the toy without importer hooks (the base class's: None), asked first, passes every input on to the
    # crank's and the slider's recognition: the written file is the same text
    from analytic.format import foreign
    before = foreign.dumps(foreign.read(PEERS / name, inputs))
    _registered_first(monkeypatch, GearedInJoints())
    assert foreign.dumps(foreign.read(PEERS / name, inputs)) == before
    assert '\nkind = "crank"' in before


def test_a_slider_pair_is_recognised_by_the_slider_kind(monkeypatch):
    # Pyslvs' (base, base) drives the block of the P/RP joint at the base: the slider kind's own recognition;
    # with the toy (which claims only pairs of two joints) asked first, still the slider's
    from analytic.format import pyslvs
    _registered_first(monkeypatch, GearedImported())
    form = pyslvs.to_form(pyslvs.parse_expression("M[J[RP,A[0],P[0,0],L[ground,a]]]", "x"), [(0, 0)], "x")
    assert form["inputs"] == [{"kind": "slider", "point": "J0"}]
