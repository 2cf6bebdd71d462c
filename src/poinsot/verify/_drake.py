"""Run a free rigid body in Drake and read its states in poinsot's conventions.

The model: a continuous-time ``MultibodyPlant`` (``time_step=0``) with one rigid body
(``AddRigidBody``), which Drake joins to the world by a ``QuaternionFloatingJoint`` at
``Finalize``; no geometry (so no contact), gravity set by
``plant.mutable_gravity_field().set_gravity_vector`` (zero for the free bodies). Its
``SpatialInertia`` is ``SpatialInertia.MakeFromCentralInertia(mass, p_BoBcm_B,
I_BBcm_B)``: the mass, the centre of mass from the body origin (zero: the body frame
is at the centre of mass) and the ``RotationalInertia`` about the centre of mass in
body axes, the full matrix (Drake takes the products of inertia as they are).

Conventions of Drake (``QuaternionFloatingJoint``, ``MultibodyPlant`` docs; the plant's
state names ``body_qw, body_qx, body_qy, body_qz, body_x, body_y, body_z`` then
``body_wx, ...``):

- the positions are ``q = [qw, qx, qy, qz, x, y, z]``: a **scalar-first** quaternion
  of the body's orientation in the world, ``R_WB`` (body -> world): poinsot's
  convention, normalised (Drake's integrators do not keep it unit) and made
  sign-continuous;
- the velocities are ``v = [w_WB, v_WBo]``, the angular velocity **expressed in the
  world frame**: poinsot's body-axes ``omega = R_WB^T w_WB`` (and ``w_WB = R_WB
  omega0`` to set the initial state);
- ``[x, y, z]`` and ``v_WBo`` are the position and velocity of the body origin, the
  centre of mass here, in **world** axes: poinsot's ``position`` and ``velocity``
  of a pose, taken as they are (:func:`run_drake_pose`; zero at the start of a rigid
  case).

Integration: ``drake.systems.analysis.Simulator`` with the integrator given by
name (``ResetIntegratorFromFlags``); an error-controlled integrator runs with
``set_target_accuracy(accuracy)`` unless a fixed ``step`` is given
(``set_fixed_step_mode``); one without error estimation (``explicit_euler``,
``runge_kutta2``, ``semi_explicit_euler``) runs with a fixed step. The grid's times are
reached by ``AdvanceTo``, which ends a step on each of them (no interpolation).

**A gyrostat** (``rotor_momentum`` given, docs/theory.md §10.1): a second rigid body,
the rotor, joined to the body (the platform) by a ``RevoluteJoint`` along
``a = h / |h|`` through the centre of mass, with zero damping; the mapping of the
case to the two bodies (inertias, mass shares, initial hinge rate) is
:func:`poinsot.verify._mujoco.rotor_inputs`. The platform's floating joint is found by
``floating_positions_start`` / ``floating_velocities_start_in_v`` (the hinge's
coordinates come after or before it as Drake orders them).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import InvalidInputError, PoinsotError
from ._mujoco import ROTOR_MASS_SHARE, _vec, body_inputs, rotor_inputs
from ._pybullet import _rotate_back

#: Drake's integration schemes (``GetIntegrationSchemes()``, Drake 1.51); "cenic"
#: (contact-aware, for discrete convex contact) is left out
INTEGRATORS = (
    "runge_kutta5", "runge_kutta3", "bogacki_shampine3", "radau3", "radau1",
    "implicit_euler", "velocity_implicit_euler", "runge_kutta2", "explicit_euler",
    "semi_explicit_euler",
)  # fmt: skip
#: the schemes without error estimation: fixed step only
FIXED_STEP = ("runge_kutta2", "explicit_euler", "semi_explicit_euler")


class DrakeMissing(PoinsotError, ImportError):
    """The ``drake`` package is not installed."""


def _pydrake() -> Any:
    try:
        import pydrake.multibody.plant as plant
        import pydrake.multibody.tree as tree
        import pydrake.systems.analysis as analysis
    except ImportError as exc:
        raise DrakeMissing(
            f"the Drake adapter needs the `drake` package: pip install 'poinsot[verify]' ({exc})"
        ) from exc
    return plant, tree, analysis


def run_drake(*, inertia: Any, mass: float, q0: Any, omega0: Any, gravity: Any, t: Any,
              integrator: str = "runge_kutta5", accuracy: float | None = 1e-13,
              step: float | None = None, rotor_momentum: Any = None
              ) -> tuple[np.ndarray, np.ndarray, int]:  # fmt: skip
    """Integrate one free rigid body in Drake; states on the grid ``t``.

    Parameters
    ----------
    inertia : array_like (3, 3)
        About the centre of mass, body axes (kg m^2), symmetric positive definite.
    mass : float
        kg, > 0.
    q0 : array_like (4,)
        Initial attitude, scalar-first unit quaternion, body -> space.
    omega0 : array_like (3,)
        Initial angular velocity, body axes (rad/s).
    gravity : array_like (3,)
        m/s^2, space axes.
    t : array_like (n,)
        Times from 0 (s), increasing.
    integrator : str
        One of :data:`INTEGRATORS` (Drake's scheme names).
    accuracy : float, optional
        Target accuracy of an error-controlled integrator (ignored with ``step``).
    step : float, optional
        Fixed step (s); needed by the schemes of :data:`FIXED_STEP`. Without it an
        error-controlled scheme runs with ``accuracy`` and a largest step of the
        grid's spacing.
    rotor_momentum : array_like (3,), optional
        A gyrostat's constant rotor momentum ``h`` relative to the body (kg m^2/s, body
        axes; docs/theory.md §10.1): the rotor is a second body on a revolute joint,
        ``inertia`` the gyrostat's ``J`` (see the module docstring).

    Returns
    -------
    q : ndarray (n, 4)
        Scalar-first unit quaternions body -> space, sign-continuous (the platform's
        for a gyrostat).
    omega : ndarray (n, 3)
        Body-axes angular velocity (rad/s).
    evaluations : int
        Drake's count of derivative evaluations.

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.verify._drake import run_drake
    >>> q, w, n = run_drake(inertia=np.diag([1.0, 2.0, 3.0]), mass=1.0,
    ...                     q0=[1.0, 0.0, 0.0, 0.0], omega0=[0.0, 0.0, 1.0],
    ...                     gravity=np.zeros(3), t=np.linspace(0.0, 1.0, 11))
    >>> round(2.0 * float(np.arctan2(q[-1, 3], q[-1, 0])), 9), w[-1].round(9).tolist()
    (1.0, [0.0, 0.0, 1.0])

    A gyrostat spinning steadily about its rotor's axis keeps its angular velocity:

    >>> q, w, n = run_drake(inertia=np.diag([1.0, 2.0, 3.0]), mass=1.0,
    ...                     q0=[1.0, 0.0, 0.0, 0.0], omega0=[0.0, 1.0, 0.0],
    ...                     gravity=np.zeros(3), t=np.linspace(0.0, 1.0, 11),
    ...                     rotor_momentum=[0.0, 3.0, 0.0])
    >>> w[-1].round(9).tolist()
    [0.0, 1.0, 0.0]
    """
    q, w, _, _, n = _simulate(inertia=inertia, mass=mass, q0=q0, omega0=omega0,
                              gravity=gravity, t=t, integrator=integrator, accuracy=accuracy,
                              step=step, rotor_momentum=rotor_momentum)  # fmt: skip
    return q, w, n


def run_drake_pose(*, inertia: Any, mass: float, position0: Any, velocity0: Any, q0: Any,
                   omega0: Any, gravity: Any, t: Any, integrator: str = "runge_kutta5",
                   accuracy: float | None = 1e-13, step: float | None = None
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, int]:  # fmt: skip
    """Integrate one free rigid body in Drake in six degrees of freedom (docs/theory.md
    §9, §10): the body's origin, its centre of mass, moves too, gravity as given.

    Parameters
    ----------
    inertia, mass, q0, omega0, gravity, t, integrator, accuracy, step
        As :func:`run_drake`.
    position0, velocity0 : array_like (3,)
        The centre of mass's initial position and velocity (m, m/s, world axes).

    Returns
    -------
    position, velocity : ndarray (n, 3)
        The centre of mass (m, m/s, world axes).
    q, omega, evaluations
        As :func:`run_drake`.

    Examples
    --------
    >>> import numpy as np
    >>> r, v, q, w, n = run_drake_pose(inertia=np.eye(3), mass=1.0, position0=[0.0, 0.0, 1.0],
    ...                                velocity0=[1.0, 0.0, 0.0], q0=[1.0, 0.0, 0.0, 0.0],
    ...                                omega0=[0.0, 0.0, 1.0], gravity=[0.0, 0.0, -10.0],
    ...                                t=np.linspace(0.0, 1.0, 11))
    >>> r[-1].round(9).tolist(), v[-1].round(9).tolist()
    ([1.0, 0.0, -4.0], [1.0, 0.0, -10.0])
    """
    q, w, r, v, n = _simulate(inertia=inertia, mass=mass, q0=q0, omega0=omega0,
                              gravity=gravity, t=t, integrator=integrator, accuracy=accuracy,
                              step=step, position0=position0, velocity0=velocity0)  # fmt: skip
    return r, v, q, w, n


def _simulate(*, inertia: Any, mass: float, q0: Any, omega0: Any, gravity: Any, t: Any,
              integrator: str, accuracy: float | None, step: float | None,
              position0: Any = (0.0, 0.0, 0.0), velocity0: Any = (0.0, 0.0, 0.0),
              rotor_momentum: Any = None
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, int]:  # fmt: skip
    """The run of :func:`run_drake` and :func:`run_drake_pose`: ``(q, omega, position,
    velocity, evaluations)`` (the centre of mass's, world axes)."""
    mplant, tree, analysis = _pydrake()
    if integrator not in INTEGRATORS:
        raise InvalidInputError(
            f"Expected `integrator` to be one of {', '.join(INTEGRATORS)}, got {integrator!r}."
        )
    j, m, q, w0, g = body_inputs(inertia, mass, q0, omega0, gravity)
    r0, v0 = _vec(position0, 3, "position0"), _vec(velocity0, 3, "velocity0")
    for name, x in (("accuracy", accuracy), ("step", step)):
        if x is not None and not (math.isfinite(float(x)) and float(x) > 0):
            raise InvalidInputError(f"Expected `{name}` to be positive, got {x!r}.")
    if step is None and integrator in FIXED_STEP:
        raise InvalidInputError(
            f"Expected a fixed `step` for Drake's {integrator!r}, which has no error "
            "estimation (no `accuracy`)."
        )
    if step is None and accuracy is None:
        raise InvalidInputError("Expected `accuracy` or `step` for Drake's integrator.")
    tt = np.asarray(t, dtype=float)
    if tt.ndim != 1 or tt.size < 1 or tt[0] != 0.0 or np.any(np.diff(tt) <= 0):
        raise InvalidInputError("Expected `t` to be increasing times starting at 0 (s).")

    plant, context, (qs, vs) = build(tree, mplant, j, m, q, w0, g, r0, v0, rotor_momentum)
    sim = analysis.Simulator(plant, context)
    max_step = float(step) if step is not None else float(np.min(np.diff(tt), initial=1.0))
    integ = analysis.ResetIntegratorFromFlags(sim, integrator, max_step)
    if step is not None:
        integ.set_fixed_step_mode(True)
    else:
        integ.set_target_accuracy(float(accuracy))  # type: ignore[arg-type]
    sim.Initialize()
    out = np.empty((tt.size, 13))
    nq = plant.num_positions()
    for n, time in enumerate(tt):
        if time > 0.0:
            sim.AdvanceTo(float(time))
        x = plant.GetPositionsAndVelocities(context)
        out[n] = (*x[qs : qs + 7], *x[nq + vs : nq + vs + 6])
    q_body = out[:, :4] / np.linalg.norm(out[:, :4], axis=1, keepdims=True)
    w_body = _rotate_back(q_body, out[:, 7:10])
    flips = np.concatenate([[1.0], np.where(np.sum(q_body[1:] * q_body[:-1], -1) < 0, -1.0, 1.0)])
    evaluations = int(integ.get_num_derivative_evaluations())
    return q_body * np.cumprod(flips)[:, None], w_body, out[:, 4:7], out[:, 10:13], evaluations


def build(tree: Any, mplant: Any, j: np.ndarray, m: float, q: np.ndarray, w0: np.ndarray,
          g: np.ndarray, r0: np.ndarray, v0: np.ndarray, rotor_momentum: Any = None
          ) -> tuple[Any, Any, tuple[int, int]]:  # fmt: skip
    """The finalised plant and its context at ``t = 0`` and ``(qs, vs)``, where the
    body's floating coordinates start in ``q`` and in ``v`` (a gyrostat's rotor on a
    revolute joint when ``rotor_momentum`` is given; the module docstring,
    docs/theory.md §10.1).

    >>> mplant, tree, _ = _pydrake()
    >>> z = np.zeros(3)
    >>> plant, context, starts = build(tree, mplant, np.diag([1.0, 2.0, 3.0]), 1.0,
    ...                                np.array([1.0, 0.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]),
    ...                                z, z, z, [0.0, 3.0, 0.0])
    >>> k = plant.CalcSpatialMomentumInWorldAboutPoint(context, z).rotational()
    >>> plant.num_velocities(), k.round(12).tolist()
    (7, [0.0, 5.0, 0.0])
    """
    if rotor_momentum is not None:
        j, jr, a, rate0 = rotor_inputs(j, rotor_momentum, w0)
        m, mr = (1.0 - ROTOR_MASS_SHARE) * m, ROTOR_MASS_SHARE * m
    plant = mplant.MultibodyPlant(time_step=0.0)
    try:
        body = plant.AddRigidBody("body", _spatial(tree, m, j))
        if rotor_momentum is not None:
            rotor = plant.AddRigidBody("rotor", _spatial(tree, mr, jr))
    except RuntimeError as exc:  # Drake's own checks (triangle inequality)
        raise InvalidInputError(f"Drake refused the body (`inertia`, `mass`): {exc}") from None
    hinge = None
    if rotor_momentum is not None:
        hinge = plant.AddJoint(tree.RevoluteJoint("hinge", body.body_frame(), rotor.body_frame(),
                                                  a, 0.0))  # fmt: skip
    plant.mutable_gravity_field().set_gravity_vector(g)
    plant.Finalize()
    context = plant.CreateDefaultContext()
    conj = np.array([1.0, -1.0, -1.0, -1.0])
    w_world = _rotate_back((q * conj)[None, :], w0[None, :])[0]  # R_WB omega0
    qs, vs = int(body.floating_positions_start()), int(body.floating_velocities_start_in_v())
    x = plant.GetPositionsAndVelocities(context)
    nq = plant.num_positions()
    x[qs : qs + 7] = (*q, *r0)
    x[nq + vs : nq + vs + 6] = (*w_world, *v0)
    plant.SetPositionsAndVelocities(context, x)
    if hinge is not None:
        hinge.set_angular_rate(context, rate0)
    return plant, context, (qs, vs)


def _spatial(tree: Any, m: float, j: np.ndarray) -> Any:
    """Drake's ``SpatialInertia`` of mass ``m`` with central inertia ``j`` at the origin."""
    rot = tree.RotationalInertia(j[0, 0], j[1, 1], j[2, 2], j[0, 1], j[0, 2], j[1, 2])
    return tree.SpatialInertia.MakeFromCentralInertia(m, np.zeros(3), rot)
