"""Adapter: a rigid body thrown onto a floor, bouncing (docs/theory.md §11.3).

Tables:

* ``[body]``: a ``shape = "box"`` (it bounces on its 8 corners), ``"sphere"`` (on its
  surface) or ``"mesh"`` (on its vertices), with its mass;
* ``[attitude]`` and ``[angular_velocity]``: at t = 0 (body -> space; body or space
  axes);
* ``[floor]``: ``restitution`` (Newton's or Poisson's ``e``, default 0.5), ``friction``
  (Coulomb's ``mu``, default 0), ``law`` (``"newton"`` or ``"poisson"``), ``g`` (m/s^2,
  default 9.80665), ``rest_speed`` (m/s, default 1e-3: a slower rebound ends the run);
* ``[launch]``: ``position`` (m, the centre of mass, ``z`` up, above the floor ``z = 0``)
  and ``velocity`` (m/s).

Solved by :func:`poinsot.dynamics.simulate_bounces`: exact flights (the parabola and the
Euler-Poinsot motion) between impacts, each impact by
:func:`poinsot.dynamics.rigid_impact`. The only method is ``"exact"``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ...dynamics import simulate_bounces
from ...mass import RigidBody
from ..describe import fmt
from ..kind import Chart, Check, Entry, Facts
from ..readers import read_angular_velocity, read_body
from . import _rigid

if TYPE_CHECKING:
    from .._toml import Table
    from ..kind import Progress, ReportSpec
    from ..schema import AttitudeSpec, Scenario
    from ..summary import ScenarioResult

_FLOOR_KEYS = ("restitution", "friction", "law", "g", "rest_speed")
_LAUNCH_KEYS = ("position", "velocity")


@dataclass(frozen=True, eq=False)
class BouncingSpec:
    """What the file says, in SI units."""

    restitution: float
    friction: float
    law: str
    g: float
    rest_speed: float
    position: np.ndarray
    velocity: np.ndarray


def _contacts(body: Any) -> dict[str, Any]:
    """``corners=`` or ``radius=`` of :func:`poinsot.dynamics.simulate_bounces` for the
    scenario body (body axes, from the centre of mass)."""
    com = np.asarray(body.center_of_mass, dtype=float)
    if body.shape == "sphere":
        return {"radius": float(body.dims[0])}
    if body.shape == "box":
        a, b, c = (float(x) for x in body.dims)
        signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
        return {"corners": signs * [a / 2, b / 2, c / 2] - com}
    return {"corners": np.asarray(body.vertices, dtype=float) - com}


class BouncingKind(_rigid.RigidKind):
    name = "bouncing"
    title = "a rigid body thrown onto a floor: exact flights and impacts with friction"
    tables = ("body", "angular_velocity", "floor", "launch")
    methods = ("exact",)
    orders: dict[str, int] = {}
    theory = "docs/theory.md §11.3"
    # measured on the shipped examples: ~2e-3 s per output sample (the exact flights are
    # evaluated per sample and scanned for the next impact)
    seconds_per_step = {"exact": 2e-3}

    def claims(self, data: Mapping[str, Any]) -> bool:
        return "floor" in data and "body" in data

    def parse(self, top: Table, attitude: AttitudeSpec) -> dict[str, Any]:
        bt = top.table("body", required=True)
        body = read_body(bt)
        if body.shape not in ("box", "sphere", "mesh"):
            raise top.error("body.shape", 'a bouncing body needs a shape that says where it '
                            'touches: "box", "sphere" or "mesh".')  # fmt: skip
        omega = read_angular_velocity(top.table("angular_velocity", required=True), attitude)
        f = top.table("floor", required=True)
        f.known(_FLOOR_KEYS)
        e = f.number("restitution", 0.5, nonnegative=True)
        if e > 1.0:
            raise f.expected("restitution", "a coefficient in [0, 1]", e)
        mu = f.number("friction", 0.0, nonnegative=True)
        law = f.string("law", "newton", choices=("newton", "poisson"))
        g = f.number("g", 9.80665, positive=True)
        rest = f.number("rest_speed", 1e-3, positive=True)
        f.finish(_FLOOR_KEYS)
        la = top.table("launch", required=True)
        la.known(_LAUNCH_KEYS)
        pos = np.array(la.vector("position", 3, what="[x, y, z] (m), z up", required=True))
        vel = np.array(la.vector("velocity", 3, what="[vx, vy, vz] (m/s)", required=False,
                                 default=(0.0, 0.0, 0.0)))  # fmt: skip
        la.finish(_LAUNCH_KEYS)
        spec = BouncingSpec(restitution=e, friction=mu, law=law, g=g, rest_speed=rest,
                            position=pos, velocity=vel)  # fmt: skip
        return {"body": body, "angular_velocity": omega, "spec": spec}

    def solve(self, scenario: Scenario, method: str, t: np.ndarray, progress: Progress) -> Any:
        s: BouncingSpec = scenario.spec
        body = RigidBody(scenario.body.mass, np.asarray(scenario.body.inertia))
        progress(0.0, "flights and impacts (exact)")
        tr = simulate_bounces(
            body, s.position, s.velocity, scenario.attitude.rotation.as_quat(),
            np.asarray(scenario.angular_velocity.omega_body), t, g=s.g,
            restitution=s.restitution, friction=s.friction, law=s.law,
            rest_speed=s.rest_speed, **_contacts(scenario.body),
        )  # fmt: skip
        progress(1.0, "flights and impacts (exact)")
        return tr

    def facts(self, scenario: Scenario) -> Facts:
        s: BouncingSpec = scenario.spec
        lowest = float(s.position[2])
        v_z = float(s.velocity[2])
        # the first fall of the centre of mass, to z = 0 (an upper bound of the first impact)
        t_fall = (v_z + np.sqrt(v_z**2 + 2 * s.g * lowest)) / s.g
        return Facts(
            {"fall_time_of_centre_to_floor": Entry(t_fall, "s", "bounds the first impact")},
            (f"impacts by Newton's (or Poisson's) law e = {fmt(s.restitution)}, Coulomb mu = "
             f"{fmt(s.friction)} ({s.law}; docs/theory.md §11.3); exact flights between them",),
        )  # fmt: skip

    def checks(self, scenario: Scenario, tr: Any) -> Sequence[Check]:
        s: BouncingSpec = scenario.spec
        m = float(scenario.body.mass)
        energy = np.asarray(tr.energy) + m * s.g * tr.position[:, 2]
        return [
            Check("mechanical_energy", "T + m g z", "J", energy, conserved=False),
            Check("height", "height of the centre of mass", "m", tr.position[:, 2],
                  conserved=False),
        ]  # fmt: skip

    def series(self, scenario: Scenario, tr: Any) -> dict[str, tuple[np.ndarray, str]]:
        s: BouncingSpec = scenario.spec
        m = float(scenario.body.mass)
        return {"mechanical_energy": (np.asarray(tr.energy) + m * s.g * tr.position[:, 2], "J")}

    def describe_scenario(self, scenario: Scenario) -> list[str]:
        s: BouncingSpec = scenario.spec
        return [f"{self.title}: {scenario.body.shape}, e = {fmt(s.restitution)}, "
                f"mu = {fmt(s.friction)}, {s.law}"]  # fmt: skip

    def report(self, result: ScenarioResult) -> ReportSpec:
        """The body's report with the height of its centre of mass and its lowest point
        (m), its mechanical energy (J, falling only at the impacts) and the impacts."""
        s: BouncingSpec = result.scenario.spec
        tr = result.trajectory
        m = float(result.scenario.body.mass)
        contacts = _contacts(result.scenario.body)
        if "radius" in contacts:
            lowest = tr.position[:, 2] - contacts["radius"]
        else:
            lowest = tr.position[:, 2] + tr.rotation[:, None].apply(contacts["corners"])[
                ..., 2
            ].min(axis=1)
        charts = [
            Chart("heights", "m", {"centre of mass": tr.position[:, 2], "lowest point": lowest}),
            Chart("mechanical energy T + m g z", "J",
                  {"T + m g z": np.asarray(tr.energy) + m * s.g * tr.position[:, 2]}),
        ]  # fmt: skip
        out = _rigid.rigid_report(result)
        return dataclasses.replace(out, charts=tuple(charts) + tuple(out.charts))


KIND = BouncingKind()
