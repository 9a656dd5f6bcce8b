"""What each result is: one typed table of the outputs and figures of merit (name, quantity, SI unit,
owner), and the display units that convert them by quantity (SPEC "Units of results").

Everything the solver and the simulation compute is SI (m, s, rad, N, N m). What people read is converted
here, once, by quantity: lengths to the file's unit (or ``--units``), angles to deg on request
(``--angles deg``), angular speeds to rpm on request (``--speeds rpm``). Forces follow the file's
``force_units`` (SPEC "Loads"): N by default, torques then N m; a kN or lbf file shows forces in its unit
and moments in that unit times the length unit (kN mm, lbf in).
Pure Python, no dependencies: front ends and summaries call it alike.
"""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass

# ------------------------------------------------------------------------------------------ quantities
LENGTH, VELOCITY, ACCELERATION = "length", "velocity", "acceleration"
ANGLE, ANGULAR_VELOCITY, ANGULAR_ACCELERATION = "angle", "angular_velocity", "angular_acceleration"
FORCE, TORQUE, TIME, RATIO = "force", "torque", "time", "ratio"
JERK, ANGULAR_JERK = "jerk", "angular_jerk"

SI_UNIT = {LENGTH: "m", VELOCITY: "m/s", ACCELERATION: "m/s^2", ANGLE: "rad", ANGULAR_VELOCITY: "rad/s",
           ANGULAR_ACCELERATION: "rad/s^2", FORCE: "N", TORQUE: "N m", TIME: "s", RATIO: "", JERK: "m/s^3",
           ANGULAR_JERK: "rad/s^3"}
"""The SI unit of each quantity (what the solver, the simulation, CSV and JSON use by default)."""

LENGTH_UNITS = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "in": 0.0254}
"""Metres per length unit (exact: the inch is 25.4 mm by definition)."""

FORCE_UNITS = {"N": 1.0, "kN": 1000.0, "lbf": 4.4482216152605}
"""Newtons per force unit (lbf: the international avoirdupois pound-force, 0.45359237 kg x 9.80665 m/s^2, exact)."""

PRESSURE_UNITS = {"Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "bar": 1e5, "psi": FORCE_UNITS["lbf"] / LENGTH_UNITS["in"] ** 2}
"""Pascals per pressure unit (bar: 1e5 Pa exactly; psi: lbf per square inch, ~6894.757 Pa)."""


def lengths_in(units: str):
    """Lengths [m] as a file writes them, for its messages: ``f(x)`` gives "950 mm", ``f(lo, hi)`` "[950, 2700]
    mm" (``units``: the file's, one of :data:`LENGTH_UNITS`; ``digits``: significant digits, default as :g)."""
    per = LENGTH_UNITS[units]

    def say(*xs: float, digits: int | None = None) -> str:
        text = [f"{x / per:.{digits}g}" if digits else f"{x / per:g}" for x in xs]
        return f"{text[0]} {units}" if len(text) == 1 else f"[{', '.join(text)}] {units}"
    return say


def parse_pressure(text: str, what: str = "--pressure") -> float:
    """``text`` such as ``"200bar"``, ``"20 MPa"`` or ``"3000psi"`` in Pa (a bare number is Pa); a
    ParameterError naming ``what`` and the units accepted otherwise, or where the pressure is not > 0."""
    from analytic.errors import ParameterError
    m = re.fullmatch(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([A-Za-z]*)\s*", str(text))
    unit = m.group(2) if m else ""
    if m is None or (unit and unit not in PRESSURE_UNITS):
        raise ParameterError(f"{what} {text!r}: give a number and one of the units {', '.join(PRESSURE_UNITS)} "
                             f"(e.g. {what} 200bar)")
    value = float(m.group(1)) * PRESSURE_UNITS[unit or "Pa"]
    if not (math.isfinite(value) and value > 0):
        raise ParameterError(f"{what} {text!r}: a pressure must be > 0")
    return value


RPM = 60.0 / (2.0 * math.pi)
"""rpm per rad/s (a turn is 2 pi rad, a minute 60 s)."""


@dataclass(frozen=True)
class Output:
    """One reported result: its SPEC name, its quantity, its SI unit and what it belongs to (a point, a
    link, a prismatic pair, a kind's own output or a drive)."""

    name: str
    quantity: str
    si_unit: str
    owner: str
    role: str = ""
    """What owns it: ``point``, ``link``, ``slide``, ``drive``, ``transmission``, ``extra`` (a kind's own) or
    ``input`` (a motion law's jerk, ``jphi1``)."""
    of: str = ""
    """The owner's name: the point, link, prismatic pair, the drive's link, the transmission angle's point."""


def _entry(name: str, quantity: str, owner: str, role: str, of: str) -> Output:
    return Output(name, quantity, SI_UNIT[quantity], owner, role, of)


def output_table(mech) -> dict[str, Output]:
    """Every output of ``mech`` by name: each point's, link's and prismatic pair's (inputs' columns
    included), each kind's own, each input's drive force ``tauL`` (a torque for a crank, a force for a
    slider), and a built-in's SPEC aliases. Built from the topology; :attr:`Mechanism.table` caches it."""
    from analytic import kinds
    table: dict[str, Output] = {}
    for p in mech.points:
        for prefix, q in (("x", LENGTH), ("y", LENGTH), ("vx", VELOCITY), ("vy", VELOCITY), ("ax", ACCELERATION),
                          ("ay", ACCELERATION)):
            table[prefix + p] = _entry(prefix + p, q, f"point {p}", "point", p)
    for ln in mech.links:
        for prefix, q in (("phi", ANGLE), ("omega", ANGULAR_VELOCITY), ("alpha", ANGULAR_ACCELERATION)):
            table[prefix + ln] = _entry(prefix + ln, q, f"link {ln}", "link", ln)
    for j in mech.slides:
        for prefix, q in (("s", LENGTH), ("ds", VELOCITY), ("dds", ACCELERATION)):
            table[prefix + j] = _entry(prefix + j, q, f"prismatic pair {j}", "slide", j)
    for e in mech.geometry.elements:
        for x in kinds.get(e["kind"]).extra_outputs(e):
            role, of = ("transmission", x.transmission) if x.transmission else ("extra", e["point"])
            table[x.name] = _entry(x.name, x.quantity, x.owner, role, of)
    for i in mech.inputs:
        if i.motion.law is not None:                 # a motion law's jerk (SPEC "Motion laws")
            table[i.qddd] = _entry(i.qddd, ANGULAR_JERK if i.angular else JERK, f"input {i.q}", "input", i.q)
        q = i.spec.drive_quantity
        table["tau" + i.link] = _entry("tau" + i.link, q, f"drive of link {i.link}", "drive", i.link)
        own = (ANGLE, ANGULAR_VELOCITY, ANGULAR_ACCELERATION) if i.angular else (LENGTH, VELOCITY, ACCELERATION)
        for name, qty in zip((i.q, i.qd, i.qdd), own):   # an input's own columns (an actuator's, a motor's)
            if name not in table:
                table[name] = _entry(name, qty, f"input {i.q}", "input", i.link)
    for alias, target in mech.aliases.items():
        if target in table:
            table[alias] = dataclasses.replace(table[target], name=alias)
    return table


def output(mech, name: str) -> Output:
    """The table entry of output ``name`` of ``mech`` (KeyError for a name it does not have)."""
    return mech.table[name]


def outputs(mech) -> tuple[Output, ...]:
    """The table of every reported output of ``mech`` (``mech.outputs``) and its drive forces."""
    names = list(mech.outputs) + [f"tau{i.link}" for i in mech.inputs]
    return tuple(mech.table[n] for n in names)


def quantity(mech, name: str) -> str:
    """The quantity of an output, an input column (phi1, omega1, s, ...) or a CSV column ``t``; ``""``
    for a name that is none of these."""
    if name == "t":
        return TIME
    if name == "loop_violation":
        return LENGTH
    entry = mech.table.get(name)
    return entry.quantity if entry is not None else ""


# -------------------------------------------------------------------------------- figures of merit
FIGURES = {
    # four-bar
    "limit_angles": ANGLE, "reachable_phi1": ANGLE, "mu_min": ANGLE, "mu_max": ANGLE, "mu_extremes": ANGLE,
    "phi3_swing": ANGLE,
    # six-bar (quick-return shaper)
    "h": LENGTH, "stroke": LENGTH, "swing": ANGLE, "theta": ANGLE, "K": RATIO, "phi1_limits": ANGLE,
    "xC_limits": LENGTH, "s_range": LENGTH,
    # five-bar
    "speed_ratio": RATIO, "S_range": LENGTH, "S_min_possible": LENGTH,
    # every mechanism
    "time_ratio": RATIO, "transmission": ANGLE,
}
"""Quantity of each figure of merit by key; the pattern rules below cover the keys named after a point."""

_FIGURE_PATTERNS = ((re.compile(r"^v[xy]\w+_range$"), VELOCITY), (re.compile(r"^a[xy]\w+_range$"), ACCELERATION),
                    (re.compile(r"^[xy]\w+_range$"), LENGTH), (re.compile(r"^v\w+_(min|mean|max)$"), VELOCITY))


def figure_quantity(key: str, angular: bool = True) -> str:
    """The quantity of a figure of merit (``""`` for text, flags and counts). The input's ranges and
    points are angles where the first input's coordinate is one (``angular``: a crank), else lengths."""
    if key in FIGURES:
        return FIGURES[key]
    if key in ("input_ranges", "dead_points", "singular_points"):
        return ANGLE if angular else LENGTH
    for pattern, q in _FIGURE_PATTERNS:
        if pattern.match(key):
            return q
    return ""


# ---------------------------------------------------------------------------------------- display
@dataclass(frozen=True)
class Display:
    """Units results are shown in: ``length`` one of LENGTH_UNITS, ``angle`` "rad" or "deg", ``speed``
    (angular speeds) "" (the angle unit per second) or "rpm", ``force`` one of FORCE_UNITS (moments: N m for
    N, else the force unit times the length unit)."""

    length: str = "m"
    angle: str = "rad"
    speed: str = ""
    force: str = "N"

    def __post_init__(self):
        from analytic import ParameterError
        if self.length not in LENGTH_UNITS:
            raise ParameterError(f"units {self.length!r}: use one of {', '.join(LENGTH_UNITS)}")
        if self.angle not in ("rad", "deg"):
            raise ParameterError(f"angles {self.angle!r}: use rad or deg")
        if self.speed not in ("", "rpm"):
            raise ParameterError(f"speeds {self.speed!r}: use rpm (or leave it out for {self.angle}/s)")
        if self.force not in FORCE_UNITS:
            raise ParameterError(f"force units {self.force!r}: use one of {', '.join(FORCE_UNITS)}")

    @property
    def is_si(self) -> bool:
        return self.length == "m" and self.angle == "rad" and self.speed == "" and self.force == "N"

    def unit(self, quantity: str) -> str:
        """The unit label of ``quantity`` in these display units."""
        if quantity in (LENGTH, VELOCITY, ACCELERATION, JERK):
            return SI_UNIT[quantity].replace("m", self.length, 1)
        if quantity == ANGLE:
            return self.angle
        if quantity == ANGULAR_VELOCITY:
            return "rpm" if self.speed == "rpm" else f"{self.angle}/s"
        if quantity == ANGULAR_ACCELERATION:
            return f"{self.angle}/s^2"
        if quantity == ANGULAR_JERK:
            return f"{self.angle}/s^3"
        if quantity == FORCE:
            return self.force
        if quantity == TORQUE and self.force != "N":
            return f"{self.force} {self.length}"
        return SI_UNIT.get(quantity, "")

    def factor(self, quantity: str) -> float:
        """Display value per SI value of ``quantity``."""
        if quantity in (LENGTH, VELOCITY, ACCELERATION, JERK):
            return 1.0 / LENGTH_UNITS[self.length]
        deg = 180.0 / math.pi if self.angle == "deg" else 1.0
        if quantity in (ANGLE, ANGULAR_ACCELERATION, ANGULAR_JERK):
            return deg
        if quantity == ANGULAR_VELOCITY:
            return RPM if self.speed == "rpm" else deg
        if quantity == FORCE:
            return 1.0 / FORCE_UNITS[self.force]
        if quantity == TORQUE and self.force != "N":
            return 1.0 / (FORCE_UNITS[self.force] * LENGTH_UNITS[self.length])
        return 1.0

    def convert(self, quantity: str, value):
        """``value`` (SI; a number, array or nested list/dict of numbers) in these display units."""
        f = self.factor(quantity)
        return value if f == 1.0 else _scale(value, f)

    def table(self, quantities: dict[str, str]) -> dict[str, str]:
        """{name: unit label} for {name: quantity}."""
        return {k: self.unit(q) for k, q in quantities.items()}


SI = Display()


def _scale(value, f: float):
    if isinstance(value, bool) or isinstance(value, str) or value is None:
        return value
    if isinstance(value, dict):
        return {k: _scale(v, f) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return type(value)(_scale(v, f) for v in value)
    return value * f


def display_for(file_units: str, units: str | None = None, angles: str | None = None,
                speeds: str | None = None, force_units: str = "N") -> Display:
    """What people read: lengths in ``units`` or else the file's unit; angles and speeds as asked; forces in
    the file's ``force_units``."""
    return Display(units or file_units, angles or "rad", speeds or "", force_units or "N")


def machine_display(units: str | None = None, angles: str | None = None, speeds: str | None = None,
                    force_units: str = "N") -> Display:
    """What CSV and JSON hold: SI unless an option was given; with ``units`` the file's ``force_units`` too."""
    return Display(units or "m", angles or "rad", speeds or "", (force_units or "N") if units else "N")


def convert_figures(figs: dict, display: Display, angular: bool = True) -> dict:
    """The figures of merit in ``display`` units, each converted by its quantity (text, flags, counts and
    ratios unchanged). ``singular_points`` keep their group names; ``min_singularity`` is a ratio."""
    out = {}
    for key, v in figs.items():
        q = figure_quantity(key, angular)
        if key == "singular_points":
            out[key] = [{**s, "at": display.convert(q, s["at"])} for s in v]
        elif key == "slides":
            out[key] = {j: {k: display.convert(LENGTH, x) for k, x in s.items()} for j, s in v.items()}
        elif q:
            out[key] = display.convert(q, v)
        else:
            out[key] = v
    return out


def figure_units(figs: dict, display: Display, angular: bool = True) -> dict[str, str]:
    """{figure key: unit label} for every figure that has a unit."""
    out = {}
    for key in figs:
        q = LENGTH if key == "slides" else figure_quantity(key, angular)
        if q and q != RATIO:
            out[key] = display.unit(q)
    return out


# -------------------------------------------------------------------------------------- parameters
_MOTION = {True: (ANGLE, ANGULAR_VELOCITY, ANGULAR_ACCELERATION), False: (LENGTH, VELOCITY, ACCELERATION)}
"""The quantities of an input's motion law (start, rate, acceleration), by whether its coordinate is an angle."""


def parameter_quantity(mech, name: str) -> str:
    """The quantity of parameter ``name`` of ``mech``: what an input's motion law uses it for (a crank's
    start angle, speed, acceleration; a slider's start, speed, acceleration), else what the file uses it as
    (a length, an angle; a number written in degrees, ``"25deg"``, is an angle); ``""`` for a branch or a
    pure number (a ratio, or a value used only inside other parameters' expressions)."""
    for i in mech.inputs:
        for q, p in zip(_MOTION[i.angular], i.parameters):
            if p == name:
                return q
    d = mech.definition
    kind = d.parameter_kind[name]
    if kind == "length":
        return LENGTH
    if kind == "angle":
        return ANGLE
    raw = d.parameters[name]
    if kind == "number" and isinstance(raw, str):
        from analytic.format import expr
        q = expr.quantity(raw)
        if q is not None and q[1]:
            return ANGLE
    return ""


def parameter_si(mech, name: str) -> float:
    """Parameter ``name`` in SI: lengths (and a slider's speed and acceleration) from the file's unit to
    metres; angles are radians already; a pure number as it is."""
    v = float(mech.values[name])
    return v * mech.scale if parameter_quantity(mech, name) in (LENGTH, VELOCITY, ACCELERATION) else v


def parameters_in(mech, display: Display) -> dict[str, float]:
    """Every parameter's value in ``display`` units, in file order (see :func:`parameter_units`)."""
    out = {}
    for name in mech.definition.parameter_order:
        q = parameter_quantity(mech, name)
        out[name] = display.convert(q, parameter_si(mech, name)) if q else float(mech.values[name])
    return out


def parameter_units(mech, display: Display) -> dict[str, str]:
    """{parameter: unit label in ``display`` units} (``""`` for a branch or a pure number)."""
    out = {}
    for name in mech.definition.parameter_order:
        q = parameter_quantity(mech, name)
        out[name] = display.unit(q) if q else ""
    return out


def parameters_text(mech, display: Display) -> str:
    """The parameters as people read them: ``"l1=0.2 m, phi4_0=60 deg, omega2=60 rpm, branch=1"``."""
    values, units = parameters_in(mech, display), parameter_units(mech, display)
    return ", ".join(f"{k}={v:g}" + (f" {units[k]}" if units[k] else "") for k, v in values.items())
