"""Per-lane step control of the lane-blocked DOP853 (numba kernels, private).

``simulate(method="dop853")`` steps the bodies of a batch ``L`` at a time: the
generated kernels of :mod:`poinsot.dynamics._fused_stages` compute the stages, the
new state and the error norm of all ``L`` lanes in loops over the lanes, which
LLVM vectorises across bodies (structure of arrays: component ``c`` of lane
``l`` at ``W[offset + c * L + l]``). Each lane keeps its own time, step size,
accept/reject, error control, output index and counters, in rows of ``W`` too; the
control is written as loops over the lanes with selects instead of branches
(:func:`lane_prepare`, :func:`lane_control`, :func:`lane_accept`), so it vectorises like
the stages, and only the rare events run lane by lane (a body starting or ending,
outputs). Every lane runs exactly the operations of
:func:`poinsot.dynamics._fused.one_body`, so every body gets bit for bit the results of
``one_body`` whatever lane or block it runs in (hence also for any number of threads).
A lane whose body ends (done, failed or cancelled) takes the next body of its chunk; a
lane with no body left is idle (``h = 0``, its results ignored), and the chunk ends when
every lane is idle.

Work-array layout (float64 offsets): ``y`` (7 x L), the 16 stages ``K_s`` (7 x L
each, ``K_0 = f(y)``), ``y_new``, the dense-output coefficients ``F`` (7 x 7 x L),
``J`` and ``J^-1`` (9 x L, row-major), the torque parameters (``NPAR`` x L), the step
``h`` and the error norm ``err`` (L each), the stage argument ``z`` and value, then the
lane state (``S_*`` rows of L), the last of them the time of the stage being evaluated
(``S_TZ``, written before each evaluation for the torques that read it, kinds 5 and 6).
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
    _C,
    _CX,
    CANCELLED,
    DIAGONAL,
    GYROSTAT,
    KEPLER,
    MAX_FACTOR,
    MIN_FACTOR,
    NONFINITE,
    NPAR,
    OK,
    SAFETY,
    STEP_TOO_SMALL,
    TOO_MANY_STEPS,
    _err_pow,
    _put,
    _torque_s,
)

depends_on(__file__, nh, _fused, G)


class Kind(int):
    """A torque kind (with the inertia form, :data:`~poinsot.dynamics._fused.DIAGONAL`)
    that numba types as a compile-time constant (``Literal[int]``): the lane kernel is
    compiled, and cached, once per kind actually called, each with one right-hand side
    whose torque branch is folded away (so the loop over the lanes has no branch and
    vectorises). The lane kernel does not take a plain ``int`` kind."""


_borrow: Any
if NUMBA:
    from numba import types as _nbtypes
    from numba.extending import intrinsic, overload, typeof_impl

    @typeof_impl.register(Kind)
    def _typeof_kind(val: Kind, c: Any) -> Any:
        return _nbtypes.IntegerLiteral(int(val))

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
OFF_H = OFF_P + NPAR * L
OFF_ERR = OFF_H + L
OFF_Z = OFF_ERR + L
OFF_KOUT = OFF_Z + 7 * L
assert G.L == L, "run tools/gen_fused_lanes.py"

# The lane state: rows of ``W`` after the stage arrays (one base pointer for every loop
# over the lanes, so that LLVM vectorises them with constant offsets and no aliasing
# checks). Counters, flags and the body index are float64 rows too (exact below 2^53).
OFF_S = OFF_KOUT + 7 * L
S_T = OFF_S  # time of the lane's state
S_HABS = OFF_S + L  # |step| to try next (the attempt's own h once prepared)
S_MINSTEP = OFF_S + 2 * L  # 10 ulp(t), set at the start of every step
S_TNEW = OFF_S + 3 * L  # time at the end of the attempt
S_TOUT = OFF_S + 4 * L  # the next output time t_out[i_out]
S_BODY = OFF_S + 5 * L  # body index, -1 for an idle lane
S_STEPS = OFF_S + 6 * L  # accepted steps
S_REJ = OFF_S + 7 * L  # rejected steps
S_NFEV = OFF_S + 8 * L  # right-hand-side evaluations
S_IOUT = OFF_S + 9 * L  # outputs written
S_FRESH = OFF_S + 10 * L  # 1: the next attempt starts a new step
S_REJFLAG = OFF_S + 11 * L  # 1: an attempt of this step was rejected
S_ACC = OFF_S + 12 * L  # 1: the last attempt was accepted
S_DENSE = OFF_S + 13 * L  # 1: outputs inside the accepted step
S_READY = OFF_S + 14 * L  # 1: prepared for the next attempt
S_END = OFF_S + 15 * L  # the status that ends the lane's body, -1 if none
S_EVENT = OFF_S + 16 * L  # 1: the accepted step needs scalar work (outputs, non-finite)
S_TZ = OFF_S + 17 * L  # time of the stage evaluated next (kinds 5 and 6 only)
N_WORK = OFF_S + 18 * L

_bits: Any
_from_bits: Any
if NUMBA:
    from llvmlite import ir
    from numba.core import types

    @intrinsic
    def _bits_intrinsic(typingctx, x):  # pragma: no cover - compiled
        """The IEEE bits of a float64 as an int64 (a bitcast, vectorised by LLVM)."""

        def codegen(context, builder, sig, args):
            return builder.bitcast(args[0], ir.IntType(64))

        return types.int64(types.float64), codegen

    @intrinsic
    def _from_bits_intrinsic(typingctx, b):  # pragma: no cover - compiled
        """The float64 of IEEE bits ``b`` (int64)."""

        def codegen(context, builder, sig, args):
            return builder.bitcast(args[0], ir.DoubleType())

        return types.float64(types.int64), codegen

    _bits, _from_bits = _bits_intrinsic, _from_bits_intrinsic
else:

    def _bits_py(x: Any) -> Any:
        return np.float64(x).view(np.int64)

    def _from_bits_py(b: Any) -> Any:
        return np.int64(b).view(np.float64)

    _bits, _from_bits = _bits_py, _from_bits_py


@njit(cache=True, inline="always")
def _next_up(t):  # pragma: no cover
    """``np.nextafter(t, inf)`` for every float64 (NaN, infinities, zeros included), from
    the bits: no libm call, so that the loop over the lanes vectorises."""
    b = _bits(t)
    b = b + 1 if (t > 0.0) & (t != np.inf) else (b - 1 if t < 0.0 else b)
    return 5e-324 if t == 0.0 else _from_bits(b)


@njit(cache=True, inline="always")
def _stage_times(W, kind, c):  # pragma: no cover
    """``S_TZ = t + c h`` of every lane, the time of the stage about to be evaluated
    (``one_body``'s ``t + _C[s] * h``), for the torque kinds that read it."""
    if kind == KEPLER or kind == GYROSTAT:
        for l in range(L):
            W[S_TZ + l] = W[S_T + l] + c * W[OFF_H + l]


@njit(cache=True, inline="always")
def _end_times(W, kind):  # pragma: no cover
    """``S_TZ = t_new`` of every lane, the time of the FSAL stage (``one_body``'s)."""
    if kind == KEPLER or kind == GYROSTAT:
        for l in range(L):
            W[S_TZ + l] = W[S_TNEW + l]


@njit(cache=True, error_model="numpy")
def lane_first_steps(W, kind, t0, span, rtol, atol, max_step):  # pragma: no cover
    """Every lane's derivative ``f = K_0`` at its state ``y`` (time ``t0``) and its first
    step (into the ``h`` row): :func:`poinsot.dynamics._fused._initial_step`'s operations,
    in its order, lane by lane, vectorised across the lanes (the ``y``, ``J``, ``J^-1``
    and parameter rows of ``W`` loaded; the other rows are scratch here)."""
    for c in range(7):
        for l in range(L):
            W[OFF_Z + c * L + l] = W[OFF_Y + c * L + l]
    for l in range(L):
        W[S_TZ + l] = t0
    _rhs_lanes(W, kind)
    for l in range(L):
        a0 = 0.0
        a1 = 0.0
        for c in range(7):
            y = W[OFF_Y + c * L + l]
            f = W[OFF_KOUT + c * L + l]
            s = atol + abs(y) * rtol
            W[OFF_K + c * L + l] = f
            W[OFF_YN + c * L + l] = s
            x = y / s
            a0 += x * x
            x = f / s
            a1 += x * x
        d0 = np.sqrt(a0 / 7.0)
        d1 = np.sqrt(a1 / 7.0)
        h0 = 1e-6 if (d0 < 1e-5) | (d1 < 1e-5) else 0.01 * d0 / d1
        h0 = min(h0, span)
        W[OFF_H + l] = h0
        W[OFF_ERR + l] = d1
        W[S_TZ + l] = t0 + h0
        for c in range(7):
            W[OFF_Z + c * L + l] = W[OFF_Y + c * L + l] + h0 * W[OFF_K + c * L + l]
    _rhs_lanes(W, kind)
    for l in range(L):
        acc = 0.0
        for c in range(7):
            x = (W[OFF_KOUT + c * L + l] - W[OFF_K + c * L + l]) / W[OFF_YN + c * L + l]
            acc += x * x
        W[OFF_Z + l] = np.sqrt(acc / 7.0) / W[OFF_H + l]  # d2
    for l in range(L):  # libm's pow, a call per lane
        h0 = W[OFF_H + l]
        d1 = W[OFF_ERR + l]
        d2 = W[OFF_Z + l]
        if d1 <= 1e-15 and d2 <= 1e-15:
            h1 = max(1e-6, h0 * 1e-3)
        else:
            h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
        W[OFF_H + l] = min(100.0 * h0, h1, span, max_step)


@njit(cache=True, inline="always")
def _lane_body(W, l, b, y0, J, Ji, par):  # pragma: no cover
    """Body ``b``'s initial state, ``J``, ``J^-1`` and torque parameters into the rows of
    lane ``l``."""
    for c in range(7):
        W[OFF_Y + c * L + l] = y0[b, c]
    for r in range(3):
        for c in range(3):
            W[OFF_J + (3 * r + c) * L + l] = J[b, r, c]
            W[OFF_JI + (3 * r + c) * L + l] = Ji[b, r, c]
    for i in range(NPAR):
        W[OFF_P + i * L + l] = par[b, i]


@njit(cache=True)
def _first_steps(lo, hi, W, y0, J, Ji, kind, par, t0, span, rtol, atol, max_step, first):
    """``first[b - lo] = (f, h)`` of the bodies ``lo`` to ``hi - 1`` starting at time
    ``t0``: their derivatives and first steps, ``L`` bodies at a time
    (:func:`lane_first_steps`, in ``W``); a short last block repeats the last body."""
    for b0 in range(lo, hi, L):
        for l in range(L):
            _lane_body(W, l, min(b0 + l, hi - 1), y0, J, Ji, par)
        lane_first_steps(W, kind, t0, span, rtol, atol, max_step)
        for l in range(min(L, hi - b0)):
            for c in range(7):
                first[b0 - lo + l, c] = W[OFF_K + c * L + l]
            first[b0 - lo + l, 7] = W[OFF_H + l]


@njit(cache=True)
def _load(b, l, W, y0, J, Ji, par, t_out, first, oq, ow, stats, done):  # pragma: no cover
    """Start body ``b`` in lane ``l``: the first output, and ``f`` and the initial step
    from ``first`` (:func:`_first_steps`), as :func:`~poinsot.dynamics._fused.one_body`.
    False when the body is done already."""
    n_out = t_out.shape[0]
    t = t_out[0]
    _put(y0[b], oq[:, b, :], ow[:, b, :], 0)
    stats[b, 0] = 0
    stats[b, 1] = 0
    stats[b, 2] = 0
    stats[b, 3] = OK
    if n_out == 1:
        return False
    done[b] = 1
    _lane_body(W, l, b, y0, J, Ji, par)
    for c in range(7):
        W[OFF_K + c * L + l] = first[c]
    W[S_T + l] = t
    W[S_HABS + l] = first[7]
    W[S_TOUT + l] = t_out[1]
    W[S_BODY + l] = b
    W[S_STEPS + l] = 0.0
    W[S_REJ + l] = 0.0
    W[S_NFEV + l] = 2.0  # f and the initial step's evaluation
    W[S_IOUT + l] = 1.0
    W[S_FRESH + l] = 1.0
    W[S_REJFLAG + l] = 0.0
    W[S_READY + l] = 0.0
    return True


@njit(cache=True)
def _finish(l, status, W, t_out, oq, ow, stats):  # pragma: no cover
    """End the body of lane ``l`` with ``status``: NaN at the outputs not reached, its
    counters; the lane becomes idle."""
    b = int(W[S_BODY + l])
    for i in range(int(W[S_IOUT + l]), t_out.shape[0]):
        for c in range(4):
            oq[i, b, c] = np.nan
        for c in range(3):
            ow[i, b, c] = np.nan
    stats[b, 0] = int(W[S_STEPS + l])
    stats[b, 1] = int(W[S_REJ + l])
    stats[b, 2] = int(W[S_NFEV + l])
    stats[b, 3] = status
    W[S_BODY + l] = -1.0
    W[S_READY + l] = 0.0
    W[OFF_H + l] = 0.0


@njit(cache=True, error_model="numpy")
def lane_prepare(W, t_end, max_step, max_steps, cancel):  # pragma: no cover
    """The checks before a step attempt (those of a new step first: cancel, step count,
    finite state, then the step size against ``10 ulp(t)``) and the attempt's ``t_new``
    and ``h``, for every busy lane not yet prepared, as ``one_body`` runs them. A lane
    that passes is committed (``READY``); a lane that fails keeps its state and gets the
    status that ends its body in ``END``. Branch-free (selects), vectorised across the
    lanes. Returns ``(busy lanes, lanes that end)``."""
    n_busy = 0
    n_end = 0
    for l in range(L):
        busy = W[S_BODY + l] >= 0.0
        todo = busy & (W[S_READY + l] == 0.0)
        fresh = W[S_FRESH + l] != 0.0
        t = W[S_T + l]
        min_step = 10.0 * abs(_next_up(t) - t) if fresh else W[S_MINSTEP + l]
        h0 = W[S_HABS + l]
        hc = max_step if h0 > max_step else (min_step if h0 < min_step else h0)
        h_abs = hc if fresh else h0
        s = W[OFF_K + 4 * L + l] + W[OFF_K + 5 * L + l] + W[OFF_K + 6 * L + l]
        fin = np.isfinite(s + W[OFF_Y + 4 * L + l] + W[OFF_Y + 5 * L + l] + W[OFF_Y + 6 * L + l])
        st = NONFINITE if not fin else -1.0
        st = TOO_MANY_STEPS if W[S_STEPS + l] >= max_steps else st
        st = CANCELLED if cancel else st
        st = st if fresh else -1.0
        # ``not >=`` also catches a NaN step from a non-finite state
        st = STEP_TOO_SMALL if (st < 0.0) & (not h_abs >= min_step) else st
        ok = todo & (st < 0.0)
        end = todo & (st >= 0.0)
        t_new = t + h_abs
        t_new = t_end if t_new > t_end else t_new
        h = t_new - t
        W[S_MINSTEP + l] = min_step if ok else W[S_MINSTEP + l]
        W[S_HABS + l] = h if ok else h0
        W[S_TNEW + l] = t_new if ok else W[S_TNEW + l]
        W[OFF_H + l] = h if ok else W[OFF_H + l]
        W[S_REJFLAG + l] = 0.0 if ok & fresh else W[S_REJFLAG + l]
        W[S_FRESH + l] = 0.0 if ok else W[S_FRESH + l]
        W[S_READY + l] = 1.0 if ok else W[S_READY + l]
        W[S_END + l] = st if end else -1.0
        n_busy += 1 if busy else 0
        n_end += 1 if end else 0
    return n_busy, n_end


@njit(cache=True)
def lane_service(
    nxt, lo, hi, W, y0, J, Ji, par, t_out, first, oq, ow, stats, done
):  # fmt: skip  # pragma: no cover
    """End the bodies :func:`lane_prepare` found ending, and give every idle lane the next
    body of the chunk (``nxt``, while ``nxt < hi``; the chunk's ``first`` steps start at
    body ``lo``). Returns the new ``nxt``."""
    for l in range(L):
        if W[S_END + l] >= 0.0:
            _finish(l, int(W[S_END + l]), W, t_out, oq, ow, stats)
            W[S_END + l] = -1.0
        while W[S_BODY + l] < 0.0 and nxt < hi:
            b = nxt
            nxt += 1
            _load(b, l, W, y0, J, Ji, par, t_out, first[b - lo], oq, ow, stats, done)
    return nxt


@njit(cache=True, error_model="numpy")
def lane_control(W):  # pragma: no cover
    """Accept or reject the attempt of every busy lane and set its next step size, as
    ``one_body`` (selects, vectorised across the lanes). Returns
    the number of lanes with outputs inside their accepted step (dense output)."""
    n_dense = 0
    for l in range(L):
        busy = W[S_BODY + l] >= 0.0
        err = W[OFF_ERR + l]
        p = _err_pow(err)
        acc = err < 1.0
        fa = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, SAFETY * p)
        fa = min(1.0, fa) if W[S_REJFLAG + l] != 0.0 else fa
        fr = max(MIN_FACTOR, SAFETY * p) if np.isfinite(err) else MIN_FACTOR
        factor = fa if acc else fr
        a = busy & acc
        r = busy & (not acc)
        W[S_HABS + l] = W[S_HABS + l] * factor if busy else W[S_HABS + l]
        W[S_NFEV + l] += 12.0 if busy else 0.0
        W[S_STEPS + l] += 1.0 if a else 0.0
        W[S_REJ + l] += 1.0 if r else 0.0
        W[S_REJFLAG + l] = 1.0 if r else W[S_REJFLAG + l]
        W[S_ACC + l] = 1.0 if a else 0.0
        d = a & (W[S_TOUT + l] < W[S_TNEW + l])
        W[S_DENSE + l] = 1.0 if d else 0.0
        W[S_READY + l] = 0.0
        n_dense += 1 if d else 0
    return n_dense


@njit(cache=True)
def lane_dense_out(W, scratch, t_out, oq, ow, done):  # pragma: no cover
    """The outputs inside the accepted step of every lane that has some, from the dense
    output (:func:`_dense`'s coefficients ``F``, the state before the step)."""
    n_out = t_out.shape[0]
    tmp = scratch[0]
    for l in range(L):
        if W[S_DENSE + l] == 0.0:
            continue
        W[S_NFEV + l] += 3.0
        b = int(W[S_BODY + l])
        i_out = int(W[S_IOUT + l])
        t = W[S_T + l]
        t_new = W[S_TNEW + l]
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
        W[S_IOUT + l] = i_out
        W[S_TOUT + l] = t_out[i_out]  # t_new <= t_out[-1]: the last output is never inside
        done[b] = i_out


@njit(cache=True, error_model="numpy")
def lane_accept(W):  # pragma: no cover
    """Every accepted lane moves to its new state: ``q`` projected onto ``|q| = 1``
    (``f = K_12`` scaled with it, ``f`` being linear in ``q``), the new time. Selects,
    vectorised across the lanes. Returns the number of lanes that need
    :func:`lane_events` (an output at the new time, a non-finite state)."""
    ks = OFF_K + 12 * 7 * L
    n_event = 0
    for l in range(L):
        a = W[S_ACC + l] != 0.0
        n0 = W[OFF_YN + l]
        n1 = W[OFF_YN + L + l]
        n2 = W[OFF_YN + 2 * L + l]
        n3 = W[OFF_YN + 3 * L + l]
        s = 1.0 / np.sqrt(n0**2 + n1**2 + n2**2 + n3**2)
        v0, v1, v2, v3 = n0 * s, n1 * s, n2 * s, n3 * s
        v4, v5, v6 = W[OFF_YN + 4 * L + l], W[OFF_YN + 5 * L + l], W[OFF_YN + 6 * L + l]
        fin = (
            np.isfinite(v0) & np.isfinite(v1) & np.isfinite(v2) & np.isfinite(v3)
            & np.isfinite(v4) & np.isfinite(v5) & np.isfinite(v6)
        )  # fmt: skip
        W[OFF_Y + l] = v0 if a else W[OFF_Y + l]
        W[OFF_Y + L + l] = v1 if a else W[OFF_Y + L + l]
        W[OFF_Y + 2 * L + l] = v2 if a else W[OFF_Y + 2 * L + l]
        W[OFF_Y + 3 * L + l] = v3 if a else W[OFF_Y + 3 * L + l]
        W[OFF_Y + 4 * L + l] = v4 if a else W[OFF_Y + 4 * L + l]
        W[OFF_Y + 5 * L + l] = v5 if a else W[OFF_Y + 5 * L + l]
        W[OFF_Y + 6 * L + l] = v6 if a else W[OFF_Y + 6 * L + l]
        W[OFF_K + l] = W[ks + l] * s if a else W[OFF_K + l]
        W[OFF_K + L + l] = W[ks + L + l] * s if a else W[OFF_K + L + l]
        W[OFF_K + 2 * L + l] = W[ks + 2 * L + l] * s if a else W[OFF_K + 2 * L + l]
        W[OFF_K + 3 * L + l] = W[ks + 3 * L + l] * s if a else W[OFF_K + 3 * L + l]
        W[OFF_K + 4 * L + l] = W[ks + 4 * L + l] if a else W[OFF_K + 4 * L + l]
        W[OFF_K + 5 * L + l] = W[ks + 5 * L + l] if a else W[OFF_K + 5 * L + l]
        W[OFF_K + 6 * L + l] = W[ks + 6 * L + l] if a else W[OFF_K + 6 * L + l]
        W[S_T + l] = W[S_TNEW + l] if a else W[S_T + l]
        W[S_FRESH + l] = 1.0 if a else W[S_FRESH + l]
        e = a & ((not fin) | (W[S_TOUT + l] == W[S_TNEW + l]))
        W[S_EVENT + l] = 1.0 if e else 0.0
        n_event += 1 if e else 0
    return n_event


@njit(cache=True)
def lane_events(W, scratch, t_out, oq, ow, stats, done):  # pragma: no cover
    """The scalar end of an accepted step, lanes flagged by :func:`lane_accept`: a
    non-finite state ends the body; the outputs at the new time are written, and the body
    ends with its last output."""
    n_out = t_out.shape[0]
    tmp = scratch[0]
    for l in range(L):
        if W[S_EVENT + l] == 0.0:
            continue
        W[S_EVENT + l] = 0.0
        nonfinite = False
        for c in range(7):
            tmp[c] = W[OFF_Y + c * L + l]
            if not np.isfinite(tmp[c]):
                nonfinite = True
        if nonfinite:
            _finish(l, NONFINITE, W, t_out, oq, ow, stats)
            continue
        b = int(W[S_BODY + l])
        i_out = int(W[S_IOUT + l])
        t_new = W[S_T + l]
        while i_out < n_out and t_out[i_out] == t_new:
            _put(tmp, oq[:, b, :], ow[:, b, :], i_out)
            i_out += 1
        W[S_IOUT + l] = i_out
        if i_out >= n_out:
            _finish(l, OK, W, t_out, oq, ow, stats)
        else:
            W[S_TOUT + l] = t_out[i_out]
            done[b] = i_out


# ---------------------------------------------------------------------------
# The stages, every lane at once (loops over the lanes: vectorised by LLVM)
# ---------------------------------------------------------------------------


@njit(cache=True, inline="always", error_model="numpy")
def _rhs_lane(W, l, kind):  # pragma: no cover
    """``K_out = f(z)`` of lane ``l``: :func:`poinsot.dynamics._fused._rhs`'s formulas (its
    torque :func:`~poinsot.dynamics._fused._torque_s`, its diagonal form for ``kind`` plus
    ``DIAGONAL``) on the lane's parameters."""
    q0, q1, q2, q3 = W[OFF_Z + l], W[OFF_Z + L + l], W[OFF_Z + 2 * L + l], W[OFF_Z + 3 * L + l]
    w0, w1, w2 = W[OFF_Z + 4 * L + l], W[OFF_Z + 5 * L + l], W[OFF_Z + 6 * L + l]
    a00, a01, a02 = W[OFF_J + l], W[OFF_J + L + l], W[OFF_J + 2 * L + l]
    a10, a11, a12 = W[OFF_J + 3 * L + l], W[OFF_J + 4 * L + l], W[OFF_J + 5 * L + l]
    a20, a21, a22 = W[OFF_J + 6 * L + l], W[OFF_J + 7 * L + l], W[OFF_J + 8 * L + l]
    i00, i01, i02 = W[OFF_JI + l], W[OFF_JI + L + l], W[OFF_JI + 2 * L + l]
    i10, i11, i12 = W[OFF_JI + 3 * L + l], W[OFF_JI + 4 * L + l], W[OFF_JI + 5 * L + l]
    i20, i21, i22 = W[OFF_JI + 6 * L + l], W[OFF_JI + 7 * L + l], W[OFF_JI + 8 * L + l]
    p0, p1, p2, p3 = W[OFF_P + l], W[OFF_P + L + l], W[OFF_P + 2 * L + l], W[OFF_P + 3 * L + l]
    p4, p5 = W[OFF_P + 4 * L + l], W[OFF_P + 5 * L + l]
    p6, p7 = W[OFF_P + 6 * L + l], W[OFF_P + 7 * L + l]
    d0, d1, d2, d3 = nh.qmul(q0, q1, q2, q3, 0.0, w0, w1, w2)
    diagonal = kind >= DIAGONAL
    if diagonal:
        k0, k1, k2 = a00 * w0, a11 * w1, a22 * w2
    else:
        k0, k1, k2 = nh.matvec(a00, a01, a02, a10, a11, a12, a20, a21, a22, w0, w1, w2)
    t0, t1, t2 = _torque_s(
        W[S_TZ + l], q0, q1, q2, q3, w0, w1, w2, a00, a01, a02, a10, a11, a12, a20, a21,
        a22, kind - DIAGONAL if diagonal else kind, p0, p1, p2, p3, p4, p5, p6, p7,
    )  # fmt: skip
    m0, m1, m2 = nh.euler_momentum_rate(k0, k1, k2, w0, w1, w2, t0, t1, t2)
    if diagonal:
        f4, f5, f6 = i00 * m0, i11 * m1, i22 * m2
    else:
        f4, f5, f6 = nh.matvec(i00, i01, i02, i10, i11, i12, i20, i21, i22, m0, m1, m2)
    W[OFF_KOUT + l] = 0.5 * d0
    W[OFF_KOUT + L + l] = 0.5 * d1
    W[OFF_KOUT + 2 * L + l] = 0.5 * d2
    W[OFF_KOUT + 3 * L + l] = 0.5 * d3
    W[OFF_KOUT + 4 * L + l] = f4
    W[OFF_KOUT + 5 * L + l] = f5
    W[OFF_KOUT + 6 * L + l] = f6


def _rhs_kinds(W, kind):  # pragma: no cover
    """``K_out = f(z)`` for every lane (the plain-Python form; compiled: the overload)."""
    for l in range(L):
        _rhs_lane(W, l, kind)


if NUMBA:

    @overload(_rhs_kinds, prefer_literal=True, jit_options={"error_model": "numpy"})
    def _rhs_kinds_compiled(W, kind):  # pragma: no cover - compiled
        """One loop over the lanes with the right-hand side of ``kind``, a :class:`Kind`
        (``Literal[int]``): its torque branch folded away."""
        if not isinstance(kind, _nbtypes.IntegerLiteral):
            raise TypeError("the lane kernel takes kind as Kind(kind), a compile-time constant")

        def one(W, kind):
            for l in range(L):
                _rhs_lane(W, l, kind)

        return one


@njit(cache=True, error_model="numpy")
def _rhs_lanes(W, kind):  # pragma: no cover
    """``K_out = f(z)`` for every lane (:func:`_rhs_kinds`). Compiled per :class:`Kind`:
    a first call compiles the right-hand side of its kind only (cold, about 2 s; the
    whole lane kernel about 20 s, where the nine forms compiled at once took 35 s)."""
    _rhs_kinds(W, kind)


@njit(cache=True, error_model="numpy")
def _attempt(W, kind, rtol, atol):  # pragma: no cover
    """One step attempt of every lane: stages 1-11, ``y_new``, the FSAL stage 12 and the
    error norm ``err`` (``one_body``'s operations, lane by lane)."""
    G._stage1(W)
    _stage_times(W, kind, _C[1])
    _rhs_lanes(W, kind)
    G._stage2(W)
    _stage_times(W, kind, _C[2])
    _rhs_lanes(W, kind)
    G._stage3(W)
    _stage_times(W, kind, _C[3])
    _rhs_lanes(W, kind)
    G._stage4(W)
    _stage_times(W, kind, _C[4])
    _rhs_lanes(W, kind)
    G._stage5(W)
    _stage_times(W, kind, _C[5])
    _rhs_lanes(W, kind)
    G._stage6(W)
    _stage_times(W, kind, _C[6])
    _rhs_lanes(W, kind)
    G._stage7(W)
    _stage_times(W, kind, _C[7])
    _rhs_lanes(W, kind)
    G._stage8(W)
    _stage_times(W, kind, _C[8])
    _rhs_lanes(W, kind)
    G._stage9(W)
    _stage_times(W, kind, _C[9])
    _rhs_lanes(W, kind)
    G._stage10(W)
    _stage_times(W, kind, _C[10])
    _rhs_lanes(W, kind)
    G._stage11(W)
    _stage_times(W, kind, _C[11])
    _rhs_lanes(W, kind)
    G._ynew(W)
    _end_times(W, kind)
    _rhs_lanes(W, kind)
    G._err(W, rtol, atol)


@njit(cache=True, error_model="numpy")
def _dense(W, kind):  # pragma: no cover
    """The 7th-order dense output of the step just taken, every lane: the extra stages
    13-15 and the interpolant's coefficients ``F``."""
    G._stage13(W)
    _stage_times(W, kind, _CX[0])
    _rhs_lanes(W, kind)
    G._stage14(W)
    _stage_times(W, kind, _CX[1])
    _rhs_lanes(W, kind)
    G._stage15(W)
    _stage_times(W, kind, _CX[2])
    _rhs_lanes(W, kind)
    G._fcoef(W)


@njit(cache=True)
def _chunk(
    lo, hi, y0, J, Ji, kind, par, t_out, rtol, atol, max_step, max_steps, oq, ow, stats,
    cancel, done,
):  # fmt: skip  # pragma: no cover
    """Bodies ``lo`` to ``hi - 1`` through the ``L`` lanes. Every phase but the rare
    events is one loop over the lanes (:func:`lane_prepare`, :func:`_attempt`,
    :func:`lane_control`, :func:`lane_accept`); a lane whose body ends takes the next one
    (:func:`lane_service`); the chunk ends when every lane is idle."""
    W = np.empty(N_WORK)
    scratch = np.empty((1, 7))
    # the caller holds the arguments for the whole call: no reference counting on them
    y0, J, Ji, par, t_out = _borrow(y0), _borrow(J), _borrow(Ji), _borrow(par), _borrow(t_out)
    oq, ow, stats = _borrow(oq), _borrow(ow), _borrow(stats)
    cancel, done = _borrow(cancel), _borrow(done)
    t_end = t_out[t_out.shape[0] - 1]
    # every body's derivative and first step up front, L bodies at a time: one at a time,
    # as the lanes free up, they took 150-180 ns per body (a third of a one-step body)
    first = np.empty((hi - lo, 8))
    _first_steps(lo, hi, W, y0, J, Ji, kind, par, t_out[0], t_end - t_out[0], rtol, atol,
                 max_step, first)  # fmt: skip
    W[:] = 0.0  # (the first steps used it as scratch)
    W[S_BODY : S_BODY + L] = -1.0
    W[S_END : S_END + L] = -1.0
    nxt = lo
    while True:
        n_busy, n_end = lane_prepare(W, t_end, max_step, max_steps, nh.cancelled(cancel))
        while n_end > 0 or (n_busy < L and nxt < hi):
            nxt = lane_service(nxt, lo, hi, W, y0, J, Ji, par, t_out, first, oq, ow,
                               stats, done)  # fmt: skip
            n_busy, n_end = lane_prepare(W, t_end, max_step, max_steps, nh.cancelled(cancel))
        if n_busy == 0:
            break
        _attempt(W, kind, rtol, atol)
        if lane_control(W) > 0:
            _dense(W, kind)
            lane_dense_out(W, scratch, t_out, oq, ow, done)
        if lane_accept(W) > 0:
            lane_events(W, scratch, t_out, oq, ow, stats, done)


def compiled(kind: int) -> Any:
    """The test of :func:`poinsot._jit.ready` for the lane kernel of ``kind``: whether a
    compilation's argument types are those of that kind (``Literal[int](kind)``)."""

    def match(sig: tuple[Any, ...]) -> bool:
        return len(sig) > 3 and getattr(sig[3], "literal_value", None) == kind

    return match


@njit(cache=True, parallel=True, nogil=True)
def integrate_batch(
    y0, J, Ji, kind, par, t_out, rtol, atol, max_step, max_steps, oq, ow, stats, cancel, done
):  # pragma: no cover
    """:func:`poinsot.dynamics._fused.integrate_batch` (same arguments, ``kind`` as a
    :class:`Kind`; same results bit for bit), in chunks of bodies stepped ``L`` at a
    time. Compiled per kind."""
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
