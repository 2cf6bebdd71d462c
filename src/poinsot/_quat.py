"""Small unvalidated quaternion helpers for the integrators: the one place for each.

Arrays ``(..., 4)`` of scalar-first quaternions ``(w, x, y, z)`` and vectors
``(..., 3)``; inputs are trusted (validated float64 arrays), outputs broadcast
like NumPy. The public, validated operations are in
:mod:`poinsot.rotations.quaternion`; the compiled products in
:mod:`poinsot.rotations._kernels`. Every NumPy-level integrator
(``simulate``, ``propagate``, ``FreeRigidBody``) takes its small helpers from here:

- :func:`pure` ``(0, v)``; :func:`conj` ``L~ = (l0, -l)``;
- :func:`mul` ``P o Q`` and :func:`rotate` ``L o (0, v) o L~`` (compiled kernels);
- :func:`normalize` ``L / |L|`` (non-zero ``L``);
- :func:`axis_angle` ``(cos(f/2), sin(f/2) e)``; :func:`axis_angle_principal`
  the same about body axis ``i``;
- :func:`from_gibbs` (Cayley map) ``(1, g) / sqrt(1 + g.g)`` for the Gibbs vector
  ``g = tan(f/2) e``; :func:`from_rotvec` ``exp((0, v)/2)``;
- :func:`attitude_distance` the angle of ``R_ref^-1 R``, ``2 atan2(|l|, |l0|)`` of
  ``L_ref~ o L`` (accurate at every angle, unlike ``arccos``).
"""

from __future__ import annotations

import numpy as np

from .rotations._lazy import kernels
from .rotations.quaternion import conjugate_array
from .rotations.rodrigues import quat_from_gibbs
from .rotations.rotvec import angle_from_quat, quat_from_rotvec

__all__ = [
    "pure",
    "conj",
    "mul",
    "rotate",
    "normalize",
    "axis_angle",
    "axis_angle_principal",
    "from_gibbs",
    "from_rotvec",
    "to_body",
    "up_body",
    "gravity_potential",
    "attitude_distance",
]

_CONJ = np.array([1.0, -1.0, -1.0, -1.0])


def pure(v: np.ndarray) -> np.ndarray:
    """The pure quaternion ``(0, v)`` of vectors ``(..., 3)``.

    >>> pure(np.array([1.0, 2.0, 3.0]))
    array([0., 1., 2., 3.])
    """
    v = np.asarray(v, dtype=np.float64)
    out = np.zeros(v.shape[:-1] + (4,))
    out[..., 1:] = v
    return out


def conj(q: np.ndarray) -> np.ndarray:
    """``L~ = (l0, -l)``.

    >>> conj(np.array([1.0, 2.0, 3.0, 4.0]))
    array([ 1., -2., -3., -4.])
    """

    return conjugate_array(q)


def mul(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Hamilton product ``P o Q`` (theory §1), compiled kernel, broadcasting."""

    out: np.ndarray = kernels().qmul(p, q)  # the lazily loaded kernel module is untyped
    return out


def rotate(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``L o (0, v) o L~`` for unit ``L``: body components -> space components."""

    out: np.ndarray = kernels().qrot(q, v)
    return out


def normalize(q: np.ndarray) -> np.ndarray:
    """``q / |q|`` for non-zero quaternions (no checks; column sums beat einsum here).

    >>> normalize(np.array([0.0, 3.0, 0.0, 4.0]))
    array([0. , 0.6, 0. , 0.8])
    """
    f = q.reshape(-1, 4)
    n2 = f[:, 0] * f[:, 0]
    for i in (1, 2, 3):
        n2 = n2 + f[:, i] * f[:, i]
    return (f * (1.0 / np.sqrt(n2))[:, None]).reshape(q.shape)


def axis_angle(axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Unit quaternions ``(cos(f/2), sin(f/2) e)`` of rotations by ``angle`` (...) about
    unit ``axis`` (..., 3) (radians, right-handed).

    >>> axis_angle(np.array([0.0, 0.0, 1.0]), np.pi).round(12) + 0.0
    array([0., 0., 0., 1.])
    """
    h = 0.5 * np.asarray(angle, dtype=np.float64)
    s = np.sin(h)[..., None] * axis
    return np.concatenate([np.broadcast_to(np.cos(h)[..., None], s.shape[:-1] + (1,)), s], -1)


def axis_angle_principal(angle: np.ndarray, i: int) -> np.ndarray:
    """:func:`axis_angle` about body axis ``e_i`` (``i`` in 0, 1, 2) for angles (...)."""
    h = 0.5 * np.asarray(angle, dtype=np.float64)
    out = np.zeros(h.shape + (4,))
    out[..., 0] = np.cos(h)
    out[..., 1 + i] = np.sin(h)
    return out


def from_gibbs(g: np.ndarray) -> np.ndarray:
    """Cayley map: the unit quaternion ``(1, g) / sqrt(1 + g.g)`` of Gibbs vectors
    ``g = tan(f/2) e`` (..., 3).

    >>> from_gibbs(np.array([0.0, 0.0, 1.0])).round(6)
    array([0.707107, 0.      , 0.      , 0.707107])
    """

    return quat_from_gibbs(g)


def from_rotvec(v: np.ndarray) -> np.ndarray:
    """``exp((0, v) / 2)``: the unit quaternion of rotation vectors ``v = f e`` (..., 3)."""

    return quat_from_rotvec(v)


def to_body(quat: np.ndarray, v_space: np.ndarray) -> np.ndarray:
    """``R^T v``: space components -> body components, for unit ``quat`` (..., 4) and
    vectors (..., 3), broadcast."""

    shape = np.broadcast_shapes(quat.shape[:-1], v_space.shape[:-1])
    return kernels().qrot(
        np.broadcast_to(quat * _CONJ, shape + (4,)), np.broadcast_to(v_space, shape + (3,))
    )


def up_body(quat: np.ndarray) -> np.ndarray:
    """``gamma = R^T e_z``, the upward vertical in body axes (third row of ``R``)."""
    return to_body(quat, np.array([0.0, 0.0, 1.0]))


def gravity_potential(quat: np.ndarray, moment: np.ndarray) -> np.ndarray:
    """``V = m g z_c = gamma . (m g c)`` (J) of gravity about a fixed point (theory §10):
    ``moment = m g c`` (N m) with ``c`` the centre of mass in body axes.

    >>> q = np.array([np.cos(np.pi / 6), np.sin(np.pi / 6), 0.0, 0.0])   # 60 deg about x
    >>> round(float(gravity_potential(q, np.array([0.0, 0.0, 2.0]))), 12)  # 2 cos(60 deg)
    1.0
    """
    return np.einsum("...i,...i->...", up_body(quat), moment)


def attitude_distance(q_ref: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Angle (rad, in ``[0, pi]``) of the rotation ``R_ref^-1 R`` between two attitudes.

    ``2 atan2(|l|, |l0|)`` of the relative quaternion ``L_ref~ o L`` (theory §2, §4):
    the geodesic distance ``|log(R_ref^-1 R)|``, accurate near 0 and near ``pi`` alike
    (``arccos`` of the scalar part loses half the digits near 0, ``arccos`` of the
    matrix trace near both). The same for ``L`` and ``-L``; a ratio of two parts of the
    same quaternion, so it does not need unit quaternions. Arrays (..., 4), broadcast.

    >>> q = np.array([np.cos(0.25), 0.0, 0.0, np.sin(0.25)])   # 0.5 rad about z
    >>> round(float(attitude_distance(np.array([1.0, 0, 0, 0]), -2.0 * q)), 15)
    0.5
    """

    return angle_from_quat(mul(conj(q_ref), q))
