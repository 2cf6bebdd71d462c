"""Scenario files: describe a rigid body and its motion in TOML, run it, write outputs.

- :func:`load_scenario` / :func:`parse_scenario`: read and validate a file into a
  frozen :class:`Scenario` (errors name the file, key and line);
- :func:`simulate_scenario`: solve it with the library (exact solution, Euler's
  equations or attitude propagation);
- :func:`run_scenario` / :func:`write_outputs`: write ``trajectory.csv``,
  ``summary.json``, figures and ``report.html`` atomically.

The format is documented in ``docs/cli.md``; ``examples/*.toml`` are worked cases
and :func:`demo_scenario` is the embedded tennis-racket flip run by ``poinsot demo``.
"""

from __future__ import annotations

from ._toml import ScenarioError
from .io import SHAPES, demo_scenario_text, load_scenario, parse_scenario
from .run import (
    CONVENTIONS,
    ScenarioResult,
    prepare_output_dir,
    run_scenario,
    simulate_scenario,
    write_outputs,
)
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

__all__ = [
    "AngularVelocitySpec",
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
