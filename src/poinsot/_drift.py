"""Relative change and drift of a quantity along a run: the one definition (private).

A quantity ``x`` sampled at times ``t_k`` (axis 0; a batch after it) that should stay
at ``x_0`` (or follow ``expected``) changes by ``d_k = x_k - x_0`` (a scalar, signed)
or ``d_k = |x_k - x_0|`` (a vector, ``vector=True``, the norm over the last axis).
Its *relative change* is ``d_k / ref`` with ``ref = |x_0|`` unless given, raised to
``floor`` where one is given; where ``ref`` is 0 the change is left absolute. Its
*relative drift* is the largest ``|d_k| / ref`` over the samples and the batch.

Used by :class:`poinsot.Trajectory` (``energy_drift``, ``conserved_drifts``...),
:class:`poinsot.scenarios.Check`, :mod:`poinsot.verify.metrics` and the heavy-body
plot. NumPy only.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["relative_change", "relative_drift"]


def relative_change(
    x: Any,
    ref: Any = None,
    *,
    expected: Any = None,
    vector: bool = False,
    floor: Any = None,
) -> np.ndarray:
    """``(x_k - e_k) / ref`` at each sample (``|x_k - e_k| / ref`` for vectors).

    Parameters
    ----------
    x : array_like, shape (n, ...) or (n, ..., 3) with ``vector``
        The quantity at each sample (time first).
    ref : array_like or None
        The size the change is measured against (broadcast with the batch shape);
        None: ``|x_0|`` (its norm for vectors).
    expected : array_like or None
        What ``x`` should be at each sample; None: ``x_0`` (conserved).
    vector : bool
        The last axis holds vector components: the change is the norm of the difference.
    floor : array_like or None
        ``ref`` is raised to at least ``floor`` (e.g. ``max_t T`` for an energy that
        starts at 0, or the smallest positive float).

    Returns
    -------
    ndarray, shape (n, ...)
        Signed for scalars; absolute (not divided) where ``ref`` is 0.

    Examples
    --------
    >>> relative_change([2.0, 2.5, 1.0]).tolist()
    [0.0, 0.25, -0.5]
    >>> relative_change([[3.0, 4.0], [3.0, 4.0 + 1e-3]], vector=True).round(12).tolist()
    [0.0, 0.0002]
    >>> relative_change([0.0, 1e-3]).tolist()  # ref 0: absolute
    [0.0, 0.001]
    """
    v = np.asarray(x, dtype=float)
    e = v[:1] if expected is None else np.asarray(expected, dtype=float)
    d = np.linalg.norm(v - e, axis=-1) if vector else v - e
    if ref is None:
        ref = np.linalg.norm(v[0], axis=-1) if vector else np.abs(v[0])
    r = np.asarray(ref, dtype=float)
    if floor is not None:
        r = np.maximum(r, floor)
    return np.divide(d, r, out=np.array(d, dtype=float), where=r > 0)


def relative_drift(x: Any, ref: Any = None, **options: Any) -> float:
    """``max_k |x_k - e_k| / ref`` over the samples and the batch: the largest
    :func:`relative_change` in magnitude (0 for no sample); ``options`` are its
    ``expected``, ``vector`` and ``floor``.

    Examples
    --------
    >>> relative_drift([2.0, 2.5, 1.0])                 # max(|0.5|, |-1|) / 2
    0.5
    >>> relative_drift([[1.0, 0.0], [1.5, 1e-3]])       # batch of 2, the second at 0
    0.5
    >>> relative_drift([0.0, 1e-3], floor=0.1)          # ref raised to 0.1
    0.01
    """
    change = relative_change(x, ref, **options)
    return float(np.max(np.abs(change), initial=0.0))
