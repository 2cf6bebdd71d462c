"""Adapter: classical coning motion (docs/theory.md §5), closed form vs integrators.

Tables: [omega_profile] with ``kind = "coning"`` (body frame), optional [body].
``method = "exact"`` is the closed form :func:`poinsot.kinematics.coning_quat`
started from the scenario's attitude, ``L(t) = L0 o Lc(0)~ o Lc(t)``; the
integrators propagate :func:`poinsot.kinematics.coning_omega`.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from ...kinematics import coning_omega, coning_quat
from ...rotations import quaternion as qa
from ...rotations.rotation import Rotation
from ...trajectory import Trajectory

if TYPE_CHECKING:
    from ..kind import Facts
    from ..schema import Scenario

import numpy as np

from ..kind import Entry, Facts
from .attitude import Attitude


class Coning(Attitude):
    name = "coning"
    title = "classical coning motion (closed form of Poisson's equation)"
    profiles = ("coning",)
    # cost estimate, one core, measured by benchmarks/bench_estimates.py on the examples
    seconds_per_step = {"exact": 2e-7, "magnus4": 4.5e-5, "rk4": 4.5e-5, "adaptive": 4.5e-5}
    seconds_per_run = {"exact": 3e-4}

    def claims(self, data: Mapping[str, Any]) -> bool:
        profile = data.get("omega_profile")
        return isinstance(profile, dict) and profile.get("kind") == "coning"

    def exact(self, scenario: Any, t: Any) -> Any:
        p = scenario.omega_profile
        qc = coning_quat(p.half_angle, p.rate, t)
        q = qa.multiply(qa.multiply(scenario.attitude.quat, qa.conjugate(qc[0])), qc)
        return Trajectory(
            t,
            Rotation.from_quat(q),
            coning_omega(p.half_angle, p.rate, t),
            "exact",
            info={"frame": "body", "closed_form": "coning"},
        )

    def facts(self, scenario: Scenario) -> Facts:
        p = scenario.omega_profile
        assert p is not None and p.half_angle is not None  # set by this kind's parse
        return Facts(
            {
                "coning_half_angle": Entry(p.half_angle, "rad"),
                "coning_rate": Entry(p.rate, "rad/s"),
                "period": Entry(2 * np.pi / abs(p.rate) if p.rate else None, "s"),
            },
            (
                f"coning: half-angle {np.degrees(p.half_angle):.4g} deg at "
                f"{p.rate:.4g} rad/s; the attitude is periodic, q(t + period) = q(t) "
                "(docs/theory.md §5)",
            ),
        )

    def describe_scenario(self, scenario: Scenario) -> list[str]:
        p = scenario.omega_profile
        assert p is not None and p.half_angle is not None  # set by this kind's parse
        return [
            f"{self.title}: half-angle {np.degrees(p.half_angle):.4g} deg, rate {p.rate:.4g} rad/s"
        ]


KIND = Coning()
