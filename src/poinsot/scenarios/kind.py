"""The contract of a scenario kind: what an adapter module provides.

A *kind* of scenario (a torque-free body, a heavy top, attitude propagation, ...)
is one small adapter module under ``poinsot/scenarios/kinds/`` that defines a
subclass of :class:`ScenarioKind` and one instance of it, registered by one line
in :data:`poinsot.scenarios.registry.KINDS`. The physics stays in the library
(``poinsot.dynamics``, ``poinsot.kinematics``); the adapter only

1. reads its TOML tables (:meth:`ScenarioKind.parse`, with the precise errors of
   :class:`~poinsot.scenarios._toml.Table`),
2. calls the library (:meth:`ScenarioKind.solve` -> the library's own result on
   the output times: a :class:`~poinsot.trajectory.Trajectory` for a rigid body,
   a :class:`~poinsot.trajectory.PointTrajectory` for a particle, a
   :class:`~poinsot.trajectory.CoordinateTrajectory` for generalized
   coordinates; never a result of another kind filled with dummy values),
3. says what is known in closed form (:meth:`ScenarioKind.facts` -> a
   :class:`Facts`, which summarises and describes itself),
4. says which quantities must be conserved or follow a law along the motion
   (:meth:`ScenarioKind.checks` -> :class:`Check` objects, from which the
   accuracy section and the warnings are built), and
5. lists the figures that apply (:meth:`ScenarioKind.figures` ->
   :class:`FigureSpec`, drawn by functions of :mod:`poinsot.plotting`), and
6. says what ``report.html`` shows (:meth:`ScenarioKind.report` -> a
   :class:`ReportSpec`: the scene, the charts, extra HTML sections), rendered by
   the generic :func:`poinsot.plotting.write_report`. :class:`ReportSpec`,
   :class:`BodyLayer`, :class:`Drawing` and :class:`Chart` are defined in
   :mod:`poinsot.plotting.spec` (the renderer's input) and re-exported here.

Everything else (times, overrides, cost limits, progress, the reference run, the
comparison with it on the result's own state, :func:`poinsot.trajectory.compare`,
the summary's common sections, files, text) is shared. The recipe,
with a complete example, is ``docs/adding-a-motion.md``.

Summaries are grouped in sections (``scenario``, ``body``, ``initial_state``,
``results``, ``accuracy``, ``run``); in ``summary.json`` each section is an object
whose numeric entries have their units in the section's ``"units"`` object.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

# what report.html shows: the plotting layer's spec, re-exported here for the kinds
from ..plotting.spec import BodyLayer, Chart, Drawing, ReportSpec
from . import figures as common
from .facts import Check, Entry, Facts, FigureSpec, Progress, section
from .schema import agreement_thresholds

if TYPE_CHECKING:  # pragma: no cover
    from ..trajectory import Comparison
    from ._toml import Table
    from .schema import AttitudeSpec, Scenario, SimulationSpec
    from .summary import ScenarioResult

__all__ = [
    "ScenarioKind",
    "Facts",
    "Check",
    "FigureSpec",
    "Entry",
    "section",
    "Progress",
    "Chart",
    "BodyLayer",
    "Drawing",
    "ReportSpec",
]


class ScenarioKind:
    """Base class of a scenario adapter (one per kind; see ``docs/adding-a-motion.md``).

    Class attributes to set: :attr:`name`, :attr:`title`, :attr:`tables`,
    :attr:`methods`, :attr:`orders`. Methods to implement: :meth:`claims`,
    :meth:`parse`, :meth:`solve`; usually also :meth:`facts`, :meth:`checks`,
    :meth:`figures`.
    """

    #: Registry key, also accepted as the top-level ``kind = "..."`` of a file.
    name: str = ""
    #: What it is, in words (printed by ``poinsot check``).
    title: str = ""
    #: The top-level TOML tables it reads (besides name, description, kind,
    #: attitude and simulation, read for every kind).
    tables: tuple[str, ...] = ()
    #: The ``[simulation] method`` / ``reference`` values it accepts.
    methods: tuple[str, ...] = ()
    #: Order of accuracy of each fixed-step method (used to suggest a step).
    orders: Mapping[str, int] = {}
    #: The theory section it follows, cited in text (``"docs/theory.md §10"``).
    theory: str = ""
    #: Rough seconds per integration step (or closed-form sample) of each method,
    #: for the cost estimate of ``poinsot check`` (measure them on your kind).
    seconds_per_step: Mapping[str, float] = {}
    #: Fixed seconds of each method's solve (set-up, invariants, summary), added once
    #: per method to ``seconds_per_step`` times its steps (``benchmarks/bench_estimates.py``
    #: measures both; default 2 ms).
    seconds_per_run: Mapping[str, float] = {}

    # ------------------------------------------------------------------ reading
    def claims(self, data: Mapping[str, Any]) -> bool:
        """True if a file without a ``kind`` key is of this kind (``data`` is the
        raw TOML). Kinds are asked in registry order."""
        return False

    def parse(self, top: Table, attitude: AttitudeSpec) -> dict[str, Any]:
        """Read this kind's tables from ``top`` (the whole file) and return the
        :class:`~poinsot.scenarios.schema.Scenario` fields they define (``body``,
        ``angular_velocity``, ``torque``, ``omega_profile`` or ``spec``)."""
        raise NotImplementedError

    def refuse_method(self, method: str, fields: Mapping[str, Any]) -> str | None:
        """A reason why ``method`` cannot solve this scenario (``None``: it can)."""
        return None

    def check_simulation(
        self, simulation: SimulationSpec, fields: Mapping[str, Any]
    ) -> tuple[str, str] | None:
        """``(key, reason)`` if ``simulation`` (a SimulationSpec) does not suit this
        scenario, e.g. a duration past the end of a table; ``None`` if it does.
        Called when the file is read and again after ``--duration``."""
        return None

    # ------------------------------------------------------------------ solving
    def solve(self, scenario: Scenario, method: str, t: np.ndarray, progress: Progress) -> Any:
        """The motion on the output times ``t`` by ``method``: the result the library
        call returns (a Trajectory, PointTrajectory, CoordinateTrajectory...)."""
        raise NotImplementedError

    def motion_inertia(self, scenario: Scenario) -> np.ndarray | None:
        """The inertia tensor (body axes) the equations of motion use, or None."""
        return None if scenario.body is None else np.asarray(scenario.body.inertia)

    # ------------------------------------------------------------------ results
    def facts(self, scenario: Scenario) -> Facts:
        """What is known in closed form (the ``results`` section)."""
        return Facts()

    def body_entries(self, scenario: Scenario) -> dict[str, Entry]:
        """Extra entries of the ``body`` section (e.g. the inertia about a pin)."""
        return {}

    def series(self, scenario: Scenario, tr: Any) -> dict[str, tuple[np.ndarray, str]]:
        """Extra columns of the trajectory files, ``name -> (values (n,), units)``
        (e.g. ``"V"`` the potential energy), read from the kind's own result ``tr``."""
        return {}

    def checks(self, scenario: Scenario, tr: Any) -> Sequence[Check]:
        """The quantities with a known behaviour along ``tr`` (the kind's own
        result; accuracy)."""
        return ()

    def tolerances(self, scenario: Scenario, comparison: Comparison) -> dict[str, float]:
        """The largest accepted difference from the reference run of each quantity
        of ``comparison`` (a :class:`poinsot.trajectory.Comparison`), in its units.

        The rule (``docs/cli.md``, "Accuracy"): the attitude of a rigid body
        ``[simulation] attitude_threshold`` rad (default 1e-2); every other
        quantity (a rigid body's ``omega``, a particle's position and velocity,
        each generalized coordinate and rate) ``agreement_threshold`` (default
        1e-2) times its scale, the largest magnitude of the quantity along the
        reference run. A kind may override it.
        """

        att_tol, rel_tol = agreement_thresholds(scenario)
        return {
            d.name: att_tol if d.name == "attitude" and d.units == "rad" else rel_tol * d.scale
            for d in comparison.differences
        }

    def figures(self, result: ScenarioResult) -> list[FigureSpec]:
        """The figures that apply to ``result`` (a ScenarioResult)."""

        return common.default_figures(result)

    def report(self, result: ScenarioResult) -> ReportSpec:
        """What ``report.html`` shows for ``result`` (a ScenarioResult).

        The default shows the motion (``result.trajectory``) and the checks. The kinds
        of a rigid body derive from :class:`.kinds._rigid.RigidKind`, whose report
        draws the body (its shape, the fixed point under gravity, the torque, the Euler
        angles, the reference's axes and attitude error); other kinds override it.
        """
        return ReportSpec(motion=result.trajectory, checks=tuple(result.checks))

    def describe_scenario(self, scenario: Scenario) -> list[str]:
        """Phrases describing the scenario before it is run (``poinsot check``)."""
        return [self.title] if self.title else []
