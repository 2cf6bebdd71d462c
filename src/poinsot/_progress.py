"""Progress reports and Ctrl-C for long compiled calls (private).

A compiled loop (numba, ``nogil=True``) cannot be interrupted: the interpreter runs a
signal handler only between bytecodes. Every kernel checks a shared cancel flag once
per step; :func:`run_compiled` raises it on Ctrl-C in one of two ways:

* **In the calling thread** (no progress asked for, the main thread, Python's own
  SIGINT handler in place, POSIX): for the call, SIGINT goes to a three-instruction
  native handler (:class:`_SigintFlag`, built once with llvmlite) that stores 1 into
  the flag; the previous handler is restored afterwards, bit for bit, and
  ``KeyboardInterrupt`` raised if the signal came. The kernel keeps numba's thread
  team of the calling thread: a worker thread would start a new OpenMP team each call,
  and the old team's spinning threads compete with it for the cores (measured: 10,000
  free bodies took 20-25 % longer that way on 2 cores).
* **In a worker thread** otherwise: the calling thread stays in Python, waking every
  ``poll`` seconds to report progress; on ``KeyboardInterrupt`` it raises the flag and
  waits for the worker to stop (one step: milliseconds).

Ctrl-C while numba compiles the kernel (a cold cache) stops the call at once too: while
the main thread compiles, the native handler also makes Python's SIGINT pending, which
the compiler's Python code raises; a worker thread that is compiling is not waited for
(it finishes the compilation, which numba caches, and its kernel stops at the first
step).

Either way nothing partial is returned and no kernel is left running. The kernel's
arithmetic is untouched: results are bit-identical with or without it.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from ._jit import MAIN_COMPILING, NUMBA, compiling
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
    """``kernel(*args)``, interruptible by Ctrl-C: in the calling thread with the
    native SIGINT flag when it can be (module notes), else in a worker thread.

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
    if progress is None:
        flag = _sigint_flag()
        if flag is not None:
            cancel[0] = 0
            with flag.raising(cancel):
                return kernel(*args)
    out: dict[str, Any] = {}

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

        if compiling(worker.ident):
            # numba is compiling the kernel (a cold cache: up to minutes) and cannot be
            # stopped: the daemon thread finishes the compilation (and caches it) on its
            # own; its kernel then sees the flag at its first step and returns
            if progress is not None:
                progress.close()
            raise
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


class _SigintFlag:
    """SIGINT as a store of 1 into a cancel flag, for a compiled call in the main thread.

    The handler is native code (an async-signal-safe store through a pointer slot),
    compiled once per process with llvmlite's JIT, which numba already loads: a Python
    handler cannot run while the main thread is inside the kernel, and a numba
    ``cfunc`` would cost a compile per process for three instructions.
    """

    def __init__(self) -> None:
        import ctypes

        import llvmlite.binding as llvm

        self._slot = np.zeros(1, dtype=np.int64)  # the address of the current flag
        # ... and, while the main thread compiles (poinsot._jit.MAIN_COMPILING: Python
        # code, minutes on a cold cache), Python's own SIGINT made pending
        # (PyErr_SetInterruptEx is documented async-signal-safe), so that the compiler
        # raises KeyboardInterrupt at once; never while the kernel runs (its boxing calls
        # into Python, which must not find an exception set)

        interrupt = ctypes.cast(ctypes.pythonapi.PyErr_SetInterruptEx, ctypes.c_void_p).value
        ir = f"""
        define void @poinsot_sigint(i32 %sig) {{
          %slot = inttoptr i64 {self._slot.ctypes.data} to i64**
          %flag = load volatile i64*, i64** %slot
          store volatile i64 1, i64* %flag
          %cp = inttoptr i64 {MAIN_COMPILING.ctypes.data} to i64*
          %c = load volatile i64, i64* %cp
          %busy = icmp ne i64 %c, 0
          br i1 %busy, label %raise, label %done
        raise:
          %fn = inttoptr i64 {interrupt} to i32 (i32)*
          %r = call i32 %fn(i32 %sig)
          br label %done
        done:
          ret void
        }}
        """
        llvm.initialize_native_target()
        llvm.initialize_native_asmprinter()
        module = llvm.parse_assembly(ir)
        module.verify()
        machine = llvm.Target.from_default_triple().create_target_machine()
        self._engine = llvm.create_mcjit_compiler(module, machine)  # kept: owns the code
        self._engine.finalize_object()
        self._handler = ctypes.c_void_p(self._engine.get_function_address("poinsot_sigint"))
        libc = ctypes.CDLL(None, use_errno=True)
        self._signal = libc.signal
        self._signal.argtypes = [ctypes.c_int, ctypes.c_void_p]
        self._signal.restype = ctypes.c_void_p
        self._sigaction = libc.sigaction
        self._sigaction.argtypes = [ctypes.c_int, ctypes.c_void_p, ctypes.c_void_p]
        self._sigaction.restype = ctypes.c_int
        # the previous `struct sigaction`, kept opaque (no platform's is over 256 bytes)
        self._old = ctypes.create_string_buffer(512)

    def install(self, cancel: np.ndarray) -> bool:
        """Route SIGINT to ``cancel[0] = 1``; ``False`` (nothing changed) if the current
        disposition cannot be read."""
        self._slot[0] = cancel.ctypes.data
        if self._sigaction(signal.SIGINT, None, self._old) != 0:
            return False
        self._signal(signal.SIGINT, self._handler)
        return True

    def restore(self) -> None:
        """Put back the exact disposition :meth:`install` found (Python's handler)."""
        self._sigaction(signal.SIGINT, self._old, None)

    def raising(self, cancel: np.ndarray) -> _Raising:
        return _Raising(self, cancel)


class _Raising:
    """``with flag.raising(cancel):`` SIGINT sets ``cancel[0]`` during the block, and
    ``KeyboardInterrupt`` is raised at its end if it did (as Python would have)."""

    def __init__(self, flag: _SigintFlag, cancel: np.ndarray) -> None:
        self._flag, self._cancel, self._on = flag, cancel, False

    def __enter__(self) -> None:
        self._on = self._flag.install(self._cancel)

    def __exit__(self, *exc: object) -> None:
        if self._on:
            self._flag.restore()
        if self._cancel[0] != 0 and exc[0] is None:
            raise KeyboardInterrupt


_FLAG: list[_SigintFlag | None] = []  # built on first use; [None] if it cannot be


def _sigint_flag() -> _SigintFlag | None:
    """The native SIGINT flag when a compiled call may run in this thread (module notes),
    else ``None`` (the caller takes the worker thread)."""
    if (
        os.name != "posix"
        or threading.current_thread() is not threading.main_thread()
        or signal.getsignal(signal.SIGINT) is not signal.default_int_handler
    ):
        return None

    if not NUMBA:  # the NumPy executor's kernels are Python: keep the worker thread
        return None
    if not _FLAG:
        try:
            _FLAG.append(_SigintFlag())
        except Exception:  # pragma: no cover - no llvmlite JIT or libc here
            _FLAG.append(None)
    return _FLAG[0]


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
