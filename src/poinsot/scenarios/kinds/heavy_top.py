"""Adapter: the heavy rigid body about a fixed point (docs/theory.md §10).

Tables: [body] (the fixed point is the origin of the body axes, the centre of
mass ``center_of_mass`` from it), [angular_velocity], [torque] with
``model = "gravity"``. Solved by :class:`poinsot.dynamics.HeavyRigidBody`
(integrators; the default structure-preserving splitting keeps ``K_z`` to
round-off) or, for a Lagrange top (``A = B`` about the pin, centre of mass on the
body ``z`` axis), by the exact :class:`poinsot.dynamics.LagrangeTop`
(``method = "exact"``, also usable as the ``reference``). Facts: the integrals,
the roots of the cubic, the nutation band and period, the motion type and the
Maievskii ratio of a Lagrange top; the Kovalevskaya integral when ``A = B = 2 C``
with the centre of mass in the equatorial plane. Checks: ``T + V`` and ``K_z``
(and ``H = C r``, or the Kovalevskaya integral) are conserved.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from ...dynamics import (
    HeavyRigidBody,
    LagrangeTop,
    critical_spin,
    gyroscope_precession_rate,
    regular_precession_rates,
)
from ...errors import InvalidInputError
from ...plotting.heavy_top import (
    plot_axis_track,
    plot_cubic,
    plot_invariant_drift,
    plot_kovalevskaya,
    plot_nutation,
)
from ..report import figure_sections
from ..solve import chunked

if TYPE_CHECKING:
    from .._toml import Table
    from ..kind import Check, Entry, Facts, FigureSpec, Progress, ReportSpec
    from ..schema import AttitudeSpec, Scenario
    from ..summary import ScenarioResult

import math

import numpy as np

from ... import integrators
from ..describe import fmt
from ..kind import Check, Entry, Facts, FigureSpec
from ..schema import DYNAMICS_METHODS
from . import _rigid


def _heavy(body: Any, torque: Any) -> Any:
    return HeavyRigidBody(body.inertia_about_origin(), body.mass, body.center_of_mass, g=torque.g)


def _lagrange(body: Any, torque: Any, rotation: Any = None, omega: Any = None) -> Any:
    """The scenario's LagrangeTop, or ``(None, reason)`` when the body is not one."""

    rot = rotation if rotation is not None else np.array([1.0, 0.0, 0.0, 0.0])
    w = omega if omega is not None else np.zeros(3)
    try:
        return LagrangeTop.from_state(_heavy(body, torque), None, rot, w), None
    except InvalidInputError as exc:
        return None, str(exc)


def _kovalevskaya(body: Any) -> bool:
    """``A = B = 2 C`` about the pin and the centre of mass in the equatorial plane."""
    j = np.asarray(body.inertia_about_origin())
    c = np.asarray(body.center_of_mass)
    tol = 1e-9 * float(np.max(np.abs(j)))
    diag = np.max(np.abs(j - np.diag(np.diag(j)))) <= tol
    return bool(
        diag
        and abs(j[0, 0] - j[1, 1]) <= tol
        and abs(j[0, 0] - 2.0 * j[2, 2]) <= tol
        and abs(c[2]) <= 1e-12 * float(np.linalg.norm(c))
    )


def _lagrange_facts(top: Any, scenario: Any) -> Facts:
    body = scenario.body
    lo, hi = top.nutation_bounds
    p_min, p_max = top.psi_rate_at_bounds()
    u1, u2, u3 = top.cos_theta_roots
    e: dict[str, Entry] = {
        "case": Entry("Lagrange top (docs/theory.md §10)"),
        "solution": Entry("exact: Jacobi elliptic functions and integrals of the third kind"),
        "A": Entry(top.A, "kg m^2", "equatorial moment about the fixed point"),
        "C": Entry(top.C, "kg m^2", "axial moment about the fixed point"),
        "l": Entry(float(body.center_of_mass[2]), "m", "signed distance pin -> centre of mass"),
        "mgl": Entry(top.mgl, "N m"),
        "H": Entry(top.H, "kg m^2/s", "H = C r"),
        "K_z": Entry(top.K_z, "kg m^2/s", "area integral"),
        "E": Entry(top.E, "J", "E = T + V - H^2/(2C): the energy without the spin term"),
        "energy": Entry(top.energy, "J", "total energy T + V (conserved)"),
        "motion": Entry(top.motion_type),
        "maievskii_ratio": Entry(top.maievskii_ratio, "1", "C^2 r^2 / (4 A m g l)"),
        "critical_spin": Entry(float(critical_spin(top.A, top.C, top.mgl)), "rad/s"),
        "cos_theta_roots": Entry([u1, u2, u3], "1", "roots u1 <= u2 <= u3 of P(u)"),
        "nutation_theta_min": Entry(lo, "rad"),
        "nutation_theta_max": Entry(hi, "rad"),
        "nutation_period": Entry(top.nutation_period, "s"),
        "precession_per_nutation": Entry(top.precession_per_nutation, "rad"),
        "mean_precession_rate": Entry(top.mean_precession_rate, "rad/s"),
        "psi_dot_at_theta_min": Entry(p_min, "rad/s"),
        "psi_dot_at_theta_max": Entry(p_max, "rad/s"),
    }
    theta0 = float(top.theta(0.0))
    if top.spin != 0.0:
        e["gyroscope_precession_rate"] = Entry(
            float(gyroscope_precession_rate(top.C, top.mgl, top.spin)), "rad/s", "m g l / (C r)"
        )
    try:
        slow, fast = regular_precession_rates(top.A, top.C, top.mgl, theta0, top.spin)
        e["regular_precession_rates"] = Entry(
            [float(slow), float(fast)], "rad/s", "slow and fast psi' at the initial tilt"
        )
    except InvalidInputError:  # they do not exist (spin too slow): not reported
        pass
    for k, v in list(e.items()):
        if isinstance(v.value, float) and not math.isfinite(v.value):
            del e[k]  # JSON has no inf/NaN: absent means "not defined" (e.g. separatrix)
    band = f"tilt {np.degrees(lo):.4f} to {np.degrees(hi):.4f} deg"
    period = top.nutation_period
    per = f", nutation period {fmt(period)} s" if math.isfinite(period) else ""
    lines = (
        f"Lagrange top, exact solution (docs/theory.md §10): {top.motion_type}, {band}{per}",
        f"H = C r = {fmt(top.H)} kg m^2/s, K_z = {fmt(top.K_z)} kg m^2/s, "
        f"roots of P(u): {fmt(u1)}, {fmt(u2)}, {fmt(u3)}",
        f"Maievskii ratio C^2 r^2/(4 A m g l) = {fmt(top.maievskii_ratio)} "
        f"(the upright top is stable above 1)",
        f"energies: total T + V = {fmt(top.energy)} J (conserved, checked below); "
        f"E = T + V - H^2/(2C) = {fmt(top.E)} J leaves out the constant spin term and is "
        "the energy of the nutation in P(u) (docs/theory.md §10)",
    )
    return Facts(e, lines)


class HeavyTop(_rigid.RigidKind):
    name = "heavy-top"
    title = "heavy rigid body about a fixed point (Euler-Poisson; Lagrange, Kovalevskaya tops)"
    tables = _rigid.TABLES
    methods = DYNAMICS_METHODS
    orders = integrators.orders(DYNAMICS_METHODS)
    theory = "docs/theory.md §10"
    # cost estimate, one core, measured by benchmarks/bench_estimates.py on the examples
    seconds_per_step = {
        "exact": 4e-7,
        "splitting": 7.5e-8,
        "midpoint": 3e-7,
        "rk4": 1e-6,
        "dop853": 5e-7,
        "adaptive": 1.5e-4,
    }
    seconds_per_run = {"exact": 1.5e-3, "splitting": 1.7e-2}

    def claims(self, data: Mapping[str, Any]) -> bool:
        torque = data.get("torque")
        return isinstance(torque, dict) and torque.get("model") == "gravity"

    def parse(self, top: Table, attitude: AttitudeSpec) -> dict[str, Any]:
        fields = _rigid.parse_rigid(top, attitude)
        if fields["torque"].model != "gravity":
            raise top.error(
                "torque.model",
                'a "heavy-top" scenario is a body in gravity about a fixed point: expected '
                f'[torque] model = "gravity", found "{fields["torque"].model}".',
            )
        return fields

    def refuse_method(self, method: str, fields: Mapping[str, Any]) -> str | None:
        if method != "exact":
            return None
        top, reason = _lagrange(fields["body"], fields["torque"])
        if top is None:
            return (
                '"exact" solves the Lagrange top (docs/theory.md §10) but this body is not '
                f'one: {reason} Use an integrator, e.g. "splitting".'
            )
        return None

    def motion_inertia(self, scenario: Scenario) -> np.ndarray | None:
        return scenario.body.inertia_about_origin()

    def _top(self, scenario: Any) -> Any:
        return _lagrange(
            scenario.body,
            scenario.torque,
            scenario.attitude.rotation,
            np.asarray(scenario.angular_velocity.omega_body),
        )[0]

    def solve(self, scenario: Scenario, method: str, t: np.ndarray, progress: Progress) -> Any:
        if method == "exact":
            top = self._top(scenario)
            progress(0.0, "exact solution")
            tr = top.trajectory(t)
            progress(1.0, "exact solution")
            return tr

        body = _heavy(scenario.body, scenario.torque)
        return chunked(
            lambda rot, w, tt: body.simulate(
                rot, w, tt, method=method, max_step=scenario.simulation.max_step
            ),
            scenario.attitude.rotation,
            np.asarray(scenario.angular_velocity.omega_body),
            t,
            progress,
            f"integrating ({method})",
        )

    def body_entries(self, scenario: Scenario) -> dict[str, Entry]:
        return {"inertia_about_fixed_point": Entry(scenario.body.inertia_about_origin(), "kg m^2")}

    def series(self, scenario: Scenario, tr: Any) -> dict[str, tuple[np.ndarray, str]]:
        v = _rigid.torque_model(scenario).potential(tr.quat)
        return {"V": (np.asarray(v), "J")}

    def facts(self, scenario: Scenario) -> Facts:
        top = self._top(scenario)
        if top is not None:
            return _lagrange_facts(top, scenario)
        body = _heavy(scenario.body, scenario.torque)
        rot = scenario.attitude.rotation
        w = np.asarray(scenario.angular_velocity.omega_body)
        entries = {
            "case": Entry("heavy body about a fixed point (docs/theory.md §10)"),
            "energy": Entry(float(body.energy(rot, w)), "J", "total energy T + V"),
            "K_z": Entry(float(body.momentum_z(rot, w)), "kg m^2/s", "area integral"),
        }
        lines = [
            f"heavy body: E = {fmt(entries['energy'].value)} J and K_z = "
            f"{fmt(entries['K_z'].value)} kg m^2/s are conserved (docs/theory.md §10)"
        ]
        if _kovalevskaya(scenario.body):
            k = float(body.kovalevskaya_integral(rot, w))
            entries["case"] = Entry("Kovalevskaya top (docs/theory.md §10)")
            entries["kovalevskaya_integral"] = Entry(k, "rad^4/s^4")
            lines.append(
                f"Kovalevskaya top (A = B = 2C about the fixed point, centre of mass in the "
                f"equatorial plane): the fourth integral "
                f"k = {fmt(k)} rad^4/s^4 is conserved"
            )
        return Facts(entries, tuple(lines))

    def checks(self, scenario: Scenario, tr: Any) -> Sequence[Check]:
        model = _rigid.torque_model(scenario)
        inv = _rigid.invariants_of(self.motion_inertia(scenario), tr, model)
        k0 = float(inv.momentum_norm[0])
        total = inv.energy
        out = [
            Check(
                "total_energy",
                "total energy T + V",
                "J",
                total,
                scale=max(abs(total[0]), abs(inv.kinetic[0]), 1e-300),
            ),
            Check("momentum_z", "K_z (vertical)", "kg m^2/s", inv.momentum_z, scale=k0),
        ]
        if self._top(scenario) is not None:
            # Lagrange top: the momentum about the symmetry axis, H = C r, is conserved
            out.append(
                Check(
                    "spin_momentum_H",
                    "H = C r (symmetry axis)",
                    "kg m^2/s",
                    inv.momentum_body[..., 2],
                    scale=k0,
                )
            )
        elif _kovalevskaya(scenario.body):
            body = _heavy(scenario.body, scenario.torque)
            k = np.asarray(body.kovalevskaya_integral(tr.rotation, tr.omega))
            out.append(Check("kovalevskaya_integral", "Kovalevskaya integral", "rad^4/s^4", k))
        return out

    def figures(self, result: ScenarioResult) -> list[FigureSpec]:
        figs = super().figures(result)
        scenario = result.scenario
        top = self._top(scenario)
        tr = result.trajectory
        if top is not None:

            def track(ax: Any) -> Any:
                return plot_axis_track(top, tr.t[:: max(1, tr.t.size // 1500)], ax=ax)

            def cubic(ax: Any) -> Any:
                return plot_cubic(top, ax=ax)

            def nutation(ax: Any) -> Any:
                numerical = tr if tr.method != "exact" else result.reference
                return plot_nutation(top, numerical, ax=ax)

            figs.append(FigureSpec("axis_track.png", track, (6.0, 6.0), "3d"))
            figs.append(FigureSpec("cubic.png", cubic))
            figs.append(FigureSpec("nutation.png", nutation))
        body = _heavy(scenario.body, scenario.torque)
        numerical = tr if tr.method != "exact" else result.reference
        if numerical is not None:

            def drift(ax: Any) -> Any:
                return plot_invariant_drift(body, numerical, ax=ax)

            figs.append(FigureSpec("heavy_invariants.png", drift))
        if top is None and _kovalevskaya(scenario.body):

            def kova(ax: Any) -> Any:
                return plot_kovalevskaya([(f"{tr.method}", body, tr)], ax=ax)

            figs.append(FigureSpec("kovalevskaya.png", kova))
        return figs

    def report(self, result: ScenarioResult) -> ReportSpec:
        """A rigid body's report (the top on its pin, the gravity torque, ZXZ angles)
        with the heavy-top figures (axis track, P(u), theta(t), invariants) as
        inline SVG."""

        titles = {
            "axis_track.png": "Track of the symmetry axis on the unit sphere (docs/theory.md §10)",
            "cubic.png": "The cubic P(u) = u'^2 with its roots and the nutation band",
            "nutation.png": "theta(t): exact (elliptic functions) and numerical",
            "heavy_invariants.png": "Drift of E, K_z and |gamma| along the numerical run",
            "kovalevskaya.png": "The Kovalevskaya integral along the run",
        }
        specs = [f for f in self.figures(result) if f.name in titles]
        sections = figure_sections(specs, [titles[f.name] for f in specs])
        return _rigid.rigid_report(result, sections=sections)

    def describe_scenario(self, scenario: Scenario) -> list[str]:
        top, _ = _lagrange(scenario.body, scenario.torque)
        if top is not None:
            return [f"{self.title}: a Lagrange top (exact solution available)"]
        if _kovalevskaya(scenario.body):
            return [f"{self.title}: a Kovalevskaya top"]
        return [self.title]


KIND = HeavyTop()
