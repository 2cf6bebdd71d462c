"""Compiled loops of :func:`poinsot.rotations.determine_attitude` (QUEST, ESOQ2).

The formulas are those of :mod:`poinsot.rotations._wahba` (plain Python), compiled
here inline; this file's cache is stamped with that file and with
:mod:`poinsot.rotations._scalar` (:func:`poinsot._numba_cache.depends_on`). Imported
lazily, only with numba (the NumPy executor runs :func:`~._wahba.solve` on columns).

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

depends_on(__file__, W, S)

for _fn in (
    W.finite3,
    W.unit,
    W.sym_det,
    W.k_parts,
    W.sym_mv,
    W.lambda_max,
    W.quest_raw,
    W.normalised4,
    W.turned,
    W.turned_back,
    W.quest,
    W.quest_turned,
    W.cross,
    W.esoq2,
):  # callable from compiled code (numba compiles the plain function; LLVM inlines it)
    overload(_fn, strict=False)(lambda *args, _fn=_fn: _fn)

# error_model="numpy": a division needs no zero test (there are none left: the status
# checks come first), which lets the loops vectorise
_OPTS: dict[str, Any] = {"cache": True, "error_model": "numpy"}

for _scalar_fn in (S.hamilton, S.to_matrix):
    overload(_scalar_fn, strict=False)(lambda *args, _f=_scalar_fn: _f)
# inlined where it is called (numba's IR inlining): each call site below sees its
# constant n, so LLVM unrolls the loops over the observations (about 1/4 faster)
_one = njit(inline="always", **_OPTS)(W.solve)


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


@njit(**_OPTS)
def _rows(ob, rf, w, lo, hi, method, want_cov, q, loss, cov, status):  # pragma: no cover
    """Sets ``lo`` to ``hi``: one loop for n = 2, one for n = 3, one for the others.
    For n = 2 and 3 a set goes to ``_one`` as tuples of floats: an array argument
    (a slice ``ob[i]`` or the whole batch) is reference-counted per set by the
    inlined code, an atomic add on a counter the threads share."""
    n = ob.shape[1]
    # 0 for a batch-wide catalogue or weight vector (int64: prange's index may be
    # unsigned, and i if ... else 0 would then be a float)
    so = np.int64(1 if ob.shape[0] > 1 else 0)
    sr = np.int64(1 if rf.shape[0] > 1 else 0)
    sw = np.int64(1 if w.shape[0] > 1 else 0)
    if n == 2:
        for i in range(lo, hi):
            k = np.int64(i)
            kw = k * sw
            r = _one(_two(ob, k * so), _two(rf, k * sr), (w[kw, 0], w[kw, 1]), 2,
                     method, want_cov)  # fmt: skip
            _store(i, r, want_cov, q, loss, cov, status)
    elif n == 3:
        for i in range(lo, hi):
            k = np.int64(i)
            kw = k * sw
            r = _one(_three(ob, k * so), _three(rf, k * sr), (w[kw, 0], w[kw, 1], w[kw, 2]),
                     3, method, want_cov)  # fmt: skip
            _store(i, r, want_cov, q, loss, cov, status)
    else:
        for i in range(lo, hi):
            k = np.int64(i)
            r = _one(ob[k * so], rf[k * sr], w[k * sw], n, method, want_cov)
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
