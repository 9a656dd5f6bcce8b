"""Titles that fit their figure: a title wider than its room (a long mechanism name in a suptitle, a long
figure in a panel's title) is wrapped onto more lines before the figure is saved, and shrunk if a word alone
is still too wide, so that nothing is cut at the image's edge; x tick labels that run into each other are
thinned (issue 32: synthesis plots' titles cut off, a Pareto front's ticks 0.0000 0.0025 ... overlapping)."""

from __future__ import annotations

import textwrap

MIN_FONTSIZE = 6.0
"""The smallest a title is shrunk to (points) when wrapping at spaces leaves a word wider than its room."""
GAP_PX = 2.0
"""The least gap between two neighbouring tick labels [pixels]."""


def _wrap(text_artist, room_px: float, renderer) -> bool:
    """Wrap one title to ``room_px``; True if it changed."""
    text = text_artist.get_text()
    if not text:
        return False
    width = text_artist.get_window_extent(renderer).width
    if width <= room_px:
        return False
    longest = max(len(line) for line in text.splitlines())
    chars = max(12, int(longest * room_px / width))
    text_artist.set_text("\n".join(textwrap.fill(line, chars, break_long_words=False) or line
                                   for line in text.splitlines()))
    while text_artist.get_window_extent(renderer).width > room_px and text_artist.get_fontsize() > MIN_FONTSIZE:
        text_artist.set_fontsize(max(MIN_FONTSIZE, 0.9 * text_artist.get_fontsize()))
    return True


def fit_titles(fig) -> bool:
    """Wrap the figure's suptitle to 96 % of its width and each panel's title to its column's width (the
    panel's own width plus its share of the gaps), then lay the figure out again if anything moved. True if
    a title changed."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    fig_px = fig.get_figwidth() * fig.dpi
    changed = False
    sup = getattr(fig, "_suptitle", None)
    if sup is not None:
        changed |= _wrap(sup, 0.96 * fig_px, renderer)
    for ax in fig.axes:
        if not ax.get_visible():
            continue
        cols = ax.get_gridspec().ncols if ax.get_gridspec() is not None else 1
        room = max(ax.get_position().width * fig_px, 0.94 * fig_px / cols)
        for t in (ax.title, ax._left_title, ax._right_title):
            if t.get_text():                      # a centred title: as wide as twice its way to the nearer edge
                box = t.get_window_extent(renderer)
                centre = 0.5 * (box.x0 + box.x1)
                changed |= _wrap(t, min(room, 2 * min(centre, fig_px - centre) - 4.0), renderer)
    engine = fig.get_layout_engine()
    if changed and (engine is None or type(engine).__name__ == "PlaceHolderLayoutEngine"):
        fig.tight_layout()                        # laid out once by tight_layout: again, for the new lines
                                                  # (a constrained layout redoes itself when saved)
    return changed


def thin_ticks(fig) -> bool:
    """Fewer x tick labels (MaxNLocator, down to 2 bins) on each linear x axis whose neighbouring labels run
    into each other, then the figure laid out again; True if an axis changed."""
    from matplotlib.ticker import MaxNLocator
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
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
            fig.canvas.draw()
            renderer = fig.canvas.get_renderer()
            changed = True
    engine = fig.get_layout_engine()
    if changed and (engine is None or type(engine).__name__ == "PlaceHolderLayoutEngine"):
        fig.tight_layout()
    return changed


def fit(fig) -> None:
    """:func:`fit_titles` and :func:`thin_ticks` until neither changes anything (a re-layout can narrow a panel
    again: at most 4 passes). Call it after the figure's own layout (tight or constrained)."""
    for _ in range(4):
        if not (fit_titles(fig) | thin_ticks(fig)):
            return
