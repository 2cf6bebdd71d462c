"""The ``poinsot`` command: thin wrappers around library functions.

Subcommands: ``run`` (a scenario file), ``demo`` (the embedded tennis-racket flip),
``check`` (validate a scenario and estimate its cost), ``convert`` (between rotation
representations), ``inertia`` (inertia tensor of a solid), ``ensemble`` (a Monte-Carlo
ensemble), ``verify`` (an engine against exact solutions), ``exercise`` (exercises with worked
solutions). Exit codes: 0 success,
2 invalid input, a run refused by its limits or a diverging integration (a
one-line message with advice, no traceback), 1 a failure: a verdict of failure with
its outputs written (``verify`` FAIL; ``ensemble``: more than ``--max-failed`` of the
samples failed) or an unexpected failure (a bug; traceback with ``--debug``), 130
interrupted (Ctrl-C; ``ensemble`` says how many chunks are kept for ``--resume``). The
scenario format and every option are documented in ``docs/cli.md``.

Examples
--------
>>> from poinsot.cli import main
>>> main(["convert", "euler:ZXZ", "quat", "90", "0", "0", "--degrees"])
0.70710678 0 0 0.70710678
0
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
import traceback
import warnings
from collections.abc import Iterable
from typing import Any

from .. import __version__
from ..errors import IntegrationError, InvalidInputError, InvalidTypeError, PoinsotWarning
from ._common import PROG, _error, _Usage
from ._common import ProgressBar as ProgressBar  # the progress bar of `run` and `demo`

__all__ = ["main", "build_parser"]

#: The commands, in the order of ``poinsot --help``, with their one-line help. Each is the
#: module of this package of the same name (``poinsot.cli.run``...): its ``DESCRIPTION``,
#: ``EPILOG``, ``add_arguments(parser)`` (which sets ``func``, the command) and the command
#: itself. This table is the one place that imports them, and only the command given:
#: ``poinsot --help`` and ``poinsot convert`` load no scenario, numba, SciPy or Matplotlib.
COMMANDS: dict[str, str] = {
    "run": "run a scenario file",
    "demo": "run the embedded tennis-racket flip",
    "check": "validate a scenario file",
    "convert": "convert a rotation between representations",
    "inertia": "inertia tensor and principal axes of a solid",
    "ensemble": "Monte-Carlo ensemble of a dispersed scenario (Dask)",
    "verify": "check a physics engine against exact solutions",
    "warmup": "compile every kernel into numba's cache (once per install)",
    "exercise": "exercises with worked solutions (md, html, tex, Moodle XML)",
}


class _Formatter(argparse.RawDescriptionHelpFormatter):
    pass


def build_parser(commands: Iterable[str] | None = None) -> argparse.ArgumentParser:
    """The argument parser of the ``poinsot`` command.

    With ``commands``, only these commands get their arguments (their modules are
    imported); the others are listed by name and help, which is all ``poinsot --help``
    shows and all a command line naming one of ``commands`` needs.
    """
    selected = set(COMMANDS if commands is None else commands)
    parser = argparse.ArgumentParser(
        prog=PROG,
        description="Kinematics and dynamics of rigid bodies, built on quaternions.",
        epilog="example: poinsot demo    (run `poinsot COMMAND --help` for each command)",
        formatter_class=_Formatter,
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    parser.add_argument(
        "--debug", action="store_true", help="show the full traceback of unexpected errors"
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, help in COMMANDS.items():
        if name not in selected:
            sub.add_parser(name, help=help, formatter_class=_Formatter)
            continue
        module = importlib.import_module(f"{__name__}.{name}")
        p = sub.add_parser(
            name,
            help=help,
            description=module.DESCRIPTION,
            epilog=module.EPILOG,
            formatter_class=_Formatter,
        )
        # every subcommand also accepts --debug after its own arguments (hidden)
        p.add_argument(
            "--debug", action="store_true", default=argparse.SUPPRESS, help=argparse.SUPPRESS
        )
        module.add_arguments(p)
    return parser


def _named(argv: list[str]) -> list[str]:
    """The command named in ``argv`` (its first word that is not an option), if any."""
    for word in argv:
        if not word.startswith("-"):
            return [word] if word in COMMANDS else []
    return []


def main(argv: list[str] | None = None) -> int:
    """Run the ``poinsot`` command with ``argv`` (default ``sys.argv[1:]``).

    Returns the exit code: 0 success, 2 invalid input (also a run refused by its
    limits, or an integration that diverged), 1 a failure: a verdict of failure
    (``verify`` FAIL, ``ensemble`` over ``--max-failed``) or an unexpected one (a bug),
    130 interrupted (Ctrl-C).
    """
    argv = sys.argv[1:] if argv is None else list(argv)
    debug = "--debug" in argv
    try:
        parser = build_parser(_named(argv))
        try:
            args = parser.parse_args(argv)
        except SystemExit as exc:  # --help, --version, or a usage error (code 2)
            return int(exc.code or 0) if not isinstance(exc.code, str) else 2
        debug = debug or getattr(args, "debug", False)
        seen: set[str] = set()
        original = warnings.showwarning

        def show(
            message: Any,
            category: type[Warning],
            filename: str,
            lineno: int,
            file: Any = None,
            line: str | None = None,
        ) -> None:
            if issubclass(category, PoinsotWarning):
                text = f"{PROG}: warning: {message}"
                if text not in seen:  # the same warning once, however often it is issued
                    seen.add(text)
                    print(text, file=sys.stderr)
            else:
                original(message, category, filename, lineno, file, line)

        with warnings.catch_warnings():
            warnings.simplefilter("always", PoinsotWarning)
            warnings.showwarning = show
            return args.func(args)
    except (_Usage, InvalidInputError, InvalidTypeError) as exc:
        if debug:
            traceback.print_exc()
        _error(str(exc))
        return 2
    except IntegrationError as exc:  # a valid input the chosen method cannot handle
        if debug:
            traceback.print_exc()
        advice = getattr(exc, "advice", None) or (
            'set a shorter [simulation] max_step, or method = "adaptive" '
            "(docs/cli.md, 'Accuracy')."
        )
        _error(f"the integration failed: {exc} Advice: {advice}")
        return 2
    except KeyboardInterrupt:
        print(f"\n{PROG}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # e.g. `poinsot convert ... | head` (an OSError: caught first)
        try:
            sys.stdout = open(os.devnull, "w")  # noqa: SIM115 - no flush error at exit
        except OSError:
            pass
        return 0
    except OSError as exc:  # an output that cannot be written (permissions, disk full...)
        if debug:
            traceback.print_exc()
        where = f": {exc.filename}" if getattr(exc, "filename", None) else ""
        _error(f"cannot write the outputs{where}: {exc.strerror or exc}.")
        return 2
    except Exception as exc:
        if debug:
            traceback.print_exc()
        _error(
            f"unexpected failure: {type(exc).__name__}: {exc}"
            + ("" if debug else " (run with --debug for the traceback)")
        )
        return 1
