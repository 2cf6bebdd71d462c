"""``poinsot demo``: run the embedded tennis-racket flip."""

from __future__ import annotations

import argparse
from pathlib import Path

from ..rotations.rotation import Rotation
from ..scenarios import demo_scenario
from ._common import PROG, _nums, add_run_options
from ._runs import _default_out, _print_result, _refuse_large, _run_with_progress

DESCRIPTION = "Run the embedded demo scenario (the tennis-racket flip)."
EPILOG = """\
example:
  poinsot demo
  poinsot demo --out /tmp/demo --force

Runs the embedded tennis-racket flip (spin about the intermediate axis) twice,
with the exact solution and with a numerical integrator, and writes the same
outputs as `poinsot run`. Without --out a fresh ./poinsot-out/tennis-racket-flip[-N]
directory is used, so the demo never overwrites earlier results.
"""


def add_arguments(p: argparse.ArgumentParser) -> None:
    add_run_options(p)
    p.set_defaults(func=_cmd_demo)


def _cmd_demo(args: argparse.Namespace) -> int:
    scenario = demo_scenario()
    _refuse_large(scenario, args)
    if args.out:
        out = Path(args.out)
    else:
        # the default directory is never overwritten: a new one is numbered instead
        out = _default_out(scenario.name)
        k = 1
        while not args.force and out.exists() and (not out.is_dir() or any(out.iterdir())):
            k += 1
            out = _default_out(f"{scenario.name}-{k}")
    result, files = _run_with_progress(scenario, out, args)
    a = Rotation.from_axis_angle([1.0, 0.0, 0.0], 90.0, degrees=True)
    b = Rotation.from_axis_angle([0.0, 1.0, 0.0], 90.0, degrees=True)
    rows = "; ".join(" ".join(_nums(row)) for row in (b * a).as_matrix())
    tour = (
        "composition (docs/theory.md §4): A = 90 deg about x, then B = 90 deg about y, both about "
        f"fixed axes: B * A = C = [{rows}]",
    )
    _print_result(result, out, files, quiet=args.quiet, title=f"{PROG} demo", extra=tour)
    return 0
