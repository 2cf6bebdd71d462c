"""The result of every time-stepping computation: a frozen :class:`Trajectory`.

Both attitude propagation (:func:`poinsot.kinematics.propagate`, theory §5) and
rigid-body simulation (:func:`poinsot.dynamics.simulate`, theory §10) return one.

Conventions: ``rotation[k]`` maps body components to space components at time
``t[k]`` (``v_space = R v_body``, theory §2); ``omega`` is the angular velocity in
**body** axes (rad/s); ``momentum`` is the angular momentum in **space** axes;
``position`` and ``velocity`` (optional translational part) are in space axes.

The keys of :attr:`Trajectory.info` are listed once, in :data:`INFO_KEYS` (and in
``docs/conventions.md``); every method uses these names and only these.
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

__all__ = ["Trajectory", "INFO_KEYS"]

#: The documented keys of ``Trajectory.info`` (a method sets those that apply to it).
INFO_KEYS = {
    "steps": "number of steps taken per body (int; fixed-step methods)",
    "step_size": "longest step taken (s)",
    "min_step_size": "shortest step taken (s)",
    "order": "order of accuracy of the method (int)",
    "stages_per_step": "stages of a composed step (int; 1, 3 or 7)",
    "rtol": "relative tolerance (adaptive methods)",
    "atol": "absolute tolerance (adaptive methods)",
    "solver": "scipy.integrate.solve_ivp method (adaptive methods)",
    "evaluations": "right-hand-side evaluations (adaptive methods, int)",
    "status": "solve_ivp status (adaptive propagation, int)",
    "message": "solver message (adaptive methods)",
    "torque_calls": "calls of a torque model evaluated in Python (int)",
    "max_newton_iterations": "most Newton iterations of one implicit step (int)",
    "regime": "motion regime of an exact solution (e.g. 'symmetric', 'rotating')",
    "frame": "axes of a prescribed angular velocity ('body' or 'space')",
    "omega_input": "kind of prescribed angular velocity ('constant', 'callable', 'samples')",
    "interpolation": "interpolation of sampled angular velocities",
    "chunks": "number of pieces a long run was split into (int)",
    "closed_form": "name of the closed-form solution used (e.g. 'coning', 'jacobi')",
    "motion_type": "kind of motion of a closed form (e.g. a Lagrange top's nutation type)",
    "path": "which implementation ran (e.g. compiled kernel or solve_ivp fallback)",
}


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
        Rotational kinetic energy ``T = w^T J w / 2`` (theory §8).
    momentum : ndarray, shape (n, 3) or (n, N, 3), optional
        Angular momentum ``K = R J w`` in space axes (theory §8, §10).
    info : mapping
        Read-only details of the method, with the keys of :data:`INFO_KEYS`:
        ``steps``, ``step_size``, ``min_step_size``, ``order``,
        ``stages_per_step``, ``rtol``, ``atol``, ``solver``, ``evaluations``,
        ``status``, ``message``, ``torque_calls``, ``max_newton_iterations``,
        ``regime``, ``frame``, ``omega_input``, ``interpolation``, ``chunks``,
        ``closed_form``, ``motion_type``, ``path``
        (each method sets those that apply).
    position : ndarray, shape (n, 3) or (n, N, 3), optional
        Translational part: position of the body's reference point (or a
        particle) in space axes (m).
    velocity : ndarray, shape (n, 3) or (n, N, 3), optional
        Its velocity in space axes (m/s).

    Notes
    -----
    Frozen and picklable (ensembles send trajectories between processes); the
    arrays are read-only.

    Examples
    --------
    >>> import numpy as np, poinsot
    >>> t = np.linspace(0.0, 1.0, 3)
    >>> tr = Trajectory(t, poinsot.Rotation.identity((3,)), np.zeros((3, 3)), "none")
    >>> tr.quat.shape
    (3, 4)
    >>> import pickle
    >>> pickle.loads(pickle.dumps(tr)).omega.shape
    (3, 3)
    """

    t: np.ndarray
    rotation: Rotation
    omega: np.ndarray
    method: str
    energy: np.ndarray | None = None
    momentum: np.ndarray | None = None
    info: Mapping[str, Any] = field(default_factory=dict)
    position: np.ndarray | None = None
    velocity: np.ndarray | None = None

    def __reduce__(self):
        # MappingProxyType does not pickle: rebuild from a plain dict
        args = (self.t, self.rotation, self.omega, self.method, self.energy, self.momentum)
        return (_rebuild, (args, dict(self.info), self.position, self.velocity))

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
            "position": (*self.rotation.shape, 3),
            "velocity": (*self.rotation.shape, 3),
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


def _rebuild(args, info, position, velocity) -> Trajectory:
    return Trajectory(*args, info=info, position=position, velocity=velocity)


def _relative(diff: np.ndarray, ref: np.ndarray) -> float:
    """Largest ``diff / ref``, using ``diff`` itself where the reference is zero."""
    ref = np.broadcast_to(ref, diff.shape)
    scaled = np.divide(diff, ref, out=np.array(diff, dtype=float), where=ref != 0)
    return float(np.max(scaled))
