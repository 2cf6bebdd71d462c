"""so(3) helpers and the matrix faces of the quaternion product (docs/theory.md §1, §2).

``hat``/``vee`` between vectors and skew-symmetric matrices, the matrix exponential
and logarithm of so(3) (through the rotation vector: exact near 0 and near pi), the
4x4 matrices of left and right quaternion multiplication, and the eigen-structure of
a rotation matrix. Shapes broadcast over leading dimensions.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validate import as_trailing
from .._vec import hat as _hat
from ..errors import InvalidInputError
from .rotation import Rotation

__all__ = [
    "hat",
    "vee",
    "expm_so3",
    "logm_so3",
    "quat_left_matrix",
    "quat_right_matrix",
    "rotation_eigen",
    "RotationEigen",
]

#: Largest ``max |W + W^T|`` accepted by :func:`vee` and :func:`expm_so3` (relative to
#: ``max |W|``): the matrix must be skew-symmetric.
SKEW_RTOL = 1e-12


def hat(v: ArrayLike) -> FloatArray:
    """The skew matrix ``v^`` (..., 3, 3) with ``v^ u = v x u`` (theory §2).

    Examples
    --------
    >>> hat([1.0, 2.0, 3.0])
    array([[ 0., -3.,  2.],
           [ 3.,  0., -1.],
           [-2.,  1.,  0.]])
    """
    return _hat(as_trailing(v, "v", (3,)))


def vee(matrix: ArrayLike) -> FloatArray:
    """The vector ``v`` (..., 3) of a skew matrix ``v^`` (the inverse of :func:`hat`).

    Raises :class:`~poinsot.InvalidInputError` if ``matrix`` is not skew-symmetric
    (``|W + W^T| > 1e-12 |W|``).

    Examples
    --------
    >>> vee(hat([1.0, 2.0, 3.0]))
    array([1., 2., 3.])
    """
    w = as_trailing(matrix, "matrix", (3, 3))
    sym = np.abs(w + np.swapaxes(w, -1, -2)).max(axis=(-2, -1), initial=0.0)
    scale = np.abs(w).max(axis=(-2, -1), initial=0.0)
    if np.any(sym > SKEW_RTOL * np.maximum(scale, 1e-300)):
        raise InvalidInputError(
            f"Expected `matrix` to be skew-symmetric, got |W + W^T| up to {float(sym.max()):.3g}."
        )
    return 0.5 * np.stack(
        [w[..., 2, 1] - w[..., 1, 2], w[..., 0, 2] - w[..., 2, 0], w[..., 1, 0] - w[..., 0, 1]],
        axis=-1,
    )


def expm_so3(matrix: ArrayLike) -> FloatArray:
    """``exp(W)`` (..., 3, 3) of skew matrices ``W = phi^``: the rotation by ``|phi|``
    about ``phi`` (Rodrigues, theory §2), computed through the quaternion (exact near 0
    and near pi).

    Examples
    --------
    >>> expm_so3(hat([0.0, 0.0, np.pi / 2])).round(12) + 0.0
    array([[ 0., -1.,  0.],
           [ 1.,  0.,  0.],
           [ 0.,  0.,  1.]])
    """
    return Rotation.from_rotvec(vee(matrix)).as_matrix()


def logm_so3(matrix: ArrayLike) -> FloatArray:
    """The principal logarithm ``phi^`` (..., 3, 3) of rotation matrices (``|phi| <= pi``;
    at exactly ``pi`` either sign of ``phi`` is a logarithm). Accurate near 0 and near
    pi (through the quaternion, not ``arccos((tr R - 1)/2)``).

    Examples
    --------
    >>> bool(np.allclose(logm_so3(expm_so3(hat([0.1, -0.2, 0.3]))), hat([0.1, -0.2, 0.3])))
    True
    """
    return _hat(Rotation.from_matrix(matrix).as_rotvec())


def quat_left_matrix(q: ArrayLike) -> FloatArray:
    """``L(q)`` (..., 4, 4) with ``q o p = L(q) p`` (Hamilton product, scalar first,
    theory §1).

    Examples
    --------
    >>> from poinsot.quaternion import multiply
    >>> q, p = np.array([0.5, 0.5, -0.5, 0.5]), np.array([1.0, 2.0, 3.0, 4.0])
    >>> bool(np.allclose(quat_left_matrix(q) @ p, multiply(q, p)))
    True
    """
    w, x, y, z = np.moveaxis(as_trailing(q, "q", (4,)), -1, 0)
    rows = [[w, -x, -y, -z], [x, w, -z, y], [y, z, w, -x], [z, -y, x, w]]
    return np.stack([np.stack(r, axis=-1) for r in rows], axis=-2)


def quat_right_matrix(q: ArrayLike) -> FloatArray:
    """``R(q)`` (..., 4, 4) with ``p o q = R(q) p`` (Hamilton product, scalar first,
    theory §1); ``L(p)`` and ``R(q)`` commute.

    Examples
    --------
    >>> from poinsot.quaternion import multiply
    >>> q, p = np.array([0.5, 0.5, -0.5, 0.5]), np.array([1.0, 2.0, 3.0, 4.0])
    >>> bool(np.allclose(quat_right_matrix(q) @ p, multiply(p, q)))
    True
    """
    w, x, y, z = np.moveaxis(as_trailing(q, "q", (4,)), -1, 0)
    rows = [[w, -x, -y, -z], [x, w, z, -y], [y, -z, w, x], [z, y, -x, w]]
    return np.stack([np.stack(r, axis=-1) for r in rows], axis=-2)


@dataclass(frozen=True)
class RotationEigen:
    """The eigen-structure of rotation matrices (:func:`rotation_eigen`).

    Attributes
    ----------
    eigenvalues : ndarray, shape (..., 3), complex
        ``(1, e^{i f}, e^{-i f})``.
    axis : ndarray, shape (..., 3)
        Unit eigenvector of 1 (the axis; ``e_z`` by convention for the identity).
    angle : ndarray, shape (...)
        ``f`` in ``[0, pi]`` (rad).
    plane : ndarray, shape (..., 2, 3)
        Orthonormal ``u, v = axis x u`` spanning the invariant plane, turned by ``f``:
        ``R u = cos f u + sin f v``; ``u +- i v`` are the eigenvectors of
        ``e^{-+i f}``.
    """

    eigenvalues: np.ndarray
    axis: FloatArray
    angle: FloatArray
    plane: FloatArray


def rotation_eigen(matrix: ArrayLike) -> RotationEigen:
    """Eigenvalues ``1, e^{+-i f}``, the axis and the invariant plane of rotation
    matrices (..., 3, 3) (theory §2: Euler's theorem).

    Examples
    --------
    >>> e = rotation_eigen(expm_so3(hat([0.0, 0.0, np.pi / 3])))
    >>> e.axis, round(float(e.angle), 12), e.eigenvalues.round(6)
    (array([0., 0., 1.]), 1.047197551197, array([1. +0.j     , 0.5+0.866025j, 0.5-0.866025j]))
    """
    axis, angle = Rotation.from_matrix(matrix).as_axis_angle()
    angle = np.asarray(angle, dtype=float)
    axis = np.where((angle > 0)[..., None], axis, [0.0, 0.0, 1.0])
    # u: the unit of axis x (the basis vector least along the axis), orthogonal to it
    k = np.argmin(np.abs(axis), axis=-1)
    base = np.eye(3)[k]
    u = np.cross(axis, base)
    u = u / np.linalg.norm(u, axis=-1, keepdims=True)
    v = np.cross(axis, u)
    ones = np.ones(angle.shape, dtype=complex)
    values = np.stack([ones, np.exp(1j * angle), np.exp(-1j * angle)], axis=-1)
    return RotationEigen(values, axis, angle, np.stack([u, v], axis=-2))
