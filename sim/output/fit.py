"""Titles that fit their figure: a title wider than its room (a long mechanism name in a suptitle, a long
figure in a panel's title) is wrapped onto more lines before the figure is saved, so that nothing is cut
at the image's edge."""

from __future__ import annotations

import textwrap


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
    text_artist.set_text("\n".join(textwrap.fill(line, chars) for line in text.splitlines()))
    return True


def fit_titles(fig) -> None:
    """Wrap the figure's suptitle to 96 % of its width and each panel's title to its column's width (the
    panel's own width plus its share of the gaps), then lay the figure out again if anything moved."""
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
            changed |= _wrap(t, room, renderer)
    engine = fig.get_layout_engine()
    if changed and (engine is None or type(engine).__name__ == "PlaceHolderLayoutEngine"):
        fig.tight_layout()                        # laid out once by tight_layout: again, for the new lines
                                                  # (a constrained layout redoes itself when saved)
