"""Tests of the heavy rigid body about a fixed point (Euler-Poisson, docs/theory.md §10).

Oracles: the Poisson equation ``gamma' = gamma x w`` checked against finite
differences of ``R^T e_z`` along the quaternion kinematics; the conservation of
``E``, ``K . e_z`` and ``|gamma|``; the exact Lagrange top
(:class:`~poinsot.dynamics.LagrangeTop`, itself checked against SciPy in
``test_lagrange_top.py``) for the splitting's order; ``solve_ivp(DOP853)`` for an
asymmetric body. Tolerances >= 10x the errors observed.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from poinsot import InvalidInputError, InvalidTypeError, Rotation
from poinsot.dynamics import GravityTorque, HeavyRigidBody, LagrangeTop

J_ASYM = [[1.2, 0.1, -0.05], [0.1, 1.6, 0.02], [-0.05, 0.02, 2.1]]
COM = [0.05, -0.02, 0.3]


def _gamma_fd(q, w, h=1e-6):
    """d/dt (R^T e_z) by central differences of the attitude moved by exp(h w / 2)."""
    r = Rotation.from_quat(q)
    step = Rotation.from_rotvec(h * np.asarray(w))
    up = (r * step).apply([0.0, 0.0, 1.0], inverse=True)
    dn = (r * step.inv()).apply([0.0, 0.0, 1.0], inverse=True)
    return (up - dn) / (2 * h)


def test_euler_poisson_rhs():
    body = HeavyRigidBody(J_ASYM, 2.0, COM, g=9.81)
    rng = np.random.default_rng(3)
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    w = rng.normal(size=3)
    gamma = body.gamma(q)
    assert np.allclose(gamma, Rotation.from_quat(q).apply([0, 0, 1.0], inverse=True), atol=1e-15)
    dw, dgamma = body.euler_poisson(w, gamma)
    # Poisson: gamma' = gamma x w, against finite differences of the attitude
    assert np.allclose(dgamma, _gamma_fd(q, w), atol=1e-8)
    # Euler: J w' + w x J w = m g gamma x c
    j = np.asarray(J_ASYM)
    lhs = j @ dw + np.cross(w, j @ w)
    assert np.allclose(lhs, 2.0 * 9.81 * np.cross(gamma, COM), atol=1e-13)
    # the quaternion form agrees, and the torque is the GravityTorque model's
    y = body.rhs(0.0, np.concatenate([q, w]))
    assert np.allclose(y[4:], dw, atol=1e-14)
    m = GravityTorque(2.0, COM, g=9.81).body_torque(0.0, q, w)
    assert np.allclose(np.cross(gamma, body.moment), m, atol=1e-14)
    # batches broadcast
    ys = body.rhs(0.0, np.tile(np.concatenate([q, w]), (4, 2, 1)))
    assert ys.shape == (4, 2, 7) and np.allclose(ys[3, 1], y)


def test_splitting_keeps_the_casimirs_to_round_off_and_the_energy_bounded():
    body = HeavyRigidBody(J_ASYM, 2.0, COM, g=9.81)
    q0 = Rotation.from_euler("ZXZ", [0.3, 0.8, -0.2]).as_quat()
    w0 = [1.0, -2.0, 6.0]
    t = np.linspace(0.0, 40.0, 401)
    tr = body.simulate(q0, w0, t, max_step=4e-3)  # 10^4 steps
    kz = body.momentum_z(tr.rotation, tr.omega)
    e = body.energy(tr.rotation, tr.omega)
    gam = body.gamma(tr.rotation)
    scale = np.linalg.norm(np.asarray(J_ASYM) @ w0)
    assert np.abs(kz - kz[0]).max() < 1e-13 * scale  # observed ~2e-15
    assert np.abs(np.linalg.norm(gam, axis=-1) - 1.0).max() < 1e-15
    de = np.abs(e - e[0]) / abs(e[0])
    # second order: bounded, no drift (the second half no worse than the first)
    assert de.max() < 1e-4
    assert de[200:].max() < 3 * de[:200].max()


def test_splitting_orders_on_the_exact_lagrange_top():
    a, c, mgl = 2.0, 1.0, 4.0
    top = LagrangeTop(a, c, mgl, theta=0.5, spin=20.0, precession_rate=0.3, theta_rate=0.2)
    body = HeavyRigidBody([a, a, c], 1.0, [0.0, 0.0, mgl / 9.80665])
    t = np.linspace(0.0, 2.0, 5)
    w_ex = top.omega(t)
    errs = {}
    for order in (2, 4):
        for h in (4e-3, 2e-3):
            tr = body.simulate(top.rotation(0.0), top.omega(0.0), t, order=order, max_step=h)
            errs[order, h] = np.abs(tr.omega - w_ex).max()
    assert 3.6 < errs[2, 4e-3] / errs[2, 2e-3] < 4.4
    assert 13.0 < errs[4, 4e-3] / errs[4, 2e-3] < 19.0
    assert errs[4, 2e-3] < 1e-7


def test_other_methods_and_batches_agree_with_dop853():
    body = HeavyRigidBody(J_ASYM, 2.0, COM, g=9.81)
    q0 = np.array([Rotation.from_euler("ZXZ", [0.3, a, -0.2]).as_quat() for a in (0.4, 1.1, 2.0)])
    w0 = np.array([[1.0, -2.0, 6.0], [0.0, 0.5, 3.0], [2.0, 0.0, -1.0]])
    t = np.linspace(0.0, 1.0, 3)
    j = np.asarray(J_ASYM)
    ji = np.linalg.inv(j)

    def f(_, y):
        q, w = y[:4], y[4:]
        g = (
            2.0
            * np.array(  # third row of R(q)
                [q[1] * q[3] - q[0] * q[2], q[2] * q[3] + q[0] * q[1], 0.5 - q[1] ** 2 - q[2] ** 2]
            )
            / (q @ q)
        )
        dw = ji @ (2.0 * 9.81 * np.cross(g, COM) - np.cross(w, j @ w))
        wq = np.array([0.0, *w])
        dq = 0.5 * np.array(
            [
                -q[1:] @ wq[1:],
                *(q[0] * wq[1:] + np.cross(q[1:], wq[1:])),
            ]
        )
        return np.concatenate([dq, dw])

    ref = []
    for i in range(3):
        s = solve_ivp(
            f, (0, 1), np.concatenate([q0[i], w0[i]]), "DOP853", t_eval=t, rtol=1e-12, atol=1e-12
        )
        ref.append(s.y.T[:, 4:])
    ref = np.stack(ref, axis=1)  # (n, 3, 3)
    for method, kw, tol in (
        ("splitting", dict(order=4, max_step=2e-3), 1e-8),
        ("midpoint", dict(order=4, max_step=2.5e-3), 1e-7),
        ("rk4", dict(max_step=5e-3), 1e-8),
        ("dop853", dict(rtol=1e-12, atol=1e-12), 1e-9),
        ("adaptive", dict(rtol=1e-12, atol=1e-12), 1e-9),
    ):
        tr = body.simulate(q0, w0, t, method=method, **kw)
        assert tr.omega.shape == (3, 3, 3)
        assert np.abs(tr.omega - ref).max() < tol, method
    # one body of the batch alone gives the same numbers
    one = body.simulate(q0[1], w0[1], t, max_step=2e-3)
    many = body.simulate(q0, w0, t, max_step=2e-3)
    assert np.array_equal(one.omega, many.omega[:, 1])


def test_invariants_and_repr():
    body = HeavyRigidBody([2.0, 2.0, 1.0], 1.0, [0.0, 0.0, 0.5], g=10.0)
    q = Rotation.from_euler("x", 60, degrees=True)
    assert math.isclose(float(body.energy(q, [0.0, 0.0, 2.0])), 2.0 + 5.0 * 0.5, rel_tol=1e-14)
    assert math.isclose(float(body.momentum_z(q, [0.0, 0.0, 2.0])), 2.0 * 0.5, rel_tol=1e-14)
    assert "HeavyRigidBody" in repr(body)


@pytest.mark.parametrize(
    "args, kwargs, exc, match",
    [
        (([1.0, 2.0, 3.0], 0.0, [0, 0, 1.0]), {}, InvalidInputError, "mass"),
        (([1.0, 2.0, 3.0], 1.0, [0, 0, np.nan]), {}, InvalidInputError, "center_of_mass"),
        (([1.0, 2.0, 3.0], 1.0, [0, 1.0]), {}, InvalidInputError, "center_of_mass"),
        (([1.0, 1.0, 3.0], 1.0, [0, 0, 1.0]), {}, InvalidInputError, "inertia"),
        (([1.0, 2.0, 3.0], 1.0, [0, 0, 1.0]), {"g": -1.0}, InvalidInputError, "g"),
        (([1.0, 2.0, 3.0], "x", [0, 0, 1.0]), {}, InvalidTypeError, "mass"),
    ],
)
def test_bad_input(args, kwargs, exc, match):
    with pytest.raises(exc, match=match):
        HeavyRigidBody(*args, **kwargs)


def test_bad_simulate_input():
    body = HeavyRigidBody([2.0, 2.0, 1.0], 1.0, [0.0, 0.0, 0.5])
    with pytest.raises(InvalidInputError, match="method"):
        body.simulate([1.0, 0, 0, 0], [0, 0, 1.0], [0.0, 1.0], method="euler")
    with pytest.raises(InvalidInputError, match="omega0"):
        body.simulate([1.0, 0, 0, 0], [0, np.inf, 1.0], [0.0, 1.0])
    with pytest.raises(InvalidInputError, match="state"):
        body.rhs(0.0, np.zeros(6))
