"""Mass geometry: inertia tensors, solids, principal axes, rigid bodies (theory §8).

Conventions
-----------
- ``J_O = sum m (rho^T rho E - rho rho^T)``: diagonal entries are moments, the
  off-diagonal ones are *negative* products of inertia.
- Change of axes with ``S = C_ab`` (columns = new axes ``b`` in the old basis
  ``a``): ``J_b = S^T J_a S`` (:func:`rotate_inertia`).
- A :class:`RigidBody` stores the inertia about its centre of mass in body axes
  and the centre of mass relative to the body reference point; every vector its
  methods take or return is in body axes.

Examples
--------
>>> from poinsot.mass import RigidBody, principal_axes
>>> body = RigidBody.box(1.0, 1.0, 2.0, 3.0) + RigidBody.sphere(1.0, 0.5).placed(
...     position=[0.0, 0.0, 2.0])
>>> body.mass, body.center_of_mass
(2.0, array([0., 0., 1.]))
>>> body.principal_moments.round(4)
array([0.5167, 2.9333, 3.1833])
>>> moments, axes = body.principal_axes()   # axes: a Rotation (columns of its matrix)
"""

from __future__ import annotations

from . import body, meshes, solids, tensor
from .body import *  # noqa: F403
from .meshes import *  # noqa: F403
from .solids import *  # noqa: F403
from .tensor import *  # noqa: F403

__all__ = [*solids.__all__, *tensor.__all__, *meshes.__all__, *body.__all__]


def __dir__() -> list[str]:
    # the public API only (not `annotations` or the submodules' names)
    return sorted(__all__)
