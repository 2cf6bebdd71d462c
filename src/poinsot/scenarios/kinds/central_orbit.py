"""Adapter: a particle under a central force (docs/theory.md §9).

Table [orbit]: the potential energy as a sum of terms -- ``mu`` (Kepler
``-mu/r``), ``beta`` (``beta/r^2``), ``k`` (oscillator ``k r^2/2``), at least one
-- then ``mass`` (kg, default 1) and the initial state: either ``position`` (m)
and ``velocity`` (m/s), or ``energy`` (J) and ``angular_momentum`` (kg m^2/s)
(start at the pericentre). Solved by :class:`poinsot.dynamics.CentralOrbit`:
``method = "exact"`` is Kepler's equation (a pure Kepler potential only),
``"adaptive"`` the integration (DOP853, rtol 1e-12); either returns the
library's :class:`~poinsot.trajectory.PointTrajectory` (position and velocity in
inertial axes). Checks: energy and the angular momentum vector are conserved.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from ...dynamics import CentralOrbit, ParticleSystem, harmonic, inverse_square, kepler
from ...errors import PoinsotError
from ...plotting.particles import plot_effective_potential, plot_orbit
from ..kind import ReportSpec
from ..report import figure_sections, unit_charts

if TYPE_CHECKING:
    from .._toml import Table
    from ..kind import Check, Facts, FigureSpec, Progress, ReportSpec
    from ..schema import AttitudeSpec, Scenario
    from ..summary import ScenarioResult

from dataclasses import dataclass

import numpy as np

from ..describe import fmt
from ..figures import invariants_figure
from ..kind import Check, Drawing, Entry, Facts, FigureSpec, ScenarioKind

_TERMS = ("mu", "beta", "k")


@dataclass(frozen=True)
class OrbitSpec:
    """What [orbit] says, in SI units."""

    mu: float | None
    beta: float | None
    k: float | None
    mass: float
    position: tuple[Any, ...] | None = None
    velocity: tuple[Any, ...] | None = None
    energy: float | None = None
    angular_momentum: float | None = None


def apsides_line(t: np.ndarray, position: np.ndarray) -> np.ndarray | None:
    """The line of apsides as the run traces it, for ``report.html``: at each sample
    the segment from the origin through the latest pericentre passage (a local
    minimum of ``r = |position|``; the first one before it is reached), from the
    apocentre side (the largest ``r``) to the pericentre, shape (n, 2, 3). A
    precessing orbit's line turns by ``2 Phi - 2 pi`` per radial period (apsidal
    angle ``Phi``, docs/theory.md §9); a Kepler ellipse's stays. None without a
    pericentre passage (a circle, or too short a run).

    Examples
    --------
    >>> t = np.linspace(0.1, 4 * np.pi, 400)  # an ellipse about its focus, r 0.5 .. 1.5 m
    >>> pos = np.column_stack([np.cos(t) - 0.5, np.sqrt(0.75) * np.sin(t), 0 * t])
    >>> apsides_line(t, pos)[-1].round(2).tolist()
    [[-1.5, 0.0, 0.0], [0.5, 0.0, 0.0]]
    """
    r = np.linalg.norm(position, axis=-1)
    if r.size < 3 or np.ptp(r) <= 1e-9 * float(np.max(r)):
        return None
    minima = np.flatnonzero((r[1:-1] <= r[:-2]) & (r[1:-1] < r[2:])) + 1
    if minima.size == 0:
        return None
    latest = minima[np.clip(np.searchsorted(minima, np.arange(r.size), side="right") - 1, 0, None)]
    e = position[latest] / r[latest, None]
    return np.stack([-float(np.max(r)) * e, r[latest, None] * e], axis=1)


def _orbit(spec: Any) -> Any:
    terms = []
    if spec.mu is not None:
        terms.append(kepler(spec.mu))
    if spec.beta is not None:
        terms.append(inverse_square(spec.beta))
    if spec.k is not None:
        terms.append(harmonic(spec.k))
    potential = terms[0]
    for term in terms[1:]:
        potential = potential + term
    if spec.position is not None:
        return CentralOrbit.from_state(potential, spec.position, spec.velocity, mass=spec.mass)
    return CentralOrbit(
        potential, energy=spec.energy, angular_momentum=spec.angular_momentum, mass=spec.mass
    )


class CentralOrbitKind(ScenarioKind):
    name = "central-orbit"
    title = "particle under a central force (Kepler and beyond)"
    tables = ("orbit",)
    methods = ("exact", "adaptive")  # of integrators.names("particle", exact=True)
    orders: dict[str, int] = {}
    theory = "docs/theory.md §9"
    # cost estimate, one core, measured by benchmarks/bench_estimates.py on the examples
    seconds_per_step = {"exact": 1.5e-6, "adaptive": 8e-6}
    seconds_per_run = {"exact": 1e-3, "adaptive": 3e-3}

    def claims(self, data: Mapping[str, Any]) -> bool:
        return "orbit" in data

    def parse(self, top: Table, attitude: AttitudeSpec) -> dict[str, Any]:
        t = top.table("orbit", required=True)
        keys = (*_TERMS, "mass", "position", "velocity", "energy", "angular_momentum")
        t.known(keys)
        terms: dict[str, Any] = {name: t.number(name) for name in _TERMS}  # float or None
        if all(v is None for v in terms.values()):
            raise t.error(
                None,
                "expected at least one potential term: `mu` (-mu/r), "
                "`beta` (beta/r^2) or `k` (k r^2/2).",
            )
        mass = t.number("mass", 1.0, positive=True)
        how = t.exclusive(("position", "energy"), what="the initial state")
        if how == "position":
            spec = OrbitSpec(
                **terms,
                mass=mass,
                position=t.vector("position", 3),
                velocity=t.vector("velocity", 3),
            )
        else:
            spec = OrbitSpec(
                **terms,
                mass=mass,
                energy=t.number("energy", required=True),
                angular_momentum=t.number("angular_momentum", required=True),
            )
        t.finish(keys)

        try:
            _orbit(spec)
        except PoinsotError as exc:
            raise t.error(None, f"no orbit: {exc}") from None
        return {"spec": spec}

    def refuse_method(self, method: str, fields: Mapping[str, Any]) -> str | None:
        sp = fields["spec"]
        if method == "exact" and (sp.mu is None or sp.mu <= 0 or sp.beta or sp.k):
            return (
                '"exact" (Kepler\'s equation) needs a pure attractive Kepler potential '
                '(only `mu` > 0); use "adaptive".'
            )
        return None

    def motion_inertia(self, scenario: Scenario) -> np.ndarray | None:
        return None

    def solve(self, scenario: Scenario, method: str, t: np.ndarray, progress: Progress) -> Any:
        orb = _orbit(scenario.spec)
        progress(0.0, method)
        tr = orb.trajectory(t, method="kepler" if method == "exact" else "integrate")
        progress(1.0, method)
        return tr

    def facts(self, scenario: Scenario) -> Facts:
        orb = _orbit(scenario.spec)
        r1, r2 = orb.apsides
        entries = {
            "energy": Entry(orb.energy, "J"),
            "angular_momentum": Entry(orb.angular_momentum, "kg m^2/s"),
            "pericentre": Entry(r1, "m"),
            "apocentre": Entry(r2, "m"),
            "bound": not orb.unbound,
            "radial_period": Entry(orb.radial_period, "s"),
            "apsidal_angle": Entry(orb.apsidal_angle, "rad"),
            "apsidal_angle_over_pi": Entry(orb.apsidal_angle / np.pi, "1"),
            "areal_velocity": Entry(orb.areal_velocity, "m^2/s"),
            "closed": orb.is_closed(),
        }
        lines = [
            f"apsides {fmt(r1)} m and {fmt(r2)} m; apsidal angle "
            f"{fmt(orb.apsidal_angle / np.pi)} pi, radial period {fmt(orb.radial_period)} s, "
            f"areal velocity {fmt(orb.areal_velocity)} m^2/s (docs/theory.md §9)"
        ]
        sp = scenario.spec
        if sp.mu is not None and sp.mu > 0 and not sp.beta and not sp.k:
            c = orb.conic
            entries.update(
                {
                    "semi_latus_rectum": Entry(c.p, "m"),
                    "eccentricity": Entry(c.e, "1"),
                    "semi_major_axis": Entry(c.a, "m"),
                    "kepler_period": Entry(c.period, "s"),
                }
            )
            lines.append(
                f"Kepler conic: p = {fmt(c.p)} m, e = {fmt(c.e)}, a = {fmt(c.a)} m, "
                f"period {fmt(c.period)} s"
            )
        return Facts(entries, tuple(lines))

    def checks(self, scenario: Scenario, tr: Any) -> Sequence[Check]:
        orb = _orbit(scenario.spec)
        sys = ParticleSystem(
            np.full((tr.t.size, 1), orb.mass), tr.position[:, None], tr.velocity[:, None]
        )
        r = np.linalg.norm(tr.position, axis=-1)
        energy = sys.kinetic_energy + orb.potential(r)
        out = []
        sp = scenario.spec
        if sp.mu is not None and sp.mu > 0 and not sp.beta and not sp.k:
            out.append(
                Check(
                    "kepler_position",
                    "position vs Kepler's equation",
                    "m",
                    tr.position,
                    expected=orb.orbit(tr.t, method="kepler"),
                    scale=orb.apsides.pericentre,
                    conserved=False,
                    law="the conic r = p / (1 + e cos nu), Kepler's equation",
                )
            )
        return (
            *out,
            Check(
                "energy",
                "energy T + U",
                "J",
                energy,
                scale=float(max(abs(orb.energy), np.max(np.abs(energy - orb.energy)), 1e-300)),
            ),
            Check(
                "angular_momentum",
                "angular momentum vector K_O",
                "kg m^2/s",
                sys.angular_momentum(),
            ),
        )

    def figures(self, result: ScenarioResult) -> list[FigureSpec]:
        tr = result.trajectory
        orb = _orbit(result.scenario.spec)

        def orbit(ax: Any) -> Any:
            return plot_orbit(orb, tr.t, ax=ax)

        def ueff(ax: Any) -> Any:
            return plot_effective_potential(orb, ax=ax)

        figs = [
            FigureSpec("orbit.png", orbit, (6.0, 6.0)),
            FigureSpec("effective_potential.png", ueff),
        ]
        inv = invariants_figure(result)
        return figs + ([inv] if inv is not None else [])

    def report(self, result: ScenarioResult) -> ReportSpec:
        """``report.html``: the point and its orbit in space, charts of the position
        and velocity components, the checks, and the orbit (apsides marked) and the
        effective potential as inline SVG."""

        tr = result.trajectory
        names = ("x", "y", "z")
        columns = {n: (tr.position[:, k], "m") for k, n in enumerate(names)}
        columns.update({f"v{n}": (tr.velocity[:, k], "m/s") for k, n in enumerate(names)})
        specs = [f for f in self.figures(result) if f.name != "invariants.png"]
        titles = {
            "orbit.png": "The orbit, apsides marked (docs/theory.md §9)",
            "effective_potential.png": "Effective potential U + L^2/(2 m r^2)",
        }
        guide = apsides_line(tr.t, tr.position)
        label = "line of apsides through the latest pericentre (dashed)"
        return ReportSpec(
            motion=tr,
            charts=tuple(unit_charts(columns)),
            checks=tuple(result.checks),
            sections=tuple(figure_sections(specs, [titles.get(f.name, f.name) for f in specs])),
            drawing=None if guide is None else Drawing(guides={label: guide}),
        )

    def describe_scenario(self, scenario: Scenario) -> list[str]:
        sp = scenario.spec
        terms = [f"{n} = {fmt(getattr(sp, n))}" for n in _TERMS if getattr(sp, n) is not None]
        return [f"{self.title}: {', '.join(terms)}"]


KIND = CentralOrbitKind()
