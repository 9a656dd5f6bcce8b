"""Command-line parameters: ``--set NAME=VALUE`` parsing and the sampling of one run's input motion."""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass

import numpy as np

from analytic import MECHANISMS, FiveBar, FourBar, ParameterError, SixBar, fourbar

CLASSES = {"fourbar": FourBar, "sixbar": SixBar, "fivebar": FiveBar}
FIRST_CRANK = {"fourbar": "1", "sixbar": "1", "fivebar": "2"}
"""The crank whose revolutions count the run (SPEC: the first crank)."""
OUTPUT_POINT = {"fourbar": ("xE", "yE"), "sixbar": ("xC", None), "fivebar": ("xP", "yP")}
"""The output point's coordinate outputs: coupler point E, ram C (which moves on y = h), five-bar P."""

_NUMBER = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(deg)?\s*$")


def parse_value(name: str, text: str) -> float:
    """A number, optionally written in degrees with a ``deg`` suffix (converted to radians)."""
    m = _NUMBER.match(text)
    if not m:
        raise ParameterError(f"{name}={text!r} is not a number (write e.g. {name}=0.25 or {name}=30deg)")
    value = float(m.group(1))
    return math.radians(value) if m.group(2) else value


def build(mechanism: str, sets: list[str] | None) -> object:
    """The mechanism's parameter dataclass with SPEC defaults overridden by ``NAME=VALUE`` strings."""
    cls = CLASSES[mechanism]
    names = [f.name for f in dataclasses.fields(cls)]
    values: dict[str, float] = {}
    for item in sets or []:
        if "=" not in item:
            raise ParameterError(f"--set {item!r} is not NAME=VALUE (e.g. --set l1=0.12)")
        name, text = (x.strip() for x in item.split("=", 1))
        if name not in names:
            raise ParameterError(f"--set {name}: not a {mechanism} parameter; valid names: {', '.join(names)}")
        value = parse_value(name, text)
        if name == "branch":
            if value not in (1.0, -1.0):
                raise ParameterError(f"branch={text} is not a valid branch: use +1 or -1")
            value = int(value)
        values[name] = value
    return cls(**values)


def first_crank(mech) -> tuple[float, float, float]:
    """``(phi_0, omega, alpha)`` of the crank whose revolutions count the run."""
    n = FIRST_CRANK[mechanism_name(mech)]
    return getattr(mech, f"phi{n}_0"), getattr(mech, f"omega{n}"), getattr(mech, f"alpha{n}")


def mechanism_name(mech) -> str:
    for name, cls in CLASSES.items():
        if isinstance(mech, cls):
            return name
    raise TypeError(f"not a mechanism: {mech!r}")


def duration(mech, revolutions: float) -> float:
    """Time [s] for the first crank to turn ``revolutions`` times: omega t + alpha t^2 / 2 = 2 pi R."""
    if not (math.isfinite(revolutions) and revolutions > 0):
        raise ParameterError(f"--revolutions {revolutions!r} must be a number > 0")
    _, omega, alpha = first_crank(mech)
    n = FIRST_CRANK[mechanism_name(mech)]
    if omega == 0.0 and alpha == 0.0:
        raise ParameterError(f"omega{n}=0: the crank does not turn; set a non-zero omega{n}")
    angle = 2.0 * math.pi * revolutions
    if alpha == 0.0:
        return angle / abs(omega)
    sign = math.copysign(1.0, omega if omega != 0.0 else alpha)
    # (alpha/2) t^2 + omega t - sign * angle = 0, smallest positive root.
    a, b, c = 0.5 * alpha, omega, -sign * angle
    disc = b * b - 4.0 * a * c
    roots = [] if disc < 0 else [(-b + r) / (2 * a) for r in (math.sqrt(disc), -math.sqrt(disc))]
    roots = [t for t in roots if t > 0]
    if not roots:
        raise ParameterError(f"alpha{n}={alpha:g} stops the crank before it turns {revolutions:g} times; "
                             f"reduce |alpha{n}| or the revolutions")
    return min(roots)


@dataclass(frozen=True)
class Inputs:
    """Sampled input motion: time [s] and each crank's angle [rad], speed [rad/s], acceleration."""

    t: np.ndarray
    columns: dict[str, np.ndarray]


def sample_inputs(mech, samples: int, revolutions: float = 1.0,
                  input_range: tuple[float, float] | None = None) -> Inputs:
    """The input motion of one run: ``samples`` instants evenly spaced in time over ``revolutions`` of the
    first crank, or (four-bar only) crank angles evenly spaced over ``input_range`` [rad]."""
    name = mechanism_name(mech)
    if not (isinstance(samples, int) and samples >= 2):
        raise ParameterError(f"--samples {samples!r} must be an integer >= 2")
    if input_range is not None:
        lo, hi = input_range
        if name != "fourbar":
            raise ParameterError("--input-range applies to the four-bar only (its crank may not turn fully)")
        if not hi > lo:
            raise ParameterError(f"--input-range {lo}:{hi} must have its end above its start")
        phi1 = np.linspace(lo, hi, samples)
        fourbar.check_reachable(mech, phi1)
        omega = mech.omega1 if mech.omega1 != 0 else 1.0
        t = (phi1 - lo) / abs(omega)
        return Inputs(t, {"phi1": phi1, "omega1": np.full_like(phi1, mech.omega1),
                          "alpha1": np.zeros_like(phi1)})
    t = np.linspace(0.0, duration(mech, revolutions), samples)
    module = MECHANISMS[name]
    if name == "fivebar":
        cols = dict(zip(("phi2", "phi4", "omega2", "omega4", "alpha2", "alpha4"), module.drive(mech, t)))
    else:
        cols = dict(zip(("phi1", "omega1", "alpha1"), module.drive(mech, t)))
    if name == "fourbar":
        limits = fourbar.crank_limits(mech)
        if not limits.full_turn:
            ends = ", ".join(f"{math.degrees(a):.2f}deg" for a in limits.limit_angles)
            raise ParameterError(
                f"the crank l1={mech.l1:g} cannot turn fully (limit angles {ends}; reachable "
                f"{fourbar.describe_range(limits)}): analyse between the limits with --input-range LO:HI")
    return Inputs(t, cols)


def solve(mech, inputs: Inputs):
    """The analytic state at the sampled inputs."""
    name = mechanism_name(mech)
    c = inputs.columns
    if name == "fivebar":
        return MECHANISMS[name].solve(mech, c["phi2"], c["phi4"], c["omega2"], c["omega4"],
                                      c["alpha2"], c["alpha4"])
    return MECHANISMS[name].solve(mech, c["phi1"], c["omega1"], c["alpha1"])
