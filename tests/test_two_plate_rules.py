"""Two-plate layouts (clevis links) checked where the library's own layouts do not reach: a pin's span by hand
(analytic.parts.layers.spans), a ground pin of a two-plate layout that must reach the frame or the stack's top
(whitworth with its crank fixed above layer 0), the BOM's volume against its mass and density, and MuJoCo's
scene: a pin's cylinder touches a two-plate link's upper plate, and every two links sharing a layer (a plate of
either) are a pair it measures. Each was found missing by benchmarks/mutation.py (round 4)."""

from pathlib import Path

import numpy as np
import pytest

from analytic.parts import layers as lay
from sim import service
from sim.service import parts as parts_service

LIBRARY = Path(__file__).resolve().parent.parent / "analytic" / "library"


def prepared(name):
    return parts_service.prepare(service.load(name, {}))


def rule(members, crossing, ground):
    return lay.PinRule("P", tuple(members), tuple(crossing), ground)


def test_a_ground_pins_span_by_hand():
    """A ground pin on link X (layer 2) passed over by link Y: from the frame (layers -1..2) only where Y is
    above layer 2, from a top plate (2..top) only where Y is below it, neither where Y is on X's own layer 2
    (the pin would run through Y's plate either way)."""
    assert lay.spans(rule("X", "Y", True), {"X": (2,), "Y": (3,)}) == [lay.Span(-1, 2, "below")]
    assert lay.spans(rule("X", "Y", True), {"X": (2,), "Y": (1,)}) == [lay.Span(2, None, "above")]
    assert lay.spans(rule("X", "Y", True), {"X": (2,), "Y": (2,)}) == []


def test_a_pins_span_through_a_clevis_by_hand():
    """A pin joining X (layer 2) and a two-plate Z (plates 1 and 3) passed over by Y on layer 2 or 0: through Z's
    lower plate and X (1..2) or its upper plate and X (2..3) or both plates (1..3); none holds with Y on layer 2
    (X's own), with Y on layer 0 all three do, shortest first."""
    assert lay.spans(rule("XZ", "Y", False), {"X": (2,), "Z": (1, 3), "Y": (2,)}) == []
    got = lay.spans(rule("XZ", "Y", False), {"X": (2,), "Z": (1, 3), "Y": (0,)})
    assert got == [lay.Span(1, 2, ""), lay.Span(2, 3, ""), lay.Span(1, 3, "")]


def _whitworth_crank_on(tmp_path, layer: int):
    text = (LIBRARY / "whitworth.toml").read_text() + f'\n[parts]\nlayers = {{ "2" = {layer} }}\n'
    path = tmp_path / "whitworth_crank_up.toml"
    path.write_text(text)
    return parts_service.prepare(service.load(str(path), {}))


def _ground_pins_anchored(pm):
    """Each ground pin's span reaches the frame (z = 0) or the top of the stack (the highest plate's top)."""
    L = pm.layout
    top = max([z1 for _, z1 in L.z.values()] + [z1 for _, (_, z1) in (L.second or {}).values()])
    for p in pm.mech.ground_points:
        if p not in L.pins:
            continue
        lo, hi = L.pins[p]
        # both ends are sums of the same thicknesses and gaps: equal to rounding
        assert lo == pytest.approx(0.0, abs=1e-9) or hi == pytest.approx(top, rel=1e-12), (p, L.pins[p], top)


def test_a_ground_pin_of_a_two_plate_layout_reaches_the_frame_or_the_top(tmp_path):
    """The Whitworth with its crank fixed on layer 1 ([parts].layers): still a two-plate lever, and the crank's
    ground pin O, on a link above layer 0, runs down to the frame (z = 0), not from the crank's bottom face."""
    pm = _whitworth_crank_on(tmp_path, 1)
    L = pm.layout
    assert L.second and L.layers["2"] == 1 and not L.clashes
    _ground_pins_anchored(pm)
    lo, hi = L.pins["O"]
    assert lo == pytest.approx(0.0, abs=1e-9)               # from the frame
    assert hi == pytest.approx(L.z["2"][1], rel=1e-12)      # to the crank's top face (its plate alone)
    for name in ("whitworth", "stephenson_ii", "double_butterfly"):
        _ground_pins_anchored(prepared(name))


def test_bom_volume_of_a_two_plate_link_is_its_mass_over_the_density():
    """rho V = m, row by row (the BOM's volume in the file's unit cubed, the mass in kg): the two-plate lever's
    volume is both plates', as its mass is."""
    from sim.output import parts_files
    pm = prepared("whitworth")
    s3 = pm.mech.scale ** 3
    rows = parts_files.bom_rows(pm)
    assert any(r["plates"] == 2 for r in rows)
    for r in rows:
        # one product of the same figures: rounding
        assert r["volume"] * s3 * r["density_kg_m3"] == pytest.approx(r["mass_kg"], rel=1e-12), r["link"]


def test_mujocos_pin_touches_the_upper_plate_of_a_two_plate_link():
    """The Whitworth's scene with pin O's span moved into the lever's upper plate only (z 49..57 of its 48..58):
    at an instant where O lies inside the lever's outline in plan by more than the pin's radius (shapely, from
    the outline and the solver's motion), MuJoCo finds the pin's cylinder in the lever's solid; at one where the
    outline is far from O, it does not."""
    import dataclasses

    import mujoco
    import shapely

    from analytic.parts import model
    from sim.model import parts_scene
    pm = prepared("whitworth")
    L = pm.layout
    # the lever's upper plate [mm]: sums of the plates' thicknesses and the gaps, exact to rounding
    assert L.second["3"][1] == pytest.approx((48.0, 58.0), abs=1e-9)
    layout = dataclasses.replace(L, pins={**L.pins, "O": (49.0, 57.0)})
    scene = parts_scene.build(pm.mech, pm.parts, layout, pm.chord, ("O",))
    r = model.settings(pm.mech).pin_diameter / 2
    polys = lay.Swept(lay.outlines(pm.mech, pm.parts), pm.sweep).polys("3")
    at = shapely.points(pm.sweep.points["O"])
    # inside by twice the pin's radius: the chord's facets and the cylinder's own rounding are far smaller
    inside = np.asarray(shapely.contains(polys, at)) & (np.asarray(shapely.distance(shapely.boundary(polys), at)) > 2 * r)
    far = np.asarray(shapely.distance(polys, at)) > 4 * r      # clear by the pin's diameter and more
    assert inside.any() and far.any()
    data = mujoco.MjData(scene.model)
    parts_scene.pose(scene, data, pm.sweep, int(np.flatnonzero(inside)[0]))
    assert parts_scene.in_contact(scene, data, "3", "pin_O")
    parts_scene.pose(scene, data, pm.sweep, int(np.flatnonzero(far)[0]))
    assert not parts_scene.in_contact(scene, data, "3", "pin_O")


@pytest.mark.parametrize("name", ["whitworth", "stephenson_ii", "double_butterfly"])
def test_the_scene_measures_every_two_links_with_plates_at_one_height(name):
    """The pairs MuJoCo measures: every two links (not meshing gears) with a plate each whose z ranges overlap,
    from the layout's z of each plate (a two-plate link's upper plate too); no pair without."""
    from sim.model import parts_scene
    pm = prepared(name)
    L = pm.layout
    scene = parts_scene.build(pm.mech, pm.parts, L, pm.chord)
    zs = {ln: [L.z[ln]] + ([L.second[ln][1]] if L.second and ln in L.second else []) for ln in pm.parts}
    links = list(pm.parts)
    meshing = {frozenset(p) for p in L.meshing}
    want = {frozenset((a, b)) for i, a in enumerate(links) for b in links[i + 1:]
            if frozenset((a, b)) not in meshing
            and any(p[0] < q[1] and q[0] < p[1] for p in zs[a] for q in zs[b])}
    got = {frozenset(p) for p in scene.pairs if lay.FRAME not in p}
    assert got == want


def test_a_two_plate_links_plates_have_a_layer_between_them():
    """The search on a hand graph: X must be two plates (no plain layering is asked for here) joined by its pin
    P, Y free. With two layers no clevis fits (its plates need a layer between, where the links it holds
    pass), so the answer has three: X on layers 0 and 2, P through both, Y on layer 0 (the first tried)."""
    found = lay.two_plates(["X", "Y"], [], {}, [rule("X", (), False)], [], {"X": ["P"]}, 2)
    assert found == ({"X": (0, 2), "Y": (0,)}, {"P": lay.Span(0, 2, "")}, {"X": "P"})
