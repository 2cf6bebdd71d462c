"""Rotations: quaternion algebra, every representation (docs/theory.md §1-§4) and the
finite displacements of SE(3) (§6).

The unit quaternion is the hub: each representation module converts to and
from it (``dcm``, ``rotvec``, ``euler``, ``rodrigues``, ``frames``), and
:class:`~poinsot.Rotation` is the facade over them.
"""

from . import quaternion
from ._lazy import PARALLEL_MIN_SIZE, get_num_threads, set_num_threads
from .determination import ATTITUDE_METHODS, AttitudeSolution, determine_attitude
from .lie import (
    RotationEigen,
    expm_so3,
    hat,
    logm_so3,
    quat_left_matrix,
    quat_right_matrix,
    rotation_eigen,
    vee,
)
from .rotation import Rotation, compose, slerp
from .transform import FiniteScrew, RigidTransform, sclerp

__all__ = [
    "ATTITUDE_METHODS",
    "AttitudeSolution",
    "PARALLEL_MIN_SIZE",
    "FiniteScrew",
    "RigidTransform",
    "Rotation",
    "RotationEigen",
    "compose",
    "determine_attitude",
    "expm_so3",
    "hat",
    "logm_so3",
    "quat_left_matrix",
    "quat_right_matrix",
    "rotation_eigen",
    "vee",
    "get_num_threads",
    "quaternion",
    "sclerp",
    "set_num_threads",
    "slerp",
]


def __dir__() -> list[str]:
    # the public API only (not `annotations` or the submodules' names)
    return sorted(__all__)
