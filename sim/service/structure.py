"""A mechanism's structure as ``linkage check`` reports it: links, joints, gear pairs, loops, mobility, solve
order, Assur groups, the input's range, its dead points and singular poses, the outputs."""

from __future__ import annotations

import math

from analytic import kinds, laws
from analytic.applications import figures
from analytic.quantities import LENGTH, Display
from sim.service.simulation import passes_smoothly


def structure_report(mech, display=None) -> str:
    """``linkage check``'s report; lengths in ``display`` units (default the file's), a crank's angles in
    deg; an input's range rounded inward, so that it can be pasted into ``--input-range``."""
    display = display or Display(mech.units)
    d = mech.definition
    topo = mech.topology
    n, _, _ = topo.counts
    lines = [f"{mech.name}: {d.description}" if d.description else mech.name,
             f"  source: {d.source} (units: {d.units})",
             f"  links: {n} ({', '.join(('ground',) + mech.links)})"]
    joints = mech.joints
    lines.append(f"  joints: {len(joints)} ({', '.join(f'{x.name} {x.kind[0].upper()} {x.a}-{x.b}' for x in joints)})")
    gears = [c for c in topo.couplings if c.kind == "gear"]
    cams = [c for c in topo.couplings if c.kind == "cam"]
    if gears:
        lines.append(f"  gear pairs: {len(gears)} (" + ", ".join(f"{c.link}-{c.mesh} on {c.carrier}" for c in gears) + ")")
    if cams:
        lines.append(f"  cam contacts: {len(cams)} (" + ", ".join(f"{c.mesh}-{c.link}" for c in cams) + ")")
    _, start = mech.solve_at([0.0])
    if start.valid.all():                          # what the kinds say about their elements (pitch radii)
        pose = {p: (float(start["x" + p][0]), float(start["y" + p][0])) for p in mech.points}
        notes = (kinds.get(e["kind"]).describe(e, pose, (mech.scale, mech.units)) for e in mech.geometry.elements)
        lines += [f"  {note}" for note in notes if note]
    lines.append(f"  independent loops: {len(topo.loops)}")
    lines.append(f"  mobility (Gruebler): {topo.gruebler()}; inputs: "
                 + ", ".join(f"{i.q} ({i.kind} at {i.joint})" for i in mech.inputs))
    for i in mech.inputs:                         # a motion law: its segments and their jumps (SPEC "Motion laws")
        if i.motion.law is not None:
            law_lines = laws.describe(i.motion.law, i.angular, i.q, i.motion.q0,
                                      (display.factor(LENGTH) ** -1, display.unit(LENGTH)))
            lines += [f"  {i.q} {law_lines[0]}"] + [f"  {x}" for x in law_lines[1:]]
    lines.append("  solve order: " + " -> ".join(f"{'+'.join(e.places)} ({e.kind})" for e in d.order))
    groups = [(e, kinds.get(e.kind).group_label(r)) for e, r in zip(d.order, mech.geometry.elements)]
    lines.append("  Assur groups: " + (", ".join(f"{'+'.join(e.places)} (links {', '.join(e.links())}): {cls}"
                                                for e, cls in groups if cls)
                                      or "none"))
    if len(mech.inputs) == 1:
        ranges = figures.assembly_ranges(mech)
        first = mech.inputs[0]
        crank = first.angular

        def at(x):                                   # an input value as people read it
            if crank:
                return f"{(math.degrees(x) + 180) % 360 - 180:.4f}deg"
            return f"{display.convert(LENGTH, x):.6g} {display.unit(LENGTH)}"

        if figures.turns_fully(mech, ranges):
            lines.append(f"  {first.q} assembles over a full turn")
        elif ranges:
            element = next(e for e in mech.geometry.elements if e.get("input") == 0
                           and kinds.get(e["kind"]).section == "inputs")
            stops = kinds.get(element["kind"]).stops(element)
            ends = list(dict.fromkeys(a for r in ranges for a in r))
            near = 1e-4 * (stops[1] - stops[0]) if stops else 0.0      # the scan's ends, found to ~1e-6 of them
            stopped = [a for a in ends if stops and min(abs(a - stops[0]), abs(a - stops[1])) <= near]
            dead = [a for a in ends if a not in stopped]
            words = ([f"dead points at {', '.join(at(a) for a in dead)}"] if dead else []) + (
                [f"stroke ends at {', '.join(at(a) for a in stopped)}"] if stopped else [])
            lines.append(f"  {first.q} assembles in {figures.describe_ranges(first, ranges, display)} (ends rounded "
                         f"inward); " + "; ".join(words))
        else:
            lines.append(f"  {first.q} assembles nowhere: change the lengths")
        for x, label, _ in figures.singular_poses(mech):
            where = f"{math.degrees(x) % 360:.2f}deg" if crank else at(x)
            how = ("passed on its declared branch, its form kept (change = 1)" if passes_smoothly(mech, label, x)
                   else "the motion is undefined there")
            lines.append(f"  singular pose at {first.q}={where}: {label} folds (change point; {how})")
    lines.append(f"  outputs: {len(mech.outputs)} ({' '.join(mech.outputs[:12])}{' ...' if len(mech.outputs) > 12 else ''})")
    return "\n".join(lines)
