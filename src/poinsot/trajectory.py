"""The result of every time-stepping computation: a frozen :class:`Trajectory`.

Both attitude propagation (:func:`poinsot.kinematics.propagate`, SPEC S5) and
rigid-body simulation (:func:`poinsot.dynamics.simulate`, SPEC S10) return one.

Conventions: ``rotation[k]`` maps body components to space components at time
``t[k]`` (``v_space = R v_body``, SPEC S2); ``omega`` is the angular velocity in
**body** axes (rad/s); ``momentum`` is the angular momentum in **space** axes.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np

from ._validate import as_float_array
from .errors import InvalidInputError, InvalidTypeError
from .rotations.rotation import Rotation

__all__ = ["Trajectory"]


@dataclass(frozen=True, eq=False)
class Trajectory:
    """Samples of a rigid body's rotational motion.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Output times (s).
    rotation : Rotation, shape (n,) or (n, N)
        Attitude (body -> space) at each time, for one body or a batch of N.
    omega : ndarray, shape (n, 3) or (n, N, 3)
        Angular velocity in body axes (rad/s).
    method : str
        Name of the method that produced the samples.
    energy : ndarray, shape (n,) or (n, N), optional
        Rotational kinetic energy ``T = w^T J w / 2`` (SPEC S8).
    momentum : ndarray, shape (n, 3) or (n, N, 3), optional
        Angular momentum ``K = R J w`` in space axes (SPEC S8, S10).
    info : mapping
        Method-specific details (step size, number of steps, solver status...).

    Examples
    --------
    >>> import numpy as np, poinsot
    >>> t = np.linspace(0.0, 1.0, 3)
    >>> tr = Trajectory(t, poinsot.Rotation.identity((3,)), np.zeros((3, 3)), "none")
    >>> tr.quat.shape
    (3, 4)
    """

    t: np.ndarray
    rotation: Rotation
    omega: np.ndarray
    method: str
    energy: np.ndarray | None = None
    momentum: np.ndarray | None = None
    info: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not isinstance(self.rotation, Rotation):
            raise InvalidTypeError(
                f"Expected `rotation` to be a poinsot.Rotation, got {type(self.rotation).__name__}."
            )
        if not isinstance(self.method, str):
            raise InvalidTypeError(f"Expected `method` to be a string, got {self.method!r}.")
        object.__setattr__(self, "info", MappingProxyType(dict(self.info)))
        n = self.rotation.shape[:1]
        expected = {
            "t": n,
            "omega": (*self.rotation.shape, 3),
            "energy": self.rotation.shape,
            "momentum": (*self.rotation.shape, 3),
        }
        for name, shape in expected.items():
            a = getattr(self, name)
            if a is None:
                continue
            a = np.array(as_float_array(a, name, finite=False), dtype=float)
            if a.shape != shape:
                raise InvalidInputError(
                    f"Expected `{name}` to have shape {shape} to match `rotation` "
                    f"{self.rotation.shape}, got {a.shape}."
                )
            a.setflags(write=False)
            object.__setattr__(self, name, a)

    @property
    def quat(self) -> np.ndarray:
        """Scalar-first unit quaternions, shape ``rotation.shape + (4,)``."""
        return self.rotation.as_quat()

    @property
    def omega_space(self) -> np.ndarray:
        """Angular velocity in space axes, ``w_x = R w_xi`` (rad/s)."""
        return self.rotation.apply(self.omega)

    @property
    def momentum_norm(self) -> np.ndarray | None:
        """``|K|`` at each sample."""
        return None if self.momentum is None else np.linalg.norm(self.momentum, axis=-1)

    @property
    def energy_drift(self) -> float | None:
        """``max_k |T_k - T_0| / |T_0|`` (relative drift of the kinetic energy).

        Absolute (``max_k |T_k - T_0|``) where ``T_0 = 0``, e.g. a body at rest.
        """
        if self.energy is None:
            return None
        return _relative(np.abs(self.energy - self.energy[0]), np.abs(self.energy[0]))

    @property
    def momentum_drift(self) -> float | None:
        """``max_k ||K_k| - |K_0|| / |K_0|`` (relative drift of ``|K|``; absolute at 0)."""
        k = self.momentum_norm
        if k is None:
            return None
        return _relative(np.abs(k - k[0]), k[0])

    @property
    def momentum_vector_drift(self) -> float | None:
        """``max_k |K_k - K_0| / |K_0|``: for a free body the space vector is constant."""
        if self.momentum is None:
            return None
        d = np.linalg.norm(self.momentum - self.momentum[0], axis=-1)
        return _relative(d, np.linalg.norm(self.momentum[0], axis=-1))


def _relative(diff: np.ndarray, ref: np.ndarray) -> float:
    """Largest ``diff / ref``, using ``diff`` itself where the reference is zero."""
    ref = np.broadcast_to(ref, diff.shape)
    scaled = np.divide(diff, ref, out=np.array(diff, dtype=float), where=ref != 0)
    return float(np.max(scaled))
