"""analytic.format.expr.evaluate, now through closures built once per expression: every value must be the one
Python's own evaluation of the same arithmetic gives (an independent evaluator of the same grammar), and the
errors must stay the readable ones."""

import math
import random

import pytest

from analytic.format import expr

EXPRESSIONS = [
    "l2", "-b", "+b", "2*l2", "l3*(1 + sqrt(1 - (l1/l6)**2))/2", "l1 - l2 + l3 * l4 / l5", "(l1 + l2) ** 2 - l3",
    "atan2(l2, -l3) + pi", "hypot(l1, l2) - abs(-l3)", "min(l1, l2, l3) + max(l4, 2)", "30deg + l1", "-(90deg)",
    "degrees(radians(l2))", "sin(l1)*cos(l2) - tan(l3/10)", "asin(l1/(l1 + l2)) + acos(0.5)", "l1 - -l2",
    "2 ** -l1", "1.5e-3*l4 - .25", "l5 / l4 / l3 / l2",
]


def python_value(text, values):
    source = expr._DEG.sub(lambda m: f"radians({m.group(1)})", text)
    names = {**expr.FUNCTIONS, **expr.CONSTANTS, **values}
    return float(eval(source, {"__builtins__": {}}, names))  # noqa: S307 (the oracle: only the test's own texts)


@pytest.mark.parametrize("text", EXPRESSIONS)
def test_values_are_pythons(text):
    rng = random.Random(text)
    for _ in range(20):
        values = {f"l{i}": rng.uniform(0.5, 3.0) for i in range(1, 6)} | {"l6": rng.uniform(3.5, 5), "b": rng.uniform(-2, 2)}
        # the same float operations in the same order: equal to the last bit, compared with a zero tolerance
        assert math.isclose(expr.evaluate(text, values), python_value(text, values), rel_tol=0.0, abs_tol=0.0)


@pytest.mark.parametrize("text, values, message", [
    ("l1 + q", {"l1": 1.0}, "'q', which is not a parameter"),
    ("l1 / (l1 - l1)", {"l1": 1.0}, "divides by zero"),
    ("l1 ** 65", {"l1": 1.0}, "exponent 65 is too large"),
    ("l1 ** 60", {"l1": 1e10}, "overflows"),
    ("sqrt(-l1)", {"l1": 1.0}, "sqrt(-1) is undefined"),
    ("l1 * 1e308 * 10", {"l1": 1.0}, "not a finite number"),
    ("(-l1) ** 0.5", {"l1": 1.0}, "not a finite number"),
    ("open(l1)", {"l1": 1.0}, "unknown function"),
])
def test_errors_stay_readable(text, values, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)").replace("*", r"\*")):
        expr.evaluate(text, values)


def test_a_parameter_changed_is_seen():
    """The closures are cached per text, never per values."""
    assert expr.evaluate("2*l1", {"l1": 1.0}) == pytest.approx(2.0, abs=0)    # exact: one doubling
    assert expr.evaluate("2*l1", {"l1": 3.0}) == pytest.approx(6.0, abs=0)


@pytest.mark.parametrize("text", EXPRESSIONS)
def test_arrays_are_pythons_at_every_sample(text):
    """The array path of the one evaluator (what the batch solver uses) against Python's own arithmetic at each
    sample: numpy's elementwise operations round as Python's floats do, its transcendental functions may
    differ in the last bits."""
    import numpy as np
    rng = random.Random("array " + text)
    rows = [{f"l{i}": rng.uniform(0.5, 3.0) for i in range(1, 6)} | {"l6": rng.uniform(3.5, 5),
                                                                     "b": rng.uniform(-2, 2)} for _ in range(16)]
    arrays = {k: np.array([r[k] for r in rows]) for k in rows[0]}
    got = np.broadcast_to(expr.evaluate_array(text, arrays), (16,))     # a constant's value is one number
    want = [python_value(text, r) for r in rows]
    np.testing.assert_allclose(got, want, rtol=1e-13, atol=0)   # a few ulps: numpy's libm against Python's


def test_arrays_give_nan_where_a_value_is_undefined_and_name_an_unknown():
    import numpy as np
    x = np.array([1.0, 0.0, -4.0])
    got = expr.evaluate_array("sqrt(l1) + 1/l1 + l1 ** 65 * 0", {"l1": x})
    assert np.isnan(got).all()            # the exponent over 64 is NaN everywhere; sqrt(-4), 1/0 where they are
    assert expr.evaluate_array("sqrt(l1)", {"l1": x})[0] == pytest.approx(1.0, abs=0)     # exact: sqrt(1)
    with pytest.raises(ValueError, match="'q', which is not a parameter"):
        expr.evaluate_array("l1 + q", {"l1": x})
    with pytest.raises(ValueError, match="q: not an input"):
        expr.evaluate_array("l1 + q", {"l1": x}, unknown=lambda name: f"{name}: not an input")
