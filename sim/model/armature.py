"""A joint's rotor inertia (MuJoCo's ``dof_armature``) changed after the model is compiled.

MuJoCo derives constants from the inertias at compile time: a body whose centre of mass lies on its joint's
axis is "simple", and its mass-matrix entry is then the compiled ``dof_M0`` (the diagonal inertia at the
reference pose, armature included) rather than one computed each step. Writing ``dof_armature`` alone left
that entry stale: a flywheel on a crank whose centre of mass is its pivot was absent from the motor run (the
crank's own inertia alone, a stall at the first step). :func:`set_armature` changes both by the same amount
(the other compiled constants, e.g. the constraints' ``dof_invweight0``, are left as compiled, as before)."""

from __future__ import annotations


def set_armature(model, joint: str, value: float) -> None:
    """Give the tree joint named ``joint`` the rotor inertia ``value`` [kg m^2 or kg], its compiled diagonal
    inertia ``dof_M0`` changed with it."""
    dof = model.jnt_dofadr[model.joint(joint).id]
    model.dof_M0[dof] += float(value) - float(model.dof_armature[dof])
    model.dof_armature[dof] = float(value)


__all__ = ["set_armature"]
