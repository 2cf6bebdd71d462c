"""What the rigid-body kinds share: reading [body], [angular_velocity], [torque],
solving with :func:`poinsot.dynamics.simulate`, and the invariants of a trajectory."""

from __future__ import annotations

import dataclasses

import numpy as np

from ..io import read_angular_velocity, read_body, read_torque

TABLES = ("body", "angular_velocity", "torque")

#: Rough seconds per step of poinsot.dynamics.simulate / FreeRigidBody (cost estimate),
#: measured on the tennis racket (10001 samples) on a loaded 2-core machine.
SECONDS_PER_STEP = {
    "exact": 2e-6,
    "midpoint": 4e-6,
    "splitting": 8e-6,
    "rk4": 4e-4,
    "adaptive": 1.5e-4,
}


def parse_rigid(top, attitude) -> dict:
    """The fields of a rigid-body scenario: ``body``, ``angular_velocity``, ``torque``."""
    body = read_body(top.table("body", required=True))
    angular_velocity = read_angular_velocity(top.table("angular_velocity", required=True), attitude)
    torque = read_torque(top.table("torque"))
    if torque.model == "gravity" and not np.any(body.center_of_mass):
        raise top.error(
            "body.center_of_mass",
            "gravity about a fixed point needs the centre "
            "of mass away from the fixed point (the origin of the body axes), "
            "found [0, 0, 0]: add `center_of_mass = [x, y, z]` to [body].",
        )
    return {"body": body, "angular_velocity": angular_velocity, "torque": torque}


def simulate_rigid(scenario, inertia, torque, method, t, progress):
    """Euler's equations with the attitude (docs/theory.md §10), in chunks."""
    from ...dynamics import simulate
    from ..solve import chunked

    return chunked(
        lambda rot, w, tt: simulate(
            inertia,
            rot,
            w,
            tt,
            torque=torque,
            method=method,
            max_step=scenario.simulation.max_step,
        ),
        scenario.attitude.rotation,
        np.asarray(scenario.angular_velocity.omega_body),
        t,
        progress,
        f"integrating ({method})",
    )


def torque_model(scenario):
    """The scenario's ``[torque]`` as a :class:`poinsot.dynamics.TorqueModel` (or None)."""
    from ...dynamics import ConstantBodyTorque, ConstantSpaceTorque, GravityTorque

    tq = scenario.torque
    if tq is None or tq.model == "none":
        return None
    if tq.model == "body":
        return ConstantBodyTorque(tq.vector)
    if tq.model == "space":
        return ConstantSpaceTorque(tq.vector)
    return GravityTorque(scenario.body.mass, scenario.body.center_of_mass, g=tq.g)


def invariants_of(inertia, tr, torque=None):
    """:func:`poinsot.dynamics.invariants` along a trajectory (docs/theory.md §8, §10)."""
    from ...dynamics import invariants

    return invariants(inertia, tr.rotation, tr.omega, torque=torque)


def with_invariants(inertia, tr):
    """``tr`` with the kinetic energy and the space angular momentum filled in
    (docs/theory.md §8) when they are missing."""
    if tr.energy is not None and tr.momentum is not None:
        return tr
    inv = invariants_of(inertia, tr)
    return dataclasses.replace(tr, energy=inv.kinetic, momentum=inv.momentum_space)
