"""Running a scenario for ``run``, ``demo`` and ``check``: the limits, the compile note,
the progress bar and the text printed after a run. Imports the scenarios (and numba):
loaded only by those commands."""

from __future__ import annotations

import argparse
import contextlib
import sys
from pathlib import Path
from typing import Any

from .._jit import NUMBA, compile_estimate, mute_compile_notice, say_seconds
from ..scenarios import run_scenario
from ..scenarios.describe import describe
from ..scenarios.solve import check_cost
from ._common import PROG, ProgressBar, _warn


def _default_out(name: str) -> Path:
    return Path("poinsot-out") / name


def _print_result(
    result: Any,
    out: Path,
    files: Any,
    *,
    quiet: bool,
    title: str,
    extra: Any = (),
) -> None:
    acc = result.summary["accuracy"]
    for w in acc["warnings"]:  # on stderr, also with --quiet: results may be poor
        _warn(f"accuracy: {w}")
    if acc["warnings"]:
        if acc["suggested_max_step"]:
            _warn(
                f"suggestion: set [simulation] max_step = {acc['suggested_max_step']:g} s "
                f"(the integration step is {acc['integration_step']:g} s; thresholds in "
                "docs/cli.md, 'Accuracy')"
            )
        elif acc["integration_step"] is not None:
            _warn("suggestion: a shorter `step` or `max_step` (docs/cli.md, 'Accuracy')")
        else:  # adaptive methods only: their tolerances, or a motion sensitive to its start
            _warn(
                "suggestion: tighter tolerances where the scenario sets them, or a shorter "
                "duration; methods that disagree while each keeps its integrals often mean a "
                "motion sensitive to its initial state (docs/cli.md, 'Accuracy')"
            )
    if quiet:
        return

    text = describe(result, title=title, notes=getattr(files, "notes", ()))
    lines = [
        ln
        for ln in text.splitlines()
        if not ln.startswith(("accuracy warning", "suggestion"))  # already on stderr
    ]
    if acc["warnings"]:
        lines.append(
            f"accuracy: {len(acc['warnings'])} warning(s), on stderr, in summary.json and "
            "report.html"
        )
    print("\n".join(lines))
    for line in extra:
        print(line)
    names = ", ".join(p.name for p in files)
    print(f"outputs: {out}{'/' if not str(out).endswith('/') else ''} ({names})")
    report = [p for p in files if p.name == "report.html"]
    if report:  # the one file to open: said last, as a path a browser takes
        print(f"report: {Path(report[0]).resolve().as_uri()}")


def _run_with_progress(scenario: Any, out: Path, args: argparse.Namespace) -> Any:
    """Run ``scenario`` into ``out`` (already prepared) with the options of ``run``/``demo``."""
    bar = ProgressBar(quiet=args.quiet)
    try:
        with _compile_note(quiet=args.quiet):
            return run_scenario(
                scenario,
                out,
                fmt=args.format,
                report=not args.no_report,
                figures=not args.no_figures,
                force=args.force,
                duration=args.duration,
                progress=bar,
                allow_large=args.allow_large,
            )
    finally:
        bar.close()


class _compile_note:
    """Say "compiling (first run only)" once when numba starts compiling a kernel (a cold
    cache: the first run after an install or an upgrade sits ~10-15 s in compilation);
    a cached kernel is loaded without a word. Listens to numba's ``numba:compile``
    event, which fires for a compilation and not for a load from the cache."""

    said = False

    def __init__(self, quiet: bool) -> None:
        self.quiet = quiet
        self._stack: Any = None

    def __enter__(self) -> _compile_note:
        # the CLI says it in its own words (or not at all, --quiet): not the library too
        self._stack = contextlib.ExitStack()
        self._stack.enter_context(mute_compile_notice())
        if self.quiet or _compile_note.said or not NUMBA:
            return self
        from numba.core import event

        class Listener(event.Listener):
            def on_start(self, ev: Any) -> None:
                if not _compile_note.said:
                    _compile_note.said = True
                    est = say_seconds(compile_estimate((ev.data or {}).get("dispatcher")))
                    print(f"\r{PROG}: compiling (first run only; {est} for the first kernel) ...",
                          file=sys.stderr, flush=True)  # fmt: skip

            def on_end(self, ev: Any) -> None:
                pass

        self._stack.enter_context(event.install_listener("numba:compile", Listener()))
        return self

    def __exit__(self, *exc: object) -> None:
        if self._stack is not None:
            self._stack.close()


def _refuse_large(scenario: Any, args: argparse.Namespace) -> None:
    """Refuse a run beyond the limits before anything is created (exit 2)."""
    check_cost(scenario, duration=args.duration, allow_large=args.allow_large)
