"""Gibbs (Rodrigues) vectors and modified Rodrigues parameters (theory §2).

**Convention:** Gibbs vector ``g = e tan(f/2) = l / l0``; MRP
``p = e tan(f/4) = l / (1 + l0)``. Both are taken from the quaternion with
``l0 >= 0`` (shortest rotation), so ``|p| <= 1``; at exactly ``f = pi``
(``l0 = 0``) the sign makes the first non-zero component positive, as
:meth:`Rotation.as_rotvec` does (SciPy's ``as_mrp`` keeps the stored sign there:
both are valid). The Gibbs vector is infinite for ``f = pi``:
:func:`gibbs_from_quat` then returns ``+-inf`` components along the axis and
issues a :class:`~poinsot.SingularityWarning`.
"""

from __future__ import annotations

import warnings

import numpy as np

from .._vec import length as length_array
from ..errors import SingularityWarning
from ._lazy import big, flat, kernels, threaded
from .quaternion import canonical_array

__all__ = ["quat_from_gibbs", "gibbs_from_quat", "quat_from_mrp", "mrp_from_quat"]


def _positive_scalar(q: np.ndarray) -> np.ndarray:
    # The canonical sign (l0 > 0, or at exactly pi the first non-zero component > 0),
    # shared with the rotation vector and axis-angle outputs.
    return canonical_array(q)


def quat_from_gibbs(g: np.ndarray) -> np.ndarray:
    """``L = (1 + g) / sqrt(1 + |g|^2)`` for Gibbs vectors (..., 3).

    The length is taken without overflow, so ``|g|`` up to ``1e308`` (angles
    within ``1e-308`` of pi) still gives a unit quaternion.
    """
    q = np.concatenate([np.ones(g.shape[:-1] + (1,)), g], axis=-1)
    return q / length_array(q)[..., None]


def gibbs_from_quat(q: np.ndarray) -> np.ndarray:
    """``g = l / l0`` (with ``l0 >= 0``) for unit quaternions (..., 4)."""
    q = _positive_scalar(q)
    w, v = q[..., :1], q[..., 1:]
    at_pi = w == 0
    if np.any(at_pi):
        warnings.warn(
            "Gibbs vector of a rotation by pi is infinite; returning +-inf along the axis.",
            SingularityWarning,
            stacklevel=3,
        )
    safe_w = np.where(at_pi, 1.0, w)
    inf_along_axis = np.where(v == 0, 0.0, np.copysign(np.inf, v))
    return np.where(at_pi, inf_along_axis, v / safe_w)


def quat_from_mrp(p: np.ndarray) -> np.ndarray:
    """``L = ((1 - |p|^2) + 2 p) / (1 + |p|^2)`` for MRPs (..., 3).

    For ``|p| > 1e100`` (where ``|p|^2`` could overflow) the shadow set
    ``-p / |p|^2`` (the same rotation, ``-L``) is used and the sign restored.
    """
    if big(p.shape[:-1]):  # one compiled pass, unless a row needs the shadow set
        q = np.empty(p.shape[:-1] + (4,))
        if threaded(kernels().from_mrp_flat, flat(p, 3), q.reshape(-1, 4)) == 0:
            return q
    n = length_array(p)
    far = n > 1e100
    if np.any(far):
        safe = np.where(far, n, 1.0)[..., None]
        p = np.where(far[..., None], -p / safe / safe, p)
    # summed in the order of the compiled and one-rotation paths (einsum's may differ)
    a, b, c = p[..., 0], p[..., 1], p[..., 2]
    n2 = (a * a + b * b + c * c)[..., None]
    q = np.concatenate([1.0 - n2, 2.0 * p], axis=-1) / (1.0 + n2)
    return np.where(far[..., None], -q, q) if np.any(far) else q


def mrp_from_quat(q: np.ndarray) -> np.ndarray:
    """``p = l / (1 + l0)`` (with ``l0 >= 0``, so ``|p| <= 1``) for unit quaternions."""
    if big(q.shape[:-1]):
        p = np.empty(q.shape[:-1] + (3,))
        threaded(kernels().to_mrp_flat, flat(q, 4), p.reshape(-1, 3))
        return p
    q = _positive_scalar(q)
    return q[..., 1:] / (1.0 + q[..., :1])
