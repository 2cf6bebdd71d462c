"""Kinematics (theory §3, §5-§7): rates of every attitude representation, angular
velocity from attitude histories, attitude propagation, velocity and acceleration
fields, composite motion (Coriolis), screw axis, and the Frenet frame.

**Convention:** ``omega`` is named by the frame of its components: ``frame="body"``
(``w_xi``, the default) or ``frame="space"`` (``w_x = C w_xi``); rad/s. See
``docs/kinematics.md``.

>>> from poinsot.kinematics import velocity_field
>>> velocity_field([1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0])
array([0., 0., 0.])
"""

from __future__ import annotations

from .attitude_history import (
    RotationSpline,
    angular_velocity,
    fornberg_weights,
    rotation_spline,
)
from .coning import (
    coning_omega,
    coning_quat,
)
from .fields import (
    AngularMotion,
    CompositeMotion,
    FrameMotion,
    acceleration_field,
    chain,
    compose_angular,
    point_motion,
    velocity_field,
)
from .plane import Centrodes, acceleration_center, centrodes, velocity_center
from .point import (
    FrenetFrame,
    frenet,
)
from .poisson_matrix import PoissonMatrixRun, integrate_poisson_matrix
from .propagation import (
    propagate,
)
from .rates import (
    GIMBAL_ERROR_DET,
    GIMBAL_WARN_DET,
    dcm_rate,
    euler_rate_matrix,
    euler_rates,
    gibbs_rate,
    mrp_rate,
    mrp_shadow,
    mrp_switch,
    omega_from_dcm_rate,
    omega_from_euler_rates,
    omega_from_gibbs_rate,
    omega_from_mrp_rate,
    omega_from_quat_rate,
    omega_from_rotvec_rate,
    quat_rate,
    rotvec_rate,
)
from .screw import (
    ReducedMotion,
    Screw,
    reduce_motions,
    screw_axis,
)

__all__ = [
    "PoissonMatrixRun",
    "integrate_poisson_matrix",
    "Centrodes",
    "acceleration_center",
    "centrodes",
    "velocity_center",
    "quat_rate",
    "omega_from_quat_rate",
    "dcm_rate",
    "omega_from_dcm_rate",
    "euler_rates",
    "omega_from_euler_rates",
    "euler_rate_matrix",
    "gibbs_rate",
    "omega_from_gibbs_rate",
    "mrp_rate",
    "omega_from_mrp_rate",
    "mrp_shadow",
    "mrp_switch",
    "rotvec_rate",
    "omega_from_rotvec_rate",
    "GIMBAL_WARN_DET",
    "GIMBAL_ERROR_DET",
    "angular_velocity",
    "rotation_spline",
    "RotationSpline",
    "fornberg_weights",
    "propagate",
    "velocity_field",
    "acceleration_field",
    "compose_angular",
    "AngularMotion",
    "FrameMotion",
    "CompositeMotion",
    "point_motion",
    "chain",
    "Screw",
    "screw_axis",
    "ReducedMotion",
    "reduce_motions",
    "FrenetFrame",
    "frenet",
    "coning_quat",
    "coning_omega",
]


def __dir__() -> list[str]:
    # the public API only (not `annotations` or the submodules' names)
    return sorted(__all__)
