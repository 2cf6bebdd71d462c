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
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import InvalidInputError, PoinsotError

INTEGRATORS = ("Euler", "RK4", "implicit", "implicitfast")


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


def model_xml(inertia: Any, mass: float, com: Any, gravity: Any, fixed_point: bool,
              integrator: str, timestep: float) -> str:  # fmt: skip
    """The MJCF of one body (free or ball joint at its origin); see the module docstring."""
    j = np.asarray(inertia, dtype=float)
    full = " ".join(f"{v:.17g}" for v in (j[0, 0], j[1, 1], j[2, 2], j[0, 1], j[0, 2], j[1, 2]))
    pos = " ".join(f"{v:.17g}" for v in com)
    grav = " ".join(f"{v:.17g}" for v in gravity)
    joint = '<joint type="ball" pos="0 0 0"/>' if fixed_point else "<freejoint/>"
    return f"""<mujoco model="poinsot-verify">
  <compiler angle="radian" autolimits="true"/>
  <option timestep="{timestep:.17g}" gravity="{grav}" integrator="{integrator}">
    <flag contact="disable" constraint="disable"/>
  </option>
  <worldbody>
    <body name="body" pos="0 0 0">
      {joint}
      <inertial pos="{pos}" mass="{mass:.17g}" fullinertia="{full}"/>
    </body>
  </worldbody>
</mujoco>
"""


def run_mujoco(*, inertia: Any, mass: float, com: Any, q0: Any, omega0: Any, gravity: Any,
               fixed_point: bool, t: Any, integrator: str, timestep: float
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

    Returns
    -------
    q : ndarray (n, 4)
        Scalar-first quaternions body -> space, sign-continuous.
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
    """
    q, w, _, _ = _simulate(inertia=inertia, mass=mass, com=com, q0=q0, omega0=omega0,
                           gravity=gravity, fixed_point=fixed_point, t=t, integrator=integrator,
                           timestep=timestep)  # fmt: skip
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


def _simulate(*, inertia: Any, mass: float, com: Any, q0: Any, omega0: Any, gravity: Any,
              fixed_point: bool, t: Any, integrator: str, timestep: float,
              position0: Any = (0.0, 0.0, 0.0), velocity0: Any = (0.0, 0.0, 0.0)
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:  # fmt: skip
    """The run of :func:`run_mujoco` and :func:`run_mujoco_pose`: ``(q, omega, position,
    velocity)`` (the last two of a free joint's origin; zero for a ball joint)."""
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
    tt = np.asarray(t, dtype=float)
    if tt.ndim != 1 or tt.size < 1 or tt[0] != 0.0 or np.any(np.diff(tt) <= 0):
        raise InvalidInputError("Expected `t` to be increasing times starting at 0 (s).")
    whole, frac = sampling(tt, h)
    try:
        model = mujoco.MjModel.from_xml_string(
            model_xml(j, m, c, g, bool(fixed_point), integrator, h)
        )
    except ValueError as exc:  # MuJoCo's own checks, e.g. its triangle inequality
        raise InvalidInputError(
            f"MuJoCo refused the body (`inertia`, `mass`, `com`): {exc}"
        ) from None
    data = mujoco.MjData(model)
    qa = 0 if fixed_point else 3  # where the quaternion starts in qpos
    wa = 0 if fixed_point else 3  # where the angular velocity starts in qvel
    data.qpos[qa : qa + 4] = q
    data.qvel[wa : wa + 3] = w0
    if not fixed_point:
        data.qpos[:3] = _vec(position0, 3, "position0")
        data.qvel[:3] = _vec(velocity0, 3, "velocity0")
    mujoco.mj_forward(model, data)
    out_q = np.empty((tt.size, 4))
    out_w = np.empty((tt.size, 3))
    out_rv = np.zeros((tt.size, 6))
    scratch = mujoco.MjData(model)
    done = 0
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
    flips = np.concatenate([[1.0], np.where(np.sum(out_q[1:] * out_q[:-1], -1) < 0, -1.0, 1.0)])
    return out_q * np.cumprod(flips)[:, None], out_w, out_rv[:, :3], out_rv[:, 3:]
