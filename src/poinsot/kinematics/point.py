"""Kinematics of a point: the natural (Frenet) trihedron (theory §7, numeric part).

:func:`frenet` takes a curve ``r(t)`` -- samples at (possibly non-uniform)
times, or a callable -- and returns the unit tangent ``T``, normal ``N`` and
binormal ``B``, the curvature ``kappa = 1/rho``, the torsion ``tau``, the speed
``v = s'`` and the two components of the acceleration
``w = v' T + (v^2 / rho) N``.

Derivatives come from finite differences with weights computed for the actual
nodes by Fornberg's algorithm (the kernel shared with
:func:`poinsot.kinematics.angular_velocity`) (B. Fornberg, *Calculation of weights in finite
difference formulas*, SIAM Rev. 40 (1998) 685-691), or from exact derivative
callables when the caller has them.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._typing import ArrayLike
from .._validate import as_float_array, as_int, as_times, is_integer
from ..errors import InvalidInputError, SingularityWarning
from .attitude_history import _fornberg
from .fields import _scalar

__all__ = ["FrenetFrame", "frenet"]

#: Default number of samples in the finite-difference stencil for sampled curves.
DEFAULT_STENCIL = 7
#: Default step (in units of ``t``) for differentiating a callable curve.
DEFAULT_STEP = 1e-2
#: Half-width of the central stencil used for callable curves (9 points).
_CALLABLE_HALF = 4
#: Default relative tolerance for a straight (zero-curvature) point.
DEFAULT_RTOL = 1e-8
#: Rounding-error bound of a finite difference: ``_NOISE * sum_j |c_j| |r_j|``.
_NOISE = 64.0 * np.finfo(np.float64).eps


@dataclass(frozen=True, eq=False)
class FrenetFrame:
    """The natural trihedron of a curve and the kinematic quantities along it.

    Attributes
    ----------
    t : ndarray, shape (n,) or the shape of the times given
        The times.
    position, velocity, acceleration : ndarray, shape (..., 3)
        ``r``, ``v = r'`` and ``w = r''``.
    tangent : ndarray, shape (..., 3)
        ``T = v / |v|``.
    normal : ndarray, shape (..., 3)
        Principal normal ``N = B x T`` (towards the centre of curvature).
    binormal : ndarray, shape (..., 3)
        ``B = (v x w) / |v x w|``.
    curvature : ndarray, shape (...)
        ``kappa = 1/rho = |v x w| / |v|^3``.
    torsion : ndarray, shape (...)
        ``tau = (v x w) . r''' / |v x w|^2`` (positive for a right-handed helix).
    speed : ndarray, shape (...)
        ``|v| = ds/dt``.
    tangential_acceleration : ndarray, shape (...)
        ``w . T = d|v|/dt`` (signed).
    normal_acceleration : ndarray, shape (...)
        ``w . N = |v|^2 kappa = |v|^2 / rho`` (non-negative).
    singular : ndarray of bool, shape (...)
        Where the frame is not defined: a straight point (``kappa = 0``; then
        ``normal``, ``binormal``, ``torsion`` and ``normal_acceleration`` are
        set to 0) or a stationary point (``v = 0``; then ``tangent`` and
        ``tangential_acceleration`` and ``curvature`` are 0 too).
    """

    t: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    tangent: np.ndarray
    normal: np.ndarray
    binormal: np.ndarray
    curvature: np.ndarray
    torsion: np.ndarray
    speed: np.ndarray
    tangential_acceleration: np.ndarray
    normal_acceleration: np.ndarray
    singular: np.ndarray

    @property
    def radius_of_curvature(self) -> np.ndarray:
        """``rho = 1 / kappa`` (``inf`` where the curvature is 0)."""
        k = self.curvature
        return np.divide(1.0, k, out=np.full_like(k, np.inf), where=k > 0)


def _stencil_derivatives(
    t: np.ndarray, r: np.ndarray, w: int, stride: int | np.ndarray, where: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Derivatives 0..3 at the samples ``where`` from ``w`` samples ``stride`` apart
    (``stride`` an int or an array matching ``where``).

    ``r`` has shape (n, m, 3). Returns ``d`` (4, p, m, 3) and the rounding-error
    bounds ``sum_j |c_jk| |r_j|`` (4, p, m). Stencils are centred where possible
    and one-sided at the ends; weights by Fornberg's algorithm on nodes scaled
    to unit width (well conditioned for any spacing).
    """
    n = t.size
    step = np.asarray(stride)
    start = np.clip(where - step * (w // 2), 0, n - 1 - step * (w - 1))
    idx = start[:, None] + step[..., None] * np.arange(w)  # (p, w)
    x = t[idx] - t[where][:, None]
    h = x[:, -1] - x[:, 0]  # stencil width, > 0
    c = _fornberg(0.0, x / h[:, None], 3)  # (p, w, 4)
    c = c / h[:, None, None] ** np.arange(4)
    nodes = r[idx]  # (p, w, m, 3)
    d = np.einsum("pjk,pjmi->kpmi", c, nodes, optimize=True)
    size = _norm(nodes)  # (p, w, m)
    noise = np.einsum("pjk,pjm->kpm", np.abs(c), size, optimize=True)
    return d, noise


def _auto_strides(t: np.ndarray, r: np.ndarray, w: int) -> tuple[int, int, int]:
    """Stride for derivatives 1, 2, 3 that minimises the estimated error.

    For strides ``s = 1, 2, 4, ...`` the difference between the estimates with
    ``s`` and ``2 s`` (at up to 257 probe samples, worst case over them) bounds
    the error of the better one: it grows with ``s`` where truncation dominates
    and shrinks where rounding (``~ eps |r| / h^k``) dominates. Dense samples
    thus get wider stencils for the higher derivatives.
    """
    n = t.size
    strides = [1]
    while 2 * strides[-1] * (w - 1) <= n - 1:
        strides.append(2 * strides[-1])
    if len(strides) == 1:
        return 1, 1, 1
    probes = np.unique(np.linspace(0, n - 1, min(n, 257)).astype(np.intp))
    p = probes.size
    d = _stencil_derivatives(t, r, w, np.repeat(strides, p), np.tile(probes, len(strides)))[0][
        1:
    ]  # (3, len(strides) * p, m, 3)
    d = d.reshape(3, len(strides), p, *d.shape[2:])
    est = _norm(d[:, :-1] - d[:, 1:]).reshape(3, len(strides) - 1, -1).max(axis=-1).T
    best = np.argmin(est, axis=0)
    s1, s2, s3 = (int(strides[b]) for b in best)
    return s1, s2, s3


def _sample_derivatives(
    t: np.ndarray, r: np.ndarray, w: int, stride: int | str
) -> tuple[list[np.ndarray], list[np.ndarray], tuple[int, ...]]:
    """Derivatives 1..3 of samples ``r`` (n, m, 3), their rounding bounds, the strides."""
    n = t.size
    # `stride` is validated by the caller: "auto" or an int
    strides = _auto_strides(t, r, w) if isinstance(stride, str) else (stride,) * 3
    where = np.arange(n)
    cache: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    derivs, noises = [], []
    for k, s in enumerate(strides, start=1):
        if s not in cache:
            cache[s] = _stencil_derivatives(t, r, w, s, where)
        derivs.append(cache[s][0][k])
        noises.append(cache[s][1][k])
    return derivs, noises, strides


def _eval_curve(func: Callable[..., Any], tt: np.ndarray, name: str) -> np.ndarray:
    """Call a curve and return shape ``tt.shape + (3,)`` (2-D curves padded)."""
    try:
        out = func(tt)
    except Exception as exc:  # a user callable: report which one failed
        raise InvalidInputError(
            f"Calling `{name}` on an array of times of shape {tt.shape} failed "
            f"({type(exc).__name__}: {exc}); it must accept NumPy arrays of times."
        ) from exc
    if isinstance(out, list | tuple) and len(out) in (2, 3):
        try:
            comps = np.broadcast_arrays(*(np.asarray(o, dtype=np.float64) for o in out), tt)[:-1]
        except (TypeError, ValueError):
            comps = None
        if comps is not None and all(cc.shape == tt.shape for cc in comps):
            out = np.stack(comps, axis=-1)
    a = as_float_array(out, f"{name}(t)")
    if a.shape[:-1] == tt.shape and a.shape[-1] in (2, 3):
        pass
    elif a.ndim >= 1 and a.shape[1:] == tt.shape and a.shape[0] in (2, 3):
        a = np.moveaxis(a, 0, -1)
    else:
        raise InvalidInputError(
            f"Expected `{name}(t)` to return shape (..., 3) (or (3, ...)) for t of shape "
            f"{tt.shape}, got {a.shape}."
        )
    return _pad3(a)


def _pad3(a: np.ndarray) -> np.ndarray:
    if a.shape[-1] == 2:
        a = np.concatenate([a, np.zeros(a.shape[:-1] + (1,))], axis=-1)
    return a


def _norm(a: np.ndarray) -> np.ndarray:
    return np.sqrt(np.einsum("...i,...i->...", a, a))


def _scaled(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(m, x/m)`` with ``m`` the largest |component| per point (1 where x = 0), so that
    products of the scaled vectors neither overflow nor underflow."""
    m = np.max(np.abs(x), axis=-1)
    m = np.where(m > 0, m, 1.0)
    return m, x / m[..., None]


def _frenet_kernel(
    t: np.ndarray,
    r: np.ndarray,
    v: np.ndarray,
    a: np.ndarray,
    j: np.ndarray,
    noise_v: np.ndarray,
    noise_a: np.ndarray,
    rtol: float,
) -> FrenetFrame:
    """The trihedron from the derivatives; ``noise_*`` bound their rounding errors.

    Every product is formed from per-point scaled vectors ``v = V v^``, ``a = A a^``,
    ``j = J j^`` (``V, A, J`` the largest components), e.g.
    ``kappa = (A/V^2) |v^ x a^| / |v^|^3``: curves of any length scale work.
    """
    with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
        V, vs = _scaled(v)
        A, as_ = _scaled(a)
        Jm, js = _scaled(j)
        speed_s = _norm(vs)
        speed = V * speed_s
        vxa_s = np.cross(vs, as_)
        cross_s = _norm(vxa_s)
        stationary = speed <= _NOISE * noise_v
        # normal acceleration |v x a| / |v| against the size of a and its rounding error
        # (|v x a| <= |v| (rtol |a| + noise), divided by V A)
        straight = ~stationary & (cross_s <= speed_s * (rtol * _norm(as_) + _NOISE * noise_a / A))
        singular = stationary | straight
        regular = ~singular

        safe_speed = np.where(stationary, 1.0, speed_s)
        safe_cross = np.where(singular, 1.0, cross_s)
        tangent = np.where(stationary[..., None], 0.0, vs / safe_speed[..., None])
        binormal = np.where(singular[..., None], 0.0, vxa_s / safe_cross[..., None])
        normal = np.cross(binormal, tangent)
        curvature = np.where(singular, 0.0, (A / V / V) * (cross_s / safe_speed**3))
        torsion = np.where(
            regular,
            (Jm / V / A) * np.einsum("...i,...i->...", vxa_s, js) / safe_cross**2,
            0.0,
        )
        a_t = np.einsum("...i,...i->...", a, tangent)
        a_n = np.where(singular, 0.0, A * (cross_s / safe_speed))
    if not (np.all(np.isfinite(curvature)) and np.all(np.isfinite(torsion))):
        raise InvalidInputError(
            "Expected the curve to have a curvature and torsion representable in "
            "float64; they overflow for these `t` and `r` (rescale the time or length unit)."
        )

    count = int(np.count_nonzero(singular))
    if count:
        warnings.warn(
            f"{count} point(s) of the curve are straight (curvature 0) or stationary "
            "(velocity 0): there the normal, binormal and torsion are undefined and set "
            "to 0 (see FrenetFrame.singular).",
            SingularityWarning,
            stacklevel=3,
        )
    return FrenetFrame(
        t=t,
        position=r,
        velocity=v,
        acceleration=a,
        tangent=tangent,
        normal=normal,
        binormal=binormal,
        curvature=curvature,
        torsion=torsion,
        speed=speed,
        tangential_acceleration=a_t,
        normal_acceleration=a_n,
        singular=singular,
    )


def frenet(
    t: ArrayLike,
    r: ArrayLike | Callable[..., Any],
    *,
    derivatives: tuple[Callable[..., Any], Callable[..., Any], Callable[..., Any]] | None = None,
    step: float = DEFAULT_STEP,
    stencil: int = DEFAULT_STENCIL,
    stride: int | str = "auto",
    rtol: float = DEFAULT_RTOL,
) -> FrenetFrame:
    """Natural (Frenet) trihedron, curvature and torsion of a curve (theory §7).

    Parameters
    ----------
    t : array_like
        Times. With samples: shape (n,), strictly increasing (non-uniform
        spacing allowed). With a callable: any shape.
    r : array_like, shape (n, ..., 3) or (n, ..., 2), or callable
        Samples of the position at the times ``t`` (extra middle axes are
        independent curves; 2-D curves lie in the plane z = 0), or a function
        ``r(t)`` that accepts an array of times and returns positions of shape
        ``t.shape + (3,)`` (``(3,) + t.shape`` and a tuple of components are
        accepted too).
    derivatives : tuple of 3 callables, optional
        Exact ``(r', r'', r''')`` for a callable ``r`` (same conventions as
        ``r``); skips the finite differences.
    step : float, optional
        Step ``h`` of the 9-point central differences used for a callable ``r``
        (default ``1e-2``, in units of ``t``; pick about 1/100 of the time
        over which the curve turns). Errors: ``O(h^8)`` for ``v``, ``O(h^6)``
        for ``r'''``, plus rounding ``~ 1e-16 |r| / h^k`` for the k-th derivative.
    stencil : int, optional
        Number of consecutive samples in each finite-difference stencil
        (default 7, at least 4): derivative k is exact for polynomials of degree
        ``< stencil`` and has error ``O(h^(stencil - k))`` (one order more at
        interior points of a uniform grid for even k). Stencils are centred
        where possible and one-sided at the ends.
    stride : int or "auto", optional
        Use every ``stride``-th sample in the stencils. ``"auto"`` (default)
        picks, separately for each of the three derivatives, the stride among
        1, 2, 4, ... whose estimate changes least when the stride is doubled:
        on densely sampled curves rounding (``~ 1e-16 |r| / h^k`` for the k-th
        derivative) would otherwise dominate the higher derivatives.
    rtol : float, optional
        A point counts as straight where the normal acceleration is below
        ``rtol |w|`` plus the rounding-error bound of the differences
        (default ``1e-8``).

    Returns
    -------
    FrenetFrame
        ``T = v/|v|``, ``B = v x w / |v x w|``, ``N = B x T``,
        ``kappa = |v x w| / |v|^3``, ``tau = (v x w) . r''' / |v x w|^2``,
        speed ``|v|``, tangential ``w . T`` and normal ``|v|^2 kappa``
        acceleration, so that ``v = s' T`` and ``w = v' T + (v^2/rho) N``.

    Warns
    -----
    SingularityWarning
        Where the curve is straight or stationary (the normal is undefined):
        ``normal``, ``binormal`` and ``torsion`` are set to 0 there and
        ``FrenetFrame.singular`` marks those points.

    Raises
    ------
    InvalidInputError
        Bad shapes, non-finite values, non-increasing or too few samples
        (fewer than ``stencil``), a bad ``step``/``stencil``/``stride``/``rtol``.

    Notes
    -----
    **Convention:** any fixed Cartesian frame; ``t`` in s (any consistent
    time unit), curvature in 1/length, torsion in 1/length, accelerations in
    length/time^2.

    Examples
    --------
    A helix ``(a cos t, a sin t, b t)`` has ``kappa = a/(a^2+b^2)`` and
    ``tau = b/(a^2+b^2)``:

    >>> import numpy as np
    >>> from poinsot.kinematics import frenet
    >>> helix = lambda t: (2 * np.cos(t), 2 * np.sin(t), 1 * t)
    >>> f = frenet(np.array([0.0, 1.0]), helix)
    >>> f.curvature.round(9), f.torsion.round(7)
    (array([0.4, 0.4]), array([0.2, 0.2]))

    From samples (non-uniform times):

    >>> t = np.sort(np.random.default_rng(0).uniform(0, 6, 400))
    >>> r = np.stack([2 * np.cos(t), 2 * np.sin(t), t], axis=-1)
    >>> f = frenet(t, r)
    >>> bool(np.allclose(f.curvature, 0.4, atol=1e-6))
    True
    """
    rtol = _scalar(rtol, "rtol")
    stencil = as_int(stencil, "stencil", minimum=4)
    if callable(r):
        return _frenet_callable(t, r, derivatives, step, rtol)
    if derivatives is not None:
        raise InvalidInputError(
            "Expected `derivatives` only with a callable `r`, got samples for `r`."
        )
    r = as_float_array(r, "r")
    t_arr = as_float_array(t, "t")
    if t_arr.ndim != 1:
        raise InvalidInputError(f"Expected `t` to have shape (n,), got {t_arr.shape}.")
    if r.ndim < 2 or r.shape[-1] not in (2, 3):
        raise InvalidInputError(
            f"Expected `r` to have shape (n, ..., 3) or (n, ..., 2), got {r.shape}."
        )
    if r.shape[0] != t_arr.shape[0]:
        raise InvalidInputError(
            f"Expected `r` to have one sample per time: len(t) = {t_arr.shape[0]} but "
            f"`r` has shape {r.shape}."
        )
    t_arr = as_times(t_arr, "t", min_len=stencil)
    n = t_arr.size
    if not (isinstance(stride, str) and stride == "auto"):
        if (
            isinstance(stride, str)
            or not is_integer(stride)
            or stride < 1
            or stride * (stencil - 1) > n - 1
        ):
            raise InvalidInputError(
                f"Expected `stride` to be 'auto' or an integer >= 1 with "
                f"stride * (stencil - 1) <= len(t) - 1 = {n - 1}, got {stride!r}."
            )
    r = _pad3(r)
    batch = r.shape[1:-1]
    # differences of r / L (L ~ max |r|, a power of 2 so that the scaling is exact):
    # the rounding bounds (|c| |r| sums) cannot overflow for any length scale of the
    # curve; the derivatives are scaled back
    L = float(np.ldexp(1.0, np.frexp(np.max(np.abs(r), initial=0.0))[1]))
    with np.errstate(all="ignore"):
        (v, a, j), (nv, na, _), _ = _sample_derivatives(
            t_arr, r.reshape(n, -1, 3) / L, stencil, stride
        )
        v, a, j, nv, na = (L * x for x in (v, a, j, nv, na))
    if not (np.all(np.isfinite(v)) and np.all(np.isfinite(a)) and np.all(np.isfinite(j))):
        raise InvalidInputError(
            "Expected `t` and `r` to give finite first to third derivatives in float64; "
            "they overflow (rescale the time or length unit)."
        )

    def back(x: np.ndarray) -> np.ndarray:
        return x.reshape((n, *batch) + x.shape[2:])

    return _frenet_kernel(t_arr, r, back(v), back(a), back(j), back(nv), back(na), rtol)


def _frenet_callable(
    t: ArrayLike,
    r: Callable[..., Any],
    derivatives: tuple[Callable[..., Any], Callable[..., Any], Callable[..., Any]] | None,
    step: float,
    rtol: float,
) -> FrenetFrame:
    t = as_float_array(t, "t")
    if derivatives is not None:
        if (
            not isinstance(derivatives, list | tuple)
            or len(derivatives) != 3
            or not all(callable(f) for f in derivatives)
        ):
            raise InvalidInputError(
                "Expected `derivatives` to be a tuple of three callables (r', r'', r''')."
            )
        pos = _eval_curve(r, t, "r")
        v, a, j = (
            _eval_curve(f, t, name)
            for f, name in zip(
                derivatives, ("derivatives[0]", "derivatives[1]", "derivatives[2]"), strict=True
            )
        )
        zero = np.zeros(t.shape)
        return _frenet_kernel(t, pos, v, a, j, zero, zero, rtol)
    step = _scalar(step, "step", strict=True)
    # the finite-difference nodes t + k step must be distinct to ~1e-6 of the step
    if np.any(np.spacing(np.abs(t)) > 1e-6 * step):
        raise InvalidInputError(
            f"Expected `step` ({step:g}) to be resolvable at the times `t` (max |t| = "
            f"{float(np.max(np.abs(t))):g}): t + step must differ from t by more than "
            "rounding; use a larger step or shift the time origin."
        )
    offsets = step * np.arange(-_CALLABLE_HALF, _CALLABLE_HALF + 1, dtype=np.float64)
    c = _fornberg(0.0, np.arange(-_CALLABLE_HALF, _CALLABLE_HALF + 1.0), 3)
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        c = c / step ** np.arange(4)  # (w, 4)
        nodes = _eval_curve(r, t[..., None] + offsets, "r")  # (..., w, 3)
        d = np.einsum("jk,...jd->k...d", c, nodes)
    if not np.all(np.isfinite(d)):
        raise InvalidInputError(
            f"Expected `step` ({step:g}) and the scale of the curve to give finite "
            "differences, but the derivatives overflow; use a moderate step (e.g. 1e-3 "
            "to 1e-1 of the time scale of the curve)."
        )
    m, unit = _scaled(nodes)  # |r| without overflow in r.r
    size = m * _norm(unit)
    noise = np.einsum("jk,...j->k...", np.abs(c), size)
    return _frenet_kernel(
        t, nodes[..., _CALLABLE_HALF, :], d[1], d[2], d[3], noise[1], noise[2], rtol
    )
