"""Lazy access to the compiled kernels (numba loads on first use, not on import).

Also the choice between the broadcasting kernels and the threaded flat loops: a
batch of at least :data:`PARALLEL_MIN_SIZE` rotations runs on every numba thread
(``NUMBA_NUM_THREADS``, or :func:`set_num_threads`); the result is bit-identical
whatever the number of threads (each element runs the same code).
"""

from __future__ import annotations

import importlib
from types import ModuleType

import numpy as np

_MODULE: ModuleType | None = None

#: Batches of at least this many rotations use the threaded kernels (every numba thread).
PARALLEL_MIN_SIZE = 20_000


def kernels() -> ModuleType:
    """Return :mod:`poinsot.rotations._kernels`, importing (and compiling) it once."""
    global _MODULE
    if _MODULE is None:
        _MODULE = importlib.import_module("poinsot.rotations._kernels")
    return _MODULE


def set_num_threads(n: int) -> None:
    """Number of threads used for large rotation batches (theory §2, ``docs/conventions.md``).

    Batches of at least ``PARALLEL_MIN_SIZE`` (20,000) rotations split their loop
    over numba's threads; this sets numba's thread count for the calling thread
    (``numba.set_num_threads``), between 1 and ``NUMBA_NUM_THREADS`` (default:
    the number of cores; set that environment variable before starting Python to
    change the maximum). Results are bit-identical for every thread count.

    >>> from poinsot.rotations import set_num_threads, get_num_threads
    >>> set_num_threads(1); get_num_threads()
    1
    >>> import numba; set_num_threads(numba.config.NUMBA_NUM_THREADS)
    """
    from numba import config
    from numba import set_num_threads as _set

    from .._validate import as_int

    k = as_int(n, "n", minimum=1)
    if k > config.NUMBA_NUM_THREADS:
        from ..errors import InvalidInputError

        raise InvalidInputError(
            f"Expected `n` to be at most NUMBA_NUM_THREADS = {config.NUMBA_NUM_THREADS}, got {n!r}."
        )
    _set(k)


def get_num_threads() -> int:
    """Threads used for large rotation batches (see :func:`set_num_threads`).

    >>> get_num_threads() >= 1
    True
    """
    from numba import get_num_threads as _get

    return int(_get())


def flat(a: np.ndarray, k: int) -> np.ndarray:
    """``a`` as a contiguous ``(N, k)`` float64 array (a view when already contiguous)."""
    return np.ascontiguousarray(a).reshape(-1, k)


def big(shape: tuple[int, ...]) -> bool:
    """Whether a batch of this leading shape takes the threaded flat kernels."""
    n = 1
    for d in shape:
        n *= d
    return n >= PARALLEL_MIN_SIZE
