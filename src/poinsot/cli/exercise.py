"""``poinsot exercise``: exercises with worked solutions (issue 46). Light: NumPy and
poinsot's numeric API (no SymPy or Matplotlib)."""

from __future__ import annotations

import argparse

from ..exercises import EXERCISE_TYPES, generate, render
from ._common import _Usage

DESCRIPTION = (
    "Generate exercises of theoretical mechanics with worked solutions, each step citing "
    "docs/theory.md; the answer is computed twice (the solution's own formulas and "
    "poinsot's API), and typical mistakes are listed with the answers they give."
)
EPILOG = """\
formats:
  md      Markdown with $...$ math         html    a self-contained HTML page
  tex     a LaTeX article body             moodle  a Moodle XML quiz (numerical questions)
--count K gives the exercises of seeds N, N+1, ..., N+K-1 (the same seed, the same exercise).

examples:
  poinsot exercise --list
  poinsot exercise composition --seed 1
  poinsot exercise composite-inertia --seed 5 --count 10 --format moodle > quiz.xml
"""

MAX_COUNT = 1000


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("type", metavar="TYPE", nargs="?", help="the problem type (see --list)")
    p.add_argument("--seed", type=int, default=0, metavar="N", help="first seed (default 0)")
    p.add_argument(
        "--count", type=int, default=1, metavar="K", help="number of exercises (default 1)"
    )
    p.add_argument(
        "--format",
        default="md",
        choices=("md", "html", "tex", "moodle"),
        help="output format (default md)",
    )
    p.add_argument("--list", action="store_true", help="list the problem types and exit")
    p.set_defaults(func=_cmd_exercise)


def _cmd_exercise(args: argparse.Namespace) -> int:
    if args.list:
        width = max(len(k) for k in EXERCISE_TYPES)
        for name, what in EXERCISE_TYPES.items():
            print(f"{name:<{width}}  {what}")
        return 0
    if args.type is None:
        raise _Usage("exercise: TYPE is required (one of " + ", ".join(EXERCISE_TYPES) + ").")
    if args.type not in EXERCISE_TYPES:
        raise _Usage(
            f"exercise: unknown TYPE {args.type!r}: expected one of "
            + ", ".join(EXERCISE_TYPES)
            + " (poinsot exercise --list)."
        )
    if args.seed < 0:
        raise _Usage(f"exercise: --seed must be >= 0, found {args.seed}.")
    if not 1 <= args.count <= MAX_COUNT:
        raise _Usage(f"exercise: --count must be between 1 and {MAX_COUNT}, found {args.count}.")
    exercises = [generate(args.type, args.seed + k) for k in range(args.count)]
    print(render(exercises, args.format), end="")
    return 0
