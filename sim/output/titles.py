"""Text that fits its figure: titles wrapped (then shrunk) to their panel's width, tick labels thinned until
they do not overlap. Measured on the rendered figure (matplotlib's own text extents), so it holds for any
font, length and panel size (issue 32: synthesis plot titles were cut off at the figure's edge)."""

from __future__ import annotations

import textwrap

MIN_FONTSIZE = 6.0
"""The smallest a title is shrunk to (points) after wrapping; below it a title stays wrapped at this size."""
SLACK = 1.05
"""A title may be this much wider than its panel (it is centred over it: the neighbours' titles stay clear)."""
GAP_PX = 2.0
"""The least gap between two neighbouring tick labels [pixels]."""


def _renderer(fig):
    fig.canvas.draw()
    return fig.canvas.get_renderer()


def _titles(ax):
    return [t for t in (ax.title, ax._left_title, ax._right_title) if t.get_text()]


def _too_wide(fig, ax, t, renderer) -> bool:
    box = t.get_window_extent(renderer)
    room = ax.get_window_extent(renderer).width * SLACK
    return box.width > room or box.x0 < 0 or box.x1 > fig.bbox.width


def _wrap(text: str, width: int) -> str:
    """Each line of ``text`` wrapped at spaces to ``width`` characters (a longer word stays whole)."""
    return "\n".join(textwrap.fill(line, width=width, break_long_words=False, break_on_hyphens=False) or line
                     for line in text.split("\n"))


def fit_titles(fig) -> bool:
    """Wrap each axes title of ``fig`` that is wider than its panel (or past the figure's edge) at spaces to
    fit, from its text as first written, then shrink its font (to MIN_FONTSIZE) if a word is still too long.
    True if a title changed."""
    renderer = _renderer(fig)
    changed = False
    for ax in fig.axes:
        if not ax.get_visible():
            continue
        for t in _titles(ax):
            original = getattr(t, "_fit_original", None)
            if original is None:
                original = t._fit_original = t.get_text()
            for _ in range(12):
                if not _too_wide(fig, ax, t, renderer):
                    break
                box = t.get_window_extent(renderer)
                room = min(ax.get_window_extent(renderer).width * SLACK, fig.bbox.width)
                longest = max(len(line) for line in t.get_text().split("\n"))
                chars = int(0.97 * room / (box.width / max(longest, 1)))
                wrapped = _wrap(original, max(chars, 8))
                if wrapped != t.get_text() and chars >= 8:
                    t.set_text(wrapped)
                elif t.get_fontsize() > MIN_FONTSIZE:
                    t.set_fontsize(max(MIN_FONTSIZE, 0.9 * t.get_fontsize()))
                else:
                    break
                changed = True
    return changed


def thin_ticks(fig) -> bool:
    """Fewer x tick labels on any axes whose neighbouring labels overlap (MaxNLocator, down to 2 bins). True if
    an axes changed."""
    from matplotlib.ticker import MaxNLocator
    renderer = _renderer(fig)
    changed = False
    for ax in fig.axes:
        if not ax.get_visible() or not ax.axison or ax.get_xscale() != "linear":
            continue
        for nbins in (6, 5, 4, 3, 2):
            boxes = sorted((t.get_window_extent(renderer) for t in ax.get_xticklabels()
                            if t.get_visible() and t.get_text()), key=lambda b: b.x0)
            if all(a.x1 + GAP_PX <= b.x0 for a, b in zip(boxes, boxes[1:])):
                break
            ax.xaxis.set_major_locator(MaxNLocator(nbins=nbins))
            renderer = _renderer(fig)
            changed = True
    return changed


def fit(fig, layout=None) -> None:
    """Titles and tick labels of ``fig`` fitted (:func:`fit_titles`, :func:`thin_ticks`), ``layout`` (e.g.
    ``fig.tight_layout``; none for a constrained layout, which the measuring draw runs) first and after each
    pass that changed something, until a pass finds everything fitting (a wrapped title can narrow a panel of fixed
    aspect: at most 5 passes)."""
    if layout is not None:
        layout()
    for _ in range(5):
        changed = fit_titles(fig)
        changed |= thin_ticks(fig)
        if not changed:
            return
        if layout is not None:
            layout()


__all__ = ["fit", "fit_titles", "thin_ticks"]
