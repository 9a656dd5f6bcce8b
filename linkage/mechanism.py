"""The mechanism a script holds: :class:`analytic.mechanism.Mechanism` (parameters, inputs, ``solve``) that
also shows itself in a notebook (its drawing and a table of its parameters)."""

from __future__ import annotations

from dataclasses import fields

from analytic.mechanism import Mechanism as _Base


class Mechanism(_Base):
    """A planar linkage with its parameter values (:func:`linkage.load` makes one): ``name``, ``values``
    (the parameters, file units), ``inputs`` (each with its ``q``, ``qd``, ``qdd`` names), ``points``,
    ``outputs``, ``solve(q, qd, qdd)``; in Jupyter its drawing at the start and a table of its parameters.

    Example:
        >>> mech = lk.load("fourbar")
        >>> [i.q for i in mech.inputs], mech.output_point
        (['phi1'], 'E')
    """

    def _repr_html_(self) -> str:
        from linkage.notebook import mechanism_html
        return mechanism_html(self)


def of(mech: _Base) -> Mechanism:
    """``mech`` as a :class:`Mechanism` (the same fields)."""
    if isinstance(mech, Mechanism):
        return mech
    return Mechanism(**{f.name: getattr(mech, f.name) for f in fields(mech)})
