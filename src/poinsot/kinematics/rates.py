"""Rates of every attitude representation: the kinematic equations (theory §3, §5).

Each representation ``x`` of an attitude has a pair of functions

* ``x_rate(x, omega, *, frame="body")`` -- the time derivative ``x'`` produced by
  the angular velocity ``omega``;
* ``omega_from_x_rate(x, xdot, *, frame="body")`` -- the angular velocity that
  produces a given derivative ``x'`` (the inverse map).

``frame`` names the axes ``omega`` is written in: ``"body"`` (``w_xi``, the
moving axes) or ``"space"`` (``w_x``, the fixed axes); the two are related by
``w_x = C w_xi`` where ``C`` maps body components to space components (theory §2).
Angular velocities are always in rad/s.

================================  =================================================
representation                    kinematic equation (body frame / space frame)
================================  =================================================
quaternion ``L`` (S5)             ``L' = 1/2 L o w_xi``  /  ``L' = 1/2 w_x o L``
direction cosines ``A`` (S5)      ``A' = A w_xi^``       /  ``A' = w_x^ A``
Euler angles (S3)                 ``w = M(angles) angles'``, any of the 12 sequences
Gibbs ``g = e tan(f/2)``          ``g' = 1/2 (w + s g x w + (g.w) g)``
MRP ``p = e tan(f/4)``            ``p' = 1/4 ((1 - p.p) w + 2 s p x w + 2 (p.w) p)``
rotation vector ``phi = f e``     ``phi' = w + s/2 phi x w + c(f) phi x (phi x w)``
================================  =================================================

with ``s = +1`` for the body frame and ``s = -1`` for the space frame, and
``c(f) = (1 - (f/2) cot(f/2)) / f^2``.
"""

from __future__ import annotations

import math
import numbers
import warnings
from typing import Any, TypeGuard

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validate import (
    as_bool,
    as_choice,
    as_matrix3,
    as_quat,
    as_trailing,
    as_vec3,
    plain_floats,
    plain_vec3,
)
from .._vec import cross as _cross
from .._vec import dot as _dot
from .._vec import hat as _hat
from ..errors import GimbalLockWarning, InvalidInputError, InvalidTypeError, SingularityWarning
from ..rotations import _scalar as S
from ..rotations._lazy import kernels
from ..rotations.dcm import ORTHOGONALITY_ATOL
from ..rotations.euler import parse_sequence
from ..rotations.quaternion import conjugate as _qconjugate
from ..rotations.quaternion import multiply as _qmultiply
from ..rotations.rotation import Rotation, _seq, _unit4

__all__ = [
    "quat_rate",
    "omega_from_quat_rate",
    "dcm_rate",
    "omega_from_dcm_rate",
    "euler_rates",
    "omega_from_euler_rates",
    "euler_rate_matrix",
    "gibbs_rate",
    "omega_from_gibbs_rate",
    "mrp_rate",
    "omega_from_mrp_rate",
    "mrp_shadow",
    "mrp_switch",
    "rotvec_rate",
    "omega_from_rotvec_rate",
    "GIMBAL_WARN_DET",
    "GIMBAL_ERROR_DET",
]

FRAMES = ("body", "space")

#: ``euler_rates`` warns (:class:`~poinsot.GimbalLockWarning`) where the
#: determinant of the Euler rate matrix (``+-sin`` or ``+-cos`` of the middle
#: angle) is smaller than this in magnitude: the angle rates are then more than
#: 1000 times larger than ``|omega|`` and lose digits in proportion.
GIMBAL_WARN_DET = 1e-3
#: ``euler_rates`` raises :class:`~poinsot.InvalidInputError` where the
#: determinant is smaller than this (the matrix is numerically singular).
GIMBAL_ERROR_DET = 1e-12
#: Below this rotation angle (rad) the rotation-vector coefficients use their
#: Taylor series (truncation error < 1e-17), above it the closed forms.
ROTVEC_SERIES_ANGLE = 0.1
#: ``rotvec_rate`` warns (:class:`~poinsot.SingularityWarning`) where the angle
#: is within this distance (rad) of ``2 pi``, where ``cot(f/2)`` blows up.
ROTVEC_WARN_GAP = 1e-2


# --------------------------------------------------------------------------
# small vector kernels (no validation)
# --------------------------------------------------------------------------


def _vee_antisym(m: np.ndarray) -> np.ndarray:
    """Vector of the antisymmetric part of ``m``: ``vee((m - m^T)/2)``."""
    return 0.5 * np.stack(
        [m[..., 2, 1] - m[..., 1, 2], m[..., 0, 2] - m[..., 2, 0], m[..., 1, 0] - m[..., 0, 1]],
        axis=-1,
    )


def _pure(v: ArrayLike) -> np.ndarray:
    """The pure quaternion ``(0, v)``."""
    v = np.asarray(v, dtype=float)
    return np.concatenate([np.zeros(v.shape[:-1] + (1,)), v], axis=-1)


def _frame(frame: object) -> str:
    return as_choice(frame, "frame", FRAMES)


def _sign(frame: str) -> float:
    return 1.0 if frame == "body" else -1.0


def _batch(**named: tuple[np.ndarray, int]) -> tuple[int, ...]:
    """Check that the batch (leading) shapes of named arrays broadcast together.

    ``named`` maps an argument name to ``(array, core_ndim)``, where ``core_ndim``
    trailing axes are the per-item shape (1 for vectors, 2 for matrices).
    """
    shapes = {k: a.shape[: a.ndim - nd] for k, (a, nd) in named.items()}
    try:
        return np.broadcast_shapes(*shapes.values())
    except ValueError:
        desc = ", ".join(f"`{k}` {s}" for k, s in shapes.items())
        raise InvalidInputError(
            f"Expected the batch (leading) shapes of {desc} to broadcast."
        ) from None


def _finite_result(out: np.ndarray, name: str) -> np.ndarray:
    """Raise instead of returning inf/NaN produced by an overflowing magnitude."""
    if not np.all(np.isfinite(out)):
        raise InvalidInputError(
            f"Expected `{name}` to have a moderate magnitude: the result overflows "
            "(inf/NaN) for these values."
        )
    return out


# --------------------------------------------------------------------------
# one state: the same formulas on Python floats (validation kept: type, shape,
# finite values; anything unusual goes to the general path, which reports it)
# --------------------------------------------------------------------------
_SIGNS = {"body": 1.0, "space": -1.0}


def _fast_sign(frame: object) -> float | None:
    return _SIGNS.get(frame) if type(frame) is str else None


def _plain_quat(q: object) -> tuple[float, float, float, float] | None:
    """A single attitude as four unit Python floats, or None (general path)."""
    if type(q) is Rotation:
        return q._q.tolist() if q._q.ndim == 1 else None
    t = plain_floats(q, 4)
    return None if t is None else _unit4(t)


def _finite3(a: float, b: float, c: float) -> np.ndarray | None:
    return np.array((a, b, c)) if math.isfinite(a + b + c) else None


def _is_matrix(m: object) -> TypeGuard[np.ndarray]:
    """A float64 array of shape (3, 3) (its values are checked by the caller)."""
    return type(m) is np.ndarray and m.shape == (3, 3) and m.dtype == np.float64


def _quat_arg(q: Any, name: str) -> np.ndarray:
    """Unit quaternions from an array (scalar first) or a :class:`Rotation`."""
    if hasattr(q, "as_quat") and not isinstance(q, np.ndarray):
        q = q.as_quat(scalar_first=True)  # poinsot's or SciPy's Rotation
    return as_quat(q, name)


# --------------------------------------------------------------------------
# quaternion (theory §5)
# --------------------------------------------------------------------------
def _quat_rate(q: np.ndarray, omega: np.ndarray, frame: str) -> np.ndarray:
    if frame == "body":
        return 0.5 * _qmultiply(q, _pure(omega))
    return 0.5 * _qmultiply(_pure(omega), q)


def _omega_from_quat_rate(q: np.ndarray, qdot: np.ndarray, frame: str) -> np.ndarray:
    if frame == "body":
        return 2.0 * _qmultiply(_qconjugate(q), qdot)[..., 1:]
    return 2.0 * _qmultiply(qdot, _qconjugate(q))[..., 1:]


def quat_rate(q: Rotation | ArrayLike, omega: ArrayLike, *, frame: str = "body") -> FloatArray:
    """Time derivative of the attitude quaternion (Poisson's equation, theory §5).

    Parameters
    ----------
    q : array_like, shape (..., 4), or Rotation
        Attitude quaternions, scalar first (body -> space). Non-unit ``q`` is
        normalised first (``q/|q|`` is used); zero ``q`` raises.
    omega : array_like, shape (..., 3)
        Angular velocity (rad/s) in the axes named by ``frame``.
    frame : {"body", "space"}
        ``"body"``: ``L' = 1/2 L o w_xi``; ``"space"``: ``L' = 1/2 w_x o L``.

    Returns
    -------
    qdot : ndarray, shape (..., 4)
        Derivative of the unit quaternion ``q/|q|`` (1/s), broadcast over the
        leading dimensions of ``q`` and ``omega``.

    Notes
    -----
    **Convention:** Hamilton product, scalar first; ``omega`` in rad/s, body or
    space axes as named. ``qdot`` is tangent to the unit sphere (``q . qdot = 0``).

    Examples
    --------
    >>> import numpy as np
    >>> q = [np.cos(0.25), 0.0, 0.0, np.sin(0.25)]          # 0.5 rad about z
    >>> quat_rate(q, [0.0, 0.0, 2.0]).round(4)                # spin about z
    array([-0.2474,  0.    ,  0.    ,  0.9689])
    """
    s = _fast_sign(frame)
    t, w = _plain_quat(q), plain_vec3(omega)
    if s is not None and t is not None and w is not None:
        w1, w2, w3 = w
        r = S.hamilton(*t, 0.0, w1, w2, w3) if s > 0 else S.hamilton(0.0, w1, w2, w3, *t)
        return np.array((0.5 * r[0], 0.5 * r[1], 0.5 * r[2], 0.5 * r[3]))
    frame = _frame(frame)
    q = _quat_arg(q, "q")
    omega = as_vec3(omega, "omega")
    _batch(q=(q, 1), omega=(omega, 1))
    return _quat_rate(q, omega, frame)


def omega_from_quat_rate(
    q: Rotation | ArrayLike, qdot: ArrayLike, *, frame: str = "body"
) -> FloatArray:
    """Angular velocity from the quaternion and its derivative (theory §5).

    ``w_xi = 2 vec(L~ o L')`` (body) or ``w_x = 2 vec(L' o L~)`` (space).

    Parameters
    ----------
    q : array_like, shape (..., 4), or Rotation
        Attitude quaternions, scalar first. Normalised first (a non-unit ``q``
        is read as the rotation ``q/|q|``); zero ``q`` raises.
    qdot : array_like, shape (..., 4)
        Derivative of the *unit* quaternion ``q/|q|`` (not normalised). If you
        have the derivative of a non-unit quaternion path ``Q(t)``, pass
        ``Qdot/|Q|``: the component of ``qdot`` along ``q`` only changes the
        scalar part of ``L~ o L'``, which is discarded.
    frame : {"body", "space"}
        Axes in which the result is written.

    Returns
    -------
    omega : ndarray, shape (..., 3)
        Angular velocity (rad/s).

    Notes
    -----
    **Convention:** Hamilton product, scalar first; result in rad/s in the axes
    named by ``frame``. Exact inverse of :func:`quat_rate`.

    Examples
    --------
    >>> import numpy as np
    >>> q = np.array([np.cos(0.25), 0.0, 0.0, np.sin(0.25)])
    >>> qdot = quat_rate(q, [1.0, 2.0, 3.0])
    >>> omega_from_quat_rate(q, qdot).round(12)
    array([1., 2., 3.])
    """
    s = _fast_sign(frame)
    t, d = _plain_quat(q), plain_floats(qdot, 4)
    if s is not None and t is not None and d is not None:
        w, x, y, z = t
        d0, d1, d2, d3 = d
        if s > 0:
            r = S.hamilton(w, -x, -y, -z, d0, d1, d2, d3)
        else:
            r = S.hamilton(d0, d1, d2, d3, w, -x, -y, -z)
        return np.array((2.0 * r[1], 2.0 * r[2], 2.0 * r[3]))
    frame = _frame(frame)
    q = _quat_arg(q, "q")
    qdot = as_trailing(qdot, "qdot", (4,))
    _batch(q=(q, 1), qdot=(qdot, 1))
    return _omega_from_quat_rate(q, qdot, frame)


# --------------------------------------------------------------------------
# direction cosine matrix (theory §5)
# --------------------------------------------------------------------------
_ORTHO_TOL = ORTHOGONALITY_ATOL


def _as_rotation_matrix(C: ArrayLike, name: str) -> np.ndarray:
    C = as_matrix3(C, name)
    err = np.abs(np.swapaxes(C, -1, -2) @ C - np.eye(3)).max(axis=(-2, -1), initial=0.0)
    det = np.linalg.det(C) if C.size else np.ones(C.shape[:-2])
    if np.any(err > _ORTHO_TOL) or np.any(det < 0):
        raise InvalidInputError(
            f"Expected `{name}` to be rotation matrices (C^T C = E within {_ORTHO_TOL:g}, "
            "det C = +1)."
        )
    return C


def dcm_rate(C: ArrayLike, omega: ArrayLike, *, frame: str = "body") -> FloatArray:
    """Time derivative of a direction cosine matrix (Poisson, theory §5).

    ``A' = A w_xi^`` (body) or ``A' = w_x^ A`` (space); column by column
    ``a_k' = w_x x a_k``.

    Parameters
    ----------
    C : array_like, shape (..., 3, 3)
        Rotation matrices (body -> space, ``v_space = C v_body``), orthonormal to
        1e-6.
    omega : array_like, shape (..., 3)
        Angular velocity (rad/s) in the axes named by ``frame``.
    frame : {"body", "space"}

    Returns
    -------
    Cdot : ndarray, shape (..., 3, 3)

    Notes
    -----
    **Convention:** ``C`` maps body to space components; ``omega`` in rad/s.

    Examples
    --------
    >>> import numpy as np
    >>> dcm_rate(np.eye(3), [0.0, 0.0, 1.0])
    array([[ 0., -1.,  0.],
           [ 1.,  0.,  0.],
           [ 0.,  0.,  0.]])
    """
    s = _fast_sign(frame)
    t = plain_vec3(omega)
    if s is not None and t is not None and _is_matrix(C):
        out = np.empty((3, 3))
        w = omega if type(omega) is np.ndarray else np.array(t)
        if kernels().dcm_rate1(C, w, s < 0, _ORTHO_TOL, out):
            return out
    frame = _frame(frame)
    C = _as_rotation_matrix(C, "C")
    omega = as_vec3(omega, "omega")
    _batch(C=(C, 2), omega=(omega, 1))
    return _dcm_rate(C, omega, frame)


def _dcm_rate(C: np.ndarray, omega: np.ndarray, frame: str) -> np.ndarray:
    """``A' = A w^`` (body) or ``w^ A`` (space): the formula (``poinsot.jax`` runs it too)."""
    w_hat = _hat(omega)
    return C @ w_hat if frame == "body" else w_hat @ C


def omega_from_dcm_rate(C: ArrayLike, Cdot: ArrayLike, *, frame: str = "body") -> FloatArray:
    """Angular velocity from a rotation matrix and its derivative (theory §5).

    ``w_xi^ = A^T A'`` (body) or ``w_x^ = A' A^T`` (space). The product is
    antisymmetrised before reading off the vector, so a ``Cdot`` with a small
    non-tangent (e.g. finite-difference) error still gives the best estimate.

    Parameters
    ----------
    C : array_like, shape (..., 3, 3)
        Rotation matrices (body -> space), orthonormal to 1e-6.
    Cdot : array_like, shape (..., 3, 3)
        Their time derivatives.
    frame : {"body", "space"}

    Returns
    -------
    omega : ndarray, shape (..., 3)
        Angular velocity (rad/s).

    Notes
    -----
    **Convention:** ``C`` maps body to space components; result in rad/s.

    Examples
    --------
    >>> import numpy as np
    >>> C = np.eye(3)
    >>> omega_from_dcm_rate(C, dcm_rate(C, [1.0, 2.0, 3.0]), frame="space")
    array([1., 2., 3.])
    """
    s = _fast_sign(frame)
    if s is not None and _is_matrix(C) and _is_matrix(Cdot) and math.isfinite(Cdot.sum()):
        out = np.empty(3)
        if kernels().omega_from_dcm_rate1(C, Cdot, s < 0, _ORTHO_TOL, out):
            return out
    frame = _frame(frame)
    C = _as_rotation_matrix(C, "C")
    Cdot = as_matrix3(Cdot, "Cdot")
    _batch(C=(C, 2), Cdot=(Cdot, 2))
    return _omega_from_dcm_rate(C, Cdot, frame)


def _omega_from_dcm_rate(C: np.ndarray, Cdot: np.ndarray, frame: str) -> np.ndarray:
    """``w = vee(A^T A')`` (body) or ``vee(A' A^T)`` (space), antisymmetrised."""
    Ct = np.swapaxes(C, -1, -2)
    return _vee_antisym(Ct @ Cdot if frame == "body" else Cdot @ Ct)


# --------------------------------------------------------------------------
# Euler angles, all 12 sequences (theory §3)
# --------------------------------------------------------------------------
def _elementary(axis: int, angle: np.ndarray) -> np.ndarray:
    """Rotation matrices about coordinate axis ``axis`` by ``angle``, (..., 3, 3)."""
    c, s = np.cos(angle), np.sin(angle)
    one, zero = np.ones_like(c), np.zeros_like(c)
    i, j = (axis + 1) % 3, (axis + 2) % 3
    rows = [[zero, zero, zero] for _ in range(3)]
    rows[axis][axis] = one
    rows[i][i], rows[i][j], rows[j][i], rows[j][j] = c, -s, s, c
    return np.stack([np.stack(r, axis=-1) for r in rows], axis=-2)


def _euler_matrix(seq: str, angles: np.ndarray, frame: str) -> np.ndarray:
    """Matrix ``M`` with ``omega = M @ angle_rates`` (angles in rad), (..., 3, 3).

    Column ``k`` is the axis of the ``k``-th elementary rotation written in the
    chosen frame (theory §3): the attitude is ``C = F0 F1 F2`` with
    ``F = (R_a1, R_a2, R_a3)`` for an intrinsic and ``(R_a3, R_a2, R_a1)`` for an
    extrinsic sequence; the space-frame axis of factor ``k`` is
    ``F0 .. F(k-1) e_k`` and the body-frame one ``(F(k+1) .. F2)^T e_k``.
    """
    axes, intrinsic = parse_sequence(seq)
    if len(axes) != 3:
        raise InvalidInputError(f"Expected `seq` to have 3 axes, got {seq!r}.")
    order = (0, 1, 2) if intrinsic else (2, 1, 0)
    factors = [(axes[k], k, _elementary(axes[k], angles[..., k])) for k in order]
    cols: dict[int, np.ndarray] = {}
    eye = np.broadcast_to(np.eye(3), angles.shape[:-1] + (3, 3))
    if frame == "space":
        P = eye
        for axis, k, F in factors:
            cols[k] = P[..., :, axis]
            P = P @ F
    else:
        Q = eye
        for axis, k, F in reversed(factors):
            cols[k] = Q[..., axis, :]
            Q = F @ Q
    return np.stack([cols[k] for k in range(3)], axis=-1)


def _euler_one(
    seq: object, angles: object, other: object, degrees: object, frame: object
) -> tuple[Any, np.ndarray, np.ndarray, np.ndarray, bool] | None:
    """One state of the Euler kinematics: ``(kernels, code, angles (rad), other, space)``
    as float64 arrays for the one-state compiled kernels, or ``None`` (general path)."""
    s = _fast_sign(frame)
    t = plain_vec3(angles)
    u = (0.0, 0.0, 0.0) if other is None else plain_vec3(other)
    if s is None or t is None or u is None or not (degrees is False or degrees is True):
        return None
    code = _seq(seq)[2]
    if code is None:
        return None
    if degrees:
        a = np.array((t[0] * _DEG, t[1] * _DEG, t[2] * _DEG))
    else:
        a = angles if type(angles) is np.ndarray else np.array(t)
    o = other if type(other) is np.ndarray else np.array(u)
    return kernels(), code, a, o, s < 0


_DEG = math.pi / 180.0  # the constants of np.deg2rad and np.rad2deg
_RAD = 180.0 / math.pi


def _euler_args(seq: object, angles: ArrayLike, degrees: object) -> np.ndarray:
    if not isinstance(seq, str):
        raise InvalidTypeError(f"Expected `seq` to be a string, got {type(seq).__name__}.")
    angles = as_vec3(angles, "angles")
    if as_bool(degrees, "degrees"):
        angles = np.deg2rad(angles)
    return angles


def euler_rate_matrix(
    seq: str, angles: ArrayLike, *, frame: str = "body", degrees: bool = False
) -> FloatArray:
    """The matrix ``M(angles)`` of the Euler kinematic equations ``omega = M angles'``.

    One construction for all 12 sequences (theory §3): column ``k`` is the unit
    axis of the ``k``-th elementary rotation of ``seq`` written in ``frame``
    axes. ``det M`` is ``+-sin`` (proper Euler) or ``+-cos`` (Tait-Bryan) of the
    middle angle; it vanishes at gimbal lock.

    Parameters
    ----------
    seq : str
        ``"ZXZ"``-style intrinsic (upper case) or ``"zxz"``-style extrinsic
        (lower case) sequence, or a preset ``"euler"`` (= ``"ZXZ"``) or
        ``"krylov"`` (= ``"ZXY"``).
    angles : array_like, shape (..., 3)
        The three angles in the order of ``seq``.
    frame : {"body", "space"}
    degrees : bool
        Angles in degrees. ``M`` is dimensionless either way.

    Returns
    -------
    M : ndarray, shape (..., 3, 3)

    Notes
    -----
    **Convention:** rotations as in :meth:`poinsot.Rotation.from_euler`; omega
    and angle rates in the same unit.

    Examples
    --------
    >>> euler_rate_matrix("euler", [0.0, 0.5, 0.0]).round(4)   # psi, theta, phi
    array([[0.    , 1.    , 0.    ],
           [0.4794, 0.    , 0.    ],
           [0.8776, 0.    , 1.    ]])
    """
    one = _euler_one(seq, angles, None, degrees, frame)
    if one is not None:
        k, code, a, _, space = one
        m = np.empty((3, 3))
        k.euler_matrix1(code, a, space, m)
        return m
    frame = _frame(frame)
    return _euler_matrix(seq, _euler_args(seq, angles, degrees), frame)


def omega_from_euler_rates(
    seq: str, angles: ArrayLike, rates: ArrayLike, *, frame: str = "body", degrees: bool = False
) -> FloatArray:
    """Angular velocity from Euler angles and their rates (theory §3).

    ``omega = sum_k angle_k' * (axis of the k-th elementary rotation)``. For
    ``seq="euler"`` (z-x-z, angles ``(psi, theta, phi)``) and the body frame this
    is exactly ``p = psi' sin(theta) sin(phi) + theta' cos(phi)``,
    ``q = psi' sin(theta) cos(phi) - theta' sin(phi)``,
    ``r = psi' cos(theta) + phi'``. Never singular.

    Parameters
    ----------
    seq : str
        Any of the 12 sequences, intrinsic (``"ZXZ"``) or extrinsic (``"zxz"``),
        or ``"euler"`` / ``"krylov"``.
    angles : array_like, shape (..., 3)
    rates : array_like, shape (..., 3)
        Time derivatives of the angles.
    frame : {"body", "space"}
        Axes of the returned angular velocity.
    degrees : bool
        If True, ``angles`` are in degrees and ``rates`` in deg/s. The angular
        velocity is always returned in rad/s.

    Returns
    -------
    omega : ndarray, shape (..., 3)
        Angular velocity in rad/s.

    Notes
    -----
    **Convention:** angles as in :meth:`poinsot.Rotation.from_euler`; ``omega``
    always in rad/s, ``degrees`` applies to the angles and their rates only.

    Examples
    --------
    >>> omega_from_euler_rates("euler", [0.0, 0.5, 0.0], [1.0, 0.0, 0.0]).round(4)
    array([0.    , 0.4794, 0.8776])
    >>> omega_from_euler_rates("ZYX", [10, 20, 30], [0, 0, 90], degrees=True).round(4)
    array([1.5708, 0.    , 0.    ])
    """
    one = _euler_one(seq, angles, rates, degrees, frame)
    if one is not None:
        k, code, a, d, space = one
        if degrees:
            d = d * _DEG
        out = np.empty(3)
        k.omega_from_euler_rates1(code, a, d, space, out)
        return out
    frame = _frame(frame)
    angles = _euler_args(seq, angles, degrees)
    rates = as_vec3(rates, "rates")
    _batch(angles=(angles, 1), rates=(rates, 1))
    if degrees:
        rates = np.deg2rad(rates)
    return _omega_from_euler_rates(seq, angles, rates, frame)


def _omega_from_euler_rates(
    seq: str, angles: np.ndarray, rates: np.ndarray, frame: str
) -> np.ndarray:
    """``omega = M(angles) angles'`` (radians): the formula (``poinsot.jax`` runs it too)."""
    M = _euler_matrix(seq, angles, frame)
    return np.einsum("...ij,...j->...i", M, rates)


def euler_rates(
    seq: str, angles: ArrayLike, omega: ArrayLike, *, frame: str = "body", degrees: bool = False
) -> FloatArray:
    """Euler angle rates from the angular velocity (theory §3, inverted).

    Solves ``M(angles) angles' = omega`` in closed form
    (``M^-1 = adj(M)/det M``, rows ``c2 x c3, c3 x c1, c1 x c2`` over the triple
    product of the columns). For ``seq="euler"`` and the body frame:
    ``psi' = (p sin(phi) + q cos(phi))/sin(theta)``,
    ``theta' = p cos(phi) - q sin(phi)``,
    ``phi' = r - (p sin(phi) + q cos(phi)) cot(theta)``.

    Parameters
    ----------
    seq : str
        Any of the 12 sequences, intrinsic (``"ZXZ"``) or extrinsic (``"zxz"``),
        or ``"euler"`` / ``"krylov"``.
    angles : array_like, shape (..., 3)
    omega : array_like, shape (..., 3)
        Angular velocity in rad/s, in the axes named by ``frame``.
    frame : {"body", "space"}
    degrees : bool
        If True, ``angles`` are in degrees and the returned rates in deg/s.
        ``omega`` is always in rad/s.

    Returns
    -------
    rates : ndarray, shape (..., 3)

    Warns
    -----
    GimbalLockWarning
        Where ``|det M| < GIMBAL_WARN_DET`` (1e-3): the middle angle is within
        about 0.06 deg of gimbal lock and the rates are ill-conditioned.

    Raises
    ------
    InvalidInputError
        Where ``|det M| < GIMBAL_ERROR_DET`` (1e-12): at gimbal lock the rates
        of the first and third angles are not determined.

    Notes
    -----
    **Convention:** angles as in :meth:`poinsot.Rotation.from_euler`; ``omega``
    always in rad/s, ``degrees`` applies to the angles and their rates only.

    Examples
    --------
    >>> import numpy as np
    >>> euler_rates("euler", [0.0, np.pi / 2, 0.0], [0.0, 1.0, 0.0]).round(12) + 0.0
    array([1., 0., 0.])
    """
    one = _euler_one(seq, angles, omega, degrees, frame)
    if one is not None:
        k, code, a, w, space = one
        out = np.empty(3)
        if abs(k.euler_rates1(code, a, w, space, GIMBAL_WARN_DET, out)) >= GIMBAL_WARN_DET:
            return out * _RAD if degrees else out  # else: the general path warns or raises
    frame = _frame(frame)
    angles = _euler_args(seq, angles, degrees)
    omega = as_vec3(omega, "omega")
    _batch(angles=(angles, 1), omega=(omega, 1))
    adj, det = _euler_adjugate(seq, angles, frame)
    small = np.abs(det)
    if np.any(small < GIMBAL_ERROR_DET):
        raise InvalidInputError(
            f"Euler kinematic equations of {seq!r} are singular at these `angles` (gimbal "
            "lock: the middle angle makes det M = 0, so the first and third angle rates "
            "are not determined)."
        )
    if np.any(small < GIMBAL_WARN_DET):
        warnings.warn(
            f"`angles` within {GIMBAL_WARN_DET:g} (det M) of gimbal lock for {seq!r}: the "
            "angle rates are ill-conditioned.",
            GimbalLockWarning,
            stacklevel=2,
        )
    rates = _euler_rates(adj, det, omega)
    return np.rad2deg(rates) if degrees else rates


def _euler_adjugate(seq: str, angles: np.ndarray, frame: str) -> tuple[np.ndarray, np.ndarray]:
    """``(adj M, det M)`` of the Euler rate matrix: rows ``c1 x c2``, ``c2 x c0``,
    ``c0 x c1`` of its columns ``c_k``, ``det M = c0 . (c1 x c2)``."""
    M = _euler_matrix(seq, angles, frame)
    c0, c1, c2 = M[..., :, 0], M[..., :, 1], M[..., :, 2]
    adj = np.stack([_cross(c1, c2), _cross(c2, c0), _cross(c0, c1)], axis=-2)
    return adj, _dot(c0, adj[..., 0, :])


def _euler_rates(adj: np.ndarray, det: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """``angles' = M^-1 omega = adj(M) omega / det M`` (radians per second)."""
    return np.einsum("...ij,...j->...i", adj, omega) / det[..., None]


# --------------------------------------------------------------------------
# Gibbs vector g = e tan(f/2) = l / l0
# --------------------------------------------------------------------------
def gibbs_rate(g: ArrayLike, omega: ArrayLike, *, frame: str = "body") -> FloatArray:
    """Time derivative of the Gibbs vector (Rodrigues parameters).

    ``g' = 1/2 (w + s g x w + (g.w) g)``, ``s = +1`` (body) or ``-1`` (space);
    from ``g = l/l0`` and theory §5.

    Parameters
    ----------
    g : array_like, shape (..., 3)
        Gibbs vectors ``e tan(f/2)`` (infinite at ``f = pi``).
    omega : array_like, shape (..., 3)
        Angular velocity (rad/s) in the axes named by ``frame``.
    frame : {"body", "space"}

    Returns
    -------
    gdot : ndarray, shape (..., 3)

    Notes
    -----
    **Convention:** ``g`` of the body -> space rotation; ``omega`` in rad/s.

    Examples
    --------
    >>> gibbs_rate([0.0, 0.0, 0.0], [2.0, 0.0, 0.0])
    array([1., 0., 0.])
    """
    s = _fast_sign(frame)
    t, u = plain_vec3(g), plain_vec3(omega)
    if s is not None and t is not None and u is not None:
        c, gw = S.cross(*t, *u), t[0] * u[0] + t[1] * u[1] + t[2] * u[2]
        out = _finite3(*(0.5 * (u[i] + s * c[i] + gw * t[i]) for i in range(3)))
        if out is not None:
            return out
    s = _sign(_frame(frame))
    g = as_vec3(g, "g")
    w = as_vec3(omega, "omega")
    _batch(g=(g, 1), omega=(w, 1))
    with np.errstate(over="ignore", invalid="ignore"):
        out = 0.5 * (w + s * _cross(g, w) + _dot(g, w)[..., None] * g)
    return _finite_result(out, "g")


def omega_from_gibbs_rate(g: ArrayLike, gdot: ArrayLike, *, frame: str = "body") -> FloatArray:
    """Angular velocity from the Gibbs vector and its rate.

    ``w = 2 (g' - s g x g') / (1 + g.g)``: the inverse of
    ``E + s g^ + g g^T`` is ``(E - s g^)/(1 + g.g)``.

    Parameters
    ----------
    g, gdot : array_like, shape (..., 3)
    frame : {"body", "space"}

    Returns
    -------
    omega : ndarray, shape (..., 3)
        Angular velocity (rad/s).

    Notes
    -----
    **Convention:** as :func:`gibbs_rate`, of which this is the exact inverse.

    Examples
    --------
    >>> g = [0.1, -0.2, 0.3]
    >>> omega_from_gibbs_rate(g, gibbs_rate(g, [1.0, 2.0, 3.0])).round(12)
    array([1., 2., 3.])
    """
    s = _fast_sign(frame)
    t, d = plain_vec3(g), plain_vec3(gdot)
    if s is not None and t is not None and d is not None:
        c, n = S.cross(*t, *d), 1.0 + (t[0] * t[0] + t[1] * t[1] + t[2] * t[2])
        out = _finite3(*(2.0 * (d[i] - s * c[i]) / n for i in range(3)))
        if out is not None:
            return out
    s = _sign(_frame(frame))
    g = as_vec3(g, "g")
    gd = as_vec3(gdot, "gdot")
    _batch(g=(g, 1), gdot=(gd, 1))
    return 2.0 * (gd - s * _cross(g, gd)) / (1.0 + _dot(g, g))[..., None]


# --------------------------------------------------------------------------
# modified Rodrigues parameters p = e tan(f/4) = l / (1 + l0)
# --------------------------------------------------------------------------
def mrp_rate(p: ArrayLike, omega: ArrayLike, *, frame: str = "body") -> FloatArray:
    """Time derivative of modified Rodrigues parameters (MRP).

    ``p' = 1/4 [(1 - p.p) E + 2 s p^ + 2 p p^T] w``, ``s = +1`` (body) or
    ``-1`` (space). The same equation holds for the shadow set
    (:func:`mrp_shadow`), so a propagation may switch sets at any time.

    Parameters
    ----------
    p : array_like, shape (..., 3)
        MRPs ``e tan(f/4)`` (either set).
    omega : array_like, shape (..., 3)
        Angular velocity (rad/s) in the axes named by ``frame``.
    frame : {"body", "space"}

    Returns
    -------
    pdot : ndarray, shape (..., 3)

    Notes
    -----
    **Convention:** ``p`` of the body -> space rotation; ``omega`` in rad/s.

    Examples
    --------
    >>> mrp_rate([0.0, 0.0, 0.0], [0.0, 4.0, 0.0])
    array([0., 1., 0.])
    """
    s = _fast_sign(frame)
    t, u = plain_vec3(p), plain_vec3(omega)
    if s is not None and t is not None and u is not None:
        c = S.cross(*t, *u)
        pp = t[0] * t[0] + t[1] * t[1] + t[2] * t[2]
        pw = t[0] * u[0] + t[1] * u[1] + t[2] * u[2]
        out = _finite3(
            *(0.25 * ((1.0 - pp) * u[i] + 2.0 * s * c[i] + 2.0 * pw * t[i]) for i in range(3))
        )
        if out is not None:
            return out
    s = _sign(_frame(frame))
    p = as_vec3(p, "p")
    w = as_vec3(omega, "omega")
    _batch(p=(p, 1), omega=(w, 1))
    with np.errstate(over="ignore", invalid="ignore"):
        p2 = _dot(p, p)[..., None]
        out = 0.25 * ((1.0 - p2) * w + 2.0 * s * _cross(p, w) + 2.0 * _dot(p, w)[..., None] * p)
    return _finite_result(out, "p")


def omega_from_mrp_rate(p: ArrayLike, pdot: ArrayLike, *, frame: str = "body") -> FloatArray:
    """Angular velocity from MRPs and their rate.

    ``w = 4 [(1 - p.p) E - 2 s p^ + 2 p p^T] p' / (1 + p.p)^2`` (the MRP rate
    matrix ``B`` satisfies ``B^T B = (1 + p.p)^2 E``).

    Parameters
    ----------
    p, pdot : array_like, shape (..., 3)
    frame : {"body", "space"}

    Returns
    -------
    omega : ndarray, shape (..., 3)
        Angular velocity (rad/s).

    Notes
    -----
    **Convention:** as :func:`mrp_rate`, of which this is the exact inverse.

    Examples
    --------
    >>> p = [0.1, -0.2, 0.3]
    >>> omega_from_mrp_rate(p, mrp_rate(p, [1.0, 2.0, 3.0])).round(12)
    array([1., 2., 3.])
    """
    s = _fast_sign(frame)
    t, d = plain_vec3(p), plain_vec3(pdot)
    if s is not None and t is not None and d is not None:
        c = S.cross(*t, *d)
        pp = t[0] * t[0] + t[1] * t[1] + t[2] * t[2]
        pd_ = t[0] * d[0] + t[1] * d[1] + t[2] * d[2]
        k = 1.0 + pp
        out = _finite3(
            *(
                4.0 * ((1.0 - pp) * d[i] - 2.0 * s * c[i] + 2.0 * pd_ * t[i]) / (k * k)
                for i in range(3)
            )
        )
        if out is not None:
            return out
    s = _sign(_frame(frame))
    p = as_vec3(p, "p")
    pd = as_vec3(pdot, "pdot")
    _batch(p=(p, 1), pdot=(pd, 1))
    with np.errstate(over="ignore", invalid="ignore"):
        p2 = _dot(p, p)[..., None]
        num = (1.0 - p2) * pd - 2.0 * s * _cross(p, pd) + 2.0 * _dot(p, pd)[..., None] * p
        out = 4.0 * num / (1.0 + p2) ** 2
    return _finite_result(out, "p")


def mrp_shadow(p: ArrayLike) -> FloatArray:
    """The shadow MRP set ``p_s = -p / (p.p)`` (same rotation, ``|p_s| = 1/|p|``).

    Parameters
    ----------
    p : array_like, shape (..., 3)
        Non-zero MRPs (the identity ``p = 0`` has its shadow at infinity).

    Returns
    -------
    p_shadow : ndarray, shape (..., 3)

    Notes
    -----
    **Convention:** the shadow set describes the rotation ``f - 2 pi`` about the
    same axis: ``e tan((f - 2 pi)/4) = -e cot(f/4)``.

    Examples
    --------
    >>> mrp_shadow([0.0, 0.0, 2.0])
    array([-0. , -0. , -0.5])
    """
    p = as_vec3(p, "p")
    # scaled by the largest component so that |p|^2 neither overflows nor underflows
    m = np.max(np.abs(p), axis=-1, initial=0.0)[..., None]
    if np.any(m == 0.0):
        raise InvalidInputError("Expected `p` to be non-zero (the shadow of p = 0 is at infinity).")
    u = p / m
    with np.errstate(over="ignore"):
        out = -(u / _dot(u, u)[..., None]) / m
    return _finite_result(out, "p")


def mrp_switch(p: ArrayLike, *, threshold: float = 1.0) -> FloatArray:
    """Switch MRPs to their shadow set where ``|p| > threshold`` (keeps ``|p| <= 1``).

    The usual rule for propagating MRPs: after each step, replace ``p`` by
    ``-p/|p|^2`` once it leaves the unit ball, which keeps ``p`` away from the
    singularity at ``f = 2 pi``.

    Parameters
    ----------
    p : array_like, shape (..., 3)
    threshold : float
        Switching radius, at least 1 (the two sets swap roles at ``|p| = 1``).

    Returns
    -------
    p : ndarray, shape (..., 3)

    Notes
    -----
    **Convention:** MRPs of the body -> space rotation, as :func:`mrp_shadow`.

    Examples
    --------
    >>> mrp_switch([[0.0, 0.0, 2.0], [0.0, 0.5, 0.0]])
    array([[ 0. ,  0. , -0.5],
           [ 0. ,  0.5,  0. ]])
    """
    p = as_vec3(p, "p")
    if not (
        isinstance(threshold, numbers.Real)
        and not isinstance(threshold, bool)
        and 1.0 <= threshold < 1e150
    ):
        raise InvalidInputError(
            f"Expected `threshold` to be a number >= 1 (and < 1e150), got {threshold!r}."
        )
    pp = _dot(p, p)
    out = pp > threshold**2
    safe = np.where(out, pp, 1.0)[..., None]
    return np.where(out[..., None], -p / safe, p) + 0.0


# --------------------------------------------------------------------------
# rotation vector phi = f e
# --------------------------------------------------------------------------
def _rotvec_coefficients(f: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``c = (1 - (f/2) cot(f/2))/f^2`` (for ``J^-1``), ``k1 = (1 - cos f)/f^2``,
    ``k2 = (f - sin f)/f^3`` (for ``J``), with Taylor series below
    ``ROTVEC_SERIES_ANGLE``."""
    f = np.asarray(f, dtype=float)
    small = f < ROTVEC_SERIES_ANGLE
    fs = np.where(small, ROTVEC_SERIES_ANGLE, f)  # keep the closed forms finite
    f2 = f * f
    with np.errstate(divide="ignore", invalid="ignore"):
        c_big = (1.0 - 0.5 * fs / np.tan(0.5 * fs)) / fs**2
    c_small = 1 / 12 + f2 * (1 / 720 + f2 * (1 / 30240 + f2 / 1209600))
    k1_big = (1.0 - np.cos(fs)) / fs**2
    k1_small = 0.5 - f2 * (1 / 24 - f2 * (1 / 720 - f2 / 40320))
    k2_big = (fs - np.sin(fs)) / fs**3
    k2_small = 1 / 6 - f2 * (1 / 120 - f2 * (1 / 5040 - f2 / 362880))
    return (
        np.where(small, c_small, c_big),
        np.where(small, k1_small, k1_big),
        np.where(small, k2_small, k2_big),
    )


def _rotvec_coefficients_one(f: float) -> tuple[float, float, float]:
    """:func:`_rotvec_coefficients` for one angle (Python floats, same expressions)."""
    f2 = f * f
    if f < ROTVEC_SERIES_ANGLE:
        return (
            1 / 12 + f2 * (1 / 720 + f2 * (1 / 30240 + f2 / 1209600)),
            0.5 - f2 * (1 / 24 - f2 * (1 / 720 - f2 / 40320)),
            1 / 6 - f2 * (1 / 120 - f2 * (1 / 5040 - f2 / 362880)),
        )
    return (
        (1.0 - 0.5 * f / math.tan(0.5 * f)) / f**2,
        (1.0 - math.cos(f)) / f**2,
        (f - math.sin(f)) / f**3,
    )


def _rotvec_one(rotvec: object, other: object, frame: object, inverse: bool) -> np.ndarray | None:
    """One state of :func:`rotvec_rate` (``inverse=False``) or
    :func:`omega_from_rotvec_rate` (``True``) on Python floats, or ``None`` (general
    path: also every case that warns or raises)."""
    s = _fast_sign(frame)
    t, u = plain_vec3(rotvec), plain_vec3(other)
    if s is None or t is None or u is None:
        return None
    f = math.sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2])
    if not f <= ROTVEC_MAX_ANGLE:
        return None
    k = round(f / (2 * math.pi))
    if not inverse and k > 0 and abs(f - 2 * math.pi * k) < ROTVEC_WARN_GAP:
        return None
    c, k1, k2 = _rotvec_coefficients_one(f)
    a = S.cross(*t, *u)
    b = S.cross(t[0], t[1], t[2], *a)
    if inverse:  # J phi' = phi' - s k1 phi x phi' + k2 phi x (phi x phi')
        return np.array([u[i] - s * k1 * a[i] + k2 * b[i] for i in range(3)])
    # J^-1 w = w + s/2 phi x w + c phi x (phi x w)
    return np.array([u[i] + 0.5 * s * a[i] + c * b[i] for i in range(3)])


def _rotvec_rate(phi: np.ndarray, w: np.ndarray, s: float) -> np.ndarray:
    """``J^-1 w = w + s/2 phi x w + c phi x (phi x w)`` (no validation)."""
    f = np.sqrt(_dot(phi, phi))
    c = _rotvec_coefficients(f)[0][..., None]
    pxw = _cross(phi, w)
    return w + 0.5 * s * pxw + c * _cross(phi, pxw)


def _rotvec_jacobian_apply(phi: np.ndarray, phidot: np.ndarray, s: float) -> np.ndarray:
    """``J phi' = phi' - s k1 phi x phi' + k2 phi x (phi x phi')`` (no validation).

    ``J = J_r`` (body, ``s = +1``) or ``J_l`` (space, ``s = -1``): the angular
    velocity of ``exp(phi^)`` when ``phi`` changes at rate ``phi'``.
    """
    f = np.sqrt(_dot(phi, phi))
    _, k1, k2 = _rotvec_coefficients(f)
    pxd = _cross(phi, phidot)
    return phidot - s * k1[..., None] * pxd + k2[..., None] * _cross(phi, pxd)


#: Largest rotation angle (rad) the rotation-vector rates accept: beyond it the
#: spacing of doubles exceeds 1e-3 rad and ``cot(f/2)`` has no correct digit left.
ROTVEC_MAX_ANGLE = 1e12


def _check_rotvec_angle(f: np.ndarray) -> None:
    if np.any(f > ROTVEC_MAX_ANGLE):
        raise InvalidInputError(
            f"Expected `rotvec` to have a norm (rotation angle) below {ROTVEC_MAX_ANGLE:g} rad, "
            f"got {float(np.max(f)):g}: reduce the angle modulo 2 pi first."
        )


def rotvec_rate(rotvec: ArrayLike, omega: ArrayLike, *, frame: str = "body") -> FloatArray:
    """Time derivative of the rotation vector (Bortz's equation).

    ``phi' = w + s/2 phi x w + (1/f^2)(1 - (f/2) cot(f/2)) phi x (phi x w)``
    with ``f = |phi|``, ``s = +1`` (body) or ``-1`` (space); a Taylor series
    ``1/12 + f^2/720 + f^4/30240 + ...`` replaces the coefficient below
    ``f = 0.1``.

    Parameters
    ----------
    rotvec : array_like, shape (..., 3)
        Rotation vectors ``phi = f e``.
    omega : array_like, shape (..., 3)
        Angular velocity (rad/s) in the axes named by ``frame``.
    frame : {"body", "space"}

    Returns
    -------
    rotvec_dot : ndarray, shape (..., 3)

    Warns
    -----
    SingularityWarning
        Where ``|phi|`` is within ``ROTVEC_WARN_GAP`` (0.01 rad) of a non-zero
        multiple of ``2 pi``; raises :class:`InvalidInputError` within 1e-12.

    Notes
    -----
    **Convention:** ``exp(phi^)`` maps body to space components; rad, rad/s.

    Examples
    --------
    >>> import numpy as np
    >>> rotvec_rate([0.0, 0.0, 1.0], [0.0, 0.0, 3.0])   # spin about the axis
    array([0., 0., 3.])
    >>> rotvec_rate([0.0, 0.0, np.pi / 2], [1.0, 0.0, 0.0]).round(4)
    array([0.7854, 0.7854, 0.    ])
    """
    one = _rotvec_one(rotvec, omega, frame, inverse=False)
    if one is not None:
        return one
    s = _sign(_frame(frame))
    phi = as_vec3(rotvec, "rotvec")
    w = as_vec3(omega, "omega")
    _batch(rotvec=(phi, 1), omega=(w, 1))
    f = np.sqrt(_dot(phi, phi))
    _check_rotvec_angle(f)
    k = np.round(f / (2 * np.pi))
    gap = np.abs(f - 2 * np.pi * k)[k > 0]
    if np.any(gap < 1e-12):
        raise InvalidInputError(
            "Expected `rotvec` to have a norm different from a non-zero multiple of 2 pi "
            "(the rotation-vector rate is singular there)."
        )
    if np.any(gap < ROTVEC_WARN_GAP):
        warnings.warn(
            "`rotvec` is close to a non-zero multiple of 2 pi, where its rate is singular.",
            SingularityWarning,
            stacklevel=2,
        )
    return _rotvec_rate(phi, w, s)


def omega_from_rotvec_rate(
    rotvec: ArrayLike, rotvec_dot: ArrayLike, *, frame: str = "body"
) -> FloatArray:
    """Angular velocity from the rotation vector and its rate.

    ``w = phi' - s (1 - cos f)/f^2 phi x phi' + (f - sin f)/f^3 phi x (phi x phi')``
    (``J_r`` for the body frame, ``J_l`` for the space frame); series below
    ``f = 0.1``. Never singular.

    Parameters
    ----------
    rotvec, rotvec_dot : array_like, shape (..., 3)
    frame : {"body", "space"}

    Returns
    -------
    omega : ndarray, shape (..., 3)
        Angular velocity (rad/s).

    Notes
    -----
    **Convention:** as :func:`rotvec_rate`, of which this is the exact inverse.

    Examples
    --------
    >>> v = [0.3, -1.0, 2.0]
    >>> omega_from_rotvec_rate(v, rotvec_rate(v, [1.0, 2.0, 3.0])).round(12)
    array([1., 2., 3.])
    """
    one = _rotvec_one(rotvec, rotvec_dot, frame, inverse=True)
    if one is not None:
        return one
    s = _sign(_frame(frame))
    phi = as_vec3(rotvec, "rotvec")
    d = as_vec3(rotvec_dot, "rotvec_dot")
    _batch(rotvec=(phi, 1), rotvec_dot=(d, 1))
    _check_rotvec_angle(np.sqrt(_dot(phi, phi)))
    return _rotvec_jacobian_apply(phi, d, s)
