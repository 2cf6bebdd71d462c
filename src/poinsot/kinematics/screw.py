"""Instantaneous screw axis (Chasles/Mozzi) and reduction of motions (theory §6).

The velocity field ``V(r) = V0 + w x (r - O)`` of a rigid body with ``w != 0``
is, at every instant, a rotation about an axis plus a slide along it (a
*twist*): the points of the instantaneous screw axis move with the smallest
speed ``|V . w| / |w|``, along ``w``. :func:`screw_axis` finds that axis;
:func:`reduce_motions` adds any number of simultaneous rotations about axes
through given points and translations, reduces them at a pole and classifies
the result (screw, rotation, translation or rest).

**Convention:** all vectors in one frame at the instant (m, m/s, rad/s).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validate import as_float_array, as_vec3
from .._vec import cross as _cross
from ..errors import InvalidInputError
from .fields import _as_list, _broadcast_shape, _scalar

__all__ = ["Screw", "screw_axis", "ReducedMotion", "reduce_motions"]

#: Default absolute tolerance on ``|omega|`` (rad/s) below which
#: :func:`screw_axis` declares the motion a translation.
OMEGA_ATOL = 1e-12

#: Default relative tolerance of :func:`reduce_motions` (see its Notes).
REDUCE_RTOL = 1e-10


@dataclass(frozen=True, eq=False)
class Screw:
    """Instantaneous screw axis of a rigid-body velocity field.

    Attributes
    ----------
    point : ndarray, shape (..., 3)
        The point of the axis nearest the reference point (the ``pole`` of
        :func:`screw_axis` and of :func:`reduce_motions`).
    direction : ndarray, shape (..., 3)
        Unit vector along ``omega``.
    parameter : ndarray, shape (...)
        Screw parameter (pitch per radian) ``lam = (V . w) / |w|^2``, in m/rad:
        points on the axis move with velocity ``lam w``. Positive for a
        right-handed screw.
    min_speed : ndarray, shape (...)
        Smallest speed of the body's points, ``|V . w| / |w|``, reached on the axis.
    """

    point: np.ndarray
    direction: np.ndarray
    parameter: np.ndarray
    min_speed: np.ndarray

    def closest_point(self, point: ArrayLike) -> FloatArray:
        """The point of the axis nearest ``point`` (shape ``(..., 3)``)."""
        x = as_vec3(point, "point")
        d = self.direction
        return self.point + np.einsum("...i,...i->...", x - self.point, d)[..., None] * d


def _norm_dir(omega: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(|w|, w/|w|)`` scaled by the largest component: no overflow or underflow in w.w."""
    m = np.max(np.abs(omega), axis=-1, initial=0.0)
    u = omega / np.where(m > 0, m, 1.0)[..., None]
    un = np.sqrt(np.einsum("...i,...i->...", u, u))
    return m * un, u / np.where(un > 0, un, 1.0)[..., None]


def _screw(v0: np.ndarray, omega: np.ndarray, origin: np.ndarray) -> Screw:
    """Kernel: screw of the field ``v0 + w x (r - origin)``, ``w != 0``.

    Written with the unit direction ``e = w/|w|`` (``point = origin + e x v0/|w|``,
    ``lam = v0.e/|w|``) so that any scale of ``w`` and ``v0`` works.
    """
    wn, e = _norm_dir(omega)
    ve = np.einsum("...i,...i->...", v0, e)
    point = origin + _cross(e, v0) / wn[..., None]
    shape = np.broadcast_shapes(v0.shape, omega.shape, origin.shape)
    return Screw(
        point=np.broadcast_to(point, shape).copy(),
        direction=np.broadcast_to(e, shape).copy(),
        parameter=np.broadcast_to(ve / wn, shape[:-1]).copy(),
        min_speed=np.broadcast_to(np.abs(ve), shape[:-1]).copy(),
    )


def screw_axis(
    v0: ArrayLike,
    omega: ArrayLike,
    *,
    pole: ArrayLike = (0.0, 0.0, 0.0),
    atol: float = OMEGA_ATOL,
) -> Screw:
    """Instantaneous screw axis of a rigid body (Chasles/Mozzi, theory §6).

    Parameters
    ----------
    v0 : array_like, shape (..., 3)
        Velocity of the body point at ``pole``.
    omega : array_like, shape (..., 3)
        Angular velocity of the body; must be non-zero.
    pole : array_like, shape (..., 3), optional
        The reference point whose velocity is ``v0`` (as in
        :func:`velocity_field`); default the coordinate origin.
        :attr:`Screw.point` is the point of the axis nearest it.
    atol : float, optional
        ``|omega| <= atol`` (rad/s) counts as zero. Default ``1e-12``.

    Returns
    -------
    Screw
        ``point = pole + (w x v0) / |w|^2``, ``direction = w / |w|``,
        ``parameter = (v0 . w) / |w|^2``, ``min_speed = |v0 . w| / |w|``.

    Raises
    ------
    InvalidInputError
        If ``|omega| <= atol`` somewhere: a translation has no axis (use
        :func:`reduce_motions`, which classifies it).

    Notes
    -----
    The axis is the set of points ``r`` with ``v0 + w x (r - pole) = lam w``.
    ``V . w`` is the same at every point of the body, so any point's velocity
    can be given as ``v0`` if ``pole`` is that point.

    **Convention:** all vectors in one frame at the instant (m, m/s, rad/s).

    Examples
    --------
    A body turning at 2 rad/s about the vertical line through (1, 0, 0) while
    rising at 0.5 m/s; the origin moves with ``V0 = w x (O - P) + 0.5 e_z``:

    >>> from poinsot.kinematics import screw_axis
    >>> s = screw_axis([0, -2, 0.5], [0, 0, 2])
    >>> s.point + 0.0, s.direction + 0.0
    (array([1., 0., 0.]), array([0., 0., 1.]))
    >>> float(s.parameter), float(s.min_speed)
    (0.25, 0.5)
    """
    v0 = as_vec3(v0, "v0")
    omega = as_vec3(omega, "omega")
    origin = as_vec3(pole, "pole")
    _broadcast_shape({"v0": v0, "omega": omega, "pole": origin})
    atol = _scalar(atol, "atol")
    wn = _norm_dir(omega)[0]
    if np.any(wn <= atol):
        raise InvalidInputError(
            f"Expected `omega` to be non-zero (|omega| > {atol:g}), got |omega| = "
            f"{float(np.min(wn)):g}: a pure translation has no screw axis; "
            "use reduce_motions to classify the motion."
        )
    return _screw(v0, omega, origin)


@dataclass(frozen=True, eq=False)
class ReducedMotion:
    """A set of simultaneous rotations and translations reduced at a pole.

    Attributes
    ----------
    omega : ndarray, shape (3,)
        Resultant angular velocity ``w = sum w_i``.
    velocity : ndarray, shape (3,)
        Velocity of the body point at the pole, ``v = sum OP_i x w_i + sum v_k``.
    pole : ndarray, shape (3,)
        The pole ``O``.
    kind : str
        The simplest equivalent motion: ``"screw"`` (``w != 0``, ``v . w != 0``),
        ``"rotation"`` (``w != 0``, ``v . w = 0``: a rotation about an axis),
        ``"translation"`` (``w = 0``, ``v != 0``; e.g. a couple of rotations)
        or ``"rest"``.
    screw : Screw or None
        The axis (with ``parameter`` and ``min_speed`` exactly 0 for a
        rotation) when ``kind`` is
        ``"screw"`` or ``"rotation"``, else ``None``.
    """

    omega: np.ndarray
    velocity: np.ndarray
    pole: np.ndarray
    kind: str
    screw: Screw | None

    def velocity_at(self, point: ArrayLike) -> FloatArray:
        """Velocity ``v + w x (point - pole)`` of the body point at ``point``."""
        r = as_vec3(point, "point")
        return self.velocity + _cross(self.omega, r - self.pole)


def _as_single(v: object, name: str) -> np.ndarray:
    a = as_float_array(v, name)
    if a.shape != (3,):
        raise InvalidInputError(f"Expected `{name}` to have shape (3,), got {a.shape}.")
    return a


def reduce_motions(
    rotations: Sequence[tuple[ArrayLike, ArrayLike]] = (),
    translations: Sequence[ArrayLike] = (),
    *,
    pole: ArrayLike = (0.0, 0.0, 0.0),
    rtol: float = REDUCE_RTOL,
    atol: float = 0.0,
) -> ReducedMotion:
    """Reduce simultaneous rotations and translations to the simplest motion (theory §6).

    Parameters
    ----------
    rotations : sequence of (omega_i, P_i)
        Angular velocities ``omega_i`` (shape (3,)) about axes through the
        points ``P_i`` (shape (3,)).
    translations : sequence of array_like, shape (3,)
        Translation velocities ``v_k``.
    pole : array_like, shape (3,), optional
        The reduction point ``O`` (default the coordinate origin).
    rtol, atol : float, optional
        Tolerances for the classification (see Notes).

    Returns
    -------
    ReducedMotion
        ``w = sum w_i``, ``v = sum OP_i x w_i + sum v_k`` (the velocity of the
        body point at ``O``), the ``kind`` and the ``screw`` (its ``point`` is
        the point of the axis nearest ``O``).

    Notes
    -----
    The velocity at ``O`` of a rotation ``w_i`` about an axis through ``P_i``
    is ``w_i x (O - P_i) = OP_i x w_i``. The classification compares with the
    size of the data, so that cancellations are recognised despite rounding:
    ``w`` counts as zero if ``|w| <= rtol * sum |w_i| + atol``; ``v`` (when
    ``w = 0``) if ``|v| <= rtol * S + atol`` and the slide ``|v . w| / |w|``
    (when ``w != 0``) if it is ``<= rtol * S + atol``, with
    ``S = sum |OP_i| |w_i| + sum |v_k|``. ``omega`` and ``velocity`` are
    returned as summed (a residual of rounding size is kept, not zeroed).

    **Convention:** all vectors in one frame at the instant (m, m/s, rad/s).

    Examples
    --------
    Two equal and opposite rotations about parallel axes (a couple of
    rotations) are a translation:

    >>> from poinsot.kinematics import reduce_motions
    >>> m = reduce_motions([([0, 0, 1], [0, 0, 0]), ([0, 0, -1], [1, 0, 0])])
    >>> m.kind, m.velocity + 0.0
    ('translation', array([0., 1., 0.]))

    Rotations about two axes that meet at (1, 1, 0) are a rotation about an
    axis through that point:

    >>> m = reduce_motions([([0, 0, 1], [1, 1, 5]), ([1, 0, 0], [0, 1, 0])])
    >>> m.kind, m.screw.closest_point([1, 1, 0]).round(12) + 0.0
    ('rotation', array([1., 1., 0.]))
    """
    pole = _as_single(pole, "pole")
    rtol = _scalar(rtol, "rtol")
    atol = _scalar(atol, "atol")
    omega = np.zeros(3)
    velocity = np.zeros(3)
    w_scale = 0.0
    v_scale = 0.0
    rotations = _as_list(rotations, "rotations", "a sequence of (omega, point) pairs")
    translations = _as_list(translations, "translations", "a sequence of 3-vectors")
    for i, item in enumerate(rotations):
        try:
            w_i, p_i = item
        except (TypeError, ValueError):
            raise InvalidInputError(
                f"Expected `rotations[{i}]` to be a pair (omega, point), got {item!r}."
            ) from None
        w_i = _as_single(w_i, f"rotations[{i}][0]")
        op = _as_single(p_i, f"rotations[{i}][1]") - pole
        omega = omega + w_i
        velocity = velocity + np.cross(op, w_i)
        w_scale += float(np.linalg.norm(w_i))
        v_scale += float(np.linalg.norm(op) * np.linalg.norm(w_i))
    for k, v_k in enumerate(translations):
        v_k = _as_single(v_k, f"translations[{k}]")
        velocity = velocity + v_k
        v_scale += float(np.linalg.norm(v_k))

    wn = float(np.linalg.norm(omega))
    tol_v = rtol * v_scale + atol
    screw = None
    if wn <= rtol * w_scale + atol:
        kind = "rest" if float(np.linalg.norm(velocity)) <= tol_v else "translation"
    else:
        slide = abs(float(velocity @ omega)) / wn
        if slide <= tol_v:
            kind = "rotation"
            # drop the rounding-level slide: the axis of a rotation has parameter 0
            axis = _screw(velocity - (velocity @ omega) / wn**2 * omega, omega, pole)
            screw = replace(axis, parameter=np.zeros(()), min_speed=np.zeros(()))
        else:
            kind = "screw"
            screw = _screw(velocity, omega, pole)
    return ReducedMotion(omega=omega, velocity=velocity, pole=pole, kind=kind, screw=screw)
