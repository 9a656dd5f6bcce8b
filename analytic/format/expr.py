"""Values in mechanism files: numbers, quantities such as ``"30deg"``, parameter names and small
arithmetic expressions of them (``"l3*(1 + sqrt(1 - (l1/l6)**2))/2"``).

An expression is parsed with :mod:`ast` and evaluated by walking the tree (turned once into closures): only numbers, parameter
names, ``+ - * / **``, parentheses and the functions in :data:`FUNCTIONS` are accepted. Nothing in a
file is ever executed.
"""

from __future__ import annotations

import ast
import functools
import math
import re

from analytic.errors import ParameterError

FUNCTIONS = {"sqrt": math.sqrt, "sin": math.sin, "cos": math.cos, "tan": math.tan, "asin": math.asin,
             "acos": math.acos, "atan": math.atan, "atan2": math.atan2, "hypot": math.hypot,
             "abs": abs, "min": min, "max": max, "radians": math.radians, "degrees": math.degrees}
CONSTANTS = {"pi": math.pi}

# Possessive quantifiers and a look-behind: each pattern matches in time linear in the text (the
# former ``\d+\.?\d*`` split a run of digits in quadratically many ways and re-tried it at each start).
_UNSIGNED = r"(?:\d++(?:\.\d*+)?+|\.\d++)(?:[eE][-+]?+\d++)?+"
_NUMBER = rf"[-+]?+{_UNSIGNED}"
_QUANTITY = re.compile(rf"^\s*+({_NUMBER})\s*+(deg)?+\s*+$")
_DEG = re.compile(rf"(?<![\w.])({_UNSIGNED})\s*+deg\b")
MAX_LENGTH = 400         # characters in one expression: a design's formula is far shorter
MAX_DEPTH = 40           # nested parentheses/operators in one expression
_DEG_MARK = "_deg_"      # what a ``deg`` suffix becomes while parsing: a call that marks the angle
NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


def quantity(text: str) -> tuple[float, bool] | None:
    """``"30deg"`` -> (0.5236, True); ``"0.25"`` -> (0.25, False); anything else -> None."""
    m = _QUANTITY.match(text)
    if not m:
        return None
    value = float(m.group(1))
    return (math.radians(value), True) if m.group(2) else (value, False)


def names_in(text: str) -> set[str]:
    """The parameter names an expression uses (raises ValueError if it is not a valid expression)."""
    tree = _parse(text)
    return {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)} - set(FUNCTIONS) - set(CONSTANTS) - {_DEG_MARK}


def _short(text: str, limit: int = 60) -> str:
    r = repr(text)
    return r if len(r) <= limit else r[:limit - 5] + "...'" + f" ({len(text)} characters)"


def _depth(node, level: int = 0) -> int:
    """Nesting depth of an expression tree (stops counting past MAX_DEPTH)."""
    if level > MAX_DEPTH:
        return level
    return max((_depth(c, level + 1) for c in ast.iter_child_nodes(node)), default=level)


@functools.lru_cache(maxsize=4096)
def _parse(text: str) -> ast.Expression:
    """The checked tree of an expression; cached (a file's expressions are parsed again for every set of
    values: a slider move, each step of a drag). The trees are only read, never changed."""
    if len(text) > MAX_LENGTH:
        raise ValueError(f"{_short(text)} is too long: an expression is at most {MAX_LENGTH} characters")
    source = _DEG.sub(lambda m: f"{_DEG_MARK}({m.group(1)})", text)
    try:
        tree = ast.parse(source.strip(), mode="eval")
    except (SyntaxError, RecursionError, MemoryError, ValueError):
        raise ValueError(f"{_short(text)} is not a number, a parameter name or an arithmetic expression") from None
    if _depth(tree) > MAX_DEPTH:
        raise ValueError(f"{_short(text)} is nested too deeply (at most {MAX_DEPTH} levels)")
    for node in ast.walk(tree):
        if isinstance(node, ast.BinOp) and (isinstance(node.op, ast.Pow) or isinstance(node.op, ast.Div)) and any(
                isinstance(n, ast.Call) and isinstance(n.func, ast.Name) and n.func.id == _DEG_MARK
                for side in ((node.left, node.right) if isinstance(node.op, ast.Pow) else (node.right,))
                for n in ast.walk(side)):
            raise ValueError(f"{_short(text)}: a 'deg' value divides or is raised to a power, which gives no "
                             f"angle; write the angle whole, e.g. \"2deg\" or \"(1/30)*1deg\"")
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == _DEG_MARK:
            continue
        if not isinstance(node, _ALLOWED):
            raise ValueError(f"{_short(text)}: only numbers, parameter names, + - * / ** and "
                             f"{', '.join(FUNCTIONS)} are allowed")
        if isinstance(node, ast.Call) and not (isinstance(node.func, ast.Name) and node.func.id in FUNCTIONS
                                               and not node.keywords) and not (
                isinstance(node.func, ast.Name) and node.func.id == _DEG_MARK):
            raise ValueError(f"{_short(text)}: unknown function; use one of {', '.join(FUNCTIONS)}")
        if isinstance(node, ast.Constant) and not isinstance(node.value, (int, float)):
            raise ValueError(f"{_short(text)}: only numbers are allowed as constants")
    return tree


_ALLOWED = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Constant, ast.Name, ast.Load, ast.Call,
            ast.Add, ast.Sub, ast.Mult, ast.Div, ast.Pow, ast.USub, ast.UAdd)


class _Unknown(Exception):
    """A name the values do not hold (its message is the caller's: a parameter's, a load's input)."""

    def __init__(self, name: str):
        super().__init__(name)
        self.name = name


def evaluate(text: str, values: dict[str, float]) -> float:
    """Evaluate an expression with parameter ``values``; raises ValueError with a readable message."""
    try:
        result = _compiled(text, False)(values)
    except _Unknown as exc:
        raise ValueError(f"{_short(text)} uses {exc.name!r}, which is not a parameter") from None
    if isinstance(result, complex) or not math.isfinite(result):
        raise ValueError(f"{_short(text)} evaluates to {result!r}, not a finite number")
    return float(result)


def evaluate_array(text: str, values: dict, unknown=None):
    """The same expression (the same parse, the same evaluator as :func:`evaluate`) on arrays of values
    (numpy): where it is undefined at a sample (a division by zero, a root of a negative, an exponent over
    64) that sample is NaN, never an error; the caller decides what a NaN means. ``unknown(name)``: the
    message for a name ``values`` lacks (default: not a parameter)."""
    import numpy as np
    try:
        with np.errstate(all="ignore"):
            return np.asarray(_compiled(text, True)(values), dtype=float)
    except _Unknown as exc:
        raise ValueError(unknown(exc.name) if unknown else
                         f"{_short(text)} uses {exc.name!r}, which is not a parameter") from None


def _array_functions() -> dict:
    """:data:`FUNCTIONS` on arrays (outside a function's domain: NaN)."""
    import numpy as np
    return {"sqrt": np.sqrt, "sin": np.sin, "cos": np.cos, "tan": np.tan, "asin": np.arcsin, "acos": np.arccos,
            "atan": np.arctan, "atan2": np.arctan2, "hypot": np.hypot, "abs": np.abs,
            "min": lambda *a: functools.reduce(np.minimum, a), "max": lambda *a: functools.reduce(np.maximum, a),
            "radians": np.radians, "degrees": np.degrees}


@functools.lru_cache(maxsize=4096)
def _compiled(text: str, array: bool):
    """The checked tree of ``text`` (:func:`_parse`) turned once into nested closures ``values -> value``, on
    numbers (``array`` False: an undefined value raises its readable ValueError) or on numpy arrays (NaN
    instead). A file's expressions are evaluated again at every step of a drag: the closures skip the
    per-node dispatch of a tree walk. Nothing is executed that the tree walk would not have done."""
    return _closure(_parse(text), text, _array_functions() if array else None)


def _closure(node, text: str, arrays: dict | None):
    """One node's closure; ``arrays``: the numpy functions (the array evaluator), or None (numbers)."""
    if isinstance(node, ast.Expression):
        return _closure(node.body, text, arrays)
    if isinstance(node, ast.Constant):
        c = float(node.value)
        return lambda values: c
    if isinstance(node, ast.Name):
        name = node.id
        if name in CONSTANTS:
            c = CONSTANTS[name]
            return lambda values: c

        def lookup(values):
            if name not in values:
                raise _Unknown(name)
            return values[name]
        return lookup
    if isinstance(node, ast.UnaryOp):
        operand = _closure(node.operand, text, arrays)
        if isinstance(node.op, ast.USub):
            return lambda values: -operand(values)
        return operand
    if isinstance(node, ast.BinOp):
        left, right, op = _closure(node.left, text, arrays), _closure(node.right, text, arrays), type(node.op)
        if op is ast.Add:
            return lambda values: left(values) + right(values)
        if op is ast.Sub:
            return lambda values: left(values) - right(values)
        if op is ast.Mult:
            return lambda values: left(values) * right(values)
        if arrays is not None:
            import numpy as np
            if op is ast.Div:
                return lambda values: np.divide(left(values), right(values))

            def power(values):
                a, b = left(values), right(values)
                return np.where(np.abs(b) > 64, np.nan, np.power(np.asarray(a, dtype=float), b))
            return power

        def divide_or_power(values):
            a, b = left(values), right(values)
            if op is ast.Pow and abs(b) > 64:
                raise ValueError(f"{_short(text)}: exponent {b:g} is too large")
            try:
                return a / b if op is ast.Div else a ** b
            except (ZeroDivisionError, OverflowError):
                raise ValueError(f"{_short(text)} divides by zero or overflows") from None
        return divide_or_power
    if isinstance(node, ast.Call) and node.func.id == _DEG_MARK:
        arg = _closure(node.args[0], text, arrays)
        if arrays is not None:
            return lambda values: arrays["radians"](arg(values))
        return lambda values: math.radians(arg(values))
    if isinstance(node, ast.Call):
        args_of, fname = [_closure(a, text, arrays) for a in node.args], node.func.id
        if arrays is not None:
            fn = arrays[fname]
            return lambda values: fn(*[a(values) for a in args_of])

        def call(values):
            args = [a(values) for a in args_of]
            try:
                return float(FUNCTIONS[fname](*args))
            except (ValueError, TypeError, OverflowError):
                raise ValueError(f"{_short(text)}: {fname}({', '.join(f'{a:g}' for a in args)}) is undefined")
        return call

    def invalid(values):
        raise ValueError(f"{_short(text)} is not a valid expression")
    return invalid


def parse_value(name: str, text: str, angle: bool | None = None) -> float:
    """A command-line value: a number, or an angle with a ``deg`` suffix (converted to radians).

    ``angle`` False refuses a ``deg`` suffix (the parameter is a length), None accepts both. Values
    must be finite and not absurdly large (|v| <= 1e12).
    """
    q = quantity(text)
    if q is None:
        raise ParameterError(f"{name}={_short(text)} is not a number (write e.g. {name}=0.25"
                             f"{'' if angle is False else f' or {name}=30deg'})")
    value, deg = q
    if deg and angle is False:
        raise ParameterError(f"{name}={_short(text)}: {name} is a length, not an angle; drop the 'deg' suffix")
    if not math.isfinite(value) or abs(value) > 1e12:
        raise ParameterError(f"{name}={_short(text)} is out of range: give a finite value of magnitude <= 1e12")
    return value
