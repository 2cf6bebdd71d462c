"""Direction cosine matrices (theory §2) <-> unit quaternions.

**Convention:** the matrix ``A`` of a rotation has as columns the images of the
reference basis vectors written in the reference basis (``a_ij = cos(e_i, e'_j)``),
so ``v_ref = A v_body``. ``A = E + 2 l0 l^ + 2 l^ l^`` for ``L = (l0, l)``.

Matrices given by users are checked: determinant > 0, and orthogonal within
:data:`ORTHOGONALITY_ATOL` (``max |A^T A - E|``). A matrix that is orthogonal to
within :data:`EXACT_ATOL` passes straight to the largest-square formula (machine
precision); one between the two tolerances is first projected onto the nearest
rotation in the Frobenius norm (``U diag(1, 1, det(U V^T)) V^T`` from the SVD).
"""

from __future__ import annotations

import math

import numpy as np

from .._typing import ArrayLike
from .._validate import as_trailing
from ..errors import InvalidInputError
from ._lazy import big, flat, kernels, threaded

__all__ = ["ORTHOGONALITY_ATOL", "EXACT_ATOL", "matrix_from_quat", "quat_from_matrix"]

#: Largest ``max |A^T A - E|`` accepted by :meth:`Rotation.from_matrix` (then projected).
ORTHOGONALITY_ATOL = 1e-6
#: Below this ``max |A^T A - E|`` a matrix is used as is (no projection).
EXACT_ATOL = 1e-14

_D3 = np.zeros(3)
_D4 = np.zeros(4)
_NONE = np.empty(0)
#: Parts of a large batch for ``from_matrix_flat`` (each a run of whole blocks, spread
#: over the threads; each counts its bad matrices).
_PARTS = 64
#: ``to_matrix_flat``'s translations, unused for rows of 9.
_NO_T = np.empty((0, 3))


def matrix_from_quat(q: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
    """``A = (2 l0^2 - 1) E + 2 l0 l^ + 2 l l^T`` for unit ``q`` (..., 4) -> (..., 3, 3),
    written into ``out`` when given (trusted: a C-contiguous float64 array of that shape).
    """
    if big(q.shape[:-1]):
        f = flat(q, 4)
        m = np.empty((f.shape[0], 9)) if out is None else out.reshape(-1, 9)
        threaded(kernels().to_matrix_flat, f, _NO_T, m)
        return m.reshape(q.shape[:-1] + (3, 3)) if out is None else out
    m = kernels().quat_to_matrix(q, _D3)  # C order from numba; the NumPy executor's is not
    if out is None:
        return np.ascontiguousarray(m)  # so that np.empty_like(result) is a valid out
    out[...] = m
    return out


def _to_quat(m: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(q, max |A^T A - E|, det A)`` for matrices (..., 3, 3) (threaded when large)."""
    shape = m.shape[:-2]
    if big(shape):
        f = flat(m, 9)
        q, err, det = np.empty((f.shape[0], 4)), np.empty(f.shape[0]), np.empty(f.shape[0])
        threaded(kernels().from_matrix_flat, f, q, err, det, np.empty(_PARTS, np.int64), 0.0)
        return q.reshape(shape + (4,)), err.reshape(shape), det.reshape(shape)
    return kernels().matrix_to_quat(m, _D4)


def _quat_counting(m: np.ndarray, tol: float) -> tuple[np.ndarray, int]:
    """A large batch's quaternions, and how many of its matrices are not rotations within
    ``tol`` (``max |A^T A - E| <= tol``, ``det > 0``, finite).

    Without the two per-matrix arrays of :func:`_to_quat` (see ``from_matrix_flat``):
    the quaternions are the same bits; a batch with a bad matrix goes through
    :func:`_to_quat` again for its messages and projections.
    """
    f = flat(m, 9)
    q = np.empty((f.shape[0], 4))
    bad = np.zeros(_PARTS, dtype=np.int64)
    threaded(kernels().from_matrix_flat, f, q, _NONE, _NONE, bad, tol)
    return q.reshape(m.shape[:-2] + (4,)), int(bad.sum())


def quat_from_matrix(m: np.ndarray) -> np.ndarray:
    """Largest-square-first conversion of rotation matrices (..., 3, 3) -> (..., 4).

    Trusts its input (no checks): use :func:`quat_from_user_matrix` for user data.
    """
    if big(m.shape[:-2]):
        return _quat_counting(m, math.inf)[0]
    return _to_quat(m)[0]


def _nearest_rotation(m: np.ndarray) -> np.ndarray:
    u, _, vt = np.linalg.svd(m)
    d = np.sign(np.linalg.det(u @ vt))
    u = u.copy()
    u[..., :, 2] *= d[..., None]
    return u @ vt


def quat_from_user_matrix(
    m: ArrayLike, name: str = "matrix", *, atol: float = ORTHOGONALITY_ATOL
) -> np.ndarray:
    """Check, project if needed, and convert user matrices (see module notes)."""
    # finiteness is checked on the kernel's output (its err is NaN exactly for a
    # non-finite matrix): one pass over the matrices instead of two
    m = as_trailing(m, name, (3, 3), finite=False)
    if big(m.shape[:-2]):  # the common case first: every matrix a rotation to round-off
        with np.errstate(invalid="ignore", over="ignore"):
            q, n_bad = _quat_counting(m, min(atol, EXACT_ATOL))
        if n_bad == 0:
            return q
    with np.errstate(invalid="ignore", over="ignore"):  # NaN/inf in: NaN err out, no warning
        q, err, det = _to_quat(m)
    if err.size == 0:
        return q
    worst = float(np.max(err))  # NaN if any is NaN
    if math.isnan(worst):
        raise InvalidInputError(f"Expected `{name}` to contain only finite values (no NaN/inf).")
    if float(np.min(det)) <= 0.0:
        bad = np.asarray(det)[det <= 0].ravel()[0]
        raise InvalidInputError(
            f"Expected `{name}` to be a proper rotation (determinant > 0), got det = {bad:.6g}."
        )
    if worst > atol:
        raise InvalidInputError(
            f"Expected `{name}` to be orthogonal within {atol:g} (max |A^T A - E|), "
            f"got {worst:.3g}."
        )
    if worst > EXACT_ATOL:
        fix = err > EXACT_ATOL
        q = np.array(q)
        q[fix] = quat_from_matrix(_nearest_rotation(m[fix]))
    return q
