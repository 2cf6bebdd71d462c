"""Input validation at the public entry points.

Every public function turns its array arguments into float64 NumPy arrays here,
so that a wrong shape, a non-numeric or a non-finite value is reported with the
argument's name and what was expected, e.g.
``Expected `quat` to have shape (..., 4), got (3,).`` Internal kernels then
trust their inputs (no validation inside hot loops).
"""

from __future__ import annotations

import numbers
from collections.abc import Sequence

import numpy as np

from ._vec import length, unit
from .errors import InvalidInputError, InvalidTypeError

__all__ = [
    "as_float_array",
    "as_trailing",
    "as_quat",
    "as_vec3",
    "as_matrix3",
    "as_positive",
    "as_bool",
    "as_choice",
    "as_times",
]


def _shape_str(tail: Sequence[int | None]) -> str:
    parts = ["..."] + ["n" if d is None else str(d) for d in tail]
    return "(" + ", ".join(parts) + ")"


def as_float_array(x, name: str, *, finite: bool = True) -> np.ndarray:
    """Convert ``x`` to a float64 array, checking it is numeric (and finite)."""
    if isinstance(x, str | bytes):
        raise InvalidTypeError(f"Expected `{name}` to be array-like of numbers, got a string.")
    if x is None:
        raise InvalidTypeError(f"Expected `{name}` to be array-like of numbers, got None.")
    try:
        a = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidTypeError(
            f"Expected `{name}` to be array-like of real numbers, got {type(x).__name__}: {exc}"
        ) from None
    if finite and not np.all(np.isfinite(a)):
        raise InvalidInputError(f"Expected `{name}` to contain only finite values (no NaN/inf).")
    return a


def as_trailing(x, name: str, tail: Sequence[int | None], *, finite: bool = True) -> np.ndarray:
    """Array with trailing shape ``tail`` (``None`` = any length) and any leading shape."""
    a = as_float_array(x, name, finite=finite)
    k = len(tail)
    ok = a.ndim >= k and all(
        t is None or s == t for s, t in zip(a.shape[a.ndim - k :], tail, strict=True)
    )
    if not ok:
        raise InvalidInputError(
            f"Expected `{name}` to have shape {_shape_str(tail)}, got {a.shape}."
        )
    return a


def as_quat(q, name: str = "quat", *, normalize: bool = True) -> np.ndarray:
    """Quaternions of shape ``(..., 4)``, scalar first; non-zero; normalised if asked."""
    a = as_trailing(q, name, (4,))
    n = length(a)  # overflow/underflow-free: (1e200, 1e200, 0, 0) is a valid quaternion
    if np.any(n == 0.0):
        raise InvalidInputError(f"Expected `{name}` to be non-zero quaternions, got a zero one.")
    if normalize:
        a = unit(a, n)
    return a


def as_vec3(v, name: str) -> np.ndarray:
    """3-vectors of shape ``(..., 3)``."""
    return as_trailing(v, name, (3,))


def as_matrix3(m, name: str) -> np.ndarray:
    """3x3 matrices of shape ``(..., 3, 3)``."""
    return as_trailing(m, name, (3, 3))


def as_positive(x, name: str, *, strict: bool = True) -> np.ndarray:
    """Real numbers that must be > 0 (or >= 0 if ``strict=False``)."""
    a = as_float_array(x, name)
    bad = a <= 0 if strict else a < 0
    if np.any(bad):
        word = "positive" if strict else "non-negative"
        raise InvalidInputError(
            f"Expected `{name}` to be {word}, got {float(a[bad].ravel()[0])!r}."
        )
    return a


def as_bool(value, name: str) -> bool:
    """A Python or NumPy bool (e.g. ``degrees``); anything else is a type error."""
    if not isinstance(value, bool | np.bool_):
        raise InvalidTypeError(f"Expected `{name}` to be a bool, got {value!r}.")
    return bool(value)


def as_choice(value, name: str, choices: Sequence[str]) -> str:
    """A string that must be one of ``choices``."""
    if not isinstance(value, str) or value not in choices:
        opts = ", ".join(repr(c) for c in choices)
        raise InvalidInputError(f"Expected `{name}` to be one of {opts}, got {value!r}.")
    return value


def as_times(t, name: str = "t", *, min_len: int = 1, strictly_increasing: bool = True):
    """A 1-D array of finite, strictly increasing times with at least ``min_len`` samples."""
    a = as_float_array(t, name)
    if a.ndim != 1:
        raise InvalidInputError(f"Expected `{name}` to have shape (n,), got {a.shape}.")
    if a.size < min_len:
        raise InvalidInputError(
            f"Expected `{name}` to have at least {min_len} samples, got {a.size}."
        )
    if strictly_increasing and a.size > 1 and not np.all(np.diff(a) > 0):
        raise InvalidInputError(f"Expected `{name}` to be strictly increasing.")
    return a


def is_integer(x) -> bool:
    return isinstance(x, numbers.Integral) and not isinstance(x, bool)
