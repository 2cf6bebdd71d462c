"""Angular velocity from an attitude history (theory §5, task (b)).

Two tools for sampled attitudes ``R(t_k)`` (quaternions or :class:`Rotation`):

* :func:`angular_velocity` -- the angular velocity *at the samples*, by
  high-order finite differences of the rotation vectors of the samples relative
  to each sample (``r_j = log(R_k^T R_j)``, so ``r'(t_k) = w_xi(t_k)`` exactly).
  Fornberg weights make it work on non-uniform grids; the error is
  ``O(h^order)`` (4 by default) and it is exact for a constant angular
  velocity, whatever the step.
* :func:`rotation_spline` -- a C2 interpolant (cubic rotation-vector
  increments, the construction of SciPy's ``RotationSpline``) giving attitude,
  angular velocity and angular acceleration at any time. By default its end
  conditions use the 4th-order estimate of :func:`angular_velocity`, which
  makes it far more accurate near the ends than SciPy's chord rule.

Both are robust to the ``q`` / ``-q`` sign flips of real quaternion data: the
sequence is made continuous (or the shortest increment is taken) first.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .._typing import ArrayLike, FloatArray
from .._validate import (
    _is_scipy_rotation,
    as_choice,
    as_float_array,
    as_int,
    as_rotation_quat,
    as_times,
    as_trailing,
)
from .._vec import cross as _cross
from .._vec import dot as _dot
from ..errors import InvalidInputError
from ..rotations import quaternion as _quat
from ..rotations.rotation import Rotation
from ..rotations.rotvec import quat_from_rotvec
from .rates import (
    FRAMES,
    _rotvec_coefficients,
    _rotvec_jacobian_apply,
    _rotvec_rate,
)

__all__ = ["angular_velocity", "rotation_spline", "RotationSpline", "fornberg_weights"]

_ORDERS = (2, 4, 6, 8)


# --------------------------------------------------------------------------
# helpers
# --------------------------------------------------------------------------
def _quat_samples(rotations: object, name: str = "rotations") -> np.ndarray:
    """Unit quaternions ``(n, ..., 4)`` from a Rotation or a scalar-first array."""
    single = isinstance(rotations, Rotation) or _is_scipy_rotation(rotations)
    q = as_rotation_quat(rotations, name)
    if single and q.ndim < 2:
        raise InvalidInputError(
            f"Expected `{name}` to be a sequence of rotations (shape (n, ...)), "
            "got a single rotation."
        )
    if q.ndim < 2:
        raise InvalidInputError(f"Expected `{name}` to have shape (n, ..., 4), got {q.shape}.")
    return q


def _check_lengths(t: np.ndarray, q: np.ndarray, name: str = "rotations") -> None:
    if q.shape[0] != t.shape[0]:
        raise InvalidInputError(
            f"Expected `{name}` to have {t.shape[0]} samples along axis 0 (one per time in "
            f"`t`), got {q.shape[0]}."
        )


def _make_continuous(q: np.ndarray) -> np.ndarray:
    """Flip signs along axis 0 so that consecutive quaternions have ``q_k . q_k-1 >= 0``."""
    d = _dot(q[1:], q[:-1])
    flips = np.concatenate([np.ones((1,) + d.shape[1:]), np.where(d < 0.0, -1.0, 1.0)])
    return q * np.cumprod(flips, axis=0)[..., None]


def _rotvec_unwrapped(q: np.ndarray) -> np.ndarray:
    """``2 vec(log q)`` for unit ``q`` without taking the shortest path: the angle
    is ``2 atan2(|v|, w)`` in ``[0, 2 pi]``, continuous along a continuous path."""
    return 2.0 * _quat.log(q)[..., 1:]


def _fornberg(x0: ArrayLike, x: ArrayLike, m: int) -> np.ndarray:
    """Finite-difference weights (Fornberg 1988), vectorised over leading dims.

    ``x0`` (...), ``x`` (..., N) -> ``c`` (..., N, m + 1) such that
    ``f^(k)(x0) ~ sum_j c[..., j, k] f(x_j)``.
    """
    x = np.asarray(x, dtype=float)
    x0 = np.asarray(x0, dtype=float)
    n = x.shape[-1]
    c = np.zeros(x.shape + (m + 1,))
    c[..., 0, 0] = 1.0
    c1 = np.ones(x0.shape)
    c4 = x[..., 0] - x0
    for i in range(1, n):
        mn = min(i, m)
        c2 = np.ones(x0.shape)
        c5 = c4
        c4 = x[..., i] - x0
        for j in range(i):
            c3 = x[..., i] - x[..., j]
            c2 = c2 * c3
            if j == i - 1:
                for k in range(mn, 0, -1):
                    c[..., i, k] = c1 * (k * c[..., i - 1, k - 1] - c5 * c[..., i - 1, k]) / c2
                c[..., i, 0] = -c1 * c5 * c[..., i - 1, 0] / c2
            for k in range(mn, 0, -1):
                c[..., j, k] = (c4 * c[..., j, k] - k * c[..., j, k - 1]) / c3
            c[..., j, 0] = c4 * c[..., j, 0] / c3
        c1 = c2
    return c


def fornberg_weights(x0: ArrayLike, x: ArrayLike, deriv: int = 1) -> FloatArray:
    """Finite-difference weights for the ``deriv``-th derivative at ``x0`` on nodes ``x``.

    Fornberg's algorithm (Math. Comp. 51, 1988): with ``N`` distinct nodes the
    weights are exact for polynomials of degree ``N - 1``, so the first
    derivative is ``O(h^(N-1))`` accurate on any (non-uniform) grid.

    Parameters
    ----------
    x0 : float or array_like, shape (...)
        Evaluation points.
    x : array_like, shape (..., N)
        Distinct nodes (broadcast against ``x0``).
    deriv : int
        Derivative order, ``0 <= deriv < N``.

    Returns
    -------
    w : ndarray, shape (..., N)

    Notes
    -----
    **Convention:** ``f^(deriv)(x0) ~ sum_j w[..., j] f(x[..., j])``.

    Examples
    --------
    >>> fornberg_weights(0.0, [-1.0, 0.0, 1.0]).round(12) + 0.0
    array([-0.5,  0. ,  0.5])
    """
    x = as_float_array(x, "x")
    x0 = as_float_array(x0, "x0")
    if x.ndim < 1 or x.shape[-1] < 1:
        raise InvalidInputError(f"Expected `x` to have shape (..., N), got {x.shape}.")
    deriv = as_int(deriv, "deriv", choices=range(x.shape[-1]), what=f" in [0, {x.shape[-1] - 1}]")
    xs = np.sort(x, axis=-1)
    if np.any(np.diff(xs, axis=-1) == 0):
        raise InvalidInputError("Expected `x` to have distinct nodes.")
    x0, x = np.broadcast_arrays(x0[..., None], x)
    return _fornberg(x0[..., 0], x, deriv)[..., deriv]


# --------------------------------------------------------------------------
# angular velocity at the samples
# --------------------------------------------------------------------------
def _angular_velocity(t: np.ndarray, q: np.ndarray, frame: str, order: int) -> np.ndarray:
    """Core of :func:`angular_velocity` (validated, continuous ``q`` (n, ..., 4))."""
    n = t.shape[0]
    m = order + 1
    start = np.clip(np.arange(n) - order // 2, 0, n - m)
    idx = start[:, None] + np.arange(m)  # (n, m)
    weights = _fornberg(t, t[idx], 1)[..., 1]  # (n, m)
    q_k = q[:, None]  # (n, 1, ..., 4)
    rel = _quat.multiply(_quat.conjugate(q_k), q[idx])  # R_k^T R_j, (n, m, ..., 4)
    r = _rotvec_unwrapped(rel)  # (n, m, ..., 3)
    w_shape = weights.shape + (1,) * (r.ndim - 2)
    omega_b = np.sum(weights.reshape(w_shape) * r, axis=1)
    if frame == "space":
        return _quat.rotate(q, omega_b)
    return omega_b


def angular_velocity(
    t: ArrayLike, rotations: Rotation | ArrayLike, *, frame: str = "body", order: int = 4
) -> FloatArray:
    """Angular velocity at the samples of an attitude history (theory §5, task (b)).

    For each sample ``k`` the rotation vectors of the neighbouring samples
    relative to it, ``r_j = log(R_k^T R_j)`` (body-frame increments), are
    differentiated at ``t_k`` with Fornberg finite-difference weights on the
    ``order + 1`` nearest samples (centred inside, one-sided at the ends).
    Because ``log(R_k^T R(t))`` has derivative exactly ``w_xi(t_k)`` at ``t_k``,
    no Jacobian correction is needed.

    Parameters
    ----------
    t : array_like, shape (n,)
        Strictly increasing sample times (any spacing), ``n >= order + 1``.
    rotations : Rotation of shape (n, ...) or array_like, shape (n, ..., 4)
        Attitudes (body -> space) at ``t``; arrays are scalar-first quaternions,
        normalised here (a SciPy ``Rotation`` is accepted too). Sign flips
        ``q -> -q`` between samples are harmless.
    frame : {"body", "space"}
        Axes of the result (``w_x = R w_xi``).
    order : {2, 4, 6, 8}
        Order of accuracy (stencil of ``order + 1`` samples).

    Returns
    -------
    omega : ndarray, shape (n, ..., 3)
        Angular velocity (rad/s) at each sample.

    Notes
    -----
    **Convention:** ``R`` maps body to space components; ``t`` in s, result in
    rad/s.

    Accuracy: the error is ``O(h^order)`` on smooth motions (``h`` the local
    spacing; measured ~16x smaller per halving of ``h`` for ``order=4``), exact
    (to rounding) for a constant angular velocity at any step. The samples must
    resolve the motion: the body must turn by less than ``pi`` between
    consecutive samples (otherwise the direction of rotation is ambiguous).

    Examples
    --------
    >>> import numpy as np, poinsot
    >>> t = np.linspace(0.0, 1.0, 11)
    >>> R = poinsot.Rotation.from_rotvec(np.outer(t, [0.0, 0.0, 2.0]))
    >>> angular_velocity(t, R)[[0, 5, 10]].round(12) + 0.0
    array([[0., 0., 2.],
           [0., 0., 2.],
           [0., 0., 2.]])
    """
    frame = as_choice(frame, "frame", FRAMES)
    order = as_int(order, "order", choices=_ORDERS)
    t = as_times(t, "t", min_len=order + 1)
    q = _quat_samples(rotations)
    _check_lengths(t, q)
    return _angular_velocity(t, _make_continuous(q), frame, int(order))


# --------------------------------------------------------------------------
# C2 rotation spline
# --------------------------------------------------------------------------
def _series(f2: np.ndarray, terms: Sequence[float]) -> np.ndarray:
    """Horner evaluation of ``sum_k terms[k] f2^k``."""
    out = np.zeros_like(f2) + terms[-1]
    for c in terms[-2::-1]:
        out = out * f2 + c
    return out


def _fact(k: int) -> float:
    out = 1.0
    for i in range(2, k + 1):
        out *= i
    return out


# -k1'/f and k2'/f (k1 = (1 - cos f)/f^2, k2 = (f - sin f)/f^3), as Taylor series
_M1_TERMS = [(-1) ** (n + 1) * 2 * n / _fact(2 * n + 2) for n in range(1, 10)]
_M2_TERMS = [(-1) ** n * 2 * n / _fact(2 * n + 3) for n in range(1, 10)]
_ACCEL_SERIES_ANGLE = 0.5


def _rotvec_accel_term(r: np.ndarray, rd: np.ndarray) -> np.ndarray:
    """``(d/dt J_r(r)) r'``: the part of the angular acceleration of ``exp(r^)`` that
    is quadratic in ``r'`` (``alpha_xi = J_r(r) r'' + this``)."""
    f2 = _dot(r, r)
    f = np.sqrt(f2)
    small = f < _ACCEL_SERIES_ANGLE
    fs = np.where(small, 1.0, f)
    m1 = np.where(small, _series(f2, _M1_TERMS), (2.0 - 2.0 * np.cos(fs) - fs * np.sin(fs)) / fs**4)
    m2 = np.where(
        small, _series(f2, _M2_TERMS), (3.0 * np.sin(fs) - 2.0 * fs - fs * np.cos(fs)) / fs**5
    )
    _, _, k2 = _rotvec_coefficients(f)
    cp = _cross(r, rd)
    dp = _dot(r, rd)[..., None]
    return dp * (m1[..., None] * cp + m2[..., None] * _cross(r, cp)) + k2[..., None] * _cross(
        rd, cp
    )


def _jr_inv_apply(r: np.ndarray, w: np.ndarray) -> np.ndarray:
    """``J_r(r)^-1 w`` (body frame rotation-vector rate)."""

    return _rotvec_rate(r, w, 1.0)


def _jr_matrices(r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``J_r(r)`` and ``J_r(r)^-1`` as (..., 3, 3) matrices (columns = images of e_k)."""
    eye = np.broadcast_to(np.eye(3), r.shape[:-1] + (3, 3))
    rr = r[..., None, :]
    j = _rotvec_jacobian_apply(rr, eye, 1.0)  # rows: J e_k
    ji = _jr_inv_apply(rr, eye)
    return np.swapaxes(j, -1, -2), np.swapaxes(ji, -1, -2)


_SPLINE_MAX_ITER = 30
_SPLINE_TOL = 1e-13


def _solve_knot_rates(
    dt: np.ndarray, r: np.ndarray, w_first: np.ndarray, w_last: np.ndarray
) -> np.ndarray:
    """Body angular velocities at the interior knots making the angular
    acceleration continuous.

    The conditions read ``A w + N(w) = b`` with ``A`` block-tridiagonal and
    ``N`` the quadratic term of the acceleration, which for row ``k`` depends
    only on ``w_k+1`` (its own unknown). Newton's method therefore only adds a
    block to the diagonal of ``A``: ``(A + D) w_new = b - N(w) + D w`` with
    ``D = dN/dw`` exact (``N`` is quadratic). Converges quadratically, also
    for large rotations between samples where SciPy's fixed-point iteration
    stops unconverged.
    """
    from scipy.linalg import solve_banded

    m = len(dt) - 1  # interior knots
    J, Ji = _jr_matrices(r)  # J_r(r_i), J_r(r_i)^-1 for each interval i
    ab = np.zeros((11, 3 * m))
    u = 5

    kk = np.arange(m)
    diag = 4.0 * (1.0 / dt[:-1] + 1.0 / dt[1:])
    for a in range(3):
        ab[u, 3 * kk + a] = diag
    if m > 1:
        lower = 2.0 * J[1:-1] / dt[1:-1, None, None]  # row k (k >= 1), column k - 1
        upper = 2.0 * Ji[1:-1] / dt[1:-1, None, None]  # row k (k <= m-2), column k + 1
        for a in range(3):
            for b in range(3):
                i, j = 3 * kk[1:] + a, 3 * kk[:-1] + b
                ab[u + i - j, j] = lower[:, a, b]
                i, j = 3 * kk[:-1] + a, 3 * kk[1:] + b
                ab[u + i - j, j] = upper[:, a, b]
    b0 = 6.0 * (r[:-1] / dt[:-1, None] ** 2 + r[1:] / dt[1:, None] ** 2)
    b0[0] -= 2.0 / dt[0] * (J[0] @ w_first)
    b0[-1] -= 2.0 / dt[-1] * (Ji[-1] @ w_last)
    r_left, Ji_left = r[:-1], Ji[:-1]  # interval left of interior knot k + 1
    eye = np.eye(3)
    n_unit = _rotvec_accel_term(r_left[:, None], eye)  # N(r, e_j), (m, 3, 3)
    w_in = r[:-1] / dt[:-1, None]  # initial guess: chord rates
    converged = False
    for _ in range(_SPLINE_MAX_ITER):
        # r'(dt_k) = J_r(r_k)^-1 w_k+1 on the interval left of interior knot k + 1
        rd = np.einsum("kij,kj->ki", Ji_left, w_in)
        n_val = _rotvec_accel_term(r_left, rd)
        # exact derivative of the quadratic N: dN[e_j] = N(rd + e_j) - N(rd) - N(e_j)
        n_plus = _rotvec_accel_term(r_left[:, None], rd[:, None] + eye)
        dn = np.swapaxes(n_plus - n_val[:, None] - n_unit, -1, -2) @ Ji_left  # (m, 3, 3)
        abn = ab.copy()
        for a in range(3):
            for b in range(3):
                abn[u + a - b, 3 * kk + b] += dn[:, a, b]
        rhs = b0 - n_val + np.einsum("kij,kj->ki", dn, w_in)
        new = solve_banded((5, 5), abn, rhs.ravel()).reshape(m, 3)
        delta = np.abs(new - w_in)
        w_in = new
        if not np.all(np.isfinite(new)):
            break
        if np.all(delta <= _SPLINE_TOL * (1.0 + np.abs(new))):
            converged = True
            break
    if not converged:
        raise InvalidInputError(
            "rotation_spline did not converge: `rotations` change too fast between samples "
            "of `t` (the body turns by a large fraction of a revolution per sample)."
        )
    return w_in


@dataclass(frozen=True, eq=False)
class RotationSpline:
    """A C2 attitude interpolant (returned by :func:`rotation_spline`).

    On ``[t_k, t_k+1]`` the attitude is ``R_k exp(r(tau)^)`` with
    ``r(tau) = a tau^3 + b tau^2 + c tau``, ``tau = t - t_k``: it passes through
    every sample, and its angular velocity and acceleration are continuous.
    Outside ``[t_0, t_n-1]`` the end cubics are extrapolated (as SciPy does).

    Attributes
    ----------
    t : ndarray, shape (n,)
        Knot times.
    knots : Rotation, shape (n,)
        Knot attitudes.
    coefficients : ndarray, shape (3, n - 1, 3)
        ``a, b, c`` of each interval (``c`` = body angular velocity at ``t_k``).

    Notes
    -----
    **Convention:** ``R`` maps body to space components; ``omega(t)`` (rad/s)
    and ``alpha(t)`` (rad/s^2) in body axes unless ``frame="space"``
    (``alpha_x = R alpha_xi``).

    Examples
    --------
    >>> import numpy as np, poinsot
    >>> t = np.linspace(0.0, 1.0, 6)
    >>> s = rotation_spline(t, poinsot.Rotation.from_rotvec(np.outer(t**2, [0, 0, 1.0])))
    >>> s.rotation(0.5).as_rotvec().round(6) + 0.0      # angle t^2 about z
    array([0.  , 0.  , 0.25])
    >>> s.omega([0.5], frame="space").round(6) + 0.0    # 2 t
    array([[0., 0., 1.]])
    >>> s(0.5, 2).round(6) + 0.0                         # 2 rad/s^2
    array([0., 0., 2.])
    """

    t: np.ndarray
    knots: Rotation
    coefficients: np.ndarray

    def _locate(
        self, t: ArrayLike
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        t = as_float_array(t, "t")
        if t.ndim > 1:
            raise InvalidInputError(f"Expected `t` to have shape () or (m,), got {t.shape}.")
        k = np.clip(np.searchsorted(self.t, t, side="right") - 1, 0, len(self.t) - 2)
        tau = (t - self.t[k])[..., None]
        a, b, c = (self.coefficients[i][k] for i in range(3))
        return k, tau, a, b, c

    def _r(self, t: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        k, tau, a, b, c = self._locate(t)
        r = ((a * tau + b) * tau + c) * tau
        rd = (3.0 * a * tau + 2.0 * b) * tau + c
        rdd = 6.0 * a * tau + 2.0 * b
        return k, r, rd, rdd

    def _attitude(self, k: np.ndarray, r: np.ndarray) -> np.ndarray:
        return _quat.multiply(self.knots.as_quat()[k], quat_from_rotvec(r))

    def rotation(self, t: ArrayLike) -> Rotation:
        """Interpolated attitude at ``t`` (shape () or (m,))."""
        k, r, _, _ = self._r(t)
        return Rotation.from_quat(self._attitude(k, r))

    def omega(self, t: ArrayLike, *, frame: str = "body") -> FloatArray:
        """Angular velocity (rad/s) at ``t`` in ``frame`` axes, shape (..., 3)."""
        k, r, rd, _ = self._r(t)
        w = _rotvec_jacobian_apply(r, rd, 1.0)
        if as_choice(frame, "frame", FRAMES) == "space":
            return _quat.rotate(self._attitude(k, r), w)
        return w

    def alpha(self, t: ArrayLike, *, frame: str = "body") -> FloatArray:
        """Angular acceleration ``omega'`` (rad/s^2) at ``t`` in ``frame`` axes.

        ``alpha_x = R alpha_xi`` (the two frames' derivatives agree because
        ``w x w = 0``).
        """
        k, r, rd, rdd = self._r(t)
        a = _rotvec_jacobian_apply(r, rdd, 1.0) + _rotvec_accel_term(r, rd)
        if as_choice(frame, "frame", FRAMES) == "space":
            return _quat.rotate(self._attitude(k, r), a)
        return a

    def __call__(self, t: ArrayLike, order: int = 0) -> Rotation | FloatArray:
        """SciPy-style evaluation: ``order`` 0 -> Rotation, 1 -> body angular
        velocity, 2 -> body angular acceleration."""
        if order == 0:
            return self.rotation(t)
        if order == 1:
            return self.omega(t)
        if order == 2:
            return self.alpha(t)
        raise InvalidInputError(f"Expected `order` to be 0, 1 or 2, got {order!r}.")


def rotation_spline(
    t: ArrayLike,
    rotations: Rotation | ArrayLike,
    *,
    end_omega: str | ArrayLike = "estimate",
) -> RotationSpline:
    """C2 attitude interpolant through samples ``(t_k, R_k)``.

    The rotation vector of ``R_k^T R(t)`` is a cubic in ``t`` on each interval
    (Hermite form: body angular velocities ``w_k`` at the knots); the interior
    ``w_k`` are chosen so that the angular acceleration is continuous, which
    gives a block-tridiagonal system with a quadratic term, solved here by
    Newton's method -- the construction of SciPy's ``RotationSpline`` (which
    uses a fixed-point iteration). The two
    end velocities are the boundary conditions.

    Parameters
    ----------
    t : array_like, shape (n,)
        Strictly increasing knot times, ``n >= 2``.
    rotations : Rotation of shape (n,) or array_like, shape (n, 4)
        Attitudes (body -> space); arrays are scalar-first quaternions (a SciPy
        ``Rotation`` is accepted too). Sign flips between samples are harmless
        (each increment takes the shortest rotation, so consecutive samples
        must differ by less than ``pi``).
    end_omega : {"estimate", "chord"} or array_like, shape (2, 3)
        Body angular velocities at ``t_0`` and ``t_n-1``. ``"estimate"``
        (default): from :func:`angular_velocity` (4th order; 2nd order when
        ``n < 5``; ``"chord"`` when ``n = 2``). ``"chord"``: the mean rate of the
        end intervals, ``log(R_0^T R_1)/(t_1 - t_0)``, exactly SciPy's rule.
        An array: known end angular velocities (clamped spline).

    Returns
    -------
    spline : RotationSpline
        ``spline.rotation(t)``, ``spline.omega(t, frame=)``,
        ``spline.alpha(t, frame=)``, or ``spline(t, order)`` like SciPy.

    Notes
    -----
    **Convention:** ``R`` maps body to space components; ``omega`` and
    ``alpha`` in rad/s and rad/s^2, body axes unless ``frame="space"``.

    Accuracy on a smooth motion (h = spacing): attitude ``O(h^4)``, angular
    velocity ``O(h^3)``, acceleration ``O(h^2)`` with ``"estimate"`` or exact end
    velocities; with ``"chord"`` (SciPy) the end intervals limit the attitude to
    ``O(h^2)`` and the angular velocity to ``O(h)``.

    Examples
    --------
    >>> import numpy as np, poinsot
    >>> t = np.linspace(0.0, 2.0, 9)
    >>> R = poinsot.Rotation.from_rotvec(np.outer(t, [0.0, 1.5, 0.0]))
    >>> s = rotation_spline(t, R)
    >>> s.omega([0.3, 1.7]).round(10) + 0.0
    array([[0. , 1.5, 0. ],
           [0. , 1.5, 0. ]])
    """
    t = as_times(t, "t", min_len=2)
    q = _quat_samples(rotations)
    if q.ndim != 2:
        raise InvalidInputError(
            f"Expected `rotations` to have shape (n, 4) (one attitude per time), got {q.shape}."
        )
    _check_lengths(t, q)
    n = t.shape[0]
    dt = np.diff(t)
    rel = _quat.multiply(_quat.conjugate(q[:-1]), q[1:])
    rel = np.where(rel[..., :1] < 0.0, -rel, rel)  # shortest increment
    r = _rotvec_unwrapped(rel)  # (n-1, 3)
    if isinstance(end_omega, str):
        as_choice(end_omega, "end_omega", ("estimate", "chord"))
        if end_omega == "chord" or n == 2:
            w_first, w_last = r[0] / dt[0], r[-1] / dt[-1]
        else:
            order = 4 if n >= 5 else 2
            m = order + 1  # the end stencils only involve the first / last m samples
            w_first = _angular_velocity(t[:m], _make_continuous(q[:m]), "body", order)[0]
            w_last = _angular_velocity(t[-m:], _make_continuous(q[-m:]), "body", order)[-1]
    else:
        ends = as_trailing(end_omega, "end_omega", (3,))
        if ends.shape != (2, 3):
            raise InvalidInputError(f"Expected `end_omega` to have shape (2, 3), got {ends.shape}.")
        w_first, w_last = ends[0], ends[1]
    if n == 2:
        w_knots = np.stack([w_first, w_last])
    else:
        w_in = _solve_knot_rates(dt, r, w_first, w_last)
        w_knots = np.concatenate([w_first[None], w_in, w_last[None]])
    rd_end = _jr_inv_apply(r, w_knots[1:])  # r'(dt_i) on each interval
    w0 = w_knots[:-1]
    h = dt[:, None]
    a = (-2.0 * r + h * w0 + h * rd_end) / h**3
    b = (3.0 * r - 2.0 * h * w0 - h * rd_end) / h**2
    coeffs = np.stack([a, b, w0])
    t = t.copy()  # never freeze the caller's array
    for arr in (t, coeffs):
        arr.setflags(write=False)
    return RotationSpline(t=t, knots=Rotation.from_quat(q), coefficients=coeffs)
