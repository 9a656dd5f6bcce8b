"""The conformance suite of the element kinds: every kind in the registry (``analytic.kinds.KINDS``) runs
through the same checks, as scikit-learn's ``check_estimator`` runs over every estimator. Adding a kind to
the registry puts it under every check; a kind needs an example mechanism ``tests/kinds/<name>*.toml``
using it (and its equations in ``tests/oracle_linkage.py``).

For each example (both assembly branches where it has a ``branch`` parameter):
* the solver agrees with the independent Newton oracle (positions <= 1e-12 of the size, rates <= 1e-9 of
  their peak: ``agreement.py``);
* velocities and accelerations match five-point finite differences of positions and velocities;
* the compiled path (when the kind has one and numba is installed) gives the numpy path's numbers;
* the generated MuJoCo model compiles, closes its loops as built and passes ``compare`` over a short run;
* every field of the kind, given a value of the wrong type, is refused in one line naming it;
* its joint forces (its closed form, or the general Newton-Euler solve of its element) equal the independent
  whole-linkage Newton-Euler oracle (``oracle_forces.py``) to 1e-9 of the peak force, under gravity and a load.
"""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import numpy as np
import pytest

import analytic
from agreement import FD_TOL, assert_agree, compare, drive, period, rng_for, skip_without_cam_contact
from analytic import ParameterError, kinds
from analytic.format import linkfile

EXAMPLES = Path(__file__).resolve().parent / "kinds"
FILES = sorted(EXAMPLES.glob("*.toml"))


def _kind_of(path: Path) -> str:
    stem = path.stem.split("__")[0]
    return next(k for k in kinds.KINDS if k.lower() == stem.lower())


CASES = [(p, b) for p in FILES for b in ((1, -1) if "branch" in analytic.load(str(p)).values else (None,))]
IDS = [f"{p.stem}{'' if b is None else ('+' if b > 0 else '-')}" for p, b in CASES]


def _load(path: Path, branch):
    m = analytic.load(str(path))
    return m if branch is None else m.with_values(branch=branch)


def test_every_kind_has_an_example_that_uses_it():
    covered = {}
    for p in FILES:
        used = {e.kind for e in linkfile.read(p).order}
        covered[_kind_of(p)] = _kind_of(p) in used
    missing = [k for k in kinds.KINDS if not covered.get(k)]
    assert not missing, f"kinds without an example in tests/kinds/ that uses them: {missing}"


@pytest.mark.parametrize("name", list(kinds.KINDS))
def test_every_kind_states_what_it_is(name):
    kind = kinds.get(name)
    assert kind.name == name and kind.summary and kind.section in ("inputs", "groups")
    assert kind.fields and any(f.type in ("new", "news") for f in kind.fields.values())
    if kind.section == "inputs":
        assert isinstance(kind.angular, bool) and len(kind.motion_fields) == 3 and len(kind.columns) == 3
    docs = (Path(__file__).resolve().parent.parent / "docs" / "CONVENTIONS.md").read_text()
    assert f"| `{name}`" in docs, f"docs/CONVENTIONS.md's table of kinds has no row for {name!r}"


@pytest.mark.parametrize("path, branch", CASES, ids=IDS)
def test_agrees_with_the_newton_oracle(path, branch):
    m = _load(path, branch)
    assert_agree(path.stem, compare(m, rng_for(path.stem + str(branch))))


def _five_point(f, h):
    return (f[0] - 8 * f[1] + 8 * f[3] - f[4]) / (12 * h)


@pytest.mark.parametrize("path, branch", CASES, ids=IDS)
def test_rates_match_finite_differences(path, branch):
    m = _load(path, branch)
    h = period(m) / 4000
    t, *_ = drive(m, 61)
    sols = [m.solve_at(t + k * h)[1] for k in (-2, -1, 0, 1, 2)]
    mid = sols[2]
    assert mid.valid.all(), mid.first_failure()
    for p in (p for e in m.geometry.elements for p in e["places"]):
        for d, dd in (("", "v"), ("v", "a")):
            fx = _five_point([s[f"{d}x{p}"] for s in sols], h)
            fy = _five_point([s[f"{d}y{p}"] for s in sols], h)
            ref_x, ref_y = mid[f"{dd}x{p}"], mid[f"{dd}y{p}"]
            peak = max(np.max(np.hypot(ref_x, ref_y)), 1e-12)
            assert np.max(np.hypot(fx - ref_x, fy - ref_y)) / peak <= FD_TOL, (p, dd)


@pytest.mark.parametrize("path, branch", CASES, ids=IDS)
def test_compiled_path_equals_numpy(path, branch, monkeypatch):
    pytest.importorskip("numba")
    from analytic.solver import jit
    m = _load(path, branch)
    if not jit.supports(m.geometry):
        pytest.skip("a kind of this example has no compiled row (numpy solves it)")
    _, q, qd, qdd = drive(m, 257, rng_for(path.stem))
    monkeypatch.setenv("LINKAGE_JIT", "0")
    ref = m.solve(q, qd, qdd)
    monkeypatch.setenv("LINKAGE_JIT", "1")
    got = m.solve(q, qd, qdd)
    for name in ref:
        peak = max(float(np.max(np.abs(ref[name]))), m.size * 1e-9)
        # both paths evaluate the same formulas in the same order; sin, cos and atan2 differ by <= 2 ulp
        assert np.max(np.abs(got[name] - ref[name])) <= 1e-12 * peak, name


@pytest.mark.parametrize("path, branch", CASES, ids=IDS)
def test_its_mujoco_model_closes_and_passes_compare(path, branch):
    from sim import service
    from sim.model import build
    m = _load(path, branch)
    skip_without_cam_contact(m)
    if any(e["kind"] == "cam" for e in m.geometry.elements) and not m.definition.loads:
        # nothing presses these examples' followers on their cams: compare refuses them in one line
        from analytic import ParameterError
        from sim import service
        with pytest.raises(ParameterError, match="the follower leaves the cam"):
            service.compare(m, revolutions=0.3)
        return
    built = build(m)
    import mujoco
    data = mujoco.MjData(built.model)
    data.qpos[:] = built.qpos0
    mujoco.mj_forward(built.model, data)
    for lp in built.loops:                        # as built: the bodies sit at the assembled pose
        gap = np.linalg.norm(data.site(lp.site1).xpos - data.site(lp.site2).xpos)
        assert gap <= 1e-12 * m.size, (lp.name, gap)
    built, c = service.compare(m, revolutions=0.3)
    failed = {k: v for k, v in c.errors.items() if not v["passed"]}
    assert c.passed, (failed, c.drive_error, c.work_balance)


def _elements(data: dict):
    return [e for section in ("inputs", "groups") for e in data.get(section, [])]


@pytest.mark.parametrize("path", FILES, ids=[p.stem for p in FILES])
def test_a_field_of_the_wrong_type_is_refused_in_one_line_naming_it(path):
    name = _kind_of(path)
    data = tomllib.loads(path.read_text())
    first = next(i for i, e in enumerate(_elements(data)) if e["kind"] == name)
    for fname in kinds.get(name).fields:
        bad = json.loads(json.dumps(data))
        element = _elements(bad)[first]
        if fname not in element:
            continue
        element[fname] = {"not": "a value"}
        with pytest.raises(ParameterError) as err:
            linkfile.parse(json.dumps(bad), str(path), json_format=True)
        message = str(err.value)
        assert "\n" not in message and f"field {fname!r}" in message, (fname, message)


@pytest.mark.parametrize("path, branch", CASES, ids=IDS)
def test_its_joint_forces_equal_the_newton_euler_oracle(path, branch):
    import oracle_forces
    from analytic import mass
    from analytic.applications import forces
    m = _load(path, branch)
    _, q, qd, qdd = drive(m, 61, rng_for(path.stem + "forces"))
    peak = forces.peak(forces.solve(m, q, qd, qdd, mass.model(m)))
    # gravity and a load of the order of the inertia forces; errors are relative to the peak joint force:
    # rounding of two eliminations (per group vs one dense solve), times 1/sin of the transmission angle
    worst = oracle_forces.compare(m, q, qd, qdd, (1.3, -9.81), (0.8 * peak, -0.6 * peak))
    assert max(worst["joints"], worst["couples"], worst["drives"], worst["shaking"]) <= 1e-9, worst
