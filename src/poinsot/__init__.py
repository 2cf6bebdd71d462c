"""poinsot: kinematics and dynamics of rigid bodies, built on quaternions.

Conventions (see ``docs/conventions.md``): Hamilton quaternions stored scalar
first ``(w, x, y, z)``; a rotation maps body components to reference-frame
components; radians unless ``degrees=True``.

>>> import poinsot
>>> r = poinsot.Rotation.from_euler("x", 90, degrees=True)
>>> r.apply([0.0, 1.0, 0.0]).round(12) + 0.0
array([0., 0., 1.])
"""

from __future__ import annotations

import importlib
import sys
from types import ModuleType

from .errors import (
    AccuracyWarning,
    GimbalLockWarning,
    IntegrationError,
    InvalidInputError,
    InvalidTypeError,
    PoinsotError,
    PoinsotWarning,
    SingularityWarning,
)
from .rotations import quaternion
from .rotations.rotation import Rotation, compose, slerp
from .trajectory import (
    Comparison,
    CoordinateTrajectory,
    PointTrajectory,
    PoseTrajectory,
    Result,
    Trajectory,
    compare,
)

# `import poinsot.quaternion` works as well as `poinsot.quaternion`.
sys.modules[__name__ + ".quaternion"] = quaternion

__version__ = "0.1.0"

__all__ = [
    "AccuracyWarning",
    "GimbalLockWarning",
    "IntegrationError",
    "InvalidInputError",
    "InvalidTypeError",
    "PoinsotError",
    "PoinsotWarning",
    "Rotation",
    "SingularityWarning",
    "Trajectory",
    "PointTrajectory",
    "PoseTrajectory",
    "CoordinateTrajectory",
    "Result",
    "Comparison",
    "compare",
    "compose",
    "quaternion",
    "slerp",
]

# Heavy or optional subpackages load on first access so that `import poinsot`
# stays fast and never pulls in SymPy or matplotlib.
_LAZY = {
    "kinematics",
    "mass",
    "dynamics",
    "symbolic",
    "ensemble",
    "plotting",
    "scenarios",
    "verify",
    "cli",
}


def __getattr__(name: str) -> ModuleType:
    if name in _LAZY:
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    # the public API only: no `annotations`, `importlib`, private helpers
    return sorted({*__all__, "__version__"} | _LAZY)
