"""Quaternion algebra (theory §1), on arrays of shape ``(..., 4)``.

**Convention:** Hamilton quaternions (``i1 o i2 = i3``), stored scalar first
``[l0, l1, l2, l3]``. Every function broadcasts over leading dimensions like a
NumPy ufunc. Quaternions here need not be unit: :func:`norm_squared` is the
notes' norm ``||L|| = L o L~``, :func:`norm` the length ``|L|``.

Examples
--------
>>> from poinsot import quaternion as Q
>>> i, j = [0, 1, 0, 0], [0, 0, 1, 0]
>>> Q.multiply(i, j)          # i1 o i2 = i3
array([0., 0., 0., 1.])
>>> Q.multiply(j, i)          # anticommuting
array([ 0.,  0.,  0., -1.])
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .._jit import primitive
from .._typing import ArrayLike, FloatArray
from .._validate import as_float_array, as_trailing, as_vec3
from .._vec import length as length_array
from .._vec import unit
from ..errors import InvalidInputError
from ._lazy import kernels

__all__ = [
    "multiply",
    "conjugate",
    "norm",
    "norm_squared",
    "inverse",
    "exp",
    "log",
    "power",
    "rotate",
    "normalize",
]


#: Largest real part whose exponential is finite in float64 (``log(DBL_MAX)``).
_LOG_MAX = float(np.log(np.finfo(np.float64).max))


def _quat(q: ArrayLike, name: str = "q") -> np.ndarray:
    return as_trailing(q, name, (4,))


def _nonzero(q: np.ndarray, name: str) -> np.ndarray:
    """Lengths ``|q|`` (robust, see :func:`length_array`); a zero quaternion raises."""
    n = length_array(q)
    if np.any(n == 0.0):
        raise InvalidInputError(f"Expected `{name}` to be non-zero quaternions, got a zero one.")
    return n


def normalize_array(q: np.ndarray, name: str = "quat") -> np.ndarray:
    """``q / |q|`` for validated float arrays (..., 4); a zero quaternion raises."""
    return unit(q, _nonzero(q, name))


def _checked(kernel: Callable[..., np.ndarray], what: str, *args: np.ndarray) -> np.ndarray:
    # A float64 overflow inside a kernel becomes a named error instead of inf/NaN
    # and a RuntimeWarning.
    with np.errstate(over="raise", invalid="raise"):
        try:
            return kernel(*args)
        except FloatingPointError:
            raise InvalidInputError(
                f"Expected {what} to stay within float64 range, but it overflows."
            ) from None


def _broadcast(name_a: str, a: np.ndarray, name_b: str, b: np.ndarray) -> None:
    try:
        np.broadcast_shapes(a.shape[:-1], b.shape[:-1])
    except ValueError:
        raise InvalidInputError(
            f"Expected the leading shapes of `{name_a}` {a.shape[:-1]} and `{name_b}` "
            f"{b.shape[:-1]} to broadcast."
        ) from None


@primitive  # validates, then a compiled kernel: poinsot.jax runs its own product
def multiply(p: ArrayLike, q: ArrayLike) -> FloatArray:
    """Hamilton product ``P o Q``.

    ``P o Q = p0 q0 - p.q + p0 q + q0 p + p x q`` (theory §1).

    Parameters
    ----------
    p, q : array_like, shape (..., 4)
        Scalar-first quaternions; leading shapes broadcast.

    Returns
    -------
    ndarray, shape (..., 4)

    Notes
    -----
    **Convention:** Hamilton, scalar first. ``multiply(q2, q1)`` is the rotation
    ``q1`` followed by ``q2`` about fixed axes (theory §4).

    Examples
    --------
    >>> multiply([1, 2, 3, 4], [5, 6, 7, 8])
    array([-60.,  12.,  30.,  24.])
    """
    p, q = _quat(p, "p"), _quat(q, "q")
    _broadcast("p", p, "q", q)
    return _checked(kernels().qmul, "the product of `p` and `q`", p, q)


@primitive  # writes into its result: poinsot.jax runs its own
def conjugate(q: ArrayLike) -> FloatArray:
    """Conjugate ``L~ = l0 - l`` (theory §1).

    Examples
    --------
    >>> conjugate([1.0, 2.0, 3.0, 4.0])
    array([ 1., -2., -3., -4.])
    """
    return conjugate_array(_quat(q))


def conjugate_array(q: np.ndarray) -> np.ndarray:
    """:func:`conjugate` without validation (for trusted float arrays, hot paths)."""
    # negate all, restore the scalar: two streaming passes, 2x faster than `q * [1, -1, -1, -1]`
    out = np.negative(q)
    out[..., 0] = q[..., 0]
    return out


def canonical_array(q: np.ndarray) -> np.ndarray:
    """Sign choice making ``q`` unique (as SciPy): ``w > 0``, or the first non-zero ``> 0``."""
    first_nonzero = np.argmax(q != 0, axis=-1)
    lead = np.take_along_axis(q, first_nonzero[..., None], axis=-1)
    return np.where(lead < 0, -q, q)


def norm_squared(q: ArrayLike) -> FloatArray:
    """The notes' norm ``||L|| = L o L~ = l0^2 + |l|^2`` (theory §1).

    Examples
    --------
    >>> float(norm_squared([1.0, 2.0, 3.0, 4.0]))
    30.0
    """
    q = _quat(q)
    return np.einsum("...i,...i->...", q, q)[()]


def norm(q: ArrayLike) -> FloatArray:
    """Length ``|L| = sqrt(||L||)`` (theory §1).

    Examples
    --------
    >>> float(norm([0.0, 3.0, 0.0, 4.0]))
    5.0
    """
    return length_array(_quat(q))[()]


def normalize(q: ArrayLike) -> FloatArray:
    """``L / |L|``; a zero quaternion raises :class:`~poinsot.InvalidInputError`.

    Examples
    --------
    >>> normalize([0.0, 3.0, 0.0, 4.0])
    array([0. , 0.6, 0. , 0.8])
    """
    return normalize_array(_quat(q), "q")


def inverse(q: ArrayLike) -> FloatArray:
    """Inverse ``L^-1 = L~ / ||L||`` for ``L != 0`` (theory §1).

    Examples
    --------
    >>> multiply([1.0, 2.0, 3.0, 4.0], inverse([1.0, 2.0, 3.0, 4.0])).round(15) + 0.0
    array([1., 0., 0., 0.])
    """
    q = _quat(q)
    n = _nonzero(q, "q")[..., None]
    return conjugate_array(q) / n / n  # two divisions: |q|^2 may over/underflow


def exp(q: ArrayLike) -> FloatArray:
    """Quaternion exponential ``exp(a + v) = e^a (cos|v| + v/|v| sin|v|)``.

    The analogue of de Moivre's formula (theory §1); for a pure quaternion
    ``(0, f e / 2)`` it gives the unit quaternion of the rotation by ``f``
    about ``e`` (theory §2). ``sin|v|/|v|`` is evaluated without cancellation
    near ``v = 0``.

    Examples
    --------
    >>> import numpy as np
    >>> exp([0.0, 0.0, 0.0, np.pi / 4]).round(8)     # 90 deg about z
    array([0.70710678, 0.        , 0.        , 0.70710678])
    """
    return _exp(_quat(q), "Expected the scalar part of `q` to be at most")


def _exp(q: np.ndarray, message: str) -> np.ndarray:
    a, v = q[..., 0], q[..., 1:]
    if np.any(a > _LOG_MAX):
        raise InvalidInputError(f"{message} {_LOG_MAX:.6g} (e^a overflows float64).")
    n = length_array(v)
    ea = np.exp(a)
    out = np.empty(q.shape)
    out[..., 0] = ea * np.cos(n)
    out[..., 1:] = (ea * np.sinc(n / np.pi))[..., None] * v
    return out


def log(q: ArrayLike) -> FloatArray:
    """Quaternion logarithm ``log L = log|L| + e f`` with ``L = |L|(cos f + e sin f)``.

    ``f = atan2(|l|, l0)`` lies in ``[0, pi]``. For a negative real ``L`` the
    axis ``e`` is undetermined and ``i1`` is used (any unit axis is a valid
    logarithm). A zero quaternion raises :class:`~poinsot.InvalidInputError`.

    Examples
    --------
    >>> log(exp([0.0, 0.1, 0.2, 0.3])).round(15)
    array([0. , 0.1, 0.2, 0.3])
    """
    q = _quat(q)
    length_q = _nonzero(q, "q")
    a, v = q[..., 0], q[..., 1:]
    n = length_array(v)
    f = np.arctan2(n, a)
    # f / n -> 1 / a as n -> 0 with a > 0 (atan2 keeps full accuracy for n > 0).
    safe = n > 0
    scale = np.where(safe, f / np.where(safe, n, 1.0), 1.0 / np.where(a != 0, a, 1.0))
    out = np.empty(q.shape)
    out[..., 0] = np.log(length_q)
    out[..., 1:] = scale[..., None] * v
    neg_real = (~safe) & (a < 0)
    if np.any(neg_real):
        out[..., 1] = np.where(neg_real, np.pi, out[..., 1])
    return out


def power(q: ArrayLike, t: ArrayLike) -> FloatArray:
    """Real power ``L^t = |L|^t (cos tf + e sin tf) = exp(t log L)`` (theory §1, de Moivre).

    Parameters
    ----------
    q : array_like, shape (..., 4)
    t : array_like, shape (...)
        Exponents, broadcast against the leading shape of ``q``.

    Examples
    --------
    >>> import numpy as np
    >>> q = exp([0.0, 0.0, 0.0, np.pi / 4])      # 90 deg about z
    >>> power(q, 2).round(12) + 0.0               # 180 deg about z
    array([0., 0., 0., 1.])
    """
    t = as_float_array(t, "t")
    q = _quat(q)
    try:
        np.broadcast_shapes(q.shape[:-1], t.shape)
    except ValueError:
        raise InvalidInputError(
            f"Expected the leading shape of `q` {q.shape[:-1]} and the shape of `t` {t.shape} "
            "to broadcast."
        ) from None
    with np.errstate(over="ignore", invalid="ignore"):
        lt = log(q) * t[..., None]
    if not np.all(np.isfinite(lt[..., 1:])):
        raise InvalidInputError("Expected `t` times the angle of `q` to stay within float64 range.")
    return _exp(lt, "Expected `t` log|q| to be at most")


def rotate(q: ArrayLike, v: ArrayLike) -> FloatArray:
    """The sandwich ``q o v o q~`` of a vector ``v`` (as a pure quaternion).

    For a unit ``q = cos(f/2) + e sin(f/2)`` this rotates ``v`` by ``f`` about
    ``e`` (right-handed, theory §2); for a non-unit ``q`` the result is scaled by
    ``||q||``. Expanded: ``v' = (q0^2 - |q|^2) v + 2 (q.v) q + 2 q0 (q x v)``.

    Parameters
    ----------
    q : array_like, shape (..., 4)
    v : array_like, shape (..., 3)

    Returns
    -------
    ndarray, shape (..., 3)

    Examples
    --------
    >>> import numpy as np
    >>> q = [np.cos(np.pi / 4), 0.0, 0.0, np.sin(np.pi / 4)]   # 90 deg about z
    >>> rotate(q, [1.0, 0.0, 0.0]).round(12) + 0.0
    array([0., 1., 0.])
    """
    q, v = _quat(q), as_vec3(v, "v")
    _broadcast("q", q, "v", v)
    return _checked(kernels().qrot, "`rotate(q, v)`", q, v)
