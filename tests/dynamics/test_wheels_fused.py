"""Reaction wheels under constant motor torques in the compiled DOP853 (docs/theory.md
§10.1): ``simulate_wheels(..., command=<array>)`` runs Euler's equations of ``J_f`` under
``GyrostaticTorque(h0, rate=U)`` (torque kind 5, ``M_b = (h0 + U t) x w - U``) and
rebuilds the wheel speeds from the closed-form ``h_i(t) = h_i(t0) + u_i (t - t0)``.

Oracles: the Python path of ``simulate_wheels`` (the full state ``(q, w, Omega)`` in
SciPy's DOP853 at rtol 1e-12, with the same constant command as a callable); the balance
laws of the section (``K = R (J w + h)`` constant without external torque, the motors
being internal; ``T' = sum_i u_i Omega_i``, the motors' power, integrated by Simpson's
rule from the samples); kind 5 without a rate (``GyrostaticTorque(h)``), bit for bit.
Every tolerance is >= 10x the error observed (noted at each).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import cumulative_simpson

from poinsot import InvalidInputError, Rotation
from poinsot.dynamics import GyrostaticTorque, pyramid, simulate, simulate_wheels

BETA = np.arccos(1.0 / np.sqrt(3.0))
WHEELS = pyramid(BETA, 0.02, max_torque=0.05, max_speed=600.0)
TOL = {"rtol": 1e-12, "atol": 1e-14}


def _angle(r, s):
    """Rotation angle of ``r^-1 s`` (rad)."""
    return (r.inv() * s).magnitude()


def _bodies(n, seed=5):
    """``n`` heterogeneous bodies: tensors (some off-diagonal), attitudes, rates, wheel
    speeds and commands within the limits."""
    rng = np.random.default_rng(seed)
    moments = rng.uniform(8.0, 14.0, (n, 3))  # A + B >= C always
    turn = Rotation.from_rotvec(rng.normal(scale=0.3, size=(n, 3))).as_matrix()
    j = turn @ (moments[:, :, None] * np.eye(3)) @ np.swapaxes(turn, 1, 2)
    q0 = Rotation.from_rotvec(rng.normal(size=(n, 3))).as_quat()
    w0 = rng.normal(scale=0.05, size=(n, 3))
    om0 = rng.uniform(-100.0, 100.0, (n, 4))
    u = rng.uniform(-0.02, 0.02, (n, 4))
    return j, q0, w0, om0, u


def _constant(u):
    return lambda t, q, w, om: u


def test_one_body_equals_the_python_path():
    j, q0, w0, om0, u = (a[0] for a in _bodies(1))
    t = np.linspace(0.0, 120.0, 25)
    fast = simulate_wheels(j, WHEELS, q0, w0, om0, t, command=u, **TOL)
    slow = simulate_wheels(j, WHEELS, q0, w0, om0, t, command=_constant(u), **TOL)
    assert fast.info["solver"].startswith("DOP853 (compiled")
    assert slow.info["solver"] == "DOP853"
    assert fast.rotation.shape == (25,) and fast.wheel_speed.shape == (25, 4)
    # observed: 1.6e-12 rad, 2.5e-13 rad/s, 3.3e-13 rad/s (wheels), 6.9e-15 N m s,
    # 2.0e-13 J, 1.2e-12 N m s
    assert _angle(fast.rotation, slow.rotation).max() < 2e-11
    assert np.abs(fast.omega - slow.omega).max() < 3e-12
    assert np.abs(fast.wheel_speed - slow.wheel_speed).max() < 4e-12
    assert np.abs(fast.wheel_momentum - slow.wheel_momentum).max() < 1e-13
    assert np.abs(fast.energy - slow.energy).max() < 3e-12
    assert np.abs(fast.momentum - slow.momentum).max() < 2e-11
    np.testing.assert_array_equal(fast.motor_torque, slow.motor_torque)
    assert fast.info["conserved"] == slow.info["conserved"] == ("momentum",)


def test_command_is_clipped_and_t0_not_zero():
    j, q0, w0, om0, _ = (a[0] for a in _bodies(1, seed=8))
    u = np.array([0.2, -0.01, 0.0, -0.3])  # two beyond max_torque 0.05
    t = np.linspace(30.0, 90.0, 13)
    fast = simulate_wheels(j, WHEELS, q0, w0, om0, t, command=u, **TOL)
    slow = simulate_wheels(j, WHEELS, q0, w0, om0, t, command=_constant(u), **TOL)
    np.testing.assert_array_equal(fast.motor_torque[0], [0.05, -0.01, 0.0, -0.05])
    # observed: 6.9e-13 rad, 1.1e-13 rad/s (wheels)
    assert _angle(fast.rotation, slow.rotation).max() < 1e-11
    assert np.abs(fast.wheel_speed - slow.wheel_speed).max() < 1e-10


def test_heterogeneous_batch_equals_each_body_alone():
    n = 5
    j, q0, w0, om0, u = _bodies(n)
    t = np.linspace(0.0, 60.0, 13)
    tr = simulate_wheels(j, WHEELS, q0, w0, om0, t, command=u, **TOL)
    assert tr.rotation.shape == (13, n) and tr.omega.shape == (13, n, 3)
    assert tr.wheel_speed.shape == tr.motor_torque.shape == (13, n, 4)
    assert tr.wheel_momentum.shape == tr.momentum.shape == (13, n, 3)
    assert tr.energy.shape == (13, n)
    for b in range(n):
        one = simulate_wheels(j[b], WHEELS, q0[b], w0[b], om0[b], t, command=_constant(u[b]),
                              **TOL)  # fmt: skip
        # observed (worst body): 3.2e-12 rad, 3.3e-13 rad/s, 3.1e-13 rad/s (wheels),
        # 4.5e-13 J, 3.6e-12 N m s
        assert _angle(tr.rotation[:, b], one.rotation).max() < 4e-11
        assert np.abs(tr.omega[:, b] - one.omega).max() < 4e-12
        assert np.abs(tr.wheel_speed[:, b] - one.wheel_speed).max() < 4e-12
        assert np.abs(tr.energy[:, b] - one.energy).max() < 5e-12
        assert np.abs(tr.momentum[:, b] - one.momentum).max() < 4e-11


def test_batch_broadcasts_shared_arguments():
    j, q0, w0, om0, u = _bodies(3)
    t = np.linspace(0.0, 20.0, 5)
    tr = simulate_wheels(j[0], WHEELS, q0[0], w0, om0[0], t, command=u, **TOL)
    for b in range(3):
        one = simulate_wheels(j[0], WHEELS, q0[0], w0[b], om0[0], t, command=u[b], **TOL)
        # the batch's lanes against one body's loop: equal to rounding (observed 4e-17)
        np.testing.assert_allclose(tr.omega[:, b], one.omega, rtol=0, atol=1e-15)
        np.testing.assert_allclose(tr.wheel_speed[:, b], one.wheel_speed, rtol=0, atol=1e-12)
        np.testing.assert_array_equal(tr.motor_torque[:, b], one.motor_torque)


def test_momentum_is_constant_and_energy_changes_by_the_motor_work():
    j, q0, w0, om0, u = _bodies(4, seed=11)
    t = np.linspace(0.0, 100.0, 2001)
    tr = simulate_wheels(j, WHEELS, q0, w0, om0, t, command=u, **TOL)
    # K = R (J w + h): the motor torques are internal. observed 7.3e-12 N m s (|K| ~ 3)
    assert np.abs(tr.momentum - tr.momentum[0]).max() < 1e-10
    # T' = sum_i u_i Omega_i; Simpson on h = 0.05 s. observed 3.3e-11 J (|T - T0| up to
    # 340 J)
    power = np.sum(tr.motor_torque * tr.wheel_speed, axis=-1)
    work = cumulative_simpson(power, x=t, axis=0, initial=0.0)
    assert np.abs(tr.energy - tr.energy[0] - work).max() < 4e-10
    assert np.abs(tr.energy[-1] - tr.energy[0]).min() > 10.0  # the check has a content


def test_saturating_command_falls_back_for_one_body_and_raises_for_a_batch():
    wheels = pyramid(BETA, 0.02, max_torque=0.05, max_speed=150.0)
    j, q0, w0, om0, _ = (a[0] for a in _bodies(1))
    om0 = np.array([100.0, 0.0, 0.0, 0.0])
    u = np.array([0.05, 0.0, 0.0, 0.0])  # 2.5 rad/s^2: wheel 0 reaches 150 at ~20 s
    t = np.linspace(0.0, 60.0, 13)
    tr = simulate_wheels(j, wheels, q0, w0, om0, t, command=u, **TOL)
    slow = simulate_wheels(j, wheels, q0, w0, om0, t, command=_constant(u), **TOL)
    assert tr.info["solver"] == "DOP853"  # the Python path: the speed is held
    np.testing.assert_array_equal(tr.wheel_speed, slow.wheel_speed)
    assert np.abs(tr.wheel_speed[-1, 0]) <= 150.0 * (1 + 1e-8)
    with pytest.raises(InvalidInputError, match="`command`.*`max_speed`"):
        simulate_wheels(j, wheels, q0, w0, [om0, -om0], t, command=u, **TOL)


def test_batches_elsewhere_raise_naming_the_argument():
    j, q0, w0, om0, u = _bodies(2)
    t = np.linspace(0.0, 1.0, 3)
    rubbing = pyramid(BETA, 0.02, viscous=1e-5)
    with pytest.raises(InvalidInputError, match="`command` of shape \\(4,\\) .*batches run"):
        simulate_wheels(j[0], rubbing, q0[0], w0[0], om0[0], t, command=u)
    with pytest.raises(InvalidInputError, match="`command` of shape"):
        simulate_wheels(j[0], WHEELS, q0[0], w0[0], om0[0], t, command=u, method="rk4")
    with pytest.raises(InvalidInputError, match="`rotation0`.*batches run"):
        simulate_wheels(j[0], WHEELS, q0, w0[0], om0[0], t, command=_constant(u[0]))
    with pytest.raises(InvalidInputError, match="`command` to be callable or an array"):
        simulate_wheels(j[0], WHEELS, q0[0], w0[0], om0[0], t, command=[0.0, 0.0])
    # one body with friction takes the Python path with the constant command
    tr = simulate_wheels(j[0], rubbing, q0[0], w0[0], om0[0], t, command=u[0])
    assert tr.info["solver"] == "DOP853"


def test_rate_zero_is_kind5_bit_for_bit_and_the_formula():
    j, q0, w0, om0, _ = _bodies(9, seed=2)
    h = np.random.default_rng(0).normal(size=(9, 3))
    t = np.linspace(0.0, 10.0, 6)
    for sl in (slice(None), 0):  # the lanes and one body
        a = simulate(j[sl], q0[sl], w0[sl], t, torque=GyrostaticTorque(h[sl]), method="dop853")
        b = simulate(j[sl], q0[sl], w0[sl], t, torque=GyrostaticTorque(h[sl], rate=np.zeros(3)),
                     method="dop853")  # fmt: skip
        np.testing.assert_array_equal(a.quat, b.quat)
        np.testing.assert_array_equal(a.omega, b.omega)
        assert b.info["conserved"] == ("energy",)
    model = GyrostaticTorque([0.1, -0.2, 0.3], rate=[0.01, 0.02, -0.03])
    w = np.array([0.4, 0.5, -0.6])
    want = np.cross([0.1 + 0.05, -0.2 + 0.1, 0.3 - 0.15], w) - [0.01, 0.02, -0.03]
    np.testing.assert_allclose(model.body_torque(5.0, [1.0, 0, 0, 0], w), want, rtol=1e-15)
    np.testing.assert_allclose(model.momentum(5.0), [0.15, -0.1, 0.15], rtol=1e-15)
    with pytest.raises(InvalidInputError, match="`rate`"):
        GyrostaticTorque([0.0, 0.0, 1.0], rate=[1.0, 2.0])
