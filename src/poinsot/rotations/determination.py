"""Attitude determination from vector observations: Wahba's problem (docs/theory.md §2.4).

A body measures unit directions ``b_i`` in its own axes (star tracker, Sun sensor,
magnetometer) of objects whose directions ``r_i`` in a reference frame are known
(catalogue, ephemeris, field model). :func:`determine_attitude` finds the rotation
that best maps one set onto the other, for whole batches of observation sets at
once, by one of five classical methods (SVD, TRIAD, Davenport's q-method, QUEST,
ESOQ2), and returns an :class:`AttitudeSolution` with the Wahba loss and the QUEST
attitude error covariance.

**Convention:** observations ``b_i ~ A r_i`` with ``A = C_nb^T`` the attitude matrix
(reference -> body); the result is the scalar-first quaternion ``L`` of ``C_nb``
(body -> reference), ``r_i ~ L o b_i o L~``, as every poinsot attitude
(docs/conventions.md, "Attitude from vector observations").
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass

import numpy as np

from .. import _jit
from .._typing import ArrayLike
from .._validate import as_choice, as_trailing, batch_shape
from ..errors import InvalidInputError
from . import _wahba_codes as _C
from ._lazy import PARALLEL_MIN_SIZE, threaded
from .dcm import matrix_from_quat, quat_from_matrix
from .frames import _svd_rotation
from .rotation import Rotation

__all__ = ["AttitudeSolution", "determine_attitude", "ATTITUDE_METHODS"]

#: The methods of :func:`determine_attitude`.
ATTITUDE_METHODS = ("quest", "svd", "q-method", "esoq2", "triad")

#: Observations count as parallel when ``det(sum w_i (E - u_i u_i^T)) <= 1e-12 lambda0^3``
#: (two unit vectors about ``2e-6`` rad apart), the analogue of ``align_vectors``' bound.
PARALLEL_RTOL = _C.PARALLEL_RTOL

#: QUEST rotates the reference frame when the solved ``|l0|`` is below this.
QUEST_ROTATION_THRESHOLD = _C.QUEST_ROTATION_THRESHOLD

_EYE = np.eye(3)


@dataclass(frozen=True, repr=False)
class AttitudeSolution:
    """The solution of Wahba's problem for a batch of observation sets.

    Attributes
    ----------
    quat : ndarray, shape (..., 4)
        Scalar-first unit quaternion ``L`` of ``C_nb`` (body -> reference), ``l0 >= 0``.
    loss : ndarray, shape (...)
        Wahba's loss at the solution, ``1/2 sum_i w_i |r_i - C_nb b_i|^2`` for the unit
        directions (units of ``weights``; dimensionless for ``1/sigma^2`` in rad^-2).
    covariance : ndarray, shape (..., 3, 3), or None
        Attitude error covariance in body axes (rad^2 when ``weights`` are
        ``1/sigma_i^2`` in rad^-2): ``P = (sum_i w_i (E - b_i b_i^T))^-1`` (Shuster's
        QUEST measurement model), the covariance of ``dtheta`` in
        ``L_est = L_true o exp(dtheta/2)``. ``None`` when solved with
        ``covariance=False``.
    method : str
        The method that solved it.

    Notes
    -----
    **Convention:** ``b_i ~ A r_i`` with ``A = C_nb^T``; ``quat`` is ``C_nb`` (body ->
    reference), docs/theory.md §2.4. The arrays are read-only.

    Examples
    --------
    >>> from poinsot.rotations import determine_attitude
    >>> sol = determine_attitude([[1, 0, 0], [0, 0, 1]], [[0, 1, 0], [0, 0, 1]])
    >>> sol.rotation.apply([1.0, 0.0, 0.0]).round(12) + 0.0
    array([0., 1., 0.])
    >>> sol
    AttitudeSolution(method='quest', shape=())
    """

    quat: np.ndarray
    loss: np.ndarray
    covariance: np.ndarray | None
    method: str

    @property
    def rotation(self) -> Rotation:
        """The poinsot :class:`~poinsot.Rotation` of ``quat`` (``v_ref = R.apply(v_body)``)."""
        return Rotation._wrap(self.quat)

    @property
    def shape(self) -> tuple[int, ...]:
        """The batch shape (``()`` for one observation set)."""
        return tuple(self.quat.shape[:-1])

    def __repr__(self) -> str:
        return f"AttitudeSolution(method={self.method!r}, shape={self.shape})"


def _first(bad: np.ndarray) -> str:
    if bad.ndim == 0:
        return ""
    return f" at index {tuple(int(i) for i in np.argwhere(bad)[0])}"


def _unit_dirs(v: np.ndarray, name: str) -> np.ndarray:
    s = np.max(np.abs(v), axis=-1, keepdims=True)  # scaled: no overflow for 1e200
    zero = s[..., 0] == 0.0
    if np.any(zero):
        raise InvalidInputError(
            f"Expected `{name}` to contain non-zero vectors, got a zero vector{_first(zero)}."
        )
    u = v / s
    out: np.ndarray = u / np.sqrt(np.einsum("...i,...i->...", u, u))[..., None]
    return out


def _spread(u: np.ndarray, w: np.ndarray) -> np.ndarray:
    """``sum_i w_i (E - u_i u_i^T)`` (..., 3, 3) for unit ``u`` (..., n, 3)."""
    out: np.ndarray = np.sum(w, axis=-1)[..., None, None] * _EYE - np.einsum(
        "...i,...ij,...ik->...jk", w, u, u
    )
    return out


def _check_spread(m: np.ndarray, lam0: np.ndarray, name: str) -> None:
    bad = ~(np.linalg.det(m) > PARALLEL_RTOL * lam0**3)
    if np.any(bad):
        raise InvalidInputError(
            f"Expected `{name}` to contain at least two non-parallel directions with "
            f"non-zero weight{_first(bad)}; the rotation about a common direction is not "
            "determined."
        )


def _k_parts(b: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``S = B + B^T``, ``sigma = tr B``, ``z = (B23 - B32, B31 - B13, B12 - B21)``."""
    s = b + np.swapaxes(b, -1, -2)
    sigma = np.trace(b, axis1=-2, axis2=-1)
    z = np.stack(
        [b[..., 1, 2] - b[..., 2, 1], b[..., 2, 0] - b[..., 0, 2], b[..., 0, 1] - b[..., 1, 0]],
        axis=-1,
    )
    return s, sigma, z


def _k_matrix(b: np.ndarray) -> np.ndarray:
    """Davenport's ``K = [[sigma, z^T], [z, S - sigma E]]`` in poinsot's ``(l0, l)`` order."""
    s, sigma, z = _k_parts(b)
    k = np.empty(b.shape[:-2] + (4, 4))
    k[..., 0, 0] = sigma
    k[..., 0, 1:] = z
    k[..., 1:, 0] = z
    k[..., 1:, 1:] = s - sigma[..., None, None] * _EYE
    return k


def _normalised(q: np.ndarray) -> np.ndarray:
    out: np.ndarray = q / np.sqrt(np.einsum("...i,...i->...", q, q))[..., None]
    return out


def _q_method(b: np.ndarray) -> np.ndarray:
    _, vecs = np.linalg.eigh(_k_matrix(b))
    out: np.ndarray = vecs[..., :, -1]
    return out


def _svd(b: np.ndarray) -> np.ndarray:
    c, _, _ = _svd_rotation(np.swapaxes(b, -1, -2))  # r_i ~ C b_i: a = r, b = b
    return quat_from_matrix(np.ascontiguousarray(c))


def _triad(bu: np.ndarray, ru: np.ndarray) -> np.ndarray:
    def triad(u: np.ndarray) -> np.ndarray:
        t1 = u[..., 0, :]
        t2 = _normalised(np.cross(u[..., 0, :], u[..., 1, :]))
        return np.stack([t1, t2, np.cross(t1, t2)], axis=-1)  # columns t1, t2, t3

    c = triad(ru) @ np.swapaxes(triad(bu), -1, -2)  # C t_b = t_r
    return quat_from_matrix(np.ascontiguousarray(c))


#: Status bits of the solving loop, in the order they are checked (as the NumPy path's).
_STATUS = (
    (_C.NONFINITE_OBSERVED, "finite", "observed"),
    (_C.NONFINITE_REFERENCE, "finite", "reference"),
    (_C.ZERO_OBSERVED, "zero", "observed"),
    (_C.ZERO_REFERENCE, "zero", "reference"),
    (_C.PARALLEL_OBSERVED, "parallel", "observed"),
    (_C.PARALLEL_REFERENCE, "parallel", "reference"),
)
_WAHBA_KERNELS = "poinsot.rotations._wahba_kernels"
_WAHBA = "poinsot.rotations._wahba"
_CALLED: set[str] = set()


def _raise_status(
    status: np.ndarray, shape: tuple[int, ...], arrays: dict[str, np.ndarray]
) -> None:
    """Raise the error of the first status bit set (the NumPy path's error and message;
    a zero vector is located in ``arrays[name]`` as given)."""
    bits = int(np.bitwise_or.reduce(status))
    for bit, kind, name in _STATUS:
        if not bits & bit:
            continue
        if kind == "finite":
            raise InvalidInputError(
                f"Expected `{name}` to contain only finite values (no NaN/inf)."
            )
        if kind == "zero":
            _unit_dirs(arrays[name], name)  # raises, with the index of the vector
        bad = ((status & bit) != 0).reshape(shape)
        raise InvalidInputError(
            f"Expected `{name}` to contain at least two non-parallel directions with "
            f"non-zero weight{_first(bad)}; the rotation about a common direction is not "
            "determined."
        )


def _flat_sets(a: np.ndarray, shape: tuple[int, ...], core: tuple[int, ...]) -> np.ndarray:
    """``a`` (batch shape broadcasting to ``shape``) as ``(N, *core)``, or ``(1, *core)``
    when it is one set for the whole batch (no copy of a contiguous input)."""
    lead = a.shape[: a.ndim - len(core)]
    if int(np.prod(lead, dtype=np.int64)) == 1:
        return np.ascontiguousarray(a).reshape((1,) + core)
    if lead != shape:
        a = np.broadcast_to(a, shape + core)
    return np.ascontiguousarray(a).reshape((-1,) + core)


def _solve_sets(
    ob: np.ndarray,
    ref: np.ndarray,
    w: np.ndarray,
    shape: tuple[int, ...],
    n: int,
    method: str,
    want_cov: bool,
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """QUEST / ESOQ2 with validation, loss and covariance in one pass per set: the
    formulas of :mod:`._wahba`, compiled (a parallel loop) or run on NumPy columns."""
    code = _C.QUEST if method == "quest" else _C.ESOQ2
    size = int(np.prod(shape, dtype=np.int64))
    sets = [
        _flat_sets(ob, shape, (n, 3)),
        _flat_sets(ref, shape, (n, 3)),
        _flat_sets(w, shape, (n,)),
    ]
    _jit.njit  # noqa: B018  (binds the executor: is numba there and importing?)
    if _jit.NUMBA:
        q = np.empty((size, 4))
        loss = np.empty(size)
        cov = np.empty((size, 3, 3) if want_cov else (1, 3, 3))
        status = np.empty(size, dtype=np.uint8)
        big = size >= PARALLEL_MIN_SIZE
        name = "solve_flat" if big else "solve_serial"
        args = (*sets, code, want_cov, q, loss, cov, status)
        if name in _CALLED:
            kernel = getattr(importlib.import_module(_WAHBA_KERNELS), name)
            threaded(kernel, *args) if big else kernel(*args)
        else:  # the first call compiles (or loads from numba's cache): one process at a time
            with _jit.compile_lock("wahba"):
                kernel = getattr(importlib.import_module(_WAHBA_KERNELS), name)
                threaded(kernel, *args) if big else kernel(*args)
            _CALLED.add(name)
    else:
        cols = [np.moveaxis(np.broadcast_to(a, (size,) + a.shape[1:]), 0, -1) for a in sets]
        if size == 0:
            res: tuple[np.ndarray, ...] = (np.empty(0),) * 12
        else:
            with np.errstate(all="ignore"):  # as compiled: the failed sets give NaN, no warning
                # the formula source binds the executor's names (numba): loaded on use
                solve = importlib.import_module(_WAHBA).solve
                res = _jit.lanes(solve, size, *cols, n, code, want_cov)
        res = tuple(np.broadcast_to(np.asarray(r, dtype=float), (size,)) for r in res)
        q = np.stack(res[:4], axis=-1)
        loss = np.array(res[4])
        status = res[11].astype(np.uint8)
        if want_cov:
            c00, c01, c02, c11, c12, c22 = res[5:11]
            cov = np.stack([c00, c01, c02, c01, c11, c12, c02, c12, c22], axis=-1)
            cov = cov.reshape(size, 3, 3)
    if status.any():
        _raise_status(status, shape, {"observed": ob, "reference": ref})
    return (
        q.reshape(shape + (4,)),
        loss.reshape(shape),
        cov.reshape(shape + (3, 3)) if want_cov else None,
    )


def determine_attitude(
    observed: ArrayLike,
    reference: ArrayLike,
    weights: ArrayLike | None = None,
    *,
    method: str = "quest",
    covariance: bool = True,
) -> AttitudeSolution:
    """The attitude that best maps body-frame observations onto reference directions.

    Solves Wahba's problem: minimise over rotations ``A`` (reference -> body)

        L(A) = 1/2 sum_i w_i |b_i - A r_i|^2 = lambda0 - tr(A B^T),
        B = sum_i w_i b_i r_i^T,   lambda0 = sum_i w_i,

    for the unit directions ``b_i = observed_i / |observed_i|`` and
    ``r_i = reference_i / |reference_i|`` (magnitudes are ignored), and returns the
    quaternion of ``C_nb = A^T`` (body -> reference). With Davenport's
    ``K = [[sigma, z^T], [z, S - sigma E]]`` (``S = B + B^T``, ``sigma = tr B``,
    ``z = sum_i w_i b_i x r_i``) the loss is ``lambda0 - L^T K L``, so the optimum is
    the eigenvector of the largest eigenvalue ``lambda_max`` of ``K``.

    Parameters
    ----------
    observed : array_like, shape (..., n, 3)
        The directions ``b_i`` measured in body axes (any non-zero length).
    reference : array_like, shape (..., n, 3)
        The same directions ``r_i`` in the reference frame. The batch shapes of
        ``observed``, ``reference`` and ``weights`` broadcast (e.g. one catalogue
        ``(n, 3)`` for a batch of measurements ``(N, n, 3)``).
    weights : array_like, shape (..., n) or (n,), optional
        Non-negative ``w_i``; for a meaningful ``covariance`` the inverse variances
        ``1/sigma_i^2`` (rad^-2) of the observation errors. Default: all 1 (then
        ``covariance`` is the geometry factor, in units of ``sigma^2``). Ignored by
        ``"triad"``.
    method : {"quest", "svd", "q-method", "esoq2", "triad"}, keyword-only
        ``"svd"``: ``C_nb = U diag(1, 1, det(U V^T)) V^T`` for ``B^T = U s V^T`` (the
        SVD of :meth:`poinsot.Rotation.align_vectors`, batched). ``"q-method"``:
        Davenport's eigenvector of ``K`` (``numpy.linalg.eigh``). ``"quest"``
        (Shuster): Newton's iteration on the characteristic polynomial of ``K`` from
        ``lambda0``, then the Gibbs vector ``x / gamma``; where ``|l0| < 0.3`` (read
        from the Gibbs denominator, ``gamma = f'(lambda_max) l0^2``) the
        reference frame is turned by a half-turn about x, y or z (Shuster's method
        of sequential rotations: of the three turned solutions, the one with the
        largest ``|l0'|``) and the quaternion turned back, so rotations near 180 deg
        lose nothing.
        ``"esoq2"`` (Mortari): the same ``lambda_max``; the rotation axis ``e`` is
        the null vector of ``M = (lambda - sigma)(S - (lambda + sigma) E) + z z^T``
        (the largest cross product of two of its columns), and
        ``L ~ (z.e, (lambda - sigma) e)``; it is singular at the identity, so the
        frame is first turned by the half-turn with the smallest diagonal of ``K``.
        ``"triad"``: exactly two observations, weights ignored; the first pair is
        matched exactly, the second only fixes the rotation about it:
        ``C_nb = [r1, r1 x r2 /|.|, ...] [b1, b1 x b2 /|.|, ...]^T``.
    covariance : bool, keyword-only
        Whether to return the covariance (default ``True``). ``False`` skips its
        inverse and its ``(..., 3, 3)`` array (for QUEST and ESOQ2 on 1e6 sets, the
        largest part of the memory written): ``AttitudeSolution.covariance`` is then
        ``None``.

    Returns
    -------
    AttitudeSolution
        ``quat`` (..., 4) scalar first with ``l0 >= 0``, ``loss`` (...),
        ``covariance`` (..., 3, 3) = ``(sum_i w_i (E - b_i b_i^T))^-1`` (rad^2, body
        axes; ``None`` with ``covariance=False``), ``method``.

    Raises
    ------
    InvalidInputError
        Mismatched shapes, fewer than two observations (``"triad"``: not exactly two),
        a zero vector, all (weighted) directions of a set parallel (det of
        ``sum w_i (E - u_i u_i^T)`` at most ``1e-12 lambda0^3``), negative weights, an
        unknown ``method``.

    Notes
    -----
    **Convention:** ``b_i ~ A r_i``, ``A = C_nb^T`` (reference -> body); the returned
    ``L`` is ``C_nb`` (body -> reference): ``r_i ~ L o b_i o L~``, i.e.
    ``Rotation.apply(b) ~ r``, and ``Rotation.align_vectors(reference, observed)``
    gives the same rotation. docs/theory.md §2.4, docs/conventions.md.

    All methods are vectorised over the batch (no Python loop over it). ``"quest"``
    and ``"esoq2"`` solve each set in one pass (validation, the solution, the loss and
    the covariance) by formulas written once (``poinsot.rotations._wahba``): compiled
    by numba into a loop over the batch, split over the idle cores from
    ``PARALLEL_MIN_SIZE`` sets (:func:`~poinsot.rotations.set_num_threads`; the
    results do not depend on the thread count), or, under ``POINSOT_NUMBA=0``, run on
    NumPy columns of the whole batch (the same operations). ``"svd"``, ``"q-method"``
    and ``"triad"`` are NumPy (LAPACK). Throughput: docs/performance.md, "Attitude
    determination".

    References
    ----------
    Wahba, SIAM Review 7 (1965) 409; Davenport (1968); Shuster & Oh, J. Guidance and
    Control 4 (1981) 70-77; Mortari, J. Astronaut. Sci. 45 (1997) 195-205 (ESOQ2);
    Markley & Mortari, J. Astronaut. Sci. 48 (2000) 359-380.

    Examples
    --------
    SciPy's ``align_vectors`` example: ``(1, 0, 0)`` and ``(0, 0, 1)`` seen in body
    axes are ``(0, 1, 0)`` and ``(0, 0, 1)`` in the reference frame: a quarter turn
    about z (body -> reference), ``L = (1, 0, 0, 1)/sqrt(2)``:

    >>> import numpy as np
    >>> from poinsot.rotations import determine_attitude
    >>> b = [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    >>> r = [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    >>> sol = determine_attitude(b, r, method="quest")
    >>> sol.quat.round(12) + 0.0
    array([0.70710678, 0.        , 0.        , 0.70710678])
    >>> float(sol.loss) < 1e-30, np.diag(sol.covariance).round(12) + 0.0
    (True, array([1. , 0.5, 1. ]))
    """
    method = as_choice(method, "method", ATTITUDE_METHODS)
    fused = method in ("quest", "esoq2")  # finiteness checked in the solving loop
    ob = as_trailing(observed, "observed", (None, 3), finite=not fused)
    ref = as_trailing(reference, "reference", (None, 3), finite=not fused)
    n = ob.shape[-2]
    if ref.shape[-2] != n:
        raise InvalidInputError(
            "Expected `observed` and `reference` to have the same number of observations "
            f"(shapes (..., n, 3)), got {ob.shape} and {ref.shape}."
        )
    if method == "triad" and n != 2:
        raise InvalidInputError(
            f"Expected `observed` to have exactly two observations for method='triad' "
            f"(shape (..., 2, 3)), got n = {n}."
        )
    if n < 2:
        raise InvalidInputError(
            "Expected `observed` to have at least two observations (shape (..., n, 3), "
            f"n >= 2), got n = {n}; one direction leaves the rotation about it undetermined."
        )
    if weights is None or method == "triad":
        w = np.ones(n)
    else:
        w = as_trailing(weights, "weights", (None,))
        if w.shape[-1] != n:
            raise InvalidInputError(
                f"Expected `weights` to have shape (..., {n}) or ({n},), got {w.shape}."
            )
        if np.any(w < 0):
            raise InvalidInputError(
                f"Expected `weights` to be non-negative, got {float(w[w < 0].ravel()[0])!r}."
            )
    shape = batch_shape(observed=(ob, 2), reference=(ref, 2), weights=(w, 1))
    if fused:
        q, loss, cov = _solve_sets(ob, ref, w, shape, n, method, covariance)
        for a in (q, loss, cov):
            if a is not None:
                a.setflags(write=False)
        return AttitudeSolution(quat=q, loss=loss, covariance=cov, method=method)
    bu = np.broadcast_to(_unit_dirs(ob, "observed"), shape + (n, 3))
    ru = np.broadcast_to(_unit_dirs(ref, "reference"), shape + (n, 3))
    w = np.broadcast_to(w, shape + (n,))
    lam0 = np.sum(w, axis=-1)
    spread_b = _spread(bu, w)
    _check_spread(spread_b, lam0, "observed")
    _check_spread(_spread(ru, w), lam0, "reference")
    ws = w / lam0[..., None]  # lambda0 = 1 inside: the polynomial's scale is fixed
    bmat = np.einsum("...i,...ij,...ik->...jk", ws, bu, ru)
    if method == "svd":
        q = _svd(bmat)
    elif method == "q-method":
        q = _q_method(bmat)
    else:
        q = _triad(bu, ru)
    q = np.where(q[..., :1] < 0.0, -q, q)
    c = matrix_from_quat(np.ascontiguousarray(q))
    resid = ru - np.einsum("...jk,...ik->...ij", c, bu)
    loss = np.asarray(0.5 * np.sum(w * np.einsum("...i,...i->...", resid, resid), axis=-1))
    cov = np.linalg.inv(spread_b) if covariance else None
    for a in (q, loss, cov):
        if a is not None:
            a.setflags(write=False)
    return AttitudeSolution(quat=q, loss=loss, covariance=cov, method=method)
