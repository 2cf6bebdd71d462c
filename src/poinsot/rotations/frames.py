"""Rotations determined by vectors: basis images (theory §2, Theorem 1) and Wahba's problem."""

from __future__ import annotations

import numpy as np

from .._typing import ArrayLike
from .._validate import as_float_array, as_vec3
from ..errors import InvalidInputError
from .dcm import EXACT_ATOL, ORTHOGONALITY_ATOL, _nearest_rotation

__all__ = ["quat_from_basis", "align_vectors"]

_EYE = np.eye(3)


def quat_from_basis(
    e1: ArrayLike, e2: ArrayLike, e3: ArrayLike, *, atol: float = ORTHOGONALITY_ATOL
) -> np.ndarray:
    """Quaternion ``L`` with ``e_k = L o i_k o L~`` (theory §2, the notes' Theorem 1).

    With ``r_k = e_k - i_k``, ``s_k = e_k + i_k``:
    ``L = +-((s_m . r_k) + r_k x r_m) / sqrt((s_m . r_k)^2 + |r_k x r_m|^2)`` for a
    cyclic pair ``(k, m)``. Every cyclic pair gives the same ``L`` (or ``-L``)
    when its denominator is non-zero; the pair with the largest denominator is
    used, which handles every degenerate case (a basis vector fixed, rotations
    by pi); all ``r_k = 0`` gives ``L = 1``. Returned with ``l0 >= 0``.
    """
    e = np.stack(
        np.broadcast_arrays(as_vec3(e1, "e1"), as_vec3(e2, "e2"), as_vec3(e3, "e3")), axis=-1
    )  # columns are the basis images: the rotation matrix
    gram = np.swapaxes(e, -1, -2) @ e
    err = np.max(np.abs(gram - _EYE), axis=(-2, -1))
    det = np.linalg.det(e)
    if np.any(err > atol):
        raise InvalidInputError(
            f"Expected `e1, e2, e3` to be orthonormal within {atol:g}, got max |e_i.e_j - "
            f"delta_ij| = {float(np.max(err)):.3g}."
        )
    if np.any(det <= 0):
        raise InvalidInputError(
            "Expected `e1, e2, e3` to form a right-handed basis (e1 x e2 . e3 > 0)."
        )
    if np.any(err > EXACT_ATOL):
        e = np.where((err > EXACT_ATOL)[..., None, None], _nearest_rotation(e), e)
    r = e - _EYE  # columns r_k
    s = e + _EYE
    best = np.zeros(e.shape[:-2] + (4,))
    best_n2 = np.full(e.shape[:-2], -1.0)
    for k, m in ((0, 1), (1, 2), (2, 0)):
        rk, rm, sm = r[..., :, k], r[..., :, m], s[..., :, m]
        cand = np.concatenate(
            [np.einsum("...i,...i->...", sm, rk)[..., None], np.cross(rk, rm)], axis=-1
        )
        n2 = np.einsum("...i,...i->...", cand, cand)
        take = n2 > best_n2
        best = np.where(take[..., None], cand, best)
        best_n2 = np.where(take, n2, best_n2)
    identity = best_n2 == 0.0
    best = np.where(identity[..., None], [1.0, 0.0, 0.0, 0.0], best)
    best = best / np.sqrt(np.where(identity, 1.0, best_n2))[..., None]
    return np.where(best[..., :1] < 0, -best, best)


def _svd_rotation(bmat: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The rotation ``C = U diag(1, 1, d) V^T`` maximising ``tr(C^T B)``, batched.

    The ONE SVD solution of Wahba's problem (theory §2.4), shared by
    :func:`align_vectors` and :func:`poinsot.rotations.determine_attitude`: for
    ``B = U diag(s) V^T`` (..., 3, 3), ``d = sign det(U V^T)``. Returns ``(C, s, d)``
    (trusted input, no checks).

    >>> c, s, d = _svd_rotation(np.diag([2.0, 1.0, 0.5]))
    >>> c.round(12) + 0.0, float(d)
    (array([[1., 0., 0.],
           [0., 1., 0.],
           [0., 0., 1.]]), 1.0)
    """
    u, sv, vt = np.linalg.svd(bmat)
    d = np.sign(np.linalg.det(u @ vt))
    c = (u * np.stack(np.broadcast_arrays(1.0, 1.0, d), axis=-1)[..., None, :]) @ vt
    return c, sv, d


def align_vectors(
    a: ArrayLike,
    b: ArrayLike,
    weights: ArrayLike | None = None,
    *,
    return_sensitivity: bool = False,
) -> tuple[np.ndarray, float] | tuple[np.ndarray, float, np.ndarray]:
    """Optimal rotation matrix ``C`` for Wahba's problem ``a_i ~ C b_i`` and the RSSD.

    Minimises ``sum_i w_i |a_i - C b_i|^2`` by the SVD of ``B = sum_i w_i a_i b_i^T``
    (Kabsch/Markley): ``C = U diag(1, 1, det(U V^T)) V^T``. Needs at least two
    linearly independent (weighted) vector pairs, otherwise the rotation is not
    determined and :class:`~poinsot.InvalidInputError` is raised: the pairs count
    as dependent when the second singular value of ``B`` is below ``1e-12`` times
    the first (two unit pairs less than about ``1.4e-6`` rad apart). ``B`` is
    formed from ``a``, ``b`` and ``w`` scaled to a largest entry of 1 (the optimal
    ``C`` does not change), so vectors of any magnitude (``1e-200``, ``1e200``)
    are handled. With ``return_sensitivity`` the covariance-like sensitivity
    matrix of SciPy (Markley & Crassidis) is returned as a third value.
    """
    a = as_vec3(a, "a")
    b = as_vec3(b, "b")
    if a.ndim != 2 or b.ndim != 2 or a.shape != b.shape:
        raise InvalidInputError(
            "Expected `a` and `b` to have the same shape (n, 3) with n >= 2 vector pairs, "
            f"got {a.shape} and {b.shape}."
        )
    n = a.shape[0]
    if weights is None:
        w = np.ones(n)
    else:
        w = as_float_array(weights, "weights")
        if w.shape != (n,):
            raise InvalidInputError(f"Expected `weights` to have shape ({n},), got {w.shape}.")
        if np.any(w < 0):
            raise InvalidInputError("Expected `weights` to be non-negative.")
    # Scale everything to a largest entry of 1: B then neither overflows (an SVD of
    # an inf matrix never returns) nor underflows; C is invariant to the scales.
    sa = float(np.max(np.abs(a), initial=0.0))
    sb = float(np.max(np.abs(b), initial=0.0))
    sw = float(np.max(w, initial=0.0))
    degenerate = InvalidInputError(
        "Expected `a` and `b` to contain at least two linearly independent vector pairs "
        "(with non-zero weight); the rotation is not determined."
    )
    if n < 2 or sa == 0.0 or sb == 0.0 or sw == 0.0:
        raise degenerate
    a_s, b_s, w_s = a / sa, b / sb, w / sw
    bmat = np.einsum("i,ij,ik->jk", w_s, a_s, b_s)
    c, sv, d = _svd_rotation(bmat)
    if sv[1] <= 1e-12 * sv[0]:
        raise degenerate
    s = max(sa, sb)
    resid = a / s - (b / s) @ c.T
    with np.errstate(over="ignore"):  # inf only if the true RSSD exceeds float64
        rssd = s * np.sqrt(sw) * float(np.sqrt(np.sum(w_s * np.einsum("ij,ij->i", resid, resid))))
    if not return_sensitivity:
        return c, float(rssd)
    sv = sv * np.array([1.0, 1.0, d])
    zeta = (sv[0] + sv[1]) * (sv[1] + sv[2]) * (sv[2] + sv[0])
    kappa = sv[0] * sv[1] + sv[1] * sv[2] + sv[2] * sv[0]
    # SciPy: mean(w) / zeta * (kappa E + B B^T) for the unscaled B = (sa sb sw) B_s.
    sens = np.mean(w_s) / zeta * (kappa * _EYE + bmat @ bmat.T) / (sa * sb)
    return c, float(rssd), sens
