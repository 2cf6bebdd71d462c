"""Scenario files: describe a rigid body and its motion in TOML, run it, write outputs.

- :func:`load_scenario` / :func:`parse_scenario` (``io``): read and validate a file
  into a frozen :class:`Scenario` (errors name the file, key and line);
- :func:`estimate_cost` / :func:`simulate_scenario` (``solve``): the cost of a run,
  and the run itself by the scenario's kind (its adapter in ``kinds/``, listed in
  ``registry.KINDS``);
- :class:`ScenarioResult` (``summary``): the trajectories and a summary in sections
  with units; :func:`describe` / :func:`describe_scenario` (``describe``): text;
- :func:`run_scenario` / :func:`write_outputs` (``output``): write
  ``trajectory.csv``, ``summary.json``, figures and ``report.html`` atomically;
  :func:`write_scenario_report` (``report``): ``report.html`` alone, drawn from
  the kind's :class:`ReportSpec` (:meth:`ScenarioKind.report`).

The format is documented in ``docs/cli.md``, the way to add a kind of motion in
``docs/adding-a-motion.md``; ``examples/*.toml`` are worked cases and
:func:`demo_scenario` is the embedded tennis-racket flip run by ``poinsot demo``.
"""

from __future__ import annotations

from ._toml import ScenarioError
from .describe import describe, describe_scenario
from .io import SHAPES, demo_scenario_text, load_scenario, parse_scenario
from .kind import (
    BodyLayer,
    Chart,
    Check,
    Drawing,
    Entry,
    Facts,
    FigureSpec,
    ReportSpec,
    ScenarioKind,
)
from .output import OutputFiles, prepare_output_dir, run_scenario, write_outputs
from .registry import KINDS
from .report import write_scenario_report
from .schema import (
    AngularVelocitySpec,
    AttitudeSpec,
    BodySpec,
    OmegaProfileSpec,
    PartSpec,
    Scenario,
    SimulationSpec,
    TorqueSpec,
)
from .solve import Cost, estimate_cost, simulate_scenario
from .summary import (
    AGREEMENT_THRESHOLD,
    ATTITUDE_THRESHOLD,
    CONVENTIONS,
    DRIFT_THRESHOLD,
    ScenarioResult,
)

__all__ = [
    "AGREEMENT_THRESHOLD",
    "ATTITUDE_THRESHOLD",
    "BodyLayer",
    "Drawing",
    "Chart",
    "ReportSpec",
    "write_scenario_report",
    "AngularVelocitySpec",
    "Check",
    "Cost",
    "DRIFT_THRESHOLD",
    "Entry",
    "Facts",
    "FigureSpec",
    "KINDS",
    "OutputFiles",
    "ScenarioKind",
    "describe",
    "describe_scenario",
    "estimate_cost",
    "AttitudeSpec",
    "BodySpec",
    "CONVENTIONS",
    "OmegaProfileSpec",
    "PartSpec",
    "SHAPES",
    "Scenario",
    "ScenarioError",
    "ScenarioResult",
    "SimulationSpec",
    "TorqueSpec",
    "demo_scenario",
    "demo_scenario_text",
    "load_scenario",
    "parse_scenario",
    "prepare_output_dir",
    "run_scenario",
    "simulate_scenario",
    "write_outputs",
]


def demo_scenario() -> Scenario:
    """The embedded demo scenario (the tennis-racket flip), parsed.

    Examples
    --------
    >>> s = demo_scenario()
    >>> s.name, s.simulation.method, s.simulation.reference
    ('tennis-racket-flip', 'midpoint', 'exact')
    """
    return parse_scenario(
        demo_scenario_text(),
        source="<embedded demo: tennis_racket.toml>",
        name="tennis-racket-flip",
    )


def __dir__() -> list[str]:
    # the public API only (not `annotations` or the submodules' names)
    return sorted(__all__)
