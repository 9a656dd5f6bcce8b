"""The three built-in mechanisms' own textbook closed forms (seed 000's four-bar and shaper, seed 003's
five-bar), the independent checks of the general solver (their inverse dynamics: tests/builtin_dynamics.py)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Builtin:
    """What a built-in mechanism adds to its file: SPEC output names and its dedicated closed form.

    ``aliases`` maps a SPEC name to the general output name; ``outputs`` are the SPEC outputs in CSV
    order; ``module`` is its closed-form module (:mod:`.fourbar` ...) and ``params`` its parameter
    dataclass, used as an independent check and for its own figures of merit."""

    outputs: tuple[str, ...]
    aliases: dict[str, str]
    module: object
    params: type
    figures: object
    """figures(params, solution) -> dict: the mechanism's own figures of merit."""
    summary: object
    """summary(figures, display) -> list of lines for the analysis summary."""

    def parameters(self, values: dict):
        """The parameter dataclass (FourBar, SixBar, FiveBar) with a mechanism's values (its own checks
        run)."""
        names = set(self.params.__dataclass_fields__)
        kw = {k: v for k, v in values.items() if k in names}
        if "branch" in kw:
            kw["branch"] = int(kw["branch"])
        return self.params(**kw)


def closed_form(mech, q, qd=0.0, qdd=0.0) -> dict[str, np.ndarray]:
    """A built-in mechanism's dedicated closed form at the inputs, as {SPEC name: array}."""
    from analytic._common import ParameterError
    b = mech.builtin
    if b is None:
        raise ParameterError(f"{mech.name} has no dedicated closed form (only the built-ins do)")
    p = b.parameters(mech.values)
    q, qd, qdd = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (q, qd, qdd)))
    if len(mech.inputs) == 1:
        if q.ndim == 2 and q.shape[-1] == 1:
            q, qd, qdd = q[:, 0], qd[:, 0], qdd[:, 0]
        st = b.module.solve(p, q, qd, qdd)
    else:
        st = b.module.solve(p, q[..., 0], q[..., 1], qd[..., 0], qd[..., 1], qdd[..., 0], qdd[..., 1])
    return {n: np.asarray(getattr(st, n)) for n in b.outputs}
