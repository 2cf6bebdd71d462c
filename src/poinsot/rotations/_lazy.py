"""Lazy access to the compiled kernels (numba loads on first use, not on import).

Also the choice between the broadcasting kernels and the threaded flat loops: a
batch of at least :data:`PARALLEL_MIN_SIZE` rotations runs on numba's threads
(:func:`threaded`); the result is bit-identical whatever the number of threads
(each element runs the same code).

**How many threads.** After :func:`set_num_threads(n) <set_num_threads>`,
exactly ``n``. Until then, every *idle* core: numba's count
(``NUMBA_NUM_THREADS``, default the number of cores) capped by the cores the
1-minute load average leaves free (a busy, shared machine gets one thread: there,
waking a second thread costs more than it saves).
"""

from __future__ import annotations

import importlib
import os
import sys
from collections.abc import Callable
from types import ModuleType
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import _jit
from .._jit import NUMBA
from .._validate import as_int
from ..errors import InvalidInputError

if TYPE_CHECKING:
    from concurrent.futures import ThreadPoolExecutor

_MODULE: ModuleType | None = None
_USER_THREADS = False  # set_num_threads was called: use numba's count as it is

#: Batches of at least this many rotations use the threaded kernels (every numba thread).
PARALLEL_MIN_SIZE = 20_000


#: Whether this process runs the rotation kernels on the NumPy executor because numba's
#: cache was cold at their first use (:func:`kernels`).
_TWIN = False


def kernels() -> ModuleType:
    """Return :mod:`poinsot.rotations._kernels`, importing (and compiling) it once; on a
    cold cache (no ``poinsot warmup`` yet, :func:`poinsot._jit.is_warm`), its NumPy-executor
    twin (:func:`poinsot._jit.numpy_twin`), which compiles nothing, while a background
    process fills the cache for the next one (docs/performance.md, "Cold start")."""
    global _MODULE, _TWIN
    if _MODULE is None:
        cold = _jit.interpret_first() and _KERNELS not in sys.modules
        if cold and not _jit.is_warm() and not _cached(_KERNELS):
            _MODULE, _TWIN = _jit.numpy_twin(_KERNELS), True
            _jit.build_in_background()
        else:
            _MODULE = _import_kernels()
    return _MODULE


def _import_kernels() -> ModuleType:
    # its gufuncs compile (or load) at import: under the lock of _jit.compile_lock
    if _KERNELS in sys.modules or not NUMBA:
        return importlib.import_module(_KERNELS)
    with _jit.compile_lock("rotations"):
        return importlib.import_module(_KERNELS)


_KERNELS = "poinsot.rotations._kernels"


def _compiled() -> None:
    """Leave the twin for the compiled kernels (a batch large enough to pay for them)."""
    global _MODULE, _TWIN
    _MODULE, _TWIN = _import_kernels(), False


def _cached(name: str) -> bool:
    """Whether numba's cache holds compilations of the kernel module ``name``: its index
    files where the first of numba's locators that applies puts them (as numba looks
    them up). True when that cannot be told: the module then loads (or compiles) as
    it always did."""
    try:
        import importlib.util
        from pathlib import Path

        from numba.core import caching

        impl = getattr(caching, "CacheImpl", None) or caching._CacheImpl  # type: ignore[attr-defined]
        spec = importlib.util.find_spec(name)
        if spec is None or spec.origin is None:
            return True
        path = spec.origin
        ns: dict[str, Any] = {}
        exec(compile("def probe():\n    pass\n", path, "exec"), ns)  # a function of that file
        for cls in impl._locator_classes:
            try:
                loc = cls.from_function(ns["probe"], path)
            except Exception:  # a locator that does not apply to this file
                continue
            if loc is not None:
                return any(Path(loc.get_cache_path()).glob(Path(path).stem + ".*.nbi"))
    except Exception:
        return True
    return True


class _OneRotation:
    """numba's compiled entry points of the one-rotation kernels (``to_matrix1``...),
    resolved on first use: ``one.to_matrix1(q, m)``.

    Calling the entry point compiled for the exact argument types skips the
    dispatcher's type matching (about 0.1 us of a 0.5 us one-rotation call). It does
    not check its arguments, so callers pass exactly these types: a single
    rotation's quaternion (always a C-contiguous float64 ``(4,)`` array, see
    ``Rotation._wrap``) and freshly allocated float64 / int64 C arrays.
    """

    _SIGNATURES = {
        "to_matrix1": ("q", "f2"),
        "to_rotvec1": ("q", "f1"),
        "to_mrp1": ("q", "f1"),
        "to_euler1": ("q", "i1", "f1"),
        "angle1": ("q",),
        "conj1": ("q", "f1"),
        "pow1": ("q", "f", "f1"),
    }

    def __getattr__(self, name: str) -> Any:
        if not _numba():  # the NumPy executor: the kernel is the plain Python function
            if name not in self._SIGNATURES:
                raise AttributeError(name)
            return getattr(kernels(), name)
        from numba import types

        kinds = {
            "q": types.Array(types.float64, 1, "C", readonly=True),
            "f1": types.Array(types.float64, 1, "C"),
            "f2": types.Array(types.float64, 2, "C"),
            "i1": types.Array(types.int64, 1, "C"),
            "f": types.float64,
        }
        try:
            sig = self._SIGNATURES[name]
        except KeyError:
            raise AttributeError(name) from None
        entry = getattr(kernels(), name).compile(tuple(kinds[k] for k in sig))
        setattr(self, name, entry)  # later lookups find the attribute directly
        return entry


one = _OneRotation()

_FALLBACK_THREADS = [1]  # the NumPy executor runs on the calling thread


def _numba() -> bool:
    """Whether the kernels are compiled by numba (:mod:`poinsot._jit`; imported here,
    not at ``import poinsot``): not when this process runs their NumPy-executor twin."""
    kernels()
    return NUMBA and not _TWIN


def set_num_threads(n: int | None) -> None:
    """Number of threads used for large rotation batches (theory §2, ``docs/conventions.md``).

    Batches of at least ``PARALLEL_MIN_SIZE`` (20,000) rotations split their loop
    over numba's threads; this sets numba's thread count for the calling thread
    (``numba.set_num_threads``), between 1 and ``NUMBA_NUM_THREADS`` (default:
    the number of cores; set that environment variable before starting Python to
    change the maximum), and from then on exactly ``n`` threads are used. Before
    any call, large batches use the idle cores (numba's count capped by the cores
    the 1-minute load average leaves free). Results are bit-identical for every
    thread count. ``n=None`` restores the default (idle cores, numba's count left
    as it is).

    >>> from poinsot.rotations import set_num_threads, get_num_threads
    >>> set_num_threads(1); get_num_threads()
    1
    >>> import numba; set_num_threads(numba.config.NUMBA_NUM_THREADS)
    >>> set_num_threads(None)      # back to the default: the idle cores
    """

    global _USER_THREADS
    if n is None:
        _USER_THREADS = False
        return
    k = as_int(n, "n", minimum=1)
    if not _numba():  # the NumPy executor uses no threads of its own
        _FALLBACK_THREADS[0] = k
        _USER_THREADS = True
        return
    from numba import config
    from numba import set_num_threads as _set

    # numba.config sets its NUMBA_* attributes at import: its stubs do not list them
    limit: int = config.NUMBA_NUM_THREADS  # type: ignore[attr-defined]
    if k > limit:
        raise InvalidInputError(
            f"Expected `n` to be at most NUMBA_NUM_THREADS = {limit}, got {n!r}."
        )
    _set(k)
    _USER_THREADS = True


def get_num_threads() -> int:
    """Threads used for large rotation batches (see :func:`set_num_threads`).

    >>> get_num_threads() >= 1
    True
    """
    if not _numba():
        return _FALLBACK_THREADS[0]
    from numba import get_num_threads as _get

    return int(_get())


def _idle_threads(n: int) -> int:
    try:
        load = os.getloadavg()[0]
    except OSError:  # pragma: no cover - platforms without a load average
        return n
    # the load includes this process itself (about 1)
    return max(1, min(n, int(round((os.cpu_count() or 1) - load + 1.0))))


def thread_count() -> int:
    """Threads a large batch runs on now (the rule in the module notes)."""
    if not _numba():
        return 1
    from numba import get_num_threads as _get

    n0 = _get()
    return n0 if _USER_THREADS else _idle_threads(n0)


def threaded(kernel: Callable[..., Any], *args: Any) -> Any:
    """Call a threaded flat kernel with the thread count described in the module notes."""
    if _USER_THREADS or not NUMBA:  # the NumPy executor runs on the calling thread
        return kernel(*args)
    from numba import get_num_threads as _get
    from numba import set_num_threads as _set

    n0 = _get()
    n = _idle_threads(n0)
    if n == n0:
        return kernel(*args)
    _set(n)
    try:
        return kernel(*args)
    finally:
        _set(n0)


#: Rotations per chunk of :func:`chunked` (fixed: results do not depend on threads).
CHUNK = 4096
_POOL: tuple[int, ThreadPoolExecutor] | None = None


def chunked(step: Callable[[int, int], object], n: int, chunk: int = CHUNK) -> None:
    """Call ``step(lo, hi)`` on the chunks ``[lo, hi)`` of ``chunk`` rotations
    covering ``range(n)``, spread over :func:`thread_count` threads.

    For the conversions whose compiled parts release the GIL (their halves around
    one of NumPy's vectorised trig loops, or ``nogil`` kernels): Python threads, not
    numba's OpenMP, so also in a forked child. The chunk boundaries do not depend on
    the thread count, so neither do the results.
    """
    global _POOL
    starts = range(0, n, chunk)
    threads = min(thread_count(), len(starts))
    if threads <= 1:
        for lo in starts:
            step(lo, min(lo + chunk, n))
        return
    if _POOL is None or _POOL[0] != os.getpid():  # a forked child needs its own threads
        from concurrent.futures import ThreadPoolExecutor

        from numba import config

        _POOL = (
            os.getpid(),
            ThreadPoolExecutor(
                config.NUMBA_NUM_THREADS,  # type: ignore[attr-defined]  # set at import
                thread_name_prefix="poinsot",
            ),
        )

    def run(part: range) -> None:
        for lo in part:
            step(lo, min(lo + chunk, n))

    parts = [starts[t::threads] for t in range(threads)]
    futures = [_POOL[1].submit(run, part) for part in parts[1:]]
    run(parts[0])
    for f in futures:
        f.result()


def flat(a: np.ndarray, k: int) -> np.ndarray:
    """``a`` as a contiguous ``(N, k)`` float64 array (a view when already contiguous)."""
    return np.ascontiguousarray(a).reshape(-1, k)


def big(shape: tuple[int, ...]) -> bool:
    """Whether a batch of this leading shape takes the threaded flat kernels (never
    under the NumPy executor: its broadcasting kernels are already vectorised)."""
    n = 1
    for d in shape:
        n *= d
    if _numba():  # resolves the kernels first: on a cold cache, their twin
        return n >= PARALLEL_MIN_SIZE
    if n >= PARALLEL_MIN_SIZE and _TWIN and NUMBA:
        _compiled()  # rent or buy: a batch this large pays for compiling the kernels
        return True
    return False
