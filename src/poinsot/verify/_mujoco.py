"""Run a rigid-body case in MuJoCo and read its states in poinsot's conventions.

The model is built in memory (MJCF): one body with a **free joint** (a free body;
gravity as given, normally zero) or a **ball joint** at its origin, the fixed point
(a top). The body's ``<inertial>`` has the given mass, the centre of mass at ``com``
(body frame) and ``fullinertia`` about the centre of mass in body axes. Contacts and
every constraint are disabled; no damping, armature or friction.

Conversions (MuJoCo's documentation, "Floating objects" / ``qpos``/``qvel``):

- ``qpos`` stores the body's orientation as a **scalar-first** unit quaternion
  ``(w, x, y, z)`` mapping body to world components: poinsot's convention, taken
  as it is (made sign-continuous along the run);
- the angular velocity in ``qvel`` (the last three components of a free joint, the
  three of a ball joint) is in the body's **local** frame: poinsot's body-axes
  ``omega``, taken as it is;
- a free joint's ``qpos`` starts with the position of the body origin and its
  ``qvel`` with the origin's linear velocity, both in **world** axes (checked: a
  body turned 90 degrees about ``z`` and given ``qvel = (1, 0, 0, ...)`` moves
  along world ``x``). The body origin is the centre of mass of a free body here
  (``com`` zero), so these are poinsot's centre-of-mass ``position`` and
  ``velocity`` of a pose (:func:`run_mujoco_pose`); a rigid case starts them at
  zero.

Sampling: the run steps MuJoCo from ``t[0] = 0`` with ``timestep``. A time of the
grid that falls on a whole step is read there; one that falls between steps (the
tops' 0.005 s grid at MuJoCo's default 0.002 s) is read by **one shorter MuJoCo step**
from the last whole step before it, on a copy of the state (the run goes on from the
whole step, unchanged): the state is MuJoCo's own, by its own integrator, with a
local error no larger than that of a whole step. No interpolation.

**A gyrostat** (``rotor_momentum`` given, docs/theory.md §10.1): the rotor is a second
body, a child of the free body on a frictionless **hinge** along ``a = h / |h|`` through
the centre of mass (:func:`rotor_inputs` maps the case to the two bodies; the mapping
is derived there). The hinge angle and rate follow the free joint in ``qpos``/``qvel``;
the scored states are the platform's, as above.

**An external torque** (``torque(t, q, w)`` given, body axes, e.g. the gravity-gradient
torque of docs/theory.md §10.2): added to ``qfrc_passive`` of the free joint's
rotational degrees of freedom (their generalized force is the torque in body axes) by
a ``mjcb_passive`` callback. MuJoCo calls it from ``mj_passive`` inside every
evaluation of the forward dynamics, so each of the four stages of ``RK4`` sees the
torque of its own state and time (``d.time`` is the stage's time): the scheme keeps its
fourth order (measured, tests/verify/test_mujoco_gyrostat_pitch.py). The callback is
global: the previous one is restored when the run ends (``finally``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from ..errors import InvalidInputError, PoinsotError

INTEGRATORS = ("Euler", "RK4", "implicit", "implicitfast")

#: an external torque ``(t, q, w) -> (3,)`` (N m, body axes)
Torque = Callable[[float, np.ndarray, np.ndarray], np.ndarray]


def _mujoco() -> Any:
    try:
        import mujoco
    except ImportError as exc:
        raise MuJoCoMissing(
            f"the MuJoCo adapter needs the `mujoco` package: pip install 'poinsot[verify]' ({exc})"
        ) from exc
    return mujoco


class MuJoCoMissing(PoinsotError, ImportError):
    """The ``mujoco`` package is not installed."""


def _vec(x: Any, n: int, name: str) -> np.ndarray:
    a = np.asarray(x, dtype=float)
    if a.shape != (n,) or not np.all(np.isfinite(a)):
        raise InvalidInputError(f"Expected `{name}` to be {n} finite numbers, got {x!r}.")
    return a


def body_inputs(
    inertia: Any, mass: Any, q0: Any, omega0: Any, gravity: Any
) -> tuple[np.ndarray, float, np.ndarray, np.ndarray, np.ndarray]:
    """The checked inputs of an engine adapter's body: ``(J (3, 3) symmetric positive
    definite, m > 0, q0 a unit quaternion, omega0 (3,), gravity (3,))``; a bad one raises
    :class:`~poinsot.errors.InvalidInputError` naming it."""
    j = np.asarray(inertia, dtype=float)
    if j.shape != (3, 3) or not np.all(np.isfinite(j)) or not np.allclose(j, j.T, rtol=1e-12):
        raise InvalidInputError(
            f"Expected `inertia` to be a symmetric 3x3 matrix, got {inertia!r}."
        )
    if np.min(np.linalg.eigvalsh(j)) <= 0:
        raise InvalidInputError("Expected `inertia` to be positive definite.")
    m = float(mass)
    if not (math.isfinite(m) and m > 0):
        raise InvalidInputError(f"Expected `mass` to be positive (kg), got {mass!r}.")
    q = _vec(q0, 4, "q0")
    if abs(np.linalg.norm(q) - 1.0) > 1e-9:
        raise InvalidInputError(
            f"Expected `q0` to be a unit quaternion, got |q0| = {np.linalg.norm(q)}."
        )
    return j, m, q, _vec(omega0, 3, "omega0"), _vec(gravity, 3, "gravity")


#: the rotor of a gyrostat in the engines: axial inertia I_r and transverse inertia I_t
#: (kg m^2) of a thin disc (I_r = 2 I_t, dyadic numbers: the platform's inertia is exact)
ROTOR_AXIAL, ROTOR_TRANSVERSE = 0.25, 0.125
#: the rotor's share of the case's mass (its centre of mass is the platform's)
ROTOR_MASS_SHARE = 0.25


def rotor_axis(inertia: Any, rotor_momentum: Any, omega0: Any, axial: float = ROTOR_AXIAL
               ) -> tuple[np.ndarray, np.ndarray, float]:  # fmt: skip
    """The part of :func:`rotor_inputs` that does not depend on the rotor's transverse
    inertia: ``(J_L, a, W0)``, the locked inertia ``J_L = J + I_r a a^T``, the axis
    ``a = h / |h|`` and the initial rate of the rotor relative to the body
    ``W0 = |h| / I_r - a . w0`` (``I_r = axial``; the derivation there). An engine whose
    rotor adds no inertia of its own (Basilisk's balanced reaction wheel) gives its body
    ``J_L``.

    >>> jl, a, w = rotor_axis(np.diag([1.0, 2.0, 3.0]), [0.0, 3.0, 0.0], [0.1, 1.0, 0.1])
    >>> np.diag(jl).tolist(), a.tolist(), w
    ([1.0, 2.25, 3.0], [0.0, 1.0, 0.0], 11.0)
    """
    j, _, _, w0, _ = body_inputs(inertia, 1.0, (1.0, 0.0, 0.0, 0.0), omega0, np.zeros(3))
    h = _vec(rotor_momentum, 3, "rotor_momentum")
    size = float(np.linalg.norm(h))
    if size == 0.0:
        raise InvalidInputError("Expected `rotor_momentum` to be nonzero (kg m^2/s).")
    ir = float(axial)
    if not (math.isfinite(ir) and ir > 0):
        raise InvalidInputError(f"Expected `axial` > 0 (kg m^2), got {axial!r}.")
    a = h / size
    return j + ir * np.outer(a, a), a, size / ir - float(a @ w0)


def rotor_inputs(inertia: Any, rotor_momentum: Any, omega0: Any,
                 axial: float = ROTOR_AXIAL, transverse: float = ROTOR_TRANSVERSE
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:  # fmt: skip
    """A gyrostat ``J w' + w x (J w + h) = 0`` (docs/theory.md §10.1) as two rigid
    bodies: a platform and a free axisymmetric rotor on a hinge along ``a = h / |h|``.

    The rotor (axial inertia ``I_r``, transverse ``I_t``, its centre of mass the
    platform's) has no hinge torque, so its absolute axial momentum
    ``h_s = I_r (a . w + W)`` is constant (``W`` the hinge rate). With ``J_L`` the
    inertia of both bodies locked, the total angular momentum about the centre of mass
    is ``K = R (J_L w + I_r W a) = R ((J_L - I_r a a^T) w + h_s a)``, and ``K' = 0``
    gives ``J' w' + w x (J' w + h_s a) = 0``, ``J' = J_L - I_r a a^T``. The case's
    ``(J, h)`` is reproduced exactly by ``J_L = J + I_r a a^T`` and ``h_s = |h|``:

    - the rotor's inertia ``J_r = I_t (E - a a^T) + I_r a a^T`` (about its centre of
      mass, platform axes);
    - the platform's ``J_p = J_L - J_r = J - I_t (E - a a^T)``;
    - the initial hinge rate ``W0 = |h| / I_r - a . w0``.

    A flat ``J`` (``A + B = C``, the case's ``diag(1, 2, 3)``) gives a flat ``J_p``
    (``trace - 2 max`` drops by ``2 I_t`` at most as much as the trace): the default
    ``I_t``, ``I_r`` are dyadic so that ``J_p`` stays exactly on the bound.

    Parameters
    ----------
    inertia : array_like (3, 3)
        The gyrostat's ``J`` (kg m^2, body axes), symmetric positive definite.
    rotor_momentum : array_like (3,)
        ``h`` (kg m^2/s, body axes), nonzero.
    omega0 : array_like (3,)
        The platform's initial angular velocity (rad/s, body axes).
    axial, transverse : float, optional
        ``I_r > 0`` and ``I_t >= I_r / 2`` (the rotor's triangle inequality), kg m^2.

    Returns
    -------
    platform : ndarray (3, 3)
        ``J_p`` (kg m^2), checked positive definite with its triangle inequality.
    rotor : ndarray (3, 3)
        ``J_r`` (kg m^2).
    axis : ndarray (3,)
        ``a``, the hinge axis (body axes).
    rate0 : float
        ``W0`` (rad/s), the hinge rate (rotor relative to platform).

    Examples
    --------
    >>> jp, jr, a, w = rotor_inputs(np.diag([1.0, 2.0, 3.0]), [0.0, 3.0, 0.0],
    ...                             [0.1, 1.0, 0.1])
    >>> np.diag(jp).tolist(), np.diag(jr).tolist(), a.tolist(), w
    ([0.875, 2.0, 2.875], [0.125, 0.25, 0.125], [0.0, 1.0, 0.0], 11.0)
    """
    _, a, rate0 = rotor_axis(inertia, rotor_momentum, omega0, axial)
    j = np.asarray(inertia, dtype=float)
    ir, it = float(axial), float(transverse)
    if not (math.isfinite(it) and 2.0 * it >= ir):
        raise InvalidInputError(
            f"Expected `axial` > 0 and `transverse` >= axial / 2 (kg m^2), got {axial!r}, "
            f"{transverse!r}."
        )
    across = np.eye(3) - np.outer(a, a)
    rotor = it * across + ir * np.outer(a, a)
    platform = j - it * across
    moments = np.linalg.eigvalsh(platform)
    if moments[0] <= 0 or moments[0] + moments[1] < moments[2] * (1.0 - 1e-12):
        raise InvalidInputError(
            f"Expected `inertia` to leave the platform a valid inertia with a rotor of "
            f"transverse inertia {it} kg m^2; its moments would be {moments.tolist()}."
        )
    return platform, rotor, a, rate0


def sampling(t: np.ndarray, timestep: float) -> tuple[np.ndarray, np.ndarray]:
    """``(whole, frac)``: the whole MuJoCo steps before each time of ``t`` and the
    shorter step (s) from there to it (0 on a whole step, to 1e-6 of a step).

    >>> w, f = sampling(np.array([0.0, 0.005, 0.01]), 0.002)
    >>> w.tolist(), np.round(f, 12).tolist()
    ([0, 2, 5], [0.0, 0.001, 0.0])
    """
    x = np.asarray(t, dtype=float) / timestep
    whole = np.floor(x + 1e-6).astype(np.int64)
    frac = np.where(x - whole > 1e-6, (x - whole) * timestep, 0.0)
    return whole, frac


def _full(j: np.ndarray) -> str:
    """MJCF's ``fullinertia``: ``Ixx Iyy Izz Ixy Ixz Iyz``."""
    return " ".join(f"{v:.17g}" for v in (j[0, 0], j[1, 1], j[2, 2], j[0, 1], j[0, 2], j[1, 2]))


def model_xml(inertia: Any, mass: float, com: Any, gravity: Any, fixed_point: bool,
              integrator: str, timestep: float,
              rotor: tuple[np.ndarray, np.ndarray, float] | None = None) -> str:  # fmt: skip
    """The MJCF of one body (free or ball joint at its origin); see the module docstring.
    ``rotor = (J_r, a, m_r)``: a child body at the origin on a hinge along ``a``."""
    j = np.asarray(inertia, dtype=float)
    full = _full(j)
    pos = " ".join(f"{v:.17g}" for v in com)
    grav = " ".join(f"{v:.17g}" for v in gravity)
    joint = '<joint type="ball" pos="0 0 0"/>' if fixed_point else "<freejoint/>"
    child = ""
    if rotor is not None:
        jr, a, mr = rotor
        axis = " ".join(f"{v:.17g}" for v in a)
        child = f"""
      <body name="rotor" pos="0 0 0">
        <joint name="hinge" type="hinge" pos="0 0 0" axis="{axis}" damping="0" armature="0"
               frictionloss="0"/>
        <inertial pos="0 0 0" mass="{mr:.17g}" fullinertia="{_full(jr)}"/>
      </body>"""
    return f"""<mujoco model="poinsot-verify">
  <compiler angle="radian" autolimits="true"/>
  <option timestep="{timestep:.17g}" gravity="{grav}" integrator="{integrator}">
    <flag contact="disable" constraint="disable"/>
  </option>
  <worldbody>
    <body name="body" pos="0 0 0">
      {joint}
      <inertial pos="{pos}" mass="{mass:.17g}" fullinertia="{full}"/>{child}
    </body>
  </worldbody>
</mujoco>
"""


def run_mujoco(*, inertia: Any, mass: float, com: Any, q0: Any, omega0: Any, gravity: Any,
               fixed_point: bool, t: Any, integrator: str, timestep: float,
               rotor_momentum: Any = None, torque: Torque | None = None
               ) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Integrate one rigid body in MuJoCo; states on the grid ``t``.

    Parameters
    ----------
    inertia : array_like (3, 3)
        About the centre of mass, body axes (kg m^2), symmetric positive definite.
    mass : float
        kg, > 0.
    com : array_like (3,)
        Centre of mass from the body origin (the fixed point of a top), body axes (m).
    q0 : array_like (4,)
        Initial attitude, scalar-first unit quaternion, body -> space.
    omega0 : array_like (3,)
        Initial angular velocity, body axes (rad/s).
    gravity : array_like (3,)
        m/s^2, space axes.
    fixed_point : bool
        A ball joint at the body origin (True) or a free joint (False).
    t : array_like (n,)
        Times from 0 (s), increasing; any spacing (see the module docstring: a time
        between steps is reached by one shorter step from the last whole step).
    integrator : {"Euler", "RK4", "implicit", "implicitfast"}
    timestep : float
        MuJoCo's step (s).
    rotor_momentum : array_like (3,), optional
        A gyrostat's constant rotor momentum ``h`` relative to the body (kg m^2/s, body
        axes; docs/theory.md §10.1): the rotor is a second body on a hinge
        (:func:`rotor_inputs`; a free body only), ``inertia`` the gyrostat's ``J``.
    torque : callable, optional
        ``torque(t, q, w) -> (3,)``, an external torque (N m, body axes) of the time,
        the scalar-first attitude and the body angular velocity, applied at every
        stage of the integrator through ``mjcb_passive`` (a free body only).

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
    >>> from poinsot.verify._mujoco import run_mujoco
    >>> q, w = run_mujoco(inertia=np.diag([1.0, 1.0, 1.0]), mass=1.0, com=np.zeros(3),
    ...                   q0=[1.0, 0.0, 0.0, 0.0], omega0=[0.0, 0.0, 1.0], gravity=np.zeros(3),
    ...                   fixed_point=False, t=np.linspace(0.0, 1.0, 11), integrator="RK4",
    ...                   timestep=0.01)
    >>> round(2.0 * float(np.arctan2(q[-1, 3], q[-1, 0])), 12), w[-1].round(12).tolist()
    (1.0, [0.0, 0.0, 1.0])

    A gyrostat spinning steadily about its rotor's axis keeps its angular velocity:

    >>> q, w = run_mujoco(inertia=np.diag([1.0, 2.0, 3.0]), mass=1.0, com=np.zeros(3),
    ...                   q0=[1.0, 0.0, 0.0, 0.0], omega0=[0.0, 1.0, 0.0], gravity=np.zeros(3),
    ...                   fixed_point=False, t=np.linspace(0.0, 1.0, 11), integrator="RK4",
    ...                   timestep=0.01, rotor_momentum=[0.0, 3.0, 0.0])
    >>> w[-1].round(12).tolist()
    [0.0, 1.0, 0.0]
    """
    q, w, _, _ = _simulate(inertia=inertia, mass=mass, com=com, q0=q0, omega0=omega0,
                           gravity=gravity, fixed_point=fixed_point, t=t, integrator=integrator,
                           timestep=timestep, rotor_momentum=rotor_momentum,
                           torque=torque)  # fmt: skip
    return q, w


def run_mujoco_pose(*, inertia: Any, mass: float, position0: Any, velocity0: Any, q0: Any,
                    omega0: Any, gravity: Any, t: Any, integrator: str, timestep: float
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:  # fmt: skip
    """Integrate one free rigid body in MuJoCo in six degrees of freedom (docs/theory.md
    §9, §10): a free joint at the centre of mass, gravity as given.

    Parameters
    ----------
    inertia, mass, q0, omega0, gravity, t, integrator, timestep
        As :func:`run_mujoco`.
    position0, velocity0 : array_like (3,)
        The centre of mass's initial position and velocity (m, m/s, world axes).

    Returns
    -------
    position, velocity : ndarray (n, 3)
        The centre of mass (m, m/s, world axes).
    q, omega : ndarray (n, 4), (n, 3)
        As :func:`run_mujoco`.

    Examples
    --------
    >>> import numpy as np
    >>> r, v, q, w = run_mujoco_pose(inertia=np.eye(3), mass=1.0, position0=[0.0, 0.0, 1.0],
    ...                              velocity0=[1.0, 0.0, 0.0], q0=[1.0, 0.0, 0.0, 0.0],
    ...                              omega0=[0.0, 0.0, 1.0], gravity=[0.0, 0.0, -10.0],
    ...                              t=np.linspace(0.0, 1.0, 11), integrator="RK4",
    ...                              timestep=0.01)
    >>> r[-1].round(12).tolist(), v[-1].round(12).tolist()
    ([1.0, 0.0, -4.0], [1.0, 0.0, -10.0])
    """
    q, w, r, v = _simulate(inertia=inertia, mass=mass, com=np.zeros(3), q0=q0, omega0=omega0,
                           gravity=gravity, fixed_point=False, t=t, integrator=integrator,
                           timestep=timestep, position0=position0, velocity0=velocity0)  # fmt: skip
    return r, v, q, w


def build(*, inertia: Any, mass: float, com: Any, q0: Any, omega0: Any, gravity: Any,
          fixed_point: bool, integrator: str, timestep: float,
          position0: Any = (0.0, 0.0, 0.0), velocity0: Any = (0.0, 0.0, 0.0),
          rotor_momentum: Any = None) -> tuple[Any, Any]:  # fmt: skip
    """The MuJoCo ``(model, data)`` of :func:`run_mujoco` at ``t = 0`` (after
    ``mj_forward``); the arguments as there (docs/theory.md §10.1 for the rotor). The
    free joint (or ball joint) comes first in ``qpos``/``qvel``, a gyrostat's hinge
    after it.

    >>> model, data = build(inertia=np.diag([1.0, 2.0, 3.0]), mass=1.0, com=np.zeros(3),
    ...                     q0=[1.0, 0.0, 0.0, 0.0], omega0=[0.1, 1.0, 0.1],
    ...                     gravity=np.zeros(3), fixed_point=False, integrator="RK4",
    ...                     timestep=1e-3, rotor_momentum=[0.0, 3.0, 0.0])
    >>> model.nv, float(data.qvel[6])
    (7, 11.0)
    """
    mujoco = _mujoco()
    if integrator not in INTEGRATORS:
        raise InvalidInputError(
            f"Expected `integrator` to be one of {', '.join(INTEGRATORS)}, got {integrator!r}."
        )
    j, m, q, w0, g = body_inputs(inertia, mass, q0, omega0, gravity)
    c = _vec(com, 3, "com")
    h = float(timestep)
    if not (math.isfinite(h) and h > 0):
        raise InvalidInputError(f"Expected `timestep` to be positive (s), got {timestep!r}.")
    rotor = None
    if rotor_momentum is not None:
        if fixed_point or np.any(c):
            raise InvalidInputError(
                "Expected a free body with `com` zero for a `rotor_momentum` (a gyrostat)."
            )
        j, jr, a, rate0 = rotor_inputs(j, rotor_momentum, w0)
        rotor = (jr, a, ROTOR_MASS_SHARE * m)
        m = (1.0 - ROTOR_MASS_SHARE) * m
    try:
        model = mujoco.MjModel.from_xml_string(
            model_xml(j, m, c, g, bool(fixed_point), integrator, h, rotor)
        )
    except ValueError as exc:  # MuJoCo's own checks, e.g. its triangle inequality
        raise InvalidInputError(
            f"MuJoCo refused the body (`inertia`, `mass`, `com`): {exc}"
        ) from None
    data = mujoco.MjData(model)
    qa = 0 if fixed_point else 3  # where the quaternion starts in qpos
    data.qpos[qa : qa + 4] = q
    data.qvel[qa : qa + 3] = w0
    if not fixed_point:
        data.qpos[:3] = _vec(position0, 3, "position0")
        data.qvel[:3] = _vec(velocity0, 3, "velocity0")
    if rotor is not None:
        data.qvel[6] = rate0  # the hinge, after the free joint
    mujoco.mj_forward(model, data)
    return model, data


def _simulate(*, inertia: Any, mass: float, com: Any, q0: Any, omega0: Any, gravity: Any,
              fixed_point: bool, t: Any, integrator: str, timestep: float,
              position0: Any = (0.0, 0.0, 0.0), velocity0: Any = (0.0, 0.0, 0.0),
              rotor_momentum: Any = None, torque: Torque | None = None
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:  # fmt: skip
    """The run of :func:`run_mujoco` and :func:`run_mujoco_pose`: ``(q, omega, position,
    velocity)`` (the last two of a free joint's origin; zero for a ball joint)."""
    mujoco = _mujoco()
    tt = np.asarray(t, dtype=float)
    if tt.ndim != 1 or tt.size < 1 or tt[0] != 0.0 or np.any(np.diff(tt) <= 0):
        raise InvalidInputError("Expected `t` to be increasing times starting at 0 (s).")
    if torque is not None and (fixed_point or not callable(torque)):
        raise InvalidInputError("Expected `torque` to be a callable, on a free body.")
    # a Python passive callback (ours, or one installed before) breaks MuJoCo's model
    # compilation ("Python exception raised"): none while building, the previous one
    # restored at the end
    previous = mujoco.get_mjcb_passive()
    mujoco.set_mjcb_passive(None)
    try:
        model, data = build(inertia=inertia, mass=mass, com=com, q0=q0, omega0=omega0,
                            gravity=gravity, fixed_point=fixed_point, integrator=integrator,
                            timestep=timestep, position0=position0, velocity0=velocity0,
                            rotor_momentum=rotor_momentum)  # fmt: skip
    except BaseException:
        mujoco.set_mjcb_passive(previous)
        raise
    if torque is None:
        mujoco.set_mjcb_passive(previous)
    h = float(timestep)
    whole, frac = sampling(tt, h)
    qa = 0 if fixed_point else 3  # where the quaternion starts in qpos
    wa = 0 if fixed_point else 3  # where the angular velocity starts in qvel
    out_q = np.empty((tt.size, 4))
    out_w = np.empty((tt.size, 3))
    out_rv = np.zeros((tt.size, 6))
    scratch = mujoco.MjData(model)
    done = 0
    try:
        if torque is not None:

            def passive(m: Any, d: Any) -> None:  # every evaluation of the dynamics
                d.qfrc_passive[3:6] += torque(float(d.time), d.qpos[3:7].copy(),
                                              d.qvel[3:6].copy())  # fmt: skip

            mujoco.set_mjcb_passive(passive)
            mujoco.mj_forward(model, data)
        for n in range(tt.size):
            if whole[n] > done:
                mujoco.mj_step(model, data, nstep=int(whole[n] - done))
                done = int(whole[n])
            src = data
            if frac[n] > 0.0:  # between steps: one shorter step on a copy of the state
                mujoco.mj_copyData(scratch, model, data)
                model.opt.timestep = frac[n]
                try:
                    mujoco.mj_step(model, scratch)
                finally:
                    model.opt.timestep = h
                src = scratch
            out_q[n], out_w[n] = src.qpos[qa : qa + 4], src.qvel[wa : wa + 3]
            if not fixed_point:
                out_rv[n] = (*src.qpos[:3], *src.qvel[:3])
    finally:
        if torque is not None:
            mujoco.set_mjcb_passive(previous)
    flips = np.concatenate([[1.0], np.where(np.sum(out_q[1:] * out_q[:-1], -1) < 0, -1.0, 1.0)])
    return out_q * np.cumprod(flips)[:, None], out_w, out_rv[:, :3], out_rv[:, 3:]
