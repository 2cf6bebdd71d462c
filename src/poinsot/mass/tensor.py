"""Inertia tensors: validation, Huygens-Steiner, change of axes, principal axes (theory §8).

Every function accepts inertia tensors of shape ``(..., 3, 3)`` and broadcasts
over the leading (batch) dimensions.

Conventions
-----------
- An inertia tensor about a point ``O`` is ``J_O = sum m (rho^T rho E - rho rho^T)``
  (``rho`` the position relative to ``O``): diagonal entries are the moments
  ``int (y^2 + z^2) dm``..., off-diagonal entries the *negative* products of
  inertia ``-int x y dm``... (theory §8).
- A change of axes is described by ``S = C_ab``, the rotation of frame ``b``
  relative to frame ``a``: its columns are the ``b`` axes written in ``a``
  components (``v_a = C_ab v_b``). The tensor transforms as
  ``J_b = S^T J_a S`` (and back, ``J_a = S J_b S^T``).
- Units are whatever the caller uses consistently (e.g. kg, m, kg m^2).
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validate import (
    _is_scipy_rotation,
    as_bool,
    as_float_array,
    as_matrix3,
    as_positive,
    as_trailing,
    as_vec3,
    check_rotation_matrix,
    plain_vec3,
)
from ..errors import InvalidInputError
from ..rotations.rotation import Rotation

__all__ = [
    "check_inertia",
    "check_principal_moments",
    "points",
    "parallel_axis",
    "to_center_of_mass",
    "rotate_inertia",
    "moment_about",
    "principal_axes",
    "inertia_ellipsoid",
]

#: Default relative tolerance of the physical checks (relative to the largest moment).
RTOL = 1e-9


# ---------------------------------------------------------------------------
# Kernels (no validation)
# ---------------------------------------------------------------------------


def _steiner(mass: ArrayLike, offset: ArrayLike) -> np.ndarray:
    """``m (a^T a E - a a^T)``: the inertia of a point mass ``m`` at ``a`` about the origin.

    ``mass`` has shape ``(...)`` and ``offset`` shape ``(..., 3)``; broadcasts.
    This one kernel serves the Huygens-Steiner theorem and :func:`points`.
    """
    a = np.asarray(offset, dtype=np.float64)
    m = np.asarray(mass, dtype=np.float64)[..., None, None]
    aa = np.einsum("...i,...i->...", a, a)[..., None, None]
    return m * (aa * np.eye(3) - a[..., :, None] * a[..., None, :])


def _transpose(m: np.ndarray) -> np.ndarray:
    return np.swapaxes(m, -1, -2)


def _where(bad: np.ndarray) -> str:
    """`` at index (i, j)`` for the first bad entry of a batch, or an empty string."""
    if bad.ndim == 0:
        return ""
    idx = tuple(int(i) for i in np.argwhere(bad)[0])
    return f" at batch index {idx}"


def _first(values: np.ndarray, bad: np.ndarray) -> np.ndarray:
    return values[tuple(np.argwhere(bad)[0])] if bad.ndim else values


def _check_moments(
    moments: np.ndarray, tol: np.ndarray | float, name: str, allow_singular: object, what: str
) -> None:
    """Raise unless sorted principal ``moments`` (..., 3) are >= / > 0 and satisfy A + B >= C."""
    allow_singular = as_bool(allow_singular, "allow_singular")
    a, b, c = moments[..., 0], moments[..., 1], moments[..., 2]
    bad = a < -tol if allow_singular else a <= tol
    if np.any(bad):
        word = "positive semi-definite" if allow_singular else "positive definite"
        m = _first(moments, bad)
        raise InvalidInputError(
            f"Expected `{name}` to be {word} (a physical {what}), but its smallest principal "
            f"moment is {m[0]:.6g}{_where(bad)} (principal moments {_fmt(m)})."
        )
    bad = a + b < c - tol
    if np.any(bad):
        m = _first(moments, bad)
        raise InvalidInputError(
            f"`{name}` is not a physical {what}: it violates the triangle inequality "
            f"A + B >= C of the principal moments{_where(bad)}: A + B = {m[0] + m[1]:.6g} < "
            f"C = {m[2]:.6g} (principal moments {_fmt(m)})."
        )


def _sort3(m: np.ndarray) -> np.ndarray:
    """``np.sort(m, axis=-1)`` for a trailing axis of 3 by a min/max network: the same
    values, about 8x faster than NumPy's sort on 10,000 rows (each call of ``simulate``
    checks its moments)."""
    x, y, z = m[..., 0], m[..., 1], m[..., 2]
    lo_xy, hi_xy = np.minimum(x, y), np.maximum(x, y)
    lo, hi = np.minimum(lo_xy, z), np.maximum(hi_xy, z)
    mid = np.maximum(lo_xy, np.minimum(hi_xy, z))
    return np.stack([lo, mid, hi], axis=-1)


def _fmt(m: Iterable[float]) -> str:
    return "(" + ", ".join(f"{x:.6g}" for x in m) + ")"


def _tolerance(scale: np.ndarray | float, rtol: ArrayLike, atol: ArrayLike) -> np.ndarray:
    rtol, atol = as_float_array(rtol, "rtol"), as_float_array(atol, "atol")
    if rtol.ndim or atol.ndim or rtol < 0 or atol < 0:
        raise InvalidInputError(
            "Expected `rtol` and `atol` to be >= 0 (scalars), "
            f"got {rtol.tolist()!r}, {atol.tolist()!r}."
        )
    return atol + rtol * scale


# ---------------------------------------------------------------------------
# Validation
# ---------------------------------------------------------------------------


def _validated(
    inertia: ArrayLike,
    name: str,
    rtol: float = RTOL,
    atol: float = 0.0,
    allow_singular: object = False,
    vectors: bool = False,
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """:func:`check_inertia`, also returning the ascending moments (and eigenvectors)."""
    j = as_matrix3(inertia, name)
    scale = np.max(np.abs(j), axis=(-2, -1))
    tol = _tolerance(scale, rtol, atol)
    asym = np.max(np.abs(j - _transpose(j)), axis=(-2, -1))
    bad = asym > tol
    if np.any(bad):
        tol_b = np.broadcast_to(tol, bad.shape)
        raise InvalidInputError(
            f"Expected `{name}` to be symmetric{_where(bad)}, got max |J - J^T| = "
            f"{_first(asym, bad):.3g} (tolerance {_first(tol_b, bad):.3g})."
        )
    js = 0.5 * (j + _transpose(j))
    if vectors:
        moments, axes = np.linalg.eigh(js)
    else:
        moments, axes = np.linalg.eigvalsh(js), None
    _check_moments(moments, tol, name, allow_singular, "inertia tensor")
    return js, moments, axes


def check_inertia(
    inertia: ArrayLike,
    name: str = "inertia",
    *,
    rtol: float = RTOL,
    atol: float = 0.0,
    allow_singular: bool = False,
) -> FloatArray:
    """Validate a physical inertia tensor and return it as a symmetric float array.

    Checks, in this order, that ``inertia`` has shape ``(..., 3, 3)``, is finite,
    symmetric, positive definite (or semi-definite if ``allow_singular``) and that
    its principal moments ``A <= B <= C`` satisfy the triangle inequality
    ``A + B >= C`` (the cyclic ones, ``B + C >= A`` and ``C + A >= B``, then hold
    automatically). Each check allows ``atol + rtol * max|J_ij|``.

    Parameters
    ----------
    inertia : array_like, shape (..., 3, 3)
        Inertia tensor(s) about some point, in some axes.
    name : str, optional
        Argument name used in error messages.
    rtol, atol : float, optional
        Relative (to the largest entry) and absolute tolerances. Defaults
        ``1e-9`` and ``0``.
    allow_singular : bool, optional
        Accept a zero principal moment (a thin rod, a point mass, a plane figure's
        limit). Default ``False``: positive definite, as the Euler equations need.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        ``(J + J^T) / 2`` as float64.

    Raises
    ------
    InvalidInputError
        Naming the argument and the condition that failed (shape, finiteness,
        symmetry, definiteness, or the triangle inequality).

    Notes
    -----
    The principal moments of any mass distribution obey ``A + B >= C`` since
    ``A + B - C = 2 int z^2 dm >= 0`` in principal axes (theory §8); equality holds
    for plane figures in the ``xy`` plane.

    **Convention:** any consistent units; the axes and point do not matter.

    Examples
    --------
    >>> from poinsot.mass import check_inertia
    >>> check_inertia([[2.0, 0, 0], [0, 3.0, 0], [0, 0, 4.0]]).diagonal()
    array([2., 3., 4.])
    >>> check_inertia([[1.0, 0, 0], [0, 1.0, 0], [0, 0, 3.0]])  # doctest: +ELLIPSIS
    Traceback (most recent call last):
        ...
    poinsot.errors.InvalidInputError: `inertia` is not a physical inertia tensor: ... A + B >= C ...
    """
    return _validated(inertia, name, rtol, atol, allow_singular)[0]


def check_principal_moments(
    moments: ArrayLike,
    name: str = "moments",
    *,
    rtol: float = RTOL,
    atol: float = 0.0,
    allow_singular: bool = False,
) -> FloatArray:
    """Validate principal moments ``(A, B, C)`` (any order) and return them as floats.

    Same physical conditions as :func:`check_inertia` (positive, and
    ``A + B >= C`` for every ordering), for a diagonal tensor given by its
    diagonal.

    Parameters
    ----------
    moments : array_like, shape (..., 3)
        Principal moments of inertia, in any order.
    name : str, optional
        Argument name used in error messages.
    rtol, atol : float, optional
        Relative (to the largest moment) and absolute tolerances.
    allow_singular : bool, optional
        Accept a zero moment.

    Returns
    -------
    ndarray, shape (..., 3)
        The moments as float64, in the order given.

    Notes
    -----
    **Convention:** principal axes; any consistent units (theory §8).

    Examples
    --------
    >>> from poinsot.mass import check_principal_moments
    >>> check_principal_moments([3.0, 1.0, 2.0])
    array([3., 1., 2.])
    """
    m = as_trailing(moments, name, (3,))
    s = _sort3(m)
    # max |m_i| from the sorted ends: the values of np.max(np.abs(m), axis=-1), whose
    # reduction over an axis of 3 took 0.5 ms of each `simulate` call on 10,000 bodies
    tol = _tolerance(np.maximum(s[..., 2], -s[..., 0]), rtol, atol)
    _check_moments(s, tol, name, allow_singular, "set of principal moments")
    return m


def single_principal_moments(x: object) -> list[float] | None:
    """Short path of :func:`check_principal_moments` for one plain 3-vector: the moments as
    Python floats when they pass the same checks (finite, positive, ``A + B >= C`` within
    ``RTOL`` of the largest), else ``None`` (the caller's general path then raises)."""
    j = plain_vec3(x)
    if j is None:
        return None
    lo, mid, hi = sorted(j)
    tol = RTOL * max(abs(j[0]), abs(j[1]), abs(j[2]))
    if lo <= tol or lo + mid < hi - tol:
        return None
    return j


def as_inertia(
    inertia: object, name: str = "inertia", *, allow_singular: bool = False
) -> tuple[np.ndarray, bool]:
    """Validated inertia: ``(moments (..., 3), True)`` or ``(tensor (..., 3, 3), False)``.

    The one reader of "principal moments or a tensor" used by every entry point
    that takes an inertia (``euler_rhs``, ``simulate``, ``invariants``,
    ``RigidBody``). An array whose last two dimensions are ``(3, 3)`` is a tensor
    in body axes; any other array of shape ``(..., 3)`` holds principal moments
    (body axes then principal axes). Both are checked physical (positive definite,
    or semi-definite with ``allow_singular``; ``A + B >= C``). A batch of three
    bodies' principal moments has shape ``(3, 3)`` and would read as one tensor:
    pass it as tensors, ``moments[..., None] * np.eye(3)``.
    """
    a = as_float_array(inertia, name)
    if a.ndim >= 2 and a.shape[-2:] == (3, 3):
        return check_inertia(a, name, allow_singular=allow_singular), False
    if a.ndim >= 1 and a.shape[-1] == 3:
        return check_principal_moments(a, name, allow_singular=allow_singular), True
    raise InvalidInputError(
        f"Expected `{name}` to have shape (..., 3) (principal moments) or (..., 3, 3) "
        f"(a tensor), got {a.shape}."
    )


def _as_rotation_matrix(rotation: Any, name: str = "rotation") -> np.ndarray:
    """``S`` (..., 3, 3) from a poinsot or SciPy ``Rotation`` or a proper orthogonal matrix
    (checked by :func:`poinsot._validate.check_rotation_matrix`, tolerance 1e-6)."""
    if isinstance(rotation, Rotation) or _is_scipy_rotation(rotation):
        return np.asarray(rotation.as_matrix(), dtype=np.float64)
    return check_rotation_matrix(rotation, name)


# ---------------------------------------------------------------------------
# Public functions
# ---------------------------------------------------------------------------


def points(masses: ArrayLike, positions: ArrayLike) -> FloatArray:
    """Inertia tensor of point masses about the origin.

    ``J_O = sum_k m_k (rho_k^T rho_k E - rho_k rho_k^T)`` (theory §8).

    Parameters
    ----------
    masses : array_like, shape (..., n)
        Positive point masses.
    positions : array_like, shape (..., n, 3)
        Their positions relative to the origin ``O``.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Inertia about ``O`` in the axes of ``positions`` (positive semi-definite:
        collinear points have a zero moment about their line).

    Notes
    -----
    **Convention:** ``positions`` and the result share the same axes; any
    consistent units. The centre of mass is ``sum m rho / sum m``; see
    :meth:`RigidBody.from_points` for the inertia about it.

    Examples
    --------
    >>> from poinsot.mass import points
    >>> points([1.0, 1.0], [[1.0, 0, 0], [-1.0, 0, 0]]).diagonal()
    array([0., 2., 2.])
    """
    m = as_positive(masses, "masses")
    r = as_trailing(positions, "positions", (None, 3))
    if m.ndim == 0:
        raise InvalidInputError(f"Expected `masses` to have shape (..., n), got {m.shape}.")
    if m.shape[-1] != r.shape[-2]:
        raise InvalidInputError(
            f"Expected `masses` (..., n) and `positions` (..., n, 3) to have the same n, "
            f"got {m.shape[-1]} and {r.shape[-2]}."
        )
    return _steiner(m, r).sum(axis=-3)


def parallel_axis(inertia_cm: ArrayLike, mass: ArrayLike, offset: ArrayLike) -> FloatArray:
    """Huygens-Steiner: inertia about the point at ``offset`` from the centre of mass.

    ``J_O = J_C + m (a^T a E - a a^T)`` with ``a = offset`` (theory §8); about an
    axis, ``J_Oe = J_Ce + m d^2``.

    Parameters
    ----------
    inertia_cm : array_like, shape (..., 3, 3)
        Inertia about the centre of mass ``C``.
    mass : array_like, shape (...)
        Mass, > 0.
    offset : array_like, shape (..., 3)
        Position of the new point ``O`` relative to ``C`` (the vector ``CO``; the
        sign does not matter), in the same axes as ``inertia_cm``.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Inertia about ``O``, same axes.

    Notes
    -----
    **Convention:** one set of axes for all arguments; any consistent units.
    Inverse: :func:`to_center_of_mass`.

    Examples
    --------
    >>> from poinsot.mass import parallel_axis, rod
    >>> # a thin rod about its end: m L^2 / 3
    >>> parallel_axis(rod(3.0, 2.0), 3.0, [0, 0, 1.0]).diagonal()
    array([4., 4., 0.])
    """
    j = check_inertia(inertia_cm, "inertia_cm", allow_singular=True)
    m = as_positive(mass, "mass")
    a = as_vec3(offset, "offset")
    return j + _steiner(m, a)


def to_center_of_mass(inertia_o: ArrayLike, mass: ArrayLike, offset: ArrayLike) -> FloatArray:
    """Inverse Huygens-Steiner: inertia about the centre of mass from that about ``O``.

    ``J_C = J_O - m (a^T a E - a a^T)`` with ``a`` the position of ``O``
    relative to ``C`` (theory §8).

    Parameters
    ----------
    inertia_o : array_like, shape (..., 3, 3)
        Inertia about the point ``O``.
    mass : array_like, shape (...)
        Mass, > 0.
    offset : array_like, shape (..., 3)
        Position of ``O`` relative to the centre of mass (the sign does not matter).

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Inertia about the centre of mass, same axes.

    Raises
    ------
    InvalidInputError
        If the result is not a physical inertia tensor: ``inertia_o``, ``mass``
        and ``offset`` cannot describe one body.

    Notes
    -----
    **Convention:** one set of axes for all arguments; any consistent units.

    Examples
    --------
    >>> from poinsot.mass import to_center_of_mass
    >>> to_center_of_mass([[4.0, 0, 0], [0, 4.0, 0], [0, 0, 0]], 3.0, [0, 0, 1.0]).diagonal()
    array([1., 1., 0.])
    """
    j = check_inertia(inertia_o, "inertia_o", allow_singular=True)
    m = as_positive(mass, "mass")
    a = as_vec3(offset, "offset")
    jc = j - _steiner(m, a)
    scale = np.max(np.abs(j), axis=(-2, -1))
    try:
        _check_moments(np.linalg.eigvalsh(jc), RTOL * scale, "inertia_o", True, "inertia tensor")
    except InvalidInputError as exc:
        raise InvalidInputError(
            "`inertia_o`, `mass` and `offset` are inconsistent: the inertia about the centre "
            f"of mass would not be physical. {exc}"
        ) from None
    return jc


def rotate_inertia(inertia: ArrayLike, rotation: Rotation | ArrayLike) -> FloatArray:
    """Express an inertia tensor in new axes: ``J_b = S^T J_a S`` (theory §8).

    Parameters
    ----------
    inertia : array_like, shape (..., 3, 3)
        ``J_a``, the tensor in the old axes ``a``.
    rotation : Rotation or array_like, shape (..., 3, 3)
        ``S = C_ab``: the new axes ``b`` relative to the old axes ``a``. Its matrix
        columns are the new axes written in the old basis (``v_a = S v_b``). A
        matrix must be proper orthogonal (``S^T S = E``, ``det S = +1``).

    Returns
    -------
    ndarray, shape (..., 3, 3)
        ``J_b``, the same tensor (same body, same point) in the new axes.

    Notes
    -----
    **Convention:** with a body ``b`` whose attitude relative to frame ``a`` is
    ``R = C_ab`` (body -> frame components), ``rotate_inertia(J_a, R)`` gives the
    body-axes tensor and ``rotate_inertia(J_b, R.inv())`` the frame-axes one,
    ``J_a = R J_b R^T``. :func:`principal_axes` returns the ``R`` for which
    ``rotate_inertia(J, R)`` is diagonal.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot import Rotation
    >>> from poinsot.mass import rotate_inertia
    >>> s = Rotation.from_axis_angle([0, 0, 1.0], np.pi / 2)   # new x = old y
    >>> rotate_inertia(np.diag([1.0, 2.0, 3.0]), s).diagonal().round(12)
    array([2., 1., 3.])
    """
    j = check_inertia(inertia, allow_singular=True)
    s = _as_rotation_matrix(rotation)
    return _transpose(s) @ j @ s


def moment_about(inertia: ArrayLike, axis: ArrayLike) -> FloatArray:
    """Moment of inertia about an axis through the tensor's point: ``J_e = e^T J e``.

    Parameters
    ----------
    inertia : array_like, shape (..., 3, 3)
        Inertia about a point ``O``.
    axis : array_like, shape (..., 3)
        Direction of the axis through ``O`` (normalised here; must be non-zero).

    Returns
    -------
    ndarray, shape (...)
        The moment ``e^T J e`` (theory §8).

    Notes
    -----
    **Convention:** ``axis`` in the axes of ``inertia``.

    Examples
    --------
    >>> from poinsot.mass import box, moment_about
    >>> float(moment_about(box(12.0, 1.0, 1.0, 1.0), [1.0, 1.0, 1.0]).round(12))
    2.0
    """
    j = check_inertia(inertia, allow_singular=True)
    v = as_vec3(axis, "axis")
    # scale by the largest component first: no overflow/underflow for any |axis|
    big = np.max(np.abs(v), axis=-1, initial=0.0)
    if np.any(big == 0.0):
        raise InvalidInputError("Expected `axis` to be a non-zero vector, got a zero vector.")
    u = v / big[..., None]
    e = u / np.linalg.norm(u, axis=-1)[..., None]
    try:
        return np.einsum("...i,...ij,...j->...", e, j, e)
    except ValueError:
        raise InvalidInputError(
            f"Expected the batch shapes of `inertia` {j.shape[:-2]} and `axis` {v.shape[:-1]} "
            "to broadcast."
        ) from None


def _principal(j: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Kernel: ascending moments and a proper rotation matrix of principal axes (columns)."""
    w, v = np.linalg.eigh(j)
    return w, _proper_axes(v)


def _proper_axes(v: ArrayLike) -> np.ndarray:
    """Deterministic signs for eigenvector columns, third = first x second (det +1)."""
    v = np.array(v, copy=True)
    for k in (0, 1):
        col = v[..., :, k]
        idx = np.argmax(np.abs(col), axis=-1)[..., None]
        sign = np.where(np.take_along_axis(col, idx, axis=-1) < 0, -1.0, 1.0)
        v[..., :, k] = col * sign
    v[..., :, 2] = np.cross(v[..., :, 0], v[..., :, 1])
    return v


def principal_axes(inertia: ArrayLike) -> tuple[FloatArray, Rotation]:
    """Principal moments (ascending) and principal axes as a proper rotation.

    Solves ``S^T J S = diag(A, B, C)``, ``A <= B <= C`` (theory §8).

    Parameters
    ----------
    inertia : array_like, shape (..., 3, 3)
        A physical inertia tensor (positive semi-definite allowed).

    Returns
    -------
    moments : ndarray, shape (..., 3)
        Principal moments ``A <= B <= C``.
    rotation : Rotation, shape (...)
        ``S = C_ab`` from the input axes ``a`` to the principal axes ``b``: the
        columns of ``rotation.as_matrix()`` are the principal axes written in the
        input axes, ``det = +1``, and
        ``S.T @ J @ S == diag(moments)`` (so ``rotate_inertia(J, rotation)`` is
        diagonal).

    Notes
    -----
    The axes come from ``numpy.linalg.eigh`` (LAPACK ``syevd``), which returns
    an orthonormal basis even for repeated moments. Each axis is defined up to
    sign; the first two columns are made deterministic (their largest-magnitude
    component is positive) and the third is their cross product, which makes the
    matrix proper. For repeated moments (a sphere, a cube, a symmetric top) any
    orthonormal basis of the degenerate eigenspace is valid and one of them is
    returned; only the diagonalisation is guaranteed, not a particular basis.

    **Convention:** the moments are in the input's units; the rotation maps
    principal-axis components to input-axis components (``v_a = S v_b``).

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.mass import principal_axes
    >>> moments, rot = principal_axes(np.diag([3.0, 1.0, 2.0]))
    >>> moments
    array([1., 2., 3.])
    >>> rot.as_matrix().round(12) + 0.0
    array([[0., 0., 1.],
           [1., 0., 0.],
           [0., 1., 0.]])
    """
    _, w, v = _validated(inertia, "inertia", allow_singular=True, vectors=True)
    assert v is not None  # vectors=True
    return w, Rotation.from_matrix(_proper_axes(v))


def inertia_ellipsoid(inertia: ArrayLike) -> tuple[FloatArray, Rotation]:
    """Semi-axes and orientation of the inertia ellipsoid ``r^T J r = 1`` (theory §8).

    In principal axes the ellipsoid is ``A x^2 + B y^2 + C z^2 = 1``; the point
    on an axis ``e`` is ``r = e / sqrt(J_e)``.

    Parameters
    ----------
    inertia : array_like, shape (..., 3, 3)
        A positive definite inertia tensor about a point ``O`` (the ellipsoid's
        centre).

    Returns
    -------
    semi_axes : ndarray, shape (..., 3)
        ``1 / sqrt(moments)`` in **descending** order: the ``k``-th semi-axis lies
        along the ``k``-th principal axis of :func:`principal_axes` (the longest
        along the axis of smallest moment).
    rotation : Rotation, shape (...)
        The principal axes, as returned by :func:`principal_axes`.

    Notes
    -----
    **Convention:** lengths in ``1 / sqrt(inertia units)``; the rotation maps
    ellipsoid (principal) axes to input axes.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.mass import inertia_ellipsoid
    >>> semi, rot = inertia_ellipsoid(np.diag([4.0, 1.0, 4.0]))
    >>> semi
    array([1. , 0.5, 0.5])
    """
    _, w, v = _validated(inertia, "inertia", vectors=True)
    assert v is not None  # vectors=True
    return 1.0 / np.sqrt(w), Rotation.from_matrix(_proper_axes(v))


# ---------------------------------------------------------------------------
# Kernels (no validation): the single implementation of K = J w and T = w.J w/2,
# used by poinsot.mass (Koenig) and poinsot.dynamics (invariants, free body)
# ---------------------------------------------------------------------------


def _momentum(
    j: np.ndarray, principal: bool, w: np.ndarray, out: np.ndarray | None = None
) -> np.ndarray:
    """``K = J w`` for principal moments ``j`` (..., 3) or a tensor ``j`` (..., 3, 3)
    (``out``: an array of the broadcast shape to write it into)."""
    if principal:
        return np.multiply(j, w, out=out)
    return np.einsum("...ij,...j->...i", j, w, out=out)


def _kinetic(j: np.ndarray, principal: bool, w: np.ndarray) -> np.ndarray:
    """``T = w . J w / 2``."""
    return 0.5 * np.einsum("...i,...i->...", w, _momentum(j, principal, w))
