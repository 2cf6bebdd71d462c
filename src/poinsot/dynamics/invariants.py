"""Kinetic and potential energy, angular momentum and the area integral (theory §8, §10).

The ONE place where poinsot computes the invariants of a rigid body turning
about its centre of mass or a fixed point: :func:`kinetic_energy`
``T = w . J w / 2``, :func:`angular_momentum` ``K = J w`` (body axes), and
:func:`invariants`, which adds the space momentum ``K_s = R K``, the potential
energy of a torque model (:mod:`poinsot.dynamics.torques`), the total energy
``E = T + V`` and the area integral ``K_s . e_z``. ``simulate``,
``FreeRigidBody``, the scenarios and the plots call these.

**Convention:** ``inertia`` about the centre of mass or the fixed point, in body
axes: principal moments ``(..., 3)`` (then body axes are principal axes) or a
tensor ``(..., 3, 3)``; ``omega`` in body axes (rad/s); the attitude maps body to
space components (``v_s = R v_b``), scalar-first quaternions. SI units: J,
kg m^2/s.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validate import as_rotation_quat, as_vec3, batch_shape, plain_vec3
from .._vec import length
from ..mass.tensor import _kinetic, _momentum, as_inertia, single_principal_moments
from ..rotations._lazy import kernels
from .torques import as_torque

if TYPE_CHECKING:
    from ..rotations.rotation import Rotation
    from .torques import TorqueModel

__all__ = ["kinetic_energy", "angular_momentum", "invariants", "Invariants"]


# ---------------------------------------------------------------------------
# Kernels (no validation): K = J w and T = w . J w / 2 live with the inertia tensor
# (poinsot.mass.tensor: mass sits below dynamics); imported here for the callers.
# ---------------------------------------------------------------------------


def _inertia(inertia: object) -> tuple[np.ndarray, bool]:
    return as_inertia(inertia, "inertia")


def _checked(inertia: object, omega: ArrayLike) -> tuple[np.ndarray, bool, np.ndarray]:
    j, principal = _inertia(inertia)
    w = as_vec3(omega, "omega")
    batch_shape(inertia=(j, 1 if principal else 2), omega=(w, 1))
    return j, principal, w


# ---------------------------------------------------------------------------
# Public
# ---------------------------------------------------------------------------


def kinetic_energy(inertia: ArrayLike, omega: ArrayLike) -> FloatArray | np.float64:
    """Rotational kinetic energy ``T = w^T J w / 2`` (theory §8).

    Parameters
    ----------
    inertia : array_like, shape (..., 3) or (..., 3, 3)
        Principal moments ``(A, B, C)`` or the inertia tensor, about the centre of
        mass or the fixed point, in body axes (kg m^2).
    omega : array_like, shape (..., 3)
        Angular velocity in body axes (rad/s).

    Returns
    -------
    ndarray, shape (...)
        ``T`` (J); in principal axes ``(A p^2 + B q^2 + C r^2) / 2``. Batch shapes
        broadcast.

    Notes
    -----
    For a body that also translates, Koenig's theorem adds ``m V_c^2 / 2``:
    :func:`poinsot.mass.kinetic_energy`.

    Examples
    --------
    >>> from poinsot.dynamics import kinetic_energy
    >>> float(kinetic_energy([1.0, 2.0, 3.0], [1.0, 1.0, 1.0]))
    3.0
    """
    j = single_principal_moments(inertia)
    w = None if j is None else plain_vec3(omega)
    if j is not None and w is not None:  # one state: same checks and operations, no array overhead
        return np.float64(
            0.5 * (w[0] * (j[0] * w[0]) + w[1] * (j[1] * w[1]) + w[2] * (j[2] * w[2]))
        )
    ja, principal, wa = _checked(inertia, omega)
    return _kinetic(ja, principal, wa)


def angular_momentum(inertia: ArrayLike, omega: ArrayLike) -> FloatArray:
    """Angular momentum in body axes, ``K = J w`` (theory §8).

    Parameters
    ----------
    inertia : array_like, shape (..., 3) or (..., 3, 3)
        Principal moments or tensor in body axes, about the centre of mass or
        the fixed point (kg m^2).
    omega : array_like, shape (..., 3)
        Angular velocity in body axes (rad/s).

    Returns
    -------
    ndarray, shape (..., 3)
        ``K`` in body axes (kg m^2/s); ``R K`` gives the space components (see
        :func:`invariants`).

    Examples
    --------
    >>> from poinsot.dynamics import angular_momentum
    >>> angular_momentum([1.0, 2.0, 3.0], [1.0, 1.0, 1.0])
    array([1., 2., 3.])
    >>> angular_momentum([[2.0, -1.0, 0.0], [-1.0, 2.0, 0.0], [0.0, 0.0, 3.0]], [1.0, 0, 0])
    array([ 2., -1.,  0.])
    """
    j, principal, w = _checked(inertia, omega)
    return _momentum(j, principal, w)


@dataclass(frozen=True, eq=False)
class Invariants:
    """Energies and angular momenta of a rigid body at one or many states.

    Attributes
    ----------
    kinetic : ndarray, shape (...)
        Kinetic energy ``T = w . J w / 2`` (J).
    potential : ndarray, shape (...), or None
        Potential energy ``V`` of the torque model (J); ``None`` when there is no
        torque model (free body) or the torque has no potential.
    energy : ndarray, shape (...)
        Total energy ``E = T + V`` (``T`` when ``potential`` is ``None``) (J).
    momentum_body : ndarray, shape (..., 3)
        ``K = J w`` in body axes (kg m^2/s).
    momentum_space : ndarray, shape (..., 3)
        ``K_s = R K`` in space axes (kg m^2/s).
    momentum_z : ndarray, shape (...)
        The area integral ``K_s . e_z`` (kg m^2/s): conserved under gravity
        along ``-z`` (theory §10) and for the free body.
    """

    kinetic: np.ndarray
    potential: np.ndarray | None
    energy: np.ndarray
    momentum_body: np.ndarray
    momentum_space: np.ndarray
    momentum_z: np.ndarray

    @property
    def momentum_norm(self) -> np.ndarray:
        """``|K|`` (kg m^2/s), the same in both frames."""

        return length(self.momentum_body)


def _invariants(
    j: np.ndarray, principal: bool, q: np.ndarray, w: np.ndarray, torque_model: TorqueModel | None
) -> Invariants:
    """Kernel of :func:`invariants` (validated arrays, a TorqueModel or None)."""
    k = _momentum(j, principal, w)
    t, ks = _kinetic_space(q, w, k)
    v = None if torque_model is None else torque_model.potential(q)
    energy = t if v is None else t + v
    return Invariants(
        kinetic=np.asarray(t),
        potential=None if v is None else np.asarray(v),
        energy=np.asarray(energy),
        momentum_body=k,
        momentum_space=ks,
        momentum_z=np.asarray(ks[..., 2]),
    )


def _kinetic_space(q: np.ndarray, w: np.ndarray, k: np.ndarray) -> tuple[Any, np.ndarray]:
    """``T = w.K / 2`` and ``K_s = q K q~`` from the body momentum ``K = J w`` (theory §8):
    the free body's invariants, written once for :func:`_invariants` and ``simulate``."""

    t = np.einsum("...i,...i->...", w, k)
    t *= 0.5  # in place: the same values as 0.5 * t, without a second array
    shape = np.broadcast_shapes(q.shape[:-1], k.shape[:-1])
    ks = kernels().qrot(np.broadcast_to(q, shape + (4,)), np.broadcast_to(k, shape + (3,)))
    return t, ks


def invariants(
    inertia: ArrayLike,
    rotation: Rotation | ArrayLike,
    omega: ArrayLike,
    *,
    torque: TorqueModel | ArrayLike | Callable[..., ArrayLike] | None = None,
) -> Invariants:
    """Energies and angular momenta of a rigid body (theory §8, §10): the one place.

    Parameters
    ----------
    inertia : array_like, shape (..., 3) or (..., 3, 3)
        Principal moments or tensor in body axes, about the point the body turns
        about (its centre of mass, or the fixed point of a top) (kg m^2).
    rotation : Rotation, scipy Rotation or array_like, shape (..., 4)
        Attitude, body -> space (``v_s = R v_b``), scalar-first quaternions.
    omega : array_like, shape (..., 3)
        Angular velocity in body axes (rad/s).
    torque : TorqueModel, array_like (3,), callable or None, optional
        The torque acting on the body (see :func:`poinsot.dynamics.as_torque`);
        its potential energy ``V`` enters ``potential`` and ``energy``. ``None``:
        a free body (``potential`` is ``None``, ``energy = T``).

    Returns
    -------
    Invariants
        ``kinetic`` ``T = w.J w/2``, ``potential`` ``V`` (``None`` if the torque
        has none), ``energy`` ``T + V``, ``momentum_body`` ``J w``,
        ``momentum_space`` ``R J w``, ``momentum_z`` ``(R J w)_z``. Leading
        shapes broadcast.

    Notes
    -----
    For a free body ``T``, ``K_s`` (hence ``|K|`` and ``K_z``) are constant;
    under gravity (``g`` along ``-z`` of space) about a fixed point ``E = T + V``
    and ``K_z`` are constant (theory §10).

    Examples
    --------
    >>> from poinsot.dynamics import invariants, GravityTorque
    >>> inv = invariants([1.0, 1.0, 0.5], [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 10.0],
    ...                  torque=GravityTorque(2.0, [0.0, 0.0, 0.1], g=10.0))
    >>> float(inv.kinetic), float(inv.potential), float(inv.energy), float(inv.momentum_z)
    (25.0, 2.0, 27.0, 5.0)
    """

    j, principal = _inertia(inertia)
    q = as_rotation_quat(rotation, "rotation")
    w = as_vec3(omega, "omega")
    batch_shape(inertia=(j, 1 if principal else 2), rotation=(q, 1), omega=(w, 1))
    model = as_torque(torque)
    return _invariants(j, principal, q, w, model)
