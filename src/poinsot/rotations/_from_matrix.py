"""A rotation from a nearly orthogonal matrix given by a user (a scenario's
``[attitude] matrix``, ``poinsot convert matrix ...``), projected onto the nearest
rotation with a warning saying by how much it moved."""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from ..errors import AccuracyWarning, PoinsotError
from .rotation import Rotation

__all__ = ["MATRIX_TOLERANCE", "PROJECTION_WARN", "rotation_from_matrix"]

#: Default of ``[attitude] tolerance``: the largest ``max |A^T A - E|`` of a matrix that
#: is accepted (and projected onto the nearest rotation).
MATRIX_TOLERANCE = 1e-6
#: A projection that moves an entry by more than this is reported with a warning.
PROJECTION_WARN = 1e-12


def rotation_from_matrix(
    values: Any,
    tolerance: float = MATRIX_TOLERANCE,
    *,
    where: str = "matrix",
    knob: str = "`tolerance`",
) -> Any:
    """A rotation from a nearly orthogonal matrix, projected onto the nearest rotation
    (SVD) when it is not orthogonal to round-off, with an
    :class:`~poinsot.errors.AccuracyWarning` saying by how much it moved.

    ``tolerance`` bounds ``max |A^T A - E|`` (the matrix is refused above it, with a
    message naming ``knob``, the setting that raises it); ``where`` starts the warning.

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     r = rotation_from_matrix([[0, -1, 0], [1, 0, 0.0001], [0, 0, 1]], 1e-3)
    >>> "projected" in str(w[0].message)
    True
    """
    m = np.asarray(values, dtype=float)
    try:
        r = Rotation.from_matrix(m, atol=tolerance)
    except PoinsotError as exc:
        msg = str(exc)
        if "orthogonal within" in msg:
            msg += f" Raise {knob} to accept it (it is then projected)."
        raise type(exc)(msg.replace("`matrix`", "the matrix")) from None
    moved = float(np.max(np.abs(r.as_matrix() - m)))
    if moved > PROJECTION_WARN:
        warnings.warn(
            f"{where}: the matrix is not orthogonal (tolerance {tolerance:g}); it was "
            f"projected onto the nearest rotation, which moved an entry by up to {moved:.3g}.",
            AccuracyWarning,
            stacklevel=2,
        )
    return r
