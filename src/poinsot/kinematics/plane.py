"""Plane motion of a rigid body (docs/theory.md §6): the instantaneous centres of
velocities and of accelerations, and the fixed and moving centrodes.

A plane motion is given by a point ``A`` of the body (its position, velocity and
acceleration, 2-D vectors ``(..., 2)`` in the fixed plane's axes, m, m/s, m/s^2), the
angular velocity ``omega`` and angular acceleration ``eps`` about the normal ``k``
(rad/s, rad/s^2, counter-clockwise positive). The velocity field is
``v_B = v_A + omega k x AB`` and the acceleration field
``a_B = a_A + eps k x AB - omega^2 AB``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validate import as_float_array, as_trailing, batch_shape

__all__ = ["velocity_center", "acceleration_center", "centrodes", "Centrodes"]


def _perp(v: FloatArray) -> FloatArray:
    """``k x v`` for plane vectors: ``(-v_y, v_x)``."""
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


def velocity_center(point: ArrayLike, velocity: ArrayLike, omega: ArrayLike) -> FloatArray:
    """The instantaneous centre of velocities ``P = A + k x v_A / omega`` (m, (..., 2)).

    The one point of the moving plane at rest at this instant; the body turns about
    it. For ``omega = 0`` (an instantaneous translation) the centre is at infinity:
    ``inf`` components (``nan`` if ``v_A = 0`` too: rest, every point is a centre).

    Examples
    --------
    A wheel of radius 0.5 m rolling right at 2 m/s turns clockwise at 4 rad/s: the
    contact point is the centre.

    >>> velocity_center([0.0, 0.5], [2.0, 0.0], -4.0)
    array([0., 0.])
    """
    a = as_trailing(point, "point", (2,))
    v = as_trailing(velocity, "velocity", (2,))
    w = as_float_array(omega, "omega")
    batch_shape(point=(a, 1), velocity=(v, 1), omega=(w, 0))
    with np.errstate(divide="ignore", invalid="ignore"):
        return a + _perp(v) / w[..., None]


def acceleration_center(
    point: ArrayLike, acceleration: ArrayLike, omega: ArrayLike, eps: ArrayLike
) -> FloatArray:
    """The instantaneous centre of accelerations (m, (..., 2)):
    ``Q = A + (eps k x a_A + omega^2 a_A) / (eps^2 + omega^4)``.

    The one point with zero acceleration (``a_Q = 0`` solves
    ``eps k x AQ - omega^2 AQ = -a_A``); ``inf`` components when ``omega = eps = 0``
    and ``a_A != 0`` (a translation: no point is at rest in acceleration), ``nan`` when
    ``a_A = 0`` too (every point is such a centre), as :func:`velocity_center`.

    Examples
    --------
    The wheel rolling at constant speed: its centre has no acceleration.

    >>> acceleration_center([0.0, 0.5], [0.0, 0.0], -4.0, 0.0)
    array([0. , 0.5])
    >>> acceleration_center([0.0, 0.5], [1.0, 0.0], 0.0, 0.0)   # a translation
    array([inf, inf])
    """
    a = as_trailing(point, "point", (2,))
    acc = as_trailing(acceleration, "acceleration", (2,))
    w = as_float_array(omega, "omega")
    e = as_float_array(eps, "eps")
    batch_shape(point=(a, 1), acceleration=(acc, 1), omega=(w, 0), eps=(e, 0))
    w, e = w[..., None], e[..., None]
    den = e * e + w**4
    with np.errstate(divide="ignore", invalid="ignore"):
        q = a + (e * _perp(acc) + w * w * acc) / den
    # 0/0 above when omega = eps = 0: the centre is at infinity unless a_A = 0 too
    moving = np.any(acc != 0.0, axis=-1, keepdims=True)
    return np.where(den == 0.0, np.where(moving, np.inf, np.nan), q)


@dataclass(frozen=True)
class Centrodes:
    """The centrodes of a plane motion (:func:`centrodes`).

    Attributes
    ----------
    fixed : ndarray, shape (n, ..., 2)
        The instantaneous centre in the fixed plane at each sample (the fixed
        centrode, m).
    moving : ndarray, shape (n, ..., 2)
        The same points in the body's axes (origin ``A``, turned by ``angle``): the
        moving centrode, which rolls without slipping on the fixed one (m).
    """

    fixed: FloatArray
    moving: FloatArray


def centrodes(
    point: ArrayLike, velocity: ArrayLike, angle: ArrayLike, omega: ArrayLike
) -> Centrodes:
    """The fixed and moving centrodes of a sampled plane motion (theory §6).

    Parameters
    ----------
    point, velocity : array_like, shape (n, ..., 2)
        Position and velocity of the body point ``A`` at each sample (m, m/s).
    angle : array_like, shape (n, ...)
        The body's angle (rad, counter-clockwise from the fixed x axis).
    omega : array_like, shape (n, ...)
        Its rate (rad/s).

    Returns
    -------
    Centrodes
        ``fixed = P(t)`` and ``moving = R(angle)^T (P(t) - A(t))``.

    Examples
    --------
    The rolling wheel (radius 0.5 m): the fixed centrode is the ground, the moving
    one the rim.

    >>> import numpy as np
    >>> th = np.linspace(0.0, 1.0, 5)          # the wheel turns clockwise by th
    >>> c = centrodes(np.stack([0.5 * th, 0.5 + 0 * th], -1), [[0.5, 0.0]] * 5, -th, -1.0)
    >>> bool(np.abs(c.fixed[:, 1]).max() < 1e-15)
    True
    >>> bool(np.allclose(np.linalg.norm(c.moving, axis=-1), 0.5))
    True
    """
    a = as_trailing(point, "point", (2,))
    v = as_trailing(velocity, "velocity", (2,))
    w = as_float_array(omega, "omega")
    f = as_float_array(angle, "angle")
    batch_shape(point=(a, 1), velocity=(v, 1), angle=(f, 0), omega=(w, 0))
    p = velocity_center(a, v, w)
    c, s = np.cos(f), np.sin(f)
    d = p - a
    moving = np.stack([c * d[..., 0] + s * d[..., 1], -s * d[..., 0] + c * d[..., 1]], axis=-1)
    return Centrodes(p, moving)
