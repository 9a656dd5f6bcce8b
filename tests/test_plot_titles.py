"""Synthesis plots keep their text inside the figure (issue 32: titles cut off at the figure's edge;
sim.output.fit). The figures the commands draw are caught before they are closed and measured as rendered:
every title lies inside the figure, no two titles overlap, no title runs into the labels of the panel above,
every word of a title is still there, and neighbouring tick labels do not overlap."""

from __future__ import annotations

import types

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from sim.output import fit  # noqa: E402

LONG = ("the traced point meets targets 5 and 6 out of order and the crank cannot turn fully between targets 2 "
        "and 3 of the 8")


def _boxes(fig):
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    return r, [(ax, t, t.get_window_extent(r)) for ax in fig.axes if ax.get_visible()
               for t in (ax.title, ax._left_title, ax._right_title) if t.get_text()]


def assert_fits(fig, words: dict):
    """Every title inside the figure, not overlapping another title or the labels of the panel above, with its
    words; x tick labels apart."""
    r, boxes = _boxes(fig)
    W, H = fig.bbox.width, fig.bbox.height
    for ax, t, b in boxes:
        # 0.5 px: the renderer's rounding of a text extent
        assert b.x0 >= -0.5 and b.x1 <= W + 0.5 and b.y0 >= -0.5 and b.y1 <= H + 0.5, (t.get_text(), b, W, H)
        if t.get_text().split()[0] in words:
            assert t.get_text().split() == words[t.get_text().split()[0]]          # wrapped, nothing dropped
    for (_, t1, b1) in boxes:
        for (_, t2, b2) in boxes:
            if t1 is not t2 and b1.overlaps(b2):
                raise AssertionError(f"titles overlap: {t1.get_text()!r} and {t2.get_text()!r}")
    # no title runs into the axis labels or tick labels of the panel above it
    others = [(ax, t) for ax in fig.axes if ax.axison for t in [ax.xaxis.label, *ax.get_xticklabels()] if t.get_text()]
    for ax1, t1, b1 in boxes:
        for ax2, t2 in others:
            if ax2 is not ax1 and b1.overlaps(t2.get_window_extent(r)):
                raise AssertionError(f"title {t1.get_text()!r} runs into {t2.get_text()!r}")
    for ax in fig.axes:
        if not ax.axison:
            continue
        xs = sorted((t.get_window_extent(r) for t in ax.get_xticklabels() if t.get_text()), key=lambda b: b.x0)
        assert all(a.x1 <= b.x0 for a, b in zip(xs, xs[1:])), [t.get_text() for t in ax.get_xticklabels()]


@pytest.fixture
def caught(monkeypatch):
    """The figures the code under test closes, kept open for measuring."""
    figs = []
    real_close = plt.close

    def keep(fig=None):
        if fig is not None and not isinstance(fig, str):
            figs.append(fig)
            return None
        return real_close(fig)
    monkeypatch.setattr(plt, "close", keep)
    yield figs
    for f in figs:
        real_close(f)


def _ellipse(n=200):
    a = np.linspace(0, 2 * np.pi, n)
    return np.column_stack([0.3 + 0.1 * np.cos(a), 0.2 + 0.05 * np.sin(a)])


def _found(label, failed, sum_sq):
    family = types.SimpleNamespace(label=label, pivots=lambda x: np.array([[[0.0, 0.0], [0.3, -0.2]]]),
                                   pivot_names=("A", "D"))
    return {"design": types.SimpleNamespace(family=family, x=np.zeros(3)), "failed": failed,
            "error": {"sum_sq": sum_sq}}


def test_synthesize_path_panel_titles_fit(tmp_path, monkeypatch, caught):
    """Three candidates side by side, the outer ones with a long failure note (what used to run off the
    figure's left and right edges)."""
    from sim.front.cli import synth_path
    monkeypatch.setattr(synth_path, "design_service", types.SimpleNamespace(curve=lambda f: _ellipse()))
    target = types.SimpleNamespace(xy=_ellipse(8))
    found = [_found("slider-crank", LONG, 1.234e-5), _found("four-bar", None, 2.5e-5),
             _found("Watt six-bar (chain 2, branches +1 -1)", LONG, 123456.789)]
    synth_path.plot(str(tmp_path / "p.png"), target, found, "mm")
    (fig,) = caught
    _, before = _boxes(fig)
    assert any("\n" in t.get_text() and len(t.get_text().split("\n")) > 2 for _, t, _ in before)   # was wrapped
    assert_fits(fig, {"#1": ("#1 slider-crank: sum of squares 1.234e-05 mm^2 (" + LONG + ")").split(),
                      "#3": ("#3 Watt six-bar (chain 2, branches +1 -1): sum of squares 1.235e+05 mm^2 (" + LONG
                             + ")").split()})
    assert (tmp_path / "p.png").stat().st_size > 0


@pytest.mark.parametrize("count", [2, 4])
def test_pareto_plot_titles_and_small_ticks_fit(tmp_path, monkeypatch, caught, count):
    """A front of errors 0 .. 0.0178 m (two objectives: the front's tick labels ran into each other, 0.0000 to
    0.0175 every 0.0025) and four objectives in each design's title."""
    from sim.front.cli import synth_pareto
    P = synth_pareto.P
    objectives = list(P.OBJECTIVES)[:count]
    monkeypatch.setattr(synth_pareto, "design_service", types.SimpleNamespace(curve=lambda f: _ellipse()))
    front = []
    for n, e in enumerate([1.05e-4, 0.01765, 0.01781]):
        f = _found("four-bar", None, e)
        f.update({P.OBJECTIVES[o]: v for o, v in zip(objectives, [e, 5.43 - n, 123.456 + n, 0.987654])})
        front.append(f)
    synth_pareto.plot(str(tmp_path / "f.png"), types.SimpleNamespace(xy=_ellipse(8)), front, objectives, "m")
    (fig,) = caught
    assert_fits(fig, {})


def test_a_title_without_spaces_is_shrunk_not_left_past_the_edge(caught):
    fig, axes = plt.subplots(1, 3, figsize=(9, 3))
    for ax in axes:
        ax.set_title("x" * 45, fontsize=10)      # ~370 px at 10 pt in a 300 px column; ~225 px at 6 pt
    fig.tight_layout()
    fit.fit(fig)
    sizes = [ax.title.get_fontsize() for ax in axes]
    assert all(fit.MIN_FONTSIZE <= s < 10 for s in sizes)
    assert_fits(fig, {})
    plt.close(fig)


def test_two_position_plot_fits(tmp_path, caught):
    import cli_runner
    r = cli_runner.run("synthesize", "two-position", "--plot", str(tmp_path / "tp.png"))
    assert r.returncode == 0, r.stderr
    (fig,) = caught
    assert_fits(fig, {})


def test_a_title_that_fits_is_left_as_written(caught):
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.set_title("#1 four-bar: sum of squares 4.551e-06 m^2", fontsize=9)
    ax.plot([0, 0.4], [0, 1])
    fig.tight_layout()
    fit.fit(fig)
    assert ax.title.get_text() == "#1 four-bar: sum of squares 4.551e-06 m^2" and ax.title.get_fontsize() == 9
    plt.close(fig)
