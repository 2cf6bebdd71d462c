"""Compiled, fused, adaptive DOP853 for batches of rigid bodies (numba kernels).

One compiled loop integrates Euler's dynamic equations with Poisson's
quaternion equation (docs/theory.md §5, §10) for each body of a batch, every
body with its own step size and error control (Hairer's DOP853: order 8,
embedded 5th/3rd-order error estimate, 7th-order dense output). Nothing is
allocated per stage and no Python runs per step; bodies are independent, so a
batch is spread over threads with ``prange`` (the idle cores, by the rule of
:func:`poinsot.rotations._lazy.threaded`) and the result is bit-identical for any
number of threads. :func:`integrate` runs the lane-blocked form of these kernels
(:mod:`poinsot.dynamics._fused_lanes`: eight bodies stepped together, SIMD across
bodies, each with its own step control; bit for bit the results of
:func:`one_body`); :func:`integrate_batch` here, one body per loop iteration, is
the reference it is tested against and what the NumPy executor runs.

The quaternion is integrated as a vector of R^4 (its exact flow keeps ``|q|``)
and projected back onto the unit sphere after every accepted step and at every
output (a projection onto an invariant manifold keeps the order of the method,
Hairer, Lubich & Wanner, *Geometric Numerical Integration*, IV.4).

Built-in torques are fused into the right-hand side (``kind``):

0. none;
1. constant in body axes, ``par = (Mx, My, Mz, 0)``;
2. constant in space axes, ``par = (Mx, My, Mz, 0)``: ``M_b = R^T M_s``;
3. uniform gravity about a fixed point, ``par = (m g, cx, cy, cz)``:
   ``M_b = m g (gamma x c)``, ``gamma = R^T e_z`` the upward vertical in body
   axes (the Euler-Poisson equations of the heavy body);
4. gravity gradient, ``par = (3 mu / R^3, nx, ny, nz)`` with ``n`` the unit
   space direction of the orbit radius: ``M_b = k (n_b x J n_b)``,
   ``n_b = R^T n``;
5. the gyrostatic torque of rotors whose momentum changes at a constant rate (constant
   motor torques, no friction), ``par = (h0x, h0y, h0z, Ux, Uy, Uz, 0, 0)`` in body
   axes: ``M_b = (h0 + U t) x w - U`` (theory §10.1) with ``h0`` the rotors' momentum
   at ``t = 0`` and ``U = h'``; ``U = 0`` is the gyrostat of constant ``h``,
   ``M_b = h x w``. The only kind that depends on the angular velocity ``w`` (the
   other kinds ignore it), and with kind 6 the kinds that read the time ``t``;
6. gravity gradient along a Kepler orbit (theory §10.2), which depends on
   the time ``t``: ``par = (n, e, M_0, sqrt(1 - e^2), p0, p1, p2, p3)`` with ``n`` the
   mean motion, ``M_0`` the mean anomaly at ``t = 0`` and ``p`` the unit quaternion of
   the perifocal axes ``[P Q W]`` (:func:`_orbit_direction`): Kepler's equation is
   solved at every evaluation (:func:`poinsot._numba_helpers.kepler`) and the torque
   is kind 4's with ``n = R(p) (cos f, sin f, 0)``, ``3 mu / r^3 = 3 n^2 / (1 - e cos
   E)^3``.

``par`` has :data:`NPAR` columns (the unused ones zero).

``kind + DIAGONAL`` (kinds 0 and 3) marks a batch whose inertia tensors are all
diagonal (principal axes): the right-hand side then multiplies by the moments instead
of 3x3 matrices.
The stage sums ``y + h sum_j a_sj K_j`` (and those of ``y_new``, the error estimate
and the dense output) run as chains of fused multiply-adds (:func:`poinsot._numba_helpers.fma`),
which both kernels share, so they stay equal bit for bit.

This module holds only the kernels; :func:`poinsot.dynamics.simulate`
(``method="dop853"``) validates inputs and builds the :class:`Trajectory`.
"""

from __future__ import annotations

import math

import numpy as np

from .. import _numba_helpers as nh
from .._jit import named_copy, njit, prange
from .._numba_cache import depends_on
from . import _dop853_tableau as _tab

depends_on(__file__, nh)  # the cache sees edits of the inlined helpers

_NS = _tab.N_STAGES  # 12 stages, the 13th (FSAL) is f(t + h, y_new)
_A = np.ascontiguousarray(_tab.A[:_NS, :_NS])
_B = np.ascontiguousarray(_tab.B)
_C = np.ascontiguousarray(_tab.C[:_NS])
_E3 = np.ascontiguousarray(_tab.E3)
_E5 = np.ascontiguousarray(_tab.E5)
_D = np.ascontiguousarray(_tab.D)
_AX = np.ascontiguousarray(_tab.A[_NS + 1 :])
_CX = np.ascontiguousarray(_tab.C[_NS + 1 :])

SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0
EXPONENT = -1.0 / 8.0  # -1 / (error estimator order + 1)

#: Added to the torque ``kind`` (none or gravity) of the DOP853 kernels when every body's
#: ``J`` is diagonal (principal axes, the usual case): the right-hand side skips the
#: zero products.
DIAGONAL = 8

#: Columns of the torque parameters ``par`` (kind 6 uses all of them).
NPAR = 8

#: The torque kind of gravity gradient along a Kepler orbit (reads ``t``).
KEPLER = 6

#: The torque kind of the gyrostat's rotors, ``(h0 + U t) x w - U`` (reads ``t`` and ``w``).
GYROSTAT = 5

#: ``stats`` columns: accepted steps, rejected steps, evaluations, status.
OK, STEP_TOO_SMALL, TOO_MANY_STEPS, NONFINITE, CANCELLED = 0, 1, 2, 3, 4


@njit(cache=True, inline="always")
def _orbit_direction(t, n, e, m0, b, p0, p1, p2, p3):  # pragma: no cover
    """Kind 6: the unit direction from the centre to the body on a Kepler orbit at time
    ``t``, inertial axes, and ``3 mu / r^3`` (theory §10.2), from ``par = (n, e, M_0,
    b = sqrt(1 - e^2), p)``: ``M = M_0 + n t`` reduced to ``[-pi, pi)``, ``E`` from
    Kepler's equation (:func:`poinsot._numba_helpers.kepler`; in NumPy
    ``poinsot.dynamics.orbit.KeplerOrbit.eccentric_anomaly``), the true anomaly's
    ``cos f = (cos E - e) / (1 - e cos E)``, ``sin f = b sin E / (1 - e cos E)``, turned
    by the perifocal quaternion ``p``; ``3 mu / r^3 = 3 n^2 / (1 - e cos E)^3``
    (``r = a (1 - e cos E)``, ``mu = n^2 a^3``)."""
    m = m0 + n * t
    m -= 2.0 * math.pi * math.floor((m + math.pi) / (2.0 * math.pi))
    _, c, s = nh.kepler(m, e)
    g = 1.0 - e * c
    ig = 1.0 / g
    v0, v1, v2 = nh.qrot(p0, p1, p2, p3, (c - e) * ig, b * s * ig, 0.0)
    return v0, v1, v2, 3.0 * n * n * ig * ig * ig


@njit(cache=True, inline="always")
def _torque_s(
    t, q0, q1, q2, q3, w0, w1, w2, j00, j01, j02, j10, j11, j12, j20, j21, j22, kind,
    p0, p1, p2, p3, p4, p5, p6, p7,
):  # fmt: skip  # pragma: no cover
    """The body torque of a built-in model (``kind``, ``par = (p0, ..., p7)``: see the
    module notes) at time ``t``, attitude ``q`` and angular velocity ``w``, for inertia
    ``J`` given by rows; shared by the DOP853 right-hand sides (one body, lanes), RK4 and
    the midpoint rule."""
    t0, t1, t2 = 0.0, 0.0, 0.0
    if kind == 1:
        t0, t1, t2 = p0, p1, p2
    elif kind == 5:  # the rotors' reaction (h0 + U t) x w - U (gyrostat, theory §10.1)
        # U = 0 (rotors of constant momentum): h0 + 0 t = h0 and x - 0 = x, the bits of
        # h x w (but for the sign of a zero component of h0 when t >= 0)
        t0, t1, t2 = nh.cross(p0 + p3 * t, p1 + p4 * t, p2 + p5 * t, w0, w1, w2)
        t0, t1, t2 = t0 - p3, t1 - p4, t2 - p5
    elif kind == 3:  # gravity about the pin: gamma x (m g c), gamma = R^T e_z
        # R^T e_z directly (the sandwich with e_z is mostly products with 0, which the
        # compiler must keep), scaled by 1 / |L|^2 as the sandwich is. The scale m g /
        # |L|^2 is applied last: the division then runs alongside the cross product,
        # not before it (the latency of each stage of the lane DOP853: 4-5% less time
        # on one thread in one process, 0.6% on two), with three products fewer
        g0, g1, g2 = nh.vertical(q0, q1, q2, q3)
        s = p0 / (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
        t0, t1, t2 = nh.cross(g0, g1, g2, p1, p2, p3)
        t0, t1, t2 = s * t0, s * t1, s * t2
    elif kind == 2 or kind == 4 or kind == KEPLER:
        # body components of a space vector: the torque or the direction to the body
        # (fixed, or on the orbit at t), with the gravity-gradient coefficient k
        if kind == 2:
            v0, v1, v2, k = p0, p1, p2, 1.0
        elif kind == 4:
            v0, v1, v2, k = p1, p2, p3, p0
        else:
            v0, v1, v2, k = _orbit_direction(t, p0, p1, p2, p3, p4, p5, p6, p7)
        b0, b1, b2 = nh.qrot_inverse(q0, q1, q2, q3, v0, v1, v2)
        if kind == 2:
            t0, t1, t2 = b0, b1, b2
        else:  # gravity gradient: k n_b x J n_b
            j0, j1, j2 = nh.matvec(j00, j01, j02, j10, j11, j12, j20, j21, j22, b0, b1, b2)
            t0, t1, t2 = nh.cross(b0, b1, b2, j0, j1, j2)
            t0, t1, t2 = k * t0, k * t1, k * t2
    return t0, t1, t2


@njit(cache=True, inline="always")
def _torque(t, q0, q1, q2, q3, w0, w1, w2, J, kind, par):
    """:func:`_torque_s` with ``J`` (3, 3) and ``par`` (:data:`NPAR`,) arrays."""
    return _torque_s(
        t, q0, q1, q2, q3, w0, w1, w2, J[0, 0], J[0, 1], J[0, 2], J[1, 0], J[1, 1], J[1, 2],
        J[2, 0], J[2, 1], J[2, 2], kind, par[0], par[1], par[2], par[3], par[4], par[5],
        par[6], par[7],
    )  # fmt: skip


def _rhs_formula(t, y, J, Ji, kind, par, f):
    """``f = (q', w')`` with ``q' = q o (0, w) / 2`` and ``J w' = M - w x J w``
    (theory §5, §10); every formula from :mod:`poinsot._numba_helpers`. ``kind`` plus
    :data:`DIAGONAL` (principal axes): ``J`` and ``J^-1`` are diagonal, and their
    products with ``w`` skip the zero terms (which only change the sign of a zero)."""
    q0, q1, q2, q3 = y[0], y[1], y[2], y[3]
    w0, w1, w2 = y[4], y[5], y[6]
    d0, d1, d2, d3 = nh.qmul(q0, q1, q2, q3, 0.0, w0, w1, w2)
    f[0] = 0.5 * d0
    f[1] = 0.5 * d1
    f[2] = 0.5 * d2
    f[3] = 0.5 * d3
    diagonal = kind >= DIAGONAL
    if diagonal:
        k0, k1, k2 = J[0, 0] * w0, J[1, 1] * w1, J[2, 2] * w2
    else:
        k0, k1, k2 = nh.matvec(
            J[0, 0], J[0, 1], J[0, 2], J[1, 0], J[1, 1], J[1, 2], J[2, 0], J[2, 1], J[2, 2],
            w0, w1, w2,
        )  # fmt: skip
    t0, t1, t2 = _torque(
        t, q0, q1, q2, q3, w0, w1, w2, J, kind - DIAGONAL if diagonal else kind, par
    )
    m0, m1, m2 = nh.euler_momentum_rate(k0, k1, k2, w0, w1, w2, t0, t1, t2)
    if diagonal:
        f[4], f[5], f[6] = Ji[0, 0] * m0, Ji[1, 1] * m1, Ji[2, 2] * m2
    else:
        f[4], f[5], f[6] = nh.matvec(
            Ji[0, 0], Ji[0, 1], Ji[0, 2], Ji[1, 0], Ji[1, 1], Ji[1, 2], Ji[2, 0], Ji[2, 1],
            Ji[2, 2], m0, m1, m2,
        )  # fmt: skip


#: The right-hand side at the hot site (the stage loop, 11 of a step's 12 evaluations),
#: inlined there; every other site calls one compiled function: each inlined copy of the
#: torque models costs seconds of compiling (one_body: 27 s with six copies, 10 s with none).
_rhs_inlined = njit(cache=True, inline="always")(_rhs_formula)
_rhs = njit(cache=True)(_rhs_formula)


@njit(cache=True, inline="always")
def _err_pow(err):
    """``err ** EXPONENT = err^(-1/8)`` by three square roots and a division: each
    correctly rounded and vectorised by LLVM (libm's ``pow`` is a call per lane), within
    a few ulp of ``pow``; the step-size controller of both DOP853 kernels."""
    return 1.0 / math.sqrt(math.sqrt(math.sqrt(err)))


@njit(cache=True, inline="always")
def _rms(v, scale):
    acc = 0.0
    for i in range(7):
        x = v[i] / scale[i]
        acc += x * x
    return np.sqrt(acc / 7.0)


@njit(cache=True, inline="always")
def _put(y, oq, ow, i):
    """Write the state at output ``i``, the quaternion projected onto |q| = 1."""
    s = 1.0 / np.sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3])
    for k in range(4):
        oq[i, k] = y[k] * s
    for k in range(3):
        ow[i, k] = y[4 + k]


# NumPy's error model: with atol = 0, a zero component of the state has scale 0 and its
# norm is 0/0 = NaN, so the step is NaN and the body fails as STEP_TOO_SMALL, as in
# the lanes; Python's model raised ZeroDivisionError inside a threaded kernel (SystemError)
@njit(cache=True, error_model="numpy")
def _initial_step(t, y, f, span, rtol, atol, max_step, J, Ji, kind, par, tmp, k1, scale):
    """First step (Hairer, Norsett & Wanner, II.4), as SciPy's select_initial_step;
    one right-hand-side evaluation (into ``k1``), ``f`` the derivative at ``(t, y)``.
    The one-body kernel's; the lanes run its operations, in its order, across the lanes
    (:func:`poinsot.dynamics._fused_lanes.lane_first_steps`: the same bits, tested)."""
    for i in range(7):
        scale[i] = atol + abs(y[i]) * rtol
    d0 = _rms(y, scale)
    d1 = _rms(f, scale)
    if d0 < 1e-5 or d1 < 1e-5:
        h0 = 1e-6
    else:
        h0 = 0.01 * d0 / d1
    h0 = min(h0, span)
    for i in range(7):
        tmp[i] = y[i] + h0 * f[i]
    _rhs(t + h0, tmp, J, Ji, kind, par, k1)
    for i in range(7):
        tmp[i] = k1[i] - f[i]
    d2 = _rms(tmp, scale) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
    return min(100.0 * h0, h1, span, max_step)


@njit(cache=True, error_model="numpy")
def one_body(
    y0, J, Ji, kind, par, t_out, rtol, atol, max_step, max_steps, oq, ow, stats, cancel, done
):
    """Integrate one body from ``t_out[0]``; write ``oq`` (n, 4), ``ow`` (n, 3).

    ``cancel[0] != 0`` (set by another thread on Ctrl-C) stops it before the next step
    (status CANCELLED); ``done[0]`` counts the output times written (progress)."""
    n_out = t_out.shape[0]
    K = np.empty((16, 7))
    y = y0.copy()
    y_new = np.empty(7)
    tmp = np.empty(7)
    scale = np.empty(7)
    F = np.empty((7, 7))
    f = np.empty(7)
    t = t_out[0]
    t_end = t_out[n_out - 1]
    _put(y, oq, ow, 0)
    stats[0] = 0
    stats[1] = 0
    stats[2] = 0
    stats[3] = OK
    if n_out == 1:
        return
    _rhs(t, y, J, Ji, kind, par, f)
    nfev = 1

    h_abs = _initial_step(t, y, f, t_end - t, rtol, atol, max_step, J, Ji, kind, par,
                          tmp, K[1], scale)  # fmt: skip
    nfev += 1

    i_out = 1
    steps = 0
    rejected = 0
    while i_out < n_out:
        if nh.cancelled(cancel):
            stats[3] = CANCELLED
            break
        done[0] = i_out
        if steps >= max_steps:
            stats[3] = TOO_MANY_STEPS
            break
        min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
        if h_abs > max_step:
            h_abs = max_step
        elif h_abs < min_step:
            h_abs = min_step
        if not np.isfinite(f[4] + f[5] + f[6] + y[4] + y[5] + y[6]):
            stats[3] = NONFINITE
            break
        step_rejected = False
        failed = False
        while True:
            if not h_abs >= min_step:  # also catches a NaN step from a non-finite state
                failed = True
                break
            t_new = t + h_abs
            if t_new > t_end:
                t_new = t_end
            h = t_new - t
            h_abs = h
            for k in range(7):
                K[0, k] = f[k]
            for s in range(1, _NS):
                for k in range(7):
                    acc = 0.0
                    for j in range(s):
                        acc = nh.fma(_A[s, j], K[j, k], acc)
                    tmp[k] = nh.fma(h, acc, y[k])
                _rhs_inlined(t + _C[s] * h, tmp, J, Ji, kind, par, K[s])
            for k in range(7):
                acc = 0.0
                for j in range(_NS):
                    acc = nh.fma(_B[j], K[j, k], acc)
                y_new[k] = nh.fma(h, acc, y[k])
            _rhs(t_new, y_new, J, Ji, kind, par, K[_NS])
            nfev += _NS
            e5 = 0.0
            e3 = 0.0
            for k in range(7):
                sc = atol + max(abs(y[k]), abs(y_new[k])) * rtol
                a5 = 0.0
                a3 = 0.0
                for j in range(_NS + 1):
                    a5 = nh.fma(_E5[j], K[j, k], a5)
                    a3 = nh.fma(_E3[j], K[j, k], a3)
                a5 /= sc
                a3 /= sc
                e5 += a5 * a5
                e3 += a3 * a3
            if e5 == 0.0 and e3 == 0.0:
                err = 0.0
            else:
                err = h * e5 / np.sqrt((e5 + 0.01 * e3) * 7.0)
            if err < 1.0:
                if err == 0.0:
                    factor = MAX_FACTOR
                else:
                    factor = min(MAX_FACTOR, SAFETY * _err_pow(err))
                if step_rejected:
                    factor = min(1.0, factor)
                h_abs *= factor
                break
            if not np.isfinite(err):
                factor = MIN_FACTOR
            else:
                factor = max(MIN_FACTOR, SAFETY * _err_pow(err))
            h_abs *= factor
            step_rejected = True
            rejected += 1
        if failed:
            stats[3] = STEP_TOO_SMALL
            break
        steps += 1
        # Dense output at every output time inside the step (3 more stages, once).
        if t_out[i_out] < t_new:
            for s in range(3):
                for k in range(7):
                    acc = 0.0
                    for j in range(_NS + 1 + s):
                        acc = nh.fma(_AX[s, j], K[j, k], acc)
                    tmp[k] = nh.fma(h, acc, y[k])
                _rhs(t + _CX[s] * h, tmp, J, Ji, kind, par, K[_NS + 1 + s])
            nfev += 3
            for k in range(7):
                dy = y_new[k] - y[k]
                F[0, k] = dy
                F[1, k] = h * K[0, k] - dy
                F[2, k] = 2.0 * dy - h * (K[_NS, k] + K[0, k])
                for i in range(4):
                    acc = 0.0
                    for j in range(16):
                        acc = nh.fma(_D[i, j], K[j, k], acc)
                    F[3 + i, k] = h * acc
            while i_out < n_out and t_out[i_out] < t_new:
                x = (t_out[i_out] - t) / h
                for k in range(7):
                    v = 0.0
                    for i in range(7):
                        v += F[6 - i, k]
                        if i % 2 == 0:
                            v *= x
                        else:
                            v *= 1.0 - x
                    tmp[k] = v + y[k]
                _put(tmp, oq, ow, i_out)
                i_out += 1
        # Project the quaternion back onto the unit sphere; f is linear in q.
        s = 1.0 / np.sqrt(y_new[0] ** 2 + y_new[1] ** 2 + y_new[2] ** 2 + y_new[3] ** 2)
        for k in range(4):
            y[k] = y_new[k] * s
            f[k] = K[_NS, k] * s
        for k in range(4, 7):
            y[k] = y_new[k]
            f[k] = K[_NS, k]
        t = t_new
        nonfinite = False
        for k in range(7):
            if not np.isfinite(y[k]):
                nonfinite = True
        if nonfinite:
            stats[3] = NONFINITE
            break
        while i_out < n_out and t_out[i_out] == t_new:
            _put(y, oq, ow, i_out)
            i_out += 1
    for i in range(i_out, n_out):
        for k in range(4):
            oq[i, k] = np.nan
        for k in range(3):
            ow[i, k] = np.nan
    stats[0] = steps
    stats[1] = rejected
    stats[2] = nfev


def integrate_batch(
    y0, J, Ji, kind, par, t_out, rtol, atol, max_step, max_steps, oq, ow, stats, cancel, done
):
    """Integrate ``N`` independent bodies in parallel.

    ``y0`` (N, 7) = (q, w); ``J``, ``Ji`` (N, 3, 3); ``par`` (N, :data:`NPAR`); outputs
    ``oq`` (n, N, 4), ``ow`` (n, N, 3), ``stats`` (N, 4) int64; ``cancel`` (1,) and
    ``done`` (N,) int64 (see :func:`one_body`). Without the GIL, so that the calling
    thread can take Ctrl-C (``poinsot._progress.run_compiled``).
    """
    for b in prange(y0.shape[0]):
        one_body(
            y0[b],
            J[b],
            Ji[b],
            kind,
            par[b],
            t_out,
            rtol,
            atol,
            max_step,
            max_steps,
            oq[:, b, :],
            ow[:, b, :],
            stats[b],
            cancel,
            done[b : b + 1],
        )


#: :func:`integrate_batch` on the calling thread: the same results bit for bit, and no
#: parallel region to compile (a one-body DOP853 compile in 7 s instead of 8.6 s, cold,
#: measured). :func:`poinsot.dynamics._fused_run.integrate` runs it for one body while
#: numba's cache does not hold :func:`integrate_batch`, whose one body ran 16% faster here
#: (the same machine code but for stack slots).
integrate_serial = njit(cache=True, nogil=True)(named_copy(integrate_batch, "integrate_serial"))
integrate_batch = njit(cache=True, parallel=True, nogil=True)(integrate_batch)


@njit(cache=True)
def rk4_body(y0, J, Ji, kind, par, t_out, nsub, oq, ow, cancel, done):  # pragma: no cover
    """Classical RK4 for one body with ``nsub[k]`` equal steps in output interval ``k``
    (``method="rk4"``: the same stages as the NumPy path of ``simulate``, the
    quaternion renormalised after every step). Returns the index of the first output
    interval whose end state is non-finite, or -1; -2 when ``cancel[0]`` was set
    (checked at every step; ``done[0]`` counts the intervals done)."""
    y = y0.copy()
    k1 = np.empty(7)
    k2 = np.empty(7)
    k3 = np.empty(7)
    k4 = np.empty(7)
    ys = np.empty(7)
    _put(y, oq, ow, 0)
    for k in range(t_out.shape[0] - 1):
        done[0] = k
        h = (t_out[k + 1] - t_out[k]) / nsub[k]
        for s in range(nsub[k]):
            if nh.cancelled(cancel):  # at every step: one interval may hold them all
                return -2
            tn = t_out[k] + s * h
            _rhs(tn, y, J, Ji, kind, par, k1)
            for i in range(7):
                ys[i] = y[i] + h / 2 * k1[i]
            _rhs(tn + h / 2, ys, J, Ji, kind, par, k2)
            for i in range(7):
                ys[i] = y[i] + h / 2 * k2[i]
            _rhs(tn + h / 2, ys, J, Ji, kind, par, k3)
            for i in range(7):
                ys[i] = y[i] + h * k3[i]
            _rhs(tn + h, ys, J, Ji, kind, par, k4)
            for i in range(7):
                y[i] = y[i] + h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i])
            n2 = y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]
            if not (0.0 < n2 < np.inf):
                # a diverged step: normalising would divide by zero, and an exception
                # raised inside the parallel loop reaches Python as a SystemError
                y[0] = np.nan
                break
            y[0], y[1], y[2], y[3] = nh.qnormalize(y[0], y[1], y[2], y[3])
        for i in range(7):
            if not np.isfinite(y[i]):
                for m in range(k + 1, t_out.shape[0]):
                    for c in range(4):
                        oq[m, c] = np.nan
                    for c in range(3):
                        ow[m, c] = np.nan
                return k
        _put(y, oq, ow, k + 1)
    return -1


@njit(cache=True, parallel=True, nogil=True)
def rk4_batch(y0, J, Ji, kind, par, t_out, nsub, oq, ow, failed, cancel, done):  # pragma: no cover
    """:func:`rk4_body` for ``N`` bodies in parallel (``failed`` (N,) int64)."""
    for b in prange(y0.shape[0]):
        failed[b] = rk4_body(
            y0[b],
            J[b],
            Ji[b],
            kind,
            par[b],
            t_out,
            nsub,
            oq[:, b, :],
            ow[:, b, :],
            cancel,
            done[b : b + 1],
        )


@njit(cache=True)
def midpoint_body(
    q, m, J, Ji, kind, par, t_out, nsub, coef, oq, om, cancel, done
):  # pragma: no cover
    """The implicit Lie-Poisson midpoint rule of ``simulate(method="midpoint")`` for one
    body under a built-in torque that depends on the attitude, ``w`` or ``t`` (kinds 2-6,
    the torque taken at the midpoint time, attitude and angular velocity ``W x``): the NumPy
    path's step (``integrators.midpoint._midpoint_step_numpy``), the same operations per
    body, compiled. ``q`` (4,) unit, ``m = J w`` (3,); ``coef`` the composition
    coefficients. Newton on the midpoint momentum ``x``, the torque taken at the midpoint
    attitude ``L o cay(b)``, ``b`` the Gibbs vector of half the step's rotation, its
    dependence on ``x`` left out of the Jacobian (so the convergence may be linear: the
    stopping rule predicts the next update from the last two). Returns ``(status, k,
    iterations)``: status 0 ok (iterations = the most any step took), 1 not converged,
    2 non-finite, 3 cancelled (``cancel[0]`` set by another thread on Ctrl-C, checked
    at every step; ``done[0]`` counts the intervals done), ``k`` the last
    output index reached."""
    q0, q1, q2, q3 = q[0], q[1], q[2], q[3]
    m0, m1, m2 = m[0], m[1], m[2]
    w00, w01, w02 = Ji[0, 0], Ji[0, 1], Ji[0, 2]
    w10, w11, w12 = Ji[1, 0], Ji[1, 1], Ji[1, 2]
    w20, w21, w22 = Ji[2, 0], Ji[2, 1], Ji[2, 2]
    oq[0, 0], oq[0, 1], oq[0, 2], oq[0, 3] = q0, q1, q2, q3
    om[0, 0], om[0, 1], om[0, 2] = m0, m1, m2
    nc = coef.shape[0]
    worst = 0
    # the first step's predictor uses the torque at the start, later ones the previous
    # step's midpoint torque (as the NumPy path); the torque at w = W m (kind 5 takes it)
    o0, o1, o2 = nh.matvec(w00, w01, w02, w10, w11, w12, w20, w21, w22, m0, m1, m2)
    t0, t1, t2 = _torque(t_out[0], q0, q1, q2, q3, o0, o1, o2, J, kind, par)
    for k in range(t_out.shape[0] - 1):
        done[0] = k
        hk = (t_out[k + 1] - t_out[k]) / nsub[k]
        tn = t_out[k]
        for s_ in range(nsub[k] * nc):
            if nh.cancelled(cancel):  # at every step: one interval may hold them all
                return 3, k, worst
            if s_ % nc == 0:  # the step's start time, as integrators._common._stages
                tn = t_out[k] + (s_ // nc) * hk
            h = hk * coef[s_ % nc]
            h2 = 0.5 * h
            tm = tn + h2  # the midpoint time (kind 6 takes it)
            tn += h
            o0, o1, o2 = nh.matvec(w00, w01, w02, w10, w11, w12, w20, w21, w22, m0, m1, m2)
            f0, f1, f2 = nh.euler_momentum_rate(m0, m1, m2, o0, o1, o2, t0, t1, t2)
            x0, x1, x2 = m0 + h2 * f0, m1 + h2 * f1, m2 + h2 * f2
            prev = np.inf
            it = 0
            while True:
                it += 1
                o0, o1, o2 = nh.matvec(w00, w01, w02, w10, w11, w12, w20, w21, w22, x0, x1, x2)
                a0, a1, a2 = h2 * o0, h2 * o1, h2 * o2
                d = 1.0 + math.sqrt(1.0 + a0 * a0 + a1 * a1 + a2 * a2)
                p0, p1, p2, p3 = nh.qmul_gibbs(q0, q1, q2, q3, a0 / d, a1 / d, a2 / d)
                p0, p1, p2, p3 = nh.qnormalize(p0, p1, p2, p3)
                t0, t1, t2 = _torque(tm, p0, p1, p2, p3, o0, o1, o2, J, kind, par)
                f0, f1, f2 = nh.euler_momentum_rate(x0, x1, x2, o0, o1, o2, t0, t1, t2)
                r0 = x0 - m0 - h2 * f0
                r1 = x1 - m1 - h2 * f1
                r2 = x2 - m2 - h2 * f2
                # Newton's Jacobian holds the torque (see the docstring)
                d0, d1, d2 = nh.midpoint_newton_step(
                    x0, x1, x2, o0, o1, o2, w00, w01, w02, w10, w11, w12, w20, w21, w22,
                    h2, r0, r1, r2,
                )  # fmt: skip
                x0 -= d0
                x1 -= d1
                x2 -= d2
                num = max(abs(d0), abs(d1), abs(d2))
                den = max(abs(x0), abs(x1), abs(x2))
                if not (num == num and den == den and den < np.inf):
                    return 2, k, it
                rel = 0.0 if num == 0.0 else num / (den if den != 0.0 else 1.0)
                stop = nh.midpoint_newton_done(rel, prev, it)
                if stop > 0:
                    break
                if stop < 0:
                    return 1, k, it
                prev = rel
            if it > worst:
                worst = it
            o0, o1, o2 = nh.matvec(w00, w01, w02, w10, w11, w12, w20, w21, w22, x0, x1, x2)
            a0, a1, a2 = h2 * o0, h2 * o1, h2 * o2
            # m+ = (I + a^)^-1 [(I - a^) m + h M*], q+ = L o cay(a)
            m0, m1, m2 = nh.midpoint_momentum(m0, m1, m2, a0, a1, a2, h, t0, t1, t2)
            p0, p1, p2, p3 = nh.qmul_gibbs(q0, q1, q2, q3, a0, a1, a2)
            q0, q1, q2, q3 = nh.qnormalize(p0, p1, p2, p3)
        if not (np.isfinite(q0 + q1 + q2 + q3) and np.isfinite(m0 + m1 + m2)):
            return 2, k, worst
        oq[k + 1, 0], oq[k + 1, 1], oq[k + 1, 2], oq[k + 1, 3] = q0, q1, q2, q3
        om[k + 1, 0], om[k + 1, 1], om[k + 1, 2] = m0, m1, m2
    return 0, t_out.shape[0] - 1, worst


@njit(cache=True, parallel=True)
def midpoint_batch(
    q, m, J, Ji, kind, par, t_out, nsub, coef, oq, om, res, cancel, done
):  # pragma: no cover
    """:func:`midpoint_body` for ``N`` bodies in parallel; ``res`` (N, 3) int64 receives
    each body's ``(status, k, iterations)``; ``done`` (N,) the intervals done per body."""
    for b in prange(q.shape[0]):
        res[b, 0], res[b, 1], res[b, 2] = midpoint_body(
            q[b], m[b], J[b], Ji[b], kind, par[b], t_out, nsub, coef, oq[:, b, :], om[:, b, :],
            cancel, done[b : b + 1],
        )  # fmt: skip
