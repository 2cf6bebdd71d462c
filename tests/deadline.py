"""A guard that fails a test instead of letting it hang (issue 38's hangs).

``with deadline(60): ...`` raises :class:`Hung` after 60 s. SciPy's step loop is Python,
so the alarm's handler runs inside it; ``Hung`` is not an ``Exception``, so nothing on
the way (the CLI's catch-all) turns it into a result. Skips where there is no SIGALRM.
"""

from __future__ import annotations

import contextlib
import signal
from collections.abc import Iterator

import pytest


class Hung(BaseException):
    """Raised by :func:`deadline` when the guarded block runs too long."""


@contextlib.contextmanager
def deadline(seconds: int) -> Iterator[None]:
    if not hasattr(signal, "SIGALRM"):
        pytest.skip("no SIGALRM to guard a hang with")

    def hung(*_: object) -> None:
        raise Hung(f"still running after {seconds} s")

    old = signal.signal(signal.SIGALRM, hung)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
