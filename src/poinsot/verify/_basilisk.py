"""Run a free rigid body in Basilisk and read its states in poinsot's conventions.

The model: one Basilisk ``spacecraft.Spacecraft`` (``Basilisk.simulation.spacecraft``)
in a simulation of one process and one task, its hub alone: ``hub.mHub`` the mass,
``hub.IHubPntBc_B`` the inertia about the hub's centre of mass ``Bc`` in body axes
(the full matrix), ``hub.r_BcB_B = 0`` (the body frame's origin is at the centre of
mass), no gravity body, no state or dynamic effector: a torque-free rigid body.
Its translation (``r_CN_NInit``, ``v_CN_NInit``) starts at rest at the origin.

Conventions of Basilisk (``spacecraft`` module documentation; Schaub & Junkins,
*Analytical Mechanics of Space Systems*, on which Basilisk's ``RigidBodyKinematics``
is built):

- the attitude state is ``sigma_BN``: the modified Rodrigues parameters (MRPs) of the
  direction cosine matrix ``[BN]``, which maps **inertial components to body
  components**; poinsot's quaternion maps body to inertial, ``R_ib = [BN]^T``. The
  Euler parameters of ``[BN]`` (``MRP2EP``) are poinsot's scalar-first quaternion up
  to sign, so ``sigma_BN = q_v / (1 + q_w)`` and back
  ``q = ((1 - s^2), 2 sigma) / (1 + s^2)`` (``s = |sigma|``); Basilisk switches to the
  shadow set when ``|sigma| > 1`` (a quaternion sign flip), undone here by making
  the quaternions sign-continuous;
- the angular velocity ``omega_BN_B`` is in **body axes**, as poinsot's.

Integration: the spacecraft's state integrator, set by ``sc.setIntegrator`` to one
of Basilisk's ``svIntegrators`` (``svIntegratorRK4``, Basilisk's default,
``svIntegratorEuler``, ``svIntegratorRK2``, ``svIntegratorRKF45``,
``svIntegratorRKF78``), over the task's period ``timestep``. The adaptive
``RKF45``/``RKF78`` take the task period as their longest step and cut it to meet
their ``relTol`` / ``absTol``. The grid's times are reached by
``ConfigureStopTime`` + ``ExecuteSimulation`` and the hub's state read from its
``scStateOutMsg``, written at the end of each task update; they must be whole
multiples of the task period (Basilisk's clock is in integer nanoseconds).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import InvalidInputError, PoinsotError
from ._mujoco import body_inputs

#: Basilisk's state integrators (``Basilisk.simulation.svIntegrators``), by the name
#: of the adapter's option: class names ``svIntegrator<NAME>``
INTEGRATORS = ("RK4", "Euler", "RK2", "RKF45", "RKF78")
#: the adaptive ones (``relTol``, ``absTol``)
ADAPTIVE = ("RKF45", "RKF78")


class BasiliskMissing(PoinsotError, ImportError):
    """The ``bsk`` package (Basilisk) is not installed."""


def _basilisk() -> tuple[Any, Any, Any, Any]:
    try:
        from Basilisk.simulation import spacecraft, svIntegrators
        from Basilisk.utilities import SimulationBaseClass, macros
    except ImportError as exc:
        raise BasiliskMissing(
            "the Basilisk adapter needs Basilisk: pip install bsk (in an environment of "
            f"its own: it caps pandas and matplotlib) ({exc})"
        ) from exc
    return spacecraft, svIntegrators, SimulationBaseClass, macros


def quat_to_mrp(q: Any) -> np.ndarray:
    """Basilisk's ``sigma_BN`` of poinsot's scalar-first quaternion(s) body -> inertial
    (the set with ``|sigma| <= 1``).

    >>> quat_to_mrp([0.0, 0.0, 0.0, 1.0]).tolist()  # a half turn about z
    [0.0, 0.0, 1.0]
    """
    a = np.asarray(q, dtype=float)
    a = np.where(a[..., :1] < 0, -a, a)
    return a[..., 1:] / (1.0 + a[..., :1])


def mrp_to_quat(sigma: Any) -> np.ndarray:
    """poinsot's scalar-first quaternion(s) body -> inertial of Basilisk's ``sigma_BN``.

    >>> mrp_to_quat([0.0, 0.0, 1.0]).tolist()
    [0.0, 0.0, 0.0, 1.0]
    """
    s = np.asarray(sigma, dtype=float)
    s2 = np.sum(s * s, axis=-1, keepdims=True)
    return np.concatenate([1.0 - s2, 2.0 * s], axis=-1) / (1.0 + s2)


def run_basilisk(*, inertia: Any, mass: float, q0: Any, omega0: Any, t: Any,
                 integrator: str = "RK4", timestep: float = 1e-3,
                 rtol: float | None = None) -> tuple[np.ndarray, np.ndarray, int]:  # fmt: skip
    """Integrate one free rigid body in Basilisk; states on the grid ``t``.

    Parameters
    ----------
    inertia : array_like (3, 3)
        About the centre of mass, body axes (kg m^2), symmetric positive definite.
    mass : float
        kg, > 0.
    q0 : array_like (4,)
        Initial attitude, scalar-first unit quaternion, body -> inertial.
    omega0 : array_like (3,)
        Initial angular velocity, body axes (rad/s).
    t : array_like (n,)
        Times from 0 (s), increasing, whole multiples of ``timestep``.
    integrator : str
        One of :data:`INTEGRATORS`.
    timestep : float
        The task period (s): the step of the fixed-step integrators, the longest step
        of the adaptive ones.
    rtol : float, optional
        ``relTol`` of an adaptive integrator (``absTol = rtol * 1e-3``); default
        Basilisk's own.

    Returns
    -------
    q : ndarray (n, 4)
        Scalar-first unit quaternions body -> inertial, sign-continuous.
    omega : ndarray (n, 3)
        Body-axes angular velocity (rad/s).
    steps : int
        The task updates (steps of the fixed-step integrators).

    Examples
    --------
    >>> import numpy as np
    >>> from poinsot.verify._basilisk import run_basilisk
    >>> q, w, n = run_basilisk(inertia=np.diag([1.0, 2.0, 3.0]), mass=1.0,
    ...                        q0=[1.0, 0.0, 0.0, 0.0], omega0=[0.0, 0.0, 1.0],
    ...                        t=np.linspace(0.0, 1.0, 11), timestep=0.01)
    >>> round(2.0 * float(np.arctan2(q[-1, 3], q[-1, 0])), 12), w[-1].round(12).tolist()
    (1.0, [0.0, 0.0, 1.0])
    """
    spacecraft, sv, sim_base, macros = _basilisk()
    if integrator not in INTEGRATORS:
        raise InvalidInputError(
            f"Expected `integrator` to be one of {', '.join(INTEGRATORS)}, got {integrator!r}."
        )
    j, m, q, w0, _ = body_inputs(inertia, mass, q0, omega0, np.zeros(3))  # no gravity here
    h = float(timestep)
    if not (math.isfinite(h) and h > 0):
        raise InvalidInputError(f"Expected `timestep` to be positive (s), got {timestep!r}.")
    if rtol is not None and not (math.isfinite(float(rtol)) and float(rtol) > 0):
        raise InvalidInputError(f"Expected `rtol` to be positive, got {rtol!r}.")
    tt = np.asarray(t, dtype=float)
    if tt.ndim != 1 or tt.size < 1 or tt[0] != 0.0 or np.any(np.diff(tt) <= 0):
        raise InvalidInputError("Expected `t` to be increasing times starting at 0 (s).")
    dt_ns = int(round(h * 1e9))
    t_ns = np.round(tt * 1e9).astype(np.int64)
    if dt_ns <= 0 or np.any(t_ns % dt_ns):
        raise InvalidInputError(
            f"Expected the grid's times to be whole multiples of Basilisk's task period "
            f"{h:g} s (its clock counts nanoseconds and the hub's state is read at the end "
            "of a task update)."
        )

    sim = sim_base.SimBaseClass()
    proc = sim.CreateNewProcess("proc")
    proc.addTask(sim.CreateNewTask("task", dt_ns))
    sc = spacecraft.Spacecraft()
    sc.ModelTag = "body"
    sc.hub.mHub = m
    sc.hub.r_BcB_B = [[0.0], [0.0], [0.0]]
    sc.hub.IHubPntBc_B = j.tolist()
    sc.hub.r_CN_NInit = [[0.0], [0.0], [0.0]]
    sc.hub.v_CN_NInit = [[0.0], [0.0], [0.0]]
    sc.hub.sigma_BNInit = [[float(x)] for x in quat_to_mrp(q)]
    sc.hub.omega_BN_BInit = [[float(x)] for x in w0]
    integ = getattr(sv, f"svIntegrator{integrator}")(sc)
    if integrator in ADAPTIVE and rtol is not None:
        integ.relTol = float(rtol)
        integ.absTol = float(rtol) * 1e-3
    sc.setIntegrator(integ)
    sim.AddModelToTask("task", sc)
    sim.InitializeSimulation()

    sigma = np.empty((tt.size, 3))
    omega = np.empty((tt.size, 3))
    for n, stop in enumerate(t_ns):
        if stop > 0:
            sim.ConfigureStopTime(int(stop))
            sim.ExecuteSimulation()
        msg = sc.scStateOutMsg.read()
        sigma[n] = np.asarray(msg.sigma_BN, dtype=float).ravel()
        omega[n] = np.asarray(msg.omega_BN_B, dtype=float).ravel()

    q_out = mrp_to_quat(sigma)
    q_out /= np.linalg.norm(q_out, axis=1, keepdims=True)
    flips = np.concatenate([[1.0], np.where(np.sum(q_out[1:] * q_out[:-1], -1) < 0, -1.0, 1.0)])
    return q_out * np.cumprod(flips)[:, None], omega, int(t_ns[-1] // dt_ns)
