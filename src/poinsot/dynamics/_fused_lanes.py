"""Per-lane step control of the lane-blocked DOP853 (numba kernels, private).

``simulate(method="dop853")`` steps the bodies of a batch ``L`` at a time: the
generated kernels of :mod:`poinsot.dynamics._fused_lanes` compute the stages, the
new state and the error norm of all ``L`` lanes in loops over the lanes, which
LLVM vectorises across bodies (structure of arrays: component ``c`` of lane
``l`` at ``W[offset + c * L + l]``). Each lane keeps its own time, step size,
accept/reject, error control, output index and counters; the functions here run
that control lane by lane, exactly as :func:`poinsot.dynamics._fused.one_body`
runs it for one body, so that every body gets bit for bit the results of
``one_body`` whatever lane or block it runs in (hence also for any number of
threads). A lane whose body ends (done, failed or cancelled) takes the next body
of its chunk; a lane with no body left is idle (``h = 0``, its results ignored),
and the chunk ends when every lane is idle.

Work-array layout (float64 offsets): ``y`` (7 x L), the 16 stages ``K_s`` (7 x L
each, ``K_0 = f(y)``), ``y_new``, the dense-output coefficients ``F`` (7 x 7 x L),
``J`` and ``J^-1`` (9 x L, row-major), the torque parameters (4 x L), the step
``h`` and the error norm ``err`` (L each).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .. import _numba_helpers as nh
from .._jit import NUMBA, njit, prange
from .._numba_cache import depends_on
from . import _fused
from . import _fused_stages as G
from ._fused import (
    CANCELLED,
    EXPONENT,
    MAX_FACTOR,
    MIN_FACTOR,
    NONFINITE,
    OK,
    SAFETY,
    STEP_TOO_SMALL,
    TOO_MANY_STEPS,
    _initial_step,
    _put,
    _rhs,
    _torque_s,
)

depends_on(__file__, nh, _fused, G)

_borrow: Any
if NUMBA:
    from numba.extending import intrinsic

    @intrinsic
    def _borrow_intrinsic(typingctx, arr):  # pragma: no cover - compiled
        """A view of ``arr`` without its meminfo: no reference counting on it.

        numba increments and decrements an array's reference count (atomic operations on
        its meminfo) around every call that passes it; on the arrays every thread shares
        (the bodies, the outputs) the two cores then fight over one cache line on each
        call of the per-lane control. Only for arrays that the caller keeps alive for the
        whole call (the kernel's arguments)."""

        def codegen(context, builder, sig, args):
            ary = context.make_array(sig.args[0])(context, builder, value=args[0])
            out = context.make_array(sig.return_type)(context, builder)
            context.populate_array(
                out, data=ary.data, shape=ary.shape, strides=ary.strides,
                itemsize=ary.itemsize, meminfo=None,
            )  # fmt: skip
            return out._getvalue()

        return arr(arr), codegen

    _borrow = _borrow_intrinsic
else:  # the lane kernel runs compiled only; the NumPy executor steps one body at a time

    def _identity(arr: Any) -> Any:
        return arr

    _borrow = _identity


#: Lanes per block: 8 float64, two AVX2 registers (or one AVX-512) per operation. Two
#: independent registers per operation let the core overlap the long dependency chains of
#: the stage sums and the right-hand side; measured against 4 lanes on a 2-core AMD EPYC
#: (AVX2): 20-25% less time per evaluation, 16 lanes no better than 8.
L = 8
#: Most bodies per chunk, the unit of ``prange`` (a lane takes the next body of its chunk).
CHUNK = 256

OFF_Y = 0
OFF_K = 7 * L
OFF_YN = OFF_K + 16 * 7 * L
OFF_F = OFF_YN + 7 * L
OFF_J = OFF_F + 7 * 7 * L
OFF_JI = OFF_J + 9 * L
OFF_P = OFF_JI + 9 * L
OFF_H = OFF_P + 4 * L
OFF_ERR = OFF_H + L
OFF_Z = OFF_ERR + L
OFF_KOUT = OFF_Z + 7 * L
N_WORK = OFF_KOUT + 7 * L
assert G.L == L, "run tools/gen_fused_lanes.py"

# rows of the lane state: floats ``ls`` and integers ``li``
T, HABS, MINSTEP, TNEW = 0, 1, 2, 3
N_LS = 4
BODY, STEPS, REJ, NFEV, IOUT, FRESH, REJFLAG, ACC, DENSE = 0, 1, 2, 3, 4, 5, 6, 7, 8
N_LI = 9


@njit(cache=True)
def _load(
    b, l, W, ls, li, scratch, y0, J, Ji, kind, par, t_out, rtol, atol, max_step, oq, ow, stats
):  # pragma: no cover
    """Start body ``b`` in lane ``l``: the first output, ``f`` and the initial step, as
    :func:`~poinsot.dynamics._fused.one_body`. False when the body is done already."""
    n_out = t_out.shape[0]
    y = scratch[0]
    f = scratch[1]
    tmp = scratch[2]
    k1 = scratch[3]
    scale = scratch[4]
    for i in range(7):
        y[i] = y0[b, i]
    t = t_out[0]
    t_end = t_out[n_out - 1]
    _put(y, oq[:, b, :], ow[:, b, :], 0)
    stats[b, 0] = 0
    stats[b, 1] = 0
    stats[b, 2] = 0
    stats[b, 3] = OK
    if n_out == 1:
        return False
    _rhs(t, y, J[b], Ji[b], kind, par[b], f)
    nfev = 1
    h_abs = _initial_step(t, y, f, t_end - t, rtol, atol, max_step, J[b], Ji[b], kind,
                          par[b], tmp, k1, scale)  # fmt: skip
    nfev += 1
    for c in range(7):
        W[OFF_Y + c * L + l] = y[c]
        W[OFF_K + c * L + l] = f[c]
    for r in range(3):
        for c in range(3):
            W[OFF_J + (3 * r + c) * L + l] = J[b, r, c]
            W[OFF_JI + (3 * r + c) * L + l] = Ji[b, r, c]
    for i in range(4):
        W[OFF_P + i * L + l] = par[b, i]
    ls[T, l] = t
    ls[HABS, l] = h_abs
    li[BODY, l] = b
    li[STEPS, l] = 0
    li[REJ, l] = 0
    li[NFEV, l] = nfev
    li[IOUT, l] = 1
    li[FRESH, l] = 1
    li[REJFLAG, l] = 0
    li[ACC, l] = 0
    li[DENSE, l] = 0
    return True


@njit(cache=True)
def _start(l, W, ls, li, t_out, max_step, max_steps, cancel, done):  # pragma: no cover
    """The checks before a step attempt of lane ``l`` (those of a new step first), then
    its ``t_new`` and ``h``. Returns -1 to go on, else the status that ends the body."""
    if li[FRESH, l] != 0:
        if cancel[0] != 0:
            return CANCELLED
        done[li[BODY, l]] = li[IOUT, l]
        if li[STEPS, l] >= max_steps:
            return TOO_MANY_STEPS
        t = ls[T, l]
        min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
        ls[MINSTEP, l] = min_step
        h_abs = ls[HABS, l]
        if h_abs > max_step:
            h_abs = max_step
        elif h_abs < min_step:
            h_abs = min_step
        ls[HABS, l] = h_abs
        s = W[OFF_K + 4 * L + l] + W[OFF_K + 5 * L + l] + W[OFF_K + 6 * L + l]
        if not np.isfinite(s + W[OFF_Y + 4 * L + l] + W[OFF_Y + 5 * L + l] + W[OFF_Y + 6 * L + l]):
            return NONFINITE
        li[REJFLAG, l] = 0
        li[FRESH, l] = 0
    h_abs = ls[HABS, l]
    if not h_abs >= ls[MINSTEP, l]:  # also catches a NaN step from a non-finite state
        return STEP_TOO_SMALL
    t = ls[T, l]
    t_new = t + h_abs
    t_end = t_out[t_out.shape[0] - 1]
    if t_new > t_end:
        t_new = t_end
    h = t_new - t
    ls[HABS, l] = h
    ls[TNEW, l] = t_new
    W[OFF_H + l] = h
    return -1


@njit(cache=True)
def _finish(l, status, W, li, t_out, oq, ow, stats):  # pragma: no cover
    """End the body of lane ``l`` with ``status``: NaN at the outputs not reached, its
    counters; the lane becomes idle."""
    b = li[BODY, l]
    for i in range(li[IOUT, l], t_out.shape[0]):
        for c in range(4):
            oq[i, b, c] = np.nan
        for c in range(3):
            ow[i, b, c] = np.nan
    stats[b, 0] = li[STEPS, l]
    stats[b, 1] = li[REJ, l]
    stats[b, 2] = li[NFEV, l]
    stats[b, 3] = status
    li[BODY, l] = -1
    W[OFF_H + l] = 0.0


@njit(cache=True)
def lane_fill(
    nxt, hi, W, ls, li, scratch, y0, J, Ji, kind, par, t_out, rtol, atol, max_step, max_steps,
    oq, ow, stats, cancel, done,
):  # fmt: skip  # pragma: no cover
    """Prepare every lane for the next attempt: a lane without a body takes body ``nxt``
    (while ``nxt < hi``), a body that ends before its attempt is finished and replaced.
    Returns ``(nxt, number of lanes with a body)``."""
    active = 0
    for l in range(L):
        while True:
            if li[BODY, l] < 0:
                if nxt >= hi:
                    break
                b = nxt
                nxt += 1
                if not _load(
                    b, l, W, ls, li, scratch, y0, J, Ji, kind, par, t_out, rtol, atol,
                    max_step, oq, ow, stats,
                ):  # fmt: skip
                    continue
            st = _start(l, W, ls, li, t_out, max_step, max_steps, cancel, done)
            if st < 0:
                active += 1
                break
            _finish(l, st, W, li, t_out, oq, ow, stats)
    return nxt, active


@njit(cache=True)
def lane_control(W, ls, li, t_out):  # pragma: no cover
    """Accept or reject the attempt of every busy lane and set its next step size, as
    ``one_body``. Returns whether a lane needs dense output in its accepted step."""
    any_dense = False
    for l in range(L):
        if li[BODY, l] < 0:
            continue
        err = W[OFF_ERR + l]
        li[NFEV, l] += 12
        h_abs = ls[HABS, l]
        if err < 1.0:
            if err == 0.0:
                factor = MAX_FACTOR
            else:
                factor = min(MAX_FACTOR, SAFETY * err**EXPONENT)
            if li[REJFLAG, l] != 0:
                factor = min(1.0, factor)
            ls[HABS, l] = h_abs * factor
            li[STEPS, l] += 1
            li[ACC, l] = 1
            dense = t_out[li[IOUT, l]] < ls[TNEW, l]
            li[DENSE, l] = 1 if dense else 0
            any_dense = any_dense or dense
        else:
            if not np.isfinite(err):
                factor = MIN_FACTOR
            else:
                factor = max(MIN_FACTOR, SAFETY * err**EXPONENT)
            ls[HABS, l] = h_abs * factor
            li[REJFLAG, l] = 1
            li[REJ, l] += 1
            li[ACC, l] = 0
            li[DENSE, l] = 0
    return any_dense


@njit(cache=True)
def lane_accept(W, ls, li, scratch, t_out, oq, ow, stats):  # pragma: no cover
    """For every lane whose attempt was accepted: the dense outputs inside the step, the
    projection of ``q`` onto ``|q| = 1`` (``f`` scaled with it), the outputs at the new
    time; the body ends when its last output is written or its state is not finite."""
    n_out = t_out.shape[0]
    tmp = scratch[0]
    for l in range(L):
        if li[BODY, l] < 0 or li[ACC, l] == 0:
            continue
        li[ACC, l] = 0
        b = li[BODY, l]
        i_out = li[IOUT, l]
        t = ls[T, l]
        t_new = ls[TNEW, l]
        if li[DENSE, l] != 0:
            li[NFEV, l] += 3
            h = W[OFF_H + l]
            while i_out < n_out and t_out[i_out] < t_new:
                x = (t_out[i_out] - t) / h
                for c in range(7):
                    v = 0.0
                    for i in range(7):
                        v += W[OFF_F + ((6 - i) * 7 + c) * L + l]
                        if i % 2 == 0:
                            v *= x
                        else:
                            v *= 1.0 - x
                    tmp[c] = v + W[OFF_Y + c * L + l]
                _put(tmp, oq[:, b, :], ow[:, b, :], i_out)
                i_out += 1
        n0 = W[OFF_YN + l]
        n1 = W[OFF_YN + L + l]
        n2 = W[OFF_YN + 2 * L + l]
        n3 = W[OFF_YN + 3 * L + l]
        s = 1.0 / np.sqrt(n0**2 + n1**2 + n2**2 + n3**2)
        ks = OFF_K + 12 * 7 * L
        nonfinite = False
        for c in range(7):
            v = W[OFF_YN + c * L + l]
            fc = W[ks + c * L + l]
            if c < 4:
                v *= s
                fc *= s
            W[OFF_Y + c * L + l] = v
            W[OFF_K + c * L + l] = fc
            tmp[c] = v
            if not np.isfinite(v):
                nonfinite = True
        ls[T, l] = t_new
        li[IOUT, l] = i_out
        if nonfinite:
            _finish(l, NONFINITE, W, li, t_out, oq, ow, stats)
            continue
        while i_out < n_out and t_out[i_out] == t_new:
            _put(tmp, oq[:, b, :], ow[:, b, :], i_out)
            i_out += 1
        li[IOUT, l] = i_out
        li[FRESH, l] = 1
        if i_out >= n_out:
            _finish(l, OK, W, li, t_out, oq, ow, stats)


# ---------------------------------------------------------------------------
# The stages, every lane at once (loops over the lanes: vectorised by LLVM)
# ---------------------------------------------------------------------------


@njit(cache=True, inline="always", error_model="numpy")
def _rhs_lane(W, l, kind):  # pragma: no cover
    """``K_out = f(z)`` of lane ``l``: :func:`poinsot.dynamics._fused._rhs`'s formulas (its
    torque :func:`~poinsot.dynamics._fused._torque_s`) on the lane's parameters."""
    q0, q1, q2, q3 = W[OFF_Z + l], W[OFF_Z + L + l], W[OFF_Z + 2 * L + l], W[OFF_Z + 3 * L + l]
    w0, w1, w2 = W[OFF_Z + 4 * L + l], W[OFF_Z + 5 * L + l], W[OFF_Z + 6 * L + l]
    a00, a01, a02 = W[OFF_J + l], W[OFF_J + L + l], W[OFF_J + 2 * L + l]
    a10, a11, a12 = W[OFF_J + 3 * L + l], W[OFF_J + 4 * L + l], W[OFF_J + 5 * L + l]
    a20, a21, a22 = W[OFF_J + 6 * L + l], W[OFF_J + 7 * L + l], W[OFF_J + 8 * L + l]
    i00, i01, i02 = W[OFF_JI + l], W[OFF_JI + L + l], W[OFF_JI + 2 * L + l]
    i10, i11, i12 = W[OFF_JI + 3 * L + l], W[OFF_JI + 4 * L + l], W[OFF_JI + 5 * L + l]
    i20, i21, i22 = W[OFF_JI + 6 * L + l], W[OFF_JI + 7 * L + l], W[OFF_JI + 8 * L + l]
    p0, p1, p2, p3 = W[OFF_P + l], W[OFF_P + L + l], W[OFF_P + 2 * L + l], W[OFF_P + 3 * L + l]
    d0, d1, d2, d3 = nh.qmul(q0, q1, q2, q3, 0.0, w0, w1, w2)
    k0, k1, k2 = nh.matvec(a00, a01, a02, a10, a11, a12, a20, a21, a22, w0, w1, w2)
    t0, t1, t2 = _torque_s(
        q0, q1, q2, q3, a00, a01, a02, a10, a11, a12, a20, a21, a22, kind, p0, p1, p2, p3
    )
    m0, m1, m2 = nh.euler_momentum_rate(k0, k1, k2, w0, w1, w2, t0, t1, t2)
    f4, f5, f6 = nh.matvec(i00, i01, i02, i10, i11, i12, i20, i21, i22, m0, m1, m2)
    W[OFF_KOUT + l] = 0.5 * d0
    W[OFF_KOUT + L + l] = 0.5 * d1
    W[OFF_KOUT + 2 * L + l] = 0.5 * d2
    W[OFF_KOUT + 3 * L + l] = 0.5 * d3
    W[OFF_KOUT + 4 * L + l] = f4
    W[OFF_KOUT + 5 * L + l] = f5
    W[OFF_KOUT + 6 * L + l] = f6


@njit(cache=True, error_model="numpy")
def _rhs_lanes(W, kind):  # pragma: no cover
    """``K_out = f(z)`` for every lane; one loop per torque kind (the kind a constant in
    each, so that the loop body has no branch and vectorises)."""
    if kind == 0:
        for l in range(L):
            _rhs_lane(W, l, 0)
    elif kind == 1:
        for l in range(L):
            _rhs_lane(W, l, 1)
    elif kind == 2:
        for l in range(L):
            _rhs_lane(W, l, 2)
    elif kind == 3:
        for l in range(L):
            _rhs_lane(W, l, 3)
    else:
        for l in range(L):
            _rhs_lane(W, l, 4)


@njit(cache=True, error_model="numpy")
def _attempt(W, kind, rtol, atol):  # pragma: no cover
    """One step attempt of every lane: stages 1-11, ``y_new``, the FSAL stage 12 and the
    error norm ``err`` (``one_body``'s operations, lane by lane)."""
    G._stage1(W)
    _rhs_lanes(W, kind)
    G._stage2(W)
    _rhs_lanes(W, kind)
    G._stage3(W)
    _rhs_lanes(W, kind)
    G._stage4(W)
    _rhs_lanes(W, kind)
    G._stage5(W)
    _rhs_lanes(W, kind)
    G._stage6(W)
    _rhs_lanes(W, kind)
    G._stage7(W)
    _rhs_lanes(W, kind)
    G._stage8(W)
    _rhs_lanes(W, kind)
    G._stage9(W)
    _rhs_lanes(W, kind)
    G._stage10(W)
    _rhs_lanes(W, kind)
    G._stage11(W)
    _rhs_lanes(W, kind)
    G._ynew(W)
    _rhs_lanes(W, kind)
    G._err(W, rtol, atol)


@njit(cache=True, error_model="numpy")
def _dense(W, kind):  # pragma: no cover
    """The 7th-order dense output of the step just taken, every lane: the extra stages
    13-15 and the interpolant's coefficients ``F``."""
    G._stage13(W)
    _rhs_lanes(W, kind)
    G._stage14(W)
    _rhs_lanes(W, kind)
    G._stage15(W)
    _rhs_lanes(W, kind)
    G._fcoef(W)


@njit(cache=True)
def _chunk(
    lo, hi, y0, J, Ji, kind, par, t_out, rtol, atol, max_step, max_steps, oq, ow, stats,
    cancel, done,
):  # fmt: skip  # pragma: no cover
    """Bodies ``lo`` to ``hi - 1`` through the ``L`` lanes: a lane whose body ends takes
    the next one (:func:`lane_fill`); the chunk ends when every lane is idle."""
    W = np.zeros(N_WORK)
    ls = np.zeros((N_LS, L))
    li = np.zeros((N_LI, L), dtype=np.int64)
    li[BODY, :] = -1
    scratch = np.empty((5, 7))
    # the caller holds the arguments for the whole call: no reference counting on them
    y0, J, Ji, par, t_out = _borrow(y0), _borrow(J), _borrow(Ji), _borrow(par), _borrow(t_out)
    oq, ow, stats = _borrow(oq), _borrow(ow), _borrow(stats)
    cancel, done = _borrow(cancel), _borrow(done)
    nxt = lo
    while True:
        nxt, active = lane_fill(
            nxt, hi, W, ls, li, scratch, y0, J, Ji, kind, par, t_out, rtol, atol, max_step,
            max_steps, oq, ow, stats, cancel, done,
        )  # fmt: skip
        if active == 0:
            break
        _attempt(W, kind, rtol, atol)
        if lane_control(W, ls, li, t_out):
            _dense(W, kind)
        lane_accept(W, ls, li, scratch, t_out, oq, ow, stats)


@njit(cache=True, parallel=True, nogil=True)
def integrate_batch(
    y0, J, Ji, kind, par, t_out, rtol, atol, max_step, max_steps, oq, ow, stats, cancel, done
):  # pragma: no cover
    """:func:`poinsot.dynamics._fused.integrate_batch` (same arguments, same results bit
    for bit), in chunks of bodies stepped ``L`` at a time."""
    n = y0.shape[0]
    # at least 16 chunks (of 4 L to CHUNK bodies) to share among the threads; a lane idles
    # only at the end of its chunk. A body's results do not depend on its lane or chunk.
    # (numba's get_num_threads() here would make the kernel uncachable: a ctypes pointer)
    size = min(CHUNK, max(4 * L, -(-n // 16)))
    for c in prange((n + size - 1) // size):
        _chunk(
            c * size, min(n, (c + 1) * size), y0, J, Ji, kind, par, t_out, rtol, atol,
            max_step, max_steps, oq, ow, stats, cancel, done,
        )  # fmt: skip
