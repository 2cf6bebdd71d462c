"""Compiled loops of :func:`poinsot.rotations.determine_attitude` (QUEST, ESOQ2).

The formulas are those of :mod:`poinsot.rotations._wahba` (plain Python), compiled
here inline; this file's cache is stamped with that file and with
:mod:`poinsot.rotations._scalar` (:func:`poinsot._numba_cache.depends_on`). Imported
lazily, only with numba (the NumPy executor runs :func:`~._wahba.solve` on columns).
The helpers are inlined by LLVM (``forceinline``), not by numba's IR inlining (much
slower to compile here): a call left in a loop stops its vectorising.

Inputs ``(No, n, 3)``, ``(Nr, n, 3)``, ``(Nw, n)`` with each of ``No``, ``Nr``, ``Nw``
either ``N`` or 1 (one catalogue or one weight vector for the whole batch).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._jit import njit, overload, prange
from .._numba_cache import depends_on
from . import _scalar as S
from . import _wahba as W
from . import _wahba_codes as C

depends_on(__file__, W, S, C)

# error_model="numpy" (as _OPTS below): a division by zero gives inf or NaN, no test
_INLINE: dict[str, Any] = {"forceinline": True, "error_model": "numpy"}
for _fn in (
    W.finite3,
    W.unit,
    W.sym_det,
    W.k_parts,
    W.sym_mv,
    W.lambda_coeffs,
    W.newton_step,
    W.newton_fast,
    W.fprime,
    W.lambda_max,
    W.quest_raw,
    W.normalised4,
    W.turned,
    W.turned_back,
    W.quest,
    W.quest_turned,
    W.cross,
    W.esoq2,
    W.accumulate,
    W.attitude,
    W.spreads,
    W.polynomial,
    W.solve_fast,
    W.solve_slow,
):  # callable from compiled code, inlined by LLVM where called: the block loop of _pass
    # must see no call to vectorise (LLVM's own inliner leaves the larger ones as calls)
    overload(_fn, strict=False, jit_options=_INLINE)(lambda *args, _fn=_fn: _fn)

# error_model="numpy": a division needs no zero test (there are none left: the status
# checks come first), which lets the loops vectorise
_OPTS: dict[str, Any] = {"cache": True, "error_model": "numpy"}

for _scalar_fn in (S.hamilton, S.to_matrix):
    overload(_scalar_fn, strict=False)(lambda *args, _f=_scalar_fn: _f)
# solve is solve_slow, and solve_fast agrees with it bit for bit where it does not flag
# the set. The loops run solve_fast on blocks, inlined where called (each call site
# sees its constant n: LLVM unrolls the loops over the observations and vectorises the
# block loop), and solve_slow set by set as a function of its own (one copy per tuple
# type, not one per block loop: the cold compile). Neither has a numba cache of its own
# (it would be stamped with _wahba.py only, not _scalar.py): compiled into the kernels
# below, they are cached with this file's stamp, which covers both.
_fast = njit(forceinline=True, error_model="numpy")(W.solve_fast)
_slow_body = njit(forceinline=True, error_model="numpy")(W.solve_slow)


@njit(**_OPTS)
def _slow(ob, rf, w, n, method, want_cov):  # pragma: no cover
    """:func:`~._wahba.solve_slow` as a function of its own (one copy per type)."""
    return _slow_body(ob, rf, w, n, method, want_cov)


@njit(inline="always", **_OPTS)
def _store(i, r, want_cov, q, loss, cov, status):  # pragma: no cover
    q[i, 0], q[i, 1], q[i, 2], q[i, 3] = r[0], r[1], r[2], r[3]
    loss[i] = r[4]
    status[i] = np.uint8(r[11])
    if want_cov:
        cov[i, 0, 0], cov[i, 0, 1], cov[i, 0, 2] = r[5], r[6], r[7]
        cov[i, 1, 0], cov[i, 1, 1], cov[i, 1, 2] = r[6], r[8], r[9]
        cov[i, 2, 0], cov[i, 2, 1], cov[i, 2, 2] = r[7], r[9], r[10]


@njit(inline="always", **_OPTS)
def _two(a, k):  # pragma: no cover
    return (a[k, 0, 0], a[k, 0, 1], a[k, 0, 2]), (a[k, 1, 0], a[k, 1, 1], a[k, 1, 2])


@njit(inline="always", **_OPTS)
def _three(a, k):  # pragma: no cover
    return (
        (a[k, 0, 0], a[k, 0, 1], a[k, 0, 2]),
        (a[k, 1, 0], a[k, 1, 1], a[k, 1, 2]),
        (a[k, 2, 0], a[k, 2, 1], a[k, 2, 2]),
    )


#: Sets per block of :func:`_rows`' first pass (its results, 13 rows of BLOCK, stay in
#: the L1 cache until the second pass stores them).
BLOCK = 128


@njit(inline="always", **_OPTS)
def _at(out, row, j):  # pragma: no cover
    """Entry ``row`` of set ``j`` of a block in the scratch array of :func:`_pass`."""
    return out[row * BLOCK + j]


@njit(inline="always", **_OPTS)
def _vec(out, row, j):  # pragma: no cover
    return _at(out, row, j), _at(out, row + 1, j), _at(out, row + 2, j)


@njit(inline="always", **_OPTS)
def _pass(ob, rf, w, lo, hi, so, sr, sw, n, method, out):  # pragma: no cover
    """:func:`~._wahba.solve_fast` on sets ``lo`` to ``hi`` (at most BLOCK) into rows 0
    to 12 of the scratch ``out`` (one row per result): the sets are first copied to its
    rows 13 on (one row per entry, structure of arrays), then one loop with no branch
    runs over the whole block, which LLVM vectorises across sets. ``out`` is one flat
    array indexed ``row * BLOCK + j``: constant offsets, so LLVM sees that the rows
    do not overlap without a run-time test (a 2-D array's stride is not a constant
    there: too many such tests, no vectorising)."""
    for j in range(hi - lo):
        k = np.int64(lo + j)
        ko, kr, kw = k * so, k * sr, k * sw
        for i in range(n):
            for x in range(3):
                out[(13 + 3 * i + x) * BLOCK + j] = ob[ko, i, x]
                out[(13 + 3 * n + 3 * i + x) * BLOCK + j] = rf[kr, i, x]
            out[(13 + 6 * n + i) * BLOCK + j] = w[kw, i]
    for j in range(BLOCK):  # the whole block: the sets after hi are left-overs, unused
        if n == 2:
            bb = (_vec(out, 13, j), _vec(out, 16, j))
            rr = (_vec(out, 19, j), _vec(out, 22, j))
            r = _fast(bb, rr, (_at(out, 25, j), _at(out, 26, j)), 2, method, True)
        else:
            b3 = (_vec(out, 13, j), _vec(out, 16, j), _vec(out, 19, j))
            r3 = (_vec(out, 22, j), _vec(out, 25, j), _vec(out, 28, j))
            w3 = (_at(out, 31, j), _at(out, 32, j), _at(out, 33, j))
            r = _fast(b3, r3, w3, 3, method, True)
        for x in range(13):
            out[x * BLOCK + j] = r[x]


@njit(inline="always", **_OPTS)
def _blocks(
    ob, rf, w, lo, hi, so, sr, sw, n, method, want_cov, q, loss, cov, status
):  # pragma: no cover
    """Sets ``lo`` to ``hi`` of ``n`` (2 or 3) observations, BLOCK at a time: the
    vectorised pass, then the stores, with :func:`~._wahba.solve_slow` for the sets it
    left (a status, or Newton not stopped)."""
    out = np.zeros((13 + 7 * 3) * BLOCK)  # results, then the inputs (n <= 3)
    for b0 in range(lo, hi, BLOCK):
        b1 = min(hi, b0 + BLOCK)
        _pass(ob, rf, w, b0, b1, so, sr, sw, n, method, out)
        for i in range(b0, b1):
            j = i - b0
            if _at(out, 12, j) != 0.0:
                k = np.int64(i)
                kw = k * sw
                if n == 2:
                    r = _slow(_two(ob, k * so), _two(rf, k * sr), (w[kw, 0], w[kw, 1]), 2,
                              method, want_cov)  # fmt: skip
                else:
                    r = _slow(_three(ob, k * so), _three(rf, k * sr),
                              (w[kw, 0], w[kw, 1], w[kw, 2]), 3, method, want_cov)  # fmt: skip
                _store(i, r, want_cov, q, loss, cov, status)
            else:
                q[i, 0], q[i, 1] = _at(out, 0, j), _at(out, 1, j)
                q[i, 2], q[i, 3] = _at(out, 2, j), _at(out, 3, j)
                loss[i] = _at(out, 4, j)
                status[i] = np.uint8(0)
                if want_cov:
                    c00, c01, c02 = _at(out, 5, j), _at(out, 6, j), _at(out, 7, j)
                    c11, c12, c22 = _at(out, 8, j), _at(out, 9, j), _at(out, 10, j)
                    cov[i, 0, 0], cov[i, 0, 1], cov[i, 0, 2] = c00, c01, c02
                    cov[i, 1, 0], cov[i, 1, 1], cov[i, 1, 2] = c01, c11, c12
                    cov[i, 2, 0], cov[i, 2, 1], cov[i, 2, 2] = c02, c12, c22


@njit(**_OPTS)
def _rows(ob, rf, w, lo, hi, method, want_cov, q, loss, cov, status):  # pragma: no cover
    """Sets ``lo`` to ``hi``: for n = 2 and 3, :func:`_blocks` (one copy per method and
    n, each with its constants); for the others, :func:`~._wahba.solve_slow` set by set.
    A set reaches the formulas as tuples of floats: an array argument (a slice
    ``ob[i]`` or the whole batch) is reference-counted per set by the inlined code, an
    atomic add on a counter the threads share."""
    n = ob.shape[1]
    # 0 for a batch-wide catalogue or weight vector (int64: prange's index may be
    # unsigned, and i if ... else 0 would then be a float)
    so = np.int64(1 if ob.shape[0] > 1 else 0)
    sr = np.int64(1 if rf.shape[0] > 1 else 0)
    sw = np.int64(1 if w.shape[0] > 1 else 0)
    if n == 2 and method == C.QUEST:
        _blocks(ob, rf, w, lo, hi, so, sr, sw, 2, C.QUEST, want_cov, q, loss, cov, status)
    elif n == 2:
        _blocks(ob, rf, w, lo, hi, so, sr, sw, 2, C.ESOQ2, want_cov, q, loss, cov, status)
    elif n == 3 and method == C.QUEST:
        _blocks(ob, rf, w, lo, hi, so, sr, sw, 3, C.QUEST, want_cov, q, loss, cov, status)
    elif n == 3:
        _blocks(ob, rf, w, lo, hi, so, sr, sw, 3, C.ESOQ2, want_cov, q, loss, cov, status)
    else:
        for i in range(lo, hi):
            k = np.int64(i)
            r = _slow(ob[k * so], rf[k * sr], w[k * sw], n, method, want_cov)
            _store(i, r, want_cov, q, loss, cov, status)


#: Sets per chunk of :func:`solve_flat` (the chunks, not the sets, go to the threads).
CHUNK = 2048


@njit(parallel=True, **_OPTS)
def solve_flat(ob, rf, w, method, want_cov, q, loss, cov, status):  # pragma: no cover
    """Every set, in chunks split over numba's threads (each set runs the same code
    whatever the thread count: bit-identical results)."""
    size = q.shape[0]
    for c in prange((size + CHUNK - 1) // CHUNK):
        lo = c * CHUNK
        _rows(ob, rf, w, lo, min(size, lo + CHUNK), method, want_cov, q, loss, cov, status)


@njit(**_OPTS)
def solve_serial(ob, rf, w, method, want_cov, q, loss, cov, status):  # pragma: no cover
    """Every set on the calling thread (small batches: no threads to wake)."""
    _rows(ob, rf, w, 0, q.shape[0], method, want_cov, q, loss, cov, status)
