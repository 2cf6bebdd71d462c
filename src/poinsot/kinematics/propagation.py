"""Attitude propagation: given ``w(t)`` and ``L(t0)``, find ``L(t)`` (theory §5, task (a)).

The attitude quaternion ``L`` (body -> space) obeys Poisson's kinematic equation

``L' = 1/2 L o w_xi``   (``w_xi``: angular velocity in body axes), or
``L' = 1/2 w_x o L``    (``w_x``: angular velocity in space axes).

The equation is linear in ``L`` and its coefficient does not depend on ``L``, so
every fixed-step method below advances the attitude by an *increment* quaternion
``D_j`` that depends only on ``w`` over step ``j``:
``L_{j+1} = L_j o D_j`` (body) or ``L_{j+1} = D_j o L_j`` (space). All increments
are computed at once (vectorised over steps and bodies) and then chained by an
associative scan of quaternion products.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, cast

import numpy as np

from .. import _quat as _q
from .. import integrators
from .._typing import ArrayLike
from .._validate import (
    as_bool,
    as_choice,
    as_float_array,
    as_int,
    as_rotation_quat,
    as_times,
    batch_shape,
)
from .._vec import cross as _cross
from ..errors import IntegrationError, InvalidInputError
from ..rotations import quaternion as _quat
from ..rotations.rotation import Rotation
from ..rotations.rotvec import quat_from_rotvec
from ..trajectory import Trajectory
from .poisson_matrix import integrate_poisson_matrix

__all__ = ["propagate"]

#: The attitude-propagation methods (from :data:`poinsot.integrators.INTEGRATORS`).
METHODS = integrators.names("attitude")
FRAMES = ("body", "space")

#: Order of accuracy of each fixed-step method for smooth ``w(t)`` (global error ~ h^p).
ORDER = {"magnus4": 4, "magnus6": 6, "rk4": 4, "exponential": 2, "exponential-samples": 1}

# Offset of the two Gauss-Legendre nodes from the step midpoint, in units of h.
_GAUSS = math.sqrt(3.0) / 6.0
# Coefficient of the commutator term of the 4th-order Magnus method.
_MAGNUS_C = math.sqrt(3.0) / 12.0
# Three-point Gauss nodes (offsets from the midpoint, units of h) of the 6th-order method.
_GAUSS3 = math.sqrt(15.0) / 10.0
# Work arrays hold about this many body-steps at a time (memory bound).
_CHUNK = 1 << 16
# Below this many bodies, steps are chained by a parallel scan; above, one by one.
_SCAN_MAX_BODIES = 32


# --------------------------------------------------------------------------- kernels


_pure = _q.pure
_mul = _q.mul
_normalize = _q.normalize


def _chain(mul: Callable[[np.ndarray, np.ndarray], np.ndarray], d: np.ndarray) -> np.ndarray:
    """Inclusive scan ``S_j = mul(S_{j-1}, D_j)`` along axis 0 (Hillis-Steele, log2 passes)."""
    s = d.copy()
    k = 1
    while k < s.shape[0]:
        s[k:] = mul(s[:-k], s[k:])
        k *= 2
    return s


# --------------------------------------------------------------------------- omega sources


class _Samples:
    """Angular velocity given as samples ``w_k`` on the output times ``t_k``."""

    kind = "samples"

    def __init__(self, t: np.ndarray, w: np.ndarray, hold: bool) -> None:
        self.t = t
        self.w = w  # (n, Nw, 3)
        self.hold = hold
        self._spline: Any = None  # scipy's CubicSpline (SciPy ships no types)
        if not hold:
            from scipy.interpolate import CubicSpline

            self._spline = CubicSpline(t, w, axis=0)  # not-a-knot

    @property
    def interpolation(self) -> str:
        return "zero-order hold" if self.hold else "cubic spline (not-a-knot)"

    def at(self, s: np.ndarray) -> np.ndarray:
        if self.hold:
            k = np.clip(np.searchsorted(self.t, s, side="right") - 1, 0, len(self.t) - 2)
            return self.w[k]
        return self._spline(s)

    def at_outputs(self) -> np.ndarray:
        return self.w


class _Callable:
    """Angular velocity given as a function of time."""

    kind = "callable"
    interpolation = None

    def __init__(self, fun: Callable[..., Any], t: np.ndarray, vectorized: bool) -> None:
        self.fun = fun
        self.t = t
        self.vectorized = vectorized
        if vectorized:
            first = self._call(np.asarray(t[:1]))
            if first.ndim < 2 or first.shape[0] != 1 or first.shape[-1] != 3:
                raise InvalidInputError(
                    "Expected `omega(t)` with `vectorized=True` to return shape (m, 3) or "
                    f"(m, ..., 3) for m = len(t), got {first.shape} for m = 1."
                )
            self.bshape = first.shape[1:-1]
        else:
            first = self._call(float(t[0]))
            if first.ndim < 1 or first.shape[-1] != 3:
                raise InvalidInputError(
                    f"Expected `omega(t)` to return shape (..., 3), got {first.shape}."
                )
            self.bshape = first.shape[:-1]
        self.nw = math.prod(self.bshape)
        self.expand_to: tuple[int, ...] | None = None  # batch shape to broadcast to

    def _call(self, s: float | np.ndarray) -> np.ndarray:
        # finiteness is checked by the callers, which know the time
        return as_float_array(self.fun(s), "omega(t)", finite=False)

    def at(self, s: np.ndarray) -> np.ndarray:
        """Values at the times ``s`` (1-D), shape ``(len(s), Nw, 3)``, checked finite."""
        w: np.ndarray | None
        if self.vectorized:
            w = self._call(s)
            expect = (len(s),) + self.bshape + (3,)
        else:
            expect = (len(s),) + self.bshape + (3,)
            try:
                w = np.array([self.fun(x) for x in s.tolist()], dtype=np.float64)
            except (TypeError, ValueError):
                w = None
            if w is None or w.shape != expect:
                for x in s.tolist():  # find the culprit for the message
                    v = self._call(x)
                    if v.shape != expect[1:]:
                        raise InvalidInputError(
                            f"Expected `omega(t)` to return shape {expect[1:]} at every t, "
                            f"got {v.shape} at t = {x!r}."
                        )
                w = np.stack([self._call(x) for x in s.tolist()])
        if w.shape != expect:
            raise InvalidInputError(
                f"Expected `omega(t)` with `vectorized=True` to return shape {expect}, "
                f"got {w.shape}."
            )
        bad = ~np.isfinite(w)
        if np.any(bad):
            k = np.argwhere(bad)[0][0]
            raise InvalidInputError(
                f"Expected `omega(t)` to return only finite values, got {w[bad][0]} "
                f"at t = {float(s[k])!r}."
            )
        if self.expand_to is not None:
            pad = (1,) * (len(self.expand_to) - len(self.bshape))
            w = w.reshape((len(s),) + pad + self.bshape + (3,))
            w = np.broadcast_to(w, (len(s),) + self.expand_to + (3,))
            return w.reshape(len(s), -1, 3)
        return w.reshape(len(s), self.nw, 3)

    def at_outputs(self) -> np.ndarray:
        return self.at(self.t)


# --------------------------------------------------------------------------- increments


def _increments(
    method: str, frame: str, src: _Callable | _Samples, a: np.ndarray, h: np.ndarray
) -> np.ndarray:
    """Increment quaternions ``D_j`` of the steps ``[a_j, a_j + h_j]``, shape ``(m, Nw, 4)``."""
    hh = h[:, None, None]
    if method == "exponential":
        # Constant w on the step: D = exp(w h / 2) (exact for constant w; midpoint value
        # for a callable = exponential midpoint rule; left sample for held samples).
        w = src.at(a if src.kind == "samples" else a + 0.5 * h)
        return quat_from_rotvec(w * hh)
    if method == "magnus4":
        # Two-point Gauss Magnus: Omega = h/2 (w1 + w2) + s sqrt(3) h^2/12 (w1 x w2),
        # s = +1 for L' = 1/2 L o w (body), -1 for L' = 1/2 w o L (space).
        w1 = src.at(a + (0.5 - _GAUSS) * h)
        w2 = src.at(a + (0.5 + _GAUSS) * h)
        c = _MAGNUS_C if frame == "body" else -_MAGNUS_C
        theta = 0.5 * hh * (w1 + w2) + (c * hh * hh) * _cross(w1, w2)
        return quat_from_rotvec(theta)
    if method == "magnus6":
        # Three-point Gauss Magnus (Blanes, Casas, Ros 2000; Blanes et al. 2009, sec. 4)
        # written for rotation vectors, where the Lie bracket is the cross product:
        # a1 = h w2, a2 = sqrt(15) h/3 (w3 - w1), a3 = 10 h/3 (w3 - 2 w2 + w1),
        # C1 = [a1, a2], C2 = -1/60 [a1, 2 a3 + C1],
        # Omega = a1 + a3/12 + 1/240 [-20 a1 - a3 + C1, a2 + C2],
        # with [x, y] = x x y for L' = 1/2 w o L (space) and y x x for L' = 1/2 L o w (body).
        w1 = src.at(a + (0.5 - _GAUSS3) * h)
        w2 = src.at(a + 0.5 * h)
        w3 = src.at(a + (0.5 + _GAUSS3) * h)
        if frame == "space":
            br = _cross
        else:

            def br(a: np.ndarray, b: np.ndarray) -> np.ndarray:
                return _cross(b, a)

        a1 = hh * w2
        a2 = (math.sqrt(15.0) / 3.0) * hh * (w3 - w1)
        a3 = (10.0 / 3.0) * hh * (w3 - 2.0 * w2 + w1)
        c1 = br(a1, a2)
        c2 = (-1.0 / 60.0) * br(a1, 2.0 * a3 + c1)
        theta = a1 + a3 / 12.0 + br(-20.0 * a1 - a3 + c1, a2 + c2) / 240.0
        return quat_from_rotvec(theta)
    # rk4: classical RK4 applied to y' = f(t, y) from y = 1. Because the equation is
    # linear and equivariant (body: y -> L o y; space: y -> y o L), one RK4 step from
    # L equals L o D (body) or D o L (space) with this D; renormalising L after the
    # step is the same as normalising D.
    m = len(a)
    s = np.empty(2 * m + 1)
    s[0:-1:2] = a
    s[1::2] = a + 0.5 * h
    s[-1] = a[-1] + h[-1]
    w = src.at(s)
    w_a, w_m, w_b = _pure(w[0:-1:2]), _pure(w[1::2]), _pure(w[2::2])
    if frame == "body":

        def f(wq: np.ndarray, y: np.ndarray) -> np.ndarray:
            return 0.5 * _mul(y, wq)

    else:

        def f(wq: np.ndarray, y: np.ndarray) -> np.ndarray:
            return 0.5 * _mul(wq, y)

    one = np.zeros((1, 1, 4))
    one[..., 0] = 1.0
    k1 = f(w_a, one)
    k2 = f(w_m, one + 0.5 * hh * k1)
    k3 = f(w_m, one + 0.5 * hh * k2)
    k4 = f(w_b, one + hh * k3)
    return _normalize(one + hh / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4))


def _fixed_step(
    method: str,
    frame: str,
    src: _Callable | _Samples,
    q: np.ndarray,
    t: np.ndarray,
    nsub: np.ndarray,
) -> np.ndarray:
    """Unit quaternions at the output times, shape ``(len(t), N, 4)``."""
    n_bodies = q.shape[0]
    out = np.empty((len(t), n_bodies, 4))
    out[0] = q
    if len(t) == 1:
        return out
    h_int = np.diff(t) / nsub
    a = np.repeat(t[:-1], nsub) + h_int.repeat(nsub) * (
        np.arange(nsub.sum()) - np.repeat(np.cumsum(nsub) - nsub, nsub)
    )
    h = np.repeat(h_int, nsub)
    ends = np.cumsum(nsub)  # output k (k >= 1) is the state after step ends[k-1] - 1
    if frame == "body":

        def mul(x: np.ndarray, y: np.ndarray) -> np.ndarray:  # x earlier, y later
            return _mul(x, y)

    else:

        def mul(x: np.ndarray, y: np.ndarray) -> np.ndarray:
            return _mul(y, x)

    m = len(a)
    chunk = max(1, _CHUNK // n_bodies)
    carry = q
    k_out = 1
    n_since = 0
    for j0 in range(0, m, chunk):
        j1 = min(m, j0 + chunk)
        d = _increments(method, frame, src, a[j0:j1], h[j0:j1])
        d = np.broadcast_to(d, (j1 - j0, n_bodies, 4))
        # steps of this chunk (relative index) that end at an output time
        stop = np.searchsorted(ends, j1, side="right")
        want = ends[k_out - 1 : stop] - 1 - j0
        if n_bodies <= _SCAN_MAX_BODIES:
            s = mul(carry[None], _chain(mul, d))
            out[k_out : k_out + len(want)] = _normalize(s[want])
            carry = _normalize(s[-1])
        else:
            slot = dict(zip(want.tolist(), range(k_out, k_out + len(want)), strict=True))
            for j in range(j1 - j0):
                carry = mul(carry, d[j])
                n_since += 1
                if j in slot:
                    out[slot[j]] = carry = _normalize(carry)
                    n_since = 0
                elif n_since == 64:  # the unit norm drifts by ~eps per step: renormalise
                    carry = _normalize(carry)
                    n_since = 0
        k_out += len(want)
    return out


def _adaptive(
    frame: str,
    src: _Callable | _Samples,
    q: np.ndarray,
    t: np.ndarray,
    rtol: float | None,
    atol: float | None,
    max_step: float | None,
) -> tuple[np.ndarray, dict[str, Any]]:
    from scipy.integrate import solve_ivp

    n_bodies = q.shape[0]
    if len(t) == 1:
        return q[None].copy(), {"evaluations": 0, "status": 0, "message": "nothing to integrate"}

    def rhs(s: float, y: np.ndarray) -> np.ndarray:
        lq = y.reshape(n_bodies, 4)
        wq = _pure(src.at(np.array([s]))[0])
        dq = _mul(lq, wq) if frame == "body" else _mul(wq, lq)
        return 0.5 * dq.reshape(-1)

    sol = solve_ivp(
        rhs,
        (t[0], t[-1]),
        q.reshape(-1),
        method="DOP853",
        t_eval=t,
        rtol=rtol,
        atol=atol,
        max_step=np.inf if max_step is None else max_step,
    )
    if not sol.success:
        raise IntegrationError(f"Adaptive attitude propagation failed: {sol.message}")
    states = _normalize(sol.y.T.reshape(len(t), n_bodies, 4))
    return states, {"evaluations": int(sol.nfev), "status": int(sol.status), "message": sol.message}


# --------------------------------------------------------------------------- public


def propagate(
    rotation0: Rotation | ArrayLike,
    omega: Callable[..., ArrayLike] | ArrayLike,
    t: ArrayLike,
    *,
    frame: str = "body",
    method: str = "magnus4",
    steps_per_sample: int = 1,
    max_step: float | None = None,
    vectorized: bool = False,
    rtol: float | None = None,
    atol: float | None = None,
    representation: str = "quaternion",
) -> Trajectory:
    """Attitude from angular velocity: integrate Poisson's equation (theory §5, task (a)).

    Parameters
    ----------
    rotation0 : Rotation or array_like, shape (..., 4)
        Attitude at ``t[0]`` (body -> space): a :class:`~poinsot.Rotation`, a
        SciPy ``Rotation`` (converted with ``as_quat(scalar_first=True)``) or
        scalar-first quaternions (normalised here; zero is an error). Leading
        (batch) dimensions propagate many bodies at once; they broadcast with
        those of ``omega``.
    omega : callable or array_like
        Angular velocity (rad/s) in the axes named by ``frame``, either

        - a callable ``omega(t) -> (3,)`` (shared by all bodies) or ``(..., 3)``;
          with ``vectorized=True`` it receives an array of times of shape ``(m,)``
          and returns ``(m, 3)`` or ``(m, ..., 3)``;
        - samples on ``t``, shape ``(len(t), 3)`` or ``(len(t), ..., 3)``. Between
          samples, ``"magnus4"``, ``"magnus6"``, ``"rk4"`` and ``"adaptive"`` evaluate the
          not-a-knot cubic spline through the samples (needs at least 4
          samples); ``"exponential"`` holds ``w_k`` constant on ``[t_k, t_{k+1})``
          (zero-order hold, needs at least 2 samples).
    t : array_like, shape (n,)
        Strictly increasing output times (s); ``rotation0`` is the attitude at ``t[0]``.
    frame : {"body", "space"}
        Axes of ``omega``: ``"body"`` for ``L' = 1/2 L o w_xi``, ``"space"`` for
        ``L' = 1/2 w_x o L``.
    method : {"magnus4", "magnus6", "rk4", "exponential", "adaptive"}
        ``"magnus4"`` (default): 4th-order Magnus (Lie-group) method with two
        Gauss points, ``L_{j+1} = L_j o exp(Omega/2)`` with
        ``Omega = h/2 (w1 + w2) + sqrt(3) h^2/12 (w1 x w2)`` (body; the
        commutator term changes sign in space axes). ``"magnus6"``: the
        6th-order Magnus method with three Gauss points (for a callable; with
        samples the cubic spline limits it to order 4). ``"rk4"``: classical
        RK4 on the quaternion equation, renormalised every step (order 4).
        ``"exponential"``: ``L_{j+1} = L_j o exp(w h/2)`` with ``w`` constant on the
        step, exact for constant ``w`` (order 2 for a callable, evaluated at the
        step midpoint; order 1 for samples, zero-order hold). It was called
        ``"exact"`` before 0.2; ``method="exact"`` now means an exact solution
        only and is rejected here. ``"adaptive"``:
        :func:`scipy.integrate.solve_ivp` (DOP853) with ``rtol``/``atol``,
        outputs renormalised.
    steps_per_sample : int, optional
        Fixed-step methods: number of equal steps per output interval (default 1).
    max_step : float, optional
        Largest step (s). Fixed-step methods use
        ``max(steps_per_sample, ceil(dt / max_step))`` steps per interval;
        ``"adaptive"`` passes it to ``solve_ivp``.
    vectorized : bool, optional
        Whether the callable ``omega`` accepts an array of times (faster).
    rtol, atol : float, optional
        Tolerances of ``"adaptive"`` (defaults ``1e-10`` and ``1e-12``).
    representation : {"quaternion", "dcm", "dcm6"}, optional
        ``"quaternion"`` (default): the methods above. ``"dcm"`` / ``"dcm6"``:
        Poisson's matrix equation itself, 9 equations or the course's 6 (the third
        column the cross product), integrated by SciPy's DOP853 for one body with a
        constant or callable ``omega`` (:func:`integrate_poisson_matrix`, with
        ``method="adaptive"``); the result's ``rotation`` is the nearest rotation and
        ``info["orthonormality_drift"]`` the largest ``|C^T C - E|``, so that a
        course can compare matrices with quaternions.

    Returns
    -------
    Trajectory
        ``t``; ``rotation`` of shape ``(n,)`` (or ``(n, *batch)``), unit norm to
        round-off; ``omega`` in **body** axes at ``t``, shape ``(n, 3)`` (or
        ``(n, N, 3)``), converted by ``w_xi = L~ o w_x o L`` if ``frame="space"``;
        ``method``; ``info`` with ``frame``, ``omega_input``; fixed-step:
        ``steps`` (steps per body), ``step_size`` (the longest) and ``order`` (of the global
        error for smooth ``w``); adaptive: ``evaluations``, ``status``, ``message``,
        ``rtol``, ``atol``; for samples, ``interpolation``.

    Raises
    ------
    InvalidInputError
        Bad shapes, zero ``rotation0``, non-increasing ``t``, non-finite ``omega``,
        too few samples for the method, unknown ``frame`` or ``method``.
    IntegrationError
        If ``solve_ivp`` fails (``"adaptive"``).

    Notes
    -----
    **Convention:** ``L`` maps body to space components; ``omega`` in rad/s in the
    axes of ``frame``; times in s.

    The equation is linear and ``w`` does not depend on ``L``, so each
    fixed-step method reduces to ``L_{j+1} = L_j o D_j`` (body) or
    ``D_j o L_j`` (space), where the unit increment ``D_j`` depends only on
    ``w`` over step ``j`` (for ``"rk4"``, ``D_j`` is one RK4 step started from
    ``1``, normalised). All increments are formed at once and chained by an
    associative scan; for a batch the chaining runs over steps with all bodies
    vectorised. Observed orders (global error ~ ``h^p``): ``magnus4`` 4,
    ``magnus6`` 6, ``rk4`` 4, ``exponential`` 2 (callable) or 1 (samples); ``exponential``,
    ``magnus4`` and ``magnus6`` are exact when ``w`` is constant, and the two
    Magnus methods keep ``|L| = 1`` by construction (products of unit
    quaternions). With samples the not-a-knot cubic spline adds an ``O(h^4)``
    error, so no method beats order 4 there.

    References
    ----------
    Iserles, Munthe-Kaas, Norsett, Zanna, "Lie-group methods", Acta Numerica 9
    (2000), 215-365 (two-point Gauss Magnus method). Blanes, Casas, Oteo, Ros,
    "The Magnus expansion and some of its applications", Phys. Rep. 470 (2009)
    151-238, section 4 (the 6th-order three-point method).

    Examples
    --------
    Spin at 1 rad/s about the body z axis for pi/2 seconds:

    >>> import numpy as np
    >>> from poinsot.kinematics import propagate
    >>> tr = propagate([1, 0, 0, 0], lambda t: [0.0, 0.0, 1.0], [0.0, np.pi / 2])
    >>> tr.quat[-1].round(6) + 0.0
    array([0.707107, 0.      , 0.      , 0.707107])
    >>> tr.rotation.apply([1.0, 0.0, 0.0])[-1].round(12) + 0.0
    array([0., 1., 0.])
    """
    if method == "exact":
        raise InvalidInputError(
            "Expected `method` to be one of 'magnus4', 'magnus6', 'rk4', 'exponential', "
            "'adaptive', got 'exact': method='exact' means an exact solution only; the "
            "exponential step exact for constant `omega` is method='exponential'."
        )
    method = integrators.check_method(method, METHODS, "attitude propagation")
    frame = as_choice(frame, "frame", FRAMES)
    representation = as_choice(representation, "representation", ("quaternion", "dcm", "dcm6"))
    if representation != "quaternion":
        return _propagate_matrix(rotation0, omega, t, frame, method, representation, rtol, atol)
    vectorized = as_bool(vectorized, "vectorized")
    steps_per_sample = as_int(steps_per_sample, "steps_per_sample", minimum=1)
    if max_step is not None:
        max_step = float(as_float_array(max_step, "max_step"))
        if not max_step > 0:
            raise InvalidInputError(f"Expected `max_step` to be positive, got {max_step!r}.")
    if method == "adaptive":
        if steps_per_sample != 1:
            raise InvalidInputError(
                "`steps_per_sample` applies to fixed-step methods; use `max_step`, "
                "`rtol` and `atol` with method='adaptive'."
            )
        rtol = 1e-10 if rtol is None else float(as_float_array(rtol, "rtol"))
        atol = 1e-12 if atol is None else float(as_float_array(atol, "atol"))
        if not (rtol > 0 and atol > 0):
            raise InvalidInputError(
                f"Expected `rtol` and `atol` to be positive, got {rtol!r}, {atol!r}."
            )
    elif rtol is not None or atol is not None:
        raise InvalidInputError(
            f"`rtol` and `atol` apply to method='adaptive' only, not {method!r}; "
            "use `steps_per_sample` or `max_step`."
        )

    q = as_rotation_quat(rotation0, "rotation0")

    src: _Callable | _Samples
    if callable(omega):
        t = as_times(t, "t", min_len=1)
        src = _Callable(omega, t, vectorized)
        wshape = src.bshape
    else:
        need = 2 if method == "exponential" else 4
        t = as_times(t, "t", min_len=1)
        w = as_float_array(omega, "omega")
        if w.ndim < 2 or w.shape[0] != len(t) or w.shape[-1] != 3:
            raise InvalidInputError(
                f"Expected `omega` samples to have shape (len(t), 3) or (len(t), ..., 3) "
                f"with len(t) = {len(t)}, got {w.shape}."
            )
        if len(t) < need:
            why = "a cubic spline" if need == 4 else "one interval"
            raise InvalidInputError(
                f"Expected at least {need} samples of `omega` for method={method!r} "
                f"({why}), got {len(t)}."
            )
        wshape = w.shape[1:-1]
    bshape = batch_shape(rotation0=(q, 1), omega=(wshape, 0))
    # flattened omega must be one row or one row per body: broadcast it to the batch
    # when its batch shape differs from the bodies' (e.g. (3,) against (2, 3))
    padded = (1,) * (len(bshape) - len(wshape)) + tuple(wshape)
    expand = padded != bshape and math.prod(wshape) != 1
    if callable(omega):
        if expand:
            cast(_Callable, src).expand_to = bshape
    else:
        if expand:
            w = np.broadcast_to(w.reshape((len(t),) + padded + (3,)), (len(t),) + bshape + (3,))
        src = _Samples(t, w.reshape(len(t), -1, 3), hold=method == "exponential")
    n_bodies = math.prod(bshape)
    qn = np.ascontiguousarray(np.broadcast_to(q, bshape + (4,)).reshape(n_bodies, 4))

    info: dict[str, Any] = {"frame": frame, "omega_input": src.kind}
    if src.interpolation is not None:
        info["interpolation"] = src.interpolation
    if method == "adaptive":
        states, extra = _adaptive(frame, src, qn, t, rtol, atol, max_step)
        info.update(extra, rtol=rtol, atol=atol)
    else:
        nsub = np.full(len(t) - 1, steps_per_sample, dtype=np.int64)
        if max_step is not None and len(t) > 1:
            nsub = np.maximum(nsub, np.ceil(np.diff(t) / max_step * (1.0 - 1e-12)).astype(np.int64))
        states = _fixed_step(method, frame, src, qn, t, nsub)
        info["steps"] = int(nsub.sum())
        key = (
            "exponential-samples" if (method == "exponential" and src.kind == "samples") else method
        )
        info["order"] = min(ORDER[key], 4) if src.kind == "samples" else ORDER[key]
        info["step_size"] = float(np.max(np.diff(t) / nsub)) if len(t) > 1 else 0.0

    w_out = np.broadcast_to(src.at_outputs(), (len(t), n_bodies, 3))
    if frame == "space":
        w_out = _quat.rotate(_quat.conjugate(states), w_out)
    shape = (len(t),) + bshape
    return Trajectory(
        t=t,
        # unit quaternions already: skip from_quat's re-validation (a full extra pass)
        rotation=Rotation._wrap(states.reshape(shape + (4,))),
        omega=w_out.reshape(shape + (3,)),
        method=method,
        info=info,
    )


def _propagate_matrix(
    rotation0: Any,
    omega: Any,
    t: ArrayLike,
    frame: str,
    method: str,
    representation: str,
    rtol: float | None,
    atol: float | None,
) -> Trajectory:
    """``propagate(..., representation="dcm" | "dcm6")``: Poisson's matrix equation."""

    if method != "adaptive":
        raise InvalidInputError(
            f"`representation={representation!r}` integrates the matrix equation with "
            f"method='adaptive' (SciPy's DOP853), got method={method!r}."
        )
    run = integrate_poisson_matrix(
        rotation0,
        omega,
        t,
        frame=frame,
        equations=9 if representation == "dcm" else 6,
        rtol=1e-10 if rtol is None else float(rtol),
        atol=1e-12 if atol is None else float(atol),
    )
    w = np.array([np.asarray(omega(tk) if callable(omega) else omega, dtype=float) for tk in run.t])
    if frame == "space":
        w = run.rotation.apply(w, inverse=True)
    info = {
        "solver": f"DOP853 on the matrix equation ({run.equations} equations)",
        "rtol": 1e-10 if rtol is None else float(rtol),
        "atol": 1e-12 if atol is None else float(atol),
        "frame": frame,
        "orthonormality_drift": float(run.orthonormality_drift.max()),
    }
    return Trajectory(run.t, run.rotation, w, "adaptive", info=info)
