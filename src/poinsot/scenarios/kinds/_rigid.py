"""What the rigid-body kinds share: reading [body], [angular_velocity], [torque],
solving with :func:`poinsot.dynamics.simulate`, the invariants of a trajectory, and
what ``report.html`` shows of a rigid body (:func:`rigid_report`)."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from ...dynamics import ConstantBodyTorque, ConstantSpaceTorque, GravityTorque, invariants, simulate
from ...integrators import INTEGRATORS
from ...mass import solids
from ...plotting._report_shapes import SOLIDS, axes_from_inertia, equivalent_ellipsoid
from ..kind import BodyLayer, Drawing, ReportSpec, ScenarioKind
from ..readers import read_angular_velocity, read_body, read_torque
from ..solve import chunked

TABLES = ("body", "angular_velocity", "torque")

#: Seconds per step of poinsot.dynamics.simulate / FreeRigidBody for the cost estimate,
#: one core: each method's ``cost["rigid"]`` in poinsot.integrators.INTEGRATORS (measured
#: by benchmarks/bench_estimates.py on the shipped examples), and per run.
SECONDS_PER_STEP = {n: i.cost["rigid"] for n, i in INTEGRATORS.items() if "rigid" in i.cost}
SECONDS_PER_RUN = {"exact": 5e-4}


def parse_rigid(top: Any, attitude: Any) -> dict[str, Any]:
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


def simulate_rigid(
    scenario: Any, inertia: Any, torque: Any, method: Any, t: Any, progress: Any
) -> Any:
    """Euler's equations with the attitude (docs/theory.md §10), in chunks."""

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


def torque_model(scenario: Any) -> Any:
    """The scenario's ``[torque]`` as a :class:`poinsot.dynamics.TorqueModel` (or None)."""

    tq = scenario.torque
    if tq is None or tq.model == "none":
        return None
    if tq.model == "body":
        return ConstantBodyTorque(tq.vector)
    if tq.model == "space":
        return ConstantSpaceTorque(tq.vector)
    return GravityTorque(scenario.body.mass, scenario.body.center_of_mass, g=tq.g)


def invariants_of(inertia: Any, tr: Any, torque: Any = None) -> Any:
    """:func:`poinsot.dynamics.invariants` along a trajectory (docs/theory.md §8, §10)."""

    return invariants(inertia, tr.rotation, tr.omega, torque=torque)


def with_invariants(inertia: Any, tr: Any) -> Any:
    """``tr`` with the kinetic energy and the space angular momentum filled in
    (docs/theory.md §8) when they are missing."""
    if tr.energy is not None and tr.momentum is not None:
        return tr
    inv = invariants_of(inertia, tr)
    return dataclasses.replace(tr, energy=inv.kinetic, momentum=inv.momentum_space)


def body_shapes(body: Any) -> list[dict[str, Any]] | None:
    """The solids of a scenario body (its shape, or its parts) in body axes, as
    :func:`poinsot.plotting.write_report` takes them (None: draw the equivalent
    ellipsoid)."""

    if body.shape == "mesh":  # vertices already in body axes
        return [{"kind": "mesh", "vertices": body.vertices, "faces": body.faces}]
    if body.shape in SOLIDS and body.dims:
        return [{"kind": body.shape, "dims": list(body.dims), "center": body.center_of_mass}]
    if not body.parts:
        return None
    out = []
    for p in body.parts:
        if p.shape == "mesh":  # placed by its position/orientation: in body axes
            out.append({"kind": "mesh", "vertices": p.vertices, "faces": p.faces})
        elif p.shape in SOLIDS and p.dims:
            canon = np.asarray(getattr(solids, p.shape)(1.0, *p.dims), dtype=float)
            # the part's inertia may be turned (orientation =): find its axes
            axes = axes_from_inertia(canon, np.asarray(p.inertia) / p.mass)
            out.append({"kind": p.shape, "dims": list(p.dims), "center": p.position, "axes": axes})
        else:  # a point mass (or a part given by its inertia): a small sphere
            out.append({"kind": "point", "dims": [0.0], "center": p.position})
    return out


def body_torque(scenario: Any, tr: Any) -> np.ndarray | None:
    """The torque of the scenario's model on the body along ``tr`` (body axes, N m,
    shape (n, 3)), or None without a torque (or if the model cannot say)."""
    if scenario.torque is None or scenario.torque.model == "none":
        return None
    if tr.rotation.shape != tr.t.shape:
        return None
    try:
        model = torque_model(scenario)
        torque = np.asarray(model.body_torque(tr.t, tr.quat, tr.omega), dtype=float)
        return np.array(np.broadcast_to(torque, tr.omega.shape))
    except Exception:  # the torque is optional in the report
        return None


def top_drawing(rotation: Any, center_of_mass: Any, reach: float = 1.5) -> Any:
    """A top on its pin, for ``report.html``: the stem from the fixed point (the
    origin) to the centre of mass, and the tip of the axis through them at ``reach``
    times the centre's distance, with its trail (the loops and cusps of the
    nutation, docs/theory.md §10), as a :class:`~poinsot.scenarios.Drawing`.

    Examples
    --------
    >>> import poinsot
    >>> d = top_drawing(poinsot.Rotation.identity((2,)), np.array([0.0, 0.0, 0.1]))
    >>> d.points["axis tip"][0].round(3).tolist(), d.links, d.trails
    ([0.0, 0.0, 0.15], (('fixed point', 'centre of mass'),), ('axis tip',))
    """

    com = np.asarray(center_of_mass, dtype=float)
    c = rotation.apply(com)
    return Drawing(
        {"fixed point": np.zeros_like(c), "centre of mass": c, "axis tip": reach * c},
        links=(("fixed point", "centre of mass"),),
        trails=("axis tip",),
    )


def rigid_report(result: Any, *, polhode: bool = False, sections: Any = ()) -> Any:
    """The :class:`~poinsot.scenarios.kind.ReportSpec` of a rigid body's run: the
    body's shape at its centre of mass, the fixed point under gravity, the polhode
    and herpolhode when ``polhode`` (the torque-free body, docs/theory.md §10), the
    torque, Euler angles of the scenario's sequence (``"ZXZ"`` precession,
    nutation and spin under a torque, else ``"ZYX"``) and the reference run."""
    s = result.scenario
    tr = result.trajectory
    body = None
    torque = None
    if s.body is not None:
        b = s.body
        body = BodyLayer(
            shapes=body_shapes(b),
            inertia=np.asarray(b.inertia),
            mass=float(b.mass),
            center_of_mass=np.asarray(b.center_of_mass),
            fixed_point=s.torque is not None and s.torque.model == "gravity",
            polhode=polhode,
        )
        torque = body_torque(s, tr)
    drawing = None
    if s.body is not None and body is not None and body.fixed_point:
        # the tip beyond the body (its equivalent ellipsoid), so that its trail shows
        com = np.asarray(s.body.center_of_mass, dtype=float)
        semi, _ = equivalent_ellipsoid(float(s.body.mass), np.asarray(s.body.inertia))
        reach = 1.0 + 1.25 * float(semi.max()) / float(np.linalg.norm(com))
        drawing = top_drawing(tr.rotation, com, reach)
    seq = s.attitude.sequence if s.attitude.sequence else ("ZXZ" if torque is not None else "ZYX")
    return ReportSpec(
        drawing=drawing,
        motion=tr,
        body=body,
        reference=result.reference,
        torque=torque,
        euler_seq=seq if len(seq) == 3 else "ZYX",  # as given (case: intrinsic or extrinsic)
        checks=tuple(result.checks),
        sections=tuple(sections),
    )


class RigidKind(ScenarioKind):
    """The base of the kinds whose result is a rigid body's
    :class:`~poinsot.trajectory.Trajectory`: their report draws the body
    (:func:`rigid_report`)."""

    def report(self, result: Any) -> ReportSpec:
        return rigid_report(result)
