"""Adapter: a torque-free rigid body (Euler-Poinsot case, docs/theory.md §10).

Tables: [body], [angular_velocity], [torque] (absent or ``model = "none"``).
Solved by :class:`poinsot.dynamics.FreeRigidBody` (``method = "exact"``: Jacobi
elliptic functions) or :func:`poinsot.dynamics.simulate` (integrators). Checks:
``T``, ``|K|`` and the space vector ``K`` are conserved.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from ...dynamics import FreeRigidBody
from ...plotting.free_body import plot_maccullagh, plot_poinsot

if TYPE_CHECKING:
    from .._toml import Table
    from ..kind import Check, Facts, FigureSpec, Progress, ReportSpec
    from ..schema import AttitudeSpec, Scenario
    from ..summary import ScenarioResult

from dataclasses import dataclass

import numpy as np

from ... import integrators
from ..describe import fmt
from ..kind import Check, Entry, Facts, FigureSpec
from ..schema import DYNAMICS_METHODS
from . import _rigid


def _free_body(scenario: Any) -> Any:
    return FreeRigidBody(
        np.asarray(scenario.body.inertia),
        omega0=np.asarray(scenario.angular_velocity.omega_body),
        rotation0=scenario.attitude.rotation,
    )


@dataclass(frozen=True)
class FreeBodyFacts(Facts):
    """The closed-form properties of a torque-free motion (a FreeRigidBody)."""

    body: Any = None  # the FreeRigidBody
    diagonal: bool = True  # body axes are principal (axes named x, y, z in text)

    def entries_(self) -> Any:
        fb = self.body
        out = {"solution": Entry("Jacobi elliptic functions (docs/theory.md §10)")}
        for key, units in (
            ("energy", "J"),
            ("momentum", "kg m^2/s"),
            ("momentum_norm", "kg m^2/s"),
            ("principal_moments", "kg m^2"),
            ("principal_axes", "1"),
            ("regime", ""),
            ("polhode_axis", ""),
            ("stable_axes", ""),
            ("period", "s"),
            ("precession_per_period", "rad"),
            ("complementary_parameter", "1"),
        ):
            value: Any = getattr(fb, key, None)
            if key == "principal_axes":  # a method, as on mass.RigidBody: (moments, S)
                value = value()[1].as_matrix()
            if value is not None:
                out[key] = Entry(np.asarray(value) if key == "principal_axes" else value, units)
        rate = self.precession_rate
        if rate is not None:
            out["precession_rate"] = Entry(rate, "rad/s")
        return out

    @property
    def precession_rate(self) -> float | None:
        """Symmetric body: regular precession about ``K`` at ``|K| / A`` (``A`` the
        moment of the two equal axes), docs/theory.md §10."""
        m = np.asarray(self.body.principal_moments)
        if (m[0] == m[1] or m[1] == m[2]) and m[0] != m[2]:
            a = m[0] if m[0] == m[1] else m[1]
            return float(self.body.momentum_norm / a)
        return None

    def describe(self) -> Any:
        fb = self.body
        period = fb.period
        per = (
            f"omega periodic with period {fmt(period)} s"
            if np.isfinite(period)
            else "omega not periodic"
        )
        lines = [
            f"exact solution, Jacobi elliptic functions (docs/theory.md §10): "
            f"T = {fmt(fb.energy)} J, |K| = {fmt(fb.momentum_norm)} kg m^2/s, {per}"
        ]
        stable, moments = fb.stable_axes, np.asarray(fb.principal_moments)
        if len(set(moments.tolist())) == 3:
            names = [
                f"{'xyz'[k]} ({fmt(m)} kg m^2)" if self.diagonal else f"the axis of moment {fmt(m)}"
                for k, m in enumerate(moments)
            ]
            good = " and ".join(n for n, ok in zip(names, stable, strict=True) if ok)
            bad = " and ".join(n for n, ok in zip(names, stable, strict=True) if not ok)
            lines.append(
                f"permanent rotations: stable about {good}, unstable about {bad} "
                "(docs/theory.md §10)"
            )
        if self.precession_rate is not None:
            lines.append(f"regular precession about K at {fmt(self.precession_rate)} rad/s")
        return lines


class FreeBody(_rigid.RigidKind):
    name = "free-body"
    title = "torque-free rigid body (Euler-Poinsot case)"
    tables = _rigid.TABLES
    methods = DYNAMICS_METHODS
    orders = integrators.orders(DYNAMICS_METHODS)
    theory = "docs/theory.md §10"
    seconds_per_step = _rigid.SECONDS_PER_STEP
    seconds_per_run = _rigid.SECONDS_PER_RUN

    def claims(self, data: Mapping[str, Any]) -> bool:
        return "body" in data or "angular_velocity" in data

    def parse(self, top: Table, attitude: AttitudeSpec) -> dict[str, Any]:
        fields = _rigid.parse_rigid(top, attitude)
        if fields["torque"].model != "none":
            raise top.error(
                "torque.model",
                f'a "free-body" scenario has no torque: expected "none", found '
                f'"{fields["torque"].model}" (remove `kind` to solve it with the torque).',
            )
        return fields

    def solve(self, scenario: Scenario, method: str, t: np.ndarray, progress: Progress) -> Any:
        if method == "exact":
            fb = _free_body(scenario)
            progress(0.0, "exact solution")
            tr = fb.trajectory(t)
            progress(1.0, "exact solution")
            return tr
        inertia = np.asarray(scenario.body.inertia)
        return _rigid.simulate_rigid(scenario, inertia, None, method, t, progress)

    def facts(self, scenario: Scenario) -> Facts:
        j = np.asarray(scenario.body.inertia)
        diagonal = bool(np.max(np.abs(j - np.diag(np.diag(j)))) <= 1e-12 * np.max(np.abs(j)))
        return FreeBodyFacts(body=_free_body(scenario), diagonal=diagonal)

    def checks(self, scenario: Scenario, tr: Any) -> Sequence[Check]:
        inv = _rigid.invariants_of(np.asarray(scenario.body.inertia), tr)
        k = inv.momentum_space
        return (
            Check("energy", "kinetic energy T", "J", inv.kinetic),
            Check("momentum_norm", "|K|", "kg m^2/s", inv.momentum_norm),
            Check("momentum_vector", "K (space axes)", "kg m^2/s", k),
        )

    def figures(self, result: ScenarioResult) -> list[FigureSpec]:
        figs = super().figures(result)
        fb = result.facts.body  # type: ignore[attr-defined]  # this kind's FreeBodyFacts
        t = result.trajectory.t

        def maccullagh(ax: Any) -> Any:
            return plot_maccullagh(fb, ax=ax)

        def poinsot(ax: Any) -> Any:
            return plot_poinsot(fb, t[:: max(1, t.size // 800)], ax=ax)

        figs.append(FigureSpec("maccullagh.png", maccullagh, (6.0, 6.0), "3d"))
        figs.append(FigureSpec("poinsot.png", poinsot, (6.0, 6.0), "3d"))
        return figs

    def report(self, result: ScenarioResult) -> ReportSpec:
        """A rigid body's report with the polhode and herpolhode (docs/theory.md §10)."""
        return _rigid.rigid_report(result, polhode=True)


KIND = FreeBody()
