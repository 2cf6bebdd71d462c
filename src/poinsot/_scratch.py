"""Per-thread scratch arrays reused from call to call (private).

A compiled batch call packs its inputs into arrays that live only for the call (the
bodies' states, ``J^-1``, counters). Freshly allocated, arrays of 128 KiB to a few MiB
come from the top of glibc's heap, which ``free`` may give back to the operating system
once the call is over: the next call then touches new pages, and every 4 KiB page costs
a page fault. On the 2-core KVM machine of ``docs/performance.md`` a fault costs about
4 us, and a
``simulate`` call on 10,000 free bodies took 750-1100 of them: 3-4 ms of a 14-20 ms
call (measured; arrays of 4 MiB and more get transparent huge pages from NumPy and fault
far less). Arrays taken from here are kept by the thread that asked for them, so a call
on the same sizes touches no new page.

Contract: the contents are undefined (the caller fills them); an array is valid until
its thread's next :func:`hold` for the same ``name``; a thread that is inside a
:func:`hold` block (a progress callback that calls ``simulate`` again) gets fresh
arrays instead; a block left by an exception (Ctrl-C: its kernel may still be running
in a worker thread) drops the thread's arrays; arrays larger than :data:`MAX_BYTES` are
never kept.
"""

from __future__ import annotations

import contextlib
import threading
from collections.abc import Iterator
from typing import Any

import numpy as np

#: Largest array kept (bytes): NumPy asks for transparent huge pages from 4 MiB on, so a
#: fresh array that large faults once per 2 MiB, not per 4 KiB; and a kept one pins its
#: memory for the life of the thread (at most a few arrays of this size per thread).
MAX_BYTES = 4 << 20

_local = threading.local()


class _Scratch:
    """The arrays one :func:`hold` block hands out (``kept``: from the thread's store)."""

    def __init__(self, store: dict[str, np.ndarray] | None) -> None:
        self._store = store

    def empty(self, name: str, shape: tuple[int, ...], dtype: Any = np.float64) -> np.ndarray:
        """An uninitialised array of ``shape``: the thread's kept array ``name`` when it
        fits (reshaped view of it), else a fresh one (then kept for next time)."""
        dt = np.dtype(dtype)
        size = int(np.prod(shape, dtype=np.int64))
        nbytes = size * dt.itemsize
        if self._store is None or nbytes > MAX_BYTES:
            return np.empty(shape, dtype=dt)
        buf = self._store.get(name)
        if buf is None or buf.dtype != dt or buf.size < size:
            buf = np.empty(size, dtype=dt)
            self._store[name] = buf
        return buf[:size].reshape(shape)

    def zeros(self, name: str, shape: tuple[int, ...], dtype: Any = np.float64) -> np.ndarray:
        """:meth:`empty`, zeroed."""
        a = self.empty(name, shape, dtype)
        a.fill(0)
        return a


@contextlib.contextmanager
def hold() -> Iterator[_Scratch]:
    """The calling thread's scratch arrays for the duration of the block (fresh arrays
    when the thread is already inside one: re-entry must not overwrite them).

    >>> with hold() as s:
    ...     a = s.zeros("demo", (2, 3))
    >>> with hold() as s:
    ...     b = s.empty("demo", (3, 2))
    >>> bool(np.shares_memory(a, b)), b.shape
    (True, (3, 2))
    """
    store = getattr(_local, "store", None)
    if store is None:
        store = _local.store = {}
    if getattr(_local, "busy", False):
        yield _Scratch(None)
        return
    _local.busy = True
    try:
        yield _Scratch(store)
    except BaseException:
        # a kernel interrupted by Ctrl-C may still be writing them in its worker thread
        _local.store = {}
        raise
    finally:
        _local.busy = False
