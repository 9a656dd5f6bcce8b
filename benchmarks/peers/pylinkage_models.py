"""pylinkage's public example linkages, built with pylinkage 1.3's component API (dimensions as its examples
give them; the old joints API's examples rebuilt with the same components). Each builder returns the
linkage, our point names -> its components, and the crank (anchor, tip) our input angle is measured on.

Sources (HugoFara/pylinkage): docs/examples/{fourbar_linkage,inverted_stroke_engine,strider}.py,
api/routers/examples.py, app/examples/prebuilt.py (removed 2025-12-16). Our files for them, written by hand,
are benchmarks/peers/pylinkage/<name>.toml; ``api_pantograph`` is locked and has no pylinkage model here.
"""

from __future__ import annotations

import math


def _model(pl, comps, points, crank, name):
    return pl.Linkage(comps, name=name), points, crank


def docs_fourbar(pl):
    A, D = pl.Ground(0.0, 0.0, name="A"), pl.Ground(3.0, 0.0, name="D")
    B = pl.Crank(A, 1.0, angular_velocity=0.31, initial_angle=0.0, name="B")
    C = pl.RRRDyad(B.output, D, 3.0, 1.0, name="C")
    return _model(pl, [A, D, B, C], {"A": A, "D": D, "B": B, "C": C}, ("A", "B"), "My four-bar linkage")


def docs_stroke_engine(pl):
    O, L1, L2 = pl.Ground(0, 0, name="Crank anchor"), pl.Ground(0, 0, name="Line A"), pl.Ground(1, 0, name="Line B")
    B = pl.Crank(O, 1.0, angular_velocity=0.1, name="Crank")
    C = pl.RRPDyad(B.output, L1, L2, 1.5, name="Slider")
    return _model(pl, [O, L1, L2, B, C], {"O": O, "B": B, "C": C}, ("O", "B"), "Simple four-stroke engine")


def docs_strider(pl):
    triangle, aperture, femur, rocker_l, rocker_s, phi, tibia, f = 2, math.pi / 4, 1.8, 2.6, 1.4, math.pi + .2, 2.5, 1.8
    A, Y = pl.Ground(0, 0, name="A"), pl.Ground(0, 1, name="Y")
    B = pl.FixedDyad(A, Y, triangle, -aperture, name="B")
    Bp = pl.FixedDyad(A, Y, triangle, aperture, name="B_p")
    C = pl.Crank(A, 1, angular_velocity=-2 * math.pi / 10, name="C")
    D = pl.RRRDyad(Bp, C.output, femur, rocker_l, x=-2.25, y=0, name="D")
    E = pl.RRRDyad(B, C.output, femur, rocker_l, x=2.25, y=0, name="E")
    F = pl.FixedDyad(C.output, E, rocker_s, -phi, name="F")
    G = pl.FixedDyad(C.output, D, rocker_s, phi, name="G")
    H = pl.RRRDyad(D, F, tibia, f, x=-2.7, y=-2.7, name="H")
    I_ = pl.RRRDyad(E, G, tibia, f, x=2.7, y=-2.7, name="I")
    comps = [A, Y, B, Bp, C, D, E, F, G, H, I_]
    return _model(pl, comps, {"A": A, "B": B, "B_p": Bp, "C": C, "D": D, "E": E, "F": F, "G": G, "H": H, "I": I_},
                  ("A", "C"), "Strider")


def api_fourbar(pl):
    O1, O2 = pl.Ground(0, 0, name="O1"), pl.Ground(100, 0, name="O2")
    B = pl.Crank(O1, 25, angular_velocity=0.1, initial_angle=math.pi / 4, name="B")
    C = pl.RRRDyad(B.output, O2, 70, 60, name="C")
    return _model(pl, [O1, O2, B, C], {"O1": O1, "O2": O2, "B": B, "C": C}, ("O1", "B"), "four-bar")


def api_chebyshev(pl):
    O1, O2 = pl.Ground(0, 0, name="O1"), pl.Ground(100, 0, name="O2")
    lo, hi = math.acos(0.8), math.acos(-0.2)
    B = pl.ArcCrank(O1, 125, angular_velocity=0.05, arc_start=lo, arc_end=hi, initial_angle=(lo + hi) / 2, name="B")
    C = pl.RRRDyad(B.output, O2, 50, 125, name="C")
    M = pl.FixedDyad(B.output, C, 25, 0.0, name="M")
    return _model(pl, [O1, O2, B, C, M], {"O1": O1, "O2": O2, "B": B, "C": C, "M": M}, ("O1", "B"), "chebyshev")


def api_crank_slider(pl):
    O, R1, R2 = pl.Ground(0, 0, name="O"), pl.Ground(0, 0, name="rail0"), pl.Ground(1, 0, name="rail1")
    B = pl.Crank(O, 50, angular_velocity=0.1, initial_angle=math.atan2(40, 30), name="B")
    C = pl.RRPDyad(B.output, R1, R2, 100, name="C")
    return _model(pl, [O, R1, R2, B, C], {"O": O, "B": B, "C": C}, ("O", "B"), "crank-slider")


def prebuilt_fourbar(pl):
    A, D = pl.Ground(0, 0, name="A"), pl.Ground(3, 0, name="D")
    B = pl.Crank(A, 1, angular_velocity=2 * math.pi / 20, initial_angle=math.pi / 2, name="B")
    C = pl.RRRDyad(B.output, D, 3, 2, x=3, y=2, name="C")
    return _model(pl, [A, D, B, C], {"A": A, "D": D, "B": B, "C": C}, ("A", "B"), "Four-Bar Linkage")


def prebuilt_chebyshev(pl):
    A, B0 = pl.Ground(-2, 0, name="A"), pl.Ground(2, 0, name="B")
    C = pl.Crank(A, 1, angular_velocity=2 * math.pi / 20, initial_angle=math.atan2(0.86, 0.5), name="C")
    D = pl.RRRDyad(C.output, B0, 4, 2, x=1.5, y=1.73, name="D")
    P = pl.FixedDyad(C.output, D, 2, 0.0, name="P")
    return _model(pl, [A, B0, C, D, P], {"A": A, "B": B0, "C": C, "D": D, "P": P}, ("A", "C"), "Chebyshev Linkage")


def prebuilt_crank_slider(pl):
    A, R1, R2 = pl.Ground(0, 0, name="A"), pl.Ground(-3, 0, name="Rail_Start"), pl.Ground(5, 0, name="Rail_End")
    B = pl.Crank(A, 1, angular_velocity=2 * math.pi / 20, initial_angle=0.0, name="B")
    C = pl.RRPDyad(B.output, R1, R2, 2, x=2, y=0, name="C")
    return _model(pl, [A, R1, R2, B, C], {"A": A, "B": B, "C": C}, ("A", "B"), "Crank-Slider")


def prebuilt_watt(pl):
    A, D = pl.Ground(0, 0, name="A"), pl.Ground(4, 0, name="D")
    B = pl.Crank(A, 2, angular_velocity=2 * math.pi / 20, initial_angle=math.pi / 2, name="B")
    C = pl.RRRDyad(B.output, D, 4, 2, x=4, y=2, name="C")
    E = pl.FixedDyad(B.output, C, 2, 0.0, name="E")
    return _model(pl, [A, D, B, C, E], {"A": A, "D": D, "B": B, "C": C, "E": E}, ("A", "B"), "Watt Linkage")


def prebuilt_pantograph(pl):
    O = pl.Ground(0, 0, name="O")
    A = pl.Crank(O, math.sqrt(2), angular_velocity=2 * math.pi / 20, initial_angle=math.pi / 4, name="A")
    B = pl.RRRDyad(A.output, O, math.sqrt(2), 2 * math.sqrt(2), x=2, y=2, name="B")
    C = pl.FixedDyad(O, B, 2 * math.sqrt(2), 0.0, name="C")
    return _model(pl, [O, A, B, C], {"O": O, "A": A, "B": B, "C": C}, ("O", "A"), "Pantograph")


MODELS = {f.__name__: f for f in (docs_fourbar, docs_stroke_engine, docs_strider, api_fourbar, api_chebyshev,
                                  api_crank_slider, prebuilt_fourbar, prebuilt_chebyshev, prebuilt_crank_slider,
                                  prebuilt_watt, prebuilt_pantograph)}
LOCKED = {"api_pantograph": "crank 50 at O and an arm of 50 from the crank's tip back to O: two links pinned at "
                            "both ends"}
