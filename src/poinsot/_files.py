"""Atomic file writes: the one writer every output goes through (private).

:func:`atomic_write` writes a file in full under a temporary name in the same
directory, flushes it to disk and renames it over ``path`` (``os.replace``, atomic on
POSIX and Windows): a reader sees the old file or the new one, never half of one, and a
write that fails (an exception in the callback, Ctrl-C, a full disk) leaves the old
file as it was and no temporary file behind. Standard library only.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

__all__ = ["atomic_write"]


def atomic_write(path: str | Path, write: Callable[[Any], object], mode: str = "w") -> Path:
    """Write ``path`` through ``write(fh)`` on a temporary file, then rename it over.

    Parameters
    ----------
    path : str or Path
        The file to (re)write; its directory must exist.
    write : callable
        Called once with the open temporary file.
    mode : {"w", "b"}
        ``"w"``: text, UTF-8 with ``"\\n"`` line ends; anything else (``"b"``): binary.

    Returns
    -------
    Path
        ``path``. The file has the permissions of a new file (umask), as ``open`` gives.

    Examples
    --------
    >>> import tempfile
    >>> p = Path(tempfile.mkdtemp()) / "a.txt"
    >>> atomic_write(p, lambda fh: fh.write("one\\n")).read_text()
    'one\\n'
    """
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.partial")
    try:
        with (
            open(tmp, "w", encoding="utf-8", newline="\n") if mode == "w" else open(tmp, "wb")
        ) as fh:
            write(fh)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path
