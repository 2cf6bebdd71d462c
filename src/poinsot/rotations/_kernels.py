"""Compiled kernels: each quaternion formula of theory §1-§3, from :mod:`._scalar`.

The formulas themselves are the plain-Python scalar functions of
:mod:`poinsot.rotations._scalar` (also the short path for one rotation), compiled
here with ``inline="always"``; this file's on-disk cache is stamped with that file
(:func:`poinsot._numba_cache.depends_on`). Two kinds of kernels use them:

* ``guvectorize`` kernels that broadcast over leading dimensions like NumPy ufuncs
  (any shapes; used for small batches and broadcasting inputs);
* ``*_flat`` loops over contiguous ``(N, k)`` arrays compiled with
  ``parallel=True``: for batches of at least :data:`PARALLEL_MIN_SIZE` rotations
  the wrappers in the representation modules call these, which split the loop
  over numba's threads (``NUMBA_NUM_THREADS`` or ``numba.set_num_threads``, see
  :func:`poinsot.rotations.set_num_threads`). Each element runs the same code
  whatever the number of threads, so the results are bit-identical;
* ``*_args_flat`` / ``*_from_*_flat`` pairs: the halves of a formula around a
  trig function that large batches take from NumPy's vectorised loop
  (:func:`poinsot.rotations._lazy.chunked`).

They trust their inputs (shapes, finiteness, unit norm where stated); validation
happens at the public entry points. This module is imported lazily (on first use)
so that ``import poinsot`` does not pay for numba.

Numba cannot size an output from a literal dimension, so gufuncs whose output size
does not appear among their inputs take a small ``dummy`` array of that size
(``_D3``/``_D4``); the wrappers in the representation modules hide it.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .. import _numba_helpers as nh
from .._jit import NUMBA, guvectorize, lanes, njit, overload, prange
from .._numba_cache import depends_on
from . import _scalar as S

depends_on(__file__, S, nh)

_D3 = np.zeros(3)
_D4 = np.zeros(4)

# typed Any: numba's stubs want literal option values, a plain dict[str, bool] matches none
_OPTS: dict[str, Any] = {"nopython": True, "cache": True}
_PAR: dict[str, Any] = {"cache": True, "parallel": True}

_inline = njit(inline="always", cache=True)


def _callable_when_compiled(fn):
    # Some _scalar formulas are written as two helpers with a trig call between them
    # (the batch path takes that call from NumPy's vectorised loop); this lets compiled
    # code call the helpers by name too (inlined), leaving them plain Python functions.
    overload(fn, inline="always", strict=False)(lambda *args: fn)


for _fn in (
    S.matrix_residual,
    S.angle_atan2_args,
    S.euler_atan2_args,
    S.euler_axes,
    S.euler_args,
    S.euler_from_atan2,
    S.rotvec_angle,
    S.from_rotvec_tan,
):
    _callable_when_compiled(_fn)

_hamilton = _inline(S.hamilton)
_rotate = _inline(S.rotate)
_to_matrix = _inline(S.to_matrix)
_matrix_check = _inline(S.matrix_check)
_is_rotation_within = _inline(S.is_rotation_within)
_from_matrix = _inline(S.from_matrix)
_from_rotvec = _inline(S.from_rotvec)
_to_rotvec = _inline(S.to_rotvec)
_canonical = _inline(S.canonical)
_to_mrp = _inline(S.to_mrp)
_from_mrp = _inline(S.from_mrp)
_angle = _inline(S.angle)
_euler_quat = _inline(S.from_euler)
_to_euler = _inline(S.to_euler)
_euler_axes = _inline(S.euler_axes)
_euler_args = _inline(S.euler_args)
_euler_from_atan2 = _inline(S.euler_from_atan2)
_atan2_poly = _inline(S.atan2_poly)
_rotvec_angle = _inline(S.rotvec_angle)
_angle_atan2_args = _inline(S.angle_atan2_args)
_from_rotvec_tan = _inline(S.from_rotvec_tan)


@guvectorize(["void(float64[:], float64[:], float64[:])"], "(n),(n)->(n)", **_OPTS)
def qmul(p, q, r):  # pragma: no cover - compiled
    r[0], r[1], r[2], r[3] = _hamilton(p[0], p[1], p[2], p[3], q[0], q[1], q[2], q[3])


@njit(cache=True)
def qmul1(p, q):  # pragma: no cover - compiled
    # One product of two single quaternions: a plain jitted call costs ~0.4 us less
    # than a gufunc call.
    r = np.empty(4)
    r[0], r[1], r[2], r[3] = _hamilton(p[0], p[1], p[2], p[3], q[0], q[1], q[2], q[3])
    return r


@guvectorize(["void(float64[:], float64[:], float64[:])"], "(n),(m)->(m)", **_OPTS)
def qrot(q, v, out):  # pragma: no cover - compiled
    out[0], out[1], out[2] = _rotate(q[0], q[1], q[2], q[3], v[0], v[1], v[2])


@guvectorize(["void(float64[:], float64[:], float64[:,:])"], "(n),(m)->(m,m)", **_OPTS)
def quat_to_matrix(q, dummy, m):  # pragma: no cover - compiled
    r = _to_matrix(q[0], q[1], q[2], q[3])
    m[0, 0], m[0, 1], m[0, 2] = r[0], r[1], r[2]
    m[1, 0], m[1, 1], m[1, 2] = r[3], r[4], r[5]
    m[2, 0], m[2, 1], m[2, 2] = r[6], r[7], r[8]


@njit(inline="always", cache=True)
def _nan_unless_finite(a00, a01, a02, a10, a11, a12, a20, a21, a22):  # pragma: no cover
    # 0 * a is 0 for finite a and NaN for inf or NaN: added to max |A^T A - E|, it makes
    # the error NaN exactly when the matrix is not finite (NaN can be lost by max()), so
    # that the caller needs no separate pass over the matrices to check finiteness.
    return (0.0 * a00 + 0.0 * a01 + 0.0 * a02 + 0.0 * a10 + 0.0 * a11 + 0.0 * a12) + (
        0.0 * a20 + 0.0 * a21 + 0.0 * a22
    )


@guvectorize(
    ["void(float64[:,:], float64[:], float64[:], float64[:], float64[:])"],
    "(m,m),(n)->(n),(),()",
    **_OPTS,
)
def matrix_to_quat(a, dummy, q, err, det):  # pragma: no cover - compiled
    # Also reports max |A^T A - E| (NaN for a non-finite A) and det A so the caller can
    # reject or project.
    a00, a01, a02, a10, a11, a12 = a[0, 0], a[0, 1], a[0, 2], a[1, 0], a[1, 1], a[1, 2]
    a20, a21, a22 = a[2, 0], a[2, 1], a[2, 2]
    e, det[0] = _matrix_check(a00, a01, a02, a10, a11, a12, a20, a21, a22)
    err[0] = e + _nan_unless_finite(a00, a01, a02, a10, a11, a12, a20, a21, a22)
    q[0], q[1], q[2], q[3] = _from_matrix(a00, a01, a02, a10, a11, a12, a20, a21, a22)


@guvectorize(["void(float64[:], float64[:], float64[:])"], "(m),(n)->(n)", **_OPTS)
def rotvec_to_quat(v, dummy, q):  # pragma: no cover - compiled
    q[0], q[1], q[2], q[3] = _from_rotvec(v[0], v[1], v[2])


@guvectorize(["void(float64[:], float64[:], float64[:])"], "(n),(m)->(m)", **_OPTS)
def quat_to_rotvec(q, dummy, v):  # pragma: no cover - compiled
    w, x, y, z = _canonical(q[0], q[1], q[2], q[3])
    v[0], v[1], v[2] = _to_rotvec(w, x, y, z)


@guvectorize(["void(int64[:], float64[:], float64[:], float64[:])"], "(k),(k),(n)->(n)", **_OPTS)
def euler_to_quat(axes, angles, dummy, q):  # pragma: no cover - compiled
    k = axes.shape[0]
    a1 = angles[1] if k > 1 else 0.0
    a2 = angles[2] if k > 2 else 0.0
    q[0], q[1], q[2], q[3] = _euler_quat(axes, angles[0], a1, a2)


@njit(cache=True)
def quat_to_euler_serial(q, seq, angles, singular):  # pragma: no cover - compiled
    # q (N, 4) unit; seq = (i, j, k, extrinsic) with i, j, k the axes in *extrinsic*
    # order (the caller reverses intrinsic sequences). A plain loop (not a gufunc):
    # per-element gufunc overhead doubled its cost. Small batches only: large ones
    # take to_euler_flat.
    i, j, k, extrinsic = seq[0], seq[1], seq[2], seq[3] != 0
    eps = 1e-7  # documented gimbal-lock threshold (rad)
    for n in range(q.shape[0]):
        a, b, c, s = _to_euler(q[n, 0], q[n, 1], q[n, 2], q[n, 3], i, j, k, extrinsic, eps)
        angles[n, 0], angles[n, 1], angles[n, 2] = a, b, c
        singular[n] = s


# ------------------------------------------------------------------- flat loops
# (N, k) contiguous arrays; a first argument with one row broadcasts.
@njit(**_PAR)
def qmul_flat(p, q, r):  # pragma: no cover - compiled
    lp, lq = p.shape[0] - 1, q.shape[0] - 1
    for n in prange(r.shape[0]):
        a = min(np.int64(n), lp)
        b = min(np.int64(n), lq)
        r[n, 0], r[n, 1], r[n, 2], r[n, 3] = _hamilton(
            p[a, 0], p[a, 1], p[a, 2], p[a, 3], q[b, 0], q[b, 1], q[b, 2], q[b, 3]
        )


@njit(**_PAR)
def qrot_flat(q, v, s, out):  # pragma: no cover - compiled
    # s = -1.0 rotates by the conjugates (an exact sign flip: the inverse without a
    # conjugated copy of the batch)
    lq, lv = q.shape[0] - 1, v.shape[0] - 1
    for n in prange(out.shape[0]):
        a = min(np.int64(n), lq)
        b = min(np.int64(n), lv)
        out[n, 0], out[n, 1], out[n, 2] = _rotate(
            q[a, 0], s * q[a, 1], s * q[a, 2], s * q[a, 3], v[b, 0], v[b, 1], v[b, 2]
        )


#: Results of at least this many bytes (half the L3 of the 2-core machine measured) are
#: written by :func:`conj_flat`, :func:`to_matrix_flat` and :func:`from_matrix_flat`
#: with streaming stores (:func:`nh.store_nt`): they would not stay in the caches
#: anyway, and a streaming store skips reading each line before writing it. On 10^6
#: rotations (2 threads, 3 runs of 41 interleaved rounds) the inverse took 1.63-1.89 ns
#: per rotation instead of 1.96-2.31; the same values.
STREAM_MIN_BYTES = 1 << 24
#: Parts of a streamed result (each thread writes whole parts, then fences them).
_STREAM_PARTS = 64


@njit(**_PAR)
def conj_flat(q, out):  # pragma: no cover - compiled
    n = q.shape[0]
    if out.nbytes < STREAM_MIN_BYTES:
        for k in prange(n):
            out[k, 0], out[k, 1], out[k, 2], out[k, 3] = q[k, 0], -q[k, 1], -q[k, 2], -q[k, 3]
        return
    src, dst = q.reshape(-1), out.reshape(-1)
    size = -(-n // _STREAM_PARTS)
    for part in prange(_STREAM_PARTS):
        for i in range(4 * part * size, 4 * min(n, (part + 1) * size), 4):
            nh.store_nt(dst, i, src[i])
            nh.store_nt(dst, i + 1, -src[i + 1])
            nh.store_nt(dst, i + 2, -src[i + 2])
            nh.store_nt(dst, i + 3, -src[i + 3])
        nh.fence()


@njit(inline="always")
def _put(dst, i, v, stream):  # pragma: no cover - compiled
    if stream:
        nh.store_nt(dst, i, v)
    else:
        dst[i] = v


@njit(inline="always")
def _matrix_row(dst, q, t, i, width, stream):  # pragma: no cover - compiled
    # row i of to_matrix_flat, each value stored in address order: streaming stores
    # that alternated between the two cache lines of a 16-row took 390 ns per row
    # instead of 12 (10^6 rows, 2 threads)
    r = _to_matrix(q[i, 0], q[i, 1], q[i, 2], q[i, 3])
    o = width * i
    if width == 9:
        for k in range(9):
            _put(dst, o + k, r[k], stream)
    else:
        for k in range(3):
            _put(dst, o + 4 * k, r[3 * k], stream)
            _put(dst, o + 4 * k + 1, r[3 * k + 1], stream)
            _put(dst, o + 4 * k + 2, r[3 * k + 2], stream)
            _put(dst, o + 4 * k + 3, t[i, k], stream)
        for k in range(12, 15):
            _put(dst, o + k, 0.0, stream)
        _put(dst, o + 15, 1.0, stream)


@njit(**_PAR)
def to_matrix_flat(q, t, m):  # pragma: no cover - compiled
    # Rows of 9 (R), or of 16 ([[R, t], [0, 0, 0, 1]], t given per row). Streamed from
    # STREAM_MIN_BYTES: the fresh result's pages come zeroed by the OS and already
    # evicted, so an ordinary store would read each line back first. On 10^6 rotations
    # (a Zen 4 EPYC, 11 interleaved rounds) 9.2 instead of 10.4 ns per rotation on one
    # thread, 5.8 against 5.9 on two; into a reused array 3.3 against 4.0.
    n, width = q.shape[0], m.shape[1]
    dst = m.reshape(-1)
    if m.nbytes < STREAM_MIN_BYTES:
        for i in prange(n):
            _matrix_row(dst, q, t, i, width, False)
        return
    size = -(-n // _STREAM_PARTS)
    for part in prange(_STREAM_PARTS):
        for i in range(part * size, min(n, (part + 1) * size)):
            _matrix_row(dst, q, t, i, width, True)
        nh.fence()


#: Rotations per block of :func:`from_matrix_flat` (its buffers, 15 * 8 * 256 bytes, stay in L1).
_BLOCK = 256
#: How many matrices ahead :func:`from_matrix_flat` asks for the lines it will read
#: (software prefetch; both ends of a 72-byte matrix, so that no line is skipped).
#: Without it the transposition's loads waited on memory: on 10^6 matrices (72 MB, from
#: DRAM; one thread, a Zen 4 EPYC) the kernel took 21 ns per rotation against 8-9.5 on
#: batches that fit in L3, and 10 ns with it. Measured on the transposition alone:
#: 8.8 ns per matrix without, 5.8 / 5.2 / 5.1 / 6.0 ns 16 / 32 / 64 / 128 matrices ahead.
_AHEAD = 64


@njit(cache=True, parallel=True, error_model="numpy")
def from_matrix_flat(a, q, err, det, bad, tol):  # pragma: no cover - compiled
    # SIMD across rotations: each block of matrices is first transposed into a (9, block)
    # buffer. On unit-stride rows LLVM vectorises the formula, turning the largest-square
    # choice into selects (all four candidates computed, one kept, no branch); on the
    # (N, 9) rows it stays scalar (measured: 18 -> 12.6 ns per rotation on one AVX2
    # thread). NumPy's error model: Python's division check is a branch that stops the
    # vectorisation (the divisor is >= 1 anyway: the four 4 q_k^2 sum to 4). Each
    # rotation runs the same operations as in _scalar.from_matrix, whatever the block
    # or thread: bit-identical results.
    #
    # The rows are split into at most len(bad) parts of whole blocks (bad[p] is part
    # p's). Two modes. With err and det of length N: each matrix's max |A^T A - E| (NaN if it
    # is not finite) and det A, for the messages and the projection of the rare batch
    # that needs them. Otherwise (the common case) only bad[p], how many matrices of
    # part p are not a rotation within tol. Writing the two N-arrays and the NaN-safe
    # max (which LLVM vectorised less well than the six comparisons) cost 1.4-1.5 ns of
    # the kernel's 7.7 per rotation (10^6 rotations, 2 threads), and their reduction in
    # the caller 0.4-0.6 ns more.
    n = a.shape[0]
    full = err.shape[0] == n
    stream = q.nbytes >= STREAM_MIN_BYTES
    blocks = (n + _BLOCK - 1) // _BLOCK
    parts = min(bad.shape[0], blocks)
    per = -(-blocks // parts)
    dst = q.reshape(-1)
    src = a.reshape(-1)
    for p in prange(parts):
        buf = np.empty((9, _BLOCK))
        out = np.empty((6, _BLOCK))
        count = 0
        for b in range(p * per, min(blocks, (p + 1) * per)):
            lo = b * _BLOCK
            m = min(lo + _BLOCK, n) - lo
            for j in range(m):
                i = 9 * (lo + j + _AHEAD)  # see _AHEAD
                nh.prefetch(src, i)
                nh.prefetch(src, i + 8)
                for c in range(9):
                    buf[c, j] = a[lo + j, c]
            # two loops rather than a test of `full` in one: LLVM vectorised that one
            # less well (measured: 12.0 against 9.2 ns per rotation, one thread)
            if full:
                for j in range(m):
                    a00, a01, a02 = buf[0, j], buf[1, j], buf[2, j]
                    a10, a11, a12 = buf[3, j], buf[4, j], buf[5, j]
                    a20, a21, a22 = buf[6, j], buf[7, j], buf[8, j]
                    e, out[5, j] = _matrix_check(a00, a01, a02, a10, a11, a12, a20, a21, a22)
                    out[4, j] = e + _nan_unless_finite(a00, a01, a02, a10, a11, a12, a20, a21, a22)
                    out[0, j], out[1, j], out[2, j], out[3, j] = _from_matrix(
                        a00, a01, a02, a10, a11, a12, a20, a21, a22
                    )
            else:
                for j in range(m):
                    a00, a01, a02 = buf[0, j], buf[1, j], buf[2, j]
                    a10, a11, a12 = buf[3, j], buf[4, j], buf[5, j]
                    a20, a21, a22 = buf[6, j], buf[7, j], buf[8, j]
                    count += 1 - _is_rotation_within(
                        a00, a01, a02, a10, a11, a12, a20, a21, a22, tol
                    )
                    out[0, j], out[1, j], out[2, j], out[3, j] = _from_matrix(
                        a00, a01, a02, a10, a11, a12, a20, a21, a22
                    )
            if stream:  # see STREAM_MIN_BYTES
                for j in range(m):
                    i = 4 * (lo + j)
                    nh.store_nt(dst, i, out[0, j])
                    nh.store_nt(dst, i + 1, out[1, j])
                    nh.store_nt(dst, i + 2, out[2, j])
                    nh.store_nt(dst, i + 3, out[3, j])
            else:
                for j in range(m):
                    q[lo + j, 0], q[lo + j, 1] = out[0, j], out[1, j]
                    q[lo + j, 2], q[lo + j, 3] = out[2, j], out[3, j]
            if full:
                for j in range(m):
                    err[lo + j], det[lo + j] = out[4, j], out[5, j]
        if stream:
            nh.fence()
        bad[p] = count


@njit(cache=True, nogil=True, error_model="numpy")
def to_euler_flat(q, seq, angles):  # pragma: no cover - compiled
    # The Euler angles of _scalar.to_euler in one pass, SIMD across rotations: each
    # block's quaternion components (w and those of the sequence's axes, picked once
    # per sequence) are first copied into a (4, block) buffer, on whose unit-stride rows
    # LLVM vectorises the formula with _scalar.atan2_poly in place of libm's atan2
    # (which does not vectorise: 3 calls of ~20 ns per rotation); the angles go back to
    # the (N, 3) rows through a (3, block) buffer. seq as quat_to_euler_serial's.
    # Returns how many rotations are in gimbal lock. Each rotation runs the same
    # operations whatever the block: the caller splits a batch over its threads
    # (_lazy.chunked: no OpenMP, safe in a forked child) with the same bits.
    i, j, k, extrinsic = seq[0], seq[1], seq[2], seq[3] != 0
    kk, sign, symmetric = _euler_axes(i, j, k)
    n = q.shape[0]
    buf = np.empty((4, _BLOCK))
    out = np.empty((3, _BLOCK))
    count = 0
    for lo in range(0, n, _BLOCK):
        m = min(lo + _BLOCK, n) - lo
        for t in range(m):
            buf[0, t] = q[lo + t, 0]
            buf[1, t] = q[lo + t, 1 + i]
            buf[2, t] = q[lo + t, 1 + j]
            buf[3, t] = q[lo + t, 1 + kk]
        for t in range(m):
            y1, x1, y2, x2, y3, x3 = _euler_args(
                buf[0, t], buf[1, t], buf[2, t], buf[3, t], sign, symmetric
            )
            a, c, d, s = _euler_from_atan2(
                _atan2_poly(y1, x1),
                _atan2_poly(y2, x2),
                _atan2_poly(y3, x3),
                i,
                j,
                k,
                extrinsic,
                1e-7,
            )
            out[0, t], out[1, t], out[2, t] = a, c, d
            count += s
        for t in range(m):
            angles[lo + t, 0], angles[lo + t, 1] = out[0, t], out[1, t]
            angles[lo + t, 2] = out[2, t]
    return count


@njit(**_PAR)
def outer_sums_flat(q, w, chunk, out):  # pragma: no cover - compiled
    # out[k, c] = the 10 entries (upper triangle, row by row) of sum w_i q_i q_i^T over
    # rotations [c chunk, (c + 1) chunk) of set k: fixed chunks, so the caller's sum of
    # them does not depend on the thread count
    sets, n = w.shape
    parts = out.shape[1]
    for t in prange(sets * parts):
        k, c = t // parts, t % parts
        s00 = s01 = s02 = s03 = s11 = s12 = s13 = s22 = s23 = s33 = 0.0
        for i in range(c * chunk, min(n, (c + 1) * chunk)):
            a, b, d, e = q[k, i, 0], q[k, i, 1], q[k, i, 2], q[k, i, 3]
            wa, wb, wd, we = w[k, i] * a, w[k, i] * b, w[k, i] * d, w[k, i] * e
            s00 += wa * a
            s01 += wa * b
            s02 += wa * d
            s03 += wa * e
            s11 += wb * b
            s12 += wb * d
            s13 += wb * e
            s22 += wd * d
            s23 += wd * e
            s33 += we * e
        out[k, c, 0], out[k, c, 1], out[k, c, 2], out[k, c, 3] = s00, s01, s02, s03
        out[k, c, 4], out[k, c, 5], out[k, c, 6] = s11, s12, s13
        out[k, c, 7], out[k, c, 8], out[k, c, 9] = s22, s23, s33


@njit(**_PAR)
def to_mrp_flat(q, p):  # pragma: no cover - compiled
    for n in prange(q.shape[0]):
        w, x, y, z = _canonical(q[n, 0], q[n, 1], q[n, 2], q[n, 3])
        p[n, 0], p[n, 1], p[n, 2] = _to_mrp(w, x, y, z)


#: |p|^2 above which :func:`from_mrp_flat` leaves a batch to the caller's shadow-set
#: path (which takes ``-p / |p|^2`` for ``|p| > 1e100``): below it, both agree.
MRP_DIRECT_MAX = 1e199


@njit(**_PAR)
def from_mrp_flat(p, q):  # pragma: no cover - compiled
    # returns how many rows have |p|^2 > MRP_DIRECT_MAX (or NaN): the caller then
    # converts the batch its own way
    far = 0
    for n in prange(p.shape[0]):
        a, b, c = p[n, 0], p[n, 1], p[n, 2]
        far += not (a * a + b * b + c * c <= MRP_DIRECT_MAX)
        q[n, 0], q[n, 1], q[n, 2], q[n, 3] = _from_mrp(a, b, c)
    return far


@njit(**_PAR)
def to_rotvec_flat(q, v):  # pragma: no cover - compiled
    for n in prange(q.shape[0]):
        w, x, y, z = _canonical(q[n, 0], q[n, 1], q[n, 2], q[n, 3])
        v[n, 0], v[n, 1], v[n, 2] = _to_rotvec(w, x, y, z)


@njit(**_PAR)
def euler_to_quat_flat(axes, angles, q):  # pragma: no cover - compiled
    k = axes.shape[0]
    for n in prange(angles.shape[0]):
        a1 = angles[n, 1] if k > 1 else 0.0
        a2 = angles[n, 2] if k > 2 else 0.0
        q[n, 0], q[n, 1], q[n, 2], q[n, 3] = _euler_quat(axes, angles[n, 0], a1, a2)


# ------------------------------------ the halves around NumPy's vectorised trig
# For large batches (rotations._lazy.chunked): chunks of a few thousand rotations,
# the arguments of the trig functions into a small buffer, NumPy's SIMD atan2/tan
# over it (~2 ns instead of ~20 ns per libm call), then the rest of the formula.
@njit(cache=True, nogil=True)
def angle_atan2_args_flat(q, buf):  # pragma: no cover - compiled
    # buf (2, m): the y = |l| and x = |l0| of 2 atan2(y, x)
    for n in range(q.shape[0]):
        buf[0, n], buf[1, n] = _angle_atan2_args(q[n, 0], q[n, 1], q[n, 2], q[n, 3])


@njit(cache=True, nogil=True)
def rotvec_angle_flat(v, buf):  # pragma: no cover - compiled
    # buf (2, m): f = |phi| and f / 4 (tan is taken of row 1 in place)
    for n in range(v.shape[0]):
        f = _rotvec_angle(v[n, 0], v[n, 1], v[n, 2])
        buf[0, n], buf[1, n] = f, 0.25 * f


@njit(cache=True, nogil=True)
def from_rotvec_tan_flat(v, buf, q):  # pragma: no cover - compiled
    for n in range(v.shape[0]):
        q[n, 0], q[n, 1], q[n, 2], q[n, 3] = _from_rotvec_tan(
            v[n, 0], v[n, 1], v[n, 2], buf[0, n], buf[1, n]
        )


# ------------------------------------------------------------- one rotation
# Array in, preallocated array out: a numba call with array arguments costs less
# than building the result from Python floats (used by Rotation's short paths).
@njit(cache=True)
def to_matrix1(q, m):  # pragma: no cover - compiled
    m[0, 0], m[0, 1], m[0, 2], m[1, 0], m[1, 1], m[1, 2], m[2, 0], m[2, 1], m[2, 2] = _to_matrix(
        q[0], q[1], q[2], q[3]
    )


@njit(cache=True)
def to_rotvec1(q, v):  # pragma: no cover - compiled
    w, x, y, z = _canonical(q[0], q[1], q[2], q[3])
    v[0], v[1], v[2] = _to_rotvec(w, x, y, z)


@njit(cache=True)
def to_mrp1(q, v):  # pragma: no cover - compiled
    w, x, y, z = _canonical(q[0], q[1], q[2], q[3])
    v[0], v[1], v[2] = _to_mrp(w, x, y, z)


@njit(cache=True)
def pow1(q, n, out):  # pragma: no cover - compiled
    # r ** n: the rotation vector (shortest rotation) times n, back to a quaternion
    w, x, y, z = _canonical(q[0], q[1], q[2], q[3])
    a, b, c = _to_rotvec(w, x, y, z)
    out[0], out[1], out[2], out[3] = _from_rotvec(n * a, n * b, n * c)


@njit(cache=True)
def angle1(q):  # pragma: no cover - compiled
    return _angle(q[0], q[1], q[2], q[3])


@njit(cache=True)
def conj1(q, out):  # pragma: no cover - compiled
    out[0], out[1], out[2], out[3] = q[0], -q[1], -q[2], -q[3]


@njit(cache=True)
def to_euler1(q, seq, angles):  # pragma: no cover - compiled
    a, b, c, singular = _to_euler(q[0], q[1], q[2], q[3], seq[0], seq[1], seq[2], seq[3] != 0, 1e-7)
    angles[0], angles[1], angles[2] = a, b, c
    return singular


# ------------------------------------------------- Euler kinematics, one state
_euler_columns = _inline(S.euler_columns)
_cross = _inline(S.cross)


@njit(inline="always", cache=True)
def _euler_m(code, a, space):  # pragma: no cover - compiled
    # code: the axes in extrinsic order and the extrinsic flag (as quat_to_euler_serial's).
    # C = F0 F1 F2 with F0 about code[2]; factor m holds the angle k_m.
    ext = code[3] != 0
    k0 = 2 if ext else 0
    k2 = 0 if ext else 2
    r = _euler_columns(
        code[2],
        code[1],
        code[0],
        math.cos(a[k0]),
        math.sin(a[k0]),
        math.cos(a[1]),
        math.sin(a[1]),
        math.cos(a[k2]),
        math.sin(a[k2]),
        space,
    )
    return k0, k2, r


@njit(cache=True)
def euler_matrix1(code, a, space, m):  # pragma: no cover - compiled
    k0, k2, r = _euler_m(code, a, space)
    for i in range(3):
        m[i, k0], m[i, 1], m[i, k2] = r[i], r[3 + i], r[6 + i]


@njit(cache=True)
def omega_from_euler_rates1(code, a, d, space, out):  # pragma: no cover - compiled
    k0, k2, r = _euler_m(code, a, space)
    for i in range(3):
        out[i] = r[i] * d[k0] + r[3 + i] * d[1] + r[6 + i] * d[k2]


@njit(cache=True)
def euler_rates1(code, a, w, space, min_det, out):  # pragma: no cover - compiled
    # M^-1 = adj(M) / det M: rows c1 x c2, c2 x c0, c0 x c1 over c0 . (c1 x c2).
    k0, k2, r = _euler_m(code, a, space)
    x = _cross(r[3], r[4], r[5], r[6], r[7], r[8])
    y = _cross(r[6], r[7], r[8], r[0], r[1], r[2])
    z = _cross(r[0], r[1], r[2], r[3], r[4], r[5])
    det = r[0] * x[0] + r[1] * x[1] + r[2] * x[2]
    if abs(det) >= min_det:
        out[k0] = (x[0] * w[0] + x[1] * w[1] + x[2] * w[2]) / det
        out[1] = (y[0] * w[0] + y[1] * w[1] + y[2] * w[2]) / det
        out[k2] = (z[0] * w[0] + z[1] * w[1] + z[2] * w[2]) / det
    return det


# ------------------------------------------------- DCM kinematics, one state
@njit(inline="always", cache=True)
def _is_rotation(c, tol):  # pragma: no cover - compiled
    # orthonormal within tol and det >= 0 (a NaN fails both)
    err, det = _matrix_check(
        c[0, 0], c[0, 1], c[0, 2], c[1, 0], c[1, 1], c[1, 2], c[2, 0], c[2, 1], c[2, 2]
    )
    return err <= tol and det >= 0.0


@njit(cache=True)
def dcm_rate1(c, w, space, tol, out):  # pragma: no cover - compiled
    # Checks C (orthonormal within tol, det >= 0; NaN fails) and writes
    # C w^ (body: row i is row_i(C) x w) or w^ C (space: column j is w x col_j(C)).
    if not _is_rotation(c, tol):
        return False
    for i in range(3):
        if space:
            out[0, i], out[1, i], out[2, i] = _cross(w[0], w[1], w[2], c[0, i], c[1, i], c[2, i])
        else:
            out[i, 0], out[i, 1], out[i, 2] = _cross(c[i, 0], c[i, 1], c[i, 2], w[0], w[1], w[2])
    return True


@njit(cache=True)
def omega_from_dcm_rate1(c, d, space, tol, out):  # pragma: no cover - compiled
    # vee of the antisymmetric part of C^T Cdot (body) or Cdot C^T (space).
    if not _is_rotation(c, tol):
        return False
    m = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            if space:
                m[i, j] = d[i, 0] * c[j, 0] + d[i, 1] * c[j, 1] + d[i, 2] * c[j, 2]
            else:
                m[i, j] = c[0, i] * d[0, j] + c[1, i] * d[1, j] + c[2, i] * d[2, j]
    out[0] = 0.5 * (m[2, 1] - m[1, 2])
    out[1] = 0.5 * (m[0, 2] - m[2, 0])
    out[2] = 0.5 * (m[1, 0] - m[0, 1])
    return True


if not NUMBA:  # the NumPy executor: one vectorised pass over the batch, not a Python loop

    def quat_to_euler_serial(q, seq, angles, singular):  # noqa: F811
        i, j, k, extrinsic = int(seq[0]), int(seq[1]), int(seq[2]), bool(seq[3] != 0)
        a, b, c, s = lanes(S.to_euler, q.shape[0], *q.T, i, j, k, extrinsic, 1e-7)
        angles[:, 0], angles[:, 1], angles[:, 2] = a, b, c
        singular[:] = s
