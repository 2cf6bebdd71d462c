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

**A gyrostat** (``rotor_momentum`` given, docs/theory.md §10.1): one reaction wheel,
Basilisk's ``reactionWheelStateEffector`` built by ``simIncludeRW.rwFactory``
(``"custom"``, ``RWModel = BalancedWheels``, no friction, no torque limit, motor
torque ``u_s = 0``: no command message) on the spin axis ``gsHat_B = a = h / |h|`` at
the centre of mass. Basilisk's balanced wheel (``reactionWheelStateEffector.cpp``, bsk
2.12.1): the wheel adds **no mass properties** to the spacecraft (its ``mass``, ``Jt``
and ``Jg`` are not used: ``updateEffectorMassProps`` adds nothing for
``BalancedWheels``; cf. AVSLab/basilisk#600, later versions add them behind
``includeWheelMassProperties``, off by default), so ``IHubPntBc_B`` must hold the
wheel's spin inertia ``Js``; the wheel's state ``Omega`` is its speed **relative to
the hub** about ``gsHat_B``, with ``Omega' = u_s / Js - gsHat . w'`` (here ``u_s = 0``)
and the hub's back-substitution ``[I_hub - Js g g^T] w' = -w x (I_hub w + Js Omega g)``.
So ``h_s = Js (g . w + Omega)`` is constant and, with ``J' = I_hub - Js g g^T``,
``J' w' + w x (J' w + h_s g) = 0``: the free rotor of
:func:`poinsot.verify._mujoco.rotor_inputs` with ``I_r = Js``. The case's ``(J, h)``
is reproduced exactly by ``I_hub = J_L = J + Js a a^T`` (the locked inertia) and
``Omega(0) = |h| / Js - a . w(0)``, both from :func:`poinsot.verify._mujoco.rotor_axis`
(``I_r = Js`` = :data:`~poinsot.verify._mujoco.ROTOR_AXIAL`), the hub's mass the
case's. Checked: Basilisk's own total angular momentum
at ``t = 0`` (``computeEnergyMomentum``, ``totRotAngMomPntC_N``) is the case's
``R (J w + h)``, and the hub given ``J`` alone (the wheel's inertia left out) fails
(tests/verify/test_engine_basilisk.py).

**A constant body torque** (``torque`` given, N m, body axes): an ``extForceTorque``
dynamic effector with ``extTorquePntB_B`` set once (constant in body axes, evaluated
by the spacecraft at every stage of its integrator).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import InvalidInputError, PoinsotError
from ._mujoco import ROTOR_AXIAL, _vec, body_inputs, rotor_axis

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


def build_basilisk(*, inertia: Any, mass: float, q0: Any, omega0: Any, integrator: str = "RK4",
                   timestep: float = 1e-3, rtol: float | None = None,
                   rotor_momentum: Any = None, torque: Any = None,
                   ) -> tuple[Any, Any, list[Any]]:  # fmt: skip
    """The Basilisk ``(simulation, spacecraft, effectors)`` of :func:`run_basilisk` at
    ``t = 0``, initialized (``InitializeSimulation``); the arguments as there (the module
    docstring for the wheel's mapping). ``effectors`` holds the effectors added (keep it
    alive while the simulation runs).

    >>> sim, sc, eff = build_basilisk(inertia=np.diag([1.0, 2.0, 3.0]), mass=1.0,
    ...                               q0=[1.0, 0.0, 0.0, 0.0], omega0=[0.1, 1.0, 0.1],
    ...                               rotor_momentum=[0.0, 3.0, 0.0])
    >>> sc.computeEnergyMomentum(0.0)
    >>> np.ravel(sc.totRotAngMomPntC_N).round(12).tolist(), eff[0].ReactionWheelData[0].Omega
    ([0.1, 5.0, 0.3], 11.0)
    """
    spacecraft, sv, sim_base, _ = _basilisk()
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
    wheel = None
    if rotor_momentum is not None:  # the hub holds the wheel's spin inertia: J_L
        j, a, rate0 = rotor_axis(j, rotor_momentum, w0, ROTOR_AXIAL)
        wheel = (a, rate0)
    m_b = None if torque is None else _vec(torque, 3, "torque")

    sim = sim_base.SimBaseClass()
    proc = sim.CreateNewProcess("proc")
    proc.addTask(sim.CreateNewTask("task", int(round(h * 1e9))))
    sc = spacecraft.Spacecraft()
    sc.ModelTag = "body"
    sc.hub.mHub = m
    sc.hub.r_BcB_B = [[0.0], [0.0], [0.0]]
    sc.hub.IHubPntBc_B = j.tolist()
    sc.hub.r_CN_NInit = [[0.0], [0.0], [0.0]]
    sc.hub.v_CN_NInit = [[0.0], [0.0], [0.0]]
    sc.hub.sigma_BNInit = [[float(x)] for x in quat_to_mrp(q)]
    sc.hub.omega_BN_BInit = [[float(x)] for x in w0]
    effectors: list[Any] = []
    if wheel is not None:
        from Basilisk.architecture import messaging
        from Basilisk.simulation import reactionWheelStateEffector
        from Basilisk.utilities import simIncludeRW

        factory = simIncludeRW.rwFactory()
        rw = factory.create("custom", [float(x) for x in wheel[0]], Js=float(ROTOR_AXIAL),
                            RWModel=messaging.BalancedWheels, useRWfriction=False,
                            useMaxTorque=False, rWB_B=[0.0, 0.0, 0.0])  # fmt: skip
        rw.Omega = float(wheel[1])  # rad/s, relative to the hub (create takes rpm)
        rw_effector = reactionWheelStateEffector.ReactionWheelStateEffector()
        factory.addToSpacecraft("wheel", rw_effector, sc)
        effectors.append(rw_effector)
    if m_b is not None:
        from Basilisk.simulation import extForceTorque

        ext = extForceTorque.ExtForceTorque()
        ext.ModelTag = "torque"
        ext.extTorquePntB_B = [[float(x)] for x in m_b]
        sc.addDynamicEffector(ext)
        effectors.append(ext)
    integ = getattr(sv, f"svIntegrator{integrator}")(sc)
    if integrator in ADAPTIVE and rtol is not None:
        integ.relTol = float(rtol)
        integ.absTol = float(rtol) * 1e-3
    sc.setIntegrator(integ)
    sim.AddModelToTask("task", sc)
    for e in effectors:
        sim.AddModelToTask("task", e)
    effectors.append(integ)  # kept alive with the effectors
    sim.InitializeSimulation()
    return sim, sc, effectors


def run_basilisk(*, inertia: Any, mass: float, q0: Any, omega0: Any, t: Any,
                 integrator: str = "RK4", timestep: float = 1e-3,
                 rtol: float | None = None, rotor_momentum: Any = None,
                 torque: Any = None) -> tuple[np.ndarray, np.ndarray, int]:  # fmt: skip
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
    rotor_momentum : array_like (3,), optional
        A gyrostat's constant rotor momentum ``h`` relative to the body (kg m^2/s, body
        axes; docs/theory.md §10.1): a balanced reaction wheel with no motor torque
        (the module docstring), ``inertia`` the gyrostat's ``J``.
    torque : array_like (3,), optional
        A constant external torque in body axes (N m): an ``extForceTorque`` effector.

    Returns
    -------
    q : ndarray (n, 4)
        Scalar-first unit quaternions body -> inertial, sign-continuous (the hub's).
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

    A gyrostat spinning steadily about its wheel's axis keeps its angular velocity:

    >>> q, w, n = run_basilisk(inertia=np.diag([1.0, 2.0, 3.0]), mass=1.0,
    ...                        q0=[1.0, 0.0, 0.0, 0.0], omega0=[0.0, 1.0, 0.0],
    ...                        t=np.linspace(0.0, 1.0, 11), timestep=0.01,
    ...                        rotor_momentum=[0.0, 3.0, 0.0])
    >>> w[-1].round(12).tolist()
    [0.0, 1.0, 0.0]
    """
    tt = np.asarray(t, dtype=float)
    if tt.ndim != 1 or tt.size < 1 or tt[0] != 0.0 or np.any(np.diff(tt) <= 0):
        raise InvalidInputError("Expected `t` to be increasing times starting at 0 (s).")
    h = float(timestep)
    dt_ns = int(round(h * 1e9)) if math.isfinite(h) and h > 0 else 0
    t_ns = np.round(tt * 1e9).astype(np.int64)
    sim, sc, effectors = build_basilisk(inertia=inertia, mass=mass, q0=q0, omega0=omega0,
                                        integrator=integrator, timestep=timestep, rtol=rtol,
                                        rotor_momentum=rotor_momentum,
                                        torque=torque)  # fmt: skip
    if dt_ns <= 0 or np.any(t_ns % dt_ns):
        raise InvalidInputError(
            f"Expected the grid's times to be whole multiples of Basilisk's task period "
            f"{h:g} s (its clock counts nanoseconds and the hub's state is read at the end "
            "of a task update)."
        )

    sigma = np.empty((tt.size, 3))
    omega = np.empty((tt.size, 3))
    for n, stop in enumerate(t_ns):
        if stop > 0:
            sim.ConfigureStopTime(int(stop))
            sim.ExecuteSimulation()
        msg = sc.scStateOutMsg.read()
        sigma[n] = np.asarray(msg.sigma_BN, dtype=float).ravel()
        omega[n] = np.asarray(msg.omega_BN_B, dtype=float).ravel()
    del effectors

    q_out = mrp_to_quat(sigma)
    q_out /= np.linalg.norm(q_out, axis=1, keepdims=True)
    flips = np.concatenate([[1.0], np.where(np.sum(q_out[1:] * q_out[:-1], -1) < 0, -1.0, 1.0)])
    return q_out * np.cumprod(flips)[:, None], omega, int(t_ns[-1] // dt_ns)
