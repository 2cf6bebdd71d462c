"""Adapter: a rigid body under a torque (docs/theory.md §9, §10).

Tables: [body], [angular_velocity], [torque] with ``model`` ``"body"`` (constant
body torque), ``"space"`` (constant space torque) or ``"gravity"`` (the heavy
body about a fixed point, the origin of the body axes). Solved by
:func:`poinsot.dynamics.simulate`. Files with gravity are claimed by the
``heavy-top`` kind (:mod:`.heavy_top`), whose facts and checks are used here too
when ``kind = "torqued-body"`` is named explicitly. Under a space torque
``K(t) = K(0) + M t``; under a body torque ``T`` and ``K`` are only reported.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

from .heavy_top import KIND as HEAVY

if TYPE_CHECKING:
    from .._toml import Table
    from ..kind import Check, Entry, Facts, Progress
    from ..schema import AttitudeSpec, Scenario

import numpy as np

from ... import integrators
from ..kind import Check, Entry, Facts
from ..schema import DYNAMICS_METHODS
from . import _rigid


class TorquedBody(_rigid.RigidKind):
    name = "torqued-body"
    title = "rigid body under a torque (constant body or space torque, or gravity about a pin)"
    tables = _rigid.TABLES
    methods = DYNAMICS_METHODS
    orders = integrators.orders(DYNAMICS_METHODS)
    theory = "docs/theory.md §10"
    # cost estimate, one core, measured by benchmarks/bench_estimates.py on the examples
    seconds_per_step = {**_rigid.SECONDS_PER_STEP, "midpoint": 6e-7, "rk4": 6e-7}

    def claims(self, data: Mapping[str, Any]) -> bool:
        torque = data.get("torque")
        return isinstance(torque, dict) and torque.get("model", "none") != "none"

    def parse(self, top: Table, attitude: AttitudeSpec) -> dict[str, Any]:
        fields = _rigid.parse_rigid(top, attitude)
        if fields["torque"].model == "none":
            raise top.error(
                "torque",
                'a "torqued-body" scenario needs a torque: expected [torque] with model '
                '"body", "space" or "gravity".',
            )
        return fields

    def refuse_method(self, method: str, fields: Mapping[str, Any]) -> str | None:
        if method == "exact":
            model = fields["torque"].model
            return (
                f'"exact" is the closed-form torque-free solution (docs/theory.md §10), '
                f'but [torque] model is "{model}": expected one of '
                + ", ".join(f'"{x}"' for x in self.methods if x != "exact")
                + "."
            )
        return None

    def motion_inertia(self, scenario: Scenario) -> np.ndarray | None:
        # about the fixed point under gravity (Huygens-Steiner), else the centre of mass
        if scenario.torque.model == "gravity":
            return scenario.body.inertia_about_origin()
        return np.asarray(scenario.body.inertia)

    def solve(self, scenario: Scenario, method: str, t: np.ndarray, progress: Progress) -> Any:
        return _rigid.simulate_rigid(
            scenario,
            self.motion_inertia(scenario),
            _rigid.torque_model(scenario),
            method,
            t,
            progress,
        )

    def body_entries(self, scenario: Scenario) -> dict[str, Entry]:
        if scenario.torque.model == "gravity":
            return {
                "inertia_about_fixed_point": Entry(scenario.body.inertia_about_origin(), "kg m^2")
            }
        return {}

    def series(self, scenario: Scenario, tr: Any) -> dict[str, tuple[np.ndarray, str]]:
        model = _rigid.torque_model(scenario)
        v = model.potential(tr.quat)
        return {} if v is None else {"V": (np.asarray(v), "J")}

    def facts(self, scenario: Scenario) -> Facts:
        if scenario.torque.model == "gravity":  # the heavy body (kind "heavy-top") knows it
            return HEAVY.facts(scenario)
        return Facts()

    def checks(self, scenario: Scenario, tr: Any) -> Sequence[Check]:
        if scenario.torque.model == "gravity":
            return HEAVY.checks(scenario, tr)
        model = _rigid.torque_model(scenario)
        inv = _rigid.invariants_of(self.motion_inertia(scenario), tr, model)
        k = inv.momentum_space
        out = [
            Check("energy", "kinetic energy T", "J", inv.kinetic, conserved=False),
            Check("momentum_norm", "|K|", "kg m^2/s", inv.momentum_norm, conserved=False),
            Check("momentum_vector", "K (space axes)", "kg m^2/s", k, conserved=False),
        ]
        if scenario.torque.model == "space":
            # dK/dt = M in space axes, so K(t) = K(0) + M t exactly (docs/theory.md §9)
            expected = k[0] + np.outer(tr.t - tr.t[0], np.asarray(scenario.torque.vector))
            out.append(
                Check(
                    "momentum_balance",
                    "K (space axes)",
                    "kg m^2/s",
                    k,
                    expected=expected,
                    scale=max(float(np.max(np.linalg.norm(expected, axis=-1))), 1e-300),
                    law="K(t) = K(0) + M t",
                )
            )
        return out

    def describe_scenario(self, scenario: Scenario) -> list[str]:
        return [f"{self.title}: torque {scenario.torque.model}"]


KIND = TorquedBody()
