"""Gibbs (Rodrigues) vectors and modified Rodrigues parameters (SPEC S2).

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
    n = length_array(p)
    big = n > 1e100
    if np.any(big):
        safe = np.where(big, n, 1.0)[..., None]
        p = np.where(big[..., None], -p / safe / safe, p)
    n2 = np.einsum("...i,...i->...", p, p)[..., None]
    q = np.concatenate([1.0 - n2, 2.0 * p], axis=-1) / (1.0 + n2)
    return np.where(big[..., None], -q, q) if np.any(big) else q


def mrp_from_quat(q: np.ndarray) -> np.ndarray:
    """``p = l / (1 + l0)`` (with ``l0 >= 0``, so ``|p| <= 1``) for unit quaternions."""
    q = _positive_scalar(q)
    return q[..., 1:] / (1.0 + q[..., :1])
