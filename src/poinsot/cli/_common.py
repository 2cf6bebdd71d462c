"""What the commands of ``poinsot`` share: the program name, the usage error, the
progress bar, messages on stderr, numbers printed without round-off noise and the
options several commands take. Light: no command module, nothing of numba or SciPy."""

from __future__ import annotations

import argparse
import sys
import time
from typing import Any

from .._display import clean

PROG = "poinsot"


class _Usage(Exception):
    """Invalid command-line input detected by the CLI itself (exit code 2)."""


class ProgressBar:
    """A progress bar on stderr, drawn only on a terminal, after ``delay`` seconds,
    and not when ``quiet``."""

    def __init__(self, *, quiet: bool = False, delay: float = 1.0, stream: Any = None) -> None:
        self.stream = sys.stderr if stream is None else stream
        isatty = getattr(self.stream, "isatty", None)
        self.enabled = not quiet and bool(isatty and isatty())
        self.delay = delay
        self.start = time.monotonic()
        self.shown = False
        self._last = -1.0

    def __call__(self, fraction: float, stage: str) -> None:
        if not self.enabled or time.monotonic() - self.start < self.delay:
            return
        fraction = min(max(float(fraction), 0.0), 1.0)
        now = time.monotonic()
        if self.shown and now - self._last < 0.1 and fraction < 1.0:
            return
        self._last = now
        width = 30
        filled = int(round(width * fraction))
        bar = "#" * filled + "-" * (width - filled)
        elapsed = now - self.start
        self.stream.write(f"\r[{bar}] {100 * fraction:5.1f}% {elapsed:6.1f} s  {stage:<28.28}")
        self.stream.flush()
        self.shown = True

    def close(self) -> None:
        if self.shown:
            self.stream.write("\n")
            self.stream.flush()
            self.shown = False


def _warn(message: str) -> None:
    print(f"{PROG}: warning: {message}", file=sys.stderr)


def _error(message: str) -> None:
    message = str(message).strip()
    print(f"{PROG}: error: {message}", file=sys.stderr)


def _num(x: float) -> str:
    s = f"{x:.15g}"
    return "0" if s in ("0", "-0") else s


def _nums(values: Any, scale: float | None = None) -> list[str]:
    """15 significant digits, round-off noise (below 1e-12 of the largest) as 0."""
    return [_num(x) for x in clean(values, scale)]


def _user_names(message: str, names: dict[str, str]) -> str:
    """Replace the library's argument names (`seq`) by what the user typed."""
    for internal, user in names.items():
        message = message.replace(f"`{internal}`", user)
    return message


# ------------------------------------------------------------------------- options
def add_run_options(p: argparse.ArgumentParser) -> None:
    """The options of a run (``run`` and ``demo``)."""
    p.add_argument(
        "--out", metavar="DIR", help="output directory (default ./poinsot-out/<scenario name>)"
    )
    p.add_argument(
        "--format",
        choices=("csv", "npz"),
        default="csv",
        help="trajectory file format (default csv)",
    )
    p.add_argument("--no-report", action="store_true", help="do not write report.html")
    p.add_argument("--no-figures", action="store_true", help="do not write the PNG figures")
    p.add_argument(
        "--quiet",
        action="store_true",
        help="print nothing on success and hide the progress bar",
    )
    p.add_argument(
        "--force",
        action="store_true",
        help="overwrite the files of an existing output directory",
    )
    p.add_argument(
        "--duration", type=float, metavar="SECONDS", help="override [simulation] duration"
    )
    add_allow_large(p)


def add_allow_paths(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--allow-paths",
        action="store_true",
        help="let the scenario read a mesh file outside its own directory",
    )


def add_allow_large(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--allow-large",
        action="store_true",
        help="run even if the estimated memory (> 2 GiB) or integration steps (> 5e7) "
        "exceed the limits (the limit of 5000000 output samples always holds)",
    )
