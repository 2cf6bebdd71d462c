"""Regular precession, the sleeping top and the gyroscope: array functions (docs/theory.md §10).

The closed-form rates of a heavy symmetric top about a fixed point (moments ``A``,
``C`` about it, ``m g l`` the signed gravity moment arm): the two rates of a regular
precession, the gyroscope approximation ``m g l / (C r)`` of the slow one,
Maievskii's critical spin of the sleeping top and the gyroscopic moment that
keeps a symmetric body in regular precession. The exact motion of the top is
:class:`poinsot.dynamics.LagrangeTop` (:mod:`poinsot.dynamics.lagrange_top`).

**Convention:** ``theta`` is the tilt of the symmetry axis from the *upward*
vertical (z-x-z Euler angles, docs/theory.md §3); rates in rad/s; SI units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._typing import ArrayLike, BoolArray, FloatArray
from .._validate import as_bool, as_float_array
from ..errors import InvalidInputError

__all__ = [
    "regular_precession_rates",
    "gyroscope_precession_rate",
    "critical_spin",
    "sleeping_top_stable",
    "GyroscopicMoment",
    "gyroscopic_moment",
]

_EPS = float(np.finfo(float).eps)


# ---------------------------------------------------------------------------
# Validation
# ---------------------------------------------------------------------------


def _moment_arrays(a: ArrayLike, c: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    av = as_float_array(a, "A")
    cv = as_float_array(c, "C")
    if np.any(av <= 0):
        raise InvalidInputError(
            f"Expected `A` to be positive (kg m^2), got {av[av <= 0].flat[0]!r}."
        )
    if np.any(cv <= 0):
        raise InvalidInputError(
            f"Expected `C` to be positive (kg m^2), got {cv[cv <= 0].flat[0]!r}."
        )
    if np.any(cv > 2.0 * av * (1.0 + 4 * _EPS)):
        raise InvalidInputError(
            "Expected `C` <= 2 `A` (triangle inequality A + B >= C of a rigid body)."
        )
    return av, cv


def _angle(
    x: ArrayLike, name: str, degrees: bool, *, lo: float | None = None, hi: Any = None
) -> np.ndarray:
    a = as_float_array(x, name)
    if degrees:
        a = np.deg2rad(a)
    if lo is not None and np.any((a < lo) | (a > hi)):
        unit = "degrees" if degrees else "rad"
        bad = float(
            np.rad2deg(a[(a < lo) | (a > hi)].flat[0])
            if degrees
            else a[(a < lo) | (a > hi)].flat[0]
        )
        raise InvalidInputError(
            f"Expected `{name}` in [0, pi] (the tilt of the symmetry axis from the upward "
            f"vertical), got {bad!r} {unit}."
        )
    return a


# ---------------------------------------------------------------------------
# Regular precession, sleeping top, gyroscope (array functions)
# ---------------------------------------------------------------------------


def regular_precession_rates(
    A: ArrayLike,
    C: ArrayLike,
    mgl: ArrayLike,
    theta: ArrayLike,
    spin: ArrayLike,
    *,
    degrees: bool = False,
) -> tuple[FloatArray | float, FloatArray | float]:
    """The two precession rates ``psi'`` of a regular precession of the heavy top.

    ``theta`` stays constant iff ``A psi'^2 cos(theta) - H psi' + m g l = 0``,
    ``H = C r`` (docs/theory.md §10):

    ``psi' = (H -+ sqrt(H^2 - 4 A m g l cos(theta))) / (2 A cos(theta))``.

    Parameters
    ----------
    A, C : array_like
        Equatorial and axial moments of inertia about the fixed point (kg m^2).
    mgl : array_like
        ``m g l`` (N m), ``l`` the signed distance from the fixed point to the
        centre of mass along the symmetry axis (negative: centre of mass below).
    theta : array_like
        Tilt of the symmetry axis from the upward vertical, in ``[0, pi]`` (rad, or
        degrees with ``degrees=True``).
    spin : array_like
        ``r``, the axial component of the angular velocity (rad/s).
    degrees : bool, optional
        ``theta`` in degrees.

    Returns
    -------
    slow, fast : ndarray
        The slow rate (the smaller ``|psi'|``, ``~ m g l / H`` for a fast top, see
        :func:`gyroscope_precession_rate`) and the fast one ``~ H / (A cos theta)``
        (rad/s). Written without cancellation: ``slow = 2 m g l / (H + sign(H)
        sqrt(D))``, ``fast = (H + sign(H) sqrt(D)) / (2 A cos theta)``. At
        ``theta = pi/2`` the fast rate is infinite (``+-inf``); with ``H = 0`` the
        two rates are ``+-sqrt(-m g l / (A cos theta))`` (returned as ``(+, -)``).

    Raises
    ------
    InvalidInputError
        If the rates do not exist, ``C^2 r^2 < 4 A m g l cos(theta)`` (the spin is
        too slow), or for unphysical moments or ``theta`` outside ``[0, pi]``.

    Examples
    --------
    >>> from poinsot.dynamics import regular_precession_rates, gyroscope_precession_rate
    >>> slow, fast = regular_precession_rates(2.0, 1.0, 4.0, 1.0, 50.0)
    >>> round(float(slow), 6), round(float(gyroscope_precession_rate(1.0, 4.0, 50.0)), 6)
    (0.080139, 0.08)
    """
    a, c = _moment_arrays(A, C)
    g = as_float_array(mgl, "mgl")
    th = _angle(theta, "theta", as_bool(degrees, "degrees"), lo=0.0, hi=math.pi)
    r = as_float_array(spin, "spin")
    a, c, g, th, r = np.broadcast_arrays(a, c, g, th, r)
    h = c * r
    u = np.cos(th)
    d = h * h - 4.0 * a * g * u
    if np.any(d < 0):
        i = np.flatnonzero(d < 0)[0]
        lhs, rhs = float(h.flat[i] ** 2), float(4 * a.flat[i] * g.flat[i] * u.flat[i])
        raise InvalidInputError(
            f"Expected a spin fast enough for a regular precession, C^2 r^2 >= 4 A m g l "
            f"cos(theta): got C^2 r^2 = {lhs!r} < {rhs!r} (no real psi' keeps theta constant)."
        )
    zero = (h == 0) & (g * u == 0) & (g != 0)
    if np.any(zero):
        raise InvalidInputError(
            "Expected `spin` != 0 or `theta` != pi/2: a non-spinning top with a horizontal "
            "axis cannot precess regularly (m g l != 0)."
        )
    sgn = np.where(h < 0, -1.0, 1.0)
    qq = 0.5 * (h + sgn * np.sqrt(d))
    with np.errstate(divide="ignore", invalid="ignore"):
        fast = np.where(u == 0, sgn * np.inf, qq / (a * u))
        slow = np.where(qq != 0, g / qq, 0.0)
        w = np.sqrt(np.abs(g / (a * np.where(u == 0, 1.0, u))))
    slow = np.where(h == 0, w, slow)
    fast = np.where(h == 0, -w, fast)
    return slow[()], fast[()]


def gyroscope_precession_rate(C: ArrayLike, mgl: ArrayLike, spin: ArrayLike) -> FloatArray | float:
    """The gyroscope approximation of the slow precession, ``psi' ~ m g l / (C r)``.

    The slow root of :func:`regular_precession_rates` for a fast top (``H = C r``
    large): ``psi'_slow = m g l / H (1 + A m g l cos(theta) / H^2 + ...)``
    (docs/theory.md §10).

    Parameters
    ----------
    C : array_like
        Axial moment about the fixed point (kg m^2).
    mgl : array_like
        ``m g l`` (N m).
    spin : array_like
        ``r`` (rad/s), non-zero.

    Returns
    -------
    ndarray
        ``m g l / (C r)`` (rad/s).

    Examples
    --------
    >>> from poinsot.dynamics import gyroscope_precession_rate
    >>> float(gyroscope_precession_rate(0.5, 2.0, 40.0))
    0.1
    """
    c = as_float_array(C, "C")
    g = as_float_array(mgl, "mgl")
    r = as_float_array(spin, "spin")
    if np.any(c <= 0):
        raise InvalidInputError("Expected `C` to be positive (kg m^2).")
    if np.any(r == 0):
        raise InvalidInputError(
            "Expected `spin` to be non-zero (the gyroscope approximation m g l / (C r))."
        )
    return (g / (c * r))[()]


def critical_spin(A: ArrayLike, C: ArrayLike, mgl: ArrayLike) -> FloatArray | float:
    """Maievskii's critical spin of the sleeping top, ``r_c = 2 sqrt(A m g l) / C``.

    The upright (sleeping) top is stable iff ``C^2 r^2 > 4 A m g l``
    (docs/theory.md §10); for ``m g l <= 0`` (centre of mass at or below the
    fixed point) it is stable at any spin and ``r_c = 0``.

    Parameters
    ----------
    A, C : array_like
        Equatorial and axial moments about the fixed point (kg m^2).
    mgl : array_like
        ``m g l`` (N m).

    Returns
    -------
    ndarray
        ``r_c`` (rad/s), ``>= 0``.

    Examples
    --------
    >>> from poinsot.dynamics import critical_spin
    >>> float(critical_spin(2.0, 1.0, 2.0))
    4.0
    """
    a, c = _moment_arrays(A, C)
    g = as_float_array(mgl, "mgl")
    return (2.0 * np.sqrt(np.maximum(a * g, 0.0)) / c)[()]


def sleeping_top_stable(
    A: ArrayLike, C: ArrayLike, mgl: ArrayLike, spin: ArrayLike
) -> bool | BoolArray:
    """Whether the upright (sleeping) top is stable: ``C^2 r^2 > 4 A m g l`` (Maievskii).

    Parameters
    ----------
    A, C : array_like
        Equatorial and axial moments about the fixed point (kg m^2).
    mgl : array_like
        ``m g l`` (N m).
    spin : array_like
        ``r`` (rad/s).

    Returns
    -------
    bool or ndarray of bool

    Examples
    --------
    >>> from poinsot.dynamics import sleeping_top_stable
    >>> bool(sleeping_top_stable(2.0, 1.0, 2.0, 4.1)), bool(sleeping_top_stable(2.0, 1.0, 2.0, 3.9))
    (True, False)
    """
    a, c = _moment_arrays(A, C)
    g = as_float_array(mgl, "mgl")
    r = as_float_array(spin, "spin")
    out = (c * r) ** 2 > 4.0 * a * g
    return bool(out) if out.ndim == 0 else out


@dataclass(frozen=True)
class GyroscopicMoment:
    """The moment that keeps a symmetric body in regular precession (docs/theory.md §10).

    Attributes
    ----------
    moment : ndarray
        ``M = [C + (C - A)(psi'/phi') cos(theta)] psi' phi' sin(theta)`` (N m): the
        component of ``[C + (C - A)(psi'/phi') cos theta] psi' x phi'`` along the line
        of nodes ``e_z x e_3 / |e_z x e_3|`` (the moment vector is along it).
    approximation : ndarray
        The gyroscope approximation ``C psi' phi' sin(theta)`` (N m).
    relative_error : ndarray
        ``|approximation - moment| / |moment|`` (``= |(C - A) psi' cos(theta)| /
        |C phi' + (C - A) psi' cos(theta)|``); ``inf`` where ``moment = 0``.
    """

    moment: np.ndarray
    approximation: np.ndarray
    relative_error: np.ndarray


def gyroscopic_moment(
    A: ArrayLike,
    C: ArrayLike,
    theta: ArrayLike,
    precession_rate: ArrayLike,
    spin_rate: ArrayLike,
    *,
    degrees: bool = False,
) -> GyroscopicMoment:
    """Moment needed for a regular precession of a symmetric body (the gyroscope).

    ``M = [C + (C - A)(psi'/phi') cos(theta)] psi' x phi'`` with ``psi'`` along the
    precession axis (space ``e_z``), ``phi'`` along the symmetry axis ``e_3``
    (docs/theory.md §10); for ``|phi'| >> |psi'|`` or ``theta = pi/2`` it is
    ``C psi' x phi'``.

    Parameters
    ----------
    A, C : array_like
        Equatorial and axial moments about the fixed point (kg m^2).
    theta : array_like
        Angle between the precession axis and the symmetry axis (rad, or degrees
        with ``degrees=True``), in ``[0, pi]``.
    precession_rate, spin_rate : array_like
        ``psi'`` and ``phi'`` (rad/s); ``phi'`` is the rate of the spin *angle*
        (the axial angular velocity is ``r = phi' + psi' cos(theta)``).
    degrees : bool, optional

    Returns
    -------
    GyroscopicMoment
        The exact moment along the line of nodes, the approximation ``C psi' phi'
        sin(theta)`` and its relative error.

    Examples
    --------
    >>> from poinsot.dynamics import gyroscopic_moment
    >>> import numpy as np
    >>> g = gyroscopic_moment(2.0, 1.0, np.pi / 3, 0.5, 100.0)
    >>> round(float(g.moment), 4), round(float(g.approximation), 4)
    (43.193, 43.3013)
    >>> f"{float(g.relative_error):.1e}"
    '2.5e-03'

    A heavy top precessing regularly needs exactly its gravity moment ``m g l sin(theta)``:

    >>> from poinsot.dynamics import regular_precession_rates
    >>> slow, _ = regular_precession_rates(2.0, 1.0, 3.0, 0.7, 30.0)
    >>> M = gyroscopic_moment(2.0, 1.0, 0.7, slow, 30.0 - slow * np.cos(0.7)).moment
    >>> bool(np.isclose(M, 3.0 * np.sin(0.7), rtol=1e-13))
    True
    """
    a, c = _moment_arrays(A, C)
    th = _angle(theta, "theta", as_bool(degrees, "degrees"), lo=0.0, hi=math.pi)
    pr = as_float_array(precession_rate, "precession_rate")
    sr = as_float_array(spin_rate, "spin_rate")
    sin = np.sin(th)
    extra = (c - a) * pr * np.cos(th)  # (C - A) psi' cos(theta), times psi' sin(theta)
    exact = (c * sr + extra) * pr * sin
    approx = c * pr * sr * sin
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.abs(extra) / np.abs(c * sr + extra)
    rel = np.where(exact == 0, np.where(approx == 0, 0.0, np.inf), rel)
    return GyroscopicMoment(exact[()], approx[()], rel[()])
