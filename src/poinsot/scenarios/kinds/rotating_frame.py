"""Adapters: a particle in the rotating Earth's frame (docs/theory.md §9).

Kinds:

``free-fall``
    Table [free_fall]: ``height`` (m), ``latitude``, ``degrees`` (default true),
    optional ``g`` (m/s^2, default 9.80665), ``omega`` (rad/s, default the
    Earth's), ``mass`` (kg). A body dropped from rest in
    :func:`poinsot.dynamics.earth_frame`, integrated by
    :func:`poinsot.dynamics.simulate_particle`; compared with the first-order
    :func:`poinsot.dynamics.eastward_deflection`.
``foucault``
    Table [foucault]: ``length`` (m), ``latitude``, ``degrees``, optional
    ``amplitude`` (m, default 1), ``g``, ``omega``, ``mass``. The linearised
    pendulum of :func:`poinsot.dynamics.foucault_pendulum`; its swing plane
    turns at :func:`poinsot.dynamics.foucault_precession_rate`.

Both return the library's :class:`~poinsot.dynamics.ParticleTrajectory` (a
:class:`~poinsot.trajectory.PointTrajectory`): the position and velocity relative
to the Earth (east, north, up axes, m and m/s; its ``frame_name`` says so), with
the inertial motion and the frame's attitude alongside; the trajectory files,
the comparison with a reference run and ``report.html`` read it directly.
``method = "adaptive"`` (DOP853, tolerances ``rtol = 1e-11``, ``atol = 1e-12`` m).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from ...dynamics import (
    EARTH_ROTATION_RATE,
    STANDARD_GRAVITY,
    PendulumForce,
    UniformGravity,
    earth_frame,
    eastward_deflection,
    foucault_frame,
    foucault_pendulum,
    foucault_period,
    foucault_precession_rate,
    jacobi_integral,
    simulate_particle,
)
from ...plotting.particles import plot_path, plot_swing_plane
from ..kind import ReportSpec
from ..report import figure_sections, unit_charts

if TYPE_CHECKING:
    from .._toml import Table
    from ..kind import Check, Facts, FigureSpec, Progress, ReportSpec
    from ..schema import AttitudeSpec, Scenario, SimulationSpec
    from ..summary import ScenarioResult

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..describe import fmt
from ..figures import invariants_figure
from ..kind import Check, Drawing, Entry, Facts, FigureSpec, ScenarioKind

RTOL, ATOL = 1e-11, 1e-12


@dataclass(frozen=True)
class EarthSpec:
    """What [free_fall] / [foucault] say, in SI units (radians)."""

    latitude: float  # rad
    g: float  # m/s^2
    omega: float  # rad/s
    mass: float  # kg
    height: float = 0.0  # m (free fall)
    length: float = 0.0  # m (Foucault)
    amplitude: float = 0.0  # m (Foucault)


def _read_common(t: Any, extra: Any) -> Any:
    keys = ("latitude", "degrees", "g", "omega", "mass", *extra)
    t.known(keys)
    degrees = t.boolean("degrees", True)
    lat = t.number("latitude", required=True)
    if abs(lat) > (90.0 if degrees else np.pi / 2):
        raise t.error("latitude", f"expected a latitude within +-90 deg, found {lat!r}.")
    common = {
        "latitude": float(np.deg2rad(lat) if degrees else lat),
        "g": t.number("g", STANDARD_GRAVITY, positive=True),
        "omega": t.number("omega", EARTH_ROTATION_RATE),
        "mass": t.number("mass", 1.0, positive=True),
    }
    return keys, common


class _EarthKind(ScenarioKind):
    methods = ("adaptive",)
    orders = {}
    theory = "docs/theory.md §9"
    # cost estimate, one core, measured by benchmarks/bench_estimates.py on the examples
    seconds_per_step = {"adaptive": 2.5e-5}
    seconds_per_run = {"adaptive": 5e-4}

    def motion_inertia(self, scenario: Scenario) -> np.ndarray | None:
        return None

    def components(self, tr: Any) -> dict[str, tuple[np.ndarray, str]]:
        """The relative position and velocity by named component (east, north, up)."""
        names = ("x_east", "y_north", "z_up")
        out = {n: (tr.position[:, k], "m") for k, n in enumerate(names)}
        out.update({f"v{n[0]}": (tr.velocity[:, k], "m/s") for k, n in enumerate(names)})
        return out

    def _jacobi(self, scenario: Any, tr: Any, frame: Any, potential: Any) -> Any:
        r, v = tr.position, tr.velocity
        h = jacobi_integral(frame, r, v, mass=scenario.spec.mass, potential=potential(r))
        return Check(
            "jacobi_integral",
            "Jacobi integral T_r - m|w x r|^2/2 + U",
            "J",
            h,
            scale=float(np.max(np.abs(h))) or 1.0,
        )

    def report(self, result: ScenarioResult) -> ReportSpec:
        """``report.html``: the point and its path relative to the Earth (east,
        north, up), charts of its position and velocity components, the checks,
        and the kind's figures (the path in the Earth's frame and in space, the
        swing plane) as inline SVG."""

        tr = result.trajectory
        specs = [f for f in self.figures(result) if f.name != "invariants.png"]
        titles = {
            "path_frame.png": "Path relative to the Earth (docs/theory.md §9)",
            "path_space.png": "Path in space (inertial axes)",
            "swing_plane.png": "The swing plane turning at -Omega sin(latitude)",
        }
        return ReportSpec(
            motion=tr,
            charts=tuple(unit_charts(self.components(tr))),
            checks=tuple(result.checks),
            sections=tuple(figure_sections(specs, [titles.get(f.name, f.name) for f in specs])),
        )

    def _path_figures(self, result: Any, components: Any, what: Any) -> Any:
        tr = result.trajectory

        def relative(ax: Any) -> Any:
            return plot_path(
                tr.position,
                components=components,
                ax=ax,
                title=f"{result.scenario.name}: path relative to the Earth ({what})",
                axis_names=("east", "north", "up"),
            )

        def inertial(ax: Any) -> Any:
            return plot_path(
                tr.inertial_position,
                components=components,
                ax=ax,
                title=f"{result.scenario.name}: path in space (inertial axes)",
                axis_names=("X", "Y", "Z"),
            )

        return [
            FigureSpec("path_frame.png", relative, (6.0, 4.8)),
            FigureSpec("path_space.png", inertial, (6.0, 4.8)),
        ]


class FreeFall(_EarthKind):
    name = "free-fall"
    title = "free fall on the rotating Earth (Coriolis deflection)"
    tables = ("free_fall",)

    def claims(self, data: Mapping[str, Any]) -> bool:
        return "free_fall" in data

    def parse(self, top: Table, attitude: AttitudeSpec) -> dict[str, Any]:
        t = top.table("free_fall", required=True)
        keys, common = _read_common(t, ("height",))
        spec = EarthSpec(height=t.number("height", positive=True, required=True), **common)
        t.finish(keys)
        return {"spec": spec}

    def check_simulation(
        self, simulation: SimulationSpec, fields: Mapping[str, Any]
    ) -> tuple[str, str] | None:
        sp = fields["spec"]
        fall = float(np.sqrt(2 * sp.height / sp.g))
        if simulation.duration > 1.5 * fall:
            return (
                "duration",
                f"expected a duration <= 1.5 x the fall time "
                f"({fmt(fall)} s: the ground is not modelled), "
                f"found {simulation.duration:g} s.",
            )
        return None

    def solve(self, scenario: Scenario, method: str, t: np.ndarray, progress: Progress) -> Any:
        sp = scenario.spec
        progress(0.0, "adaptive (DOP853)")
        tr = simulate_particle(
            earth_frame(sp.latitude, sp.omega),
            UniformGravity(sp.mass, sp.g),
            [0.0, 0.0, sp.height],
            [0.0, 0.0, 0.0],
            t,
            mass=sp.mass,
            rtol=RTOL,
            atol=ATOL,
            inertial=True,
            max_step=scenario.simulation.max_step or np.inf,
        )
        progress(1.0, "adaptive (DOP853)")
        return dataclasses.replace(tr, method=method, frame_name="the Earth's east, north, up")

    def facts(self, scenario: Scenario) -> Facts:
        sp = scenario.spec
        fall = float(np.sqrt(2 * sp.height / sp.g))
        d = float(eastward_deflection(sp.height, sp.latitude, sp.g, sp.omega))
        return Facts(
            {
                "fall_time": Entry(fall, "s", "fall time sqrt(2h/g)"),
                "eastward_deflection": Entry(d, "m", "first order (1/3) Omega g t^3 cos(lat)"),
                "latitude": Entry(sp.latitude, "rad"),
                "omega": Entry(sp.omega, "rad/s"),
                "g": Entry(sp.g, "m/s^2"),
                "relative_order_neglected": Entry(float((sp.omega * fall) ** 2), "1"),
            },
            (
                f"dropped from {fmt(sp.height)} m: fall time {fmt(fall)} s; the Coriolis force "
                f"deflects it {fmt(1000 * d)} mm east, (1/3) Omega g t^3 cos(lat) to first "
                f"order in Omega (docs/theory.md §9)",
            ),
        )

    def checks(self, scenario: Scenario, tr: Any) -> Sequence[Check]:
        sp = scenario.spec
        frame = earth_frame(sp.latitude, sp.omega)
        jac = self._jacobi(scenario, tr, frame, UniformGravity(sp.mass, sp.g).potential)
        r = tr.position
        first = eastward_deflection(sp.height - r[:, 2], sp.latitude, sp.g, sp.omega)
        east = Check(
            "eastward_deflection",
            "east displacement vs (1/3) Omega g t^3 cos(lat)",
            "m",
            r[:, 0],
            expected=first,
            scale=float(np.max(np.abs(first))) or 1.0,
            conserved=False,
            law="x = (1/3) Omega cos(lat) sqrt(8 d^3 / g) after a drop d, first order in Omega",
        )
        return (jac, east)

    def figures(self, result: ScenarioResult) -> list[FigureSpec]:
        figs = self._path_figures(result, (0, 2), "east, up")
        inv = invariants_figure(result)
        return figs + ([inv] if inv is not None else [])

    def describe_scenario(self, scenario: Scenario) -> list[str]:
        sp = scenario.spec
        return [f"{self.title}: {fmt(sp.height)} m at latitude {fmt(np.degrees(sp.latitude))} deg"]


class Foucault(_EarthKind):
    name = "foucault"
    title = "Foucault pendulum (linearised) on the rotating Earth"
    tables = ("foucault",)

    def claims(self, data: Mapping[str, Any]) -> bool:
        return "foucault" in data

    def parse(self, top: Table, attitude: AttitudeSpec) -> dict[str, Any]:
        t = top.table("foucault", required=True)
        keys, common = _read_common(t, ("length", "amplitude"))
        spec = EarthSpec(
            length=t.number("length", positive=True, required=True),
            amplitude=t.number("amplitude", 1.0, positive=True),
            **common,
        )
        t.finish(keys)
        return {"spec": spec}

    def solve(self, scenario: Scenario, method: str, t: np.ndarray, progress: Progress) -> Any:
        sp = scenario.spec
        progress(0.0, "adaptive (DOP853)")
        tr = foucault_pendulum(
            sp.length,
            sp.latitude,
            t,
            amplitude=sp.amplitude,
            g=sp.g,
            omega=sp.omega,
            mass=sp.mass,
            rtol=RTOL,
            atol=ATOL,
            max_step=scenario.simulation.max_step or np.inf,
            inertial=True,
        )
        progress(1.0, "adaptive (DOP853)")
        return dataclasses.replace(tr, method=method, frame_name="the Earth's east, north, up")

    def facts(self, scenario: Scenario) -> Facts:
        sp = scenario.spec
        rate = float(foucault_precession_rate(sp.latitude, sp.omega))
        period = float(foucault_period(sp.latitude, sp.omega))
        swing = float(2 * np.pi * np.sqrt(sp.length / sp.g))
        return Facts(
            {
                "precession_rate": Entry(rate, "rad/s", "-Omega sin(lat)"),
                "precession_period": Entry(period, "s", "2 pi / (Omega |sin lat|)"),
                "swing_period": Entry(swing, "s", "2 pi sqrt(l/g)"),
                "latitude": Entry(sp.latitude, "rad"),
                "omega": Entry(sp.omega, "rad/s"),
            },
            (
                f"the swing plane turns at -Omega sin(lat) = {fmt(rate)} rad/s, a full turn in "
                f"{fmt(period / 3600)} h (docs/theory.md §9); swing period {fmt(swing)} s",
            ),
        )

    def checks(self, scenario: Scenario, tr: Any) -> Sequence[Check]:
        sp = scenario.spec
        force = PendulumForce(sp.mass, sp.g, sp.length)
        return (self._jacobi(scenario, tr, foucault_frame(sp.latitude, sp.omega), force.potential),)

    def figures(self, result: ScenarioResult) -> list[FigureSpec]:
        figs = self._path_figures(result, (0, 1), "east, north")
        tr = result.trajectory
        sp = result.scenario.spec

        def plane(ax: Any) -> Any:
            return plot_swing_plane(tr, rate=foucault_precession_rate(sp.latitude, sp.omega), ax=ax)

        figs.append(FigureSpec("swing_plane.png", plane))
        inv = invariants_figure(result)
        return figs + ([inv] if inv is not None else [])

    def report(self, result: ScenarioResult) -> ReportSpec:
        """The Earth kinds' report, with the swing plane drawn turning at
        ``-Omega sin(lat)`` from the release direction (docs/theory.md §9)."""

        spec = super().report(result)
        tr = result.trajectory
        sp = result.scenario.spec
        r0 = np.asarray(tr.position[0], dtype=float)
        a = np.arctan2(r0[1], r0[0]) + foucault_precession_rate(sp.latitude, sp.omega) * (
            tr.t - tr.t[0]
        )
        e = 1.15 * sp.amplitude * np.column_stack([np.cos(a), np.sin(a), np.zeros_like(a)])
        label = "swing plane, turning at -Omega sin(lat) (dashed)"
        return dataclasses.replace(spec, drawing=Drawing(guides={label: np.stack([-e, e], axis=1)}))

    def describe_scenario(self, scenario: Scenario) -> list[str]:
        sp = scenario.spec
        return [f"{self.title}: {fmt(sp.length)} m at latitude {fmt(np.degrees(sp.latitude))} deg"]


FREE_FALL = FreeFall()
FOUCAULT = Foucault()
KIND = FREE_FALL
