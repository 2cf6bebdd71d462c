"""Classical coning motion: a closed-form attitude and its body angular velocity.

Coning is the standard test of strapdown attitude algorithms (docs/theory.md §5):
the body ``z`` axis sweeps a cone of half-angle ``a`` at the rate ``W`` while the
attitude stays bounded, so any drift of an integrator is its coning error.

With ``Lc(t) = (cos a/2, sin a/2 cos W t, sin a/2 sin W t, 0)`` (scalar first,
body -> space), Poisson's equation ``w = 2 Lc~ o Lc'`` (docs/theory.md §5) gives the
body angular velocity ``w = (-W sin a sin W t, W sin a cos W t, -2 W sin^2(a/2))``.
A motion starting from any attitude ``L0`` is ``L(t) = L0 o Lc(0)~ o Lc(t)``: the
same body rates, since a constant left factor does not change ``Lc~ o Lc'``.
"""

from __future__ import annotations

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validate import as_float_array
from ..errors import InvalidInputError

__all__ = ["coning_quat", "coning_omega"]


def _args(half_angle: ArrayLike, rate: ArrayLike, t: ArrayLike) -> tuple[float, float, np.ndarray]:
    a, w = as_float_array(half_angle, "half_angle"), as_float_array(rate, "rate")
    for name, x in (("half_angle", a), ("rate", w)):
        if x.ndim:
            raise InvalidInputError(f"Expected `{name}` to be a real number, got shape {x.shape}.")
    return float(a), float(w), as_float_array(t, "t")


def coning_quat(half_angle: float, rate: float, t: ArrayLike) -> FloatArray:
    """Attitude of classical coning motion ``Lc(t)``, scalar-first quaternions.

    ``Lc(t) = (cos a/2, sin a/2 cos W t, sin a/2 sin W t, 0)`` (docs/theory.md §5).

    Parameters
    ----------
    half_angle : float
        Half-angle ``a`` of the cone swept by the body ``z`` axis (rad).
    rate : float
        Coning rate ``W`` (rad/s).
    t : array_like
        Times (s), any shape.

    Returns
    -------
    ndarray, shape ``t.shape + (4,)``
        Unit quaternions (w, x, y, z), body -> space (``v_space = L v_body``).

    Examples
    --------
    >>> from poinsot.kinematics import coning_quat
    >>> coning_quat(0.2, 3.0, [0.0]).round(4)
    array([[0.995 , 0.0998, 0.    , 0.    ]])
    """
    a, w, t = _args(half_angle, rate, t)
    c, s = np.cos(a / 2.0), np.sin(a / 2.0)
    phase = w * t
    return np.stack(
        [np.full_like(t, c), s * np.cos(phase), s * np.sin(phase), np.zeros_like(t)], axis=-1
    )


def coning_omega(half_angle: float, rate: float, t: ArrayLike) -> FloatArray:
    """Body angular velocity of :func:`coning_quat` (rad/s).

    ``w = (-W sin a sin W t, W sin a cos W t, -2 W sin^2(a/2))`` in body axes
    (docs/theory.md §5).

    Returns
    -------
    ndarray, shape ``t.shape + (3,)``

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.kinematics import coning_omega
    >>> coning_omega(np.pi / 2, 1.0, 0.0).round(6) + 0.0
    array([ 0.,  1., -1.])
    """
    a, w, t = _args(half_angle, rate, t)
    phase = w * t
    return np.stack(
        [
            -w * np.sin(a) * np.sin(phase),
            w * np.sin(a) * np.cos(phase),
            np.full_like(t, -2.0 * w * np.sin(a / 2.0) ** 2),
        ],
        axis=-1,
    )
