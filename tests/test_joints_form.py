"""The links-and-joints form of ``linkage/1``: the Assur groups it finds, and the motion it gives checked against
the file's own joints (rigid links, pins, slides) and against hand geometry; one line for every file that is
not a mechanism.

The checks share nothing with the converter: ``joint_residuals`` reads the form as written (each link's points,
each P joint's guide, block and direction) and measures how far a solved motion breaks it.
"""

from __future__ import annotations

import math
import tomllib
import types
from pathlib import Path

import numpy as np
import pytest

import analytic
from analytic import FileError, kinds
from analytic.format import foreign

import cli_runner  # the command in this process (tests/cli_runner.py)
from fourbar_text import joints_fourbar_text  # the mm four-bar in the links-and-joints form

EXAMPLES = Path(__file__).parent / "peers_examples"
POSE_TOL = 1e-9     # / size: the pose's positions through the derived lengths and angles (rounding, ~1e-15)
JOINT_TOL = 1e-9    # / size: a joint of the file broken by the solved motion (rounding of the closed forms)
HAND_TOL = 1e-12    # / size: the solver against hand geometry written in the test (both closed forms)


# ----------------------------------------------------------------------------------- independent checks
def link_points(form: dict) -> dict[str, list[str]]:
    """Every link's points as the form says: listed, pinned by an R joint, the block's point of a P joint."""
    out: dict[str, list[str]] = {"ground": list(form.get("ground", {}))}
    for item in form.get("links", []):
        out.setdefault(item["name"], []).extend(item.get("points", []))
    for j in form.get("joints", []):
        for ln in (j["links"] if j["kind"] == "R" else [j["block"]]):
            if j["point"] not in out.setdefault(ln, []):
                out[ln].append(j["point"])
    return out


def pose_of(form: dict) -> dict[str, np.ndarray]:
    return {p: np.array(xy, dtype=float) for p, xy in {**form.get("ground", {}), **form["pose"]}.items()}


def size_of(form: dict) -> float:
    xy = np.array(list(pose_of(form).values()))
    return float(np.max(np.linalg.norm(xy[:, None] - xy[None], axis=-1)))


def _angle(v):
    return np.arctan2(v[..., 1], v[..., 0])


def _turn(form, pts, link, links, pose, turns, seen=()):
    """A link's rotation from the pose (rad, per sample), from two of its points, or as driven (``turns``);
    None where neither tells."""
    if link == "ground":
        return 0.0
    if link in turns:
        return turns[link]
    p = [x for x in links[link] if x in pts]
    if len(p) < 2:                           # a block with one point turns as the link it slides on
        for j in form.get("joints", []):
            if j["kind"] == "P" and link in (j["guide"], j["block"]):
                other = j["block"] if j["guide"] == link else j["guide"]
                if other not in seen:
                    t = _turn(form, pts, other, links, pose, turns, seen + (link,))
                    if t is not None:
                        return t
        return None
    q = max(p[1:], key=lambda x: np.linalg.norm(pose[x] - pose[p[0]]))
    return _angle(pts[q] - pts[p[0]]) - _angle(pose[q] - pose[p[0]])


def joint_residuals(form: dict, pts: dict[str, np.ndarray], turns: dict | None = None) -> float:
    """The largest violation, over the samples, of the form's joints by solved positions ``pts`` (file units,
    arrays (N, 2)), relative to the size: every link rigid (its points keep their coordinates in the frame of
    two of them; the ground's stay put), and every P joint's block point on the line of its guide (through
    the point's pose position, direction ``angle``, turning with the guide) with the block keeping its angle to
    the guide. ``turns``: the rotation of driven links (crank angle minus its start), where their points
    do not show it."""
    turns = turns or {}
    links, pose, size = link_points(form), pose_of(form), size_of(form)
    worst = 0.0

    def wrap(a):
        return np.abs((a + np.pi) % (2 * np.pi) - np.pi)

    for ln, ps in links.items():
        if ln == "ground":
            for p in ps:
                worst = max(worst, float(np.max(np.linalg.norm(pts[p] - pose[p], axis=-1))) / size)
            continue
        if len(ps) < 2:
            continue
        o = ps[0]
        x = max(ps[1:], key=lambda p: np.linalg.norm(pose[p] - pose[o]))    # a frame from two distinct points
        e0 = (pose[x] - pose[o]) / np.linalg.norm(pose[x] - pose[o])
        d = pts[x] - pts[o]
        e = d / np.linalg.norm(d, axis=-1, keepdims=True)
        worst = max(worst, float(np.max(np.abs(np.linalg.norm(d, axis=-1) - np.linalg.norm(pose[x] - pose[o]))))
                    / size)
        for p in ps[1:]:
            r0 = pose[p] - pose[o]
            u0, v0 = r0 @ e0, e0[0] * r0[1] - e0[1] * r0[0]
            r = pts[p] - pts[o]
            u, v = np.sum(r * e, axis=-1), e[:, 0] * r[:, 1] - e[:, 1] * r[:, 0]
            worst = max(worst, float(np.max(np.hypot(u - u0, v - v0))) / size)
    for j in form.get("joints", []):
        if j["kind"] != "P":
            continue
        a0 = math.radians(float(str(j["angle"]).removesuffix("deg")))
        turn = _turn(form, pts, j["guide"], links, pose, turns)
        assert turn is not None, f"guide {j['guide']} needs two points for this check"
        u = np.stack([np.cos(a0 + turn), np.sin(a0 + turn)], axis=-1) * np.ones((len(pts[j["point"]]), 1))
        g = [p for p in links[j["guide"]] if p in pts] or [None]
        ref, ref0 = (pts[g[0]], pose[g[0]]) if g[0] else (np.zeros(2), np.zeros(2))
        side0 = math.cos(a0) * (pose[j["point"]] - ref0)[1] - math.sin(a0) * (pose[j["point"]] - ref0)[0]
        r = pts[j["point"]] - ref
        side = u[:, 0] * r[..., 1] - u[:, 1] * r[..., 0]
        worst = max(worst, float(np.max(np.abs(side - side0))) / size)
        block = _turn(form, pts, j["block"], links, pose, turns)
        if block is not None:
            worst = max(worst, float(np.max(wrap(block - turn))))
    return worst


def solved_points(mech, q) -> dict[str, np.ndarray]:
    """Every point's solved position in the file's unit, (N, 2)."""
    sol = mech.solve(q)
    return {p: np.stack([sol["x" + p], sol["y" + p]], axis=-1) / mech.scale for p in mech.points}


def range_near_start(mech, span: float = 0.6, n: int = 121) -> np.ndarray:
    """Input values around the first input's start, within its assembly range, for a single input."""
    q0 = mech.inputs[0].motion.q0
    if mech.inputs[0].kind == "slider":
        return q0 + np.linspace(-0.05, 0.05, n) * mech.size
    from analytic.applications import figures
    ranges = figures.assembly_ranges(mech)
    lo, hi = q0 - span, q0 + span
    for a, b in ranges:                      # the reachable interval holding the start (mod 2 pi)
        k = math.floor((q0 - a) / (2 * math.pi))
        a, b = a + 2 * math.pi * k, b + 2 * math.pi * k
        if a <= q0 <= b:
            lo, hi = max(lo, a + 0.05 * (b - a)), min(hi, b - 0.05 * (b - a))
    return np.linspace(lo, hi, n)


def check_motion(mech, form: dict):
    """The pose at the start, the joints over a range of the input, and no jump between samples."""
    size = size_of(form)
    at0 = solved_points(mech, np.array([i.motion.q0 for i in mech.inputs])[None])
    for p, xy in pose_of(form).items():
        assert np.linalg.norm(at0[p][0] - xy) <= POSE_TOL * size, p
    q = range_near_start(mech)
    pts = solved_points(mech, q)
    assert all(np.all(np.isfinite(v)) for v in pts.values())
    turns = {}
    for item in form["inputs"]:
        if item["kind"] == "crank":
            link = item.get("link") or next(x for x in mech.inputs if x.joint == item["pivot"]).link
            turns[link] = q - mech.inputs[0].motion.q0
            if "point" in item:                     # the input is the angle pivot -> point (Pyslvs' convention)
                d = pts[item["point"]] - pts[item["pivot"]]
                err = np.abs((np.arctan2(d[:, 1], d[:, 0]) - q + np.pi) % (2 * np.pi) - np.pi)
                assert np.max(err) <= 1e-12           # rad: rounding of the crank's closed form
    assert joint_residuals(form, pts, turns) <= JOINT_TOL
    step = np.max([np.max(np.linalg.norm(np.diff(v, axis=0), axis=-1)) for v in pts.values()])
    assert step <= 0.05 * size       # continuity: 121 samples over < 70 deg move no point by a twentieth of the size


def form_and_mech(path: Path, inputs=None):
    if path.suffix == ".toml":
        text = path.read_text()
        return tomllib.loads(text), analytic.from_text(text, str(path))
    form = foreign.read(path, inputs)
    return form, analytic.registry.Mechanism.from_definition(foreign.definition(path, inputs), {})


FOURBAR = joints_fourbar_text('kind = "crank"\npivot = "A"\npoint = "B"', name="fourbar_lj")


def test_fourbar_against_hand_geometry():
    m = analytic.from_text(FOURBAR, "fourbar_lj.toml")
    assert [e.kind for e in m.definition.order] == ["crank", "RRR", "point"]
    A, B0, C0, D, E0 = (np.array(v) for v in ([0, 0], [12.5, 21.6506], [74.2099, 54.6944], [80, 0],
                                              [29.506, 53.4436]))
    r, a, b = np.linalg.norm(B0 - A), np.linalg.norm(C0 - B0), np.linalg.norm(C0 - D)
    q = np.linspace(0, 2 * np.pi, 73)
    pts = solved_points(m, q)
    u0 = (C0 - B0) / a
    eu, ev = (E0 - B0) @ u0, u0[0] * (E0 - B0)[1] - u0[1] * (E0 - B0)[0]
    for k, phi in enumerate(q):                       # circle-circle by hand, upper branch (C above B-D)
        B = A + r * np.array([math.cos(phi), math.sin(phi)])
        d = D - B
        L = np.linalg.norm(d)
        x = (a * a - b * b + L * L) / (2 * L)
        C = B + x * d / L + math.sqrt(a * a - x * x) * np.array([-d[1], d[0]]) / L
        u = (C - B) / a
        E = B + eu * u + ev * np.array([-u[1], u[0]])
        for p, want in (("B", B), ("C", C), ("E", E)):
            assert np.linalg.norm(pts[p][k] - want) <= HAND_TOL * 80, (p, phi)
    assert m.inputs[0].motion.q0 == pytest.approx(math.atan2(21.6506, 12.5), abs=1e-15)
    assert m.inputs[0].motion.rate == pytest.approx(2 * math.pi)       # the default: one turn per second


@pytest.mark.parametrize("name,inputs", [("fourbar.pyslvs", None), ("slider_crank_rp.txt", [(0, 1)]),
                                         ("quick_return.txt", [(0, 1)]), ("offset_block.txt", None),
                                         ("moving_guide.txt", None), ("quirks.txt", None)])
def test_examples_keep_their_pose_and_joints(name, inputs):
    form, m = form_and_mech(EXAMPLES / name, inputs)
    check_motion(m, form)


def test_direction_by_a_point_equals_direction_by_angle():
    text = (EXAMPLES / "offset_block.txt").read_text()
    form = foreign.read(EXAMPLES / "offset_block.txt")
    assert any(j["kind"] == "P" for j in form["joints"])
    by_angle = analytic.registry.Mechanism.from_definition(analytic.format.linkfile.from_data(form, "a"), {})
    form2 = dict(form, pose={**form["pose"], "G": [40.0, 0.0]})
    form2["links"] = form["links"] + [{"name": "ground", "points": ["G"]}]
    form2["joints"] = [dict({k: v for k, v in j.items() if k != "angle"}, along="G") if j["kind"] == "P" else j
                       for j in form["joints"]]
    by_point = analytic.registry.Mechanism.from_definition(analytic.format.linkfile.from_data(form2, "b"), {})
    q = np.linspace(0, 6, 25)
    a, b = by_angle.solve(q), by_point.solve(q)
    for p in form["pose"]:
        assert np.max(np.abs(a["x" + p] - b["x" + p])) <= 1e-15 + 1e-13 * by_angle.size   # same lines, rounding
    assert text


def test_symbolic_pose_follows_its_parameters():
    """Pose values that are parameters: --set moves the derived lengths, start angle and offsets with them,
    exactly as a file with those numbers written in."""
    sym = FOURBAR.replace("[pose]", '[parameters]\nl4 = 80\ncx = 74.2099\nth = "60deg"\n\n[pose]')
    sym = sym.replace("D = [80, 0]", 'D = ["l4", 0]').replace("C = [74.2099, 54.6944]", 'C = ["cx", 54.6944]')
    sym = sym.replace("B = [12.5, 21.6506]", 'B = ["25*cos(th)", "25*sin(th)"]')
    m = analytic.from_text(sym, "sym.toml")
    assert m.definition.parameter_kind["l4"] == m.definition.parameter_kind["cx"] == "length"
    num = analytic.from_text(FOURBAR.replace("D = [80, 0]", "D = [83, 0]").replace(
        "C = [74.2099, 54.6944]", "C = [76.5, 54.6944]").replace(
        "B = [12.5, 21.6506]", f"B = [{25 * math.cos(0.9)!r}, {25 * math.sin(0.9)!r}]"), "num.toml")
    moved = m.with_values(l4=83.0, cx=76.5, th=0.9)
    q = np.linspace(0, 6, 13)
    a, b = moved.solve(q), num.solve(q)
    for k in ("xC", "yC", "xE", "yE"):
        assert np.max(np.abs(a[k] - b[k])) <= 1e-13 * num.size        # rounding of two evaluation orders
    assert moved.inputs[0].motion.q0 == pytest.approx(0.9, abs=1e-15)


# ------------------------------------------------------------------------------------------ groups
def test_stephenson_triad_is_one_group(monkeypatch):
    """With no dyad left after the crank, the four links of the triad are found as one group whose pose is the
    file's (the kind itself is tested on its own)."""
    if "group" not in kinds.KINDS:
        monkeypatch.setitem(kinds.KINDS, "group", types.SimpleNamespace(section="groups"))
    from analytic.format import joints, linkfile
    data = tomllib.loads((EXAMPLES / "stephenson.toml").read_text())
    conv = joints.convert(data, "stephenson.toml", {})
    groups = [g for g in conv.data["groups"] if g["kind"] == "group"]
    assert len(groups) == 1
    g = groups[0]
    assert sorted(g["points"]) == ["P1", "P2", "P3"]
    assert {k: sorted(v) for k, v in g["links"].items()} == {"l1": ["B", "P1"], "l2": ["D", "P2"],
                                                             "l3": ["F", "P3"], "T": ["P1", "P2", "P3"]}
    assert g["pose"] == {p: data["pose"][p] for p in g["pose"]}
    assert [x["point"] for x in conv.data["groups"] if x["kind"] == "point"] == ["E"]
    assert linkfile  # the converter writes plain tables; the kind reads them


def test_stephenson_refused_or_solved():
    form, path = tomllib.loads((EXAMPLES / "stephenson.toml").read_text()), EXAMPLES / "stephenson.toml"
    if "group" not in kinds.KINDS:
        with pytest.raises(FileError, match=r"links l1, l2, l3, T: .*Assur group that is not a chain of dyads"):
            analytic.load(str(path))
        return
    check_motion(analytic.load(str(path)), form)


@pytest.mark.skipif(not {"RPP", "PRP"} <= set(kinds.KINDS), reason="the PP dyad kinds are not registered")
@pytest.mark.parametrize("name,kind", [("rpp.txt", "RPP"), ("prp.txt", "PRP")])
def test_pp_dyads(name, kind):
    form, m = form_and_mech(EXAMPLES / name)
    assert kind in [e.kind for e in m.definition.order]
    check_motion(m, form)


# --------------------------------------------------------------------------------------- bad input
def _bad(text_or_path, match):
    with pytest.raises(FileError, match=match) as info:
        if isinstance(text_or_path, Path):
            analytic.load(str(text_or_path))
        else:
            analytic.from_text(text_or_path, "m.toml")
    assert "\n" not in str(info.value)
    return str(info.value)


def test_locked_loops_are_refused_with_the_loop():
    _bad(EXAMPLES / "locked_pantograph.toml", r"links\[2\] \(arm\): the loop arm - crank cannot move: link 'arm' "
                                              r"is held at A, O.*Gruebler: 3 x \(3 - 1\) - 2 x 3 = 0, with 1 input")
    _bad(EXAMPLES / "locked_ppp.txt", r"links a, b: the loop input - a - b - ground locks the mechanism: the "
                                      r"prismatic pairs at J1, J2, J3")


def test_not_a_mechanism_one_line_each():
    extra = FOURBAR + '\n[[links]]\nname = "loose"\npoints = ["E", "F"]\n'
    _bad(extra, r"links\[4\] \(loose\): point 'E' is on links coupler, loose but no R joint pins coupler, loose "
                r"there; add \{kind = \"R\", point = \"E\", links = \[\"coupler\", \"loose\"\]\} under")
    _bad(FOURBAR + '\n[[links]]\nname = "idle"\npoints = ["C"]\n', r"point 'C' is on links .* no R joint pins idle")
    _bad(FOURBAR.replace("E = [29.506, 53.4436]", "E = [29.506, 53.4436]\nF = [1, 1]") +
         '\n[[links]]\nname = "idle"\npoints = ["F"]\n', r"links\[4\] \(idle\): link 'idle' has no joint")
    dangling = FOURBAR.replace("E = [29.506, 53.4436]", "E = [29.506, 53.4436]\nF = [40, 70]") + \
        '\n[[links]]\nname = "flap"\npoints = ["E", "F"]\n\n[[joints]]\nkind = "R"\npoint = "E"\nlinks = ["coupler", "flap"]\n'
    _bad(dangling, r"inputs: the mechanism has mobility 2 \(Gruebler: 3 x \(5 - 1\) - 2 x 5 = 2\) but 1 input: "
                   r"links flap are not fixed")
    brace = FOURBAR + '\n[[links]]\nname = "brace"\npoints = ["B", "D"]\n' + \
        '\n[[joints]]\nkind = "R"\npoint = "B"\nlinks = ["crank", "brace"]\n' + \
        '\n[[joints]]\nkind = "R"\npoint = "D"\nlinks = ["ground", "brace"]\n'
    _bad(brace, r"links\[4\] \(brace\): the loop brace - .*cannot move: link 'brace' is held at B, D")
    rigid = FOURBAR.replace('points = ["D", "C"]', 'points = ["D", "C"]\nlengths = [["D", "C", 55.5]]')
    _bad(rigid, r"links\[3\] \(rocker\): the pose puts D and C 55.000.* apart but 'lengths' gives 55.5")
    ok = FOURBAR.replace('points = ["D", "C"]', 'points = ["D", "C"]\nlengths = [["D", "C", 55.00002]]')
    assert analytic.from_text(ok, "ok.toml")                      # within 1e-6 of the size
    dead = FOURBAR.replace("C = [74.2099, 54.6944]", "C = [100, 0]").replace("D = [80, 0]", "D = [120, 0]")
    dead = dead.replace("B = [12.5, 21.6506]", "B = [25, 0]")
    _bad(dead, r"links coupler, rocker \(point C\): the pose is singular: B, C and D are in line")
    _bad(FOURBAR.replace('pivot = "A"', 'pivot = "C"'), r"inputs\[1\] \(pivot C\): field 'pivot': 'C' is not on the "
                                                        r"ground")
    _bad(FOURBAR.replace('kind = "R"\npoint = "D"', 'kind = "Q"\npoint = "D"'), r"joints\[4\] \(point D\): unknown "
                                                                            r"kind 'Q'")
    _bad(FOURBAR.replace("E = [29.506, 53.4436]\n", ""), r"point 'E' has no position; give it under \[pose\]")
    _bad(FOURBAR.replace("D = [80, 0]", 'D = ["80 +", 0]'), r"pose.D: '80 \+' is not a number, a parameter name or an")
    _bad(FOURBAR.replace("D = [80, 0]", 'D = ["l4", 0]'), r"pose.D: 'l4' uses 'l4', which is not a parameter")


def test_cli_exit_2_one_line(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(FOURBAR.replace('pivot = "A"', 'pivot = "C"'))
    r = cli_runner.run("check", str(bad))
    assert r.returncode == 2 and r.stdout == ""
    assert r.stderr.count("\n") == 1 and "Traceback" not in r.stderr
    r = cli_runner.run("check", str(EXAMPLES / "offset_block.txt"))
    assert r.returncode == 0
    assert "Assur groups: J2 (links coupler, output): dyad RRP (class II)" in r.stdout


def test_the_documented_example_reads_and_keeps_its_pose():
    docs = (Path(__file__).resolve().parent.parent / "docs" / "CONVENTIONS.md").read_text()
    block = docs.split("## Links and joints", 1)[1].split("```toml\n", 1)[1].split("```", 1)[0]
    m = analytic.from_text(block, "docs.toml")
    assert [e.kind for e in m.definition.order] == ["crank", "RRP", "point"]
    check_motion(m, tomllib.loads(block))
