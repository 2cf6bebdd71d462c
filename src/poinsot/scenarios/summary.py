"""The result of a run and its summary, grouped in sections with units.

:class:`ScenarioResult` holds the scenario, the trajectories and what the kind
knows about the motion (:class:`~poinsot.scenarios.kind.Facts`, the
:class:`~poinsot.scenarios.kind.Check` quantities); it summarises itself
(:attr:`ScenarioResult.summary`, a fresh dict each time), describes itself
(:meth:`ScenarioResult.describe`) and lists its figures
(:meth:`ScenarioResult.figures`).

Sections of ``summary.json`` (each numeric entry's units in the section's
``"units"`` object):

- ``scenario``: name, description, source file, kind, the parsed file echoed;
- ``conventions``: one line (:data:`CONVENTIONS` for a rigid body,
  :data:`MOTION_CONVENTIONS` for other motions);
- ``body``: mass, inertia, centre of mass, principal moments and axes;
- ``initial_state``: attitude quaternion, angular velocity in body and space axes;
- ``initial_state``: a rigid body's attitude quaternion and angular velocity in
  body and space axes; for other motions the initial value of each state quantity
  of the kind's result (a particle's position and velocity, each coordinate and
  rate), with units;
- ``results``: what is known in closed form for this kind;
- ``accuracy``: the method and reference, the integration step, the drift of every
  conserved quantity (``invariants``, ``reference_invariants``), the comparison with
  the reference on the result's own state (:func:`poinsot.trajectory.compare`:
  each quantity's largest difference, when, its final difference and tolerance,
  in its units), the thresholds, ``warnings`` and a ``suggested_max_step``;
- ``run``: output times, wall time, the cost estimate, solver details, versions,
  notes and (once written) the list of files.

Accuracy thresholds (docs/cli.md): a conserved quantity whose maximum relative
drift exceeds :data:`DRIFT_THRESHOLD`, or a state quantity that differs from the
reference run by more than its tolerance, gives a warning (printed by ``poinsot
run``, recorded in ``accuracy.warnings``, shown in ``report.html``) with a
suggested ``max_step``. The tolerance of a rigid body's attitude is
:data:`ATTITUDE_THRESHOLD` rad; that of every other quantity (a rigid body's
``omega``, a particle's position and velocity, each generalized coordinate and
rate) :data:`AGREEMENT_THRESHOLD` times its scale, the largest magnitude of the
quantity along the reference run (:meth:`ScenarioKind.tolerances
<poinsot.scenarios.ScenarioKind.tolerances>`). A scenario may set its own in
``[simulation] drift_threshold``, ``attitude_threshold`` and
``agreement_threshold``.
"""

from __future__ import annotations

import copy
import math
import platform
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np

from .. import __version__
from ..mass import principal_axes
from ..trajectory import (
    PER_SAMPLE_INFO,
    CoordinateTrajectory,
    PointTrajectory,
    Trajectory,
    compare,
    quantity_label,
)
from .describe import describe
from .facts import Check, Entry, Facts, jsonable, section
from .schema import (
    AGREEMENT_THRESHOLD,
    ATTITUDE_THRESHOLD,
    DRIFT_THRESHOLD,
    Scenario,
    agreement_thresholds,
)

__all__ = [
    "ScenarioResult",
    "CONVENTIONS",
    "MOTION_CONVENTIONS",
    "POINT_CONVENTIONS",
    "COORDINATE_CONVENTIONS",
    "conventions_of",
    "DRIFT_THRESHOLD",
    "ATTITUDE_THRESHOLD",
    "AGREEMENT_THRESHOLD",
    "agreement_thresholds",
    "versions",
]

#: The conventions of every output, in one line.
CONVENTIONS = (
    "Hamilton quaternions, scalar first (w, x, y, z); attitude R maps body to space "
    "components (v_space = R v_body); omega in body axes (rad/s); angular momentum K in "
    "space axes (kg m^2/s); SI units; angles in radians."
)
#: The conventions of the outputs of other motions (particles, generalized coordinates).
MOTION_CONVENTIONS = (
    "SI units; angles in radians; a particle's position and velocity in the axes of the "
    "frame its result names (inertial axes, or a moving frame's); generalized coordinates "
    "in the unit of each coordinate, their rates per second."
)

#: The conventions of a particle's outputs.
POINT_CONVENTIONS = (
    "SI units; position (m) and velocity (m/s) in the axes of the frame the result "
    "names (inertial axes, or a moving frame's)."
)
#: The conventions of a motion in generalized coordinates.
COORDINATE_CONVENTIONS = (
    "SI units; generalized coordinates each in its own unit (m for a length, rad for an "
    "angle), their rates per second (m/s, rad/s)."
)


def conventions_of(tr: Any) -> str:
    """The conventions line of a result: a rigid body's (quaternions, omega in body
    axes...), a particle's or generalized coordinates'; none speaks of another's.

    Examples
    --------
    >>> from poinsot.trajectory import CoordinateTrajectory
    >>> t = np.zeros(1)
    >>> conventions_of(CoordinateTrajectory(t, t[:, None], t[:, None], ("x",)))[:40]
    'SI units; generalized coordinates each i'
    """
    if isinstance(tr, Trajectory):
        return CONVENTIONS
    if isinstance(tr, PointTrajectory):
        return POINT_CONVENTIONS
    if isinstance(tr, CoordinateTrajectory):
        return COORDINATE_CONVENTIONS
    return MOTION_CONVENTIONS


def versions() -> dict[str, Any]:
    """Versions of poinsot, Python, NumPy and SciPy (for ``summary.json``).

    Examples
    --------
    >>> sorted(versions())
    ['numpy', 'poinsot', 'python', 'scipy']
    """
    import scipy

    return {
        "poinsot": __version__,
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
    }


def _comparison(scenario: Scenario, tr: Any, ref: Any) -> tuple[dict[str, Any] | None, list[Any]]:
    """The ``accuracy.comparison`` entry, from :func:`poinsot.trajectory.compare` on
    the kind's own state, and the differences beyond their tolerance as
    ``(Difference, tolerance)`` pairs."""
    if ref is None:
        return None, []
    cmp = compare(tr, ref)
    tols = scenario.adapter.tolerances(scenario, cmp)
    differences: dict[str, dict[str, Any]] = {}
    exceeded: list[tuple[Any, float]] = []
    for d in cmp.differences:
        tol = tols.get(d.name)
        differences[d.name] = {
            "max": float(d.max),
            "time_of_max_s": float(d.time_of_max),
            "final": float(d.final),
            "scale": float(d.scale),
            "tolerance": None if tol is None else float(tol),
            "units": d.units,
        }
        if tol is not None and d.max > tol:
            exceeded.append((d, float(tol)))
    out: dict[str, Any] = {"reference": ref.method, "differences": differences}
    names = cmp.names()
    if isinstance(tr, Trajectory) and "attitude" in names and "omega" in names:
        # the rigid body's keys of earlier versions (same numbers, stated units)
        att, omega = cmp["attitude"], cmp["omega"]
        out.update(
            {
                "max_attitude_error_rad": float(att.max),
                "final_attitude_error_rad": float(att.final),
                "max_omega_error": float(omega.max),
                "max_relative_omega_error": (
                    float(omega.max / omega.scale) if omega.scale > 0 else None
                ),
                "units": {
                    "max_attitude_error_rad": "rad",
                    "final_attitude_error_rad": "rad",
                    "max_omega_error": "rad/s",
                },
            }
        )
    return out, exceeded


def _round_step(h: float) -> float:
    """``h`` rounded down to one significant digit (0.0347 -> 0.03)."""
    if not (h > 0 and math.isfinite(h)):
        return h
    e = math.floor(math.log10(h))
    return math.floor(h / 10**e) * 10**e


def _tidy(a: Any, scale: float) -> np.ndarray:
    """``a`` with round-off (``|x| <= 1e-12 scale``, e.g. an off-diagonal -1.7e-18 kg m^2
    of an inertia summed from parts) and ``-0.0`` written as 0.

    Examples
    --------
    >>> _tidy([[2.0, -1.7e-18], [-0.0, 1.0]], 2.0).tolist()
    [[2.0, 0.0], [0.0, 1.0]]
    """
    out = np.array(a, dtype=float)
    out[np.abs(out) <= 1e-12 * scale] = 0.0
    return out


@dataclass(frozen=True)
class Accuracy:
    """The accuracy assessment of a run: thresholds, warnings and a suggested step."""

    drift_threshold: float
    attitude_threshold: float
    integration_step: float | None
    warnings: tuple[str, ...] = ()
    suggested_max_step: float | None = None
    agreement_threshold: float = AGREEMENT_THRESHOLD


def _assess(scenario: Scenario, checks: Any, ref_checks: Any, exceeded: Any) -> Accuracy:
    kind = scenario.adapter
    sim = scenario.simulation
    drift_tol = getattr(sim, "drift_threshold", None) or DRIFT_THRESHOLD
    att_tol, rel_tol = agreement_thresholds(scenario)
    numerical = [m for m in (sim.method, sim.reference) if m is not None and m in kind.orders]
    h = sim.integration_step() if numerical else None
    warnings: list[str] = []
    factors: list[tuple[float, int]] = []  # (measured / threshold, order)
    for method, cks in ((sim.method, checks), (sim.reference, ref_checks)):
        for c in cks or ():
            if not c.conserved:
                continue
            drift = c.max_relative_deviation
            if drift > drift_tol:
                what = f"deviates from {c.law}" if c.law else "drifts"
                warnings.append(
                    f"{c.label} {what} by {drift:.2g} (relative) with method {method!r}, "
                    f"more than the threshold {drift_tol:g}"
                )
                if method in kind.orders:
                    factors.append((drift / drift_tol, kind.orders[method]))
    orders = [kind.orders[m] for m in (sim.method, sim.reference) if m in kind.orders]
    for d, tol in exceeded:
        units = f" {d.units}" if d.units else ""
        if d.name == "attitude" and tol == att_tol:
            rule = "the attitude threshold"
        elif math.isclose(tol, rel_tol * d.scale, rel_tol=1e-12):
            rule = f"{rel_tol:g} of its scale {d.scale:.3g}{units}"
        else:
            rule = f"the tolerance of the {scenario.kind} kind"
        warnings.append(
            f"{sim.method!r} and {sim.reference!r} differ by up to {d.max:.3g}{units} in "
            f"{quantity_label(d.name)} (at t = {d.time_of_max:.4g} s), more than the threshold "
            f"{tol:.3g}{units} ({rule})"
        )
        if orders and tol > 0:
            factors.append((d.max / tol, min(orders)))
    suggested = None
    if factors and h is not None:
        # error ~ C h^p: a step that brings the worst quantity 10x below its threshold
        suggested = min(h * (0.1 / ratio) ** (1.0 / p) for ratio, p in factors)
        suggested = _round_step(suggested)
    return Accuracy(drift_tol, att_tol, h, tuple(warnings), suggested, rel_tol)


@dataclass(frozen=True, eq=False)
class ScenarioResult:
    """Outcome of :func:`~poinsot.scenarios.simulate_scenario`.

    Attributes
    ----------
    scenario : Scenario
        The scenario run (with any override applied).
    trajectory : Result
        The result of ``simulation.method``: the kind's own result (a
        :class:`~poinsot.trajectory.Trajectory` for a rigid body, a
        :class:`~poinsot.trajectory.PointTrajectory` for a particle, a
        :class:`~poinsot.trajectory.CoordinateTrajectory` for generalized
        coordinates).
    reference : Result or None
        The result of ``simulation.reference`` (same type), on the same times.
    facts : Facts
        What the kind knows in closed form (the ``results`` section).
    checks, reference_checks : tuple of Check
        Conserved quantities (or known laws) along each trajectory.
    accuracy : Accuracy
        Thresholds, warnings and a suggested step.
    wall_time : float
        Seconds spent by ``simulation.method`` (numba's compilation not counted).
    reference_time : float or None
        Seconds spent by ``simulation.reference`` (compilation not counted).
    compile_time : float
        Seconds numba spent compiling during the run (0 from a warm cache).
    cost : Cost or None
        The cost estimated before the run.
    comparison : dict or None
        ``accuracy.comparison`` of the summary: the differences from the
        reference on the result's own state, in its units.
    """

    scenario: Scenario
    trajectory: Any
    reference: Any
    facts: Facts = field(default_factory=Facts)
    checks: tuple[Check, ...] = ()
    reference_checks: tuple[Check, ...] = ()
    accuracy: Accuracy | None = None
    wall_time: float = 0.0
    cost: Any = None
    comparison: dict[str, Any] | None = None
    reference_time: float | None = None
    compile_time: float = 0.0

    @classmethod
    def build(
        cls,
        scenario: Scenario,
        tr: Any,
        ref: Any,
        *,
        wall_time: Any = 0.0,
        cost: Any = None,
        reference_time: float | None = None,
        compile_time: float = 0.0,
    ) -> ScenarioResult:
        """Ask the scenario's kind for its facts and checks, compare the result with
        the reference on its own state and assess the accuracy."""
        kind = scenario.adapter
        checks = tuple(kind.checks(scenario, tr))
        ref_checks = tuple(kind.checks(scenario, ref)) if ref is not None else ()
        comparison, exceeded = _comparison(scenario, tr, ref)
        accuracy = _assess(scenario, checks, ref_checks, exceeded)
        return cls(
            scenario,
            tr,
            ref,
            kind.facts(scenario),
            checks,
            ref_checks,
            accuracy,
            float(wall_time),
            cost,
            comparison,
            None if reference_time is None else float(reference_time),
            float(compile_time),
        )

    # ------------------------------------------------------------------ pieces
    @property
    def potential(self) -> np.ndarray | None:
        """Potential energy (J) at each sample of ``trajectory``, or None."""
        series = self.scenario.adapter.series(self.scenario, self.trajectory)
        return series["V"][0] if "V" in series else None

    @property
    def warnings(self) -> tuple[str, ...]:
        """Accuracy warnings (also in ``summary["accuracy"]["warnings"]``)."""
        return () if self.accuracy is None else self.accuracy.warnings

    def sections(self) -> dict[str, Any]:
        """The summary sections (a new dict at every call; see the module notes)."""
        return copy.deepcopy(self._sections)

    @cached_property
    def _sections(self) -> dict[str, Any]:
        s = self.scenario
        kind = s.adapter
        tr, ref = self.trajectory, self.reference
        out: dict[str, Any] = {
            "scenario": {
                "name": s.name,
                "description": s.description,
                "source": s.source,
                "kind": s.kind,
                "kind_title": kind.title,
                "file": jsonable(s.data),
            },
            "conventions": conventions_of(tr),
            "body": self._body(),
            "initial_state": self._initial_state(),
            "results": self.facts.section(),
        }
        acc = self.accuracy
        comparison = copy.deepcopy(self.comparison)
        out["accuracy"] = {
            "method": tr.method,
            "reference": None if ref is None else ref.method,
            "integration_step": None if acc is None else acc.integration_step,
            "invariants": {c.name: c.entry() for c in self.checks},
            "reference_invariants": (
                None if ref is None else {c.name: c.entry() for c in self.reference_checks}
            ),
            "comparison": comparison,
            "drift_threshold": None if acc is None else acc.drift_threshold,
            "attitude_threshold": None if acc is None else acc.attitude_threshold,
            "agreement_threshold": None if acc is None else acc.agreement_threshold,
            "warnings": [] if acc is None else list(acc.warnings),
            "suggested_max_step": None if acc is None else acc.suggested_max_step,
            "units": {
                "integration_step": "s",
                "attitude_threshold": "rad",
                "suggested_max_step": "s",
            },
        }
        sim = s.simulation
        out["run"] = {
            "method": tr.method,
            "reference_method": None if ref is None else ref.method,
            "times": {
                "duration": sim.duration,
                "samples": int(tr.t.size),
                "step": sim.step,
                "units": "s",
            },
            # the solve, split: the method, the reference, numba's compilation (a cold
            # cache); wall_time_s is their sum
            "wall_time_s": self.wall_time + (self.reference_time or 0.0) + self.compile_time,
            "solve_time_s": self.wall_time,
            "reference_time_s": self.reference_time,
            "compile_time_s": self.compile_time,
            "cost": None
            if self.cost is None
            else {
                "samples": self.cost.samples,
                "integration_steps": self.cost.steps,
                "memory_bytes": self.cost.memory_bytes,
                "seconds": self.cost.seconds,
                "seconds_by_method": dict(self.cost.methods),
            },
            # the run's details, not its per-sample series (V is in the invariants)
            "info": jsonable({k: v for k, v in tr.info.items() if k not in PER_SAMPLE_INFO}),
            "versions": versions(),
            "notes": [],
            "units": {
                "wall_time_s": "s",
                "solve_time_s": "s",
                "reference_time_s": "s",
                "compile_time_s": "s",
            },
        }
        return out

    def _initial_state(self) -> dict[str, Any]:
        tr = self.trajectory
        if isinstance(tr, Trajectory):
            return section(
                {
                    "quat": Entry(self.scenario.attitude.quat, "1"),
                    "omega_body": Entry(tr.omega[0], "rad/s"),
                    "omega_space": Entry(tr.rotation[0].apply(tr.omega[0]), "rad/s"),
                }
            )
        return section(
            {
                name: Entry(np.asarray(ch.values)[0], ch.units)
                for name, ch in tr.state_channels().items()
            }
        )

    def _body(self) -> dict[str, Any] | None:
        s = self.scenario
        if s.body is None:
            return None

        b = s.body
        J = np.asarray(b.inertia, dtype=float)
        moments, axes = principal_axes(J)
        big = float(np.max(np.abs(J)))
        com = np.asarray(b.center_of_mass, dtype=float)
        entries: dict[str, Any] = {
            "mass": Entry(b.mass, "kg"),
            "inertia": Entry(_tidy(J, big), "kg m^2"),
            "center_of_mass": Entry(_tidy(com, float(np.max(np.abs(com)))), "m"),
            "principal_moments": Entry(_tidy(moments, big), "kg m^2"),
            "principal_axes_columns": Entry(_tidy(axes.as_matrix(), 1.0), "1"),
        }
        # a body given by its inertia has no shape: no empty rows
        if b.shape not in (None, "none"):
            entries["shape"] = b.shape
        if b.dims:
            entries["dims"] = Entry(b.dims, "m")
        if b.parts:
            entries["parts"] = [p.name for p in b.parts]
        faces = [f for f in (b.faces, *(p.faces for p in b.parts)) if f is not None]
        if faces:  # a mesh has no dims: its size is its triangle count
            entries["mesh_triangles"] = sum(int(f.shape[0]) for f in faces)
        entries.update(s.adapter.body_entries(s))
        return section(entries)

    @property
    def summary(self) -> dict[str, Any]:
        """The JSON-ready summary: :meth:`sections` (a new dict at every access, so
        that writing the outputs never changes the result)."""
        return self.sections()

    # ------------------------------------------------------------------ text, figures
    def describe(self, *, title: str = "poinsot") -> str:
        """A short human summary (printed by ``poinsot run`` and ``poinsot demo``)."""

        return describe(self, title=title)

    def figures(self) -> Any:
        """The :class:`~poinsot.scenarios.kind.FigureSpec` figures of this run."""
        return self.scenario.adapter.figures(self)
