"""The plot's legend names are set literally: an output or input name's underscores (``phiboom_barrel``,
``s_boom``) are glyphs of the name, not subscripts that swallow the next letter (``s_boom`` drawn as s with a
subscript b, then "oom")."""

from __future__ import annotations

import pytest
from matplotlib.mathtext import MathTextParser

from sim.output.plot import math_name


@pytest.mark.parametrize("name", ["s_J2_x", "phiboom_barrel", "s_boom", "xB"])
def test_every_character_of_a_name_is_drawn(name):
    parsed = MathTextParser("path").parse(math_name(name))
    # one glyph per character, each the character itself (its code point: matplotlib's glyph tuple, 3rd field)
    assert [g[2] for g in parsed.glyphs] == [ord(c) for c in name]
