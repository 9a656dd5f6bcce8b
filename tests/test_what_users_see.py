"""What users see (issue 20, item 7): export --toml keeps the file as written; compare tables led by what
moves; videos drawn like the app (content checks, not golden pixels)."""

import json
from pathlib import Path

import numpy as np

import analytic

import cli_runner  # the command in this process (tests/cli_runner.py)

LIB = Path(analytic.__file__).parent / "library"


def run(*args, ok=(0,)):
    p = cli_runner.run(*map(str, args))
    assert p.returncode in ok, p.stderr
    return p.stdout


def test_export_toml_rewrites_only_the_changed_values(tmp_path):
    out = tmp_path / "h.toml"
    run("export", "hoekens", "--toml", out, "--set", "crank=55", "--set", "omega1=720deg")
    before, after = (LIB / "hoekens.toml").read_text().splitlines(), out.read_text().splitlines()
    assert len(before) == len(after)
    diff = [(a, b) for a, b in zip(before, after) if a != b]
    assert diff == [("crank = 50.0       # AB (unit a = 50 mm)", "crank = 55.0       # AB (unit a = 50 mm)"),
                    ('omega1 = "360deg"', 'omega1 = "720deg"')]
    # the written file is the design that was exported: same analysis as the --set run
    a = json.loads(run("analyze", out, "--json"))
    b = json.loads(run("analyze", "hoekens", "--set", "crank=55", "--set", "omega1=720deg", "--json"))
    np.testing.assert_allclose(a["ranges"]["vxP"], b["ranges"]["vxP"], rtol=1e-12)   # same floats, same solver


def test_export_toml_unchanged_is_the_file_itself_and_json_is_generated(tmp_path):
    run("export", "fivebar", "--toml", tmp_path / "f.toml")
    assert (tmp_path / "f.toml").read_text() == (LIB / "fivebar.toml").read_text()
    assert '"60deg"' in (tmp_path / "f.toml").read_text()
    # a JSON file has no TOML text to keep: the generated file, which still reads back as the design
    import tomllib
    src = tmp_path / "four.json"
    data = tomllib.loads((LIB / "fourbar.toml").read_text())
    src.write_text(json.dumps({**data, "name": "four"}))
    run("export", src, "--toml", tmp_path / "g.toml", "--set", "l1=0.11")
    g = json.loads(run("analyze", tmp_path / "g.toml", "--json"))
    h = json.loads(run("analyze", "fourbar", "--set", "l1=0.11", "--json"))
    np.testing.assert_allclose(g["ranges"]["xE"], h["ranges"]["xE"], rtol=1e-12)   # same floats, same solver


# ---------------------------------------------------------------------------------------- videos
def _rgb(hexcolor):
    return np.array([int(hexcolor[i:i + 2], 16) for i in (1, 3, 5)])


def test_video_colours_are_the_apps():
    import re
    from sim.output import drawing
    js = (Path(__file__).resolve().parent.parent / "sim" / "front" / "static" / "app.js").read_text()
    app = re.search(r"const COLORS = \[(.*?)\];", js).group(1)
    assert tuple(re.findall(r'"(#[0-9a-f]{6})"', app)) == drawing.COLORS


def test_a_frame_has_pins_plates_bars_scale_and_readout():
    """jansen: links of three points (plates) and of two (bars). Read the frame at known places: a pin's
    centre is white (the output point's red), a plate's centroid is its colour blended at alpha 0x2e over
    white, a bar's midpoint its colour; the scale bar and the readout put dark pixels in their corners."""
    from analytic.quantities import Display
    from sim.output import drawing
    from sim.output import render
    from sim import service
    built, tr = service.simulate(service.load("jansen"), 0.25)
    qpos, _ = render.frame_poses(tr.t, tr.qpos, np.array([0.1]))
    xy, angles = drawing.poses(built, qpos)
    sc = drawing.scene(built, xy, Display("mm"))
    painter = drawing.Painter(sc, (640, 480))
    frame = painter.frame(xy[0], {}, xy[:1, 0], xy[:1, 0], 0.1, 0.5).astype(int)
    px = painter.px(xy[0]) / drawing.SUPERSAMPLE
    where = {p: np.round(px[i]).astype(int) for i, p in enumerate(sc.points)}

    def at(p):
        x, y = p
        return frame[y, x]
    for p in sc.points:
        expect = _rgb("#d62728") if p == sc.output_point else np.array([255, 255, 255])
        assert np.abs(at(where[p]) - expect).max() <= 40, p          # the pin (resampling blurs its edge)
    plates = bars = 0
    for k, (name, pts, block) in enumerate(sc.links):
        color = _rgb(drawing.COLORS[k % len(drawing.COLORS)])
        c = np.mean([where[p] for p in pts], axis=0).round().astype(int)
        if len(pts) == 3 and not block:
            tint = 255 + (color - 255) * 0x2e / 255                 # alpha blending over white
            if np.abs(at(c) - tint).max() <= 12:                    # unless another link crosses the centroid
                plates += 1
        elif len(pts) == 2:
            if np.abs(at(c) - color).max() <= 40:
                bars += 1
    assert plates >= 2 and bars >= 5                                 # jansen: 3 plates, 7 bars
    assert (frame[440:, 400:] < 80).all(axis=-1).sum() > 100         # the scale bar and its label
    assert (frame[:30, 320:] < 80).all(axis=-1).sum() > 50           # "phi... = ... · t = 0.100 s"


def test_scale_bar_length_is_round_in_the_display_unit():
    from sim.output.drawing import nice_step
    assert nice_step(600.0) == 100.0 and nice_step(0.6) == 0.1 and nice_step(1.3) == 0.5
