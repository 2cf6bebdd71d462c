"""Dynamics (SPEC S8, S10): Euler's equations, structure-preserving integrators,
and the exact Euler-Poinsot motion of the free rigid body.

**Convention:** angular velocity in body axes, angular momentum in space axes,
attitude maps body to space components. See ``docs/dynamics.md`` and
``docs/free-body.md``.

>>> from poinsot.dynamics import FreeRigidBody
>>> body = FreeRigidBody([1.0, 2.0, 3.0], omega0=[0.0, 0.0, 1.0])
>>> float(body.energy)
1.5
"""

from __future__ import annotations

from .euler_equations import (
    METHODS,
    euler_rhs,
    simulate,
)
from .free_body import (
    NEAR_SEPARATRIX,
    SEPARATRIX_RTOL,
    SYMMETRY_RTOL,
    FreeRigidBody,
    MacCullaghGeometry,
    PoinsotGeometry,
)
from .invariants import Invariants, angular_momentum, invariants, kinetic_energy
from .torques import (
    STANDARD_GRAVITY,
    CallableTorque,
    ConstantBodyTorque,
    ConstantSpaceTorque,
    GravityTorque,
    TorqueModel,
    as_torque,
)

__all__ = [
    "euler_rhs",
    "simulate",
    "METHODS",
    "FreeRigidBody",
    "MacCullaghGeometry",
    "PoinsotGeometry",
    "SYMMETRY_RTOL",
    "SEPARATRIX_RTOL",
    "NEAR_SEPARATRIX",
    "kinetic_energy",
    "angular_momentum",
    "invariants",
    "Invariants",
    "TorqueModel",
    "ConstantBodyTorque",
    "ConstantSpaceTorque",
    "GravityTorque",
    "CallableTorque",
    "as_torque",
    "STANDARD_GRAVITY",
]
