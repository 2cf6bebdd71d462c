"""Inertia tensors of uniform solids about their centre of mass, in their own axes (theory §8).

Every function broadcasts over array parameters: with parameters of (broadcast)
shape ``(...)`` the result has shape ``(..., 3, 3)``. The tensors are diagonal
(the symmetry axes are principal). Masses and dimensions must be > 0.

=================  ========================  ==========================  ==============
solid              ``J_xx``                  ``J_yy``                    ``J_zz``
=================  ========================  ==========================  ==============
box a x b x c      m (b^2 + c^2) / 12        m (a^2 + c^2) / 12          m (a^2 + b^2) / 12
solid sphere       2/5 m r^2                 2/5 m r^2                   2/5 m r^2
hollow sphere      2/3 m r^2                 2/3 m r^2                   2/3 m r^2
solid cylinder     m (3 r^2 + h^2) / 12      m (3 r^2 + h^2) / 12        m r^2 / 2
thin-walled tube   m (6 r^2 + h^2) / 12      m (6 r^2 + h^2) / 12        m r^2
solid cone         3/80 m (4 r^2 + h^2)      3/80 m (4 r^2 + h^2)        3/10 m r^2
ellipsoid a, b, c  m (b^2 + c^2) / 5         m (a^2 + c^2) / 5           m (a^2 + b^2) / 5
thin rod           m L^2 / 12                m L^2 / 12                  0
thin disc          m r^2 / 4                 m r^2 / 4                   m r^2 / 2
thin ring (hoop)   m r^2 / 2                 m r^2 / 2                   m r^2
=================  ========================  ==========================  ==============

References
----------
.. [1] L. D. Landau, E. M. Lifshitz, *Mechanics*, 3rd ed., Sec. 32, Problem 2
   (rod, sphere, cylinder, parallelepiped, cone, ellipsoid).
.. [2] "List of moments of inertia", Wikipedia (hollow sphere, thin-walled
   tube, disc, hoop).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import ParamSpec

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validate import as_bool, as_positive, batch_shape
from ..errors import InvalidInputError

__all__ = ["box", "sphere", "cylinder", "cone", "ellipsoid", "rod", "disc", "ring"]

#: Solids accepted by a scenario's ``shape =`` and by ``poinsot inertia``, and the meaning
#: of their ``dims`` (m), in order. Axisymmetric solids have their axis along body ``z``;
#: a rod lies along ``z``. (A scenario's ``shape = "mesh"`` is read by
#: ``poinsot.scenarios``.)
SHAPES: dict[str, tuple[str, ...]] = {
    "box": ("length along x", "width along y", "height along z"),
    "sphere": ("radius",),
    "cylinder": ("radius", "height"),
    "cone": ("base radius", "height"),
    "ellipsoid": ("semi-axis a along x", "semi-axis b along y", "semi-axis c along z"),
    "rod": ("length",),
    "disc": ("radius",),
    "ring": ("radius",),
}

_P = ParamSpec("_P")


def _diag(jxx: ArrayLike, jyy: ArrayLike, jzz: ArrayLike) -> np.ndarray:
    """Kernel: diagonal tensors of shape (..., 3, 3) from broadcastable diagonals."""
    jxx, jyy, jzz = np.broadcast_arrays(jxx, jyy, jzz)
    out = np.zeros(jxx.shape + (3, 3))
    out[..., 0, 0] = jxx
    out[..., 1, 1] = jyy
    out[..., 2, 2] = jzz
    return out


def _positive(**named: ArrayLike) -> list[np.ndarray]:
    """Validate positive arguments and check that their shapes broadcast together."""
    arrays = {k: as_positive(v, k) for k, v in named.items()}
    batch_shape(**{k: (a, 0) for k, a in arrays.items()})
    return list(arrays.values())


def _representable(
    *, zero_zz: bool = False
) -> Callable[[Callable[_P, FloatArray]], Callable[_P, FloatArray]]:
    """Decorator: a mass or dimension so large (small) that ``m d^2`` overflows
    (underflows to 0) raises :class:`InvalidInputError` instead of returning inf/0."""

    def deco(fn: Callable[_P, FloatArray]) -> Callable[_P, FloatArray]:
        @functools.wraps(fn)
        def wrapper(*args: _P.args, **kwargs: _P.kwargs) -> FloatArray:
            with np.errstate(over="ignore", under="ignore"):
                out = fn(*args, **kwargs)
            d = np.diagonal(out, axis1=-2, axis2=-1)
            d = d[..., :2] if zero_zz else d
            if not (np.all(np.isfinite(out)) and np.all(d > 0)):
                raise InvalidInputError(
                    f"Expected the mass and dimensions of the {fn.__name__} to give a "
                    "representable inertia: m d^2 overflows or underflows in float64 "
                    "(use units that keep the numbers moderate)."
                )
            return out

        return wrapper

    return deco


@_representable()
def box(mass: ArrayLike, a: ArrayLike, b: ArrayLike, c: ArrayLike) -> FloatArray:
    """Uniform rectangular box (cuboid) with edges ``a, b, c`` along ``x, y, z``.

    ``J = m/12 diag(b^2 + c^2, a^2 + c^2, a^2 + b^2)`` (Landau-Lifshitz, Sec. 32).

    Parameters
    ----------
    mass : array_like
        Mass, > 0.
    a, b, c : array_like
        Full edge lengths along ``x``, ``y``, ``z``, > 0.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Inertia about the centre (the centre of mass), box axes.

    Notes
    -----
    **Convention:** axes along the edges, origin at the centre; consistent units.

    Examples
    --------
    >>> from poinsot.mass import box
    >>> box(12.0, 1.0, 2.0, 3.0).diagonal()
    array([13., 10.,  5.])
    """
    m, a, b, c = _positive(mass=mass, a=a, b=b, c=c)
    a2, b2, c2 = a * a, b * b, c * c
    return _diag(m * (b2 + c2) / 12.0, m * (a2 + c2) / 12.0, m * (a2 + b2) / 12.0)


@_representable()
def sphere(mass: ArrayLike, radius: ArrayLike, *, hollow: bool = False) -> FloatArray:
    """Uniform solid ball, or thin spherical shell if ``hollow``.

    ``J = 2/5 m r^2 E`` (solid), ``J = 2/3 m r^2 E`` (shell).

    Parameters
    ----------
    mass, radius : array_like
        Mass and radius, > 0.
    hollow : bool, optional
        A thin-walled spherical shell instead of a solid ball.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Inertia about the centre (isotropic).

    Notes
    -----
    **Convention:** origin at the centre; any axes; consistent units.

    Examples
    --------
    >>> from poinsot.mass import sphere
    >>> sphere(5.0, 2.0).diagonal()
    array([8., 8., 8.])
    >>> sphere(3.0, 1.0, hollow=True).diagonal()
    array([2., 2., 2.])
    """
    m, r = _positive(mass=mass, radius=radius)
    k = m * r * r * (2.0 / 3.0 if as_bool(hollow, "hollow") else 0.4)
    return _diag(k, k, k)


@_representable()
def cylinder(
    mass: ArrayLike, radius: ArrayLike, height: ArrayLike, *, hollow: bool = False
) -> FloatArray:
    """Uniform solid circular cylinder, or thin-walled tube if ``hollow``; axis ``z``.

    Solid: ``J_zz = m r^2 / 2``, ``J_xx = J_yy = m (3 r^2 + h^2) / 12``.
    Tube (open ends): ``J_zz = m r^2``, ``J_xx = J_yy = m (6 r^2 + h^2) / 12``.

    Parameters
    ----------
    mass, radius, height : array_like
        Mass, radius and height (length along ``z``), > 0.
    hollow : bool, optional
        A thin-walled open tube (all mass at distance ``radius`` from the axis).

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Inertia about the centre, axis along ``z``.

    Notes
    -----
    **Convention:** symmetry axis ``z``, origin at mid-height; consistent units.

    Examples
    --------
    >>> from poinsot.mass import cylinder
    >>> cylinder(12.0, 1.0, 3.0).diagonal()
    array([12., 12.,  6.])
    """
    m, r, h = _positive(mass=mass, radius=radius, height=height)
    r2, h2 = r * r, h * h
    if as_bool(hollow, "hollow"):
        return _diag(m * (6.0 * r2 + h2) / 12.0, m * (6.0 * r2 + h2) / 12.0, m * r2)
    return _diag(m * (3.0 * r2 + h2) / 12.0, m * (3.0 * r2 + h2) / 12.0, 0.5 * m * r2)


@_representable()
def cone(mass: ArrayLike, radius: ArrayLike, height: ArrayLike) -> FloatArray:
    """Uniform solid right circular cone about its centre of mass; axis ``z``.

    ``J_zz = 3/10 m r^2``, ``J_xx = J_yy = 3/80 m (4 r^2 + h^2)``
    (Landau-Lifshitz, Sec. 32, Problem 2e).

    Parameters
    ----------
    mass, radius, height : array_like
        Mass, base radius and height, > 0.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Inertia about the centre of mass, which lies on the axis at ``h / 4``
        from the base (``3 h / 4`` from the apex).

    Notes
    -----
    **Convention:** symmetry axis ``z``, origin at the centre of mass (the
    result does not depend on whether the apex points to ``+z`` or ``-z``).

    Examples
    --------
    >>> from poinsot.mass import cone
    >>> cone(10.0, 2.0, 2.0).diagonal()
    array([ 7.5,  7.5, 12. ])
    """
    m, r, h = _positive(mass=mass, radius=radius, height=height)
    t = 3.0 / 80.0 * m * (4.0 * r * r + h * h)
    return _diag(t, t, 0.3 * m * r * r)


@_representable()
def ellipsoid(mass: ArrayLike, a: ArrayLike, b: ArrayLike, c: ArrayLike) -> FloatArray:
    """Uniform solid ellipsoid with semi-axes ``a, b, c`` along ``x, y, z``.

    ``J = m/5 diag(b^2 + c^2, a^2 + c^2, a^2 + b^2)`` (Landau-Lifshitz, Sec. 32).

    Parameters
    ----------
    mass : array_like
        Mass, > 0.
    a, b, c : array_like
        Semi-axes along ``x``, ``y``, ``z``, > 0.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Inertia about the centre, ellipsoid axes.

    Notes
    -----
    **Convention:** axes along the semi-axes, origin at the centre.

    Examples
    --------
    >>> from poinsot.mass import ellipsoid
    >>> ellipsoid(5.0, 1.0, 2.0, 3.0).diagonal()
    array([13., 10.,  5.])
    """
    m, a, b, c = _positive(mass=mass, a=a, b=b, c=c)
    a2, b2, c2 = a * a, b * b, c * c
    return _diag(m * (b2 + c2) / 5.0, m * (a2 + c2) / 5.0, m * (a2 + b2) / 5.0)


@_representable(zero_zz=True)
def rod(mass: ArrayLike, length: ArrayLike) -> FloatArray:
    """Thin uniform rod along ``z``: ``J_xx = J_yy = m L^2 / 12``, ``J_zz = 0``.

    Parameters
    ----------
    mass, length : array_like
        Mass and length, > 0.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Inertia about the midpoint. Singular (``J_zz = 0``): accepted by
        :class:`RigidBody` and composite bodies, but not a body for Euler's
        equations on its own.

    Notes
    -----
    **Convention:** rod along ``z``, origin at its midpoint.

    Examples
    --------
    >>> from poinsot.mass import rod
    >>> rod(3.0, 2.0).diagonal()
    array([1., 1., 0.])
    """
    m, ell = _positive(mass=mass, length=length)
    t = m * ell * ell / 12.0
    return _diag(t, t, np.zeros_like(t))


@_representable()
def disc(mass: ArrayLike, radius: ArrayLike) -> FloatArray:
    """Thin uniform disc with normal ``z``: ``J_zz = m r^2 / 2``, ``J_xx = J_yy = m r^2 / 4``.

    Parameters
    ----------
    mass, radius : array_like
        Mass and radius, > 0.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Inertia about the centre (``A + B = C``: a plane figure).

    Notes
    -----
    **Convention:** disc in the ``xy`` plane, origin at its centre.

    Examples
    --------
    >>> from poinsot.mass import disc
    >>> disc(4.0, 1.0).diagonal()
    array([1., 1., 2.])
    """
    m, r = _positive(mass=mass, radius=radius)
    t = 0.25 * m * r * r
    return _diag(t, t, 2.0 * t)


@_representable()
def ring(mass: ArrayLike, radius: ArrayLike) -> FloatArray:
    """Thin uniform ring (hoop) with normal ``z``: ``J_zz = m r^2``, ``J_xx = J_yy = m r^2 / 2``.

    Parameters
    ----------
    mass, radius : array_like
        Mass and radius, > 0.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Inertia about the centre (``A + B = C``: a plane figure).

    Notes
    -----
    **Convention:** ring in the ``xy`` plane, origin at its centre.

    Examples
    --------
    >>> from poinsot.mass import ring
    >>> ring(2.0, 1.0).diagonal()
    array([1., 1., 2.])
    """
    m, r = _positive(mass=mass, radius=radius)
    t = 0.5 * m * r * r
    return _diag(t, t, 2.0 * t)
