"""``poinsot check``: validate a scenario file and estimate the cost of its run."""

from __future__ import annotations

import argparse

from ..scenarios import describe_scenario, estimate_cost, load_scenario
from ._common import _Usage, add_allow_large, add_allow_paths
from ._runs import _compile_note

DESCRIPTION = "Validate a TOML scenario file without running it."
EPILOG = """\
example:
  poinsot check examples/symmetric_top.toml

Exit code 0 if the file is a valid scenario, 2 with a message naming the file,
the key and its line otherwise.
"""


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("scenario", metavar="SCENARIO.toml")
    p.add_argument("--quiet", action="store_true", help="print nothing when valid")
    p.add_argument("--duration", type=float, metavar="SECONDS", help="check with this duration (s)")
    add_allow_large(p)
    add_allow_paths(p)
    p.set_defaults(func=_cmd_check)


def _cmd_check(args: argparse.Namespace) -> int:
    scenario = load_scenario(args.scenario, allow_paths=args.allow_paths)
    cost = estimate_cost(scenario, duration=args.duration)
    problems = cost.problems(allow_large=args.allow_large)
    if problems:
        raise _Usage(
            f"{args.scenario}: valid, but `poinsot run` would refuse it: "
            + "; ".join(problems)
            + "."
        )
    if not args.quiet:
        print(f"ok: {args.scenario}: {describe_scenario(scenario)}", flush=True)
        # what `run` does: both methods (an adaptive one timed on a short piece) and
        # the outputs
        with _compile_note(quiet=False):
            cost = estimate_cost(scenario, duration=args.duration, measure=True, outputs=True)
        print(f"{cost.describe()} (rough; limits in docs/cli.md)")
    return 0
