"""Figures of merit of one analysed run, as a JSON-ready dict (SPEC names, SI units, angles in rad)."""

from __future__ import annotations

import math

import numpy as np

from analytic import fourbar, sixbar
from .params import mechanism_name


def _span(x) -> list[float]:
    x = np.asarray(x)
    return [float(np.nanmin(x)), float(np.nanmax(x))]


def figures(mech, state) -> dict:
    """Classification and figures of merit of ``mech``; ranges are taken over the sampled ``state``."""
    name = mechanism_name(mech)
    if name == "fourbar":
        g = fourbar.grashof(mech)
        lim = fourbar.crank_limits(mech)
        speed = np.hypot(state.vxE, state.vyE)
        return {
            "grashof": g.chain, "inversion": g.inversion,
            "crank_turns_fully": lim.full_turn,
            "limit_angles": list(lim.limit_angles),
            "reachable_phi1": [list(iv) for iv in lim.intervals],
            "mu_min": float(np.nanmin(state.mu)), "mu_max": float(np.nanmax(state.mu)),
            "mu_extremes": list(fourbar.transmission_extremes(mech)),
            "xE_range": _span(state.xE), "yE_range": _span(state.yE),
            "vE_max": float(np.nanmax(speed)),
            "phi3_swing": float(np.ptp(np.unwrap(state.phi3))),
        }
    if name == "sixbar":
        f = sixbar.figures(mech)
        return {
            "h": mech.h, "stroke": f.stroke, "swing": f.swing, "theta": f.swing, "K": f.K,
            "phi1_limits": list(f.phi1_limits), "xC_limits": list(f.xC_limits),
            "s_range": _span(state.s), "vxC_range": _span(state.vxC), "axC_range": _span(state.axC),
        }
    speed = np.hypot(state.vxP, state.vyP)
    return {
        "speed_ratio": mech.omega2 / mech.omega4 if mech.omega4 != 0 else math.inf,
        "S_range": _span(state.S), "S_min_possible": mech.l1 - mech.l2 - mech.l4,
        "xP_range": _span(state.xP), "yP_range": _span(state.yP),
        "vP_min": float(speed.min()), "vP_max": float(speed.max()), "vP_mean": float(speed.mean()),
    }
