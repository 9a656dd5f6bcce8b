"""JSON output: non-finite floats as null (JSON has no NaN), numpy values as plain numbers."""

from __future__ import annotations

import json
import math

import numpy as np


def clean(v):
    if isinstance(v, float) and not math.isfinite(v):
        return None
    if isinstance(v, np.generic):
        return clean(v.item())
    if isinstance(v, np.ndarray):
        return [clean(x) for x in v.tolist()]
    if isinstance(v, dict):
        return {str(k): clean(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [clean(x) for x in v]
    return v


def dumps(obj, indent: int | None = 2) -> str:
    return json.dumps(clean(obj), indent=indent, allow_nan=False)
