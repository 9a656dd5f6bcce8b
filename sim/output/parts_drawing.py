"""The parts drawing (SVG, PDF or PNG, matplotlib): the plan view at the pose of t = 0 with every link's
outline, holes with centre marks, ground pivots, aligned dimensions of the centre distances, the pivots'
coordinates and the input's angle; an exploded axonometric view of the layers with the pins' axes; the parts
list and a title block. Lengths in the file's unit."""

from __future__ import annotations

import math

import numpy as np

from analytic.parts import model, shapes
from sim.output.io import atomic_path

FILL = ["#dbe7f3", "#f6e3c9", "#dcefd9", "#eadcf1", "#f3dada", "#e8e8d0"]
EDGE = "#1a1a1a"
DIM = "#1f4e9a"


def _fmt(v: float) -> str:
    return f"{v:.4g}"


def _world_poly(pm, ln, arcs, chord):
    return model.to_world(pm.sweep.frames[ln][0], shapes.tessellate(arcs, chord))


def _centre_mark(ax, x, y, r, lw=0.4):
    ax.plot([x - 1.6 * r, x + 1.6 * r], [y, y], color=EDGE, lw=lw, dashes=(6, 2, 1, 2), zorder=6)
    ax.plot([x, x], [y - 1.6 * r, y + 1.6 * r], color=EDGE, lw=lw, dashes=(6, 2, 1, 2), zorder=6)


def _dimension(ax, p, q, offset, text, fs, placed=None, spacing=0.0):
    """An aligned dimension of p-q, its line ``offset`` to the left of p->q (moved out in steps while its
    text would land within ``spacing`` of a text in ``placed``), extension lines, arrows."""
    p, q = np.asarray(p, float), np.asarray(q, float)
    if placed is not None and spacing > 0:
        d0 = q - p
        n0 = np.array([-d0[1], d0[0]]) / max(float(np.hypot(*d0)), 1e-300)
        base = offset
        for k in range(6):
            offset = base * (1 + 0.8 * k)
            mid = 0.5 * (p + q) + n0 * offset
            if all(float(np.hypot(*(mid - m))) > spacing for m in placed):
                break
        placed.append(0.5 * (p + q) + n0 * offset)
    d = q - p
    L = float(np.hypot(*d))
    if L == 0:
        return
    n = np.array([-d[1], d[0]]) / L
    a, b = p + n * offset, q + n * offset
    gap = 0.15 * abs(offset) * np.sign(offset)
    for s, e in ((p + n * gap, a + n * 0.25 * gap * 2), (q + n * gap, b + n * 0.25 * gap * 2)):
        ax.plot([s[0], e[0]], [s[1], e[1]], color=DIM, lw=0.5, zorder=7)
    ax.annotate("", xy=a, xytext=b, arrowprops=dict(arrowstyle="<|-|>", color=DIM, lw=0.6, shrinkA=0, shrinkB=0,
                                                    mutation_scale=7), zorder=7)
    ang = math.degrees(math.atan2(d[1], d[0]))
    if ang > 90 or ang <= -90:
        ang -= 180 if ang > 0 else -180
    m = 0.5 * (a + b)
    ax.text(m[0], m[1], text, color=DIM, fontsize=fs, rotation=ang, rotation_mode="anchor", ha="center",
            va="bottom", zorder=8, bbox=dict(boxstyle="square,pad=0.1", fc="white", ec="none", alpha=0.85))


def plan(ax, pm, fs: float = 7.0) -> None:
    """The plan view with dimensions (see the module docstring)."""
    mech = pm.mech
    chord = pm.chord
    cfg = model.settings(mech)
    unit = mech.units
    for ln in sorted(pm.parts, key=lambda x: pm.layout.layers[x]):
        part = pm.parts[ln]
        layer = pm.layout.layers[ln]
        poly = _world_poly(pm, ln, part.outline, chord)
        ax.fill(poly[:, 0], poly[:, 1], fc=FILL[layer % len(FILL)], ec=EDGE, lw=0.9, alpha=0.75, zorder=2 + layer * 0.01)
        for sl in part.slots:
            sp = _world_poly(pm, ln, sl.outline, chord)
            ax.fill(sp[:, 0], sp[:, 1], fc="white", ec=EDGE, lw=0.7, zorder=3)
        for h in part.holes:
            (x, y), = model.to_world(pm.sweep.frames[ln][0], [(h.x, h.y)])
            ax.add_patch(_circle(x, y, h.r))
    # gears: the pitch circle as a chain line, its diameter
    for ln, part in pm.parts.items():
        if part.gear_radius:
            centre = next(p for p, uv in part.points.items()
                          if any(abs(a.r - part.gear_radius) < 1e-9 * (1 + a.r) and math.hypot(a.x - uv[0], a.y - uv[1])
                                 < 1e-9 * (1 + a.r) for a in part.outline))
            (x, y), = model.to_world(pm.sweep.frames[ln][0], [part.points[centre]])
            t = np.linspace(0, 2 * np.pi, 361)
            r = part.gear_radius
            ax.plot(x + r * np.cos(t), y + r * np.sin(t), color=EDGE, lw=0.5, dashes=(10, 3, 2, 3), zorder=6)
            ax.annotate(f"pitch Ø{_fmt(2 * r)}", xy=(x + r * math.cos(-2.2), y + r * math.sin(-2.2)),
                        xytext=(x + 1.25 * r * math.cos(-2.2), y + 1.25 * r * math.sin(-2.2)), fontsize=fs,
                        color=DIM, ha="center", arrowprops=dict(arrowstyle="-|>", color=DIM, lw=0.5,
                                                                mutation_scale=7), zorder=8)
    # centre marks on every joint, labels
    size = mech.size / mech.scale
    pts = {p: pm.sweep.points[p][0] for p in mech.points}
    for p, (x, y) in pts.items():
        _centre_mark(ax, x, y, cfg.hole / 2)
        ax.text(x + 0.012 * size, y + 0.012 * size, p, fontsize=fs + 1, color=EDGE, zorder=9, weight="bold")
    # ground pivots: the hatched symbol and the coordinates
    for g in mech.ground_points:
        x, y = pts[g]
        w = 0.05 * size
        ax.plot([x - w, x + w], [y - 0.6 * w, y - 0.6 * w], color=EDGE, lw=1.0, zorder=4)
        for k in range(6):
            u = x - w + k * 2 * w / 5
            ax.plot([u, u - 0.3 * w], [y - 0.6 * w, y - 0.95 * w], color=EDGE, lw=0.6, zorder=4)
        ax.plot([x - 0.4 * w, x, x + 0.4 * w], [y - 0.6 * w, y, y - 0.6 * w], color=EDGE, lw=0.8, zorder=4)
        ax.annotate(f"{g} ({_fmt(x)}, {_fmt(y)})", xy=(x, y), xytext=(x - 0.05 * size, y - 0.16 * size),
                    fontsize=fs, color=DIM, ha="center", zorder=9,
                    arrowprops=dict(arrowstyle="-", color=DIM, lw=0.5))
    # centre distances of every link
    off = 0.0
    texts: list = []
    for ln, part in pm.parts.items():
        joints = [h.point for h in part.holes]
        rad = part.width / 2 + 0.05 * size
        if part.kind == "block":
            continue
        named = list(dict.fromkeys(joints + list(part.points)))
        pairs = [(named[i], named[j]) for i in range(len(named)) for j in range(i + 1, len(named))]
        if len(named) > 3:
            pairs = pairs[:3]
        c = np.mean([pts[p] for p in named], axis=0)
        for a, b in pairs:
            pa, pb = pts[a], pts[b]
            d = pb - pa
            n = np.array([-d[1], d[0]])
            side = 1.0 if np.dot(n, 0.5 * (pa + pb) - c) >= 0 else -1.0
            L = float(np.hypot(*d))
            _dimension(ax, pa, pb, side * (rad + off), f"{a}{b} = {_fmt(L)}", fs, texts, 0.07 * size)
    # the first input's angle at the pose
    first = mech.inputs[0]
    if first.angular:
        piv = pts[first.joint]
        tip = pts[first.point]
        ang = math.degrees(math.atan2(tip[1] - piv[1], tip[0] - piv[0]))
        r = 0.55 * float(np.hypot(*(tip - piv)))
        from matplotlib.patches import Arc as MArc
        lo, hi = (0.0, ang) if ang >= 0 else (ang, 0.0)
        ax.add_patch(MArc(piv, 2 * r, 2 * r, theta1=lo, theta2=hi, color=DIM, lw=0.6, zorder=7))
        ax.plot([piv[0], piv[0] + 1.2 * r], [piv[1], piv[1]], color=DIM, lw=0.4, dashes=(4, 2), zorder=7)
        ax.annotate(f"{first.q} = {ang:.1f}°", xy=(piv[0] + r * math.cos(math.radians(0.5 * (lo + hi))),
                                                   piv[1] + r * math.sin(math.radians(0.5 * (lo + hi)))),
                    xytext=(piv[0] + 0.05 * size, piv[1] - 0.24 * size), fontsize=fs, color=DIM, ha="left",
                    arrowprops=dict(arrowstyle="-", color=DIM, lw=0.4), zorder=8)
    if cfg.frame:
        f = np.asarray(cfg.frame + (cfg.frame[0],))
        ax.plot(f[:, 0], f[:, 1], color="#555555", lw=1.0, dashes=(8, 3), zorder=1)
    ax.set_aspect("equal")
    ax.margins(0.12)
    ax.set_xticks([])
    ax.set_yticks([])
    for s in ax.spines.values():
        s.set_visible(False)
    q0 = pm.sweep.q[0]
    at = f"{math.degrees(q0):.4g}°" if first.angular else f"{q0 / mech.scale:.4g} {unit}"
    ax.set_title(f"PLAN VIEW at {first.q} = {at}  (dimensions in {unit})", fontsize=fs + 2, loc="left")


def _circle(x, y, r):
    from matplotlib.patches import Circle
    return Circle((x, y), r, fc="white", ec=EDGE, lw=0.7, zorder=5)


def _iso(xy, z):
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    return np.column_stack([(xy[:, 0] - xy[:, 1]) * c, (xy[:, 0] + xy[:, 1]) * s + z])


def exploded(ax, pm, fs: float = 7.0) -> None:
    """The layers pulled apart along z in an isometric view; pins as chain lines through the layers they join."""
    mech = pm.mech
    size = mech.size / mech.scale
    chord = 20 * pm.chord
    flat = np.vstack([_world_poly(pm, ln, p.outline, chord) for ln, p in pm.parts.items()])
    iso = _iso(flat, 0.0)
    gap = 0.9 * float(iso[:, 1].max() - iso[:, 1].min())
    count = pm.layout.count
    pts = {p: pm.sweep.points[p][0] for p in mech.points}
    for k in range(count):
        members = [ln for ln in pm.parts if any(j == k for j, _ in pm.layout.plates(ln))]   # two-plate links twice
        z = k * gap
        for ln in members:
            part = pm.parts[ln]
            t = part.thickness
            top = _iso(_world_poly(pm, ln, part.outline, chord), z + t)
            bot = _iso(_world_poly(pm, ln, part.outline, chord), z)
            ax.fill(bot[:, 0], bot[:, 1], fc="#9aa5b1", ec=EDGE, lw=0.4, zorder=10 * k + 1)
            ax.fill(top[:, 0], top[:, 1], fc=FILL[k % len(FILL)], ec=EDGE, lw=0.7, zorder=10 * k + 2)
            for h in part.holes:
                hp = _iso(_world_poly(pm, ln, shapes.hull([shapes.Disc(h.x, h.y, h.r)]), chord), z + t)
                ax.fill(hp[:, 0], hp[:, 1], fc="white", ec=EDGE, lw=0.5, zorder=10 * k + 3)
            for sl in part.slots:
                sp = _iso(_world_poly(pm, ln, sl.outline, chord), z + t)
                ax.fill(sp[:, 0], sp[:, 1], fc="white", ec=EDGE, lw=0.5, zorder=10 * k + 3)
            c = _iso(np.asarray([np.mean([pts[p] for p in part.points], axis=0)]), z + t)[0]
            plates = pm.layout.plates(ln)
            label = ln if len(plates) == 1 else f"{ln} ({'lower' if plates[0][0] == k else 'upper'})"
            ax.text(c[0], c[1], label, fontsize=fs, ha="center", va="center", zorder=10 * k + 4, weight="bold")
        ax.text(float(iso[:, 0].min()) - 0.05 * size, float(iso[:, 1].mean()) + k * gap, f"layer {k}",
                fontsize=fs + 1, color=DIM, ha="right", va="center")
    # pins: their spans (a ground pivot's from the frame below or a top plate above), as chain lines
    plates = [pl for ln in pm.parts for pl in pm.layout.plates(ln)]     # (layer, (z0, z1)), a two-plate link's both
    zs = sorted({z for _, span in plates for z in span})
    zmax = zs[-1] if zs else 1.0

    used = sorted({k for k, _ in plates})              # a layer may be empty (a frame over the ground
                                                        # pivots lifts every link off layer 0)

    def zlevel(z):                                    # a z [file units] in the exploded view's spacing
        k = min(used, key=lambda i: abs(min(v[0] for j, v in plates if j == i) - z))
        base = min(v[0] for j, v in plates if j == k)
        return k * gap + (z - base)

    for p, (lo, hi) in pm.layout.pins.items():
        a = _iso(np.asarray([pts[p]]), zlevel(lo) - (0.1 * gap if lo == 0 else 0.0))[0]
        b = _iso(np.asarray([pts[p]]), zlevel(hi) + (0.1 * gap if hi >= zmax else 0.0))[0]
        ax.plot([a[0], b[0]], [a[1], b[1]], color="#b22222", lw=0.6, dashes=(8, 2, 1, 2), zorder=10 * count + 5)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    for s in ax.spines.values():
        s.set_visible(False)
    ax.set_title(f"EXPLODED VIEW: {count} layer{'s' if count != 1 else ''} (0 = against the frame), pins "
                 f"as chain lines", fontsize=fs + 2, loc="left")


def parts_list(ax, pm, fs: float = 7.0) -> None:
    from sim.output.parts_files import bom_rows
    rows = bom_rows(pm)
    unit = pm.mech.units
    head = ["link", "layer", "kind", f"length [{unit}]", f"width [{unit}]", f"thick. [{unit}]", "holes", "mass [g]",
            "analysis [g]"]
    body = [[r["link"], r["layer"] if r["plates"] == 1 else f"{r['layer']} + {r['upper_layer']}",
             r["kind"] if r["plates"] == 1 else f"2 x {r['kind']}", _fmt(r["length"]), _fmt(r["width"]), _fmt(r["thickness"]), r["holes"],
             f"{1000 * r['mass_kg']:.3g}", _analysis_mass(r)] for r in rows]
    ax.axis("off")
    table = ax.table(cellText=body, colLabels=head, loc="upper left", cellLoc="center", colLoc="center")
    table.auto_set_font_size(False)
    table.set_fontsize(fs)
    table.scale(1.0, 1.25)
    for (r, _), cell in table.get_celld().items():
        cell.set_linewidth(0.5)
        if r == 0:
            cell.set_facecolor("#e9eef5")
    ax.set_title("PARTS LIST", fontsize=fs + 2, loc="left")


def _analysis_mass(row) -> str:
    """The parts list's "analysis" cell: the mass the analysis gives the link and what gave it ("= part" where
    it is the part's own)."""
    m = f"{1000 * row['analysis_mass_kg']:.3g}"
    if row["analysis_mass_from"] == "parts":                # the part's plates, both of a two-plate link
        # the same part's moments summed apart (BOM and mass model): equal to rounding, 1e-9 relative
        same = abs(row["analysis_mass_kg"] - row["mass_kg"]) <= 1e-9 * max(row["mass_kg"], 1e-30)
        what = "part" if row["plates"] == 1 else f"{row['plates']} plates"
        return f"= {what}" if same else f"{m} ({what} + counterweights)"
    return f"{m} ({row['analysis_mass_from']})"


def mass_note(pm) -> str:
    """What the drawing says of the analysis's masses (forces, dynamics, MuJoCo) against these parts'."""
    from analytic import mass
    src = set(mass.sources(pm.mech).values())
    both = ", both plates of a two-plate link" if pm.layout.second else ""
    if src == {"parts"}:
        return f"4. The analysis (forces, dynamics, MuJoCo) uses these parts' masses (holes and slots cut{both})."
    if "parts" in src:
        return "4. The analysis uses these parts' masses, except where the column 'analysis' names [inertia]."
    return ("4. The analysis uses other masses (column 'analysis'); with a [parts] section in the file it uses "
            "these parts'.")


def two_plate_note(pm) -> str:
    """Note 5: the two-plate links, each drawn (and listed) as two plates, and the pin joining them."""
    L = pm.layout
    if not L.second:
        return ""
    return "5. Two plates of one outline, joined by a pin fixed in both (a clevis): " + ", ".join(
        f"{ln} (layers {L.layers[ln]} and {L.second[ln][0]}, pin {L.joined[ln]})" for ln in L.second) + "."


def title_block(ax, pm, fs: float = 7.0) -> None:
    mech = pm.mech
    cfg = model.settings(mech)
    ax.axis("off")
    ax.add_patch(__import__("matplotlib.patches", fromlist=["Rectangle"]).Rectangle(
        (0, 0), 1, 1, transform=ax.transAxes, fill=False, lw=1.2, ec=EDGE))
    lines = [(mech.name.upper().replace("_", " "), fs + 5, "bold"),
             (f"units: {mech.units}   pins Ø{_fmt(cfg.pin_diameter)}, holes Ø{_fmt(cfg.hole)} "
              f"(clearance {_fmt(cfg.clearance)})", fs, "normal"),
             (f"layer gap {_fmt(cfg.layer_gap)}   {pm.layout.count} layers   {len(pm.parts)} links, "
              f"{len(pm.parts) + len(pm.layout.second or {})} plates", fs, "normal"),
             ("linkage export --svg/--pdf: parts at the start pose", fs - 1, "normal")]
    y = 0.8
    for text, size, weight in lines:
        ax.text(0.04, y, text, fontsize=size, weight=weight, transform=ax.transAxes, va="center")
        y -= 0.22


def figure(pm):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig = plt.figure(figsize=(16.5, 11.7))
    gs = fig.add_gridspec(3, 2, width_ratios=[1.35, 1.0], height_ratios=[1.0, 0.62, 0.30], wspace=0.05, hspace=0.12,
                          left=0.03, right=0.98, top=0.95, bottom=0.03)
    plan(fig.add_subplot(gs[0:2, 0]), pm)
    exploded(fig.add_subplot(gs[0, 1]), pm)
    parts_list(fig.add_subplot(gs[1, 1]), pm)
    title_block(fig.add_subplot(gs[2, 1]), pm)
    ax = fig.add_subplot(gs[2, 0])
    ax.axis("off")
    notes = ["NOTES", "1. Outlines: rounded plates over each link's joints; holes = pin + clearance on every joint.",
             "2. Links on one layer never come closer than the clearance over the cycle (linkage check --interference).",
             "3. Ground pivots dimensioned from the file's origin; link dimensions are centre distances.",
             mass_note(pm)] + ([two_plate_note(pm)] if pm.layout.second else [])
    step = min(0.22, 0.9 / (len(notes) - 1))
    for k, t in enumerate(notes):
        ax.text(0.0, 0.9 - step * k, t, fontsize=8 if k else 9, weight="bold" if k == 0 else "normal",
                transform=ax.transAxes)
    fig.patch.set_facecolor("white")
    border = fig.add_axes([0.005, 0.005, 0.99, 0.99])
    border.axis("off")
    border.add_patch(__import__("matplotlib.patches", fromlist=["Rectangle"]).Rectangle(
        (0, 0), 1, 1, transform=border.transAxes, fill=False, lw=1.5, ec=EDGE))
    return fig


def write(pm, path) -> None:
    import matplotlib.pyplot as plt
    fig = figure(pm)
    suffix = str(path).rsplit(".", 1)[-1].lower()
    try:
        with atomic_path(path) as tmp:
            fig.savefig(tmp, format=suffix, dpi=110)
    finally:
        plt.close(fig)
