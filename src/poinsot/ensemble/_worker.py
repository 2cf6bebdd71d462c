"""Preloaded by the worker processes of a local Dask cluster that poinsot starts.

Ctrl-C in a terminal sends SIGINT to the whole foreground process group, so the
worker processes receive it too: each printed a ``KeyboardInterrupt`` traceback
and Dask's ``CancelledError`` lines over the command's own message. They ignore
it here; the process that started them stops them (see ``engine._stop``).
"""

from __future__ import annotations

import signal
import threading
from typing import Any


def _ignore_sigint() -> None:
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.SIG_IGN)


_ignore_sigint()  # at import, as early as the worker reads its preloads


def dask_setup(worker: Any) -> None:
    """Dask's preload hook (the import above has done the work)."""
    _ignore_sigint()
