"""Adapter: attitude propagated from a prescribed angular velocity (docs/theory.md §5).

Tables: [omega_profile] (``kind`` ``"constant"`` or ``"samples"``; ``"coning"`` is
the :mod:`.coning` kind) and an optional [body] (then ``T`` and ``K`` are reported).
Solved by :func:`poinsot.kinematics.propagate` (Poisson's equation).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from ...kinematics import coning_omega, propagate
from ...rotations.rotation import Rotation
from ...trajectory import Trajectory
from ..solve import chunked

if TYPE_CHECKING:
    from .._toml import Table
    from ..kind import Check, Facts, Progress
    from ..schema import AttitudeSpec, Scenario, SimulationSpec

import numpy as np

from ... import integrators
from ..kind import Check, Entry, Facts
from ..readers import read_body, read_omega_profile
from ..schema import KINEMATICS_METHODS
from . import _rigid


def omega_function(profile: Any) -> Any:
    """``omega(t)`` of a profile, as :func:`poinsot.kinematics.propagate` takes it."""
    if profile.kind == "constant":
        w = np.asarray(profile.vector)
        return lambda t: w
    if profile.kind == "coning":
        return lambda t: coning_omega(profile.half_angle, profile.rate, t)
    ts, ws = np.asarray(profile.t), np.asarray(profile.omega)

    def sampled(t: Any) -> Any:
        # linear interpolation of the table (the times are checked to lie inside it)
        return np.array([np.interp(t, ts, ws[:, k]) for k in range(3)])

    return sampled


class Attitude(_rigid.RigidKind):
    name = "attitude"
    title = "attitude propagated from a prescribed angular velocity (Poisson's equation)"
    tables = ("body", "omega_profile")
    methods = KINEMATICS_METHODS
    orders = integrators.orders(KINEMATICS_METHODS)
    theory = "docs/theory.md §5"
    # measured on the shipped examples: a Python omega(t) per step dominates
    # measured by benchmarks/bench_estimates.py (one core)
    seconds_per_step = {"exact": 2e-7, "magnus4": 1.5e-5, "rk4": 1.5e-5, "adaptive": 1.5e-5}
    profiles: tuple[str, ...] = ("constant", "samples")

    def claims(self, data: Mapping[str, Any]) -> bool:
        return "omega_profile" in data

    def parse(self, top: Table, attitude: AttitudeSpec) -> dict[str, Any]:
        profile_t = top.table("omega_profile", required=True)
        body_t = top.table("body")
        body = read_body(body_t) if body_t is not None else None
        top.forbid(
            ["angular_velocity"],
            "a scenario with [omega_profile] takes its angular "
            "velocity from the profile (remove [angular_velocity])",
        )
        top.forbid(
            ["torque"],
            "[omega_profile] scenarios propagate the attitude only (no dynamics, no torque)",
        )
        profile = read_omega_profile(profile_t)
        if profile.kind not in self.profiles:
            raise profile_t.error(
                "kind",
                f"a {self.name!r} scenario takes a profile of kind "
                + " or ".join(f'"{p}"' for p in self.profiles)
                + f", found {profile.kind!r}.",
            )
        return {"body": body, "omega_profile": profile}

    def refuse_method(self, method: str, fields: Mapping[str, Any]) -> str | None:
        if method == "exact" and fields["omega_profile"].kind == "samples":
            return (
                '"exact" needs a closed form, and a tabulated angular '
                "velocity has none: expected one of "
                + ", ".join(f'"{x}"' for x in self.methods if x != "exact")
                + "."
            )
        return None

    def check_simulation(
        self, simulation: SimulationSpec, fields: Mapping[str, Any]
    ) -> tuple[str, str] | None:
        p = fields["omega_profile"]
        if p.kind == "samples" and simulation.duration > p.t[-1]:
            return (
                "duration",
                f"expected at most the last time of [omega_profile] t ({p.t[-1]:g} s): the "
                f"angular velocity is not known after it, found {simulation.duration:g}.",
            )
        return None

    def propagate(self, scenario: Any, method: Any, t: Any, progress: Any) -> Any:
        profile = scenario.omega_profile
        omega = omega_function(profile)
        return chunked(
            lambda rot, w, tt: propagate(
                rot,
                omega,
                tt,
                frame=profile.frame,
                method=method,
                max_step=scenario.simulation.max_step,
            ),
            scenario.attitude.rotation,
            None,
            t,
            progress,
            f"propagating ({method})",
        )

    def exact(self, scenario: Any, t: Any) -> Any:
        """Constant ``w``: ``R(t) = R0 exp(t w^)`` (body axes) or ``exp(t w^) R0``
        (space axes), docs/theory.md §5."""

        p = scenario.omega_profile
        w = np.asarray(p.vector)
        turn = Rotation.from_rotvec(np.outer(t, w))
        r0 = scenario.attitude.rotation
        rot = r0 * turn if p.frame == "body" else turn * r0
        omega_b = (
            np.broadcast_to(w, (t.size, 3)) if p.frame == "body" else rot.apply(w, inverse=True)
        )
        return Trajectory(
            t, rot, np.array(omega_b), "exact", info={"frame": "body", "closed_form": "constant"}
        )

    def solve(self, scenario: Scenario, method: str, t: np.ndarray, progress: Progress) -> Any:
        if method == "exact":
            tr = self.exact(scenario, t)
            progress(1.0, "exact solution")
        else:
            tr = self.propagate(scenario, method, t, progress)
        if scenario.body is not None:
            tr = _rigid.with_invariants(np.asarray(scenario.body.inertia), tr)
        return tr

    def facts(self, scenario: Scenario) -> Facts:
        p = scenario.omega_profile
        if p.kind != "constant":
            return Facts()
        assert p.vector is not None  # a constant profile has its vector
        rate = float(np.linalg.norm(p.vector))
        entries = {
            "rotation_rate": Entry(rate, "rad/s"),
            "period": Entry(2 * np.pi / rate if rate > 0 else None, "s"),
            "axis": Entry(np.asarray(p.vector) / rate if rate > 0 else None, "1"),
        }
        return Facts(entries)

    def checks(self, scenario: Scenario, tr: Any) -> Sequence[Check]:
        if tr.energy is None:
            return ()
        k = np.asarray(tr.momentum)
        # prescribed motion: T and K follow the profile, their changes are reported
        return (
            Check("energy", "kinetic energy T", "J", np.asarray(tr.energy), conserved=False),
            Check("momentum_norm", "|K|", "kg m^2/s", np.linalg.norm(k, axis=-1), conserved=False),
            Check("momentum_vector", "K (space axes)", "kg m^2/s", k, conserved=False),
        )

    def describe_scenario(self, scenario: Scenario) -> list[str]:
        p = scenario.omega_profile
        return [f"{self.title}: {p.kind} angular velocity ({p.frame} axes)"]


KIND = Attitude()
