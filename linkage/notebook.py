"""How a mechanism and a result show themselves in Jupyter (``_repr_html_``): an SVG drawing (the links at
the start and the output point's path; the motion animated where there is a run) and a summary table. Plain
SVG and HTML built here, no plotting library: a notebook cell shows it at once."""

from __future__ import annotations

import html
import math

import numpy as np

FRAMES = 72
"""Most poses in an animation (the run's samples thinned evenly): smooth enough, a small page."""
WIDTH, HEIGHT, MARGIN = 420, 300, 24
"""The drawing's size and margin [px]."""
COLOURS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22")


def _links(mech) -> list[dict]:
    from sim.service.mechanisms import link_drawing
    return link_drawing(mech)


def _frames(mech, solution, n: int) -> tuple[dict, int]:
    """Every point's (x, y) arrays [m] at up to ``n`` evenly thinned samples of ``solution``; their count."""
    size = len(np.atleast_1d(np.asarray(solution[f"x{mech.points[0]}"])))
    idx = np.unique(np.linspace(0, size - 1, min(n, size)).round().astype(int))
    pts = {}
    for p in mech.points:
        x = np.atleast_1d(np.asarray(solution[f"x{p}"], dtype=float))
        y = np.atleast_1d(np.asarray(solution[f"y{p}"], dtype=float))
        pts[p] = (x[idx] if x.size == size else np.full(idx.size, x[0]),
                  y[idx] if y.size == size else np.full(idx.size, y[0]))
    return pts, int(idx.size)


class _View:
    """World [m] to pixels: the points' box over every frame fitted into the drawing, y up."""

    def __init__(self, pts: dict):
        xs = np.concatenate([v[0] for v in pts.values()])
        ys = np.concatenate([v[1] for v in pts.values()])
        ok = np.isfinite(xs) & np.isfinite(ys)
        xs, ys = (xs[ok], ys[ok]) if ok.any() else (np.zeros(1), np.zeros(1))
        self.x0, self.y1 = float(xs.min()), float(ys.max())
        span = max(float(xs.max() - xs.min()), float(ys.max() - ys.min()), 1e-9)
        self.k = min((WIDTH - 2 * MARGIN) / max(float(xs.max() - xs.min()), span * 1e-3),
                     (HEIGHT - 2 * MARGIN) / max(float(ys.max() - ys.min()), span * 1e-3))
        self.dx = (WIDTH - 2 * MARGIN - self.k * float(xs.max() - xs.min())) / 2
        self.dy = (HEIGHT - 2 * MARGIN - self.k * float(ys.max() - ys.min())) / 2

    def __call__(self, x: float, y: float) -> tuple[float, float]:
        return MARGIN + self.dx + (x - self.x0) * self.k, MARGIN + self.dy + (self.y1 - y) * self.k


def _fmt(v: float) -> str:
    return f"{v:.1f}" if math.isfinite(v) else "0"


def drawing_svg(mech, solution, title: str = "", animate: bool = True, seconds: float = 3.0) -> str:
    """An SVG of ``mech`` over ``solution`` (closed forms or MuJoCo's outputs, point columns ``xP``/``yP``):
    the output point's path, the links at the first sample, the ground pivots; with ``animate`` and more than
    one sample, the links move through the samples in ``seconds`` (SVG's own animation, looping)."""
    pts, n = _frames(mech, solution, FRAMES)
    view = _View(pts)
    moving = animate and n > 1
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{HEIGHT}" '
           f'viewBox="0 0 {WIDTH} {HEIGHT}" style="background:#fff;border:1px solid #ddd">']
    if title:
        out.append(f'<text x="6" y="14" font-size="11" fill="#555">{html.escape(title)}</text>')
    op = mech.output_point
    if op in pts and n > 1:
        path = " ".join(f"{_fmt(a)},{_fmt(b)}" for a, b in (view(x, y) for x, y in zip(*pts[op])))
        out.append(f'<polyline points="{path}" fill="none" stroke="#999" stroke-dasharray="3,2"/>')
    for k, link in enumerate(_links(mech)):
        names = [p for p in link["points"] if p in pts]
        if not names:
            continue
        colour = COLOURS[k % len(COLOURS)]
        frames = [" ".join(f"{_fmt(a)},{_fmt(b)}" for a, b in (view(pts[p][0][i], pts[p][1][i]) for p in names))
                  for i in range(n)]
        if link["block"]:
            x, y = view(pts[names[0]][0][0], pts[names[0]][1][0])
            out.append(f'<rect x="{_fmt(x - 7)}" y="{_fmt(y - 5)}" width="14" height="10" fill="{colour}" '
                       f'fill-opacity="0.5" stroke="{colour}">')
            if moving:
                xs = ";".join(_fmt(view(a, b)[0] - 7) for a, b in zip(*pts[names[0]]))
                ys = ";".join(_fmt(view(a, b)[1] - 5) for a, b in zip(*pts[names[0]]))
                out.append(f'<animate attributeName="x" values="{xs}" dur="{seconds:g}s" repeatCount="indefinite"/>'
                           f'<animate attributeName="y" values="{ys}" dur="{seconds:g}s" repeatCount="indefinite"/>')
            out.append("</rect>")
            continue
        closed = len(names) > 2
        tag = "polygon" if closed else "polyline"
        out.append(f'<{tag} points="{frames[0]}" fill="{colour if closed else "none"}" fill-opacity="0.15" '
                   f'stroke="{colour}" stroke-width="3" stroke-linejoin="round">')
        if moving:
            out.append(f'<animate attributeName="points" values="{";".join(frames)}" dur="{seconds:g}s" '
                       f'repeatCount="indefinite"/>')
        out.append(f"</{tag}>")
    for p in mech.ground_points:
        if p in pts:
            x, y = view(pts[p][0][0], pts[p][1][0])
            out.append(f'<path d="M{_fmt(x)},{_fmt(y)} l-7,12 h14 z" fill="#666"/>')
    for p, (xs, ys) in pts.items():
        x, y = view(xs[0], ys[0])
        out.append(f'<circle cx="{_fmt(x)}" cy="{_fmt(y)}" r="3" fill="#fff" stroke="#000">')
        if moving and p not in mech.ground_points:
            cx = ";".join(_fmt(view(a, b)[0]) for a, b in zip(xs, ys))
            cy = ";".join(_fmt(view(a, b)[1]) for a, b in zip(xs, ys))
            out.append(f'<animate attributeName="cx" values="{cx}" dur="{seconds:g}s" repeatCount="indefinite"/>'
                       f'<animate attributeName="cy" values="{cy}" dur="{seconds:g}s" repeatCount="indefinite"/>')
        out.append("</circle>")
        out.append(f'<text x="{_fmt(x + 5)}" y="{_fmt(y - 5)}" font-size="10" fill="#333">{html.escape(p)}</text>')
    out.append("</svg>")
    return "".join(out)


def table_html(rows: list[tuple], head: tuple = ()) -> str:
    """An HTML table of ``rows`` (each cell escaped), with a header row ``head`` when given."""
    def cell(v, tag="td"):
        return f"<{tag} style='text-align:left;padding:1px 8px'>{html.escape(_text(v))}</{tag}>"
    lines = ["<table style='border-collapse:collapse;font-size:12px'>"]
    if head:
        lines.append("<tr>" + "".join(cell(h, "th") for h in head) + "</tr>")
    lines += ["<tr>" + "".join(cell(v) for v in r) + "</tr>" for r in rows]
    lines.append("</table>")
    return "".join(lines)


def _text(v) -> str:
    if isinstance(v, float):
        return f"{v:.6g}"
    if isinstance(v, (list, tuple)) and len(v) <= 4 and all(isinstance(x, (int, float)) for x in v):
        return ", ".join(_text(float(x)) for x in v)
    return str(v)


def _side_by_side(svg: str, table: str, title: str) -> str:
    return (f"<div><b>{html.escape(title)}</b><div style='display:flex;gap:16px;align-items:flex-start'>"
            f"<div>{svg}</div><div>{table}</div></div></div>")


def _run_solution(mech):
    """One cycle of ``mech`` (61 samples of one turn, or its rocking range), or the start pose alone where it
    cannot turn fully."""
    from analytic import ParameterError
    from sim.service.analysis import analyze
    try:
        return analyze(mech, 61, 1.0, mech.rock or _file_range(mech), figures=False).solution
    except ParameterError:
        q, qd, qdd = mech.drive(np.zeros(1))
        return mech.solve(q, qd, qdd)


def _file_range(mech):
    from linkage._inputs import input_range_of
    return input_range_of(mech, None)


def mechanism_html(mech) -> str:
    """The mechanism's drawing over one cycle and its parameters (name, value, unit)."""
    from sim.service.mechanisms import parameter_table
    rows = [(p["name"], p["value"], p["unit"] or p["kind"]) for p in parameter_table(mech)]
    rows += [("inputs", ", ".join(i.q for i in mech.inputs), ""), ("output point", mech.output_point, "")]
    return _side_by_side(drawing_svg(mech, _run_solution(mech), mech.name), table_html(rows, ("parameter", "value",
                                                                                             "unit")),
                         f"{mech.name}: {mech.description}")


def _scalars(record: dict) -> list[tuple]:
    """The record's top-level numbers, texts and flags (and short pairs), as (name, value)."""
    out = []
    for k, v in record.items():
        if isinstance(v, (bool, int, float, str)) or v is None:
            if not (isinstance(v, str) and len(v) > 80):
                out.append((k, v))
        elif isinstance(v, list) and len(v) <= 4 and all(isinstance(x, (int, float)) for x in v):
            out.append((k, v))
    return out


def result_html(result) -> str:
    """A result's view: the motion (animated where it has a run: an analysis, a simulation, a comparison) and
    a table of its figures (its ``to_dict()``'s top-level values and what the result adds, ``_view()``)."""
    name = type(result).__name__
    mech = getattr(result, "mechanism", None)
    solution, extra = result._view()
    rows = extra if solution is False else _scalars(result.to_dict()) + extra
    table = table_html(rows, (name.lower(), ""))
    if mech is None or solution is False:
        return f"<div><b>{html.escape(name)}</b>{table}</div>"
    svg = drawing_svg(mech, solution if solution is not None else _run_solution(mech), f"{mech.name} ({name.lower()})")
    return _side_by_side(svg, table, f"{name} of the {mech.name}")


def figure_rows(figures: dict) -> list[tuple]:
    """The figures of merit of an analysis's record as (name, value) rows (the short ones)."""
    out = []
    for k, v in figures.items():
        if isinstance(v, (int, float)) or (isinstance(v, list) and len(v) <= 4):
            out.append((k, v))
        elif isinstance(v, dict):
            out += [(f"{k} {j}", x) for j, x in v.items() if isinstance(x, (int, float, list))][:4]
    return out
