"""Peer cross-checks of :class:`poinsot.dynamics.Spacecraft` against Basilisk (issue 42).

The shared case: a rigid satellite, ``J = diag(80, 100, 40) kg m^2`` (Basilisk's hub
``IHubPntBc_B``, mass 750 kg, centre of mass at the body origin), on a circular
7000 km orbit at 51.6 deg inclination about a point-mass Earth with
``mu = 3.986004418e14 m^3/s^2`` in both codes. Basilisk integrates the orbit itself
(``spacecraft.Spacecraft`` + ``gravBodyFactory``'s Earth with ``mu`` overridden),
poinsot takes it from :class:`~poinsot.dynamics.KeplerOrbit` exactly; both start
from the same ``(r, v)``. Basilisk's translation and attitude are integrated by its
default fixed-step RK4 at the task rate ``dt``; poinsot's by DOP853 at
``rtol = 1e-12``, ``atol = 1e-14``, whose own error (< 1e-11 here) is far below
what is compared.

**Conventions.** Basilisk's ``sigma_BN`` are the MRPs of the DCM ``[BN]``
(inertial -> body components); poinsot's quaternion maps body -> inertial, so
``R_ib = [BN]^T = MRP2C(sigma_BN)^T`` and ``MRP2EP(sigma_BN) = +-q``
(:func:`test_mrp_convention_on_the_initial_state`). Both give ``omega_BN_B`` in
body axes. Basilisk's ``hillPoint`` frame is poinsot's ``"rtn"`` frame.

**What Basilisk's step allows.**

* Free gravity gradient (no control): the difference is Basilisk's RK4 error and
  shrinks 16x per halving of ``dt`` (measured 1.07e-6, 6.35e-8, 3.86e-9, 5.7e-12 in
  the attitude matrix over a quarter orbit at ``dt = 2, 1, 0.5, 0.1 s``, a 0.034
  rad/s tumble).
* MRP feedback (``mrpFeedback``, ``controlLawType = 1``, ``Ki = -1``): Basilisk's
  flight software holds the torque over each task period (zero-order hold), which
  poinsot's continuous law does not; the difference is first order in ``dt`` and
  halves exactly with it (ratio 2.00); Richardson extrapolation of the two Basilisk
  runs removes the hold's first-order term and agrees with poinsot to second order.

* Reaction wheels (``reactionWheelStateEffector`` + ``rwMotorTorque`` fed by
  ``mrpFeedback`` with the wheel speeds): the same hold, and the same Richardson
  check against poinsot's :func:`~poinsot.dynamics.simulate_wheels` driven by
  Basilisk's wheel law. poinsot's own :meth:`MRPFeedback.wheel_command` differs from
  that law by design (it also cancels the wheels' reaction to the body's
  acceleration, ``J_a w_d'``, so the body feels ``L`` exactly), an O(``I_w / J``)
  difference that is measured and bounded, not hidden.
"""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("Basilisk")

from Basilisk.architecture import messaging  # noqa: E402
from Basilisk.fswAlgorithms import (  # noqa: E402
    attTrackingError,
    hillPoint,
    mrpFeedback,
    rwMotorTorque,
)
from Basilisk.simulation import (  # noqa: E402
    GravityGradientEffector,
    extForceTorque,
    reactionWheelStateEffector,
    simpleNav,
    spacecraft,
)
from Basilisk.utilities import RigidBodyKinematics as rbk  # noqa: E402
from Basilisk.utilities import (  # noqa: E402
    SimulationBaseClass,
    macros,
    simIncludeGravBody,
    simIncludeRW,
)

from poinsot import Rotation  # noqa: E402
from poinsot.dynamics import (  # noqa: E402
    KeplerOrbit,
    MRPFeedback,
    ReactionWheels,
    Spacecraft,
    simulate_wheels,
)

MU = 3.986004418e14
INERTIA = np.diag([80.0, 100.0, 40.0])
ORBIT = KeplerOrbit(7.0e6, 0.0, np.radians(51.6), 0.3, 0.0, 0.2, mu=MU)
SAMPLE = 10.0  # s between recorded samples
RTOL, ATOL = 1e-12, 1e-14


def _bsk_run(dt, t_end, q0, w0, feedback=None, wheels=None):
    """Run Basilisk at the task rate ``dt`` (s) from body -> inertial ``q0`` and body
    ``w0``; with ``feedback = (K, P)`` an MRP feedback to the Hill frame acts as an
    external torque. Everything runs in one task, flight software first, so the
    torque computed from the state at ``t_k`` acts over ``[t_k, t_k + dt]``. With
    ``wheels = (I_w, Omega0)`` three wheels on the body axes (axial inertia ``I_w``,
    initial speeds ``Omega0`` rad/s, no friction, no limits) carry out the torque.

    Returns the sample times, ``R_ib`` (n, 3, 3), ``omega_BN_B`` (n, 3), with
    feedback ``sigma_BR`` (n, 3) and with wheels their speeds (n, 3)."""
    r0, v0 = ORBIT.state(0.0)
    sim = SimulationBaseClass.SimBaseClass()
    proc = sim.CreateNewProcess("proc")
    proc.addTask(sim.CreateNewTask("task", macros.sec2nano(dt)))

    sc = spacecraft.Spacecraft()
    sc.ModelTag = "sat"
    sc.hub.mHub = 750.0
    sc.hub.IHubPntBc_B = INERTIA.tolist()
    sc.hub.r_CN_NInit = r0.tolist()
    sc.hub.v_CN_NInit = v0.tolist()
    sc.hub.sigma_BNInit = rbk.C2MRP(Rotation.from_quat(q0).as_matrix().T).tolist()
    sc.hub.omega_BN_BInit = np.asarray(w0, dtype=float).tolist()

    grav = simIncludeGravBody.gravBodyFactory()
    earth = grav.createEarth()
    earth.isCentralBody = True
    earth.mu = MU
    grav.addBodiesTo(sc)

    gg = GravityGradientEffector.GravityGradientEffector()
    gg.ModelTag = "gg"
    gg.addPlanetName(earth.planetName)
    sc.addDynamicEffector(gg)

    models = [gg, sc]
    err = None
    if feedback is not None:
        k, p = feedback
        ext = extForceTorque.ExtForceTorque()
        ext.ModelTag = "ext"
        sc.addDynamicEffector(ext)
        nav = simpleNav.SimpleNav()
        nav.ModelTag = "nav"
        nav.scStateInMsg.subscribeTo(sc.scStateOutMsg)
        hill = hillPoint.hillPoint()
        hill.ModelTag = "hill"
        hill.transNavInMsg.subscribeTo(nav.transOutMsg)
        err = attTrackingError.attTrackingError()
        err.ModelTag = "err"
        err.attRefInMsg.subscribeTo(hill.attRefOutMsg)
        err.attNavInMsg.subscribeTo(nav.attOutMsg)
        config = messaging.VehicleConfigMsgPayload()
        config.ISCPntB_B = INERTIA.flatten().tolist()
        config_msg = messaging.VehicleConfigMsg().write(config)
        ctl = mrpFeedback.mrpFeedback()
        ctl.ModelTag = "mrp"
        ctl.guidInMsg.subscribeTo(err.attGuidOutMsg)
        ctl.vehConfigInMsg.subscribeTo(config_msg)
        ctl.K, ctl.P = k, p
        ctl.Ki = -1.0  # no integral feedback
        ctl.integralLimit = 0.0
        ctl.controlLawType = 1  # the gyroscopic term w x J w, as MRPFeedback
        models = [nav, hill, err, ctl, *models]
        if wheels is None:
            ext.cmdTorqueInMsg.subscribeTo(ctl.cmdTorqueOutMsg)
            models.insert(4, ext)
        else:
            i_w, speed0 = wheels
            factory = simIncludeRW.rwFactory()
            for axis, speed in zip(np.eye(3), speed0, strict=True):
                factory.create(
                    "custom", axis.tolist(), Js=float(i_w), Omega=float(speed / macros.RPM),
                    useRWfriction=False, useMaxTorque=False, useMinTorque=False,
                    rWB_B=[0.0, 0.0, 0.0],
                )  # fmt: skip
            rw = reactionWheelStateEffector.ReactionWheelStateEffector()
            rw.ModelTag = "rw"
            factory.addToSpacecraft("rw", rw, sc)
            rw_params = factory.getConfigMessage()
            ctl.rwParamsInMsg.subscribeTo(rw_params)
            ctl.rwSpeedsInMsg.subscribeTo(rw.rwSpeedOutMsg)
            motors = rwMotorTorque.rwMotorTorque()
            motors.ModelTag = "motors"
            motors.controlAxes_B = [1, 0, 0, 0, 1, 0, 0, 0, 1]
            motors.vehControlInMsg.subscribeTo(ctl.cmdTorqueOutMsg)
            motors.rwParamsInMsg.subscribeTo(rw_params)
            rw.rwMotorCmdInMsg.subscribeTo(motors.rwMotorTorqueOutMsg)
            models.insert(4, motors)
            models.insert(5, rw)
    for m in models:
        sim.AddModelToTask("task", m)
    state = sc.scStateOutMsg.recorder(macros.sec2nano(SAMPLE))
    sim.AddModelToTask("task", state)
    if err is not None:
        guid = err.attGuidOutMsg.recorder(macros.sec2nano(SAMPLE))
        sim.AddModelToTask("task", guid)
    if wheels is not None:
        speeds = rw.rwSpeedOutMsg.recorder(macros.sec2nano(SAMPLE))
        sim.AddModelToTask("task", speeds)

    sim.InitializeSimulation()
    sim.ConfigureStopTime(macros.sec2nano(t_end))
    sim.ExecuteSimulation()

    t = state.times() * 1e-9
    r_ib = np.array([rbk.MRP2C(s).T for s in np.array(state.sigma_BN)])
    out = (t, r_ib, np.array(state.omega_BN_B))
    if err is not None:
        np.testing.assert_allclose(guid.times() * 1e-9, t)
        out += (np.array(guid.sigma_BR),)
    if wheels is not None:
        out += (np.array(speeds.wheelSpeeds)[:, :3],)
    return out


def _mrp(rotation):
    """MRPs with ``|sigma| <= 1`` of a Rotation (array), as Basilisk's ``sigma_BR``."""
    s = np.atleast_2d(rotation.as_mrp())
    n2 = np.sum(s * s, axis=1, keepdims=True)
    return np.where(n2 > 1.0, -s / n2, s)


def _offset_start(sat, rotvec, rate):
    q0 = (sat.orbit_attitude(0.0) * Rotation.from_rotvec(rotvec)).as_quat()
    return q0, sat.orbit_rate(q0, 0.0) + np.asarray(rate)


def test_mrp_convention_on_the_initial_state():
    """Basilisk's ``sigma_BN`` gives ``[BN] = R_ib^T`` and its Euler parameters are
    poinsot's quaternion up to sign; the initial state comes back unchanged."""
    sat = Spacecraft(INERTIA, ORBIT)
    q0, w0 = _offset_start(sat, [0.1, -0.2, 0.15], [0.02, -0.01, 0.03])
    sigma = rbk.C2MRP(Rotation.from_quat(q0).as_matrix().T)
    beta = rbk.MRP2EP(sigma)
    assert min(np.abs(beta - q0).max(), np.abs(beta + q0).max()) < 1e-14
    # and independently of the DCM route: poinsot's own MRPs (of body -> inertial)
    # are Basilisk's sigma_BN, up to the shadow set
    np.testing.assert_allclose(_mrp(Rotation.from_quat(q0))[0], sigma, atol=1e-14)

    t, r_ib, w = _bsk_run(1.0, 0.0, q0, w0)
    assert t[0] == 0.0
    np.testing.assert_allclose(r_ib[0], Rotation.from_quat(q0).as_matrix(), atol=1e-15)
    np.testing.assert_allclose(w[0], w0, rtol=0, atol=1e-18)


def test_gravity_gradient_free_motion():
    """Gravity gradient only, started 0.27 rad off LVLH with a 0.034 rad/s tumble,
    over a quarter orbit (1458 s).

    Measured (max over the samples, attitude-matrix entries / omega in rad/s):
    ``dt = 1 s``: 6.35e-8 / 4.8e-10, ``dt = 0.5 s``: 3.86e-9 / 3.0e-11 -- a ratio
    of 16.5, RK4's fourth order: the agreement is what Basilisk's step allows
    (5.7e-12 at ``dt = 0.1 s``, also run once). Tolerances 10x above."""
    sat = Spacecraft(INERTIA, ORBIT)
    q0, w0 = _offset_start(sat, [0.1, -0.2, 0.15], [0.02, -0.01, 0.03])
    t_end = ORBIT.period / 4
    errors = []
    for dt in (1.0, 0.5):
        t, r_ib, w = _bsk_run(dt, t_end, q0, w0)
        tr = sat.simulate(q0, w0, t, rtol=RTOL, atol=ATOL)
        errors.append((np.abs(r_ib - tr.rotation.as_matrix()).max(), np.abs(w - tr.omega).max()))
    (att1, w1), (att2, w2) = errors
    assert att2 < 4e-8 and w2 < 3e-10
    assert 12.0 < att1 / att2 < 21.0
    assert 12.0 < w1 / w2 < 21.0


def test_mrp_feedback_to_the_hill_frame():
    """MRP feedback (``K = 2 N m``, ``P = 15 N m s``, no integral term) to the Hill
    (``"rtn"``) frame with the gravity gradient on, from 64 deg off and a
    0.027 rad/s rate, over 600 s (the error falls to 1e-8 deg).

    Basilisk: ``simpleNav`` -> ``hillPoint`` -> ``attTrackingError`` ->
    ``mrpFeedback`` -> ``extForceTorque`` at the dynamics rate; poinsot:
    :class:`~poinsot.dynamics.MRPFeedback` with ``target=sat.orbit_reference()``.
    Measured (max over the samples): ``dt = 0.1 s``: 1.85e-3 in the attitude matrix,
    1.09e-4 rad/s in omega, 1.74e-4 in ``sigma_BR``; ``dt = 0.05 s``: 9.24e-4,
    5.4e-5, 8.7e-5 -- the ratio is 2.00: the zero-order hold of the torque limits the
    agreement, not the laws. The Richardson combination ``2 X(0.05) - X(0.1)`` of
    Basilisk's runs agrees with poinsot to 1.8e-6 / 4.2e-7 rad/s / 4.5e-7.
    Tolerances 10x above."""
    ref = Spacecraft(INERTIA, ORBIT, frame="rtn")
    law = MRPFeedback(2.0, 15.0, INERTIA, target=ref.orbit_reference())
    sat = Spacecraft(INERTIA, ORBIT, frame="rtn", control=law)
    q0 = (sat.orbit_attitude(0.0) * Rotation.from_rotvec([0.5, -0.8, 0.6])).as_quat()
    w0 = np.array([0.01, -0.02, 0.015])
    t_end = 600.0

    runs = [_bsk_run(dt, t_end, q0, w0, feedback=(2.0, 15.0)) for dt in (0.1, 0.05)]
    t = runs[0][0]
    np.testing.assert_allclose(runs[1][0], t)
    tr = sat.simulate(q0, w0, t, rtol=RTOL, atol=ATOL)
    q_r = Rotation.from_quat(np.array([law.target(tt)[0] for tt in t]))
    sigma_br = _mrp(q_r.inv() * tr.rotation)
    mine = (tr.rotation.as_matrix(), tr.omega, sigma_br)
    assert np.degrees(4 * np.arctan(np.linalg.norm(sigma_br[-1]))) < 1e-6

    def diff(x):
        return [float(np.abs(a - b).max()) for a, b in zip(x, mine, strict=True)]

    coarse, fine = diff(runs[0][1:]), diff(runs[1][1:])
    richardson = diff([2 * f - c for f, c in zip(runs[1][1:], runs[0][1:], strict=True)])
    assert fine[0] < 1e-2 and fine[1] < 6e-4 and fine[2] < 1e-3
    for c, f in zip(coarse, fine, strict=True):
        assert 1.8 < c / f < 2.2
    assert richardson[0] < 2e-5 and richardson[1] < 5e-6 and richardson[2] < 5e-6


def test_mrp_feedback_through_reaction_wheels():
    """The Hill-frame case of :func:`test_mrp_feedback_to_the_hill_frame` carried out by
    three reaction wheels on the body axes (axial inertia 0.05 kg m^2, starting at
    (100, -50, 20) rad/s).

    Basilisk: ``mrpFeedback`` (with the wheel speeds, so its gyroscopic term is
    ``w x (J w + G h_s)``, ``h_s`` the wheels' absolute momenta) -> ``rwMotorTorque``
    -> ``reactionWheelStateEffector`` (balanced wheels), hub inertia ``J``: the
    inertia with the wheels locked, as poinsot's ``inertia`` (measured: taking
    ``J - 2 I_w 1`` for the hub, i.e. counting the wheels' ``Js`` and ``Jt = Js / 2``
    apart, leaves an O(``I_w / J``) difference, 1e-4, that Richardson does not remove).

    poinsot: :func:`~poinsot.dynamics.simulate_wheels` under the same wheel law,
    ``u = -(L + w x h_s)`` with ``L`` from :class:`~poinsot.dynamics.MRPFeedback`.
    Measured: Basilisk vs poinsot at ``dt = 0.1`` / 0.05 s: 2.0e-3 / 1.0e-3 in the
    attitude matrix (ratio ~2, the hold); the Richardson combination: 2.2e-6 in the
    attitude matrix, 3.4e-7 rad/s in omega, 5.2e-4 rad/s in the wheel speeds
    (~100 rad/s). poinsot's ``Spacecraft(..., wheels=...)`` with
    :meth:`MRPFeedback.wheel_command` (which also cancels ``J_a w_d'``) differs from
    Basilisk's law by 1.1e-4 in the attitude matrix and 1.1e-2 rad/s in the wheel
    speeds. Tolerances 10x above."""
    i_w, speed0 = 0.05, np.array([100.0, -50.0, 20.0])
    ref = Spacecraft(INERTIA, ORBIT, frame="rtn")
    law = MRPFeedback(2.0, 15.0, INERTIA, target=ref.orbit_reference())
    rw = ReactionWheels(np.eye(3), i_w)
    sat = Spacecraft(INERTIA, ORBIT, frame="rtn", control=law, wheels=rw)
    q0 = (sat.orbit_attitude(0.0) * Rotation.from_rotvec([0.5, -0.8, 0.6])).as_quat()
    w0 = np.array([0.01, -0.02, 0.015])
    t_end = 600.0

    runs = [
        _bsk_run(dt, t_end, q0, w0, feedback=(2.0, 15.0), wheels=(i_w, speed0))
        for dt in (0.1, 0.05)
    ]
    t = runs[0][0]

    def basilisk_wheel_law(tt, q, w, speed):
        return -(law.body_torque(tt, q, w) + np.cross(w, i_w * (w + speed)))

    same_law = simulate_wheels(
        INERTIA, rw, q0, w0, speed0, t, command=basilisk_wheel_law,
        torque=sat.environment(), rtol=RTOL, atol=ATOL,
    )  # fmt: skip
    own_law = sat.simulate(q0, w0, t, wheel_speed0=speed0, rtol=RTOL, atol=ATOL)

    def states(x):
        return (x.rotation.as_matrix(), x.omega, x.wheel_speed)

    def diff(x, y):
        return [float(np.abs(a - b).max()) for a, b in zip(x, y, strict=True)]

    coarse = diff((runs[0][1], runs[0][2], runs[0][4]), states(same_law))
    fine = diff((runs[1][1], runs[1][2], runs[1][4]), states(same_law))
    richardson = [2 * runs[1][k] - runs[0][k] for k in (1, 2, 4)]
    assert fine[0] < 1e-2 and fine[1] < 6e-4
    assert 1.6 < coarse[0] / fine[0] < 2.4 and 1.6 < coarse[1] / fine[1] < 2.4
    gap = diff(richardson, states(same_law))
    assert gap[0] < 2.5e-5 and gap[1] < 4e-6 and gap[2] < 6e-3
    own = diff(richardson, states(own_law))
    assert own[0] < 1.5e-3 and own[1] < 1e-4 and own[2] < 0.15
