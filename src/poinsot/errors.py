"""Exceptions and warnings raised by poinsot.

Every error poinsot raises on purpose derives from :class:`PoinsotError`, so
``except poinsot.PoinsotError`` catches all of them; each also derives from the
builtin a NumPy/SciPy user would expect (``ValueError`` for bad values,
``TypeError`` for wrong types, ``RuntimeError`` for a failed computation).

Examples
--------
>>> import poinsot
>>> issubclass(poinsot.InvalidInputError, ValueError)
True
>>> issubclass(poinsot.InvalidInputError, poinsot.PoinsotError)
True
"""

from __future__ import annotations

__all__ = [
    "PoinsotError",
    "InvalidInputError",
    "InvalidTypeError",
    "IntegrationError",
    "PoinsotWarning",
    "GimbalLockWarning",
    "SingularityWarning",
    "AccuracyWarning",
]


class PoinsotError(Exception):
    """Base class of every error raised by poinsot."""


class InvalidInputError(PoinsotError, ValueError):
    """An argument has the wrong shape, a non-finite or out-of-range value."""


class InvalidTypeError(PoinsotError, TypeError):
    """An argument has the wrong type (e.g. a string where an array is expected)."""


class IntegrationError(PoinsotError, RuntimeError):
    """A numerical integration failed (diverged, became non-finite, stalled)."""


class PoinsotWarning(UserWarning):
    """Base class of the warnings poinsot issues."""


class GimbalLockWarning(PoinsotWarning):
    """Euler/Tait-Bryan angles requested at (or within the documented threshold
    of) a singular middle angle: the first and third angles are not separately
    determined there."""


class SingularityWarning(PoinsotWarning):
    """A computation is close to a singularity of its formula (e.g. Euler
    kinematic equations near gimbal lock, a near-separatrix free body)."""


class AccuracyWarning(PoinsotWarning):
    """A result is less accurate than the documented tolerance."""
