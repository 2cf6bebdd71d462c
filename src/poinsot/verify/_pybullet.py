"""Run a free rigid body in PyBullet and read its states in poinsot's conventions.

The model: one PyBullet multibody with a base and no links, in a ``DIRECT`` (no GUI)
physics client of its own, gravity as given (zero for the free bodies), no other
body (so no contact), linear and angular damping set to zero (PyBullet's default is
0.04 for both, which would drain the energy).

Conventions of PyBullet (PyBullet Quickstart Guide: ``createMultiBody``,
``getBasePositionAndOrientation``, ``getBaseVelocity``, ``resetBaseVelocity``;
bullet3 issues #2096 and #3312, answered by its author):

- quaternions are **scalar-last** ``[x, y, z, w]`` and give the orientation of the
  base in world coordinates (body -> world): reordered to poinsot's ``(w, x, y, z)``;
- ``getBasePositionAndOrientation`` / ``resetBasePositionAndOrientation`` refer to
  the base's **inertial frame** (its centre of mass, axes along the principal axes
  of inertia), not to the frame it was created in; its inertia is the diagonal
  ``localInertiaDiagonal`` in that frame. So the body is given to PyBullet in its
  principal frame ``P`` (``J = P diag(l) P^T``, ``det P = +1``): PyBullet's attitude is
  ``R P`` (quaternion ``q_body * q_P``) and poinsot's is read back as
  ``q_pybullet * conj(q_P)``. A diagonal inertia has ``P = E``;
- the angular velocity of ``getBaseVelocity`` / ``resetBaseVelocity`` is in **world**
  axes: poinsot's body-axes ``omega = R^T w_world`` (and ``w_world = R omega0`` to set
  the initial state).

Integration: ``stepSimulation`` with ``setTimeStep(timestep)``: Bullet's
semi-implicit (symplectic) Euler step, first order. ``coordinates="reduced"``
(PyBullet's default) builds a Featherstone ``btMultiBody``, whose forward dynamics
carry the gyroscopic term ``w x J w`` in the bias force, evaluated explicitly at the
start of the step; ``"maximal"`` (``useMaximalCoordinates=True``) builds a
``btRigidBody``, whose gyroscopic term Bullet (2.83 and later) integrates implicitly
in body axes by default (``BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY``). PyBullet's
Python API has no call that changes that flag. A maximal-coordinates base without a
collision shape is static (PyBullet reports its mass as 0), so that body gets a
sphere collision shape with its collision filter mask set to 0 (it collides with
nothing), and its inertia is then set by ``changeDynamics`` as for the other.

Sampling: as the MuJoCo adapter (:func:`poinsot.verify._mujoco.sampling`): a time
of the grid on a whole step is read there; one between steps by one shorter step
from the last whole step, on a saved state (``saveState``/``restoreState``).

**A gyrostat** (``rotor_momentum`` given, docs/theory.md §10.1; reduced coordinates):
the rotor is a link of the multibody on a ``JOINT_REVOLUTE`` along ``a = h / |h|``
through the centre of mass, its motor switched off (``setJointMotorControl2``
``VELOCITY_CONTROL`` with ``force=0``; PyBullet motorises revolute joints by default)
and no joint damping; the two bodies are those of
:func:`poinsot.verify._mujoco.rotor_inputs`. The joint axis and the rotor's inertial
frame are given in the base's (the platform's principal) frame.

**An external torque** (``torque(t, q, w)`` given, body axes): ``applyExternalTorque``
in world axes (``R`` times it) before every step, from the state at its start (Bullet
clears applied forces after each step): first order, like the step itself.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .. import _quat
from ..errors import InvalidInputError, PoinsotError
from ..rotations.rotation import Rotation
from ._mujoco import ROTOR_MASS_SHARE, Torque, _vec, body_inputs, rotor_inputs, sampling

COORDINATES = ("reduced", "maximal")

#: why maximal coordinates take no rotor and no external torque here
MAXIMAL_SKIP = (
    "PyBullet's maximal-coordinates adapter takes no rotor link (a rigid body has no "
    "joint of its own) and its applyExternalTorque was measured wrong: a constant 3 N m "
    "on a 3 kg m^2 axis from rest gives 0.85 rad/s after 0.1 s at a 1 ms step, not "
    "0.1 rad/s (reduced coordinates: 0.1)"
)


class PyBulletMissing(PoinsotError, ImportError):
    """The ``pybullet`` package is not installed."""


def _pybullet() -> Any:
    try:
        import pybullet
    except ImportError as exc:
        raise PyBulletMissing(
            "the PyBullet adapter needs the `pybullet` package: "
            f"pip install 'poinsot[verify]' ({exc})"
        ) from exc
    return pybullet


def _rotate_back(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``R(q)^T v`` for scalar-first unit quaternions ``q`` (n, 4) and vectors (n, 3):
    space components -> body components."""
    return _quat.rotate(_quat.conj(q), v)


def principal_frame(inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(moments, q_P)``: the principal moments and the scalar-first quaternion of the
    rotation ``P`` (columns: the principal axes in body axes, ``det P = +1``) with
    ``J = P diag(moments) P^T``. A diagonal ``J`` gives ``q_P = (1, 0, 0, 0)``.

    >>> m, q = principal_frame(np.diag([1.0, 2.0, 3.0]))
    >>> m.tolist(), q.tolist()
    ([1.0, 2.0, 3.0], [1.0, 0.0, 0.0, 0.0])
    """
    j = np.asarray(inertia, dtype=float)
    if np.array_equal(j, np.diag(np.diag(j))):
        return np.diag(j).copy(), np.array([1.0, 0.0, 0.0, 0.0])
    moments, p = np.linalg.eigh(j)
    if np.linalg.det(p) < 0:
        p[:, 2] = -p[:, 2]
    return moments, np.asarray(Rotation.from_matrix(p).as_quat(), dtype=float)


def run_pybullet(*, inertia: Any, mass: float, q0: Any, omega0: Any, gravity: Any, t: Any,
                 timestep: float, coordinates: str = "reduced", rotor_momentum: Any = None,
                 torque: Torque | None = None) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Integrate one free rigid body in PyBullet; states on the grid ``t``.

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
        m/s^2, space axes (zero for a free body; the attitude does not feel it).
    t : array_like (n,)
        Times from 0 (s), increasing (a time between steps: see the module docstring).
    timestep : float
        PyBullet's step (s).
    coordinates : {"reduced", "maximal"}
        A Featherstone multibody (PyBullet's default) or a maximal-coordinates rigid
        body (see the module docstring).
    rotor_momentum : array_like (3,), optional
        A gyrostat's constant rotor momentum ``h`` relative to the body (kg m^2/s, body
        axes; docs/theory.md §10.1): the rotor is a link on a revolute joint (reduced
        coordinates only), ``inertia`` the gyrostat's ``J``.
    torque : callable, optional
        ``torque(t, q, w) -> (3,)``, an external torque (N m, body axes), applied
        before every step from the state at its start.

    Returns
    -------
    q : ndarray (n, 4)
        Scalar-first quaternions body -> space, sign-continuous (the platform's for a
        gyrostat).
    omega : ndarray (n, 3)
        Body-axes angular velocity (rad/s).

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.verify._pybullet import run_pybullet
    >>> q, w = run_pybullet(inertia=np.diag([1.0, 2.0, 3.0]), mass=1.0,
    ...                     q0=[1.0, 0.0, 0.0, 0.0], omega0=[0.0, 0.0, 1.0],
    ...                     gravity=np.zeros(3), t=np.linspace(0.0, 1.0, 11), timestep=0.01)
    >>> round(2.0 * float(np.arctan2(q[-1, 3], q[-1, 0])), 12), w[-1].round(12).tolist()
    (1.0, [0.0, 0.0, 1.0])

    A gyrostat spinning steadily about its rotor's axis keeps its angular velocity:

    >>> q, w = run_pybullet(inertia=np.diag([1.0, 2.0, 3.0]), mass=1.0,
    ...                     q0=[1.0, 0.0, 0.0, 0.0], omega0=[0.0, 1.0, 0.0],
    ...                     gravity=np.zeros(3), t=np.linspace(0.0, 1.0, 11), timestep=0.01,
    ...                     rotor_momentum=[0.0, 3.0, 0.0])
    >>> w[-1].round(9).tolist()
    [0.0, 1.0, 0.0]
    """
    q, w, _, _ = _simulate(inertia=inertia, mass=mass, q0=q0, omega0=omega0, gravity=gravity,
                           t=t, timestep=timestep, coordinates=coordinates,
                           rotor_momentum=rotor_momentum, torque=torque)  # fmt: skip
    return q, w


def run_pybullet_pose(*, inertia: Any, mass: float, position0: Any, velocity0: Any, q0: Any,
                      omega0: Any, gravity: Any, t: Any, timestep: float,
                      coordinates: str = "reduced"
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:  # fmt: skip
    """Integrate one free rigid body in PyBullet in six degrees of freedom (docs/theory.md
    §9, §10): the base's centre of mass moves too, gravity as given.

    Parameters
    ----------
    inertia, mass, q0, omega0, gravity, t, timestep, coordinates
        As :func:`run_pybullet`.
    position0, velocity0 : array_like (3,)
        The centre of mass's initial position and velocity (m, m/s, world axes).

    Returns
    -------
    position, velocity : ndarray (n, 3)
        The centre of mass (m, m/s, world axes).
    q, omega : ndarray (n, 4), (n, 3)
        As :func:`run_pybullet`.

    Examples
    --------
    >>> import numpy as np
    >>> r, v, q, w = run_pybullet_pose(inertia=np.eye(3), mass=1.0, position0=[0.0, 0.0, 1.0],
    ...                                velocity0=[1.0, 0.0, 0.0], q0=[1.0, 0.0, 0.0, 0.0],
    ...                                omega0=[0.0, 0.0, 1.0], gravity=[0.0, 0.0, -10.0],
    ...                                t=np.linspace(0.0, 1.0, 11), timestep=0.01)
    >>> r[-1].round(9).tolist(), v[-1].round(9).tolist()  # semi-implicit Euler: z off by g h t / 2
    ([1.0, 0.0, -4.05], [1.0, 0.0, -10.0])
    """
    q, w, r, v = _simulate(inertia=inertia, mass=mass, q0=q0, omega0=omega0, gravity=gravity,
                           t=t, timestep=timestep, coordinates=coordinates,
                           position0=position0, velocity0=velocity0)  # fmt: skip
    return r, v, q, w


def _simulate(*, inertia: Any, mass: float, q0: Any, omega0: Any, gravity: Any, t: Any,
              timestep: float, coordinates: str, position0: Any = (0.0, 0.0, 0.0),
              velocity0: Any = (0.0, 0.0, 0.0), rotor_momentum: Any = None,
              torque: Torque | None = None
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:  # fmt: skip
    """The run of :func:`run_pybullet` and :func:`run_pybullet_pose`: ``(q, omega,
    position, velocity)`` (the centre of mass's, world axes)."""
    pb = _pybullet()
    if coordinates not in COORDINATES:
        raise InvalidInputError(
            f"Expected `coordinates` to be 'reduced' or 'maximal', got {coordinates!r}."
        )
    j, m, q, w0, g = body_inputs(inertia, mass, q0, omega0, gravity)
    r0 = [float(x) for x in _vec(position0, 3, "position0")]
    v0 = [float(x) for x in _vec(velocity0, 3, "velocity0")]
    h = float(timestep)
    if not (math.isfinite(h) and h > 0):
        raise InvalidInputError(f"Expected `timestep` to be positive (s), got {timestep!r}.")
    tt = np.asarray(t, dtype=float)
    if tt.ndim != 1 or tt.size < 1 or tt[0] != 0.0 or np.any(np.diff(tt) <= 0):
        raise InvalidInputError("Expected `t` to be increasing times starting at 0 (s).")
    whole, frac = sampling(tt, h)
    if torque is not None and (coordinates != "reduced" or not callable(torque)):
        raise InvalidInputError(
            "Expected `torque` to be a callable (t, q, w) -> (3,), with `coordinates` "
            f"'reduced': {MAXIMAL_SKIP}."
        )
    link: dict[str, Any] = {}
    rate0 = 0.0
    if rotor_momentum is not None:
        if coordinates != "reduced":
            raise InvalidInputError(
                "Expected `coordinates` 'reduced' for a `rotor_momentum` (the rotor is a "
                "link of a Featherstone multibody)."
            )
        j, jr, a, rate0 = rotor_inputs(j, rotor_momentum, w0)
        m, mr = (1.0 - ROTOR_MASS_SHARE) * m, ROTOR_MASS_SHARE * m

    moments, q_p = principal_frame(j)
    q_pb = _quat.mul(q, q_p)  # the principal frame's attitude, PyBullet's base
    conj = np.array([1.0, -1.0, -1.0, -1.0])
    w_world = _rotate_back((q * conj)[None, :], w0[None, :])[0]  # R(q0) omega0
    if rotor_momentum is not None:  # the rotor link, in the base's (principal) frame
        rotor_moments, q_r = principal_frame(jr)
        a_p = _rotate_back(q_p[None, :], a[None, :])[0]  # P^T a
        q_rp = _quat.mul(q_p * conj, q_r)  # the rotor's principal frame in the base's
        link = {"linkMasses": [mr], "linkCollisionShapeIndices": [-1],
                "linkVisualShapeIndices": [-1], "linkPositions": [[0.0, 0.0, 0.0]],
                "linkOrientations": [[0.0, 0.0, 0.0, 1.0]],
                "linkInertialFramePositions": [[0.0, 0.0, 0.0]],
                "linkInertialFrameOrientations": [[q_rp[1], q_rp[2], q_rp[3], q_rp[0]]],
                "linkParentIndices": [0], "linkJointTypes": [pb.JOINT_REVOLUTE],
                "linkJointAxis": [[float(x) for x in a_p]]}  # fmt: skip
    cid = pb.connect(pb.DIRECT)
    try:
        kw = {"physicsClientId": cid}
        pb.setGravity(*g, **kw)
        pb.setTimeStep(h, **kw)
        maximal = coordinates == "maximal"
        shape = pb.createCollisionShape(pb.GEOM_SPHERE, radius=0.1, **kw) if maximal else -1
        body = pb.createMultiBody(
            baseMass=m, baseCollisionShapeIndex=shape, baseVisualShapeIndex=-1,
            basePosition=r0,
            baseOrientation=[q_pb[1], q_pb[2], q_pb[3], q_pb[0]],
            useMaximalCoordinates=maximal, **link, **kw,
        )  # fmt: skip
        if maximal:
            pb.setCollisionFilterGroupMask(body, -1, 0, 0, **kw)
        pb.changeDynamics(body, -1, mass=m, localInertiaDiagonal=[float(x) for x in moments],
                          linearDamping=0.0, angularDamping=0.0,
                          activationState=pb.ACTIVATION_STATE_DISABLE_SLEEPING, **kw)  # fmt: skip
        pb.resetBaseVelocity(body, v0, [float(x) for x in w_world], **kw)
        if link:
            pb.changeDynamics(body, 0, mass=mr, localInertiaDiagonal=[float(x) for x in
                              rotor_moments], jointDamping=0.0, **kw)  # fmt: skip
            pb.setJointMotorControl2(body, 0, pb.VELOCITY_CONTROL, force=0.0, **kw)
            pb.resetJointState(body, 0, targetValue=0.0, targetVelocity=rate0, **kw)

        def step(time: float) -> None:
            if torque is not None:  # the body torque of the state at the step's start
                _, qx = pb.getBasePositionAndOrientation(body, **kw)
                _, wx = pb.getBaseVelocity(body, **kw)
                qb = _quat.mul(np.array([qx[3], qx[0], qx[1], qx[2]]), q_p * conj)
                qb = qb / np.linalg.norm(qb)
                wb = _rotate_back(qb[None, :], np.asarray(wx, dtype=float)[None, :])[0]
                mw = _rotate_back((qb * conj)[None, :], torque(time, qb, wb)[None, :])[0]
                pb.applyExternalTorque(body, -1, [float(x) for x in mw], pb.WORLD_FRAME, **kw)
            pb.stepSimulation(**kw)

        out_q = np.empty((tt.size, 4))
        out_w = np.empty((tt.size, 3))
        out_rv = np.empty((tt.size, 6))

        def read(n: int) -> None:
            rx, qx = pb.getBasePositionAndOrientation(body, **kw)
            vx, wx = pb.getBaseVelocity(body, **kw)
            out_q[n] = (qx[3], qx[0], qx[1], qx[2])
            out_w[n] = wx
            out_rv[n] = (*rx, *vx)

        done = 0
        for n in range(tt.size):
            while done < whole[n]:
                step(done * h)
                done += 1
            if frac[n] > 0.0:  # between steps: one shorter step from a saved state
                state = pb.saveState(**kw)
                pb.setTimeStep(float(frac[n]), **kw)
                step(done * h)
                read(n)
                pb.setTimeStep(h, **kw)
                pb.restoreState(stateId=state, **kw)
                pb.removeState(state, **kw)
            else:
                read(n)
    finally:
        pb.disconnect(physicsClientId=cid)

    q_body = _quat.mul(out_q, q_p * conj)  # q_pb * conj(q_P)
    q_body /= np.linalg.norm(q_body, axis=1, keepdims=True)
    w_body = _rotate_back(q_body, out_w)
    flips = np.concatenate([[1.0], np.where(np.sum(q_body[1:] * q_body[:-1], -1) < 0, -1.0, 1.0)])
    return q_body * np.cumprod(flips)[:, None], w_body, out_rv[:, :3], out_rv[:, 3:]
