"""Adapter: a rigid body under a torque (docs/theory.md §9, §10).

Tables: [body], [angular_velocity], [torque] with ``model`` ``"body"`` (constant
body torque), ``"space"`` (constant space torque) or ``"gravity"`` (the heavy
body about a fixed point, the origin of the body axes). Solved by
:func:`poinsot.dynamics.simulate`. Checks: under gravity ``T + V`` and ``K_z``
(and ``H = C r`` for a Lagrange top) are conserved; under a space torque
``K(t) = K(0) + M t``; under a body torque ``T`` and ``K`` are only reported.
"""

from __future__ import annotations

import numpy as np

from ..describe import fmt
from ..kind import Check, Entry, Facts, ScenarioKind
from ..schema import DYNAMICS_METHODS
from . import _rigid

_LAGRANGE_UNITS = {
    "A": "kg m^2",
    "C": "kg m^2",
    "l": "m",
    "H": "kg m^2/s",
    "K_z": "kg m^2/s",
    "E": "J",
    "maievskii_ratio": "1",
    "nutation_theta_min": "rad",
    "nutation_theta_max": "rad",
    "nutation_period": "s",
    "psi_dot_at_theta_max": "rad/s",
    "psi_dot_at_theta_min": "rad/s",
}


def _lagrange(scenario) -> dict | None:
    if scenario.torque.model != "gravity":
        return None
    from .._lagrange import lagrange_top

    return lagrange_top(
        scenario.body.inertia_about_origin(),
        scenario.body.mass,
        scenario.body.center_of_mass,
        scenario.torque.g,
        scenario.attitude.quat,
        scenario.angular_velocity.omega_body,
    )


def _lagrange_facts(props: dict) -> Facts:
    entries = {k: Entry(v, _LAGRANGE_UNITS.get(k, "")) for k, v in props.items()}
    line = f"{props['case']}: {props['motion']}"
    if "nutation_theta_min" in props:
        line += (
            f", tilt {np.degrees(props['nutation_theta_min']):.4f} to "
            f"{np.degrees(props['nutation_theta_max']):.4f} deg"
        )
    if props.get("nutation_period"):
        line += f", nutation period {fmt(props['nutation_period'])} s"
    line += f"; Maievskii ratio C^2 r^2/(4 A m g l) = {fmt(props['maievskii_ratio'])}"
    return Facts(entries, (line,))


class TorquedBody(ScenarioKind):
    name = "torqued-body"
    title = "rigid body under a torque (constant body or space torque, or gravity about a pin)"
    tables = _rigid.TABLES
    methods = DYNAMICS_METHODS
    orders = {"midpoint": 2, "splitting": 2, "rk4": 4}
    theory = "docs/theory.md §10"

    def claims(self, data):
        torque = data.get("torque")
        return isinstance(torque, dict) and torque.get("model", "none") != "none"

    def parse(self, top, attitude):
        fields = _rigid.parse_rigid(top, attitude)
        if fields["torque"].model == "none":
            raise top.error(
                "torque",
                'a "torqued-body" scenario needs a torque: expected [torque] with model '
                '"body", "space" or "gravity".',
            )
        return fields

    def refuse_method(self, method, fields):
        if method == "exact":
            model = fields["torque"].model
            return (
                f'"exact" is the closed-form torque-free solution (docs/theory.md §10), '
                f'but [torque] model is "{model}": expected one of '
                + ", ".join(f'"{x}"' for x in self.methods if x != "exact")
                + "."
            )
        return None

    def motion_inertia(self, scenario):
        # about the fixed point under gravity (Huygens-Steiner), else the centre of mass
        if scenario.torque.model == "gravity":
            return scenario.body.inertia_about_origin()
        return np.asarray(scenario.body.inertia)

    def solve(self, scenario, method, t, progress):
        return _rigid.simulate_rigid(
            scenario,
            self.motion_inertia(scenario),
            _rigid.torque_model(scenario),
            method,
            t,
            progress,
        )

    def body_entries(self, scenario):
        if scenario.torque.model == "gravity":
            return {
                "inertia_about_fixed_point": Entry(scenario.body.inertia_about_origin(), "kg m^2")
            }
        return {}

    def series(self, scenario, tr):
        model = _rigid.torque_model(scenario)
        v = model.potential(tr.quat)
        return {} if v is None else {"V": (np.asarray(v), "J")}

    def facts(self, scenario):
        props = _lagrange(scenario)
        if props is None:
            return Facts()
        return _lagrange_facts(props)

    def checks(self, scenario, tr):
        model = _rigid.torque_model(scenario)
        inv = _rigid.invariants_of(self.motion_inertia(scenario), tr, model)
        k = inv.momentum_space
        k0 = float(inv.momentum_norm[0])
        if scenario.torque.model == "gravity":
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
            if _lagrange(scenario) is not None:
                # Lagrange top: the momentum about the symmetry axis, H = C r, is conserved
                e = np.asarray(scenario.body.center_of_mass)
                h = inv.momentum_body @ (e / np.linalg.norm(e))
                out.append(
                    Check("spin_momentum_H", "H = C r (symmetry axis)", "kg m^2/s", h, scale=k0)
                )
            return out
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

    def describe_scenario(self, scenario):
        return [f"{self.title}: torque {scenario.torque.model}"]


KIND = TorquedBody()
