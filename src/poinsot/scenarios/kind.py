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

if TYPE_CHECKING:
    from ..trajectory import Comparison
    from ._toml import Table
    from .schema import AttitudeSpec, Scenario, SimulationSpec
    from .summary import ScenarioResult

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from .._drift import relative_change

# what report.html shows: the plotting layer's spec, re-exported here for the kinds
from ..plotting.spec import BodyLayer, Chart, Drawing, ReportSpec

if TYPE_CHECKING:  # pragma: no cover
    from ._toml import Table
    from .schema import AttitudeSpec, Scenario

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

#: ``progress(fraction, stage)``: called as a computation advances (fraction in [0, 1]).
Progress = Callable[[float, str], None]


@dataclass(frozen=True)
class Entry:
    """One summary entry: a value, its units (``""`` for none) and a text label.

    Examples
    --------
    >>> Entry(1.5, "J", "kinetic energy T")
    Entry(value=1.5, units='J', label='kinetic energy T')
    """

    value: Any
    units: str = ""
    label: str = ""


def section(entries: Mapping[str, Entry | Any]) -> dict[str, Any]:
    """A summary section as written to ``summary.json``: ``{key: value, ...,
    "units": {key: units}}`` (arrays become lists; non-finite floats strings).

    Examples
    --------
    >>> section({"energy": Entry(1.5, "J"), "regime": "rotation about z"})
    {'energy': 1.5, 'regime': 'rotation about z', 'units': {'energy': 'J'}}
    """
    out: dict[str, Any] = {}
    units: dict[str, str] = {}
    for key, e in entries.items():
        if isinstance(e, Entry):
            out[key] = jsonable(e.value)
            if e.units:
                units[key] = e.units
        else:
            out[key] = jsonable(e)
    if units:
        out["units"] = units
    return out


def jsonable(obj: Any) -> Any:
    """Convert NumPy values, tuples and non-finite floats to JSON-safe Python values
    (``nan`` -> ``None``, ``inf`` -> ``"inf"``).

    Examples
    --------
    >>> jsonable({"a": np.array([1.0, np.inf]), "b": (np.float64(2.0), None)})
    {'a': [1.0, 'inf'], 'b': [2.0, None]}
    """
    if isinstance(obj, Mapping):
        return {str(k): jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray | np.generic):
        return jsonable(obj.tolist())
    if isinstance(obj, float) and not np.isfinite(obj):
        return None if np.isnan(obj) else ("inf" if obj > 0 else "-inf")
    if obj is None or isinstance(obj, bool | int | float | str):
        return obj
    return str(obj)


@dataclass(frozen=True)
class Facts:
    """What is known about a motion in closed form, for the ``results`` section.

    The base class holds ordered :class:`Entry` objects and text lines; a kind may
    return it directly (``Facts(entries={...}, lines=(...))``) or subclass it and
    override :meth:`entries_` / :meth:`describe`.

    Attributes
    ----------
    entries : Mapping[str, Entry]
        Key -> value with units (the ``results`` section of ``summary.json``).
    lines : tuple of str
        Sentences printed by ``poinsot run`` (each cites ``docs/theory.md §N``
        where it states a result of the theory).

    Examples
    --------
    >>> f = Facts({"period": Entry(2.0, "s", "period")}, ("periodic with period 2 s",))
    >>> f.section()
    {'period': 2.0, 'units': {'period': 's'}}
    >>> f.describe()
    ['periodic with period 2 s']
    """

    entries: Mapping[str, Entry] = field(default_factory=dict)
    lines: tuple[str, ...] = ()

    def entries_(self) -> Mapping[str, Entry]:
        """The entries of the ``results`` section."""
        return self.entries

    def section(self) -> dict[str, Any]:
        """The ``results`` section (JSON-ready, with units)."""
        return section(self.entries_())

    def describe(self) -> list[str]:
        """Text lines for ``poinsot run``."""
        return list(self.lines)


@dataclass(frozen=True, eq=False)
class Check:
    """A quantity whose behaviour along the motion is known: conserved, or equal to
    a law (e.g. ``K(t) = K(0) + M t``). Its deviation measures the accuracy.

    Attributes
    ----------
    name : str
        Key in the ``accuracy`` section (``"energy"``, ``"momentum_z"``, ...).
    label : str
        Text label (``"kinetic energy T"``).
    units : str
        Units of ``values``.
    values : ndarray, shape (n,) or (n, 3)
        The quantity at each output time.
    expected : ndarray or None
        What it should be at each time; ``None``: its initial value (conserved).
    scale : float or None
        Reference size for the relative deviation; ``None``: ``|values[0]|``.
    conserved : bool
        True if it must stay constant (or follow ``expected``): its deviation is
        then compared with the drift threshold; False: only reported.
    law : str
        The law, in words, for the text (``"K(t) = K(0) + M t"``).

    Examples
    --------
    >>> c = Check("energy", "T", "J", np.array([1.0, 1.0, 1.001]))
    >>> round(c.max_relative_deviation, 6)
    0.001
    """

    name: str
    label: str
    units: str
    values: np.ndarray
    expected: np.ndarray | None = None
    scale: float | None = None
    conserved: bool = True
    law: str = ""

    def relative_change(self) -> np.ndarray:
        """``(values - expected) / scale`` at each time, shape (n,) (the norm of the
        difference for vectors; signed for scalars)."""
        v = np.asarray(self.values, dtype=float)
        return relative_change(v, self.scale, expected=self.expected, vector=v.ndim > 1)

    @property
    def max_relative_deviation(self) -> float:
        """``max_t |values - expected| / scale`` (vector norms for vectors)."""
        return float(np.max(np.abs(self.relative_change()), initial=0.0))

    def entry(self) -> dict[str, Any]:
        """The JSON entry: initial and final values, units, the maximum relative
        drift (or deviation from the law) and whether it must be conserved."""
        v = np.asarray(self.values, dtype=float)
        out = {
            "initial": jsonable(v[0]),
            "final": jsonable(v[-1]),
            "units": self.units,
            "max_relative_drift": self.max_relative_deviation,
            "conserved": bool(self.conserved),
        }
        if self.law:
            out["law"] = self.law
        return out


@dataclass(frozen=True)
class FigureSpec:
    """One PNG figure a kind offers: ``draw(ax)`` draws on a new axes.

    ``projection`` is ``None`` or ``"3d"``; ``size`` in inches. The writer makes a
    :class:`matplotlib.figure.Figure` (no pyplot state), calls ``draw`` and saves it
    as ``name``; a failing figure is skipped with a note, never sinks the run.
    """

    name: str
    draw: Callable[[Any], Any]
    size: tuple[float, float] = (7.0, 3.6)
    projection: str | None = None


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
        from .summary import agreement_thresholds

        att_tol, rel_tol = agreement_thresholds(scenario)
        return {
            d.name: att_tol if d.name == "attitude" and d.units == "rad" else rel_tol * d.scale
            for d in comparison.differences
        }

    def figures(self, result: ScenarioResult) -> list[FigureSpec]:
        """The figures that apply to ``result`` (a ScenarioResult)."""
        from . import figures as common

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
