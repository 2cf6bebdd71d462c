"""Progress reports and Ctrl-C for long compiled calls (private).

A compiled loop (numba, ``nogil=True``) cannot be interrupted: the interpreter runs a
signal handler only between bytecodes. So :func:`run_compiled` runs the kernel in a
worker thread and keeps the calling thread in Python, waking every ``poll`` seconds
to report progress; on ``KeyboardInterrupt`` it raises a shared cancel flag that the
kernel checks once per step, waits for the worker to stop (one step: milliseconds)
and re-raises, so nothing partial is returned and no thread is left running. The
kernel's arithmetic is untouched: results are bit-identical with or without it.
"""

from __future__ import annotations

import sys
import threading
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from .errors import InvalidTypeError

__all__ = ["as_progress", "run_compiled", "Progress", "in_chunks", "ivp_progress", "CHUNK"]

#: samples per chunk when an exact solution is evaluated on a large grid: a chunk takes
#: tens of milliseconds, the latency of Ctrl-C (handled between chunks) and of the bar
CHUNK = 1 << 16

#: ``progress=`` as the public functions take it: None/False (nothing), True (a bar),
#: or a callable receiving the fraction done in [0, 1].
Progress = bool | Callable[[float], object] | None


class _Report:
    """``progress=`` made one callable: a tqdm bar (terminals and notebooks) or, without
    tqdm, a plain stderr line every 10 % (``progress=True``), or the user's callable;
    fractions only ever increase, and :meth:`finish` reports 1 once and closes a bar."""

    def __init__(self, fn: Callable[[float], object] | None, desc: str) -> None:
        self._fn = fn
        self._desc = desc
        self._tqdm: Any = None
        self.last = -1.0
        if fn is None:
            try:
                from tqdm.auto import tqdm
            except ImportError:
                pass
            else:
                self._tqdm = tqdm(total=1000, desc=desc, leave=False)

    def __call__(self, fraction: float) -> None:
        f = min(max(float(fraction), 0.0), 1.0)
        if f <= self.last:
            return
        if self._fn is not None:
            self._fn(f)
        elif self._tqdm is not None:
            self._tqdm.update(int(1000 * f) - int(1000 * max(self.last, 0.0)))
        elif int(10 * f) != int(10 * max(self.last, 0.0)) or f == 1.0:  # whole lines
            print(f"{self._desc}: {int(100 * f)}%", file=sys.stderr, flush=True)
        self.last = f

    def finish(self) -> None:
        if self.last < 1.0:
            self(1.0)
        self.close()

    def close(self) -> None:
        if self._tqdm is not None:
            self._tqdm.close()
            self._tqdm = None


def as_progress(progress: object, desc: str) -> _Report | None:
    """The reporter behind ``progress=`` (None when nothing is reported).

    >>> as_progress(None, "simulate") is None
    True
    >>> seen = []
    >>> report = as_progress(seen.append, "simulate")
    >>> report(0.5); report(0.25); report.finish(); seen
    [0.5, 1.0]
    """
    if progress is None or progress is False:
        return None
    if progress is True:
        return _Report(None, desc)
    if callable(progress):
        return _Report(progress, desc)
    raise InvalidTypeError(
        "Expected `progress` to be None, a bool or a callable taking the fraction done, "
        f"got {type(progress).__name__}."
    )


def run_compiled(
    kernel: Callable[..., Any],
    args: tuple[Any, ...],
    *,
    cancel: np.ndarray,
    done: np.ndarray | None = None,
    total: float = 1.0,
    progress: _Report | None = None,
    poll: float = 0.1,
    background: bool = True,
) -> Any:
    """``kernel(*args)`` in a worker thread, interruptible by Ctrl-C.

    ``cancel`` (1,) int64 is set to 1 on ``KeyboardInterrupt`` (the kernel must stop
    soon after it sees it); ``done`` (any shape, int64) is summed and divided by
    ``total`` for ``progress``. Exceptions of the kernel are re-raised here; the
    numba thread count of the caller is carried into the worker (it is per thread).
    ``background=False`` (a call known to be short: a thread and its OpenMP team
    cost ~0.1-2 ms) runs it here, unless progress is asked for.
    """
    if not background and progress is None:
        cancel[0] = 0
        return kernel(*args)
    out: dict[str, Any] = {}
    from ._jit import NUMBA

    if NUMBA:
        import numba

        threads = int(numba.get_num_threads())

    # An Event, not Thread.join: a join interrupted by Ctrl-C can leave is_alive() False
    # while the thread still runs (CPython gh-90882).
    finished = threading.Event()

    def work() -> None:
        try:
            if NUMBA:
                numba.set_num_threads(threads)
            out["value"] = kernel(*args)
        except BaseException as exc:  # re-raised in the caller's thread
            out["error"] = exc
        finally:
            finished.set()

    worker = threading.Thread(target=work, name="poinsot-kernel", daemon=True)
    cancel[0] = 0
    try:
        worker.start()
        while not finished.wait(poll):
            if progress is not None and done is not None:
                progress(min(float(done.sum()) / total, 1.0))
    except KeyboardInterrupt:
        cancel[0] = 1
        t0 = time.monotonic()
        while time.monotonic() - t0 < 60.0:
            try:
                if finished.wait(0.05):
                    break
            except KeyboardInterrupt:  # a second Ctrl-C while the kernel winds down
                continue
        worker.join(1.0)
        if progress is not None:
            progress.close()
        raise
    if "error" in out:
        raise out["error"]
    return out.get("value")


def in_chunks(
    fn: Callable[[np.ndarray], tuple[np.ndarray, ...]],
    t: np.ndarray,
    progress: object,
    desc: str,
    *,
    axis: int = 0,
    chunk: int = CHUNK,
) -> tuple[np.ndarray, ...]:
    """``fn(t)`` evaluated chunk by chunk of the 1-D grid ``t`` when it is large or
    progress is asked for; the arrays ``fn`` returns are joined along ``axis`` (the
    time axis).

    Between chunks the interpreter runs, so Ctrl-C stops a long evaluation within one
    chunk (``KeyboardInterrupt``, nothing partial returned) and ``progress`` reports
    the fraction of samples done. Where ``fn`` computes each sample on its own (the
    elliptic solutions) the result is bit-identical to one call on the whole grid; an
    iteration run to round-off over the whole array (Kepler's equation) may differ in
    the last bit.

    >>> import numpy as np
    >>> seen = []
    >>> (s,) = in_chunks(lambda t: (np.sin(t),), np.linspace(0, 1, 10), seen.append, "x", chunk=4)
    >>> bool(np.array_equal(s, np.sin(np.linspace(0, 1, 10)))), seen
    (True, [0.4, 0.8, 1.0])
    """
    report = as_progress(progress, desc)
    if report is None and t.size <= chunk:
        return fn(t)
    parts = []
    try:
        for k in range(0, max(t.size, 1), chunk):
            parts.append(fn(t[k : k + chunk]))
            if report is not None:
                report(min(k + chunk, t.size) / max(t.size, 1))
    except BaseException:
        if report is not None:
            report.close()
        raise
    if report is not None:
        report.finish()
    return tuple(np.concatenate([p[i] for p in parts], axis=axis) for i in range(len(parts[0])))


def ivp_progress(
    fun: Callable[..., Any],
    t0: float,
    t1: float,
    report: Callable[[float], object] | None,
    poll: float = 0.1,
) -> Callable[..., Any]:
    """``fun(t, y, ...)`` for ``solve_ivp`` that reports ``(t - t0) / (t1 - t0)`` at most
    every ``poll`` seconds (``fun`` itself when nothing is reported). The solver's loop
    is Python, so Ctrl-C already stops it between steps."""
    if report is None:
        return fun
    span = (t1 - t0) or 1.0
    last = [time.monotonic()]

    def wrapped(t: float, y: Any, *args: Any) -> Any:
        now = time.monotonic()
        if now - last[0] >= poll:
            last[0] = now
            report((t - t0) / span)
        return fun(t, y, *args)

    return wrapped
