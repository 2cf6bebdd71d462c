"""``poinsot run``: run a scenario file and write its outputs."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from ..errors import IntegrationError
from ..scenarios import load_scenario
from ._common import PROG, add_allow_paths, add_run_options
from ._runs import _default_out, _print_result, _refuse_large, _run_with_progress

DESCRIPTION = "Run a TOML scenario and write its outputs."
EPILOG = """\
example:
  poinsot run examples/tennis_racket.toml --out out/racket --format npz
  poinsot run examples/satellite_torque.toml --duration 5 --no-report --force

Writes trajectory.csv (or .npz), summary.json, PNG figures and report.html into
--out (default ./poinsot-out/<scenario name>). An existing, non-empty output
directory is only overwritten with --force. Scenario format: docs/cli.md.

The integration step of a fixed-step method is the output spacing, unless
[simulation] max_step is shorter. A run beyond the limits (5000000 output
samples; 2 GiB of memory or 5e7 integration steps without --allow-large) is
refused before any work; `poinsot check` prints the estimate. When a conserved
quantity drifts by more than 1e-6 (relative), or the method and the reference
differ by more than 1e-2 rad in attitude or by more than 1e-2 of its scale in any
other state quantity (omega, a particle's position and velocity, each coordinate
and rate), a warning is printed with a suggestion.
"""


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("scenario", metavar="SCENARIO.toml")
    add_run_options(p)
    add_allow_paths(p)
    p.set_defaults(func=_cmd_run)


def _cmd_run(args: argparse.Namespace) -> int:
    scenario = load_scenario(args.scenario, allow_paths=args.allow_paths)
    _refuse_large(scenario, args)
    out = Path(args.out) if args.out else _default_out(scenario.name)
    # run_scenario checks the directory before any work and removes it again if it
    # made it and the run fails
    try:
        result, files = _run_with_progress(scenario, out, args)
    except IntegrationError as exc:
        exc.advice = _advice(scenario)  # type: ignore[attr-defined]
        raise
    _print_result(result, out, files, quiet=args.quiet, title=f"{PROG} run")
    return 0


def _advice(scenario: Any) -> str:
    """What to try after a failed integration, among the methods this kind has."""
    methods = list(getattr(scenario.adapter, "methods", ()))
    used = scenario.simulation.method
    if "adaptive" in methods:
        return (
            'set a shorter [simulation] max_step, or method = "adaptive" '
            "(docs/cli.md, 'Accuracy')."
        )
    others = ", ".join(f'"{m}"' for m in methods if m != used)
    if scenario.kind == "lagrangian":
        return (
            f"a smaller [lagrangian] rtol, or another method of this kind ({others}; a "
            'stiff problem wants "Radau" or "BDF") (docs/cli.md, \'Accuracy\').'
        )
    return (
        f"set a shorter [simulation] max_step, or another method ({others}) "
        "(docs/cli.md, 'Accuracy')."
    )
